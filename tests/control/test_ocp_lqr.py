"""OCP on a linear system equals the finite-horizon Riccati / LQR solution, for every solver path.

Reference (independent of mbsym.control): the discrete model of RK4 on a linear system is exactly
``x+ = Ad x + Bd u`` with the polynomials below (classical RK4 on ẋ = A x + B u, u held); the
finite-horizon LQR is the backward Riccati recursion; the infinite-horizon gain comes from
python-control's ``dlqr``. Tolerances: 1e-6 on the first control (solver tolerances ~1e-8).
"""

import casadi as ca
import control
import numpy as np
import pytest
from scipy.linalg import expm

import mbsym as mb
from mbsym.control import NMPC, OCP

A = np.array([[0.0, 1.0, 0.0], [-2.0, -0.3, 1.0], [0.0, 0.0, -0.5]])
B = np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.5]])
Q = np.diag([2.0, 0.5, 1.0])
R = np.diag([0.1, 0.3])
DT, N = 0.1, 15
X0 = np.array([1.0, -0.5, 0.3])


def linear_dynamics() -> mb.Dynamics:
    x, u, p = ca.SX.sym("x", 3), ca.SX.sym("u", 2), ca.SX.sym("p", 0)
    f = ca.Function("linear", [x, u, p], [ca.mtimes(ca.DM(A), x) + ca.mtimes(ca.DM(B), u)])
    return mb.Dynamics(f, states=["x1", "x2", "x3"], inputs=["u1", "u2"])


def rk4_matrices(h: float):
    """RK4 applied to a linear system: Ad = Σ (hA)^k/k!, k ≤ 4; Bd = h Σ (hA)^k/(k+1)! B, k ≤ 3."""
    M = h * A
    I = np.eye(3)
    Ad = I + M + M @ M / 2 + M @ M @ M / 6 + M @ M @ M @ M / 24
    Bd = h * (I + M / 2 + M @ M / 6 + M @ M @ M / 24) @ B
    return Ad, Bd


def riccati_first_gain(Ad, Bd, QN):
    P = QN
    K = None
    for _ in range(N):
        K = np.linalg.solve(R + Bd.T @ P @ Bd, Bd.T @ P @ Ad)
        P = Q + Ad.T @ P @ (Ad - Bd @ K)
    return K


def make_ocp(method="rk4", terminal=None):
    ocp = OCP(linear_dynamics(), horizon=N, dt=DT, method=method)
    ocp.track(names=["x1", "x2", "x3"], matrix=Q).track(names=["u1", "u2"], matrix=R)
    ocp.track(names=["x1", "x2", "x3"], matrix=Q if terminal is None else terminal, terminal=True)
    return ocp


@pytest.fixture(scope="module")
def reference():
    Ad, Bd = rk4_matrices(DT)
    return -riccati_first_gain(Ad, Bd, Q) @ X0


SOLVER_PATHS = [
    ("rti", "hpipm"), ("sqp", "hpipm"), ("sqp", "qrqp"), ("sqp", "osqp"), ("sqp", "daqp"), ("sqp", "qpoases"),
    ("ipopt", "hpipm"), ("fatrop", "hpipm"), ("sqpmethod", "hpipm"), ("sqpmethod", "qrqp"),
]


@pytest.mark.parametrize("solver,qp_solver", SOLVER_PATHS)
def test_first_control_equals_riccati(solver, qp_solver, reference):
    """Every solver path gives u0 = −K0 x0 of the finite-horizon Riccati recursion (tolerance 1e-6)."""
    opts = {"osqp": {"eps_abs": 1e-10, "eps_rel": 1e-10}} if qp_solver == "osqp" and solver == "sqp" else None
    mpc = NMPC(make_ocp(), solver=solver, qp_solver=qp_solver, compile=False, solver_options=opts)
    u = mpc.step(X0)
    assert mpc.stats[-1].success, mpc.stats[-1].status
    np.testing.assert_allclose(u, reference, atol=1e-6)


