"""Every error path of the core engine, with the error class and the key words of the message.

Reference: the documented contract (README "Bad input raises a typed error ... that says what is
wrong and how to fix it; a failed call leaves the System unchanged", STYLE.md "Errors", module
docstrings). Each test names the offending item in ``match=`` so that a message that stops
naming it fails the test.
"""

from __future__ import annotations

import re

import casadi as ca
import numpy as np
import pytest

import mbsym as mb


# --------------------------------------------------------------------------- helpers
def pendulum2(*, defaults=None, gravity=(0.0, 0.0, -9.81)):
    """Double pendulum; masses are parameters (without defaults unless given)."""
    sys = mb.System(gravity=list(gravity))
    q1, q2 = sys.coordinates("q1 q2")
    m1, m2 = sys.parameters("m1 m2", values=defaults)
    b1 = mb.RigidBody("b1", mass=m1, com=[0, 0, -1])
    b2 = mb.RigidBody("b2", mass=m2, com=[0, 0, -0.5])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -1]))
    return sys, (q1, q2), (b1, b2)


@pytest.fixture(scope="module")
def eom():
    return pendulum2()[0].equations()


P = {"m1": 2.0, "m2": 1.0}


# --------------------------------------------------------------------------- parameters at call time
def test_missing_parameter_values_are_named(eom):
    with pytest.raises(mb.ParameterError, match=r"missing values for parameters \['m1', 'm2'\]"):
        eom.mass_matrix([0.1, 0.2])
    with pytest.raises(mb.ParameterError, match=r"missing values for parameters \['m2'\]"):
        eom.forcing([0.1, 0.2], [0.0, 0.0], {"m1": 1.0})


def test_defaults_fill_gaps_but_missing_ones_still_named():
    sys, *_ = pendulum2(defaults={"m1": 2.0})
    e = sys.equations()
    assert e.defaults == {"m1": 2.0}
    with pytest.raises(mb.ParameterError, match=r"missing values for parameters \['m2'\]"):
        e.potential_energy([0.0, 0.0])
    assert np.isfinite(e.potential_energy([0.0, 0.0], {"m2": 1.0}))


def test_unknown_parameter_names(eom):
    with pytest.raises(mb.ParameterError, match=r"unknown parameters \['l3'\]"):
        eom.mass_matrix([0.1, 0.2], {**P, "l3": 1.0})


def test_parameters_not_a_dict(eom):
    with pytest.raises(mb.ParameterError, match=r"dict by name.*got list"):
        eom.mass_matrix([0.1, 0.2], [2.0, 1.0])


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_parameter(eom, bad):
    with pytest.raises(mb.ParameterError, match=r"parameter 'm2' is -?(nan|inf); expected a finite number"):
        eom.mass_matrix([0.1, 0.2], {"m1": 1.0, "m2": bad})


def test_non_numeric_parameter(eom):
    with pytest.raises(mb.ParameterError, match=r"parameter 'm1' is 'x' \(str\); expected a real number"):
        eom.mass_matrix([0.1, 0.2], {"m1": "x", "m2": 1.0})


# --------------------------------------------------------------------------- sizes and finiteness
@pytest.mark.parametrize("call, what, got, expected", [
    (lambda e: e.mass_matrix([0.1, 0.2, 0.3], P), "q", 3, 2),
    (lambda e: e.mass_matrix([0.1], P), "q", 1, 2),
    (lambda e: e.forcing([0.1, 0.2], [0.0], P), "qd", 1, 2),
    (lambda e: e.residual([0.1, 0.2], [0.0, 0.0], [0.0, 0.0, 0.0], P), "qdd", 3, 2),
    (lambda e: e.rhs([0.1, 0.2, 0.0], P), "x", 3, 4),
    (lambda e: e.accelerations([0.1, 0.2, 0.3], [0.0, 0.0], P), "q", 3, 2),
    (lambda e: e.kinetic_energy([0.1, 0.2], [0.0, 0.0, 1.0], P), "qd", 3, 2),
    (lambda e: e.potential_energy([], P), "q", 0, 2),
    (lambda e: e.forcing([0.1, 0.2], [0.0, 0.0], [1.0], P), "u", 1, 0),
])
def test_wrong_sizes(eom, call, what, got, expected):
    with pytest.raises(mb.DimensionError, match=rf"^{what} has {got} entries; expected {expected}"):
        call(eom)


