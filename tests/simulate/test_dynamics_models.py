"""simulate() on mbsym.Dynamics: named first-order models (composed models: structure + extra states).

Reference: a linear 3-state model x' = A x + B u (an oscillator driving a first-order lag), whose exact
response to a constant input is x(t) = expm(A t) x0 + A^-1 (expm(A t) - I) B u (scipy.linalg.expm,
independent of mbsym). Tolerances: 1e-7 relative to the state amplitude for the adaptive methods at
rtol 1e-10, 1e-6 for rk4 at dt = 0.01 s.
"""

import casadi as ca
import numpy as np
import pytest
from scipy.linalg import expm

import mbsym as mb
from mbsym.simulate import METHODS, SimulationOptionError, simulate
from mbsym.simulate.auto import epsilon

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

A = np.array([[0.0, 1.0, 0.0], [-4.0, -0.2, 1.0], [0.0, 0.0, -2.0]])
B = np.array([[0.0], [0.0], [2.0]])
X0 = np.array([1.0, 0.0, 0.0])
U0 = 0.5


def linear_dynamics():
    x, u, p = ca.SX.sym("x", 3), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, u, p], [ca.mtimes(ca.DM(A), x) + ca.mtimes(ca.DM(B), u) * p[0]])
    h = ca.Function("h", [x, u, p], [ca.vertcat(x[0], x[2] * 1e3)])
    return mb.Dynamics(f, states=["pos", "vel", "lag"], inputs=["cmd"], parameters=["gain"], defaults={"gain": 1.0},
                       outputs=h, output_names=["pos_out", "lag_kN"], output_units=["m", "N"], x0=X0,
                       name="oscillator_with_lag")


def exact(t):
    Ainv = np.linalg.inv(A)
    return np.array([expm(A * ti) @ X0 + (Ainv @ (expm(A * ti) - np.eye(3)) @ B).ravel() * U0 for ti in t])


FIRST_ORDER = [m for m, cls in METHODS.items() if not cls.needs_held and not cls.second_order]


@pytest.mark.parametrize("method", FIRST_ORDER + [None])
def test_every_first_order_method_runs_a_dynamics(method):
    dyn = linear_dynamics()
    kw = {} if method is None else {"method": method}
    if method is not None and METHODS[method].kind == "adaptive":
        kw.update(rtol=1e-10, atol=1e-12)
    t_out = np.linspace(0.0, 5.0, 51)
    res = simulate(dyn, 5.0, inputs={"cmd": U0}, t_out=t_out, **kw)
    if method is None:                                  # the accuracy-driven default: its error metric
        assert epsilon(res.x, exact(t_out)) <= 1e-3
    else:
        np.testing.assert_allclose(res.x, exact(t_out), atol=1e-6)
    assert res.states == ("pos", "vel", "lag") and res.inputs == ("cmd",)
    assert res.output_names == ("pos_out", "lag_kN") and res.units == {"pos_out": "m", "lag_kN": "N"}
    np.testing.assert_allclose(res.output("lag_kN"), 1e3 * res.state("lag"))
    assert res.structural is None
    with pytest.raises(AttributeError, match="first-order dynamics"):
        res.q


@pytest.mark.parametrize("method", [m for m, cls in METHODS.items() if not cls.needs_held and cls.second_order])
def test_second_order_methods_refuse_a_pure_dynamics(method):
    with pytest.raises(SimulationOptionError, match=rf"method '{method}' integrates the second-order residual form"):
        simulate(linear_dynamics(), 1.0, method=method, dt=0.01)


def test_parameters_and_defaults_of_the_dynamics():
    dyn = linear_dynamics()
    res = simulate(dyn, 2.0, inputs={"cmd": U0}, p={"gain": 0.0}, method="rk4")
    np.testing.assert_allclose(res.state("lag"), 0.0, atol=1e-15)        # gain 0: the lag is not driven
    np.testing.assert_allclose(res.x[0], X0)                               # the Dynamics' default state
    with pytest.raises(mb.ParameterError, match="unknown parameters"):
        simulate(dyn, 1.0, p={"k": 1.0})


def test_equations_as_dynamics_give_the_same_result(osc):
    """as_dynamics(eom) keeps [q; qd]: every method (second-order included) gives the eom's result."""
    dyn = mb.as_dynamics(osc)
    for method in ("rk4", "newmark", "cvodes"):
        r1 = simulate(osc, 2.0, x0=[0.1, 0.0], inputs={"F": 1.0}, method=method)
        r2 = simulate(dyn, 2.0, x0=[0.1, 0.0], inputs={"F": 1.0}, method=method)
        np.testing.assert_allclose(r2.x, r1.x, rtol=0, atol=1e-14)
        assert r2.structural == 1 and r2.q.shape == (r1.t.size, 1)


def test_composed_dynamics_keeps_the_structural_coordinates(osc):
    """A Dynamics whose states start with the eom's [q; qd] plus an actuator lag: q and qd views work,
    second-order methods are refused (the rhs is not the eom's), outputs by name."""
    x, u, p = ca.SX.sym("x", 3), ca.SX.sym("u", 1), ca.SX.sym("p", osc.n_p)
    force = x[2]
    xd = osc.functions.rhs(x[:2], force, p)
    f = ca.Function("f", [x, u, p], [ca.vertcat(xd, (u[0] - x[2]) / 0.05)])
    dyn = mb.Dynamics(f, states=[*osc.states, "F_act"], inputs=["F_cmd"], parameters=osc.parameters,
                      defaults=dict(osc.defaults), eom=osc, name="actuated")
    res = simulate(dyn, 1.0, inputs={"F_cmd": 2.0})
    assert res.structural == 1 and res.q.shape[1] == 1 and res.qd.shape[1] == 1
    assert res.state("F_act")[-1] == pytest.approx(2.0, abs=1e-6)
    with pytest.raises(SimulationOptionError, match="first-order dynamics"):
        simulate(dyn, 1.0, method="generalized-alpha")


def test_dynamics_hook_object():
    class Composed:
        def __init__(self):
            self._dyn = linear_dynamics()

        def dynamics(self):
            return self._dyn

        def default_inputs(self):
            return {"cmd": U0}

    t_out = np.linspace(0.0, 5.0, 11)
    res = simulate(Composed(), 5.0, t_out=t_out, method="cvodes", rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(res.x, exact(t_out), atol=1e-6)
