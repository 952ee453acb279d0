"""``mbsym simulate``: free decays of OpenFAST decks (or the built-in NREL 5 MW).

Contract (kept for acceptance checks)::

    mbsym simulate [DECK.fst] [--tmax T] [--dt DT] [--out FILE.csv] [--plot FILE.png]
                   [--compare OPENFAST.csv] [--method M] [--rtol R] [--atol A]
                   [--accuracy EPS] [--list-methods] [--stats] [--compile]

A floating deck without AeroDyn (``CompHydro``/``CompMooring`` on, e.g. a free decay in still water or in
waves) runs as the structure with its water, sea and mooring (:func:`mbsym.wind.offshore.floating_structure`;
rotor parked). No deck: the built-in NREL 5 MW onshore turbine (:func:`mbsym.wind.deck.nrel5mw`) with its
structural DOFs this template models, released from a tower-top displacement of
0.5 m fore-aft with the rotor at the deck's 10 rpm, yaw held by the NREL 5 MW
ServoDyn yaw spring and damper (ElastoDyn alone leaves the yaw free). ``--tmax`` defaults to the
deck's TMax; output is sampled every ``--dt`` (default: the deck's DT_Out).

Integration: by default mbsym chooses the method, step and compilation for ``--accuracy``
(default 1e-3: mean error below 0.1 % of each state's range against the converged solution;
:mod:`mbsym.simulate.auto`), independently of the output spacing. ``--method`` (with ``--dt``
as the step of a fixed-step method, default the deck's DT) or ``--rtol``/``--atol`` (cvodes)
choose the integration explicitly instead.

The header is printed before integrating; progress goes to stderr (on a terminal a bar, else a
line every 5 s for runs longer than that); Ctrl-C ends the run within a second with
"interrupted at t = ... s" (exit status 130, no files written). Runs whose result would exceed
the memory limit (:data:`mbsym.simulate.MEMORY_LIMIT_BYTES`) are refused before integrating.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

from . import plain as _plain
from ._run import check_files, compare_label, jsonable, number, report_comparison, time_grid, write_outputs

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="simulate an OpenFAST deck (default: built-in NREL 5 MW): a free decay, or "
                                        "operating in a wind (--wind, or a deck with AeroDyn)",
                       description=_plain(__doc__.split("\n\n")[0]))
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst); default: built-in NREL 5 MW")
    p.add_argument("--tmax", type=float, help="simulated time [s] (default: the deck's TMax)")
    p.add_argument("--dt", type=float, help="output spacing [s] (default: the deck's DT_Out); with a fixed-step "
                                            "--method also its step (default: the deck's DT)")
    p.add_argument("--out", metavar="FILE.csv", help="write OpenFAST-named channels as CSV")
    p.add_argument("--plot", metavar="FILE.png", help="write a plot of the DOF channels (overlaid with --compare)")
    p.add_argument("--compare", metavar="OPENFAST.csv", help="OpenFAST CSV output to compare with (ε, R² per channel)")
    p.add_argument("--accuracy", type=float, metavar="EPS",
                   help="error bound for the automatic choice of method, step and compilation: mean |x - x_ref| / "
                        "range(x_ref) per state against the converged solution (default 1e-3)")
    p.add_argument("--method", help="integration method instead of the automatic choice (see --list-methods)")
    p.add_argument("--rtol", type=float, help="relative tolerance of adaptive methods (default 1e-8; alone: cvodes)")
    p.add_argument("--atol", type=float, help="absolute tolerance of adaptive methods (default 1e-10; alone: cvodes)")
    p.add_argument("--list-methods", action="store_true", help="print the integration methods, one per line, and exit")
    p.add_argument("--stats", action="store_true", help="print the run statistics as one JSON object on the last line")
    p.add_argument("--compile", action="store_true", default=None,
                   help="run the integration as generated C (gcc -O1, cached on disk); by default the automatic "
                        "choice compiles when the library is cached or compiling pays off")
    add_structure_only(p)
    from .operate import add_arguments

    add_arguments(p)            # the operating turbine: --wind, --controller, --discon, --discon-input (cli/operate.py)


def add_structure_only(p) -> None:
    """The ``--structure-only`` flag (simulate, linearize, campbell)."""
    p.add_argument("--structure-only", action="store_true",
                   help="run a deck that switches on modules mbsym does not model (CompAero, CompServo, CompHydro, "
                        "...) as the ElastoDyn structure alone, with a warning (default: refuse such decks)")


from ..wind.deck.nrel5mw import NREL5MW_YAW_DAMPING, NREL5MW_YAW_SPRING  # noqa: E402  (re-exported)


def builtin_turbine():
    """The built-in scene: NREL 5 MW onshore, tower top released from 0.5 m fore-aft."""
    from ..wind import nrel5mw

    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, tower_top_fa_displacement=0.5)
    return dataclasses.replace(t, initial_conditions=ic)


def run(args: argparse.Namespace) -> int:
    from ..simulate import METHODS, ProgressPrinter, SimulationInterrupted

    if args.list_methods:
        print("\n".join(METHODS))
        return 0
    from .operate import run_operation, wants_operation

    if wants_operation(args):       # wind, aerodynamics, actuators, controller (cli/operate.py)
        return run_operation(args)
    options = _integration_options(args)
    ref, outputs = check_files(args)        # fail before any expensive work
    model, label = _model(args.deck, structure_only=args.structure_only, lines=getattr(args, "mooring_lines", None))
    outputs.add_inputs(_deck_inputs(model))
    tmax, t_out, step = time_grid(args, model.turbine.simulation)
    t0 = time.perf_counter()
    channels = model.output_function()          # derives the equations and the output Function
    prepare = time.perf_counter() - t0
    _header(label, model, tmax, options)
    printer = ProgressPrinter(sys.stderr)
    try:
        result = _simulate(model, tmax, t_out, step, options, printer)
    except SimulationInterrupted as exc:
        printer.close()
        print(f"mbsym simulate: {exc} (of {tmax:g} s); nothing written", file=sys.stderr)
        return 130
    printer.close()
    series = _series(result, channels)
    stats = dict(result.statistics)
    stats["prepare_wall_s"] = float(stats.get("prepare_wall_s", 0.0)) + prepare
    _summary(series, stats)
    if ref is not None:
        report_comparison(series, ref)
    write_outputs(outputs, series, ref, label if args.deck is None else Path(args.deck).name, series_label=f"mbsym ({_method_label(stats)})",
                  ref_label=compare_label(args.compare) if args.compare else None)
    if args.stats:
        print(json.dumps({k: jsonable(v) for k, v in stats.items()}))
    return 0


def _integration_options(args) -> dict:
    """Keyword arguments of mbsym.simulate from the integration flags (checked before any work)."""
    from ..exceptions import SimulationOptionError
    from ..simulate import METHODS
    from ..simulate.checks import check_accuracy, check_tolerances

    explicit = [f for f, v in (("--method", args.method), ("--rtol", args.rtol), ("--atol", args.atol))
                if v is not None]
    if args.accuracy is not None and explicit:
        raise SimulationOptionError(f"--accuracy chooses the method and step itself; it cannot be combined with "
                                    f"{', '.join(explicit)}. Give either --accuracy or --method (with --dt or "
                                    "--rtol/--atol).")
    if args.method is not None and args.method not in METHODS:
        raise SimulationOptionError(f"unknown --method {args.method!r}; choose one of {', '.join(METHODS)} "
                                    "(--list-methods)")
    if not explicit:
        return {"accuracy": check_accuracy(1e-3 if args.accuracy is None else args.accuracy),
                "compile": args.compile}
    method = args.method or "cvodes"
    out = {"method": method, "compile": bool(args.compile)}
    if METHODS[method].kind != "fixed-step":
        rtol, atol = check_tolerances(1e-8 if args.rtol is None else args.rtol,
                                      1e-10 if args.atol is None else args.atol)
        out.update(rtol=rtol, atol=atol)
    elif args.rtol is not None or args.atol is not None:
        raise SimulationOptionError(f"--rtol/--atol apply to adaptive methods; --method {method} has a fixed step "
                                    "(set it with --dt).")
    return out


def _deck_inputs(model) -> list[tuple[str, str]]:
    """The deck's files (never overwritten by an output)."""
    files = getattr(model.turbine, "source_files", {}) or {}
    return [(f"deck's {name}", path) for name, path in files.items()]


