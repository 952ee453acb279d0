"""Load cuts of the turbine: locked joints whose reactions are ElastoDyn's internal loads.

A *cut* puts a chain of locked coordinates (:meth:`mbsym.System.locked`) between two parts of
the structure: massless hinges that translate along and turn about the axes of the cut frame,
held at zero. The equations of motion do not change (the locked coordinates never move; their
rows cost nothing in the right-hand side), and ``eom.functions.reactions`` gives what the inboard
part exerts on the outboard part through each locked coordinate: the force along the cut's axis
(translations) and the moment about it through the cut point (rotations), with the gravity,
inertia and applied loads of everything outboard, exactly as the equations see them.

ElastoDyn's load channels are the loads the *outboard* part exerts on the inboard one, so each is
**minus** a reaction [ElastoDyn.f90, ``CalcOutput``: ``FrcS0B``, ``MomH0B`` (root, "due to the
blade"), ``FrcPRot`` (teeter pin, "due to the rotor"), ``FrcONcRt``, ``MomBNcRt`` (yaw bearing,
"due to the nacelle, generator and rotor")]:

================  ============================  ===============================================
cut               locked coordinates            channels (ElastoDyn's axes, IEC signs)
================  ============================  ===============================================
tower base        ``TwrBsRotX/Y``               ``TwrBsMxt``, ``TwrBsMyt`` [kN-m], tower axes
blade root ``k``  ``B<k>RootTrnX/Y/Z``          ``RootFxc<k>``, ``RootFyc<k>``, ``RootFzc<k>`` [kN]
                                                along the coned root axes ``i1, i2, i3``;
                                                ``RootFxb<k>``, ``RootFyb<k>`` along the pitched
                                                ``j1, j2``
blade root ``k``  ``B<k>RootRotX/Y/Z``          ``RootMxc<k>`` … ``RootMzc<k>``, ``RootMxb<k>``,
                                                ``RootMyb<k>`` [kN-m], about the root point
low-speed shaft   ``LSShftTrnX/Y/Z``            ``LSShftFxa`` (= ``RotThrust``), ``LSShftFys``,
                                                ``LSShftFzs`` [kN] along the nonrotating shaft
                                                axes ``c1``, ``−c3``, ``c2`` (x along the shaft,
                                                z up in the vertical plane of the shaft)
yaw bearing       ``YawBrTrnX/Y/Z``,            ``YawBrFxp``, ``YawBrFyp``, ``YawBrFzp`` [kN],
                  ``YawBrRotX/Y/Z``             ``YawBrMxp``, ``YawBrMyp``, ``YawBrMzp`` [kN-m]
                                                along/about the tower-top axes ``b1, −b3, b2``
                                                (deflected tower top, not yawed) at the bearing
================  ============================  ===============================================

What is outboard follows ElastoDyn: the blade (its nodes, tip mass and loads) for the root; hub
and blades for the shaft (the generator stays on the nacelle side); nacelle, generator, shaft,
hub and blades for the yaw bearing (the yaw-bearing mass stays on the tower, as in ElastoDyn's
``FrcONcRt``). The shaft and yaw-bearing forces and the root forces do not depend on the cut
point; the moments are about the root point ``S(0)`` and the tower-top point ``O``.
"""

from __future__ import annotations

from typing import Any, Sequence

import casadi as ca
import numpy as np

from ...bodies.rigid import RigidBody
from ...joints import Prismatic, Revolute

__all__ = ["TOWER_BASE_LOCKED", "BLADE_ROOT_LOCKED", "BLADE_ROOT_FORCE_LOCKED", "SHAFT_LOCKED",
           "YAW_BEARING_LOCKED", "locked_chain", "reaction_rows"]

#: Locked tower-base rotations about the platform's x and y axes (``tower_base_reactions=True``).
TOWER_BASE_LOCKED = ("TwrBsRotX", "TwrBsRotY")
#: Locked rotations at each blade root about i1, i2, i3 (``blade_root_reactions=True``): ``B{k}`` + these.
BLADE_ROOT_LOCKED = ("RootRotX", "RootRotY", "RootRotZ")
#: Locked translations at each blade root along i1, i2, i3 (``blade_root_forces=True``): ``B{k}`` + these.
BLADE_ROOT_FORCE_LOCKED = ("RootTrnX", "RootTrnY", "RootTrnZ")
#: Locked translations between the nonrotating shaft and the rotor (``shaft_reactions=True``).
SHAFT_LOCKED = ("LSShftTrnX", "LSShftTrnY", "LSShftTrnZ")
#: Locked translations and rotations between the tower top and the nacelle (``yaw_bearing_reactions=True``).
YAW_BEARING_LOCKED = ("YawBrTrnX", "YawBrTrnY", "YawBrTrnZ", "YawBrRotX", "YawBrRotY", "YawBrRotZ")

