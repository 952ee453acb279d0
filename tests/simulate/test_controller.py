"""Discrete controllers in the loop (issue 12.5, general part): sampled-data closed loops against their
exact discrete-time equivalents.

References (independent of mbsym): a first-order plant under a discrete PI controller, whose closed loop at
the sample times is the exact zero-order-hold recurrence x+ = phi x + gamma u (phi = exp(-a T), gamma =
b (1 - phi) / a; Franklin, Powell & Workman, Digital Control, ch. 4); the damped oscillator of conftest under
a sampled-data LQR, against python-control's ZOH discretization (control.c2d), dlqr gain and discrete initial
response. The plant is integrated by RK4 sub-steps: with 40-50 per sample its error is below 1e-9, the
tolerance used.
"""

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.simulate import DiscreteController, SimulationOptionError, simulate
from mbsym.simulate.auto import epsilon

from .conftest import OSC

A_PLANT, B_PLANT, T_S, KP, KI, REF = 2.0, 3.0, 0.1, 0.5, 1.5, 1.0


def first_order_plant():
    """x' = -a x + b u + d, output y2 = 2 x (a named output, to be measured too)."""
    x, u, p = ca.SX.sym("x"), ca.SX.sym("u", 2), ca.SX.sym("p", 0)
    f = ca.Function("f", [x, u, p], [-A_PLANT * x + B_PLANT * u[0] + u[1]])
    h = ca.Function("h", [x, u, p], [2 * x])
    return mb.Dynamics(f, states=["x"], inputs=["u", "d"], outputs=h, output_names=["y2"], output_units=["m"],
                       name="first_order")


def pi_law():
    I, y = ca.SX.sym("I"), ca.SX.sym("y")
    e = REF - y
    return ca.Function("PI", [I, y], [I + T_S * e, KP * e + KI * (I + T_S * e)])


def exact_pi(n):
    phi = np.exp(-A_PLANT * T_S)
    gamma = B_PLANT * (1 - phi) / A_PLANT
    x, I, us = [0.0], [0.0], []
    for _ in range(n):
        e = REF - x[-1]
        I.append(I[-1] + T_S * e)
        us.append(KP * e + KI * I[-1])
        x.append(phi * x[-1] + gamma * us[-1])
    return np.array(x), np.array(I), np.array(us)


def test_discrete_pi_matches_the_exact_zoh_recurrence():
    n = 50
    ctrl = DiscreteController(pi_law(), T_S, measurements=["x"], actuates=["u"], state_names=["I"])
    res = simulate(first_order_plant(), n * T_S, controller=ctrl, method="rk4", dt=T_S / 50,
                   t_out=np.arange(n + 1) * T_S)
    x, I, us = exact_pi(n)
    np.testing.assert_allclose(res.state("x"), x, atol=1e-9)
    np.testing.assert_allclose(res.output("I")[:-1], I[1:], atol=1e-9)        # state after each sample
    np.testing.assert_allclose(res.u[:-1, 0], us, atol=1e-9)                   # held input, right-continuous
    assert res.output_names == ("y2", "I") and res.units == {"y2": "m", "I": ""}
    s = res.statistics
    assert s["controller_samples"] == n and s["substeps"] == 50 and s["method"] == "rk4"


def test_input_is_held_between_samples():
    ctrl = DiscreteController(pi_law(), T_S, measurements=["x"], actuates=["u"])
    t_out = np.linspace(0.0, 1.0, 101)                                         # 10 outputs per sample
    res = simulate(first_order_plant(), 1.0, controller=ctrl, t_out=t_out)
    u = res.u[:-1, 0].reshape(10, 10)
    np.testing.assert_array_equal(u, np.repeat(u[:, :1], 10, axis=1))
    assert len(np.unique(u[:, 0])) == 10


def test_python_callable_equals_the_function_law():
    law = pi_law()

    def py_law(t, xc, y):
        a, b = law(xc, y)
        return np.array(a).reshape(-1), np.array(b).reshape(-1)

    kw = dict(measurements=["y2"], actuates=["u"], state_names=["I"])
    f_ctrl = DiscreteController(law, T_S, **kw)
    p_ctrl = DiscreteController(py_law, T_S, [0.0], **kw)
    inputs = {"d": lambda t: 0.3 * np.sin(2.0 * t)}                            # exogenous, alongside the controller
    r1 = simulate(first_order_plant(), 3.05, controller=f_ctrl, inputs=inputs, method="rk4", dt=T_S / 4)
    r2 = simulate(first_order_plant(), 3.05, controller=p_ctrl, inputs=inputs, method="rk4", dt=T_S / 4)
    np.testing.assert_allclose(r2.x, r1.x, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r2.y, r1.y, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r2.u, r1.u, rtol=0, atol=1e-13)
    np.testing.assert_allclose(r1.u[:, 1], 0.3 * np.sin(2.0 * r1.t), atol=1e-15)
    assert r1.t[-1] == 3.05 and r1.statistics["controller_samples"] == 31        # a shorter last sample


