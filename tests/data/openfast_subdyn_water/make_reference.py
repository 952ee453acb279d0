"""Regenerate the OpenFAST v5.0.0 extracts of this folder: HydroDyn's Morison loads on SubDyn's monopile (not run by
the tests).

Usage (from anywhere)::

    python tests/data/openfast_subdyn_water/make_reference.py [--openfast PATH] [--deck DIR] [--work DIR] [case ...]

``--deck`` is the ROSCO 2.10.6 wheel's deck folder holding ``IEA-15-240-RWT`` (default: mbsym's cache). Each case of
:data:`CASES` copies the whole ``IEA-15-240-RWT`` folder to ``WORK/<case>`` (default ``/work/scratch/hydro_sd``),
applies the edits of README.md (every ElastoDyn DOF off: the structure is held undisplaced), runs OpenFAST and writes
``<case>.csv`` next to this script, with the input files it used (``<variant>_HydroDyn.dat``,
``still|waves_SeaState.dat``, ``SubDyn.dat``).
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DECK = Path.home() / ".cache/mbsym/rosco/2.10.6/deck"
OPENFAST = Path("/work/shared/tools/openfast/openfast")
WORK = Path("/work/scratch/hydro_sd")
ROOT = "IEA-15-240-RWT-Monopile"


FST_EDITS = {"CompInflow": "0", "CompAero": "0", "CompServo": "0", "OutFileFmt": "1", "OutFmt": '"ES15.7E2"'}
ED_EDITS = {key: "False" for key in ("FlapDOF1", "FlapDOF2", "EdgeDOF", "GenDOF", "YawDOF", "TwFADOF1", "TwFADOF2",
                                     "TwSSDOF1", "TwSSDOF2", "PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF",
                                     "PtfmPDOF", "PtfmYDOF")} | {"RotSpeed": "0.0"}
HD_CHANNELS = ["HydroFxi", "HydroFyi", "HydroFzi", "HydroMxi", "HydroMyi", "HydroMzi"]
SD_CHANNELS = [f"{what}{c}ss" for what in ("Intf1", "React") for c in ("FX", "FY", "FZ", "MX", "MY", "MZ")]
SS_CHANNELS = ["Wave1Elev"]

#: case -> (TMax [s], SeaState WaveMod, HydroDyn variant (None: the deck's monopile; README.md), output decimation of
#: the 0.005 s steps)
CASES = {
    "still": ("1.0", "0", None, 20),
    "waves": ("100.0", "2", None, 40),
    "raised_still": ("1.0", "0", "raised", 20),
    "raised_waves": ("100.0", "2", "raised", 200),
    "cone_still": ("1.0", "0", "cone", 20),
    "cone_waves": ("100.0", "2", "cone", 40),
    "cone_cut_still": ("1.0", "0", "cone_cut", 20),
    "cone_cut_waves": ("100.0", "2", "cone_cut", 200),
}


def edit_keys(path: Path, changes: dict[str, str]) -> None:
    """Replace the value before each key (the first line whose second token is the key)."""
    lines = path.read_text(encoding="latin-1").splitlines()
    for key, value in changes.items():
        for i, line in enumerate(lines):
            tokens = line.split()
            if len(tokens) > 1 and tokens[1] == key:
                lines[i] = f"{value:<24} {line[line.index(key, len(tokens[0])):]}"
                break
        else:
            raise KeyError(f"{key} not in {path}")
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def replace_outlist(path: Path, start: str, channels: list[str]) -> None:
    """Replace the channel lines between the first line containing ``start`` and the next ``END``."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if start in line)
    j = next(k for k in range(i + 1, len(lines)) if lines[k].strip()[:3].upper() == "END")
    lines[i + 1:j] = [f'"{c}"' for c in channels]
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def read_out(path: Path) -> tuple[list[str], np.ndarray]:
    """Channel names and data of an OpenFAST text output."""
    lines = path.read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if line.split() and line.split()[0] == "Time")
    return lines[k].split(), np.array([[float(x) for x in line.split()] for line in lines[k + 2:] if line.strip()])


