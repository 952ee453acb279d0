"""The water's loads at the platform's exact velocity and acceleration (mbsym.wind.offshore._casadi.body_motion).

HydroDyn receives ElastoDyn's ``RotationVel``/``RotationAcc``: the angular velocity of the platform's Euler rates,
``ω = T(θ) θ̇``, not the rates themselves. References, independent of the code under test:
- the structure's own platform joint (mbsym.wind.structure.platform.platform_angular_velocity) for ``T`` and central
  differences along the motion for ``Ṫ θ̇``;
- OpenFAST v5.0.0 (tests/data/openfast_floating_axes/README.md): a roll-and-yaw decay of ``fl_decay_a`` with the
  platform held at 4° pitch (a roll acceleration then has a yaw component ``sin 4°``, which A66 = 2.0e10 kg m²
  turns into a yaw moment: with the DOF rates mbsym's yaw was at ε 14.3 %, now 1.43 %), and a decay released on
  every axis at once (sway 5 m, heave 1.5 m, roll 3°, pitch 2°, yaw 5°): ε 0.20–0.85 % on the translations, roll,
  pitch and TTDspFA, 1.8 % on yaw.
"""

from __future__ import annotations

import csv
import re
import shutil
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.wind.offshore._casadi import body_motion

from .conftest import FLOATING
from .test_offshore_morison import write_deck

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_floating_axes"
CASE = FLOATING / "cases" / "fl_decay_a"
needs_deck = pytest.mark.skipif(not CASE.is_dir(), reason=f"shared floating deck not found at {CASE}")


def test_body_motion_is_the_platform_joints_angular_velocity():
    """``J q̇`` against the platform joint's ω, and ``b = J̇ q̇`` against central differences of ``J(q(t)) q̇``."""
    from mbsym.wind.structure.platform import platform_angular_velocity

    rng = np.random.default_rng(5)
    for _ in range(5):
        q, qd = rng.normal(0, [2, 2, 1, 0.2, 0.2, 0.5]), rng.normal(0, [1, 1, 1, 0.1, 0.1, 0.1])
        v, J, b = (np.array(ca.evalf(e)) for e in body_motion(ca.DM(q), ca.DM(qd)))
        omega = np.array(ca.evalf(platform_angular_velocity(list(q[3:6]), list(qd[3:6])))).ravel()
        assert np.allclose(v.ravel(), np.r_[qd[0:3], omega], rtol=1e-13, atol=1e-15)
        assert np.allclose(J @ qd, v.ravel(), rtol=1e-13, atol=1e-15)
        h = 1e-6
        plus, minus = (np.array(ca.evalf(body_motion(ca.DM(q + s * h * qd), ca.DM(qd))[1])) @ qd for s in (1, -1))
        assert np.allclose(b.ravel(), (plus - minus) / (2 * h), rtol=1e-6, atol=1e-10)


def _edit_elastodyn(case: Path, dofs: dict[str, bool], initial: dict[str, float]) -> None:
    """Set DOF flags and initial conditions in the case's ElastoDyn file."""
    path = case / "fl_decay_a_ED.dat"
    text = path.read_text()
    for key, on in dofs.items():
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=on: f"{'True' if v else 'False'}{m.group(1)}", text,
                          count=1, flags=re.M)
        assert n == 1, key
    for key, value in initial.items():
        text, n = re.subn(rf"^\s*\S+(\s+{key}\s)", lambda m, v=value: f"{v:>12}{m.group(1)}", text, count=1,
                          flags=re.M)
        assert n == 1, key
    path.write_text(text)


def _reference(name: str) -> dict[str, np.ndarray]:
    with (DATA / f"{name}.csv").open() as fh:
        rows = list(csv.reader(fh))
    data = np.array(rows[1:], dtype=float)
    return {h.split("_[")[0]: data[:, k] for k, h in enumerate(rows[0])}


def _run(fst: Path, t_end: float, out: Path):
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    assert main(["simulate", str(fst), "--tmax", str(t_end), "--out", str(out)]) == 0
    return read_csv(out)


def _eps(run, ref, channel: str) -> float:
    from mbsym.wind.analysis.compare import error_metrics

    return error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])[0]


_PLATFORM = ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF", "TwFADOF1", "TwSSDOF1")


@needs_deck
def test_roll_acceleration_yaws_a_pitched_platform_as_in_openfast(tmp_path):
    """60 s with only roll and yaw free, pitch held at 4° (ElastoDyn holds a disabled DOF at its initial value),
    surge 10 m, heave 1.5 m, roll released from 3°, ``AddBQuad`` zeroed: yaw within ε 3 % (measured 1.43 %; 14.3 %
    with the DOF rates), roll 1 % (0.25 %)."""
    fst = write_deck(tmp_path, "none")
    _edit_elastodyn(fst.parent, {k: k in ("PtfmRDOF", "PtfmYDOF") for k in _PLATFORM}, {"PtfmRoll": 3.0})
    run = _run(fst, 60.0, tmp_path / "run.csv")
    ref = _reference("roll_yaw")
    assert _eps(run, ref, "PtfmYaw") <= 0.03
    assert _eps(run, ref, "PtfmRoll") <= 0.01
    assert np.interp(10.0, run.time, run.channel("PtfmYaw")) == pytest.approx(-0.2996, rel=0.1)   # OpenFAST's


@needs_deck
def test_decay_on_every_axis_matches_openfast(tmp_path):
    """300 s of the shared ``fl_decay_a`` (its ``AddBQuad`` kept) released from sway 5 m, heave 1.5 m, roll 3°,
    pitch 2°, yaw 5°: ε ≤ 1.5 % on surge, sway, heave, roll, pitch and TTDspFA (measured 0.85, 0.41, 0.20, 0.34,
    0.45, 0.77 %), ≤ 3 % on yaw (1.82 %)."""
    for folder in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi"):
        shutil.copytree(FLOATING / folder, tmp_path / folder, ignore=shutil.ignore_patterns("linearizations"))
    case = tmp_path / "cases" / "fl_decay_a"
    shutil.copytree(CASE, case)
    _edit_elastodyn(case, {}, {"PtfmSurge": 0.0, "PtfmSway": 5.0, "PtfmRoll": 3.0, "PtfmPitch": 2.0, "PtfmYaw": 5.0})
    run = _run(case / "fl_decay_a.fst", 300.0, tmp_path / "run.csv")
    ref = _reference("axes_decay")
    for channel in ("PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll", "PtfmPitch", "TTDspFA"):
        assert _eps(run, ref, channel) <= 0.015, (channel, _eps(run, ref, channel))
    assert _eps(run, ref, "PtfmYaw") <= 0.03
