"""The closed-loop fidelity ladder of prediction models (``mbsym.wind.analysis.prediction_ladder``).

References: the paper's ε = mean|y − y_ref| / range(y_ref) recomputed by hand; a rung with the plant's
own DOFs and inflow reproduces the plant exactly (ε = 0); a rigid tower has no tower-top displacement
(TTDspFA ≡ 0), so its ε on TTDspFA is mean|y_ref| / range(y_ref) of the plant's run.
"""

from __future__ import annotations

import numpy as np
import pytest

from _mpc_setup import turbine


def test_ladder_ranks_rigid_tower_out_and_reproduces_the_plant():
    from mbsym.wind.analysis.prediction_ladder import prediction_ladder
    from mbsym.wind.inflow import parse_wind_spec

    t = turbine()
    wind = parse_wind_spec("step:12:14:1")
    rungs = [("GenDOF",), ("GenDOF", "TwFADOF1", "TwSSDOF1", "DBEMT")]
    lad = prediction_ladder(t.plant, wind, 6.0, ladder=rungs, outputs=("GenSpeed", "TTDspFA"), tolerance=0.02)
    rigid, full = lad.rungs
    assert full.errors == {"GenSpeed": 0.0, "TTDspFA": 0.0}
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.control import BaselineController
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    plant_run = simulate_turbine(t.plant, wind, 6.0, x0=steady_guess(t.plant, 12.0).state,
                                 t_out=np.round(np.arange(0.0, 6.0 + 1e-9, 0.05), 10),
                                 controller=baseline_in_loop(BaselineController(t.deck.baseline_settings())))
    y = plant_run.output("TTDspFA")
    assert rigid.errors["TTDspFA"] == pytest.approx(np.mean(np.abs(y)) / np.ptp(y), rel=1e-9)
    assert 0 < rigid.errors["GenSpeed"] < 0.5
    assert lad.smallest().dofs == rungs[1]
    assert rigid.coordinates == ("GeAz_d", "BlPitch", "GenTq") and full.n_dofs == 9   # prediction states
    assert "Gen + FA1 + SS1 + DBEMT (9)" in lad.table()
