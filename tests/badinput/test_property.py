"""Property: a random deck with well-formed values either simulates (a short run whose output file
has every row) or is refused with one typed error line, never a traceback and never a partial file.

Random within the ElastoDyn value domains (flags, geometry, masses, initial conditions, gravity):
some combinations are physically refused (blades hitting the ground, a supersonic tip, ...),
which is an accepted outcome. Deterministic (the ``ci`` hypothesis profile of tests/conftest.py).
"""

from __future__ import annotations

import csv
import tempfile
from pathlib import Path

from hypothesis import event, given, settings
from hypothesis import strategies as st

from .conftest import copy_deck, run_cli, set_key

FLAGS = ("TwFADOF1", "TwSSDOF1", "TwFADOF2", "GenDOF", "DrTrDOF", "YawDOF", "PtfmSgDOF", "PtfmPDOF", "PtfmHvDOF",
         "TeetDOF", "FlapDOF1")
VALUES = {  # key: (low, high) of a uniform draw, in the deck's units
    "TowerHt": (55.0, 150.0), "RotSpeed": (0.0, 30.0), "TTDspFA": (-2.0, 2.0), "NacMass": (0.0, 5e5),
    "HubMass": (0.0, 1e5), "GBRatio": (1.0, 120.0), "PtfmMass": (0.0, 1e7), "ShftTilt": (-10.0, 10.0),
    "OverHang": (-10.0, 0.0), "NacYaw": (-30.0, 30.0), "Azimuth": (0.0, 359.0),
}


@settings(max_examples=10)
@given(flags=st.sets(st.sampled_from(FLAGS), max_size=4),
       values=st.fixed_dictionaries({k: st.floats(lo, hi, allow_nan=False) for k, (lo, hi) in VALUES.items()}),
       gravity=st.sampled_from(["0", "9.80665", "1e3"]))
def test_random_decks_simulate_or_are_refused(flags, values, gravity):
    with tempfile.TemporaryDirectory() as tmp:
        deck = copy_deck(Path(tmp))
        for flag in FLAGS + ("TwSSDOF2", "EdgeDOF", "FlapDOF2", "PtfmSwDOF", "PtfmRDOF", "PtfmYDOF"):
            set_key(deck.ed, flag, "True" if flag in flags else "False")
        for key, value in values.items():
            set_key(deck.ed, key, f"{value:.6g}")
        set_key(deck.fst, "Gravity", gravity)
        out = deck.dir / "out.csv"
        before = deck.files()
        code, stdout, err = run_cli(["simulate", deck.fst, "--tmax", "0.05", "--method", "rk4", "--dt", "0.01",
                                     "--out", out])
        assert "Traceback" not in err
        event(f"exit {code}: {err.strip().split(': ')[-1][:50]}")
        if code == 0:
            with out.open() as fh:
                rows = list(csv.reader(fh))
            assert len(rows) == 1 + 6 and all(len(r) == len(rows[0]) for r in rows)
        else:
            errors = [line for line in err.splitlines() if line.startswith("mbsym simulate: error:")]
            assert code == 2 and len(errors) == 1, err
            assert deck.files() == before
