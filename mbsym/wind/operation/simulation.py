"""Closed-loop simulation of an operating turbine: wind in, controller in the loop, OpenFAST channels out.

:func:`simulate_turbine` is :func:`mbsym.simulate` with the choices an operating turbine needs:

* the initial state from the deck's initial conditions, with the generator torque balancing the
  aerodynamic torque and the dynamic inflow at equilibrium for the wind at t = 0
  (:meth:`OperatingTurbine.initial_state`);
* the wind as the input ``Wind1VelX`` (any :class:`~mbsym.wind.inflow.WindSignal` or callable);
* the controller as a :class:`~mbsym.simulate.DiscreteController` (:mod:`.controllers`), or none:
  then the commands hold the initial pitch and torque (or ``commands``);
* integration: with a controller, one step per controller sample (the sample time of ROSCO's
  deck, 6.25 ms, resolves every mode of the model; the accuracy-driven default of
  :func:`mbsym.simulate` re-runs the loop to check the step, which a DISCON library — a state
  machine outside our control — cannot follow); without, the accuracy-driven default. With
  blade-element aerodynamics and a CasADi controller the default method is the deck's ElastoDyn
  ``Method`` (:func:`deck_method`; 3 ABM4: ``"abm4-held"``, 2 AB4: ``"ab4-held"``, 1 RK4: ``"rk4-held"``,
  :mod:`mbsym.simulate.held_multistep`), otherwise ``"rk4-held"`` (:mod:`mbsym.held`): the
  aerodynamics once per step, held over its RK4 stages as OpenFAST's glue code holds AeroDyn's loads
  over an ElastoDyn step; one evaluation serves the controller's measurements, the step and every
  channel at the samples. Against OpenFAST on ``ff14_flex`` ``"rk4-held"`` gives the figures of ``"rk4"``
  (the aerodynamics at every stage) to the third digit at 3-4x less cost, and ``"abm4-held"`` those of
  ``"rk4-held"`` (ε within 0.02 point, DELs within 0.1 point) with 2 right-hand sides per step instead of 4
  (benchmarks/README.md, "blade-loop-speed"). The result's ``statistics["deck_method"]`` names the deck's
  Method, and its message says where the run integrates otherwise (a DISCON library called from Python,
  the rotor-effective model: RK4).
* the blade-element aerodynamics are evaluated every :func:`default_aero_dt` (``aero_dt``), a whole number
  of controller samples, and between evaluations **extrapolated** in time through the last ones with the
  deck's ``InterpOrder`` (``aero_order``; OpenFAST's glue code extrapolates module outputs the same way),
  or held (order 0); the controller and the structure keep the controller's rate. The interval is as long
  as the rotor turns :data:`AERO_ROTATION_DEG` degrees for the order. Measured on ``ff14_flex`` (NREL 5 MW,
  6.25 ms samples, InterpOrder 2: aerodynamics every 50 ms, quadratic): the accuracy against OpenFAST of
  the every-sample run with the loads held (ε within 0.05 point, DELs within 1.7 points) at a fraction of
  its cost (benchmarks/README.md, "blade-validation").
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

import numpy as np

from ...exceptions import SimulationOptionError
from ...simulate.controller import DiscreteController
from ...simulate.held_multistep import ELASTODYN_METHODS, HELD_METHODS, MULTISTEP_METHODS, stability_limit
from .controllers import held_commands
from .hss_brake import BRAKE_INPUT
from .model import OperatingTurbine
from .sanity import check_physical

__all__ = ["simulate_turbine", "wind_at_start", "default_aero_dt", "deck_method", "AERO_ROTATION_DEG",
           "TIP_SPEED_REF", "moving_lines_controller"]

#: ElastoDyn's Method key -> its name.
ELASTODYN_NAMES = {1: "RK4", 2: "AB4", 3: "ABM4"}

#: Rotor rotation [deg] between evaluations of the blade-element aerodynamics by default, per extrapolation order
#: (0 hold, 1 linear, 2 quadratic). Held, at 2 deg the loads' 1P and 3P variation is sampled 180 times per turn
#: and the hold's delay (half an interval) is under 1.5 % of the shortest blade-mode period it couples to (NREL
#: 5 MW, flap 2 at 2 Hz: 12.5 ms of 500 ms). Measured on ff14_flex against OpenFAST (benchmarks/README.md,
#: "blade-validation"): linear extrapolation at 4 deg raised the DEL errors of TwrBsMxt and RootMyc1 by 2.3 and
#: 0.8 points over 2 deg; quadratic at 4 deg stays within 1.7 points of the every-sample run with held loads.
AERO_ROTATION_DEG = {0: 2.0, 1: 2.0, 2: 4.0}
#: Tip speed [m/s] assumed when the rotor starts slower (start-up, idling): the utility-scale design value
#: (NREL 5 MW 80 m/s at rated; IEA 15 MW 95 m/s), so the hold stays short once the rotor is up to speed.
TIP_SPEED_REF = 80.0


def simulate_turbine(model: OperatingTurbine, wind: Callable[[Any], Any] | float, tmax: float, *,
                     controller: DiscreteController | None = None, x0=None,
                     commands: Mapping[str, float] | None = None, t_out=None, p: Mapping[str, float] | None = None,
                     method: str | None = None, dt: float | None = None, accuracy: float | None = None,
                     compile: bool | None = None, progress=None, aero_dt: float | None = None,
                     aero_order: int | None = None):
    """Simulate ``model`` in ``wind`` for ``tmax`` seconds (see the module docstring).

    Parameters
    ----------
    model : OperatingTurbine
    wind : WindSignal, callable, float, UniformFieldWind or None
        Hub-height wind speed [m/s] of time [s]; for a blade-element model with uniform-wind inputs also a
        :class:`~mbsym.wind.inflow.UniformFieldWind` (every column), and None for a model that carries a
        full field (its time is the simulation time).
    tmax : float
        End time [s].
    controller : DiscreteController, optional, keyword-only
        From :func:`~.controllers.baseline_in_loop` or :func:`~.controllers.discon_in_loop`.
    x0 : array or dict, optional, keyword-only
        Initial state; default ``model.initial_state(wind(0))``.
    commands : dict, optional, keyword-only
        Without a controller: ``BlPitchCom`` [rad], ``GenTqCom`` [N m] (numbers or functions of
        time); default: hold the initial actuator states. Also any other input by name, e.g. a floating
        model's sea (``B1WvsFxi`` …, ``Wave1Elev``; default: the deck's waves, zero in still water).
    t_out : array, optional, keyword-only
        Output times [s].
    p : dict, optional, keyword-only
        Parameter values by name.
    aero_dt : float, optional, keyword-only
        Blade-element aerodynamics with a controller and a held method (``"rk4-held"``, ``"abm4-held"``,
        ``"ab4-held"``): their interval [s], a whole multiple of
        the controller's sample time (:func:`mbsym.simulate`'s ``held_dt``). Default :func:`default_aero_dt` for
        ``aero_order`` when the step is the controller's sample time and the controller a CasADi Function (a
        DISCON library, called from Python, gets the aerodynamics every sample), else every step.
    aero_order : {0, 1, 2}, optional, keyword-only
        Blade-element aerodynamics with a CasADi controller and a held method: between their evaluations they are
        held (0) or extrapolated through the last 2 (1) or 3 (2) evaluations (:func:`mbsym.simulate`'s
        ``held_order``). Default: the deck's ``InterpOrder`` (``model.turbine.simulation.interp_order``); 0 with
        a DISCON library (called from Python, it gets the aerodynamics every sample, held over the step).
    method, dt, accuracy, compile, progress
        As in :func:`mbsym.simulate`. With a controller, the default is ``method="rk4"`` (with blade-element
        aerodynamics the deck's ElastoDyn Method with a CasADi controller, else ``"rk4-held"``; see the module
        docstring) with ``dt = controller.dt``; ``accuracy``
        asks for the accuracy-driven sub-steps instead (CasADi-Function controllers only); ``compile`` defaults
        to compiling runs of more than :data:`COMPILE_FROM_SAMPLES` controller samples, and shorter ones whose
        virtual-machine time would exceed the compilation's (a large plant: :func:`_compile_pays_off`).

    Returns
    -------
    SimulationResult
        Outputs: the OpenFAST channels of the model (then the controller's states).

    Raises
    ------
    TypeError
        ``model`` is not an OperatingTurbine, or ``controller`` not a DiscreteController.
    SimulationOptionError
        ``accuracy`` with a Python-callable controller.
    UnphysicalRunError
        The run went unphysical (:func:`~.sanity.check_physical`: the rotor turning backwards, the
        nacelle yawed beyond a turn, Cp beyond the rotor's table, non-finite channels); names the time
        and channel and carries the result.
    """
    from ...simulate.api import simulate

    if not isinstance(model, OperatingTurbine):
        raise TypeError(f"model must be an OperatingTurbine; got {type(model).__name__}.")
    if controller is not None and not isinstance(controller, DiscreteController):
        raise TypeError(f"controller must be a DiscreteController (baseline_in_loop, discon_in_loop) or None; "
                        f"got {type(controller).__name__}.")
    dyn = model.dynamics()
    inputs: dict[str, Any] = model.wind.signals(wind) if model.aero == "blade" else {"Wind1VelX": wind}
    if x0 is None:
        x0 = model.initial_state(wind_at_start(model, wind))
    x0 = dyn.state_vector(x0)
    inputs.update(held_commands(model, x0) if commands is None else dict(commands))
    if model.platform is not None:                  # the deck's sea (HydroDyn's excitation series), unless given
        given = dict(commands or {})
        inputs.update({n: v for n, v in model.platform.sea_tables(tmax).items() if n not in given})
    if model.hss_brake is not None and BRAKE_INPUT not in dict(commands or {}):   # ServoDyn's brake ramp
        inputs[BRAKE_INPUT] = model.hss_brake.table(tmax)
    _yaw_command(model, controller, commands, tmax, inputs)      # ServoDyn's commanded yaw (.yaw_control)
    if model.platform is not None and getattr(model.platform, "moving_lines", None) is not None:
        controller = moving_lines_controller(model, dyn, controller, x0, compile)
    if model.structural_controls is not None:        # ServoDyn's prescribed StC loads (their files), unless given
        given = dict(commands or {})
        inputs.update({n: v for n, v in model.structural_controls.tables(tmax).items() if n not in given})
    options: dict[str, Any] = {"t_out": t_out, "p": p, "compile": compile, "progress": progress}
    if controller is not None:
        if accuracy is not None:
            if not controller.is_function:
                raise SimulationOptionError("accuracy= re-runs the closed loop to check the step, which a Python "
                                            f"controller ({controller.name!r}, e.g. a DISCON library) cannot "
                                            "follow; give method='rk4' and dt instead.")
            options["accuracy"] = accuracy
        else:
            step = controller.dt if dt is None else dt
            _check_unsteady(model, method, aero_dt, aero_order, step)
            if method in MULTISTEP_METHODS:
                unstable = _actuator_instability(model, method, step)
                if unstable:
                    raise SimulationOptionError(f"method {method!r} is unstable for this model at dt = {step:g} s: "
                                                f"{unstable}; use 'abm4-held' or 'rk4-held', or a shorter sample time.")
            options.update(method=method or _default_method(model, controller, dt), dt=step)
        if compile is None:
            options["compile"] = _compile_pays_off(dyn, tmax / controller.dt, x0, p)
    else:
        options.update(method=method, dt=dt, accuracy=accuracy)
    in_loop = controller is not None and controller.is_function and options.get("method") in HELD_METHODS \
        and options.get("dt") == controller.dt               # a Python law (DISCON library) samples every step
    if aero_order is None and in_loop:
        aero_order = 0 if _unsteady(model) is not None else int(model.turbine.simulation.interp_order)
    if aero_dt is None and in_loop:
        aero_dt = default_aero_dt(model, controller.dt, x0, order=aero_order)
    if aero_dt is not None:
        options["held_dt"] = aero_dt
    if aero_order:
        options["held_order"] = aero_order
    options = {k: v for k, v in options.items() if v is not None}
    if controller is None:
        res = simulate(dyn, tmax, x0=x0, inputs=inputs, **options)
    elif options.get("method") in HELD_METHODS:
        # the loop evaluates every channel at the samples from the aerodynamics it holds over the step
        res = simulate(dyn, tmax, x0=x0, inputs=inputs, controller=controller, **options)
    else:
        # in the loop only the measurements are evaluated; the channels afterwards, from the states
        res = simulate(model.measurement_dynamics(), tmax, x0=x0, inputs=inputs, controller=controller, **options)
        res = _with_channels(res, dyn, p, compile, len(model.measurement_dynamics().output_names))
    _state_deck_method(res, model, controller, method is not None)
    _lines_statistics(res, controller)
    check_physical(res, model)
    return res


def moving_lines_controller(model: OperatingTurbine, dyn, controller, x0: np.ndarray,
                            compile: bool | None = None) -> DiscreteController:
    """``controller`` with the floating ``model``'s moving MoorDyn lines beside it
    (:func:`mbsym.wind.offshore.lines_in_loop.with_moving_lines`), relaxed at the platform's initial position.

    Parameters
    ----------
    model : OperatingTurbine
        With a platform whose ``moving_lines`` are set (``floating_platform(..., mooring_lines="dynamic")``).
    dyn : Dynamics
        The plant the loop runs (its states name the platform DOFs).
    controller : DiscreteController or None
        The turbine's controller; None: the lines alone at the deck's ``DT``.
    x0 : array
        The plant's initial state.
    compile : bool or None
        False keeps the lines' relaxation in CasADi's virtual machine; else compiled.

    Returns
    -------
    DiscreteController
        Its ``lines_relaxation`` attribute holds the relaxation (:class:`~mbsym.wind.offshore.lumped_dynamics.Relaxed`).
    """
    from ..offshore.lines_in_loop import with_moving_lines
    from ..offshore.operating import platform_dofs

    coords = model.structure.eom.coordinates
    index, fixed, _ = platform_dofs(coords, model.turbine)
    dofs = [coords[i] if i is not None else None for i in index]
    q0 = [x0[dyn.states.index(n)] if n is not None else fixed[k] for k, n in enumerate(dofs)]
    combined, relaxed = with_moving_lines(model.platform, dofs, fixed, q0, controller=controller,
                                          dt=float(model.turbine.simulation.time_step), compile=compile is not False)
    combined.lines_relaxation = relaxed
    return combined


def _lines_statistics(res, controller) -> None:
    """The moving lines' relaxation in the result's statistics (``lines_relaxed_s``, ``lines_relaxation_converged``)."""
    relaxed = getattr(controller, "lines_relaxation", None)
    if relaxed is not None:
        res.statistics.update(lines_relaxed_s=float(relaxed.time), lines_relaxation_converged=bool(relaxed.converged))


def _yaw_command(model: OperatingTurbine, controller, commands, tmax: float, inputs: dict) -> None:
    """ServoDyn's yaw maneuver as input tables (unless given); a library's yaw (``YCMode = 5``) needs the library."""
    from ..deck.yaw_control import YAW_INPUTS, DllYaw, YawManeuver

    yaw, given = getattr(model, "yaw_control", None), dict(commands or {})
    if isinstance(yaw, YawManeuver):
        inputs.update({n: v for n, v in yaw.tables(tmax).items() if n not in given})
    elif isinstance(yaw, DllYaw) and not set(YAW_INPUTS) <= set(given) and not (
            controller is not None and set(YAW_INPUTS) <= set(controller.actuates)):
        raise SimulationOptionError("the model's yaw follows a DISCON library's yaw-rate demand (ServoDyn YCMode 5): "
                                    "run it with the library in the loop (discon_in_loop) or give YawPosCom and "
                                    "YawRateCom in commands.")


def deck_method(model: OperatingTurbine) -> int | None:
    """The ElastoDyn ``Method`` (1 RK4, 2 AB4, 3 ABM4) of the deck ``model`` was read from, else None."""
    code = getattr(model.turbine, "integration_method", None)
    return int(code) if code in ELASTODYN_METHODS else None


def _default_method(model: OperatingTurbine, controller: DiscreteController, dt: float | None) -> str:
    """With a controller: the deck's ElastoDyn Method for blade-element aerodynamics with a CasADi controller and
    one step per sample (:mod:`mbsym.simulate.held_multistep`) where the actuators' modes are inside its stability
    interval, else ``"rk4-held"`` (blade) or ``"rk4"``."""
    if model.aero != "blade":
        return "rk4"
    if _unsteady(model) is not None:                # AeroDyn's UA recursion: one held step per AeroDyn step
        return "rk4-held"
    code = deck_method(model)
    if code is None or not controller.is_function or (dt is not None and dt != controller.dt):
        return "rk4-held"
    method = ELASTODYN_METHODS[code]
    if method in MULTISTEP_METHODS and _actuator_instability(model, method, controller.dt):
        return "rk4-held"
    return method


def _actuator_instability(model: OperatingTurbine, method: str, dt: float) -> str:
    """Why ``method`` is unstable for the actuators' modes at the step ``dt`` [s] (an empty string: it is not).

    The pitch actuator (second order, ``pitch_frequency`` ω, ``pitch_damping`` ζ) and the generator-torque lag
    (``1/τ``, real) are the fastest modes of an operating turbine; each must be inside the method's stability
    interval in its direction (:func:`~mbsym.simulate.held_multistep.stability_limit`; ElastoDyn has neither:
    ServoDyn applies its commands at once)."""
    act = getattr(model, "actuators", None)
    if act is None:
        return ""
    modes = [("the generator-torque lag", 1.0 / act.torque_time_constant if act.torque_time_constant > 0 else 0.0,
              1.0), ("the pitch actuator", act.pitch_frequency, min(act.pitch_damping, 1.0))]
    bad = [f"{name} |λ| h = {lam * dt:.3g} > {stability_limit(method, zeta):.3g}" for name, lam, zeta in modes
           if lam * dt > stability_limit(method, zeta)]
    return "; ".join(bad)


def _state_deck_method(res, model: OperatingTurbine, controller, given: bool) -> None:
    """``res.statistics``: the deck's ElastoDyn Method, and in the message where the run integrates otherwise."""
    code = deck_method(model)
    stats = res.statistics
    if code is None or not isinstance(stats, dict):
        return
    used, name = stats.get("method"), ELASTODYN_NAMES[code]
    stats["deck_method"] = f"{name} (ElastoDyn Method {code})"
    if used == ELASTODYN_METHODS[code] or (code == 1 and used == "rk4"):
        return
    if given:
        why = "the method given"
    elif model.aero != "blade":
        why = "the multistep methods are modelled for blade-element aerodynamics only"
    elif controller is None:
        why = "without a controller the accuracy-driven default chooses"
    elif _unsteady(model) is not None:
        why = "AeroDyn's unsteady airfoil model (UA_Mod 3) is integrated one held step at a time"
    elif not controller.is_function:
        why = "the controller is called from Python; the multistep methods run in the compiled loop"
    elif _actuator_instability(model, ELASTODYN_METHODS[code], float(stats.get("dt", controller.dt))):
        why = (f"{name} is unstable here: " + _actuator_instability(model, ELASTODYN_METHODS[code],
                                                                  float(stats.get("dt", controller.dt))))
    else:
        why = "the multistep methods need one step per controller sample"
    stats["message"] = (str(stats.get("message", "")).rstrip() + f" The deck asks ElastoDyn Method {code} "
                        f"({name}); this run integrates with {used} ({why}).").strip()


def default_aero_dt(model: OperatingTurbine, sample_dt: float, x0: np.ndarray, *, order: int = 0) -> float:
    """Interval [s] of the blade-element aerodynamics in a controlled run: the largest whole number of
    controller samples ``sample_dt`` [s] over which the rotor turns at most :data:`AERO_ROTATION_DEG` of the
    extrapolation ``order`` (0, 1, 2), at the faster of its speed in ``x0`` (state vector) and
    :data:`TIP_SPEED_REF` over the tip radius (at least one sample). ``ff14_flex`` (12.1 rpm, 6.25 ms): held
    or linear 4 samples (25 ms), quadratic 8 samples (50 ms)."""
    if order not in AERO_ROTATION_DEG:
        raise SimulationOptionError(f"the aerodynamics' extrapolation order must be one of {sorted(AERO_ROTATION_DEG)}; "
                                    f"got {order!r}.")
    if _unsteady(model) is not None:                # AeroDyn's UA recursion: updated every step
        return sample_dt
    states = model.dynamics().states
    speed = abs(sum(float(x0[states.index(n)]) for n in ("GeAz_d", "DrTr_d") if n in states))
    speed = max(speed, TIP_SPEED_REF / float(model.rotor.tip_radius))                  # rad/s
    k = int(np.floor(np.radians(AERO_ROTATION_DEG[order]) / (speed * sample_dt) + 1e-9))
    return max(k, 1) * sample_dt


def _unsteady(model: OperatingTurbine):
    """The blade-element rotor's UA nodes (:mod:`mbsym.wind.aero.blade.unsteady`), or None."""
    return getattr(model.rotor, "unsteady", None) if model.aero == "blade" else None


def _check_unsteady(model: OperatingTurbine, method: str | None, aero_dt: float | None, aero_order: int | None,
                    step: float) -> None:
    """Refuse what breaks AeroDyn's UA recursion on a blade-element rotor with ``UA_Mod = 3``: the aerodynamics
    held over more than one step (``aero_dt``) or extrapolated across it (``aero_order``), or a multistep method
    (its derivative history mixes the recursion's updates of several steps)."""
    ua = _unsteady(model)
    if ua is None:
        return
    if aero_order:
        raise SimulationOptionError(f"aero_order = {aero_order}: the unsteady airfoil model (UA_Mod 3) holds its "
                                    "update over the step as AeroDyn does; extrapolating it across the step breaks "
                                    "the recursion. Leave aero_order unset (0).")
    if aero_dt is not None and abs(aero_dt - step) > 1e-12 * step:
        raise SimulationOptionError(f"aero_dt = {aero_dt:g} s: the unsteady airfoil model (UA_Mod 3) updates its "
                                    f"states every step ({step:g} s) as AeroDyn does; leave aero_dt unset.")
    if method in MULTISTEP_METHODS:
        raise SimulationOptionError(f"method {method!r} with the unsteady airfoil model (UA_Mod 3): its recursion "
                                    "is integrated one held step at a time; use 'rk4-held' (the default).")


def wind_at_start(model: OperatingTurbine, wind) -> "float | dict[str, float]":
    """The wind at t = 0 as :meth:`OperatingTurbine.initial_state` takes it (hub speed, or the wind inputs)."""
    if model.aero != "blade":
        return _wind_at(wind, 0.0)
    signals = model.wind.signals(wind)
    return {n: _wind_at(signals[n], 0.0) for n in model.wind.inputs}


def _with_channels(res, dyn, p, compile, n_meas: int):
    """``res`` with every OpenFAST channel of ``dyn`` (then the controller's states) as outputs; the first
    ``n_meas`` outputs of ``res`` are the plant's measurements."""
    import dataclasses
    import time

    from ...simulate.model import evaluate_outputs

    t0 = time.perf_counter()
    Y = evaluate_outputs(dyn.rhs, dyn.outputs, np.asarray(res.x), np.asarray(res.u), dyn.parameter_vector(p),
                         compile)
    extra = np.asarray(res.y)[:, n_meas:]
    stats = dict(res.statistics)
    stats["outputs_wall_s"] = float(stats.get("outputs_wall_s", 0.0)) + time.perf_counter() - t0
    units = tuple(res.output_units)[n_meas:] if res.output_units else ("",) * extra.shape[1]
    return dataclasses.replace(res, y=np.hstack([Y, extra]), output_names=tuple(dyn.output_names) +
                               tuple(res.output_names[n_meas:]), output_units=tuple(dyn.output_units) + units,
                               statistics=stats)


#: Controller samples from which compiling the closed loop (~15 s once, then cached on disk) pays off against
#: CasADi's virtual machine (~1-2 ms per sample of the NREL 5 MW with three DOFs).
COMPILE_FROM_SAMPLES = 2000
#: Right-hand-side evaluations per controller sample assumed for the virtual machine's cost (one RK4 step).
RHS_PER_SAMPLE = 4


def _compile_pays_off(dyn, samples: float, x0, p, runs: int = 1) -> bool:
    """Whether to compile the closed loop: more than :data:`COMPILE_FROM_SAMPLES` samples, or fewer whose right-hand
    sides would take longer in CasADi's virtual machine than compiling takes (:func:`mbsym.codegen.
    estimate_compile_seconds`; one evaluation timed). A large plant needs the second: the floating IEA 15 MW with
    blade-element aerodynamics and UA takes 0.58 s per evaluation in the virtual machine (1.65 s per sample of
    0.025 s measured: 3 s of `--controller discon` ran 198 s), so the sample count alone left runs of up to 50 s
    there to the virtual machine (~66 min instead of a few minutes of compiling). ``runs``: runs of ``samples`` each
    sharing the compiled loop (a sweep's cases)."""
    import time

    from ... import codegen

    if codegen.compiler_command() is None or codegen.compile_disabled():
        return False
    if samples > COMPILE_FROM_SAMPLES:
        return True
    u0, pv = np.zeros(dyn.n_u), dyn.parameter_vector(p)
    t0 = time.perf_counter()
    dyn.rhs(np.asarray(x0, dtype=float), u0, pv)
    vm = (time.perf_counter() - t0) * RHS_PER_SAMPLE * samples * runs
    return vm > codegen.estimate_compile_seconds(dyn.rhs)


def _wind_at(wind, t: float) -> float:
    if callable(wind):
        return float(np.asarray(wind(t), dtype=float).reshape(-1)[0])
    return float(wind)
