"""AeroDyn's tower drag (``TwrAero``) on the rotor-effective floating turbine, against OpenFAST v5.

The drag pushes the VolturnUS-S downwind and tilts it: in OpenFAST (tests/data/openfast_floating_tower/README.md,
``drag_only`` minus ``tower_off``, means over 200-300 s) surge +0.587 m and platform pitch +0.092°. mbsym's
rotor-effective rung runs the same two copies of the deck (drag on and off) for 300 s; the shifts must agree
within 10 % (the rotor-effective rung's own offsets, −0.9 % in pitch, cancel in the difference; measured when
written: surge +0.48 m at 600 s, pitch +0.094°).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from .conftest import floating_case_copy

REF = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_tower" / "fl_steady_13_tower_ref.json"


def _deck(tmp_path: Path, drag: bool) -> Path:
    root = tmp_path / ("drag" if drag else "off")
    root.mkdir()
    return floating_case_copy(root, (("TwrPotent", "0"), ("TwrShadow", "0"), ("TwrAero", "True" if drag else "False"),
                                     ("UA_Mod", "0")))


@pytest.mark.slow
def test_tower_drag_shifts_the_floating_platform_as_in_openfast(tmp_path):
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    means = []
    for drag in (False, True):
        out = tmp_path / f"drag_{drag}.csv"
        assert main(["simulate", str(_deck(tmp_path, drag)), "--aero", "rotor", "--controller", "baseline",
                     "--tmax", "300", "--out", str(out)]) == 0
        ours = read_csv(out)
        last = np.asarray(ours.time) >= 200.0 - 1e-9
        means.append({c: float(np.asarray(ours.channel(c))[last].mean()) for c in ("PtfmSurge", "PtfmPitch")})
    ref = json.loads(REF.read_text())
    for name in ("PtfmSurge", "PtfmPitch"):
        want = ref["drag_only"]["means_200_300_s"][name] - ref["tower_off"]["means_200_300_s"][name]
        got = means[1][name] - means[0][name]
        assert got == pytest.approx(want, rel=0.10), (name, got, want)
