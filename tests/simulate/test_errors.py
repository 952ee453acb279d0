"""Bad input raises a typed error that says what is wrong (python-control style: every path tested)."""

import warnings

import numpy as np
import pytest

import mbsym as mb
from mbsym.simulate import METHODS, SimulationOptionError, SimulationOptionWarning, simulate


def test_unknown_keyword_argument(osc):
    with pytest.raises(TypeError, match="solver"):
        simulate(osc, 1.0, solver="rk4")


def test_options_are_keyword_only(osc):
    with pytest.raises(TypeError):
        simulate(osc, 1.0, None, None, None, "rk4")


def test_system_instead_of_equations():
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", 1.0), axis=[1, 0, 0], coordinate=x))
    with pytest.raises(TypeError, match=r"sys.equations\(\)"):
        simulate(sys, 1.0)


def test_model_of_wrong_type():
    with pytest.raises(TypeError, match="EquationsOfMotion"):
        simulate(object(), 1.0)


@pytest.mark.parametrize("x0, match", [
    ([1.0, 0.0, 0.0], r"x0 has 3 entries; expected 2 \(q: 1, qd: 1\) in order \['x', 'x_d'\]"),
    ([np.nan, 0.0], r"must be finite; not finite: \['x'\]"),
    ({"y": 1.0}, r"unknown states \['y'\]; the states are \['x', 'x_d'\]"),
    ({"x": "a"}, r"x0\['x'\] must be a number"),
    ("ab", r"x0 must be 2 numbers"),
])
def test_bad_initial_state(osc, x0, match):
    with pytest.raises(mb.DimensionError, match=match):
        simulate(osc, 1.0, x0=x0)


def test_bad_parameters(osc):
    with pytest.raises(mb.ParameterError, match=r"unknown parameters \['kk'\]"):
        simulate(osc, 1.0, p={"kk": 1.0})
    with pytest.raises(mb.ParameterError, match="dict by name"):
        simulate(osc, 1.0, p=[1.0, 2.0, 3.0])


@pytest.mark.parametrize("inputs, err, match", [
    ({"G": 1.0}, mb.DimensionError, r"unknown inputs \['G'\]; this model's inputs are \['F'\]"),
    ([1.0, 2.0], mb.DimensionError, "inputs has 2 entries; expected 1"),
    ({"F": np.ones(5)}, mb.DimensionError, "no time grid"),
    ({"t": [0.0, 0.5], "F": [0.0, 1.0]}, mb.DimensionError, r"spans \[0, 0.5\] s .* never extrapolated"),
    ({"t": [0.0, 1.0], "F": [0.0, 1.0, 2.0]}, mb.DimensionError, "3 values .* grid of 2 times"),
    ({"F": ([0.0, 0.7, 0.5, 1.0], [0, 1, 2, 3])}, mb.DimensionError, "strictly increasing"),
    ({"F": ([0.0, 1.0], [0.0, np.inf])}, mb.DimensionError, "not finite at t = 1 s"),
    ({"F": (1, 2, 3)}, mb.DimensionError, r"pair \(grid, values\)"),
    ({"F": lambda t: np.nan if t > 0.5 else 0.0}, mb.DimensionError, r"input 'F' is not finite at t = 0.5\d* s"),
    ({"F": lambda t: [1.0, 2.0]}, mb.DimensionError, "must return one number"),
    ({"F": "sin"}, TypeError, "unsupported value of type str"),
    ({"F": True}, TypeError, "bool"),
    ("F", TypeError, "dict by input name"),
    (lambda t: "1.0", mb.exceptions.ArgumentTypeError, "a string"),      # a bare callable is accepted (issue 11)
])
def test_bad_inputs(osc, inputs, err, match):
    with pytest.raises(err, match=match):
        simulate(osc, 1.0, inputs=inputs)


def test_callable_error_propagates_with_a_note(osc):
    def f(t):
        raise ZeroDivisionError("boom")
    with pytest.raises(ZeroDivisionError) as info:
        simulate(osc, 1.0, inputs={"F": f})
    assert any("input 'F'" in note for note in info.value.__notes__)


@pytest.mark.parametrize("kwargs, match", [
    ({"method": "euler"}, r"unknown method 'euler'; choose one of 'rk4' \(fixed-step, order 4\)"),
    ({"dt": 0.0}, "dt must be a positive finite number"),
    ({"dt": -0.1}, "dt must be a positive finite number"),
    ({"dt": "0.1"}, "dt must be a positive number"),
    ({"method": "cvodes", "rtol": 0.0}, "rtol must be a positive"),
    ({"method": "cvodes", "rtol": 1e-16}, "rtol >= 1e-14"),
    ({"method": "cvodes", "atol": np.inf}, "atol must be a positive finite"),
    ({"t_out": [0.0, 0.5, 0.4]}, "strictly increasing"),
    ({"t_out": [0.0, 2.0]}, r"within \[0, tmax\]"),
    ({"t_out": [[0.0, 0.5]]}, "1-D"),
    ({"t_out": [0.0, np.nan]}, "finite"),
])
def test_bad_options(osc, kwargs, match):
    with pytest.raises(SimulationOptionError, match=match):
        simulate(osc, 1.0, **kwargs)


@pytest.mark.parametrize("tmax", [0.0, -1.0, np.inf, None])
def test_bad_tmax(osc, tmax):
    with pytest.raises(SimulationOptionError, match="tmax"):
        simulate(osc, tmax)


def test_option_errors_are_value_errors_and_mbsym_errors():
    assert issubclass(SimulationOptionError, ValueError) and issubclass(SimulationOptionError, mb.MbsymError)


def test_every_method_declares_order_and_kind():
    for name, cls in METHODS.items():
        assert cls.name == name
        assert isinstance(cls.order, int) and cls.order >= 1
        assert cls.kind in ("fixed-step", "adaptive")


@pytest.mark.parametrize("method, kwargs, match", [
    ("rk4", {"rtol": 1e-9}, "rtol = 1e-09 ignored: method 'rk4' has a fixed step"),
    ("newmark", {"atol": 1e-9, "dt": 0.01}, "atol = 1e-09 ignored"),
    ("generalized-alpha", {"rtol": 1e-3, "atol": 1e-5}, "rtol = 0.001 and atol = 1e-05 ignored"),
    ("cvodes", {"dt": 0.02, "t_out": [0.0, 0.5, 1.0]}, "dt = 0.02 ignored: method 'cvodes' is adaptive"),
    ("scipy-radau", {"dt": 0.02, "t_out": [0.0, 1.0]}, "dt = 0.02 ignored"),
])
def test_options_the_method_ignores_warn(osc, method, kwargs, match):
    with pytest.warns(SimulationOptionWarning, match=match):
        simulate(osc, 1.0, method=method, **kwargs)


@pytest.mark.parametrize("method, kwargs", [
    ("rk4", {"dt": 0.01, "t_out": [0.0, 0.5, 1.0]}),
    ("rk4", {}),
    ("cvodes", {"rtol": 1e-8, "atol": 1e-10, "t_out": [0.0, 1.0]}),
    ("cvodes", {"dt": 0.1}),                       # dt spaces the outputs: used
    ("cvodes", {}),
])
def test_options_the_method_uses_do_not_warn(osc, method, kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        simulate(osc, 1.0, method=method, **kwargs)


def test_option_warning_is_a_user_warning():
    assert issubclass(SimulationOptionWarning, UserWarning)
