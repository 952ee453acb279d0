"""The design-optimization example runs, reports exact gradients and meets its constraints (slow: ~1 min).

References: central finite differences of the same objective and eigenvalue (the example's own check,
tolerance 1e-5 relative), the constraint bounds it declares.
"""

from __future__ import annotations

import importlib.util
import json
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "design_optimization.py"


@pytest.mark.slow
def test_design_optimization_example(capsys):
    spec = importlib.util.spec_from_file_location("design_optimization", EXAMPLE)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.main()
    summary = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert summary["success"]
    assert summary["gradient_check_rel_err"]["response"] < 1e-5
    assert summary["gradient_check_rel_err"]["frequency"] < 1e-5
    assert summary["lowest_frequency_hz"] >= mod.F_MIN - 1e-6
    assert summary["stroke_rms_m"] <= mod.STROKE_MAX + 1e-6
    assert summary["rms_tower_top_m"]["optimum"] < summary["rms_tower_top_m"]["start"]
