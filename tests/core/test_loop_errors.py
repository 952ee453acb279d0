"""Closed loops: the general holonomic-constraint API, and every error path with its typed exception.

Reference for ``add_constraint``: the same four-bar closed by ``add_closure`` (identical equations, 1e-12:
the same constraint rows written by hand), and its multipliers equal the closure's reactions with the sign
of the rows. Errors: each bad input raises the documented exception with a message naming what is wrong.
Runtime < 2 s.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import ConstraintError, DimensionError, ModelDefinitionError, OptionError, UnsupportedFeatureError

LEN = (1.0, 2.0, 2.0, 2.5)


def tree(ground_link: float = LEN[3]):
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    qs = s.coordinates("q1 q2 q3")
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l in zip(("crank", "coupler", "rocker"), qs, LEN):
        body = mb.RigidBody(name, 1.0, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.1, 0.1]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    return s, qs, ground_link


def closed(directions="xy", ground_link=LEN[3]):
    s, _, d = tree(ground_link)
    s.add_closure(s.body("rocker"), [LEN[2], 0, 0], s.ground, [d, 0, 0], directions=directions)
    return s


GUESS = {"q2": 1.2, "q3": -2.4}


def test_general_constraint_gives_the_closure_equations():
    a = closed().equations(independent=["q1"], guess=GUESS)
    s, (q1, q2, q3), d = tree()
    t1, t2, t3 = q1, q1 + q2, q1 + q2 + q3
    tip = [LEN[0] * ca.cos(t1) + LEN[1] * ca.cos(t2) + LEN[2] * ca.cos(t3),
           LEN[0] * ca.sin(t1) + LEN[1] * ca.sin(t2) + LEN[2] * ca.sin(t3)]
    s.add_constraint([d - tip[0], -tip[1]], name="loop")
    b = s.equations(independent=["q1"], guess=GUESS)
    assert b.constraint_names == ("loop_lambda1", "loop_lambda2")
    for q, w in [(0.4, 1.0), (2.0, -2.0)]:
        assert np.allclose(a.mass_matrix([q]), b.mass_matrix([q]), rtol=1e-12, atol=1e-12)
        assert np.allclose(a.forcing([q], [w]), b.forcing([q], [w]), rtol=1e-12, atol=1e-12)
        assert np.allclose(a.constraint_forces([q], [w]), b.constraint_forces([q], [w]), rtol=1e-10, atol=1e-10)


def test_bad_closures_leave_the_system_unchanged():
    s, _, _ = tree()
    other = mb.RigidBody("stray", 1.0)
    for kwargs, match in [(dict(directions="xw"), "directions"), (dict(directions=""), "directions"),
                          (dict(directions="xx"), "directions")]:
        with pytest.raises(ModelDefinitionError, match=match):
            s.add_closure(s.body("rocker"), [2, 0, 0], s.ground, [2.5, 0, 0], **kwargs)
    with pytest.raises(ModelDefinitionError, match="not in this system"):
        s.add_closure(other, [0, 0, 0], s.ground, [0, 0, 0], directions="xy")
    with pytest.raises(ModelDefinitionError, match="two different bodies"):
        s.add_closure(s.body("rocker"), [0, 0, 0], s.body("rocker"), [1, 0, 0])
    with pytest.raises(DimensionError, match="point_a .* expected 3"):
        s.add_closure(s.body("rocker"), [2, 0], s.ground, [2.5, 0, 0])
    assert s.constraints == ()
    q1 = s.symbols.symbols("coordinate")[0]
    with pytest.raises(ModelDefinitionError, match="no coordinate"):
        s.add_constraint(ca.SX(1.0))
    with pytest.raises(ModelDefinitionError, match="not coordinates"):
        s.add_constraint(q1 - ca.SX.sym("zz"))
    with pytest.raises(ModelDefinitionError, match="coordinates or parameters"):
        s.add_constraint(s.speed(q1))
    assert s.constraints == ()


def test_independent_and_guess_are_checked():
    s = closed()
    with pytest.raises(ConstraintError, match="independent coordinates"):
        s.equations()
    with pytest.raises(ConstraintError, match="leave 1 degrees of freedom"):
        s.equations(independent=["q1", "q2"], guess=GUESS)
    with pytest.raises(ConstraintError, match="not distinct coordinates"):
        s.equations(independent=["q9"], guess=GUESS)
    with pytest.raises(ConstraintError, match="list of coordinate names"):
        s.equations(independent="q1", guess=GUESS)
    with pytest.raises(ConstraintError, match="unknown coordinates"):
        s.equations(independent=["q1"], guess={"q7": 1.0})
    with pytest.raises(ConstraintError, match="finite"):
        s.equations(independent=["q1"], guess={"q2": float("nan")})
    with pytest.raises(OptionError, match="stages"):
        s.equations(independent=["q1"], guess=GUESS, stages=0)
    with pytest.raises(ConstraintError, match="no closure"):
        tree()[0].equations(independent=["q1"])


def test_redundant_row_is_named():
    with pytest.raises(ConstraintError, match="'closure1_Fz' is redundant"):
        closed("xyz").equations(independent=["q1"], guess=GUESS)
    s = closed()
    s.add_closure(s.body("rocker"), [LEN[2], 0, 0], s.ground, [LEN[3], 0, 0], directions="y", name="again")
    with pytest.raises(ConstraintError, match=r"'again_Fy' is redundant.*closure1_Fy"):
        s.equations(independent=["q1"], guess=GUESS)


def test_inconsistent_loop_is_named():
    with pytest.raises(ConstraintError, match="cannot be satisfied.*closure1_Fx"):
        closed(ground_link=10.0).equations(independent=["q1"], guess=GUESS)


def test_badly_chosen_independent_coordinate_gets_a_suggestion():
    """A slider-crank at dead centre with the slider as independent coordinate: crank and rod angles both move
    the pin across the guide only, so they cannot follow the slider there."""
    s = mb.System()
    q1, q2, x = s.coordinates("q1 q2 x")
    crank, rod, slider = (mb.RigidBody(n, 1.0, com=[0.1, 0, 0], inertia=np.eye(3) * 0.1) for n in ("c", "r", "s"))
    s.add_joint(mb.Revolute(s.ground, crank, axis=[0, 0, 1], coordinate=q1))
    s.add_joint(mb.Revolute(crank, rod, axis=[0, 0, 1], coordinate=q2, offset=[0.5, 0, 0]))
    s.add_joint(mb.Prismatic(s.ground, slider, axis=[1, 0, 0], coordinate=x))
    s.add_closure(rod, [1.5, 0, 0], slider, [0, 0, 0], directions="xy")
    with pytest.raises(ConstraintError, match=r"do not determine the dependent coordinates \['q1', 'q2'\].*"
                                              r"independent \['q(1|2)'\]"):
        s.equations(independent=["x"], guess={"x": 2.0})
    assert s.equations(independent=["q1"], guess={"x": 2.0}).dependent == ("q2", "x")


def test_prescribed_coordinates_with_a_loop_are_refused():
    s, _, _ = tree()
    spin = s.prescribed("spin")
    s.add_joint(mb.Revolute(s.body("crank"), mb.RigidBody("disc", 1.0), axis=[0, 0, 1], coordinate=spin))
    s.add_closure(s.body("rocker"), [LEN[2], 0, 0], s.ground, [LEN[3], 0, 0], directions="xy")
    with pytest.raises(UnsupportedFeatureError, match="prescribed"):
        s.equations(independent=["q1"], guess=GUESS)


def test_parameters_without_defaults_assemble_in_the_graph():
    """Link lengths as parameters without defaults: a ModelWarning, then the same equations as the numeric
    model at those values (1e-12), the loop assembled from the guess at every evaluation."""
    from mbsym.exceptions import ModelWarning

    s = mb.System(gravity=[0.0, -9.81, 0.0])
    qs = s.coordinates("q1 q2 q3")
    ls = s.parameters("l1 l2 l3 l4")
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for name, q, l in zip(("crank", "coupler", "rocker"), qs, ls[:3]):
        body = mb.RigidBody(name, 1.0, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.1, 0.1]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    s.add_closure(parent, [ls[2], 0, 0], s.ground, [ls[3], 0, 0], directions="xy")
    with pytest.warns(ModelWarning, match="no default value"):
        sym = s.equations(independent=["q1"], guess=GUESS)
    p = dict(zip(("l1", "l2", "l3", "l4"), LEN))
    s_numeric = tree()[0]
    s_numeric.add_closure(s_numeric.body("rocker"), [LEN[2], 0, 0], s_numeric.ground, [LEN[3], 0, 0], directions="xy")
    ref = s_numeric.equations(independent=["q1"], guess=GUESS)
    for q, w in [(0.3, 1.0), (2.0, -1.0)]:
        assert np.allclose(sym.forcing([q], [w], p), ref.forcing([q], [w]), rtol=1e-12, atol=1e-12)
        assert np.allclose(sym.configuration([q], p), ref.configuration([q]), rtol=0, atol=1e-12)
