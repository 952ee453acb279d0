"""The exported baseline library (``mbsym export-discon``) run inside OpenFAST, against the ROSCO reference run.

Case: the NREL 5 MW 10 → 14 m/s step of ``shared/openfast/aero`` (``step_10_14``: OpenFAST v5.0.0, ElastoDyn
GenDOF + TwFADOF1 + TwSSDOF1, AeroDyn 15, DT = 0.00625 s, 90 s), whose reference output ``step_10_14.csv`` was
made with the real ROSCO 2.10.6 library. Here the deck is copied to a temporary directory and:

1. ``mbsym export-discon step_10_14.fst --controller baseline --out lib`` builds the library from the deck
   (its ServoDyn's DISCON.IN and sample time), and its last output line (JSON) gives the two paths;
2. the copied ServoDyn file gets exactly those two paths as ``DLL_FileName`` and ``DLL_InFile`` (nothing
   else changes in the controller's configuration), the ``.fst`` text output (``OutFileFmt 1``, ``OutFmt ES24.15E3``: 16 digits) so
   that no binary reader is needed;
3. OpenFAST runs the case; its channels are compared with the ROSCO run's: max |Δ| and the r-test check
   ``isclose(test, ref, rtol=1e-2, atol=max(10**(floor(log10(range(ref)))-1.9), 1e-6))`` (TESTING.md).

Our baseline is ROSCO's scheme computed in double with the double sample time (ROSCO: its float32 DT) and
with the documented estimator-range difference of :mod:`mbsym.wind.control.baseline`, so close agreement,
not equality, is expected.

``--case ff14_flex``: the 660 s full-field turbulence case (14 m/s, flexible blades) of the same data set.

Run: ``python benchmarks/discon_export_openfast.py [--case step_10_14|ff14_flex] [--keep DIR]``; needs ../shared
(decks and the reference CSV), the OpenFAST binary ``../shared/tools/openfast/openfast`` and a C compiler;
exits with a message otherwise. Wall time ≈ 30 s for the 90 s case (OpenFAST ~3.5x real time).
"""

from __future__ import annotations

import argparse
import csv
import json
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared"
CHANNELS = ("BldPitch1", "GenTq", "GenPwr", "RotSpeed", "GenSpeed", "TTDspFA", "TwrBsMyt", "RtAeroFxh")


def _shared() -> Path:
    for parent in HERE.parents:
        if (parent / "shared" / "openfast" / "aero").is_dir():
            return parent / "shared"
    sys.exit("benchmarks/discon_export_openfast.py: ../shared/openfast/aero not found")


def _set_value(path: Path, key: str, value: str) -> None:
    text = path.read_text()
    text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m: f"{value}{m.group(1)}", text, count=1, flags=re.M)
    if n != 1:
        sys.exit(f"{path}: key {key} not found")
    path.write_text(text)


def _read_out(path: Path) -> dict[str, np.ndarray]:
    lines = path.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.split()[:1] == ["Time"])
    names = lines[start].split()
    rows = [line.split() for line in lines[start + 2:] if line.strip()]
    data = np.array(rows, dtype=float)
    return {n: data[:, j] for j, n in enumerate(names)}


def _read_csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {name.split("_[")[0]: data[:, j] for j, name in enumerate(rows[0])}


def _rtest(test: np.ndarray, ref: np.ndarray) -> bool:
    span = np.ptp(ref)
    atol = max(10 ** (np.floor(np.log10(span)) - 1.9), 1e-6) if span > 0 else 1e-6
    return bool(np.all(np.isfinite(test)) and np.all(np.isclose(test, ref, rtol=1e-2, atol=atol)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--case", default="step_10_14")
    parser.add_argument("--keep", metavar="DIR", help="work in DIR (kept) instead of a temporary directory")
    args = parser.parse_args()
    shared = _shared()
    aero = shared / "openfast" / "aero"
    openfast = shared / "tools" / "openfast" / "openfast"
    reference = aero / f"{args.case}.csv"
    if not openfast.is_file() or not reference.is_file():
        sys.exit(f"needs {openfast} and {reference}")
    work = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="mbsym_discon_of_"))
    work.mkdir(parents=True, exist_ok=True)
    inputs = aero / "openfast_inputs"
    for name in ("deck", args.case):                    # the shared layout, so relative paths hold
        if not (work / "openfast_inputs" / name).exists():
            shutil.copytree(inputs / name, work / "openfast_inputs" / name)
    if not (work / "wind").exists():
        (work / "wind").symlink_to(aero / "wind")       # full-field cases read ../../wind/*.bts
    fst = work / "openfast_inputs" / args.case / f"{args.case}.fst"
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "mbsym", "export-discon", str(fst), "--controller", "baseline",
                           "--out", str(work / "lib")], capture_output=True, text=True, cwd=HERE.parent)
    if proc.returncode != 0:
        sys.exit(f"mbsym export-discon failed: {proc.stderr.strip()}")
    exported = json.loads(proc.stdout.strip().splitlines()[-1])
    export_s = time.perf_counter() - t0
    servodyn = work / "openfast_inputs" / "deck" / "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"
    _set_value(servodyn, "DLL_FileName", f'"{exported["library"]}"')
    _set_value(servodyn, "DLL_InFile", f'"{exported["input"]}"')
    _set_value(fst, "OutFileFmt", "1")
    _set_value(fst, "OutFmt", '"ES24.15E3"')          # full double precision in the text output
    t0 = time.perf_counter()
    run = subprocess.run([str(openfast), fst.name], capture_output=True, text=True, cwd=fst.parent)
    run_s = time.perf_counter() - t0
    if run.returncode != 0 or "terminated normally" not in run.stdout:
        sys.exit(f"OpenFAST failed (exit {run.returncode}):\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}")
    ours = _read_out(fst.with_suffix(".out"))
    ref = _read_csv(reference)
    t = ref["Time"]
    print(f"case {args.case}: export {export_s:.1f} s, OpenFAST {run_s:.1f} s ({t[-1]:g} s simulated), "
          f"library {exported['library']}, sample time {exported['sample_time_s']:g} s")
    print(f"{'channel':<10} {'max |Δ|':>12} {'range(ref)':>12} {'r-test':>7}")
    for ch in CHANNELS:
        a = np.interp(t, ours["Time"], ours[ch])
        print(f"{ch:<10} {np.max(np.abs(a - ref[ch])):12.4g} {np.ptp(ref[ch]):12.4g} "
              f"{'pass' if _rtest(a, ref[ch]) else 'FAIL':>7}")
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