def test_wrong_size_message_lists_the_order(eom):
    with pytest.raises(mb.DimensionError, match=re.escape("in order ['q1', 'q2', 'q1_d', 'q2_d']")):
        eom.rhs([0.0] * 5, P)


def test_dict_instead_of_vector(eom):
    with pytest.raises(mb.DimensionError, match=r"q must be an array of 2 numbers.*got a dict"):
        eom.mass_matrix({"q1": 0.0, "q2": 0.0}, P)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_states_are_named(eom, bad):
    with pytest.raises(mb.DimensionError, match=r"q has non-finite entries for \['q2'\]"):
        eom.mass_matrix([0.0, bad], P)
    with pytest.raises(mb.DimensionError, match=r"qd has non-finite entries for \['q1_d'\]"):
        eom.forcing([0.0, 0.0], [bad, 0.0], P)
    with pytest.raises(mb.DimensionError, match=r"x has non-finite entries for \['q2_d'\]"):
        eom.rhs([0.0, 0.0, 0.0, bad], P)


def test_inputs_required_and_checked():
    sys = mb.System()
    x = sys.coordinates("x")
    F = sys.inputs("F")
    body = mb.RigidBody("b", mass=1.0)
    sys.add_joint(mb.Prismatic(sys.ground, body, axis=[1, 0, 0], coordinate=x))
    sys.add_force(body, [F, 0, 0])
    e = sys.equations()
    with pytest.raises(mb.DimensionError, match=r"this model has inputs \['F'\]; pass u"):
        e.forcing([0.0], [0.0])
    with pytest.raises(mb.DimensionError, match=r"u has non-finite entries for \['F'\]"):
        e.forcing([0.0], [0.0], [np.nan])
    with pytest.raises(mb.DimensionError, match=r"input dict: unknown \['G'\], missing \['F'\]"):
        e.forcing([0.0], [0.0], {"G": 1.0})
    np.testing.assert_allclose(e.forcing([0.0], [0.0], {"F": 2.0}), [2.0])   # the dict form works


# --------------------------------------------------------------------------- duplicate names
def test_coordinate_declared_twice():
    sys = mb.System()
    sys.coordinates("q1")
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinate names \['q1'\] are already used"):
        sys.coordinates("q1")
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinate names \['q2'\] are given more than once"):
        sys.coordinates("q2 q2")


def test_coordinate_name_equal_to_parameter_name():
    sys = mb.System()
    sys.parameters("m")
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinate names \['m'\] are already used"):
        sys.coordinates("m")
    sys.coordinates("q")
    with pytest.raises(mb.ModelDefinitionError, match=r"parameter names \['q'\] are already used"):
        sys.parameters("q")
    with pytest.raises(mb.ModelDefinitionError, match=r"input names \['q'\] are already used"):
        sys.inputs("q")


def test_name_equal_to_a_derived_speed_name():
    sys = mb.System()
    sys.coordinates("q")
    with pytest.raises(mb.ModelDefinitionError, match=r"parameter names \['q_d'\] are already used"):
        sys.parameters("q_d")


def test_coordinate_whose_speed_name_is_taken():
    sys = mb.System()
    sys.parameters("q_d")
    with pytest.raises(mb.ModelDefinitionError, match=r"q_d"):
        sys.coordinates("q")


def test_coordinate_and_speed_name_clash_in_one_call():
    sys = mb.System()
    with pytest.raises(mb.ModelDefinitionError, match=r"q_d"):
        sys.coordinates("q q_d")


