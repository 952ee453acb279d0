"""Bad command-line argument sets: each refused with one typed error line, exit status ≠ 0, and
no file written or changed (the OpenFAST reference above all).

Bounds checked: output files (mbsym.cli._files), rotor speeds (blade tip below the speed of
sound, 343 m/s: mbsym.wind.deck.checks.MAX_TIP_SPEED), Campbell speed lists strictly increasing,
references with finite, increasing times (mbsym.wind.analysis.compare).
"""

from __future__ import annotations

import os

import pytest

from .conftest import assert_refused, run_cli, set_key


def _shuffled(deck):
    lines = deck.csv.read_text().splitlines(keepends=True)
    lines[5], lines[6] = lines[6], lines[5]
    bad = deck.dir / "shuffled.csv"
    bad.write_text("".join(lines))
    return bad


def _nan_time(deck):
    lines = deck.csv.read_text().splitlines(keepends=True)
    cells = lines[4].split(",")
    cells[0] = "nan"
    lines[4] = ",".join(cells)
    bad = deck.dir / "nan_time.csv"
    bad.write_text("".join(lines))
    return bad


def _hard_link(deck):
    link = deck.dir / "link.csv"
    os.link(deck.csv, link)
    return link


def _aero(deck):
    set_key(deck.fst, "CompAero", "2")
    return deck.fst


# (argv builder: deck -> argv, expected message regex)
CASES = [
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.csv, "--compare", d.csv], r"is the --compare file"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", _hard_link(d), "--compare", d.csv],
     r"is the --compare file"),                                                        # same inode
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.fst], r"deck file"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.ed], r"deck's elastodyn file"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.tower], r"deck's tower file"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.dir / "o.csv", "--plot", d.dir / "no" / "p.png"],
     r"--plot .*does not exist"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--plot", d.dir / "p.xyz"], r"unsupported image type 'xyz'"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.dir], r"is a directory"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", d.dir / "x.png", "--plot", d.dir / "x.png"],
     r"also the --out file"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--out", ""], r"needs a file name"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--compare", d.dir / "missing.csv"], r"not found"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--compare", _shuffled(d)], r"line 7.*does not increase"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--compare", _nan_time(d)], r"line 5.*finite time"),
    (lambda d: ["simulate", d.fst, "--tmax", "0.1", "--method", "magic"], r"unknown --method 'magic'"),
    (lambda d: ["simulate", d.dir / "missing.fst"], r"not found"),
    (lambda d: ["simulate", _aero(d), "--tmax", "0.1"], r"CompAero = 2"),
    (lambda d: ["linearize", d.fst, "--rpm", "1e9"], r"--rpm 1e\+09 rpm is unphysical.*speed of sound"),
    (lambda d: ["linearize", d.fst, "--rpm", "-1"], r"--rpm must be a finite rotor speed >= 0"),
    (lambda d: ["linearize", d.fst, "--rpm", "nan"], r"--rpm must be a finite rotor speed"),
    (lambda d: ["linearize", _aero(d)], r"CompAero = 2.*--structure-only"),
    (lambda d: ["campbell", d.fst, "--rpm", "6,3,3,0"], r"strictly increasing.*0,3,6"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,3,3"], r"strictly increasing"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,abc"], r"comma-separated numbers"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,1e6"], r"speed of sound"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,5", "--azimuths", "0"], r"--azimuths must be a positive"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,5", "--plot", d.dir], r"is a directory"),
    (lambda d: ["campbell", d.fst, "--rpm", "0,5", "--plot", d.fst], r"unsupported image type 'fst'"),
    (lambda d: ["campbell", _aero(d), "--rpm", "0,5"], r"CompAero = 2"),
]


@pytest.mark.parametrize("build, match", CASES, ids=[f"case{i}" for i in range(len(CASES))])
def test_bad_arguments_are_refused(deck, build, match):
    reference = deck.csv.read_bytes()
    argv = build(deck)
    assert_refused(deck, argv, match)
    assert deck.csv.read_bytes() == reference                      # the OpenFAST reference is untouched


@pytest.mark.parametrize("argv", [["simulate", "--tmax", "abc"], ["linearize", "--nope"], ["campbell"]])
def test_usage_errors_exit_2_with_one_line(argv, capsys):
    code, _, err = run_cli(argv)
    assert code == 2 and len(err.strip().splitlines()) == 1 and "error:" in err
