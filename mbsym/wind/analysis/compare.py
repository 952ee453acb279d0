"""Comparing time series with OpenFAST output: CSV files, error metrics, overlay plots.

The error metrics are those of the paper (Sect. 4.5) and of our validation:

- ``ε = mean|y − y_ref| / (max y_ref − min y_ref)``,
- ``R² = 1 − Σ (y − y_ref)² / Σ (y_ref − mean y_ref)²``,

evaluated on the reference's time grid (ours interpolated linearly) where the two
overlap. Angles that OpenFAST wraps (``Azimuth`` in deg, ``Q_GeAz`` in rad) are
compared through the wrapped difference, so a sample on either side of a wrap does
not count as a full-turn error.

Nothing is dropped silently: a reference whose times are not finite and strictly
increasing is refused (:func:`read_csv`), samples where either series is not finite
are left out and counted (``n_excluded`` of each :func:`compare` row), and
:func:`coverage_notes` says when the two time ranges differ (only the overlap is
compared).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import DimensionError, OpenFASTFormatError

__all__ = ["TimeSeries", "read_csv", "write_csv", "error_metrics", "compare", "not_compared", "coverage_notes",
           "overlay_plot", "overlay_figure", "WRAPPED", "time_decimals", "constant_in_both"]

#: Channels OpenFAST wraps, with their period in their own unit.
WRAPPED = {"Azimuth": 360.0, "Q_GeAz": 2 * np.pi}


@dataclass(frozen=True)
class TimeSeries:
    """Channels on a time grid: ``time`` (N,) [s], ``data`` (N, n) with ``names`` and ``units``."""

    time: np.ndarray
    names: tuple[str, ...]
    units: tuple[str, ...]
    data: np.ndarray

    def channel(self, name: str) -> np.ndarray:
        if name not in self.names:
            raise DimensionError(f"no channel {name!r}; channels are {list(self.names)}.")
        return self.data[:, self.names.index(name)]


def read_csv(path: str | Path) -> TimeSeries:
    """Read an OpenFAST-style CSV (``Time_[s]`` then ``<channel>_[<unit>]`` columns)."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"OpenFAST CSV not found: {path}")
    with path.open(newline="") as fh:
        header = next(csv.reader(fh), None)
    if not header or not header[0].startswith("Time"):
        raise OpenFASTFormatError(f"{path}, line 1: expected a header starting with 'Time_[s]'; got {header!r}.")
    try:
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as exc:
        raise OpenFASTFormatError(f"{path}: not a numeric CSV table after the header ({exc}).") from exc
    if data.shape[1] != len(header):
        raise OpenFASTFormatError(f"{path}: {len(header)} header columns but {data.shape[1]} data columns.")
    _check_time(path, data[:, 0])
    names, units = zip(*(_split_header(h) for h in header[1:])) if len(header) > 1 else ((), ())
    return TimeSeries(data[:, 0], tuple(names), tuple(units), data[:, 1:])


def _check_time(path: Path, t: np.ndarray) -> None:
    """Refuse a time column that is not finite and strictly increasing (naming the first bad line)."""
    if t.size == 0:
        raise OpenFASTFormatError(f"{path}: no data rows after the header.")
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise OpenFASTFormatError(f"{path}, line {bad[0] + 2}: time is {t[bad[0]]}; every row needs a finite time. "
                                  "Remove or fix that row.")
    back = np.flatnonzero(np.diff(t) <= 0)
    if back.size:
        i = back[0] + 1
        raise OpenFASTFormatError(f"{path}, line {i + 2}: time {t[i]:g} s does not increase (previous row "
                                  f"{t[i - 1]:g} s); the rows must be in strictly increasing time without "
                                  "duplicates. Sort the file (or remove the repeated rows).")


def _split_header(h: str) -> tuple[str, str]:
    if h.endswith("]") and "_[" in h:
        name, unit = h[:-1].rsplit("_[", 1)
        return name, unit
    return h, "-"


def time_decimals(t) -> int:
    """Decimals that keep every time of ``t`` [s] distinct and exact to 1e-3 of the smallest step
    (at least 4, OpenFAST's layout; at most 15)."""
    t = np.asarray(t, dtype=float)
    steps = np.diff(t)
    steps = steps[steps > 0]
    if steps.size == 0:
        return 4
    return int(min(15, max(4, np.ceil(-np.log10(steps.min())) + 3)))


