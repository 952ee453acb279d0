"""The README quick-start contract and the CLI entry points.

Reference: the textbook closed form of the planar double pendulum
(:func:`mbsym.demo.double_pendulum_closed_form`, derived by hand from the
Lagrangian with relative angles). Tolerance 1e-12 absolute: both sides are
exact expressions evaluated in double precision.
"""

import json
import subprocess
import sys as _sys
from pathlib import Path

import numpy as np

import mbsym as mb
from mbsym.cli import main
from mbsym.demo import double_pendulum_closed_form

ROOT = Path(__file__).resolve().parents[1]


def test_contract_snippet_matches_closed_form():
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    m1, m2, l1, l2 = sys.parameters("m1 m2 l1 l2")
    b1 = mb.RigidBody("b1", mass=m1, com=[0, 0, -l1])
    b2 = mb.RigidBody("b2", mass=m2, com=[0, 0, -l2])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, b2, axis=[0, 1, 0], coordinate=q2, offset=[0, 0, -l1]))
    eom = sys.equations()
    p = {"m1": 2.0, "m2": 1.0, "l1": 1.0, "l2": 0.5}
    M = eom.mass_matrix([0.3, -0.2], p)
    F = eom.forcing([0.3, -0.2], [0.1, 0.4], p)
    assert isinstance(M, np.ndarray) and M.shape == (2, 2)
    assert isinstance(F, np.ndarray) and F.shape == (2,)
    M_ref, F_ref = double_pendulum_closed_form([0.3, -0.2], [0.1, 0.4], **p)
    np.testing.assert_allclose(M, M_ref, rtol=0, atol=1e-12)
    np.testing.assert_allclose(F, F_ref, rtol=0, atol=1e-12)


def test_example_script_last_line_is_json():
    out = subprocess.run([_sys.executable, str(ROOT / "examples" / "double_pendulum.py")],
                         capture_output=True, text=True, check=True).stdout
    data = json.loads(out.strip().splitlines()[-1])
    assert data["max_error"] < 1e-12


def test_cli_version_and_help(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("mbsym ")
    assert main(["--no-such-flag"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert main([]) == 0
    assert "demo" in capsys.readouterr().out


def test_cli_demo_energy_and_closed_form(capsys):
    assert main(["demo", "--tmax", "2"]) == 0
    text = capsys.readouterr().out
    assert "max |M - closed form|" in text


def test_cli_bad_input_exits_nonzero(capsys):
    assert main(["demo", "--tmax", "-1"]) == 2
    assert "error" in capsys.readouterr().err
