"""Free decay of the floating IEA 15 MW (issue 20, item 7: ``fl_decay_a``) against OpenFAST v5 + MoorDyn.

The deck's structure (six platform DOFs, tower FA1/SS1, rigid blades, parked rotor) with HydroDyn's
hydrostatics, additional damping, A∞ and our radiation fit (:class:`mbsym.wind.offshore.FloatingStructure`,
RK4 at OpenFAST's 0.025 s), the MoorDyn lines as quasi-static catenaries, with and without their drag and
inertia on the quasi-static shape (``mooring_from_moordyn(line_dynamics=...)``, docs/offshore.md §6).
Reports per channel (PtfmSurge, PtfmHeave, PtfmPitch, TTDspFA) ε = RMS(error)/range(OpenFAST), R² and the
decay periods (up-crossings: heave, pitch, TTDspFA about a 40 s moving mean over t < 200 s; surge about the
mean of the last 100 s), and the cost: model build, integration wall and CPU time.

    python benchmarks/floating_decay.py [--tmax 600] [--segments 10] [--only on|off]
                                        [--reference OTHER.csv] [--plot FILE.png]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
FLOATING = HERE.parent.parent / "shared" / "openfast" / "floating"
CASE = FLOATING / "cases" / "fl_decay_a" / "fl_decay_a.fst"
#: channel, moving-mean window [s] (0: about the mean of t > 500 s), end of the period window [s]
CHANNELS = (("PtfmSurge", 0.0, 600.0), ("PtfmHeave", 40.0, 200.0), ("PtfmPitch", 40.0, 200.0),
            ("TTDspFA", 40.0, 200.0))
#: TTDspFA's decay is the platform pitch's (28.9 s); the tower's own 0.51 Hz ringing (2 mm to 7 mm RMS,
#: docs/offshore.md §6) adds up-crossings, so it is averaged over 4 s (two tower periods) first.
SMOOTH = {"TTDspFA": 4.0}


def decay_period(t: np.ndarray, x: np.ndarray, window: float, t_max: float, smooth: float = 0.0) -> float:
    """Mean time between up-crossings [s] (about a moving mean of ``window`` s, or the mean of t > 500 s),
    after a moving average over ``smooth`` s (0: none)."""
    if smooth:
        k = int(round(smooth / (t[1] - t[0])))
        x = np.convolve(x, np.ones(k) / k, "same")
    if window:
        k = int(round(window / (t[1] - t[0])))
        x = x - np.convolve(x, np.ones(k) / k, "same")
        keep = (t > window / 2 + 1) & (t < t_max)
    else:
        x = x - x[t > 500].mean()
        keep = t < t_max
    tt, xx = t[keep], x[keep]
    up = np.where((xx[:-1] < 0) & (xx[1:] >= 0))[0]
    return float(np.diff(tt[up] - xx[up] * (tt[up + 1] - tt[up]) / (xx[up + 1] - xx[up])).mean())


def read_reference(path: Path) -> dict[str, np.ndarray]:
    names = [h.split("_[")[0] for h in path.open().readline().strip().split(",")]
    data = np.loadtxt(path, delimiter=",", skiprows=1)
    return {n: data[:, k] for k, n in enumerate(names)}


def compare(t: np.ndarray, ours: dict, ref: dict, t_end: float) -> dict[str, tuple[float, float, float, float]]:
    """``channel → (ε, R², period ours, period OpenFAST)`` on OpenFAST's samples in (0, t_end]."""
    keep = (ref["Time"] > 1e-9) & (ref["Time"] <= t_end + 1e-9)
    tr = ref["Time"][keep]
    out = {}
    for name, window, t_max in CHANNELS:
        x, y = np.interp(tr, t, ours[name]), ref[name][keep]
        eps = float(np.sqrt(np.mean((x - y) ** 2)) / np.ptp(y))
        r2 = float(1 - np.sum((x - y) ** 2) / np.sum((y - y.mean()) ** 2))
        end, smooth = min(t_max, t_end), SMOOTH.get(name, 0.0)
        out[name] = (eps, r2, decay_period(tr, x, window, end, smooth), decay_period(tr, y, window, end, smooth))
    return out


