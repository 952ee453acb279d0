"""``mbsym linearize``: linear models and modes of an OpenFAST deck, as OpenFAST linearizes it.

Contract (kept for acceptance checks)::

    mbsym linearize [DECK.fst] [--rpm R] [--json] [--deflected] [--method {exact,elastodyn-fd}]
                    [--structure-only]
    mbsym linearize [DECK.fst] --wind U [--json] [--keep-azimuth] [--discon-input DISCON.IN]
                    [--inflow {dynamic,frozen,quasi-steady}]
    mbsym linearize [DECK.fst] --wind SPEEDS --closed-loop [--json] [--plot FILE.png] [--bode FILE.png]
                    [--discon-input DISCON.IN]

With ``--wind`` the operating turbine (aerodynamics, actuators, inflow) is linearized about its
trim at U m/s: see :mod:`mbsym.cli.linearize_operating` for that output; with ``--closed-loop``
also our baseline controller about each trim, connected (margins, closed-loop poles):
:mod:`mbsym.cli.linearize_closed_loop`. Without ``--wind``, the structure as below.

The operating point is the deck's RotSpeed (``--rpm`` replaces it), Azimuth, NacYaw and BlPitch
with every tower, platform and blade displacement zero, as OpenFAST's linearization of its
undeflected ``_lin0`` decks and as ``mbsym.linearize(TurbineModel(read_openfast(deck)))`` (the
turbine's ``linearization_state()``); ``--deflected`` keeps the deck's initial displacements
(OpenFAST's linearization of the deck itself at t = 0). Neither is generally an equilibrium, and
like OpenFAST the first-order model is the Jacobian of the nonlinear rhs there. No deck: the
built-in NREL 5 MW with its modelled DOFs and the NREL 5 MW yaw spring and damper.

The default method, of ``mbsym.linearize`` on a turbine too, is ``elastodyn-fd``: A by central
differences of the rhs with ElastoDyn's own steps (:func:`mbsym.linear.elastodyn_steps`), which
reproduces OpenFAST's frequencies including its finite-step error (0.8 % on a floating
platform's pitch frequency, docs/elastodyn_notes.md §8.3). ``--method exact`` uses automatic
differentiation. M, C, K are exact residual Jacobians at the operating point's own acceleration.
Rotor speeds whose blade tip would exceed the speed of sound are refused
(:data:`mbsym.wind.deck.checks.MAX_TIP_SPEED`).

The text output lists the modes, then the states with their units, A, M, C and K. ``--json``
prints one object: ``states``, ``A``, ``modes`` (``freq_hz``, ``damping_ratio``,
``dominant_dof`` (largest shape entry), ``rigid_body``, ``label`` (assigned one to one by kinetic
energy, :func:`mode_labels`: "1st tower fore-aft" vs "2nd tower fore-aft"); rigid-body modes
with ``freq_hz`` 0), ``M``, ``C``, ``K``,
and ``rpm``, ``method``, ``operating_point`` (``q``, ``qd``, ``u`` by name, SI units) and
``units`` (of the states, of M, C, K rows/columns and of the frequencies).
"""

from __future__ import annotations

import argparse
import dataclasses
import json

import numpy as np

from . import plain as _plain

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("linearize", help="linearize an OpenFAST deck at its undeflected initial state; print modes",
                       description=_plain(__doc__.split("\n\n")[0]))
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst); default: built-in NREL 5 MW")
    p.add_argument("--rpm", type=float, help="rotor speed [rpm] (default: the deck's RotSpeed)")
    p.add_argument("--deflected", action="store_true",
                   help="keep the deck's initial tower, platform and blade displacements (default: all zero, "
                        "as OpenFAST's _lin0 decks)")
    p.add_argument("--json", action="store_true",
                   help="print states, A, modes, M, C, K, rpm, operating point and units as one JSON object")
    p.add_argument("--method", choices=("exact", "elastodyn-fd"), default=None,
                   help="ElastoDyn's central differences (default, as mbsym.linearize of a turbine: reproduces "
                        "OpenFAST, including its finite-step error) or exact derivatives")
    from .simulate import add_structure_only

    add_structure_only(p)
    p.add_argument("--wind", metavar="U", help="hub-height wind speed [m/s]: linearize the operating turbine "
                                              "(aerodynamics, actuators, inflow) about its trim there, in SI units; "
                                              "with --closed-loop several: START:STOP:STEP or a comma list")
    p.add_argument("--keep-azimuth", action="store_true",
                   help="with --wind: keep the free generator azimuth GeAz as a state (default: left out, so "
                        "dcgain works)")
    p.add_argument("--inflow", metavar="{dynamic,frozen,quasi-steady}",
                   help="with --wind U: the wake (induction) of the linear model: dynamic (default, the DBEMT "
                        "states), frozen (induction held at the trim, as OpenFAST's DBEMT_Mod = -1) or "
                        "quasi-steady (induction in equilibrium with the inflow)")
    p.add_argument("--discon-input", metavar="DISCON.IN",
                   help="with --wind: ROSCO controller input file instead of the deck's (ServoDyn DLL_InFile)")
    p.add_argument("--closed-loop", action="store_true",
                   help="with --wind SPEEDS (e.g. 4:25:1): connect our baseline controller, linearized about each "
                        "trim; print pitch and torque loop margins, closed-loop poles and damping")
    p.add_argument("--plot", metavar="FILE.png", help="with --closed-loop: write margins and closed-loop poles over "
                                                      "wind speed")
    p.add_argument("--bode", metavar="FILE.png", help="with --closed-loop at one wind speed: write the Bode plot of "
                                                      "the pitch and torque loops (phase wrapped to (-360, 0] deg)")


