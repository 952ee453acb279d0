"""Another turbine as shipped: ROSCO 2.10.6's NREL 2.8-127 deck (GBoxEff 95.5 %, flexible blades, UA_Mod 3).

Reference: OpenFAST v5.0.0 with the ROSCO library, 60 s at 6 m/s (tests/data/openfast_stock_nrel2p8/README.md);
means over 30-60 s. Measured when written: RotSpeed -0.03 %, GenTq -0.05 %, GenPwr -0.07 %, RootMyc1 -0.21 %,
RootMxc1 -0.48 % of OpenFAST's. Tolerances (0.3 % rotor speed, 1 % torque, power and flap moment, 2 % edgewise
moment) are each missed by the same deck without its gearbox losses (OpenFAST: 1.44 %, 2.9 %, 4.3 %, 1.4 %, 10 %),
so the test fails if the losses are dropped. Until 2026-11-30 mbsym refused this deck (GBoxEff < 100 %).
"""

from __future__ import annotations

import io
import json
import shutil
from contextlib import redirect_stdout
from pathlib import Path

import numpy as np
import pytest

REF = Path(__file__).resolve().parents[2] / "data" / "openfast_stock_nrel2p8" / "nrel2p8_6ms_ref.json"
TOLERANCES = {"RotSpeed": 0.003, "GenTq": 0.01, "GenPwr": 0.01, "RootMyc1": 0.01, "RootMxc1": 0.02}


@pytest.fixture(scope="module")
def deck_and_lib():
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))
    import _rosco

    fst, lib = _rosco.rosco_test_case("NREL_2p8_127", "NREL-2p8-127.fst"), _rosco.rosco_library()
    if fst is None or lib is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    return fst, lib


def test_the_reference_needs_the_losses():
    """The tolerances below separate the shipped deck from the same deck without losses (OpenFAST itself)."""
    ref = json.loads(REF.read_text())
    lossy, lossless = ref["GBoxEff_95.5"]["means_30_60_s"], ref["GBoxEff_100"]["means_30_60_s"]
    for name, tol in TOLERANCES.items():
        assert abs(lossless[name] / lossy[name] - 1) > tol, name


@pytest.mark.slow
def test_stock_deck_matches_openfast(deck_and_lib, tmp_path, monkeypatch):
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst, lib = deck_and_lib
    monkeypatch.chdir(tmp_path)                       # the library's own log files land here
    deck = tmp_path / "deck"
    shutil.copytree(fst.parent, deck)
    out = tmp_path / "run.csv"
    with redirect_stdout(io.StringIO()):
        assert main(["simulate", str(deck / fst.name), "--discon", str(lib), "--tmax", "60", "--out", str(out)]) == 0
    ours = read_csv(out)
    late = np.asarray(ours.time) >= 30.0 - 1e-9
    ref = json.loads(REF.read_text())["GBoxEff_95.5"]["means_30_60_s"]
    for name, tol in TOLERANCES.items():
        assert np.asarray(ours.channel(name))[late].mean() == pytest.approx(ref[name], rel=tol), name


def test_power_based_tsr_tracking_trims_to_openfast(deck_and_lib, capsys):
    """The deck's ROSCO runs VS_ControlMode 3 (power-based TSR tracking: the speed reference is
    (P / VS_GenEff / VS_Rgn2K)^(1/3), P the measured electrical power; ROSCO's ControllerBlocks.f90). The trim at
    6 m/s against OpenFAST's 30-60 s mean (RotSpeed std 0.007 rpm there): within 1 % (measured -0.56 % on the
    rotor-effective rung; without VS_GenEff in the reference, as before 2026-11-30, -2.5 %)."""
    from mbsym.cli import main

    fst, _ = deck_and_lib
    assert main(["operating-points", str(fst), "--wind", "6", "--json"]) == 0
    result = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    ref = json.loads(REF.read_text())["GBoxEff_95.5"]["means_30_60_s"]
    assert result["RotSpeed"][0] == pytest.approx(ref["RotSpeed"], rel=0.01)
