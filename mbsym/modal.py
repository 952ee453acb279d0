"""Modal analysis of first-order linear models ``δẋ = A δx`` with ``x = [q; q̇]``.

Eigenvalues λ of A give, per mode, the natural frequency ``|λ|/2π`` [Hz], the damping
ratio ``-Re λ/|λ|`` and the damped frequency ``|Im λ|/2π``; the eigenvector's
coordinate part is the mode shape, and its largest component names the dominant
DOF (units of q mix m and rad, so this is indicative, as in OpenFAST's tools).

One entry per complex-conjugate pair (oscillatory modes) and per real non-zero
eigenvalue (over-damped motion). Eigenvalues with ``|λ| < rigid_tol`` [rad/s] are
rigid-body motion: a free DOF without stiffness gives a double zero (or a zero and
a real decay rate if damped); they are reported once per independent rigid-body
shape, with frequency 0 and damping ratio 0, never as an error.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
import scipy.linalg
import scipy.optimize

from .exceptions import DimensionError, SolverError

__all__ = ["Mode", "modal_analysis", "mode_sensitivities", "RIGID_TOL", "CLUSTER_RTOL"]

#: Eigenvalues below this magnitude [rad/s] are rigid-body motion (OpenFAST's tools use 1e-4).
RIGID_TOL = 1e-4

#: Eigenvalues closer than this, relative to |λ|, form one repeated eigenvalue in
#: :func:`mode_sensitivities`: identical blades on a symmetric support repeat to round-off,
#: a defective (Jordan) double eigenvalue splits by ~sqrt(eps) = 1.5e-8.
CLUSTER_RTOL = 1e-6


@dataclass(frozen=True)
class Mode:
    """One mode of a linear model.

    Attributes
    ----------
    freq_hz : float
        Natural frequency ``|λ|/2π`` [Hz]; 0 for rigid-body modes.
    damping_ratio : float
        ``-Re λ / |λ|`` [-] (1 for a real decaying eigenvalue, 0 for rigid-body modes).
    damped_freq_hz : float
        ``|Im λ|/2π`` [Hz].
    eigenvalue : complex
        λ [rad/s] (the one with Im λ ≥ 0 of a pair).
    shape : ndarray (n_q,), complex
        Coordinate part of the eigenvector, scaled so its dominant entry is 1.
    dominant_dof : str
        Name of the coordinate with the largest shape entry.
    rigid_body, oscillatory : bool
    eigen_index : int
        Position of λ among the eigenvalues of ``scipy.linalg.eig(A)`` (what
        :func:`mode_sensitivities` differentiates); -1 for rigid-body modes.
    """

    freq_hz: float
    damping_ratio: float
    damped_freq_hz: float
    eigenvalue: complex
    shape: np.ndarray
    dominant_dof: str
    rigid_body: bool
    oscillatory: bool
    eigen_index: int = -1

    def as_dict(self) -> dict:
        """``{"freq_hz", "damping_ratio", "dominant_dof"}`` (plain floats, for JSON)."""
        return {"freq_hz": float(self.freq_hz), "damping_ratio": float(self.damping_ratio),
                "dominant_dof": self.dominant_dof}


def _check(A, coordinates: Sequence[str]) -> np.ndarray:
    A = np.asarray(A, dtype=float)
    n = len(coordinates)
    if A.shape != (2 * n, 2 * n):
        raise DimensionError(f"A must be ({2 * n}, {2 * n}) for the {n} coordinates {list(coordinates)}; "
                             f"got {A.shape}.")
    if not np.all(np.isfinite(A)):
        raise DimensionError("A must be finite.")
    return A


def _scaled(v: np.ndarray, coordinates: Sequence[str]) -> tuple[np.ndarray, str]:
    k = int(np.argmax(np.abs(v)))
    return v / v[k], coordinates[k]


def modal_analysis(A, coordinates: Sequence[str], *, rigid_tol: float = RIGID_TOL) -> list[Mode]:
    """Modes of ``δẋ = A δx`` (``x = [q; q̇]``), sorted by natural frequency.

    Parameters
    ----------
    A : array (2 n_q, 2 n_q)
    coordinates : sequence of n_q str
        Names of q (for ``dominant_dof``).
    rigid_tol : float, keyword-only
        Eigenvalues with ``|λ| < rigid_tol`` [rad/s] are rigid-body motion.

    Returns
    -------
    list of Mode
        Rigid-body modes first (frequency 0), then by increasing frequency.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[0, 0, 1, 0], [0, 0, 0, 1], [-4.0, 0, -0.04, 0], [0, 0, 0, 0]])
    >>> [(round(m.freq_hz, 4), m.dominant_dof, m.rigid_body) for m in modal_analysis(A, ["x", "psi"])]
    [(0.0, 'psi', True), (0.3183, 'x', False)]
    """
    A = _check(A, coordinates)
    n = len(coordinates)
    lam, _, vec = _eig(A)
    zero = np.abs(lam) < rigid_tol
    modes = _rigid_modes(vec[:n, zero], coordinates)
    for i in np.flatnonzero(~zero):
        if lam[i].imag < 0:
            continue
        wn = abs(lam[i])
        shape, dof = _scaled(vec[:n, i], coordinates)
        modes.append(Mode(float(wn / (2 * np.pi)), float(-lam[i].real / wn), float(abs(lam[i].imag) / (2 * np.pi)),
                          complex(lam[i]), shape, dof, False, bool(lam[i].imag > 0), int(i)))
    return sorted(modes, key=lambda m: (not m.rigid_body, m.freq_hz))


def _eig(A: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Eigenvalues, left and right eigenvectors of A: the one decomposition modes are indexed into."""
    return scipy.linalg.eig(A, left=True, right=True)


