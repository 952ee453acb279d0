"""``mbsym simulate``: free decays of OpenFAST decks (or the built-in NREL 5 MW).

Contract (kept for acceptance checks)::

    mbsym simulate [DECK.fst] [--tmax T] [--dt DT] [--out FILE.csv] [--plot FILE.png]
                   [--compare OPENFAST.csv] [--method M] [--rtol R] [--atol A]
                   [--list-methods] [--stats] [--compile]

No deck: the built-in NREL 5 MW onshore turbine (:func:`mbsym.wind.deck.nrel5mw`) with its
structural DOFs this template models, released from a tower-top displacement of
0.5 m fore-aft with the rotor at the deck's 10 rpm, yaw held by the NREL 5 MW
ServoDyn yaw spring and damper (ElastoDyn alone leaves the yaw free). ``--tmax``/``--dt`` default to the
deck's TMax and DT; output is sampled every ``--dt`` (or the deck's DT_Out).
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

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("simulate", help="simulate a free decay of an OpenFAST deck (default: built-in NREL 5 MW)",
                       description=_plain(__doc__.split("\n\n")[0]))
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst); default: built-in NREL 5 MW")
    p.add_argument("--tmax", type=float, help="simulated time [s] (default: the deck's TMax)")
    p.add_argument("--dt", type=float, help="time step and output spacing [s] (default: the deck's DT and DT_Out)")
    p.add_argument("--out", metavar="FILE.csv", help="write OpenFAST-named channels as CSV")
    p.add_argument("--plot", metavar="FILE.png", help="write a plot of the DOF channels (overlaid with --compare)")
    p.add_argument("--compare", metavar="OPENFAST.csv", help="OpenFAST CSV output to compare with (ε, R² per channel)")
    p.add_argument("--method", default="cvodes", help="integration method (see --list-methods; default cvodes)")
    p.add_argument("--rtol", type=float, default=1e-8, help="relative tolerance of adaptive methods (default 1e-8)")
    p.add_argument("--atol", type=float, default=1e-10, help="absolute tolerance of adaptive methods (default 1e-10)")
    p.add_argument("--list-methods", action="store_true", help="print the integration methods, one per line, and exit")
    p.add_argument("--stats", action="store_true", help="print the run statistics as one JSON object on the last line")
    p.add_argument("--compile", action="store_true", help="run the integration as generated C (gcc -O1, cached on disk)")
    add_structure_only(p)


def add_structure_only(p) -> None:
    """The ``--structure-only`` flag (simulate, linearize, campbell)."""
    p.add_argument("--structure-only", action="store_true",
                   help="run a deck that switches on modules mbsym does not model (CompAero, CompServo, CompHydro, "
                        "...) as the ElastoDyn structure alone, with a warning (default: refuse such decks)")


#: NREL 5 MW baseline ServoDyn yaw spring [N m/rad] and damper [N m s/rad] (YawSpr, YawDamp of the
#: NREL 5 MW ServoDyn input file, OpenFAST regression tests).
NREL5MW_YAW_SPRING, NREL5MW_YAW_DAMPING = 9.02832e9, 1.916e7


def builtin_turbine():
    """The built-in scene: NREL 5 MW onshore, tower top released from 0.5 m fore-aft."""
    from ..wind import nrel5mw

    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, tower_top_fa_displacement=0.5)
    return dataclasses.replace(t, initial_conditions=ic)


def run(args: argparse.Namespace) -> int:
    from ..simulate import METHODS

    if args.list_methods:
        print("\n".join(METHODS))
        return 0
    if args.method not in METHODS:
        raise ValueError(f"unknown --method {args.method!r}; choose one of {', '.join(METHODS)} (--list-methods)")
    ref, outputs = _check_files(args)        # fail before any expensive work
    model, label = _model(args.deck, structure_only=args.structure_only)
    outputs.add_inputs(_deck_inputs(model))
    sim = model.turbine.simulation
    tmax = args.tmax if args.tmax is not None else sim.total_time
    dt_out = args.dt if args.dt is not None else sim.output_time_step
    step = args.dt if args.dt is not None else sim.time_step
    if not (tmax > 0 and step > 0 and dt_out > 0):
        raise ValueError(f"--tmax and --dt must be positive; got tmax={tmax}, dt={step}")
    t_out = np.round(np.arange(0.0, tmax + 0.5 * dt_out, dt_out), 10)
    t_out = t_out[t_out <= tmax + 1e-9]
    t0 = time.perf_counter()
    channels = model.output_function()          # derives the equations and the output Function
    prepare = time.perf_counter() - t0
    result = _simulate(model, tmax, t_out, step, args, METHODS[args.method].kind == "fixed-step")
    series = _series(result, channels)
    stats = dict(result.statistics)
    stats["prepare_wall_s"] = float(stats.get("prepare_wall_s", 0.0)) + prepare
    _summary(label, model, series, stats)
    if ref is not None:
        _report_comparison(series, ref)
    _write_outputs(outputs, series, ref, label if args.deck is None else Path(args.deck).name)
    if args.stats:
        print(json.dumps({k: _jsonable(v) for k, v in stats.items()}))
    return 0


def _check_files(args):
    """Read --compare and check the --out/--plot destinations before simulating (:mod:`._files`)."""
    from ._files import Outputs

    outputs = Outputs([("--compare", args.compare), ("deck", args.deck)])
    if args.out is not None:
        outputs.add("--out", args.out)
    if args.plot is not None:
        outputs.add("--plot", args.plot, image=True)
    ref = None
    if args.compare:
        from ..wind.analysis.compare import read_csv

        ref = read_csv(args.compare)
    return ref, outputs


def _deck_inputs(model) -> list[tuple[str, str]]:
    """The deck's files (never overwritten by an output)."""
    files = getattr(model.turbine, "source_files", {}) or {}
    return [(f"deck's {name}", path) for name, path in files.items()]


