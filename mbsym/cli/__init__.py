"""Command-line interface: ``mbsym --version``, ``mbsym demo``, ``mbsym simulate``, ``mbsym linearize``, ``mbsym campbell``,
``mbsym operating-points``.

Every sub-command exits with status 0 on success, and with status 2 and a
one-line message on bad input (any :class:`~mbsym.exceptions.MbsymError`).
"""

from __future__ import annotations

import argparse
import sys
from typing import Sequence

__all__ = ["main", "build_parser"]


class _Parser(argparse.ArgumentParser):
    """argparse with the one-line error contract: ``mbsym <command>: error: <message>``, exit 2."""

    def error(self, message: str):  # noqa: D102 - argparse hook
        print(f"{self.prog}: error: {' '.join(message.split())} (see {self.prog} --help)", file=sys.stderr)
        raise SystemExit(2)


class _Version(argparse.Action):
    """``--version``: reads the installed version only when asked (importlib.metadata costs start-up time)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from .. import __version__

        print(f"mbsym {__version__}")
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``mbsym`` command."""
    parser = _Parser(
        prog="mbsym",
        description="Multibody systems to CasADi equations of motion (Kane's method).",
    )
    parser.add_argument("--version", action=_Version, help="show the version and exit")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    demo = sub.add_parser("demo", help="derive, check and simulate the double pendulum of the quick start")
    demo.add_argument("--tmax", type=float, default=5.0, help="simulated time [s] (default 5)")
    from .campbell import add_parser as add_campbell
    from .linearize import add_parser as add_linearize
    from .simulate import add_parser as add_simulate

    add_simulate(sub)
    add_linearize(sub)
    add_campbell(sub)
    from .operating_points import add_parser as add_operating_points

    add_operating_points(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``mbsym`` console script."""
    from ..exceptions import MbsymError

    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:       # --help/--version (0) or a usage error already printed (2)
        return int(exc.code or 0)
    if args.command is None:
        parser.print_help()
        return 0
    try:
        if args.command == "demo":
            from ..demo import run_demo

            if not args.tmax > 0:
                raise ValueError(f"--tmax must be positive; got {args.tmax}")
            run_demo(tmax=args.tmax)
        elif args.command == "simulate":
            from .simulate import run

            return run(args)
        elif args.command == "linearize":
            from .linearize import run as run_linearize

            return run_linearize(args)
        elif args.command == "campbell":
            from .campbell import run as run_campbell

            return run_campbell(args)
        elif args.command == "operating-points":
            from .operating_points import run as run_operating_points

            return run_operating_points(args)
    except BrokenPipeError:         # e.g. `mbsym simulate --stats | head`: not an error of ours
        sys.stderr.close()
        return 0
    except (MbsymError, ValueError, OSError) as exc:
        message = " ".join(str(exc).split())
        print(f"mbsym {args.command}: error: {message}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