@pytest.mark.parametrize("names", ["1q", "q-1", "class", ""])
def test_invalid_names(names):
    sys = mb.System()
    with pytest.raises(mb.ModelDefinitionError, match=r"not a valid identifier|no coordinate names"):
        sys.coordinates(names)


def test_two_bodies_with_the_same_name():
    sys = mb.System()
    a, b = sys.coordinates("a b")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("link", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=a))
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'link' is the name of another body"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("link", 1.0, com=[1, 0, 0]), axis=[0, 0, 1],
                                  coordinate=b))


def test_body_with_two_joints():
    sys = mb.System()
    a, b = sys.coordinates("a b")
    link = mb.RigidBody("link", 1.0, com=[1, 0, 0])
    sys.add_joint(mb.Revolute(sys.ground, link, axis=[0, 0, 1], coordinate=a))
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'link' already has a joint"):
        sys.add_joint(mb.Prismatic(sys.ground, link, axis=[1, 0, 0], coordinate=b))


def test_parent_with_the_name_of_another_body():
    sys = mb.System()
    a, b = sys.coordinates("a b")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("link", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=a))
    impostor = mb.RigidBody("link", 1.0)
    with pytest.raises(mb.ModelDefinitionError, match=r"parent 'link' has the name of another body"):
        sys.add_joint(mb.Revolute(impostor, mb.RigidBody("tip", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=b))


# --------------------------------------------------------------------------- tree structure
def test_body_not_connected_to_the_tree():
    sys = mb.System()
    a, b = sys.coordinates("a b")
    b0 = mb.RigidBody("b0", 1.0, com=[1, 0, 0])
    b1, b2 = mb.RigidBody("b1", 1.0, com=[1, 0, 0]), mb.RigidBody("b2", 1.0, com=[1, 0, 0])
    sys.add_joint(mb.Revolute(sys.ground, b0, axis=[0, 0, 1], coordinate=a))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 0, 1], coordinate=b))        # b1 has no joint
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'b2' is not connected to the ground.*parent 'b1'"):
        sys.equations()


def test_every_problem_listed_at_once():
    sys = mb.System()
    a, b, _ = sys.coordinates("a b unused")
    b1, b2 = mb.RigidBody("b1", 1.0, com=[1, 0, 0]), mb.RigidBody("b2", 1.0, com=[1, 0, 0])
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 0, 1], coordinate=b))
    with pytest.raises(mb.ModelDefinitionError) as info:
        sys.equations()
    msg = str(info.value)
    assert "'b2' is not connected" in msg and "['a', 'unused']" in msg


def test_coordinate_declared_but_unused():
    sys = mb.System()
    a, _ = sys.coordinates("a spare")
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=a))
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinates \['spare'\] are declared but no joint"):
        sys.equations()


def test_system_without_coordinates():
    with pytest.raises(mb.ModelDefinitionError, match=r"no coordinates"):
        mb.System().equations()


def test_coordinate_used_by_two_joints():
    sys = mb.System()
    a = sys.coordinates("a")
    b1 = mb.RigidBody("b1", 1.0, com=[1, 0, 0])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 0, 1], coordinate=a))
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinate 'a' already moves body 'b1'"):
        sys.add_joint(mb.Prismatic(b1, mb.RigidBody("b2", 1.0), axis=[1, 0, 0], coordinate=a))


def test_coordinate_repeated_within_a_free_joint():
    sys = mb.System()
    x, y, z, a, b = sys.coordinates("x y z a b")
    with pytest.raises(mb.ModelDefinitionError, match=r"coordinate 'a' already moves body 'b'"):
        sys.add_joint(mb.Free(sys.ground, mb.RigidBody("b", 1.0, inertia=[1, 1, 1]), coordinates=[x, y, z, a, b, a]))


