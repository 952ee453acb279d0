"""examples/five_bar_nmpc.py runs: NMPC moves a closed-loop five-bar's end effector to the target.

Reference: the target point and the closed-form inverse kinematics that give the tracked motor angles
(independent of mbsym); the end effector's position is mbsym's point kinematics of the closed loop.
Tolerance: 1 mm (the run ends after 2.4 s with ~0.01 mm left); torques within their bound (8 N m) to
1e-6; the closure residual along the run below 1e-12 m (Newton-converged). Runtime ~4 s.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_five_bar_nmpc_example_reaches_the_target():
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    out = subprocess.run([sys.executable, str(ROOT / "examples" / "five_bar_nmpc.py")], capture_output=True,
                         text=True, check=True, env=env).stdout
    data = json.loads(out.strip().splitlines()[-1])
    assert data["error_m"] < 1e-3, data
    assert data["max_torque_Nm"] <= 8.0 + 1e-6
    assert data["max_closure_residual_m"] < 1e-12
    assert data["nmpc_failures"] == 0
