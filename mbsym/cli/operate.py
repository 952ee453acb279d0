"""``mbsym simulate`` of an operating turbine: wind, rotor aerodynamics, actuators and a controller.

Contract (kept for acceptance checks)::

    mbsym simulate [DECK] --wind SPEC [--controller baseline|discon|nmpc|none]
                   [--discon LIB.so --discon-input DISCON.IN] [--preview S] [--estimator ekf|mhe]
                   [--out F.csv] [--plot F.png] [--stats]

with SPEC ``steady:U``, ``step:U0:U1:T``, ``kaimal:U:TI:SEED`` (also ``ramp:…``, ``eog:…``) or a file
(an InflowWind uniform wind file, or a ``Time_[s],Wind1VelX_[m/s]`` CSV).

* A deck with AeroDyn 15 runs as an operating turbine; with InflowWind and ServoDyn (a DISCON
  library and its input file) it runs all three without flags. ``--wind`` and ``--controller``
  override the deck's. The DOFs are the deck's.
* Without a deck, ``--wind`` runs the built-in NREL 5 MW with GenDOF, TwFADOF1 and TwSSDOF1
  (the DOFs the rotor's thrust and torque and the generator's reaction act on; the set of the
  OpenFAST reference runs), ROSCO 2.10.6's NREL 5 MW settings for our baseline controller, a
  controller sample time of 0.01 s (the built-in deck's DT), and initial conditions from a
  steady-state guess for the wind at t = 0 (:func:`mbsym.wind.operation.steady_guess`).
* Controllers: ``baseline`` (our ROSCO-scheme controller compiled into the loop; settings from
  ``--discon-input``, the deck's DISCON.IN, or the built-in NREL 5 MW), ``discon`` (the library:
  ``--discon``/``--discon-input`` or the deck's ServoDyn ``DLL_FileName``/``DLL_InFile``; one
  call per sample), ``nmpc`` (the turbine NMPC, ``--preview``/``--estimator``: :mod:`.operate_mpc`),
  ``none`` (pitch and torque held at their initial values). Default: ``discon``
  when the deck's ServoDyn runs a DISCON library, ``baseline`` without a deck, else ``none``.
* Integration: one RK4 step per controller sample (``--method rk4 --dt`` changes the step, a
  divisor of the sample time; ``--accuracy`` chooses sub-steps for the baseline controller); with
  blade-element aerodynamics and the baseline controller the deck's ElastoDyn ``Method`` by default
  (3: ``abm4-held``, Adams-Bashforth-Moulton 4 as ElastoDyn; 2: ``ab4-held``; 1: ``rk4-held``), else
  ``rk4-held``: the aerodynamics once per step, held over its RK4 stages as OpenFAST's glue code holds
  AeroDyn's loads; the output says which method ran and where it differs from the deck's (``--method rk4``
  evaluates them at every stage: 3-4x the cost, the same figures against OpenFAST, benchmarks/README.md
  "blade-speed"); with the
  baseline controller the aerodynamics are evaluated every 2 deg of rotor rotation (``--aero-dt``
  overrides; :func:`mbsym.wind.operation.simulation.default_aero_dt`);
  compiled to C from 2000 controller samples on, and for shorter runs whose plant would take longer in
  CasADi's virtual machine than compiling (a blade-element floating deck: from a few seconds of simulated time;
  a compilation estimated beyond 20 s is announced on stderr); ``--compile`` forces it.
* ``--tmax`` defaults to the deck's TMax (built-in: the length of a tabulated wind, else 60 s);
  ``--dt`` is the output spacing (default: the deck's DT_Out; built-in 0.05 s).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from types import SimpleNamespace

import numpy as np

__all__ = ["add_arguments", "wants_operation", "run_operation", "CONTROLLERS"]

CONTROLLERS = ("baseline", "discon", "nmpc", "none")
#: Channels of the summary table and the default plot.
SUMMARY_CHANNELS = ("Wind1VelX", "RotSpeed", "BldPitch1", "GenTq", "GenPwr", "RtAeroFxh", "TTDspFA", "TwrBsMyt")
_BUILTIN_TMAX, _BUILTIN_DT_OUT = 60.0, 0.05


def add_arguments(p: argparse.ArgumentParser) -> None:
    """The operating-turbine flags of ``mbsym simulate``."""
    p.add_argument("--wind", metavar="SPEC",
                   help="hub-height wind: steady:U, step:U0:U1:T, kaimal:U:TI:SEED, ramp:U0:U1:T0:T1, eog:U:T0:VGUST "
                        "or a file (InflowWind uniform wind file, or CSV Time_[s],Wind1VelX_[m/s]); runs the "
                        "turbine with aerodynamics and a controller")
    p.add_argument("--aero", choices=("blade", "rotor"),
                   help="aerodynamics: blade (blade-element BEM on every blade node, in the wind over the rotor: "
                        "full field, shears) or rotor (rotor-effective Cp/Ct surfaces, hub-height wind); default: "
                        "blade when the deck's wind varies over the rotor, blade/yaw DOFs are on or its AeroDyn "
                        "has the tower disturb the blade inflow (TwrPotent, TwrShadow) or unsteady airfoils "
                        "(UA_Mod 3), else rotor")
    p.add_argument("--aero-dt", type=float, metavar="DT",
                   help="blade-element aerodynamics with the baseline controller: evaluate them every DT seconds, a "
                        "multiple of the controller's sample time (default: every 2 deg of rotor rotation, 4 deg with "
                        "quadratic extrapolation; NREL 5 MW 25 / 50 ms; every step with UA_Mod 3; the controller and "
                        "the structure keep the sample time)")
    p.add_argument("--aero-order", type=int, choices=(0, 1, 2), metavar="{0,1,2}",
                   help="blade-element aerodynamics with the baseline controller: between evaluations hold them (0) "
                        "or extrapolate them linearly (1) or quadratically (2) (default: the deck's InterpOrder)")
    p.add_argument("--controller", choices=CONTROLLERS,
                   help="baseline (ours, compiled into the loop), discon (a DISCON library), nmpc (the turbine "
                        "NMPC), none (held commands); default: the deck's DISCON library, baseline without a deck")
    p.add_argument("--discon", metavar="LIB.so", help="DISCON library (default: the deck's ServoDyn DLL_FileName)")
    from .mooring_lines import add_argument as add_mooring_argument

    add_mooring_argument(p)             # --mooring-lines (cli/mooring_lines.py)
    p.add_argument("--discon-input", metavar="DISCON.IN",
                   help="controller input file (default: the deck's ServoDyn DLL_InFile; the baseline reads it too)")
    from .operate_mpc import add_arguments as add_mpc_arguments

    add_mpc_arguments(p)                # --preview, --estimator (cli/operate_mpc.py)


def wants_operation(args: argparse.Namespace) -> bool:
    """Whether ``mbsym simulate`` runs an operating turbine (flags, or a deck with AeroDyn).

    Raises
    ------
    SimulationOptionError
        ``--structure-only`` together with an operating flag.
    """
    flags = [f"--{k.replace('_', '-')}" for k in ("wind", "aero", "controller", "discon", "discon_input")
             if getattr(args, k, None) is not None]
    if getattr(args, "structure_only", False):
        if flags:
            from ..exceptions import SimulationOptionError

            raise SimulationOptionError(f"--structure-only runs the ElastoDyn structure alone (no wind, no "
                                        f"controller); it cannot be combined with {', '.join(flags)}.")
        return False
    if flags:
        return True
    if args.deck is None:
        return False
    from ..wind.deck.openfast import read_openfast

    return "aerodyn" in read_openfast(args.deck).source_files


def run_operation(args: argparse.Namespace) -> int:
    """Run ``mbsym simulate`` for an operating turbine (see the module docstring)."""
    from ..simulate import ProgressPrinter, SimulationInterrupted
    from ._run import check_files, report_comparison, write_outputs

    options = _integration(args)
    ref, outputs = check_files(args)
    t0 = time.perf_counter()
    deck = _deck(args)
    kind = _controller_kind(args, deck)
    from .operate_mpc import check_options

    mpc = check_options(args, kind)                          # --preview/--estimator (cli/operate_mpc.py)
    aero = _aero(args, deck, mpc)
    _rotor_note(deck, aero)
    for key, flag in (("aero_dt", "--aero-dt"), ("aero_order", "--aero-order")):
        if key in options and (aero != "blade" or mpc.active):
            from ..exceptions import SimulationOptionError

            raise SimulationOptionError(f"{flag} sets how the blade-element aerodynamics are evaluated between "
                                        "controller samples; " + ("this run has the rotor-effective model: drop "
                                        f"{flag}, or use --aero blade." if aero != "blade" else "the NMPC's and the "
                                        "estimators' Python loop evaluates them at every sample: drop " + flag + "."))
    wind, wind_label = _wind(args, deck, aero)
    tmax, t_out = _grid(args, deck, wind)
    from ..wind.operation.cut_out import warn_above_cut_out

    warn_above_cut_out(wind, tmax, deck.cut_out_wind_speed, deck.cut_out_source)    # unknown for a deck: none
    outputs.add_inputs(_input_files(args, deck))             # never overwritten by --out/--plot
    controller, handle = (None, None) if mpc.active else _controller(kind, args, deck)   # files checked first
    try:
        model = _model(deck, aero, tmax)
        dyn = model.dynamics()
        controller = _for_plant(controller, handle, model, kind, args, deck)
        x0 = _initial_state(model, deck, wind)
        if mpc.active:
            parts = " and the ".join(x for x in (mpc.controller.upper() if mpc.controller == "nmpc" else "",
                                                 (mpc.estimator or "").upper()) if x)
            print(f"mbsym simulate: preparing the {parts} (models, reference table, solvers): about 3 s, more when "
                  "solver libraries compile (said below)", file=sys.stderr, flush=True)
        loop = mpc.loop(deck, model, wind, lidar=run_lidar(args, deck),
                        say=lambda line: print(f"mbsym simulate: {line}", file=sys.stderr)) if mpc.active else None
        if loop is not None:                 # the solvers' libraries compile in the background: say so, wait
            from ..codegen_async import wait_for_compilations

            wait_for_compilations(lambda line: print(f"mbsym simulate: {line}", file=sys.stderr, flush=True))
        controller = loop.controller() if loop is not None else controller
    except BaseException:
        if handle is not None:
            handle.close()
        raise
    prepare = time.perf_counter() - t0
    _header(deck, model, kind, controller, wind_label, tmax, options)
    _note_outlist(deck, dyn)
    printer = ProgressPrinter(sys.stderr)
    try:
        from ..codegen import announcing
        from ..wind.operation.simulation import simulate_turbine

        with announcing(lambda line: print(f"mbsym simulate: {line}", file=sys.stderr, flush=True)):
            if loop is not None:
                from ..wind.mpc.simulation import simulate_with_loop

                result = simulate_with_loop(model, wind, tmax, loop, x0=x0, t_out=t_out, progress=printer, **options)
            else:
                result = simulate_turbine(model, wind, tmax, controller=controller, x0=x0, t_out=t_out,
                                          progress=printer, **options)
    except SimulationInterrupted as exc:
        printer.close()
        print(f"mbsym simulate: {exc} (of {tmax:g} s); nothing written", file=sys.stderr)
        return 130
    finally:
        if handle is not None:
            handle.close()
    printer.close()
    series = _series(result, dyn)
    stats = dict(result.statistics)
    stats["prepare_wall_s"] = float(stats.get("prepare_wall_s", 0.0)) + prepare
    dt = stats.get("controller_dt", None if controller is None else controller.dt)      # the NMPC's own
    stats.update(controller=kind, controller_dt=dt,
                 real_time_factor=tmax / max(float(stats.get("integration_wall_s", 0.0)), 1e-12))
    _summary(series, stats)
    if ref is not None:
        report_comparison(series, ref)
    from ._run import compare_label

    words = _controller_words(kind, args, deck, mpc)
    title = f"{_deck_name(deck)} in {_wind_words(args, deck, wind)}, {words}"
    write_outputs(outputs, series, ref, title, SUMMARY_CHANNELS, series_label=f"mbsym ({_rung(model)}, {words})",
                  ref_label=compare_label(args.compare) if args.compare else None)
    if args.stats:
        from ._run import jsonable

        print(json.dumps({k: jsonable(v) for k, v in stats.items()}))
    return 0


# ------------------------------------------------------------------------------------------- pieces
def _input_files(args, deck) -> list[tuple[str, str]]:
    """Files the run reads (the deck's, the wind file, the controller's input)."""
    files = [(f"deck's {name}", path) for name, path in (getattr(deck.turbine, "source_files", {}) or {}).items()]
    if args.wind is not None and Path(args.wind).is_file():
        files.append(("--wind", args.wind))
    for flag, path in (("--discon-input", args.discon_input), ("deck's DISCON.IN", deck.discon_in)):
        if path is not None:
            files.append((flag, str(path)))
    return files


def _note_outlist(deck, dyn) -> None:
    """Say which channels of the deck's ElastoDyn OutList the model does not give (the CSV has the rest)."""
    wanted = getattr(deck.turbine, "output_channels", ()) if deck.path is not None else ()
    have = {n.lower() for n in dyn.output_names}
    missing = [n for n in wanted if n.lower() not in have]
    if missing:
        print(f"note: {len(missing)} of the {len(wanted)} channels of the deck's ElastoDyn OutList are not modelled "
              f"and not written: {', '.join(missing)}", file=sys.stderr)


