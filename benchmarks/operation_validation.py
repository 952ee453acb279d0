"""The operating NREL 5 MW against OpenFAST v5 + AeroDyn + ROSCO 2.10.6 (shared/openfast/aero).

(a) Simulation to steady state at the 17 wind speeds of ``steady_states.csv``: the deck's initial
    conditions of each case, 150 s as OpenFAST, means over 120-150 s; with the real ROSCO library
    in the loop and with our baseline controller. Criteria (issue 12): RotSpeed within 0.5 %,
    BldPitch1 within 0.3 deg above rated, GenPwr within 1 %, RtAeroFxh within 2 %, TTDspFA within
    3 % (DISCON); 0.5 %, 0.5 deg, 2 % (baseline).
(b) The wind step 10 -> 14 m/s (``wind/step_10_14.hh``, initial conditions of the steady 10 m/s state):
    ε = mean|y - y_OF| / range(y_OF) and R² on RotSpeed, BldPitch1, GenPwr, TTDspFA; criteria ε <= 2 %
    and R² >= 0.95 (DISCON), ε <= 5 % (baseline).

The model: the deck's ElastoDyn (GenDOF, TwFADOF1, TwSSDOF1), the rotor from the deck's AeroDyn through
mbsym's BEM surfaces with the rotor-averaged DBEMT (the deck's DBEMT_Mod = 2), the default actuators,
one RK4 step per controller sample (6.25 ms), compiled. Writes the tables into benchmarks/README.md and
the figures benchmarks/figures/operation_steady.png and operation_step.png.

    python benchmarks/operation_validation.py [--quick] [--no-discon] [--no-write]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import shared_aero, write_section  # noqa: E402


AERO = shared_aero()
INPUTS = AERO / "openfast_inputs"
CASES = {4: "4", 5: "5", 6: "6", 7: "7", 8: "8", 9: "9", 10: "10", 11: "11", 11.4: "11p4", 12: "12", 13: "13",
         14: "14", 16: "16", 18: "18", 20: "20", 22: "22", 24: "24"}
CHANNELS = ("RotSpeed", "BldPitch1", "GenPwr", "RtAeroFxh", "TTDspFA", "GenTq", "TwrBsMyt", "RotThrust")
STEP_CHANNELS = ("RotSpeed", "BldPitch1", "GenPwr", "TTDspFA")
RATED_WIND = 11.4


def rosco_library() -> Path | None:
    sys.path.insert(0, str(HERE.parent / "tests" / "wind" / "control"))
    import _rosco

    return _rosco.rosco_library()


def build(deck_fst: Path):
    from mbsym.wind.operation.deck import operating_deck

    t0 = time.perf_counter()
    deck = operating_deck(deck_fst)
    model = deck.model()
    model.dynamics()
    return deck, model, time.perf_counter() - t0


def controller(kind: str, deck, lib: Path | None):
    from mbsym.wind.control import BaselineController, DisconController
    from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop

    discon_in = INPUTS / "deck" / "DISCON.IN"
    if kind == "baseline":
        return baseline_in_loop(BaselineController(deck.baseline_settings(discon_in=discon_in))), None
    handle = DisconController(lib, discon_in, dt=deck.controller_dt)
    return discon_in_loop(handle), handle


def run_case(model, deck, kind, lib, fst: Path, wind, tmax: float, t_out):
    from mbsym.wind import read_openfast
    from mbsym.wind.operation.simulation import simulate_turbine

    ic = read_openfast(fst).initial_conditions
    x0 = model.initial_state(float(wind(0.0)), rotor_speed=ic.rotor_speed, pitch=float(ic.blade_pitch[0]),
                             tower_fa=ic.tower_top_fa_displacement, tower_ss=ic.tower_top_ss_displacement)
    ctrl, handle = controller(kind, deck, lib)
    try:
        res = simulate_turbine(model, wind, tmax, controller=ctrl, x0=x0, t_out=t_out, compile=True)
    finally:
        if handle is not None:
            handle.close()
    return res


def steady(model, deck, kind, lib, speeds, tmax=150.0):
    from mbsym.wind.inflow import SteadyWind

    rows = {}
    t_out = np.round(np.arange(0, tmax + 1e-9, 0.05), 10)
    wall = 0.0
    for u in speeds:
        fst = INPUTS / f"steady_{CASES[u]}" / f"steady_{CASES[u]}.fst"
        res = run_case(model, deck, kind, lib, fst, SteadyWind(u), tmax, t_out)
        wall += res.statistics["integration_wall_s"]
        keep = res.t >= 120.0
        rows[u] = {c: float(np.mean(res.output(c)[keep])) for c in CHANNELS}
        rows[u]["RotSpeed_std"] = float(np.std(res.output("RotSpeed")[keep]))
    return rows, wall


def reference():
    """Rows of steady_states.csv by wind speed: channel (without unit) -> mean over 120-150 s."""
    import csv

    with (AERO / "steady_states.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    out = {}
    for row in rows:
        values = {k.split("_[")[0]: float(v) for k, v in row.items()}
        out[values["WindSpeed"]] = {c: values[c] for c in CHANNELS}
    return out


def steady_table(results, ref) -> tuple[str, dict]:
    lines = ["| U m/s | controller | RotSpeed rpm (Δ %) | BldPitch1 deg (Δ deg) | GenPwr kW (Δ %) | RtAeroFxh kN (Δ %) "
             "| TTDspFA m (Δ %) | TwrBsMyt kN m (Δ %) |", "|---|---|---|---|---|---|---|---|"]
    worst: dict = {}
    for kind, rows in results.items():
        w = worst.setdefault(kind, {"RotSpeed": 0.0, "BldPitch1": 0.0, "GenPwr": 0.0, "RtAeroFxh": 0.0,
                                    "TTDspFA": 0.0, "TwrBsMyt": 0.0})
        for u, ours in rows.items():
            of = ref[float(u)]
            rel = {c: 100 * (ours[c] / of[c] - 1) for c in ("RotSpeed", "GenPwr", "RtAeroFxh", "TTDspFA", "TwrBsMyt")}
            dp = ours["BldPitch1"] - of["BldPitch1"]
            for c in rel:
                w[c] = max(w[c], abs(rel[c]))
            if u > RATED_WIND:
                w["BldPitch1"] = max(w["BldPitch1"], abs(dp))
            lines.append(f"| {u:g} | {kind} | {ours['RotSpeed']:.3f} ({rel['RotSpeed']:+.2f}) | {ours['BldPitch1']:.2f} "
                         f"({dp:+.2f}) | {ours['GenPwr']:.1f} ({rel['GenPwr']:+.2f}) | {ours['RtAeroFxh'] / 1e3:.1f} "
                         f"({rel['RtAeroFxh']:+.2f}) | {ours['TTDspFA']:.4f} ({rel['TTDspFA']:+.2f}) | "
                         f"{ours['TwrBsMyt']:.0f} ({rel['TwrBsMyt']:+.2f}) |")
    return "\n".join(lines), worst


def step(model, deck, kind, lib):
    from mbsym.wind.analysis.compare import read_csv
    from mbsym.wind.inflow import parse_wind_spec

    wind = parse_wind_spec(str(AERO / "wind" / "step_10_14.hh"))
    t_out = np.round(np.arange(0, 90.0 + 1e-9, 0.05), 10)
    res = run_case(model, deck, kind, lib, INPUTS / "step_10_14" / "step_10_14.fst", wind, 90.0, t_out)
    ref = read_csv(AERO / "step_10_14.csv")
    out = {}
    for c in STEP_CHANNELS + ("RtAeroFxh", "TwrBsMyt", "TwrBsMxt", "TTDspSS", "GenTq"):
        yr = np.interp(t_out, ref.time, ref.channel(c))
        y = res.output(c)
        out[c] = (float(np.mean(np.abs(y - yr)) / np.ptp(yr)),
                  float(1 - np.sum((y - yr) ** 2) / np.sum((yr - yr.mean()) ** 2)))
    return res, out, res.statistics["integration_wall_s"]


def plot_steady(results, ref, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    chans = ("RotSpeed", "BldPitch1", "GenPwr", "RtAeroFxh", "TTDspFA", "TwrBsMyt")
    fig, axes = plt.subplots(2, 3, figsize=(12, 6.5))
    us = sorted(ref)
    for ax, c in zip(axes.ravel(), chans):
        ax.plot(us, [ref[u][c] for u in us], "k-o", ms=4, label="OpenFAST + ROSCO")
        for (kind, rows), style in zip(results.items(), ("C1s", "C0x")):
            ks = sorted(rows)
            ax.plot(ks, [rows[u][c] for u in ks], style, ms=6, mfc="none", label=f"mbsym, {kind}")
        ax.set_title(c, fontsize=9)
        ax.set_xlabel("wind speed [m/s]", fontsize=8)
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_step(runs, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from mbsym.wind.analysis.compare import read_csv

    ref = read_csv(AERO / "step_10_14.csv")
    chans = ("Wind1VelX", "RotSpeed", "BldPitch1", "GenPwr", "TTDspFA", "TwrBsMyt", "TTDspSS")
    fig, axes = plt.subplots(len(chans), 1, figsize=(9, 13), sharex=True)
    for ax, c in zip(axes, chans):
        ax.plot(ref.time, ref.channel(c), "k-", lw=1.5, label="OpenFAST + ROSCO")
        for (kind, res), style in zip(runs.items(), ("C1--", "C0:")):
            ax.plot(res.t, res.output(c), style, lw=1.2, label=f"mbsym, {kind}")
        ax.set_ylabel(c, fontsize=8)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("Time [s]")
    axes[-1].set_xlim(20, 90)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="3 wind speeds only")
    ap.add_argument("--no-discon", action="store_true", help="skip the ROSCO library runs")
    ap.add_argument("--no-write", action="store_true", help="do not touch README.md and the figures")
    args = ap.parse_args()
    lib = None if args.no_discon else rosco_library()
    kinds = ["baseline"] + (["discon"] if lib is not None else [])
    deck, model, prep = build(INPUTS / "step_10_14" / "step_10_14.fst")
    print(f"model built in {prep:.1f} s: {model}")
    speeds = [8, 12, 18] if args.quick else list(CASES)
    ref = reference()
    results, walls = {}, {}
    for kind in kinds:
        t0 = time.perf_counter()
        results[kind], walls[kind] = steady(model, deck, kind, lib, speeds)
        print(f"steady states, {kind}: {time.perf_counter() - t0:.1f} s wall ({walls[kind]:.1f} s integration)")
    table, worst = steady_table(results, ref)
    print(table)
    print("worst:", worst)
    runs, step_rows = {}, []
    for kind in kinds:
        res, metrics, wall = step(model, deck, kind, lib)
        runs[kind] = res
        step_rows.append(f"| {kind} | " + " | ".join(f"{100 * metrics[c][0]:.2f} / {metrics[c][1]:.4f}"
                                                     for c in STEP_CHANNELS + ("RtAeroFxh", "TwrBsMyt", "TwrBsMxt"))
                         + f" | {wall:.2f} |")
    step_table = ("| controller | " + " | ".join(f"{c} ε % / R²" for c in STEP_CHANNELS + ("RtAeroFxh", "TwrBsMyt",
                                                                                          "TwrBsMxt"))
                  + " | integration s |\n|" + "---|" * 9 + "\n" + "\n".join(step_rows))
    print(step_table)
    if args.no_write:
        return
    figs = HERE / "figures"
    figs.mkdir(exist_ok=True)
    plot_steady(results, ref, figs / "operation_steady.png")
    plot_step(runs, figs / "operation_step.png")
    worst_lines = "\n".join(
        f"- {kind}: RotSpeed {w['RotSpeed']:.2f} %, BldPitch1 {w['BldPitch1']:.2f} deg (above rated), GenPwr "
        f"{w['GenPwr']:.2f} %, RtAeroFxh {w['RtAeroFxh']:.2f} %, TTDspFA {w['TTDspFA']:.2f} %, TwrBsMyt "
        f"{w['TwrBsMyt']:.2f} %" for kind, w in worst.items())
    write_section("operation-validation",
                  f"Worst deviations over the {len(speeds)} wind speeds:\n\n{worst_lines}\n\n{table}\n\n"
                  f"Step 10 -> 14 m/s (ε = mean|y - y_OF| / range(y_OF), R²):\n\n{step_table}\n\n"
                  "![steady states](figures/operation_steady.png)\n\n![step](figures/operation_step.png)")


if __name__ == "__main__":
    main()
