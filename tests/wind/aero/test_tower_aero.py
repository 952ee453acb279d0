"""AeroDyn's tower aerodynamics (mbsym.wind.aero.tower) against closed forms.

- Potential flow: the velocity of uniform flow past a circular cylinder from its complex potential
  ``w = W (ζ + a²/ζ)``, ``u − i v = W (1 − a²/ζ²)`` (any textbook of potential flow), evaluated here
  independently of the module's algebra, on a tilted, moving tower. Tolerance 1e-9 relative: both are exact.
- Powles shadow: its formula at one point; AeroDyn's cut-offs (upstream no shadow, 20 D, the end taper).
- Drag: ``½ ρ C_d D V²`` across the tower, nothing along it; the drag on the operating turbine moves the
  tower-base moment by the closed-form moment of the load (1 %: the tower's deflection changes the arms).
"""

from __future__ import annotations

import math
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.aero.tower import TowerAero, drag_per_length


def _rotation(tilt: float) -> np.ndarray:
    """Rotation about ground y by ``tilt`` [rad]."""
    c, s = math.cos(tilt), math.sin(tilt)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _cylinder(points_local: np.ndarray, speed: float, radius: float) -> np.ndarray:
    """Disturbance of flow ``speed`` along local x past a cylinder along local z (complex potential)."""
    zeta = points_local[0] + 1j * points_local[1]
    conj = speed * (1 - radius**2 / zeta**2)          # u − i v
    return np.vstack([conj.real - speed, -conj.imag, np.zeros_like(zeta.real)])


def test_potential_flow_is_the_cylinder_flow_on_a_tilted_moving_tower():
    diameter, tilt = 6.0, 0.05
    tower = TowerAero([10.0, 110.0], [diameter, diameter], [0.6, 0.6], [0.1, 0.1], potential=1)
    R = _rotation(tilt)
    start = np.array([1.0, -2.0, 10.0])
    end = start + R @ np.array([0.0, 0.0, 100.0])
    moving = np.array([0.4, 0.3, 0.0])                      # the tower's velocity (same at both ends)
    local = np.array([[-9.0, 0.0, 40.0], [-7.0, 4.0, 60.0], [-5.0, -6.0, 20.0], [8.0, 3.0, 90.0]]).T
    points = start[:, None] + R @ local
    wind = np.array([11.0, 0.0, 0.0])
    got = np.array(tower.disturbance(ca.DM(points), ca.DM(np.tile(wind[:, None], (1, 4))), ca.DM(start), ca.DM(end),
                                     ca.DM(moving), ca.DM(moving)))
    rel = R.T @ (wind - moving)                             # relative flow in tower axes
    speed, angle = math.hypot(rel[0], rel[1]), math.atan2(rel[1], rel[0])
    Rz = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0], [0, 0, 1]])
    flow_axes = Rz.T @ local                                # x along the relative flow across the tower
    want = R @ Rz @ _cylinder(flow_axes, speed, 0.5 * diameter)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-12)
    assert got[0, 0] < -0.05 * speed                        # upstream on the axis: slowed by (a/x)²


def test_powles_shadow_downstream_only_and_aerodyn_cutoffs():
    d, cd = 4.0, 0.5
    tower = TowerAero([0.0, 100.0], [d, d], [cd, cd], [0.1, 0.1], shadow=1)
    up, top = ca.DM([0, 0, 100.0]), ca.DM([0, 0, 0.0])
    pts = ca.DM([[6.0, 0.0, 50.0], [-6.0, 0.0, 50.0], [6.0, 1.0, 50.0], [100.0, 0.0, 50.0], [0.0, 3.0, 101.0]]).T
    got = np.array(tower.disturbance(pts, ca.repmat(ca.DM([10.0, 0, 0]), 1, 5), top, up))
    xbar = 3.0
    assert got[0, 0] == pytest.approx(-10 * cd / math.sqrt(xbar), rel=1e-12)      # on the wake's axis
    assert got[0, 1] == 0.0                                                            # upstream: no shadow
    root = math.sqrt(math.sqrt(9.0 + 0.25))
    assert got[0, 2] == pytest.approx(-10 * cd / root * math.cos(0.5 * math.pi * 0.5 / root) ** 2, rel=1e-12)
    assert got[0, 3] == 0.0                                                            # beyond 20 D
    # half a radius above the top: the taper cos(π z̄/2) stretches the distances (z̄ = 0.5)
    stretched = 1.5 / math.cos(0.25 * math.pi)
    assert got[0, 4] == 0.0 and np.all(got[:, 4] == 0.0)      # x̄ = 0 (beside the wake): Powles is zero there
    tower_p = TowerAero([0.0, 100.0], [d, d], [cd, cd], [0.1, 0.1], potential=1)
    above = np.array(tower_p.disturbance(ca.DM([[-3.0, 0.0, 101.0], [-3.0, 0.0, 103.0]]).T,
                                         ca.repmat(ca.DM([10.0, 0, 0]), 1, 2), top, up))
    assert above[0, 0] == pytest.approx(-10 / (1.5 / math.cos(0.25 * math.pi)) ** 2, rel=1e-12)
    assert above[0, 1] == 0.0                                                          # z̄ = 1.5: none
    assert stretched > 1.5


