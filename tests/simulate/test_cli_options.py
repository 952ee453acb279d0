"""`mbsym simulate` simulation options (issue 10.3, issue 11.1/11.3/11.4): --accuracy, --dt as output spacing,
one-line typed errors naming the flag or deck key at fault, no output file left behind, header before the
integration, Ctrl-C. Decks with bad TMax/DT_Out are written to tmp_path next to nothing but a copy of the .fst
(EDFile pointing back to the shared ElastoDyn file); shared data are never modified.
"""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from mbsym.cli import main

SHARED = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"
CASE = SHARED / "paper44_fa_gen"


def _deck(tmp_path, **keys):
    """A copy of the paper44 .fst with some keys changed; EDFile made absolute."""
    if not CASE.exists():
        pytest.skip("shared OpenFAST decks not available")
    lines = (CASE / "paper44_fa_gen.fst").read_text().splitlines()
    out = []
    for line in lines:
        words = line.split()
        if len(words) > 1 and words[1] in keys:
            line = f"{keys[words[1]]:<24} {' '.join(words[1:])}"
        elif len(words) > 1 and words[1] == "EDFile":
            line = f'"{CASE / "paper44_fa_gen_ElastoDyn.dat"}" ' + " ".join(words[1:])
        out.append(line)
    path = tmp_path / "deck.fst"
    path.write_text("\n".join(out) + "\n")
    return path


def _one_line_error(capsys, argv, message, out_file=None):
    assert main(argv) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert len(err.splitlines()) == 1 and message in err, err
    assert "Q_TFA1" not in captured.out                      # nothing simulated
    if out_file is not None:
        assert not Path(out_file).exists()
    return err


@pytest.mark.parametrize("extra, message", [
    (["--tmax", "1", "--dt", "2"], "--dt = 2 s exceeds --tmax = 1 s"),
    (["--tmax", "inf"], "--tmax = inf s must be a positive finite time"),
    (["--tmax", "nan"], "--tmax = nan s must be a positive finite time"),
    (["--tmax", "1", "--dt", "0"], "--dt = 0 s must be a positive finite time"),
    (["--tmax", "1", "--method", "cvodes", "--rtol", "10"], "rtol = 10 allows errors as large as the solution"),
    (["--tmax", "1", "--rtol", "1e-16"], "rtol >= 1e-14"),
    (["--tmax", "1", "--accuracy", "0"], "accuracy must be a positive"),
    (["--tmax", "1", "--accuracy", "1e-3", "--method", "rk4"], "--accuracy chooses the method and step itself"),
    (["--tmax", "1", "--accuracy", "1e-3", "--rtol", "1e-6"], "cannot be combined with --rtol"),
    (["--tmax", "1", "--method", "rk4", "--rtol", "1e-6"], "--rtol/--atol apply to adaptive methods"),
    (["--tmax", "60", "--dt", "1e-9"], "space the outputs more widely"),
])
def test_bad_options_give_one_line_and_write_nothing(tmp_path, capsys, extra, message):
    out = tmp_path / "x.csv"
    t0 = time.perf_counter()
    _one_line_error(capsys, ["simulate", *extra, "--out", str(out)], message, out)
    assert time.perf_counter() - t0 < 30          # refused before integrating (the model build is the cost)


@pytest.mark.parametrize("keys, message", [
    ({"TMax": "0.0"}, "the deck's TMax = 0 s must be a positive finite time; set TMax in the deck or pass --tmax"),
    ({"DT_Out": "100.0"}, "the deck's DT_Out = 100 s exceeds the deck's TMax = 60 s"),
])
def test_deck_values_are_blamed_not_flags(tmp_path, capsys, keys, message):
    deck = _deck(tmp_path, **keys)
    err = _one_line_error(capsys, ["simulate", str(deck), "--out", str(tmp_path / "y.csv")], message,
                          tmp_path / "y.csv")
    assert "--dt" not in err.split(";")[0]


def test_deck_values_overridden_by_flags_run(tmp_path, capsys):
    deck = _deck(tmp_path, TMax="0.0")
    assert main(["simulate", str(deck), "--tmax", "0.5", "--stats"]) == 0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert stats["method"] == "rk4"


def test_default_is_accuracy_driven_and_dt_spaces_the_outputs(tmp_path, capsys):
    if not CASE.exists():
        pytest.skip("shared OpenFAST decks not available")
    out = tmp_path / "z.csv"
    argv = ["simulate", str(CASE / "paper44_fa_gen.fst"), "--tmax", "10", "--dt", "0.005", "--stats", "--out", str(out)]
    assert main(argv) == 0
    text = capsys.readouterr().out
    lines = text.strip().splitlines()
    stats = json.loads(lines[-1])
    assert stats["accuracy"] == 1e-3 and stats["error_estimate"] <= 1e-3
    assert stats["dt"] > 0.05                                   # the step is not the 5 ms output spacing
    header = next(i for i, ln in enumerate(lines) if "accuracy 0.001" in ln)
    result = next(i for i, ln in enumerate(lines) if ln.startswith("method rk4"))
    assert header < result                                      # header printed before the integration
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(np.diff(data[:, 0]), 0.005, atol=1e-9)


def test_explicit_method_keeps_the_deck_step(capsys):
    assert main(["simulate", "--tmax", "0.5", "--method", "rk4", "--stats"]) == 0
    stats = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert stats["method"] == "rk4" and stats["steps"] == 50 and "accuracy" not in stats


def _interrupt_the_command(out, signum):
    """Start a default run of 1e5 s (millions of steps), send ``signum`` a second after the header: (return code,
    stderr, seconds from the signal to the end). Bounded: the command is killed 30 s after the signal."""
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "mbsym", "simulate", "--tmax", "1e5", "--dt", "10", "--out",
                             str(out)], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        deadline = time.time() + 120
        line = ""
        while time.time() < deadline and "DOFs" not in line:       # the header is printed before integrating
            line = proc.stdout.readline()
            if not line and proc.poll() is not None:
                break
        assert "DOFs" in line, proc.stderr.read()
        time.sleep(1.0)
        t0 = time.time()
        proc.send_signal(signum)
        _, err = proc.communicate(timeout=30)
        return proc.returncode, err, time.time() - t0
    finally:
        proc.kill()
        proc.wait()


def test_ctrl_c_ends_the_command_without_files(tmp_path, sigint_delivered):
    """SIGINT after start-up: exit 130 within seconds, "interrupted at t = ...", no CSV. (The command gets SIGINT's
    default action from the sigint_delivered fixture, even when the test process inherited it as ignored.)"""
    out = tmp_path / "never.csv"
    code, err, elapsed = _interrupt_the_command(out, signal.SIGINT)
    assert code == 130, err
    assert elapsed < 5.0
    assert "interrupted at t = " in err and not out.exists()


def test_sigterm_ends_the_command_when_sigint_is_ignored(tmp_path, sigint_ignored):
    """Started in the background by a script, the command inherits SIGINT as ignored (Ctrl-C cannot reach it);
    SIGTERM (``kill PID``) then ends the run as Ctrl-C would: exit 130, "interrupted at t = ...", no CSV."""
    out = tmp_path / "never.csv"
    code, err, elapsed = _interrupt_the_command(out, signal.SIGTERM)
    assert code == 130, (code, err)                             # -15: killed by SIGTERM, nothing reported
    assert elapsed < 5.0
    assert "interrupted at t = " in err and not out.exists()
