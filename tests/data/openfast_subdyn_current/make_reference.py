"""Regenerate the OpenFAST v5.0.0 extracts of this folder: SeaState's steady current on HydroDyn's monopile members
over SubDyn's substructure (not run by the tests).

Usage (from anywhere)::

    python tests/data/openfast_subdyn_current/make_reference.py [--openfast PATH] [--deck DIR] [--work DIR] [case ...]

``--deck`` is the ROSCO 2.10.6 wheel's deck folder holding ``IEA-15-240-RWT`` (default: mbsym's cache). The script
copies that ``IEA-15-240-RWT`` folder once to ``WORK`` (default ``/work/scratch/s24/mono_current``), brings its
HydroDyn and SeaState files to OpenFAST v5's format (``../openfast_subdyn_water/make_reference.py``'s
``upgrade_to_v5``), and for each case of :data:`CASES` writes ``<case>.fst`` and its own ElastoDyn, SeaState,
HydroDyn and SubDyn copies next to the deck's (README.md's edits), runs OpenFAST and writes ``<case>.csv`` here.
"""

from __future__ import annotations

import argparse
import importlib.util
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("_water_reference", HERE.parent / "openfast_subdyn_water" /
                                               "make_reference.py")
water = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(water)

DECK = water.DECK
OPENFAST = water.OPENFAST
WORK = Path("/work/scratch/s24/mono_current")
ROOT = water.ROOT

#: SeaState's current of every case: a 1/7-power sub-surface part along x, a near-surface part at 45 deg and a
#: depth-independent part at -90 deg.
CURRENT = {"CurrMod": "1", "CurrSSV0": "0.8", "CurrSSDir": "0.0", "CurrNSRef": "20.0", "CurrNSV0": "0.5",
           "CurrNSDir": "45.0", "CurrDIV": "0.2", "CurrDIDir": "-90.0"}
NO_CURRENT = {"CurrMod": "0"}
HELD = water.ED_EDITS
RELEASED = {"TTDspFA": "1.0", "TTDspSS": "0.5", "RotSpeed": "0.0"}
HELD_CHANNELS = ["Wave1Elev"] + water.HD_CHANNELS + water.SD_CHANNELS
DECAY_CHANNELS = ["PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch", "ReactFXss", "ReactMXss", "ReactMYss", "HydroFxi",
                  "HydroMyi"]

#: case -> (TMax [s], WaveMod, current keys, ElastoDyn edits, channels stored, stored up to [s], output decimation
#: of the 5 ms steps); the runs' full outputs stay in WORK
CASES = {
    "held_still": ("1.0", "0", CURRENT, HELD, HELD_CHANNELS, 1.0, 20),
    "held_waves": ("100.0", "2", CURRENT, HELD, HELD_CHANNELS, 100.0, 100),
    "decay": ("60.0", "0", CURRENT, RELEASED, DECAY_CHANNELS, 30.0, 20),
    "decay_nocurrent": ("60.0", "0", NO_CURRENT, RELEASED, DECAY_CHANNELS, -1.0, 20),   # for comparison only
    "wdecay": ("60.0", "2", CURRENT, RELEASED, DECAY_CHANNELS + ["Wave1Elev"], 30.0, 20),
    # the deck operating in its sea with the current (AeroDyn, ServoDyn with ROSCO's library): a benchmark, its
    # output left in WORK (not stored here)
    "operating": ("100.0", "2", CURRENT, {}, [], -1.0, 20),
}
OPERATING_CHANNELS = ["RotSpeed", "GenPwr", "BldPitch1", "PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch",
                      "TwrBsMxt", "TwrBsMyt", "RootMyc1", "Wave1Elev"]
DISCON = Path.home() / ".cache/mbsym/rosco/2.10.6/rosco/lib/libdiscon.so"


def prepare(deck: Path, work: Path) -> Path:
    """The deck copied once to ``work`` and brought to v5's format; returns its monopile folder."""
    run = work / "IEA-15-240-RWT" / ROOT
    if not run.exists():
        shutil.copytree(deck / "IEA-15-240-RWT", work / "IEA-15-240-RWT")
        water.upgrade_to_v5(run)
    return run


