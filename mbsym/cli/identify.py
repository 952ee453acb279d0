"""``mbsym identify``: fit named turbine parameters of an OpenFAST deck to a time series.

Contract (kept for acceptance checks)::

    mbsym identify DECK --data OPENFAST.csv --params KEY[,KEY...] [--channels CH[,CH...]] [--json]
                   [--initial KEY=V[,KEY=V...]] [--estimate-x0] [--method M] [--no-compile]
                   [--model auto|loads|operating|structure] [--aero rotor|blade] [--max-time S] [--quiet]

KEY: an ElastoDyn key (``TwrFADmp(1)``, ``FAStTunr(1)``, ``NacMass``, ``PtfmPIner`` ...; see
:mod:`mbsym.wind.structure.named_parameters`) or a descriptive parameter name, values in
the deck's units; the starting values are the deck's unless ``--initial`` gives others.

The model (``--model``, default ``auto``): a deck with AeroDyn whose record holds the rotor's aerodynamic
loads (``RtAeroFxh`` ... ``RtAeroMzh``, ``Azimuth``) is its structure driven by those **loads**, the pitch and
the generator torque (:class:`~mbsym.wind.operation.measured_loads.MeasuredLoadTurbine`: the aerodynamic
damping is in the recorded loads, so no aerodynamic model biases a structural estimate; rigid blades, no
platform, no tower or nacelle drag); otherwise a deck with AeroDyn (``CompAero = 2``) is an
**operating** turbine: its structure, its aerodynamics (``--aero``, default rotor-effective, with the
disk's moment against tilt and yaw rates, unless blade or yaw DOFs or a wind that differs over the rotor
need the blade elements: ``_fit_aero``) and its wind, driven by the
record's measured hub wind ``Wind1VelX``, collective pitch ``BldPitch1`` and generator torque
``GenTq`` (the controller and the actuators out of the loop: :class:`~mbsym.wind.operation.measured.
MeasuredInputTurbine`), started from the steady state at the record's first inputs (trim); the
rotor azimuth is not estimated. A deck without AeroDyn, or ``--model structure``, is the
ElastoDyn-equivalent structure alone (free decays: no aerodynamics, no controller; said on the
output). Default channels: the ``Q_``/``QD_`` channels of the model's DOFs found in the data
(``Q_GeAz`` left out: it wraps). For an operating turbine, the channels of the DOFs the parameters
act on (``TwrFADmp(1)``: ``Q_TFA1``, ``QD_TFA1``), else those of every DOF but the rotor (the rotor
speed runs open loop on the measured torque). Progress lines go to stdout before the results (``--quiet``: none; errors
stay one line on stderr). A fit that does
not converge exits with status 1 and advice (the results are still printed). ``--json`` prints on the last line
``{"parameters": {KEY: value}, "std": {KEY: value}, "initial": {KEY: value},
"eps_pct": {CHANNEL: value}, "iterations": n, "wall_s": t}`` with KEY exactly as passed.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

__all__ = ["add_parser", "run"]


_EPILOG = ("A deck with AeroDyn whose record has the rotor loads (RtAeroFxh ... RtAeroMzh, Azimuth) is fitted as its "
           "structure driven by those loads, pitch and generator torque (--model loads). Otherwise a deck with "
           "AeroDyn "
           "is fitted as the operating turbine: the deck's structure, aerodynamics and wind, driven "
           "by the record's measured hub wind (Wind1VelX), collective pitch (BldPitch1) and generator torque (GenTq), "
           "so the controller and actuators are out of the loop; it starts from the steady state at the record's "
           "first inputs (start the record where the turbine is steady, or --estimate-x0); the rotor azimuth is not "
           "estimated. Progress lines precede the results; a fit that does not converge exits with status 1 and "
           "advice. See docs/identification.md.")


def add_parser(sub) -> None:
    p = sub.add_parser("identify", help="identify named turbine parameters (ElastoDyn keys) from an OpenFAST CSV",
                       description=__doc__.split("\n\n")[0], epilog=_EPILOG)
    p.add_argument("deck", help="main OpenFAST input file (.fst)")
    p.add_argument("--data", required=True, metavar="OPENFAST.csv", help="measured or simulated time series (CSV)")
    p.add_argument("--params", required=True, metavar="KEY[,KEY...]",
                   help="parameters to identify: ElastoDyn keys (e.g. TwrFADmp(1),FAStTunr(1)) or names")
    p.add_argument("--channels", metavar="CH[,CH...]", help="fitted channels (default: Q_/QD_ of the model's DOFs; operating turbine: "
                   "those of the DOFs the parameters act on, e.g. Q_TFA1,QD_TFA1 for TwrFADmp(1))")
    p.add_argument("--initial", metavar="KEY=V[,KEY=V...]", help="starting values in the deck's units "
                   "(default: the deck's values)")
    p.add_argument("--estimate-x0", action="store_true", help="also estimate the initial state")
    p.add_argument("--method", default="gauss-newton", help="gauss-newton (default), sqpmethod or ipopt")
    p.add_argument("--no-compile", action="store_true", help="CasADi's virtual machine instead of compiled C")
    p.add_argument("--model", choices=("auto", "loads", "operating", "structure"), default="auto",
                   help="loads: the structure driven by the record's aerodynamic rotor loads (RtAeroFxh ... "
                        "RtAeroMzh, "
                        "turned by Azimuth), pitch and generator torque; operating: structure + the deck's "
                        "aerodynamics and wind, driven by the measured pitch (BldPitch1), generator torque (GenTq) "
                        "and hub wind (Wind1VelX); structure: the structure alone (free decays); auto (default): "
                        "loads when the deck has AeroDyn and the record the rotor loads, else operating when the "
                        "deck has AeroDyn")
    p.add_argument("--aero", choices=("rotor", "blade"), help="operating model's aerodynamics: rotor-effective or "
                   "blade elements (default: rotor-effective unless blade or yaw DOFs or a wind that differs over the "
                   "rotor need blade elements)")
    p.add_argument("--max-time", type=float, metavar="S", help="wall-time limit of the iteration [s]")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    p.add_argument("--json", action="store_true", help="print the result as one JSON object on the last line")


def _split(text: str | None, what: str) -> list[str]:
    """``a,b(1),c`` -> ["a", "b(1)", "c"] (commas inside parentheses do not split)."""
    if text is None:
        return []
    out, depth, cur = [], 0, ""
    for ch in text:
        depth += ch == "("
        depth -= ch == ")"
        if ch == "," and depth == 0:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    out.append(cur.strip())
    if any(not s for s in out):
        raise ValueError(f"{what} has an empty entry: {text!r} (separate entries by single commas)")
    return out


def _initial(text: str | None) -> dict[str, float]:
    out = {}
    for item in _split(text, "--initial"):
        key, sep, value = item.partition("=")
        if not sep:
            raise ValueError(f"--initial entries must be KEY=VALUE; got {item!r}")
        try:
            out[key.strip()] = float(value)
        except ValueError:
            raise ValueError(f"--initial {key.strip()}: {value!r} is not a number") from None
    return out


def default_channels(model, names, *, skip: tuple[str, ...] = ("Q_GeAz",)) -> list[str]:
    """``Q_<dof>`` and ``QD_<dof>`` of the model's coordinates present in ``names`` (not those in ``skip``)."""
    out = []
    for c in model.eom.coordinates:
        for prefix in ("Q", "QD"):
            ch = f"{prefix}_{c}"
            if ch in names and ch not in skip:
                out.append(ch)
    return out


