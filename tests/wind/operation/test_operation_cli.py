"""``mbsym simulate`` contract for operating turbines (in-process), and its typed errors.

References: the OpenFAST channel names and units of the shared reference CSV headers
(``shared/openfast/aero/step_10_14.csv``); the steady state of the built-in turbine at 12 m/s (the
generator power of OpenFAST's 12 m/s steady state with peak shaving, 4951 kW, within 1 %); the
error contract of the CLI (exit status 2, one line naming the file, line or flag at fault).
"""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest

from _op_data import AERO, INPUTS, need
from mbsym.cli import main

STEP_DECK = INPUTS / "step_10_14" / "step_10_14.fst"


def _header(path):
    with open(path) as fh:
        return next(csv.reader(fh))


def test_builtin_steady_wind_writes_openfast_channels(tmp_path, capsys):
    out, png = tmp_path / "run.csv", tmp_path / "run.png"
    assert main(["simulate", "--wind", "steady:12", "--tmax", "3", "--stats", "--out", str(out), "--plot",
                 str(png)]) == 0
    assert png.stat().st_size > 10_000
    text = capsys.readouterr().out
    stats = json.loads(text.strip().splitlines()[-1])
    assert stats["method"] == "rk4" and stats["steps"] == 300 and stats["controller"] == "baseline"
    assert stats["integration_wall_s"] > 0 and stats["prepare_wall_s"] > 0
    assert "GenDOF" in text and "NREL 5 MW onshore (built-in)" in text
    header = _header(out)
    ref = _header(need(AERO / "step_10_14.csv"))
    for name in ("Wind1VelX", "RtVAvgxh", "RotSpeed", "GenSpeed", "BldPitch1", "GenTq", "GenPwr", "RotPwr",
                 "RotThrust", "RtAeroFxh", "RotTorq", "RtTSR", "RtAeroCp", "RtAeroCt", "TwrBsMyt", "TwrBsMxt",
                 "YawBrTAxp", "TTDspFA"):
        [ours] = [h for h in header if h.startswith(f"{name}_[")]
        [theirs] = [h for h in ref if h.startswith(f"{name}_[")]
        assert ours == theirs                                  # same name and unit as OpenFAST
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], np.arange(0, 3.0001, 0.05), atol=1e-9)
    gen_pwr = data[:, header.index("GenPwr_[kW]")]
    assert gen_pwr[-1] == pytest.approx(4951.4, rel=0.01)     # OpenFAST + ROSCO at 12 m/s


@pytest.mark.parametrize("extra", [["--controller", "none", "--wind", "step:10:12:1"],
                                   ["--wind", "kaimal:12:0.1:3"], ["--wind", "ramp:8:10:0.5:1.5"]])
def test_builtin_wind_forms_and_no_controller(extra, capsys):
    assert main(["simulate", "--tmax", "2", "--stats", *extra]) == 0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    if "none" in extra:                                        # no controller: the accuracy-driven default
        assert stats["controller"] == "none" and stats["error_estimate"] < 1e-3
    else:                                                      # one RK4 step per 0.01 s controller sample
        assert stats["controller"] == "baseline" and stats["steps"] == 200


def test_builtin_run_lasts_as_long_as_a_tabulated_wind(tmp_path, capsys):
    table = tmp_path / "short.csv"
    table.write_text("Time_[s],Wind1VelX_[m/s]\n0,9\n1.5,10\n")
    assert main(["simulate", "--wind", str(table), "--stats"]) == 0
    assert json.loads(capsys.readouterr().out.strip().splitlines()[-1])["steps"] == 150


def test_wind_files_as_spec(tmp_path, capsys):
    hh = need(AERO / "wind" / "step_10_14.hh")
    assert main(["simulate", "--wind", str(hh), "--tmax", "1", "--controller", "none"]) == 0
    table = tmp_path / "w.csv"
    table.write_text("Time_[s],Wind1VelX_[m/s]\n0,9\n0.5,9\n1,11\n")
    out = tmp_path / "o.csv"
    assert main(["simulate", "--wind", str(table), "--tmax", "1", "--out", str(out)]) == 0
    h = _header(out)
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[-1, h.index("Wind1VelX_[m/s]")], 11.0)


