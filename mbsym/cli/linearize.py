"""``mbsym linearize``: linear models and modes of an OpenFAST deck, as OpenFAST linearizes it.

Contract (kept for acceptance checks)::

    mbsym linearize [DECK.fst] [--rpm R] [--json] [--method {elastodyn-fd,exact}]

The operating point is the one of OpenFAST's linearization with zero initial
deflections: the deck's RotSpeed (or ``--rpm``), its Azimuth, NacYaw and BlPitch, and
every tower and platform displacement zero. It is generally *not* an equilibrium (the
rotor-nacelle overhang pulls the tower forward), and like OpenFAST the first-order model
is the Jacobian of the nonlinear rhs there. No deck: the built-in NREL 5 MW with its
modelled DOFs and the NREL 5 MW yaw spring and damper.

``--method elastodyn-fd`` (default) takes A by central differences of the rhs with
ElastoDyn's own steps (:func:`mbsym.linear.elastodyn_steps`), which reproduces OpenFAST's
frequencies including its finite-step error (0.8 % on a floating platform's pitch
frequency, docs/elastodyn_notes.md §8.3); ``--method exact`` uses automatic
differentiation. M, C, K are exact residual Jacobians at the operating point's own
acceleration (so ``A = [[0, I], [-M⁻¹K, -M⁻¹C]]`` for ``exact``).

``--json`` prints one object: ``states``, ``A``, ``modes`` (``freq_hz``,
``damping_ratio``, ``dominant_dof``; rigid-body modes with ``freq_hz`` 0), ``M``,
``C``, ``K``.
"""

from __future__ import annotations

import argparse
import dataclasses
import json

import numpy as np

__all__ = ["add_parser", "run"]


def add_parser(sub) -> None:
    p = sub.add_parser("linearize", help="linearize an OpenFAST deck at its undeflected initial state; print modes",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("deck", nargs="?", help="main OpenFAST input file (.fst); default: built-in NREL 5 MW")
    p.add_argument("--rpm", type=float, help="rotor speed [rpm] (default: the deck's RotSpeed)")
    p.add_argument("--json", action="store_true", help="print states, A, modes, M, C, K as one JSON object")
    p.add_argument("--method", choices=("elastodyn-fd", "exact"), default="elastodyn-fd",
                   help="A by ElastoDyn's central differences (default, as OpenFAST) or exact derivatives")


def undeflected(turbine, rpm: float | None = None):
    """The deck's turbine with zero tower and platform displacements (and ``rpm`` if given)."""
    ic = turbine.initial_conditions
    changes = dict(tower_top_fa_displacement=0.0, tower_top_ss_displacement=0.0, platform_surge=0.0,
                   platform_sway=0.0, platform_heave=0.0, platform_roll=0.0, platform_pitch=0.0, platform_yaw=0.0,
                   blade_oop_tip_deflection=0.0, blade_ip_tip_deflection=0.0, teeter_angle=0.0)
    if rpm is not None:
        if not (np.isfinite(rpm) and rpm >= 0):
            raise ValueError(f"--rpm must be a finite rotor speed >= 0 [rpm]; got {rpm}")
        changes["rotor_speed"] = rpm * np.pi / 30.0
    return dataclasses.replace(turbine, initial_conditions=dataclasses.replace(ic, **changes))


def _model(deck, rpm):
    from ..wind import nrel5mw, read_openfast
    from ..wind.structure.turbine import NON_BLADE_DOFS, TurbineModel
    from .simulate import NREL5MW_YAW_DAMPING, NREL5MW_YAW_SPRING

    if deck is None:
        turbine = undeflected(nrel5mw(), rpm)
        dofs = [f for f in NON_BLADE_DOFS if turbine.dofs.get(f)]
        model = TurbineModel(turbine, dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)
        return model, "NREL 5 MW onshore (built-in)"
    return TurbineModel(undeflected(read_openfast(deck), rpm)), str(deck)


def linear_report(model, method: str = "elastodyn-fd") -> dict:
    """The ``--json`` object of a TurbineModel at its default (initial) state."""
    from ..linear import linearize

    lin = linearize(model, qdd0="rhs", method=method)
    return {"states": list(lin.states), "A": lin.A.tolist(), "modes": [m.as_dict() for m in lin.modes()],
            "M": lin.M.tolist(), "C": lin.C.tolist(), "K": lin.K.tolist()}


def run(args: argparse.Namespace) -> int:
    model, label = _model(args.deck, args.rpm)
    report = linear_report(model, args.method)
    if args.json:
        print(json.dumps(report))
        return 0
    rpm = model.turbine.initial_conditions.rotor_speed * 30.0 / np.pi
    print(f"mbsym linearize: {label}")
    print(f"DOFs: {', '.join(model.eom.coordinates)}; rotor speed {rpm:.4g} rpm; method {args.method}")
    print(f"\n{'mode':>4} {'f [Hz]':>10} {'zeta [-]':>10}  dominant DOF")
    for i, m in enumerate(report["modes"], 1):
        kind = "  (rigid body)" if m["freq_hz"] == 0.0 else ""
        print(f"{i:>4} {m['freq_hz']:10.5f} {m['damping_ratio']:10.5f}  {m['dominant_dof']}{kind}")
    with np.printoptions(precision=5, linewidth=120):
        print(f"\nstates {report['states']}\nA =\n{np.array(report['A'])}")
    return 0
