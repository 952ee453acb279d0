"""A state-space fit of the radiation memory to the WAMIT ``.1`` data (vector fitting).

Each significant entry K_ij(iω) = B_ij(ω) + iω (A_ij(ω) − A∞_ij) is fitted on its own by
vector fitting (Gustavsen and Semlyen 1999, IEEE Trans. Power Delivery 14(3)): a strictly proper
rational function Σ c_n / (s − a_n) with stable poles, relocated from complex pairs spread over
the band by repeated linear least squares; the data at −iω (complex conjugates) keep the poles
and residues in conjugate pairs. The number of pole pairs grows per entry until the largest
error is below ``tolerance`` of the entry's peak (or ``max_pairs``). Entries whose peak is below
``coupling_threshold`` of √(peak_ii peak_jj) are left out (zero).

Two choices make the fit right where the slow modes live (surge and sway near 0.06 rad/s, pitch,
roll and heave near 0.2 rad/s), where B(ω) is tiny against its peak:

* **K(0) = 0.** B(0) = 0 and A(0) − A∞ is finite, so K(iω) → 0 as ω → 0 (no memory force on a
  steady drift). The residues are solved with that as a constraint, −Σ c_n / a_n = 0; then
  Re K = O(ω²) near 0 as in the data.
* **Relative weights.** Each sample's error counts relative to ``|K(ω)| + floor · peak``
  (``weight_floor``), not to the peak alone: unweighted, the deck's surge entry had
  B₁₁(0.0585 rad/s) = 3.0e4 N s/m where the ``.1`` data hold 1.1e2, about 0.8 % of the
  floating turbine's critical surge damping, enough to damp the slow surge oscillation the
  shared ``fl_steady_13`` run shows growing (its negative damping 2.5 % in OpenFAST).

Frequencies above ``max_frequency`` are not fitted: WAMIT's irregular frequencies put spikes in
the deck's ``.1`` data near 4.6-4.9 rad/s (even a negative heave damping), beyond any wave
spectrum of the decks (``WvHiCOff`` 3.2 rad/s). The result is a
:class:`~.radiation.RadiationStateSpace` (``F = C x = −K q̇``); judge it with its ``accuracy``.
Passivity is not enforced (see docs/offshore.md).
"""

from __future__ import annotations

import hashlib
import os

import numpy as np

from ...exceptions import OptionError, SolverError
from .radiation import RadiationStateSpace, radiation_reference

__all__ = ["fit_radiation", "fit_radiation_cached", "vector_fit", "FIT_VERSION"]

#: Names the fit's algorithm in the disk cache's key (:func:`fit_radiation_cached`): change it with the algorithm.
FIT_VERSION = "vector fit, relative weights, K(0) = 0 (2026-11-29)"


def _paired(poles: np.ndarray) -> np.ndarray:
    """Stable poles (real parts flipped to negative) in conjugate pairs, real poles kept real."""
    out = []
    for p in poles:
        p = complex(-abs(p.real), p.imag)
        if abs(p.imag) <= 1e-9 * max(1.0, abs(p)):
            out.append(complex(p.real, 0.0))
        elif p.imag > 0:
            out += [p, p.conjugate()]
    return np.array(out)


