"""The rotor-effective surfaces of a deck with the tower's inflow disturbance and UA_Mod 3 (docs/aero.md §6b): cost.

``RotorAero.from_openfast`` on the shared floating IEA 15 MW (``fl_steady_13``: TwrPotent 1, TwrShadow 1,
UA_Mod 3; 61 × 46 grid, 50 blade nodes) as written and on copies with the tower's disturbance, UA or both switched
off, best of ``--repeat`` runs each, with the ratio to the copy without either (the baseline of the same run).

    python benchmarks/deck_surfaces.py [--repeat 2]
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
FLOATING = HERE.parent.parent / "shared" / "openfast" / "floating"
AERODYN = "IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi_AeroDyn15.dat"


def _variant(root: Path, tower: bool, ua: bool) -> Path:
    for folder in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi"):
        shutil.copytree(FLOATING / folder, root / folder, ignore=shutil.ignore_patterns("linearizations", "HydroData"))
    shutil.copytree(FLOATING / "cases" / "fl_steady_13", root / "cases" / "fl_steady_13")
    path = root / AERODYN
    values = {"TwrPotent": "1" if tower else "0", "TwrShadow": "1" if tower else "0", "UA_Mod": "3" if ua else "0"}
    lines = [f"{values[line.split()[1]]}   {line.split()[1]}   -" if len(line.split()) > 1 and line.split()[1] in values
             else line for line in path.read_text().splitlines()]
    path.write_text("\n".join(lines) + "\n")
    return root / "cases" / "fl_steady_13" / "fl_steady_13.fst"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=2)
    args = ap.parse_args()
    from mbsym.wind.aero.rotor import RotorAero

    root = Path(tempfile.mkdtemp(prefix="mbsym_surfaces_"))
    rows, base = [], None
    for label, tower, ua in (("neither", False, False), ("the tower's disturbance", True, False),
                             ("UA_Mod 3", False, True), ("both (the deck as written)", True, True)):
        fst = _variant(root / label.split()[0], tower, ua)
        best = min(_timed(RotorAero.from_openfast, fst) for _ in range(max(1, args.repeat)))
        base = best if base is None else base
        rows.append(f"| {label} | {best:.2f} | {best / base:.2f} |")
    print("| surfaces with | wall s (best) | ratio to neither |\n|---|---|---|\n" + "\n".join(rows))
    return 0


def _timed(f, *args) -> float:
    t0 = time.perf_counter()
    f(*args)
    return time.perf_counter() - t0


if __name__ == "__main__":
    sys.exit(main())
