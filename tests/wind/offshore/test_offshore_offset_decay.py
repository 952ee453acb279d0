"""The slow surge oscillation about an offset platform against OpenFAST + MoorDyn (issue 20).

The mooring's surge stiffness grows with the offset, so the floating IEA 15 MW's slow surge period depends on
where the rotor's thrust holds the platform. ``fl_decay_a`` (no wind, still water) is held at the offsets of
the operating ``fl_steady_13`` run (16.04 m and 16.49 m, pitch 2.75° and 2.87°) by a constant load in
HydroDyn's ``AddF0`` and released 0.6 m downwind of them. OpenFAST v5.0.0 ran the same two decks twice
(tests/data/openfast_floating_surge/README.md, ``offset_decays``): with the deck's MoorDyn lines (50 segments,
``dtM`` 1 ms) and with 100 segments (``dtM`` 0.2 ms). The 50-segment lines lie down on the seabed one node at a
time as the platform moves, and the upwind line's stiffness ripples by ±4-5 % about the continuous catenary's
(docs/offshore.md §7): their periods are 107.85 s and 105.91 s, with 100 segments 108.71 s and 107.26 s.

- The default (``mooring_statics="lumped"``: the deck's 50 segments at rest) against the deck's run: periods
  within 0.3 % (observed −0.07 % and −0.08 %; the continuous catenaries are +0.5 % and +1.4 % off) and mean
  surge within 0.01 m (observed 0.000 and 0.001 m).
- The continuous catenaries (the limit of many segments) against the 100-segment run: periods within 0.5 %
  (observed −0.34 % and +0.10 %), mean surge within 0.01 m (observed 0.000 m at both). Slow.

8-13 s per run (the CLI's compiled run; 21 s for two with an empty library cache).
"""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from .conftest import FLOATING

CASE = FLOATING / "cases" / "fl_decay_a"
DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_surge" / "slow_surge.json"
pytestmark = pytest.mark.skipif(not CASE.is_dir(), reason=f"shared floating deck not found at {CASE}")


def _offset_deck(tmp_path: Path, run: dict) -> Path:
    """A copy of the shared floating decks with fl_decay_a's AddF0 and initial platform position set from ``run``."""
    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi", "cases"):
        shutil.copytree(FLOATING / name, tmp_path / name)
    case = tmp_path / "cases" / "fl_decay_a"
    hydro = case / "fl_decay_a_HydroDyn.dat"
    lines = hydro.read_text().splitlines()
    first = next(i for i, line in enumerate(lines) if re.search(r"\sAddF0\s", line))
    for k, value in enumerate(run["add_f0"]):         # AddF0: one value per line, the key on the first
        rest = lines[first + k].split(None, 1)
        lines[first + k] = f"{value:16.1f}   " + (rest[1] if len(rest) > 1 else "")
    hydro.write_text("\n".join(lines) + "\n")
    elasto = case / "fl_decay_a_ED.dat"
    text = elasto.read_text()
    for key, value in run["initial"].items():
        text, n = re.subn(rf"^\s*\S+(\s+{key}\s)", rf"{value:10.4f}\1", text, count=1, flags=re.M)
        assert n == 1, key
    elasto.write_text(text)
    return case / "fl_decay_a.fst"


def _period_and_mean(t: np.ndarray, surge: np.ndarray) -> tuple[float, float]:
    """Period [s] and mean [m] of a decaying surge oscillation: c + A exp(-s t) cos(w t + phi) over t >= 50 s."""
    from scipy.optimize import least_squares

    keep = t >= 50.0
    tt, xx = t[keep][::4], surge[keep][::4]

    def residual(p):
        c, a, s, w, phase = p
        return c + a * np.exp(-s * (tt - 50.0)) * np.cos(w * tt + phase) - xx

    fits = [least_squares(residual, [xx.mean(), 0.5, 0.005, 2 * np.pi / 110.0, phase])
            for phase in np.linspace(0.0, 2 * np.pi, 8, endpoint=False)]
    c, _, _, w, _ = min(fits, key=lambda q: q.cost).x
    return float(2 * np.pi / abs(w)), float(c)


@pytest.mark.parametrize("name, statics, lines, reference, tolerance", [
    ("near_16.04m", "lumped", "quasi-static", "openfast_deck", 0.003),
    ("near_16.49m", "lumped", "quasi-static", "openfast_deck", 0.003),
    pytest.param("near_16.04m", "continuous", "quasi-static", "openfast_100_segments", 0.005, marks=pytest.mark.slow),
    pytest.param("near_16.49m", "continuous", "quasi-static", "openfast_100_segments", 0.005, marks=pytest.mark.slow),
    pytest.param("near_16.04m", "lumped", "dynamic", "openfast_deck", 0.001, marks=pytest.mark.slow),
    pytest.param("near_16.49m", "lumped", "dynamic", "openfast_deck", 0.001, marks=pytest.mark.slow)])
def test_surge_period_about_an_offset_against_moordyn(tmp_path, monkeypatch, name, statics, lines, reference,
                                                      tolerance):
    """The statics rows run the quasi-static lines (``--mooring-lines quasi-static``). MoorDyn's moving lines (the
    CLI's default, docs/offshore.md §3c) against the deck's own OpenFAST runs: within 0.1 % (observed 107.87 and
    105.93 s against 107.85 and 105.91 s, +0.02 %; the lumped statics alone −0.07 / −0.08 %)."""
    from mbsym.cli import main
    from mbsym.wind.offshore import operating

    monkeypatch.setattr(operating, "DEFAULT_MOORING_STATICS", statics)
    run = json.loads(DATA.read_text())["offset_decays"]["runs"][name]
    fst = _offset_deck(tmp_path, run)
    out = tmp_path / "decay.csv"
    assert main(["simulate", str(fst), "--mooring-lines", lines, "--out", str(out)]) == 0
    header = out.read_text().split("\n", 1)[0].split(",")
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    period, mean = _period_and_mean(data[:, 0], data[:, header.index("PtfmSurge_[m]")])
    openfast = run[reference]
    assert period == pytest.approx(openfast["period_s"], rel=tolerance), (period, openfast)
    assert abs(mean - openfast["mean_surge_m"]) < 0.01, (mean, openfast["mean_surge_m"])
