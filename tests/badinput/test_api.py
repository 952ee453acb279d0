"""Bad API calls: each raises an mbsym error (MbsymError, also the matching builtin) naming the
problem; nothing is integrated or linearized with unphysical mass properties.

Physical references: a rigid body's mass is non-negative and its inertia tensor symmetric
positive semi-definite with principal moments obeying J1 <= J2 + J3 (mbsym.mass_properties);
the mass matrix of a physical system is positive definite.
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import (
    ArgumentTypeError, DimensionError, MassPropertyError, MbsymError, ModelDefinitionError, ModelWarning,
    OpenFASTFormatError, OptionError, ParameterError, UnsupportedFeatureError,
)


def pendulum():
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    m1, m2, l1, l2 = sys.parameters("m1 m2 l1 l2", values=[2.0, 1.0, 1.0, 0.5])
    J = sys.parameters("J", values={"J": 0.1})
    b1 = mb.RigidBody("b1", m1, com=[0, 0, -l1], inertia=[J, J, J])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, mb.RigidBody("b2", m2, com=[0, 0, -l2]), axis=[0, 1, 0], coordinate=q2,
                              offset=[0, 0, -l1]))
    return sys.equations()


@pytest.fixture(scope="module")
def eom():
    return pendulum()


@pytest.fixture(scope="module")
def turbine():
    from mbsym.wind import nrel5mw
    from mbsym.wind.structure.turbine import TurbineModel

    return TurbineModel(nrel5mw(), dofs=["TwFADOF1", "GenDOF"])


def _steady_nan(turbine):
    return mb.steady_rotation(turbine, float("nan"))


# (call: (eom, turbine) -> None, expected error class, message regex)
CASES = [
    (lambda e, t: mb.RigidBody("b", mass=-1.0), MassPropertyError, r"mass is -1 kg"),
    (lambda e, t: mb.RigidBody("b", 1.0, inertia=[1.0, 1.0, 5.0]), MassPropertyError, r"triangle inequality"),
    (lambda e, t: mb.RigidBody("b", 1.0, inertia=[1.0, -1.0, 1.0]), MassPropertyError, r"not positive semi-definite"),
    (lambda e, t: mb.RigidBody("b", 1.0, inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]]), MassPropertyError,
     r"not symmetric"),
    (lambda e, t: mb.RigidBody("b", 1.0, inertia=[1, 1, 1, 0.9, 0.9, 0.9]), MassPropertyError, r"triangle"),
    (lambda e, t: mb.RigidBody("b", 1.0, lumped_inertia="yes"), ArgumentTypeError, r"lumped_inertia"),
    (lambda e, t: e.mass_matrix([0.1, 0.2], {"m1": -5.0}), MassPropertyError, r"body 'b1': mass is -5 kg.*'m1'"),
    (lambda e, t: e.forcing([0.1, 0.2], [0, 0], {"J": -1.0}), MassPropertyError, r"body 'b1'.*'J'"),
    (lambda e, t: mb.simulate(e, 0.1, [0.1, 0, 0, 0], p={"m1": -5.0}), MassPropertyError, r"mass is -5 kg"),
    (lambda e, t: mb.linearize(e, [0.1, 0.0], p={"m2": -1.0}), MassPropertyError, r"body 'b2'"),
    (lambda e, t: mb.simulate(t, 0.1, p={"nacelle_mass": -1.0}), MassPropertyError, r"nacelle.*-1 kg"),
    (lambda e, t: mb.linearize(t, p={"hub_mass": -10.0}), MassPropertyError, r"hub"),
    (lambda e, t: e.mass_matrix([0.1], {}), DimensionError, r"q has 1 entries"),
    (lambda e, t: e.mass_matrix([0.1, 0.2], {"nope": 1.0}), ParameterError, r"unknown parameters \['nope'\]"),
    (lambda e, t: e.mass_matrix([0.1, 0.2], {"m1": "heavy"}), ParameterError, r"expected a real number"),
    (lambda e, t: mb.simulate(e, 0.1, inputs={"F": 1.0}), DimensionError, r"unknown inputs"),
    (lambda e, t: mb.simulate(t, 0.1, inputs={"GenTq": lambda s: "abc"}), ArgumentTypeError, r"returned 'abc'"),
    (lambda e, t: mb.simulate(t, 0.1, inputs=lambda s: [0.0]), DimensionError, r"returned 1 values"),
    (lambda e, t: mb.simulate(t, 0.1, inputs="GenTq"), ArgumentTypeError, r"dict by input name"),
    (lambda e, t: t.__class__(t.turbine, dofs="TwFADOF1"), ArgumentTypeError, r"list of ElastoDyn flag names"),
    (lambda e, t: t.__class__(t.turbine, dofs=["TwFADOF3"]), ModelDefinitionError, r"unknown ElastoDyn DOF"),
    (lambda e, t: __import__("mbsym.wind", fromlist=["x"]).read_openfast("/no/such/deck.fst"), OpenFASTFormatError, r"not found"),
    (lambda e, t: _modules_on(t), UnsupportedFeatureError, r"CompAero = 2.*CompServo = 1"),
    (lambda e, t: __import__("mbsym.wind.deck.checks", fromlist=["x"]).check_rotor_speed(200, 63.0), OptionError,
     r"speed of sound"),
    (lambda e, t: __import__("mbsym.cli.campbell", fromlist=["x"]).parse_rpm_list("6,3,3,0"), OptionError,
     r"strictly increasing"),
    (lambda e, t: __import__("mbsym.equations", fromlist=["x"]).check_nonsingular(np.diag([1.0, -2.0]), ["a", "b"]),
     MassPropertyError, r"not positive definite.*\['b'\]"),
    (lambda e, t: __import__("mbsym.wind.analysis.compare", fromlist=["x"]).compare(
        _series([0.0, 1.0]), _series([5.0, 6.0])), DimensionError, r"no overlap"),
    (lambda e, t: mb.linearize(e, [0.0, 0.0], method="magic"), OptionError, r"unknown linearization method"),
    (lambda e, t: _steady_nan(t), OptionError, r"speed must be finite"),
    (lambda e, t: mb.steady_rotation(t, "fast"), OptionError, r"speed must be finite"),
    (lambda e, t: mb.linearize(e, [0.0, 0.0], steps=[1e-3, 1e-3]), ArgumentTypeError, r"steps= is used only"),
    (lambda e, t: mb.linearize(e, [0.0, 0.0], qdd0="zero"), OptionError, r"qdd0 must be"),
    (lambda e, t: mb.linearize("model", [0.0]), ArgumentTypeError, r"model must be an EquationsOfMotion"),
]

def _modules_on(t):
    import dataclasses

    from mbsym.wind.deck.checks import check_modules

    sim = dataclasses.replace(t.turbine.simulation, aerodynamics_model=2, servo_model=1)
    check_modules(dataclasses.replace(t.turbine, simulation=sim))


def _series(t):
    from mbsym.wind.analysis.compare import TimeSeries

    t = np.asarray(t, dtype=float)
    return TimeSeries(t, ("a",), ("m",), np.c_[t])


@pytest.mark.parametrize("call, err, match", CASES, ids=[f"api{i}" for i in range(len(CASES))])
def test_bad_call_raises_a_typed_error(eom, turbine, call, err, match):
    try:
        call(eom, turbine)
    except MbsymError as exc:
        assert isinstance(exc, err), f"{type(exc).__name__} is not a {err.__name__}: {exc}"
        assert isinstance(exc, (ValueError, TypeError, RuntimeError, OSError))
        import re

        assert re.search(match, str(exc)), f"{exc} does not match {match!r}"
    except Exception as exc:                                   # noqa: BLE001 - a plain builtin error is the defect
        raise AssertionError(f"{type(exc).__name__} (not an mbsym error): {exc}") from exc
    else:
        raise AssertionError("no error raised")


def test_failed_binding_leaves_the_model_usable(eom):
    with pytest.raises(MassPropertyError):
        eom.mass_matrix([0.1, 0.2], {"m1": -5.0})
    M = eom.mass_matrix([0.0, 0.0])
    assert M[0, 0] == pytest.approx(2.0 * 1.0 + 1.0 * 1.5**2 + 0.1)   # m1 l1^2 + m2 (l1 + l2)^2 + J


def test_idealized_inertias_are_accepted():
    """Massless frames, inertia about one axis only (ElastoDyn's hub/generator/nacelle yaw), rounded
    disc data 0.5 % over the triangle bound (paper Sect. 4.4 rotor), lumped equivalent inertias."""
    mb.RigidBody("frame", 0.0)
    mb.RigidBody("generator", 0.0, inertia=[534.116, 0.0, 0.0])
    mb.RigidBody("rotor", 1.1e5, inertia=[3.86e7, 1.92e7, 1.92e7])
    mb.RigidBody("rotor_gen", 1.1e5, inertia=[3.86e7 + 534.116 * 97**2, 1.92e7, 1.92e7], lumped_inertia=True)


def test_positive_definite_check_before_integration():
    """check_mass_matrix: a negative eigenvalue is refused; a positive definite M passes."""
    from mbsym.mass_properties import check_mass_matrix

    e = pendulum()
    check_mass_matrix(e, [0.3, -0.2])
    with pytest.raises(MassPropertyError):
        check_mass_matrix(e, [0.3, -0.2], p=np.array([-2.0, 1.0, 1.0, 0.5, 0.1]))


def test_bare_callable_inputs_are_accepted(turbine):
    """inputs=f(t) -> n_u values, as documented: same result as the per-input dict (to 1e-12)."""
    n_u = len(turbine.eom.inputs)
    a = mb.simulate(turbine, 0.2, inputs=lambda t: [1e5 * t] + [0.0] * (n_u - 1))
    b = mb.simulate(turbine, 0.2, inputs={"GenTq": lambda t: 1e5 * t})
    np.testing.assert_allclose(a.x, b.x, rtol=1e-12, atol=1e-12)


def test_teeter_dof_on_three_blades_is_ignored_with_a_note(tmp_path):
    from .conftest import copy_deck, set_key

    deck = copy_deck(tmp_path)
    set_key(deck.ed, "TeetDOF", "True")
    with pytest.warns(ModelWarning, match="TeetDOF = True ignored"):
        t = __import__("mbsym.wind", fromlist=["x"]).read_openfast(deck.fst)
    assert t.dofs["TeetDOF"] is False