def _rigid_modes(V: np.ndarray, coordinates: Sequence[str]) -> list[Mode]:
    """One mode per independent coordinate shape among the zero eigenvalues' eigenvectors.

    A free DOF gives a (defective) double zero whose two eigenvectors are parallel:
    the rank of their normalized coordinate parts counts the rigid-body modes.
    """
    if V.shape[1] == 0:
        return []
    V = V / np.linalg.norm(V, axis=0, keepdims=True)
    U, s, _ = np.linalg.svd(V)
    rank = max(1, int(np.sum(s > 1e-4 * s[0])))
    modes = []
    for k in range(rank):
        shape, dof = _scaled(U[:, k], coordinates)
        modes.append(Mode(0.0, 0.0, 0.0, 0j, shape, dof, True, False))
    return modes


def mode_sensitivities(A, dA, modes: Sequence[Mode]) -> tuple[np.ndarray, np.ndarray]:
    """Derivatives of the modes' natural frequency [Hz] and damping ratio.

    First-order eigenvalue perturbation ``∂λ = wᴴ ∂A v / (wᴴ v)`` with the left
    (w) and right (v) eigenvectors of A, then ``∂|λ| = Re(λ̄ ∂λ)/|λ|`` and
    ``∂ζ = -(Re ∂λ + ζ ∂|λ|)/|λ|``. Rigid-body modes get 0.

    A repeated eigenvalue (a cluster closer than :data:`CLUSTER_RTOL` |λ|, e.g.
    identical blades at standstill) has no unique eigenvectors: its derivatives are
    the eigenvalues of ``(W_Sᴴ V_S)⁻¹ W_Sᴴ ∂A V_S`` on the cluster S (degenerate
    perturbation theory; directional derivatives, one set per parameter), each given
    to the mode whose eigenvector the perturbed one overlaps most.

    Parameters
    ----------
    A : array (n_x, n_x)
    dA : array (n_s, n_x, n_x)
        ∂A per parameter.
    modes : sequence of Mode
        From :func:`modal_analysis` of the same A.

    Returns
    -------
    dfreq, dzeta : ndarray (n_s, len(modes))

    Raises
    ------
    SolverError
        If a repeated eigenvalue is defective (a Jordan block, e.g. a critically
        damped mode): its derivative does not exist.
    """
    A = np.asarray(A, dtype=float)
    dA = np.asarray(dA, dtype=float).reshape(-1, *A.shape)
    lam, W, V = _eig(A)
    dfreq = np.zeros((dA.shape[0], len(modes)))
    dzeta = np.zeros_like(dfreq)
    index = _eigen_indices(lam, modes)                 # mode k -> eigenvalue index
    done: set[int] = set()
    for k in index:
        if k in done:
            continue
        cluster = np.flatnonzero(np.abs(lam - lam[index[k]]) <= CLUSTER_RTOL * abs(lam[index[k]]))
        members = [j for j in index if index[j] in cluster]
        dlam = _cluster_derivatives(lam, W, V, dA, cluster, [index[j] for j in members], modes[k])
        for col, j in enumerate(members):
            lk = lam[index[j]]
            wn = abs(lk)
            dwn = np.real(np.conj(lk) * dlam[:, col]) / wn
            dfreq[:, j] = dwn / (2 * np.pi)
            dzeta[:, j] = -(np.real(dlam[:, col]) + (-lk.real / wn) * dwn) / wn
        done.update(members)
    return dfreq, dzeta


