"""Steady BEM: closed forms, invariants, robustness, and AeroDyn's rotor coefficients.

References:
* momentum theory of an ideal rotor without wake rotation and losses: a rotor designed
  for a = 1/3 at every radius gives Ct = 8/9 and Cp = 16/27 (Betz) on the annulus
  area (Burton et al., Wind Energy Handbook, Sect. 3.2-3.5);
* Glauert's orthogonality a'(1 + a') λr² = a (1 - a) of a drag-free BEM solution
  without tip/hub loss (Burton et al., Sect. 3.5.1);
* Prandtl's tip-loss factor F = 2/π acos(exp(-B (R - r) / (2 r sin φ)));
* AeroDyn 15 itself: RtAeroCp/Ct, RtAeroFxh/Mxh/Pwr of the 17 steady OpenFAST runs in
  ``shared/openfast/aero/steady_states.csv`` (OpenFAST v5, NREL 5 MW, rigid blades).
"""

from __future__ import annotations

import csv
import dataclasses
import math

import numpy as np
import pytest

from mbsym.exceptions import DimensionError, ParameterError
from mbsym.wind.aero import BEMRotor, nrel5mw_bem_rotor, rotor_coefficients, solve_bem
from mbsym.wind.aero._induction import _Elements, _prandtl
from mbsym.wind.deck.airfoils import AirfoilPolar

from .conftest import AERO, need

B = 3
R_HUB, R_TIP = 5.0, 50.0
CL_SLOPE = 2 * math.pi
# a thin-airfoil polar, linear (Cl = 2 pi alpha) for |alpha| < 0.4 rad, drag-free
POLAR = AirfoilPolar(name="thin", alpha=np.array([-math.pi, -0.4, 0.4, math.pi]),
                     cl=np.array([0.0, -0.4 * CL_SLOPE, 0.4 * CL_SLOPE, 0.0]),
                     cd=np.zeros(4), cm=np.zeros(4), reynolds=1e6)


def ideal_rotor(design_tsr: float = 8.0, n: int = 25, cl: float = 1.0) -> BEMRotor:
    """A rotor designed for a = 1/3, a' = 0 at every station (momentum theory)."""
    r = np.linspace(R_HUB, R_TIP, n)
    lambda_r = design_tsr * r / R_TIP
    phi = np.arctan2(2.0 / 3.0, lambda_r)  # tan(phi) = (1 - a) / lambda_r
    # a / (1 - a) = 1/2 = sigma Cl cos(phi) / (4 sin^2 phi)  ->  chord
    sigma = 2.0 * np.sin(phi) ** 2 / (cl * np.cos(phi))
    chord = sigma * 2 * math.pi * r / B
    twist = phi - cl / CL_SLOPE
    zeros = np.zeros(n)
    return BEMRotor(n_blades=B, hub_radius=R_HUB, precone=0.0, span=r - R_HUB, curve_ac=zeros,
                    sweep_ac=zeros, curve_angle=zeros, twist=twist, chord=chord,
                    polars=(POLAR,) * n, tip_loss=False, hub_loss=False,
                    tangential_induction=False, pitching_moment=False)


# ----------------------------------------------------------------------------- closed forms
def test_ideal_rotor_reaches_betz():
    rotor = ideal_rotor()
    sol = solve_bem(rotor, 8.0, 0.0)
    annulus = 1.0 - (R_HUB / R_TIP) ** 2  # the loads act on the annulus hub..tip
    np.testing.assert_allclose(sol.a, 1.0 / 3.0, rtol=0, atol=1e-9)
    assert abs(sol.cp - 16.0 / 27.0 * annulus) < 1e-9
    assert abs(sol.ct - 8.0 / 9.0 * annulus) < 1e-9
    assert abs(sol.cq - sol.cp / 8.0) < 1e-12
    assert sol.converged.all()


def test_off_design_ideal_rotor_stays_below_betz():
    # Betz: no rotor without wake rotation extracts more than 16/27 of the annulus power.
    rotor = ideal_rotor()
    tsr = np.linspace(3.0, 14.0, 23)
    cp, ct, _ = rotor_coefficients(rotor, tsr, np.zeros_like(tsr))
    annulus = 1.0 - (R_HUB / R_TIP) ** 2
    assert np.all(cp <= 16.0 / 27.0 * annulus + 1e-9)
    assert abs(cp.max() - 16.0 / 27.0 * annulus) < 2e-3  # reached near the design TSR


