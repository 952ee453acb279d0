"""Tower damping identified on an operating turbine: speed and accuracy of the models `mbsym identify` can fit.

Problem (issue 22, item 2): ``TwrFADmp(1)`` (the deck's 1 %) from the shared OpenFAST v5 run ``step_10_14``
(NREL 5 MW, AeroDyn 15 + DBEMT, ROSCO 2.10.6; wind 10 -> 14 m/s at 30 s), ``mbsym identify`` as a user runs it
(``--json``, the whole command timed: reading, building, compiling from a warm disk cache, fitting). Rows:

- ``loads`` (the baseline of the ratios): the structure driven by AeroDyn's recorded rotor loads
  (``tests/data/openfast_step_rotor_loads``: the same run with ``RtAeroFyh`` … ``RtAeroMzh`` recorded);
- ``operating``: the operating turbine (rotor-effective, the deck's default) on the shared record, which has
  thrust and torque but not the in-plane loads: the disk's tilt damping from the BEM's ⟨r²⟩ (now), and with
  ⟨r²⟩ = (R² + r_hub²)/2 (before 2026-11-30; ``RotorAero.thrust_radius2`` switched off in this process);
- ``loads``, thrust and torque only: the disk's moment left out, to show what it is worth.

Run: ``python benchmarks/identify_operating.py [--no-write]`` (needs ../shared/openfast); writes the table into
benchmarks/README.md between the ``identify-operating`` markers.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import tempfile
import time
from pathlib import Path

from _report import shared_aero, write_section

HERE = Path(__file__).resolve().parent
RECORD = HERE.parent / "tests" / "data" / "openfast_step_rotor_loads" / "step_10_14_rotor_loads.csv"


def _identify(fst: Path, data: Path, *extra: str) -> tuple[dict, float]:
    from mbsym.cli import main

    buf = io.StringIO()
    t0 = time.perf_counter()
    with contextlib.redirect_stdout(buf):
        code = main(["identify", str(fst), "--data", str(data), "--params", "TwrFADmp(1)", "--json", "--quiet",
                     *extra])
    wall = time.perf_counter() - t0
    if code != 0:
        raise SystemExit(f"mbsym identify {' '.join(extra)} exited {code}")
    return json.loads(buf.getvalue().strip().splitlines()[-1]), wall


def _thrust_torque_only(record: Path, folder: Path) -> Path:
    """The rotor-load record with its in-plane loads zeroed (thrust and torque kept)."""
    lines = record.read_text().splitlines()
    names = [h.split("_[")[0] for h in lines[0].split(",")]
    zero = [names.index(n) for n in ("RtAeroFyh", "RtAeroFzh", "RtAeroMyh", "RtAeroMzh")]
    out = [lines[0]]
    for line in lines[1:]:
        cells = line.split(",")
        for k in zero:
            cells[k] = "0"
        out.append(",".join(cells))
    path = folder / "thrust_torque_only.csv"
    path.write_text("\n".join(out) + "\n")
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--no-write", action="store_true", help="print only")
    args = parser.parse_args()
    from mbsym.wind.aero.rotor import RotorAero

    aero = shared_aero()
    fst = aero / "openfast_inputs" / "step_10_14" / "step_10_14.fst"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        _identify(fst, RECORD, "--model", "loads")                       # warm the disk cache
        base, base_wall = _identify(fst, RECORD, "--model", "loads", "--initial", "TwrFADmp(1)=2")
        rows.append(("structure driven by the recorded rotor loads (`--model loads`, auto)", "rotor-load record",
                     base, base_wall))
        torque_only = _thrust_torque_only(RECORD, Path(tmp))
        res, wall = _identify(fst, torque_only, "--model", "loads", "--initial", "TwrFADmp(1)=2")
        rows.append(("the same, thrust and torque only (in-plane loads zeroed)", "rotor-load record", res, wall))
        _identify(fst, aero / "step_10_14.csv")                          # warm the disk cache
        res, wall = _identify(fst, aero / "step_10_14.csv")
        rows.append(("operating turbine, rotor-effective, BEM ⟨r²⟩ (auto on this record)", "shared record", res,
                     wall))
        original = RotorAero.thrust_radius2
        RotorAero.thrust_radius2 = lambda self, *a, **k: None               # the formula before 2026-11-30
        try:
            _identify(fst, aero / "step_10_14.csv")
            res, wall = _identify(fst, aero / "step_10_14.csv")
        finally:
            RotorAero.thrust_radius2 = original
        rows.append(("operating turbine, rotor-effective, ⟨r²⟩ = (R² + r_hub²)/2 (before)", "shared record", res,
                     wall))
    lines = ["| model | record | TwrFADmp(1) [%] (deck 1 %) | std | fit max ε [%] | iterations | wall [s] | "
             "× loads |", "|---|---|---:|---:|---:|---:|---:|---:|"]
    for label, record, res, wall in rows:
        value = res["parameters"]["TwrFADmp(1)"]
        lines.append(f"| {label} | {record} | {value:.3f} ({100 * (value - 1):+.1f} %) | "
                     f"{res['std']['TwrFADmp(1)']:.3f} | {max(res['eps_pct'].values()):.3f} | {res['iterations']} | "
                     f"{wall:.1f} | {wall / base_wall:.1f} |")
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines.append("")
    lines.append(f"Whole-command wall time, warm disk cache (the first run of each model compiles its shooting "
                 f"functions: add 5-10 s); 1-min load average {load:.1f} on 2 cores.")
    table = "\n".join(lines)
    print(table)
    if not args.no_write:
        write_section("identify-operating", table)


if __name__ == "__main__":
    main()
