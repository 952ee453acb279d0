"""Command-line interface: ``mbsym --version``, ``mbsym demo``, ``mbsym simulate``, ``mbsym linearize``, ``mbsym campbell``,
``mbsym identify``, ``mbsym operating-points``, ``mbsym sweep``, ``mbsym export-discon``.

Every sub-command exits with status 0 on success, and with status 2 and a
one-line message on bad input (any :class:`~mbsym.exceptions.MbsymError`).
Warnings are printed on stderr as one line each, ``mbsym <command>: warning: <message>``.
"""

from __future__ import annotations

import argparse
import re
import sys
import warnings
from typing import Sequence

__all__ = ["main", "build_parser", "plain"]


def plain(text: str) -> str:
    """Help text without reStructuredText markup: ``:func:`x``` and ````x```` become ``x``."""
    text = re.sub(r":[a-z]+:`~?([^`]+)`", r"\1", text)
    return text.replace("``", "")


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
    from .identify import add_parser as add_identify
    from .linearize import add_parser as add_linearize
    from .simulate import add_parser as add_simulate
    from .sweep import add_parser as add_sweep

    add_simulate(sub)
    add_linearize(sub)
    add_campbell(sub)
    add_identify(sub)
    from .operating_points import add_parser as add_operating_points

    add_operating_points(sub)
    add_sweep(sub)
    from .export_discon import add_parser as add_export_discon

    add_export_discon(sub)
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
        with warnings.catch_warnings():
            warnings.simplefilter("default")
            warnings.showwarning = _one_line_warning(args.command)
            return _dispatch(args)
    except BrokenPipeError:         # e.g. `mbsym simulate --stats | head`: not an error of ours
        sys.stderr.close()
        return 0
    except (MbsymError, ValueError, OSError) as exc:
        message = " ".join(str(exc).split())
        print(f"mbsym {args.command}: error: {message}", file=sys.stderr)
        return 2


def _one_line_warning(command: str):
    def show(message, category, filename, lineno, file=None, line=None):  # noqa: ARG001 - warnings hook
        print(f"mbsym {command}: warning: {' '.join(str(message).split())}", file=sys.stderr)
    return show


def _dispatch(args) -> int:
    if args.command == "demo":
        from ..demo import run_demo
        from ..exceptions import OptionError

        if not args.tmax > 0:
            raise OptionError(f"--tmax must be positive; got {args.tmax}")
        run_demo(tmax=args.tmax)
        return 0
    if args.command == "simulate":
        from .simulate import run
    elif args.command == "linearize":
        from .linearize import run
    elif args.command == "identify":
        from .identify import run
    elif args.command == "operating-points":
        from .operating_points import run
    elif args.command == "sweep":
        from .sweep import run
    elif args.command == "export-discon":
        from .export_discon import run
    else:
        from .campbell import run
    return run(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
