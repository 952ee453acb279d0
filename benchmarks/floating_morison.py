"""Free decays of the floating IEA 15 MW with Morison members: accuracy against OpenFAST and cost.

The shared ``fl_decay_a`` with ``AddBQuad`` zeroed and members added (``write_deck`` of
tests/wind/offshore/test_offshore_morison.py: drag-only ``columns``, ``braces``, ``growth``; strip-theory ``strip``
(submerged), ``piercing`` (two more through the surface), ``strip_growth_uniform`` (with marine growth) and
``morison_only`` (``PotMod`` 0: the VolturnUS-S as strip-theory members); ``none`` without members), run 300 s with
``mbsym simulate`` (the default path) beside the OpenFAST v5.0.0 runs of the same decks
(tests/data/openfast_morison). Prints per deck the ε of surge, heave, pitch and TTDspFA against OpenFAST's
run of the same deck, the wall time of the run and its ratio to the run without members, measured in
the same process (the compiled model cached after the first run of each deck: the second of two runs is timed).
Then ``columns``, ``piercing``, ``morison_only`` and ``none`` in JONSWAP waves (``wave_deck``: Hs 4 m, Tp 10 s, first
order) against OpenFAST's ``waves`` run of ``columns`` and ``<deck>_waves`` of the others, their cost against the run
without members in the same waves. ε also of roll for the strip-theory decks (they roll).
With ``--current`` only the runs in SeaState's current (tests/wind/offshore/test_offshore_current.py's
``current_deck``: ``braces`` in still water, ``morison_only`` in the waves) against OpenFAST's runs with it, each
beside the same deck without the current (its ratio: the cost of the current).

    python benchmarks/floating_morison.py [--current]
"""

from __future__ import annotations

import contextlib
import csv
import io
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
DATA = HERE.parent / "tests" / "data" / "openfast_morison"
CHANNELS = ("PtfmSurge", "PtfmHeave", "PtfmPitch", "TTDspFA", "PtfmRoll")


def _reference(name: str) -> dict[str, np.ndarray]:
    with (DATA / f"{name}.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}


def _run(fst: Path, out: Path) -> float:
    from mbsym.cli import main

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        main(["simulate", str(fst), "--tmax", "300", "--out", str(out)])          # compiles and caches
        t0 = time.perf_counter()
        code = main(["simulate", str(fst), "--tmax", "300", "--out", str(out)])
    if code != 0:
        raise SystemExit(f"mbsym simulate {fst} failed ({code})")
    return time.perf_counter() - t0


def _eps(run, ref: dict) -> list:
    """ε of :data:`CHANNELS` against an OpenFAST reference (None where it lacks the channel)."""
    from mbsym.wind.analysis.compare import error_metrics

    return [error_metrics(run.time, run.channel(c), ref["Time"], ref[c])[0] if c in ref else None for c in CHANNELS]


def _current_rows(root: Path) -> list:
    """The decks in a current and without it, against OpenFAST's runs in the current."""
    from mbsym.wind.analysis.compare import read_csv
    from tests.wind.offshore.test_offshore_current import current_deck
    from tests.wind.offshore.test_offshore_morison import wave_deck, write_deck

    rows = []
    for variant, waves, ref_name in (("braces", False, "braces_current"),
                                     ("morison_only", True, "morison_only_current_waves")):
        plain = write_deck(root / f"{variant}_plain", variant)
        plain = wave_deck(plain) if waves else plain
        base = _run(plain, root / "plain.csv")
        label = f"{variant}{' in waves' if waves else ''}"
        rows.append((f"{label}, no current", ref_name, *_eps(read_csv(root / "plain.csv"), _reference(ref_name)),
                     base, 1.0))
        wall = _run(current_deck(root / f"{variant}_current", variant, waves), root / "current.csv")
        rows.append((f"{label} + current", ref_name, *_eps(read_csv(root / "current.csv"), _reference(ref_name)),
                     wall, wall / base))
    return rows


def main() -> int:
    from mbsym.wind.analysis.compare import read_csv
    from tests.wind.offshore.test_offshore_morison import wave_deck, write_deck

    root = Path(tempfile.mkdtemp(prefix="mbsym_morison_"))
    if "--current" in sys.argv[1:]:
        return _table(_current_rows(root), "ratio to no current")
    decks = ("columns", "braces", "growth", "strip", "piercing", "strip_growth_uniform", "morison_only")
    refs = {name: _reference(name) for name in decks}
    rows, base = [], None
    for variant in ("none", *decks):
        fst = write_deck(root / variant, variant)
        out = root / f"{variant}.csv"
        wall = _run(fst, out)
        base = wall if base is None else base
        run = read_csv(out)
        for ref_name, ref in refs.items():
            if variant != "none" and ref_name != variant:
                continue
            rows.append((variant, ref_name, *_eps(run, ref), wall, wall / base))
    wave_base = None                # in JONSWAP waves (WAVE_EDITS): the members' drag in the waves' velocity
    for variant, ref_name in (("none", "waves"), ("columns", "waves"), ("piercing", "piercing_waves"),
                              ("morison_only", "morison_only_waves")):
        fst = wave_deck(write_deck(root / f"{variant}_waves", variant))
        out = root / f"{variant}_waves.csv"
        wall = _run(fst, out)
        wave_base = wall if wave_base is None else wave_base
        run = read_csv(out)
        rows.append((f"{variant} in waves", ref_name, *_eps(run, _reference(ref_name)), wall, wall / wave_base))
    return _table(rows, "ratio to no members")


def _table(rows: list, ratio: str) -> int:
    print(f"| mbsym deck | OpenFAST run | ε surge | ε heave | ε pitch | ε TTDspFA | ε roll | wall [s] | {ratio} |")
    print("|---|---|---|---|---|---|---|---|---|")
    for variant, ref_name, *eps, wall, ratio in rows:
        print(f"| {variant} | {ref_name} | " + " | ".join("-" if e is None else f"{100 * e:.2f} %" for e in eps)
              + f" | {wall:.2f} | {ratio:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
