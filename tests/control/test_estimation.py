"""EKF/UKF equal the Kalman filter on a linear model; MHE recovers states, unknown inputs and parameters.

References: the Kalman filter recursion written out below with the exact discrete matrices of RK4
on a linear model (independent of mbsym.control); the true simulated states for noise-free data.
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control.discretize import discretize
from mbsym.control.estimation import EKF, UKF
from mbsym.control.mhe import MHE
from mbsym.control.models import cart_double_pendulum

A = np.array([[0.0, 1.0], [-4.0, -0.4]])
B = np.array([[0.0], [1.0]])
C = np.array([[1.0, 0.0]])
DT = 0.05


def oscillator() -> mb.Dynamics:
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 0)
    f = ca.Function("osc", [x, u, p], [ca.mtimes(ca.DM(A), x) + ca.mtimes(ca.DM(B), u)])
    y = ca.Function("osc_y", [x, u, p], [x[0]])
    return mb.Dynamics(f, states=["pos", "vel"], inputs=["force"], outputs=y, output_names=["pos_meas"])


def rk4(h):
    M = h * A
    I = np.eye(2)
    return (I + M + M @ M / 2 + M @ M @ M / 6 + M @ M @ M @ M / 24,
            h * (I + M / 2 + M @ M / 6 + M @ M @ M / 24) @ B)


def kalman(ys, us, x0, P0, Q, R):
    """The textbook Kalman filter (first sample: update only)."""
    Ad, Bd = rk4(DT)
    x, P, out = x0.copy(), P0.copy(), []
    for k, (y, u) in enumerate(zip(ys, us)):
        if k:
            x = Ad @ x + Bd @ u
            P = Ad @ P @ Ad.T + Q
        S = C @ P @ C.T + R
        K = P @ C.T @ np.linalg.inv(S)
        x = x + K @ (y - C @ x)
        P = (np.eye(2) - K @ C) @ P
        out.append((x.copy(), P.copy()))
    return out


@pytest.fixture(scope="module")
def data():
    rng = np.random.default_rng(1)
    Ad, Bd = rk4(DT)
    x, xs, ys, us = np.array([1.0, 0.0]), [], [], []
    for k in range(60):
        u = np.array([np.sin(0.3 * k)])
        xs.append(x.copy())
        ys.append(C @ x + 0.05 * rng.standard_normal(1))
        us.append(u)
        x = Ad @ x + Bd @ u + np.array([0.0, 0.02]) * rng.standard_normal(2)
    return np.array(xs), ys, us


@pytest.mark.parametrize("cls,tol", [(EKF, 1e-10), (UKF, 1e-8)])
def test_filters_equal_kalman_on_linear_model(cls, tol, data):
    _, ys, us = data
    Q, R, P0 = np.diag([0.0, 0.02 ** 2]), np.array([[0.05 ** 2]]), np.diag([0.5, 0.5])
    ref = kalman(ys, [np.zeros(1)] + us[:-1], np.zeros(2), P0, Q, R)
    f = cls(oscillator(), dt=DT, measurements=["pos_meas"], process_noise={"vel": 0.02},
            measurement_noise={"pos_meas": 0.05}, x0=[0.0, 0.0], P0=P0)
    for k, (y, u) in enumerate(zip(ys, [np.zeros(1)] + us[:-1])):
        x = f.step(y, u)
        np.testing.assert_allclose(x, ref[k][0], atol=tol)
        np.testing.assert_allclose(f.P, ref[k][1], atol=tol)


@pytest.mark.parametrize("solver", ["sqp", "ipopt"])
def test_mhe_recovers_state_noise_free(solver):
    """Noise-free data, wrong prior (weak): the estimate at the last sample equals the true state (1e-6)."""
    dyn = cart_double_pendulum()
    disc = discretize(dyn.rhs, DT)
    p = dyn.parameter_vector()
    x = np.array([0.0, 0.3, -0.2, 0.1, 0.0, 0.0])
    mhe = MHE(dyn, dt=DT, window=10, measurements=["cart", "angle2", "a1"],
              process_noise={"s_d": 0.01, "a1_d": 0.01, "a2_d": 0.01},
              measurement_noise={"cart": 1e-3, "angle2": 1e-3, "a1": 1e-3}, x0=np.zeros(6),
              P0={n: 10.0 for n in dyn.states}, solver=solver, compile=False)
    u_last = np.zeros(1)
    for k in range(25):
        y = dyn.output_value(x, u_last)
        z = mhe.step([y[0], y[3], x[1]], u_last)          # measured at the current sample
        u = np.array([0.5 * np.sin(2.0 * k * DT)])
        x_now = x.copy()
        x = np.asarray(disc.step(x, [], u, p)).ravel()
        u_last = u
    assert mhe.failures == 0, [s.status for s in mhe.stats]
    np.testing.assert_allclose(z, x_now, atol=1e-6)


def test_mhe_rti_estimates_unknown_input_and_parameter():
    """A constant unknown input (random walk) and the spring constant of the oscillator, noise-free (1e-4)."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 2), ca.SX.sym("p", 1)
    f = ca.Function("osc", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0] - 0.4 * x[1] + u[0] + u[1])])
    dyn = mb.Dynamics(f, states=["pos", "vel"], inputs=["force", "disturbance"], parameters=["k"],
                      defaults={"k": 3.0})
    true_k, true_d = 4.0, 0.7
    disc = discretize(f, DT)
    mhe = MHE(dyn, dt=DT, window=30, measurements=["pos"], unknown_inputs=["disturbance"], parameters=["k"],
              process_noise={"vel": 1e-3, "disturbance": 1e-3, "k": 1e-3}, measurement_noise={"pos": 1e-4},
              x0=[0.0, 0.0, 0.0, 3.0], P0={"pos": 1.0, "vel": 1.0, "disturbance": 1.0, "k": 2.0}, compile=False)
    xk, u_last = np.array([1.0, 0.0]), np.zeros(1)
    for k in range(120):
        z = mhe.step([xk[0]], u_last)
        u_k = np.array([np.sin(0.7 * k * DT)])
        xk = np.asarray(disc.step(xk, [], np.concatenate([u_k, [true_d]]), [true_k])).ravel()
        u_last = u_k
    assert mhe.failures == 0
    assert mhe.names == ("pos", "vel", "disturbance", "k")
    np.testing.assert_allclose(z[2:], [true_d, true_k], atol=1e-4)
