"""Per-node blade-element aerodynamics (mbsym.wind.aero.blade): independent references.

References:
* a textbook BEM node computed here in plain Python (bisection on the momentum residual with
  Prandtl's tip and hub loss, tangential induction; Burton et al., Wind Energy Handbook §3.5,
  Ning 2014 for the residual);
* mbsym's steady BEM (:func:`solve_bem`, bracketing solver, numpy) on the same rotor;
* AeroDyn 15 (OpenFAST v5): RtAeroFxh and RtAeroCp of the steady NREL 5 MW runs in
  ``shared/openfast/aero/steady_states.csv`` (rigid blades, tilt 5 deg);
* the closed-form response of Øye's two-stage filter to a step (DBEMT);
* central finite differences for the derivatives.
"""

from __future__ import annotations

import csv
import math

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import DimensionError, ParameterError, UnsupportedFeatureError
from mbsym.wind.aero import BEMRotor, nrel5mw_bem_rotor, solve_bem
from mbsym.wind.aero.blade import BladeElementRotor
from mbsym.wind.aero.blade.dbemt import OYE_K
from mbsym.wind.deck.airfoils import AirfoilPolar
from mbsym.wind.deck.nrel5mw_aero import nrel5mw_aerodyn

from .conftest import AERO, need

N = 19  # NREL 5 MW AeroDyn nodes per blade


@pytest.fixture(scope="module")
def bem() -> BEMRotor:
    return nrel5mw_bem_rotor()


def rotor(bem: BEMRotor, **kw) -> BladeElementRotor:
    return BladeElementRotor(bem, **kw)


def axial_inputs(bem: BEMRotor, tsr: float, pitch: float, wind: float = 10.0):
    """All nodes of a rigid rotor in a wind ``wind`` along the shaft (bem.py's geometry)."""
    g = bem._geometry
    omega = tsr * wind / bem.radius
    vx = np.tile(g["cos_cone"], 3) * wind
    vy = np.tile(g["r_rad"], 3) * omega
    return vx, vy, np.tile(g["r"], 3), np.tile(bem.twist, 3) + pitch, omega


def numeric(out: dict, *names: str) -> list[np.ndarray]:
    return [np.asarray(ca.evalf(out[n])).ravel() for n in names]


# ----------------------------------------------------------------------------- one node by hand
THIN = AirfoilPolar(name="thin", alpha=np.array([-math.pi, -0.4, 0.4, math.pi]),
                    cl=np.array([0.0, -0.4 * 2 * math.pi, 0.4 * 2 * math.pi, 0.0]),
                    cd=np.array([0.3, 0.01, 0.01, 0.3]), cm=np.array([0.0, -0.05, -0.05, 0.0]),
                    reynolds=1e6)


def hand_node(vx, vy, r, chord, theta, z, z_hub, z_tip, B=3, rho=1.2):
    """Textbook BEM of one element: bisection of sinφ/(1-a) = cosφ Vx/Vy (1 - kp) on (0, π/2)."""
    def coefficients(alpha):
        cl = float(np.interp(alpha, THIN.alpha, THIN.cl))
        cd = float(np.interp(alpha, THIN.alpha, THIN.cd))
        cm = float(np.interp(alpha, THIN.alpha, THIN.cm))
        return cl, cd, cm

    def state(phi):
        cl, _, _ = coefficients(phi - theta)
        s, c = math.sin(phi), math.cos(phi)
        f_tip = 2 / math.pi * math.acos(math.exp(-B * (z_tip - z) / (2 * z * s)))
        f_hub = 2 / math.pi * math.acos(math.exp(-B * (z - z_hub) / (2 * z_hub * s)))
        F = f_tip * f_hub
        sigma = B * chord / (2 * math.pi * r)
        k = sigma * cl * c / (4 * F * s * s)  # drag left out of the induction (AIDrag False)
        a = k / (1 + k)
        kp = sigma * cl * s / (4 * F * s * c)
        ap = kp / (1 - kp)
        return a, ap, s / (1 - a) - c * vx / vy * (1 - kp)

    lo, hi = 1e-6, math.pi / 2 - 1e-6
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if state(lo)[2] * state(mid)[2] <= 0:
            hi = mid
        else:
            lo = mid
    a, ap, _ = state(0.5 * (lo + hi))
    phi = math.atan2(vx * (1 - a), vy * (1 + ap))
    cl, cd, cm = coefficients(phi - theta)
    q = 0.5 * rho * ((vx * (1 - a)) ** 2 + (vy * (1 + ap)) ** 2)
    cn, ct = cl * math.cos(phi) + cd * math.sin(phi), cl * math.sin(phi) - cd * math.cos(phi)
    return {"a": a, "ap": ap, "phi": phi, "fn": q * chord * cn, "ft": q * chord * ct, "m": q * chord**2 * cm}


