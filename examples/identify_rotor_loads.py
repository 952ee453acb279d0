"""Tower damping of an operating turbine from its recorded rotor loads (mbsym identify --model loads).

The record is an OpenFAST v5 run of the NREL 5 MW (AeroDyn 15 with DBEMT, the ROSCO 2.10.6 controller) through
a 10 -> 14 m/s wind step, with AeroDyn's six rotor loads recorded (tests/data/openfast_step_rotor_loads, README
there; the deck says TwrFADmp(1) = TwrSSDmp(1) = 1 %). The structure alone, driven by those loads, the pitch and
the generator torque, isolates the structural damping: the aerodynamic damping, about 6 of the tower fore-aft
mode's 7 points, is in the recorded loads, so no aerodynamic model enters the fit.

Run: ``python examples/identify_rotor_loads.py`` (a few seconds; no OpenFAST deck needed: the built-in
NREL 5 MW has the same ElastoDyn structure).
"""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import mbsym as mb
from mbsym.wind.analysis.compare import read_csv
from mbsym.wind.operation import OperatingTurbine
from mbsym.wind.operation.measured_loads import MeasuredLoadTurbine

RECORD = Path(__file__).resolve().parents[1] / "tests" / "data" / "openfast_step_rotor_loads" / \
    "step_10_14_rotor_loads.csv"


def main() -> dict:
    t0 = time.perf_counter()
    series = read_csv(RECORD)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)          # the rotor-effective surfaces are not used here
        plant = OperatingTurbine.nrel5mw(dofs=("TwFADOF1", "TwSSDOF1", "GenDOF"), disk_moments=True)
    model = MeasuredLoadTurbine(plant)
    U = model.inputs_from(series)                              # loads turned from the hub frame by the azimuth
    x0 = model.initial_state_from(series, U[0])                # at rest under the first loads
    res = mb.identify(model, series, ["TwrFADmp(1)", "TwrSSDmp(1)"], inputs=U, x0=x0,
                      channels=["Q_TFA1", "QD_TFA1", "Q_TSS1", "QD_TSS1"],
                      initial={"TwrFADmp(1)": 2.0, "TwrSSDmp(1)": 2.0})
    print(res.summary())
    print(f"deck: 1 % and 1 %; whole script {time.perf_counter() - t0:.1f} s")
    return res.parameters


if __name__ == "__main__":
    main()