def undeflected(turbine, rpm: float | None = None, *, zero_displacements: bool = True):
    """The deck's turbine with zero tower, platform and blade displacements (and ``rpm`` if given).

    Raises
    ------
    OptionError
        ``rpm`` negative, not finite, or with a supersonic blade tip
        (:func:`mbsym.wind.deck.checks.check_rotor_speed`).
    """
    from ..wind.deck.checks import check_rotor_speed

    ic = turbine.initial_conditions
    changes = {}
    if zero_displacements:
        changes = dict(tower_top_fa_displacement=0.0, tower_top_ss_displacement=0.0, platform_surge=0.0,
                       platform_sway=0.0, platform_heave=0.0, platform_roll=0.0, platform_pitch=0.0, platform_yaw=0.0,
                       blade_oop_tip_deflection=0.0, blade_ip_tip_deflection=0.0, teeter_angle=0.0)
    if rpm is not None:
        changes["rotor_speed"] = check_rotor_speed(rpm, turbine.tip_radius) * np.pi / 30.0
    return dataclasses.replace(turbine, initial_conditions=dataclasses.replace(ic, **changes))


def _model(deck, rpm, *, zero_displacements: bool = False, structure_only: bool = False):
    from ..wind import nrel5mw, read_openfast
    from ..wind.deck.checks import check_modules
    from ..wind.structure.turbine import NON_BLADE_DOFS, TurbineModel
    from .simulate import NREL5MW_YAW_DAMPING, NREL5MW_YAW_SPRING

    if deck is None:
        turbine = undeflected(nrel5mw(), rpm)
        dofs = [f for f in NON_BLADE_DOFS if turbine.dofs.get(f)]
        model = TurbineModel(turbine, dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)
        return model, "NREL 5 MW onshore (built-in)"
    turbine = read_openfast(deck)
    check_modules(turbine, structure_only=structure_only)
    return TurbineModel(undeflected(turbine, rpm, zero_displacements=zero_displacements)), str(deck)


def linear_report(model, method: str | None = None, *, deflected: bool = False) -> dict:
    """The ``--json`` object of a TurbineModel at its linearization state, or with ``deflected`` at its initial
    state (see the module docstring)."""
    from ..linear import linearize

    q0 = qd0 = None
    if deflected:
        x = model.initial_state()
        q0, qd0 = x[:model.eom.n_q], x[model.eom.n_q:]
    lin = linearize(model, q0, qd0, qdd0="rhs", method=method)
    op = lin.operating_point
    units = state_units(model)
    n = len(lin.coordinates)
    modes = lin.modes()
    labels = mode_labels(lin.M, modes, lin.coordinates)
    return {"states": list(lin.states), "A": lin.A.tolist(),
            "modes": [m.as_dict() | {"rigid_body": bool(m.rigid_body), "label": lab} for m, lab in zip(modes, labels)],
            "M": lin.M.tolist(), "C": lin.C.tolist(), "K": lin.K.tolist(),
            "rpm": float(model.turbine.initial_conditions.rotor_speed * 30.0 / np.pi), "method": lin.method,
            "operating_point": {"q": dict(zip(lin.coordinates, op["q"].tolist())),
                                "qd": dict(zip(lin.coordinates, op["qd"].tolist())),
                                "u": dict(zip(lin.inputs, op["u"].tolist()))},
            "units": {"states": units, "coordinates": units[:n], "freq_hz": "Hz", "damping_ratio": "-", "rpm": "rpm",
                      "M": "kg, kg m or kg m^2 (row i, column j: force unit of q_i / acceleration unit of q_j)",
                      "C": "force unit of q_i / speed unit of q_j", "K": "force unit of q_i / unit of q_j",
                      "A": "d(state_i rate)/d(state_j), SI"}}


