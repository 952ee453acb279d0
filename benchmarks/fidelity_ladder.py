"""Model no more than a scene needs: a fidelity ladder on the paper45 scene, vs the richest model and OpenFAST.

Scene: the paper45 deck (NREL 5 MW, TTDspFA = TTDspSS = 1 m, 5 rpm, 60 s, gravity, no aero).
Ladder (ElastoDyn flags, ``mbsym.wind.analysis.fidelity.fidelity_ladder``): FA1 -> + SS1 -> + GenDOF ->
+ DrTrDOF -> + EdgeDOF -> + FlapDOF1 -> + FlapDOF2 (the richest, 13 DOFs). A rung without
GenDOF spins the rotor at the deck's constant 5 rpm (prescribed azimuth). Outputs: TTDspFA,
TTDspSS, RotSpeed. Errors: ε = mean|y - y_ref| / range(y_ref) per channel against the richest
rung and against OpenFAST v5's output of the deck (whose DOFs are FA1 + SS1 + Gen: rung 3).
Cost: integration wall time, rk4 at OpenFAST's DT = 0.01 s, compiled (``compile=True``).

Writes ``benchmarks/figures/fidelity_ladder_paper45.png`` and the table into
``benchmarks/README.md`` between the ``fidelity:start``/``fidelity:end`` markers.

Run: ``python benchmarks/fidelity_ladder.py [--no-write]``.
"""

from __future__ import annotations

import argparse

from mbsym.wind import read_openfast
from mbsym.wind.analysis.compare import read_csv
from mbsym.wind.analysis.fidelity import fidelity_ladder

from work_precision import HERE, SHARED, write_readme

CASE = "paper45_fa_ss_gen"
LADDER = (
    ("TwFADOF1",),
    ("TwFADOF1", "TwSSDOF1"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF", "EdgeDOF"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF", "EdgeDOF", "FlapDOF1"),
    ("TwFADOF1", "TwSSDOF1", "GenDOF", "DrTrDOF", "EdgeDOF", "FlapDOF1", "FlapDOF2"),
)
OUTPUTS = ("TTDspFA", "TTDspSS", "RotSpeed")
TOLERANCES = (0.01, 0.001)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    args = parser.parse_args()
    deck = SHARED / CASE / f"{CASE}.fst"
    turbine, reference = read_openfast(deck), read_csv(deck.with_suffix(".csv"))
    ladder = fidelity_ladder(turbine, LADDER, outputs=OUTPUTS, tmax=60.0, reference=reference, method="rk4",
                             dt=0.01, compile=True, tolerance=TOLERANCES[0])
    ladder.plot(HERE / "figures" / "fidelity_ladder_paper45.png",
                title="paper45 scene, 60 s: error of each rung vs cost (rk4, dt = 0.01 s, compiled)")
    lines = [ladder.table(), ""]
    for tol in TOLERANCES:
        for against in ("richest", "reference"):
            r = ladder.smallest(tol, against=against)
            what = "the richest rung" if against == "richest" else "OpenFAST"
            lines.append(f"- all three outputs within ε ≤ {tol:g} of {what}: "
                         + (f"**{r.label}** ({r.n_dofs} DOFs)" if r else "none"))
        for out in OUTPUTS:
            hit = next((r for r in ladder.rungs if r.ok and r.errors[out] <= tol), None)
            lines.append(f"  - {out} alone within ε ≤ {tol:g} of the richest rung: "
                         + (f"{hit.label} ({hit.n_dofs} DOFs)" if hit else "none"))
    text = "\n".join(lines)
    print(text)
    if not args.no_write:
        write_readme("fidelity", text)


if __name__ == "__main__":
    main()
