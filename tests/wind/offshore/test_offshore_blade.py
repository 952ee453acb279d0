"""The blade-element rotor on the floating IEA 15 MW (VolturnUS-S): the deck's structure, platform, mooring and
controller with AeroDyn's BEM on every blade node, against OpenFAST v5 on the same deck with the same physics
(AeroDyn's unsteady aerodynamics and tower influence off, tests/data/openfast_floating_blade/README.md; and with
the deck's tower influence on: its potential flow, shadow and drag, tests/data/openfast_floating_tower/README.md).

Measured when written (300 s, steady 13 m/s, still water; means over 200-300 s): every mean within 0.33 % of
OpenFAST's (blade pitch +0.006°, platform pitch +0.19 %, TTDspFA +0.33 %), standard deviations after 100 s 4-17 %
above OpenFAST's. Before AeroDyn's curve angle (``BlCrvAng``, down to −5.8° at the prebent tip) tilted the nodes'
annulus (``blade_compose.annulus_axes``) the blade pitch was +0.12° (+1.5 %) and the platform pitch −1.0 %: the
bound on the blade pitch (0.05°) catches that.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from .conftest import floating_case_copy

REF = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_blade" / "fl_steady_13_blade_ref.json"
RELAXED = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_surge" / "fl_steady_13_relaxed_lines.csv"
TOWER_REF = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_tower" / "fl_steady_13_tower_ref.json"
_OFF = (("TwrPotent", "0"), ("TwrShadow", "0"), ("TwrAero", "False"), ("UA_Mod", "0"))


def _deck(tmp_path: Path, edits=_OFF) -> Path:
    """A copy of the shared floating decks with the reference run's AeroDyn edits; the fl_steady_13 .fst path."""
    return floating_case_copy(tmp_path, edits)


@pytest.mark.slow
def test_blade_element_rotor_on_the_floating_deck_tracks_openfast(tmp_path):
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst = _deck(tmp_path)
    out = tmp_path / "blade.csv"
    assert main(["simulate", str(fst), "--aero", "blade", "--controller", "baseline", "--tmax", "300",
                 "--out", str(out)]) == 0
    ours = read_csv(out)
    t = np.asarray(ours.time)
    ref = json.loads(REF.read_text())
    last, after = (t >= 200.0 - 1e-9), (t >= 100.0 - 1e-9)
    for name, want in ref["means_200_300_s"].items():
        y = np.asarray(ours.channel(name))
        if name == "BldPitch1":
            assert abs(y[last].mean() - want) < 0.05, (name, y[last].mean(), want)
        else:
            assert abs(y[last].mean() / want - 1.0) < 0.01, (name, y[last].mean(), want)
        ratio = y[after].std() / ref["std_100_300_s"][name]
        assert 0.75 < ratio < 1.3, (name, ratio)