_AXES = {"X": [1.0, 0.0, 0.0], "Y": [0.0, 1.0, 0.0], "Z": [0.0, 0.0, 1.0]}


def locked_chain(model, parent, names: Sequence[str], *, offset, rotation, label: str) -> tuple[Any, list, list]:
    """Insert locked hinges ``names`` (``...Trn<axis>``: translation, ``...Rot<axis>``: rotation) after ``parent``.

    The first hinge sits at ``offset`` [m] with axes ``rotation`` (parent axes); the others follow at
    zero offset. Returns ``(last hinge, [0, 0, 0], identity)``: where the outboard joint attaches.
    ``model`` is the :class:`~.turbine.TurbineModel` being built (its ``system`` and ``_add``).

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> from mbsym.wind.structure.turbine import TurbineModel
    >>> TurbineModel(nrel5mw(), ["GenDOF"], shaft_reactions=True).eom.locked
    ('LSShftTrnX', 'LSShftTrnY', 'LSShftTrnZ')
    """
    locks = model.system.locked(list(names))
    locks = locks if isinstance(locks, tuple) else (locks,)
    for name, lock in zip(names, locks):
        hinge = RigidBody(f"{label}_{lock.name()}", mass=0.0)
        joint = Prismatic if "Trn" in name else Revolute
        model._add(joint(parent, hinge, axis=_AXES[name[-1]], coordinate=lock, offset=offset, rotation=rotation))
        parent, offset, rotation = hinge, [0.0, 0.0, 0.0], np.eye(3).tolist()
    return parent, offset, rotation


def reaction_rows(locked: Sequence[str], reactions: Any, pitch: Sequence[Any] = ()) -> list[tuple[str, str, Any]]:
    """``(name, unit, expression)`` of the load channels of every cut present (module table).

    Parameters
    ----------
    locked : sequence of str
        ``eom.locked``: the names of the locked coordinates, in the order of ``reactions``.
    reactions : casadi SX or MX or array
        ``eom.functions.reactions(q, qd, qdd, u, p)`` [N, N m].
    pitch : sequence, optional
        Pitch angle of each blade [rad] (for the ``...b<k>`` channels; none without it).

    Examples
    --------
    >>> rows = reaction_rows(SHAFT_LOCKED, [-94.0e3, 0.0, 1.07e6])     # the shaft holds the rotor up
    >>> [(name, unit, round(float(value), 1)) for name, unit, value in rows]
    [('LSShftFxa', 'kN', 94.0), ('LSShftFys', 'kN', -0.0), ('LSShftFzs', 'kN', -1070.0)]
    """
    def load(name: str, scale: float = 1e-3):
        return -reactions[locked.index(name)] * scale if name in locked else None

    rows = []
    for name, channel in (("TwrBsRotX", "TwrBsMxt"), ("TwrBsRotY", "TwrBsMyt")):
        if name in locked:
            rows.append((channel, "kN-m", load(name)))
    for kind, unit, locks in (("M", "kN-m", BLADE_ROOT_LOCKED), ("F", "kN", BLADE_ROOT_FORCE_LOCKED)):
        k = 1
        while f"B{k}{locks[0]}" in locked:
            beta = pitch[k - 1] if len(pitch) >= k else None
            rows += _root_rows(kind, unit, k, [load(f"B{k}{n}") for n in locks], beta)
            k += 1
    if SHAFT_LOCKED[0] in locked:
        fx, fy, fz = (load(n) for n in SHAFT_LOCKED)
        rows += [("LSShftFxa", "kN", fx), ("LSShftFys", "kN", fy), ("LSShftFzs", "kN", fz)]
    if YAW_BEARING_LOCKED[0] in locked:
        values = [load(n) for n in YAW_BEARING_LOCKED]
        names = ("YawBrFxp", "YawBrFyp", "YawBrFzp", "YawBrMxp", "YawBrMyp", "YawBrMzp")
        rows += [(n, "kN" if n[5] == "F" else "kN-m", v) for n, v in zip(names, values)]
    return rows


def _root_rows(kind: str, unit: str, k: int, xyz: list, beta) -> list[tuple[str, str, Any]]:
    """Root force or moment of blade ``k`` in the coned axes (c) and, with the pitch, the pitched axes (b).

    ElastoDyn's ``j1 = cos β i1 − sin β i2``, ``j2 = sin β i1 + cos β i2`` (β the pitch angle).
    """
    x, y, z = xyz
    rows = [(f"Root{kind}xc{k}", unit, x), (f"Root{kind}yc{k}", unit, y), (f"Root{kind}zc{k}", unit, z)]
    if beta is not None:
        c, s = ca.cos(beta), ca.sin(beta)
        rows += [(f"Root{kind}xb{k}", unit, c * x - s * y), (f"Root{kind}yb{k}", unit, s * x + c * y)]
    return rows
