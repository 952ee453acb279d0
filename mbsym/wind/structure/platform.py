"""ElastoDyn's platform joint: the six platform DOFs between the ground and the platform body."""

from __future__ import annotations

from typing import Sequence

import casadi as ca

from ...bodies.base import Body
from ...joints import Joint
from ...kinematics import elastodyn_rotation

__all__ = ["PlatformJoint"]


class PlatformJoint(Joint):
    """ElastoDyn's platform: translations along ground axes, rotation vector (roll, pitch, yaw)
    turned into a rotation by :func:`mbsym.kinematics.elastodyn_rotation`, and angular velocity
    equal to the rotation-vector rates in ground axes (ElastoDyn's fixed-axis convention).

    Parameters
    ----------
    values : sequence of 6
        (surge, sway, heave [m], roll, pitch, yaw [rad]): a coordinate symbol for an enabled
        DOF, a number (the fixed initial value) for a disabled one.
    """

    def __init__(self, parent: Body, child: Body, *, values: Sequence, offset=(0.0, 0.0, 0.0)) -> None:
        coords = [v for v in values if isinstance(v, ca.SX)]
        super().__init__(parent, child, offset=offset, coordinates=coords)
        self.values = [v if isinstance(v, ca.SX) else ca.SX(float(v)) for v in values]

    def relative(self) -> tuple[ca.SX, ca.SX]:
        return ca.vertcat(*self.values[:3]), elastodyn_rotation(ca.vertcat(*self.values[3:]))

    def angular_velocity(self, speed) -> ca.SX:
        rates = [speed(v) if v.is_symbolic() else ca.SX(0) for v in self.values[3:]]
        return ca.vertcat(*rates)