def build(line_dynamics: bool, segments: int):
    from mbsym.exceptions import ModelWarning
    from mbsym.wind import read_openfast
    from mbsym.wind.deck.moordyn import read_moordyn
    from mbsym.wind.offshore import fit_radiation, mooring_from_moordyn, platform_hydrodynamics
    from mbsym.wind.offshore.floating import FloatingStructure
    from mbsym.wind.structure.turbine import TurbineModel

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ModelWarning)
        turbine = read_openfast(CASE)
        sim = turbine.simulation
        hydro = platform_hydrodynamics(turbine.source_files["hydrodyn"], water_density=sim.water_density,
                                       gravity=sim.gravity, seastate=turbine.source_files["seastate"])
        mooring = mooring_from_moordyn(read_moordyn(turbine.source_files["mooring"]), water_density=sim.water_density,
                                       gravity=sim.gravity, line_dynamics=line_dynamics, line_segments=segments)
    model = TurbineModel(turbine)
    return FloatingStructure(model, hydro, mooring, fit_radiation(hydro.wamit))


def run(line_dynamics: bool, segments: int, t_end: float) -> tuple[np.ndarray, dict, dict]:
    start = time.perf_counter()
    fs = build(line_dynamics, segments)
    built = time.perf_counter()
    wall, cpu = time.perf_counter(), time.process_time()
    t, states = fs.simulate(t_end, 0.025)
    cost = {"build_s": built - start, "integration_wall_s": time.perf_counter() - wall,
            "integration_cpu_s": time.process_time() - cpu}
    model = fs.model
    eom = model.eom
    channels = model.output_function()
    x = states[:2 * eom.n_q]
    y = np.array(channels.function.map(x.shape[1])(x, np.zeros((eom.n_u, 1)), eom.parameter_vector()))
    ours = {n: y[channels.names.index(n)] for n, _, _ in CHANNELS}
    return t, ours, cost


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--tmax", type=float, default=600.0)
    parser.add_argument("--segments", type=int, default=10, help="quadrature segments per line (default 10)")
    parser.add_argument("--only", choices=("on", "off"), help="only with (on) or without (off) line dynamics")
    parser.add_argument("--reference", type=Path, default=FLOATING / "fl_decay_a.csv")
    parser.add_argument("--plot", type=Path, help="write the four channels, OpenFAST and each mbsym run, to FILE.png")
    args = parser.parse_args(argv)
    ref = read_reference(args.reference)
    cases = [c for c in (False, True) if args.only is None or (args.only == "on") == c]
    runs = {}
    for dynamics in cases:
        t, ours, cost = run(dynamics, args.segments, args.tmax)
        label = f"line drag and inertia ({args.segments} segments)" if dynamics else "quasi-static lines"
        print(f"\n{label}: build {cost['build_s']:.1f} s, integration {cost['integration_wall_s']:.1f} s wall, "
              f"{cost['integration_cpu_s']:.1f} s CPU for {args.tmax:g} s")
        print("| channel | ε | R² | period mbsym / OpenFAST |\n|---|---|---|---|")
        for name, (eps, r2, p_ours, p_ref) in compare(t, ours, ref, args.tmax).items():
            print(f"| {name} | {100 * eps:.2f} % | {r2:.4f} | {p_ours:.2f} / {p_ref:.2f} s ({100 * (p_ours / p_ref - 1):+.2f} %) |")
        runs[label] = (t, ours)
    if args.plot:
        plot(args.plot, ref, runs, args.tmax)


def plot(path: Path, ref: dict, runs: dict, t_end: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(len(CHANNELS), 1, figsize=(10, 9), sharex=True)
    keep = ref["Time"] <= t_end
    units = {"PtfmSurge": "m", "PtfmHeave": "m", "PtfmPitch": "deg", "TTDspFA": "m"}
    for ax, (name, _, _) in zip(axes, CHANNELS):
        ax.plot(ref["Time"][keep], ref[name][keep], "k", lw=1.6, label="OpenFAST v5 + MoorDyn")
        for (label, (t, ours)), style in zip(runs.items(), ("C1--", "C0")):
            ax.plot(t, ours[name], style, lw=0.9, label=f"mbsym, {label}")
        ax.set_ylabel(f"{name} [{units[name]}]")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    fig.suptitle("fl_decay_a: free decay of the IEA 15 MW on the VolturnUS-S (still water)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
