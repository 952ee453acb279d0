"""``mbsym operating-points``: the JSON contract, validation against OpenFAST, bad input.

References:
- OpenFAST v5 + AeroDyn 15 + ROSCO 2.10.6 steady states of the NREL 5 MW (``shared/openfast/aero/
  steady_states.csv``, means over 120-150 s of 150 s runs, 17 wind speeds; DOFs GenDOF, TwFADOF1,
  TwSSDOF1): the issue's thresholds at every wind speed, RotSpeed 0.5 %, BldPitch1 0.3 deg (above rated;
  below rated as well here: both are at the minimum pitch), GenPwr 1 %, RtAeroFxh 2 %, TTDspFA 3 %;
- units: the JSON holds OpenFAST's units (rpm, deg, kW, N, m): the rated values 12.1 rpm and 5000 kW of
  the NREL 5 MW (NREL/TP-500-38060 Table 1-1) appear as such;
- bad input: exit status 2, one line on stderr naming the problem, no plot file written and an existing
  one left untouched.
"""

from __future__ import annotations

import csv
import json
import shutil

import numpy as np
import pytest

from _op_data import AERO, DECK, INPUTS, need
from mbsym.cli import main

TOLERANCES = {"RotSpeed": ("rel", 0.005), "BldPitch1": ("abs", 0.3), "GenPwr": ("rel", 0.01),
              "RtAeroFxh": ("rel", 0.02), "TTDspFA": ("rel", 0.03)}
COLUMNS = {"RotSpeed": "RotSpeed_[rpm]", "BldPitch1": "BldPitch1_[deg]", "GenPwr": "GenPwr_[kW]",
           "RtAeroFxh": "RtAeroFxh_[N]", "TTDspFA": "TTDspFA_[m]"}


def _openfast_steady() -> dict[float, dict[str, float]]:
    with need(AERO / "steady_states.csv").open() as fh:
        return {float(r["WindSpeed_[m/s]"]): {k: float(r[c]) for k, c in COLUMNS.items()} for r in csv.DictReader(fh)}


def _last_json(capsys) -> dict:
    out = capsys.readouterr().out.strip().splitlines()
    return json.loads(out[-1])


def _check_against_openfast(result: dict) -> None:
    ref = _openfast_steady()
    for i, U in enumerate(result["wind_speed"]):
        for name, (kind, tol) in TOLERANCES.items():
            ours, theirs = result[name][i], ref[U][name]
            err = abs(ours - theirs) if kind == "abs" else abs(ours / theirs - 1)
            assert err <= tol, (U, name, ours, theirs)


def test_json_contract_builtin(capsys, tmp_path):
    plot = tmp_path / "op.png"
    assert main(["operating-points", "--wind", "4:25:7", "--json", "--plot", str(plot)]) == 0
    d = _last_json(capsys)
    assert d["wind_speed"] == [4.0, 11.0, 18.0, 25.0]               # STOP included: on the grid
    assert {"RotSpeed", "BldPitch1", "GenPwr", "RtAeroFxh", "TTDspFA"} <= set(d)
    assert all(len(d[k]) == 4 for k in ("RotSpeed", "BldPitch1", "GenPwr", "RtAeroFxh", "TTDspFA"))
    assert d["success"] == [True] * 4 and d["region"][-1] == "3"
    assert d["RotSpeed"][-1] == pytest.approx(12.1, rel=1e-3)        # rpm
    assert d["GenPwr"][-1] == pytest.approx(5000.0, rel=1e-9)        # kW
    assert 2e5 < d["RtAeroFxh"][-1] < 4e5                            # N
    assert 0.05 < d["TTDspFA"][-1] < 0.5                             # m
    assert abs(d["BldPitch1"][-2] - 14.92) < 1.0                    # deg at 18 m/s (NREL/TP-500-38060 Table 7-1)
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["operating-points", "--wind", "11.4, 8", "--json"]) == 0
    assert _last_json(capsys)["wind_speed"] == [11.4, 8.0]


def test_builtin_matches_openfast_steady_states(capsys):
    """The built-in NREL 5 MW is the shared deck's turbine (same structure, blades and controller settings)."""
    speeds = ",".join(f"{u:g}" for u in sorted(_openfast_steady()))
    assert main(["operating-points", "--wind", speeds, "--json",
                 "--discon-input", str(need(DECK / "DISCON.IN"))]) == 0
    _check_against_openfast(_last_json(capsys))


