"""Joints: how a child body's frame is placed relative to its parent's.

Every joint defines a *joint frame* fixed to the parent: its origin is at
``offset`` (parent coordinates, [m]) and its axes are the parent's axes turned
by the constant ``rotation``. The child frame is then moved relative to the
joint frame by the joint's coordinates:

``r_child = r_joint + R_joint @ d(q)``, ``R_child = R_joint @ R_rel(q)``.

Subclasses only supply ``d(q)`` (translation, joint axes) and ``R_rel(q)``.
When the parent is a flexible body, the joint frame also follows the elastic
displacement and slope of the attachment point (see ``Body.attachment``).
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca
import numpy as np

from .bodies.base import Body, Ground
from .exceptions import DimensionError, ModelDefinitionError
from .kinematics import as_matrix3, as_vector3, rotation_about, rotation_sequence

__all__ = ["Joint", "Fixed", "Revolute", "Prismatic", "Free"]


class Joint:
    """Base class of joints. Use one of the subclasses."""

    def __init__(self, parent: Body, child: Body, *, offset=(0.0, 0.0, 0.0), rotation=None,
                 coordinates: Sequence = ()) -> None:
        if not isinstance(parent, Body):
            raise ModelDefinitionError(f"joint parent must be a Body (or sys.ground); got {parent!r}.")
        if not isinstance(child, Body):
            raise ModelDefinitionError(f"joint child must be a Body; got {child!r}.")
        if isinstance(child, Ground):
            raise ModelDefinitionError("the ground cannot be the child of a joint; swap parent and child.")
        if parent is child:
            raise ModelDefinitionError(f"joint connects body {child.name!r} to itself.")
        self.parent = parent
        self.child = child
        self.offset = as_vector3(offset, f"offset of the joint of {child.name!r}")
        self.rotation = ca.SX.eye(3) if rotation is None else _check_rotation(as_matrix3(
            rotation, f"rotation of the joint of {child.name!r}"), child.name)
        self.coordinates = tuple(coordinates)

    @property
    def name(self) -> str:
        """Name of the joint (that of its child body)."""
        return self.child.name

    def relative(self) -> tuple[ca.SX, ca.SX]:
        """Translation ``d`` (3x1, joint axes) [m] and rotation ``R_rel`` (3x3)."""
        return ca.SX.zeros(3, 1), ca.SX.eye(3)

    def angular_velocity(self, speed) -> ca.SX | None:
        """Angular velocity of the child relative to the joint frame, joint axes [rad/s].

        ``speed(c)`` returns the speed symbol of coordinate ``c``. ``None`` (the
        default) lets the kinematics use ``vee(Ṙ_rel R_relᵀ)``; joints whose
        convention defines the angular velocity otherwise override this.
        """
        return None

    def __repr__(self) -> str:
        names = [c.name() for c in self.coordinates]
        return f"{type(self).__name__}({self.parent.name!r} -> {self.child.name!r}, coordinates={names})"


class Fixed(Joint):
    """Rigid connection: the child frame is the joint frame.

    Parameters
    ----------
    parent, child : Body
    offset : sequence of 3, optional
        Child origin in parent coordinates [m].
    rotation : 3x3 array or SX, optional
        Orientation of the child axes in parent axes (child -> parent).
    """

    def __init__(self, parent: Body, child: Body, *, offset=(0.0, 0.0, 0.0), rotation=None) -> None:
        super().__init__(parent, child, offset=offset, rotation=rotation)


class Revolute(Joint):
    """Rotation about a fixed axis of the joint frame.

    Parameters
    ----------
    parent, child : Body
    axis : sequence of 3
        Rotation axis in joint axes (normalized here).
    coordinate : SX
        The rotation angle [rad], a coordinate declared by ``sys.coordinates``.
    offset : sequence of 3, optional
        Joint position in parent coordinates [m].
    rotation : 3x3, optional
        Constant orientation of the joint axes relative to the parent axes.
    order : int or None, optional
        ``None`` for the exact rotation; ``n`` for cos/sin truncated at order n
        (small-angle form).
    gear_ratio : float, optional
        Turn by ``gear_ratio * coordinate`` (e.g. a generator geared to the
        low-speed shaft). A geared joint may follow a coordinate that another
        joint already uses.

    Examples
    --------
    >>> import mbsym as mb
    >>> sys = mb.System(gravity=[0, 0, -9.81])
    >>> th = sys.coordinates("th")
    >>> link = mb.RigidBody("link", mass=1.0, com=[0, 0, -1.0])
    >>> sys.add_joint(mb.Revolute(sys.ground, link, axis=[0, 1, 0], coordinate=th))
    """

    def __init__(self, parent: Body, child: Body, *, axis, coordinate, offset=(0.0, 0.0, 0.0),
                 rotation=None, order: int | None = None, gear_ratio: float | None = None) -> None:
        super().__init__(parent, child, offset=offset, rotation=rotation, coordinates=[coordinate])
        self.axis = _unit_axis(axis, child.name)
        self.order = order
        if gear_ratio is not None:
            try:
                gear_ratio = float(gear_ratio)
            except (TypeError, ValueError) as exc:
                raise ModelDefinitionError(f"gear_ratio of the joint of {child.name!r} must be a number; "
                                           f"got {gear_ratio!r}.") from exc
            if not np.isfinite(gear_ratio) or gear_ratio == 0.0:
                raise ModelDefinitionError(f"gear_ratio of the joint of {child.name!r} must be a nonzero number; "
                                           f"got {gear_ratio}.")
        self.gear_ratio = gear_ratio
        angle = coordinate if gear_ratio is None else gear_ratio * coordinate
        self._R = rotation_about(self.axis, angle, order=order)

    def relative(self) -> tuple[ca.SX, ca.SX]:
        return ca.SX.zeros(3, 1), self._R


class Prismatic(Joint):
    """Translation along a fixed axis of the joint frame.

    Parameters
    ----------
    parent, child : Body
    axis : sequence of 3
        Direction of motion in joint axes (normalized here).
    coordinate : SX
        The displacement [m] along ``axis``.
    offset, rotation : optional
        Joint frame, as for :class:`Revolute`.
    """

    def __init__(self, parent: Body, child: Body, *, axis, coordinate, offset=(0.0, 0.0, 0.0),
                 rotation=None) -> None:
        super().__init__(parent, child, offset=offset, rotation=rotation, coordinates=[coordinate])
        self.axis = _unit_axis(axis, child.name)

    def relative(self) -> tuple[ca.SX, ca.SX]:
        return ca.DM(self.axis) * self.coordinates[0], ca.SX.eye(3)


class Free(Joint):
    """Six degrees of freedom: three translations then three rotations.

    Parameters
    ----------
    parent, child : Body
    coordinates : sequence of 6 SX
        ``(x, y, z, a1, a2, a3)``: translations [m] along the joint axes, then
        rotation angles [rad] about body-fixed axes in ``sequence``.
    sequence : str, optional
        Rotation sequence, e.g. ``'xyz'`` (default): ``R = Rx(a1) Ry(a2) Rz(a3)``.
    offset, rotation : optional
        Joint frame, as for :class:`Revolute`.
    order : int or None, optional
        Small-angle truncation of each elementary rotation (None: exact).
    """

    def __init__(self, parent: Body, child: Body, *, coordinates, sequence: str = "xyz",
                 offset=(0.0, 0.0, 0.0), rotation=None, order: int | None = None) -> None:
        coordinates = list(coordinates)
        if len(coordinates) != 6:
            raise DimensionError(
                f"Free joint of {child.name!r} has {len(coordinates)} coordinates; expected 6 "
                "(3 translations then 3 rotations)."
            )
        if len(sequence) != 3:
            raise ModelDefinitionError(f"Free joint rotation sequence must have 3 axes, e.g. 'xyz'; got {sequence!r}.")
        super().__init__(parent, child, offset=offset, rotation=rotation, coordinates=coordinates)
        self.sequence = sequence
        self.order = order
        self._R = rotation_sequence(sequence, coordinates[3:], order=order)

    def relative(self) -> tuple[ca.SX, ca.SX]:
        return ca.vertcat(*self.coordinates[:3]), self._R


def _unit_axis(axis, name: str) -> list[float]:
    try:
        a = np.asarray(axis, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise ModelDefinitionError(f"axis of the joint of {name!r} must be 3 numbers; got {axis!r}.") from exc
    if a.size != 3:
        raise DimensionError(f"axis of the joint of {name!r} has {a.size} entries; expected 3.")
    n = float(np.linalg.norm(a))
    if not np.isfinite(n) or n == 0.0:
        raise ModelDefinitionError(f"axis of the joint of {name!r} is {a.tolist()}; expected a nonzero, finite vector.")
    return (a / n).tolist()


def _check_rotation(R: ca.SX, name: str) -> ca.SX:
    """A constant joint rotation must be a proper rotation (orthonormal, det +1)."""
    if not R.is_constant():
        return R
    m = np.array(ca.evalf(R))
    if not np.allclose(m.T @ m, np.eye(3), atol=1e-9) or np.linalg.det(m) <= 0:
        raise ModelDefinitionError(
            f"rotation of the joint of {name!r} is not a proper rotation matrix (RᵀR = I, det R = +1): "
            f"{np.round(m, 6).tolist()}. Build it with mb.rotation(...) or mb.rotation_sequence(...)."
        )
    return R
