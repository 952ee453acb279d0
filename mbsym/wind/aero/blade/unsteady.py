"""AeroDyn's unsteady airfoil aerodynamics ``UA_Mod = 3`` (Beddoes–Leishman, Minnema/Pierce) per blade node.

OpenFAST v5 runs this model as a **discrete-time** system: once per AeroDyn step ``Δ`` (``DTAero``) every node's
"Kelvin chain" turns the node's angle of attack α and relative speed U at the step's start, and the node's states of
the previous step, into the coefficients Cl, Cd, Cm that load the blade now and into the states of the next step
(UnsteadyAero.f90 ``ComputeKelvinChain``, ``UA_UpdateDiscOtherState``, ``UA_CalcOutput``; read for the facts).
Written here from those facts, with its own names:

* the input filter (cut-off ``filtCutOff`` in reduced frequency, ``f = max(U, 1) k_c / (π c)``) on α, the pitch
  rate ``q = α̇ c / U`` and its rate, by first-order recursions ``y ← e^{-2πfΔ} y + (1 - e^{-2πfΔ}) x``;
* the deficiency functions ``Y ← Y e^{-Δ/T} + (x - x_prev) e^{-Δ/(2T)}`` (time) or in semichords ``ds = 2UΔ/c``:
  the circulatory lag ``X1, X2`` (``A1, b1``, ``A2, b2``, Prandtl–Glauert ``β² = 1 - M²``, ``M = U/a``), the
  impulsive terms (``T_α = 0.75 k_α c/a``, ``T_q``), the pitching-moment terms (``b5``, ``A5``), the
  leading-edge pressure lag ``Dp`` (``T_p``), the trailing-edge separation lag of ``f'`` and ``f'_c``
  (``T_f = T_f0/σ₁``), the Minnema/Pierce lag of α_f (``0.1 T_f``) and the vortex lift ``Cn_v`` (``T_V0/σ₃``);
* the separation points ``f'``, ``f'_c`` from the static polar (``FLookup = True``): ``f = (2√(Cn / (C_nα/β
  (α - α₀))) - 1)²`` capped at 1, ``f_c = min(1.44, (Cc / (C_nα/β (α - α₀) tan α) + 0.2)²)``;
* the vortex clock ``τ_V`` (semichords since the leading edge separated, ``Cn' > Cn1`` or ``< Cn2``), reset
  when a new vortex sheds (``τ_V ≥ T_VL + 2(1 - f'')/St_sh`` while the flow separates further), and the time
  constant modifiers σ₁, σ₃ chosen from the flow's state;
* the outputs ``Cn = Cn_FS (+ Cn_v once τ_V > 0)``, ``Cc = Cc_pot (√f''_c - 0.2) + Cn_v α_e (1 - τ_V/T_VL)``,
  ``Cl = Cn cos α + Cc sin α``, ``Cd = Cn sin α - Cc cos α + Cd0``, ``Cm = Cm(α_f - Dα_f) + …`` and the cosine
  blend to the static polar between ``UACutout - UACutout_delta`` and ``UACutout`` in |α| and below U = 1 m/s.

**In a continuous graph.** The 25 discrete states ``z`` of a node (:data:`STATE_SUFFIXES`) are carried as
continuous states that relax to the chain's update over one AeroDyn step:

    ż = (F(z, α, U) - z) / Δ.

An explicit step of length Δ with ``F`` held over the step (mbsym's ``"rk4-held"`` at the deck's ``DT``, the held
part evaluated once per step as AeroDyn is) gives ``z_{n+1} = F(z_n, α_n, U_n)``: OpenFAST's recursion, exactly.
Any other integrator sees a stable ODE (eigenvalues ``-1/Δ`` of the delayed copies, inside RK4's interval up to a
step of 2.78 Δ) that follows the recursion's response below ~``1/(2πΔ)``; the steady states are the recursion's
fixed points (:func:`steady_states`). Every quantity is an SX column over the nodes UA runs on.

**The update's inputs (AeroDyn v5).** AeroDyn's ``AD_UpdateStates`` builds the BEMT inputs of the step's start from
the structure at that time but from one copy of the undisturbed wind made before, at the blade positions of the
step's end (the same copy :mod:`.dbemt` describes). UA's update at step n therefore sees ``α'``, ``U'`` of the node's
relative flow plus the change of the wind along its path over the step, ``Δ ≈ dW/dt|_path Δt`` projected on its
axes (the induced velocities kept), while the coefficients of step n (AeroDyn's outputs) use the wind of step n.
:class:`~mbsym.wind.aero.blade.BladeElementRotor` does the same by default (``ua_step_end_wind``); traced with
OpenFAST v5.0.0's own UnsteadyAero built and driven on the same inputs: ignoring it leaves 1.5-6e-3 in Cl against
AeroDyn's node outputs in a sheared wind (an angle of attack 0.01-0.025° off, of one sign per half turn), taking it
into account ~1e-5 (tests/wind/blade/test_blade_unsteady.py).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Callable

import casadi as ca
import numpy as np

__all__ = ["STATE_SUFFIXES", "UA_PARAMETERS", "U_MIN", "UnsteadyNodes", "state_names", "kelvin_chain",
           "kelvin_chain_mapped", "steady_states", "unsteady_nodes"]

#: The discrete states of a node, in order (OpenFAST's ``*_minus1`` values, the vortex clock and σ₁, σ₃).
STATE_SUFFIXES = ("alpha_filt", "q", "q_f", "Kalpha_f", "Kq_f", "X1", "X2", "Kp_alpha", "Kp_q", "K3p_q", "Kpp_q",
                  "Dp", "Cn_pot", "fpp", "Df", "fp", "Df_c", "fp_c", "Dalphaf", "alpha_f", "Cn_v", "C_V", "tau_V",
                  "sigma1", "sigma3")
#: Airfoil constants the chain reads (:class:`~mbsym.wind.deck.airfoil_ua.UACoefficients` attributes).
UA_PARAMETERS = ("alpha0", "C_nalpha", "T_f0", "T_V0", "T_p", "T_VL", "b1", "b2", "b5", "A1", "A2", "A5", "Cn1",
                 "Cn2", "St_sh", "Cd0", "x_cp_bar", "UACutout", "UACutout_blend", "filtCutOff")
#: AeroDyn's floor on the relative speed inside UA [m/s] (UnsteadyAero.f90 ``UA_u_min``).
U_MIN = 0.01
_GONZALEZ = 0.2             # the offset AeroDyn puts on √f_c (``Gonzalez_factor``)
_FC_LIMIT = (1.0 + _GONZALEZ) ** 2
# NWTC EqualRealNos: |a - b| <= max(|a + b|, 1) 50 eps; AeroDyn compares f with 1 in ReKi (double in the shared
# double-precision v5.0.0 build) and the angles after a cast to single precision (SiKi)
_EQ_TOL = 50.0 * float(np.finfo(np.float64).eps)
_EQ_TOL_SINGLE = 50.0 * float(np.finfo(np.float32).eps)
_I = {name: k for k, name in enumerate(STATE_SUFFIXES)}


def state_names(nodes: list[tuple[int, int]], mode: int = 3) -> tuple[str, ...]:
    """``("B1N5_ua_alpha_filt", …)`` for ``nodes`` = (blade, node) pairs, 0-based; node-major, suffixes inner
    (``UA_Mod`` 4 and 6: the continuous states ``x1`` … ``x4`` of :mod:`.ua_continuous`)."""
    from .ua_continuous import CONTINUOUS_MODES

    suffixes = STATE_SUFFIXES if int(mode) == 3 else CONTINUOUS_MODES[int(mode)]
    return tuple(f"B{b + 1}N{j + 1}_ua_{s}" for b, j in nodes for s in suffixes)


@dataclass(frozen=True, eq=False)
class UnsteadyNodes:
    """Constants of the nodes that run UA (one entry per node, in the order of the states).

    Attributes
    ----------
    chord : ndarray (m,)
        Chord [m].
    params : dict of str to ndarray (m,)
        :data:`UA_PARAMETERS` of each node's airfoil (angles [rad], ``C_nalpha`` [1/rad]).
    dt : float
        AeroDyn's step Δ (``DTAero``) [s].
    speed_of_sound : float
        ``a`` [m/s] (the deck's ``SpdSound``).
    has_cm : bool
        The polars have a Cm column (AeroDyn ``InCol_Cm > 0``); else Cm = 0 as AeroDyn sets it.
    index : ndarray of int (m,)
        Each node's place among all nodes of all blades (blade by blade).
    node : ndarray of int (m,)
        Each node's number on its blade (0-based: its polar).
    mode : int
        ``UA_Mod``: 3 (this module), 4 or 6 (:mod:`.ua_continuous`).
    """

    chord: np.ndarray
    params: dict
    dt: float
    speed_of_sound: float
    has_cm: bool = True
    index: np.ndarray | None = None
    node: np.ndarray | None = None
    mode: int = 3

    @property
    def continuous(self) -> bool:
        """``UA_Mod`` 4 or 6: continuous states (:mod:`.ua_continuous`), not the discrete recursion."""
        return int(self.mode) != 3

    @property
    def size(self) -> int:
        """Number of nodes."""
        return int(np.size(self.chord))


def _exp_eqn(step: Any, tau: Any, y_prev: Any, x: Any, x_prev: Any) -> Any:
    """AeroDyn's deficiency recursion ``Y e^{-step/τ} + (x - x_prev) e^{-step/(2τ)}``."""
    e = -step / tau
    return y_prev * ca.exp(e) + (x - x_prev) * ca.exp(0.5 * e)


def _blend_cosine(x: Any, lower: Any, upper: Any) -> Any:
    """0 below ``lower``, 1 above ``upper``, a half cosine between (NWTC ``BlendCosine``)."""
    width = ca.fmax(upper - lower, 1e-12)
    s = 0.5 * (1.0 - ca.cos((x - lower) / width * math.pi))
    return ca.if_else(x >= upper, 1.0, ca.if_else(x <= lower, 0.0, s))


def _separation(static: Callable, alpha: Any, p: dict, cna_c: Any) -> tuple[Any, Any, Any]:
    """``f`` (Cn), its ``cn_fs`` and ``f_c`` (Cc) of the static polar at ``alpha`` (AeroDyn's FLookup)."""
    coef = static(alpha)
    d_alpha = alpha - p["alpha0"]
    cn = coef["cl"] * ca.cos(alpha) + (coef["cd"] - p["Cd0"]) * ca.sin(alpha)
    cc = coef["cl"] * ca.sin(alpha) - (coef["cd"] - p["Cd0"]) * ca.cos(alpha)
    denom = cna_c * d_alpha
    safe = ca.if_else(ca.fabs(denom) < 1e-12, 1e-12, denom)
    root = ca.fmax(cn / safe, 0.0)
    f = ca.fmin((2.0 * ca.sqrt(root) - 1.0) ** 2, 1.0)
    one = ca.fabs(f - 1.0) <= _EQ_TOL * ca.fmax(ca.fabs(f + 1.0), 1.0)
    cn_fs = ca.if_else(one, 0.0, (cn - denom * f) / ca.if_else(one, 1.0, 1.0 - f))
    dc = denom * ca.tan(alpha)
    degenerate = (ca.fabs(alpha) <= _EQ_TOL_SINGLE) + \
        (ca.fabs(d_alpha) <= _EQ_TOL_SINGLE * ca.fmax(ca.fabs(alpha + p["alpha0"]), 1.0))
    f_c = ca.if_else(degenerate + (ca.fabs(dc) < 1e-12), _FC_LIMIT,
                     ca.fmin(_FC_LIMIT, (cc / ca.if_else(ca.fabs(dc) < 1e-12, 1.0, dc) + _GONZALEZ) ** 2))
    return f, cn_fs, f_c


def kelvin_chain(nodes: UnsteadyNodes, alpha: Any, speed: Any, states: Any, static: Callable,
                 static_cm: Callable, update: tuple[Any, Any] | None = None) -> dict[str, Any]:
    """One AeroDyn step of every UA node: coefficients now and the states of the next step.

    Parameters
    ----------
    nodes : UnsteadyNodes
    alpha : SX (m, 1)
        Angle of attack [rad] (AeroDyn's ``φ - θ``).
    speed : SX (m, 1)
        Relative speed U [m/s].
    states : SX (25 m, 1)
        The states, node-major (:data:`STATE_SUFFIXES` inner).
    static : callable
        ``alpha (m, 1) -> {"cl", "cd", "cm"}`` of the static polars of the same nodes.
    static_cm : callable
        ``alpha -> cm`` (the polar's moment column; zeros where it has none).
    update : pair of SX (m, 1), optional
        The angle of attack [rad] and speed [m/s] the states' update sees, when they differ from the outputs'
        (AeroDyn v5 updates with the wind of the step's end: :mod:`module docstring <.unsteady>`); default the same.

    Returns
    -------
    dict
        ``cl``, ``cd``, ``cm`` (m, 1); ``next`` (25 m, 1): the states after the step; ``states_dot`` (25 m, 1):
        ``(next - states) / Δ``; ``weight`` (m, 1): the share of UA in the blend with the static polar.
    """
    p = {k: ca.DM(np.asarray(v, dtype=float).reshape(-1, 1)) for k, v in nodes.params.items()}
    c = ca.DM(np.asarray(nodes.chord, dtype=float).reshape(-1, 1))
    out = _step(p, c, float(nodes.dt), float(nodes.speed_of_sound), nodes.has_cm, alpha, speed, states, static,
                static_cm, update)
    out["states_dot"] = (out["next"] - states) / float(nodes.dt)
    return out


def kelvin_chain_mapped(nodes: UnsteadyNodes, alpha: Any, speed: Any, states: Any, polars: Any,
                        update: tuple[Any, Any] | None = None) -> dict[str, Any]:
    """:func:`kelvin_chain` as one node's SX Function mapped over the nodes (a loop in generated code).

    The same expressions, built once: the airfoil's constants, chord and airfoil number are the mapped Function's
    inputs and the static polars are read by airfoil number (``NodePolars.by_airfoil``, the "spline" tables). The
    rotor's compiled code holds one node's chain instead of every node's (the IEA 15 MW rotor: 99 k instead of 193 k
    instructions), for the same numbers (tests/wind/blade/test_blade_unsteady.py).
    """
    m = nodes.size
    f = _node_function(nodes, polars, update is not None)
    params = np.vstack([np.asarray(nodes.params[k], dtype=float).reshape(1, -1) for k in UA_PARAMETERS] +
                       [np.asarray(nodes.chord, dtype=float).reshape(1, -1),
                        polars.airfoil_index[np.asarray(nodes.node, dtype=int)].reshape(1, -1).astype(float)])
    args = [alpha.T, speed.T, ca.reshape(states, len(STATE_SUFFIXES), m), ca.DM(params)]
    out = _mapped(f, m)(*args, *([update[0].T, update[1].T] if update is not None else []))
    nxt = ca.vec(out[0])
    return {"cl": out[1].T, "cd": out[2].T, "cm": out[3].T, "weight": out[4].T, "next": nxt,
            "states_dot": (nxt - states) / float(nodes.dt)}


def _mapped(f: ca.Function, m: int) -> ca.Function:
    """``f`` mapped over ``m`` nodes as an MX Function that SX graphs keep as one call node (a loop in C)."""
    args = [ca.MX.sym(f.name_in(i), f.size1_in(i), m) for i in range(f.n_in())]
    return ca.Function(f"ua_nodes_{m}", args, f.map(m)(*args), {"never_inline": True})


def _node_function(nodes: UnsteadyNodes, polars: Any, separate_update: bool) -> ca.Function:
    """One node's step ``(alpha, U, z (25), constants (22)[, alpha_update, U_update]) -> (next, cl, cd, cm,
    weight)`` (cached per polars)."""
    key = (float(nodes.dt), float(nodes.speed_of_sound), bool(nodes.has_cm), separate_update)
    cache = polars.__dict__.setdefault("_ua_node", {})
    if key in cache:
        return cache[key]
    a, u, z = ca.SX.sym("alpha"), ca.SX.sym("U"), ca.SX.sym("z", len(STATE_SUFFIXES))
    c = ca.SX.sym("constants", len(UA_PARAMETERS) + 2)
    p = {k: c[i] for i, k in enumerate(UA_PARAMETERS)}
    airfoil = c[len(UA_PARAMETERS) + 1]
    static = lambda x: polars.by_airfoil(x, airfoil)              # noqa: E731
    extra = [ca.SX.sym("alpha_update"), ca.SX.sym("U_update")] if separate_update else []
    out = _step(p, c[len(UA_PARAMETERS)], key[0], key[1], key[2], a, u, z, static, lambda x: static(x)["cm"],
                tuple(extra) or None)
    f = ca.Function("ua_node", [a, u, z, c, *extra], [out["next"], out["cl"], out["cd"], out["cm"], out["weight"]],
                    ["alpha", "U", "z", "constants", *["alpha_update", "U_update"][:len(extra)]],
                    ["next", "cl", "cd", "cm", "weight"])
    cache[key] = f
    return f


def _step(p: dict, c: Any, dt: float, a_s: float, has_cm: bool, alpha: Any, speed: Any, states: Any,
          static: Callable, static_cm: Callable, update: tuple[Any, Any] | None = None) -> dict[str, Any]:
    """The step of :func:`kelvin_chain` on columns of constants ``p`` and chords ``c`` (DM or SX)."""
    m = alpha.size1()
    s = ca.reshape(states, len(STATE_SUFFIXES), m).T
    old = {name: s[:, k] for k, name in enumerate(STATE_SUFFIXES)}
    alpha, u = _wrap(alpha), ca.fmax(speed, U_MIN)
    kc = _chain(p, old, alpha, u, c, dt, a_s, static)
    out = _coefficients(p, old, kc, alpha, u, static, static_cm, has_cm)
    if update is not None:                   # AeroDyn v5: the update's inputs carry the wind of the step's end
        kc = _chain(p, old, _wrap(update[0]), ca.fmax(update[1], U_MIN), c, dt, a_s, static)
    new = _other_states(p, old, kc)
    out["next"] = ca.reshape(ca.horzcat(*[new[name] for name in STATE_SUFFIXES]).T, -1, 1)
    return out


def _wrap(alpha: Any) -> Any:
    """α into [-π, π) (AeroDyn's ``MPi2Pi``)."""
    return alpha - 2.0 * math.pi * ca.floor((alpha + math.pi) / (2.0 * math.pi))


def _chain(p: dict, old: dict, alpha: Any, u: Any, c: Any, dt: float, a_s: float, static: Callable) -> dict:
    """The Kelvin chain of one step (the quantities ``ComputeKelvinChain`` returns for UA_Mod 3)."""
    mach = u / a_s
    beta2 = 1.0 - mach**2
    beta = ca.sqrt(beta2)
    cna_c = p["C_nalpha"] / beta
    ds = 2.0 * u * dt / c
    cutoff = ca.fmax(1.0, u) * p["filtCutOff"] / math.pi / c
    lp = ca.exp(-2.0 * math.pi * dt * cutoff)
    k = {"ds": ds, "cna_c": cna_c}
    k["alpha_filt"] = lp * old["alpha_filt"] + (1.0 - lp) * alpha
    d_filt = k["alpha_filt"] - old["alpha_filt"]
    k["dalpha0"] = k["alpha_filt"] - p["alpha0"]
    k["q"] = d_filt / dt * c / u
    k["q_f"] = lp * old["q_f"] + (1.0 - lp) * k["q"]
    k["Kalpha_f"] = k["q_f"] * u / c
    k["Kq_f"] = lp * old["Kq_f"] + (1.0 - lp) * (k["q"] - old["q"]) / dt
    ab = p["A1"] * p["b1"] + p["A2"] * p["b2"]
    k_alpha = 1.0 / ((1.0 - mach) + 0.5 * p["C_nalpha"] * mach**2 * beta * ab)
    k_q = 1.0 / ((1.0 - mach) + p["C_nalpha"] * mach**2 * beta * ab)
    t_i = c / a_s
    t_alpha, t_q = 0.75 * t_i * k_alpha, 0.75 * t_i * k_q
    k["T_f"] = p["T_f0"] / old["sigma1"]
    k["Kp_alpha"] = _exp_eqn(dt, t_alpha, old["Kp_alpha"], k["Kalpha_f"], old["Kalpha_f"])
    k["Cn_alpha_nc"] = 4.0 * t_alpha * (k["Kalpha_f"] - k["Kp_alpha"]) / mach
    k["Kp_q"] = _exp_eqn(dt, t_q, old["Kp_q"], k["Kq_f"], old["Kq_f"])
    cn_q_nc = -t_q * (k["Kq_f"] - k["Kp_q"]) / mach
    cn_aq_nc = k["Cn_alpha_nc"] + cn_q_nc
    k["X1"] = _exp_eqn(ds * beta2 * p["b1"], 1.0, old["X1"], p["A1"] * d_filt, 0.0)
    k["X2"] = _exp_eqn(ds * beta2 * p["b2"], 1.0, old["X2"], p["A2"] * d_filt, 0.0)
    k["alpha_e"] = k["dalpha0"] - k["X1"] - k["X2"]
    k["Cn_aq_circ"] = cna_c * k["alpha_e"]
    d_qf = k["q_f"] - old["q_f"]
    k["K3p_q"] = _exp_eqn(p["b5"] * beta2 * ds, 1.0, old["K3p_q"], p["A5"] * d_qf, 0.0)
    k["Cm_q_circ"] = -p["C_nalpha"] * (k["q_f"] - k["K3p_q"]) * c / (16.0 * beta * u)
    k["Cn_pot"] = k["Cn_aq_circ"] + cn_aq_nc
    k_mq = 7.0 / (15.0 * (1.0 - mach) + 1.5 * p["C_nalpha"] * p["A5"] * p["b5"] * beta * mach**2)
    k["Kpp_q"] = _exp_eqn(dt, k_mq**2 * t_i, old["Kpp_q"], k["Kq_f"], old["Kq_f"])
    k["Cm_q_nc"] = -cn_q_nc / 4.0 - k_alpha**2 * t_i * (k["Kq_f"] - k["Kpp_q"]) / (3.0 * mach)
    k["Cc_pot"] = k["Cn_aq_circ"] * ca.tan(k["alpha_e"] + p["alpha0"])
    k["Dp"] = _exp_eqn(ds, p["T_p"], old["Dp"], k["Cn_pot"], old["Cn_pot"])
    k["Cn_prime"] = k["Cn_pot"] - k["Dp"]
    k["alpha_f"] = k["Cn_prime"] / cna_c + p["alpha0"]
    k["fp"], _, k["fp_c"] = _separation(static, k["alpha_f"], p, cna_c)
    k["Df"] = _exp_eqn(ds, k["T_f"], old["Df"], k["fp"], old["fp"])
    k["fpp"] = k["fp"] - k["Df"]
    k["Df_c"] = _exp_eqn(ds, p["T_f0"], old["Df_c"], k["fp_c"], old["fp_c"])        # σ₁c = 1 for UA_Mod 3
    k["fpp_c"] = k["fp_c"] - k["Df_c"]
    _, cn_fs, _ = _separation(static, k["alpha_e"] + p["alpha0"], p, cna_c)
    k["Cn_FS"] = cn_aq_nc + cna_c * k["alpha_e"] * k["fpp"] + cn_fs * (1.0 - k["fpp"])
    k["Dalphaf"] = _exp_eqn(ds, 0.1 * k["T_f"], old["Dalphaf"], k["alpha_f"], old["alpha_f"])
    k["C_V"] = k["Cn_aq_circ"] * (1.0 - (0.5 + 0.5 * ca.sqrt(ca.fmax(k["fpp"], 0.0))) ** 2)
    t_v = p["T_V0"] / old["sigma3"]
    decay = (old["tau_V"] > p["T_VL"]) * (k["Kalpha_f"] * k["dalpha0"] > 0)
    cn_v = ca.if_else(decay, old["Cn_v"] * ca.exp(-ds / t_v), _exp_eqn(ds, t_v, old["Cn_v"], k["C_V"], old["C_V"]))
    k["Cn_v"] = ca.fmax(cn_v, 0.0)
    return k


def _other_states(p: dict, old: dict, k: dict) -> dict:
    """The states after the step: σ₁, σ₃ and τ_V by AeroDyn's rules for UA_Mod 3, the rest from the chain."""
    lesf = (k["Cn_prime"] > p["Cn1"]) + (k["Cn_prime"] < p["Cn2"]) > 0
    tesf = k["fpp"] < old["fpp"]
    tau = old["tau_V"]
    vrtx = (tau <= p["T_VL"]) * (tau > 0)
    ka = k["Kalpha_f"] * k["dalpha0"]
    separating = ca.if_else(ka < 0, 2.0, ca.if_else(lesf < 1, 1.0, ca.if_else(old["fpp"] <= 0.7, 2.0, 1.75)))
    reattaching = ca.if_else(ka > 0, 0.75, ca.if_else(vrtx, 0.25, ca.if_else(lesf < 1, 0.5, 1.0)))
    sigma1 = ca.if_else(tesf, separating, reattaching)
    past = (tau <= 2.0 * p["T_VL"]) * (tau >= p["T_VL"])
    sigma3 = ca.if_else(past, ca.if_else(tesf, 3.0, 4.0),
                        ca.if_else(vrtx, ca.if_else(ka < 0, 2.0, 1.0), ca.if_else(ka < 0, 4.0, 1.0)))
    sigma3 = ca.if_else((tesf < 1) * (k["Kq_f"] * k["dalpha0"] < 0), 1.0, sigma3)
    t_sh = 2.0 * (1.0 - k["fpp"]) / p["St_sh"]
    tau_new = ca.if_else((tau > 0) + lesf > 0, tau + k["ds"], tau)
    tau_new = ca.if_else((tau_new >= p["T_VL"] + t_sh) * tesf, 0.0, tau_new)
    new = {name: k[name] for name in STATE_SUFFIXES if name in k}
    new.update(tau_V=tau_new, sigma1=sigma1, sigma3=sigma3)
    return new


def _coefficients(p: dict, old: dict, k: dict, alpha: Any, u: Any, static: Callable, static_cm: Callable,
                  has_cm: bool) -> dict:
    """Cl, Cd, Cm of the step (``UA_CalcOutput`` for UA_Mod 3 with FLookup) and the blend to the static polar."""
    tau = old["tau_V"]
    cn = k["Cn_FS"] + ca.if_else(tau > 0, k["Cn_v"], 0.0)
    cc = k["Cc_pot"] * (ca.sqrt(ca.fmax(k["fpp_c"], 0.0)) - _GONZALEZ) + \
        k["Cn_v"] * k["alpha_e"] * (1.0 - tau / p["T_VL"])
    ca_, sa = ca.cos(alpha), ca.sin(alpha)
    cl = cn * ca_ + cc * sa
    cd = cn * sa - cc * ca_ + p["Cd0"]
    if has_cm:
        cm_fs = static_cm(k["alpha_f"] - k["Dalphaf"]) + k["Cm_q_circ"] - k["Cn_alpha_nc"] / 4.0 + k["Cm_q_nc"]
        cm = cm_fs - p["x_cp_bar"] * (1.0 - ca.cos(math.pi * tau / p["T_VL"])) * k["Cn_v"]
    else:
        cm = ca.SX.zeros(alpha.size1(), 1)
    weight = (1.0 - _blend_cosine(ca.fabs(alpha), p["UACutout_blend"], p["UACutout"])) * \
        _blend_cosine(u, U_MIN, 1.0)
    steady = static(alpha)
    steady["cm"] = steady["cm"] if has_cm else 0.0 * alpha
    ua = {"cl": cl, "cd": cd, "cm": cm}                   # off (weight 0): the static polar, whatever UA's values
    out = {key: ca.if_else(weight > 0, weight * ua[key] + (1.0 - weight) * steady[key], steady[key])
           for key in ua}
    out["weight"] = weight
    return out


def steady_states(nodes: UnsteadyNodes, alpha: Any, speed: Any, static: Callable) -> Any:
    """The states at rest for constant ``alpha`` [rad] and ``speed`` [m/s]: the recursion's fixed point.

    With α and U constant the filters hold α, every rate and lag is zero and ``α_f = α_e + α₀ = α``;
    ``f' = f'' = f(α)``, ``f'_c`` likewise, ``C_V`` at its value, no vortex lift (``Cn_v = 0``), σ₃ = 1 and
    σ₁ = 0.5 (1 where the leading edge has separated, ``Cn' > Cn1`` or ``< Cn2``): AeroDyn's rules for a flow that
    neither separates further nor moves. A node whose leading edge has separated at rest has no fixed point: its
    vortex clock runs; it starts one step in (``τ_V = ds``), as after OpenFAST's first update.

    Parameters
    ----------
    nodes : UnsteadyNodes
    alpha, speed : SX or DM (m, 1)
        Angle of attack [rad] and relative speed [m/s].
    static : callable
        ``alpha (m, 1) -> {"cl", "cd", "cm"}`` of the static polars of the same nodes.

    Returns
    -------
    SX or DM (25 m, 1)
    """
    p = {k: ca.DM(np.asarray(v, dtype=float).reshape(-1, 1)) for k, v in nodes.params.items()}
    alpha, u = _wrap(alpha), ca.fmax(speed, U_MIN)
    mach = u / float(nodes.speed_of_sound)
    cna_c = p["C_nalpha"] / ca.sqrt(1.0 - mach**2)
    f, _, f_c = _separation(static, alpha, p, cna_c)
    cn = cna_c * (alpha - p["alpha0"])
    lesf = (cn > p["Cn1"]) + (cn < p["Cn2"]) > 0
    zero = 0.0 * alpha
    values = {name: zero for name in STATE_SUFFIXES}
    chord = ca.DM(np.asarray(nodes.chord, dtype=float).reshape(-1, 1))
    values.update(alpha_filt=alpha, Cn_pot=cn, fpp=f, fp=f, fp_c=f_c, alpha_f=alpha,
                  C_V=cn * (1.0 - (0.5 + 0.5 * ca.sqrt(ca.fmax(f, 0.0))) ** 2),
                  sigma1=ca.if_else(lesf, 1.0, 0.5), sigma3=zero + 1.0,
                  tau_V=ca.if_else(lesf, 2.0 * u * float(nodes.dt) / chord, 0.0))
    return ca.reshape(ca.horzcat(*[values[name] for name in STATE_SUFFIXES]).T, -1, 1)


def unsteady_nodes(aerodyn: Any, bem: Any, n_blades: int, *, dt: float | None,
                   speed_of_sound: float | None) -> UnsteadyNodes | None:
    """The UA nodes of an AeroDyn 15 input as OpenFAST v5 runs it (None when ``UA_Mod = 0``).

    UA runs on a node unless (AeroDyn.f90 ``Init_BEMTmodule``, UnsteadyAero.f90 ``UA_SetParameters``): its
    undeflected local radius over the largest is below ``UAStartRad`` (it and every node inside the last such
    one) or above ``UAEndRad`` (it and every node outside the first such one); its polar is constant (AeroDyn's
    ``ConstData``); or its ``C_nalpha`` is 0. The airfoil constants are the file's, or AeroDyn's defaults
    (:mod:`mbsym.wind.deck.airfoil_ua`).

    Parameters
    ----------
    aerodyn : AeroDynInput
    bem : BEMRotor
        The rotor's geometry and per-node polars (``AirfoilPolar.ua``).
    n_blades : int
    dt : float or None
        AeroDyn's step [s] (``DTAero``, "default" = the glue code's ``DT``).
    speed_of_sound : float or None
        ``SpdSound`` [m/s] (the ``.fst``'s in OpenFAST v5, AeroDyn's in older decks).

    Raises
    ------
    UnsupportedFeatureError
        ``UA_Mod`` other than 0, 3, 4 and 6, or ``FLookup = False``.
    ParameterError
        UA on without a positive ``dt`` or ``speed_of_sound``.
    """
    from ....exceptions import ParameterError, UnsupportedFeatureError
    from . import ua_continuous

    mode = int(aerodyn.unsteady_model)
    if mode == 0:
        return None
    extra = {k.lower(): v for k, v in dict(aerodyn.extra or {}).items()}
    if mode not in (3, 4, 6):
        raise UnsupportedFeatureError(
            f"{aerodyn.source}: UA_Mod = {mode} is not modelled; mbsym runs 0 (steady polars), 3 (Beddoes-Leishman, "
            "Minnema/Pierce, OpenFAST's recursion), 4 (HGM) and 6 (Oye). Refused: UA_Mod 2 (Gonzalez), 5 (HGM with "
            "vortex: Cn-based columns and a vortex switch AeroDyn updates after each step, not validated) and 7 "
            "(Boeing-Vertol: a discrete model, alpha rate by finite difference over DTAero). Set UA_Mod to 0, 3, 4 "
            "or 6.")
    if str(extra.get("flookup", "true")).strip().strip('"').lower() in ("false", "f", "0"):
        raise UnsupportedFeatureError(f"{aerodyn.source}: FLookup = False (the best-fit f curves of S1..S4) is not "
                                      f"modelled with UA_Mod {mode} (OpenFAST v5 refuses it too); set FLookup = True "
                                      "(the separation point from the polar).")
    if mode != 3:                # AeroDyn integrates these states itself; mbsym's integrator does (.ua_continuous)
        method = str(extra.get("integrationmethod", "3")).strip().strip('"').lower()
        if method not in ("1", "2", "3", "4", "default"):
            raise ParameterError(f"{aerodyn.source}: IntegrationMethod = {method!r}: must be 1 (RK4), 2 (AB4), "
                                 "3 (ABM4) or 4 (BDF2).")
    for value, name in ((dt, "dt (DTAero)"), (speed_of_sound, "speed_of_sound (SpdSound)")):
        if value is None or not (math.isfinite(float(value)) and float(value) > 0):
            raise ParameterError(f"{aerodyn.source}: UA_Mod {mode} needs a positive {name}; got {value!r}.")
    radius = np.asarray(bem.local_radius, dtype=float)
    frac = radius / radius.max()
    start, end = (_fraction(extra, key, default) for key, default in (("uastartrad", 0.0), ("uaendrad", 1.0)))
    inner = np.flatnonzero(frac < start)
    outer = np.flatnonzero(frac > end)
    on = np.ones(radius.size, dtype=bool)
    if inner.size:
        on[: inner.max() + 1] = False
    if outer.size:
        on[outer.min():] = False
    for j, polar in enumerate(bem.polars):
        coef = getattr(polar, "ua", None)
        slope = "C_nalpha" if mode == 3 else "C_lalpha"       # UA_TurnOff_param
        if getattr(polar, "constant_data", False) or coef is None or getattr(coef, slope) == 0.0:
            on[j] = False
        elif mode != 3 and not np.any(ua_continuous.separation_columns(polar.alpha, polar.cl, coef)[0] != 0.0):
            on[j] = False                                      # separation function 0 at all angles
    per_blade = np.flatnonzero(on)
    if per_blade.size == 0:
        return None
    keys = UA_PARAMETERS if mode == 3 else ua_continuous.PARAMETERS
    params = {k: np.array([float(getattr(bem.polars[j].ua, k)) for j in per_blade]) for k in keys}
    index = np.concatenate([b * radius.size + per_blade for b in range(n_blades)])
    params = {k: np.tile(v, n_blades) for k, v in params.items()}
    has_cm = len(aerodyn.airfoil_columns) > 3 and int(aerodyn.airfoil_columns[3] or 0) > 0
    return UnsteadyNodes(chord=np.tile(np.asarray(bem.chord, float)[per_blade], n_blades), params=params,
                         dt=float(dt), speed_of_sound=float(speed_of_sound), has_cm=has_cm, index=index,
                         node=np.tile(per_blade, n_blades), mode=mode)


def _fraction(extra: dict, key: str, default: float) -> float:
    from ....exceptions import ParameterError

    text = extra.get(key)
    if text is None or str(text).strip().strip('"').lower() == "default":
        return default
    try:
        value = float(str(text).strip().strip('"'))
    except ValueError:
        raise ParameterError(f"AeroDyn {key}: expected a fraction of the rotor radius in [0, 1]; "
                             f"got {text!r}.") from None
    if not 0.0 <= value <= 1.0:
        raise ParameterError(f"AeroDyn {key} = {value!r}: must be in [0, 1] (a fraction of the rotor radius).")
    return value