def _log(args, text: str) -> None:
    if not args.quiet:
        print(f"mbsym identify: {text}", flush=True)


def _progress(args, t0: float):
    def report(event: dict) -> None:
        if event["stage"] == "built":
            _log(args, f"shooting functions ready ({event['substeps']} RK4 sub-step(s), "
                       f"{'compiled' if event['compiled'] else 'virtual machine'}; {time.perf_counter() - t0:.1f} s)")
        else:
            _log(args, f"iteration {event['iteration']}: cost {event['cost']:.4e}, gaps {event['gap']:.1e}, "
                       f"step {event['step']:.1e} ({time.perf_counter() - t0:.1f} s)")
    return report


def _operating(args, turbine, series, keys: list[str], t0: float):
    """(model, options for mb.identify, default channels) of the operating turbine driven by the measured inputs."""
    from ..wind.operation.deck import operating_deck
    from ..wind.operation.measured import PERIODS, MeasuredInputTurbine

    _log(args, "building the operating turbine (structure, aerodynamics, wind; measured pitch and torque as inputs)")
    deck = operating_deck(args.deck)
    aero = _fit_aero(args, deck) if args.aero is None else args.aero
    options = {"disk_moments": True} if aero == "rotor" else {}         # the disk's tilt/yaw damping
    if deck.individual_pitch_control:
        _log(args, f"the deck's controller pitches the blades individually; the record's blades stay within "
                   f"{_pitch_spread(series):.3g} deg of blade 1: fitted with one collective pitch (BldPitch1)")
        options["pitch"] = "collective"
    model = MeasuredInputTurbine(deck.model(aero=aero, **options))
    dyn = model.dynamics()
    if dyn.n_x > LARGE_FIT:
        _large_fit(args, deck, dyn.n_x)
    U = model.inputs_from(series)
    x0 = model.initial_state_from(series, U[0])
    wind = (f"wind {U[0, dyn.inputs.index('Wind1VelX')]:.3g} m/s" if "Wind1VelX" in dyn.inputs else
            ", ".join(f"{n} {U[0, dyn.inputs.index(n)]:.4g}" for n in model.wind_inputs))    # a field: WindTime
    _log(args, f"trimmed at the record's first inputs ({wind}): "
               + ", ".join(f"{k} {v:.4g}" for k, v in zip(dyn.states, x0)
                           if f"Q_{k}" in series.names or f"QD_{k[:-2]}" in series.names)
               + f" ({time.perf_counter() - t0:.1f} s)")
    channels = default_channels(turbine, series.names, skip=("Q_GeAz", "QD_GeAz"))
    own = _parameter_channels(model, keys, series.names)
    return model, {"inputs": U, "x0": x0}, own or channels, PERIODS


