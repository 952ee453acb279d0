"""Fixtures of the wind-input tests: the shared OpenFAST wind files (skip when absent)."""

from __future__ import annotations

from pathlib import Path

import pytest


def _find_shared() -> Path:
    here = Path(__file__).resolve()
    for parent in here.parents[3:]:
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return here.parents[3].parent / "shared"


AERO = _find_shared() / "openfast" / "aero"


def need(path: Path) -> Path:
    """``path``, or skip the test if the shared reference data is absent."""
    if not path.exists():
        pytest.skip(f"shared reference data not found at {path}")
    return path


@pytest.fixture(scope="session")
def aero() -> Path:
    """``shared/openfast/aero`` (skips if absent)."""
    return need(AERO)