def _integration(args) -> dict:
    """Integration keywords of simulate_turbine from the flags (checked before any work)."""
    from ..exceptions import SimulationOptionError
    from ..simulate.checks import check_accuracy

    if args.rtol is not None or args.atol is not None:
        raise SimulationOptionError("--rtol/--atol do not apply to an operating turbine: it runs RK4 steps between "
                                    "controller samples (choose the step with --method rk4 --dt, or --accuracy).")
    if args.method is not None and args.method not in ("rk4", "rk4-held", "abm4-held", "ab4-held"):
        raise SimulationOptionError(f"--method {args.method}: an operating turbine runs RK4 steps between controller "
                                    "samples; use --method rk4 or rk4-held (blade-element aerodynamics held over "
                                    "each step; with --dt as the step), abm4-held or ab4-held (ElastoDyn's "
                                    "multistep methods, blade-element aerodynamics with the baseline controller) or "
                                    "leave --method unset (the deck's ElastoDyn Method where it is modelled).")
    if args.accuracy is not None and args.method is not None:
        raise SimulationOptionError("--accuracy chooses the step itself; it cannot be combined with --method.")
    out: dict = {}
    if args.accuracy is not None:
        out["accuracy"] = check_accuracy(args.accuracy)
    if args.method is not None:
        out["method"] = args.method
        if args.dt is not None:
            out["dt"] = float(args.dt)
    if args.compile:
        out["compile"] = True
    if getattr(args, "aero_dt", None) is not None:
        out["aero_dt"] = float(args.aero_dt)
    if getattr(args, "aero_order", None) is not None:
        out["aero_order"] = int(args.aero_order)
    return out


