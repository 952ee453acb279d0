"""``mbsym campbell``: Campbell diagram of an OpenFAST deck (fixed-frame modes vs rotor speed).

Contract (kept for acceptance checks)::

    mbsym campbell DECK.fst --rpm LIST [--json] [--plot FILE.png] [--azimuths N]
                   [--method {elastodyn-fd,exact}]

LIST is comma-separated rotor speeds [rpm], strictly increasing (no repeats), each with a
subsonic blade tip. For each speed the turbine of the deck (its
DOFs; a prescribed azimuth when GenDOF is off) is linearized at OpenFAST's operating point
of an undeflected deck (tower and platform displacements zero, the blades at the deck's tip
deflections, rotor spinning at that speed; :mod:`mbsym.wind.analysis.campbell_diagram`) at N
azimuths, transformed to multi-blade coordinates and averaged; the modes are labelled by
their kinetic energy ("1st flap collective", "1st edge backward whirl", "1st tower
fore-aft" …). ``--method elastodyn-fd`` (default, as ``mbsym linearize`` and OpenFAST)
takes A by ElastoDyn's central differences, ``--method exact`` by automatic
differentiation. ``--json`` prints one JSON object
``{"rpm": [...], "modes": [{"label", "freq_hz", "damping_ratio"}, ...]}`` (null where a
mode is not oscillatory at a speed) and nothing else on stdout; ``--plot`` writes frequency
vs rotor speed with the 1P, 3P and 6P lines (one colour per mode family; collective solid,
forward whirl dashed, backward whirl dotted) to FILE (``.png`` is added to a name without
suffix; the name written is printed).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
import time

import numpy as np

from . import plain as _plain

__all__ = ["add_parser", "run", "parse_rpm_list"]


def add_parser(sub) -> None:
    p = sub.add_parser("campbell", help="Campbell diagram of an OpenFAST deck (multi-blade coordinates)",
                       description=_plain(__doc__.split("\n\n")[0]))
    p.add_argument("deck", help="main OpenFAST input file (.fst)")
    p.add_argument("--rpm", required=True, metavar="LIST", help="comma-separated rotor speeds [rpm], e.g. 0,3,6,9,12")
    p.add_argument("--json", action="store_true", help="print the diagram as one JSON object (and nothing else)")
    p.add_argument("--plot", metavar="FILE.png", help="write the Campbell diagram with the 1P, 3P, 6P lines")
    p.add_argument("--azimuths", type=int, default=12, metavar="N",
                   help="azimuths per revolution averaged in multi-blade coordinates (default 12)")
    p.add_argument("--method", choices=("elastodyn-fd", "exact"), default="elastodyn-fd",
                   help="A by ElastoDyn's central differences (default, as OpenFAST) or exact derivatives")
    from .simulate import add_structure_only

    add_structure_only(p)


def parse_rpm_list(text: str, tip_radius: float | None = None) -> list[float]:
    """``"0, 3,6"`` -> ``[0.0, 3.0, 6.0]``.

    Raises
    ------
    OptionError
        An entry that is not a finite number >= 0, speeds not strictly increasing (unsorted or
        repeated), or (with ``tip_radius`` [m]) a supersonic blade tip.
    """
    from ..exceptions import OptionError
    from ..wind.deck.checks import check_rotor_speed

    out = []
    for item in str(text).split(","):
        item = item.strip()
        try:
            value = float(item)
        except ValueError:
            raise OptionError(f"--rpm must be comma-separated numbers, e.g. 0,3,6; got {item!r} in {text!r}") from None
        if not np.isfinite(value) or value < 0:
            raise OptionError(f"--rpm values must be finite and >= 0 [rpm]; got {item!r}")
        if tip_radius is not None:
            check_rotor_speed(value, tip_radius, "--rpm")
        out.append(value)
    if any(b <= a for a, b in zip(out, out[1:])):
        fixed = ",".join(f"{v:g}" for v in sorted(set(out)))
        raise OptionError(f"--rpm speeds must be strictly increasing without repeats; got {text!r}. Use e.g. {fixed}")
    return out


def run(args: argparse.Namespace) -> int:
    from ..wind import read_openfast
    from ..wind.analysis.campbell_diagram import campbell, campbell_model

    from ..exceptions import OptionError
    from ..wind.deck.checks import check_modules
    from ._files import Outputs

    parse_rpm_list(args.rpm)                    # format and order, before any work
    if args.azimuths < 1:
        raise OptionError(f"--azimuths must be a positive integer; got {args.azimuths}")
    outputs = Outputs([("deck", args.deck)])
    if args.plot is not None:
        outputs.add("--plot", args.plot, image=True)
    t0 = time.perf_counter()
    turbine = read_openfast(args.deck)
    check_modules(turbine, structure_only=args.structure_only)
    outputs.add_inputs((f"deck's {k}", v) for k, v in turbine.source_files.items())
    rpm = parse_rpm_list(args.rpm, turbine.tip_radius)
    model = campbell_model(turbine)
    diagram = campbell(model, rpm, n_azimuth=args.azimuths, method=args.method)
    wall = time.perf_counter() - t0
    log = sys.stderr if args.json else sys.stdout
    with outputs:
        if args.plot is not None:
            diagram.plot(outputs.temporary("--plot"), title=f"Campbell diagram: {Path(args.deck).name}")
        written = outputs.commit()
    if args.json:
        print(json.dumps(diagram.to_dict()))
    else:
        _table(args.deck, model, diagram, wall, args.method)
    for path in written:
        print(f"wrote {path}", file=log)
    return 0


def _table(deck, model, diagram, wall: float, method: str) -> None:
    dofs = ", ".join(f for f, on in model.dofs.items() if on)
    print(f"mbsym campbell: {deck}")
    print(f"DOFs: {dofs} ({model.eom.n_q} coordinates); fixed-frame modes (multi-blade coordinates), "
          f"method {method}, {wall:.2f} s\n")
    head = "".join(f"{r:>9.2f}" for r in diagram.rpm)
    from ._run import number

    for title, attr, fmt in (("frequency [Hz] at rotor speed [rpm]", "freq_hz", "9.4f"),
                             ("damping ratio [-] at rotor speed [rpm]", "damping_ratio", "9.5f")):
        print(title)
        print(f"{'mode':<28}{head}")
        for m in diagram.modes:
            vals = getattr(m, attr)
            print(f"{m.label:<28}" + "".join(number(v, fmt) if np.isfinite(v) else f"{'-':>9}" for v in vals))
        print()
