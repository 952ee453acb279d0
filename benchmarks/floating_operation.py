"""The floating operating turbine (issue 20, item 4): fl_steady_13 in closed loop, speed and mean offsets.

The IEA 15 MW on the VolturnUS-S (``shared/openfast/floating/cases/fl_steady_13``: steady 13 m/s, still
water): the deck's structure (six platform DOFs, tower FA1/SS1, generator), rotor-effective aerodynamics of
its AeroDyn blades with DBEMT, its actuators, HydroDyn (our radiation fit, 169 states) and MoorDyn (three
quasi-static catenaries with their drag and inertia on that shape), our baseline controller with the deck's
DISCON.IN (floating feedback Fl_Mode 2, pitch actuator model PA_Mode 2) compiled into the loop. The deck's
rotor-effective model (``OperatingDeck.model(aero="rotor")``): on the deck as written its tower's drag, its tower's
inflow disturbance as an azimuth average and ``UA_Mod`` 3 at its steady state (docs/aero.md §6b; before 2026-11-29's
second evening the rung refused the last two and this script ran on a copy with them off: docs/offshore.md §7, §7b).

Reports: the trim at 13 m/s, the 600 s run's means over its last 100 s against OpenFAST's (the shared CSV,
and optionally an OpenFAST text output ``--openfast FILE.out``, e.g. a rerun without the tower effects), and
the cost: model build, compilation (CPU of the compiler processes included), integration wall and CPU
time, real-time factor. With ``--reference RUN.csv`` (an OpenFAST run of the same deck in the shared CSV
format, ``<channel>_[<unit>]`` headers: e.g. the rerun with AeroDyn's tower effects and unsteady aerodynamics
off, docs/offshore.md §7) it also gives ε and R² of every channel after ``--settle`` s
(``mbsym.wind.analysis.compare.error_metrics``) and the means over the last 100 s; ``--summary FILE.json``
writes those numbers. ``--mooring-statics`` chooses MoorDyn's lines at rest: the deck's ``NumSegs`` lumped masses
(``lumped``, the default of a MoorDyn deck, docs/offshore.md §3b), the continuous catenaries, or ``both``, built and
timed one after the other in this run (the table of integration times gives the ratio to the first).
``--mooring-lines`` chooses quasi-static lines (the default here) or MoorDyn's lines in motion (``dynamic``, the CLI's
default for the deck: docs/offshore.md §3c), or ``both``.

    python benchmarks/floating_operation.py [--tmax 600] [--fst DECK.fst] [--openfast RUN.out]
        [--reference RUN.csv] [--settle 100] [--summary OUT.json] [--mooring-statics lumped|continuous|both]
        [--mooring-lines quasi-static|dynamic|both]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import resource
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
FLOATING = HERE.parent.parent / "shared" / "openfast" / "floating"
CHANNELS = ("PtfmSurge", "PtfmHeave", "PtfmPitch", "RotSpeed", "BldPitch1", "GenPwr", "FAIRTEN1", "FAIRTEN2",
            "FAIRTEN3", "TTDspFA")


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the C compiler)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _csv_means(path: Path, t_end: float) -> dict[str, float]:
    data = np.genfromtxt(path, delimiter=",", names=True)
    names = {n.rsplit("_", 1)[0]: n for n in data.dtype.names}
    t = data[names["Time"]]
    window = (t >= t_end - 100.0) & (t <= t_end)
    return {c: float(np.mean(data[names[c]][window])) for c in CHANNELS if c in names}


def _out_means(path: Path, t_end: float) -> dict[str, float]:
    lines = path.read_text().splitlines()
    head = next(k for k, line in enumerate(lines) if line.startswith("Time"))
    names = lines[head].split()
    data = np.array([[float(v) for v in line.split()] for line in lines[head + 2:] if line.strip()])
    t_end = min(t_end, data[-1, 0])
    window = data[:, 0] >= t_end - 100.0
    return {c: float(np.mean(data[window, names.index(c)])) for c in CHANNELS if c in names}


def _series_metrics(t: np.ndarray, y: dict[str, np.ndarray], path: Path, settle: float) -> dict[str, dict]:
    """Means over the last 100 s (ours, the reference's) and ε, R² after ``settle`` s against a CSV run."""
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    ref = read_csv(path)
    t_end = min(float(t[-1]), float(ref.time[-1]))
    ours_last = (t >= t_end - 100.0) & (t <= t_end + 1e-9)
    ref_last = (ref.time >= t_end - 100.0) & (ref.time <= t_end + 1e-9)
    after = (t >= settle - 1e-9) & (t <= t_end + 1e-9)
    rows = {}
    for c in CHANNELS:
        if c not in ref.names:
            continue
        y_ref = ref.channel(c)
        eps, r2 = error_metrics(t[after], y[c][after], ref.time[ref.time >= settle - 1e-9],
                                y_ref[ref.time >= settle - 1e-9])
        mean, mean_ref = float(np.mean(y[c][ours_last])), float(np.mean(y_ref[ref_last]))
        rows[c] = {"mean": mean, "mean_ref": mean_ref, "mean_diff_pct": 100.0 * (mean / mean_ref - 1.0),
                   "eps_pct": 100.0 * eps, "r2": r2,
                   "range_ref_after_settle": float(np.ptp(y_ref[ref.time >= settle - 1e-9])),
                   "range_after_settle": float(np.ptp(y[c][after]))}
    return rows


def _build_and_run(args, statics: str, lines: str = "quasi-static") -> dict:
    """Build the deck's rotor-effective floating model with MoorDyn's lines at rest as ``statics`` and moving as
    ``lines``, trim it at 13 m/s and run it (first run and ``--repeat`` timed runs); the best integration wall time
    [s]."""
    from mbsym.wind.control import BaselineController
    from mbsym.wind.operation import SteadyControl, trim
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.deck import operating_deck
    from mbsym.wind.operation.simulation import simulate_turbine

    t0, c0 = time.perf_counter(), _cpu()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = dataclasses.replace(operating_deck(args.fst), radiation="fit", mooring_statics=statics,
                                   mooring_lines=lines)
        model = deck.model(aero="rotor")
        dyn = model.dynamics()
    build = time.perf_counter() - t0, _cpu() - c0
    print(f"[{statics}, {lines}] model: {len(dyn.states)} states ({model.platform.n_radiation} radiation), build "
          f"{build[0]:.1f} s wall, {build[1]:.1f} s CPU")

    t0 = time.perf_counter()
    point = trim(model, 13.0, SteadyControl.from_baseline(deck.baseline_settings()))
    print(f"trim: {time.perf_counter() - t0:.2f} s, {point.message}")

    controller = baseline_in_loop(BaselineController(deck.baseline_settings()))
    t0, c0 = time.perf_counter(), _cpu()
    result = simulate_turbine(model, deck.wind(), args.tmax, controller=controller, x0=model.initial_state(13.0),
                              t_out=np.arange(0.0, args.tmax + 1e-9, 0.05), compile=True)
    wall, cpu = time.perf_counter() - t0, _cpu() - c0
    stats = result.statistics
    integ = best = float(stats["integration_wall_s"])
    print(f"first run {args.tmax:g} s: integration {integ:.2f} s ({args.tmax / integ:.0f}x real time); whole call "
          f"{wall:.1f} s wall, {cpu:.1f} s CPU incl. compiler (outputs {float(stats['outputs_wall_s']):.1f} s)")
    for _ in range(args.repeat):     # compiled loop in memory: integration and outputs only
        t0, c0 = time.perf_counter(), time.process_time()
        again = simulate_turbine(model, deck.wind(), args.tmax, controller=controller, x0=model.initial_state(13.0),
                                 t_out=np.arange(0.0, args.tmax + 1e-9, 0.05), compile=True)
        integ = float(again.statistics["integration_wall_s"])
        best = min(best, integ)
        print(f"repeat: integration {integ:.2f} s wall ({args.tmax / integ:.0f}x real time); whole call "
              f"{time.perf_counter() - t0:.2f} s wall, {time.process_time() - c0:.2f} s CPU")

    return {"point": point, "result": result, "integration_s": best}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tmax", type=float, default=600.0)
    ap.add_argument("--fst", default=str(FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"))
    ap.add_argument("--repeat", type=int, default=2, help="timed runs after the first (compiled loop reused)")
    ap.add_argument("--openfast", help="an OpenFAST text output (.out) of the same case to compare with")
    ap.add_argument("--reference", help="an OpenFAST run of the same deck as CSV (<channel>_[<unit>] headers): "
                                        "ε, R² after --settle s and the last 100 s means")
    ap.add_argument("--settle", type=float, default=100.0, help="start of the ε, R² window [s]")
    ap.add_argument("--summary", help="write the trim, means and --reference metrics to this JSON file")
    ap.add_argument("--mooring-statics", choices=("lumped", "continuous", "both"), default="lumped",
                    help="MoorDyn's lines at rest: the deck's NumSegs lumped masses (the default), the continuous "
                         "catenaries, or both timed in one run (the first for the tables; ratio to continuous)")
    ap.add_argument("--mooring-lines", choices=("quasi-static", "dynamic", "both"), default="quasi-static",
                    help="MoorDyn's lines quasi-static (default here), in motion (MoorDyn's lumped masses, the CLI's "
                         "default for the deck), or both timed in one run (ratio to quasi-static)")
    args = ap.parse_args()
    if args.reference and not Path(args.reference).is_file():
        ap.error(f"--reference {args.reference}: no such file (expected an OpenFAST run as CSV)")

    timings = {}
    both_lines = ("quasi-static", "dynamic") if args.mooring_lines == "both" else (args.mooring_lines,)
    for statics in (("lumped", "continuous") if args.mooring_statics == "both" else (args.mooring_statics,)):
        for lines in both_lines:
            run = _build_and_run(args, statics, lines)
            timings[statics, lines] = run["integration_s"]
            if len(timings) == 1:
                point, result = run["point"], run["result"]
    if len(timings) > 1:
        base = next(iter(timings.values()))
        print("\n| mooring statics | mooring lines | integration [s] (best) | real-time factor | ratio to the first |")
        print("|---|---|---|---|---|")
        for (statics, lines), integ in timings.items():
            print(f"| {statics} | {lines} | {integ:.2f} | {args.tmax / integ:.0f}x | {integ / base:.2f} |")

    t = np.asarray(result.t)
    y = dict(zip(result.output_names, np.asarray(result.y).T))
    window = t >= t[-1] - 100.0
    refs = {"OpenFAST (shared CSV)": _csv_means(FLOATING / "fl_steady_13.csv", args.tmax)}
    if args.openfast:
        refs[f"OpenFAST ({Path(args.openfast).name})"] = _out_means(Path(args.openfast), args.tmax)
    head = "| channel | trim | run (last 100 s) | " + " | ".join(refs) + " |"
    print("\n" + head + "\n|" + "---|" * (head.count("|") - 1))
    for c in CHANNELS:
        mean = float(np.mean(y[c][window]))
        cells = [f"{r[c]:.5g} ({100 * (mean / r[c] - 1):+.2f} %)" for r in refs.values()]
        print(f"| {c} | {point[c]:.5g} | {mean:.5g} | " + " | ".join(cells) + " |")
    summary = {"fst": str(args.fst), "tmax": args.tmax, "trim": {c: float(point[c]) for c in CHANNELS},
               "mean_last_100s": {c: float(np.mean(y[c][window])) for c in CHANNELS}}
    if args.reference:
        rows = _series_metrics(t, y, Path(args.reference), args.settle)
        print(f"\nagainst {Path(args.reference).name}: means over the last 100 s, ε and R² after {args.settle:g} s")
        print("| channel | reference | mbsym | difference | ε | R² |\n|---|---|---|---|---|---|")
        for c, r in rows.items():
            print(f"| {c} | {r['mean_ref']:.5g} | {r['mean']:.5g} | {r['mean_diff_pct']:+.2f} % | "
                  f"{r['eps_pct']:.2f} % | {r['r2']:.3f} |")
        summary["reference"] = {"csv": str(args.reference), "settle_s": args.settle, "channels": rows}
    if args.summary:
        Path(args.summary).write_text(json.dumps(summary, indent=1) + "\n")


if __name__ == "__main__":
    main()
