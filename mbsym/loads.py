"""Loads applied to a system: point forces, torques and generalized forces.

Loads are plain records; :mod:`mbsym.kane` turns them into generalized forces.
Gravity is not a load record: the system applies it to every body's mass.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from .bodies.base import Body

__all__ = ["PointForce", "Torque", "GeneralizedForce", "Spring", "Damper", "DistributedLoad"]


@dataclass(frozen=True)
class PointForce:
    """Force [N] on ``body`` at ``point`` (body coordinates [m]), components in ``frame``.

    ``frame`` is ``None`` for the ground (inertial) axes or a body whose axes
    the components are given in.
    """

    body: Body
    force: ca.SX
    point: ca.SX
    frame: Body | None


@dataclass(frozen=True)
class Torque:
    """Torque [N m] on ``body``, components in ``frame`` (None: ground axes)."""

    body: Body
    torque: ca.SX
    frame: Body | None


@dataclass(frozen=True)
class GeneralizedForce:
    """Generalized force added to the equation of coordinate ``index`` [N or N m]."""

    index: int
    value: ca.SX


@dataclass(frozen=True)
class Spring:
    """Linear spring on a coordinate: ``Q = -stiffness (q - rest)``; stores ``½ k (q - rest)²``."""

    index: int
    stiffness: ca.SX
    rest: ca.SX


@dataclass(frozen=True)
class Damper:
    """Linear damper on a coordinate: ``Q = -damping * qd``."""

    index: int
    damping: ca.SX


@dataclass(frozen=True)
class DistributedLoad:
    """Distributed force ``w(z) P d`` on a flexible body (paper A17-A19).

    ``integrals`` holds the profile's shape integrals per unit magnitude
    (:func:`mbsym.beam.distributed_load_integrals`); ``magnitude`` is ``P`` [N/m].
    """

    body: Body
    integrals: object
    magnitude: ca.SX