#: The built-in operating model, built once per process (derivation and surfaces take seconds).
_BUILTIN: dict = {}


def _deck(args):
    from ..wind.operation.deck import builtin_deck, operating_deck
    from .mooring_lines import with_mooring_lines

    if args.deck is not None:
        return with_mooring_lines(operating_deck(args.deck), getattr(args, "mooring_lines", None))
    with_mooring_lines(None, getattr(args, "mooring_lines", None))       # refused without a deck
    if "deck" not in _BUILTIN:
        deck = builtin_deck()
        model = deck.model()
        _BUILTIN.update(deck=deck, model=model)
    return _BUILTIN["deck"]


def _model(deck, aero: str, tmax: float | None = None):
    if deck.path is None and _BUILTIN.get("deck") is deck:
        return _BUILTIN["model"]
    return deck.model(aero=aero, t_end=tmax)


def _aero(args, deck, mpc) -> str:
    """``--aero``, else the deck's default; the NMPC and its estimators need the rotor-effective model."""
    from ..exceptions import SimulationOptionError

    if deck.path is None:
        if args.aero == "blade":
            raise SimulationOptionError("--aero blade needs a deck (its AeroDyn blade and airfoil files); the "
                                        "built-in turbine runs the rotor-effective model (--aero rotor).")
        return "rotor"
    aero = args.aero or deck.default_aero()
    if aero == "blade" and mpc.preview is not None:
        raise SimulationOptionError("--preview is an ideal preview of the rotor-effective plant's hub wind with its "
                                    "true state; this deck's plant is blade-element (its wind varies over the rotor, "
                                    "blade/yaw DOFs are on, or its AeroDyn's tower disturbs the blade inflow). Drop "
                                    "--preview (the NMPC then runs on its estimator, and on the deck's lidar when its "
                                    "InflowWind has one), or pass --aero rotor.")
    return aero


