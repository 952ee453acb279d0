"""The turbine NMPC/estimator test set-up, built once per process (a plain module, imported by name).

The built-in NREL 5 MW operating turbine (GenDOF, TwFADOF1, TwSSDOF1, dynamic inflow) as the plant,
its default prediction model (GenDOF + TwFADOF1 + dynamic inflow, rate inputs), the set-points from
ROSCO 2.10.6's NREL 5 MW settings (package data) and the steady reference table.
"""

from __future__ import annotations

import functools
from types import SimpleNamespace


@functools.lru_cache(maxsize=None)
def turbine() -> SimpleNamespace:
    from mbsym.wind.mpc.prediction import PredictionModel
    from mbsym.wind.mpc.setpoints import SetPoints, reference_table
    from mbsym.wind.operation.deck import builtin_deck

    deck = builtin_deck()
    plant = deck.model()
    plant.dynamics()
    prediction = PredictionModel(plant)
    setpoints = SetPoints.from_settings(deck.baseline_settings(), plant.rotor)
    return SimpleNamespace(deck=deck, plant=plant, prediction=prediction, setpoints=setpoints,
                           references=reference_table(prediction, setpoints))


@functools.lru_cache(maxsize=None)
def nmpc_default():
    """One compiled NMPC (default tuning), reset before each use by the tests."""
    from mbsym.wind.mpc.nmpc import TurbineNMPC

    t = turbine()
    return TurbineNMPC(t.prediction, t.setpoints, references=t.references)
