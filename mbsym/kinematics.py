"""Rotations and small vector helpers in CasADi SX.

All functions accept and return ``casadi.SX`` (numbers are promoted). Rotation
matrices map coordinates from the rotated (child) frame to the reference
(parent) frame: ``v_parent = R @ v_child``.
"""

from __future__ import annotations

from math import factorial
from typing import Sequence

import casadi as ca
import numpy as np

from .exceptions import DimensionError, ModelDefinitionError

__all__ = [
    "skew",
    "vee",
    "rotation",
    "rotation_about",
    "rotation_sequence",
    "small_rotation",
    "elastodyn_rotation",
    "as_vector3",
    "as_matrix3",
]

_AXES = {"x": 0, "y": 1, "z": 2}


def as_vector3(value, what: str = "vector") -> ca.SX:
    """Return ``value`` as a 3x1 SX column.

    Parameters
    ----------
    value : sequence of 3 numbers or SX, or SX of shape (3, 1) / (1, 3)
    what : str
        Name used in the error message.

    Raises
    ------
    DimensionError
        If ``value`` does not have exactly 3 entries.
    """
    if isinstance(value, (ca.SX, ca.DM)):
        v = ca.SX(value)
        if v.numel() != 3:
            raise DimensionError(f"{what} has {v.numel()} entries; expected 3 (x, y, z).")
        return ca.reshape(v, 3, 1)
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__"):
        raise DimensionError(f"{what} must be a sequence of 3 entries (x, y, z); got {value!r}.")
    if len(value) != 3:
        raise DimensionError(f"{what} has {len(value)} entries; expected 3 (x, y, z).")
    return ca.vertcat(*[_scalar(e, what) for e in value])


def as_matrix3(value, what: str = "matrix") -> ca.SX:
    """Return ``value`` (3x3 nested sequence, numpy array or SX) as a 3x3 SX."""
    if isinstance(value, (ca.SX, ca.DM)):
        m = ca.SX(value)
        if m.shape != (3, 3):
            raise DimensionError(f"{what} has shape {m.shape}; expected (3, 3).")
        return m
    try:
        rows = [list(r) for r in value]
    except TypeError as exc:
        raise DimensionError(f"{what} must be a 3x3 array; got {value!r}.") from exc
    if len(rows) != 3 or any(len(r) != 3 for r in rows):
        shape = (len(rows), [len(r) for r in rows])
        raise DimensionError(f"{what} has shape {shape}; expected (3, 3).")
    return ca.vertcat(*[ca.horzcat(*[_scalar(e, what) for e in r]) for r in rows])


def _scalar(e, what: str) -> ca.SX:
    if isinstance(e, (ca.SX, ca.DM)):
        if e.numel() != 1:
            raise DimensionError(f"an entry of {what} has {e.numel()} elements; expected a scalar.")
        return ca.SX(e)
    if isinstance(e, (bool, np.bool_)) or not isinstance(e, (int, float, np.integer, np.floating)):
        raise ModelDefinitionError(
            f"an entry of {what} is {e!r} ({type(e).__name__}); expected a number or a CasADi SX scalar."
        )
    if not np.isfinite(e):
        raise ModelDefinitionError(f"an entry of {what} is {e}; expected a finite number.")
    return ca.SX(float(e))


def skew(v) -> ca.SX:
    """Skew-symmetric matrix ``[v~]`` such that ``skew(v) @ w == v x w``."""
    v = as_vector3(v)
    return ca.vertcat(
        ca.horzcat(0, -v[2], v[1]),
        ca.horzcat(v[2], 0, -v[0]),
        ca.horzcat(-v[1], v[0], 0),
    )


def vee(m: ca.SX) -> ca.SX:
    """Inverse of :func:`skew` for a (nearly) skew-symmetric 3x3 matrix."""
    return 0.5 * ca.vertcat(m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1])


def _cos_sin(angle, order: int | None):
    """cos and sin of ``angle``, exact (order None) or as Taylor series to ``order``."""
    if order is None:
        return ca.cos(angle), ca.sin(angle)
    if not isinstance(order, (int, np.integer)) or isinstance(order, bool) or order < 1:
        raise ModelDefinitionError(
            f"small-angle order must be a positive integer or None (exact); got {order!r}."
        )
    c = ca.SX(0)
    s = ca.SX(0)
    for k in range(order + 1):
        term = angle**k / factorial(k)
        if k % 2 == 0:
            c += (-1) ** (k // 2) * term
        else:
            s += (-1) ** (k // 2) * term
    return c, s


def rotation(axis: str, angle, *, order: int | None = None) -> ca.SX:
    """Rotation matrix about a coordinate axis.

    Parameters
    ----------
    axis : {'x', 'y', 'z'}
        Axis of rotation.
    angle : float or SX
        Rotation angle [rad], positive by the right-hand rule.
    order : int or None, optional
        ``None`` (default) gives the exact rotation. An integer ``n`` truncates
        cos and sin at Taylor order ``n`` (``order=1``: ``cos=1, sin=angle``).

    Returns
    -------
    SX
        3x3 matrix mapping child to parent coordinates.

    Examples
    --------
    >>> import casadi as ca
    >>> R = rotation("z", ca.pi / 2)
    >>> float(ca.evalf(R)[1, 0])
    1.0
    """
    if axis not in _AXES:
        raise ModelDefinitionError(f"rotation axis must be 'x', 'y' or 'z'; got {axis!r}.")
    c, s = _cos_sin(ca.SX(angle), order)
    if axis == "x":
        return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))
    if axis == "y":
        return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))
    return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))


