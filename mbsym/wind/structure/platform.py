"""ElastoDyn's platform joint: the six platform DOFs between the ground and the platform body.

Since OpenFAST v4, ElastoDyn orients the platform with the intrinsic yaw–pitch–roll Euler
sequence (NWTC library ``EulerConstructZYX``; docs/elastodyn_notes.md §4)

``R = Rz(Y) Ry(P) Rx(R)``      (platform -> ground, IEC axes)

and uses the matching Euler-rate angular velocity ``ω = Ẏ z + Ṗ y′ + Ṙ x″`` (``y′ = Rz(Y) e_y``,
``x″ = Rz(Y) Ry(P) e_x``), whose time derivative (with the rate-products) is the angular
acceleration. The pair is consistent (``ω = vee(Ṙ Rᵀ)``), so the platform conserves energy and
yaw about the vertical is an exact symmetry. The translations (surge, sway, heave) are along
the ground axes.
"""

from __future__ import annotations

from typing import Sequence

import casadi as ca

from ...bodies.base import Body
from ...joints import Joint
from ...kinematics import rotation

__all__ = ["PlatformJoint", "platform_rotation", "platform_angular_velocity"]


def platform_rotation(roll, pitch, yaw) -> ca.SX:
    """ElastoDyn's platform orientation ``Rz(yaw) Ry(pitch) Rx(roll)`` (platform -> ground).

    Parameters
    ----------
    roll, pitch, yaw : float or SX
        Platform rotation DOFs [rad] (ElastoDyn's PtfmRoll, PtfmPitch, PtfmYaw).

    Returns
    -------
    SX
        3x3 rotation, columns the platform axes in ground (IEC) axes.

    Examples
    --------
    >>> import numpy as np, casadi as ca
    >>> R = np.array(ca.evalf(platform_rotation(0.0, 0.1, 0.0)))
    >>> bool(np.isclose(R[0, 2], np.sin(0.1)))      # pitched by P itself (not atan P)
    True
    """
    return rotation("z", yaw) @ rotation("y", pitch) @ rotation("x", roll)


def platform_angular_velocity(angles, rates) -> ca.SX:
    """Euler-rate angular velocity ``Ẏ z + Ṗ y′ + Ṙ x″`` of the platform, ground axes [rad/s].

    Parameters
    ----------
    angles : sequence of 3
        (roll, pitch, yaw) [rad].
    rates : sequence of 3
        Their time derivatives [rad/s].

    Examples
    --------
    >>> import numpy as np, casadi as ca
    >>> w = platform_angular_velocity([0.0, 0.0, np.pi / 2], [1.0, 0.0, 0.0])   # roll rate after a 90° yaw
    >>> np.round(np.array(ca.evalf(w)).ravel(), 12).tolist()
    [0.0, 1.0, 0.0]
    """
    roll, pitch, yaw = (ca.SX(a) for a in angles)
    dr, dp, dy = (ca.SX(a) for a in rates)
    cp, sp, cy, sy = ca.cos(pitch), ca.sin(pitch), ca.cos(yaw), ca.sin(yaw)
    return ca.vertcat(dr * cp * cy - dp * sy, dr * cp * sy + dp * cy, dy - dr * sp)


class PlatformJoint(Joint):
    """ElastoDyn's platform: translations along ground axes, then the yaw–pitch–roll rotation.

    The orientation is :func:`platform_rotation` ``Rz(Y) Ry(P) Rx(R)`` and the angular velocity
    the matching Euler-rate form :func:`platform_angular_velocity` (ElastoDyn v4 and later).

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
        return ca.vertcat(*self.values[:3]), platform_rotation(*self.values[3:])

    def angular_velocity(self, speed) -> ca.SX:
        rates = [speed(v) if v.is_symbolic() else ca.SX(0) for v in self.values[3:]]
        return platform_angular_velocity(self.values[3:], rates)