@pytest.mark.parametrize("method, rtol", [("linear", 1e-9), ("spline", 2e-3)])
def test_one_node_against_a_hand_computation(method, rtol):
    # 5 nodes, hub radius 2 m, no cone: z = r = 2 + span. Tolerance: the linear polar is the
    # hand computation's; the spline rounds the table's corners only near ±0.4 rad (α here
    # ~0.1 rad), so its difference is the solver's and the cd corner's, measured < 1e-3.
    span = np.array([0.0, 10.0, 20.0, 30.0, 38.0])
    zeros = np.zeros(5)
    chord = np.array([3.0, 2.8, 2.2, 1.6, 1.0])
    twist = np.radians([15.0, 8.0, 4.0, 1.0, 0.0])
    b = BEMRotor(n_blades=3, hub_radius=2.0, precone=0.0, span=span, curve_ac=zeros, sweep_ac=zeros,
                 curve_angle=zeros, twist=twist, chord=chord, polars=(THIN,) * 5)
    r = 2.0 + span
    vx, omega = 9.0, 1.6
    vy = omega * r
    rot = rotor(b, polar_method=method)
    out = rot.evaluate(np.tile(vx, 15), np.tile(vy, 3), np.tile(r, 3), np.tile(twist, 3), [0, 2, 4], rho=1.2)
    j = 2
    ref = hand_node(vx, vy[j], r[j], chord[j], twist[j], z=r[j], z_hub=2.0, z_tip=40.0)
    a, ap, phi, fn, ft, m = (v[j] for v in numeric(out, "axial_induction", "tangential_induction", "phi", "fn",
                                                     "ft", "m"))
    np.testing.assert_allclose([a, ap, phi, fn, ft, m],
                               [ref["a"], ref["ap"], ref["phi"], ref["fn"], ref["ft"], ref["m"]], rtol=rtol)


# ----------------------------------------------------------------------------- rigid rotor
@pytest.mark.parametrize("tsr, pitch_deg", [(7.6, 0.0), (5.0, 12.0), (3.4, 22.0)])
def test_nodal_loads_equal_solve_bem_with_linear_polars(bem, tsr, pitch_deg):
    # same theory and polars, different solvers (bracketing to 1e-11 vs 4 Newton steps in the
    # graph, measured error 2e-8 in a): loads agree to 1e-7 of their largest value.
    vx, vy, r, theta, _ = axial_inputs(bem, tsr, math.radians(pitch_deg), wind=1.0)
    out = rotor(bem, polar_method="linear").evaluate(vx, vy, r, theta, np.zeros(3), rho=1.0)
    fn, ft = numeric(out, "fn", "ft")
    sol = solve_bem(bem, tsr, math.radians(pitch_deg), skew=0.0)
    for got, ref in ((fn[:N], sol.fn[0]), (ft[:N], sol.ft[0])):
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-7 * np.abs(ref).max())


def rotor_sums(rot: BladeElementRotor, out: dict) -> tuple[float, float]:
    """Thrust along the shaft and shaft torque from the node weights (AeroDyn's Line2 loads)."""
    g = rot.bem._geometry
    fn, ft, m = (v.reshape(3, N) for v in numeric(out, "fn", "ft", "m"))
    w = rot.node_weights
    sin_cone = np.sin(rot.bem.precone + rot.bem.curve_angle)
    thrust = np.sum(w * fn * g["cos_cone"])
    torque = np.sum(w * (g["r_rad"] * ft - rot.sweep_ac * sin_cone * fn + m * sin_cone))
    return float(thrust), float(torque)


@pytest.mark.parametrize("tsr, pitch_deg", [(7.6, 0.0), (5.7, 8.6), (4.0, 17.4)])
def test_rotor_thrust_and_torque_equal_solve_bem(bem, tsr, pitch_deg):
    # Tolerance 0.3 %: the spline polars differ from AeroDyn's linear ones by < 0.1 % on the
    # loads (measured, docs/blade_aero.md), and the trapezoid Σ w r ft differs from solve_bem's
    # exact integral of the product of two linear functions by < 0.2 % of the torque (measured
    # 0.02-0.15 % here); the thrust integrand is linear, so only the polars enter.
    wind = 10.0
    vx, vy, r, theta, omega = axial_inputs(bem, tsr, math.radians(pitch_deg), wind)
    rot = rotor(bem)
    thrust, torque = rotor_sums(rot, rot.evaluate(vx, vy, r, theta, np.zeros(3), rho=1.225))
    sol = solve_bem(bem, tsr, math.radians(pitch_deg), skew=0.0)
    dyn = 0.5 * 1.225 * math.pi * bem.radius**2 * wind**2
    np.testing.assert_allclose(thrust, float(sol.ct) * dyn, rtol=3e-3)
    np.testing.assert_allclose(torque, float(sol.cq) * dyn * bem.radius, rtol=3e-3)


