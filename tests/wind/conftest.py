"""Shared fixtures for the wind tests.

Reference data live in the shared directory next to the repository
(``../shared`` from the repository root, computed from this file's location);
tests that need it skip cleanly when it is absent.
"""

from __future__ import annotations

import re
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import pytest

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
BASE_DIR = SHARED / "openfast" / "NREL5MW"
BASE_FST = BASE_DIR / "NREL5MW_Onshore_ElastoDynOnly.fst"


@pytest.fixture(scope="session")
def base_fst() -> Path:
    """The shared NREL 5 MW base deck (skips if ../shared is absent)."""
    if not BASE_FST.is_file():
        pytest.skip(f"shared OpenFAST reference data not found at {BASE_FST}")
    return BASE_FST


@pytest.fixture(scope="session")
def base_params(base_fst: Path):
    """TurbineParameters read from the base deck (read once per session)."""
    from mbsym.wind import read_openfast

    return read_openfast(base_fst)


@dataclass(frozen=True)
class Deck:
    """A writable copy of the base deck."""

    fst: Path
    ed: Path
    tower: Path
    blade: Path


@pytest.fixture
def deck(base_fst: Path, tmp_path: Path) -> Deck:
    """Copy the base deck (.fst, ElastoDyn, tower, blade) to ``tmp_path``."""
    names = ("NREL5MW_Onshore_ElastoDynOnly.fst", "NREL5MW_ElastoDyn_Onshore.dat",
             "NRELOffshrBsline5MW_Onshore_ElastoDyn_Tower.dat", "NRELOffshrBsline5MW_Blade.dat")
    for name in names:
        shutil.copy(base_fst.parent / name, tmp_path / name)
        (tmp_path / name).chmod(0o644)
    return Deck(*(tmp_path / name for name in names))


def _edit(path: Path, old: str, new: str, count: int = 1) -> None:
    text = path.read_text()
    changed, n = re.subn(old, new, text, count=count, flags=re.M)
    if n != count:
        raise AssertionError(f"mutation {old!r} applied {n} times to {path.name}, not {count}")
    path.write_text(changed)


@pytest.fixture
def edit() -> Callable[..., None]:
    """``edit(path, regex, replacement, count=1)``: mutate a deck file line-wise."""
    return _edit
