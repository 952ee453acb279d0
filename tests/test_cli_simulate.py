"""`mbsym simulate` contract: flags, CSV layout, statistics, errors (issue 4, issue 7 flags)."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from mbsym.cli import main

SHARED = Path(__file__).resolve().parents[1].parent / "shared" / "openfast" / "cases"


def test_builtin_default_runs(capsys):
    assert main(["simulate", "--tmax", "1.0"]) == 0
    out = capsys.readouterr().out
    assert "NREL 5 MW onshore (built-in" in out and "Q_TFA1" in out


def test_deck_out_csv_has_openfast_channels(tmp_path, capsys):
    case = SHARED / "paper45_fa_ss_gen"
    if not case.exists():
        pytest.skip("shared OpenFAST reference data not available")
    out = tmp_path / "x.csv"
    assert main(["simulate", str(case / "paper45_fa_ss_gen.fst"), "--tmax", "2", "--out", str(out)]) == 0
    with out.open() as fh:
        header = next(csv.reader(fh))
    with (case / "paper45_fa_ss_gen.csv").open() as fh:
        ref_header = next(csv.reader(fh))
    assert header[0] == "Time_[s]"
    assert set(ref_header) <= set(header), set(ref_header) - set(header)
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(np.diff(data[:, 0]), 0.02, atol=1e-9)      # the deck's DT_Out
    assert data[-1, 0] == pytest.approx(2.0)


def test_dt_sets_output_spacing(tmp_path):
    out = tmp_path / "y.csv"
    assert main(["simulate", "--tmax", "0.5", "--dt", "0.05", "--out", str(out), "--method", "rk4"]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], np.arange(0, 0.5001, 0.05), atol=1e-9)


def test_list_methods_and_stats(capsys):
    assert main(["simulate", "--list-methods"]) == 0
    methods = capsys.readouterr().out.split()
    assert {"rk4", "cvodes", "scipy-radau"} <= set(methods)
    assert main(["simulate", "--tmax", "0.5", "--method", "rk4", "--stats"]) == 0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert stats["method"] == "rk4" and stats["steps"] == 50
    assert stats["integration_wall_s"] > 0 and stats["prepare_wall_s"] > 0


def test_compare_and_plot(tmp_path, capsys):
    case = SHARED / "paper44_fa_gen"
    if not case.exists():
        pytest.skip("shared OpenFAST reference data not available")
    png = tmp_path / "p.png"
    assert main(["simulate", str(case / "paper44_fa_gen.fst"), "--tmax", "5", "--compare",
                 str(case / "paper44_fa_gen.csv"), "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert "Q_TFA1" in out and "ε [%]" in out and png.stat().st_size > 1000


@pytest.mark.parametrize("argv, message", [
    (["simulate", "no_such_deck.fst"], "no_such_deck.fst"),
    (["simulate", "--tmax", "-1"], "--tmax = -1 s must be a positive finite time"),
    (["simulate", "--tmax", "0.1", "--method", "euler"], "euler"),
])
def test_bad_input_exits_nonzero_with_one_line(argv, message, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err


@pytest.mark.parametrize("extra, message", [
    (["--out", "/no/such/dir/x.csv"], "does not exist"),
    (["--plot", "x.notanimage"], "unsupported image type"),
    (["--compare", "no_such.csv"], "no_such.csv"),
    (["--tmax", "abc"], "invalid float value"),
])
def test_file_and_usage_errors_before_any_work(extra, message, capsys):
    """Bad destinations, references and usage fail at once: nothing on stdout, one line on stderr."""
    assert main(["simulate", "--tmax", "0.1", *extra]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert len(captured.err.strip().splitlines()) == 1 and message in captured.err


def test_compare_without_time_overlap_is_an_error(tmp_path, capsys):
    ref = tmp_path / "ref.csv"
    ref.write_text("Time_[s],Q_TFA1_[m]\n100,0.1\n101,0.2\n")
    assert main(["simulate", "--tmax", "0.2", "--compare", str(ref)]) == 2
    assert "no overlap" in capsys.readouterr().err
