"""AeroDyn's continuous-state unsteady airfoil models ``UA_Mod = 4`` (HGM) and ``UA_Mod = 6`` (Øye) per blade node.

OpenFAST v5 numbers its UA models 2 (Gonzalez), 3 (Minnema/Pierce: :mod:`.unsteady`), 4 (HGM, Hansen–Gaunaa–Madsen,
four continuous states), 5 (HGM with a vortex state), 6 (Øye, one state), 7 (Boeing–Vertol, discrete) and 8
(HGM-360, refused by OpenFAST itself); ``UnsteadyAero_Types.f90``. This module models 4 and 6 from the facts of
UnsteadyAero.f90 v5.0.0 (``UA_CalcContStateDeriv``, ``UA_CalcOutput``, ``HGM_Steady``, ``Get_HGM_constants``,
``Get_alphaF``, ``UA_BlendSteady``/``UA_BlendSteadyStates``) and AirfoilInfo.f90 (``ComputeUASeparationFunction_onCl``,
``ComputeUASeparationFunction_zero``), written here with its own names:

* inputs of a node: angle of attack α, relative speed U (floored at 0.01 m/s) and ω, the rotation rate of the node's
  section about AeroDyn's annulus z axis (BEMT ``omega_z``: pitch rate, cone × rotor speed, structural rates);
* ``T_u = c / (2U)`` (clipped to [0.001, 50] s), the 3/4-chord angle ``α₃₄ = atan2(U sin α + ω c/2, U cos α)``,
  ``T_u ω`` clipped to ±1.5;
* HGM states ``x1, x2`` (shed-wake lag, ``ẋ_k = b_k/T_u (A_k α₃₄ − x_k)``), ``x3`` (lagged circulatory lift,
  ``ẋ3 = (C_lα (α_E − α₀) + π T_u ω − x3)/(T_p T_u)``, ``α_E = α₃₄ (1 − A1 − A2) + x1 + x2``) and ``x4`` (separation
  point, ``ẋ4 = (f_st(α_F) − x4)/(T_f0 T_u)``, ``α_F = x3/C_lα + α₀``); Øye keeps only ``x4`` with ``α_F = α₃₄``;
* the separation function ``f_st`` and the fully separated lift ``Cl_fs`` are columns AeroDyn adds to each polar
  from Cl (:func:`separation_columns`), interpolated like the polar;
* outputs (HGM) ``Cl = x4 Cl_fa + (1 − x4) Cl_fs + π T_u ω``, ``Cd = Cd(α_E) + (α₃₄ − α_E) Cl_c + (Cd(α_E) − Cd0)
  ΔC_d'' + Cl_c T_u ω``, ``Cm = Cm(α_E) − π/2 T_u ω``; Øye ``Cl = x4 Cl_fa + (1 − x4) Cl_fs`` at α₃₄ with the static
  Cd and Cm there; then AeroDyn's cosine blend to the static polar (``UACutout_blend`` … ``UACutout`` in |α|, 0.01 …
  1 m/s in U). Where the weight is below 1, AeroDyn also pulls the states towards their steady values after every
  step (``x ← w x + (1 − w) x_ss``); here that is the relaxation ``−(1 − w)(x − x_ss)/Δ`` added to ``ẋ``.

**Integration.** AeroDyn integrates these states inside its own update (``IntegrationMethod``: RK4, AB4, ABM4 or
BDF2 over ``DTAero``, the inputs interpolated between the step's two input times). In mbsym they are continuous
states of the composed model integrated by the simulation's integrator; the blade-element graph evaluates their
derivative at the live states with the held part's inputs (``rk4-held``: RK4 stages with α, U, ω held over the step,
so the deck's ``IntegrationMethod`` is read and checked but the integrator is mbsym's). As for ``UA_Mod 3`` the
inputs of the derivative carry the wind of the step's end (``ua_step_end_wind``). The steady states are
``HGM_Steady``'s; there the outputs are the static polar (up to the interpolation of ``f_st``, ``Cl_fs`` between
table points and where ``f_st`` is clipped to [0, 1]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

__all__ = ["CONTINUOUS_MODES", "PARAMETERS", "state_suffixes", "separation_columns", "SeparationPolar",
           "node_function", "steady_node_function", "rates",
           "separation_polars", "constants", "evaluate", "steady"]

#: The continuous UA models and their states (AeroDyn's ``x%element%x`` entries that move).
CONTINUOUS_MODES = {4: ("x1", "x2", "x3", "x4"), 6: ("x4",)}
#: Airfoil constants the models read (:class:`~mbsym.wind.deck.airfoil_ua.UACoefficients` attributes).
PARAMETERS = ("alpha0", "C_lalpha", "T_f0", "T_p", "A1", "A2", "b1", "b2", "Cd0", "UACutout", "UACutout_blend")
_U_MIN = 0.01                 # UnsteadyAero.f90 UA_u_min [m/s]
_MAX_TU_OMEGA = 1.5           # UnsteadyAero.f90 MaxTuOmega
_D34 = 0.5                    # AeroDyn_IO.f90: d_34_to_ac (fraction of chord), not a deck key
_EPS = 50.0 * float(np.finfo(np.float64).eps)


def state_suffixes(mode: int) -> tuple[str, ...]:
    """The states of one node for ``UA_Mod = mode`` (4 or 6)."""
    return CONTINUOUS_MODES[int(mode)]


def _equal(a: float, b: float) -> bool:
    return abs(a - b) <= max(abs(a + b), 1.0) * _EPS


def separation_columns(alpha: np.ndarray, cl: np.ndarray, ua: Any) -> tuple[np.ndarray, np.ndarray]:
    """AeroDyn's ``f_st`` and ``Cl_fs`` columns of a polar for the Cl-based models (HGM, Øye).

    From the table's Cl, ``C_lalpha``, ``alpha0`` and the attached region ``alphaLower``/``alphaUpper``
    (AirfoilInfo.f90: Kirchhoff inversion ``f = (2√(Cl/Cl_fa) − 1)²``, ``Cl_fs = (Cl − Cl_fa f)/(1 − f)``, ``Cl/2``
    where ``f`` reaches 1; zero separation function and ``Cl_fs = Cl`` beyond the minima of ``f`` outside the
    attached region; then ``f`` recomputed as ``(Cl − Cl_fs)/(Cl_fa − Cl_fs)`` clipped to [0, 1]).
    """
    alpha, cl = np.asarray(alpha, dtype=float), np.asarray(cl, dtype=float)
    cla, a0 = float(ua.C_lalpha), float(ua.alpha0)
    n = alpha.size
    if _equal(cla, 0.0):
        return np.zeros(n), cl.copy()
    f, fs = np.empty(n), np.empty(n)
    for r in range(n):
        if _equal(alpha[r], a0):
            f[r], fs[r] = 1.0, cl[r] / 2.0
            continue
        ratio = max(0.0, cl[r] / (cla * (alpha[r] - a0)))
        value = (2.0 * math.sqrt(ratio) - 1.0) ** 2
        if value < 1.0:
            f[r] = max(0.0, value)
            fs[r] = (cl[r] - cla * (alpha[r] - a0) * f[r]) / (1.0 - f[r])
        else:
            f[r], fs[r] = 1.0, cl[r] / 2.0
    low = np.flatnonzero(alpha < ua.alphaLower)
    high = np.flatnonzero(alpha > ua.alphaUpper)
    if low.size:                                  # the last row of the minimum of f below the attached region
        i_low = int(low[f[low] == f[low[np.argmin(f[low])]]].max())
        f[:i_low + 1], fs[:i_low + 1] = 0.0, cl[:i_low + 1]
    if high.size:                                 # the first row of the minimum above it
        i_high = int(high[np.argmin(f[high])])
        f[i_high:], fs[i_high:] = 0.0, cl[i_high:]
    for r in range(n):
        inv = cla * (alpha[r] - a0)
        f[r] = 1.0 if _equal(inv, fs[r]) else min(1.0, max(0.0, (cl[r] - fs[r]) / (inv - fs[r])))
    return f, fs


@dataclass(frozen=True, eq=False)
class SeparationPolar:
    """``f_st`` and ``Cl_fs`` of one airfoil as a polar-like record (``cl`` = f_st, ``cd`` = Cl_fs, ``cm`` = 0), so
    that :class:`~.polars.NodePolars` interpolates them exactly as it does the polar (linear or spline)."""

    alpha: np.ndarray
    cl: np.ndarray
    cd: np.ndarray
    cm: np.ndarray

    @classmethod
    def of(cls, polar: Any) -> "SeparationPolar":
        if polar.ua is None:                    # constant data: UA is off on its nodes
            f, fs = np.zeros(np.size(polar.alpha)), np.asarray(polar.cl, float)
        else:
            f, fs = separation_columns(polar.alpha, polar.cl, polar.ua)
        return cls(np.asarray(polar.alpha, float), f, fs, np.zeros_like(f))


def _near(reference: Any, angle: Any) -> Any:
    """``angle`` moved by a multiple of 2π to within π of ``reference`` (AeroDyn's ``AddOrSub2Pi``)."""
    d = angle - reference
    return reference + d - 2.0 * math.pi * ca.floor((d + math.pi) / (2.0 * math.pi))


def _blend(x: Any, lower: Any, upper: Any) -> Any:
    width = ca.fmax(upper - lower, 1e-12)
    s = 0.5 * (1.0 - ca.cos((x - lower) / width * math.pi))
    return ca.if_else(x >= upper, 1.0, ca.if_else(x <= lower, 0.0, s))


def _kinematics(alpha: Any, speed: Any, omega: Any, chord: Any) -> dict:
    a = alpha - 2.0 * math.pi * ca.floor((alpha + math.pi) / (2.0 * math.pi))
    u = ca.fmax(speed, _U_MIN)
    tu = ca.fmin(ca.fmax(chord / (2.0 * u), 0.001), 50.0)
    a34 = ca.atan2(u * ca.sin(a) + omega * _D34 * chord, u * ca.cos(a))
    tuw = ca.fmin(ca.fmax(tu * omega, -_MAX_TU_OMEGA), _MAX_TU_OMEGA)
    return {"alpha": a, "u": u, "tu": tu, "a34": a34, "tuw": tuw}


def _steady(mode: int, p: dict, k: dict, sep: Any) -> dict:
    """``HGM_Steady``: the states at constant inputs."""
    a34 = k["a34"]
    return {"x1": p["A1"] * a34, "x2": p["A2"] * a34, "x3": p["C_lalpha"] * (a34 - p["alpha0"]),
            "x4": sep(a34)["cl"]}


def _node(mode: int, p: dict, chord: Any, has_cm: bool, dt: float, z: dict, alpha: Any, speed: Any, omega: Any,
          static: Any, sep: Any, rate_inputs: tuple | None) -> dict:
    """Outputs at ``(alpha, speed, omega)`` and the derivative at ``rate_inputs`` (default the same)."""
    k = _kinematics(alpha, speed, omega, chord)
    x4 = ca.fmin(ca.fmax(z["x4"], 0.0), 1.0)
    a34 = k["a34"]
    a_e = a34 * (1.0 - p["A1"] - p["A2"]) + z["x1"] + z["x2"] if mode == 4 else a34
    at_e, sep_e = static(a_e), sep(a_e)
    cl_fa = (_near(p["alpha0"], a_e) - p["alpha0"]) * p["C_lalpha"]
    cl_c = x4 * cl_fa + (1.0 - x4) * sep_e["cd"]
    if mode == 4:
        f_e = ca.fmin(ca.fmax(sep_e["cl"], 0.0), 1.0)
        d_cd = 0.5 * (ca.sqrt(f_e) - ca.sqrt(x4)) - 0.25 * (f_e - x4)
        cl = cl_c + math.pi * k["tuw"]
        cd = at_e["cd"] + (a34 - _near(a34, a_e)) * cl_c + (at_e["cd"] - p["Cd0"]) * d_cd + cl_c * k["tuw"]
        cm = at_e["cm"] - 0.5 * math.pi * k["tuw"]
    else:
        cl, cd, cm = cl_c, at_e["cd"], at_e["cm"]
    if not has_cm:
        cm = 0.0 * cl
    weight = (1.0 - _blend(ca.fabs(k["alpha"]), p["UACutout_blend"], p["UACutout"])) * _blend(k["u"], _U_MIN, 1.0)
    st = static(k["alpha"])
    out = {"cl": weight * cl + (1.0 - weight) * st["cl"], "cd": weight * cd + (1.0 - weight) * st["cd"],
           "cm": weight * cm + (1.0 - weight) * (st["cm"] if has_cm else 0.0), "weight": weight}
    out["rates"] = rates(mode, p, chord, dt, z, *(rate_inputs or (alpha, speed, omega)), sep)
    return out


def rates(mode: int, p: dict, chord: Any, dt: float, z: dict, alpha: Any, speed: Any, omega: Any, sep: Any) -> list:
    """``UA_CalcContStateDeriv`` plus the relaxation standing for ``UA_BlendSteadyStates`` (module docstring)."""
    k = _kinematics(alpha, speed, omega, chord)
    x4 = ca.fmin(ca.fmax(z["x4"], 0.0), 1.0)
    tu, a34 = k["tu"], k["a34"]
    weight = (1.0 - _blend(ca.fabs(k["alpha"]), p["UACutout_blend"], p["UACutout"])) * _blend(k["u"], _U_MIN, 1.0)
    ss = _steady(mode, p, k, sep)
    d = {}
    if mode == 4:
        for s, a_k, b_k in (("x1", p["A1"], p["b1"]), ("x2", p["A2"], p["b2"])):
            ref = ca.if_else(ca.fabs(a_k) > 0, z[s] / ca.if_else(ca.fabs(a_k) > 0, a_k, 1.0), a34)
            d[s] = b_k / tu * (a_k * _near(ref, a34) - z[s])
        a_e = a34 * (1.0 - p["A1"] - p["A2"]) + z["x1"] + z["x2"]
        clp = p["C_lalpha"] * (_near(p["alpha0"], a_e) - p["alpha0"]) + math.pi * k["tuw"]
        d["x3"] = (clp - z["x3"]) / (p["T_p"] * tu)
        a_f = z["x3"] / p["C_lalpha"] + p["alpha0"]
    else:
        a_f = a34
    d["x4"] = (sep(a_f)["cl"] - x4) / (p["T_f0"] * tu)
    return [d[s] - (1.0 - weight) * (z[s] - ss[s]) / dt for s in state_suffixes(mode)]


def node_function(mode: int, dt: float, has_cm: bool, static: Any, sep: Any, airfoil: Any = None) -> ca.Function:
    """One node's ``(alpha, U, omega, z, constants, alpha_rate, U_rate, omega_rate) -> (cl, cd, cm, weight, zdot)``
    with ``constants`` = :data:`PARAMETERS`, chord, airfoil number. ``static``, ``sep``: ``(alpha, airfoil) ->``
    ``{"cl", "cd", "cm"}`` of the polar and of :class:`SeparationPolar` (by airfoil number for the ``"spline"``
    tables, or of one fixed node)."""
    names = state_suffixes(mode)
    a, u, w = ca.SX.sym("alpha"), ca.SX.sym("U"), ca.SX.sym("omega")
    ar, ur, wr = ca.SX.sym("alpha_rate"), ca.SX.sym("U_rate"), ca.SX.sym("omega_rate")
    zs = ca.SX.sym("z", len(names))
    c = ca.SX.sym("constants", len(PARAMETERS) + 2)
    p = {key: c[i] for i, key in enumerate(PARAMETERS)}
    number = c[len(PARAMETERS) + 1]
    z = {s: 0.0 * a for s in ("x1", "x2", "x3", "x4")}
    z.update({s: zs[i] for i, s in enumerate(names)})
    out = _node(mode, p, c[len(PARAMETERS)], has_cm, dt, z, a, u, w, lambda x: static(x, number),
                lambda x: sep(x, number), (ar, ur, wr))
    return ca.Function(f"ua{mode}_node", [a, u, w, zs, c, ar, ur, wr],
                       [out["cl"], out["cd"], out["cm"], out["weight"], ca.vertcat(*out["rates"])],
                       ["alpha", "U", "omega", "z", "constants", "alpha_rate", "U_rate", "omega_rate"],
                       ["cl", "cd", "cm", "weight", "zdot"])


def steady_node_function(mode: int, sep: Any) -> ca.Function:
    """``(alpha, U, omega, constants) -> z`` at rest (``HGM_Steady``), one node; ``sep`` as in :func:`node_function`."""
    a, u, w = ca.SX.sym("alpha"), ca.SX.sym("U"), ca.SX.sym("omega")
    c = ca.SX.sym("constants", len(PARAMETERS) + 2)
    p = {key: c[i] for i, key in enumerate(PARAMETERS)}
    number = c[len(PARAMETERS) + 1]
    k = _kinematics(a, u, w, c[len(PARAMETERS)])
    ss = _steady(mode, p, k, lambda x: sep(x, number))
    return ca.Function(f"ua{mode}_steady", [a, u, w, c], [ca.vertcat(*[ss[s] for s in state_suffixes(mode)])])


def separation_polars(polars: Any) -> Any:
    """:class:`~.polars.NodePolars` of the :class:`SeparationPolar` of every node (same method and step as
    ``polars``, cached on it)."""
    from .polars import NodePolars

    cache = polars.__dict__.setdefault("_ua_separation", {})
    if "sep" not in cache:
        made: dict[int, SeparationPolar] = {}
        for p in polars.polars:
            if id(p) not in made:
                made[id(p)] = SeparationPolar.of(p)
        per_node = tuple(made[id(p)] for p in polars.polars)
        cache["sep"] = NodePolars(per_node, method=polars.method, step=polars.step)
    return cache["sep"]


def constants(ua: Any, polars: Any) -> np.ndarray:
    """(len(PARAMETERS) + 2, m): the airfoil constants, chord and airfoil number of the UA nodes."""
    rows = [np.asarray(ua.params[k], dtype=float) for k in PARAMETERS]
    rows += [np.asarray(ua.chord, dtype=float), polars.airfoil_index[np.asarray(ua.node, dtype=int)].astype(float)]
    return np.vstack([r.reshape(1, -1) for r in rows])


def _functions(ua: Any, polars: Any) -> list:
    """The node Functions: one mapped Function ("spline"), or one per node ("linear")."""
    sep = separation_polars(polars)
    key = ("ua_continuous", int(ua.mode), float(ua.dt), bool(ua.has_cm))
    cache = polars.__dict__.setdefault("_ua_node", {})
    if polars.method == "spline":
        if key not in cache:
            cache[key] = node_function(ua.mode, ua.dt, ua.has_cm, polars.by_airfoil, sep.by_airfoil)
        return [cache[key]] * ua.size
    out = []
    for j in np.asarray(ua.node, dtype=int):
        k = key + (int(j),)
        if k not in cache:
            cache[k] = node_function(ua.mode, ua.dt, ua.has_cm, lambda x, _n, j=j: polars(x, [int(j)]),
                                     lambda x, _n, j=j: sep(x, [int(j)]))
        out.append(cache[k])
    return out


def evaluate(ua: Any, polars: Any, alpha: Any, speed: Any, omega: Any, states: Any,
             rate_inputs: tuple | None = None) -> dict:
    """Cl, Cd, Cm, weight (m, 1) of the UA nodes and the states' derivative (node-major) at ``rate_inputs``."""
    m = ua.size
    n_s = len(state_suffixes(ua.mode))
    rate_inputs = rate_inputs or (alpha, speed, omega)
    c = constants(ua, polars)
    fs = _functions(ua, polars)
    z = ca.reshape(states, n_s, m)
    if polars.method == "spline":
        args = [alpha.T, speed.T, omega.T, z, ca.DM(c), *[v.T for v in rate_inputs]]
        mx = [ca.MX.sym(fs[0].name_in(i), fs[0].size1_in(i), m) for i in range(fs[0].n_in())]
        mapped = ca.Function(f"ua{ua.mode}_nodes_{m}", mx, fs[0].map(m)(*mx), {"never_inline": True})
        res = mapped(*args)
        return {"cl": res[0].T, "cd": res[1].T, "cm": res[2].T, "weight": res[3].T, "states_dot": ca.vec(res[4])}
    cols = [f(alpha[i], speed[i], omega[i], z[:, i], ca.DM(c[:, i]), *[v[i] for v in rate_inputs])
            for i, f in enumerate(fs)]
    return {"cl": ca.vertcat(*[r[0] for r in cols]), "cd": ca.vertcat(*[r[1] for r in cols]),
            "cm": ca.vertcat(*[r[2] for r in cols]), "weight": ca.vertcat(*[r[3] for r in cols]),
            "states_dot": ca.vertcat(*[r[4] for r in cols])}


def steady(ua: Any, polars: Any, alpha: Any, speed: Any, omega: Any = None) -> Any:
    """The states at rest of the UA nodes (node-major), as ``HGM_Steady`` sets them at the first step."""
    sep = separation_polars(polars)
    omega = 0.0 * alpha if omega is None else omega
    c = constants(ua, polars)
    if polars.method == "spline":
        f = steady_node_function(ua.mode, sep.by_airfoil).map(ua.size)
        return ca.vec(f(alpha.T, speed.T, omega.T, ca.DM(c)))
    rows = []
    for i, j in enumerate(np.asarray(ua.node, dtype=int)):
        f = steady_node_function(ua.mode, lambda x, _n, j=j: sep(x, [int(j)]))
        rows.append(f(alpha[i], speed[i], omega[i], ca.DM(c[:, i])))
    return ca.vertcat(*rows)


def rates_function(ua: Any, polars: Any) -> ca.Function:
    """``(z (n_s m), inputs (3 m: alpha, U, omega)) -> ż``: the derivative alone, an SX Function callable with MX
    (the composed graph evaluates it at the live states with the held part's inputs; cached on ``polars``)."""
    key = ("ua_continuous_rates", int(ua.mode), float(ua.dt), ua.size, tuple(np.asarray(ua.node, int)))
    cache = polars.__dict__.setdefault("_ua_node", {})
    if key not in cache:
        m, n_s = ua.size, len(state_suffixes(ua.mode))
        z, inputs = ca.SX.sym("z", n_s * m), ca.SX.sym("inputs", 3 * m)
        sep = separation_polars(polars)
        c = constants(ua, polars)
        rows = []
        for i, j in enumerate(np.asarray(ua.node, dtype=int)):
            p = {k: float(c[r, i]) for r, k in enumerate(PARAMETERS)}
            zi = {s: 0.0 for s in ("x1", "x2", "x3", "x4")}
            zi.update({s: z[i * n_s + q] for q, s in enumerate(state_suffixes(ua.mode))})
            if polars.method == "spline":
                number = float(c[-1, i])
                f_sep = lambda x, number=number: sep.by_airfoil(x, number)      # noqa: E731
            else:
                f_sep = lambda x, j=j: sep(x, [int(j)])                         # noqa: E731
            rows += rates(ua.mode, p, float(c[len(PARAMETERS), i]), float(ua.dt), zi, inputs[i], inputs[m + i],
                          inputs[2 * m + i], f_sep)
        cache[key] = ca.Function(f"ua{ua.mode}_rates", [z, inputs], [ca.vertcat(*rows)], ["z", "inputs"], ["zdot"])
    return cache[key]