@pytest.mark.slow
def test_shared_deck_matches_openfast_steady_states(capsys):
    fst = need(INPUTS / "steady_12" / "steady_12.fst")
    speeds = ",".join(f"{u:g}" for u in sorted(_openfast_steady()))
    assert main(["operating-points", str(fst), "--wind", speeds, "--json"]) == 0
    _check_against_openfast(_last_json(capsys))


@pytest.mark.parametrize("args, message", [
    (["--wind", "4:3:1"], "STOP"),
    (["--wind", "4:25:0"], "STEP must be > 0"),
    (["--wind", "four"], "numbers"),
    (["--wind", "0,4"], "positive"),
    (["--wind", "4:25"], "START:STOP:STEP"),
    (["--wind", "1:100000:1"], "more than"),
    (["no_such_deck.fst", "--wind", "8"], "deck not found"),
    (["--wind", "8", "--discon-input", "no_such_DISCON.IN"], "not found"),
    (["--wind", "8", "--plot", "no_such_dir/op.png"], "does not exist"),
    (["--wind", "8", "--plot", "op.unknownformat"], "cannot write"),
])
def test_bad_input_one_line_error_and_no_file(args, message, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    keep = tmp_path / "keep.png"
    keep.write_bytes(b"old")
    assert main(["operating-points", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("mbsym operating-points: error:") and message in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.png"] and keep.read_bytes() == b"old"


def test_unsupported_controller_mode_names_file_and_line(capsys, tmp_path):
    src = need(DECK / "DISCON.IN")
    shutil.copy(DECK / "Cp_Ct_Cq.NREL5MW.txt", tmp_path)
    text = src.read_text().splitlines()
    line = next(i for i, t in enumerate(text) if t.split("!")[-1].strip().startswith("VS_ControlMode"))
    text[line] = "4" + text[line][1:]
    bad = tmp_path / "DISCON.IN"
    bad.write_text("\n".join(text) + "\n")
    plot = tmp_path / "op.png"
    assert main(["operating-points", "--wind", "8", "--discon-input", str(bad), "--plot", str(plot)]) == 2
    err = capsys.readouterr().err
    assert f"line {line + 1}, key 'VS_ControlMode' = 4" in err and not plot.exists()


def test_parse_wind_speeds_grid():
    from mbsym.wind.analysis.operating_points import parse_wind_speeds

    assert parse_wind_speeds("4:25:1") == [float(u) for u in range(4, 26)]
    assert parse_wind_speeds("3:4:0.3") == pytest.approx([3.0, 3.3, 3.6, 3.9])
    assert parse_wind_speeds("12") == [12.0]
    assert np.all(np.diff(parse_wind_speeds("0.5:24.5:0.5")) > 0)


def test_flexible_sheared_deck_trims_on_the_rotor_rung_and_says_so(capsys):
    """A deck whose wind and DOFs ask for the blade-element rung (shear, flexible blades) used to end in an
    AttributeError traceback: its operating points are now the rotor-effective rung's, with a warning naming why;
    the blade-element rung's trim is refused by name (it has no rotor-effective surfaces to guess from). Check
    against the shared OpenFAST run of the same deck at 14 m/s (steady part): rated speed and power."""
    from mbsym.exceptions import UnsupportedFeatureError
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.trim import Trimmer

    fst = need(INPUTS / "ss14_shear_flex" / "ss14_shear_flex.fst")
    assert main(["operating-points", str(fst), "--wind", "14", "--json"]) == 0
    out = capsys.readouterr()
    assert "warning" in out.err and "rotor-effective rung" in out.err     # the CLI prints ModelWarnings
    d = json.loads(out.out.strip().splitlines()[-1])
    assert d["success"] == [True] and d["RotSpeed"][0] == pytest.approx(12.1, rel=1e-3)
    assert d["GenPwr"][0] == pytest.approx(5000.0, rel=1e-6)
    blade = OperatingTurbine.from_openfast(fst, aero="blade")
    with pytest.raises(UnsupportedFeatureError, match="aero='rotor'"):
        Trimmer(blade)
