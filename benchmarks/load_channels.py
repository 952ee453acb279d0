"""Load channels of the blade-element operating NREL 5 MW against OpenFAST v5 + AeroDyn 15, and what they cost.

The channels ``LSShftFys``, ``LSShftFzs``, ``YawBrMyp``, ``YawBrMzp`` come from locked joints at the low-speed
shaft and the yaw bearing (``OperatingTurbine(..., load_channels=True)``, :mod:`mbsym.wind.structure.load_cuts`);
the shared OpenFAST runs ``ss14_shear_flex`` and ``ss14_yaw10_flex`` (steady 14 m/s, shear 0.2, and 10 deg yaw
misalignment; flexible blades, drivetrain, 4 tower modes; ROSCO) list them. Each case runs 120 s with mbsym's
baseline controller as :mod:`blade_validation` does (one RK4 step per 6.25 ms controller sample) and compares the
periodic state over t >= 60 s: mean, standard deviation, ε = mean|y - y_OF| / range(y_OF) and R² of each channel
(``LSShftFxa`` against OpenFAST's ``RotThrust``, which is ElastoDyn's ``LSShftFxa``).

Cost: the instructions of the structure's reactions Function (the load channels' share of the output Function)
and of its forcing (the right-hand side), and the wall time of one evaluation of the output Function in CasADi's
VM, with and without the extra locked joints.

    python benchmarks/load_channels.py [--case NAME ...] [--tmax S] [--no-write]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import write_section  # noqa: E402
from blade_validation import CONTROLLER_DT, INPUTS, T_FROM, reference, simulate  # noqa: E402

CASES = ("ss14_shear_flex", "ss14_yaw10_flex")
CHANNELS = {"LSShftFxa": "RotThrust", "LSShftFys": "LSShftFys", "LSShftFzs": "LSShftFzs", "YawBrMyp": "YawBrMyp",
            "YawBrMzp": "YawBrMzp", "RootMyc1": "RootMyc1", "RootMxc1": "RootMxc1"}
JSON = HERE / "figures" / "load_channels.json"


def build(case: str, load_channels: bool):
    from mbsym.wind.operation.deck import operating_deck

    deck = operating_deck(INPUTS / case / f"{case}.fst")
    model = deck.model(aero="blade", load_channels=load_channels)
    model.dynamics()
    return deck, model


def cost(case: str) -> dict:
    """Instructions and VM evaluation time of the outputs, without and with the load channels."""
    out = {}
    for flag in (False, True):
        _, model = build(case, flag)
        d, f = model.dynamics(), model.structure.eom.functions
        x, u = np.asarray(d.x0, dtype=float), np.asarray(d.u0, dtype=float)
        p = np.array([d.defaults[n] for n in d.parameters])
        times = []
        for _ in range(5):
            t0 = time.perf_counter()
            for _ in range(10):
                d.outputs(x, u, p)
            times.append((time.perf_counter() - t0) / 10)
        out["with" if flag else "without"] = {
            "locked": len(model.structure.eom.locked), "reactions_instructions": f.reactions.n_instructions(),
            "forcing_instructions": f.forcing.n_instructions(), "mass_instructions": f.mass_matrix.n_instructions(),
            "outputs_eval_ms": 1e3 * min(times), "n_outputs": len(d.output_names)}
    return out


def compare(case: str, tmax: float) -> dict:
    from mbsym.wind.analysis.compare import error_metrics
    from mbsym.wind.operation.simulation import wind_at_start

    deck, model = build(case, True)
    wind = deck.inflow.field()
    t0 = time.perf_counter()
    res = simulate(model, deck, wind, wind_at_start(model, wind), tmax, CONTROLLER_DT)
    wall = time.perf_counter() - t0
    ref = reference(case)
    rows = {}
    keep = res.t >= T_FROM - 1e-9
    rk = (ref.time >= T_FROM - 1e-9) & (ref.time <= tmax + 1e-9)
    for ours, theirs in CHANNELS.items():
        y, yr = res.output(ours)[keep], ref.channel(theirs)[rk]
        eps, r2 = error_metrics(res.t[keep], y, ref.time[rk], yr)
        rows[ours] = {"mean": float(y.mean()), "mean_of": float(yr.mean()), "std": float(y.std()),
                      "std_of": float(yr.std()), "eps": float(eps), "r2": float(r2)}
        print(f"  {case} {ours:9s} mean {y.mean():9.1f} vs {yr.mean():9.1f}  std {y.std():7.1f} vs {yr.std():7.1f}"
              f"  eps {100 * eps:5.2f} %  R2 {r2:6.3f}", flush=True)
    return {"channels": rows, "wall_s": wall, "tmax": tmax}


def table(results: dict) -> str:
    lines = ["| case | channel | mean mbsym / OpenFAST | std mbsym / OpenFAST | ε % | R² |", "|---|---|---|---|---|---|"]
    for case, r in results.items():
        if case == "cost":
            continue
        for name, m in r["channels"].items():
            unit = "kN" if "F" in name[4:7] else "kN m"
            lines.append(f"| {case} | {name} [{unit}] | {m['mean']:.1f} / {m['mean_of']:.1f} | {m['std']:.1f} / "
                         f"{m['std_of']:.1f} | {100 * m['eps']:.2f} | {m['r2']:.3f} |")
    c = results.get("cost")
    if c:
        a, b = c["without"], c["with"]
        lines += ["", "| ss14_shear_flex blade-element model | locked coordinates | reactions Function instructions | "
                  "forcing (rhs) instructions | mass matrix instructions | outputs (VM) ms per evaluation | channels |",
                  "|---|---|---|---|---|---|---|"]
        for label, v in (("default", a), ("load_channels=True", b)):
            lines.append(f"| {label} | {v['locked']} | {v['reactions_instructions']} | {v['forcing_instructions']} | "
                         f"{v['mass_instructions']} | {v['outputs_eval_ms']:.2f} | {v['n_outputs']} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", nargs="*", default=list(CASES))
    ap.add_argument("--tmax", type=float, default=120.0)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args()
    results = json.loads(JSON.read_text()) if JSON.exists() else {}
    results["cost"] = cost(CASES[0])
    print(json.dumps(results["cost"], indent=1), flush=True)
    for case in args.case:
        results[case] = compare(case, args.tmax)
        if not args.no_write:
            JSON.write_text(json.dumps(results, indent=1))
    if not args.no_write:
        JSON.write_text(json.dumps(results, indent=1))
        write_section("load_channels", table(results))
    print(table(results))


if __name__ == "__main__":
    main()
