"""Geometric stiffness of a beam along z (paper App. B, C) and rotating-beam utilities.

Sign convention: ``K_g`` is added to ``K_e`` on the left-hand side of the elastic
equations (paper Eq. A16); an axial TENSION ``N(z) > 0`` gives a positive matrix::

    K_N,ij = int_0^L N(z) Phi_i'(z) . Phi_j'(z) dz            (paper Eq. B5)

The axial force produced by a load is the force exerted on the part of the beam
outboard of ``z`` (d'Alembert inertial forces included), projected on ``+z``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from mbsym.beam.sid import ShapeIntegrals, axis_index, skew
from mbsym.exceptions import BeamDataError

__all__ = [
    "axial_geometric_stiffness",
    "unit_geometric_stiffness",
    "spin_softening",
    "rotating_stiffness",
    "southwell_coefficients",
]

_E = np.eye(3)


def axial_geometric_stiffness(weights: ArrayLike, axial_force: ArrayLike, slopes: ArrayLike) -> np.ndarray:
    """``K_N,ij = sum_k w_k N_k Phi_i'(z_k) . Phi_j'(z_k)`` (paper Eq. B5, quadrature form).

    Parameters
    ----------
    weights : array_like, shape (n,)
        Quadrature weights [m].
    axial_force : array_like, shape (n,) or scalar
        Tension at the stations [N] (compression negative).
    slopes : array_like, shape (n_e, 3, n)
        Shape slopes ``dPhi_j/dz`` at the stations [-].

    Returns
    -------
    numpy.ndarray, shape (n_e, n_e)
        [N/m].

    Examples
    --------
    >>> axial_geometric_stiffness([1.0], 2.0, np.ones((1, 3, 1)))
    array([[6.]])
    """
    d = np.asarray(slopes, dtype=float)
    wn = np.asarray(weights, dtype=float) * np.broadcast_to(np.asarray(axial_force, float), d.shape[-1:])
    return np.einsum("k,iak,jak->ij", wn, d, d)


def unit_geometric_stiffness(
    weights: ArrayLike,
    slopes: ArrayLike,
    mass_outboard: ArrayLike,
    first_moment_outboard: ArrayLike,
) -> dict[str, np.ndarray]:
    """Unit geometric-stiffness matrices of a straight beam along z (paper App. C).

    Parameters
    ----------
    weights : array_like, shape (n,)
        Quadrature weights [m].
    slopes : array_like, shape (n_e, 3, n)
        Shape slopes at the stations.
    mass_outboard : array_like, shape (n,)
        ``M_out(z) = int_z^L m dz'`` (+ tip mass) [kg].
    first_moment_outboard : array_like, shape (n,)
        ``S(z) = int_z^L m z' dz'`` (+ tip mass times L) [kg m], z-component of
        the paper's vector ``N(z) = int_z^L m s_P0 dz'`` (C6, C7).

    Returns
    -------
    dict
        ``kg_t`` (3, n_e, n_e): unit ``a - g``, ``kg_t[a] = -delta_az int M_out Phi'.Phi'``
        (d'Alembert force ``-m (a - g)`` on the outboard part; the paper's Eq. C4 omits
        the minus sign); ``kg_r`` (3, n_e, n_e): C7, zero for a straight beam;
        ``kg_omega`` (3, 3, n_e, n_e): C6,
        ``kg_omega[a, b] = -e_z . (skew(e_a) skew(e_b) e_z) int S Phi'.Phi'``
        (= ``int S Phi'.Phi'`` for ``a = b`` in {x, y}, else 0);
        ``kg_tip`` (3, n_e, n_e): C5 with ``z_k = L``, ``kg_tip[z] = int Phi'.Phi'``.
    """
    w = np.asarray(weights, dtype=float)
    k_mass = axial_geometric_stiffness(w, mass_outboard, slopes)
    k_moment = axial_geometric_stiffness(w, first_moment_outboard, slopes)
    k_unit = axial_geometric_stiffness(w, 1.0, slopes)
    ez = _E[2]
    c_t = -ez  # axial component of the d'Alembert force per unit mass and unit a_alpha: -e_alpha . e_z
    c_r = np.array([-ez @ (skew(_E[a]) @ ez) for a in range(3)])
    c_w = np.array([[-ez @ (skew(_E[a]) @ skew(_E[b]) @ ez) for b in range(3)] for a in range(3)])
    return {
        "kg_t": c_t[:, None, None] * k_mass[None],
        "kg_r": c_r[:, None, None] * k_moment[None],
        "kg_omega": c_w[:, :, None, None] * k_moment[None, None],
        "kg_tip": ez[:, None, None] * k_unit[None],
    }


def _unit_axis(axis: str | int | ArrayLike) -> np.ndarray:
    if isinstance(axis, (str, int, np.integer)):
        return _E[axis_index(axis)]
    v = np.asarray(axis, dtype=float).reshape(-1)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise BeamDataError(f"axis must be 'x', 'y', 'z' or a non-zero finite 3-vector; got {axis!r}.")
    return v / np.linalg.norm(v)


def spin_softening(sid: ShapeIntegrals, axis: str | int | ArrayLike = "x") -> np.ndarray:
    """Spin-softening stiffness per unit ``Omega^2`` for rotation about ``axis``.

    It is the part of ``omega^T O_e,i(q_e) omega`` (paper Eq. A10) linear in
    ``q_e``: ``S_ij = e^T oe.order1[j, i] e = int m [(Phi_i.e)(Phi_j.e) - Phi_i.Phi_j] dz``.
    For a shape in the rotation plane ``S_jj = -M_e,jj`` (paper Sect. 4.3:
    ``K_omega = -Omega^2 M_e``); for a shape along the axis it is 0. The engine gets
    this term from ``O_e``; it is NOT inside ``kg_omega``.

    Parameters
    ----------
    sid : ShapeIntegrals
    axis : {"x", "y", "z"}, int or array_like (3,)
        Rotation axis in the body frame.

    Returns
    -------
    numpy.ndarray, shape (n_e, n_e)
        [kg] (multiply by ``Omega^2`` [rad^2/s^2] to get N/m).
    """
    e = _unit_axis(axis)
    o1 = sid.oe.order1
    if o1 is None:
        return np.zeros((sid.n_e, sid.n_e))
    return np.einsum("a,jiab,b->ij", e, o1, e)


def rotating_stiffness(
    sid: ShapeIntegrals,
    rotor_speed: float,
    *,
    axis: str | int | ArrayLike = "x",
    hub_radius: float = 0.0,
) -> np.ndarray:
    """Stiffness of the elastic coordinates of a beam spinning at constant speed.

    ``K = K_e + K_g + Omega^2 S`` where ``K_g`` comes from ``kg_omega`` (centrifugal
    tension) and from ``kg_t`` with the centripetal acceleration of the body origin
    placed at ``hub_radius`` along +z from the axis, and ``S`` is
    :func:`spin_softening`. No gravity, no Coriolis coupling.

    Parameters
    ----------
    sid : ShapeIntegrals
    rotor_speed : float
        ``Omega`` [rad/s].
    axis : {"x", "y", "z"} or array_like (3,), keyword-only
        Rotation axis (body frame).
    hub_radius : float, keyword-only
        Distance from the rotation axis to the beam root along the beam [m].

    Returns
    -------
    numpy.ndarray, shape (n_e, n_e)
        [N/m]. ``eig(K, M_e)`` gives the rotating frequencies.
    """
    e = _unit_axis(axis)
    om = float(rotor_speed)
    r0 = np.array([0.0, 0.0, float(hub_radius)])
    accel = om**2 * (e * (e @ r0) - r0)  # centripetal acceleration of the body origin
    kg = sid.geometric_stiffness(acceleration=accel, angular_velocity=om * e)
    return sid.ke + kg + om**2 * spin_softening(sid, e)


def southwell_coefficients(
    sid: ShapeIntegrals,
    *,
    axis: str | int | ArrayLike = "x",
    hub_radius: float = 0.0,
) -> np.ndarray:
    """Southwell (rise) coefficients ``k_Omega`` of each shape taken alone (paper Sect. 4.3).

    ``k_Omega,j = K_g,jj(Omega = 1) / M_e,jj`` with ``K_g`` the centrifugal geometric
    stiffness (``kg_omega`` and, for ``hub_radius > 0``, ``kg_t`` with the centripetal
    acceleration of the root). Then ``omega^2 = omega_0^2 + k_Omega Omega^2`` for a
    flap shape (out of the rotation plane) and ``omega^2 = omega_0^2 + (k_Omega - 1)
    Omega^2`` for an edge shape (in the plane; the ``-1`` is :func:`spin_softening`).

    Parameters
    ----------
    sid : ShapeIntegrals
    axis : {"x", "y"} or array_like (3,), keyword-only
        Rotation axis, perpendicular to the beam.
    hub_radius : float, keyword-only
        Distance from the axis to the root [m].

    Returns
    -------
    numpy.ndarray, shape (n_e,)
        [-].

    Examples
    --------
    A uniform beam with its exact first mode and zero hub radius gives 1.1933.
    """
    e = _unit_axis(axis)
    if abs(e[2]) > 1e-12:
        raise BeamDataError(f"southwell_coefficients needs a rotation axis perpendicular to the beam (z); got {e.tolist()}.")
    r0 = np.array([0.0, 0.0, float(hub_radius)])
    kg = sid.geometric_stiffness(acceleration=e * (e @ r0) - r0, angular_velocity=e)
    return np.diag(kg) / np.diag(sid.me)
