"""Shape integrals (standard input data) of a beam made of lumped point masses.

ElastoDyn (OpenFAST) models each blade and the tower as point masses at element
mid-points, with no rotary inertia, whose displacement is given node by node rather
than by a continuous shape function. For shape coordinates ``q`` (``n_e`` of them)
node ``J`` sits at

``s_J(q) = (0, 0, z_J) + sum_j Phi_j(J) q_j - 1/2 (q^T Ax(J) q) e_z``

in the body frame (beam along body ``z`` from its root, the body origin), with
``Phi_j(J) = (Phi_jx, Phi_jy, 0)`` the nodal displacement of shape ``j`` and
``Ax(J)`` a symmetric ``n_e x n_e`` matrix, the axial shortening (ElastoDyn's
``AxRedBld`` / ``AxRedTFA``: ``Ax_ij(J) ~ int_0^{z_J} Phi_i' . Phi_j' dz``).
:func:`lumped_shape_integrals` turns such a body into a :class:`ShapeIntegrals`
whose integrals are all discrete sums over the nodes (and an optional tip mass): the
field to first order in ``q``, with the axial shortening as geometric stiffness (below). The
returned integrals also keep the nodes (``ShapeIntegrals.nodes``), with which
``FlexibleBody(..., kinematics="exact")`` uses the field exactly, at every order in ``q``
(:mod:`mbsym.bodies.lumped_terms`; ElastoDyn's blades and tower at large deflections).

Geometric stiffness from the axial shortening
---------------------------------------------
Let ``f_J`` be the force acting on node ``J`` (d'Alembert inertial force plus
weight, or an applied load) and ``F_J = f_J . e_z`` its axial part, **positive
outward** (pulling the beam in tension). The virtual work of ``f_J`` on the
quadratic term of ``s_J`` is ``-F_J (Ax(J) q) . delta q``; moved to the left side
of the elastic equations it is a stiffness ``K = sum_J F_J Ax(J)`` (tension
stiffens). In the body frame, with ``a`` and ``g`` the acceleration of the body
origin and gravity, ``omega``/``omegadot`` the angular velocity/acceleration of
the body, a node of mass ``m_J`` at ``z_J e_z`` carries

``F_J = -m_J [(a - g)_z + (omegadot x z_J e_z)_z + (omega x (omega x z_J e_z))_z]
      = -m_J (a - g)_z + m_J z_J (omega_x^2 + omega_y^2)``

(``(omegadot x e_z)_z = 0``). Comparing with the convention of
:class:`ShapeIntegrals` (``K_g = sum_a (a - g)_a kg_t[a] + ... + omega_a omega_b
kg_omega[a, b] + F_a kg_tip[a]``) gives, with the tip mass ``m_tip`` at ``z = L``:

* ``kg_t[z] = -sum_J m_J Ax(J) - m_tip Ax_tip``; ``kg_t[x] = kg_t[y] = 0``;
* ``kg_r = 0``;
* ``kg_omega[x, x] = kg_omega[y, y] = sum_J m_J z_J Ax(J) + m_tip L Ax_tip``
  (centrifugal tension about the body origin), every other entry 0;
* ``kg_tip[z] = Ax_tip`` (a force ``F_z`` pulling the tip outward),
  ``kg_tip[x] = kg_tip[y] = 0``.

For a rotor blade whose root sits at a hub radius ``H`` from the spin axis, the
centripetal acceleration of the root ``a_z = -Omega^2 H`` supplies the remaining
``Omega^2 H (sum_J m_J Ax(J) + m_tip Ax_tip)`` through ``kg_t[z]`` (the symbolic
engine evaluates it), so that the total is ElastoDyn's
``Omega^2 sum_J m_J (H + z_J) Ax(J)``. Spin softening is not in ``K_g``; it is the
first-order part of ``O_e`` as for continuous beams. With
``Ax(z) = int_0^z Phi'.Phi'`` these sums are the same as the continuous
``kg_t[z] = -int M_out Phi'.Phi' dz`` and ``kg_omega = int S Phi'.Phi' dz``
(integration by parts), so both kinds of body share one convention.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from mbsym.beam.integrals import _inertial_terms
from mbsym.beam.nodes import LumpedNodes
from mbsym.beam.sid import ShapeIntegrals, Taylor, _frequencies
from mbsym.exceptions import BeamDataError

__all__ = ["lumped_shape_integrals"]


def _finite(name: str, value: ArrayLike, shape: tuple[int, ...], meaning: str) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.shape != shape:
        raise BeamDataError(f"`{name}` has shape {arr.shape}; expected {shape} ({meaning}).")
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        raise BeamDataError(f"`{name}` entry {tuple(int(i) for i in bad[0])} is "
                            f"{arr[tuple(bad[0])]}; all entries must be finite numbers.")
    return arr


def _transverse(name: str, value: ArrayLike, lead: tuple[int, ...], meaning: str) -> np.ndarray:
    """(..., 2) or (..., 3) with zero z component -> (..., 3)."""
    arr = np.asarray(value, dtype=float)
    if arr.shape[:-1] != lead or arr.shape[-1:] not in ((2,), (3,)):
        raise BeamDataError(f"`{name}` has shape {arr.shape}; expected {lead + (3,)} or "
                            f"{lead + (2,)} ({meaning}).")
    arr = _finite(name, arr, arr.shape, meaning)
    if arr.shape[-1] == 2:
        return np.concatenate([arr, np.zeros(lead + (1,))], axis=-1)
    scale = max(float(np.abs(arr).max()), 1e-300)
    if np.abs(arr[..., 2]).max() > 1e-12 * scale:
        raise BeamDataError(f"`{name}` has a non-zero z (axial) component, max |z| = "
                            f"{np.abs(arr[..., 2]).max():.3g}; the first-order displacement must be "
                            "transverse (x, y). Put the axial shortening in `axial_reduction`.")
    return arr


def _symmetric(name: str, arr: np.ndarray) -> None:
    sym = np.swapaxes(arr, 0, 1)
    scale = max(float(np.abs(arr).max()), 1e-300)
    if np.abs(arr - sym).max() > 1e-9 * scale:
        raise BeamDataError(f"`{name}` must be symmetric in its two shape indices; "
                            f"max |A - A^T| / max |A| = {np.abs(arr - sym).max() / scale:.2e}.")


def _check_geometry(z: ArrayLike, masses: ArrayLike, length: float,
                    tip_mass: float) -> tuple[np.ndarray, np.ndarray, float, float]:
    zz = np.asarray(z, dtype=float)
    if zz.ndim != 1 or zz.size == 0:
        raise BeamDataError(f"`z` must be a 1-D array of node positions [m]; got shape {zz.shape}.")
    zz = _finite("z", zz, zz.shape, "node positions along the beam [m]")
    n = zz.size
    length = float(length)
    if not (np.isfinite(length) and length > 0):
        raise BeamDataError(f"`length` must be a positive finite number [m]; got {length}.")
    outside = np.flatnonzero((zz < -1e-12 * length) | (zz > length * (1 + 1e-12)))
    if outside.size:
        k = outside[0]
        raise BeamDataError(f"node {k} is at z = {zz[k]:g} m, outside the beam [0, L = {length:g}] m; "
                            "node positions are measured from the root along body z.")
    m = _finite("masses", masses, (n,), "one point mass per node [kg]")
    neg = np.flatnonzero(m < 0)
    if neg.size:
        raise BeamDataError(f"`masses` at node {neg[0]} is {m[neg[0]]:g} kg; masses must be >= 0.")
    tip_mass = float(tip_mass)
    if not (np.isfinite(tip_mass) and tip_mass >= 0):
        raise BeamDataError(f"`tip_mass` must be finite and >= 0 [kg]; got {tip_mass}.")
    if m.sum() + tip_mass <= 0:
        raise BeamDataError("the body has no mass: all node masses and the tip mass are 0.")
    return zz, m, length, tip_mass


def lumped_shape_integrals(
    z: ArrayLike,
    masses: ArrayLike,
    displacements: ArrayLike,
    axial_reduction: ArrayLike,
    *,
    length: float,
    tip_displacement: ArrayLike,
    tip_slope: ArrayLike,
    tip_axial_reduction: ArrayLike,
    stiffness: ArrayLike,
    damping: ArrayLike | None = None,
    tip_mass: float = 0.0,
) -> ShapeIntegrals:
    """Standard input data of a straight body made of point masses along body z.

    Every inertial field of :class:`ShapeIntegrals` (``mass``, ``mxt``, ``mtt``
    with its order-1 and ``mtt2`` terms, ``ct``, ``cr``, ``me``, ``gr``, ``ge``,
    ``oe``) is the discrete sum over the point masses of the same integrand as in
    :func:`mbsym.beam.shape_integrals`; the geometric-stiffness unit matrices come
    from the axial shortening ``-1/2 q^T Ax(J) q`` of each node (see the module
    docstring for the derivation). Point masses carry no rotary inertia.

    Parameters
    ----------
    z : array_like, shape (N,)
        Undeflected node positions along body z, measured from the root (body
        origin) [m], each within ``[0, length]``.
    masses : array_like, shape (N,)
        Point mass of each node [kg], >= 0.
    displacements : array_like, shape (n_e, N, 3) or (n_e, N, 2)
        ``displacements[j, J]`` = displacement of node ``J`` per unit ``q_j``, body
        axes (x, y[, z = 0]) [m/m for tip-normalised shapes].
    axial_reduction : array_like, shape (n_e, n_e, N)
        ``Ax[i, j, J]``: node ``J`` moves by ``-1/2 sum_ij Ax[i, j, J] q_i q_j``
        along z [1/m]. Symmetric in ``i, j`` (ElastoDyn's ``AxRedBld(i, j, J)``).
    length : float, keyword-only
        Undeflected length ``L`` [m]; the tip (end) point is ``(0, 0, L)``.
    tip_displacement : array_like, shape (n_e, 3) or (n_e, 2), keyword-only
        Displacement of the tip per unit ``q_j`` [m/m] (``end_displacement``; the
        tip mass moves with it).
    tip_slope : array_like, shape (n_e, 3) or (n_e, 2), keyword-only
        Slope ``dPhi_j/dz`` at the tip [1/m per unit q]; gives ``end_rotation =
        (-slope_y, slope_x, 0)``.
    tip_axial_reduction : array_like, shape (n_e, n_e), keyword-only
        ``Ax`` at the tip [1/m] (``kg_tip[z]`` and the tip mass's share of
        ``kg_t``, ``kg_omega``).
    stiffness : array_like, shape (n_e, n_e), keyword-only
        Elastic stiffness ``K_e`` [N/m], symmetric.
    damping : array_like, shape (n_e, n_e), optional, keyword-only
        Damping ``D_e`` [N s/m] (may be unsymmetric, e.g. ElastoDyn's column-wise
        rule). Default zero.
    tip_mass : float, keyword-only
        Point mass at the tip [kg], default 0.

    Returns
    -------
    ShapeIntegrals
        With ``nodes`` (:class:`~mbsym.beam.nodes.LumpedNodes`: the point masses, a tip mass
        as the last node), so that ``FlexibleBody(..., kinematics="exact")`` can use the exact
        node positions instead of the first-order integrals and geometric stiffness.

    Raises
    ------
    BeamDataError
        Wrong shapes, NaN/Inf, negative masses, nodes outside ``[0, L]``, an axial
        (z) component in the displacements or slopes, non-symmetric ``Ax``, or no
        mass at all.

    Examples
    --------
    One point mass of 2 kg at the tip of a 1 m body, one shape moving it along x:

    >>> sid = lumped_shape_integrals([1.0], [2.0], [[[1.0, 0.0]]], [[[1.0]]], length=1.0,
    ...                              tip_displacement=[[1.0, 0.0]], tip_slope=[[1.5, 0.0]],
    ...                              tip_axial_reduction=[[1.2]], stiffness=[[8.0]])
    >>> float(sid.me[0, 0]), float(sid.kg_t[2, 0, 0]), float(sid.kg_omega[0, 0, 0, 0])
    (2.0, -2.0, 2.0)
    """
    zz, m, L, m_tip = _check_geometry(z, masses, length, tip_mass)
    n = zz.size
    disp = np.asarray(displacements, dtype=float)
    n_e = disp.shape[0] if disp.ndim == 3 else -1
    if n_e < 1:
        raise BeamDataError(f"`displacements` has shape {disp.shape}; expected (n_e, {n}, 3) "
                            "(node displacement per shape, n_e >= 1).")
    phi = _transverse("displacements", disp, (n_e, n), "node displacement per shape [m]")
    ax = _finite("axial_reduction", axial_reduction, (n_e, n_e, n), "Ax[i, j, node] [1/m]")
    _symmetric("axial_reduction", ax)
    tip_u = _transverse("tip_displacement", tip_displacement, (n_e,), "tip displacement per shape [m]")
    tip_s = _transverse("tip_slope", tip_slope, (n_e,), "tip slope per shape [1/m]")
    ax_tip = _finite("tip_axial_reduction", tip_axial_reduction, (n_e, n_e), "Ax at the tip [1/m]")
    _symmetric("tip_axial_reduction", ax_tip)
    ke = _finite("stiffness", stiffness, (n_e, n_e), "K_e [N/m]")
    de = np.zeros((n_e, n_e)) if damping is None else _finite("damping", damping, (n_e, n_e), "D_e [N s/m]")

    dm, pos, pts = m, np.stack([np.zeros(n), np.zeros(n), zz], axis=1), phi
    if m_tip > 0:
        dm = np.append(m, m_tip)
        pos = np.vstack([pos, [0.0, 0.0, L]])
        pts = np.concatenate([phi, tip_u[:, None, :]], axis=1)
    t = _inertial_terms(dm, pos, pts)
    if np.linalg.eigvalsh(t["me"]).min() <= 1e-14 * max(np.abs(t["me"]).max(), 1e-300):
        raise BeamDataError("the generalized mass sum_J m_J Phi_i(J).Phi_j(J) is singular: a shape moves "
                            "no mass, or two shapes are linearly dependent on the nodes.")
    k_mass = np.einsum("J,ijJ->ij", m, ax) + m_tip * ax_tip           # sum m Ax
    k_moment = np.einsum("J,ijJ->ij", m * zz, ax) + m_tip * L * ax_tip  # sum m z Ax
    kg_t, kg_r = np.zeros((3, n_e, n_e)), np.zeros((3, n_e, n_e))
    kg_omega, kg_tip = np.zeros((3, 3, n_e, n_e)), np.zeros((3, n_e, n_e))
    kg_t[2] = -k_mass
    kg_omega[0, 0] = kg_omega[1, 1] = k_moment
    kg_tip[2] = ax_tip
    psi = np.vstack([-tip_s[:, 1], tip_s[:, 0], np.zeros(n_e)])
    return ShapeIntegrals(
        mass=t["mass"], n_e=n_e, mxt=t["mxt"], mtt=t["mtt"], ct=t["ct"], cr=Taylor(t["cr0"], t["cr1"]),
        me=t["me"], gr=t["gr"], ge=t["ge"], oe=t["oe"], ke=ke, de=de, kg_t=kg_t, kg_r=kg_r,
        kg_omega=kg_omega, kg_tip=kg_tip, end_position=np.array([0.0, 0.0, L]),
        end_displacement=tip_u.T, end_rotation=psi, frequencies_hz=_frequencies(ke, t["me"]),
        mtt2=t["mtt2"], nodes=_nodes(zz, m, phi, ax, L, m_tip, tip_u, ax_tip),
    )


def _nodes(z, m, phi, ax, length, m_tip, tip_u, ax_tip) -> LumpedNodes:
    """The point masses (a tip mass as the last node) with their exact displacement field."""
    if m_tip > 0:
        z, m = np.append(z, length), np.append(m, m_tip)
        phi = np.concatenate([phi, tip_u[:, None, :]], axis=1)
        ax = np.concatenate([ax, ax_tip[:, :, None]], axis=2)
    return LumpedNodes(z, m, phi[..., :2], ax, ax_tip)