def steady_rows():
    with open(need(AERO / "steady_states.csv")) as f:
        rows = list(csv.DictReader(f))
    return [r for r in rows if float(r["WindSpeed_[m/s]"]) in (8.0, 14.0, 20.0)]


def test_rotor_against_aerodyn_steady_states(bem):
    # AeroDyn's own operating points (RtVAvgxh along the shaft, RtSkew, RotSpeed, BldPitch1):
    # the skewed inflow is built as bem.py does, the 3 blades at 4 rotor azimuths are averaged.
    # Tolerance 1 %: mbsym's BEM (same equations) is 0.3-0.8 % below AeroDyn (docs/aero.md).
    rot = rotor(bem)
    g = bem._geometry
    sin_cone = np.sin(bem.precone + bem.curve_angle)
    for row in steady_rows():
        wind = float(row["RtVAvgxh_[m/s]"])
        chi = math.radians(float(row["RtSkew_[deg]"]))
        omega = float(row["RotSpeed_[rpm]"]) * math.pi / 30
        theta = np.tile(bem.twist, 3) + math.radians(float(row["BldPitch1_[deg]"]))
        thrust = power = 0.0
        offsets = np.radians([0.0, 30.0, 60.0, 90.0])
        for psi0 in offsets:
            psi = psi0 + np.radians([0.0, 120.0, 240.0])
            cos_psi, sin_psi = np.repeat(np.cos(psi), N), np.repeat(np.sin(psi), N)
            vx = wind * (np.tile(g["cos_cone"], 3) - math.tan(chi) * np.tile(sin_cone, 3) * cos_psi)
            vy = omega * np.tile(g["r_rad"], 3) + wind * math.tan(chi) * sin_psi
            out = rot.evaluate(vx, vy, np.tile(g["r"], 3), theta, psi, rho=1.225, skew=chi, skew_azimuth=0.0)
            t, q = rotor_sums(rot, out)
            thrust += t / offsets.size
            power += q * omega / offsets.size
        cp = power / (0.5 * 1.225 * math.pi * bem.radius**2 * wind**3)
        np.testing.assert_allclose(thrust, float(row["RtAeroFxh_[N]"]), rtol=1e-2)
        np.testing.assert_allclose(cp, float(row["RtAeroCp_[-]"]), rtol=1e-2)


def test_skew_redistribution_formula(bem):
    # AeroDyn's Pitt/Peters (BEM_Mod 1): a (1 + K tan((0.6 a + 1) χ0 / 2) r/R sin ψ_s), ψ_s - 90° =
    # ψ - ψ_w; checked against the un-skewed induction of the same graph, to rounding.
    vx, vy, r, theta, _ = axial_inputs(bem, 7.0, 0.02)
    rot = rotor(bem)
    psi, chi, psi_w = np.array([0.3, 2.4, 4.5]), 0.2, 0.7
    base = numeric(rot.evaluate(vx, vy, r, theta, psi, rho=1.2), "axial_induction")[0]
    skewed = numeric(rot.evaluate(vx, vy, r, theta, psi, rho=1.2, skew=chi, skew_azimuth=psi_w),
                     "axial_induction")[0]
    fixed = np.tile(bem._geometry["fixed"], 3)
    expected = base * (1 + 15 * math.pi / 32 * np.tan((0.6 * base + 1) * chi / 2) * r / bem.radius
                       * np.cos(np.repeat(psi, N) - psi_w))
    np.testing.assert_allclose(skewed[~fixed], expected[~fixed], rtol=1e-12)
    np.testing.assert_array_equal(skewed[fixed], 1.0)


def test_node_weights_integrate_linear_loads(bem):
    # trapezoid on the aerodynamic-centre distances: exact for a linear load (here f = 1 and
    # f = arc length), to rounding.
    rot = rotor(bem)
    length = bem._geometry["length"]
    s = np.concatenate([[0.0], np.cumsum(length)])
    np.testing.assert_allclose(rot.node_weights.sum(), s[-1], rtol=1e-14)
    np.testing.assert_allclose(rot.node_weights @ s, 0.5 * s[-1] ** 2, rtol=1e-14)


