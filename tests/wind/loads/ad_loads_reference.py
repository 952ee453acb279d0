"""OpenFAST v5 with AeroDyn 15 as the reference for the load channels of the blade-element rotor (test reference only).

:func:`write_deck` copies the shared ``ss14_shear_flex`` case (``shared/openfast/aero/openfast_inputs``: NREL 5 MW,
flap 1-2, edge, drivetrain, generator, tower FA/SS 1-2; steady 14 m/s at 90 m with power-law shear 0.2) and its
``deck/`` folder, and changes what would give the rotor states that ElastoDyn does not write: AeroDyn's dynamic
wake off (``DBEMT_Mod = 0``: quasi-steady BEM, so the aerodynamic loads are a function of the structural state
and the wind), no ServoDyn (``CompServo = 0``: pitch fixed at 8.57 deg, no generator torque), and an OutList with
every DOF's ``Q_``/``QD_`` and the load channels (:data:`LOAD_CHANNELS`). The run starts undeflected, so the
blades and tower vibrate under the suddenly applied aerodynamic loads.
``python tests/wind/loads/ad_loads_reference.py`` runs OpenFAST (3 s, DT 6.25 ms, about 10 s of wall time) and
stores ``data/ad_loads_ss14.csv`` (one row every 0.25 s). The tests rebuild the same deck with :func:`write_deck`
and evaluate the blade-element model's channels at OpenFAST's states.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ed_loads_reference import DATA, SHARED, OPENFAST, _set  # noqa: E402

CASE = "ss14_shear_flex"
INPUTS = SHARED / "openfast" / "aero" / "openfast_inputs"
NAME = "ad_loads_ss14"
DOFS = ("B1F1", "B2F1", "B3F1", "B1E1", "B2E1", "B3E1", "B1F2", "B2F2", "B3F2", "DrTr", "GeAz",
        "TFA1", "TSS1", "TFA2", "TSS2")
LOAD_CHANNELS = tuple(f"RootF{a}c{k}" for a in "xyz" for k in (1, 2, 3)) + \
    tuple(f"RootF{a}b{k}" for a in "xy" for k in (1, 2, 3)) + \
    tuple(f"RootM{a}c{k}" for a in "xyz" for k in (1, 2, 3)) + \
    ("LSShftFxa", "LSShftFys", "LSShftFzs", "YawBrFxp", "YawBrFyp", "YawBrFzp", "YawBrMxp", "YawBrMyp", "YawBrMzp",
     "TwrBsMxt", "TwrBsMyt")
OUTLIST = tuple(f"{p}_{d}" for d in DOFS for p in ("Q", "QD")) + ("Azimuth", "BldPitch1", "RotSpeed") + LOAD_CHANNELS


def write_deck(folder: Path) -> Path:
    """Write ``deck/`` and ``<NAME>/`` into ``folder`` (see the module docstring); return the .fst."""
    shutil.copytree(INPUTS / "deck", folder / "deck")
    case = folder / NAME
    case.mkdir(parents=True)
    ad = folder / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    ad.chmod(0o644)
    ad.write_text(_set(ad.read_text(), "DBEMT_Mod", 0))
    ed = (INPUTS / CASE / f"{CASE}_ED.dat").read_text()
    channels = "\n".join(f'"{c}"' for c in OUTLIST)
    start = ed.index("OutList")
    start = ed.index("\n", start) + 1
    end = ed.index("\nEND", start)
    (case / f"{NAME}_ED.dat").write_text(ed[:start] + channels + ed[end:])
    shutil.copy(INPUTS / CASE / f"{CASE}_IfW.dat", case / f"{NAME}_IfW.dat")
    fst = (INPUTS / CASE / f"{CASE}.fst").read_text()
    for key, value in (("TMax", 3.0), ("CompServo", 0), ("DT_Out", 0.25), ("OutFileFmt", 1),
                       ("OutFmt", '"ES20.12E3"'), ("EDFile", f'"{NAME}_ED.dat"'), ("InflowFile", f'"{NAME}_IfW.dat"')):
        fst = _set(fst, key, value)
    path = case / f"{NAME}.fst"
    for p in (case / f"{NAME}_ED.dat", case / f"{NAME}_IfW.dat"):
        p.chmod(0o644)
    path.write_text(fst)
    return path


def main() -> None:
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        fst = write_deck(Path(tmp))
        proc = subprocess.run([str(OPENFAST), fst.name], cwd=fst.parent, capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            raise RuntimeError(f"OpenFAST failed: {proc.stdout[-3000:]}")
        lines = fst.with_suffix(".out").read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Time"))
    names = lines[start].split()
    data = np.array([[float(v) for v in line.split()] for line in lines[start + 2:] if line.strip()])
    keep = [i for i, n in enumerate(names) if n not in ("ConvIter", "ConvError", "NumUJac")]
    rows = [",".join(repr(float(row[i])) for i in keep) for row in data]
    (DATA / f"{NAME}.csv").write_text(",".join(names[i] for i in keep) + "\n" + "\n".join(rows) + "\n")
    print(f"{NAME}: {data.shape[0]} rows, {len(keep)} channels", file=sys.stderr)


if __name__ == "__main__":
    main()
