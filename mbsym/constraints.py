"""Closed kinematic loops: the description of holonomic constraints on a tree.

A closed loop is described by cutting one of its joints: the tree that remains is an ordinary
:class:`~mbsym.System`, and the cut joint is replaced by constraints ``g(q, p) = 0`` that close the
loop again. Two kinds are recorded here (the System's ``add_closure`` and ``add_constraint`` call
these constructors, then keep the records):

- :class:`PointClosure`: a point of body *a* and a point of body *b* coincide along chosen ground
  axes (``"xz"`` for a planar loop in the x-z plane, ``"xyz"`` for a spherical cut joint). Its
  rows are ``g = e_kᵀ (r_b(q) - r_a(q))``; its multipliers are the force [N] that body *a* exerts
  on body *b* through the cut joint, ground axes.
- :class:`HolonomicConstraint`: any expressions ``g(q, p) = 0`` of coordinates and parameters (its
  multipliers are generalized reaction forces in the units of ``[force] / [g]``).

- :class:`VelocityConstraint`: non-holonomic rows ``A(q, p) q̇ + b(q, p) = 0`` (a knife edge, a
  rolling contact), linear in the speeds; their equations are first-order dynamics
  (:mod:`mbsym.loops.nonholonomic`).

:func:`constraint_rows` turns the holonomic records into one SX vector of the tree's coordinates,
with a name per row; the equations live in :mod:`mbsym.loops`.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .bodies.base import Body, Ground
from .exceptions import ModelDefinitionError
from .kinematics import as_vector3

__all__ = ["PointClosure", "HolonomicConstraint", "VelocityConstraint", "constraint_rows", "AXES"]

#: Ground axes a point closure may act along.
AXES = "xyz"


@dataclass(frozen=True)
class PointClosure:
    """Points of two bodies that coincide along some ground axes (a cut joint).

    Attributes
    ----------
    name : str
        Name of the closure; its reaction channels are ``<name>_F<axis>``.
    body_a, body_b : Body
        The two bodies (either may be the ground).
    point_a, point_b : SX (3x1)
        The points in each body's frame [m] (parameters allowed).
    directions : str
        Ground axes along which the points coincide, e.g. ``"xz"``.
    """

    name: str
    body_a: Body
    point_a: ca.SX
    body_b: Body
    point_b: ca.SX
    directions: str

    @property
    def row_names(self) -> list[str]:
        """One name per constraint row (also the reaction channel names)."""
        return [f"{self.name}_F{a}" for a in self.directions]


def _lambda_names(name: str, n: int) -> list[str]:
    """Multiplier names of an ``n``-row constraint: ``<name>_lambda``, or numbered from 1."""
    return [f"{name}_lambda"] if n == 1 else [f"{name}_lambda{i + 1}" for i in range(n)]


@dataclass(frozen=True)
class HolonomicConstraint:
    """A general holonomic constraint ``g(q, p) = 0`` (one or more rows)."""

    name: str
    expression: ca.SX

    @property
    def row_names(self) -> list[str]:
        return _lambda_names(self.name, self.expression.numel())


@dataclass(frozen=True)
class VelocityConstraint:
    """A non-holonomic constraint ``A(q, p) q̇ + b(q, p) = 0`` (one or more rows, linear in the speeds)."""

    name: str
    expression: ca.SX

    @property
    def row_names(self) -> list[str]:
        return _lambda_names(self.name, self.expression.numel())


def point_closure(name: str, body_a, point_a, body_b, point_b, directions) -> PointClosure:
    """Check the arguments of a point closure (not yet against a System) and build the record.

    Raises
    ------
    ModelDefinitionError
        If a body is not a Body, both are the same body, a point does not have 3 entries or the
        directions are not a non-empty string of distinct letters among ``"xyz"``.
    """
    for b, which in ((body_a, "body_a"), (body_b, "body_b")):
        if not isinstance(b, Body):
            raise ModelDefinitionError(f"add_closure: {which} must be a body of the system (or sys.ground); "
                                       f"got {b!r}.")
    if body_a is body_b:
        raise ModelDefinitionError(f"add_closure: body_a and body_b are both {body_a.name!r}; a closure joins "
                                   "two different bodies (the two sides of the cut joint).")
    if not isinstance(directions, str) or not directions or any(c not in AXES for c in directions) \
            or len(set(directions)) != len(directions):
        raise ModelDefinitionError(f"add_closure: directions={directions!r} is not valid; give distinct ground axes "
                                   "among 'x', 'y', 'z' as one string, e.g. 'xz' for a planar loop in the x-z "
                                   "plane or 'xyz' for a spatial loop.")
    pa = as_vector3(point_a, f"point_a of closure {name!r}")
    pb = as_vector3(point_b, f"point_b of closure {name!r}")
    order = "".join(c for c in AXES if c in directions)
    return PointClosure(name, body_a, pa, body_b, pb, order)


def holonomic_constraint(name: str, expression) -> HolonomicConstraint:
    """Build the record of a general constraint from an SX expression (or a sequence of them)."""
    try:
        g = ca.vec(ca.SX(expression)) if not isinstance(expression, (list, tuple)) \
            else ca.vertcat(*[ca.SX(e) for e in expression])
    except (NotImplementedError, TypeError, RuntimeError) as exc:
        raise ModelDefinitionError(f"add_constraint: the constraint {name!r} must be a CasADi SX expression (or a "
                                   f"list of them) of coordinates and parameters; got {expression!r}.") from exc
    if g.numel() == 0:
        raise ModelDefinitionError(f"add_constraint: the constraint {name!r} is empty; give at least one expression.")
    return HolonomicConstraint(name, g)


def check_name(name, taken: list[str], default: str) -> str:
    """A constraint name: ``default`` when None, else a new identifier."""
    if name is None:
        return default
    if not isinstance(name, str) or not name.isidentifier():
        raise ModelDefinitionError(f"constraint name {name!r} is not a valid identifier; use letters, digits, '_'.")
    if name in taken:
        raise ModelDefinitionError(f"a constraint named {name!r} already exists; constraints are {taken}.")
    return name


def constraint_rows(constraints, kin) -> tuple[ca.SX, ca.SX, list[str]]:
    """All constraint rows ``g(q, p)``, their velocities ``ġ(q, q̇, p)`` and their names.

    The velocities are the tree's own point velocities (``kin.point_velocity``): for rigid bodies
    exactly ``∂g/∂q q̇``; for flexible bodies the attachment kinematics' velocity, which is what
    Kane's partial velocities of the tree use (it differs from ``d/dt`` of the position at first
    order in the deflection times the speed). Held attachment orientations are resolved in ``g``
    and left in ``ġ`` (for :meth:`~mbsym.kane._Kinematics.rate`).

    Parameters
    ----------
    constraints : sequence of PointClosure or HolonomicConstraint
    kin : mbsym.kane._Kinematics
        The tree's kinematics (positions and velocities of body points).
    """
    rows, vels, names = [], [], []
    for c in constraints:
        if isinstance(c, PointClosure):
            ra, va = _point(kin, c.body_a, c.point_a)
            rb, vb = _point(kin, c.body_b, c.point_b)
            for a in c.directions:
                rows.append((rb - ra)[AXES.index(a)])
                vels.append((vb - va)[AXES.index(a)])
        else:
            rows.extend(ca.vertsplit(c.expression))
            vels.extend(ca.vertsplit(ca.jtimes(c.expression, kin.q_all, kin.qd_all)))
        names.extend(c.row_names)
    g = ca.vertcat(*rows)
    return kin.resolve([g])[0], ca.vertcat(*vels), names


def _point(kin, body: Body, point: ca.SX) -> tuple[ca.SX, ca.SX]:
    if isinstance(body, Ground):
        return point, ca.SX.zeros(3, 1)
    return kin.point_velocity(body, point)