# ----------------------------------------------------------------------------- DBEMT
def test_dbemt_equilibrium_reproduces_the_quasi_steady_loads(bem):
    # at the states of steady_states the derivatives vanish and the loads are the quasi-steady
    # ones (v = v_s: same induction), to the Newton residual (measured < 1e-10).
    vx, vy, r, theta, _ = axial_inputs(bem, 7.0, 0.05)
    dyn, qs = rotor(bem, dbemt_mode=2), rotor(bem)
    x0 = dyn.steady_states(vx, vy, r, theta)
    assert x0.size == len(dyn.state_names) == 4 * 3 * N
    out = dyn.evaluate(vx, vy, r, theta, np.zeros(3), x0, rho=1.2)
    ref = qs.evaluate(vx, vy, r, theta, np.zeros(3), rho=1.2)
    (xdot,) = numeric(out, "states_dot")
    np.testing.assert_allclose(xdot, 0.0, atol=1e-9)
    for name in ("fn", "ft"):
        got, want = numeric(out, name)[0], numeric(ref, name)[0]
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-8 * np.abs(want).max())


def test_dbemt_step_response_is_oye_two_time_constants(bem):
    # constant τ1 (DBEMT_Mod 3): after a step of the wind the quasi-steady v_s jumps to v2 and
    # stays; Øye's filter from equilibrium at v1 gives v(t) = v2 + A e^{-t/τ1} + C e^{-t/τ2},
    # A = (1-k)(v1-v2)/(1-τ2/τ1), C = v1 - v2 - A. The states feed back only into the Newton
    # start (converged to ~1e-6 in a): tolerance 1e-4 of the step.
    from scipy.integrate import solve_ivp

    tau1 = 4.0
    rot = rotor(bem, dbemt_mode=3, tau1_const=tau1)
    before, after = axial_inputs(bem, 7.5, 0.0, wind=9.0), axial_inputs(bem, 7.5 * 9 / 11, 0.0, wind=11.0)
    x1 = rot.steady_states(*before[:4])
    x2 = rot.steady_states(*after[:4])
    x = ca.SX.sym("x", x1.size)
    rhs = ca.Function("rhs", [x], [rot.evaluate(*after[:4], np.zeros(3), x, rho=1.2)["states_dot"]])
    t_eval = np.array([0.5, 1.0, 2.0, 4.0, 8.0])
    sol = solve_ivp(lambda t, y: np.asarray(rhs(y)).ravel(), (0, 8.0), x1, t_eval=t_eval, rtol=1e-10, atol=1e-12)
    j = 10  # blade 1, node 11 (r/R about 0.55)
    ratio = bem.local_radius[j] / bem.radius
    tau2 = (0.39 - 0.26 * ratio**2) * tau1
    for c in (0, 1):  # axial and tangential induced velocity
        v1, v2 = x1[4 * j + c], x2[4 * j + c]
        amp = (1 - OYE_K) * (v1 - v2) / (1 - tau2 / tau1)
        expected = v2 + amp * np.exp(-t_eval / tau1) + (v1 - v2 - amp) * np.exp(-t_eval / tau2)
        np.testing.assert_allclose(sol.y[4 * j + c], expected, rtol=0, atol=1e-4 * abs(v1 - v2))


# ----------------------------------------------------------------------------- derivatives
@pytest.mark.parametrize("mode", [0, 2])
def test_jacobians_against_central_differences(bem, mode):
    # AD of the whole graph (Newton steps included) vs central differences, step 1e-5 of the
    # inputs' scale; tolerance 1e-5 of the largest derivative (truncation O(h²), rounding
    # O(ε/h) ~ 1e-11 relative).
    rot = rotor(bem, dbemt_mode=mode)
    vx, vy, r, theta, _ = axial_inputs(bem, 6.5, 0.06)
    n = 3 * N
    u = ca.SX.sym("u", 3 * n)
    x = ca.SX.sym("x", len(rot.state_names))
    out = rot.evaluate(u[:n], u[n:2 * n], r, u[2 * n:], np.zeros(3), x if mode else None, rho=1.225)
    y = ca.vertcat(out["fn"], out["ft"])
    f = ca.Function("f", [u, x], [y])
    jac_f = ca.Function("jacobian_fn", [u, x], [ca.jacobian(y, u)])
    u0 = np.concatenate([vx, vy, theta])
    x0 = rot.steady_states(vx, vy, r, theta) if mode else np.zeros(0)
    jac = np.asarray(jac_f(u0, x0))
    nodes = [2, 8, 14, 17, N + 5]  # root, mid, outer, next-to-tip of blade 1, one of blade 2
    for block, h in ((0, 1e-4), (n, 5e-4), (2 * n, 1e-5)):  # vx, vy [m/s], theta [rad]
        cols = [block + j for j in nodes]
        fd = np.empty((y.shape[0], len(cols)))
        for k, i in enumerate(cols):
            du = np.zeros_like(u0)
            du[i] = h
            fd[:, k] = (np.asarray(f(u0 + du, x0)) - np.asarray(f(u0 - du, x0))).ravel() / (2 * h)
        np.testing.assert_allclose(jac[:, cols], fd, rtol=0, atol=1e-5 * np.abs(jac[:, cols]).max())


