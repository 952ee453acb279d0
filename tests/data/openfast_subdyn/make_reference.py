"""Regenerate the OpenFAST v5.0.0 SubDyn extracts of this folder (not run by the tests).

Usage (from anywhere)::

    python tests/data/openfast_subdyn/make_reference.py [--openfast PATH] [--deck DIR] [--work DIR]

``--deck`` is the ROSCO 2.10.6 wheel's ``IEA-15-240-RWT`` folder (default: mbsym's cache). Each case of
:data:`CASES` copies the IEA 15 MW monopile deck to ``WORK/<case>``, applies its edits (see README.md), runs
OpenFAST and writes ``<case>.json`` (summary-file matrices) and ``<case>.csv`` (time series) next to this script.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DECK = Path.home() / ".cache/mbsym/rosco/2.10.6/deck/IEA-15-240-RWT"
OPENFAST = Path("/work/shared/tools/openfast/openfast")
ROOT = "IEA-15-240-RWT-Monopile"

FST_EDITS = {"TMax": "2.0", "DT": "0.001", "CompInflow": "0", "CompAero": "0", "CompServo": "0", "CompSeaSt": "0",
             "CompHydro": "0", "OutFileFmt": "1", "OutFmt": '"ES16.8E2"'}
ED_EDITS = {"FlapDOF1": "False", "FlapDOF2": "False", "EdgeDOF": "False", "GenDOF": "False", "RotSpeed": "0.0",
            "PtfmSurge": "0.02", "PtfmSway": "-0.01", "PtfmHeave": "0.001", "PtfmRoll": "0.02",
            "PtfmPitch": "0.03", "PtfmYaw": "0.05", "TTDspFA": "0.3", "TTDspSS": "-0.1"}
ED_CHANNELS = ["PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll", "PtfmPitch", "PtfmYaw",
               "PtfmTVxi", "PtfmTVyi", "PtfmTVzi", "PtfmRVxi", "PtfmRVyi", "PtfmRVzi",
               "PtfmTAxi", "PtfmTAyi", "PtfmTAzi", "PtfmRAxi", "PtfmRAyi", "PtfmRAzi"]
SD_CHANNELS = ["Intf1FXss", "Intf1FYss", "Intf1FZss", "Intf1MXss", "Intf1MYss", "Intf1MZss",
               "Intf1TDXss", "Intf1TDYss", "Intf1TDZss", "Intf1RDXss", "Intf1RDYss", "Intf1RDZss",
               "Intf1TAXss", "Intf1TAYss", "Intf1TAZss", "Intf1RAXss", "Intf1RAYss", "Intf1RAZss"]

#: case -> (SubDyn file to start from (None: the deck's), SubDyn key edits, number of CB modes, merge the 1-mm members)
CASES = {
    "monopile": (None, {"OutAll": "True"}, 0, False),
    "monopile_cb": (None, {"Nmodes": "4", "JDampings": "1.0, 2.0, 3.0, 4.0", "GuyanDampMod": "1",
                           "RayleighDamp": "0.01, 0.002", "OutAll": "True"}, 4, False),
    "monopile_eb": (None, {"FEMMod": "1", "NDiv": "2", "OutAll": "True"}, 0, True),
    "tripod": (HERE / "tripod_SubDyn.dat", {"OutAll": "True"}, 6, False),
    "tripod_eb": (HERE / "tripod_SubDyn.dat", {"FEMMod": "1", "NDiv": "1", "Nmodes": "3", "GuyanDampMod": "0",
                                               "OutAll": "True"}, 3, False),
}


def edit_keys(path: Path, changes: dict[str, str]) -> None:
    """Replace the value(s) before each key (the first line whose tokens contain the key after a value)."""
    lines = path.read_text(encoding="latin-1").splitlines()
    for key, value in changes.items():
        for i, line in enumerate(lines):
            tokens = re.split(r"[\s,]+", line.strip())
            if key in tokens[1:] and not line.lstrip().startswith(("-", "=")):
                rest = line[line.index(key):]
                lines[i] = f"{value:<24} {rest}"
                break
        else:
            raise KeyError(f"{key} not in {path}")
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def replace_outlist(path: Path, start: str, channels: list[str]) -> None:
    """Replace the channel lines between the first line containing ``start`` and ``END``."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if start.lower() in line.lower())
    j = next(k for k in range(i + 1, len(lines)) if lines[k].strip()[:3].upper() == "END")
    lines[i + 1:j] = [f'"{c}"' for c in channels]
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def merge_short_members(path: Path, gap: float = 0.01) -> None:
    """Drop every joint closer than ``gap`` [m] to an earlier joint, re-link its members to that joint and
    drop the members that collapse (the IEA monopile's 1-mm members at the thickness steps)."""
    lines = path.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if "NJoints" in line)
    n = int(lines[i].split()[0])
    rows = [lines[i + 3 + k].split() for k in range(n)]
    kept, alias = [], {}
    for row in rows:
        xyz = np.array([float(v) for v in row[1:4]])
        twin = next((r for r in kept if np.linalg.norm(np.array([float(v) for v in r[1:4]]) - xyz) < gap), None)
        alias[row[0]] = twin[0] if twin else row[0]
        if twin is None:
            kept.append(row)
    lines[i] = f"{len(kept):>15}   NJoints     - Number of joints (-)"
    lines[i + 3:i + 3 + n] = ["   ".join(r) for r in kept]
    j = next(k for k, line in enumerate(lines) if "NMembers" in line)
    m = int(lines[j].split()[0])
    members = [lines[j + 3 + k].split() for k in range(m)]
    out = []
    for row in members:
        row[1], row[2] = alias[row[1]], alias[row[2]]
        if row[1] != row[2]:
            out.append(row)
    lines[j] = f"{len(out):>15}   NMembers    - Number of frame members"
    lines[j + 3:j + 3 + m] = ["   ".join(r) for r in out]
    path.write_text("\n".join(lines) + "\n", encoding="latin-1")


