"""Numbers or CasADi expressions through one code path (private).

The platform loads are written once with CasADi operations; :func:`_in` turns a numeric
argument into a ``DM`` column (checking its size and finiteness) and leaves ``SX``/``MX``
alone; :func:`_out` gives numpy back for numeric input and the expression otherwise.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, ParameterError


def _symbolic(value) -> bool:
    return isinstance(value, (ca.SX, ca.MX))


def _in(value, n: int, what: str):
    """``value`` as an ``n``-column CasADi vector (SX/MX kept; numbers → DM, checked)."""
    if _symbolic(value):
        if value.numel() != n:
            raise DimensionError(f"{what} has {value.numel()} entries; expected {n}.")
        return ca.reshape(value, n, 1)
    arr = np.asarray(value, dtype=float).ravel()
    if arr.size != n:
        raise DimensionError(f"{what} has {arr.size} entries; expected {n} (surge, sway, heave, roll, pitch, yaw).")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"All entries of {what} must be finite numbers; got {arr.tolist()}.")
    return ca.DM(arr)


def _out(value, *args):
    """numpy for numeric arguments, the CasADi expression when any argument is symbolic."""
    if any(_symbolic(a) for a in args):
        return value
    return np.array(ca.evalf(value), dtype=float).ravel()


def euler_zyx(angles) -> "ca.SX | ca.MX | ca.DM":
    """Body-to-inertial rotation R = Rz(yaw) Ry(pitch) Rx(roll) of angles ``(roll, pitch, yaw)`` [rad].

    ElastoDyn v4+/v5's platform rotation (mbsym's platform joint) and HydroDyn's
    ``EulerExtractZYX`` use this sequence, so the angles are the platform DOFs R, P, Y.
    """
    r, p, y = angles[0], angles[1], angles[2]
    cr, sr, cp, sp, cy, sy = ca.cos(r), ca.sin(r), ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(
        ca.horzcat(cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        ca.horzcat(sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        ca.horzcat(-sp, cp * sr, cp * cr))


def euler_rate_matrix(angles):
    """``T`` with the platform's angular velocity ``ω = T (Ṙ, Ṗ, Ẏ)`` in inertial axes [rad/s] for the Euler angles
    ``(roll, pitch, yaw)`` of :func:`euler_zyx`: ``ω = Ẏ z + Ṗ Rz(Y) y + Ṙ Rz(Y) Ry(P) x``, the angular velocity of
    ElastoDyn's platform (and of mbsym's platform joint, ``mbsym.wind.structure.platform``), which HydroDyn and MoorDyn
    receive as the platform's ``RotationVel``."""
    p, y = angles[1], angles[2]
    cp, sp, cy, sy = ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(ca.horzcat(cp * cy, -sy, 0.0), ca.horzcat(cp * sy, cy, 0.0), ca.horzcat(-sp, 0.0, 1.0))


def euler_rate_bias(angles, rates):
    """``Ṫ (Ṙ, Ṗ, Ẏ)``: the part of the angular acceleration ``α = T (R̈, P̈, Ÿ) + Ṫ (Ṙ, Ṗ, Ẏ)`` that the rates give
    (:func:`euler_rate_matrix`) [rad/s²]."""
    p, y = angles[1], angles[2]
    dr, dp, dy = rates[0], rates[1], rates[2]
    cp, sp, cy, sy = ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(-dr * dp * sp * cy - dr * dy * cp * sy - dp * dy * cy,
                      -dr * dp * sp * sy + dr * dy * cp * cy - dp * dy * sy,
                      -dr * dp * cp)


def body_motion(q, qd):
    """``(v, J, b)`` of the platform's reference point from its DOFs ``q`` and rates ``qd`` (surge … yaw):
    ``v = J q̇`` its velocity and angular velocity, inertial axes [m/s, rad/s]; ``J = diag(I, T)`` (6 × 6); ``b`` the
    rate part of its acceleration, ``a = J q̈ + b`` ([0; Ṫ θ̇]). HydroDyn's loads see ``v`` and ``a``."""
    T = euler_rate_matrix(q[3:6])
    J = ca.diagcat(ca.DM.eye(3), T)
    return ca.vertcat(qd[0:3], ca.mtimes(T, qd[3:6])), J, ca.vertcat(0.0, 0.0, 0.0, euler_rate_bias(q[3:6], qd[3:6]))
