"""Gearbox losses (ElastoDyn's ``GBoxEff`` < 100 %, ``mbsym.wind.structure.gearbox``).

References:
- closed form, rigid drivetrain (ElastoDyn's FillAugMat "GBFric" terms: the generator's side of the
  generator-azimuth equation times ``k = 1/eta`` when the shaft drives the generator, ``eta`` when it is driven):
  ``alpha = (Q_rotor - N T_g k) / (J_rotor + J_gen N^2 / eta)``, to 1e-10 relative;
- identity, drivetrain torsion: the drivetrain spring and damper carry the generator's side times ``k``,
  ``k N (J_gen N GeAz_dd + T_g) = K DrTr + C DrTr_d``, for either sign of the shaft torque, to 1e-9 relative;
- OpenFAST v5.0.0 + ROSCO 2.10.6 with ``GBoxEff`` 90 (tests/data/openfast_gearbox/README.md): the steady states at
  8 and 14 m/s within the tolerances of tests/wind/operation/test_operating_points_cli.py (RotSpeed 0.5 %, pitch
  0.3 deg, GenPwr 1 %, RtAeroFxh 2 %, TTDspFA 3 %), which the same turbine without the losses misses (rotor speed
  3.5 % high at 8 m/s, pitch 0.86 deg high at 14 m/s); the shaft torque (RotTorq = 97 T_g / 0.9) to 0.1 %; the
  steady drivetrain twist with DrTrDOF to 0.1 %.
"""

from __future__ import annotations

import csv
import dataclasses
import json
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from _op_data import INPUTS, need
from mbsym.cli import main
from mbsym.wind import nrel5mw
from mbsym.wind.structure.elastodyn_nodes import rotor_mass_properties
from mbsym.wind.structure.turbine import TurbineModel

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_gearbox"
ETA = 0.9


def _accelerations(model, u: dict, q: dict | None = None) -> dict:
    eom = model.eom
    qv = np.array([(q or {}).get(c, 0.0) for c in eom.coordinates])
    a = eom.accelerations(qv, np.zeros(eom.n_q), [u.get(n, 0.0) for n in eom.inputs])
    return dict(zip(eom.coordinates, np.asarray(a, dtype=float).ravel()))


@pytest.mark.parametrize("torque", [40e3, -40e3])
def test_rigid_drivetrain_closed_form(torque):
    t = dataclasses.replace(nrel5mw(), gearbox_efficiency=ETA)
    n, j_g = abs(t.gearbox_ratio), t.generator_inertia
    j_r = rotor_mass_properties(t).rotor_inertia
    k = 1.0 / ETA if torque >= 0 else ETA
    a = _accelerations(TurbineModel(t, ["GenDOF"]), {"GenTq": torque, "RotTorq": 4e6})["GeAz"]
    assert a == pytest.approx((4e6 - n * torque * k) / (j_r + j_g * n**2 / ETA), rel=1e-10)
    lossless = _accelerations(TurbineModel(nrel5mw(), ["GenDOF"]), {"GenTq": torque, "RotTorq": 4e6})["GeAz"]
    assert abs(a / lossless - 1) > 1e-3                                   # the losses act


@pytest.mark.parametrize("shaft_torque", [2e5, -2e5])
def test_drivetrain_torsion_carries_the_losses(shaft_torque):
    """With the tower, yaw and drivetrain DOFs on: the generator's side times k equals the torsion's torque."""
    t = dataclasses.replace(nrel5mw(), gearbox_efficiency=ETA)
    model = TurbineModel(t, ["GenDOF", "DrTrDOF", "TwFADOF1", "TwSSDOF1", "YawDOF"])
    n, j_g = abs(t.gearbox_ratio), t.generator_inertia
    eom = model.eom
    q = np.array([{"DrTr": shaft_torque / t.drivetrain_stiffness, "TSS1": 0.05}.get(c, 0.0) for c in eom.coordinates])
    qd = np.array([{"GeAz": 1.2, "TSS1": 0.1, "Yaw": 0.01}.get(c, 0.0) for c in eom.coordinates])
    u = [{"GenTq": 40e3, "RotTorq": 4e6}.get(name, 0.0) for name in eom.inputs]
    qdd = eom.accelerations(q, qd, u)
    kin = eom.point_kinematics("generator")(q, qd, qdd, u, eom.parameter_vector())
    out = dict(zip(eom.point_kinematics("generator").name_out(), kin))
    alpha = float(np.asarray(out["wd"]).ravel() @ np.asarray(out["R"])[:, 0])   # about the generator's axis
    spring = shaft_torque + t.drivetrain_damping * qd[eom.coordinates.index("DrTr")]
    k = 1.0 / ETA if spring >= 0 else ETA
    assert k * n * (j_g * alpha + 40e3) == pytest.approx(spring, rel=1e-9)
    assert abs(alpha - n * qdd[eom.coordinates.index("GeAz")]) > 1e-6 * abs(alpha)   # the nacelle turns too