def parse_summary(path: Path) -> dict:
    """SubDyn's ``.SD.sum.yaml``: scalars, lists and matrices (rows ``- [a, b, ...]``) by name."""
    out, name, rows = {}, None, []
    number = re.compile(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?")
    for line in path.read_text().splitlines():
        stripped = line.strip()
        if stripped.startswith("- ["):
            rows.append([float(x) for x in number.findall(stripped.split("#")[0])])
            continue
        if name is not None:
            out[name] = np.array(rows) if rows else np.zeros((0, 0))
            name, rows = None, []
        match = re.match(r"^([A-Za-z_][\w\-^ ]*?)\s*:\s*(.*)$", line)
        if not match or line.startswith("#"):
            continue
        key, value = match.group(1).strip(), match.group(2).split("#")[0].strip()
        if value == "":
            name = key
        elif value.startswith("["):
            out[key] = np.array([float(x) for x in number.findall(value)])
        else:
            try:
                out[key] = float(value)
            except ValueError:
                out[key] = value
    if name is not None:
        out[name] = np.array(rows)
    return out


def _value(path: Path, key: str) -> str:
    """The value before ``key`` in an OpenFAST input file."""
    for line in path.read_text(encoding="latin-1").splitlines():
        tokens = line.split()
        if len(tokens) > 1 and tokens[1] == key:
            return tokens[0]
    raise KeyError(f"{key} not in {path}")


def read_out(path: Path) -> tuple[list[str], np.ndarray]:
    lines = path.read_text().splitlines()
    k = next(i for i, line in enumerate(lines) if line.split() and line.split()[0] == "Time")
    names = lines[k].split()
    data = np.array([[float(x) for x in line.split()] for line in lines[k + 2:] if line.strip()])
    return names, data


def run_case(case: str, deck: Path, work: Path, openfast: Path) -> None:
    sd_source, sd_edits, n_modes, merge = CASES[case]
    root = work / case
    if root.exists():
        shutil.rmtree(root)
    root.mkdir(parents=True)
    shutil.copytree(deck / "IEA-15-240-RWT", root / "IEA-15-240-RWT")
    run = root / ROOT
    shutil.copytree(deck / ROOT, run)
    sd = run / f"{ROOT}_SubDyn.dat"
    if sd_source is not None:
        shutil.copy(sd_source, sd)
    if merge:
        merge_short_members(sd)
    edit_keys(run / f"{ROOT}.fst", FST_EDITS)
    edit_keys(run / f"{ROOT}_ElastoDyn.dat", ED_EDITS)
    replace_outlist(run / f"{ROOT}_ElastoDyn.dat", "OutList", ED_CHANNELS)
    edit_keys(sd, {"SumPrint": "True", "NMOutputs": "0", **sd_edits})
    modal = [f"SSqm{i:02d}" for i in range(1, n_modes + 1)]
    modal += [f"SSqmd{i:02d}" for i in range(1, n_modes + 1)] + [f"SSqmdd{i:02d}" for i in range(1, n_modes + 1)]
    _drop_member_outputs(sd)
    replace_outlist(sd, "SSOutList", SD_CHANNELS + modal)
    log = subprocess.run([str(openfast), f"{ROOT}.fst"], cwd=run, capture_output=True, text=True)
    (run / "log.txt").write_text(log.stdout + log.stderr)
    if log.returncode != 0:
        raise RuntimeError(f"OpenFAST failed for {case}; see {run / 'log.txt'}")
    summary = parse_summary(run / f"{ROOT}.SD.sum.yaml")
    keep = ["Mass", "CM_point", "TP_point_x", "TP_point_y", "TP_point_z", "M_P", "KBBt", "MBBt", "CBBt",
            "GY_frequencies", "CB_frequencies", "TI", "MBM", "CMMdiag", "KMMdiag", "FG", "Nodes", "Elements"]
    extract = {k: np.asarray(summary[k]).tolist() for k in keep if k in summary}
    extract["Full_frequencies_first12"] = np.ravel(summary["Full_frequencies"])[:12].tolist()
    extract["gravity"] = float(_value(run / f"{ROOT}.fst", "Gravity"))
    extract["reference_point"] = [float(_value(run / f"{ROOT}_ElastoDyn.dat", k))
                                  for k in ("PtfmRefxt", "PtfmRefyt", "PtfmRefzt")]
    extract["case"] = case
    extract["openfast"] = "v5.0.0 (../shared/tools/openfast/openfast)"
    text = ",\n".join(f" {json.dumps(k)}: {json.dumps(v)}" for k, v in extract.items())
    (HERE / f"{case}.json").write_text("{\n" + text + "\n}\n")
    shutil.copy(sd, HERE / f"{case}.dat")
    names, data = read_out(run / f"{ROOT}.out")
    columns = ["Time"] + ED_CHANNELS + SD_CHANNELS + modal
    index = [names.index(c) for c in columns]
    rows = data[::50, index]
    header = ",".join(columns)
    np.savetxt(HERE / f"{case}.csv", rows, delimiter=",", header=header, comments="", fmt="%.8e")


def _drop_member_outputs(sd: Path) -> None:
    """Remove the member output rows (the cases set NMOutputs to 0)."""
    lines = sd.read_text(encoding="latin-1").splitlines()
    i = next(k for k, line in enumerate(lines) if "NMOutputs" in line)
    j = next(k for k in range(i + 1, len(lines)) if lines[k].lstrip().startswith("---"))
    lines[i + 1:j] = lines[i + 1:i + 3]  # keep the two header lines
    sd.write_text("\n".join(lines) + "\n", encoding="latin-1")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--openfast", type=Path, default=OPENFAST)
    parser.add_argument("--deck", type=Path, default=DECK)
    parser.add_argument("--work", type=Path, default=Path("/work/scratch/subdyn/runs"))
    parser.add_argument("cases", nargs="*", default=list(CASES))
    args = parser.parse_args()
    for case in args.cases:
        run_case(case, args.deck, args.work, args.openfast)
        print(f"{case}: done")


if __name__ == "__main__":
    main()
