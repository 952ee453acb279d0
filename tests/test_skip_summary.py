"""The test run says why tests were skipped (issue 22, item 11): a summary by missing resource, with the fix.

Reference: a throw-away test directory with our conftest and three tests skipped for known reasons, run by
pytest in a subprocess; its summary must count each cause once and name where the shared data was looked for.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent


def test_skips_are_summarized_by_cause(tmp_path):
    shutil.copy(HERE / "conftest.py", tmp_path / "conftest.py")
    (tmp_path / "test_needs.py").write_text(
        "import pytest\n"
        "def test_a():\n    pytest.skip('shared OpenFAST reference data not found at /nowhere/x.fst')\n"
        "def test_b():\n    pytest.skip('shared reference data not found at /nowhere/y')\n"
        "def test_c():\n    pytest.skip('the ROSCO 2.10.6 library is not cached and could not be fetched with pip')\n"
        "def test_d():\n    pytest.skip('no display')\n"
        "def test_e():\n    assert True\n")
    run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--rootdir",
                          str(tmp_path), str(tmp_path)], capture_output=True, text=True, timeout=120)
    out = run.stdout
    assert run.returncode == 0, out + run.stderr
    assert "skipped tests, by what they need" in out
    assert "2 skipped: the shared OpenFAST/TurbSim reference data (looked for" in out
    assert "1 skipped: the ROSCO 2.10.6 wheel" in out and "1 skipped: other reasons" in out
