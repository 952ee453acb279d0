"""OpenFAST v5 linearizations of the operating NREL 5 MW (rigid blades) and their modes: the reference of
``linear_inflow.py`` and of tests/wind/operation/test_linear_inflow.py (issue 22, item 6).

Three steps, each a subcommand::

    python benchmarks/openfast_linear_inflow.py decks DIR [--wind 12,14,16,18] [--dbemt -1,0]
    python benchmarks/openfast_linear_inflow.py run DIR            # every DIR/lin_*/ with OpenFAST v5.0.0
    python benchmarks/openfast_linear_inflow.py modes DIR          # .lin -> tests/data/openfast_linear_inflow/modes.json

``decks`` writes one case per wind speed and ``DBEMT_Mod`` from the shared steady-state decks
(``shared/openfast/aero/openfast_inputs/steady_<U>``: GenDOF, TwFADOF1, TwSSDOF1, rigid blades, steady
airfoils, no tower influence) with these edits (tests/data/openfast_linear_inflow/README.md lists them):
linearization on (``Linearize``, ``CalcSteady``, ``TrimCase = 3`` pitch, ``TrimTol = 1e-3``,
``TrimGain = 0.001``, ``Twr_Kdmp = 5e4`` (a damper used only while the steady state is sought; OpenFAST
leaves it out of the linearization, FAST_Mapping.f90 ``MapCustom``), ``NLinTimes = 12``, ``LinInputs = 1``,
``LinOutputs = 0``, ``TMax = 300``); steady InflowWind (``WindType = 1``, ``HWindSpeed = U``); AeroDyn
``DBEMT_Mod`` -1 (frozen wake) or 0 (quasi-steady BEM); ServoDyn without the ROSCO library (``PCMode = 0``;
``VSContrl = 1``, simple variable speed, region 3 at 43 093.55 N m from 1161.963 rpm: the rated torque of the
other runs, constant above rated as ROSCO's constant-power torque is at the trim); initial conditions (pitch,
tower-top displacements) from the shared steady states (``steady_states.csv``).

``modes`` reads the ``.lin`` files (the A matrix at each of the 12 azimuths), applies MBC3 — here the
identity, since these cases have no rotating-frame states (no blade DOFs, no wake states) — averages A
over the azimuths, removes the azimuth state (its column averages to zero and its row is the rotor speed),
and labels the oscillatory eigenvalues by their largest tower coordinate (TFA1 or TSS1).
"""

from __future__ import annotations

import argparse
import csv
import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import shared_aero  # noqa: E402

OPENFAST_TOOLS = "tools/openfast/openfast"
TABLE = HERE.parent / "tests" / "data" / "openfast_linear_inflow" / "modes.json"
#: AeroDyn's DBEMT_Mod of each case -> mbsym's inflow choice it compares with.
INFLOW_OF_DBEMT = {-1: "frozen", 0: "quasi-steady", 3: "dynamic"}
_CASE = {-1: "frozen", 0: "qs", 3: "dbemt3"}


# ---------------------------------------------------------------------- decks
def _set(text: str, key: str, value: str) -> str:
    """Replace the value in front of ``key`` on its line (OpenFAST's ``value  key  - comment`` layout)."""
    pattern = re.compile(rf"^(\s*)(\S.*?)(\s+{re.escape(key)}\s)", re.M)
    new, n = pattern.subn(lambda m: f"{value:>12}   {key} ", text, count=1)
    if n != 1:
        raise SystemExit(f"key {key} not found")
    return new


def _steady_row(U: float) -> dict:
    with open(shared_aero() / "steady_states.csv") as f:
        for row in csv.DictReader(f):
            if abs(float(row["WindSpeed_[m/s]"]) - U) < 1e-9:
                return row
    raise SystemExit(f"no steady state at {U} m/s in steady_states.csv")


