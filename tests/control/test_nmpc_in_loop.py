"""An NMPC, alone or with a state estimator, as ``controller=`` of mbsym.simulate (issue 22, item 10).

References: a hand-written sampled loop with fresh copies of the same NMPC (and EKF) and the exact
zero-order-hold discretization of the double integrator (x⁺ = [p + v T + u T²/2, v + u T]); RK4 is exact
on it (the solution is quadratic in time), so simulate's states at the sample times equal the loop's to
round-off of the solver (1e-9 m). The closed loop drives the position to the origin (the NMPC's reference).
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.control import EKF, NMPC, OCP
from mbsym.exceptions import ControlDefinitionError

T = 0.1


def _plant():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u"), ca.SX.sym("p", 0)
    return mb.Dynamics(ca.Function("f", [x, u, p], [ca.vertcat(x[1], u)]), states=["pos", "vel"], inputs=["force"])


def _mpc(dyn):
    ocp = OCP(dyn, horizon=20, dt=T).track({"pos": 1.0, "vel": 0.1, "force": 0.01}).bound("force", -1, 1)
    return NMPC(ocp, compile=False)


def _ekf(dyn):
    return EKF(dyn, dt=T, measurements=["pos"], process_noise={"vel": 1e-4}, measurement_noise={"pos": 1e-4},
               x0=[1.0, 0.4])                                 # a wrong speed to start with


def _hand_loop(n, mpc, ekf=None):
    x, u_last, xs = np.array([1.0, 0.0]), np.zeros(1), []
    for _ in range(n):
        xs.append(x.copy())
        est = x if ekf is None else ekf.step([x[0]], u_last)
        u = mpc.step(est)
        x = np.array([x[0] + x[1] * T + 0.5 * u[0] * T**2, x[1] + u[0] * T])
        u_last = u
    return np.array(xs)


@pytest.mark.parametrize("with_estimator", [False, True])
def test_nmpc_is_a_controller(with_estimator):
    dyn = _plant()
    n = 60
    controller = (_ekf(dyn), _mpc(dyn)) if with_estimator else _mpc(dyn)
    res = mb.simulate(dyn, n * T, x0=[1.0, 0.0], controller=controller, t_out=np.arange(n) * T)
    ref = _hand_loop(n, _mpc(dyn), _ekf(dyn) if with_estimator else None)
    np.testing.assert_allclose(res.state("pos"), ref[:, 0], atol=1e-9)
    np.testing.assert_allclose(res.state("vel"), ref[:, 1], atol=1e-9)
    assert abs(ref[-1, 0]) < 0.05


def test_estimator_that_does_not_fit_is_refused():
    dyn = _plant()
    ekf = EKF(dyn, dt=0.2, measurements=["pos"], process_noise={"vel": 1e-4}, measurement_noise={"pos": 1e-4})
    with pytest.raises(ControlDefinitionError, match="sample time 0.2 s differs"):
        mb.simulate(dyn, 1.0, controller=(ekf, _mpc(dyn)))


def test_python_controller_on_a_model_with_parameters():
    """A Python-callable law on a model with parameters (the cart double pendulum) equals the same law as a CasADi
    Function (the generated loop), both with RK4 steps of 0.01 s: two implementations of the sampled loop, to 1e-9. Before the fix the callable
    path read freed memory for the parameters and the states went NaN after the first sample."""
    from mbsym.control.models import cart_double_pendulum
    from mbsym.simulate import DiscreteController

    dyn = cart_double_pendulum()
    gains = np.array([-2.0, 0.0, 0.0, -3.0, 0.0, 0.0])          # PD on the cart position

    def law(t, xc, y):
        return xc, np.array([gains @ y])

    xc, y = ca.SX.sym("xc", 0), ca.SX.sym("y", 6)
    function = ca.Function("pd", [xc, y], [xc, ca.mtimes(ca.DM(gains).T, y)])
    x0 = [0.5, 0.1, -0.1, 0.0, 0.0, 0.0]
    runs = [mb.simulate(dyn, 2.0, x0=x0, inputs={"F": 0.0}, t_out=np.linspace(0, 2, 41), method="rk4", dt=0.01,
                        controller=DiscreteController(f, 0.05, measurements=list(dyn.states), actuates=["F"]))
            for f in (law, function)]
    assert np.all(np.isfinite(runs[0].x))
    np.testing.assert_allclose(runs[0].x, runs[1].x, atol=1e-9)