def test_drag_per_length_is_across_the_tower():
    flow = ca.DM([[10.0, 0.0, 0.0], [0.0, 0.0, 10.0], [6.0, 8.0, 5.0]]).T
    f = np.array(drag_per_length(flow, ca.DM([0, 0, 1.0]), [5.0, 5.0, 5.0], [0.8, 0.8, 0.8], 1.2))
    np.testing.assert_allclose(f[:, 0], [0.5 * 1.2 * 0.8 * 5.0 * 100.0, 0, 0], rtol=1e-9)
    np.testing.assert_allclose(f[:, 1], 0.0, atol=1e-4)
    np.testing.assert_allclose(f[:, 2], 0.5 * 1.2 * 0.8 * 5.0 * 10.0 * np.array([6.0, 8.0, 0.0]), rtol=1e-9)


def test_bad_tables_and_switches_are_refused():
    with pytest.raises(ParameterError, match="increasing"):
        TowerAero([0.0, 0.0], [1, 1], [1, 1], [0.1, 0.1])
    with pytest.raises(ParameterError, match="TwrPotent"):
        TowerAero([0.0, 1.0], [1, 1], [1, 1], [0.1, 0.1], potential=3)
    with pytest.raises(ParameterError, match="TwrTI"):
        TowerAero([0.0, 1.0], [1, 1], [1, 1], [0.0, 0.0], shadow=2)


def test_rotor_effective_model_refuses_the_inflow_disturbance():
    from mbsym.wind import nrel5mw
    from mbsym.wind.operation import OperatingTurbine

    tower = TowerAero([0.0, 87.6], [6.0, 3.87], [1.0, 1.0], [0.1, 0.1], potential=1)
    with pytest.raises(ParameterError, match="blade-element rotor"):
        OperatingTurbine(nrel5mw(), dofs=["GenDOF"], tower_aero=tower)


def test_tower_drag_moves_the_tower_base_moment_by_its_closed_form_moment():
    """Steady 12 m/s on the built-in NREL 5 MW (tower FA, generator, the controller's trim): with a 40-node drag
    table the mean TwrBsMyt grows by ∫ ½ ρ C_d D(z) U² z dz over the tower (D linear: closed form) plus the
    thrust's change times the hub's height. Gravity off: with it the drag's 6 mm of extra tower-top deflection
    adds 28 kN m (1.8 %) of weight moment. Tolerance 0.1 %: the trapezoidal integration over 40 nodes."""
    from mbsym.wind import nrel5mw
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.trim import trim

    turbine = nrel5mw()
    base, top = float(turbine.tower_base_height), float(turbine.tower_height)
    z = np.linspace(base, top, 40)
    d0, d1, cd, rho, u = 6.0, 3.87, 1.0, 1.225, 12.0
    diameter = d0 + (d1 - d0) * (z - base) / (top - base)
    tower = TowerAero(z, diameter, np.full(z.size, cd), np.full(z.size, 0.1), drag=True)
    moments = []
    for aero in (None, tower):
        model = OperatingTurbine(turbine, dofs=["TwFADOF1", "GenDOF"], tower_aero=aero)
        op = trim(model, u, p={"gravity": 0.0})
        assert op.success, op.message
        moments.append((op.channels["TwrBsMyt"], op.channels["RotThrust"]))
    length = top - base
    # ∫0^L ½ ρ Cd (d0 + (d1 - d0) s/L) U² s ds
    want = 0.5 * rho * cd * u**2 * (d0 * length**2 / 2 + (d1 - d0) * length**2 / 3) / 1e3       # kN m
    thrust_arm = float(turbine.hub_height) - base
    got = moments[1][0] - moments[0][0] - (moments[1][1] - moments[0][1]) * thrust_arm
    assert got == pytest.approx(want, rel=1e-3)


def test_tower_drag_refuses_a_field_without_tower_points(tmp_path):
    """OpenFAST's InflowWind stops when AeroDyn's tower nodes are below a full field's grid without tower points;
    mbsym says so when the model is built (ff14's TurbSim grid starts at 20 m, the NREL 5 MW's TwrElev at 0)."""
    import re
    import shutil

    from mbsym.exceptions import WindInputError
    from mbsym.wind.operation.deck import operating_deck

    inputs = next((p / "shared" / "openfast" / "aero" / "openfast_inputs" for p in Path(__file__).resolve().parents
                   if (p / "shared" / "openfast" / "aero" / "openfast_inputs").is_dir()), None)
    if inputs is None:
        pytest.skip("shared/openfast/aero not found")
    shutil.copytree(inputs, tmp_path / "openfast_inputs")
    (tmp_path / "wind").symlink_to(inputs.parent / "wind")
    aerodyn = tmp_path / "openfast_inputs" / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    text, n = re.subn(r"^\S+(\s+TwrAero\s)", r"True\1", aerodyn.read_text(), count=1, flags=re.M)
    assert n == 1
    aerodyn.write_text(text)
    deck = operating_deck(tmp_path / "openfast_inputs" / "ff14_flex" / "ff14_flex.fst")
    with pytest.raises(WindInputError, match="TwrAero.*grid starts at 20 m.*tower points"):
        deck.model(aero="blade")
