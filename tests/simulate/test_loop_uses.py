"""Every use of mbsym on a closed loop: simulation (all methods), linearization, modal analysis, export,
identification, NMPC, sweeps, static equilibrium, EKF.

Model: a four-bar (crank 1, coupler 2, rocker 2, ground link d [m]; rigid links, gravity -y) in mbsym's
contract form (``add_closure(..., directions="xy")``, ``equations(independent=["q1"], guess=...)``). The
coupler mass ``m2`` and the ground link ``d`` are parameters (the closure depends on one).

References and tolerances:

- energy: the linkage is conservative, so T + V is constant (invariant). A crank that turns ~3 times in
  5 s: rk4 at dt = 2 ms drifts ~1e-9 (measured 1.2e-9, bound 1e-8); CVODES/IDAS/Adams/scipy Radau/BDF at
  rtol 1e-10 stay below 1e-6; Newmark and generalized-α are second order: measured drift ~7e-5 at
  dt = 2 ms, bound 3e-4, and halving dt must divide it by ~4 (2.8 .. 5.7).
- linearization: A and B against central differences of ``eom.rhs`` (step 1e-6: truncation ~1e-12,
  round-off ~1e-10 relative; tolerance 1e-7 relative).
- modal analysis: the frequency of small oscillations about the gravity equilibrium against the period
  of a simulated small swing (amplitude 1e-3 rad: the nonlinear period shift is ~1e-7 relative; the
  zero-crossing interpolation ~1e-6; tolerance 1e-4).
- export: the numpy-only module against CasADi (1e-12 relative).
- identification: m2 and d recovered from CVODES data (rtol 1e-11) of q1 and the dependent q3 to the
  RK4 discretization of the fit (4 sub-steps of 5 ms: ~1e-6 relative).
- NMPC: a torque on the crank brings it to 1.5 rad (within 0.01 rad after 2 s), |τ| ≤ 30 N m.
- sweep, static equilibrium, EKF: see each test.

Runtime ~18 s (all eight integration methods ~6 s).
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import ExportError

X0 = {"q1": 0.3, "q1_d": 4.0}


def fourbar(torque: bool = False) -> mb.ClosedLoopEquations:
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    q1, q2, q3 = s.coordinates("q1 q2 q3")
    m2, d = s.parameters("m2 d", values=[2.0, 2.5])
    lengths = (1.0, 2.0, 2.0)
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l, m in zip(("crank", "coupler", "rocker"), (q1, q2, q3), lengths, (1.0, m2, 1.5)):
        body = mb.RigidBody(name, m, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.2, 0.2]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    s.add_closure(parent, [lengths[2], 0, 0], s.ground, [d, 0, 0], directions="xy")
    if torque:
        tau = s.inputs("tau")
        s.add_torque(s.body("crank"), [0, 0, tau])
    return s.equations(independent=["q1"], guess={"q2": 1.2, "q3": -2.4})


@pytest.fixture(scope="module")
def eom():
    return fourbar()


def _drift(eom, res):
    E = np.array([eom.kinetic_energy(q, qd) + eom.potential_energy(q) for q, qd in zip(res.q, res.qd)])
    return np.max(np.abs(E - E[0])) / E[0]


@pytest.mark.parametrize("method", ["adams", "cvodes", "idas", "scipy-radau", "scipy-bdf"])
def test_energy_conserved_adaptive(eom, method):
    res = mb.simulate(eom, 5.0, x0=X0, method=method, rtol=1e-10, atol=1e-10, dt=0.01)
    assert res.state("q1")[-1] > 0.3 + 4 * np.pi              # the crank turned twice or more
    assert _drift(eom, res) < 1e-6
    assert np.max(res.output("closure_residual")) < 1e-12


def test_energy_conserved_rk4(eom):
    res = mb.simulate(eom, 5.0, x0=X0, method="rk4", dt=0.002)
    assert _drift(eom, res) < 1e-8


@pytest.mark.parametrize("method", ["newmark", "generalized-alpha"])
def test_energy_second_order_methods(eom, method):
    coarse = _drift(eom, mb.simulate(eom, 3.0, x0=X0, method=method, dt=0.004))
    fine = _drift(eom, mb.simulate(eom, 3.0, x0=X0, method=method, dt=0.002))
    assert fine < 3e-4 and 2.8 < coarse / fine < 5.7, (coarse, fine)


def test_default_simulation_reports_dependent_coordinates(eom):
    res = mb.simulate(eom, 1.0, x0=X0)
    q = np.array([eom.configuration([v]) for v in res.state("q1")])
    assert np.max(np.abs(res.output("q3") - q[:, 2])) < 1e-12
    assert res.states == ("q1", "q1_d") and res.unit("q1") == "rad"


def test_linearization_matches_finite_differences():
    eom = fourbar(torque=True)
    x0, u0 = np.array([1.1, -2.0]), np.array([0.7])
    lin = mb.linearize(eom, [x0[0]], [x0[1]], u0, {})
    h = 1e-6
    f = lambda x, u: eom.rhs(x, u)                                                     # noqa: E731
    A = np.column_stack([(f(x0 + h * e, u0) - f(x0 - h * e, u0)) / (2 * h) for e in np.eye(2)])
    B = ((f(x0, u0 + h) - f(x0, u0 - h)) / (2 * h)).reshape(2, 1)
    assert np.allclose(lin.A, A, rtol=1e-7, atol=1e-7 * np.max(np.abs(A)))
    assert np.allclose(lin.B, B, rtol=1e-7, atol=1e-7 * np.max(np.abs(B)))


def test_modal_frequency_matches_small_swing(eom):
    from scipy.optimize import brentq

    acc = lambda q: eom.accelerations([q], [0.0])[0]                           # noqa: E731
    grid = np.linspace(-np.pi, np.pi, 73)
    k = next(i for i in range(72) if acc(grid[i]) > 0 >= acc(grid[i + 1]))   # restoring: the stable equilibrium
    qe = brentq(acc, grid[k], grid[k + 1], xtol=1e-14)
    lin = mb.linearize(eom, [qe], [0.0], [], {})
    mode = [m for m in lin.modes() if not m.rigid_body][0]
    res = mb.simulate(eom, 12.0, x0={"q1": qe + 1e-3, "q1_d": 0.0}, method="cvodes", rtol=1e-12, atol=1e-14,
                      dt=0.001)
    th, t = res.state("q1") - qe, res.t
    i = np.flatnonzero((th[:-1] > 0) & (th[1:] <= 0))
    crossings = t[i] - th[i] * (t[i + 1] - t[i]) / (th[i + 1] - th[i])
    assert mode.freq_hz == pytest.approx(1.0 / np.mean(np.diff(crossings)), rel=1e-4)


def test_export_python_agrees_and_latex_is_refused(eom, tmp_path):
    import importlib.util

    path = eom.export_python(tmp_path / "fourbar.py", functions=["rhs", "mass_matrix", "forcing"])
    spec = importlib.util.spec_from_file_location("fourbar_export", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    p = eom.parameter_vector()
    for x in ([0.3, 1.0], [2.5, -3.0], [-2.0, 0.5]):
        ref = np.asarray(eom.functions.rhs(x, [], p)).ravel()
        got = np.asarray(mod.rhs(np.array(x), np.zeros(0), p)).ravel()
        assert np.allclose(got, ref, rtol=1e-12, atol=1e-12 * np.max(np.abs(ref)))
    with pytest.raises(ExportError, match="no LaTeX form"):
        eom.latex()


def test_identification_recovers_coupler_mass_and_ground_link(eom):
    truth = {"m2": 2.0, "d": 2.5}
    out = mb.simulate(eom, 4.0, x0={"q1": 0.5, "q1_d": 0.0}, p=truth, method="cvodes", dt=0.02, rtol=1e-11,
                      atol=1e-12)
    data = {"time": out.t, "q1": out.state("q1"), "q3": out.output("q3")}
    res = mb.identify(eom, data, ["m2", "d"], initial={"m2": 1.7, "d": 2.45}, x0={"q1": 0.5, "q1_d": 0.0},
                      substeps=4, compile=False)
    assert res.success, res.message
    assert res.parameters["m2"] == pytest.approx(2.0, rel=1e-5)
    assert res.parameters["d"] == pytest.approx(2.5, rel=1e-6)


def test_nmpc_positions_the_crank():
    from mbsym.control import NMPC, OCP

    eom = fourbar(torque=True)
    ocp = (OCP(eom, horizon=20, dt=0.05).track({"q1": 10.0, "q1_d": 0.1, "tau": 1e-3}, reference={"q1": 1.5})
           .bound("tau", -30, 30))
    mpc = NMPC(ocp, compile=False)
    x, taus = np.array([0.2, 0.0]), []
    for _ in range(40):
        u = mpc.step(x)
        taus.append(float(u[0]))
        x = mb.simulate(eom, 0.05, x0=x, inputs={"tau": taus[-1]}, method="cvodes", rtol=1e-10, atol=1e-12).x[-1]
    assert mpc.failures == 0
    assert abs(x[0] - 1.5) < 0.01 and max(abs(v) for v in taus) <= 30 + 1e-6


def test_nine_independent_coordinates_numeric_solve():
    """Beyond 8 independent coordinates (the rhs and outputs solve M_r numerically): a chain of 8 pendulum
    links hanging from the coupler; energy conserved over 0.5 s of rk4 at 5 ms (measured 2e-9, bound 1e-7)."""
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    q1, q2, q3 = s.coordinates("q1 q2 q3")
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l in zip(("crank", "coupler", "rocker"), (q1, q2, q3), (1.0, 2.0, 2.0)):
        body = mb.RigidBody(name, 1.0, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.1, 0.1]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    s.add_closure(parent, [2.0, 0, 0], s.ground, [2.5, 0, 0], directions="xy")
    names = [f"p{i}" for i in range(8)]
    parent = s.body("coupler")
    for i, c in enumerate(s.coordinates(names)):
        b = mb.RigidBody(f"pend{i}", 0.1, com=[0, -0.2, 0], inertia=np.diag([1e-3] * 3))
        offset = [0.0, -0.2, 0.0] if i else [1.0, 0.0, 0.0]
        s.add_joint(mb.Revolute(parent, b, axis=[0, 0, 1], coordinate=c, offset=offset))
        parent = b
    eom = s.equations(independent=["q1", *names], guess={"q2": 1.2, "q3": -2.4})
    res = mb.simulate(eom, 0.5, x0={"q1": 0.3, "q1_d": 1.0, "p3": 0.2}, method="rk4", dt=0.005)
    assert eom.n_q == 9 and np.max(res.output("closure_residual")) < 1e-12
    assert _drift(eom, res) < 1e-7


def test_sweep_over_the_ground_link_matches_single_runs(eom):
    """mb.sweep varies a closure parameter (the ground link d): each row's statistics of the dependent
    coordinate q3 equal a direct simulation with that d (the same rk4 run: 1e-12)."""
    kw = dict(x0={"q1": 0.3, "q1_d": 1.0})
    res = mb.sweep(eom, {"d": [2.4, 2.6]}, tmax=1.0, dt=0.01, channels=["q3"], **kw)
    assert res.table.failed == []
    for row in res.table:
        q3 = mb.simulate(eom, 1.0, p={"d": row["d"]}, method="rk4", dt=0.01, **kw).output("q3")
        assert row["q3_max"] == pytest.approx(np.max(q3), abs=1e-12)
        assert row["q3_min"] == pytest.approx(np.min(q3), abs=1e-12)


def test_static_equilibrium_and_ekf_on_the_dependent_coordinate(eom):
    """static_equilibrium finds a rest point (M_r⁻¹F_r = 0 there: 1e-10); an EKF measuring only the dependent
    rocker angle q3 (σ = 1 mrad) tracks the crank angle q1 of a CVODES run to ~mrad (bound 0.01 rad)."""
    from mbsym.control import EKF

    eq = mb.static_equilibrium(eom, q0=[1.0])
    assert eq.success and abs(eom.accelerations(eq.q, [0.0])[0]) < 1e-10
    true = mb.simulate(eom, 2.0, x0={"q1": 0.5, "q1_d": 0.0}, method="cvodes", rtol=1e-10, atol=1e-12, dt=0.01)
    ekf = EKF(eom, dt=0.01, measurements=["q3"], process_noise={"q1_d": 0.1}, measurement_noise={"q3": 1e-3},
              x0=[0.45, 0.0])
    rng = np.random.default_rng(0)
    est = [ekf.step(np.array([y + rng.normal(0, 1e-3)]), np.zeros(0)) for y in true.output("q3")[1:]]
    assert np.max(np.abs(np.array(est)[-100:, 0] - true.state("q1")[-100:])) < 0.01
