"""eom.export_c: the generated C, compiled by the system compiler, agrees with the CasADi Functions.

Reference: ``eom.functions`` in CasADi's virtual machine (the Jacobians: CasADi's AD of
``eom.functions.rhs``), tolerance 1e-12 relative to the largest entry. ``main.c`` prints
every function at the x, u, p read from standard input. Skipped without a C compiler.
"""

import shutil
import subprocess

import numpy as np
import pytest

from mbsym.exceptions import ExportError
from mbsym.export import FUNCTION_NAMES

from . import _models

CC = shutil.which("cc") or shutil.which("gcc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler on the PATH")


def build_and_run(exported, stdin: str) -> dict[str, np.ndarray]:
    # -O0: these files only check the numbers; compile time matters more than speed here.
    cmd = exported.build_command(CC, flags=("-O0",))
    done = subprocess.run(cmd, cwd=exported.directory, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    run = subprocess.run(["./main"], cwd=exported.directory, input=stdin, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    out = {}
    for line in run.stdout.splitlines():
        name, rows, cols, *vals = line.split()
        out[name] = np.array([float(v) for v in vals]).reshape((int(rows), int(cols)), order="F")
    return out


def check(eom, tmp_path, functions=FUNCTION_NAMES, seed=0):
    exported = eom.export_c(tmp_path / "c", functions=functions)
    assert exported.header.exists() and exported.main.exists()
    pt = _models.random_point(eom, seed)
    x = np.concatenate([pt["q"], pt["qd"]])
    stdin = " ".join(repr(float(v)) for v in np.concatenate([x, pt["u"], pt["p"]]))
    got = build_and_run(exported, stdin)
    assert set(got) == set(functions)
    if "rhs" in got:                                   # main evaluates the residual at the qdd of rhs
        pt["qdd"] = got["rhs"][eom.n_q:, 0]
    ref = _models.references(eom, pt)
    for name in functions:
        _models.close(got[name], ref[name].reshape(got[name].shape), f"{eom.name}.{name}")
    return got


@needs_cc
def test_double_pendulum_all_functions(tmp_path):
    got = check(_models.double_pendulum(), tmp_path)
    assert np.max(np.abs(got["residual"])) < 1e-12       # F - M qdd at rhs's qdd


@needs_cc
def test_pendulum_with_input_and_defaults(tmp_path):
    eom = _models.pendulum()
    check(eom, tmp_path, seed=3)
    got = build_and_run(eom.export_c(tmp_path / "d"), "")          # no input: x = 0, u = 0, p = defaults
    M = eom.mass_matrix([0.0], eom.defaults)
    np.testing.assert_allclose(got["mass_matrix"], M, rtol=1e-15)


@needs_cc
def test_closed_loop_four_bar(tmp_path):
    """A closed loop: the dependent-coordinate Newton steps are plain SX, so every function exports."""
    check(_models.four_bar(), tmp_path)


@needs_cc
def test_turbine_with_prescribed_azimuth(tmp_path):
    """Mass matrix (q, u, p) of a model with prescribed coordinates; M, F, rhs and the Jacobians."""
    check(_models.turbine(prescribed=True), tmp_path)


@needs_cc
def test_mx_rhs_beyond_eight_coordinates(tmp_path):
    """rhs with CasADi's qr solver generated as plain C (no CasADi library at link time)."""
    check(_models.chain(9), tmp_path, functions=("mass_matrix", "forcing", "rhs"))


def test_bad_exports(tmp_path):
    eom = _models.pendulum()
    with pytest.raises(ExportError, match="C identifier"):
        eom.export_c(tmp_path, name="2pendulum")
    with pytest.raises(ExportError, match="unknown functions"):
        eom.export_c(tmp_path, functions=["hessian"])
    with pytest.raises(TypeError):
        eom.export_c(tmp_path, compiler="gcc")
    assert not any(tmp_path.iterdir())                 # nothing written by a failed call