def write_csv(path: str | Path, series: TimeSeries) -> None:
    """Write ``Time_[s]`` and ``<channel>_[<unit>]`` columns as OpenFAST's CSV layout.

    Times get enough decimals for the smallest step (:func:`time_decimals`), values 12
    significant digits.
    """
    header = ["Time_[s]"] + [f"{n}_[{u}]" for n, u in zip(series.names, series.units)]
    digits = time_decimals(series.time)
    with Path(path).open("w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        for t, row in zip(series.time, series.data):
            w.writerow([f"{t:.{digits}f}"] + [f"{v:.12g}" for v in row])


def error_metrics(t: np.ndarray, y: np.ndarray, t_ref: np.ndarray, y_ref: np.ndarray, *,
                  period: float | None = None) -> tuple[float, float]:
    """(ε, R²) of ``y(t)`` against ``y_ref(t_ref)`` on the overlapping reference grid.

    ``period`` compares a wrapped angle through its wrapped difference. For a
    constant reference (zero range) ε and R² are NaN.

    Raises
    ------
    DimensionError
        If the two time ranges do not overlap.
    """
    return _metrics(t, y, t_ref, y_ref, period)[:2]


def _metrics(t, y, t_ref, y_ref, period) -> tuple[float, float, float]:
    """(ε, R², max |Δ|), all on the same overlapping grid and wrapped difference."""
    return _metrics_counted(t, y, t_ref, y_ref, period)[:3]


def _metrics_counted(t, y, t_ref, y_ref, period) -> tuple[float, float, float, int, int]:
    """(ε, R², max |Δ|, compared samples, samples left out as not finite)."""
    t, y, t_ref, y_ref = (np.asarray(a, dtype=float) for a in (t, y, t_ref, y_ref))
    keep = (t_ref >= t[0] - 1e-9) & (t_ref <= t[-1] + 1e-9)
    if not np.any(keep):
        raise DimensionError(f"no overlap between the simulated time [{t[0]:g}, {t[-1]:g}] s and the "
                             f"reference [{t_ref[0]:g}, {t_ref[-1]:g}] s.")
    t_ref, y_ref = t_ref[keep], y_ref[keep]
    ours_ok = np.isfinite(y)
    finite = np.isfinite(y_ref)
    if not ours_ok.all():       # our non-finite samples poison their neighbourhood in the interpolation
        finite &= np.interp(t_ref, t, (~ours_ok).astype(float)) == 0.0
        t, y = t[ours_ok], y[ours_ok]
    n_excluded = int(np.count_nonzero(~finite))
    t_ref, y_ref = t_ref[finite], y_ref[finite]
    if t_ref.size == 0 or t.size == 0:
        nan = float("nan")
        return nan, nan, nan, 0, n_excluded
    if period is not None:
        yi = np.interp(t_ref, t, np.unwrap(y, period=period))
        diff = (yi - y_ref + period / 2) % period - period / 2
    else:
        diff = np.interp(t_ref, t, y) - y_ref
    max_diff = float(np.max(np.abs(diff)))
    rng = float(np.ptp(y_ref))
    if rng <= 1e-12 * max(1.0, float(np.max(np.abs(y_ref)))):
        return float("nan"), float("nan"), max_diff, int(t_ref.size), n_excluded
    eps = float(np.mean(np.abs(diff)) / rng)
    r2 = float(1.0 - np.sum(diff**2) / np.sum((y_ref - y_ref.mean()) ** 2))
    return eps, r2, max_diff, int(t_ref.size), n_excluded


def compare(ours: TimeSeries, ref: TimeSeries) -> list[dict]:
    """Metrics for every channel present in both series (reference order).

    Each row: ``channel``, ``unit``, ``epsilon``, ``r2``, ``max_abs_diff``, ``n_compared``
    (reference samples in the common time range) and ``n_excluded`` (samples left out because
    either series is not finite there). :func:`coverage_notes` describes the time ranges.

    Raises
    ------
    DimensionError
        If no channel is common to both, or the time ranges do not overlap.
    """
    common = [n for n in ref.names if n in ours.names]
    if not common:
        raise DimensionError(f"no channel in common between the simulation ({list(ours.names)[:6]}...) and the "
                             f"reference ({list(ref.names)[:6]}...); compare with OpenFAST output of the same DOFs.")
    rows = []
    for name in common:
        eps, r2, max_diff, n, excluded = _metrics_counted(ours.time, ours.channel(name), ref.time, ref.channel(name),
                                                          WRAPPED.get(name))
        rows.append({"channel": name, "unit": ref.units[ref.names.index(name)], "epsilon": eps, "r2": r2,
                     "max_abs_diff": max_diff, "n_compared": n, "n_excluded": excluded})
    return rows


def coverage_notes(ours: TimeSeries, ref: TimeSeries) -> list[str]:
    """Sentences saying which part of each series the comparison leaves out (empty if none)."""
    a, b = max(ours.time[0], ref.time[0]), min(ours.time[-1], ref.time[-1])
    tol = 1e-9 * max(1.0, abs(b))
    notes = []
    if ours.time[-1] > b + tol:
        notes.append(f"the simulation runs to {ours.time[-1]:g} s but the reference ends at {ref.time[-1]:g} s: "
                     f"compared on [{a:g}, {b:g}] s only")
    elif ref.time[-1] > b + tol:
        notes.append(f"the reference runs to {ref.time[-1]:g} s but the simulation ends at {ours.time[-1]:g} s: "
                     f"compared on [{a:g}, {b:g}] s only")
    if ours.time[0] < a - tol or ref.time[0] < a - tol:
        notes.append(f"the comparison starts at {a:g} s (simulation from {ours.time[0]:g} s, reference from "
                     f"{ref.time[0]:g} s)")
    return notes


def not_compared(ours: TimeSeries, ref: TimeSeries) -> list[str]:
    """Reference channels the simulation does not produce (listed, never silently dropped)."""
    return [n for n in ref.names if n not in ours.names]


def constant_in_both(ours: TimeSeries, ref: TimeSeries, name: str) -> bool:
    """Whether channel ``name`` holds one and the same value in both series (finite samples; equal to 1e-12
    relative, the tolerance of a "constant" reference in :func:`compare`), e.g. a load of a DOF neither model
    has. Such channels say nothing about the agreement: tables summarize them in one line."""
    if name not in ours.names or name not in ref.names:
        return False
    a, b = ours.channel(name), ref.channel(name)
    values = np.concatenate([a[np.isfinite(a)], b[np.isfinite(b)]])
    if values.size == 0 or not np.isfinite(a).any() or not np.isfinite(b).any():
        return False
    return bool(np.ptp(values) <= 1e-12 * max(1.0, float(np.max(np.abs(values)))))


def _constant(ours: TimeSeries, ref: TimeSeries | None, name: str) -> bool:
    """Whether a channel stays constant in both series (a flat, empty-looking panel)."""
    series = [ours.channel(name)] + ([ref.channel(name)] if ref is not None and name in ref.names else [])
    for y in series:
        y = y[np.isfinite(y)]
        if y.size and np.ptp(y) > 1e-12 * max(1.0, float(np.max(np.abs(y)))):
            return False
    return True


def overlay_plot(path: str | Path, ours: TimeSeries, ref: TimeSeries | None = None, *,
                 channels: list[str] | None = None, title: str = "", label: str = "mbsym",
                 ref_label: str = "OpenFAST") -> None:
    """PNG of the chosen channels, ours alone or against a reference (:func:`overlay_figure`)."""
    import matplotlib.pyplot as plt

    fig = overlay_figure(ours, ref, channels=channels, title=title, label=label, ref_label=ref_label)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def overlay_figure(ours: TimeSeries, ref: TimeSeries | None = None, *, channels: list[str] | None = None,
                   title: str = "", label: str = "mbsym", ref_label: str = "OpenFAST"):
    """The matplotlib Figure of :func:`overlay_plot` (the caller closes it).

    Default channels: the DOF channels ``Q_*``, RotSpeed and PtfmPitch that move (constant
    ones, e.g. a held DOF, are left out). ``title`` is printed as given (the CLI names the deck's
    file, the wind and the controller). ``label`` names our series in the legend, ``ref_label`` the
    reference (the CLI passes the compared file's name: a CSV need not be OpenFAST's). Alone, our
    series is a solid line; over a reference (solid black) it is dashed, so both stay visible.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if channels is None:
        channels = [n for n in ours.names if n.startswith("Q_") or n in ("RotSpeed", "PtfmPitch")]
        channels = [c for c in channels if ref is None or c in ref.names] or list(ours.names[:4])
        moving = [c for c in channels if not _constant(ours, ref, c)]
        channels = moving or channels[:1]       # constant channels make empty panels: leave them out
    fig, axes = plt.subplots(len(channels), 1, figsize=(8, 1.9 * len(channels) + 0.6), sharex=True, squeeze=False)
    style = "C1--" if ref is not None else "C0-"
    for ax, name in zip(axes[:, 0], channels):
        if ref is not None and name in ref.names:
            ax.plot(ref.time, ref.channel(name), "k-", lw=1.6, label=ref_label)
        ax.plot(ours.time, ours.channel(name), style, lw=1.2, label=label)
        ax.set_ylabel(f"{name}\n[{ours.units[ours.names.index(name)]}]", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel("Time [s]")
    if title:
        axes[0, 0].set_title(title, fontsize=9)
    fig.tight_layout()
    return fig
