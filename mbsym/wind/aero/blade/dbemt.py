"""AeroDyn's dynamic BEMT (DBEMT, Øye's two-stage filter) per blade node, as a continuous ODE.

OpenFAST v5 runs DBEMT whenever ``Wake_Mod = 1`` and ``DBEMT_Mod > 0`` in a v4+ AeroDyn file
(``Wake_Mod = 2`` is no longer a value; a legacy ``WakeMod = 1`` key sets ``DBEMT_Mod = 0`` and
``WakeMod = 2`` sets ``Wake_Mod = 1`` with DBEMT). Read in AeroDyn_IO.f90 ("Legacy logic") and
BEMT.f90/DBEMT.f90 of OpenFAST v5. For each node, both components of the quasi-steady induced
velocity ``v_s = (-a_qs Vx, a'_qs Vy)`` [m/s] are filtered:

    τ₁ dv₁/dt + v₁ = v_s + k τ₁ dv_s/dt,     τ₂ dv/dt + v = v₁,     k = 0.6,

and the node uses ``a = -v_x / Vx``, ``a' = v_y / Vy`` (AeroDyn's limits applied). With the
state ``w = v₁ - k v_s`` (DBEMT_Mod 3's "reduced velocity" ``vind_1``) no derivative of the
input is needed, for any τ₁(t):

    dw/dt = ((1 - k) v_s - w) / τ₁,     dv/dt = (w + k v_s - v) / τ₂.

DBEMT_Mod 1 (exact discrete solution for piecewise-linear inputs) and 3 (ABM4 on the same ODE)
are time discretizations of this ODE; DBEMT_Mod 2 adds a time-varying
``τ₁ = min(1.1 R / ((1 - 1.3 min(ā, 0.5)) max(U_n, 0.1)), 100 s)`` with

* ``R`` the rotor radius (AeroDyn: the largest current ``rLocal``; here ``tip_radius``),
* ``U_n`` the disk-averaged relative wind along the shaft (AeroDyn's ``Un_disk``),
* ``ā = Σ w_i a_qs,i`` the weighted quasi-steady axial induction of all nodes with AeroDyn's
  ``IntegrateWeight``: per blade ``(35/32)(1 - u²)³``, ``u = clip((r/R_max - 0.7)/0.1, -1, 1)``,
  normalized to sum 1 per blade, divided by the number of blades (BEMT_SetParameters).

``τ₂ = (0.39 - 0.26 (r/R)²) τ₁`` per node, ``r/R`` from the current ``r_local`` (DBEMT_Mod 2)
or the undeflected geometry (1, 3), as AeroDyn does.

**The wind's rate (AeroDyn v5, DBEMT_Mod 1 and 2).** AeroDyn's finite-difference update
(DBEMT.f90 ``DBEMT_UpdateStates``: ``B = (v_s(t+Δt) - v_s(t))/Δt``, ``A = v_s(t) + k τ₁ B``) gets
both of its inputs from ``AD_UpdateStates``, which builds the inputs at t and at t + Δt from the
structural motion of each time but from one copy of the inflow made before that loop: the wind at
the step's end (at the nodes' positions of the step's end). ``BEMT_UpdateStates`` then takes the
input at t as ``-a(φ(t)) Vx`` with the inflow angle solved at the previous step (its own wind) and
this ``Vx``. So ``B`` holds every change of the induction factors (from the wind too, through φ)
and the change of ``Vx``, ``Vy`` from the motion, pitch and turning node axes, but not the change
of ``Vx``, ``Vy`` from the wind changing along the node's path (turbulence passing, rotation
through shear). In the ODE above: ``dw/dt = ((1 - k) v_s - w)/τ₁ - k (-a_qs dVx_W/dt,
a'_qs dVy_W/dt)`` with ``dV_W/dt`` the wind's rate along the path projected on the node's axes
(``wind_rate``). :class:`~mbsym.wind.aero.blade.BladeElementRotor` does this by default for modes
1 and 2 (``dbemt_wind_rate=False``; True gives Øye's filter on the whole rate, as mode 3's
continuous form has it). Measured against OpenFAST's node outputs and on the shared ``ff14_flex``
case: docs/blade_aero.md.

State layout: per node (blades outer, nodes inner) the four states ``vind_x, vind_y, vind1_x,
vind1_y`` (``v`` then ``w``), named ``B{b}N{j}_vind_x`` ... (1-based).
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

__all__ = ["OYE_K", "STATE_SUFFIXES", "state_names", "integrate_weights", "tau1", "derivatives",
           "equilibrium"]

#: Øye's k (AeroDyn's ``k_0ye``).
OYE_K = 0.6
#: The four states of a node, in order.
STATE_SUFFIXES = ("vind_x", "vind_y", "vind1_x", "vind1_y")
_TAU1_MAX = 100.0  # AeroDyn's cap on τ₁ [s]
_A_DISK_MAX = 0.5
_UN_MIN = 0.1  # [m/s]


def state_names(n_blades: int, n_nodes: int) -> tuple[str, ...]:
    """``("B1N1_vind_x", "B1N1_vind_y", "B1N1_vind1_x", ...)``: blades outer, nodes inner."""
    return tuple(f"B{b + 1}N{j + 1}_{s}" for b in range(n_blades) for j in range(n_nodes)
                 for s in STATE_SUFFIXES)


def integrate_weights(r_local: np.ndarray, n_blades: int) -> np.ndarray:
    """AeroDyn's ``IntegrateWeight`` (BEMT_SetParameters) for one blade's nodes, shape (n_nodes,).

    ``(35/32)(1 - u²)³`` with ``u = clip((r / max r - 0.7) / 0.1, -1, 1)``, normalized to sum
    1 and divided by ``n_blades`` (so the weights of all blades sum to 1).
    """
    u = np.clip((r_local / r_local.max() - 0.7) / 0.1, -1.0, 1.0)
    w = 35.0 / 32.0 * (1.0 - np.abs(u) ** 2) ** 3
    return w / w.sum() / n_blades


def tau1(mode: int, tau1_const: float, a_qs: Any, weights: np.ndarray, tip_radius: Any,
         un_disk: Any) -> Any:
    """τ₁ [s]: ``tau1_const`` (modes 1, 3) or AeroDyn's ComputeTau1 (mode 2)."""
    if mode != 2:
        return tau1_const
    a_disk = ca.fmin(ca.dot(ca.DM(weights), a_qs), _A_DISK_MAX)
    value = 1.1 * tip_radius / ((1.0 - 1.3 * a_disk) * ca.fmax(un_disk, _UN_MIN))
    return ca.fmin(value, _TAU1_MAX)


