"""What the ``mbsym simulate`` runs share: the time grid, the output files, the comparison report, JSON.

Used by :mod:`.simulate` (the structure) and :mod:`.operate` (the operating turbine), which import it and
not each other's internals.
"""

from __future__ import annotations

import numpy as np

__all__ = ["time_grid", "check_files", "write_outputs", "report_comparison", "jsonable", "number",
           "compare_label"]


def number(value: float, spec: str) -> str:
    """``format(value, spec)`` without a minus sign on a zero: ``-0.0`` (or ``-1e-9`` at ``.4f``) reads as ``0``."""
    text = format(value, spec)
    try:
        zero = float(text) == 0.0
    except ValueError:              # nan, inf
        return text
    return format(abs(value), spec) if zero else text


def time_grid(args, sim) -> tuple[float, np.ndarray, float]:
    """``(tmax, output times, step of an explicit fixed-step method)``; names the flag or deck key at fault."""
    from ..exceptions import SimulationOptionError

    def positive(value, flag_given: bool, flag: str, key: str) -> float:
        where = flag if flag_given else f"the deck's {key}"
        fix = f"pass a positive {flag}" if flag_given else f"set {key} in the deck or pass {flag}"
        if value is None or not (np.isfinite(value) and value > 0):
            shown = "none" if value is None else f"{value:g}"
            raise SimulationOptionError(f"{where} = {shown} s must be a positive finite time; {fix}.")
        return float(value)

    tmax = positive(args.tmax if args.tmax is not None else sim.total_time, args.tmax is not None, "--tmax", "TMax")
    dt_out = positive(args.dt if args.dt is not None else sim.output_time_step, args.dt is not None, "--dt",
                      "DT_Out")
    step = positive(args.dt if args.dt is not None else sim.time_step, args.dt is not None, "--dt", "DT")
    if dt_out > tmax:
        a = "--dt" if args.dt is not None else "the deck's DT_Out"
        b = "--tmax" if args.tmax is not None else "the deck's TMax"
        raise SimulationOptionError(f"{a} = {dt_out:g} s exceeds {b} = {tmax:g} s: there would be no output after "
                                    f"t = 0; use an output spacing below the simulated time.")
    from ..simulate.monitor import check_resources, output_count

    check_resources(output_count(tmax, dt_out), 8, None, tmax)        # before allocating the grid
    n = int(np.floor(tmax / dt_out + 1e-9))
    t_out = np.round(np.arange(n + 1) * dt_out, 12)
    if t_out[-1] < tmax * (1 - 1e-12):
        t_out = np.append(t_out, tmax)
    return tmax, t_out, step


def check_files(args):
    """Read --compare and check the --out/--plot destinations before simulating (:mod:`._files`)."""
    from ._files import Outputs

    outputs = Outputs([("--compare", args.compare), ("deck", args.deck)])
    if args.out is not None:
        outputs.add("--out", args.out)
    if args.plot is not None:
        outputs.add("--plot", args.plot, image=True)
    ref = None
    if args.compare:
        from ..wind.analysis.compare import read_csv

        ref = read_csv(args.compare)
    return ref, outputs


def write_outputs(outputs, series, ref, label: str, channels=None, *, series_label: str = "mbsym",
                  ref_label: str | None = None) -> None:
    """Write --out and --plot to temporaries, then move both into place (all or nothing).

    ``label`` is the plot's title, ``series_label`` names our run in its legend, ``ref_label`` the
    --compare series (default: "reference").
    """
    from ..wind.analysis.compare import overlay_plot, write_csv

    with outputs:
        if "--out" in outputs._final:
            write_csv(outputs.temporary("--out"), series)
        if "--plot" in outputs._final:
            overlay_plot(outputs.temporary("--plot"), series, ref, title=label, label=series_label,
                         ref_label=ref_label or "reference",
                         **({} if channels is None else {"channels": list(channels)}))
        written = outputs.commit()
    for path in written:
        extra = f" ({len(series.time)} rows, {len(series.names)} channels)" if path.suffix.lower() == ".csv" else ""
        print(f"wrote {path}{extra}")


def compare_label(path) -> str:
    """The --compare series' name in plots: its file name without the suffix (``ff14_flex.csv`` -> ``ff14_flex``);
    a CSV need not be OpenFAST's."""
    from pathlib import Path

    return Path(path).stem


def report_comparison(series, ref) -> None:
    """The ε/R² table, then what was not compared: channels, time ranges, non-finite samples."""
    from ..wind.analysis.compare import compare, constant_in_both, coverage_notes, not_compared

    rows = compare(series, ref)
    same = [r["channel"] for r in rows if constant_in_both(series, ref, r["channel"])]
    _print_comparison([r for r in rows if r["channel"] not in same])
    if same:
        print(f"{len(same)} channel{'s' if len(same) != 1 else ''} constant and equal in both (not in the table): "
              f"{', '.join(same)}")
    missing = not_compared(series, ref)
    if missing:
        print(f"not compared (not produced by this model): {', '.join(missing)}")
    for note in coverage_notes(series, ref):
        print(f"note: {note}")
    excluded = [f"{r['channel']} ({r['n_excluded']})" for r in rows if r["n_excluded"]]
    if excluded:
        print(f"note: samples left out where a value is not finite (NaN/inf): {', '.join(excluded)}")


def _print_comparison(rows) -> None:
    print(f"\n{'channel':<14} {'ε [%]':>9} {'R²':>10} {'max |Δ|':>12}")
    for r in rows:
        eps = "const" if np.isnan(r["epsilon"]) else f"{100 * r['epsilon']:.4f}"
        r2 = "-" if np.isnan(r["r2"]) else number(r["r2"], ".6f")
        print(f"{r['channel']:<14} {eps:>9} {r2:>10} {number(r['max_abs_diff'], '12.4g')}")


def jsonable(v):
    if isinstance(v, (np.floating, np.integer)):
        v = v.item()
    if isinstance(v, float) and not np.isfinite(v):
        return None                     # strict JSON has no NaN/inf (e.g. no linear prediction on the BDF path)
    if isinstance(v, (str, int, float, bool)) or v is None:
        return v
    return str(v)