@pytest.mark.parametrize("make", [
    lambda sys, q: q + 1.0,                       # an expression, not a symbol
    lambda sys, q: sys.parameters("k"),           # a parameter
    lambda sys, q: ca.SX.sym("q"),                # a stray symbol with a coordinate's name
    lambda sys, q: mb.System().coordinates("w"),  # a coordinate of another system
])
def test_joint_coordinate_not_of_this_system(make):
    sys = mb.System()
    q = sys.coordinates("q")
    bad = make(sys, q)
    with pytest.raises(mb.ModelDefinitionError, match=r"which is not a coordinate of this system"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=bad))


def test_joint_construction_errors():
    sys = mb.System()
    q = sys.coordinates("q")
    b = mb.RigidBody("b", 1.0)
    with pytest.raises(mb.ModelDefinitionError, match=r"axis of the joint of 'b' is \[0.0, 0.0, 0.0\]"):
        mb.Revolute(sys.ground, b, axis=[0, 0, 0], coordinate=q)
    with pytest.raises(mb.DimensionError, match=r"axis of the joint of 'b' has 2 entries; expected 3"):
        mb.Prismatic(sys.ground, b, axis=[1, 0], coordinate=q)
    with pytest.raises(mb.ModelDefinitionError, match=r"connects body 'b' to itself"):
        mb.Fixed(b, b)
    with pytest.raises(mb.ModelDefinitionError, match=r"ground cannot be the child"):
        mb.Fixed(b, sys.ground)
    with pytest.raises(mb.DimensionError, match=r"Free joint of 'b' has 5 coordinates; expected 6"):
        mb.Free(sys.ground, b, coordinates=[q] * 5)
    with pytest.raises(mb.DimensionError, match=r"offset of the joint of 'b' has 2 entries"):
        mb.Fixed(sys.ground, b, offset=[1, 2])
    with pytest.raises(mb.DimensionError, match=r"rotation of the joint of 'b' has shape"):
        mb.Fixed(sys.ground, b, rotation=np.eye(2))
    with pytest.raises(mb.ModelDefinitionError, match=r"add_joint expects a Joint"):
        sys.add_joint(b)


def test_ground_of_another_system():
    sys, other = mb.System(), mb.System()
    q = sys.coordinates("q")
    with pytest.raises(mb.ModelDefinitionError, match=r"ground of another System"):
        sys.add_joint(mb.Revolute(other.ground, mb.RigidBody("b", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=q))


# --------------------------------------------------------------------------- singular mass matrix
def test_massless_link_structural():
    """A leaf link with no mass and no inertia: its column of M is identically zero."""
    sys = mb.System(gravity=[0, 0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    b1 = mb.RigidBody("b1", 1.0, com=[0, 0, -1])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, mb.RigidBody("ghost", 0.0, com=[0, 0, -1]), axis=[0, 1, 0], coordinate=q2))
    with pytest.raises(mb.SingularMassMatrixError, match=r"coordinates \['q2'\] move no mass"):
        sys.equations()


def test_point_mass_spinning_about_itself_structural():
    """A revolute whose child is a point mass at the joint origin moves no mass."""
    sys = mb.System()
    x, th = sys.coordinates("x th")
    cart = mb.RigidBody("cart", 1.0)
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Revolute(cart, mb.RigidBody("dot", 2.0), axis=[0, 0, 1], coordinate=th))
    with pytest.raises(mb.SingularMassMatrixError, match=r"coordinates \['th'\] move no mass"):
        sys.equations()


def test_zero_mass_parameter_numeric(eom):
    """m2 = 0 at call time: accelerations name q2; the same model with m2 > 0 works."""
    with pytest.raises(mb.SingularMassMatrixError, match=r"singular at this state.*coordinates \['q2'\]"):
        eom.accelerations([0.3, -0.2], [0.0, 0.0], {"m1": 1.0, "m2": 0.0})
    assert np.all(np.isfinite(eom.accelerations([0.3, -0.2], [0.0, 0.0], P)))


def test_singular_mass_matrix_is_a_model_definition_error():
    assert issubclass(mb.SingularMassMatrixError, mb.ModelDefinitionError)
    for err in (mb.ModelDefinitionError, mb.DimensionError, mb.ParameterError, mb.SingularMassMatrixError):
        assert issubclass(err, ValueError) and issubclass(err, mb.MbsymError)


