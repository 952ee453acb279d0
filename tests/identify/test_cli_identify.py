"""``mbsym identify``: the JSON contract on a shared OpenFAST deck, and its error paths.

Reference: the deck's own values (OpenFAST generated the data with them); the fit starts 20 % off.
Tolerances: 2 % on the damping ratio and 0.1 % on the stiffness tuner (model-form differences
between mbsym and ElastoDyn leave a small bias; benchmarks/README.md lists the full-record figures).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from mbsym.cli import main


@pytest.fixture(scope="module")
def short_csv(paper45, tmp_path_factory):
    """The first 12 s of the paper45 free decay (a quick test; the CLI reads any OpenFAST CSV)."""
    _, csv = paper45
    lines = csv.read_text().splitlines()
    path = tmp_path_factory.mktemp("cli") / "paper45_12s.csv"
    path.write_text("\n".join(lines[:602]) + "\n")
    return path


def test_json_contract(paper45, short_csv, capsys):
    fst, _ = paper45
    code = main(["identify", str(fst), "--data", str(short_csv), "--params", "TwrFADmp(1),FAStTunr(1)",
                 "--initial", "TwrFADmp(1)=0.8,FAStTunr(1)=0.8", "--no-compile", "--json"])
    out = capsys.readouterr().out.strip().splitlines()
    assert code == 0
    data = json.loads(out[-1])
    assert set(data) == {"parameters", "std", "initial", "eps_pct", "iterations", "wall_s"}
    assert list(data["parameters"]) == ["TwrFADmp(1)", "FAStTunr(1)"] == list(data["std"]) == list(data["initial"])
    assert data["initial"] == {"TwrFADmp(1)": 0.8, "FAStTunr(1)": 0.8}
    assert data["parameters"]["TwrFADmp(1)"] == pytest.approx(1.0, rel=0.02)       # deck: 1 %
    assert data["parameters"]["FAStTunr(1)"] == pytest.approx(1.0, rel=1e-3)       # deck: 1
    assert all(0 < v < 1e-2 for v in data["std"].values())
    assert list(data["eps_pct"]) == ["Q_TFA1", "QD_TFA1", "Q_TSS1", "QD_TSS1", "QD_GeAz"]
    assert all(0 <= v < 0.5 for v in data["eps_pct"].values())
    assert isinstance(data["iterations"], int) and data["iterations"] >= 1
    assert data["wall_s"] > 0


def test_keys_as_passed_and_deck_starting_values(paper45, short_csv, capsys):
    """Keys are echoed exactly as written; without --initial the deck's values are the start."""
    fst, _ = paper45
    code = main(["identify", str(fst), "--data", str(short_csv), "--params", "twrssdmp1",
                 "--channels", "Q_TSS1,QD_TSS1", "--no-compile", "--json"])
    data = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert code == 0
    assert list(data["parameters"]) == ["twrssdmp1"]
    assert data["initial"] == {"twrssdmp1": 1.0}
    assert list(data["eps_pct"]) == ["Q_TSS1", "QD_TSS1"]
    assert np.isfinite(data["parameters"]["twrssdmp1"])


@pytest.mark.parametrize("args, message", [
    (["--params", "NoSuchKey"], "unknown parameter key 'NoSuchKey'"),
    (["--params", "PtfmPIner"], "not a parameter of this model: enable one of the DOFs"),
    (["--params", "NacMass", "--channels", "Q_TFA1,PtfmPitch"], "channels \\['PtfmPitch'\\] are not in the data"),
    (["--params", "NacMass", "--channels", "Q_TFA1,Q_Sg"], "channel 'Q_Sg' is neither an output nor a state"),
    (["--params", "NacMass", "--initial", "NacMass"], "--initial entries must be KEY=VALUE"),
])
def test_errors_exit_2_with_a_message(paper45, short_csv, capsys, args, message):
    fst, _ = paper45
    code = main(["identify", str(fst), "--data", str(short_csv), "--no-compile", *args])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith("mbsym identify: error:")
    import re
    assert re.search(message, err), err