def case_files(run: Path, case: str) -> Path:
    """Write ``<case>.fst`` and its edited module files into ``run``; returns the ``.fst``."""
    t_max, wave_model, current, ed_edits = CASES[case][:4]
    files = {}
    for module, key in (("ElastoDyn", "EDFile"), ("SeaState", "SeaStFile"), ("HydroDyn", "HydroFile"),
                        ("SubDyn", "SubFile")):
        files[key] = run / f"{case}_{module}.dat"
        shutil.copy(run / f"{ROOT}_{module}.dat", files[key])
    fst = run / f"{case}.fst"
    shutil.copy(run / f"{ROOT}.fst", fst)
    fst_edits = water.FST_EDITS if ed_edits else {k: v for k, v in water.FST_EDITS.items() if "Comp" not in k}
    water.edit_keys(fst, fst_edits | {"TMax": t_max} | {k: f'"{p.name}"' for k, p in files.items()})
    if ed_edits:
        water.edit_keys(files["EDFile"], ed_edits)
    else:                                        # operating: the controller's library, ElastoDyn's channels
        servo = run / f"{case}_ServoDyn.dat"
        shutil.copy(run / f"{ROOT}_ServoDyn.dat", servo)
        water.edit_keys(servo, {"DLL_FileName": f'"{DISCON}"'})
        water.edit_keys(fst, {"ServoFile": f'"{servo.name}"'})
    water.edit_keys(files["SeaStFile"], {"WaveMod": wave_model} | current)
    water.replace_outlist(files["HydroFile"], "OUTPUT CHANNELS", water.HD_CHANNELS)
    if ed_edits is RELEASED:
        water.replace_outlist(files["EDFile"], "OutList", ["PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll",
                                                          "PtfmPitch", "PtfmYaw", "TwrBsMxt", "TwrBsMyt"])
    water.replace_outlist(files["SubFile"], "SSOutList", water.SD_CHANNELS)
    return fst


def run_case(case: str, deck: Path, work: Path, openfast: Path) -> None:
    run = prepare(deck, work)
    fst = case_files(run, case)
    began = time.perf_counter()
    log = subprocess.run([str(openfast), fst.name], cwd=run, capture_output=True, text=True)
    (run / f"{case}.log").write_text((log.stdout + log.stderr).replace("\r", "\n"))
    if log.returncode != 0:
        raise RuntimeError(f"OpenFAST failed for {case}; see {run / f'{case}.log'}")
    print(f"{case}: {time.perf_counter() - began:.0f} s")
    write_extract(case, run)


def write_extract(case: str, run: Path) -> None:
    """``<case>.csv`` (and the held cases' input files) here from the run's output in ``run``."""
    _, _, _, _, channels, t_store, every = CASES[case]
    if t_store < 0:
        return
    names, data = water.read_out(run / f"{case}.out")
    columns = ["Time"] + channels
    rows = data[::every][data[::every, 0] <= t_store + 1e-9]
    np.savetxt(HERE / f"{case}.csv", rows[:, [names.index(c) for c in columns]], delimiter=",",
               header=",".join(columns), comments="", fmt="%.7e")
    if case.startswith("held"):
        for module in ("SeaState", "HydroDyn", "SubDyn"):
            shutil.copy(run / f"{case}_{module}.dat", HERE / f"{case}_{module}.dat")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--openfast", type=Path, default=OPENFAST)
    parser.add_argument("--deck", type=Path, default=DECK)
    parser.add_argument("--work", type=Path, default=WORK)
    parser.add_argument("--extract-only", action="store_true", help="rewrite the CSVs from the outputs in WORK")
    parser.add_argument("cases", nargs="*", default=list(CASES))
    args = parser.parse_args()
    for case in args.cases:
        if args.extract_only:
            write_extract(case, args.work / "IEA-15-240-RWT" / ROOT)
        else:
            run_case(case, args.deck, args.work, args.openfast)


if __name__ == "__main__":
    main()
