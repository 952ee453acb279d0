"""Points along a blade of the ElastoDyn-equivalent structure: shapes, kinematics and the loads they carry.

Blade-element aerodynamics evaluates the flow at *its own* nodes (AeroDyn's ``BlSpn``), which are
not ElastoDyn's structural nodes. OpenFAST moves them by mapping ElastoDyn's blade line mesh onto
AeroDyn's (displacements interpolated linearly along the span between the structural nodes, the
root and the tip); :func:`blade_point_shapes` does the same with ElastoDyn's twisted mode shapes
(:func:`~.elastodyn_bodies.blade_elastodyn_data`): for every point ``z`` [m] from the root, the
displacement ``Φ(z)`` and slope ``Φ'(z)`` per unit blade coordinate (body axes ``x = j1``,
``y = j2``) and the axial-shortening matrix ``Ax(z)``. In the blade's body frame a point then sits at

    p(z, q) = [Φx q, Φy q, z − ½ qᵀ Ax q]      (ElastoDyn's exact lumped-node kinematics)

and moves with ``ṗ = [Φx q̇, Φy q̇, −qᵀ Ax q̇]``. :func:`blade_point_kinematics` turns the blade's
body frame (position, orientation, velocity, angular velocity, ground axes) into the points'
ground positions, velocities and deflected span tangents; :func:`blade_point_loads` turns loads
per unit length at the points into the structure's blade-load inputs (:data:`BLADE_LOAD_INPUTS` of
:class:`~.turbine.TurbineModel`): the resultant force at the root and moment about it (body axes),
and the generalized force on every elastic coordinate, ``Q_i = Σ_j w_j f_j · ∂p_j/∂q_i``: the
virtual power of the distributed load, so ``Σ_j w_j f_j·v_j`` equals the power of the inputs
exactly (tested).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["BladePointShapes", "blade_point_shapes", "point_shapes", "check_points", "blade_point_kinematics", "blade_point_loads"]


@dataclass(frozen=True, eq=False)
class BladePointShapes:
    """ElastoDyn's blade shapes at given points of one blade (body axes; see the module docstring).

    Attributes
    ----------
    span : ndarray (N,)
        Distance of the points from the blade root along the undeflected axis [m].
    displacement, slope : ndarray (n_e, N, 2)
        ``Φ`` [m/m] and ``Φ'`` [1/m] per unit elastic coordinate, components along ``j1``, ``j2``.
    axial_reduction : ndarray (n_e, n_e, N)
        ``Ax`` [1/m]: the point moves inward by ``½ qᵀ Ax q``.
    coordinates : tuple of str
        The blade's elastic coordinates in shape order (may be empty: rigid blade).
    """

    span: np.ndarray
    displacement: np.ndarray
    slope: np.ndarray
    axial_reduction: np.ndarray
    coordinates: tuple[str, ...]

    @property
    def n_points(self) -> int:
        return int(self.span.size)


def _interp(values: np.ndarray, at: np.ndarray, grid: np.ndarray) -> np.ndarray:
    """Linear interpolation along the last axis."""
    flat = values.reshape(-1, values.shape[-1])
    rows = [np.interp(at, grid, row) for row in flat]
    return (np.stack(rows) if rows else np.zeros((0, at.size))).reshape(values.shape[:-1] + (at.size,))


def blade_point_shapes(structure, blade: int, span) -> BladePointShapes:
    """Shapes of blade ``blade`` (0-based) of ``structure`` at the points ``span`` [m from the root].

    Parameters
    ----------
    structure : TurbineModel
    blade : int
    span : array_like
        Points along the blade, within ``[0, BldFlexL]`` (1 mm tolerance) [m].

    Raises
    ------
    ParameterError
        A point off the blade.
    """
    from .elastodyn_bodies import BLADE_DOFS

    data = structure.blade_data(blade)
    length = float(data.length)
    z = check_points(span, length, "blade points must lie on the blade, 0 to BldFlexL",
                     "Check that the AeroDyn blade (BlSpn) and the ElastoDyn blade have the same length.")
    return point_shapes(data.span, length, data, [BLADE_DOFS.index(f) for f in BLADE_DOFS if structure.dofs.get(f)],
                        z, structure.blade_coordinates(blade))


def check_points(at, length: float, what: str, advice: str) -> np.ndarray:
    """``at`` as a float array, or ParameterError (``what`` = ``length`` m …, got …; ``advice``) when a point lies
    outside ``[0, length]`` by more than 1 mm or is not finite."""
    z = np.asarray(at, dtype=float).reshape(-1)
    if z.size == 0 or not np.all(np.isfinite(z)) or z.min() < -1e-3 or z.max() > length + 1e-3:
        raise ParameterError(f"{what} = {length:g} m; got {z.min() if z.size else 'none'} to "
                             f"{z.max() if z.size else 'none'} m. {advice}")
    return z


def point_shapes(nodes, length: float, data, idx, at, coordinates) -> BladePointShapes:
    """ElastoDyn's shapes of one flexible member (a blade or the tower) at the points ``at`` [m from its root].

    Displacements, slopes and axial reductions are interpolated linearly between the root (zero), the
    member's nodes ``nodes`` [m] and its end ``length`` [m], as OpenFAST's line-mesh mapping does.

    Parameters
    ----------
    nodes : array_like (N,)
        ElastoDyn's node positions along the member [m].
    length : float
        The flexible length [m].
    data : ElastoDynBladeData or ElastoDynTowerData
        Its ``displacement``, ``slope`` (n_shapes, N, 2), ``tip_displacement``, ``tip_slope`` (n_shapes, 2),
        ``axial_reduction`` (n_shapes, n_shapes, N) and ``tip_axial_reduction``.
    idx : sequence of int
        The shapes of the enabled coordinates, in coordinate order.
    at : array_like (M,)
        Points within ``[0, length]`` [m].
    coordinates : tuple of str
        The coordinates' names (same order as ``idx``).
    """
    z = np.clip(np.asarray(at, dtype=float).reshape(-1), 0.0, length)
    grid = np.concatenate([[0.0], np.asarray(nodes, dtype=float), [length]])
    idx = list(idx)

    def with_ends(values: np.ndarray, tip: np.ndarray) -> np.ndarray:     # (..., N) -> (..., N + 2)
        root = np.zeros(values.shape[:-1] + (1,))
        return np.concatenate([root, values, tip[..., None]], axis=-1)

    disp = with_ends(np.moveaxis(data.displacement[idx], -1, 1), data.tip_displacement[idx])   # (ne, 2, N+2)
    slope = with_ends(np.moveaxis(data.slope[idx], -1, 1), data.tip_slope[idx])
    ax = with_ends(data.axial_reduction[np.ix_(idx, idx)], data.tip_axial_reduction[np.ix_(idx, idx)])
    return BladePointShapes(span=z, displacement=np.moveaxis(_interp(disp, z, grid), 1, -1),
                            slope=np.moveaxis(_interp(slope, z, grid), 1, -1), axial_reduction=_interp(ax, z, grid),
                            coordinates=tuple(coordinates))


def blade_point_kinematics(shapes: BladePointShapes, frame: dict[str, Any], qe: Any, qde: Any) -> dict[str, Any]:
    """Ground positions, velocities and span tangents of the points (CasADi expressions).

    Parameters
    ----------
    shapes : BladePointShapes
    frame : dict
        The blade body frame: ``r`` (3,) origin = root [m], ``R`` (3, 3) body -> ground, ``v`` (3,) [m/s],
        ``w`` (3,) angular velocity [rad/s], ground axes (``EquationsOfMotion.point_kinematics``).
    qe, qde : SX (n_e,)
        The blade's elastic coordinates and speeds, in shape order.

    Returns
    -------
    dict
        ``p`` (3, N) body positions, ``r`` (3, N) ground positions [m], ``v`` (3, N) ground velocities
        [m/s], ``tangent`` (3, N) unit deflected span direction (ground), ``slope`` (2, N) the slopes
        ``Φ' q`` along the body axes ``x``, ``y`` [rad], ``dp`` list over coordinates of (3, N)
        ``∂p/∂q_i`` (body axes).
    """
    n, ne = shapes.n_points, len(shapes.coordinates)
    kind = ca.MX if isinstance(frame["r"], ca.MX) else ca.SX
    zeros = kind.zeros(1, n)
    z = ca.DM(shapes.span.reshape(1, -1))
    px, py, pz = zeros, zeros, z
    vx, vy, vz = zeros, zeros, zeros
    sx, sy = zeros, zeros
    dp = []
    for i in range(ne):
        phi = ca.DM(shapes.displacement[i].T)                  # (2, N)
        slope = ca.DM(shapes.slope[i].T)
        px, py = px + phi[0, :] * qe[i], py + phi[1, :] * qe[i]
        vx, vy = vx + phi[0, :] * qde[i], vy + phi[1, :] * qde[i]
        sx, sy = sx + slope[0, :] * qe[i], sy + slope[1, :] * qe[i]
        ax_q = sum((ca.DM(shapes.axial_reduction[i, j].reshape(1, -1)) * qe[j] for j in range(ne)), zeros)
        dp.append(ca.vertcat(phi[0, :], phi[1, :], -ax_q))
    for i in range(ne):
        for j in range(ne):
            axij = ca.DM(shapes.axial_reduction[i, j].reshape(1, -1))
            pz = pz - 0.5 * axij * qe[i] * qe[j]
            vz = vz - axij * qe[i] * qde[j]
    p = ca.vertcat(px, py, pz)
    pdot = ca.vertcat(vx, vy, vz)
    R, w = frame["R"], frame["w"]
    s = R @ p
    r = ca.repmat(frame["r"], 1, n) + s
    v = ca.repmat(frame["v"], 1, n) + _cross_columns(w, s) + R @ pdot
    t_body = ca.vertcat(sx, sy, ca.DM.ones(1, n))
    tangent = R @ (t_body / ca.repmat(ca.sqrt(ca.sum1(t_body**2)), 3, 1))
    return {"p": p, "r": r, "v": v, "tangent": tangent, "slope": ca.vertcat(sx, sy), "dp": dp}


def _cross_columns(a: Any, B: Any) -> Any:
    """``a × B[:, j]`` for every column of B."""
    return ca.vertcat(a[1] * B[2, :] - a[2] * B[1, :], a[2] * B[0, :] - a[0] * B[2, :],
                      a[0] * B[1, :] - a[1] * B[0, :])


def blade_point_loads(kin: dict[str, Any], R: Any, force: Any, moment: Any, weights, *,
                      offsets=None) -> dict[str, Any]:
    """The structure's blade-load inputs from loads per unit length at the points.

    Parameters
    ----------
    kin : dict
        From :func:`blade_point_kinematics` (``p``, ``dp``).
    R : SX (3, 3)
        The blade body orientation (body -> ground).
    force, moment : SX (3, N)
        Force [N/m] and moment [N m/m] per unit length at the points, ground axes.
    weights : array_like (N,)
        Integration weights of the points [m] (``Σ w_j f_j`` is the resultant).
    offsets : array_like (3, N), optional, keyword-only
        Where the loads act relative to the points, body axes [m] (AeroDyn's aerodynamic centres,
        ``BlCrvAC`` along the first and ``BlSwpAC`` along the second axis): lever arms of the root
        moment only (the points' shapes, hence ``Q``, are those of the pitch axis). Default: at the points.

    Returns
    -------
    dict
        ``F`` (3,) root force [N] and ``M`` (3,) moment about the root [N m], body axes; ``Q`` list of
        generalized forces [N] of the elastic coordinates (shape order).
    """
    w = ca.DM(np.asarray(weights, dtype=float).reshape(1, -1))
    f_body = R.T @ force
    m_body = R.T @ moment
    fw = f_body * ca.repmat(w, 3, 1)
    F = ca.sum2(fw)
    arm = kin["p"] if offsets is None else kin["p"] + ca.DM(np.asarray(offsets, dtype=float))
    M = ca.sum2(_cross_pairs(arm, fw) + m_body * ca.repmat(w, 3, 1))
    Q = [ca.sum2(ca.sum1(d * fw)) for d in kin["dp"]]
    return {"F": F, "M": M, "Q": Q}


def _cross_pairs(A: Any, B: Any) -> Any:
    """Column-wise ``A[:, j] × B[:, j]``."""
    return ca.vertcat(A[1, :] * B[2, :] - A[2, :] * B[1, :], A[2, :] * B[0, :] - A[0, :] * B[2, :],
                      A[0, :] * B[1, :] - A[1, :] * B[0, :])