def _rotor_note(deck, aero: str) -> None:
    """Say what of the deck's AeroDyn the rotor-effective rung holds only as an average (docs/aero.md §6b)."""
    if aero != "rotor" or deck.path is None or deck.aerodyn is None:
        return
    from ..wind.aero.tower import TowerAero

    tower = TowerAero.from_aerodyn(deck.aerodyn)
    held = (["tower's inflow disturbance as an azimuth average (no 3P)"] if tower is not None
            and tower.disturbs_inflow else []) + \
        ([f"UA_Mod {deck.aerodyn.unsteady_model} at its steady state (no dynamic stall)"]
         if deck.aerodyn.unsteady_model else [])
    if held:
        print(f"note: the rotor-effective rung holds the deck's {' and '.join(held)}; the blade-element rung "
              "(--aero blade) has them blade by blade")


def _controller_kind(args, deck) -> str:
    if args.controller is not None:
        return args.controller
    if args.discon is not None:
        return "discon"
    if deck.path is None:
        return "baseline"
    return "discon" if deck.uses_library else "none"


def _wind(args, deck, aero: str = "rotor"):
    """``(wind, label)``: ``--wind SPEC`` (hub-height speed), else the deck's InflowWind (for a blade-element model
    its wind over the rotor: a full field is carried by the model, so the wind is None)."""
    from ..exceptions import WindInputError
    from ..wind.inflow import parse_wind_spec

    if args.wind is not None:
        duration = args.tmax if args.tmax is not None else (
            deck.turbine.simulation.total_time if deck.path is not None else 600.0)
        return parse_wind_spec(args.wind, duration=float(duration)), f"--wind {args.wind}"
    if deck.inflow is None:
        raise WindInputError(f"{deck.label}: the deck has no InflowWind (CompInflow = 1) to take the wind from; "
                             "give one with --wind SPEC (e.g. steady:12).")
    label = f"InflowWind {deck.inflow.path}"
    if aero == "blade":
        field = deck.inflow.field()
        return (field if hasattr(field, "columns_at") else None), label
    return deck.wind(), label

