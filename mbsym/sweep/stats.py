"""Per-case summaries: channel statistics, damage-equivalent loads, modal summaries of linear models.

Every function here is plain numpy on contiguous arrays, so the same case gives the
same numbers in any process (the sweep's executors rely on it).
"""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from ..exceptions import SweepError

__all__ = ["STATISTICS", "channel_statistics", "damage_equivalent_load", "modal_summary", "del_column"]

#: Statistics of every channel, in column order (``<channel>_<statistic>``); std is the population one (ddof = 0).
STATISTICS: tuple[str, ...] = ("mean", "std", "max", "min")


def del_column(channel: str, m: float) -> str:
    """Column name of the damage-equivalent load of ``channel`` for the Wöhler exponent ``m``."""
    return f"{channel}_del_m{m:g}"


def damage_equivalent_load(signal: np.ndarray, duration: float, m: float, *, frequency: float = 1.0) -> float:
    """Damage-equivalent load of a time series by rainflow counting (full-cycle ranges, half cycles as 0.5).

    ``DEL = (sum_i n_i S_i^m / N_eq)^(1/m)`` with ``N_eq = frequency * duration`` equivalent cycles.
    A pure sine of amplitude A and frequency f over a whole number of periods T gives
    ``2 A (f T / N_eq)^(1/m)``.

    Parameters
    ----------
    signal : array
        Samples (uniform or not: only the sequence of reversals matters).
    duration : float
        Length of the record [s].
    m : float
        Wöhler (S-N curve) exponent [-], e.g. 4 for steel towers, 10 for composite blades.
    frequency : float, optional, keyword-only
        Frequency of the equivalent cycles [Hz] (default 1 Hz).

    Returns
    -------
    float
        In the units of the signal.

    Raises
    ------
    SweepError
        Without the ``rainflow`` package (``pip install 'mbsym[loads]'``).
    """
    try:
        import rainflow
    except ImportError:  # pragma: no cover - depends on the environment
        raise SweepError("damage-equivalent loads need the 'rainflow' package: pip install 'mbsym[loads]' "
                         "(or pip install rainflow).") from None
    x = np.ascontiguousarray(signal, dtype=float)
    if x.size < 2 or not np.all(np.isfinite(x)):
        return float("nan")
    total = 0.0
    for rng, count in rainflow.count_cycles(x):
        total += float(count) * float(rng) ** m
    return float((total / (frequency * duration)) ** (1.0 / m))


def channel_statistics(t: np.ndarray, columns: Mapping[str, np.ndarray], *, channels: Sequence[str],
                       del_channels: Sequence[str] = (), wohler: Sequence[float] = (10.0,),
                       del_frequency: float = 1.0, t_start: float = 0.0) -> dict[str, float]:
    """``<channel>_mean/_std/_max/_min`` of every channel and ``<channel>_del_m<m>`` of the DEL channels.

    Samples before ``t_start`` [s] are left out (an initial transient).
    """
    keep = np.asarray(t) >= t_start
    tt = np.asarray(t)[keep]
    duration = float(tt[-1] - tt[0]) if tt.size > 1 else 0.0
    out: dict[str, float] = {}
    for name in channels:
        x = np.ascontiguousarray(np.asarray(columns[name])[keep], dtype=float)
        if x.size == 0:
            out.update({f"{name}_{s}": float("nan") for s in STATISTICS})
            continue
        out[f"{name}_mean"] = float(np.mean(x))
        out[f"{name}_std"] = float(np.std(x))
        out[f"{name}_max"] = float(np.max(x))
        out[f"{name}_min"] = float(np.min(x))
    for name in del_channels:
        x = np.asarray(columns[name])[keep]
        for m in wohler:
            value = damage_equivalent_load(x, duration, m, frequency=del_frequency) if duration > 0 else float("nan")
            out[del_column(name, m)] = value
    return out


def modal_summary(A: np.ndarray, n_modes: int) -> tuple[dict[str, float], np.ndarray]:
    """Natural frequencies [Hz] and damping ratios [-] of ``xd = A x``, sorted by frequency.

    Oscillatory modes count once (the eigenvalue with positive imaginary part); real
    eigenvalues are modes of zero damped frequency (damping ratio 1 when stable, -1 when
    unstable, NaN for zero). Columns ``mode<k>_freq_hz`` and ``mode<k>_damping`` for
    ``k = 1 .. n_modes`` (NaN where the model has fewer modes). Returns the columns and
    the eigenvalues.
    """
    lam = np.linalg.eigvals(np.ascontiguousarray(A, dtype=float))
    modes = lam[lam.imag >= 0.0]
    wn = np.abs(modes)
    with np.errstate(invalid="ignore", divide="ignore"):
        zeta = np.where(wn > 0.0, -modes.real / wn, np.nan) + 0.0      # + 0.0: no negative zeros
    order = np.lexsort((zeta, wn))
    out: dict[str, float] = {}
    for k in range(n_modes):
        j = order[k] if k < order.size else None
        out[f"mode{k + 1}_freq_hz"] = float(wn[j] / (2 * np.pi)) if j is not None else float("nan")
        out[f"mode{k + 1}_damping"] = float(zeta[j]) if j is not None else float("nan")
    return out, lam
