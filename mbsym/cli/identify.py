"""``mbsym identify``: fit named turbine parameters of an OpenFAST deck to a time series.

Contract (kept for acceptance checks)::

    mbsym identify DECK --data OPENFAST.csv --params KEY[,KEY...] [--channels CH[,CH...]] [--json]
                   [--initial KEY=V[,KEY=V...]] [--estimate-x0] [--method M] [--no-compile]

KEY: an ElastoDyn key (``TwrFADmp(1)``, ``FAStTunr(1)``, ``NacMass``, ``PtfmPIner`` ...; see
:mod:`mbsym.wind.structure.named_parameters`) or a descriptive parameter name, values in
the deck's units. The model is the deck's ElastoDyn-equivalent turbine (its DOFs and
initial conditions); the starting values are the deck's unless ``--initial`` gives others.
Default channels: the ``Q_``/``QD_`` channels of the model's DOFs found in the data
(``Q_GeAz`` left out: it wraps). ``--json`` prints on the last line
``{"parameters": {KEY: value}, "std": {KEY: value}, "initial": {KEY: value},
"eps_pct": {CHANNEL: value}, "iterations": n, "wall_s": t}`` with KEY exactly as passed.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("identify", help="identify named turbine parameters (ElastoDyn keys) from an OpenFAST CSV",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("deck", help="main OpenFAST input file (.fst)")
    p.add_argument("--data", required=True, metavar="OPENFAST.csv", help="measured or simulated time series (CSV)")
    p.add_argument("--params", required=True, metavar="KEY[,KEY...]",
                   help="parameters to identify: ElastoDyn keys (e.g. TwrFADmp(1),FAStTunr(1)) or names")
    p.add_argument("--channels", metavar="CH[,CH...]", help="fitted channels (default: Q_/QD_ of the model's DOFs)")
    p.add_argument("--initial", metavar="KEY=V[,KEY=V...]", help="starting values in the deck's units "
                   "(default: the deck's values)")
    p.add_argument("--estimate-x0", action="store_true", help="also estimate the initial state")
    p.add_argument("--method", default="gauss-newton", help="gauss-newton (default), sqpmethod or ipopt")
    p.add_argument("--no-compile", action="store_true", help="CasADi's virtual machine instead of compiled C")
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


def default_channels(model, names) -> list[str]:
    """``Q_<dof>`` and ``QD_<dof>`` of the model's coordinates present in ``names`` (not ``Q_GeAz``: it wraps)."""
    out = []
    for c in model.eom.coordinates:
        for prefix in ("Q", "QD"):
            ch = f"{prefix}_{c}"
            if ch in names and ch != "Q_GeAz":
                out.append(ch)
    return out


def run(args: argparse.Namespace) -> int:
    import mbsym as mb

    from ..exceptions import DataError
    from ..wind import read_openfast
    from ..wind.analysis.compare import WRAPPED, read_csv
    from ..wind.structure.turbine import TurbineModel

    t0 = time.perf_counter()
    keys = _split(args.params, "--params")
    initial = _initial(args.initial)
    if not Path(args.deck).is_file():
        raise FileNotFoundError(f"deck not found: {args.deck}")
    series = read_csv(args.data)
    model = TurbineModel(read_openfast(args.deck))
    for key in keys:
        model.resolve_parameter(key)            # unknown or absent keys fail before any heavy work
    channels = _split(args.channels, "--channels") if args.channels else default_channels(model, series.names)
    if not channels:
        raise DataError(f"{args.data}: no Q_/QD_ channel of the model's DOFs {list(model.eom.coordinates)}; "
                        "choose channels with --channels")
    periodic = {c: WRAPPED[c] for c in channels if c in WRAPPED}
    res = mb.identify(model, series, keys, channels=channels, initial=initial, periodic=periodic,
                      estimate_x0=bool(args.estimate_x0), method=args.method, compile=not args.no_compile)
    out = res.to_json()
    out["wall_s"] = time.perf_counter() - t0           # the whole command: reading, building, identifying
    print(f"{Path(args.deck).name}: {len(series.time)} samples of {', '.join(channels)}")
    print(res.summary())
    if not res.success:
        print(f"warning: {res.message}")
    if args.json:
        print(json.dumps(out))
    return 0
