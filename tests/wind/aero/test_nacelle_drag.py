"""AeroDyn's nacelle drag (mbsym.wind.aero.nacelle): closed-form loads, deck parsing, where the load acts.

The force is AeroDyn v5.0.0's ``RotCalcNacelleDrag`` (AeroDyn.f90): ``½ ρ |V_h|² Σ A_i C_{d,i} |n_i|`` split along
``n = (cos γ, sin γ, sin τ)`` with their signs, at the yaw bearing, plus ``NacDragAC × F``.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import ParameterError
from mbsym.wind.aero.nacelle import NacelleDrag

SHARED = Path(__file__).resolve().parents[3].parent / "shared" / "openfast"
RHO = 1.225


def _rz(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _loads(drag: NacelleDrag, flow, R) -> tuple[np.ndarray, np.ndarray]:
    f, m = drag.loads(ca.DM(flow), ca.DM(R), RHO)
    return np.asarray(f).ravel(), np.asarray(m).ravel()


def test_aligned_wind_gives_half_rho_cd_a_u2_along_x_and_the_arm_moment():
    drag = NacelleDrag([300.0, 250.0, 300.0], [1.2, 1.0, 0.8], [-2.0, 1.0, 2.5])
    f, m = _loads(drag, [14.0, 0.0, 0.0], np.eye(3))
    assert f == pytest.approx([0.5 * RHO * 1.2 * 300.0 * 14.0**2, 0.0, 0.0], rel=1e-9)
    assert m == pytest.approx(np.cross([-2.0, 1.0, 2.5], f), rel=1e-9)
    assert f[0] == pytest.approx(43218.0, rel=1e-9)                    # the validation case: 14 m/s


def test_yawed_wind_and_yawed_nacelle_split_the_force_by_the_relative_angle():
    drag = NacelleDrag([300.0, 250.0, 300.0], [1.2, 1.0, 0.8], [0.0, 0.0, 0.0])
    u, gamma = 14.0, np.deg2rad(-10.0)                                  # wind turned 10 deg towards -y
    c, s = np.cos(gamma), np.sin(gamma)
    mag = 0.5 * RHO * u**2 * (360.0 * abs(c) + 250.0 * abs(s))
    f, _ = _loads(drag, [u * c, u * s, 3.0], np.eye(3))                # vertical wind: no part in AeroDyn's drag
    assert f == pytest.approx([mag * c, mag * s, 0.0], rel=1e-9)
    yaw = np.deg2rad(25.0)                                              # the same relative angle, nacelle yawed
    w = _rz(yaw) @ np.array([u * c, u * s, 0.0])
    f2, _ = _loads(drag, w, _rz(yaw))
    assert f2 == pytest.approx(f, rel=1e-9, abs=1e-6)


def test_tilted_nacelle_adds_the_z_area_along_its_z_axis():
    drag = NacelleDrag([300.0, 250.0, 300.0], [1.2, 1.0, 0.8], [0.0, 0.0, 0.0])
    tilt = np.deg2rad(2.0)                                              # x axis tilted up: AeroDyn's tiltAngle < 0
    R = _ry(-tilt)
    f, _ = _loads(drag, [14.0, 0.0, 0.0], R)
    x = R[:, 0]
    cos_g = 14.0 * x[0] / np.hypot(x[0], x[1]) / 14.0
    sin_t = -x[2] / np.hypot(x[0], x[2])
    mag = 0.5 * RHO * 14.0**2 * (360.0 * abs(cos_g) + 240.0 * abs(sin_t))
    assert f == pytest.approx([mag * cos_g, 0.0, mag * sin_t], rel=1e-9)
    assert f[2] < 0


def test_invalid_values_are_refused():
    with pytest.raises(ParameterError, match="NacArea and NacCd"):
        NacelleDrag([-1.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0])
    with pytest.raises(ParameterError, match="3 finite"):
        NacelleDrag([1.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0])


@pytest.mark.skipif(not (SHARED / "aero").is_dir(), reason="shared NREL 5 MW deck missing")
def test_from_aerodyn_reads_the_nacelle_section(tmp_path):
    from mbsym.wind.deck.aerodyn import read_aerodyn

    deck = tmp_path / "deck"
    shutil.copytree(SHARED / "aero" / "openfast_inputs" / "deck", deck)
    path = deck / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    assert NacelleDrag.from_aerodyn(read_aerodyn(path)) is None
    text = path.read_text()
    for pattern, repl in ((r"^False(\s+NacelleDrag)", r"True\1"), (r"^0, 0, 0(\s+NacArea)", r"300, 250, 300\1"),
                          (r"^0, 0, 0(\s+NacCd)", r"1.2, 1.0, 0.8\1"),
                          (r"^0, 0, 0(\s+NacDragAC)", r"-2.0, 1.0, 2.5\1")):
        text, n = re.subn(pattern, repl, text, count=1, flags=re.M)
        assert n == 1
    path.write_text(text)
    drag = NacelleDrag.from_aerodyn(read_aerodyn(path))
    assert drag.area.tolist() == [300.0, 250.0, 300.0]
    assert drag.drag_coefficient.tolist() == [1.2, 1.0, 0.8]
    assert drag.center.tolist() == [-2.0, 1.0, 2.5]


def test_nacelle_load_acts_at_the_tower_top():
    """The inputs ``NacAeroFx``/``NacAeroMy`` load the tower's first fore-aft mode with its top displacement (1: the
    coordinate is TTDspFA) and its top slope: the force acts at the yaw bearing, in nacelle axes."""
    from mbsym.wind import nrel5mw
    from mbsym.wind.structure.turbine import TurbineModel

    model = TurbineModel(nrel5mw(), dofs=["TwFADOF1"], nacelle_loads=True)
    eom = model.eom
    assert {f"NacAero{c}" for c in ("Fx", "Fy", "Fz", "Mx", "My", "Mz")} <= set(eom.inputs)
    q = ca.DM.zeros(eom.n_q)
    p = eom.parameter_vector()
    u0 = np.zeros(len(eom.inputs))

    def forcing(name: str, value: float) -> float:
        u = u0.copy()
        u[eom.inputs.index(name)] = value
        return float(eom.functions.forcing(q, q, u, p)[0] - eom.functions.forcing(q, q, u0, p)[0])

    assert forcing("NacAeroFx", 1000.0) == pytest.approx(1000.0, rel=1e-9)
    slope = forcing("NacAeroMy", 1000.0) / 1000.0                      # dθ_y/dq at the top, ~1.5/H for a cantilever
    height = float(model.turbine.tower_height - model.turbine.tower_base_height)
    assert 1.0 / height < slope < 3.0 / height
