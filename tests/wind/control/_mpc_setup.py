"""The turbine NMPC/estimator test set-up, built once per process (a plain module, imported by name).

The built-in NREL 5 MW operating turbine (GenDOF, TwFADOF1, TwSSDOF1, dynamic inflow) as the plant,
its default prediction model (GenDOF + TwFADOF1 + dynamic inflow, rate inputs), the set-points from
ROSCO 2.10.6's NREL 5 MW settings (package data) and the steady reference table.
"""

from __future__ import annotations

import functools
import math
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


LOOP_SI = (math.pi / 30.0, math.pi / 30.0, math.pi / 180.0, 1e3, 1.0, 1e3, 1.0)   # LOOP_CHANNELS -> SI


def library_closed_loop(library: dict, wind, seconds: float, x0, lidar=None):
    """An exported library (``{"library", "input", ...}``) closed on the built-in turbine's plant in mbsym's DISCON
    loop at 0.01 s from ``x0`` (float32 swap array; ``lidar`` as :class:`DisconController` takes it): every call's
    ``(t, LOOP_CHANNELS in SI as float32, commands)``, the result and the library's messages."""
    import numpy as np

    from mbsym.simulate.api import simulate
    from mbsym.simulate.controller import DiscreteController
    from mbsym.wind.control import DisconController
    from mbsym.wind.mpc import LOOP_CHANNELS, measurement_dynamics
    from mbsym.wind.operation.controllers import ACTUATED, held_commands

    t, rows = turbine(), []
    with DisconController(library["library"], library["input"], dt=0.01, individual_pitch=False, lidar=lidar) as lib:
        step = lib.callable(LOOP_CHANNELS, ("BlPitchCom1", "GenTqCom"))

        def law(tt, xc, y):
            y32 = np.asarray(y * np.asarray(LOOP_SI), dtype=np.float32).astype(float)
            u = step(tt, y32)
            rows.append((tt, y32, u))
            return xc, u

        ctrl = DiscreteController(law, 0.01, np.zeros(0), measurements=LOOP_CHANNELS, actuates=ACTUATED)
        res = simulate(measurement_dynamics(t.plant, LOOP_CHANNELS), seconds, x0=x0, controller=ctrl, method="rk4",
                       dt=0.01, inputs={"Wind1VelX": wind, **held_commands(t.plant, x0)}, compile=True)
        messages = list(lib.messages)
    return rows, res, messages


def recorded_loop(nmpc, estimator, wind, seconds: float, x0):
    """The Python loop (TurbineLoop: the NMPC's own RTI, the estimator in numpy) closed on the built-in turbine's
    plant: every loop sample's ``(t, measurements in loop units, commands)``."""
    import numpy as np

    from mbsym.wind.mpc import TurbineLoop, simulate_with_loop

    t = turbine()
    loop = TurbineLoop(t.plant, t.deck.controller_dt, nmpc=nmpc, estimator=estimator)
    law, rows = loop.law, []

    def recording(tt, xc, y):
        xn, u = law(tt, xc, y)
        rows.append((tt, np.array(y, dtype=float), np.array(u, dtype=float)))
        return xn, u

    loop.law = recording
    simulate_with_loop(t.plant, wind, seconds, loop, x0=x0, compile=True)
    return rows