# --------------------------------------------------------------------------- stray symbols
def test_stray_symbol_in_body_mass():
    sys = mb.System()
    q = sys.coordinates("q")
    rogue = ca.SX.sym("rogue")
    with pytest.raises(mb.ModelDefinitionError, match=r"property of body 'b'.*\['rogue'\].*sys\.parameters"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 2 * rogue, com=[1, 0, 0]), axis=[0, 0, 1],
                                  coordinate=q))


def test_stray_symbol_in_joint_offset():
    sys = mb.System()
    q = sys.coordinates("q")
    with pytest.raises(mb.ModelDefinitionError, match=r"joint offset.*\['L'\]"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[1, 0, 0]), axis=[0, 0, 1], coordinate=q,
                                  offset=[0, 0, ca.SX.sym("L")]))


def test_speed_or_input_in_body_property_rejected():
    sys = mb.System()
    q = sys.coordinates("q")
    u = sys.inputs("u")
    with pytest.raises(mb.ModelDefinitionError, match=r"\['q_d'\].*coordinates or parameters"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0 + sys.speed(q), com=[1, 0, 0]), axis=[0, 0, 1],
                                  coordinate=q))
    with pytest.raises(mb.ModelDefinitionError, match=r"\['u'\].*coordinates or parameters"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[u, 0, 0]), axis=[0, 0, 1], coordinate=q))


def _one_body():
    sys = mb.System()
    q = sys.coordinates("q")
    body = mb.RigidBody("b", 1.0, com=[1, 0, 0])
    sys.add_joint(mb.Revolute(sys.ground, body, axis=[0, 0, 1], coordinate=q))
    return sys, q, body


@pytest.mark.parametrize("add, what", [
    (lambda s, q, b, x: s.add_force(b, [x, 0, 0]), "force on 'b'"),
    (lambda s, q, b, x: s.add_force(b, [1, 0, 0], point=[x, 0, 0]), "point of the force on 'b'"),
    (lambda s, q, b, x: s.add_torque(b, [0, 0, x]), "torque on 'b'"),
    (lambda s, q, b, x: s.add_generalized_force(q, x * q), "generalized force"),
    (lambda s, q, b, x: s.add_spring(q, x), "spring stiffness"),
    (lambda s, q, b, x: s.add_spring(q, 1.0, rest=x), "spring rest position"),
    (lambda s, q, b, x: s.add_damper(q, x), "damping"),
    (lambda s, q, b, x: s.set_gravity([0, 0, x]), "gravity"),
])
def test_stray_symbol_in_loads(add, what):
    sys, q, body = _one_body()
    n_loads = len(sys.loads)
    with pytest.raises(mb.ModelDefinitionError, match=rf"{re.escape(what)} contains symbols \['stray'\]"):
        add(sys, q, body, ca.SX.sym("stray"))
    assert len(sys.loads) == n_loads


def test_stray_symbol_in_constructor_gravity():
    g = ca.SX.sym("g")
    with pytest.raises(mb.ModelDefinitionError, match=r"gravity.*\['g'\]"):
        sys = mb.System(gravity=[0.0, 0.0, -g])
        q = sys.coordinates("q")
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, com=[0, 0, -1]), axis=[0, 1, 0], coordinate=q))
        sys.equations()


@pytest.mark.parametrize("load", [
    lambda s, x: s.add_spring(x, s.inputs("u")),
    lambda s, x: s.add_damper(x, s.speed(x)),
])
def test_time_varying_values_rejected_where_constant_required(load):
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", 1.0), axis=[1, 0, 0], coordinate=x))
    with pytest.raises(mb.ModelDefinitionError, match=r"contains symbols \['(u|x_d)'\].*coordinates or parameters"):
        load(sys, x)


