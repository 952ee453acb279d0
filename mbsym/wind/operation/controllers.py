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
from typing import Sequence

import casadi as ca
import numpy as np

from ...simulate.controller import DiscreteController
from ..control.baseline import BaselineController
from ..control.discon import DisconController

__all__ = ["MEASUREMENTS", "TO_SI", "ACTUATED", "BLADE_MEASUREMENTS", "FLOATING_MEASUREMENTS", "PLATFORM_MEASUREMENTS",
           "DISCON_MEASUREMENTS",
           "SI_FACTORS",
           "measurement_names",
           "baseline_in_loop", "discon_in_loop", "held_commands"]

#: Plant channels the controllers read, in the order of their ``y``.
MEASUREMENTS = ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX")
#: Factors from the channels' OpenFAST units (rpm, rpm, deg, kW, m/s) to SI (rad/s, rad/s, rad, W, m/s).
TO_SI = (math.pi / 30.0, math.pi / 30.0, math.pi / 180.0, 1e3, 1.0)
#: Plant inputs the controllers set, in the order of their ``u``.
ACTUATED = ("BlPitchCom", "GenTqCom")
#: Further channels a blade-element plant measures (individual pitch control reads them): the blade-root
#: out-of-plane moments [kN-m], the azimuth [deg] and the pitch of blades 2 and 3 [deg].
BLADE_MEASUREMENTS = ("RootMyc1", "RootMyc2", "RootMyc3", "Azimuth", "BldPitch2", "BldPitch3")
#: Further channels a floating plant measures (ROSCO's floating feedback reads them): the nacelle's pitching
#: acceleration [deg/s^2] (Fl_Mode 2), the tower top's fore-aft and side-side accelerations [m/s^2] and the
#: nacelle yaw [deg] (Fl_Mode 1).
FLOATING_MEASUREMENTS = ("NcIMURAys", "YawBrTAxp", "YawBrTAyp", "NacYaw")
#: Further channels a DISCON library receives from a floating plant, as OpenFAST v5's ServoDyn fills its extended
#: records 1001-1006: the platform's displacements [m, deg] (the exported floating NMPC's EKF reads pitch and surge).
PLATFORM_MEASUREMENTS = ("PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmRoll", "PtfmPitch", "PtfmYaw")
#: Further channels a DISCON library receives from any plant that has them, as ServoDyn fills their records for
#: every library: the measured generator torque [kN-m] (record 23), the tower top's fore-aft and side-side
#: accelerations [m/s^2] (53, 54) and the nacelle yaw [deg] (37); the exported NMPC's estimator reads the first two,
#: ROSCO's tower damper (``TD_Mode`` 1) the last three on any plant.
DISCON_MEASUREMENTS = ("GenTq", "YawBrTAxp", "YawBrTAyp", "NacYaw")
#: Channel -> factor from its OpenFAST unit to SI.
SI_FACTORS = {**dict(zip(MEASUREMENTS, TO_SI)), "NcIMURAys": math.pi / 180.0, "YawBrTAxp": 1.0, "YawBrTAyp": 1.0,
              "GenTq": 1e3,
              "NacYaw": math.pi / 180.0,
              **{n: math.pi / 180.0 if n in ("PtfmRoll", "PtfmPitch", "PtfmYaw") else 1.0
                 for n in PLATFORM_MEASUREMENTS},
              "RootMyc1": 1e3, "RootMyc2": 1e3, "RootMyc3": 1e3,
              "Azimuth": math.pi / 180.0, "BldPitch2": math.pi / 180.0, "BldPitch3": math.pi / 180.0}


def measurement_names(model) -> tuple[str, ...]:
    """The channels ``model``'s measurement outputs carry (:data:`MEASUREMENTS`, for a blade-element
    plant :data:`BLADE_MEASUREMENTS`, for a floating plant :data:`FLOATING_MEASUREMENTS` and
    :data:`PLATFORM_MEASUREMENTS`, then :data:`DISCON_MEASUREMENTS` not among them)."""
    names = MEASUREMENTS + (BLADE_MEASUREMENTS if getattr(model, "aero", "rotor") == "blade" else ()) + \
        (FLOATING_MEASUREMENTS + PLATFORM_MEASUREMENTS if getattr(model, "platform", None) is not None else ())
    names += tuple(c for c in DISCON_MEASUREMENTS if c not in names)
    return names + _yaw_measurements(model, names)