def rotation_about(axis, angle, *, order: int | None = None) -> ca.SX:
    """Rotation about an arbitrary unit axis (Rodrigues' formula).

    Parameters
    ----------
    axis : sequence of 3 numbers
        Rotation axis; normalized here. Coordinate axes use :func:`rotation`.
    angle : float or SX
        Rotation angle [rad].
    order : int or None
        Small-angle truncation order, as in :func:`rotation`.
    """
    a = np.asarray(axis, dtype=float).reshape(-1)
    if a.size != 3:
        raise DimensionError(f"rotation axis has {a.size} entries; expected 3.")
    norm = float(np.linalg.norm(a))
    if not np.isfinite(norm) or norm == 0.0:
        raise ModelDefinitionError(f"rotation axis {list(a)} has zero or non-finite length; give a nonzero axis.")
    a = a / norm
    for name, idx in _AXES.items():
        if abs(a[idx] - 1.0) < 1e-15:
            return rotation(name, angle, order=order)
    c, s = _cos_sin(ca.SX(angle), order)
    k = skew(a.tolist())
    return ca.SX.eye(3) + s * k + (1 - c) * (k @ k)


def rotation_sequence(sequence: str, angles: Sequence, *, order: int | None = None) -> ca.SX:
    """Product of rotations about body-fixed (intrinsic) axes, e.g. ``'xyz'``.

    ``rotation_sequence('xyz', [a, b, c]) == Rx(a) @ Ry(b) @ Rz(c)``.
    """
    if len(sequence) != len(angles) or any(ax not in _AXES for ax in sequence):
        raise ModelDefinitionError(
            f"rotation sequence {sequence!r} must name one axis among 'x', 'y', 'z' per angle "
            f"({len(angles)} angles given)."
        )
    R = ca.SX.eye(3)
    for ax, ang in zip(sequence, angles):
        R = R @ rotation(ax, ang, order=order)
    return R


def small_rotation(theta, *, order: int | None = 1) -> ca.SX:
    """Rotation matrix for a rotation vector ``theta`` (3x1 SX).

    ``order=1`` gives ``I + [theta~]`` (linear small-angle form); ``None`` gives
    the exact rotation about ``theta/|theta|`` by ``|theta|`` (Rodrigues); an
    integer ``n > 1`` keeps the terms of the exponential map up to ``[theta~]**n``.
    """
    theta = as_vector3(theta, "rotation vector")
    k = skew(theta)
    if order is None:
        # Rodrigues R = I + A K + B K^2, A = sin(a)/a, B = (1 - cos a)/a^2 with a = |θ|, written
        # in s = a^2 with series near 0 so that values and derivatives stay finite at θ = 0.
        s = ca.dot(theta, theta)
        small = s < 1e-8
        s_safe = ca.if_else(small, 1.0, s)
        a = ca.sqrt(s_safe)
        A = ca.if_else(small, 1 - s / 6 + s**2 / 120, ca.sin(a) / a)
        B = ca.if_else(small, 0.5 - s / 24 + s**2 / 720, (1 - ca.cos(a)) / s_safe)
        return ca.SX.eye(3) + A * k + B * (k @ k)
    if not isinstance(order, (int, np.integer)) or order < 1:
        raise ModelDefinitionError(f"small-angle order must be a positive integer or None; got {order!r}.")
    R = ca.SX.eye(3)
    term = ca.SX.eye(3)
    for n in range(1, order + 1):
        term = term @ k / n
        R = R + term
    return R


def elastodyn_rotation(theta) -> ca.SX:
    """ElastoDyn's small-rotation matrix (``SmllRotTrans``) for a rotation vector ``theta``.

    The orthonormal matrix closest (Frobenius norm) to the first-order form
    ``I + [θ~]``: an exact rotation about ``θ/|θ|`` by ``atan|θ|``. Written without
    the axis so that it is smooth at θ = 0:
    ``R = (I + [θ~]) / s + θ θᵀ / (s (s + 1))`` with ``s = sqrt(1 + |θ|²)``.

    Returns
    -------
    SX
        3x3 rotation mapping child to parent coordinates.

    Examples
    --------
    >>> import casadi as ca, numpy as np
    >>> R = np.array(ca.evalf(elastodyn_rotation([0.0, 0.0, 1.0])))
    >>> bool(np.allclose(R[:2, :2], [[np.cos(np.pi/4), -np.sin(np.pi/4)], [np.sin(np.pi/4), np.cos(np.pi/4)]]))
    True
    """
    theta = as_vector3(theta, "rotation vector")
    s = ca.sqrt(1 + ca.dot(theta, theta))
    return (ca.SX.eye(3) + skew(theta)) / s + (theta @ theta.T) / (s * (s + 1))
