"""``--mooring-lines`` of ``mbsym simulate``: how a floating deck's MoorDyn lines move in the run.

* ``dynamic`` (the default for a deck with MoorDyn, ``CompMooring = 3``): MoorDyn's lumped-mass lines in motion
  beside the model at the deck's ``dtM``, relaxed before t = 0 as MoorDyn relaxes them
  (:mod:`mbsym.wind.offshore.lines_in_loop`): the deck as OpenFAST runs it;
* ``quasi-static``: the lines' shapes follow the platform at once, with MoorDyn's drag and inertia on them: several
  times faster (the floating NREL/IEA decks: docs/offshore.md §3c); trims and linear models always use them.

The same holds for a floating deck without AeroDyn (``fl_decay_a``: the structure with the water and the mooring,
:func:`structure_lines`, :func:`structure_controller`). The flag is refused where it would do nothing: the built-in
onshore turbine, a deck without MoorDyn, ``--structure-only``.
"""

from __future__ import annotations

import argparse

#: The choices of ``--mooring-lines``.
CHOICES = ("dynamic", "quasi-static")


def add_argument(p: argparse.ArgumentParser) -> None:
    """Add ``--mooring-lines`` to ``p``."""
    p.add_argument("--mooring-lines", choices=CHOICES,
                   help="a floating deck's MoorDyn lines: dynamic (default: MoorDyn's lumped masses in motion at its "
                        "dtM, relaxed before t = 0 as MoorDyn relaxes them, as OpenFAST runs the deck) or "
                        "quasi-static (their shapes follow the platform at once: several times faster; trims and "
                        "linear models use them)")


def _moordyn(deck) -> bool:
    return int(getattr(deck.turbine.simulation, "mooring_model", 0) or 0) == 3


def with_mooring_lines(deck, lines: str | None):
    """``deck`` (an :class:`~mbsym.wind.operation.deck.OperatingDeck`, None for the built-in turbine) with its
    MoorDyn lines as ``lines`` says (None: the default above).

    Raises
    ------
    OptionError
        ``lines`` given for the built-in turbine or a deck without MoorDyn.
    """
    from ..exceptions import OptionError
    from ..wind.operation.deck import replace

    if deck is None:
        if lines is not None:
            raise OptionError(f"--mooring-lines {lines}: the built-in NREL 5 MW stands on land (no mooring); drop "
                              "the flag, or give a floating deck with MoorDyn.")
        return None
    if lines is None:
        return replace(deck, mooring_lines="dynamic") if _moordyn(deck) else deck
    if not _moordyn(deck):
        raise OptionError(f"--mooring-lines {lines}: {deck.path} has no MoorDyn mooring (CompMooring = 3); drop the "
                          "flag.")
    return replace(deck, mooring_lines=lines)


def header_line(model) -> str:
    """What the run's header says about moving lines ("" without them)."""
    moving = getattr(model.platform, "moving_lines", None) if model.platform is not None else None
    if moving is None:
        return ""
    rel, segs = moving.relaxation, sorted({ln.segments for ln in moving.lines})
    return (f"mooring: MoorDyn's {moving.n_lines} lines in motion ({'/'.join(map(str, segs))} segments, RK2 at dtM "
            f"{moving.time_step:g} s), relaxed before t = 0 as MoorDyn relaxes them (dtIC {rel.interval:g} s, TmaxIC "
            f"{rel.t_max:g} s, threshIC {rel.threshold:g}); --mooring-lines quasi-static runs faster")


def structure_lines(turbine, lines: str | None) -> str:
    """How the structure-only run of ``turbine`` (a deck read by :func:`~mbsym.wind.read_openfast`, None for the
    built-in turbine or ``--structure-only``) moves its MoorDyn lines: ``lines``, or by default ``"dynamic"`` for a
    floating deck with MoorDyn.

    Raises
    ------
    OptionError
        ``lines`` given where there are no MoorDyn lines to move.
    """
    from ..exceptions import OptionError

    moordyn = turbine is not None and int(getattr(turbine.simulation, "mooring_model", 0) or 0) == 3 \
        and not int(getattr(turbine.simulation, "substructure_model", 0) or 0)
    if lines is None:
        return "dynamic" if moordyn else "quasi-static"
    if not moordyn:
        raise OptionError(f"--mooring-lines {lines}: this run has no MoorDyn lines to move (the built-in turbine, "
                          "--structure-only, or a deck without MoorDyn, CompMooring = 3); drop the flag.")
    return lines


def structure_controller(model, compile: bool | None):
    """The moving lines of a floating structure (:class:`~mbsym.wind.offshore.floating.FloatingStructure`) as the
    discrete module of its simulation, at the deck's ``DT``, relaxed at its initial position; None without them."""
    moving = getattr(model.platform, "moving_lines", None)
    if moving is None:
        return None
    from ..wind.offshore.lines_in_loop import with_moving_lines
    from ..wind.offshore.operating import platform_dofs

    dyn, x0 = model.dynamics(), model.initial_state()
    coords = model.eom.coordinates
    index, fixed, _ = platform_dofs(coords, model.turbine)
    dofs = [coords[i] if i is not None else None for i in index]
    q0 = [x0[dyn.states.index(n)] if n is not None else fixed[k] for k, n in enumerate(dofs)]
    ctrl, _ = with_moving_lines(model.platform, dofs, fixed, q0, controller=None,
                                dt=float(model.turbine.simulation.time_step), compile=compile is not False)
    return ctrl