def test_whole_trajectory_and_gauss_newton_ipopt(reference):
    """ipopt with the Gauss–Newton Hessian: the predicted states follow Ad x + Bd u exactly (1e-9)."""
    mpc = NMPC(make_ocp(), solver="ipopt", hessian="gauss-newton", compile=False)
    u = mpc.step(X0)
    np.testing.assert_allclose(u, reference, atol=1e-6)
    pred = mpc.prediction()
    Ad, Bd = rk4_matrices(DT)
    X, U = pred["x"], pred["u"]
    np.testing.assert_allclose(X[:, 1:], Ad @ X[:, :-1] + Bd @ U, atol=1e-9)


def test_terminal_weight_dare_gives_lqr_gain():
    """With the DARE solution as terminal weight the first control is the infinite-horizon LQR (python-control)."""
    Ad, Bd = rk4_matrices(DT)
    K, P, _ = control.dlqr(Ad, Bd, Q, R)
    mpc = NMPC(make_ocp(terminal=P), solver="sqp", compile=False)
    np.testing.assert_allclose(mpc.step(X0), -np.asarray(K) @ X0, atol=1e-6)


def test_collocation_close_to_exact_discretization():
    """Radau IIA (order 5) collocation vs the Riccati solution of the exact ZOH model (expm): 1e-5."""
    M = expm(np.block([[A, B], [np.zeros((2, 5))]]) * DT)
    Ad, Bd = M[:3, :3], M[:3, 3:]
    ref = -riccati_first_gain(Ad, Bd, Q) @ X0
    mpc = NMPC(make_ocp(method="collocation"), solver="ipopt", compile=False)
    np.testing.assert_allclose(mpc.step(X0), ref, atol=1e-5)


def test_rti_compiled_matches_reference(reference):
    """The compiled preparation Function (generated C) gives the same first control (1e-6)."""
    mpc = NMPC(make_ocp(), solver="rti", compile=True)
    np.testing.assert_allclose(mpc.step(X0), reference, atol=1e-6)


@pytest.mark.parametrize("solver", ["rti", "fatrop"])
def test_collocation_structure_exploiting_solvers(solver):
    """Lifted collocation variables as stage controls (hpipm, fatrop): same result as ipopt (1e-6)."""
    ref = NMPC(make_ocp(method="collocation"), solver="ipopt", compile=False).step(X0)
    np.testing.assert_allclose(NMPC(make_ocp(method="collocation"), solver=solver, compile=False).step(X0), ref,
                               atol=1e-6)


def test_chained_sensitivities_equal_inline():
    """RK4 Jacobians by chained forward sensitivities give the same RTI step as AD of the expanded step (1e-10)."""
    from mbsym.control.models import cart_double_pendulum
    dyn = cart_double_pendulum()
    x0 = np.array([0.1, 0.3, -0.2, 0.0, 0.1, 0.0])
    us = []
    for mode in ("inline", "chained"):
        ocp = OCP(dyn, horizon=10, dt=0.05, substeps=2, sensitivities=mode).track(
            {"s": 1.0, "a1": 10.0, "a2": 10.0, "s_d": 0.1, "F": 1e-3}).bound("F", -20, 20)
        assert (ocp.discretization.sensitivity is not None) == (mode == "chained")
        us.append(NMPC(ocp, solver="sqp", compile=False).step(x0))
    np.testing.assert_allclose(us[0], us[1], atol=1e-10)


@pytest.mark.parametrize("solver", ["ipopt", "fatrop"])
def test_compiled_nlp_functions_match_reference(solver, reference):
    """Compiled stage-level NLP Functions (mbsym.control.nlpfunctions) give the Riccati control (1e-6)."""
    mpc = NMPC(make_ocp(), solver=solver, compile=True)
    assert mpc.compiled
    np.testing.assert_allclose(mpc.step(X0), reference, atol=1e-6)
