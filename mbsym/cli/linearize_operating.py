"""``mbsym linearize [DECK] --wind U``: the operating turbine's linear model about its trim at U m/s.

Contract (kept for acceptance checks)::

    mbsym linearize [DECK.fst] --wind U [--json] [--keep-azimuth] [--discon-input DISCON.IN]
                    [--inflow {dynamic,frozen,quasi-steady}]

The turbine the deck describes (ElastoDyn DOFs, AeroDyn 15 rotor as rotor-effective performance
surfaces, pitch and torque actuators, dynamic inflow; no deck: the built-in NREL 5 MW) is trimmed at
the hub-height wind U [m/s] under its controller's steady settings (:mod:`mbsym.wind.operation.trim`,
as ``mbsym operating-points``) and linearized there
(:func:`mbsym.wind.analysis.trim_linear.linearize_point`), open loop: the inputs are ``Wind1VelX``
[m/s], ``BlPitchCom`` [rad], ``GenTqCom`` [N m]. Everything is in SI units (outputs converted from
their channel units: ``RotSpeed`` rad/s, ``BldPitch1`` rad, ``GenPwr`` W …). The free generator
azimuth is left out (``--keep-azimuth`` keeps it); a model that depends on it (flexible blades under
gravity) is refused without ``--keep-azimuth``. ``--inflow`` chooses the wake of the linear model
(:mod:`mbsym.wind.analysis.inflow_choice`): ``dynamic`` (default: the rotor-averaged DBEMT states
``DBEMT_w``, ``DBEMT_v``), ``frozen`` (those states removed, the induction held at its trim value:
compare with OpenFAST's linearization with ``DBEMT_Mod = -1``) or ``quasi-steady`` (the induction in
equilibrium with the inflow). The rotor is rotor-effective: thrust along the shaft, no side force,
so the tower side-side mode has no aerodynamic damping.

``--json`` prints one JSON object on the last line: ``states``, ``inputs``, ``outputs`` (names),
``A``, ``B``, ``C``, ``D`` (lists of rows), ``modes`` (per mode ``freq_hz``, ``damping_ratio``,
``dominant_dof`` (the state group with the largest participation factor), ``label``,
``rigid_body``, ``participation`` by state group), ``units`` (``states``, ``inputs``,
``outputs``, lists in the order of the names), ``wind_speed`` [m/s], ``region``,
``operating_point`` (``x``, ``u``, ``y`` by name, SI), ``removed_states`` (with ``frozen`` the held
induction states) and ``inflow``.
"""

from __future__ import annotations

import json

import numpy as np

__all__ = ["run_operating", "operating_report"]


def operating_report(lin, point) -> dict:
    """The ``--json`` object of an operating linear model (module docstring)."""
    from ..wind.analysis.trim_linear import mode_label, numbered_labels, whirl_labels

    modes = lin.modes()
    freqs = [m.freq_hz for m in modes]
    labels = numbered_labels(whirl_labels([mode_label(m) for m in modes], freqs), freqs)
    op = lin.operating_point
    return {"wind_speed": float(point.wind_speed), "region": point.region,
            "states": list(lin.states), "inputs": list(lin.inputs), "outputs": list(lin.outputs),
            "A": lin.A.tolist(), "B": lin.B.tolist(), "C": lin.Cy.tolist(), "D": lin.Dy.tolist(),
            "modes": [m.as_dict() | {"label": label, "rigid_body": bool(m.rigid_body),
                                     "participation": m.participation} for m, label in zip(modes, labels)],
            "units": {"states": [lin.units.get(s, "") for s in lin.states], "inputs": list(lin.input_units),
                      "outputs": list(lin.output_units), "freq_hz": "Hz", "damping_ratio": "-"},
            "operating_point": {"x": dict(zip(lin.states, np.asarray(op["x"], dtype=float).tolist())),
                                "u": dict(zip(lin.inputs, np.asarray(op["u"], dtype=float).tolist())),
                                "y": dict(zip(lin.outputs, np.asarray(op["y"], dtype=float).tolist()))},
            "removed_states": dict(op.get("removed_states", {})), "inflow": op.get("inflow", "dynamic")}


def run_operating(args) -> int:
    """Run ``mbsym linearize --wind U`` (module docstring); returns the exit status."""
    from ..exceptions import OptionError, SolverError
    from ..wind.analysis.inflow_choice import check_inflow
    from ..wind.analysis.operating_points import operating_points, parse_wind_speeds, turbine_and_control

    inflow = getattr(args, "inflow", None)
    inflow = check_inflow("dynamic" if inflow is None else inflow)
    speeds = parse_wind_speeds(args.wind)
    if len(speeds) != 1:
        raise OptionError(f"--wind {args.wind}: linearize takes one wind speed U [m/s] (e.g. --wind 14); got "
                          f"{len(speeds)}. Run it once per speed, or use `mbsym operating-points --wind ...`.")
    clash = [flag for flag, on in (("--rpm", args.rpm is not None), ("--deflected", args.deflected),
                                   ("--method", args.method is not None), ("--structure-only", args.structure_only))
             if on]
    if clash:
        raise OptionError(f"{', '.join(clash)} apply to the structural linearization without --wind; with --wind "
                          "the rotor speed, pitch and deflections come from the trim and derivatives are exact.")
    model, control, label = turbine_and_control(args.deck, discon_in=args.discon_input, aero="rotor")
    ops = operating_points(model, speeds, control, label=label)
    point = ops[0]
    if not point.success:
        raise SolverError(f"no operating point at {point.wind_speed:g} m/s: {point.message}")
    lin = ops.linearize(keep_azimuth=args.keep_azimuth, inflow=inflow)[0]
    report = operating_report(lin, point)
    if args.json:
        print(json.dumps(report, allow_nan=False))
        return 0
    print(f"mbsym linearize: {label} at {point.wind_speed:g} m/s (region {point.region}), controller {control!r}, "
          f"inflow {inflow}")
    print(f"\n{'mode':>4} {'f [Hz]':>10} {'zeta [-]':>10}  {'dominant':<13} label")
    from ._run import number

    for i, m in enumerate(report["modes"], 1):
        print(f"{i:>4} {m['freq_hz']:10.5f} {number(m['damping_ratio'], '10.5f')}  {m['dominant_dof']:<13} {m['label']}")
    print(f"\n{lin!r}")
    return 0
