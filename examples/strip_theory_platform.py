"""A floating platform from strip theory alone: the VolturnUS-S without WAMIT data, against its potential-flow model.

Early in a design there are no panel-method data yet: HydroDyn can model the whole platform with Morison members
(``PotMod = 0``, every member ``PropPot = FALSE``), their buoyancy taken at the displaced waterline, their added
mass and wave inertia from strip theory. This example writes such a HydroDyn file for the IEA 15 MW's VolturnUS-S
(four columns and three pontoons of the rectangles' area, ``C_a = C_p = 1``, ``C_d`` 0.6) next to the shared
``fl_decay_a`` deck, and compares, from the symbolic loads (CasADi derivatives, no finite differences):

* the buoyancy and the hydrostatic stiffness (heave, roll, pitch) with the WAMIT ``.hst`` data HydroDyn uses;
* the added mass with WAMIT's infinite-frequency A∞.

Run: ``python examples/strip_theory_platform.py [FLOATING_CASE_DIR]`` (default: the shared
``../shared/openfast/floating/cases/fl_decay_a``). The decay of the same deck, against OpenFAST, is
``benchmarks/floating_morison.py``'s ``morison_only`` row (docs/offshore.md §2c).
"""

from __future__ import annotations

import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

from mbsym.wind.offshore.platform import platform_hydrodynamics

R_OUT, A, B = 51.75, 25.875, 44.81681                 # outer columns' distance and positions (Allen et al. 2020)
COLUMNS = [((0.0, 0.0), 10.0), ((-R_OUT, 0.0), 12.5), ((A, B), 12.5), ((A, -B), 12.5)]
PONTOON_Z, PONTOON_D = -14.725, 10.55                 # 12.5 m x 7 m pontoons as circles of the same area


def _tables() -> dict[str, list[str]]:
    """HydroDyn's member tables of the strip-theory VolturnUS-S (joint axial coefficients: set 2)."""
    joints, members = [], []
    for k, ((x, y), d) in enumerate(COLUMNS):
        joints += [f"{2 * k + 1} {x} {y} -20 2 0", f"{2 * k + 2} {x} {y} 15 2 0"]
        members.append(f"{k + 1} {2 * k + 1} {2 * k + 2} {1 if k == 0 else 2} {1 if k == 0 else 2} 1 0 1.0 1 1 FALSE")
    for k, (c, s) in enumerate(((-1.0, 0.0), (0.5, 0.8660254), (0.5, -0.8660254))):
        n = 9 + 2 * k
        joints += [f"{n} {5 * c} {5 * s} {PONTOON_Z} 2 0", f"{n + 1} {45.5 * c} {45.5 * s} {PONTOON_Z} 2 0"]
        members.append(f"{5 + k} {n} {n + 1} 3 3 1 0 2.0 1 1 FALSE")
    return {"NAxCoef": ["1 0 0 1 0 0 1", "2 0 1 1 0 0 1"], "NJoints": joints,
            "NPropSetsCyl": ["1 10.0 0.05", "2 12.5 0.05", f"3 {PONTOON_D} 0.05"], "NMembers": members}


def write_strip_deck(case: Path, out: Path) -> Path:
    """A copy of ``case``'s HydroDyn file with ``PotMod = 0``, no additional loads and the members of
    :func:`_tables`; the WAMIT files it names stay reachable (its relative paths resolved against ``case``)."""
    lines = next(case.glob("*_HydroDyn.dat")).read_text().splitlines()
    for key, rows in _tables().items():
        k = next(j for j, line in enumerate(lines) if line.split()[1:2] == [key])
        old = int(lines[k].split()[0])
        lines[k] = f"{len(rows)}   {key}"
        del lines[k + 3:k + 3 + old]
        lines[k + 3:k + 3] = rows
    k = next(j for j, line in enumerate(lines) if line.split()[1:2] == ["PotMod"])
    lines[k] = "0   PotMod"
    k = next(j for j, line in enumerate(lines) if line.split()[:1] == ["SimplCd"])
    lines[k + 2] = "0.6 0.6 1.0 1.0 1.0 1.0 0.0 0.0 1.0 1.0 1.0 1.0 1.0 1.0"
    k = next(j for j, line in enumerate(lines) if "AddBQuad" in line)
    for j in range(k, k + 6):
        lines[j] = "0 0 0 0 0 0"
    out.mkdir(parents=True, exist_ok=True)
    path = out / "strip_HydroDyn.dat"
    path.write_text("\n".join(lines) + "\n")
    return path


def stiffness(hydro) -> np.ndarray:
    """``−∂F/∂q`` of the platform's hydrostatic load at rest (CasADi's exact derivative)."""
    q = ca.SX.sym("q", 6)
    load = hydro.load(q, ca.DM.zeros(6))
    return -np.array(ca.Function("k", [q], [ca.jacobian(load, q)])(np.zeros(6)))


def main() -> int:
    default = Path(__file__).resolve().parents[2] / "shared" / "openfast" / "floating" / "cases" / "fl_decay_a"
    case = Path(sys.argv[1]) if len(sys.argv) > 1 else default
    if not case.is_dir():
        print(f"floating case not found: {case} (give the folder of an OpenFAST deck with HydroDyn)")
        return 1
    work = Path(tempfile.mkdtemp(prefix="mbsym_strip_"))
    here = work / "cases" / case.name                  # the deck's relative paths (../../<platform>/…) still hold
    shutil.copytree(case, here)
    for folder in case.parents[1].iterdir():
        if folder.is_dir() and folder.name != "cases":
            shutil.copytree(folder, work / folder.name, ignore=shutil.ignore_patterns("linearizations"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        wamit = platform_hydrodynamics(next(here.glob("*_HydroDyn.dat")), water_density=1025.0, gravity=9.81)
        strip = platform_hydrodynamics(write_strip_deck(here, here), water_density=1025.0, gravity=9.81)
    rows = [("buoyancy [MN]", wamit.hydrostatics.buoyancy / 1e6, strip.load(np.zeros(6), np.zeros(6))[2] / 1e6)]
    kw, ks = stiffness(wamit), stiffness(strip)
    for i, name, unit, scale in ((2, "heave stiffness", "MN/m", 1e6), (3, "roll stiffness", "GN m/rad", 1e9),
                                 (4, "pitch stiffness", "GN m/rad", 1e9)):
        rows.append((f"{name} [{unit}]", kw[i, i] / scale, ks[i, i] / scale))
    for i, name, unit, scale in ((0, "surge added mass", "t", 1e3), (2, "heave added mass", "t", 1e3),
                                 (4, "pitch added inertia", "1e9 kg m^2", 1e9)):
        rows.append((f"{name} [{unit}]", wamit.added_mass[i, i] / scale, strip.added_mass[i, i] / scale))
    print(f"{'':28s} {'WAMIT (PotMod 1)':>18s} {'strip theory (PotMod 0)':>24s}")
    for name, a, b in rows:
        print(f"{name:28s} {a:18.4g} {b:24.4g}")
    print(f"(files in {work}; its decay against OpenFAST: benchmarks/floating_morison.py, row morison_only)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