def _write_outputs(outputs, series, ref, label: str) -> None:
    """Write --out and --plot to temporaries, then move both into place (all or nothing)."""
    from ..wind.analysis.compare import overlay_plot, write_csv

    with outputs:
        if "--out" in outputs._final:
            write_csv(outputs.temporary("--out"), series)
        if "--plot" in outputs._final:
            overlay_plot(outputs.temporary("--plot"), series, ref, title=label)
        written = outputs.commit()
    for path in written:
        extra = f" ({len(series.time)} rows, {len(series.names)} channels)" if path.suffix.lower() == ".csv" else ""
        print(f"wrote {path}{extra}")


def _model(deck, *, structure_only: bool = False):
    from ..wind import read_openfast
    from ..wind.structure.turbine import NON_BLADE_DOFS, TurbineModel

    if deck is None:
        turbine = builtin_turbine()
        dofs = [f for f in NON_BLADE_DOFS if turbine.dofs.get(f)]
        model = TurbineModel(turbine, dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)
        return model, "NREL 5 MW onshore (built-in, rigid blades), tower top released from 0.5 m fore-aft"
    from ..wind.deck.checks import check_modules

    turbine = read_openfast(deck)
    check_modules(turbine, structure_only=structure_only)
    return TurbineModel(turbine), str(deck)


def _simulate(model, tmax, t_out, step, args, fixed_step: bool):
    """One call; on a terminal a progress bar. Only fixed-step runs are cut into chunks for it
    (at multiples of the step, so the result is the same): adaptive methods would restart."""
    from ..simulate import simulate

    kw = dict(method=args.method, compile=args.compile)
    # each method gets only what it uses: the step for fixed-step methods, tolerances otherwise
    kw.update(dict(dt=step) if fixed_step else dict(rtol=args.rtol, atol=args.atol))
    if not sys.stdout.isatty():
        return simulate(model, tmax, t_out=t_out, **kw)
    if not fixed_step:
        print(f"[{'.' * 30}]    0.00 / {tmax:.2f} s", end="", flush=True)
        result = simulate(model, tmax, t_out=t_out, **kw)
        print(f"\r[{'#' * 30}] {tmax:7.2f} / {tmax:.2f} s")
        return result
    return _chunked(model, tmax, t_out, step, kw)


