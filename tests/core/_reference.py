"""Independent numpy references shared by the core tests (no mbsym code is used here).

Rotation matrices map child to parent coordinates (``v_parent = R @ v_child``), the convention
documented for mbsym joints. Everything below is written out by hand from textbook rigid-body
kinematics so that it can serve as a reference for the engine's CasADi derivation.
"""

from __future__ import annotations

import numpy as np


def rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def d_rot_x(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[0.0, 0.0, 0.0], [0.0, -s, -c], [0.0, c, -s]])


def d_rot_y(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[-s, 0.0, c], [0.0, 0.0, 0.0], [-c, 0.0, -s]])


def d_rot_z(a: float) -> np.ndarray:
    c, s = np.cos(a), np.sin(a)
    return np.array([[-s, -c, 0.0], [c, -s, 0.0], [0.0, 0.0, 0.0]])


def rodrigues(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` about the unit vector ``axis`` (right-hand rule)."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    K = skew(k)
    return np.eye(3) + np.sin(angle) * K + (1.0 - np.cos(angle)) * K @ K


def skew(v) -> np.ndarray:
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def xyz_body_rates(angles, rates):
    """Intrinsic x-y-z Euler angles: ``R = Rx(a) Ry(b) Rz(c)``.

    Returns ``(R, E, Edot_rates)`` with the body-axis angular velocity ``w = E @ rates`` and the
    body-axis angular acceleration ``wdot = E @ accels + Edot_rates``. From
    ``R^T Rdot = C^T B^T [e_x]x B C a' + C^T [e_y]x C b' + [e_z]x c'`` (A, B, C the factors).
    """
    a, b, c = angles
    ad, bd, cd = rates
    A, B, C = rot_x(a), rot_y(b), rot_z(c)
    ex, ey, ez = np.eye(3)
    E = np.column_stack([C.T @ B.T @ ex, C.T @ ey, ez])
    Cd = d_rot_z(c) * cd
    Bd = d_rot_y(b) * bd
    col0_dot = (Cd.T @ B.T + C.T @ Bd.T) @ ex
    col1_dot = Cd.T @ ey
    Edot_rates = col0_dot * ad + col1_dot * bd
    return A @ B @ C, E, Edot_rates


def free_body_residual(q, qd, qdd, *, mass, com, inertia, gravity, forces=(), torques=()):
    """Newton-Euler residual of one rigid body on a Free joint (x, y, z, then xyz angles).

    Translations are along ground axes, ``com`` is in body axes, ``inertia`` is about the centre
    of mass in body axes. Returns the generalized residual ``e = F - M qdd`` obtained by
    projecting Newton's and Euler's equations on the partial velocities:
    ``dv_G/dx = I``, ``dv_G/d(angle rates) = -[s]x R E``, ``dw/d(angle rates) = R E``.
    ``forces``: ``(f_ground, point_body)`` pairs; ``torques``: ground-axes torques. A force at
    body point p adds ``f`` to the translations and ``E^T (p x R^T f)`` to the angles, a torque
    ``E^T R^T tau``.
    """
    q, qd, qdd = (np.asarray(v, dtype=float) for v in (q, qd, qdd))
    I = np.asarray(inertia, dtype=float)
    R, E, Ed = xyz_body_rates(q[3:], qd[3:])
    w_b = E @ qd[3:]
    wd_b = E @ qdd[3:] + Ed
    s = R @ np.asarray(com, dtype=float)
    w_g, wd_g = R @ w_b, R @ wd_b
    a_G = qdd[:3] + np.cross(wd_g, s) + np.cross(w_g, np.cross(w_g, s))
    f = mass * np.asarray(gravity, dtype=float) - mass * a_G          # applied + inertia force
    tau_b = -(I @ wd_b + np.cross(w_b, I @ w_b))                        # inertia torque about G
    e_trans = f
    e_rot = E.T @ (R.T @ np.cross(s, f) + tau_b)
    for f_g, p_b in forces:
        e_trans = e_trans + np.asarray(f_g, dtype=float)
        e_rot = e_rot + E.T @ np.cross(np.asarray(p_b, dtype=float), R.T @ np.asarray(f_g, dtype=float))
    for t_g in torques:
        e_rot = e_rot + E.T @ R.T @ np.asarray(t_g, dtype=float)
    return np.concatenate([e_trans, e_rot])


def random_spd(rng: np.random.Generator, scale: float = 1.0) -> np.ndarray:
    """A random inertia tensor: symmetric positive definite, eigenvalues in [0.6, 1.2] * scale, so that
    the principal moments satisfy the triangle inequality of a rigid body (J1 <= J2 + J3)."""
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return scale * (Q @ np.diag(0.6 + 0.6 * rng.random(3)) @ Q.T)


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    Q, Rq = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q @ np.diag(np.sign(np.diag(Rq)))
    if np.linalg.det(Q) < 0:
        Q[:, 0] = -Q[:, 0]
    return Q
