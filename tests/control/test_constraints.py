"""Bounds, rate limits, soft bounds, general constraints and costs hold, and agree across solvers.

References: the constraint values themselves (checked on the returned plan to 1e-6), and the
converged ipopt solution of the same OCP (independent NLP solver; 1e-5 on the first input).
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control import NMPC, OCP


def double_integrator() -> mb.Dynamics:
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    f = ca.Function("di", [x, u, p], [ca.vertcat(x[1], u)])
    y = ca.Function("di_y", [x, u, p], [ca.vertcat(x[0] + 0.5 * x[1], u)])
    return mb.Dynamics(f, states=["pos", "vel"], inputs=["acc"], outputs=y, output_names=["lead", "acc_out"])


X0 = np.array([1.0, 0.0])


def base(N=15):
    return OCP(double_integrator(), horizon=N, dt=0.1).track({"pos": 10.0, "vel": 1.0, "acc": 0.01})


@pytest.mark.parametrize("solver", ["sqp", "rti"])
def test_rate_limit_output_bound_and_general_constraint(solver):
    ocp = (base().bound("acc", -3.0, 3.0).limit_rate("acc", -20.0, 20.0).bound("lead", 0.0, None)
           .constrain(lambda x, u, p: x[1] - 0.5 * u[0], -2.0, 2.0, name="mixed")
           .constrain(lambda x, p: x[0], -0.3, 0.3, terminal=True, name="final position"))
    mpc = NMPC(ocp, solver=solver, compile=False, u_prev=[0.0])
    u = mpc.step(X0)
    assert mpc.stats[-1].success, mpc.stats[-1].status
    pred = mpc.prediction()
    X, U = pred["x"], pred["u"][0]
    rates = np.diff(np.concatenate([[0.0], U])) / 0.1
    assert np.all(np.abs(U) <= 3.0 + 1e-6) and np.all(np.abs(rates) <= 20.0 + 1e-6)
    assert np.all(X[0, 1:] + 0.5 * X[1, 1:] >= -1e-6)                # output bound where a control acts
    assert np.all(np.abs(X[1, :-1] - 0.5 * U) <= 2.0 + 1e-6)
    assert abs(X[0, -1]) <= 0.3 + 1e-6
    ref = NMPC(ocp, solver="ipopt", compile=False, u_prev=[0.0]).step(X0)
    np.testing.assert_allclose(u, ref, atol=1e-5)


def test_soft_bound_is_exact_when_feasible_and_keeps_infeasible_problems_solvable():
    hard = NMPC(base().bound("vel", -0.5, None), solver="sqp", compile=False).step(X0)
    soft = NMPC(base().bound("vel", -0.5, None, soft=(1e3, 1e3)), solver="sqp", compile=False).step(X0)
    np.testing.assert_allclose(soft, hard, atol=1e-6)            # exact penalty: same solution
    impossible = base().bound("pos", 5.0, None, soft=(10.0, 10.0)).bound("acc", -0.1, 0.1)
    mpc = NMPC(impossible, solver="sqp", compile=False)
    mpc.step(X0)
    assert mpc.stats[-1].success and mpc.stats[-1].violation < 1e-6        # the relaxed problem is feasible
    hard_fail = NMPC(base().bound("pos", 5.0, None).bound("acc", -0.1, 0.1), solver="sqp", compile=False)
    hard_fail.step(X0)
    assert not hard_fail.stats[-1].success


def test_general_cost_matches_equivalent_tracking():
    """add_cost(stage=w (x−r)²) equals track({name: w}, reference=r) (1e-8)."""
    a = NMPC(OCP(double_integrator(), horizon=10, dt=0.1).track({"vel": 1.0, "acc": 0.01})
             .add_cost(stage=lambda x, u, p: 10.0 * (x[0] - 0.3) ** 2,
                       terminal=lambda x, p: 10.0 * (x[0] - 0.3) ** 2), solver="sqp", compile=False).step(X0)
    b = NMPC(OCP(double_integrator(), horizon=10, dt=0.1).track({"vel": 1.0, "acc": 0.01})
             .track({"pos": 10.0}, reference={"pos": 0.3}).track({"pos": 10.0}, reference={"pos": 0.3}, terminal=True),
             solver="sqp", compile=False).step(X0)
    np.testing.assert_allclose(a, b, atol=1e-8)


def test_preview_and_reference_enter_the_problem():
    """A previewed disturbance input shifts the optimal control exactly (linear model: u* + d = same)."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 2), ca.SX.sym("p", 0)
    f = ca.Function("di", [x, u, p], [ca.vertcat(x[1], u[0] + u[1])])
    dyn = mb.Dynamics(f, states=["pos", "vel"], inputs=["acc", "push"], u0=[0.0, 0.0])
    ocp = OCP(dyn, horizon=10, dt=0.1, controls=["acc"]).track({"pos": 10.0, "vel": 1.0})
    mpc = NMPC(ocp, solver="sqp", compile=False)
    u_zero = mpc.step(X0, preview={"push": 0.0})
    u_push = mpc.step(X0, preview={"push": 0.7})
    np.testing.assert_allclose(u_push, u_zero - 0.7, atol=1e-8)   # no control cost: the push is cancelled
    mpc2 = NMPC(OCP(dyn, horizon=10, dt=0.1, controls=["acc"]).track({"pos": 10.0, "vel": 1.0, "acc": 0.01}),
                solver="sqp", compile=False)
    u_ref = mpc2.step([1.3, 0.0], reference={"pos": 0.3})
    u_0 = mpc2.step([1.0, 0.0], reference={"pos": 0.0})
    np.testing.assert_allclose(u_ref, u_0, atol=1e-8)             # shifting state and reference together