def _chunked(model, tmax, t_out, step, kw):
    from ..simulate import simulate

    n_steps = int(round(tmax / step))
    edges = np.unique(np.round(np.linspace(0, n_steps, 21)).astype(int)) * step
    edges[-1] = tmax
    x0, inputs = model.default_state(), model.default_inputs()
    parts, stats = [], None
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        grid = t_out[(t_out >= a - 1e-9) & (t_out <= b + 1e-9)] - a
        grid = np.unique(np.concatenate([[0.0], grid, [b - a]]))
        shifted = {k: (lambda s, f=v, a=a: f(s + a)) if callable(v) else v for k, v in inputs.items()}
        r = simulate(model, b - a, x0=x0, inputs=shifted, t_out=grid, **kw)
        parts.append((r.t + a, r))
        x0 = r.x[-1]
        stats = _merge(stats, r.statistics)
        done = int(30 * (i + 1) / (len(edges) - 1))
        print(f"\r[{'#' * done}{'.' * (30 - done)}] {b:7.2f} / {tmax:.2f} s", end="", flush=True)
    print()
    return _Joined(parts, t_out, stats)


class _Joined:
    """Chunked results on the requested output grid."""

    def __init__(self, parts, t_out, stats):
        t = np.concatenate([tp for tp, _ in parts])
        y = np.vstack([r.y for _, r in parts])
        t, idx = np.unique(np.round(t, 9), return_index=True)
        keep = np.isin(t, np.round(t_out, 9))
        self.t, self.y = t[keep], y[idx][keep]
        self.output_names = parts[0][1].output_names
        self.statistics = stats


def _merge(acc, stats):
    if acc is None:
        return dict(stats)
    out = dict(acc)
    for k, v in stats.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool) and k.endswith(("_s", "steps", "n_rhs", "n_jac")):
            out[k] = out.get(k, 0) + v
    return out


def _series(result, channels):
    from ..wind.analysis.compare import TimeSeries

    units = dict(zip(channels.names, channels.units))
    names = tuple(result.output_names)
    return TimeSeries(np.asarray(result.t), names, tuple(units[n] for n in names), np.asarray(result.y))


def _summary(label, model, series, stats) -> None:
    print(f"mbsym simulate: {label}")
    print(f"DOFs: {', '.join(f for f, on in model.dofs.items() if on)}  ({model.eom.n_q} coordinates)")
    print(f"method {stats.get('method')}: {stats.get('steps')} steps, integration "
          f"{1e3 * float(stats.get('integration_wall_s', 0)):.1f} ms, preparation "
          f"{1e3 * float(stats.get('prepare_wall_s', 0)):.1f} ms, {series.time[-1]:.2f} s simulated\n")
    shown = [n for n in series.names if n.startswith("Q_") or n in ("RotSpeed", "TTDspFA", "TTDspSS", "PtfmPitch")]
    print(f"{'channel':<14} {'unit':<8} {'initial':>12} {'min':>12} {'max':>12} {'final':>12}")
    for n in shown:
        y = series.channel(n)
        unit = series.units[series.names.index(n)]
        print(f"{n:<14} {unit:<8} {y[0]:12.5g} {y.min():12.5g} {y.max():12.5g} {y[-1]:12.5g}")


def _report_comparison(series, ref) -> None:
    """The ε/R² table, then what was not compared: channels, time ranges, non-finite samples."""
    from ..wind.analysis.compare import compare, coverage_notes, not_compared

    rows = compare(series, ref)
    _print_comparison(rows)
    missing = not_compared(series, ref)
    if missing:
        print(f"not compared (not produced by this model): {', '.join(missing)}")
    for note in coverage_notes(series, ref):
        print(f"note: {note}")
    excluded = [f"{r['channel']} ({r['n_excluded']})" for r in rows if r["n_excluded"]]
    if excluded:
        print(f"note: samples left out where a value is not finite (NaN/inf): {', '.join(excluded)}")


def _print_comparison(rows) -> None:
    print(f"\n{'channel':<14} {'ε [%]':>9} {'R²':>10} {'max |Δ|':>12}")
    for r in rows:
        eps = "const" if np.isnan(r["epsilon"]) else f"{100 * r['epsilon']:.4f}"
        r2 = "-" if np.isnan(r["r2"]) else f"{r['r2']:.6f}"
        print(f"{r['channel']:<14} {eps:>9} {r2:>10} {r['max_abs_diff']:12.4g}")


def _jsonable(v):
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    if isinstance(v, (str, int, float, bool)) or v is None:
        return v
    return str(v)