def _yaw_measurements(model, names) -> tuple[str, ...]:
    """With a library's yaw (``YCMode = 5``): the hub wind's cross component, for its yaw error (record 24)."""
    from ..deck.yaw_control import DllYaw

    yaw = isinstance(getattr(model, "yaw_control", None), DllYaw) and getattr(model, "aero", "rotor") == "blade"
    return ("Wind1VelY",) if yaw and "Wind1VelY" not in names else ()


def baseline_in_loop(controller: BaselineController, *, name: str = "baseline", model=None,
                     x0=None) -> DiscreteController:
    """Our baseline controller as a :class:`DiscreteController` of the plant's channels.

    Parameters
    ----------
    controller : BaselineController
        E.g. ``BaselineController.from_discon("DISCON.IN", dt=0.00625)``; its ``measurements`` and
        ``commands`` (individual pitch control adds root moments and azimuth, and commands each blade).
    name : str, optional, keyword-only
        Prefix of the controller's state names in results (``baseline.first`` ...).
    model : OperatingTurbine, optional, keyword-only
        The plant, when its pitch is individual: a collective command then drives every blade.
    x0 : array_like, optional, keyword-only
        The controller's initial state (default ``controller.x0``: its first call initializes every block
        from the first measurements); e.g. a fixed point from
        :func:`~mbsym.wind.control.linear.controller_fixed_point`, to start a run at a trim.
    """
    if not isinstance(controller, BaselineController):
        raise TypeError(f"controller must be a BaselineController; got {type(controller).__name__}.")
    f = controller.function
    measured = tuple(getattr(controller, "measurements", MEASUREMENTS))
    commands = tuple(getattr(controller, "commands", ACTUATED))
    unknown = [n for n in measured if n not in SI_FACTORS]
    if unknown:
        from ...exceptions import ControllerError

        raise ControllerError(f"baseline_in_loop: the plants measure no {unknown} (the shut-down's yaw-error trigger, "
                              "SD_EnableYawError 1, reads YawErr, swap record 24); switch that trigger off, or run the "
                              "controller open loop (BaselineController.run) or exported (export_discon).")
    xc = ca.SX.sym("xc", f.numel_in(0))
    y = ca.SX.sym("y", len(measured))
    x_next, u = f(xc, y * ca.DM([SI_FACTORS[n] for n in measured]))
    u, actuates = _plant_commands(u, commands, model)
    law = ca.Function(f"{name}_in_loop", [xc, y], [x_next, u], ["xc", "y"], ["xc_next", "u"], {"cse": True})
    start = controller.x0 if x0 is None else np.asarray(x0, dtype=float).reshape(-1)
    return DiscreteController(law, controller.dt, start, measurements=measured, actuates=actuates,
                              state_names=[f"{name}.{s}" for s in controller.state_names],
                              state_units=controller.state_units, name=name)


def _plant_commands(u, commands: tuple[str, ...], model) -> tuple:
    """The controller's commands as the plant's inputs: a collective pitch spread over individual actuators."""
    plant = tuple(getattr(model, "command_names", ACTUATED)) if model is not None else commands
    if commands == plant:
        return u, commands
    if commands == ACTUATED and "BlPitchCom" not in plant:
        n = len(plant) - 1
        return ca.vertcat(*([u[0]] * n), u[1]), plant
    from ...exceptions import ControllerError

    raise ControllerError(f"the controller commands {list(commands)} but the plant takes {list(plant)}: individual "
                          "pitch control needs a plant with pitch='individual'.")


