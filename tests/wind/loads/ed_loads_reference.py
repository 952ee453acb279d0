"""OpenFAST v5 ElastoDyn's internal-load channels as the reference for the load cuts (test reference only).

:func:`write_deck` copies the shared NREL 5 MW ElastoDyn-only base deck (``shared/openfast/NREL5MW``: every
DOF of the onshore turbine on: flap 1-2, edge, drivetrain, generator, yaw, tower FA/SS 1-2) and sets a
moving, pitched, yawed start (:data:`EDITS`: tip deflections, tower-top displacements, 12 rpm, 8 deg pitch,
6 deg yaw, 30 deg azimuth, a 20 t yaw-bearing mass that must *not* appear in the yaw-bearing loads) and an
OutList with every DOF's ``Q_``/``QD_``/``QD2_`` and the load channels (:data:`LOAD_CHANNELS`).
Two cases (:data:`CASES`): the yaw DOF free (no yaw spring without ServoDyn, so ``YawBrMzp`` is zero) and
the yaw DOF off (the bearing carries the yaw moment). ``python tests/wind/loads/ed_loads_reference.py`` runs
OpenFAST (ElastoDyn only, no aerodynamics, 3 s, about 1 s of wall time each) and stores ``data/<case>.csv``
(OpenFAST's names, one row every 0.25 s). The tests rebuild the same decks with :func:`write_deck` and
evaluate mbsym's channels at OpenFAST's states.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"
#: Case name -> ElastoDyn keys changed on top of :data:`EDITS`.
CASES = {"ed_loads_free_yaw": {}, "ed_loads_fixed_yaw": {"YawDOF": "False"}}


def _shared() -> Path:
    for parent in HERE.parents:
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return HERE.parents[3].parent / "shared"


SHARED = _shared()
BASE = SHARED / "openfast" / "NREL5MW"
OPENFAST = SHARED / "tools" / "openfast" / "openfast"
FST, ED = "NREL5MW_Onshore_ElastoDynOnly.fst", "NREL5MW_ElastoDyn_Onshore.dat"
FILES = (FST, ED, "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat", "NRELOffshrBsline5MW_Blade.dat")

#: ElastoDyn keys changed from the base deck.
EDITS = {"OoPDefl": 2.0, "IPDefl": -0.5, "BlPitch(1)": 8.0, "BlPitch(2)": 8.0, "BlPitch(3)": 8.0, "Azimuth": 30.0,
         "RotSpeed": 12.0, "NacYaw": 6.0, "TTDspFA": 0.4, "TTDspSS": -0.2, "YawBrMass": 20000.0}
#: The DOFs of the base deck (OpenFAST's channel names ``Q_<dof>``).
DOFS = ("B1F1", "B2F1", "B3F1", "B1E1", "B2E1", "B3E1", "B1F2", "B2F2", "B3F2", "DrTr", "GeAz", "Yaw",
        "TFA1", "TSS1", "TFA2", "TSS2")
#: ElastoDyn's load channels checked (kN, kN-m).
LOAD_CHANNELS = tuple(f"Root{q}{a}c{k}" for q in "FM" for a in "xyz" for k in (1, 2, 3)) + \
    tuple(f"Root{q}{a}b{k}" for q in "FM" for a in "xy" for k in (1, 2, 3)) + \
    ("LSShftFxa", "LSShftFys", "LSShftFzs", "RotThrust", "YawBrFxp", "YawBrFyp", "YawBrFzp", "YawBrMxp",
     "YawBrMyp", "YawBrMzp", "TwrBsMxt", "TwrBsMyt")
OUTLIST = tuple(f"{p}_{d}" for d in DOFS for p in ("Q", "QD", "QD2")) + ("Azimuth", "BldPitch1") + LOAD_CHANNELS


def _set(text: str, key: str, value) -> str:
    pattern = re.compile(rf"^(\s*)(\S+)(\s+{re.escape(key)}\s)", re.MULTILINE)
    if not pattern.search(text):
        raise KeyError(key)
    return pattern.sub(lambda m: f"{m.group(1)}{value}{m.group(3)}", text, count=1)


def write_deck(folder: Path, case: str) -> Path:
    """Write the reference deck into ``folder`` (see the module docstring); return its .fst."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in FILES:
        shutil.copy(BASE / name, folder / name)
        (folder / name).chmod(0o644)
    ed = (folder / ED).read_text()
    for key, value in {**EDITS, **CASES[case]}.items():
        ed = _set(ed, key, value)
    channels = "\n".join(f'"{c}"' for c in OUTLIST)
    ed = re.sub(r"(OutList.*?\n).*?(\nEND)", lambda m: m.group(1) + channels + m.group(2), ed, flags=re.S)
    (folder / ED).write_text(ed)
    fst = (folder / FST).read_text()
    for key, value in (("TMax", 3.0), ("DT_Out", 0.25), ("OutFileFmt", 1), ("OutFmt", '"ES20.12E3"')):
        fst = _set(fst, key, value)
    (folder / FST).write_text(fst)
    return folder / FST


def run(folder: Path, case: str) -> tuple[list[str], np.ndarray]:
    """Run OpenFAST on the deck of :func:`write_deck` in ``folder``: channel names and rows."""
    fst = write_deck(folder, case)
    proc = subprocess.run([str(OPENFAST), fst.name], cwd=folder, capture_output=True, text=True, timeout=300)
    if proc.returncode != 0:
        raise RuntimeError(f"OpenFAST failed: {proc.stdout[-2000:]}")
    lines = fst.with_suffix(".out").read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Time"))
    names = lines[start].split()
    data = np.array([[float(v) for v in line.split()] for line in lines[start + 2:] if line.strip()])
    return names, data


def read_reference(case: str) -> dict[str, np.ndarray]:
    """The stored reference of ``case``: channel name -> values (one per row)."""
    path = DATA / f"{case}.csv"
    with open(path) as f:
        names = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {n: data[:, i] for i, n in enumerate(names)}


def main() -> None:
    import tempfile

    DATA.mkdir(exist_ok=True)
    for case in CASES:
        with tempfile.TemporaryDirectory() as tmp:
            names, data = run(Path(tmp), case)
        keep = [i for i, n in enumerate(names) if n not in ("ConvIter", "ConvError", "NumUJac")]
        rows = [",".join(repr(float(row[i])) for i in keep) for row in data]
        (DATA / f"{case}.csv").write_text(",".join(names[i] for i in keep) + "\n" + "\n".join(rows) + "\n")
        print(f"{case}: {data.shape[0]} rows, {len(keep)} channels", file=sys.stderr)


if __name__ == "__main__":
    main()
