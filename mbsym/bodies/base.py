"""Base class of every body and the ground (inertial frame)."""

from __future__ import annotations

import casadi as ca

from ..exceptions import ModelDefinitionError

__all__ = ["Body", "Ground"]


class Body:
    """A named body with a reference frame.

    Subclasses state their mass properties. Joints place a body's frame (its
    origin and orientation) relative to the frame of its parent.
    """

    def __init__(self, name: str) -> None:
        if not isinstance(name, str) or not name.isidentifier():
            raise ModelDefinitionError(
                f"body name {name!r} is not a valid identifier; use letters, digits and '_'."
            )
        self._name = name

    @property
    def name(self) -> str:
        """Name of the body."""
        return self._name

    @property
    def elastic_coordinates(self) -> tuple[ca.SX, ...]:
        """Coordinates owned by the body itself (elastic ones); none for rigid bodies."""
        return ()

    def attachment(self, offset: ca.SX) -> tuple[ca.SX, ca.SX]:
        """Position [m] and orientation (3x3) of an attachment point in this body's frame.

        Rigid bodies return ``(offset, I)``; flexible bodies add the elastic
        displacement and slope rotation of the point they are attached at.
        """
        return offset, ca.SX.eye(3)

    def attachment_angular_velocity(self, offset: ca.SX, speed) -> ca.SX | None:
        """Angular velocity [rad/s] of an attachment frame relative to this body, body axes.

        ``speed(c)`` returns the speed symbol of coordinate ``c``. ``None`` (the default) lets
        the kinematics use ``vee(Ṙ Rᵀ)`` of the attachment orientation; bodies whose convention
        defines it otherwise (ElastoDyn's tower top) override this.
        """
        return None

    def symbolic_values(self) -> list[ca.SX]:
        """Expressions the body carries (mass, geometry), for symbol checks."""
        return []

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self._name!r})"


class Ground(Body):
    """The inertial frame. Every system has exactly one, ``System.ground``."""

    def __init__(self) -> None:
        super().__init__("ground")
