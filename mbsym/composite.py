"""Composite rigid bodies: rigid bodies welded together by Fixed joints count once.

A rigid body fixed to a rigid parent moves with it, so in Kane's sums the two are
one rigid body whose mass properties are the sum of theirs. Merging them before
the assembly is exact and keeps the equations small (a turbine's nacelle and
shaft, or a hub and its rigid blades, become one body). Kinematics of every body
are still available for loads and outputs.

Mass properties are kept about the body *origin* (mass ``m``, first moment
``S = m c`` and inertia ``I_O`` about the origin, body axes), so that sums never
divide by a mass that may be zero or symbolic.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .bodies.rigid import RigidBody
from .joints import Fixed

__all__ = ["MassProperties", "mass_properties", "composite_bodies"]


@dataclass(frozen=True)
class MassProperties:
    """Rigid-body mass properties about the body origin, body axes (SX)."""

    mass: ca.SX            # [kg]
    first_moment: ca.SX    # m * com [kg m] (3x1)
    inertia: ca.SX         # about the origin [kg m^2] (3x3)


def _piece(mass, com, inertia_g) -> MassProperties:
    """One rigid piece of mass ``mass`` at ``com`` with inertia ``inertia_g`` about its COM."""
    shift = mass * (ca.dot(com, com) * ca.SX.eye(3) - com @ com.T)
    return MassProperties(mass, mass * com, inertia_g + shift)


def mass_properties(body: RigidBody) -> MassProperties:
    """Mass properties of a single rigid body about its origin."""
    return _piece(body.mass, body.com, body.inertia)


def _add(a: MassProperties, b: MassProperties) -> MassProperties:
    return MassProperties(a.mass + b.mass, a.first_moment + b.first_moment, a.inertia + b.inertia)


def composite_bodies(joints) -> tuple[dict[int, MassProperties], set[int]]:
    """Merge rigid bodies welded by Fixed joints into their rigid ancestors.

    Parameters
    ----------
    joints : sequence of Joint
        The system's joints (any order).

    Returns
    -------
    composites : dict
        ``id(root body) -> MassProperties`` of the root and everything welded to it.
    merged : set
        ``id`` of the bodies folded into a root (they take no part in Kane's sums).
    """
    by_child = {id(j.child): j for j in joints}
    root_of: dict[int, tuple[RigidBody, ca.SX, ca.SX]] = {}   # child id -> (root, offset, rotation)

    def resolve(body) -> tuple[RigidBody, ca.SX, ca.SX]:
        """Root of ``body`` and the body's origin and axes in the root frame."""
        key = id(body)
        if key in root_of:
            return root_of[key]
        j = by_child.get(key)
        if isinstance(j, Fixed) and isinstance(j.parent, RigidBody) and isinstance(body, RigidBody):
            root, o, R = resolve(j.parent)
            result = (root, o + R @ j.offset, R @ j.rotation)
        else:
            result = (body, ca.SX.zeros(3, 1), ca.SX.eye(3))
        root_of[key] = result
        return result

    composites: dict[int, MassProperties] = {}
    merged: set[int] = set()
    for j in joints:
        body = j.child
        if not isinstance(body, RigidBody):
            continue
        root, o, R = resolve(body)
        if root is body:
            composites.setdefault(id(body), mass_properties(body))
            continue
        merged.add(id(body))
        piece = _piece(body.mass, o + R @ body.com, R @ body.inertia @ R.T)
        composites[id(root)] = _add(composites.get(id(root), mass_properties(root)), piece)
    return composites, merged
