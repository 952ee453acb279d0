"""Second-order wave forces, the way HydroDyn computes them (``DiffQTF``, ``SumQTF``, ``MnDrift``, ``NewmanApp``).

HydroDyn (v5.0.0, ``WAMIT2.f90``: ``DiffQTF_InitCalc``, ``MnDrift_InitCalc``, ``SumQTF_InitCalc``,
``NewmanApp_InitCalc``) turns the first-order sea into a
force time series before the run, fixed at the platform's undisplaced position, that joins the first-order
excitation (its ``B1WvsFxi`` … channels are their sum). With the sea's DFT ``C_k`` (:class:`~.waves.IncidentWaves`,
SeaState's ``WaveElevC0``) and the amplitudes ``a_k = C_k / (N/2)`` at ``ω_k = k Δω``:

* the mean drift ``F̄ = Σ_k Re Q(ω_k, ω_k) |a_k|²`` over the first-order band ``[WvLowCOff, WvHiCOff]``;
* per difference frequency ``Ω_j = j Δω`` inside ``[WvLowCOffD, WvHiCOffD]``,
  ``H_j = ½ Σ_k a_(j+k) conj(a_k) Q(ω_(j+k), ω_k)``;
* ``F(t_n) = F̄ + 2 Σ_j 2 Re(H_j e^(i Ω_j t_n))`` on the sea's ``N`` samples (the unnormalized inverse FFT of
  ``H``, doubled), periodic with the sea, read between samples like the first-order excitation.

``Q`` is the QTF of the ``.NNd`` file (:func:`~mbsym.wind.deck.wamit_qtf.read_wamit_qtf`, redimensionalized),
read bilinearly between its frequencies and zero outside their range (HydroDyn pads its grid with zeros there),
at the waves' heading (minus ``PtfmRefY``) wrapped into the file's heading range by whole turns, bilinearly between
its headings. The sum-frequency forces (``SumQTF``, the ``.NNs`` file) are made the same way at the sum frequencies
(:func:`sum_frequency_forces`); the mean drift alone (``MnDrift`` 10-12, a difference-frequency file's diagonal) by
:func:`mean_drift_forces`; Newman's approximation (``NewmanApp``) by :func:`newman_forces`, each from a
difference-frequency file (10-12) or WAMIT's 3-D mean-drift files (7-9). Unidirectional seas only: a spread sea
(``WaveDirMod`` 1) is refused (:mod:`.platform`).
"""

from __future__ import annotations

import math

import numpy as np

from ...exceptions import UnsupportedFeatureError
from .waves import IncidentWaves

__all__ = ["difference_frequency_forces", "mean_drift_forces", "newman_forces", "sum_frequency_forces", "qtf_at"]


