"""``mbsym sweep``: run a turbine over deck keys and wind specifications, one table row per combination.

Contract (kept for acceptance checks)::

    mbsym sweep [DECK] --set KEY=V1,V2,... [--set ...] [--wind SPEC [--wind SPEC ...]] [--tmax T]
                [--controller baseline|discon|none] [--executor serial|processes:N|dask:N|dask:ADDRESS]
                --out TABLE.csv

* Columns: the swept keys exactly as passed (e.g. ``TwrFADmp(1)``), ``wind``, then
  ``<channel>_mean``, ``<channel>_std``, ``<channel>_max``, ``<channel>_min`` for the output
  channels (``--channels`` to choose; ``--del CH`` adds ``CH_del_m<m>``), and ``error``.
* KEY: an ElastoDyn key of the named parameters in the deck's units (``TwrFADmp(1)`` in %,
  ``FAStTunr(1)``, ``NacMass`` [kg]), an initial condition (``TTDspFA`` [m], ``RotSpeed`` [rpm],
  ...) or a parameter name of the model (SI).
* Without ``--wind``: structural free decays of the deck (the model of ``mbsym simulate DECK``;
  fixed-step RK4 at the deck's DT, ``wind`` = ``none``). With ``--wind``: the operating turbine
  under ``--controller`` (default as ``mbsym simulate --wind``). No deck: the built-in NREL 5 MW.
* A case that fails (a value below its physical bound, a diverging run) fills its ``error`` cell;
  the others run. Bad keys, values, specs or options: one line on stderr, exit 2, no file written.
  The CSV is written atomically once every case has run; a progress bar shows on a terminal.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

from . import plain as _plain

__all__ = ["add_parser", "run", "parse_set"]


def add_parser(sub) -> None:
    p = sub.add_parser("sweep", help="run a turbine over deck keys and wind specifications: one CSV row per case",
                       description=_plain(__doc__.split("\n\n")[0]))
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst); default: built-in NREL 5 MW")
    p.add_argument("--set", action="append", default=[], metavar="KEY=V1,V2,...",
                   help="a swept key and its values in the deck's units, e.g. TwrFADmp(1)=1,2,4 (repeat for a grid)")
    p.add_argument("--wind", action="append", metavar="SPEC",
                   help="a wind (repeatable): steady:U, step:U0:U1:T, kaimal:U:TI:SEED, ramp:..., eog:... or a file; "
                        "runs the operating turbine (default: structural free decays)")
    p.add_argument("--tmax", type=float, help="simulated time [s] (default: the deck's TMax; built in 10 s free "
                                              "decays, 60 s in wind)")
    p.add_argument("--dt", type=float, help="free decays: RK4 step [s] (default the deck's DT); wind: output "
                                            "spacing [s] (default the deck's DT_Out, built in 0.05)")
    p.add_argument("--controller", choices=("baseline", "discon", "none"),
                   help="with --wind: baseline (ours, compiled into the loop), discon (a DISCON library), none "
                        "(held commands); default: the deck's DISCON library, baseline without a deck")
    p.add_argument("--discon", metavar="LIB.so", help="DISCON library (default: the deck's ServoDyn DLL_FileName)")
    p.add_argument("--discon-input", metavar="DISCON.IN", help="controller input file (default: the deck's)")
    p.add_argument("--executor", default="serial", metavar="EXECUTOR",
                   help="serial (default), processes:N, dask:N (local cluster on 127.0.0.1, needs mbsym[dask]), "
                        "dask:ADDRESS (a running scheduler), threads:N (free decays)")
    p.add_argument("--channels", metavar="A,B,...", help="channels to summarize (default: every output channel)")
    p.add_argument("--del", dest="del_channels", action="append", default=[], metavar="CHANNEL",
                   help="damage-equivalent load of a channel (repeatable or comma-separated; needs mbsym[loads]): "
                        "column CHANNEL_del_m<M>, 1 Hz equivalent cycles")
    p.add_argument("--wohler", default="10", metavar="M[,M]",
                   help="Wöhler exponent(s) of --del (default 10; 4 for steel towers)")
    p.add_argument("--compile", action=argparse.BooleanOptionalAction, default=None,
                   help="run the loops as generated C (default: when it pays off, as mbsym simulate)")
    p.add_argument("--out", metavar="TABLE.csv", help="write the table as CSV (written once every case has run)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction, default=None,
                   help="progress bar on stderr (default: on a terminal)")


def parse_set(items) -> dict[str, list[float]]:
    """``["KEY=V1,V2", ...]`` -> ``{KEY: [V1, V2]}`` (keys kept exactly as written).

    Raises
    ------
    OptionError
        A malformed item, a value that is not a finite number, a key given twice.
    """
    from ..exceptions import OptionError

    out: dict[str, list[float]] = {}
    for item in items:
        key, eq, text = str(item).partition("=")
        key = key.strip()
        if not eq or not key or not text.strip():
            raise OptionError(f"--set {item!r}: expected KEY=V1,V2,... such as TwrFADmp(1)=1,2,4")
        if key in out:
            raise OptionError(f"--set: the key {key!r} is given twice; list all its values in one --set {key}=...")
        values = []
        for field in text.split(","):
            try:
                v = float(field)
            except ValueError:
                raise OptionError(f"--set {key}: {field.strip()!r} is not a number; expected KEY=V1,V2,... with "
                                  "numbers in the deck's units") from None
            if not math.isfinite(v):
                raise OptionError(f"--set {key}: {field.strip()!r} is not a finite number")
            values.append(v)
        out[key] = values
    return out


def _names(text: str | None, flag: str) -> list[str] | None:
    from ..exceptions import OptionError

    if text is None:
        return None
    names = [n.strip() for n in text.split(",")]
    if not all(names):
        raise OptionError(f"{flag} {text!r}: expected comma-separated channel names such as TTDspFA,TwrBsMyt")
    return names


def _wohler(text: str) -> tuple[float, ...]:
    from ..exceptions import OptionError

    try:
        ms = tuple(float(v) for v in str(text).split(","))
    except ValueError:
        raise OptionError(f"--wohler {text!r}: expected positive numbers such as 4 or 4,10") from None
    if not all(math.isfinite(m) and m > 0 for m in ms):
        raise OptionError(f"--wohler {text!r}: expected positive numbers such as 4 or 4,10")
    return ms


def run(args: argparse.Namespace) -> int:
    from ..exceptions import OptionError
    from ..sweep import parse_executor
    from ._files import Outputs

    values = parse_set(args.set)
    dels = [n for item in args.del_channels for n in _names(item, "--del")]
    wohler = _wohler(args.wohler)
    parse_executor(args.executor)
    if args.wind is None and any(v is not None for v in (args.controller, args.discon, args.discon_input)):
        raise OptionError("--controller, --discon and --discon-input apply to runs in wind: add --wind SPEC")
    for flag, value in (("--tmax", args.tmax), ("--dt", args.dt)):
        if value is not None and not (math.isfinite(value) and value > 0):
            raise OptionError(f"{flag} must be a positive finite time [s]; got {value:g}")
    outputs = Outputs([("deck", args.deck)] + [("--wind", w) for w in args.wind or ()])
    if args.out is not None:
        outputs.add("--out", args.out)
    n_cases = math.prod(len(v) for v in values.values()) * len(args.wind or [None])
    what = f"in {len(args.wind)} wind(s)" if args.wind else "free decays"
    print(f"mbsym sweep: {args.deck or 'NREL 5 MW (built-in)'}, {n_cases} case(s) ({what}; "
          f"{', '.join(values) or 'no swept keys'}) on {args.executor}", flush=True)
    from ..wind.analysis.sweep import sweep_turbine

    t0 = time.perf_counter()
    try:
        res = sweep_turbine(args.deck, values, wind=args.wind, tmax=args.tmax, dt=args.dt, controller=args.controller,
                            discon=args.discon, discon_input=args.discon_input,
                            channels=_names(args.channels, "--channels"), del_channels=dels, wohler=wohler,
                            executor=args.executor, progress=args.progress, compile=args.compile)
    except KeyboardInterrupt:
        print("mbsym sweep: interrupted; nothing written", file=sys.stderr)
        return 130
    table = res.table
    failed = table.failed
    for i in failed:
        row = table.row(i)
        case = ", ".join(f"{k}={row[k]}" for k in list(values) + ["wind"])
        print(f"mbsym sweep: case {i + 1} ({case}) failed: {row['error']}", file=sys.stderr)
    print(f"{len(table)} case(s), {len(failed)} failed, {time.perf_counter() - t0:.1f} s "
          f"(executor {res.executor}; preparation {res.prepare_wall_s:.1f} s)")
    if args.out is not None:
        with outputs:
            table.to_csv(outputs.temporary("--out"))
            outputs.commit()
        print(f"wrote {outputs.path('--out')} ({len(table)} rows, {len(table.columns)} columns)")
    else:
        print(table)
    return 0
