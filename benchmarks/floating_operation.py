"""The floating operating turbine (issue 20, item 4): fl_steady_13 in closed loop, speed and mean offsets.

The IEA 15 MW on the VolturnUS-S (``shared/openfast/floating/cases/fl_steady_13``: steady 13 m/s, still
water): the deck's structure (six platform DOFs, tower FA1/SS1, generator), rotor-effective aerodynamics of
its AeroDyn blades with DBEMT, its actuators, HydroDyn (our radiation fit, 169 states) and MoorDyn (three
quasi-static catenaries), our baseline controller with the deck's DISCON.IN (floating feedback Fl_Mode 2,
pitch actuator model PA_Mode 2) compiled into the loop. Built with the public constructor, since the deck's
AeroDyn switches on tower effects the rotor-effective model does not have (docs/offshore.md §7).

Reports: the trim at 13 m/s, the 600 s run's means over its last 100 s against OpenFAST's (the shared CSV,
and optionally an OpenFAST text output ``--openfast FILE.out``, e.g. a rerun without the tower effects), and
the cost: model build, compilation (CPU of the compiler processes included), integration wall and CPU
time, real-time factor.

    python benchmarks/floating_operation.py [--tmax 600] [--openfast RUN.out]
"""

from __future__ import annotations

import argparse
import dataclasses
import resource
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
FLOATING = HERE.parent.parent / "shared" / "openfast" / "floating"
CHANNELS = ("PtfmSurge", "PtfmHeave", "PtfmPitch", "RotSpeed", "BldPitch1", "GenPwr", "FAIRTEN1", "TTDspFA")


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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tmax", type=float, default=600.0)
    ap.add_argument("--fst", default=str(FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"))
    ap.add_argument("--repeat", type=int, default=2, help="timed runs after the first (compiled loop reused)")
    ap.add_argument("--openfast", help="an OpenFAST text output (.out) of the same case to compare with")
    args = ap.parse_args()

    from mbsym.wind.control import BaselineController
    from mbsym.wind.operation import OperatingTurbine, SteadyControl, trim
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.deck import operating_deck
    from mbsym.wind.operation.dynamic_inflow import DynamicInflow
    from mbsym.wind.operation.simulation import simulate_turbine

    t0, c0 = time.perf_counter(), _cpu()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = dataclasses.replace(operating_deck(args.fst), radiation="fit")
        mode, tau1 = deck.dbemt
        model = OperatingTurbine(deck.turbine, deck.rotor, actuators=deck.actuators, platform=deck.platform,
                                 dynamic_inflow=DynamicInflow(deck.rotor, mode=mode, tau1_const=tau1))
        dyn = model.dynamics()
    build = time.perf_counter() - t0, _cpu() - c0
    print(f"model: {len(dyn.states)} states ({model.platform.n_radiation} radiation), build {build[0]:.1f} s wall, "
          f"{build[1]:.1f} s CPU")

    t0 = time.perf_counter()
    point = trim(model, 13.0, SteadyControl.from_baseline(deck.baseline_settings()))
    print(f"trim: {time.perf_counter() - t0:.2f} s, {point.message}")

    controller = baseline_in_loop(BaselineController(deck.baseline_settings()))
    t0, c0 = time.perf_counter(), _cpu()
    result = simulate_turbine(model, deck.wind(), args.tmax, controller=controller, x0=model.initial_state(13.0),
                              t_out=np.arange(0.0, args.tmax + 1e-9, 0.05), compile=True)
    wall, cpu = time.perf_counter() - t0, _cpu() - c0
    stats = result.statistics
    integ = float(stats["integration_wall_s"])
    print(f"first run {args.tmax:g} s: integration {integ:.2f} s ({args.tmax / integ:.0f}x real time); whole call "
          f"{wall:.1f} s wall, {cpu:.1f} s CPU incl. compiler (outputs {float(stats['outputs_wall_s']):.1f} s)")
    for _ in range(args.repeat):     # compiled loop in memory: integration and outputs only
        t0, c0 = time.perf_counter(), time.process_time()
        again = simulate_turbine(model, deck.wind(), args.tmax, controller=controller, x0=model.initial_state(13.0),
                                 t_out=np.arange(0.0, args.tmax + 1e-9, 0.05), compile=True)
        integ = float(again.statistics["integration_wall_s"])
        print(f"repeat: integration {integ:.2f} s wall ({args.tmax / integ:.0f}x real time); whole call "
              f"{time.perf_counter() - t0:.2f} s wall, {time.process_time() - c0:.2f} s CPU")

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


if __name__ == "__main__":
    main()
