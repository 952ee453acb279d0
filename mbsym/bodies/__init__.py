"""Bodies of a multibody system: the ground, rigid bodies and flexible bodies."""

from .base import Body, Ground
from .flexible import FlexibleBody
from .rigid import RigidBody

__all__ = ["Body", "Ground", "RigidBody", "FlexibleBody"]
