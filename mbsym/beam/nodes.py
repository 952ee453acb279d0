"""Point masses of a lumped beam with their exact (quadratic) displacement field.

ElastoDyn's blades and tower are point masses whose body-frame position is, for shape
coordinates ``q`` (``n_e`` of them),

``s_J(q) = (Phi_Jx q, Phi_Jy q, z_J - 1/2 q^T Ax_J q)``

with the partial velocities ``S_J = ds_J/dq`` (rows ``Phi_Jx``, ``Phi_Jy``, ``-(Ax_J q)^T``).
Every inertial quantity of such a body (first and second moments of mass, the coupling
``sum m s x S``, the generalized mass ``sum m S^T S`` …) is then a polynomial in ``q`` of
degree at most 4, whose coefficients are sums over the nodes of products of ``z``, ``Phi``
and ``Ax``. :class:`LumpedNodes` keeps the node data; :meth:`LumpedNodes.moments` computes
those coefficient tensors once (:class:`NodeMoments`), so that a flexible body evaluates its
exact Kane terms (:mod:`mbsym.bodies.lumped_terms`) without a symbolic sum over the nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from mbsym.exceptions import BeamDataError

__all__ = ["LumpedNodes", "NodeMoments"]


@dataclass(frozen=True, eq=False)
class NodeMoments:
    """Sums over the nodes (weights ``m_J``) that make the lumped body's polynomial terms.

    Indices ``a, b`` run over the transverse axes (x, y), ``i, j, k, l`` over the shapes.

    Attributes
    ----------
    mass : float
        ``sum m`` [kg].
    z1, z2 : float
        ``sum m z`` [kg m], ``sum m z^2`` [kg m^2].
    p : ndarray (2, n_e)
        ``P[a, i] = sum m Phi_a,i`` [kg].
    pz : ndarray (2, n_e)
        ``sum m z Phi_a,i`` [kg m].
    pp : ndarray (2, 2, n_e, n_e)
        ``sum m Phi_a,i Phi_b,j`` [kg].
    k1, kz : ndarray (n_e, n_e)
        ``sum m Ax_ij`` [kg/m], ``sum m z Ax_ij`` [kg].
    kp : ndarray (2, n_e, n_e, n_e)
        ``sum m Ax_ij Phi_a,k`` [kg/m].
    kk : ndarray (n_e, n_e, n_e, n_e)
        ``sum m Ax_ij Ax_kl`` [kg/m^2].
    """

    mass: float
    z1: float
    z2: float
    p: np.ndarray
    pz: np.ndarray
    pp: np.ndarray
    k1: np.ndarray
    kz: np.ndarray
    kp: np.ndarray
    kk: np.ndarray


@dataclass(frozen=True, eq=False)
class LumpedNodes:
    """Point masses along body z with ElastoDyn's exact displacement field.

    Parameters
    ----------
    z : array_like (N,)
        Undeflected node positions along body z from the root [m] (a tip mass is a node).
    mass : array_like (N,)
        Node masses [kg], >= 0.
    displacement : array_like (n_e, N, 2)
        Transverse (x, y) displacement of each node per unit shape coordinate [m/m].
    axial_reduction : array_like (n_e, n_e, N)
        ``Ax[i, j, J]`` [1/m], symmetric in ``i, j``: node ``J`` moves by
        ``-1/2 q^T Ax_J q`` along z.
    end_axial_reduction : array_like (n_e, n_e)
        ``Ax`` at the body's end (attachment point) [1/m].

    Examples
    --------
    >>> n = LumpedNodes([1.0], [2.0], [[[1.0, 0.0]]], [[[0.5]]], [[0.5]])
    >>> n.positions([0.2]).round(6).tolist()
    [[0.2, 0.0, 0.99]]
    """

    z: np.ndarray
    mass: np.ndarray
    displacement: np.ndarray
    axial_reduction: np.ndarray
    end_axial_reduction: np.ndarray
    _moments: list = field(default_factory=list, init=False, repr=False)

    def __post_init__(self) -> None:
        z = _array("z", self.z, 1)
        n = z.size
        m = _array("mass", self.mass, 1)
        phi = _array("displacement", self.displacement, 3)
        n_e = phi.shape[0]
        ax = _array("axial_reduction", self.axial_reduction, 3)
        ax_end = _array("end_axial_reduction", self.end_axial_reduction, 2)
        expected = {"mass": (m.shape, (n,)), "displacement": (phi.shape, (n_e, n, 2)),
                    "axial_reduction": (ax.shape, (n_e, n_e, n)), "end_axial_reduction": (ax_end.shape, (n_e, n_e))}
        bad = [f"{k} has shape {got}, expected {want}" for k, (got, want) in expected.items() if got != want]
        if bad:
            raise BeamDataError("LumpedNodes: " + "; ".join(bad) + " (N nodes, n_e shapes).")
        if np.any(m < 0):
            raise BeamDataError(f"LumpedNodes: node masses must be >= 0; got {m.min():g} kg.")
        for name, a in (("axial_reduction", ax), ("end_axial_reduction", ax_end)):
            if np.abs(a - np.swapaxes(a, 0, 1)).max(initial=0.0) > 1e-9 * max(np.abs(a).max(initial=0.0), 1e-300):
                raise BeamDataError(f"LumpedNodes: {name} must be symmetric in its two shape indices.")
        for name, a in (("z", z), ("mass", m), ("displacement", phi), ("axial_reduction", ax),
                        ("end_axial_reduction", ax_end)):
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def n_e(self) -> int:
        """Number of shapes."""
        return self.displacement.shape[0]

    def positions(self, q: ArrayLike) -> np.ndarray:
        """Node positions ``s_J(q)`` in the body frame, shape (N, 3) [m]."""
        q = np.asarray(q, dtype=float).reshape(-1)
        xy = np.einsum("iJa,i->Ja", self.displacement, q)
        drop = 0.5 * np.einsum("ijJ,i,j->J", self.axial_reduction, q, q)
        return np.column_stack([xy, self.z - drop])

    def partial_velocities(self, q: ArrayLike) -> np.ndarray:
        """``S_J = ds_J/dq``, shape (N, 3, n_e) [m/m]."""
        q = np.asarray(q, dtype=float).reshape(-1)
        axq = np.einsum("ijJ,j->Ji", self.axial_reduction, q)
        return np.concatenate([np.moveaxis(self.displacement, 0, -1), -axq[:, None, :]], axis=1)

    def select(self, indices: Sequence[int]) -> "LumpedNodes":
        """The nodes with the shapes ``indices`` only (in that order)."""
        idx = np.asarray(indices, dtype=int).reshape(-1)
        sq = np.ix_(idx, idx)
        return LumpedNodes(self.z, self.mass, self.displacement[idx], self.axial_reduction[sq],
                           self.end_axial_reduction[sq])

    def moments(self) -> NodeMoments:
        """The coefficient tensors of the exact polynomial terms (computed once)."""
        if not self._moments:
            m, z, ax = self.mass, self.z, self.axial_reduction
            phi = np.moveaxis(self.displacement, -1, 0)                     # (2, n_e, N)
            self._moments.append(NodeMoments(
                mass=float(m.sum()), z1=float(m @ z), z2=float(m @ z**2),
                p=phi @ m, pz=phi @ (m * z),
                pp=np.einsum("J,aiJ,bjJ->abij", m, phi, phi),
                k1=ax @ m, kz=ax @ (m * z),
                kp=np.einsum("J,ijJ,akJ->aijk", m, ax, phi),
                kk=np.einsum("J,ijJ,klJ->ijkl", m, ax, ax),
            ))
        return self._moments[0]


def _array(name: str, value: ArrayLike, ndim: int) -> np.ndarray:
    a = np.array(value, dtype=float)
    if a.ndim != ndim:
        raise BeamDataError(f"LumpedNodes: {name} must have {ndim} dimension(s); got shape {a.shape}.")
    if not np.all(np.isfinite(a)):
        raise BeamDataError(f"LumpedNodes: {name} contains NaN or Inf; all entries must be finite.")
    return a