# ----------------------------------------------------------------------------- bad input
def test_bad_inputs(bem):
    rot = rotor(bem)
    vx, vy, r, theta, _ = axial_inputs(bem, 7.0, 0.0)
    with pytest.raises(DimensionError, match="expected 57"):
        rot.evaluate(vx[:-1], vy, r, theta, np.zeros(3), rho=1.2)
    with pytest.raises(DimensionError, match="quasi-steady"):
        rot.evaluate(vx, vy, r, theta, np.zeros(3), np.zeros(4), rho=1.2)
    with pytest.raises(DimensionError, match="azimuth"):
        rot.evaluate(vx, vy, r, theta, np.zeros(2), rho=1.2, skew=0.1)
    dyn = rotor(bem, dbemt_mode=2)
    with pytest.raises(DimensionError, match="DBEMT and UA states"):
        dyn.evaluate(vx, vy, r, theta, np.zeros(3), rho=1.2)
    with pytest.raises(ParameterError, match="finite"):
        dyn.steady_states(np.full(57, np.nan), vy, r, theta)
    with pytest.raises(TypeError, match="unexpected keyword"):
        dyn.steady_states(vx, vy, r, theta, wind=3.0)
    with pytest.raises(ParameterError, match="DBEMT_Mod 1 needs tau1_const"):
        rotor(bem, dbemt_mode=1)
    with pytest.raises(ParameterError, match="n_newton"):
        rotor(bem, n_newton=0)
    with pytest.raises(ParameterError, match="polar method"):
        rotor(bem, polar_method="cubic")


def test_unsteady_aerodynamics_other_than_ua_mod_3_4_and_6_are_refused():
    import dataclasses

    from mbsym.exceptions import ParameterError

    for mode in (2, 5, 7):
        aerodyn = dataclasses.replace(nrel5mw_aerodyn(), unsteady_model=mode)
        with pytest.raises(UnsupportedFeatureError, match=f"UA_Mod = {mode} is not modelled"):
            BladeElementRotor.from_aerodyn(aerodyn, hub_radius=1.5, precone=-0.04, n_blades=3, ua_dt=0.01,
                                           speed_of_sound=335.0)
    aerodyn = dataclasses.replace(nrel5mw_aerodyn(), unsteady_model=3)
    with pytest.raises(ParameterError, match="DTAero"):               # the AeroDyn step is needed
        BladeElementRotor.from_aerodyn(aerodyn, hub_radius=1.5, precone=-0.04, n_blades=3)
    rot = BladeElementRotor.from_aerodyn(aerodyn, hub_radius=1.5, precone=-0.04, n_blades=3, ua_dt=0.01,
                                         speed_of_sound=335.0)
    assert rot.unsteady is not None and rot.state_names[-1].endswith("_ua_sigma3")


def test_from_aerodyn_runs_dbemt_as_openfast_v5():
    # the packaged deck has Wake_Mod 1, DBEMT_Mod 2, tau1_const 4 in the v4+ format:
    # OpenFAST v5 runs DBEMT (AeroDyn_IO.f90 legacy logic only for a WakeMod key)
    rot = BladeElementRotor.from_aerodyn(nrel5mw_aerodyn(), hub_radius=1.5, precone=math.radians(-2.5), n_blades=3)
    assert rot.dbemt_mode == 2 and rot.tau1_const == 4.0
    assert rot.state_names[:2] == ("B1N1_vind_x", "B1N1_vind_y") and len(rot.state_names) == 228
    quasi = BladeElementRotor.from_aerodyn(nrel5mw_aerodyn(), hub_radius=1.5, precone=math.radians(-2.5),
                                           n_blades=3, dynamic_wake=False)
    assert quasi.state_names == ()