def _model(deck, *, structure_only: bool = False, lines: str | None = None):
    from ..wind import read_openfast
    from ..wind.structure.turbine import NON_BLADE_DOFS, TurbineModel

    from .mooring_lines import structure_lines

    if deck is None:
        structure_lines(None, lines)                   # refused without a deck
        turbine = builtin_turbine()
        dofs = [f for f in NON_BLADE_DOFS if turbine.dofs.get(f)]
        model = TurbineModel(turbine, dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)
        return model, "NREL 5 MW onshore (built-in, rigid blades), tower top released from 0.5 m fore-aft"
    from ..wind.deck.checks import FLOATING_MODELLED, MODELLED, check_modules

    turbine = read_openfast(deck)
    sim = turbine.simulation
    if not structure_only and (sim.hydrodynamics_model or sim.mooring_model or sim.substructure_model):
        # an offshore deck without aerodynamics: the structure with the water, the sea and the mooring, or on its
        # SubDyn substructure
        from ..wind.offshore.floating import floating_structure
        from ..wind.structure.structural_control import structure_servodyn

        modelled = {k: v | FLOATING_MODELLED.get(k, set()) for k, v in MODELLED.items()}
        check_modules(turbine, modelled=modelled | {"CompServo": {0, 1}})
        stc = structure_servodyn(turbine, sim.total_time)   # ServoDyn: its StCs, or refused (no controller here)
        what = "bottom-fixed: SubDyn" if sim.substructure_model else "floating: HydroDyn, SeaState, mooring"
        what += "; ServoDyn's StCs" if stc is not None else ""
        moving = structure_lines(turbine, lines)           # MoorDyn's lines move by default (cli/mooring_lines.py)
        what += "; MoorDyn's lines in motion" if moving == "dynamic" else ""
        return (floating_structure(turbine, structural_controls=stc, mooring_lines=moving),
                f"{deck} ({what}; rotor parked)")
    structure_lines(None if structure_only else turbine, lines)
    check_modules(turbine, structure_only=structure_only)
    return TurbineModel(turbine), str(deck)