def _grid(args, deck, wind) -> tuple[float, np.ndarray]:
    from ._run import time_grid

    sim = deck.turbine.simulation
    if deck.path is None:
        from ..wind.inflow import TabulatedWind

        table = isinstance(wind, TabulatedWind) and np.size(wind.time) > 1
        tmax = float(wind.time[-1]) if table else _BUILTIN_TMAX
        sim = SimpleNamespace(total_time=tmax, output_time_step=_BUILTIN_DT_OUT, time_step=deck.controller_dt)
    tmax, t_out, _ = time_grid(args, sim)
    return tmax, t_out


def _initial_state(model, deck, wind):
    from ..wind.operation.simulation import wind_at_start
    from ..wind.operation.steady import steady_guess

    if model.aero == "blade":
        return model.initial_state(wind_at_start(model, wind))
    u0 = float(np.asarray(wind(0.0)).reshape(-1)[0])
    if deck.path is not None:
        return model.initial_state(u0)          # the deck's ElastoDyn initial conditions, as OpenFAST starts
    return steady_guess(model, u0).state


def _controller(kind, args, deck):
    """``(DiscreteController or None, DisconController to close or None)``."""
    from ..wind.control import BaselineController, DisconController
    from ..wind.operation.controllers import baseline_in_loop, discon_in_loop

    if kind == "none":
        return None, None
    if kind == "baseline":
        settings = deck.baseline_settings(discon_in=args.discon_input)
        return baseline_in_loop(BaselineController(settings)), None
    library, infile = deck.discon_paths(args.discon, args.discon_input, folder=output_folder(args))
    if deck.path is None and args.discon_input is None:
        print(f"wrote the built-in NREL 5 MW controller input (ROSCO 2.10.6 settings) to {infile} and "
              f"{infile.parent / 'Cp_Ct_Cq.txt'}; the library reads them", flush=True)
    _warn_flap_control(infile, deck)
    handle = DisconController(library, infile, dt=deck.controller_dt, n_blades=deck.turbine.number_of_blades,
                              lidar=run_lidar(args, deck))
    return discon_in_loop(handle), handle