#: States beyond which a blade-element fit is refused unless asked for (--aero blade), its set-up being long (the
#: 234-state blade-element NREL 5 MW's interval Jacobian did not compile in 600 s, docs/identification.md).
LARGE_FIT = 200


def _large_fit(args, deck, n_states: int) -> None:
    """A blade-element fit of ``n_states`` states: refused when the rung was the default (its set-up takes tens of
    minutes, beyond ``--max-time``), said when the user asked for it (``--aero blade``)."""
    from ..exceptions import IdentificationOptionError

    flexible = {f for f, on in deck.turbine.dofs.items() if on} & {"FlapDOF1", "FlapDOF2", "EdgeDOF"}
    why = (f"the operating model has {n_states} states (the blade elements' wake and airfoil states per node; "
           f"{'flexible blades' if flexible else 'a wind that differs over the rotor'} need them): setting up its "
           "shooting functions takes tens of minutes, beyond --max-time (the stock NREL 5 MW deck's 1385 states did "
           "not compile in 10 min)")
    if args.aero == "blade":
        _log(args, why)
        return
    others = ("--aero rotor leaves the blades without aerodynamic loads (a biased fit)" if flexible else
              "with rigid blades, a record of AeroDyn's rotor loads (RtAeroFxh ... RtAeroMzh, Azimuth) is fitted in "
              "seconds (--model loads)")
    raise IdentificationOptionError(f"{why}. Pass --aero blade to fit it anyway; {others}; see "
                                    "docs/identification.md.")


def _fit_aero(args, deck) -> str:
    """The aerodynamic rung an identification fits by default: the rotor-effective one unless blade or yaw DOFs
    need the blade elements' loads or the wind differs over the rotor.

    A deck's simulations take blade elements also for AeroDyn's features that only disturb the blade inflow (the
    tower's potential flow and shadow, unsteady airfoils, sector averaging); with DBEMT and UA per node that is
    hundreds to thousands of states, whose shooting functions take longer to set up than an identification may.
    The rotor-effective rung takes those as their azimuth averages and steady states (docs/operation.md), driven by
    the record's hub wind, which is the rotor's wind only where the deck's wind is uniform over it.
    """
    aero = deck.default_aero()
    flags = {f for f, on in deck.turbine.dofs.items() if on}
    if aero == "rotor" or flags & {"FlapDOF1", "FlapDOF2", "EdgeDOF", "YawDOF"} or deck.wind_varies_over_rotor():
        return aero
    _log(args, "rotor-effective aerodynamics for the fit (the deck simulates with blade elements for AeroDyn's "
               "tower or unsteady airfoils; their per-node wake and airfoil states make a fit take far longer): the "
               "tower's disturbance as its azimuth average, unsteady airfoils at their steady state; --aero blade "
               "to fit the blade elements")
    return "rotor"


