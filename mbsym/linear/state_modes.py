"""Modes of a general first-order model ``δẋ = A δx``, each named by the state it lives in.

A composed model has states beyond ``[q; q̇]`` (actuators, inflow, controller states) in
mixed units (m, rad, N m …), so neither the size of an eigenvector's entries nor the kinetic
energy can say which state a mode belongs to. The *participation factor* of state ``i`` in
mode ``k`` (Pérez-Arriaga, Verghese & Schweppe, IEEE Trans. PAS 101(9), 1982),

    p_ik = |l_ik r_ik| / Σ_j |l_jk r_jk|,

with the right (``r``) and left (``l``) eigenvectors of A, does not change when a state is
rescaled (its unit changed), and for a decoupled state it is 1 in that state's own mode. A
coordinate and its speed (``x`` and ``x_d``) form one group; a mode's ``dominant_dof`` is the
group with the largest summed participation.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..exceptions import DimensionError

__all__ = ["StateMode", "state_modes", "participation_factors", "state_groups"]


@dataclass(frozen=True)
class StateMode:
    """One mode of a first-order model, named by its dominant state group.

    Attributes
    ----------
    freq_hz : float
        Natural frequency ``|λ|/2π`` [Hz] (0 for rigid-body modes).
    damping_ratio : float
        ``-Re λ/|λ|`` [-] (1 for a real decaying eigenvalue, 0 for rigid-body modes).
    damped_freq_hz : float
        ``|Im λ|/2π`` [Hz].
    eigenvalue : complex
        λ [rad/s] (the one with Im λ ≥ 0 of a pair).
    dominant_dof : str
        The state group (a coordinate with its speed, or a single state) with the largest
        participation.
    participation : dict of str to float
        Participation of every group, summing to 1, largest first.
    rigid_body, oscillatory : bool
    """

    freq_hz: float
    damping_ratio: float
    damped_freq_hz: float
    eigenvalue: complex
    dominant_dof: str
    participation: dict = field(default_factory=dict)
    rigid_body: bool = False
    oscillatory: bool = False

    def as_dict(self) -> dict:
        """``{"freq_hz", "damping_ratio", "dominant_dof"}`` (plain floats, for JSON)."""
        return {"freq_hz": float(self.freq_hz), "damping_ratio": float(self.damping_ratio),
                "dominant_dof": self.dominant_dof}


def state_groups(states: Sequence[str]) -> list[str]:
    """The group of each state: ``x_d`` joins ``x`` when both are states, every other state is its own.

    Examples
    --------
    >>> state_groups(["TFA1", "TFA1_d", "GeAz_d", "BlPitch", "BlPitch_d", "GenTq"])
    ['TFA1', 'TFA1', 'GeAz_d', 'BlPitch', 'BlPitch', 'GenTq']
    """
    names = set(states)
    return [s[:-2] if s.endswith("_d") and s[:-2] in names else s for s in states]


def participation_factors(A) -> tuple[np.ndarray, np.ndarray]:
    """Eigenvalues and participation factors of ``A`` (module docstring).

    Returns
    -------
    lam : ndarray (n,), complex
    P : ndarray (n, n)
        ``P[i, k]`` the participation of state ``i`` in eigenvalue ``k``; columns sum to 1.

    Raises
    ------
    DimensionError
        ``A`` not square or not finite.
    """
    import scipy.linalg

    A = np.asarray(A, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or not np.all(np.isfinite(A)):
        raise DimensionError(f"A must be a square finite matrix; got shape {A.shape}.")
    lam, left, right = scipy.linalg.eig(A, left=True, right=True)
    P = np.abs(left.conj() * right)
    total = P.sum(axis=0, keepdims=True)
    return lam, P / np.where(total > 0, total, 1.0)


def state_modes(A, states: Sequence[str], *, rigid_tol: float = 1e-4) -> list[StateMode]:
    """Modes of ``δẋ = A δx`` named by their dominant state group, sorted by natural frequency.

    Parameters
    ----------
    A : array (n, n)
    states : sequence of n str
        State names; ``x`` and ``x_d`` form one group (:func:`state_groups`).
    rigid_tol : float, keyword-only
        Eigenvalues with ``|λ| < rigid_tol`` [rad/s] are rigid-body motion (frequency 0).

    Returns
    -------
    list of StateMode
        One per complex-conjugate pair and per real eigenvalue.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.array([[0, 1.0, 0], [-4.0, -0.4, 1.0], [0, 0, -50.0]])   # oscillator driven by a lag
    >>> [(round(m.freq_hz, 4), m.dominant_dof) for m in state_modes(A, ["x", "x_d", "F"])]
    [(0.3183, 'x'), (7.9577, 'F')]
    """
    states = list(states)
    A = np.asarray(A, dtype=float)
    if A.shape != (len(states), len(states)):
        raise DimensionError(f"A must be ({len(states)}, {len(states)}) for the states {states}; got {A.shape}.")
    lam, P = participation_factors(A)
    groups = state_groups(states)
    names = list(dict.fromkeys(groups))
    G = np.zeros((len(names), len(states)))
    for i, g in enumerate(groups):
        G[names.index(g), i] = 1.0
    modes = []
    for k in np.flatnonzero(lam.imag >= 0):
        share = G @ P[:, k]
        order = np.argsort(-share, kind="stable")
        wn = abs(lam[k])
        rigid = wn < rigid_tol
        modes.append(StateMode(0.0 if rigid else float(wn / (2 * np.pi)),
                               0.0 if rigid else float(-lam[k].real / wn), float(abs(lam[k].imag) / (2 * np.pi)),
                               complex(lam[k]), names[order[0]], {names[j]: float(share[j]) for j in order},
                               bool(rigid), bool(lam[k].imag > 0 and not rigid)))
    return sorted(modes, key=lambda m: (not m.rigid_body, m.freq_hz))