def test_drag_free_solution_is_glauert_orthogonal():
    # With tangential induction, Cd = 0 and no losses, the induced velocity is normal to
    # the relative wind: a'(1 + a') lambda_r^2 = a (1 - a) at every element.
    rotor = dataclasses.replace(ideal_rotor(), tangential_induction=True)
    for tsr, pitch in ((6.0, 0.02), (8.0, 0.06), (10.0, 0.1)):
        sol = solve_bem(rotor, tsr, pitch)
        lambda_r = tsr * rotor.local_radius / rotor.radius
        lhs = sol.ap[0] * (1 + sol.ap[0]) * lambda_r**2
        rhs = sol.a[0] * (1 - sol.a[0])
        assert np.all(sol.a < 0.4)  # momentum region, no Buhl correction
        np.testing.assert_allclose(lhs, rhs, rtol=1e-8, atol=1e-12)


def test_prandtl_factor_limits():
    # F = 1 far inboard with many blades, 0 (floored at 1e-4) at the tip, and the closed
    # form in between.
    r, R, phi = np.array([10.0, 30.0, 49.999999, 50.0]), 50.0, np.full(4, 0.2)
    tip_const = B * (R - r) / (2 * r)
    e = _Elements(vx=np.ones(4), vy=np.ones(4), theta=np.zeros(4), sigma=np.zeros(4),
                  tip_const=tip_const, hub_const=np.full(4, np.inf), rows=np.zeros(4, int),
                  tables={}, n_blades=B, tip_loss=True, hub_loss=True, tangential_induction=True,
                  axial_drag=False, tangential_drag=False)
    f = _prandtl(np.sin(phi), e)
    expected = 2 / math.pi * np.arccos(np.exp(-tip_const / np.sin(phi)))
    np.testing.assert_allclose(f[:3], expected[:3], rtol=1e-12)
    assert f[3] == 1e-4 and f[0] > 0.999999
    many = dataclasses.replace(e, tip_const=100 * (R - r) / (2 * r))
    assert _prandtl(np.sin(phi[:2]), many.take(np.arange(2)))[1] > 1 - 1e-12


# ----------------------------------------------------------------------------- robustness
def test_always_converges_over_extreme_operating_points():
    # Ning's bracketed residual: a solution (or AeroDyn's "invalid -> zero induction") for
    # windmill, turbulent-wake, propeller-brake and parked conditions; finite everywhere.
    rotor = nrel5mw_bem_rotor()
    tsr, pitch = np.meshgrid([0.5, 1.5, 4.0, 8.0, 16.0, 25.0],
                             np.radians([-15, -5, 0, 10, 30, 60, 90]), indexing="ij")
    sol = solve_bem(rotor, tsr, pitch)
    for name in ("cp", "ct", "cq"):
        assert np.all(np.isfinite(getattr(sol, name)))
    assert sol.converged[tsr >= 2.0].all()
    # high TSR at fine pitch: heavily loaded (Buhl region), thrust above 1
    assert sol.ct[-1, 1] > 1.0
    # feathered blades produce no power (and a small negative one at high TSR)
    assert np.all(sol.cp[:, -1] < 0.01)


def test_inputs_are_checked():
    rotor = nrel5mw_bem_rotor()
    with pytest.raises(ParameterError, match="tsr must hold positive"):
        solve_bem(rotor, [7.0, 0.0], 0.0)
    with pytest.raises(ParameterError, match="pitch must hold finite"):
        solve_bem(rotor, 7.0, np.nan)
    with pytest.raises(ParameterError, match="n_azimuth"):
        solve_bem(rotor, 7.0, 0.0, n_azimuth=0)
    with pytest.raises(ParameterError, match="skew"):
        solve_bem(rotor, 7.0, 0.0, skew=2.0)
    with pytest.raises(TypeError, match="BEMRotor"):
        solve_bem("rotor", 7.0, 0.0)  # type: ignore[arg-type]
    with pytest.raises(TypeError):
        solve_bem(rotor, 7.0, 0.0, azimuths=4)  # type: ignore[call-arg]
    with pytest.raises(DimensionError, match="chord has 3 values"):
        dataclasses.replace(rotor, chord=np.ones(3))
    with pytest.raises(ParameterError, match="polars must hold 19"):
        dataclasses.replace(rotor, polars=rotor.polars[:3])