def test_coordinate_dependent_joint_rotation_rejected_or_exact():
    """A joint rotation must be constant: a coordinate in it would turn b2 without its rate entering
    the kinematics (M would be 3.0 instead of m1 + m2 + Izz = 3.5), so it is rejected."""
    sys = mb.System()
    x = sys.coordinates("x")
    b1 = mb.RigidBody("b1", 1.0)
    b2 = mb.RigidBody("b2", 2.0, inertia=[0.3, 0.2, 0.5])
    sys.add_joint(mb.Prismatic(sys.ground, b1, axis=[1, 0, 0], coordinate=x))
    with pytest.raises(mb.ModelDefinitionError, match=r"depends on coordinates \['x'\].*must be constant"):
        sys.add_joint(mb.Fixed(b1, b2, rotation=mb.rotation("z", x)))
    assert len(sys.joints) == 1


def test_coordinate_dependent_com_rejected_or_exact():
    """A body com must be constant: com = [x, 0, 0] on a prismatic joint x would need M = 4 m but
    its rate would be ignored (M = m), so it is rejected."""
    sys = mb.System()
    x = sys.coordinates("x")
    with pytest.raises(mb.ModelDefinitionError, match=r"depends on coordinates \['x'\].*must be constant"):
        sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", 2.0, com=[x, 0, 0]), axis=[1, 0, 0], coordinate=x))
    assert len(sys.joints) == 0


# --------------------------------------------------------------------------- loads on foreign bodies
def test_load_on_body_not_in_system():
    sys, q, body = _one_body()
    loose = mb.RigidBody("loose", 1.0)
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'loose' is not in this system"):
        sys.add_force(loose, [1, 0, 0])
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'loose' is not in this system"):
        sys.add_torque(loose, [1, 0, 0])
    twin = mb.RigidBody("b", 1.0)          # same name as the system's body, different object
    with pytest.raises(mb.ModelDefinitionError, match=r"body 'b' is not in this system"):
        sys.add_force(twin, [1, 0, 0])
    with pytest.raises(mb.ModelDefinitionError, match=r"must act on a body of the system"):
        sys.add_force(sys.ground, [1, 0, 0])
    with pytest.raises(mb.ModelDefinitionError, match=r"frame .* is not a body of this system"):
        sys.add_force(body, [1, 0, 0], frame=loose)
    assert sys.loads == ()


def test_generalized_load_on_unknown_coordinate():
    sys, q, body = _one_body()
    other = mb.System().coordinates("z")
    for add in (lambda: sys.add_spring(other, 1.0), lambda: sys.add_damper(q * 2, 1.0),
                lambda: sys.add_generalized_force(other, 1.0), lambda: sys.speed(other)):
        with pytest.raises(mb.ModelDefinitionError, match=r"is not a coordinate of this system"):
            add()


def test_load_wrong_sizes():
    sys, q, body = _one_body()
    with pytest.raises(mb.DimensionError, match=r"force on 'b' has 2 entries; expected 3"):
        sys.add_force(body, [1, 0])
    with pytest.raises(mb.DimensionError, match=r"torque on 'b' has 4 entries; expected 3"):
        sys.add_torque(body, [1, 0, 0, 0])
    with pytest.raises(mb.DimensionError, match=r"generalized force.*2 elements; expected a scalar"):
        sys.add_generalized_force(q, ca.SX.zeros(2, 1))
    assert sys.loads == ()


# --------------------------------------------------------------------------- bad numbers in the description
def test_non_finite_numbers_in_description():
    with pytest.raises(mb.ModelDefinitionError, match=r"mass of body 'b'.*expected a finite number"):
        mb.RigidBody("b", float("nan"))
    with pytest.raises(mb.ModelDefinitionError, match=r"gravity.*expected a finite number"):
        mb.System(gravity=[0, 0, float("inf")])
    with pytest.raises(mb.ModelDefinitionError, match=r"com of body 'b'.*'1' \(str\)"):
        mb.RigidBody("b", 1.0, com=[0, 0, "1"])
    with pytest.raises(mb.DimensionError, match=r"inertia of body 'b' has 4 entries"):
        mb.RigidBody("b", 1.0, inertia=[1, 2, 3, 4])
    with pytest.raises(mb.ModelDefinitionError, match=r"body name 'my body' is not a valid identifier"):
        mb.RigidBody("my body", 1.0)


