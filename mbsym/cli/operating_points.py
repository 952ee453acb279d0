"""``mbsym operating-points``: steady operating points (the power curve) under the controller's settings.

Contract (kept for acceptance checks)::

    mbsym operating-points [DECK.fst] --wind 4:25:1 [--json] [--plot FILE.png] [--discon-input DISCON.IN]

``--wind`` is ``START:STOP:STEP`` (STOP included when on the grid) or a comma list [m/s]. No deck:
the built-in NREL 5 MW with ROSCO 2.10.6's NREL 5 MW settings (package data); a deck: its
ElastoDyn DOFs, its AeroDyn 15 rotor (mbsym's BEM surfaces) and the ROSCO ``DISCON.IN`` its
ServoDyn names (``--discon-input`` instead). Each point is trimmed on the composed model
(:mod:`mbsym.wind.operation.trim`): TSR target, rated speed and power, minimum pitch and
peak-shaving schedule on the estimated wind, as the controller settles.

Prints a table (one row per wind speed, OpenFAST channel names and units) and the timing;
``--json`` adds one JSON object on the last line: ``{"wind_speed", "RotSpeed" [rpm],
"BldPitch1" [deg], "GenPwr" [kW], "RtAeroFxh" [N], "TTDspFA" [m], "region", "success"}``; a floating
deck (HydroDyn and a mooring) adds the platform's mean offsets ``"PtfmSurge"`` [m], ``"PtfmHeave"`` [m],
``"PtfmPitch"`` [deg] and the fairlead tensions ``"FAIRTEN1"`` … [N] to the table, the JSON and the plot.
A point that cannot be trimmed is reported (``null`` in the JSON, its reason on stderr) and the
exit status is 1; bad input exits with status 2 and a one-line message. ``--plot`` is written
only when every point succeeded, atomically (a temporary file renamed into place).
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("operating-points", help="steady operating points over wind speed (power curve) under the "
                                                "deck's controller settings (default: built-in NREL 5 MW)",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst) with AeroDyn 15 and ServoDyn; default: "
                                           "built-in NREL 5 MW")
    p.add_argument("--wind", required=True, metavar="START:STOP:STEP",
                   help="hub-height wind speeds [m/s]: START:STOP:STEP (STOP included when on the grid) or a comma "
                        "list, e.g. 4:25:1 or 8,11.4,16")
    p.add_argument("--json", action="store_true", help="print the results as one JSON object on the last line")
    p.add_argument("--plot", metavar="FILE.png", help="write rotor speed, pitch, power, thrust, TTDspFA (floating: "
                                                           "surge, heave, pitch) vs wind speed")
    p.add_argument("--discon-input", metavar="DISCON.IN", help="ROSCO controller input file instead of the deck's "
                                                               "(ServoDyn DLL_InFile)")


def _check_plot_path(raw: str) -> Path:
    """The plot's destination, checked before any work (an OutputFileError-like ValueError otherwise)."""
    from ..exceptions import ParameterError

    if not raw.strip():
        raise ParameterError("--plot needs a file name; got an empty string")
    p = Path(raw).expanduser()
    if p.is_dir():
        raise ParameterError(f"--plot {raw}: is a directory; give a file name, e.g. {p / 'operating_points.png'}")
    if not p.suffix:
        p = p.with_suffix(".png")
    from matplotlib.figure import Figure

    kinds = Figure().canvas.get_supported_filetypes()
    if p.suffix.lstrip(".").lower() not in kinds:
        raise ParameterError(f"--plot {raw}: matplotlib cannot write '{p.suffix}' files; use one of "
                             f"{', '.join('.' + k for k in sorted(kinds))}")
    parent = p.resolve().parent
    if not parent.is_dir():
        raise ParameterError(f"--plot {raw}: the directory {parent} does not exist; create it first")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ParameterError(f"--plot {raw}: the directory {parent} is not writable; choose another place")
    if p.exists() and (not p.is_file() or not os.access(p, os.W_OK)):
        raise ParameterError(f"--plot {raw}: exists and is not a writable regular file; choose another name")
    return p


def _write_atomically(path: Path, write) -> None:
    """``write(tmp)`` into a temporary file next to ``path``, then rename it onto ``path``."""
    fd, name = tempfile.mkstemp(dir=path.resolve().parent, prefix=f".{path.name}.", suffix=path.suffix)
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    finally:
        if tmp.exists():
            tmp.unlink()


def run(args) -> int:
    """Run ``mbsym operating-points`` (see the module docstring); returns the exit status."""
    from ..exceptions import ParameterError
    from ..wind.analysis.operating_points import operating_points, parse_wind_speeds, turbine_and_control

    speeds = parse_wind_speeds(args.wind)
    plot = _check_plot_path(args.plot) if args.plot is not None else None
    if args.deck is not None and not Path(args.deck).is_file():
        raise ParameterError(f"deck not found: '{args.deck}'; give the main OpenFAST input file (.fst) or no deck "
                             "for the built-in NREL 5 MW")
    if args.discon_input is not None and not Path(args.discon_input).is_file():
        raise ParameterError(f"--discon-input '{args.discon_input}' not found; give a ROSCO DISCON.IN")
    t0 = time.perf_counter()
    model, control, label = turbine_and_control(args.deck, discon_in=args.discon_input, aero="rotor")
    model.dynamics()
    t_model = time.perf_counter() - t0
    print(f"mbsym operating-points: {label}")
    print(f"controller: {control!r} ({control.source})")
    for note in control.notes:
        print(f"note: {note}")
    sys.stdout.flush()
    ops = operating_points(model, speeds, control, label=label)
    print(ops.table())
    n = len(ops)
    print(f"time: model {t_model:.2f} s, trim problem {ops.build_seconds:.2f} s, {n} point{'s' if n > 1 else ''} "
          f"{ops.seconds:.3f} s ({1e3 * ops.seconds / n:.1f} ms per point)")
    status = 0
    if not ops.success:
        for p in ops.failures:
            print(f"mbsym operating-points: error: no operating point at {p.wind_speed:g} m/s: {p.message}",
                  file=sys.stderr)
        status = 1
    elif plot is not None:
        _write_atomically(plot, lambda tmp: ops.plot(tmp))
        print(f"plot: {plot}")
    if args.json:
        print(json.dumps(ops.to_dict(), allow_nan=False))
    return status
