"""Fixtures of the rotor-aerodynamics tests.

Reference data: ``shared/openfast/aero`` (OpenFAST v5 + AeroDyn 15 steady states of the
NREL 5 MW, ROSCO's performance table and the AeroDyn deck). The shared directory sits next
to the repository (``../shared``); from a git worktree nested one level deeper it is found
by walking up the ancestors. Tests needing it skip cleanly when it is absent.
"""

from __future__ import annotations

from pathlib import Path

import pytest


def _find_shared() -> Path:
    here = Path(__file__).resolve()
    for parent in here.parents[3:]:  # the repository root, then its ancestors
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return here.parents[3].parent / "shared"


SHARED = _find_shared()
AERO = SHARED / "openfast" / "aero"
DECK = AERO / "openfast_inputs" / "deck"
ROSCO_TABLE = AERO / "Cp_Ct_Cq.NREL5MW.txt"
AERODYN_MAIN = DECK / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"


def need(path: Path) -> Path:
    """Return ``path``, or skip the test if the shared reference data is absent."""
    if not path.exists():
        pytest.skip(f"shared reference data not found at {path}")
    return path