def derivatives(states: Any, v_s: Any, tau_1: Any, span_ratio: Any, wind_rate: Any = None) -> Any:
    """Time derivatives of the states (layout in the module docstring).

    Parameters
    ----------
    states : SX, shape (4 n, 1)
    v_s : SX, shape (n, 2)
        Quasi-steady induced velocities ``(-a_qs Vx, a'_qs Vy)`` [m/s].
    tau_1 : SX or float
        τ₁ [s].
    span_ratio : SX or ndarray, shape (n, 1)
        ``r / R`` of each node.
    wind_rate : SX, shape (n, 2), optional
        ``(-a_qs dVx_W/dt, a'_qs dVy_W/dt)`` [m/s²]: the part of ``dv_s/dt`` that AeroDyn v5's
        DBEMT_Mod 1 and 2 leave out of Øye's rate term (module docstring); ``dw/dt`` gains
        ``-k wind_rate``.
    """
    x = ca.reshape(states, 4, -1).T  # (n, 4)
    v, w = x[:, 0:2], x[:, 2:4]
    tau_2 = (0.39 - 0.26 * span_ratio**2) * tau_1
    w_dot = ((1.0 - OYE_K) * v_s - w) / tau_1
    if wind_rate is not None:
        w_dot = w_dot - OYE_K * wind_rate
    v_dot = (w + OYE_K * v_s - v) / ca.repmat(tau_2, 1, 2)
    return ca.reshape(ca.horzcat(v_dot, w_dot).T, -1, 1)


def equilibrium(v_s: np.ndarray) -> np.ndarray:
    """States at rest for quasi-steady induced velocities ``v_s`` (n, 2): ``v = v_s``, ``w = (1-k) v_s``."""
    v_s = np.asarray(v_s, dtype=float).reshape(-1, 2)
    return np.concatenate([v_s, (1.0 - OYE_K) * v_s], axis=1).ravel()