def make_deck(out: Path, U: float, dbemt: int) -> Path:
    """One linearization case ``out/lin_<U>_<frozen|qs|dbemt3>/`` (module docstring)."""
    src_root = shared_aero() / "openfast_inputs"
    src = src_root / f"steady_{U:g}"
    if not (out / "deck").is_dir():
        shutil.copytree(src_root / "deck", out / "deck")
    name = f"lin_{U:g}_{_CASE[dbemt]}"
    case = out / name
    case.mkdir(parents=True, exist_ok=True)
    fst = (src / f"steady_{U:g}.fst").read_text()
    for key, value in [("TMax", "300"), ("Linearize", "True"), ("CalcSteady", "True"), ("TrimCase", "3"),
                       ("TrimTol", "1e-3"), ("TrimGain", "0.001"), ("Twr_Kdmp", "5e4"), ("NLinTimes", "12"),
                       ("LinInputs", "1"), ("LinOutputs", "0"), ("SumPrint", "False"), ("OutFileFmt", "1"),
                       ("DT_Out", "0.5")]:
        fst = _set(fst, key, value)
    for old, new in [(f'"steady_{U:g}_ED.dat"', '"ED.dat"'), (f'"steady_{U:g}_IfW.dat"', '"IfW.dat"'),
                     ('"../deck/NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"', '"AD.dat"'),
                     ('"../deck/NRELOffshrBsline5MW_Onshore_ServoDyn.dat"', '"SrvD.dat"')]:
        fst = fst.replace(old, new)
    (case / f"{name}.fst").write_text(fst)
    ed = (src / f"steady_{U:g}_ED.dat").read_text()
    row = _steady_row(U)
    for key, col in [("TTDspFA", "TTDspFA_[m]"), ("TTDspSS", "TTDspSS_[m]"), ("BlPitch(1)", "BldPitch1_[deg]"),
                     ("BlPitch(2)", "BldPitch1_[deg]"), ("BlPitch(3)", "BldPitch1_[deg]")]:
        ed = _set(ed, key, f"{float(row[col]):.6f}")
    (case / "ED.dat").write_text(ed)
    ifw = _set(_set((src / f"steady_{U:g}_IfW.dat").read_text(), "WindType", "1"), "HWindSpeed", f"{U:g}")
    (case / "IfW.dat").write_text(ifw)
    ad = _set((src_root / "deck/NRELOffshrBsline5MW_Onshore_AeroDyn15.dat").read_text(), "DBEMT_Mod", str(dbemt))
    ad = ad.replace('"Airfoils/', '"../deck/Airfoils/').replace(
        '"NRELOffshrBsline5MW_AeroDyn_blade.dat"', '"../deck/NRELOffshrBsline5MW_AeroDyn_blade.dat"')
    (case / "AD.dat").write_text(ad)
    sd = (src_root / "deck/NRELOffshrBsline5MW_Onshore_ServoDyn.dat").read_text()
    for key, value in [("PCMode", "0"), ("VSContrl", "1"), ("VS_RtGnSp", "1161.963"), ("VS_RtTq", "43093.55"),
                       ("VS_Rgn2K", "0.0255764"), ("VS_SlPc", "10")]:
        sd = _set(sd, key, value)
    (case / "SrvD.dat").write_text(sd)
    return case


# ---------------------------------------------------------------------- .lin files
def read_lin(path: Path) -> dict:
    """The parts of an OpenFAST ``.lin`` file used here: ``rotor_speed`` [rad/s], ``azimuth`` [rad],
    ``wind_speed`` [m/s], ``states`` (description, operating point, rotating frame), ``inputs`` (same) and
    ``A`` (n_x, n_x)."""
    lines = Path(path).read_text().splitlines()
    out: dict = {}
    for key, label in (("rotor_speed", "Rotor Speed:"), ("azimuth", "Azimuth:"), ("wind_speed", "Wind Speed:"),
                       ("time", "Simulation time:")):
        line = next(ln for ln in lines if ln.strip().startswith(label))
        out[key] = float(line.split(":")[1].split()[0])
    out["states"] = _table(lines, "Order of continuous states:")
    out["inputs"] = _table(lines, "Order of inputs:")
    n = len(out["states"])
    start = next(i for i, ln in enumerate(lines) if ln.strip().startswith("A:"))
    out["A"] = np.array([[float(v) for v in lines[start + 1 + r].split()] for r in range(n)])
    return out


def _table(lines: list[str], title: str) -> list[dict]:
    i = next(k for k, ln in enumerate(lines) if ln.strip() == title) + 3
    rows = []
    while i < len(lines) and lines[i].strip():
        parts = lines[i].split(None, 4)
        rows.append({"op": float(parts[1]), "rotating": parts[2] == "T", "description": parts[4].strip()})
        i += 1
    return rows


