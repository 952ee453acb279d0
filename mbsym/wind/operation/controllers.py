"""Controllers in the loop of an operating turbine (:class:`mbsym.simulate.DiscreteController`).

The plant's measurements are its OpenFAST channels (:data:`MEASUREMENTS`: ``GenSpeed`` [rpm],
``RotSpeed`` [rpm], ``BldPitch1`` [deg], ``GenPwr`` [kW], ``Wind1VelX`` [m/s]); the
controllers work in SI units, so each law below first multiplies them by :data:`TO_SI`. The
commands are the plant's inputs ``BlPitchCom`` [rad] and ``GenTqCom`` [N m], held between
samples (zero-order hold, as ServoDyn holds a DISCON library's commands).

* :func:`baseline_in_loop`: our :class:`~mbsym.wind.control.BaselineController` (a CasADi
  Function), so plant, aerodynamics and controller run in **one generated loop**;
* :func:`discon_in_loop`: a DISCON library (:class:`~mbsym.wind.control.DisconController`),
  called once per sample from Python between compiled plant steps;
* no controller: the commands are inputs like the wind (:func:`held_commands` gives the
  constants that keep the initial state).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np

from ...simulate.controller import DiscreteController
from ..control.baseline import BaselineController
from ..control.discon import DisconController

__all__ = ["MEASUREMENTS", "TO_SI", "ACTUATED", "baseline_in_loop", "discon_in_loop", "held_commands"]

#: Plant channels the controllers read, in the order of the controllers' ``y``.
MEASUREMENTS = ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX")
#: Factors from the channels' OpenFAST units (rpm, rpm, deg, kW, m/s) to SI (rad/s, rad/s, rad, W, m/s).
TO_SI = (math.pi / 30.0, math.pi / 30.0, math.pi / 180.0, 1e3, 1.0)
#: Plant inputs the controllers set, in the order of their ``u``.
ACTUATED = ("BlPitchCom", "GenTqCom")


def baseline_in_loop(controller: BaselineController, *, name: str = "baseline") -> DiscreteController:
    """Our baseline controller as a :class:`DiscreteController` of the plant's channels.

    Parameters
    ----------
    controller : BaselineController
        E.g. ``BaselineController.from_discon("DISCON.IN", dt=0.00625)``.
    name : str, optional, keyword-only
        Prefix of the controller's state names in results (``baseline.first`` ...).
    """
    if not isinstance(controller, BaselineController):
        raise TypeError(f"controller must be a BaselineController; got {type(controller).__name__}.")
    f = controller.function
    xc = ca.SX.sym("xc", f.numel_in(0))
    y = ca.SX.sym("y", len(MEASUREMENTS))
    x_next, u = f(xc, y * ca.DM(TO_SI))
    law = ca.Function(f"{name}_in_loop", [xc, y], [x_next, u], ["xc", "y"], ["xc_next", "u"], {"cse": True})
    return DiscreteController(law, controller.dt, controller.x0, measurements=MEASUREMENTS, actuates=ACTUATED,
                              state_names=[f"{name}.{s}" for s in controller.state_names], name=name)


def discon_in_loop(controller: DisconController, *, name: str = "discon") -> DiscreteController:
    """A DISCON library as a :class:`DiscreteController` (a Python call per sample).

    The library is initialized at the first sample (t = 0) and keeps its state; use a new
    :class:`DisconController` for every simulation (:meth:`DisconController.close` after).
    """
    if not isinstance(controller, DisconController):
        raise TypeError(f"controller must be a DisconController; got {type(controller).__name__}.")
    step = controller.callable(MEASUREMENTS, ("BlPitchCom1", "GenTqCom"))
    scale = np.asarray(TO_SI)
    empty = np.zeros(0)

    def law(t: float, xc: np.ndarray, y: np.ndarray):
        return empty, step(t, y * scale)

    return DiscreteController(law, controller.dt, measurements=MEASUREMENTS, actuates=ACTUATED, name=name)


def held_commands(model, x0) -> dict[str, float]:
    """Constant commands that hold the actuators of ``model`` at the state ``x0``: ``{BlPitchCom…, GenTqCom}``."""
    dyn = model.dynamics()
    x = dict(zip(dyn.states, np.asarray(x0, dtype=float)))
    out = {c: float(x[n]) for n, c in zip(model.pitch_names, model.command_names)}
    out["GenTqCom"] = float(x["GenTq"])
    return out
