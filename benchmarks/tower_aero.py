"""Cost of AeroDyn's tower on the blade-element rung: the rotor's Function and the right-hand side, with and without.

The shared ``ff14_flex`` deck (NREL 5 MW, flexible blades, 3 x 19 AeroDyn nodes, DBEMT, full-field wind) as shipped
(`TwrPotent` 0: the baseline, measured in the same run) and on a copy with the tower's potential flow on (`TwrPotent`
1, the deck's own tower table; the drag, `TwrAero`, would need the field's tower points, which ff14's TurbSim file
does not have). Compiled Functions (``mbsym.codegen``,
gcc -O1) timed through ``Function.buffer``, median of repeated batches; instruction counts of the rotor's SX
Function. Accuracy of the same physics against OpenFAST: docs/blade_aero.md §5.

    python benchmarks/tower_aero.py [--no-write]
"""

from __future__ import annotations

import argparse
import re
import shutil
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import write_section  # noqa: E402
from blade_speed import INPUTS, aero_arguments, per_call_us, point  # noqa: E402


def _tower_copy(root: Path) -> Path:
    """A copy of the shared inputs with the tower's potential flow on; the ff14_flex .fst path."""
    shutil.copytree(INPUTS, root / "openfast_inputs")
    (root / "wind").symlink_to(INPUTS.parent / "wind")
    aerodyn = root / "openfast_inputs" / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    text = aerodyn.read_text()
    for key, value in (("TwrPotent", "1"),):
        text, n = re.subn(rf"^\s*\S+(\s+{key}\s)", rf"{value}\1", text, count=1, flags=re.M)
        assert n == 1, key
    aerodyn.write_text(text)
    return root / "openfast_inputs" / "ff14_flex" / "ff14_flex.fst"


def _costs(fst: Path) -> tuple[float, float, int]:
    """(rhs [µs], rotor Function [µs], its instructions) of the deck's blade-element model at 30 s."""
    from mbsym import codegen
    from mbsym.wind.operation.deck import operating_deck

    model = operating_deck(fst).model(aero="blade")
    d, x, u, p = point(model, {"WindTime": 30.0})
    rhs = per_call_us(codegen.compile_function(d.rhs).function, (x, u, p))
    aero = model._parts["blade_aero"]
    return rhs, per_call_us(codegen.compile_function(aero).function, aero_arguments(model, d, x)), \
        aero.n_instructions()


def _table(rows: list) -> str:
    """The markdown table of ``(label, rhs, rotor Function, instructions)`` rows, ratios to the first row."""
    base = rows[0]
    head = ("| ff14_flex, blade-element | rhs [µs] | vs baseline | rotor Function [µs] | vs baseline | its instructions |\n"
            "|---|---:|---:|---:|---:|---:|")
    return head + "".join(f"\n| {label} | {rhs:.1f} | {rhs / base[1]:.2f}× | {aero:.1f} | {aero / base[2]:.2f}× | {n} |"
                          for label, rhs, aero, n in rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true")
    no_write = parser.parse_args().no_write
    if INPUTS is None:
        raise SystemExit("shared/openfast/aero not found")
    rows = [("as shipped (no tower: baseline)", *_costs(INPUTS / "ff14_flex" / "ff14_flex.fst"))]
    with tempfile.TemporaryDirectory() as tmp:
        rows.append(("TwrPotent 1", *_costs(_tower_copy(Path(tmp)))))
    print(_table(rows))
    if not no_write:
        write_section("tower-aero", _table(rows))


if __name__ == "__main__":
    main()
