"""NMPC on the cart double pendulum reaches the upright target.

The plant is integrated independently of the controller's RK4 (scipy's DOP853, rtol 1e-9), so
the test also covers model-discretization mismatch. Target: both links upright and the cart at
0 within 0.02 (rad, m) after 3 s; the input bound |F| ≤ 20 N is never exceeded.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from mbsym.control import NMPC, OCP
from mbsym.control.models import cart_double_pendulum

DYN = cart_double_pendulum()
P = DYN.parameter_vector()


def plant_step(x, u, dt):
    sol = solve_ivp(lambda t, z: np.asarray(DYN.rhs(z, u, P)).ravel(), (0.0, dt), x, method="DOP853",
                    rtol=1e-9, atol=1e-11)
    return sol.y[:, -1]


def balance_ocp(N=30):
    return (OCP(DYN, horizon=N, dt=0.05)
            .track({"s": 1.0, "a1": 10.0, "a2": 10.0, "s_d": 0.1, "a1_d": 0.1, "a2_d": 0.1, "F": 1e-3})
            .track({"s": 10.0, "a1": 100.0, "a2": 100.0, "s_d": 1.0, "a1_d": 1.0, "a2_d": 1.0}, terminal=True)
            .bound("F", -20, 20))


@pytest.mark.parametrize("solver", ["rti", pytest.param("sqp", marks=pytest.mark.slow)])
def test_balances_from_tilted_start(solver):
    mpc = NMPC(balance_ocp(), solver=solver, compile=False)
    x = np.array([0.0, 0.3, -0.2, 0.0, 0.0, 0.0])
    us = []
    for _ in range(60):
        u = mpc.step(x)
        us.append(u[0])
        x = plant_step(x, u, 0.05)
    assert mpc.failures == 0, [s.status for s in mpc.stats]
    assert np.max(np.abs(x[:3])) < 0.02, x
    assert np.max(np.abs(us)) <= 20.0 + 1e-6


def test_prepare_then_feedback_equals_step():
    """RTI split: prepare() before the measurement, then step(); same input as a plain step (1e-12)."""
    x = np.array([0.0, 0.2, 0.0, 0.0, 0.0, 0.0])
    a, b = NMPC(balance_ocp(), compile=False), NMPC(balance_ocp(), compile=False)
    ua = a.step(x)
    b.step(x)
    x = plant_step(x, ua, 0.05)
    b.prepare()
    assert b.stats[-1].preparation_s >= 0.0
    np.testing.assert_allclose(b.step(x), a.step(x), atol=1e-12)
    assert b.stats[-1].preparation_s == 0.0 and a.stats[-1].preparation_s > 0.0


def test_controller_protocol_and_prediction():
    mpc = NMPC(balance_ocp(N=20), compile=False)
    u = mpc(0.0, np.array([0.0, 0.1, 0.0, 0.0, 0.0, 0.0]))
    assert mpc.inputs == ("F",) and mpc.sample_time == 0.05 and u.shape == (1,)
    pred = mpc.prediction()
    assert pred["x"].shape == (6, 21) and pred["u"].shape == (1, 20)
    np.testing.assert_allclose(pred["x"][:, 0], [0.0, 0.1, 0.0, 0.0, 0.0, 0.0], atol=1e-9)
    s = mpc.summary()
    assert s["steps"] == 1 and s["failures"] == 0