def _eigen_indices(lam: np.ndarray, modes: Sequence[Mode]) -> dict[int, int]:
    """Eigenvalue index of each non-rigid mode: its ``eigen_index`` when it matches, else the nearest free one."""
    index: dict[int, int] = {}
    used: set[int] = set()
    for k, mode in enumerate(modes):
        i = mode.eigen_index
        if not mode.rigid_body and 0 <= i < lam.size and abs(lam[i] - mode.eigenvalue) <= 1e-12 * abs(lam[i]):
            index[k] = i
            used.add(i)
    for k, mode in enumerate(modes):
        if not mode.rigid_body and k not in index:
            dist = np.abs(lam - mode.eigenvalue)
            dist[list(used)] = np.inf
            index[k] = int(np.argmin(dist))
            used.add(index[k])
    return index


def _cluster_derivatives(lam, W, V, dA, cluster, rows, mode: Mode) -> np.ndarray:
    """(n_s, len(rows)): ∂λ of the eigenvalues ``rows`` of one cluster of (numerically) equal eigenvalues."""
    Ws, Vs = W[:, cluster], V[:, cluster]
    G = np.einsum("ia,sij,jb->sab", Ws.conj(), dA, Vs)
    N = Ws.conj().T @ Vs                             # biorthogonality on the cluster
    if cluster.size == 1:
        return (G[:, 0, 0] / N[0, 0])[:, np.newaxis]
    s = np.linalg.svd(Vs / np.linalg.norm(Vs, axis=0), compute_uv=False)
    if s[-1] < 1e-6 * s[0]:
        raise SolverError(f"the eigenvalue {complex(lam[cluster[0]]):.6g} rad/s (mode at {mode.freq_hz:.6g} Hz, "
                          f"dominant DOF {mode.dominant_dof}) is repeated {cluster.size} times and defective "
                          "(a Jordan block, e.g. critical damping): its derivative does not exist. Perturb the "
                          "damping or stiffness slightly.")
    pos = [int(np.flatnonzero(cluster == r)[0]) for r in rows]
    out = np.zeros((dA.shape[0], len(rows)), dtype=complex)
    for p in range(dA.shape[0]):
        mu, Y = np.linalg.eig(np.linalg.solve(N, G[p]))
        weight = np.abs(Y[pos]) ** 2 / np.sum(np.abs(Y) ** 2, axis=0)     # mode row, perturbed eigvec column
        r, c = scipy.optimize.linear_sum_assignment(-weight)
        out[p, r] = mu[c]
    return out
