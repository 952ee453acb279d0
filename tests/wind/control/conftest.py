"""Fixtures of the controller tests.

Reference data: ``shared/openfast/aero`` (the OpenFAST + ROSCO 2.10.6 runs of the NREL 5 MW and their
deck: ServoDyn file, DISCON.IN, Cp table), found next to the repository or, from a git worktree, by
walking up the ancestors; tests needing it skip cleanly when it is absent.  The real ROSCO library is
fetched once into a cache by :mod:`_rosco` (``pip download --no-deps rosco==2.10.6``); tests needing it
skip cleanly without registry access.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import _rosco
from _ctrl_data import DECK, need


@pytest.fixture(scope="session")
def rosco_lib() -> Path:
    """ROSCO 2.10.6's libdiscon.so from the cached wheel (skips without it and without registry access)."""
    lib = _rosco.rosco_library()
    if lib is None:
        pytest.skip("the ROSCO 2.10.6 library is not cached and could not be fetched with pip")
    return lib


@pytest.fixture(scope="session")
def discon_in() -> Path:
    """The NREL 5 MW DISCON.IN of the shared OpenFAST runs (LoggingLevel 0)."""
    return need(DECK / "DISCON.IN")
