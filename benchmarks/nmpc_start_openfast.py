"""The exported NMPC's start on the ROSCO wheel's stock decks, inside OpenFAST, against ROSCO from the same start.

A user's first run of ``mbsym export-discon DECK --controller nmpc`` is often a stock deck as shipped, started from
its own initial conditions (rotor at rated speed, pitch 0-1 deg, blades, tower and platform at rest and
undeflected) in a steady wind far above rated: a start far from steady operation, which rings the flexible modes
the controller's models do not hold. This script runs it for two stock decks of the ``rosco`` 2.10.6 wheel:

* ``nrel5mw``: ``Examples/Test_Cases/NREL-5MW`` (flexible blades and drivetrain, both tower modes each way, yaw);
* ``semi``: ``Examples/Test_Cases/IEA-15-240-RWT/IEA-15-240-RWT-UMaineSemi`` (flexible blades, both tower modes,
  six platform DOFs, HydroDyn, MoorDyn);

each copied, its InflowWind set to a steady ``--wind`` m/s (``WindType 1``), ``TMax`` to ``--seconds`` (30 and 60 s
by default) and text output, then run by OpenFAST v5.0.0 (``../shared/tools/openfast``) twice: with the wheel's
ROSCO library and the deck's DISCON.IN, and with the library ``mbsym export-discon`` builds for the copy (its two
paths put into ServoDyn, nothing else changed). Printed per deck and controller: the peak rotor speed (and over
rated), the time spent above 1.1 x rated, the peak electrical power, the mean rotor speed over the last 10 s and the
failed QPs the library reported (``QP failed`` messages in OpenFAST's log).

Run: ``python benchmarks/nmpc_start_openfast.py [--decks nrel5mw semi] [--wind 16] [--work DIR] [--wheel DIR]``
(``--wheel``: a directory holding the wheel's ``Examples/Test_Cases`` (or the tests' extracted ``deck/``) and
``rosco/lib/libdiscon.so``; default the test cache ``~/.cache/mbsym/rosco/2.10.6``, filled by the tests, or
``pip download --no-deps rosco==2.10.6`` unzipped). Needs a C compiler. About 4 min.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE)]
from discon_export_openfast import _read_out, _shared  # noqa: E402  (the benchmarks' OpenFAST helpers)
from discon_export_openfast import _set_value as _set  # noqa: E402

WHEEL = Path.home() / ".cache" / "mbsym" / "rosco" / "2.10.6"
#: Per deck: folders copied from Examples/Test_Cases, the .fst, its InflowWind and ServoDyn files (relative to the
#: copy), the rated rotor speed [rpm] (the decks' DISCON.IN: PC_RefSpd / gearbox ratio) and the default run length.
DECKS = {
    "nrel5mw": dict(copy=("NREL-5MW",), fst="NREL-5MW/NREL-5MW.fst",
                    inflow="NREL-5MW/NRELOffshrBsline5MW_InflowWind.dat",
                    servo="NREL-5MW/NRELOffshrBsline5MW_Onshore_ServoDyn.dat", rated=12.1, seconds=30.0),
    "semi": dict(copy=("IEA-15-240-RWT/IEA-15-240-RWT", "IEA-15-240-RWT/IEA-15-240-RWT-UMaineSemi"),
                 fst="IEA-15-240-RWT/IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi.fst",
                 inflow="IEA-15-240-RWT/IEA-15-240-RWT/IEA-15-240-RWT_InflowFile.dat",
                 servo="IEA-15-240-RWT/IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi_ServoDyn.dat",
                 rated=7.56, seconds=60.0),
}


def _copy(wheel: Path, deck: dict, work: Path, wind: float, seconds: float) -> Path:
    roots = (wheel / "deck", wheel / "Examples" / "Test_Cases")     # the test cache's extracted cases, or the wheel's
    cases = next((r for r in roots if (r / deck["fst"]).is_file()), None)
    if cases is None:
        sys.exit(f"{deck['fst']} not found under {' or '.join(map(str, roots))}: give --wheel the unpacked rosco "
                 "2.10.6 wheel (its Examples/Test_Cases)")
    for folder in deck["copy"]:
        shutil.copytree(cases / folder, work / folder, dirs_exist_ok=True)
    _set(work / deck["inflow"], "WindType", "1")
    _set(work / deck["inflow"], "HWindSpeed", f"{wind:g}")
    fst = work / deck["fst"]
    for key, value in (("TMax", f"{seconds:g}"), ("OutFileFmt", "1"), ("OutFmt", '"ES15.7E2"')):
        _set(fst, key, value)
    return fst


def _openfast(fst: Path, library: str, infile: str | None, servo: Path) -> tuple[dict, str, float]:
    _set(servo, "DLL_FileName", f'"{library}"')
    if infile is not None:
        _set(servo, "DLL_InFile", f'"{infile}"')
    exe = _shared() / "tools" / "openfast" / "openfast"
    c0 = time.perf_counter()
    proc = subprocess.run([str(exe), fst.name], cwd=fst.parent, capture_output=True, text=True)
    wall = time.perf_counter() - c0
    log = proc.stdout.replace("\r", "\n") + proc.stderr
    if "terminated normally" not in log:
        sys.exit(f"OpenFAST failed on {fst}:\n{log[-2000:]}")
    return _read_out(fst.with_suffix(".out")), log, wall


def _export(fst: Path, out: Path) -> dict:
    proc = subprocess.run([sys.executable, "-m", "mbsym", "export-discon", str(fst), "--controller", "nmpc", "--out",
                           str(out)], capture_output=True, text=True, cwd=HERE.parent)
    if proc.returncode != 0:
        sys.exit(f"mbsym export-discon failed: {proc.stderr.strip()[-2000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def measures(c: dict, rated: float, log: str) -> dict:
    t, rpm = c["Time"], c["RotSpeed"]
    dt = float(t[1] - t[0])
    return {"max rpm": float(rpm.max()), "over rated": float(rpm.max() / rated - 1.0),
            "s above 1.1 x rated": float(np.sum(rpm > 1.1 * rated) * dt), "max power [MW]": float(c["GenPwr"].max() / 1e3),
            "mean rpm, last 10 s": float(rpm[t >= t[-1] - 10.0].mean()), "failed QPs": log.count("QP failed")}


def run(names, wind: float, work: Path, wheel: Path, seconds: float | None) -> dict:
    library = wheel / "rosco" / "lib" / "libdiscon.so"
    if not library.is_file():
        sys.exit(f"{library} not found: give --wheel the unpacked rosco 2.10.6 wheel")
    table = {}
    for name in names:
        deck = DECKS[name]
        length = deck["seconds"] if seconds is None else seconds
        rows = {}
        for controller in ("ROSCO 2.10.6", "mbsym NMPC"):
            root = work / name / controller.split()[0].lower()
            if root.exists():
                shutil.rmtree(root)
            fst = _copy(wheel, deck, root, wind, length)
            if controller.startswith("ROSCO"):
                out, log, wall = _openfast(fst, str(library), None, root / deck["servo"])
            else:
                c0 = time.perf_counter()
                lib = _export(fst, root / "lib")
                print(f"{name}: export {time.perf_counter() - c0:.0f} s")
                out, log, wall = _openfast(fst, lib["library"], lib["input"], root / deck["servo"])
            rows[controller] = {**measures(out, deck["rated"], log), "OpenFAST wall [s]": wall}
        table[name] = rows
        _print(name, wind, length, rows)
    return table


def _print(name: str, wind: float, seconds: float, rows: dict) -> None:
    keys = list(next(iter(rows.values())))
    print(f"\n{name}, steady {wind:g} m/s from the deck's initial conditions, {seconds:g} s in OpenFAST v5.0.0")
    print("| controller | " + " | ".join(keys) + " |")
    print("|---|" + "---:|" * len(keys))
    for controller, m in rows.items():
        cells = [f"{m[k]:+.1%}" if k == "over rated" else f"{m[k]:.4g}" for k in keys]
        print(f"| {controller} | " + " | ".join(cells) + " |")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--decks", nargs="+", choices=sorted(DECKS), default=sorted(DECKS))
    p.add_argument("--wind", type=float, default=16.0)
    p.add_argument("--seconds", type=float, help="run length [s] (default 30 for nrel5mw, 60 for semi)")
    p.add_argument("--work", default="/tmp/mbsym_nmpc_start")
    p.add_argument("--wheel", default=str(WHEEL))
    args = p.parse_args()
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    table = run(args.decks, args.wind, work, Path(args.wheel), args.seconds)
    (work / "table.json").write_text(json.dumps(table, indent=1))


if __name__ == "__main__":
    main()
