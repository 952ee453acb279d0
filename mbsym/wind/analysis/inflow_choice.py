"""The inflow of an operating turbine's linear model: dynamic, frozen or quasi-steady wake.

An operating turbine's aerodynamics carry wake (induction) states: the rotor-averaged DBEMT
``DBEMT_w``, ``DBEMT_v`` of the rotor-effective rung (:mod:`mbsym.wind.operation.dynamic_inflow`)
or Øye's two stages per node and blade ``B<k>N<j>_vind_x`` … of the blade-element rung
(:mod:`mbsym.wind.aero.blade.dbemt`). A linear model about an operating point treats them in one
of three ways, as OpenFAST's ``DBEMT_Mod`` does when it linearizes:

``"dynamic"`` (default)
    The wake states stay states (OpenFAST: ``DBEMT_Mod = 3``, continuous DBEMT).
``"frozen"``
    The induced velocities are held at their trim values: the wake states are removed and
    their values become constants, so the loads respond to every change of the relative wind
    (tower motion, wind, rotor speed, pitch) with the induction of the trim (OpenFAST:
    ``DBEMT_Mod = -1``, frozen wake, which holds AeroDyn's induced velocities
    ``-Vx a`` and ``Vy a'`` of the operating point, BEMT.f90 ``computeFrozenWake``). For the
    linear model that is exact truncation: the rows and columns of the wake states are deleted
    (``δz = 0``).
``"quasi-steady"``
    The induction is in equilibrium with the instantaneous inflow (no wake states; OpenFAST:
    ``DBEMT_Mod = 0``). The wake equations ``δż = A_zx δx + A_zz δz + B_z δu`` are solved for
    ``δż = 0`` and substituted (residualization):
    ``A' = A_xx − A_xz A_zz⁻¹ A_zx``, ``B' = B_x − A_xz A_zz⁻¹ B_z``,
    ``C' = C_x − C_z A_zz⁻¹ A_zx``, ``D' = D − C_z A_zz⁻¹ B_z``. At equilibrium Øye's filter
    passes the quasi-steady induction unchanged (``v = v_qs``), so this is the linearization of
    the quasi-steady rotor. The blade-element rung does it at every azimuth in the rotating
    frame, before the multi-blade transformation, so every node's induction follows its own
    inflow.

Which to compare with OpenFAST: like with like, ``frozen`` with ``DBEMT_Mod = -1`` (the usual
OpenFAST linearization), ``dynamic`` with ``DBEMT_Mod = 3``, ``quasi-steady`` with
``DBEMT_Mod = 0``. The rotor-effective rung's thrust acts along the shaft only: it has no rotor
side force, so its tower side-side mode has no aerodynamic damping whatever the inflow choice;
the blade-element rung has the side forces.

The simpler first-order lag on thrust and torque (``RotThrustLag``, ``RotTorqLag``) is not an
induction: it can be quasi-steady (the lags in equilibrium) but not frozen.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Sequence

import numpy as np

from ...exceptions import ArgumentTypeError, OptionError, UnsupportedFeatureError

__all__ = ["INFLOW_CHOICES", "check_inflow", "wake_states", "lag_states", "reduce_inflow", "with_inflow"]

#: The inflow choices of an operating linear model (module docstring).
INFLOW_CHOICES = ("dynamic", "frozen", "quasi-steady")
_LAG_STATES = ("RotThrustLag", "RotTorqLag")


def check_inflow(inflow: object) -> str:
    """``inflow`` if it is one of :data:`INFLOW_CHOICES`.

    Raises
    ------
    ArgumentTypeError
        Not a string.
    OptionError
        Another string.

    Examples
    --------
    >>> check_inflow("frozen")
    'frozen'
    """
    if not isinstance(inflow, str):
        raise ArgumentTypeError(f"inflow must be a string, one of {list(INFLOW_CHOICES)}; got "
                                f"{type(inflow).__name__} {inflow!r}.")
    if inflow not in INFLOW_CHOICES:
        raise OptionError(f"inflow {inflow!r} is not an inflow choice; expected one of {list(INFLOW_CHOICES)} "
                          "(dynamic: wake states kept; frozen: induction held at the trim, as OpenFAST's "
                          "DBEMT_Mod = -1; quasi-steady: induction in equilibrium, as DBEMT_Mod = 0).")
    return inflow


def wake_states(states: Sequence[str]) -> list[str]:
    """The induction (wake) states among ``states``: ``DBEMT_w``, ``DBEMT_v`` and the blade-element
    rung's ``…_vind…`` (in any coordinates: ``B1N5_vind_x``, ``N5_vind_x_coll``).

    Examples
    --------
    >>> wake_states(["TFA1", "GenTq", "DBEMT_w", "DBEMT_v", "B1N3_vind1_y"])
    ['DBEMT_w', 'DBEMT_v', 'B1N3_vind1_y']
    """
    return [s for s in states if s in ("DBEMT_w", "DBEMT_v") or "_vind" in s]


def lag_states(states: Sequence[str]) -> list[str]:
    """The thrust and torque lag states (``RotThrustLag``, ``RotTorqLag``) among ``states``."""
    return [s for s in states if s in _LAG_STATES]


def reduce_inflow(A: np.ndarray, B: np.ndarray, C: np.ndarray, D: np.ndarray, states: Sequence[str],
                  inflow: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[int]]:
    """``(A, B, C, D, keep)`` of one linear model with the inflow choice applied (module docstring).

    Parameters
    ----------
    A, B, C, D : ndarray
        ``(n_x, n_x)``, ``(n_x, n_u)``, ``(n_y, n_x)``, ``(n_y, n_u)`` in the order of ``states``.
    states : sequence of str
    inflow : {"dynamic", "frozen", "quasi-steady"}

    Returns
    -------
    tuple
        The reduced matrices and ``keep``, the indices of the remaining states.

    Raises
    ------
    UnsupportedFeatureError
        ``frozen`` on a model without induction states (nothing to freeze) or with the thrust and
        torque lag (a lag on the loads, not an induction).
    SolverError
        ``quasi-steady`` with a singular wake block ``A_zz`` (the wake has no equilibrium).
    """
    inflow = check_inflow(inflow)
    states = list(states)
    n = len(states)
    if inflow == "dynamic":
        return A, B, C, D, list(range(n))
    wake = wake_states(states)
    lags = lag_states(states)
    if inflow == "frozen" and (lags or not wake):
        why = (f"its inflow states {lags} lag the thrust and torque (no induction to hold)" if lags else
               "it has no induction states (a quasi-steady rotor: its loads follow the inflow at once)")
        raise UnsupportedFeatureError(f"inflow='frozen' needs wake (induction) states; {why}. Use inflow="
                                      "'quasi-steady' or 'dynamic', or a model with dynamic inflow (DBEMT).")
    z = [states.index(s) for s in wake + lags]
    keep = [i for i in range(n) if i not in set(z)]
    Ax, Bx, Cx = A[np.ix_(keep, keep)], B[keep], C[:, keep]
    if inflow == "frozen" or not z:
        return Ax, Bx, Cx, D, keep
    Azz = A[np.ix_(z, z)]
    try:
        gain = np.linalg.solve(Azz, np.hstack([A[np.ix_(z, keep)], B[z]]))
    except np.linalg.LinAlgError:
        from ...exceptions import SolverError

        raise SolverError("inflow='quasi-steady': the wake block of A is singular (the induction has no "
                          "equilibrium at this point); use inflow='dynamic' or 'frozen'.") from None
    gx, gu = gain[:, :len(keep)], gain[:, len(keep):]
    Axz, Cz = A[np.ix_(keep, z)], C[:, z]
    return Ax - Axz @ gx, Bx - Axz @ gu, Cx - Cz @ gx, D - Cz @ gu, keep


def with_inflow(lin, inflow: str = "dynamic"):
    """A :class:`~mbsym.linear.LinearModel` of an operating turbine with the inflow choice applied.

    Parameters
    ----------
    lin : LinearModel
        With the wake states (e.g. :func:`~.trim_linear.linearize_point`); ``"dynamic"`` returns it.
    inflow : {"dynamic", "frozen", "quasi-steady"}
        Module docstring.

    Returns
    -------
    LinearModel
        Without the wake states for ``frozen`` and ``quasi-steady``; ``operating_point`` records
        ``inflow`` and the trim values of the removed states under ``removed_states`` (the
        constants of the frozen wake).

    Raises
    ------
    ArgumentTypeError, OptionError, UnsupportedFeatureError, SolverError
        See :func:`check_inflow`, :func:`reduce_inflow`.
    """
    inflow = check_inflow(inflow)
    op = dict(lin.operating_point)
    op["inflow"] = inflow
    if inflow == "dynamic":
        return replace(lin, operating_point=op)
    Cy = lin.Cy.reshape(len(lin.outputs), len(lin.states))
    Dy = lin.Dy.reshape(len(lin.outputs), len(lin.inputs))
    A, B, C, D, keep = reduce_inflow(lin.A, lin.B.reshape(len(lin.states), -1), Cy, Dy, lin.states, inflow)
    dropped = [i for i in range(len(lin.states)) if i not in keep]
    x = op.get("x")
    full = x is not None and np.size(x) == len(lin.states)
    removed = dict(op.get("removed_states", {}))
    removed.update({lin.states[i]: float(np.asarray(x)[i]) if full else float("nan") for i in dropped})
    op["removed_states"] = removed
    for key in ("x", "xd"):
        if op.get(key) is not None and np.size(op[key]) == len(lin.states):
            op[key] = np.asarray(op[key])[keep]
    names = [lin.states[i] for i in dropped]
    return replace(lin, A=A, B=B, Cy=C, Dy=D, states=tuple(lin.states[i] for i in keep), operating_point=op,
                   units={s: u for s, u in lin.units.items() if s not in names})