def _load_model(deck_path):
    """:class:`~mbsym.wind.operation.measured_loads.MeasuredLoadTurbine` of a deck (raises ModelDefinitionError)."""
    from ..wind.operation.deck import operating_deck
    from ..wind.operation.measured_loads import MeasuredLoadTurbine

    return MeasuredLoadTurbine(operating_deck(deck_path).model(aero="rotor", disk_moments=True, wind_given=True))


def _loads(args, series, keys: list[str], t0: float, model=None):
    """(model, options for mb.identify, default channels) of the structure driven by the recorded rotor loads."""
    model = _load_model(args.deck) if model is None else model
    _log(args, "the structure driven by the record's rotor loads (RtAeroFxh ... RtAeroMzh), pitch and generator "
               "torque: the aerodynamics are in the measured loads, no aerodynamic model is fitted")
    U = model.inputs_from(series)
    x0 = model.initial_state_from(series, U[0])
    _log(args, "at rest under the record's first loads: " + ", ".join(
        f"{k} {v:.4g}" for k, v in zip(model.dynamics().states, x0) if not k.startswith("GeAz"))
        + f" ({time.perf_counter() - t0:.1f} s)")
    own = _parameter_channels(model, keys, series.names)
    return model, {"inputs": U, "x0": x0}, own or default_channels(model.structure, series.names,
                                                                   skip=("Q_GeAz", "QD_GeAz"))


def _auto_kind(args, series, has_aero: bool):
    """``auto``: (kind, the load-driven model or None); loads when the deck has AeroDyn, the record the rotor
    loads, the deck no load they miss and no ``--aero`` asks for the aerodynamics."""
    from ..exceptions import ModelDefinitionError
    from ..wind.operation.measured_loads import rotor_loads_recorded

    if not has_aero:
        return "structure", None
    if args.aero is not None:
        return "operating", None
    missing = rotor_loads_recorded(series.names)
    if missing:
        _log(args, f"the record lacks the rotor-load channels {missing}: fitting through the deck's aerodynamics")
        return "operating", None
    try:
        model = _load_model(args.deck)
    except ModelDefinitionError as e:
        _log(args, f"rotor loads recorded, but {e}")
        return "operating", None
    return "loads", model


#: Largest difference of the blades' recorded pitch from blade 1 that one collective pitch may stand for [deg].
PITCH_SPREAD_DEG = 0.1


def _pitch_spread(series) -> float:
    """Largest |BldPitch<k> - BldPitch1| of a record [deg]; DataError when the blades are not recorded or pitch
    apart by more than :data:`PITCH_SPREAD_DEG` (the operating identification takes one measured pitch)."""
    import numpy as np

    from ..exceptions import DataError
    from ..wind.operation.measured import match_channel

    names = list(series.names)
    found = {n: match_channel(names, n) for n in ("BldPitch1", "BldPitch2", "BldPitch3")}
    missing = [n for n, f in found.items() if f is None]
    if missing:
        raise DataError(f"the deck's controller pitches the blades individually and the record has no {missing}: the "
                        "operating identification takes one measured pitch, so it needs every blade's to check they "
                        "agree. Record BldPitch1-3, or record AeroDyn's rotor loads (RtAeroFxh ... RtAeroMzh) and "
                        "fit the structure they drive (--model loads).")
    data = np.asarray(series.data, dtype=float)
    first = data[:, names.index(found["BldPitch1"])]
    spread = max(float(np.max(np.abs(data[:, names.index(found[n])] - first))) for n in ("BldPitch2", "BldPitch3"))
    if spread > PITCH_SPREAD_DEG:
        raise DataError(f"the record's blades pitch up to {spread:.3g} deg apart (individual pitch control): the "
                        f"operating identification takes one measured pitch (within {PITCH_SPREAD_DEG} deg). Record "
                        "AeroDyn's rotor loads (RtAeroFxh ... RtAeroMzh) and fit the structure they drive "
                        "(--model loads).")
    return spread


