"""Shared reference data of the operation tests (a plain module: test files import it by name).

``shared/openfast/aero`` (OpenFAST v5 + AeroDyn + ROSCO 2.10.6 runs of the NREL 5 MW) is found next to the
repository or, from a git worktree, by walking up the ancestors; tests needing it skip cleanly when absent.
"""

from __future__ import annotations

import dataclasses
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
INPUTS = AERO / "openfast_inputs"
DECK = INPUTS / "deck"


def need(path: Path) -> Path:
    """``path``, or skip the test if the shared reference data is absent."""
    if not path.exists():
        pytest.skip(f"shared reference data not found at {path}")
    return path


def baseline_settings_data(discon_in: Path) -> dict:
    """The package-data dict of :mod:`mbsym.wind.operation.nrel5mw` generated from a DISCON.IN."""
    from mbsym.wind.control import BaselineSettings

    s = BaselineSettings.from_discon(discon_in, dt=0.01)
    # IPC off (the NREL 5 MW file): the ipc_* settings keep their defaults and are not stored
    values = {k: v for k, v in dataclasses.asdict(s).items()
              if k not in ("dt", "source") and not (k.startswith("ipc_") and s.ipc_mode == 0)}
    values["cp"] = [list(row) for row in values["cp"]]
    return {"_source": {
        "controller": "ROSCO 2.10.6 (rosco wheel on PyPI), Examples/Test_Cases/NREL-5MW/DISCON.IN and its "
                      "performance table Cp_Ct_Cq.NREL5MW.txt (Apache-2.0), mapped by "
                      "mbsym.wind.control.settings.DISCON_MAP (SI units)",
        "generated_by": "tests/wind/operation/test_operation_data.py"},
        "settings": {k: (list(v) if isinstance(v, tuple) else v) for k, v in values.items()}}
