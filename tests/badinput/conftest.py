"""Shared helpers of the bad-input suite (issue 11).

Every case mutates a private copy of a shared OpenFAST deck (``../shared/openfast``: the
``paper44_fa_gen`` case, TwFADOF1 + GenDOF, with the NREL 5 MW tower and blade files in the same
relative layout) and runs the ``mbsym`` command in-process (:func:`mbsym.cli.main`) or an API
call. A CLI failure must exit with a non-zero status and one ``mbsym <command>: error: …`` line
on stderr, and leave no new file behind (not even a temporary one).
"""

from __future__ import annotations

import contextlib
import io
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import pytest

SHARED = Path(__file__).resolve().parents[2].parent / "shared" / "openfast"
CASE = "paper44_fa_gen"


@dataclass
class Deck:
    """A writable copy of the paper44 deck: ``root/cases/c/{fst, ed, csv}`` and ``root/NREL5MW/*``."""

    root: Path
    fst: Path
    ed: Path
    csv: Path
    tower: Path
    blade: Path

    @property
    def dir(self) -> Path:
        return self.fst.parent

    def files(self) -> set[Path]:
        return {p for p in self.root.rglob("*") if p.is_file()}


def copy_deck(root: Path) -> Deck:
    """Copy the paper44 case and the NREL 5 MW files into ``root`` (skips if ../shared is absent)."""
    src = SHARED / "cases" / CASE
    if not (src / f"{CASE}.fst").is_file():
        pytest.skip(f"shared OpenFAST reference data not found at {src}")
    case_dir, base = root / "cases" / "c", root / "NREL5MW"
    case_dir.mkdir(parents=True)
    base.mkdir()
    for name in (f"{CASE}.fst", f"{CASE}_ElastoDyn.dat", f"{CASE}.csv"):
        shutil.copy(src / name, case_dir / name)
    for f in (SHARED / "NREL5MW").iterdir():
        shutil.copy(f, base / f.name)
    for p in root.rglob("*"):
        p.chmod(0o755 if p.is_dir() else 0o644)
    return Deck(root, case_dir / f"{CASE}.fst", case_dir / f"{CASE}_ElastoDyn.dat", case_dir / f"{CASE}.csv",
                base / "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat", base / "NRELOffshrBsline5MW_Blade.dat")


@pytest.fixture
def deck(tmp_path: Path) -> Deck:
    return copy_deck(tmp_path)


def set_key(path: Path, key: str, value: str) -> None:
    """Replace the value of ``key`` (first token of its line) in an OpenFAST file."""
    text = path.read_text()
    new, n = re.subn(rf"^(\s*)\S+(\s+{re.escape(key)}\s)", lambda m: f"{m.group(1)}{value}{m.group(2)}", text,
                     count=1, flags=re.M)
    if n != 1:
        raise AssertionError(f"key {key!r} not found in {path.name}")
    path.write_text(new)


def delete_key(path: Path, key: str) -> None:
    text = path.read_text()
    new, n = re.subn(rf"^\s*\S+\s+{re.escape(key)}\s.*\n", "", text, count=1, flags=re.M)
    if n != 1:
        raise AssertionError(f"key {key!r} not found in {path.name}")
    path.write_text(new)


def set_table_cell(path: Path, row: int, col: int, value: str) -> None:
    """Replace cell (row, col) of the first numeric table (rows after a units line '(...)')."""
    lines = path.read_text().splitlines(keepends=True)
    start = next(i for i, line in enumerate(lines) if line.strip().startswith("(")) + 1
    cells = lines[start + row].split()
    cells[col] = value
    lines[start + row] = "  ".join(cells) + "\n"
    path.write_text("".join(lines))


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``mbsym <argv>`` in-process: (exit status, stdout, stderr)."""
    from mbsym.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def assert_refused(deck: Deck, argv: list, match: str, command: str | None = None) -> str:
    """The command fails with one error line matching ``match`` and writes no file."""
    before = deck.files()
    code, out, err = run_cli(argv)
    command = command or str(argv[0])
    errors = [line for line in err.splitlines() if line.startswith(f"mbsym {command}: error:")]
    assert code != 0, f"exit 0 for {argv}; stdout: {out[-300:]}"
    assert len(errors) == 1 and "Traceback" not in err, f"not one error line: {err!r}"
    assert re.search(match, errors[0]), f"{errors[0]!r} does not match {match!r}"
    assert deck.files() == before, f"files left behind: {sorted(map(str, deck.files() - before))}"
    return errors[0]