@pytest.mark.slow
def test_blade_element_rotor_with_the_decks_tower_tracks_openfast(tmp_path):
    """The deck's AeroDyn as written but ``UA_Mod`` 0 (tower potential flow, Powles shadow and drag on): it runs
    on the blade-element rung by default. Without the potential flow the rotor's steady tilt moment (the 1P
    amplitude of ``RtFldMyh``) is 29 % below OpenFAST's (the 3 % bound catches it); without the drag the platform
    surges 2.8 % less (the 1 % bound on the means)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst = _deck(tmp_path, edits=(("UA_Mod", "0"),))
    out = tmp_path / "tower.csv"
    assert main(["simulate", str(fst), "--controller", "baseline", "--tmax", "300", "--out", str(out)]) == 0
    ours = read_csv(out)
    t = np.asarray(ours.time)
    ref = json.loads(TOWER_REF.read_text())["tower_on"]
    last, after = (t >= 200.0 - 1e-9), (t >= 100.0 - 1e-9)
    for name, want in ref["means_200_300_s"].items():
        if name == "RtFldMyh":
            continue                      # a 1P sine in the rotating hub axes: its mean is noise
        y = np.asarray(ours.channel(name))
        if name == "BldPitch1":
            assert abs(y[last].mean() - want) < 0.05, (name, y[last].mean(), want)
        else:
            assert abs(y[last].mean() / want - 1.0) < 0.01, (name, y[last].mean(), want)
    for name in ("RotSpeed", "BldPitch1"):
        ratio = np.asarray(ours.channel(name))[after].std() / ref["std_100_300_s"][name]
        assert 0.75 < ratio < 1.3, (name, ratio)
    # the rotor's steady tilt moment, a 1P sine of amplitude √2 σ in the hub axes (mbsym's RtAeroMyh, OpenFAST's
    # RtFldMyh [N-m]): the tower's potential flow raises it by 41 %
    tilt = np.asarray(ours.channel("RtAeroMyh"))[after].std() / ref["std_100_300_s"]["RtFldMyh"]
    assert abs(tilt - 1.0) < 0.03, tilt


@pytest.mark.slow
def test_the_shared_floating_deck_as_written_tracks_openfast(tmp_path):
    """The shared fl_steady_13 deck exactly as written (tower potential flow, shadow and drag, ``UA_Mod`` 3, MoorDyn's
    lines in motion and relaxed before t = 0 as MoorDyn relaxes them: the CLI's default for a MoorDyn deck) from the
    CLI, 600 s, against the shared OpenFAST v5.0.0 run of the same deck.

    The unsteady airfoils raise the rotor's steady tilt moment (σ of the 1P of ``RtFldMyh`` over 100-600 s) from
    1.402 to 1.631 MN m in OpenFAST; mbsym has 1.628 (1.400 with ``UA_Mod`` 0: the 1 % bound catches a run
    without UA). Means over 500-600 s within 0.15 % (observed within 0.01 %). The issue's ε ≤ 3 % after 100 s on
    PtfmSurge, PtfmPitch, RotSpeed, GenPwr and the fairlead tensions (observed 0.69, 0.40, 0.78, 0.78 and 0.62 /
    0.55 / 0.58 %; with the quasi-static lines, which start at rest while MoorDyn's swing, the growing 107 s surge
    oscillation takes another phase: 16.4, 4.7, 2.8, 2.8, 14.7 / 11.6 / 13.9 %)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    from .conftest import FLOATING

    fst = FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"
    ref_csv = FLOATING / "fl_steady_13.csv"
    if not ref_csv.is_file():
        pytest.skip(f"shared floating reference not found at {ref_csv}")
    out = tmp_path / "as_written.csv"
    assert main(["simulate", str(fst), "--controller", "baseline", "--tmax", "600", "--out", str(out)]) == 0
    ours, ref = read_csv(out), read_csv(ref_csv)
    t, tr = np.asarray(ours.time), np.asarray(ref.time)
    tilt = np.asarray(ours.channel("RtAeroMyh"))[t >= 100].std() / \
        np.asarray(ref.channel("RtFldMyh"))[tr >= 100].std()
    assert abs(tilt - 1.0) < 0.01, tilt
    for name in ("PtfmSurge", "PtfmHeave", "PtfmPitch", "RotSpeed", "BldPitch1", "FAIRTEN1", "TTDspFA", "TwrBsMyt"):
        mine, theirs = np.asarray(ours.channel(name))[t >= 500].mean(), np.asarray(ref.channel(name))[tr >= 500].mean()
        assert abs(mine / theirs - 1.0) < 0.0015, (name, mine, theirs)
    for name in ("PtfmSurge", "PtfmPitch", "RotSpeed", "GenPwr", "FAIRTEN1", "FAIRTEN2", "FAIRTEN3"):
        theirs = np.asarray(ref.channel(name))[tr >= 100]
        mine = np.interp(tr[tr >= 100], t, np.asarray(ours.channel(name)))
        eps = np.mean(np.abs(mine - theirs)) / np.ptp(theirs)
        assert eps < 0.03, (name, eps)


@pytest.mark.slow
def test_quasi_static_lines_track_openfast_with_relaxed_lines(tmp_path):
    """The deck as written with ``--mooring-lines quasi-static`` (the fast rung) against OpenFAST v5.0.0 run on the
    same deck with MoorDyn's initial relaxation taken to ``threshIC`` 1e-5 (``TmaxIC`` 300 s;
    tests/data/openfast_floating_surge/README.md), where MoorDyn's lines start at rest as quasi-static ones do:
    ε ≤ 3 % on PtfmSurge, PtfmPitch, RotSpeed, GenPwr after 100 s (observed 0.7, 1.1, 1.4, 1.4 %; with the continuous
    catenaries, whose surge period is 1.2 % longer than the 50-segment lines', 6.1, 2.3, 1.9, 1.9 %). The fairlead
    tensions lack MoorDyn's line dynamics (fluctuations faster than 10 s, std 2 kN): FAIRTEN1-3 within 5, 9 and 13 %
    (observed 4.2, 7.5, 11.6 % of ranges of 63, 23 and 15 kN)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    from .conftest import FLOATING

    fst = FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"
    if not fst.is_file():
        pytest.skip(f"shared floating deck not found at {fst}")
    out = tmp_path / "quasi_static.csv"
    assert main(["simulate", str(fst), "--controller", "baseline", "--mooring-lines", "quasi-static", "--tmax", "600",
                 "--out", str(out)]) == 0
    ours, relaxed = read_csv(out), read_csv(RELAXED)
    t, trr = np.asarray(ours.time), np.asarray(relaxed.time)
    for name, bound in (("PtfmSurge", 0.03), ("PtfmPitch", 0.03), ("RotSpeed", 0.03), ("GenPwr", 0.03),
                        ("FAIRTEN1", 0.05), ("FAIRTEN2", 0.09), ("FAIRTEN3", 0.13)):
        theirs = np.asarray(relaxed.channel(name))[trr >= 100]
        mine = np.interp(trr[trr >= 100], t, np.asarray(ours.channel(name)))
        eps = np.mean(np.abs(mine - theirs)) / np.ptp(theirs)
        assert eps < bound, (name, eps)
