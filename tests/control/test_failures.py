"""Failures are reported in the step status, never silent, and the documented fallback is applied.

Infeasible problem: a state bound x1 ≥ 5 reachable from x1 = 0 in neither 1 nor N steps with |u| ≤ 0.1
(reference: the reachable set of the double integrator, |x1(N dt)| ≤ ½ 0.1 (N dt)² = 0.05 m).
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control import NMPC, OCP


def double_integrator(nan: bool = False) -> mb.Dynamics:
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    acc = ca.sqrt(x[0] - 10.0) if nan else u          # NaN for x1 < 10: a broken model
    f = ca.Function("di", [x, u, p], [ca.vertcat(x[1], acc)])
    return mb.Dynamics(f, states=["x1", "x2"], inputs=["u"])


def base_ocp(dyn=None, N=10):
    return (OCP(dyn or double_integrator(), horizon=N, dt=0.1)
            .track({"x1": 1.0, "x2": 0.1, "u": 0.01}).bound("u", -0.1, 0.1))


@pytest.mark.parametrize("solver", ["rti", "sqp", "ipopt", "fatrop", "sqpmethod"])
def test_infeasible_reports_failure_and_holds_input(solver):
    mpc = NMPC(base_ocp().bound("x1", 5.0, None), solver=solver, compile=False, max_iter=30, u_prev=[0.05])
    u = mpc.step([0.0, 0.0])
    st = mpc.stats[-1]
    assert not st.success and st.fallback and st.status.startswith("fallback")
    assert mpc.failures == 1
    np.testing.assert_allclose(u, [0.05])          # no plan yet: the last applied input is held


def test_fallback_uses_previous_plan_shifted():
    """After a success, a failing step applies the next input of the previous plan."""
    mpc = NMPC(base_ocp(), compile=False)
    mpc.step([1.0, 0.0])
    plan_u = mpc.prediction()["u"][0].copy()
    mpc.prepare(reference={"x1": np.full(11, 1e200)})       # absurd reference: inf/NaN in the QP
    u = mpc.step([1.0, 0.0])
    st = mpc.stats[-1]
    assert st.fallback and not st.success, st.status
    np.testing.assert_allclose(u, [plan_u[1]])


def test_nan_model_reported():
    mpc = NMPC(base_ocp(double_integrator(nan=True)), solver="rti", compile=False)
    mpc.step([0.0, 0.0])
    assert not mpc.stats[-1].success
    assert "nan" in mpc.stats[-1].status.lower() or "fail" in mpc.stats[-1].status.lower()


def test_max_iterations_reported():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    f = ca.Function("pend", [x, u, p], [ca.vertcat(x[1], -9.81 * ca.sin(x[0]) + u)])
    dyn = mb.Dynamics(f, states=["a", "w"], inputs=["u"])
    ocp = OCP(dyn, horizon=20, dt=0.1).track({"a": 1.0, "w": 0.1, "u": 0.01}, reference={"a": np.pi})
    mpc = NMPC(ocp, solver="sqp", max_iter=1, compile=False)
    mpc.step([0.0, 0.0])
    assert mpc.stats[-1].status == "fallback (max_iterations)"