def difference_frequency_forces(qtf, waves: IncidentWaves, *, band: tuple[float, float],
                                difference_band: tuple[float, float], heading: float | None = None) -> np.ndarray:
    """HydroDyn's difference-frequency force series (module docstring), ``(N + 1, 6)`` [N, N m] on
    ``waves.times()`` (last = first), inertial axes at the WAMIT reference point.

    Parameters
    ----------
    qtf : QtfData
        A redimensionalized difference-frequency QTF.
    waves : IncidentWaves
        A unidirectional sea.
    band, difference_band : (float, float), keyword-only
        ``(WvLowCOff, WvHiCOff)`` and ``(WvLowCOffD, WvHiCOffD)`` [rad/s].
    heading : float, optional, keyword-only
        The waves' heading as the platform sees it [rad] (default the sea's direction).

    Raises
    ------
    UnsupportedFeatureError
        A spread sea, a sum-frequency QTF, or a heading outside the file's headings.
    """
    if qtf.diagonal:
        raise UnsupportedFeatureError(f"{qtf.source}: a mean-drift file (equal frequencies only); the "
                                      "difference-frequency forces need a full QTF (.10d, .11d or .12d).")
    beta, a, w, n_half = _sea(qtf, waves, heading, "difference", "the difference-frequency forces", "DiffQTF")
    k = np.arange(1, n_half + 1)
    in_band = k[(w[k] >= band[0]) & (w[k] <= band[1])]
    mean = np.sum(qtf_at(qtf, w[in_band], w[in_band], beta).real * (np.abs(a[in_band]) ** 2)[:, None], axis=0)
    live = k[(np.abs(a[k]) > 0) & (k < n_half)]
    hi, lo = np.meshgrid(live, live, indexing="ij")
    pair = hi > lo
    hi, lo = hi[pair], lo[pair]
    j = hi - lo
    omega = j * waves.frequency_step
    keep = (omega >= difference_band[0]) & (omega <= difference_band[1]) & (j < n_half)
    hi, lo, j = hi[keep], lo[keep], j[keep]
    terms = (a[hi] * np.conj(a[lo]))[:, None] * qtf_at(qtf, w[hi], w[lo], beta)
    h = np.zeros((n_half + 1, 6), dtype=complex)
    for m in range(6):
        real, imag = (np.bincount(j, part, n_half + 1) for part in (terms[:, m].real, terms[:, m].imag))
        h[:, m] = 0.5 * (real + 1j * imag)
    series = 2.0 * waves.n_steps * np.fft.irfft(h, n=waves.n_steps, axis=0) + mean
    return np.vstack([series, series[:1]])


def mean_drift_forces(qtf, waves: IncidentWaves, *, band: tuple[float, float],
                      heading: float | None = None) -> np.ndarray:
    """HydroDyn's mean drift alone (``MnDrift``: a 3-D file 7-9, read along its diagonal, or a difference-frequency
    file 10-12, read as :func:`qtf_at`; ``MnDrift_InitCalc``):
    ``F̄ = Σ_k Re Q(ω_k, ω_k) |a_k|²`` over ``band`` (``WvLowCOff``, ``WvHiCOff``) [rad/s], as a constant
    ``(N + 1, 6)`` series [N, N m] on ``waves.times()``.

    Raises
    ------
    UnsupportedFeatureError
        As :func:`difference_frequency_forces`.
    """
    beta, a, w, n_half = _sea(qtf, waves, heading, "difference", "the mean drift", "MnDrift")
    k = np.arange(1, n_half + 1)
    k = k[(w[k] >= band[0]) & (w[k] <= band[1])]
    q = _diagonal_at(qtf, w[k], beta) if qtf.diagonal else qtf_at(qtf, w[k], w[k], beta)     # 3-D or 4-D data
    mean = np.sum(q.real * (np.abs(a[k]) ** 2)[:, None], axis=0)
    return np.tile(mean, (waves.n_steps + 1, 1))


def newman_forces(qtf, waves: IncidentWaves, *, band: tuple[float, float],
                  heading: float | None = None) -> np.ndarray:
    """HydroDyn's mean and slow drift by Newman's approximation (``NewmanApp`` with a 3-D file 7-9 or a
    difference-frequency file 10-12; ``NewmanApp_InitCalc``): with ``q_k = Re Q(ω_k, ω_k)`` (read along the file's diagonal, as HydroDyn's
    3-D copy of the data) over ``band`` (first-order cut-offs) [rad/s],
    ``F(t) = |Σ_(q_k>0) a_k √q_k e^{iω_k t}|² − |Σ_(q_k<0) a_k √(−q_k) e^{iω_k t}|²`` on ``waves.times()``
    ``(N + 1, 6)`` [N, N m] (HydroDyn's one-sided complex inverse FFT, frequencies below N/2).

    Raises
    ------
    UnsupportedFeatureError
        As :func:`difference_frequency_forces`.
    """
    beta, a, w, n_half = _sea(qtf, waves, heading, "difference", "Newman's approximation", "NewmanApp")
    n = waves.n_steps
    k = np.arange(1, n_half)                                  # HydroDyn's transform keeps frequencies below N/2
    k = k[(w[k] >= band[0]) & (w[k] <= band[1])]
    q = _diagonal_at(qtf, w[k], beta).real             # HydroDyn reads the diagonal alone here (its 3-D copy)
    plus, minus = np.zeros((n, 6), dtype=complex), np.zeros((n, 6), dtype=complex)
    plus[k] = a[k, None] * np.sqrt(np.fmax(q, 0.0))
    minus[k] = a[k, None] * np.sqrt(np.fmax(-q, 0.0))
    series = np.abs(n * np.fft.ifft(plus, axis=0)) ** 2 - np.abs(n * np.fft.ifft(minus, axis=0)) ** 2
    return np.vstack([series, series[:1]])