def _warn_flap_control(infile, deck) -> None:
    """A ROSCO input asking for flap control (``Flp_Mode`` > 0) where ServoDyn sends no airfoil commands
    (``AfCmode`` 0, the only mode mbsym models): ROSCO 2.10.6's library stops with a segmentation fault at its first
    call in that set-up, in OpenFAST v5.0.0 too (the wheel's BAR_10 deck), and takes the process down: say so."""
    import warnings

    from ..exceptions import ModelWarning, OpenFASTFormatError
    from ..wind.deck.discon_in import read_discon_in

    try:
        flap = int(read_discon_in(infile)["Flp_Mode"] or 0)
    except (OpenFASTFormatError, KeyError, TypeError, ValueError, OSError):
        return                                   # not a ROSCO input: nothing to say
    servo = getattr(deck, "servodyn", None)
    if flap and int(getattr(servo, "airfoil_control_mode", 0) or 0) == 0:
        warnings.warn(f"{infile}: Flp_Mode = {flap} asks ROSCO for flap control, but ServoDyn's AfCmode is 0 (no "
                      "airfoil commands reach AeroDyn); ROSCO 2.10.6's library crashes (segmentation fault) at its "
                      "first call in this set-up, in OpenFAST too. Set Flp_Mode = 0 if it does.", ModelWarning,
                      stacklevel=2)



def run_lidar(args, deck):
    """The deck's lidar measurement for this run (None without one); with ``--wind`` the plant's wind is not the
    deck's, so its lidar would measure another wind: left out with a :class:`~mbsym.exceptions.ModelWarning`."""
    import warnings

    from ..exceptions import ModelWarning

    if deck.inflow is None or getattr(deck.inflow, "lidar", None) is None:
        return None
    if getattr(args, "wind", None) is not None:
        warnings.warn(f"{deck.inflow.path}: the lidar (SensorType = 1) measures the deck's wind; this run's wind is "
                      f"--wind {args.wind}, so the controller gets no lidar records. Drop --wind to use it.",
                      ModelWarning, stacklevel=2)
        return None
    return deck.lidar_measurement()


def output_folder(args) -> Path:
    """The run's output folder: that of --out, else of --plot, else the working directory."""
    for target in (getattr(args, "out", None), getattr(args, "plot", None)):
        if target is not None:
            return Path(target).absolute().parent
    return Path.cwd()


def _for_plant(controller, handle, model, kind, args, deck):
    """The controller wired to the plant: a DISCON library always gets every record the plant measures (the
    measured torque, record 23, and the tower-top acceleration, 53, as ServoDyn fills them; with a blade-element
    plant the root moments, azimuth and per-blade pitch; with a floating one the platform's motion); the
    baseline is rewired for a blade-element or floating plant, else as built."""
    from ..wind.control import BaselineController
    from ..wind.operation.controllers import baseline_in_loop, discon_in_loop

    if controller is None:
        return controller
    if kind != "baseline":
        return discon_in_loop(handle, model=model)
    if model.aero != "blade" and getattr(model, "platform", None) is None:
        return controller
    settings = deck.baseline_settings(discon_in=args.discon_input)
    return baseline_in_loop(BaselineController(settings), model=model)


def _series(result, dyn):
    """The plant's channels, then the estimated ``<channel>_est`` channels (with an estimator)."""
    from ..wind.analysis.compare import TimeSeries

    n = dyn.n_y
    est = [i for i, name in enumerate(result.output_names) if i >= n and name.endswith("_est")]
    cols = list(range(n)) + est
    names = tuple(result.output_names[i] for i in cols)
    units = tuple(dyn.output_units) + tuple(result.output_units[i] for i in est)
    return TimeSeries(np.asarray(result.t), names, units, np.asarray(result.y)[:, cols])


def _deck_name(deck) -> str:
    return deck.label if deck.path is None else Path(deck.path).name


def _rung(model) -> str:
    return "blade-element" if model.aero == "blade" else "rotor-effective"


def _controller_words(kind: str, args, deck, mpc) -> str:
    """The controller as a plot says it: ``baseline controller``, ``DISCON libdiscon.so``, ``NMPC, ekf estimator``,
    ``NMPC, 5 s preview``."""
    if kind == "none":
        return "no controller (held pitch and torque)"
    if kind == "discon":
        library = args.discon or deck.library
        return f"DISCON {Path(library).name}" if library is not None else "DISCON"
    words = "NMPC" if kind == "nmpc" else "baseline controller"
    if mpc.preview is not None:
        words += f", {mpc.preview:g} s preview"
    if mpc.estimator is not None:
        words += f", {mpc.estimator} estimator"
    return words