def test_bad_default_parameter_values():
    sys = mb.System()
    with pytest.raises(mb.ParameterError, match=r"default value of 'k' is inf; expected a finite number"):
        sys.parameters("m k", values={"k": float("inf")})
    with pytest.raises(mb.ParameterError, match=r"default values given for \['c'\], which are not among"):
        sys.parameters("m k", values={"c": 1.0})
    with pytest.raises(mb.ModelDefinitionError, match=r"1 default values given for 2 parameters"):
        sys.parameters("m k", values=[1.0])
    assert sys.symbols.names("parameter") == []


# --------------------------------------------------------------------------- unknown keyword arguments
@pytest.mark.parametrize("call", [
    lambda s, q, b, e: mb.System(gravty=[0, 0, -9.81]),
    lambda s, q, b, e: mb.RigidBody("c", mass=1.0, centre=[0, 0, 0]),
    lambda s, q, b, e: mb.Revolute(s.ground, mb.RigidBody("c", 1.0), axis=[0, 0, 1], coordinate=q, offest=[0, 0, 0]),
    lambda s, q, b, e: mb.Prismatic(s.ground, mb.RigidBody("c", 1.0), axis=[0, 0, 1], coordinate=q, rot=None),
    lambda s, q, b, e: mb.Fixed(s.ground, mb.RigidBody("c", 1.0), axis=[0, 0, 1]),
    lambda s, q, b, e: mb.Free(s.ground, mb.RigidBody("c", 1.0), coordinates=[q] * 6, seq="xyz"),
    lambda s, q, b, e: s.add_force(b, [1, 0, 0], pont=[0, 0, 0]),
    lambda s, q, b, e: s.add_torque(b, [1, 0, 0], point=[0, 0, 0]),
    lambda s, q, b, e: s.add_spring(q, 1.0, rest_length=0.0),
    lambda s, q, b, e: s.add_damper(q, 1.0, rest=0.0),
    lambda s, q, b, e: s.parameters("k", default={"k": 1.0}),
    lambda s, q, b, e: s.equations(nam="x"),
    lambda s, q, b, e: e.mass_matrix([0.0], params={}),
    lambda s, q, b, e: e.forcing([0.0], [0.0], inputs=[]),
])
def test_unknown_keyword_arguments(call):
    sys, q, body = _one_body()
    e = sys.equations()
    n_loads, n_par = len(sys.loads), len(sys.symbols.names("parameter"))
    with pytest.raises(TypeError, match=r"unexpected keyword argument"):
        call(sys, q, body, e)
    assert len(sys.loads) == n_loads and len(sys.symbols.names("parameter")) == n_par