def _lstsq_complex(M: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """Complex unknowns of M x ≈ rhs by real least squares."""
    n = M.shape[1]
    big = np.hstack([M, 1j * M])
    x = np.linalg.lstsq(np.vstack([big.real, big.imag]), np.concatenate([rhs.real, rhs.imag]), rcond=None)[0]
    return x[:n] + 1j * x[n:]


def vector_fit(omega, values, n_pairs: int, *, iterations: int = 30, weight_floor: float | None = None,
               zero_at_origin: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Poles and residues of ``Σ c_n / (iω − a_n)`` fitted to ``values`` at ``omega`` [rad/s].

    Parameters
    ----------
    n_pairs : int
        Number of pole pairs.
    iterations : int, keyword-only
        Pole relocations.
    weight_floor : float or None, keyword-only
        None: every sample weighs the same (least absolute error). A number ``f > 0``: each
        sample's error is divided by ``|value| + f · max |value|`` (relative error, floored).
    zero_at_origin : bool, keyword-only
        Constrain the fit to vanish at ω = 0 (``Σ c_n / a_n = 0``).

    Examples
    --------
    >>> w = np.linspace(0.1, 3, 60); h = 2.0 / (1j * w + 0.5)
    >>> poles, res = vector_fit(w, h, 1)
    >>> bool(np.abs((res[None] / (1j * w[:, None] - poles[None])).sum(1) - h).max() < 1e-8)
    True
    """
    if weight_floor is not None and not (isinstance(weight_floor, (int, float)) and weight_floor > 0.0):
        raise OptionError(f"weight_floor must be None or a positive number; got {weight_floor!r}.")
    omega, values = np.asarray(omega, float), np.asarray(values, complex)
    s = np.concatenate([1j * omega, -1j * omega])
    f = np.concatenate([values, values.conj()])
    scale = max(np.abs(f).max(), 1e-300)
    w = np.ones(len(f)) if weight_floor is None else 1.0 / (np.abs(f) / scale + weight_floor)
    beta = np.geomspace(omega[0], omega[-1], n_pairs)
    poles = np.concatenate([-0.01 * beta + 1j * beta, -0.01 * beta - 1j * beta])
    for _ in range(iterations):
        basis = 1.0 / (s[:, None] - poles[None, :])
        x = _lstsq_complex(w[:, None] * np.hstack([basis, -(f / scale)[:, None] * basis]), w * f / scale)
        sigma = x[len(poles):]
        poles = _paired(np.linalg.eigvals(np.diag(poles) - np.outer(np.ones(len(poles)), sigma)))
    M, rhs = w[:, None] / (s[:, None] - poles[None, :]), w * f / scale
    if zero_at_origin:  # one heavy row: the fit's value at s = 0, -sum c/a, is zero
        heavy = 1e3 * np.sqrt(len(f)) * w.max()
        M, rhs = np.vstack([M, heavy * (-1.0 / poles)[None, :]]), np.append(rhs, 0.0)
    return poles, scale * _lstsq_complex(M, rhs)


def _realize(poles: np.ndarray, residues: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Real (A, b, c) with c (sI − A)⁻¹ b = Σ r/(s − p): a real pole → one state; a pair
    α ± iβ with residues r, r̄ → A = [[α, β], [−β, α]], b = [2, 0], c = [Re r, Im r]."""
    blocks = []
    for p, r in zip(poles, residues):
        if p.imag == 0:
            blocks.append((np.array([[p.real]]), np.array([1.0]), np.array([r.real])))
        elif p.imag > 0:
            blocks.append((np.array([[p.real, p.imag], [-p.imag, p.real]]), np.array([2.0, 0.0]),
                           np.array([r.real, r.imag])))
    n = sum(b[0].shape[0] for b in blocks)
    A, b, c, k = np.zeros((n, n)), np.zeros(n), np.zeros(n), 0
    for Ab, bb, cb in blocks:
        d = Ab.shape[0]
        A[k:k + d, k:k + d], b[k:k + d], c[k:k + d] = Ab, bb, cb
        k += d
    return A, b, c


def fit_radiation(wamit, *, max_frequency: float = 4.0, tolerance: float = 0.02, max_pairs: int = 12,
                  coupling_threshold: float = 0.01, weight_floor: float = 0.02) -> RadiationStateSpace:
    """Fit the radiation memory of ``wamit`` (a :class:`~mbsym.wind.deck.wamit.WamitHydrodynamics`).

    Parameters
    ----------
    max_frequency : float, keyword-only
        Highest fitted frequency [rad/s] (module docstring).
    tolerance : float, keyword-only
        Target largest error per entry, relative to its peak over the band.
    max_pairs : int, keyword-only
        Most pole pairs per entry.
    coupling_threshold : float, keyword-only
        Entries smaller than this fraction of √(peak_ii peak_jj) are not fitted.
    weight_floor : float, keyword-only
        Floor of the relative weights, as a fraction of the entry's peak (module docstring).

    Raises
    ------
    SolverError
        When the band holds fewer than 8 frequencies.
    OptionError
        When ``weight_floor`` is not in (0, 1].
    """
    if not (isinstance(weight_floor, (int, float)) and 0.0 < weight_floor <= 1.0):
        raise OptionError(f"weight_floor must be a number in (0, 1] (a fraction of each entry's peak); "
                          f"got {weight_floor!r}.")
    band = wamit.frequencies <= max_frequency
    if band.sum() < 8:
        raise SolverError(f"only {band.sum()} WAMIT frequencies up to {max_frequency} rad/s; at least 8 are needed.")
    omega, K = wamit.frequencies[band], -radiation_reference(wamit)[band]
    peak = np.abs(K).max(axis=0)
    blocks = []
    for i in range(6):
        for j in range(6):
            if peak[i, j] == 0 or peak[i, j] < coupling_threshold * np.sqrt(peak[i, i] * peak[j, j]):
                continue
            for pairs in range(2, max_pairs + 1):
                poles, res = vector_fit(omega, K[:, i, j], pairs, weight_floor=weight_floor, zero_at_origin=True)
                fit = (res[None] / (1j * omega[:, None] - poles[None])).sum(axis=1)
                if np.abs(fit - K[:, i, j]).max() <= tolerance * peak[i, j]:
                    break
            blocks.append((i, j, *_realize(poles, res)))
    n = sum(b[2].shape[0] for b in blocks)
    A, B, C, k = np.zeros((n, n)), np.zeros((n, 6)), np.zeros((6, n)), 0
    for i, j, Ab, bb, cb in blocks:
        d = Ab.shape[0]
        A[k:k + d, k:k + d], B[k:k + d, j], C[i, k:k + d] = Ab, bb, -cb   # F = −K q̇
        k += d
    return RadiationStateSpace(A, B, C)


def fit_radiation_cached(wamit, **options) -> RadiationStateSpace:
    """:func:`fit_radiation` through a disk cache: the same ``.1`` data and options give the stored block.

    The fit takes about 3 s on an idle machine and far longer on a loaded one (numpy's threaded LAPACK
    on its many small least-squares solves: 121 s measured), at every build of a floating model. The
    block is kept in ``<cache dir>/radiation/<key>.npz`` (:func:`mbsym.codegen.cache_dir`), the key a
    SHA-256 of :data:`FIT_VERSION`, the options and the frequencies, A(ω), A∞ and B(ω) it fits. An
    unreadable or unwritable cache is bypassed (the fit is computed).
    """
    from ...codegen import cache_dir

    digest = hashlib.sha256(FIT_VERSION.encode())
    digest.update(repr(sorted(options.items())).encode())
    for array in (wamit.frequencies, wamit.added_mass[:, :6, :6], wamit.added_mass_infinite[:6, :6],
                  wamit.damping[:, :6, :6]):
        digest.update(np.ascontiguousarray(array, dtype=float).tobytes())
    path = cache_dir() / "radiation" / f"{digest.hexdigest()[:32]}.npz"
    try:
        with np.load(path) as stored:
            return RadiationStateSpace(stored["A"], stored["B"], stored["C"])
    except (OSError, KeyError, ValueError):
        pass
    block = fit_radiation(wamit, **options)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(f"{path.stem}.{os.getpid()}.partial.npz")
        np.savez(partial, A=block.A, B=block.B, C=block.C)
        os.replace(partial, path)                       # atomic: a reader sees the whole file or none
    except OSError:
        pass
    return block
