"""Turbine sweeps: deck keys x wind specifications through :func:`mbsym.sweep`, one row per combination.

:func:`sweep_turbine` is the Python side of ``mbsym sweep`` (:mod:`mbsym.cli.sweep`):

* **without winds** the structural model of the deck (``mbsym simulate DECK``'s model; built in:
  the NREL 5 MW with rigid blades, tower top released from 0.5 m fore-aft) runs free decays by
  fixed-step RK4 at the deck's ``DT`` through the general engine's simulation plan (the whole
  loop in CasADi; cases of the in-process executor go through one CasADi ``map``); statistics on
  the step grid;
* **with winds** the operating turbine (``mbsym simulate --wind``: structure, rotor aerodynamics,
  actuators) runs closed-loop under a controller (default: the deck's DISCON library, the
  baseline without a deck) through a picklable runner holding the serialized Functions
  (:mod:`.sweep_runner`); statistics on the output grid (the deck's ``DT_Out``, built in 0.05 s).

Keys (:mod:`.sweep_keys`) are ElastoDyn keys of the named parameters in the deck's units
(``TwrFADmp(1)`` in %), initial conditions (``TTDspFA``, ``RotSpeed``, ...) or the model's
parameter names. The table's columns: the keys exactly as given, ``wind`` (``"none"`` for free
decays), ``<channel>_mean``, ``_std``, ``_max``, ``_min``, optional ``<channel>_del_m<m>``, and
``error`` (a case that fails, e.g. a value below its physical bound or a diverging run, fills
it; the others go on). Every executor gives the same numbers bit for bit.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from ...exceptions import ParameterError, SweepError
from .sweep_keys import KeyTarget, resolve_key
from .sweep_runner import CASE_KEY, ClosedLoopRunner, WindCase
from ..deck.nrel5mw import NREL5MW_YAW_DAMPING, NREL5MW_YAW_SPRING

__all__ = ["sweep_turbine", "builtin_free_decay", "FREE_DECAY", "CONTROLLERS", "COMPILE_FROM_STEPS"]

#: ``wind`` column of a structural free decay.
FREE_DECAY = "none"
CONTROLLERS = ("baseline", "discon", "none")
#: Total RK4 steps of a structural sweep from which its step is compiled (~10-20 s once, then on disk).
COMPILE_FROM_STEPS = 200_000
#: Built-in operating runs: simulated time [s] and output spacing [s] (as ``mbsym simulate --wind``).
_BUILTIN_TMAX, _BUILTIN_DT_OUT = 60.0, 0.05
#: The built-in operating deck and model of this process (derivation and rotor surfaces take seconds).
_BUILTIN: dict = {}


def builtin_free_decay():
    """The built-in structural scene of ``mbsym simulate``: NREL 5 MW, rigid blades, TTDspFA = 0.5 m."""
    import dataclasses

    from ..deck.nrel5mw import nrel5mw
    from ..structure.turbine import NON_BLADE_DOFS, TurbineModel

    t = nrel5mw()
    t = dataclasses.replace(t, initial_conditions=dataclasses.replace(t.initial_conditions,
                                                                      tower_top_fa_displacement=0.5))
    dofs = [f for f in NON_BLADE_DOFS if t.dofs.get(f)]
    return TurbineModel(t, dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)


def sweep_turbine(deck: Any = None, set: Mapping[str, Sequence[float]] | None = None, *,  # noqa: A002
                  wind: Sequence[str] | str | None = None, tmax: float | None = None, dt: float | None = None,
                  controller: str | None = None, discon: str | None = None, discon_input: str | None = None,
                  channels: Sequence[str] | None = None, del_channels: Sequence[str] = (),
                  wohler: float | Sequence[float] = 10.0, executor: Any = "serial", progress: bool | None = None,
                  compile: bool | None = None, series: bool = False):
    """Sweep a turbine over deck keys and wind specifications; one row per combination.

    Parameters
    ----------
    deck : str, Path, TurbineModel or OperatingDeck, optional
        An OpenFAST ``.fst`` (default: the built-in NREL 5 MW), or a model already built: a
        :class:`~mbsym.wind.TurbineModel` for free decays, an
        :class:`~mbsym.wind.operation.OperatingDeck` for wind runs.
    set : dict, optional
        ``{key: [values]}``: every combination is run (the last key varies fastest, then the
        winds). Keys: module docstring of :mod:`.sweep_keys`; values in the key's units.
    wind : str or sequence of str, optional, keyword-only
        Wind specifications (``steady:U``, ``step:U0:U1:T``, ``kaimal:U:TI:SEED``, a file): runs
        the operating turbine in each. None: structural free decays.
    tmax : float, optional, keyword-only
        Simulated time [s]; default the deck's TMax (built in: 10 s free decays, 60 s in wind).
    dt : float, optional, keyword-only
        Free decays: the RK4 step [s] (default the deck's DT). Wind: the output spacing [s]
        (default the deck's DT_Out, built in 0.05 s); the step is the controller's sample time.
    controller : {"baseline", "discon", "none"}, optional, keyword-only
        Wind runs only. Default: the deck's DISCON library when its ServoDyn runs one, the
        baseline without a deck, else none (held commands).
    discon, discon_input : str, optional, keyword-only
        DISCON library and its input file (default the deck's ServoDyn ``DLL_FileName``,
        ``DLL_InFile``); ``discon_input`` also feeds the baseline controller.
    channels : sequence of str, optional, keyword-only
        Channels summarized; default every OpenFAST channel of the model.
    del_channels : sequence of str, optional, keyword-only
        Channels with damage-equivalent loads (``pip install 'mbsym[loads]'``), columns
        ``<channel>_del_m<m>``, 1 Hz equivalent cycles over the simulated time.
    wohler : float or sequence of float, optional, keyword-only
        Wöhler exponents of the DELs (default 10; 4 for steel towers).
    executor : str or distributed.Client, optional, keyword-only
        ``"serial"``, ``"threads:N"`` (free decays), ``"processes:N"``, ``"dask:N"``,
        ``"dask:ADDRESS"`` (:mod:`mbsym.sweep.executors`).
    progress : bool, optional, keyword-only
        Progress bar on stderr (default: on a terminal).
    compile : bool, optional, keyword-only
        Generated C for the loops; default: free decays from :data:`COMPILE_FROM_STEPS` RK4 steps in
        all, wind runs from 2000 controller samples per case (as ``mbsym simulate``).
    series : bool, optional, keyword-only
        Keep every case's time series (``result.series``; free decays only).

    Returns
    -------
    SweepResult
        ``table``: the keys as given, ``wind``, the statistics, ``error``.

    Raises
    ------
    ParameterError
        An unknown key, or one the model does not have (before anything runs).
    WindInputError, OpenFASTFormatError, ControllerError
        A bad wind specification, deck or controller file (before anything runs).
    SweepError
        Bad options, channels or executor.

    Examples
    --------
    >>> from mbsym.wind.analysis.sweep import sweep_turbine
    >>> res = sweep_turbine(set={"FAStTunr(1)": [0.9, 1.1]}, tmax=1.0, channels=["TTDspFA"])
    >>> res.table.columns
    ('FAStTunr(1)', 'wind', 'TTDspFA_mean', 'TTDspFA_std', 'TTDspFA_max', 'TTDspFA_min', 'error')
    """
    axes = _axes(set)
    winds = _winds(wind)
    if winds is None:
        if controller is not None or discon is not None or discon_input is not None:
            raise SweepError("controller, discon and discon_input apply to wind runs; give wind specifications too "
                             "(e.g. wind=['steady:12']).")
        return _structural(deck, axes, tmax=tmax, dt=dt, channels=channels, del_channels=del_channels,
                           wohler=wohler, executor=executor, progress=progress, compile=compile, series=series)
    return _operating(deck, axes, winds, tmax=tmax, dt_out=dt, controller=controller, discon=discon,
                      discon_input=discon_input, channels=channels, del_channels=del_channels, wohler=wohler,
                      executor=executor, progress=progress, compile=compile, series=series)


# ------------------------------------------------------------------------------------------- inputs
def _axes(values) -> dict[str, list[float]]:
    if values is None:
        return {}
    if not isinstance(values, Mapping):
        raise SweepError(f"set must be a dict {{key: [values]}}; got {type(values).__name__}.")
    out = {}
    for key, vals in values.items():
        if isinstance(vals, (int, float)) and not isinstance(vals, bool):
            vals = [vals]
        if isinstance(vals, (str, bytes)) or not hasattr(vals, "__len__") or len(vals) == 0:
            raise SweepError(f"the values of {key!r} must be a non-empty list of numbers; got {vals!r}.")
        nums = []
        for v in vals:
            if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)) or not math.isfinite(v):
                raise ParameterError(f"{key}: every value must be a finite number; got {v!r}.")
            nums.append(float(v))
        out[str(key)] = nums
    return out


def _winds(wind) -> list[str] | None:
    if wind is None:
        return None
    winds = [wind] if isinstance(wind, (str, Path)) else list(wind)
    if not winds:
        raise SweepError("wind is empty: give at least one specification (e.g. ['steady:12']) or None for free "
                         "decays.")
    return [str(w) for w in winds]


def _grid(axes: dict, winds: list[str]) -> list[dict]:
    from ...sweep import grid

    return grid({**axes, "wind": winds}) if axes else [{"wind": w} for w in winds]


def _targets(axes: dict, *, parameters, states, dofs) -> list[KeyTarget]:
    return [resolve_key(k, parameters=parameters, states=states, dofs=dofs) for k in axes]


# ------------------------------------------------------------------------------------------- free decays
def _structural(deck, axes, *, tmax, dt, channels, del_channels, wohler, executor, progress, compile, series):
    from ...dynamics import as_dynamics
    from ...simulate.checks import check_step, check_tmax
    from ...sweep import sweep
    from ..structure.turbine import TurbineModel

    model = _structure_model(deck)
    if not isinstance(model, TurbineModel):
        raise TypeError(f"free decays need a deck path or a TurbineModel; got {type(model).__name__}.")
    dyn = as_dynamics(model)
    targets = _targets(axes, parameters=dyn.parameters, states=dyn.states, dofs=model.dofs)
    sim = model.turbine.simulation
    tmax = check_tmax(sim.total_time if tmax is None else tmax)
    h, n = check_step(sim.time_step if dt is None else dt, tmax)
    cases = _grid(axes, [FREE_DECAY])
    if compile is None:
        compile = n * len(cases) >= COMPILE_FROM_STEPS and _can_compile()
    setters = {t.key: t.apply for t in targets}
    setters["wind"] = lambda value: {}
    return sweep(model, cases, tmax=tmax, dt=h, setters=setters, channels=_channels(channels, dyn.output_names),
                 del_channels=tuple(del_channels), wohler=wohler, executor=executor, progress=progress,
                 compile=bool(compile), series=series)


def _structure_model(deck):
    from ..structure.turbine import TurbineModel

    if deck is None:
        return builtin_free_decay()
    if isinstance(deck, TurbineModel):
        return deck
    if isinstance(deck, (str, Path)):
        from ..deck.checks import check_modules
        from ..deck.openfast import read_openfast

        turbine = read_openfast(deck)
        check_modules(turbine, structure_only=True)       # aero/servo left out, with a warning
        return TurbineModel(turbine)
    return deck


def _channels(channels, available) -> tuple[str, ...]:
    if channels is None:
        return tuple(available)
    if isinstance(channels, str):
        raise SweepError("channels must be a list of names, e.g. ['TTDspFA', 'TwrBsMyt'].")
    unknown = [c for c in channels if c not in available]
    if unknown:
        raise SweepError(f"channels {unknown} are not outputs of this model; its channels are {list(available)}.")
    return tuple(channels)


def _wohler(wohler) -> tuple[float, ...]:
    ms = (wohler,) if isinstance(wohler, (int, float)) and not isinstance(wohler, bool) else tuple(wohler) \
        if isinstance(wohler, (list, tuple)) else ()
    if not ms or not all(isinstance(m, (int, float)) and not isinstance(m, bool) and math.isfinite(m) and m > 0
                         for m in ms):
        raise SweepError(f"wohler must be a positive number or a sequence of them (e.g. 4 or (4, 10)); got {wohler!r}.")
    return tuple(float(m) for m in ms)


def _can_compile() -> bool:
    from ... import codegen

    return codegen.compiler_command() is not None and not codegen.compile_disabled()


# ------------------------------------------------------------------------------------------- wind runs
def _operating(deck, axes, winds, *, tmax, dt_out, controller, discon, discon_input, channels, del_channels, wohler,
               executor, progress, compile, series):
    from ...simulate.checks import check_tmax
    from ...sweep import parse_executor, sweep
    from ..inflow import parse_wind_spec

    parse_executor(executor)                                  # a bad executor fails before the model is built
    if series:
        raise SweepError("series=True is not available for wind runs (the table holds each case's statistics); run "
                         "one case with mbsym.wind.operation.simulate_turbine for its time series.")
    if controller is not None and controller not in CONTROLLERS:
        raise SweepError(f"controller must be one of {list(CONTROLLERS)}; got {controller!r}.")
    deck = _operating_deck(deck)
    sim = deck.turbine.simulation
    builtin = deck.path is None
    tmax = check_tmax((_BUILTIN_TMAX if builtin else sim.total_time) if tmax is None else tmax)
    dt_out = check_tmax((_BUILTIN_DT_OUT if builtin else sim.output_time_step) if dt_out is None else dt_out)
    if dt_out > tmax:
        raise SweepError(f"the output spacing {dt_out:g} s exceeds tmax = {tmax:g} s; choose a smaller dt.")
    signals = {w: parse_wind_spec(w, duration=tmax) for w in dict.fromkeys(winds)}   # bad specs fail here
    kind = controller or ("discon" if discon is not None else "baseline" if builtin else
                          "discon" if deck.uses_library else "none")
    runner_controller = _controller_settings(kind, deck, discon, discon_input)
    model = _cached_model(deck)
    dyn = model.dynamics()
    targets = _targets(axes, parameters=dyn.parameters, states=dyn.states, dofs=model.dofs)
    chans = _channels(channels, dyn.output_names)
    samples = math.ceil(tmax / runner_controller["dt"] - 1e-9)
    if compile is None:
        from ..operation.simulation import _compile_pays_off

        x_start = dyn.state_vector(model.initial_state(10.0))
        compile = _compile_pays_off(dyn, samples, x_start, None, runs=len(_grid(axes, winds))) and _can_compile()
    runner = _runner(model, runner_controller, tmax, dt_out, bool(compile))
    runner.channels, runner.del_channels = chans, _channels(del_channels, dyn.output_names)
    runner.wohler = _wohler(wohler)
    cases = _grid(axes, winds)
    for settings in cases:
        settings[CASE_KEY] = _wind_case(model, deck, targets, settings, signals[settings["wind"]])
    if compile:
        _warm_up(runner, cases)
    res = sweep(None, cases, run=runner, wohler=wohler, executor=executor, progress=progress)
    return _without_case_key(res)


def _operating_deck(deck):
    from ..operation.deck import OperatingDeck, builtin_deck, operating_deck

    if deck is None:
        if "deck" not in _BUILTIN:
            _BUILTIN["deck"] = builtin_deck()
        return _BUILTIN["deck"]
    if isinstance(deck, OperatingDeck):
        return deck
    if isinstance(deck, (str, Path)):
        return operating_deck(deck)
    raise TypeError(f"wind runs need a deck path or an OperatingDeck; got {type(deck).__name__}.")


def _cached_model(deck):
    if deck.path is not None:
        return deck.model()
    if _BUILTIN.get("model_of") is not deck:
        _BUILTIN.update(model_of=deck, model=deck.model())
    return _BUILTIN["model"]


def _controller_settings(kind: str, deck, discon, discon_input) -> dict:
    """The runner's controller settings; bad controller files fail here, before the model is built."""
    from ..control import BaselineController
    from ..operation.controllers import baseline_in_loop

    out = {"kind": kind, "dt": float(deck.controller_dt)}
    if kind == "baseline":
        law = baseline_in_loop(BaselineController(deck.baseline_settings(discon_in=discon_input)))
        out.update(law=law.law.serialize(), x0=tuple(float(v) for v in law.x0), states=tuple(law.state_names))
    elif kind == "discon":
        library, infile = deck.discon_paths(discon, discon_input)
        out.update(library=str(Path(library).resolve()), input=str(Path(infile).resolve()),
                   n_blades=int(deck.turbine.number_of_blades))
    return out


def _runner(model, ctrl: dict, tmax: float, dt_out: float, compile: bool) -> ClosedLoopRunner:
    from ..operation.controllers import ACTUATED, MEASUREMENTS

    dyn, meas = model.dynamics(), model.measurement_dynamics()
    functions = {"rhs": dyn.rhs.serialize(), "measurements": meas.outputs.serialize(),
                 "channels": dyn.outputs.serialize()}
    controller = {k: v for k, v in ctrl.items() if k not in ("law", "states")}
    names = {"states": tuple(dyn.states), "inputs": tuple(dyn.inputs), "parameters": tuple(dyn.parameters),
             "measurements": tuple(meas.output_names), "law_measurements": tuple(MEASUREMENTS),
             "measurement_units": tuple(meas.output_units),
             "channels": tuple(dyn.output_names), "channel_units": tuple(dyn.output_units),
             "state_units": tuple(dyn.state_units), "input_units": tuple(dyn.input_units),
             "actuates": tuple(ACTUATED), "controller_states": tuple(ctrl.get("states", ()))}
    if "law" in ctrl:
        functions["law"] = ctrl["law"]
    return ClosedLoopRunner(functions, names, controller, float(tmax), float(dt_out), compile)


def _wind_case(model, deck, targets: list[KeyTarget], settings: dict, signal) -> WindCase:
    """Initial state and parameters of one case (the case's parameters in the balances); failures kept."""
    dyn = model.dynamics()
    try:
        parts = {"p": {}, "x0": {}}
        for t in targets:
            for part, values in t.apply(settings[t.key]).items():
                parts[part].update(values)
        p = parts["p"]
        u0 = float(np.asarray(signal(0.0), dtype=float).reshape(-1)[0])
        if deck.path is None:
            from ..operation.steady import steady_guess

            x0 = steady_guess(model, u0, settings=deck.baseline_settings(), p=p).state
        else:
            x0 = model.initial_state(u0, p=p)
        x = dict(zip(dyn.states, np.asarray(x0, dtype=float)))
        x.update(parts["x0"])
        x_vec = np.array([x[s] for s in dyn.states], dtype=float)
        p_vec = np.asarray(dyn.parameter_vector(p), dtype=float).reshape(-1)
        if not (np.all(np.isfinite(x_vec)) and np.all(np.isfinite(p_vec))):
            raise ParameterError("the initial state or the parameters are not finite for this case.")
        return WindCase(settings["wind"], x_vec, p_vec)
    except Exception as exc:  # noqa: BLE001 - the case fails in its row, the others run
        return WindCase(settings["wind"], None, None, exc)


def _warm_up(runner: ClosedLoopRunner, cases: list[dict]) -> None:
    """Compile the loop and the channels once here (disk cache), so that workers on this machine only load them."""
    import dataclasses

    from ...simulate.model import OUTPUT_BLOCK

    first = next((c[CASE_KEY] for c in cases if c[CASE_KEY].failure is None), None)
    if first is None:
        return
    short = min(runner.tmax, (OUTPUT_BLOCK + 1) * runner.dt_out)
    try:
        dataclasses.replace(runner, tmax=short, key="").run(first)
    except Exception:  # noqa: BLE001 - the case itself reports its failure when it runs
        pass


def _without_case_key(res):
    """The result with the hidden per-case numbers removed from the table and the cases."""
    from ...sweep import SweepTable

    rows = res.table.rows()
    res.table = SweepTable({c: [r[c] for r in rows] for c in res.table.columns if c != CASE_KEY})
    for case in res.cases:
        if case is not None:
            case.settings.pop(CASE_KEY, None)
            case.options.pop(CASE_KEY, None)
    return res
