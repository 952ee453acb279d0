"""Choosing the NMPC's prediction model with the fidelity ladder, in closed loop.

:func:`prediction_ladder` runs the operating turbine of every rung (a DOF set, with or without the
dynamic inflow) in the same closed-loop scene — our baseline controller compiled into the loop, the
same wind, each rung from its own steady guess at the first wind sample — and measures, for chosen
channels, the paper's ``ε = mean|y − y_ref| / range(y_ref)`` against the richest rung (the plant's
model), as :func:`mbsym.wind.analysis.fidelity.fidelity_ladder` does for free decays. Its result is a
:class:`~mbsym.wind.analysis.fidelity.FidelityLadder` (table, plot, :meth:`smallest`); each rung's
``coordinates`` are the states of its prediction model (:class:`~mbsym.wind.mpc.prediction.PredictionModel`, control
form), so ``n_dofs`` reads as the number of states the NMPC carries.

The rung flag ``"DBEMT"`` stands for the rotor-averaged dynamic inflow (two states).
"""

from __future__ import annotations

import time
from typing import Callable, Sequence

import numpy as np

from .fidelity import FidelityLadder, Rung, _epsilon

__all__ = ["prediction_ladder", "PREDICTION_LADDER", "LADDER_OUTPUTS"]

#: Rungs from the rotor alone to the plant's DOFs, with and without dynamic inflow.
PREDICTION_LADDER: tuple[tuple[str, ...], ...] = (
    ("GenDOF",),
    ("GenDOF", "DBEMT"),
    ("GenDOF", "TwFADOF1"),
    ("GenDOF", "TwFADOF1", "DBEMT"),
    ("GenDOF", "TwFADOF1", "TwSSDOF1", "DBEMT"),
)
#: Channels compared.
LADDER_OUTPUTS = ("GenSpeed", "BldPitch1", "GenPwr", "TTDspFA", "TwrBsMyt")


def prediction_ladder(plant, wind: Callable, tmax: float, *, ladder: Sequence[Sequence[str]] = PREDICTION_LADDER,
                      outputs: Sequence[str] = LADDER_OUTPUTS, tolerance: float = 0.02, settings=None,
                      t_out=None) -> FidelityLadder:
    """Closed-loop fidelity ladder of prediction models (module docstring).

    Parameters
    ----------
    plant : OperatingTurbine
        Gives the turbine data, rotor, actuators and dynamic-inflow model of every rung.
    wind : WindSignal or callable
        Hub-height wind [m/s] of time [s].
    tmax : float
        Simulated time [s].
    ladder : sequence of sequences of str, keyword-only
        ElastoDyn DOF flags per rung (with ``"DBEMT"`` for the dynamic inflow), smallest first.
    outputs : sequence of str, keyword-only
        Channels compared (OpenFAST names).
    tolerance : float, keyword-only
        ε for :meth:`FidelityLadder.smallest`.
    settings : BaselineSettings, optional, keyword-only
        Of the baseline controller (default: the built-in NREL 5 MW's).
    t_out : array, optional, keyword-only
        Output times (default every 0.05 s).

    Returns
    -------
    FidelityLadder
        ``integration_wall_s`` is the closed-loop run's integration time; ``build_wall_s`` the
        model's build.
    """
    from ..operation.controllers import baseline_in_loop
    from ..operation.model import OperatingTurbine
    from ..operation.nrel5mw import nrel5mw_baseline_settings
    from ..operation.simulation import simulate_turbine
    from ..operation.steady import steady_guess
    from ..control.baseline import BaselineController
    from ..mpc.prediction import PredictionModel

    if not ladder:
        raise ValueError("ladder must contain at least one rung.")
    settings = nrel5mw_baseline_settings() if settings is None else settings
    t_out = np.round(np.arange(0.0, tmax + 1e-9, 0.05), 10) if t_out is None else np.asarray(t_out, dtype=float)
    u0 = float(np.asarray(wind(0.0), dtype=float).reshape(-1)[0])
    runs = []
    for rung in ladder:
        dofs = tuple(f for f in rung if f != "DBEMT")
        inflow = "DBEMT" in rung
        t0 = time.perf_counter()
        model = OperatingTurbine(plant.turbine, plant.rotor, dofs=dofs, actuators=plant.actuators,
                                 dynamic_inflow=plant.dynamic_inflow if inflow else False, name="rung")
        model.dynamics()
        states = PredictionModel(model, dofs=dofs, dynamic_inflow=inflow).states
        build = time.perf_counter() - t0
        res = simulate_turbine(model, wind, tmax, controller=baseline_in_loop(BaselineController(settings)),
                               x0=steady_guess(model, u0).state, t_out=t_out)
        runs.append((tuple(rung), res, build, states))
    richest = runs[-1][1]
    rungs = []
    for rung, res, build, states in runs:
        errors = {o: _epsilon(res.t, res.output(o), richest.t, richest.output(o), o) for o in outputs}
        s = res.statistics
        rungs.append(Rung(rung, states, errors, {}, build, float(s.get("prepare_wall_s", np.nan)),
                          float(s["integration_wall_s"])))
    return FidelityLadder(tuple(rungs), tuple(outputs), float(tolerance), "rk4, baseline controller in the loop")