def test_deck_runs_its_inflowwind_and_discon_in_with_the_baseline(capsys):
    assert main(["simulate", str(need(STEP_DECK)), "--controller", "baseline", "--tmax", "1", "--stats"]) == 0
    out = capsys.readouterr().out
    assert "InflowWind" in out and "baseline every 0.00625 s" in out and "TwFADOF1, TwSSDOF1, GenDOF" in out
    assert json.loads(out.strip().splitlines()[-1])["steps"] == 160
    # the deck's ElastoDyn Method 3 (ABM4) is not modelled for the rotor-effective rung: the output says so
    assert "The deck asks ElastoDyn Method 3 (ABM4); this run integrates with rk4" in out


def test_deck_without_its_library_names_the_path_and_the_fix(capsys):
    assert main(["simulate", str(need(STEP_DECK)), "--tmax", "1"]) == 2
    err = capsys.readouterr().err
    assert "libdiscon.so" in err and "--discon" in err and "pip download" in err
    assert len(err.strip().splitlines()) == 1


def test_deck_runs_aerodyn_inflowwind_and_its_discon_library_without_flags(rosco_lib, tmp_path, capsys):
    """The shared deck laid out as its ServoDyn expects: ../rosco/lib/libdiscon.so next to the deck folder."""
    need(STEP_DECK)
    for folder in ("step_10_14", "deck"):
        (tmp_path / folder).mkdir()
        for f in (INPUTS / folder).iterdir():
            (tmp_path / folder / f.name).symlink_to(f)
    (tmp_path / "rosco" / "lib").mkdir(parents=True)
    (tmp_path / "rosco" / "lib" / "libdiscon.so").symlink_to(rosco_lib)
    assert main(["simulate", str(tmp_path / "step_10_14" / "step_10_14.fst"), "--tmax", "1", "--stats"]) == 0
    out = capsys.readouterr().out
    stats = json.loads(out.strip().splitlines()[-1])
    assert stats["controller"] == "discon" and "InflowWind" in out and "dynamic inflow" in out


def test_deck_with_the_rosco_library(rosco_lib, capsys):
    assert main(["simulate", str(need(STEP_DECK)), "--discon", str(rosco_lib), "--tmax", "1", "--stats"]) == 0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert stats["controller"] == "discon" and stats["steps"] == 160


@pytest.mark.parametrize("args, words", [
    (["--wind", "gust:3"], ["gust:3", "steady:U"]),
    (["--wind", "steady:12", "--method", "cvodes"], ["--method cvodes", "rk4"]),
    (["--wind", "steady:12", "--rtol", "1e-6"], ["--rtol"]),
    (["--controller", "discon", "--wind", "steady:12"], ["--discon", "no DISCON library"]),
    (["--wind", "steady:12", "--aero-dt", "0.025"], ["--aero-dt", "rotor-effective"]),
])
def test_bad_flags_are_one_line_errors(args, words, capsys):
    assert main(["simulate", "--tmax", "1", *args]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    for w in words:
        assert w in err


def test_bad_wind_file_names_file_and_line(tmp_path, capsys):
    bad = tmp_path / "bad.hh"
    bad.write_text("! header\n0.0 10 0 0 0 0 0 0 0\n1.0 ten 0 0 0 0 0 0 0\n")
    assert main(["simulate", "--wind", str(bad), "--tmax", "1"]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "line 3" in err


def test_bad_controller_file_names_file_and_line(tmp_path, capsys):
    text = need(INPUTS / "deck" / "DISCON.IN").read_text(encoding="latin-1")
    bad = tmp_path / "DISCON.IN"
    bad.write_text(text.replace("1.57080             ! F_LPFCornerFreq", "fast                ! F_LPFCornerFreq"),
                   encoding="latin-1")
    assert main(["simulate", "--wind", "steady:12", "--discon-input", str(bad), "--tmax", "1"]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "line 38" in err and "F_LPFCornerFreq" in err


def test_deck_without_aerodyn_is_refused_for_operation(capsys):
    case = need(AERO.parent / "cases" / "paper44_fa_gen" / "paper44_fa_gen.fst")
    assert main(["simulate", str(case), "--wind", "steady:8", "--tmax", "1"]) == 2
    assert "CompAero" in capsys.readouterr().err