def test_sampled_data_lqr_matches_python_control():
    control = pytest.importorskip("control")
    m, k, c = OSC["m"], OSC["k"], OSC["c"]
    A = np.array([[0.0, 1.0], [-k / m, -c / m]])
    B = np.array([[0.0], [1.0 / m]])
    T = 0.05
    dsys = control.c2d(control.ss(A, B, np.eye(2), 0), T, method="zoh")
    K, _, _ = control.dlqr(dsys.A, dsys.B, np.diag([100.0, 1.0]), np.array([[0.01]]))
    x0 = np.array([0.1, -0.3])
    n = 60
    closed = control.ss(dsys.A - dsys.B @ K, np.zeros((2, 1)), np.eye(2), 0, T)
    ref = control.initial_response(closed, T=np.arange(n + 1) * T, X0=x0).states.T
    xc, y = ca.SX.sym("xc", 0), ca.SX.sym("y", 2)
    law = ca.Function("lqr", [xc, y], [xc, -ca.mtimes(ca.DM(K), y)])
    ctrl = DiscreteController(law, T, measurements=["x", "x_d"], actuates=["F"])
    eom = _oscillator()
    res = simulate(eom, n * T, x0=x0, controller=ctrl, method="rk4", dt=T / 40, t_out=np.arange(n + 1) * T)
    np.testing.assert_allclose(res.x, ref, atol=1e-9)
    assert abs(res.x[-1, 0]) < 1e-3 * abs(x0[0]) * 50          # regulated (and not by accident: K != 0)


def _oscillator():
    from .conftest import oscillator

    return oscillator()


def test_accuracy_driven_substeps_meet_the_accuracy():
    ctrl = DiscreteController(pi_law(), 0.5, measurements=["x"], actuates=["u"])
    inputs = {"d": lambda t: 0.5 * np.sin(3.0 * t)}
    res = simulate(first_order_plant(), 10.0, controller=ctrl, inputs=inputs, accuracy=1e-5)
    ref = simulate(first_order_plant(), 10.0, controller=ctrl, inputs=inputs, method="rk4", dt=0.5 / 400,
                   t_out=res.t)
    assert epsilon(res.x, ref.x) <= 1e-5
    assert res.statistics["substeps"] > 1 and res.statistics["error_estimate"] <= 1e-5


def test_interrupt_and_partial_result_of_python_law(monkeypatch):
    """A KeyboardInterrupt raised inside a Python law ends the run with SimulationInterrupted."""
    from mbsym.simulate import SimulationInterrupted

    def law(t, xc, y):
        if t >= 0.5:
            raise KeyboardInterrupt
        return xc, np.array([1.0])

    ctrl = DiscreteController(law, 0.1, measurements=["x"], actuates=["u"])
    with pytest.raises(SimulationInterrupted, match=r"interrupted at t = 0.5 s") as info:
        simulate(first_order_plant(), 2.0, controller=ctrl)
    assert info.value.partial is not None and info.value.partial.t[-1] < 0.5


@pytest.mark.parametrize("make, err, match", [
    (lambda: DiscreteController(pi_law(), 0.0, measurements=["x"], actuates=["u"]), SimulationOptionError,
     "sample time dt must be a positive"),
    (lambda: DiscreteController(pi_law(), 0.1, measurements=["x", "y2"], actuates=["u"]), mb.DimensionError,
     "takes y of 1 values; measurements names 2"),
    (lambda: DiscreteController(pi_law(), 0.1, measurements=["x"], actuates=["u", "d"]), mb.DimensionError,
     "returns u of 1 values; actuates names 2"),
    (lambda: DiscreteController(pi_law(), 0.1, [0.0, 1.0], measurements=["x"], actuates=["u"]), mb.DimensionError,
     "x0 has 2 values"),
    (lambda: DiscreteController(pi_law(), 0.1, measurements="x", actuates=["u"]), TypeError, "sequence of names"),
    (lambda: DiscreteController(42, 0.1, measurements=["x"], actuates=["u"]), TypeError, "law must be"),
    (lambda: DiscreteController(pi_law(), 0.1, measurements=["x"], actuates=[]), mb.DimensionError,
     "at least one"),
])
def test_bad_controllers(make, err, match):
    with pytest.raises(err, match=match):
        make()


