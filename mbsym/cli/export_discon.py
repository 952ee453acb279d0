"""``mbsym export-discon``: a controller as a self-contained Bladed-style DISCON library.

Contract (kept for acceptance checks)::

    mbsym export-discon [DECK] --controller baseline|nmpc [--estimator ekf|mhe] --out DIR
                        [--discon-input DISCON.IN] [--sample-time S] [--name NAME]

writes the library ``DIR/NAME.so`` and its input file ``DIR/NAME.IN`` (with the C sources in
``DIR/src``) and prints one JSON object on its last line: ``{"library": "<path>.so", "input":
"<path>", "controller": "baseline", "sample_time_s": ...}``. Putting the two paths into a ServoDyn
file (``DLL_FileName``, ``DLL_InFile``; ``PCMode`` and ``VSContrl`` 5, ``DLL_DT`` a divisor of the
sample time, ``Ptch_Cntrl`` 1 with IPC) is all OpenFAST needs.

The deck configures the controller exactly as ``mbsym simulate DECK --controller baseline`` does:
its ServoDyn ``DLL_InFile`` (ROSCO's ``DISCON.IN``; ``--discon-input`` instead) and its controller
sample time (``DLL_DT``, else ServoDyn's ``DT``, else the glue ``DT``; ``--sample-time`` instead).
Without a deck: ROSCO 2.10.6's NREL 5 MW settings at 0.01 s (the built-in turbine of ``mbsym
simulate``). ``--controller nmpc`` (and ``--estimator``) is part of the contract but not yet
available: it is refused with exit status 2.
"""

from __future__ import annotations

import json
import math

__all__ = ["add_parser", "run"]

CONTROLLERS = ("baseline", "nmpc")


def add_parser(sub) -> None:
    p = sub.add_parser("export-discon", help="compile a controller into a DISCON library (.so) and its input file "
                                             "for OpenFAST/ServoDyn", description=__doc__.split("\n\n")[0])
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst) whose ServoDyn DISCON.IN and controller "
                                           "sample time configure the controller; default: built-in NREL 5 MW")
    p.add_argument("--controller", required=True, choices=CONTROLLERS,
                   help="baseline (our ROSCO-scheme controller); nmpc: not yet available")
    p.add_argument("--estimator", choices=("ekf", "mhe"), help="the NMPC's estimator (nmpc only; not yet available)")
    p.add_argument("--out", required=True, metavar="DIR", help="directory for the library, its input file and src/")
    p.add_argument("--discon-input", metavar="DISCON.IN", help="ROSCO controller input file instead of the deck's "
                                                               "(ServoDyn DLL_InFile)")
    p.add_argument("--sample-time", type=float, metavar="S",
                   help="controller sample time [s] (default: the deck's DLL_DT/DT; built-in 0.01)")
    p.add_argument("--name", default="baseline_discon", help="file name stem (default baseline_discon)")


def run(args) -> int:
    """Export and print the JSON line (see the module docstring)."""
    from ..exceptions import ControllerError, OptionError

    if args.controller == "nmpc":
        raise ControllerError("export-discon --controller nmpc is not yet available (issue 21: the NMPC with its "
                              "estimator as generated C); export --controller baseline for now.")
    if args.estimator is not None:
        raise OptionError(f"--estimator {args.estimator} belongs to --controller nmpc; the baseline controller has "
                          "its own wind-speed estimator (set by WE_Mode in its DISCON.IN). Drop --estimator.")
    if args.sample_time is not None and not (math.isfinite(args.sample_time) and args.sample_time > 0):
        raise OptionError(f"--sample-time must be a positive finite time [s]; got {args.sample_time:g}.")
    from ..wind.control.baseline import BaselineController
    from ..wind.control.discon_export import export_discon
    from ..wind.operation.deck import builtin_deck, operating_deck

    deck = operating_deck(args.deck) if args.deck is not None else builtin_deck()
    settings = deck.baseline_settings(discon_in=args.discon_input, dt=args.sample_time)
    controller = BaselineController(settings)
    source = settings.source or "built-in NREL 5 MW"
    print(f"mbsym export-discon: baseline controller from {source}, sample time {controller.dt:g} s, "
          f"{len(controller.state_names)} states, measurements {', '.join(controller.measurements)}")
    out = export_discon(controller, args.out, name=args.name)
    print(f"wrote {out['library']}\nwrote {out['input']}\nServoDyn: DLL_FileName \"{out['library']}\", "
          f"DLL_InFile \"{out['input']}\", DLL_DT a divisor of {controller.dt:g} s"
          + (", Ptch_Cntrl 1" if controller.ipc else ""))
    print(json.dumps(out))
    return 0