def discon_in_loop(controller: DisconController, *, name: str = "discon", model=None,
                   measurements: Sequence[str] | None = None) -> DiscreteController:
    """A DISCON library as a :class:`DiscreteController` (a Python call per sample).

    The library is initialized at the first sample (t = 0) and keeps its state; use a new
    :class:`DisconController` for every simulation (:meth:`DisconController.close` after). With a
    blade-element ``model`` the library also receives the blade-root moments (records 30-32), the azimuth
    (60) and every blade's pitch (4, 33, 34); with ``pitch='individual'`` its pitch demands per blade
    (records 42-44) drive the blades. With a ``model`` it also receives :data:`DISCON_MEASUREMENTS` where the
    model measures them (:func:`measurement_names`; records 23 and 53, as from ServoDyn). ``measurements``: the
    channels to give it instead (names of :data:`SI_FACTORS`), for a caller with the plant's measurement names but
    not the model (a sweep's worker).
    """
    if not isinstance(controller, DisconController):
        raise TypeError(f"controller must be a DisconController; got {type(controller).__name__}.")
    if measurements is not None:
        measured = tuple(measurements)
        unknown = [m for m in measured if m not in SI_FACTORS]
        if unknown:
            from ...exceptions import OptionError

            raise OptionError(f"discon_in_loop: no swap record for {unknown}; known channels: {list(SI_FACTORS)}.")
    else:
        measured = measurement_names(model) if model is not None else MEASUREMENTS
    individual = getattr(model, "pitch", "collective") == "individual"
    n = model.turbine.number_of_blades if individual else 1
    commands = tuple(f"BlPitchCom{k + 1}" for k in range(n)) + ("GenTqCom",)
    actuates = model.command_names if individual else ACTUATED
    from ..deck.yaw_control import DllYaw

    yaw = getattr(model, "yaw_control", None)
    if isinstance(yaw, DllYaw):
        return _with_library_yaw(controller, yaw, measured, commands, tuple(actuates), name)
    step = controller.callable(measured, commands)
    scale = np.asarray([SI_FACTORS[m] for m in measured])
    empty = np.zeros(0)

    def law(t: float, xc: np.ndarray, y: np.ndarray):
        return empty, step(t, y * scale)

    return DiscreteController(law, controller.dt, measurements=measured, actuates=actuates, name=name)


def _with_library_yaw(controller: DisconController, yaw, measured: tuple, commands: tuple, actuates: tuple,
                      name: str) -> DiscreteController:
    """:func:`discon_in_loop` with ServoDyn's ``YCMode = 5``: the library also gets the yaw error (record 24,
    ``atan2(Wind1VelY, Wind1VelX) − NacYaw``, as OpenFAST's glue code fills ServoDyn's ``YawErr``) and its yaw-rate
    demand (record 48) is integrated as ServoDyn does (:class:`~.yaw_control.DllYaw`) into the commands
    ``YawPosCom``, ``YawRateCom``; the controller's state is ServoDyn's ``YawPosComInt`` [rad]."""
    from ..deck.yaw_control import YAW_INPUTS

    known = tuple(m for m in measured if m in SI_FACTORS)
    step = controller.callable(known + ("YawErr",), commands + ("YawRateCom",))
    scale = np.asarray([SI_FACTORS[m] for m in known])
    pick = [measured.index(m) for m in known]
    yaw_at = measured.index("NacYaw")
    cross = measured.index("Wind1VelY") if "Wind1VelY" in measured else None
    along = measured.index("Wind1VelX")
    dt = controller.dt

    def law(t: float, xc: np.ndarray, y: np.ndarray):
        wind_dir = math.atan2(y[cross], y[along]) if cross is not None else 0.0
        u = step(t, np.r_[y[pick] * scale, wind_dir - y[yaw_at] * SI_FACTORS["NacYaw"]])
        integrated, position, rate = yaw.step(t, float(xc[0]), float(u[-1]), dt, first=bool(xc[1]))
        return np.array([integrated, 0.0]), np.r_[u[:-1], position, rate]

    return DiscreteController(law, dt, [yaw.neutral, 1.0], measurements=measured, actuates=actuates + YAW_INPUTS,
                              state_names=[f"{name}.YawPosComInt", f"{name}.first"], state_units=["rad", "-"],
                              name=name)


def held_commands(model, x0) -> dict[str, float]:
    """Constant commands that hold the actuators of ``model`` at the state ``x0``: ``{BlPitchCom…, GenTqCom}``."""
    dyn = model.dynamics()
    x = dict(zip(dyn.states, np.asarray(x0, dtype=float)))
    out = {c: float(x[n]) for n, c in zip(model.pitch_names, model.command_names)}
    out["GenTqCom"] = float(x["GenTq"])
    return out
