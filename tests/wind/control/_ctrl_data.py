"""Where the shared reference data of the controller tests is (a plain module: test files import it by name).

``shared/openfast/aero`` (the OpenFAST + ROSCO 2.10.6 runs of the NREL 5 MW and their deck) is found next
to the repository or, from a git worktree, by walking up the ancestors.
"""

from __future__ import annotations

from pathlib import Path

import pytest


def _find_shared() -> Path:
    here = Path(__file__).resolve()
    for parent in here.parents[3:]:
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return here.parents[3].parent / "shared"


SHARED = _find_shared()
AERO = SHARED / "openfast" / "aero"
DECK = AERO / "openfast_inputs" / "deck"


def need(path: Path) -> Path:
    """``path``, or skip the test if the shared reference data is absent."""
    if not path.exists():
        pytest.skip(f"shared reference data not found at {path}")
    return path


def discon_variant(folder: Path, changes: dict) -> Path:
    """The shared NREL 5 MW DISCON.IN written into ``folder`` with the values of some keys replaced (vectors as one
    string), next to a copy of its Cp/Ct/Cq table."""
    import re
    import shutil

    text = need(DECK / "DISCON.IN").read_text()
    for key, value in changes.items():
        text, n = re.subn(rf"^[^!\n]*?(\s+! {key}\b)", rf"{value}\1", text, count=1, flags=re.MULTILINE)
        assert n == 1, key
    path = folder / "DISCON.IN"
    path.write_text(text)
    shutil.copy(DECK / "Cp_Ct_Cq.NREL5MW.txt", folder)
    return path