def case_modes(case: Path, min_azimuths: int = 12) -> dict:
    """Azimuth-averaged modes of one case (module docstring); with ``min_azimuths`` < 12, of the complete
    ``.lin`` files written so far (``n_azimuths`` in the result says how many)."""
    files = sorted(case.glob("*.lin"), key=lambda p: int(p.suffixes[-2][1:]))
    lins = []
    for f in files:
        try:
            lins.append(read_lin(f))
        except (StopIteration, IndexError, ValueError):      # still being written
            continue
    if len(lins) < min_azimuths:
        raise SystemExit(f"{case}: {len(lins)} complete .lin files, expected {min_azimuths} (did OpenFAST finish?)")
    states = [s["description"] for s in lins[0]["states"]]
    if any(s["rotating"] for s in lins[0]["states"]):
        raise SystemExit(f"{case}: rotating-frame states {states}: MBC3 of blade states is not implemented here")
    A = np.mean([lin["A"] for lin in lins], axis=0)
    azimuth = [i for i, s in enumerate(states) if "DOF_GeAz" in s and "derivative" not in s]
    keep = [i for i in range(len(states)) if i not in azimuth]
    A = A[np.ix_(keep, keep)]
    names = [_short(states[i]) for i in keep]
    lam, V = np.linalg.eig(A)
    modes = {}
    for k in np.flatnonzero(lam.imag > 1e-6):
        tower = {n: abs(V[names.index(n), k]) for n in ("TFA1", "TSS1") if n in names}
        label = {"TFA1": "1st tower fore-aft", "TSS1": "1st tower side-side"}[max(tower, key=tower.get)]
        modes[label] = {"freq_hz": float(abs(lam[k]) / (2 * np.pi)), "damping_ratio": float(-lam[k].real / abs(lam[k]))}
    pitch = next(s["op"] for s in lins[0]["inputs"] if "collective blade-pitch command" in s["description"])
    return {"wind_speed": lins[0]["wind_speed"], "rotor_speed_rpm": float(np.mean([x["rotor_speed"] for x in lins])
                                                                          * 30 / np.pi),
            "pitch_deg": float(np.degrees(pitch)), "n_azimuths": len(lins),
            "azimuth_deg": [round(float(np.degrees(x["azimuth"])), 2) for x in lins],
            "linearization_time_s": float(lins[0]["time"]), "states": names, "modes": modes,
            "eigenvalues": [[float(v.real), float(v.imag)] for v in sorted(lam, key=lambda v: (abs(v), v.imag))]}


def _short(description: str) -> str:
    m = re.search(r"DOF_(\w+)\)", description)
    base = m.group(1) if m else description
    return base + "_d" if description.startswith("ED First time derivative") else base


def write_table(root: Path, path: Path = TABLE, min_azimuths: int = 12) -> dict:
    """Modes of every finished case under ``root`` to ``path`` (JSON)."""
    cases = []
    for case in sorted(root.glob("lin_*")):
        kind = case.name.split("_", 2)[2]
        dbemt = {v: k for k, v in _CASE.items()}[kind]
        cases.append({"case": case.name, "DBEMT_Mod": dbemt, "inflow": INFLOW_OF_DBEMT[dbemt], **case_modes(case, min_azimuths)})
    cases.sort(key=lambda c: (c["inflow"], c["wind_speed"]))
    table = {"source": "OpenFAST v5.0.0 linearizations (CalcSteady, NLinTimes 12) of the NREL 5 MW with rigid "
                       "blades; see README.md here and benchmarks/openfast_linear_inflow.py",
             "units": {"freq_hz": "Hz", "damping_ratio": "-", "rotor_speed_rpm": "rpm", "pitch_deg": "deg",
                       "eigenvalues": "rad/s (real, imag)"},
             "cases": cases}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(table, indent=1) + "\n")
    return table


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("step", choices=("decks", "run", "modes"))
    ap.add_argument("dir", type=Path)
    ap.add_argument("--wind", default="12,14,16,18")
    ap.add_argument("--dbemt", default="-1,0")
    ap.add_argument("--min-azimuths", type=int, default=12,
                    help="modes: accept cases with at least this many complete .lin files (default all 12)")
    args = ap.parse_args(argv)
    if args.step == "decks":
        for dbemt in (int(v) for v in args.dbemt.split(",")):
            for U in (float(v) for v in args.wind.split(",")):
                print(make_deck(args.dir, U, dbemt))
    elif args.step == "run":
        exe = shared_aero().parents[1] / OPENFAST_TOOLS
        procs = [subprocess.Popen([str(exe), f"{c.name}.fst"], cwd=c, stdout=open(c / "log.txt", "w"),
                                  stderr=subprocess.STDOUT) for c in sorted(args.dir.glob("lin_*"))]
        return max(p.wait() for p in procs)
    else:
        table = write_table(args.dir, min_azimuths=args.min_azimuths)
        for c in table["cases"]:
            print(c["case"], c["n_azimuths"], {k: (round(v["freq_hz"], 4), round(v["damping_ratio"], 4)) for k, v in c["modes"].items()})
    return 0


if __name__ == "__main__":
    sys.exit(main())
