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
    # IPC, floating feedback, pitch actuator model, generator-speed notches, tower damper, power reference,
    # shut-down and start-up off (the NREL 5 MW file): their settings keep their defaults and are not stored
    groups = ((s.ipc_mode, ("ipc_",)), (s.floating_mode, ("floating_", "tower_notch_")),
              (s.actuator_mode, ("actuator_",)), (getattr(s, "speed_notch_freqs", ()), ("speed_notch_",)),
              (getattr(s, "tower_damper_mode", 0), ("tower_damper_",)),
              (getattr(s, "power_reference_mode", 0), ("power_reference_", "power_rating_")),
              (getattr(s, "shutdown_mode", 0), ("shutdown_",)), (getattr(s, "startup_mode", 0), ("startup_",)))
    off = tuple(prefix for on, prefixes in groups if not on for prefix in prefixes)
    values = {k: v for k, v in dataclasses.asdict(s).items()
              if k not in ("dt", "source") and not k.startswith(off)}
    values["cp"] = [list(row) for row in values["cp"]]
    return {"_source": {
        "controller": "ROSCO 2.10.6 (rosco wheel on PyPI), Examples/Test_Cases/NREL-5MW/DISCON.IN and its "
                      "performance table Cp_Ct_Cq.NREL5MW.txt (Apache-2.0), mapped by "
                      "mbsym.wind.control.settings.DISCON_MAP (SI units)",
        "generated_by": "tests/wind/operation/test_operation_data.py"},
        "settings": {k: (list(v) if isinstance(v, tuple) else v) for k, v in values.items()}}


def edit_deck_file(path: Path, old: str, new: str) -> None:
    """Replace the first line matching the regular expression ``old`` (multiline) with ``new``; fail if none."""
    import re

    text, n = re.subn(old, new, path.read_text(), count=1, flags=re.M)
    assert n == 1, f"mutation {old!r} did not apply to {path.name}"
    path.write_text(text)


def runnable_rosco_deck(fst: Path, target: Path) -> Path:
    """A copy of ROSCO's NREL 5 MW deck in ``target`` with the AeroDyn settings mbsym refuses switched off
    (tower potential flow and drag, unsteady airfoil aerodynamics: mbsym.wind.deck.aero_audit)."""
    import shutil

    shutil.copytree(fst.parent, target)
    aero = target / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"
    edit_deck_file(aero, r"^\s*1\s+TwrPotent", "0   TwrPotent")
    edit_deck_file(aero, r"^True\s+TwrAero", "False   TwrAero")
    edit_deck_file(aero, r"^3\s+UA_Mod", "0   UA_Mod")
    return target / fst.name


#: DISCON.IN keys the writer derives from BaselineSettings (their vectors' lengths, the performance file).
DERIVED_DISCON_KEYS = ("PC_GS_n", "VS_n", "WE_FOPoles_N", "PS_BldPitchMin_N", "PerfFileName", "PerfTableSize")


def discon_other_data(discon_in: Path) -> dict:
    """The package data of :func:`mbsym.wind.operation.nrel5mw.write_nrel5mw_discon` generated from a DISCON.IN:
    every key ROSCO reads that :data:`~mbsym.wind.control.settings.DISCON_MAP` does not map (nor one derived from
    the mapped ones), and the thrust and torque tables of its performance file (the power table is in the
    settings)."""
    import numpy as np

    from mbsym.wind.control.settings import DISCON_MAP
    from mbsym.wind.deck.discon_in import DISCON_KEYS, read_discon_in
    from mbsym.wind.deck.performance import read_performance_table

    d = read_discon_in(discon_in)
    other = {}
    for spec in DISCON_KEYS:
        if spec.key in DISCON_MAP or spec.key in DERIVED_DISCON_KEYS:
            continue
        value = d[spec.key]
        other[spec.key] = np.asarray(value).tolist() if isinstance(value, np.ndarray) else value
    table = read_performance_table(d.performance_file)
    return {"_source": {
        "controller": "ROSCO 2.10.6 (rosco wheel on PyPI), Examples/Test_Cases/NREL-5MW/DISCON.IN (LoggingLevel 0) "
                      "and its performance table Cp_Ct_Cq.NREL5MW.txt (Apache-2.0): the keys that "
                      "mbsym.wind.control.settings.DISCON_MAP does not map, and the thrust and torque tables",
        "generated_by": "tests/wind/operation/test_discon_write.py"},
        "other": other, "ct": np.asarray(table.ct).tolist(), "cq": np.asarray(table.cq).tolist()}