def _wind_words(args, deck, wind) -> str:
    """The wind as a title says it: ``steady 14 m/s``, ``Kaimal 14 m/s TI 16 % seed 3``, or the wind file's name."""
    from ..wind.inflow import RampWind, SteadyWind, StepWind
    from ..wind.inflow.kaimal import KaimalWind
    from ..wind.inflow.signals import ExtremeOperatingGust

    if isinstance(wind, SteadyWind):
        return f"steady {wind.speed:g} m/s"
    if isinstance(wind, StepWind):
        return f"step {wind.before:g} to {wind.after:g} m/s at {wind.time:g} s"
    if isinstance(wind, RampWind):
        return f"ramp {wind.start_speed:g} to {wind.end_speed:g} m/s over {wind.start:g}-{wind.end:g} s"
    if isinstance(wind, KaimalWind):
        return (f"Kaimal {wind.mean_speed:g} m/s TI {100 * wind.turbulence_intensity:.3g} % seed {wind.seed}")
    if isinstance(wind, ExtremeOperatingGust):
        return f"EOG at {wind.hub_speed:g} m/s, gust {wind.gust_speed:g} m/s from {wind.start:g} s"
    if args.wind is not None:
        return Path(args.wind).name
    inflow = deck.inflow
    if inflow.wind_type == 1:
        return f"steady {inflow.steady_speed:g} m/s (InflowWind)"
    kind = inflow.wind_type
    if kind in (4, 7):
        name = inflow.bladed_file_name + (".wnd" if kind == 4 else "")
    elif kind == 5:
        name = str(inflow.hawc.files[0])
    else:
        name = inflow.full_field_file_name if kind == 3 else inflow.uniform_file_name
    return f"{Path(name).name} (InflowWind)"


def _header(deck, model, kind, controller, wind_label, tmax, options) -> None:
    dofs = ", ".join(f for f, on in model.dofs.items() if on)
    inflow = "dynamic inflow (DBEMT)" if model.dynamic_inflow is not None else "quasi-steady inflow"
    rotor = model.rotor.source if model.aero == "rotor" else f"blade-element {model.rotor!r}"
    if model.aero == "blade":
        inflow = f"wind {model.wind!r}"
    ctrl = "none (held commands)" if controller is None else f"{kind} every {controller.dt:g} s"
    how = f"accuracy {options['accuracy']:g}" if "accuracy" in options else "one step per controller sample" \
        if controller is not None and "method" not in options else f"method {options.get('method', 'auto')}"
    print(f"mbsym simulate: {deck.label} operating in {wind_label}")
    print(f"DOFs: {dofs}; rotor {rotor}, {inflow}; controller {ctrl}")
    print(f"{tmax:g} s, {how}", flush=True)
    from .mooring_lines import header_line

    if header_line(model):
        print(header_line(model), flush=True)
    if model.aero == "blade" and controller is not None and not controller.is_function:
        print(f"note: the DISCON library is called from Python at every sample, so the blade-element aerodynamics "
              f"are evaluated every sample and held over it (the deck's InterpOrder "
              f"{model.turbine.simulation.interp_order} extrapolates them with compiled controllers)", flush=True)


def _held_text(stats) -> str:
    """How the blade-element aerodynamics were evaluated (empty when every step)."""
    if "held_dt" not in stats:
        return ""
    how = ("held", "extrapolated linearly", "extrapolated quadratically")[int(stats.get("held_order", 0))]
    return f"; aerodynamics every {1e3 * float(stats['held_dt']):.4g} ms, {how} in between"


def _summary(series, stats) -> None:
    from ._run import number

    compiled = ", compiled" if stats.get("compiled") else ""
    step = f" of {stats['dt']:.4g} s" if stats.get("dt") else ""
    print(f"method {stats.get('method')}{compiled}: {stats.get('steps')} steps{step}, integration "
          f"{1e3 * float(stats.get('integration_wall_s', 0)):.1f} ms ({stats['real_time_factor']:.0f}x real time), "
          f"preparation {1e3 * float(stats.get('prepare_wall_s', 0)):.1f} ms, {series.time[-1]:.2f} s simulated"
          + _held_text(stats))
    if stats.get("deck_method"):
        note = str(stats.get("message", ""))
        note = note[note.index("The deck asks"):] if "The deck asks" in note else \
            f"the deck's ElastoDyn Method: {stats['deck_method']}"
        print(note)
    print()
    print(f"{'channel':<12} {'unit':<6} {'initial':>12} {'min':>12} {'max':>12} {'mean':>12} {'final':>12}")
    for n in SUMMARY_CHANNELS:
        y = series.channel(n)
        unit = series.units[series.names.index(n)]
        print(f"{n:<12} {unit:<6} " + " ".join(number(v, "12.5g") for v in (y[0], y.min(), y.max(), y.mean(), y[-1])))