@pytest.mark.parametrize("ctrl_kw, sim_kw, err, match", [
    ({"measurements": ["z"], "actuates": ["u"]}, {}, mb.DimensionError, r"measures \['z'\]"),
    ({"measurements": ["x"], "actuates": ["w"]}, {}, mb.DimensionError, r"actuates \['w'\]"),
    ({"measurements": ["x"], "actuates": ["u"]}, {"method": "cvodes"}, SimulationOptionError, "RK4 sub-steps"),
    ({"measurements": ["x"], "actuates": ["u"]}, {"method": "rk4", "dt": 0.03}, SimulationOptionError,
     "must divide the controller sample time"),
    ({"measurements": ["x"], "actuates": ["u"], "state_names": ["y2"]}, {}, mb.DimensionError, "also model outputs"),
])
def test_bad_closed_loops(ctrl_kw, sim_kw, err, match):
    ctrl = DiscreteController(pi_law(), 0.1, **ctrl_kw)
    with pytest.raises(err, match=match):
        simulate(first_order_plant(), 1.0, controller=ctrl, **sim_kw)


def test_python_law_returning_the_wrong_size():
    ctrl = DiscreteController(lambda t, xc, y: (xc, np.array([1.0, 2.0])), 0.1, measurements=["x"], actuates=["u"])
    with pytest.raises(mb.DimensionError, match=r"returned xc_next of 0 and u of 2 values at t = 0 s"):
        simulate(first_order_plant(), 1.0, controller=ctrl)


def test_python_law_with_hidden_state_is_run_once():
    """A Python law that keeps hidden state (as a DISCON library does) must not be re-run by the
    accuracy check: the answer would continue from the end of the first run. Reference: the same
    law written without hidden state (its state in xc) gives the same trajectory."""
    import casadi as ca

    x, u, p = ca.SX.sym("x"), ca.SX.sym("u"), ca.SX.sym("p", 0)
    plant = mb.Dynamics(ca.Function("f", [x, u, p], [-0.5 * x + u]), states=["x"], inputs=["u"], x0=[1.0])

    class Hidden:
        def __init__(self):
            self.integral, self.calls = 0.0, 0

        def __call__(self, t, xc, y):
            self.calls += 1
            self.integral += 0.1 * (0.2 - y[0])
            return xc, np.array([2.0 * (0.2 - y[0]) + self.integral])

    def explicit(t, xc, y):
        integral = xc[0] + 0.1 * (0.2 - y[0])
        return np.array([integral]), np.array([2.0 * (0.2 - y[0]) + integral])

    hidden = Hidden()
    a = mb.simulate(plant, 5.0, controller=DiscreteController(hidden, 0.1, measurements=["x"], actuates=["u"]))
    b = mb.simulate(plant, 5.0, controller=DiscreteController(explicit, 0.1, [0.0], measurements=["x"],
                                                              actuates=["u"]))
    assert hidden.calls == 50 and "not run again" in a.statistics["check"]      # 5 s of 0.1 s samples, once
    np.testing.assert_allclose(a.x, b.x, rtol=0, atol=1e-12)


def test_hidden_states_are_carried_but_not_recorded():
    """A law with an extra state (here a copy of the integral, the second of two) hidden: the loop runs as with the
    state shown (the same plant states and inputs), the result records only the first; the exact recurrence holds."""
    I, y = ca.SX.sym("I", 2), ca.SX.sym("y")
    e = REF - y
    nxt = ca.vertcat(I[0] + T_S * e, I[1] + T_S * e)
    law = ca.Function("PI2", [I, y], [nxt, KP * e + KI * nxt[1]])          # the command uses the hidden copy
    kw = dict(measurements=["x"], actuates=["u"])
    shown = DiscreteController(law, T_S, **kw, state_names=["I", "J"])
    hidden = DiscreteController(law, T_S, **kw, state_names=["I"], hidden_states=1)
    n = 30
    grid = dict(method="rk4", dt=T_S / 50, t_out=np.arange(n + 1) * T_S)
    r1 = simulate(first_order_plant(), n * T_S, controller=shown, **grid)
    r2 = simulate(first_order_plant(), n * T_S, controller=hidden, **grid)
    np.testing.assert_array_equal(r2.x, r1.x)
    np.testing.assert_array_equal(r2.u, r1.u)
    assert r2.output_names == ("y2", "I") and r1.output_names == ("y2", "I", "J")
    x, _, _ = exact_pi(n)
    np.testing.assert_allclose(r2.state("x"), x, atol=1e-9)
    with pytest.raises(mb.DimensionError, match="hidden_states"):
        DiscreteController(law, T_S, **kw, hidden_states=3)
    with pytest.raises(mb.DimensionError, match="state_names has 2 names for 1"):
        DiscreteController(law, T_S, **kw, state_names=["I", "J"], hidden_states=1)
