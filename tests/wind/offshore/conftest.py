"""Fixtures of the offshore tests (issue 20).

Reference data: ``shared/openfast/floating`` (the IEA 15 MW on the VolturnUS-S semi-submersible, OpenFAST
v5 deck and results; see its README). The shared directory sits next to the repository (``../shared``);
from a git worktree nested one level deeper it is found by walking up the ancestors, as in
``tests/wind/aero/conftest.py``. Tests needing it skip cleanly when it is absent.
"""

from __future__ import annotations

from pathlib import Path


def _find_shared() -> Path:
    here = Path(__file__).resolve()
    for parent in here.parents[3:]:  # the repository root, then its ancestors
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return here.parents[3].parent / "shared"


FLOATING = _find_shared() / "openfast" / "floating"
SEMI = FLOATING / "IEA-15-240-RWT-UMaineSemi"


def rosco_library():
    """ROSCO 2.10.6's ``libdiscon.so`` from the cached wheel (``tests/wind/control/_rosco.py``), or None."""
    import importlib.util

    path = Path(__file__).resolve().parents[1] / "control" / "_rosco.py"
    spec = importlib.util.spec_from_file_location("mbsym_tests_rosco", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.rosco_library()


def floating_case_copy(tmp_path: Path, aerodyn_edits) -> Path:
    """A copy of the shared floating decks in ``tmp_path`` with the AeroDyn keys ``aerodyn_edits`` ((key, value)
    pairs) set; the fl_steady_13 .fst path. Skips without the shared decks."""
    import re
    import shutil

    import pytest

    if not (FLOATING / "cases" / "fl_steady_13").is_dir():
        pytest.skip(f"shared floating decks not found at {FLOATING}")
    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi", "cases"):
        shutil.copytree(FLOATING / name, tmp_path / name)
    aerodyn = tmp_path / "IEA-15-240-RWT-UMaineSemi" / "IEA-15-240-RWT-UMaineSemi_AeroDyn15.dat"
    text = aerodyn.read_text()
    for key, value in aerodyn_edits:
        text, n = re.subn(rf"^\S+(\s+{key}\s)", rf"{value}\1", text, count=1, flags=re.M)
        assert n == 1, key
    aerodyn.write_text(text)
    return tmp_path / "cases" / "fl_steady_13" / "fl_steady_13.fst"