def _parameter_channels(model, keys: list[str], names) -> list[str]:
    """``Q_``/``QD_`` channels of the DOFs the parameters act on (e.g. ``TwrFADmp(1)``: TFA1), when every
    parameter names its DOFs; else []. The other DOFs' misfit (model-form differences, such as the missing
    rotor side force on the side-side mode) then does not bias the estimate."""
    from ..wind.structure.dof_tables import STATE_ORDER

    coords = []
    for key in keys:
        requires = getattr(model.resolve_parameter(key), "requires", ())
        if not requires:
            return []
        coords += [STATE_ORDER[f] for f in requires if f in STATE_ORDER]
    return [f"{pre}_{c}" for c in dict.fromkeys(coords) for pre in ("Q", "QD") if f"{pre}_{c}" in names]


def run(args: argparse.Namespace) -> int:
    import mbsym as mb

    from ..exceptions import ConvergenceWarning, DataError, OptionError
    from ..wind import read_openfast
    from ..wind.analysis.compare import WRAPPED, read_csv
    from ..wind.structure.turbine import TurbineModel

    t0 = time.perf_counter()
    keys = _split(args.params, "--params")
    initial = _initial(args.initial)
    if not Path(args.deck).is_file():
        raise FileNotFoundError(f"deck not found: {args.deck}")
    series = read_csv(args.data)
    turbine = read_openfast(args.deck)
    structure = TurbineModel(turbine)
    for key in keys:
        structure.resolve_parameter(key)            # unknown or absent keys fail before any heavy work
    has_aero = turbine.source_files.get("aerodyn") is not None
    kind, load_model = _auto_kind(args, series, has_aero) if args.model == "auto" else (args.model, None)
    if kind in ("operating", "loads") and not has_aero:
        raise OptionError(f"--model {kind}: {args.deck} has no AeroDyn input (CompAero = 2 and AeroFile); an "
                          "operating turbine needs its aerodynamics. Use --model structure for a free decay.")
    if args.aero is not None and kind != "operating":
        raise OptionError("--aero describes the operating turbine's aerodynamics; it needs --model operating.")
    if kind == "operating":
        model, options, default, periods = _operating(args, structure, series, keys, t0)
    elif kind == "loads":
        model, options, default = _loads(args, series, keys, t0, load_model)
        periods = WRAPPED
    else:
        if has_aero:
            _log(args, "--model structure: the deck's aerodynamics, controller and wind are NOT modelled (a free "
                       "decay of the structure alone)")
        model, options, periods = structure, {}, WRAPPED
        default = default_channels(structure, series.names)
    channels = _split(args.channels, "--channels") if args.channels else default
    if not channels:
        raise DataError(f"{args.data}: no Q_/QD_ channel of the model's DOFs {list(structure.eom.coordinates)}; "
                        "choose channels with --channels")
    periodic = {c: periods[c] for c in channels if c in periods}
    _log(args, f"fitting {', '.join(keys)} to {', '.join(channels)} ({len(series.time)} samples)")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)      # said below, with the exit status
        res = mb.identify(model, series, keys, channels=channels, initial=initial, periodic=periodic,
                          estimate_x0=bool(args.estimate_x0), method=args.method, compile=not args.no_compile,
                          progress=None if args.quiet else _progress(args, t0), max_time=args.max_time,
                          **options)
    out = res.to_json()
    out["wall_s"] = time.perf_counter() - t0           # the whole command: reading, building, identifying
    what = {"operating": "operating turbine, measured pitch/torque/wind as inputs", "structure": "structure alone",
            "loads": "structure driven by the measured rotor loads, pitch and torque"}[kind]
    print(f"{Path(args.deck).name} ({what}): {len(series.time)} samples of {', '.join(channels)}")
    print(res.summary())
    if args.json:
        print(json.dumps(out))
    if not res.success:
        print(f"mbsym identify: error: not converged ({res.message}); the estimates above are where the iteration "
              "stopped. Try starting values nearer the expected ones (--initial), fewer parameters or channels, "
              "or a larger --max-time; check that the model describes the data.", file=sys.stderr)
        return 1
    return 0
