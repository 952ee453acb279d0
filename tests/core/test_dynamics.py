"""mbsym.Dynamics: named first-order dynamics from equations of motion and from model objects.

References: the rhs of a Dynamics made from an EquationsOfMotion must equal the
equations' own rhs bit for bit (same Function); a hand-written linear system gives
the closed form f = A x + B u.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb


@pytest.fixture(scope="module")
def pendulum():
    sys = mb.System(gravity=[0, 0, -9.81])
    th = sys.coordinates("th")
    m, l = sys.parameters("m l", values={"m": 2.0, "l": 1.5})
    tau = sys.inputs("tau")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", m, com=[0, 0, -l]), axis=[0, 1, 0], coordinate=th))
    sys.add_generalized_force(th, tau)
    return sys.equations()


def test_from_equations_is_the_same_rhs(pendulum):
    dyn = mb.as_dynamics(pendulum)
    assert dyn.states == pendulum.states and dyn.inputs == ("tau",) and dyn.eom is pendulum
    x, u = [0.3, -0.2], [0.7]
    np.testing.assert_array_equal(dyn.rhs_value(x, u), pendulum.rhs(x, u))
    # closed form: th'' = (tau - m g l sin th) / (m l^2)
    m, l, g = 2.0, 1.5, 9.81
    assert dyn.rhs_value(x, u, {"m": m})[1] == pytest.approx((0.7 - m * g * l * np.sin(0.3)) / (m * l * l), rel=1e-12)


def test_linear_closed_form_and_named_vectors():
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    A = ca.vertcat(ca.horzcat(0, 1), ca.horzcat(-p, -0.1))
    f = ca.Function("f", [x, u, p], [A @ x + ca.vertcat(0, 1) * u])
    h = ca.Function("h", [x, u, p], [x[0] + 0 * u])
    dyn = mb.Dynamics(f, states=["y", "v"], inputs=["F"], parameters=["k"], defaults={"k": 4.0}, outputs=h,
                      output_names=["pos"], output_units=["m"], x0=[1.0, 0.0])
    np.testing.assert_allclose(dyn.rhs_value({"v": 2.0}, [3.0]), [2.0, -4.0 * 1.0 - 0.2 + 3.0], rtol=1e-15)
    assert dyn.output_value([0.5, 0.0]).tolist() == [0.5] and dyn.output_units == ("m",)


@pytest.mark.parametrize("kwargs, err, match", [
    ({"states": ["a"]}, mb.DimensionError, "x \\(1\\)"),
    ({"states": ["a", "a"]}, mb.DimensionError, "unique"),
    ({"states": ["a", "b"], "defaults": {"zz": 1.0}}, mb.ParameterError, "unknown parameters"),
    ({"states": ["a", "b"], "x0": [1.0]}, mb.DimensionError, "x0 has 1 entries"),
    ({"states": ["a", "b"], "output_names": ["y"]}, mb.DimensionError, "without an outputs"),
])
def test_bad_definitions(kwargs, err, match):
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, u, p], [x * p + u])
    kwargs = {"inputs": ["u"], "parameters": ["k"], **kwargs}
    with pytest.raises(err, match=match):
        mb.Dynamics(f, **kwargs)


def test_bad_numeric_calls(pendulum):
    dyn = mb.as_dynamics(pendulum)
    with pytest.raises(mb.ParameterError, match="unknown parameters"):
        dyn.parameter_vector({"mass": 1.0})
    with pytest.raises(mb.ParameterError, match="finite"):
        dyn.parameter_vector({"m": float("nan")})
    with pytest.raises(mb.DimensionError, match="unknown entries"):
        dyn.state_vector({"phi": 1.0})
    with pytest.raises(TypeError, match="EquationsOfMotion"):
        mb.as_dynamics(object())
    with pytest.raises(TypeError, match="casadi.Function"):
        mb.Dynamics(lambda x: x, states=["a"])


def test_turbine_model_object_gives_named_outputs():
    from mbsym.wind import TurbineModel, nrel5mw

    model = TurbineModel(nrel5mw(), dofs=["TwFADOF1", "GenDOF"])
    dyn = mb.as_dynamics(model)
    assert dyn.states == model.eom.states and dyn.n_y == len(dyn.output_names) > 0
    i = dyn.output_names.index("Q_TFA1")
    assert dyn.output_units[i] == "m"
    x0 = dyn.x0
    # the output Q_TFA1 is the state TFA1 itself (OpenFAST's definition)
    assert dyn.output_value(x0)[i] == pytest.approx(x0[dyn.states.index("TFA1")], abs=1e-15)