def _simulate(model, tmax, t_out, step, options, printer):
    """One call of mbsym.simulate; progress on stderr."""
    from ..simulate import METHODS, simulate

    kw = dict(options)
    if "method" in kw and METHODS[kw["method"]].kind == "fixed-step":
        kw["dt"] = step                 # an explicit fixed-step method: --dt (or the deck's DT) is its step
    if hasattr(model, "sea_tables"):    # a floating structure: its Dynamics, fed the deck's sea
        from .mooring_lines import structure_controller

        ctrl = structure_controller(model, kw.get("compile"))      # MoorDyn's moving lines beside it, or None
        return simulate(model.dynamics(), tmax, t_out=t_out, progress=printer, inputs=model.sea_tables(tmax),
                        controller=ctrl, **kw)
    return simulate(model, tmax, t_out=t_out, progress=printer, **kw)


def _series(result, channels):
    from ..wind.analysis.compare import TimeSeries

    units = dict(zip(channels.names, channels.units))
    names = tuple(result.output_names)
    return TimeSeries(np.asarray(result.t), names, tuple(units[n] for n in names), np.asarray(result.y))


def _method_label(stats) -> str:
    """The integration as the plot's legend says it: ``rk4, dt 0.01724 s`` or ``cvodes``."""
    dt = stats.get("dt")
    return f"{stats.get('method')}, dt {dt:.4g} s" if dt else str(stats.get("method"))


def _header(label, model, tmax, options) -> None:
    """What is about to run, printed before integrating."""
    how = (f"accuracy {options['accuracy']:g} (method, step and compilation chosen automatically)"
           if "accuracy" in options else f"method {options['method']}")
    print(f"mbsym simulate: {label}")
    print(f"DOFs: {', '.join(f for f, on in model.dofs.items() if on)}  ({model.eom.n_q} coordinates); "
          f"{tmax:g} s, {how}", flush=True)


def _summary(series, stats) -> None:
    compiled = ", compiled" if stats.get("compiled") else ""
    estimate = stats.get("error_estimate")
    est = f", error estimate {estimate:.1e}" if isinstance(estimate, float) else ""
    step = f" of {stats['dt']:.4g} s" if stats.get("dt") else ""
    print(f"method {stats.get('method')}{compiled}: {stats.get('steps')} steps{step}, integration "
          f"{1e3 * float(stats.get('integration_wall_s', 0)):.1f} ms, preparation "
          f"{1e3 * float(stats.get('prepare_wall_s', 0)):.1f} ms{est}, {series.time[-1]:.2f} s simulated\n")
    shown = [n for n in series.names if n.startswith("Q_") or n in ("RotSpeed", "TTDspFA", "TTDspSS", "PtfmPitch")]
    print(f"{'channel':<14} {'unit':<8} {'initial':>12} {'min':>12} {'max':>12} {'final':>12}")
    for n in shown:
        y = series.channel(n)
        unit = series.units[series.names.index(n)]
        print(f"{n:<14} {unit:<8} " + " ".join(number(v, "12.5g") for v in (y[0], y.min(), y.max(), y[-1])))