def _deck(tmp_path: Path, case: str, *, drivetrain: bool = False) -> Path:
    """A copy of the shared ``case`` with GBoxEff 90 (and DrTrDOF True), the shared deck folder beside it."""
    src = need(INPUTS / case)
    tmp_path.mkdir(parents=True, exist_ok=True)
    dst = tmp_path / case
    shutil.copytree(src, dst)
    (tmp_path / "deck").symlink_to(INPUTS / "deck")
    ed = dst / f"{case}_ED.dat"
    text = re.sub(r"^\s*\S+(\s+GBoxEff\b)", r"90\1", ed.read_text(), count=1, flags=re.M)
    if drivetrain:
        text = re.sub(r"^\s*\S+(\s+DrTrDOF\b)", r"True\1", text, count=1, flags=re.M)
    ed.write_text(text)
    return dst / f"{case}.fst"


def _reference() -> dict[float, dict[str, float]]:
    with (DATA / "steady_gboxeff90.csv").open() as fh:
        return {float(r["WindSpeed_[m/s]"]): {k.split("_[")[0]: float(v) for k, v in r.items()}
                for r in csv.DictReader(fh)}


TOLERANCES = {"RotSpeed": ("rel", 0.005), "BldPitch1": ("abs", 0.3), "GenPwr": ("rel", 0.01),
              "RtAeroFxh": ("rel", 0.02), "TTDspFA": ("rel", 0.03)}


def _misses(result: dict, ref: dict) -> list:
    out = []
    for i, u in enumerate(result["wind_speed"]):
        for name, (kind, tol) in TOLERANCES.items():
            ours, theirs = result[name][i], ref[u][name]
            err = abs(ours - theirs) if kind == "abs" else abs(ours / theirs - 1)
            if err > tol:
                out.append((u, name, ours, theirs))
    return out


def test_steady_states_match_openfast(tmp_path, capsys):
    fst = _deck(tmp_path, "steady_14")
    ref = _reference()
    assert main(["operating-points", str(fst), "--wind", "8,14", "--json"]) == 0
    result = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert result["success"] == [True, True]
    assert _misses(result, ref) == []
    # the losses matter at these tolerances: the turbine without them misses OpenFAST's lossy runs
    assert main(["operating-points", str(need(INPUTS / "steady_14" / "steady_14.fst")), "--wind", "8,14",
                 "--json"]) == 0
    lossless = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert {(u, n) for u, n, *_ in _misses(lossless, ref)} >= {(8.0, "RotSpeed"), (14.0, "BldPitch1")}


def test_shaft_torque_and_twist_match_openfast(tmp_path):
    """RotTorq of the steady 14 m/s run (rigid drivetrain, the trim: N T_g / eta) and the drivetrain's twist with
    DrTrDOF (step_10_14 settled: K DrTr = N T_g / eta), 0.1 %."""
    from mbsym.wind.operation import OperatingTurbine, trim

    ref = _reference()[14.0]
    with (DATA / "drtr_step_gboxeff90.csv").open() as fh:
        settled = {r["quantity"]: float(r["value"]) for r in csv.DictReader(fh)}
    drtr = OperatingTurbine.from_openfast(_deck(tmp_path / "drtr", "steady_14", drivetrain=True))
    assert drtr.gearbox_efficiency == ETA
    x0 = drtr.initial_state(14.0, rotor_speed=12.1 * np.pi / 30, pitch=np.deg2rad(ref["BldPitch1"]),
                            torque=1e3 * settled["GenTq_mean_60_90s"])
    assert x0[drtr.dynamics().states.index("DrTr")] == pytest.approx(settled["Q_DrTr_mean_60_90s"], rel=1e-3)
    point = trim(OperatingTurbine.from_openfast(_deck(tmp_path / "rigid", "steady_14")), 14.0)
    assert point.success
    assert point["RotTorq"] == pytest.approx(ref["RotTorq"], rel=1e-3)
    assert point["GenTq"] == pytest.approx(ref["GenTq"], rel=1e-3)
