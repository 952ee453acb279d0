"""The turbine NMPC exported as DISCON libraries (with its EKF, then its MHE) and run in mbsym's own DISCON loop.

``mbsym export-discon --controller nmpc [--estimator mhe]`` writes a self-contained library (generated C, no
Python at run time) that OpenFAST's ServoDyn loads as it loads ROSCO's. Here both libraries, and our baseline
controller beside them, drive the built-in NREL 5 MW (rotor-effective aerodynamics, tower and generator DOFs) for
30 s of a 14 m/s Kaimal wind through the same swap array OpenFAST would use; the table shows what each controller
does (rotor speed about rated, pitch activity, tower-base load) and what it costs (wall time of the run, every
library call from Python). A last run retunes the EKF library without compiling: its input file edited (the
tower-velocity scale halved, the pitch-rate scale doubled: more tower damping for more pitch activity), the run-time
settings of docs/discon_export.md, "The NMPC's input file". The NMPC's figures inside OpenFAST: benchmarks/README.md, "The NMPC judged inside
OpenFAST".

Run: ``python examples/nmpc_discon_export.py [--seconds 30] [--out DIR]`` (needs a C compiler; the two exports
take 20-60 s each).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from mbsym.cli import main as cli
from mbsym.codegen import compiler_command
from mbsym.wind.control import BaselineController, DisconController
from mbsym.wind.inflow import kaimal_wind
from mbsym.wind.operation import simulate_turbine
from mbsym.wind.operation.controllers import baseline_in_loop, discon_in_loop
from mbsym.wind.operation.deck import builtin_deck
from mbsym.wind.operation.steady import steady_guess


def export(kind: str, out: Path) -> dict:
    """``mbsym export-discon --controller nmpc --estimator KIND --out OUT``; its JSON line."""
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = cli(["export-discon", "--controller", "nmpc", "--estimator", kind, "--out", str(out)])
    if code != 0:
        raise SystemExit(f"export-discon failed (exit {code})")
    return json.loads(buf.getvalue().strip().splitlines()[-1])


def retuned(lib: dict, changes: dict, out: Path) -> dict:
    """``lib`` with a copy of its input file whose run-time settings ``changes`` (key -> factor) are scaled."""
    lines = []
    for line in Path(lib["input"]).read_text().splitlines(True):
        parts = line.split()
        if len(parts) > 1 and parts[1] in changes:
            line = f"{float(parts[0]) * changes[parts[1]]!r:<24} {parts[1]} ! edited\n"
        lines.append(line)
    out.write_text("".join(lines))
    return {**lib, "input": str(out)}


def measures(res, seconds: float) -> dict:
    """Rotor speed range [rpm], pitch-rate RMS [deg/s], tower-base fore-aft moment std [MN m] after 5 s."""
    t = np.asarray(res.t)
    keep = t >= 5.0
    pitch = np.asarray(res.output("BldPitch1"))
    rate = np.gradient(pitch, t)[keep]
    speed = np.asarray(res.output("RotSpeed"))[keep]
    return {"speed min": speed.min(), "speed max": speed.max(), "pitch-rate RMS": float(np.sqrt(np.mean(rate ** 2))),
            "TwrBsMyt std": float(np.std(np.asarray(res.output("TwrBsMyt"))[keep]) / 1e3)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=30.0)
    ap.add_argument("--out", help="directory for the libraries (default: a temporary one)")
    args = ap.parse_args()
    if compiler_command() is None:
        print("needs a C compiler (gcc/cc, or $CC) to export the libraries", file=sys.stderr)
        return 2
    out = Path(args.out or tempfile.mkdtemp(prefix="mbsym_nmpc_"))
    deck = builtin_deck()
    model = deck.model()
    wind = kaimal_wind(14.0, 0.14, 3, duration=args.seconds + 1.0)
    x0 = steady_guess(model, float(wind(0.0))).state       # steady operation at the first wind (as mbsym simulate)
    runs = {"baseline (compiled in the loop)": None}
    for kind in ("ekf", "mhe"):
        c0 = time.perf_counter()
        runs[f"NMPC + {kind.upper()} (library)"] = export(kind, out / kind)
        print(f"exported the NMPC with its {kind.upper()} in {time.perf_counter() - c0:.0f} s: "
              f"{runs[f'NMPC + {kind.upper()} (library)']['library']}")
    runs["NMPC + EKF, input file edited"] = retuned(runs["NMPC + EKF (library)"],
                                                    {"TowerVelocityScale": 0.5, "PitchRateScale": 2.0},
                                                    out / "ekf" / "retuned.IN")
    print(f"\n{args.seconds:g} s at 14 m/s (Kaimal, TI 14 %), after 5 s; rated rotor speed 12.1 rpm")
    print(f"{'controller':<32} {'rpm min':>8} {'rpm max':>8} {'pitch rate':>11} {'TwrBsMyt std':>13} {'wall':>7}")
    print(f"{'':<32} {'':>8} {'':>8} {'[deg/s]':>11} {'[MN m]':>13} {'[s]':>7}")
    for name, lib in runs.items():
        c0 = time.perf_counter()
        if lib is None:
            res = simulate_turbine(model, wind, args.seconds, x0=x0,
                                   controller=baseline_in_loop(BaselineController(deck.baseline_settings())))
        else:
            with DisconController(lib["library"], lib["input"], dt=lib["sample_time_s"]) as handle:
                res = simulate_turbine(model, wind, args.seconds, x0=x0,
                                       controller=discon_in_loop(handle, model=model))
        wall = time.perf_counter() - c0
        m = measures(res, args.seconds)
        print(f"{name:<32} {m['speed min']:8.2f} {m['speed max']:8.2f} {m['pitch-rate RMS']:11.3f} "
              f"{m['TwrBsMyt std']:13.2f} {wall:7.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
