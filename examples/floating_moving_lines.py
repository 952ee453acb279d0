"""MoorDyn's lines in motion against quasi-static ones: the floating IEA 15 MW's first 20 s at 13 m/s.

The shared ``fl_steady_13`` deck (VolturnUS-S, MoorDyn with three 50-segment lines, steady 13 m/s, still water) is
run twice on the rotor-effective rung with mbsym's baseline controller: with the lines quasi-static (their shapes
follow the platform at once, their drag and inertia on that shape) and with MoorDyn's lumped masses in motion,
relaxed before t = 0 as MoorDyn relaxes them (docs/offshore.md §3c). It prints the relaxation (how long, whether it
met the deck's ``threshIC``), the cost of each run and, against the shared OpenFAST run of the same deck, the
largest difference of surge and of the upwind fairlead tension over the first 20 s: the moving lines carry MoorDyn's
start (the lines still swinging at t = 0) and the tensions' fast part; the quasi-static ones start at rest (measured:
surge within 0.005 m against 0.11 m, FAIRTEN1 within 6 kN against 18 kN).

Run: ``python examples/floating_moving_lines.py [FLOATING_DIR]`` (default: the shared ``../shared/openfast/floating``).
"""

from __future__ import annotations

import dataclasses
import sys
import warnings
from pathlib import Path

import numpy as np

from mbsym.wind.control import BaselineController
from mbsym.wind.operation.controllers import baseline_in_loop
from mbsym.wind.operation.deck import operating_deck
from mbsym.wind.operation.simulation import simulate_turbine

#: [s] the start, where MoorDyn's relaxation shows (later the rotor-effective rung's own differences from OpenFAST's
#: blade-element rotor grow: docs/offshore.md §3c)
TMAX = 20.0


def run(fst: Path, lines: str):
    """The deck's rotor-effective model with its MoorDyn lines ``lines`` ("quasi-static" or "dynamic"), TMAX s."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        deck = dataclasses.replace(operating_deck(fst), mooring_lines=lines)
        model = deck.model(aero="rotor")
    controller = baseline_in_loop(BaselineController(deck.baseline_settings()))
    return simulate_turbine(model, deck.wind(), TMAX, controller=controller, t_out=np.arange(0.0, TMAX + 1e-9, 0.05))


def main() -> None:
    floating = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).resolve().parents[2] / "shared" / \
        "openfast" / "floating"
    fst = floating / "cases" / "fl_steady_13" / "fl_steady_13.fst"
    ref = np.genfromtxt(floating / "fl_steady_13.csv", delimiter=",", names=True)
    keep = ref["Time_s"] <= TMAX
    print("| mooring lines | integration [s] | max |surge error| [m] | max |FAIRTEN1 error| [kN] |")
    print("|---|---|---|---|")
    for lines in ("quasi-static", "dynamic"):
        res = run(fst, lines)
        t = np.asarray(res.t)
        surge = np.interp(ref["Time_s"][keep], t, np.asarray(res.output("PtfmSurge")))
        tension = np.interp(ref["Time_s"][keep], t, np.asarray(res.output("FAIRTEN1")))
        e_s = np.max(np.abs(surge - ref["PtfmSurge_m"][keep]))
        e_t = np.max(np.abs(tension - ref["FAIRTEN1_N"][keep])) / 1e3
        print(f"| {lines} | {res.statistics['integration_wall_s']:.2f} | {e_s:.4f} | {e_t:.1f} |")
        if "lines_relaxed_s" in res.statistics:
            print(f"  (MoorDyn's relaxation: {res.statistics['lines_relaxed_s']:.1f} s, converged: "
                  f"{res.statistics['lines_relaxation_converged']})")


if __name__ == "__main__":
    main()