def sum_frequency_forces(qtf, waves: IncidentWaves, *, sum_band: tuple[float, float],
                         heading: float | None = None) -> np.ndarray:
    """HydroDyn's sum-frequency force series (``SumQTF``; ``WAMIT2.f90``, ``SumQTF_InitCalc``), ``(N + 1, 6)``
    [N, N m] on ``waves.times()`` (last = first), inertial axes at the WAMIT reference point:
    ``F(t) = Re Σ_k a_k² Q⁺(ω_k, ω_k) e^{2iω_k t} + 2 Re Σ_(k<m) a_k a_m Q⁺(ω_k, ω_m) e^{i(ω_k+ω_m) t}`` over the
    sum frequencies inside ``[WvLowCOffS, WvHiCOffS]`` (``sum_band`` [rad/s]); ``qtf`` a redimensionalized
    sum-frequency QTF (``.NNs``), read as :func:`qtf_at` reads it.

    Raises
    ------
    UnsupportedFeatureError
        A spread sea, a difference-frequency QTF, or a heading outside the file's headings.
    """
    beta, a, w, n_half = _sea(qtf, waves, heading, "sum", "the sum-frequency forces", "SumQTF")
    inside = lambda om: (om >= sum_band[0]) & (om <= sum_band[1])          # noqa: E731
    term1 = np.zeros((n_half + 1, 6), dtype=complex)                        # equal frequencies, at 2 ω_k
    k = np.arange(1, (n_half - 1) // 2 + 1)
    k = k[inside(2.0 * w[k])]
    term1[2 * k] = (a[k] ** 2)[:, None] * qtf_at(qtf, w[k], w[k], beta)
    live = np.nonzero(np.abs(a[:n_half + 1]) > 0)[0]                         # distinct frequencies k < m
    lo, hi = np.meshgrid(live, live, indexing="ij")
    pair = lo < hi
    lo, hi = lo[pair], hi[pair]
    j = lo + hi
    keep = (j <= n_half) & inside(j * waves.frequency_step)
    lo, hi, j = lo[keep], hi[keep], j[keep]
    terms = (a[lo] * a[hi])[:, None] * qtf_at(qtf, w[lo], w[hi], beta)
    term2 = np.zeros((n_half + 1, 6), dtype=complex)
    for m in range(6):
        real, imag = (np.bincount(j, part, n_half + 1) for part in (terms[:, m].real, terms[:, m].imag))
        term2[:, m] = real + 1j * imag
    n = waves.n_steps
    series = 0.5 * n * (np.fft.irfft(term1, n=n, axis=0) + 2.0 * np.fft.irfft(term2, n=n, axis=0))
    return np.vstack([series, series[:1]])


def _sea(qtf, waves: IncidentWaves, heading: float | None, kind: str, what: str, key: str):
    """``(β, a_k, ω_k, N/2)`` for ``what`` (HydroDyn's ``key``) from a ``kind`` QTF; spread seas and the other
    kind of file refused."""
    if qtf.kind != kind:
        raise UnsupportedFeatureError(f"{qtf.source}: a {qtf.kind}-frequency QTF; for {what} a {kind}-frequency "
                                      f"file (.{'NNs' if kind == 'sum' else 'NNd'}) is needed.")
    if waves.directions is not None:
        raise UnsupportedFeatureError(f"{what}: modelled for a unidirectional sea; the sea is spread over headings "
                                      f"(WaveDirMod = 1). Set WaveDirMod = 0 or {key} = 0.")
    n_half = len(waves.spectrum) - 1
    beta = waves.direction if heading is None else heading
    return beta, np.asarray(waves.spectrum, dtype=complex) / n_half, waves.frequencies, n_half


def qtf_at(qtf, omega1: np.ndarray, omega2: np.ndarray, heading: float) -> np.ndarray:
    """``Q(ω1, ω2, β, β)`` ``(len(ω1), 6)`` [N/m², N m/m²]: bilinear in frequency, zero outside the file's
    frequencies; at one heading β [rad], bilinear between the file's headings (module docstring)."""
    plane = _heading_plane(qtf, heading)
    f = qtf.frequencies
    out = np.zeros((len(omega1), 6), dtype=complex)
    w1, w2 = np.asarray(omega1, dtype=float), np.asarray(omega2, dtype=float)
    inside = (w1 >= f[0]) & (w1 <= f[-1]) & (w2 >= f[0]) & (w2 <= f[-1])
    if len(f) == 1:
        out[inside] = plane[0, 0]
        return out
    i, t = _bracket(f, w1[inside])
    m, u = _bracket(f, w2[inside])
    t, u = t[:, None], u[:, None]
    out[inside] = ((1 - t) * (1 - u) * plane[i, m] + t * (1 - u) * plane[i + 1, m]
                   + (1 - t) * u * plane[i, m + 1] + t * u * plane[i + 1, m + 1])
    return out


def _diagonal_at(qtf, omega: np.ndarray, heading: float) -> np.ndarray:
    """``Q(ω, ω, β, β)`` ``(len(ω), 6)`` read linearly along the file's diagonal (equal frequencies), zero outside
    its frequencies: HydroDyn's Newman approximation always works on this 3-D copy of the data."""
    plane = _heading_plane(qtf, heading)
    f = qtf.frequencies
    diag = plane[np.arange(len(f)), np.arange(len(f))]                    # (n, 6)
    w = np.asarray(omega, dtype=float)
    return np.stack([np.interp(w, f, diag[:, m].real, left=0.0, right=0.0)
                     + 1j * np.interp(w, f, diag[:, m].imag, left=0.0, right=0.0) for m in range(6)], axis=1)


def _bracket(grid: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    i = np.clip(np.searchsorted(grid, x, side="right") - 1, 0, len(grid) - 2)
    return i, (x - grid[i]) / (grid[i + 1] - grid[i])


def _heading_plane(qtf, heading: float) -> np.ndarray:
    """``Q[:, :, β, β, :]`` at ``heading`` [rad]: the file's headings [deg] wrapped by whole turns, bilinear."""
    heads = np.asarray(qtf.headings, dtype=float)
    beta = math.degrees(heading)
    beta -= 360.0 * math.floor((beta - heads[0]) / 360.0)
    if len(heads) == 1:
        if not (math.isclose(beta, heads[0], abs_tol=1e-6) or math.isclose(beta - 360.0, heads[0], abs_tol=1e-6)):
            raise UnsupportedFeatureError(f"{qtf.source} holds the heading {heads[0]:g} deg only; the waves come from "
                                          f"{math.degrees(heading):g} deg. Rerun WAMIT with that heading.")
        return qtf.values[:, :, 0, 0, :]
    if beta > heads[-1] + 1e-9:
        raise UnsupportedFeatureError(f"{qtf.source} covers wave headings {heads[0]:g}..{heads[-1]:g} deg; the waves "
                                      f"come from {math.degrees(heading):g} deg. Use a heading inside that range.")
    (i,), (t,) = _bracket(heads, np.array([beta]))
    v = qtf.values
    return ((1 - t) ** 2 * v[:, :, i, i] + t * (1 - t) * (v[:, :, i + 1, i] + v[:, :, i, i + 1])
            + t ** 2 * v[:, :, i + 1, i + 1])
