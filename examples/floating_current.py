"""The VolturnUS-S in a current: the members' drag at rest and the mean surge it costs, over the current's speed.

A current (SeaState's ``CurrMod = 1``) loads a floating platform through the viscous drag of its Morison members
alone (HydroDyn: potential-flow bodies feel no steady flow). This example takes the strip-theory VolturnUS-S of
``examples/strip_theory_platform.py`` (columns and pontoons as members, ``C_d`` 0.6) next to the shared ``fl_decay_a``
deck, puts a uniform current along x into its SeaState file, and for each speed

* reads the drag on the platform at rest from the symbolic loads (``platform_hydrodynamics(...).load``), against
  the closed form ``½ ρ Σ C_d D L U²`` of the members' wetted lengths across the flow;
* finds the surge where the MoorDyn lines (quasi-static catenaries, ``mooring_from_moordyn``) hold that drag
  (CasADi's Newton rootfinder on the exact derivatives; pitch and heave held at rest — the decay of the full model
  in a current against OpenFAST is ``benchmarks/floating_morison.py --current``).

Run: ``python examples/floating_current.py [FLOATING_CASE_DIR]`` (default: the shared
``../shared/openfast/floating/cases/fl_decay_a``).
"""

from __future__ import annotations

import re
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

from mbsym.wind.deck import read_moordyn
from mbsym.wind.offshore import mooring_from_moordyn
from mbsym.wind.offshore.platform import platform_hydrodynamics

sys.path.insert(0, str(Path(__file__).resolve().parent))
from strip_theory_platform import COLUMNS, PONTOON_D, write_strip_deck  # noqa: E402

RHO, G, DEPTH = 1025.0, 9.81, 200.0


def current_sea(case: Path, speed: float) -> Path:
    """``case``'s SeaState file with a depth-independent current ``speed`` [m/s] along x (``CurrDIV``)."""
    text = next(case.glob("*_SeaState.dat")).read_text()
    for key, value in (("CurrMod", "1"), ("CurrSSV0", "0"), ("CurrSSDir", "0"), ("CurrNSV0", "0"),
                       ("CurrDIV", f"{speed:g}"), ("CurrDIDir", "0")):
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=value: f"{v:>12}{m.group(1)}", text, count=1,
                          flags=re.M)
        assert n == 1, key
    path = case / f"current_{speed:g}_SeaState.dat"
    path.write_text(text)
    return path


def closed_form_drag(speed: float) -> float:
    """½ ρ C_d Σ D L U² [N]: the four columns' 20 m below water and the three 40.5 m pontoons, of which only the flow
    across the axis drags (``|v_n| v_n`` along x: ``U² |sin θ|³`` for a pontoon at θ to the flow)."""
    columns = sum(d * 20.0 for _, d in COLUMNS)
    pontoons = sum(PONTOON_D * 40.5 * abs(s) ** 3 for s in (0.0, 0.8660254, -0.8660254))
    return 0.5 * RHO * 0.6 * (columns + pontoons) * speed ** 2


def main() -> int:
    default = Path(__file__).resolve().parents[2] / "shared" / "openfast" / "floating" / "cases" / "fl_decay_a"
    case = Path(sys.argv[1]) if len(sys.argv) > 1 else default
    if not case.is_dir():
        print(f"floating case not found: {case} (give the folder of an OpenFAST deck with HydroDyn and MoorDyn)")
        return 1
    work = Path(tempfile.mkdtemp(prefix="mbsym_current_"))
    here = work / "cases" / case.name                  # the deck's relative paths (../../<platform>/…) still hold
    shutil.copytree(case, here)
    for folder in case.parents[1].iterdir():
        if folder.is_dir() and folder.name != "cases":
            shutil.copytree(folder, work / folder.name, ignore=shutil.ignore_patterns("linearizations"))
    hydrodyn = write_strip_deck(here, here)
    moordyn = next((work / "IEA-15-240-RWT-UMaineSemi").glob("*_MoorDyn.dat"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lines = mooring_from_moordyn(read_moordyn(moordyn), water_density=RHO, gravity=G, line_dynamics=False)
    surge = ca.SX.sym("surge")
    q = ca.vertcat(surge, ca.DM.zeros(5))
    print(f"{'current [m/s]':>14s} {'drag at rest [kN]':>18s} {'closed form [kN]':>17s} {'mean surge [m]':>15s}")
    for speed in (0.25, 0.5, 0.75, 1.0, 1.5):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            hydro = platform_hydrodynamics(hydrodyn, water_density=RHO, gravity=G, water_depth=DEPTH,
                                           seastate=current_sea(here, speed))
        drag = float(hydro.morison.load(np.zeros(6), np.zeros(6))[0])
        balance = ca.Function("balance", [surge], [lines.load(q)[0] - lines.load(ca.DM.zeros(6))[0] + drag])
        offset = float(ca.rootfinder("offset", "newton", balance)(0.0))
        print(f"{speed:14.2f} {drag / 1e3:18.1f} {closed_form_drag(speed) / 1e3:17.1f} {offset:15.2f}")
    print(f"(files in {work})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