def test_unsupported_aerodyn_models_are_refused():
    from mbsym.wind.deck.nrel5mw_aero import nrel5mw_aerodyn

    ad = nrel5mw_aerodyn()
    for change in ({"bem_model": 2}, {"wake_model": 3}, {"wake_model": 0}):
        with pytest.raises(ParameterError, match="BEM_Mod = 1"):
            BEMRotor.from_aerodyn(dataclasses.replace(ad, **change), hub_radius=1.5, precone=0.0)
    # AFTabMod 2 (Reynolds interpolation) is AeroDyn's first table when each file has one; refused with several
    BEMRotor.from_aerodyn(dataclasses.replace(ad, airfoil_table_mode=2), hub_radius=1.5, precone=0.0)
    several = (dataclasses.replace(ad.airfoils[0], n_tables=3),) + tuple(ad.airfoils[1:])
    with pytest.raises(ParameterError, match="AFTabMod = 2 interpolates"):
        BEMRotor.from_aerodyn(dataclasses.replace(ad, airfoil_table_mode=2, airfoils=several), hub_radius=1.5,
                              precone=0.0)


# ----------------------------------------------------------------------------- AeroDyn
@pytest.fixture(scope="module")
def openfast_states() -> list[dict[str, float]]:
    with open(need(AERO / "steady_states.csv"), newline="") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


@pytest.fixture(scope="module")
def deck_rotor() -> BEMRotor:
    return BEMRotor.from_openfast(need(AERO / "openfast_inputs" / "steady_12" / "steady_12.fst"))


def test_bem_reproduces_aerodyn_rotor_coefficients_within_1_percent(openfast_states, deck_rotor):
    # Inputs: AeroDyn's own RtTSR, the blade pitch and the skew RtSkew of each steady run;
    # reference: RtAeroCp, RtAeroCt (both based on RtVAvgxh, the wind along the shaft).
    # Observed: Cp -0.52..-0.76 %, Ct -0.31..-0.45 % (benchmarks/README.md).
    s = openfast_states
    tsr = np.array([x["RtTSR_[-]"] for x in s])
    pitch = np.radians([x["BldPitch1_[deg]"] for x in s])
    for k, state in enumerate(s):
        sol = solve_bem(deck_rotor, tsr[k], pitch[k], skew=math.radians(state["RtSkew_[deg]"]))
        assert abs(sol.cp / state["RtAeroCp_[-]"] - 1) < 0.01, state["WindSpeed_[m/s]"]
        assert abs(sol.ct / state["RtAeroCt_[-]"] - 1) < 0.01, state["WindSpeed_[m/s]"]
        # dimensional: thrust, torque and power with AeroDyn's reference speed and area
        u, rho = state["RtVAvgxh_[m/s]"], 1.225
        q_area = 0.5 * rho * math.pi * deck_rotor.radius**2 * u**2
        assert abs(sol.ct * q_area / state["RtAeroFxh_[N]"] - 1) < 0.01
        assert abs(sol.cq * q_area * deck_rotor.radius / state["RtAeroMxh_[N-m]"] - 1) < 0.01
        assert abs(sol.cp * q_area * u / state["RtAeroPwr_[W]"] - 1) < 0.01


def test_rotor_radius_is_aerodyns_rmax(openfast_states, deck_rotor):
    # AeroDyn: RtTSR = Omega rmax / RtVAvgxh  ->  rmax from the outputs.
    s = openfast_states[4]
    rmax = s["RtTSR_[-]"] * s["RtVAvgxh_[m/s]"] / (s["RotSpeed_[rpm]"] * math.pi / 30)
    assert abs(deck_rotor.radius - rmax) < 2e-3 * rmax  # output rounding of RotSpeed/RtTSR