# --------------------------------------------------------------------------- failed calls change nothing
def test_failed_add_joint_leaves_system_unchanged():
    """Each failure mode of add_joint, then the correct call: the system builds and its M at q = 0
    is the double pendulum's closed form (m1=2, m2=1, l1=1, l2=0.5):
    [[(m1+m2) l1^2 + m2 l2^2 + 2 m2 l1 l2, m2 l2^2 + m2 l1 l2], [., m2 l2^2]] = [[4.25, 0.75], [0.75, 0.25]]."""
    sys = mb.System(gravity=[0, 0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    b1 = mb.RigidBody("b1", 2.0, com=[0, 0, -1])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    snapshot = (sys.joints, sys.bodies, sys.loads)
    bad_calls = [
        lambda: sys.add_joint(mb.Revolute(b1, mb.RigidBody("b2", 1.0, com=[0, 0, -0.5]), axis=[0, 1, 0],
                                          coordinate=q1, offset=[0, 0, -1])),                     # q1 used
        lambda: sys.add_joint(mb.Revolute(b1, mb.RigidBody("b2", ca.SX.sym("m"), com=[0, 0, -0.5]),
                                          axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -1])),     # stray symbol
        lambda: sys.add_joint(mb.Revolute(b1, mb.RigidBody("b1", 1.0), axis=[0, 1, 0], coordinate=q2)),  # name
        lambda: sys.add_joint(mb.Free(b1, mb.RigidBody("b2", 1.0), coordinates=[q2, q2, q2, q2, q2, q2])),
    ]
    for bad in bad_calls:
        with pytest.raises(mb.ModelDefinitionError):
            bad()
        assert (sys.joints, sys.bodies, sys.loads) == snapshot
    b2 = mb.RigidBody("b2", 1.0, com=[0, 0, -0.5])
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -1]))
    M = sys.equations().mass_matrix([0.0, 0.0])
    np.testing.assert_allclose(M, [[3.0 + 0.25 + 1.0, 0.25 + 0.5], [0.75, 0.25]], rtol=1e-12)


def test_failed_parameters_call_declares_nothing():
    sys = mb.System()
    sys.coordinates("q")
    for bad, err in [(lambda: sys.parameters("a b q"), mb.ModelDefinitionError),         # q taken
                     (lambda: sys.parameters("a b", values=[1.0, float("nan")]), mb.ParameterError),
                     (lambda: sys.parameters("a b", values={"a": 1.0, "z": 2.0}), mb.ParameterError),
                     (lambda: sys.parameters("a b b"), mb.ModelDefinitionError),
                     (lambda: sys.parameters("a 2b"), mb.ModelDefinitionError)]:
        with pytest.raises(err):
            bad()
        assert sys.symbols.names("parameter") == []
    a, b = sys.parameters("a b", values={"a": 1.0})        # the names are still free
    assert sys.symbols.names("parameter") == ["a", "b"] and sys.symbols.defaults() == {"a": 1.0}


def test_failed_coordinates_and_inputs_calls_declare_nothing():
    sys = mb.System()
    sys.parameters("m")
    with pytest.raises(mb.ModelDefinitionError):
        sys.coordinates("q1 m")
    with pytest.raises(mb.ModelDefinitionError):
        sys.inputs("u m")
    assert sys.symbols.names("coordinate") == [] and sys.symbols.names("input") == []
    sys.coordinates("q1")
    sys.inputs("u")


def test_failed_load_calls_leave_loads_unchanged_and_model_builds():
    sys, q, body = _one_body()
    with pytest.raises(mb.ModelDefinitionError):
        sys.add_force(body, [ca.SX.sym("f"), 0, 0])
    with pytest.raises(mb.DimensionError):
        sys.add_torque(body, [0, 0])
    sys.add_spring(q, 4.0)
    e = sys.equations()
    np.testing.assert_allclose(e.forcing([0.5], [0.0]), [-2.0], rtol=1e-12)   # only the spring acts


def test_coordinate_dependent_inertia_rejected():
    """inertia = 1 + th**2 would need -½ I'(th) thd² in F; constant quantities reject coordinates."""
    sys = mb.System()
    th = sys.coordinates("th")
    with pytest.raises(mb.ModelDefinitionError, match=r"depends on coordinates \['th'\]"):
        sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("b", 1.0, inertia=[1, 1, 1 + th**2]),
                                  axis=[0, 0, 1], coordinate=th))
    assert sys.bodies == ()


def test_rhs_with_singular_mass_names_the_coordinate():
    """rhs never returns NaN silently: with m2 = 0 the point mass b2 on its own link leaves q2 massless."""
    from mbsym.demo import double_pendulum
    eom = double_pendulum().equations()
    with pytest.raises(mb.SingularMassMatrixError, match=r"q2"):
        eom.rhs([0.1, 0.2, 0.0, 0.0], {"m1": 1.0, "m2": 0.0, "l1": 1.0, "l2": 0.5})
