"""The NMPC's models and loop on decks unlike the shared ones (found on the ROSCO wheel's NREL 2.8-127, 2026-11-30).

- a deck without a tower DOF (the stock NREL 2.8-127: flap, edge, generator): the prediction model takes the DOFs
  the plant has, as the estimation model does; it had asked for the first tower mode, and the estimator, which
  has no tower, then refused ("the estimator does not estimate ['TFA1', 'TFA1_d']");
- a plant pitched blade by blade (a deck whose controller runs IPC): the loop's one collective command goes to
  every blade; it had been refused ("the controller actuates ['BlPitchCom'], which are not inputs");
- ``mbsym export-discon --controller nmpc`` on such a deck: the fallback baseline without IPC, said.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

AERO = Path(__file__).resolve().parents[3].parent / "shared" / "openfast" / "aero"


def test_prediction_model_takes_the_dofs_the_plant_has():
    from mbsym.wind.mpc.estimator import estimation_model
    from mbsym.wind.mpc.nmpc import TurbineNMPC
    from mbsym.wind.mpc.prediction import PredictionModel
    from mbsym.wind.mpc.setpoints import SetPoints
    from mbsym.wind.operation import OperatingTurbine
    from mbsym.wind.operation.nrel5mw import nrel5mw_baseline_settings

    plant = OperatingTurbine.nrel5mw(dofs=("GenDOF",))
    prediction = PredictionModel(plant)
    assert prediction.dofs == ("GenDOF",) and "TFA1" not in prediction.states
    assert set(prediction.states) <= set(estimation_model(plant).states) | {"GenTq", "BlPitch"}
    nmpc = TurbineNMPC(prediction, SetPoints.from_settings(nrel5mw_baseline_settings(), plant.rotor))
    assert nmpc.prediction is prediction
    assert PredictionModel(OperatingTurbine.nrel5mw()).dofs == ("GenDOF", "TwFADOF1")     # unchanged with a tower


def test_loop_spreads_its_collective_pitch_over_a_plant_pitched_blade_by_blade():
    from mbsym.wind.control import BaselineController
    from mbsym.wind.mpc.loop import TurbineLoop
    from mbsym.wind.operation.deck import operating_deck

    fst = AERO / "openfast_inputs" / "ff14_rigid" / "ff14_rigid.fst"
    if not fst.is_file():
        pytest.skip(f"shared OpenFAST data not found at {fst}")
    deck = operating_deck(fst)
    plant = deck.model(aero="blade", pitch="individual")
    controller = TurbineLoop(plant, 0.00625, baseline=BaselineController(deck.baseline_settings())).controller()
    assert controller.actuates == ("BlPitchCom1", "BlPitchCom2", "BlPitchCom3", "GenTqCom")
    y = np.array([1170.0, 12.06, 10.0, 5000.0, 14.0, 43.0, 0.0])[:len(controller.measurements)]
    _, u = controller.law(0.0, controller.x0, y)
    assert u.shape == (4,) and u[0] == u[1] == u[2] == pytest.approx(np.deg2rad(10.0))    # the first call holds


@pytest.mark.slow
def test_export_nmpc_on_a_deck_with_ipc_leaves_it_out_of_the_fallback(tmp_path, capsys):
    """The shared steady deck with its DISCON.IN's IPC_ControlMode 1 (a copy): the export works and says so."""
    import json
    import shutil

    from mbsym.cli import main

    src = AERO / "openfast_inputs"
    if not (src / "steady_14").is_dir():
        pytest.skip(f"shared OpenFAST data not found at {src}")
    for name in ("steady_14", "deck"):
        shutil.copytree(src / name, tmp_path / name)
    discon = tmp_path / "deck" / "DISCON.IN"
    text = discon.read_text()
    discon.write_text(text.replace("0                   ! IPC_ControlMode", "1                   ! IPC_ControlMode"))
    assert main(["export-discon", str(tmp_path / "steady_14" / "steady_14.fst"), "--controller", "nmpc", "--out",
                 str(tmp_path / "lib")]) == 0
    out = capsys.readouterr().out
    assert "leaves out the deck's individual pitch control (IPC_ControlMode 1)" in out
    assert Path(json.loads(out.strip().splitlines()[-1])["library"]).is_file()


@pytest.mark.slow
def test_nmpc_holds_the_stock_nrel5mw_deck_at_rated(tmp_path):
    """The ROSCO wheel's NREL 5 MW deck as shipped (flexible blades, drivetrain, yaw, UA, a uniform wind: a
    blade-element plant) at a steady 16 m/s, ``mbsym simulate --controller nmpc``: with the rotor-effective tunings
    its EKF's wind ran from 14.4 to −1.7 m/s and the rotor to 24 rpm, no warning; it now takes the tunings made for
    a blade-element plant (``blade_element_plant``): measured max 13.37 rpm at the start, 12.11 rpm and 5.01 MW at
    30 s. Bounds: max 1.15x rated speed, the last 5 s within 1 % of 12.1 rpm and 2 % of 5 MW."""
    import _rosco

    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    fst = _rosco.rosco_nrel5mw_deck()
    if fst is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    out = tmp_path / "nmpc.csv"
    assert main(["simulate", str(fst), "--controller", "nmpc", "--tmax", "30", "--wind", "steady:16", "--out",
                 str(out)]) == 0
    rec = read_csv(out)
    names, data, t = list(rec.names), np.asarray(rec.data, dtype=float), np.asarray(rec.time)
    speed = data[:, next(i for i, n in enumerate(names) if n.startswith("RotSpeed"))]
    power = data[:, next(i for i, n in enumerate(names) if n.startswith("GenPwr"))]
    last = t >= 25.0
    assert speed.max() < 1.15 * 12.1
    assert np.all(np.abs(speed[last] / 12.1 - 1.0) < 0.01) and np.all(np.abs(power[last] / 5000.0 - 1.0) < 0.02)