def insert_after(path: Path, key: str, line: str) -> None:
    """Insert ``line`` after the first line whose second token is ``key``."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, text in enumerate(lines) if len(text.split()) > 1 and text.split()[1] == key)
    lines.insert(i + 1, line)
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def upgrade_to_v5(run: Path) -> None:
    """The lines OpenFAST v5.0.0 (and mbsym's readers) need that the wheel's HydroDyn and SeaState files lack."""
    hd, sea = run / f"{ROOT}_HydroDyn.dat", run / f"{ROOT}_SeaState.dat"
    edit_keys(hd, {"RdtnDT": '"DEFAULT"'})
    insert_after(hd, "PtfmCOByt", "             0   NAddDOF        - Number of additional generalized DOFs (-)")
    insert_after(hd, "AMMod", "             0   HstMod         - Hydrostatic loads up to the still-water level (0)")
    insert_after(sea, "WaveStMod", "             0   WvCrntMod      - Wave-current interaction {0: none} (switch)")


def _table(path: Path, count_key: str, rows: list[str]) -> None:
    """Replace a HydroDyn table: its count line (``count_key``) and the rows after its two header lines."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if len(line.split()) > 1 and line.split()[1] == count_key)
    old = int(lines[i].split()[0])
    lines[i] = f"{len(rows):>14}   {count_key}" + lines[i].split(count_key, 1)[1]
    lines[i + 3:i + 3 + old] = rows
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def _axial(path: Path, row: str) -> None:
    """Replace the (single) axial-coefficient row."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if "NAxCoef" in line)
    lines[i + 3] = row
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def hydrodyn_variant(path: Path, variant: str | None) -> None:
    """The HydroDyn edits of README.md's variants."""
    if variant is None:
        return
    bottom = "-30.1000" if variant == "cone_cut" else "-29.0000"
    top = "2.00000" if variant.startswith("cone") else "0.00000"
    _table(path, "NJoints", [f"   1      0.00000     0.00000   {bottom}       1            0",
                             f"   2      {top}     0.00000    15.0000       1            0"])
    if not variant.startswith("cone"):
        return
    _table(path, "NPropSetsCyl", ["   1        10.0            0.055341", "   2         8.0            0.050000"])
    _table(path, "NMembers", ["    1         2          1           2            1             1            0"
                              "         0.5000      1          1       FALSE"])
    _table(path, "NMGDepths", ["    0.0      0.15       1100.0", "  -30.0      0.05       1100.0"])
    _axial(path, "    1     0.50     0.50     1.00      0        0.00       1.00")


def run_case(case: str, deck: Path, work: Path, openfast: Path) -> None:
    t_max, wave_model, variant, every = CASES[case]
    root = work / case
    if root.exists():
        shutil.rmtree(root)
    shutil.copytree(deck / "IEA-15-240-RWT", root / "IEA-15-240-RWT")
    run = root / "IEA-15-240-RWT" / ROOT
    upgrade_to_v5(run)
    edit_keys(run / f"{ROOT}.fst", FST_EDITS | {"TMax": t_max})
    edit_keys(run / f"{ROOT}_ElastoDyn.dat", ED_EDITS)
    edit_keys(run / f"{ROOT}_SeaState.dat", {"WaveMod": wave_model})
    hd = run / f"{ROOT}_HydroDyn.dat"
    replace_outlist(hd, "OUTPUT CHANNELS", HD_CHANNELS)
    hydrodyn_variant(hd, variant)
    replace_outlist(run / f"{ROOT}_SubDyn.dat", "SSOutList", SD_CHANNELS)
    began = time.perf_counter()
    log = subprocess.run([str(openfast), f"{ROOT}.fst"], cwd=run, capture_output=True, text=True)
    (run / "log.txt").write_text(log.stdout + log.stderr)
    if log.returncode != 0:
        raise RuntimeError(f"OpenFAST failed for {case}; see {run / 'log.txt'}")
    print(f"{case}: {time.perf_counter() - began:.0f} s")
    names, data = read_out(run / f"{ROOT}.out")
    columns = ["Time"] + SS_CHANNELS + HD_CHANNELS + SD_CHANNELS
    index = [names.index(c) for c in columns]
    np.savetxt(HERE / f"{case}.csv", data[::every, index], delimiter=",", header=",".join(columns), comments="",
               fmt="%.7e")
    shutil.copy(hd, HERE / f"{variant or 'monopile'}_HydroDyn.dat")
    shutil.copy(run / f"{ROOT}_SeaState.dat", HERE / f"{'waves' if wave_model != '0' else 'still'}_SeaState.dat")
    shutil.copy(run / f"{ROOT}_SubDyn.dat", HERE / "SubDyn.dat")
    summary = run / f"{ROOT}.HD.sum"
    if summary.exists():
        text = summary.read_text(encoding="latin-1")
        match = re.search(r"Total Buoyancy loads.*?Total\s*:[^\n]*", text, flags=re.S)
        if match:
            print(match.group(0))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--openfast", type=Path, default=OPENFAST)
    parser.add_argument("--deck", type=Path, default=DECK)
    parser.add_argument("--work", type=Path, default=WORK)
    parser.add_argument("cases", nargs="*", default=list(CASES))
    args = parser.parse_args()
    for case in args.cases:
        run_case(case, args.deck, args.work, args.openfast)


if __name__ == "__main__":
    main()