def mode_labels(M: np.ndarray, modes, coordinates) -> list[str]:
    """A label per mode ("1st tower fore-aft", "2nd tower fore-aft", …), assigned one to one.

    Each oscillatory mode's kinetic energy is split over the coordinates, coordinate ``i``
    carrying ``|Re(conj(v_i) (M v)_i)|``; an optimal one-to-one assignment of modes to
    coordinates (the generator azimuth excluded: it is the rotor's rigid-body rotation) names
    each mode, so the 2nd tower mode is not called after TFA1 although TFA1 dominates its
    shape. Rigid-body modes are "rigid body (<dominant DOF>)".
    """
    from scipy.optimize import linear_sum_assignment

    from ..wind.analysis.campbell_diagram import DOF_LABELS
    from ..wind.structure.dofs import blade_dof

    def words(name: str) -> str:
        blade = blade_dof(name)
        kinds = {"F1": "1st flap", "E1": "1st edge", "F2": "2nd flap"}
        return f"blade {blade[0]} {kinds[blade[1]]}" if blade else DOF_LABELS.get(name, name)

    labels = [f"rigid body ({m.dominant_dof})" if m.rigid_body else words(m.dominant_dof) for m in modes]
    osc = [k for k, m in enumerate(modes) if not m.rigid_body]
    cols = [i for i, c in enumerate(coordinates) if c != "GeAz"]
    if not osc or not cols:
        return labels
    S = np.zeros((len(osc), len(cols)))
    for r, k in enumerate(osc):
        v = np.asarray(modes[k].shape)
        share = np.abs((v.conj() * (M @ v)).real)[cols]
        S[r] = share / share.sum() if share.sum() > 0 else share
    rows, assigned = linear_sum_assignment(S, maximize=True)
    for r, c in zip(rows, assigned):
        labels[osc[r]] = words(coordinates[cols[c]])
    return labels


def state_units(model) -> list[str]:
    """Units of the states ``[q; qd]`` of a TurbineModel (m or rad; m/s or rad/s), from its Q_/QD_ channels."""
    channels = model.output_function()
    units = dict(zip(channels.names, channels.units))
    coords = model.eom.coordinates
    return ([units.get(f"Q_{c}", "?") for c in coords] + [units.get(f"QD_{c}", "?") for c in coords])


def run(args: argparse.Namespace) -> int:
    if getattr(args, "inflow", None) is not None and (getattr(args, "wind", None) is None
                                                       or getattr(args, "closed_loop", False)):
        from ..exceptions import OptionError

        raise OptionError(f"--inflow {args.inflow} applies to the operating turbine's open-loop linear model: "
                          "mbsym linearize [DECK] --wind U --inflow frozen (not to the structure alone, nor to "
                          "--closed-loop, which keeps the dynamic inflow).")
    if getattr(args, "closed_loop", False) or getattr(args, "plot", None) is not None or \
            getattr(args, "bode", None) is not None:
        from ..exceptions import OptionError

        if getattr(args, "wind", None) is None or not getattr(args, "closed_loop", False):
            raise OptionError("--closed-loop needs --wind SPEEDS (e.g. --wind 4:25:1), and --plot and --bode need "
                              "--closed-loop: mbsym linearize [DECK] --wind 4:25:1 --closed-loop [--plot F.png] "
                              "(--bode F.png at one wind speed).")
        from .linearize_closed_loop import run_closed_loop

        return run_closed_loop(args)
    if getattr(args, "wind", None) is not None:
        from .linearize_operating import run_operating

        return run_operating(args)
    if getattr(args, "keep_azimuth", False) or getattr(args, "discon_input", None) is not None:
        from ..exceptions import OptionError

        raise OptionError("--keep-azimuth and --discon-input need --wind U (the operating turbine's linear model).")
    args.method = getattr(args, "method", None) or "elastodyn-fd"
    model, label = _model(args.deck, args.rpm, zero_displacements=not args.deflected,
                          structure_only=args.structure_only)
    report = linear_report(model, args.method, deflected=args.deflected)
    if args.json:
        print(json.dumps(report))
        return 0
    print(f"mbsym linearize: {label}")
    print(f"DOFs: {', '.join(model.eom.coordinates)}; rotor speed {report['rpm']:.4g} rpm; method {args.method}; "
          f"operating point: the deck's initial state{'' if args.deflected else ' without displacements'}")
    print(f"\n{'mode':>4} {'f [Hz]':>10} {'zeta [-]':>10}  {'dominant DOF':<13} label")
    from ._run import number

    for i, m in enumerate(report["modes"], 1):
        print(f"{i:>4} {m['freq_hz']:10.5f} {number(m['damping_ratio'], '10.5f')}  {m['dominant_dof']:<13} {m['label']}")
    states = [f"{s} [{u}]" for s, u in zip(report["states"], report["units"]["states"])]
    print(f"\nstates: {', '.join(states)}")
    with np.printoptions(precision=5, linewidth=120):
        for name in ("A", "M", "C", "K"):
            print(f"{name} ({report['units'][name]}) =\n{np.array(report[name])}")
    return 0
