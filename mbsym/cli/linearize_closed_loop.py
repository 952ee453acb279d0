"""``mbsym linearize [DECK] --wind 4:25:1 --closed-loop``: the turbine with its baseline controller, linearized.

Contract (kept for acceptance checks)::

    mbsym linearize [DECK.fst] --wind SPEEDS --closed-loop [--json] [--plot FILE.png] [--bode FILE.png]
                    [--discon-input DISCON.IN]

At each wind speed (``START:STOP:STEP``, STOP included when on the grid, a comma list or one number) the
turbine the deck describes (rotor-effective aerodynamics; no deck: the built-in NREL 5 MW) is trimmed under
the steady laws of our baseline controller (settings from the deck's ROSCO ``DISCON.IN``, or
``--discon-input``; the built-in turbine: ROSCO 2.10.6's NREL 5 MW), and the plant and the controller are
linearized there and connected (:mod:`mbsym.wind.analysis.closed_loop`): a discrete-time closed loop at the
controller's sample time. The text output is a table: per wind speed the gain and phase margins of the pitch
loop (broken at ``BlPitchCom``) and of the torque loop (broken at ``GenTqCom``), closed-loop stability and the
least-damped closed-loop pole.

``--json`` prints one JSON object on the last line of stdout (layout kept; docs/operating_points.md):

* ``wind_speed`` (list, m/s), ``sample_time`` (s), ``region``, ``success``, ``message`` (lists per speed);
* per loop ``<loop>`` in ``pitch``, ``torque``: ``<loop>_active`` (the loop's transfer function is not zero
  there), ``<loop>_gain_margin_db``, ``<loop>_phase_margin_deg``, ``<loop>_phase_crossover_hz``,
  ``<loop>_gain_crossover_hz`` (lists per speed; ``null`` for an infinite margin — no crossover below the
  Nyquist frequency —, for an inactive loop and for a failed point);
* ``stable``, ``spectral_radius`` (largest |z| of the closed loop; < 1 is stable);
* ``closed_loop_poles``: per speed a list of poles (one per complex pair), each ``{"freq_hz",
  "damping_ratio"`` (of the continuous equivalent s = ln(z)/dt), ``"z": [re, im]`` (the discrete
  eigenvalue), ``"dominant_state", "label"}``, sorted by frequency; ``deadbeat_poles``: how many
  eigenvalues are at z = 0 (not listed);
* ``units``.

``--plot FILE.png`` writes margins and closed-loop poles over wind speed; ``--bode FILE.png`` (one wind speed)
the Bode plot of both loops, the phase wrapped into (−360°, 0°] (:mod:`mbsym.linear.frequency`: the continuous
phase of the sampled loops falls to −810° at the Nyquist frequency). A speed without a trim or
without a controller fixed point is reported (``success`` false, ``message``) and the others go on;
the exit status is then 1.
"""

from __future__ import annotations

import json
import sys

__all__ = ["run_closed_loop"]


def _turbine_and_controller(deck_path, discon_in):
    """``(model, BaselineController, label)`` of a deck (rotor-effective aerodynamics with the disk's moment, as the
    open-loop linear models: :func:`~mbsym.wind.analysis.operating_points.turbine_and_control`) or of the built-in
    turbine."""
    from ..exceptions import ControllerError
    from ..wind.control import BaselineController
    from ..wind.operation.deck import builtin_deck, operating_deck

    if deck_path is None:
        deck = builtin_deck()
        return deck.model(disk_moments=True), BaselineController(_collective(deck.baseline_settings(
            discon_in=discon_in))), deck.label
    deck = operating_deck(deck_path)
    if discon_in is None and deck.discon_in is None:
        raise ControllerError(f"{deck_path}: the deck names no controller input file (ServoDyn DLL_InFile); the "
                              "closed loop needs the controller's settings (a ROSCO DISCON.IN): pass --discon-input.")
    controller = BaselineController(_collective(deck.baseline_settings(discon_in=discon_in)))
    return deck.model(aero="rotor", disk_moments=True, wind_given=True), controller, deck.label


def _collective(settings):
    """``settings`` without individual pitch control, said on stderr: IPC acts on the blade-root moments' 1P, which
    the rotor-effective model of the loops has not, and adds nothing to the collective pitch (its inverse Coleman
    transform has zero mean over the blades), so the loops about a steady point are the same without it."""
    import dataclasses

    if settings.ipc_mode == 0:
        return settings
    print(f"mbsym linearize --closed-loop: the controller's individual pitch control (IPC_ControlMode "
          f"{settings.ipc_mode}) is left out: it acts on the blade-root moments' 1P, which the rotor-effective model "
          "has not, and adds nothing to the collective pitch of these loops", file=sys.stderr)
    return dataclasses.replace(settings, ipc_mode=0)


def run_closed_loop(args) -> int:
    """Run ``mbsym linearize --wind SPEEDS --closed-loop`` (module docstring); returns the exit status."""
    from ..exceptions import OptionError
    from ..wind.analysis.operating_points import parse_wind_speeds
    from ._files import Outputs

    speeds = parse_wind_speeds(args.wind)
    clash = [flag for flag, on in (("--rpm", args.rpm is not None), ("--deflected", args.deflected),
                                   ("--method", args.method is not None), ("--structure-only", args.structure_only),
                                   ("--keep-azimuth", args.keep_azimuth)) if on]
    if clash:
        raise OptionError(f"{', '.join(clash)} do not apply to --closed-loop (the azimuth is always left out; the "
                          "operating point is the trim).")
    outputs = Outputs([("deck", args.deck)] if args.deck else [])
    if args.plot is not None:
        outputs.add("--plot", args.plot, image=True)
    bode = getattr(args, "bode", None)
    if bode is not None:
        if len(speeds) != 1:
            raise OptionError(f"--bode plots the loops at one operating point; --wind {args.wind} gives {len(speeds)} "
                              "wind speeds. Give one (e.g. --wind 16).")
        outputs.add("--bode", bode, image=True)
    from ..wind.analysis.closed_loop import closed_loop_sweep          # after the checks: scipy takes seconds

    model, controller, label = _turbine_and_controller(args.deck, args.discon_input)
    sweep = closed_loop_sweep(model, speeds, controller)
    log = sys.stderr if args.json else sys.stdout
    with outputs:
        if args.plot is not None:
            sweep.plot(outputs.temporary("--plot"), title=f"Closed loop with the baseline controller: {label} "
                                                           f"(dt = {controller.dt:g} s)")
        if bode is not None and sweep.models[0] is not None:
            sweep.models[0].bode_plot(outputs.temporary("--bode"),
                                      title=f"Loops of {label} at {speeds[0]:g} m/s (region {sweep.models[0].region}), "
                                            f"baseline controller, dt = {controller.dt:g} s")
        written = outputs.commit()
    if args.json:
        for path in written:
            print(f"wrote {path}", file=log)
        print(json.dumps(sweep.to_dict(), allow_nan=False))
        return 0 if sweep.success else 1
    print(f"mbsym linearize --closed-loop: {label}, {controller!r}")
    print("margins at the actuator commands (loop broken at BlPitchCom / GenTqCom, the other closed); "
          "'-' inactive loop, inf no crossover\n")
    print(sweep.table())
    for path in written:
        print(f"wrote {path}", file=log)
    return 0 if sweep.success else 1
