"""Kane's method with dependent coordinates and speeds, and the dependent coordinates in the graph.

With the tree's equations ``M(q) q̈ = F(q, q̇)`` (speeds are q̇, :mod:`mbsym.kane`) and constraint
rows ``g(q, p) = 0`` with Jacobian ``G = [G_i  G_d]`` split into independent and dependent
coordinates, the velocity constraint ``G q̇ = 0`` gives the dependent speeds

``q̇_d = A_rs q̇_i``,  ``A_rs = -G_d⁻¹ G_i``  (SymPy's ``KanesMethod`` calls it ``Ars``),

so every speed is ``q̇ = C q̇_i`` with ``C = [I; A_rs]`` (rows in coordinate order), and its time
derivative ``G q̈ + Ġ q̇ = 0`` gives ``q̈ = C q̈_i + c₀`` with ``c₀ = [0; -G_d⁻¹ Ġ q̇]``. Kane's
equations of the independent speeds are the tree's equations projected on the partial
velocities of the constrained motion, ``Cᵀ (F - M q̈) = 0``:

``M_r q̈_i = F_r``,  ``M_r = Cᵀ M C``,  ``F_r = Cᵀ (F - M c₀)``.

``G`` is read from the velocities of the closure points as the tree computes them (the same
partial velocities Kane's terms use; for rigid bodies exactly ``∂g/∂q``; for flexible bodies the
attachment kinematics', which differ from ``∂g/∂q`` at first order in the deflection), and ``Ġ q̇``
is their rate at ``q̈ = 0``. The position constraint ``g = 0`` fixes the dependent coordinates.

The reaction of the cut joints follows from ``M q̈ - F = Gᵀ λ`` on the dependent rows,
``λ = G_d⁻ᵀ (M q̈ - F)_d``: for a point closure ``g = r_b - r_a``, λ is the force body *a* exerts on
body *b* at the point [N, ground axes].

The dependent coordinates ``q_d(q_i, p)`` are solved inside the same SX graph. For one independent
coordinate that turns fully (a crank) a Fourier series of ``q_d`` over a turn, fitted at derivation
(:func:`mbsym.loops.assembly.turn_series`), predicts them and Newton steps correct the prediction.
Otherwise a fixed continuation runs from the assembled configuration ``(q_i*, q_d*)`` along the straight path to
``q_i`` in ``stages`` equal steps, each an Euler predictor along the tangent ``A_rs`` and
``newton_steps`` Newton steps on ``g`` (two more at the end). Independent
coordinates on which ``g`` is 2π-periodic (revolute joints) take the shorter way round
(``q_i - q_i*`` wrapped to (-π, π]), so a crank turns any number of revolutions on one branch. The
last Newton step at a converged point makes the first derivatives of ``q_d`` exact
(``∂q_d/∂q_i = A_rs``), so linearizations and optimal control see the constrained motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

__all__ = ["Reduction", "reduce_equations", "solve_dependent", "periodic_coordinates"]


@dataclass
class Reduction:
    """Reduced equations in the independent coordinates (SX of q_i, q̇_i, q̈_i, u, p)."""

    M: ca.SX          # (k, k) mass matrix of the independent speeds
    F: ca.SX          # (k,) forcing
    T: ca.SX          # kinetic energy [J]
    V: ca.SX          # potential energy [J]
    power: ca.SX      # power of the non-conservative loads [W]
    q_dep: ca.SX      # (m,) dependent coordinates
    qd_dep: ca.SX     # (m,) dependent speeds
    lam: ca.SX        # (m,) constraint reactions, of q̈_i too
    residual: ca.SX   # max |g| at the solved configuration
    C: ca.SX          # (n, k) speeds of every coordinate per independent speed
    c0: ca.SX         # (n,) acceleration of every coordinate at q̈_i = 0


def reduce_equations(d, g: ca.SX, g_dot: ca.SX, ind: tuple[int, ...], dep: tuple[int, ...], q_ref: np.ndarray,
                     periodic: list[bool], stages: int, newton_steps: int, final_steps: int = 2,
                     references: dict | None = None, assembly_steps: int = 0) -> Reduction:
    """Kane's equations of the independent speeds with ``q_d`` solved in the graph (module docstring).

    Parameters
    ----------
    d : mbsym.kane.Derivation
        The tree's derivation (every coordinate, speeds are q̇).
    g : SX
        Constraint rows, expressions of ``d.q`` and ``d.p``.
    g_dot : SX
        Their velocities by the tree's point kinematics (linear in ``d.qd``;
        :func:`mbsym.constraints.constraint_rows`).
    ind, dep : tuple of int
        Indices of the independent and dependent coordinates.
    q_ref : ndarray
        The assembled configuration (every coordinate).
    periodic : list of bool
        Per independent coordinate: ``g`` is 2π-periodic in it.
    stages, newton_steps : int
        Continuation stages and Newton steps per stage.
    final_steps : int
        Newton steps added to the last stage.
    references : dict, optional
        Fourier series of the dependent coordinates over a full turn of the one independent
        coordinate (see :func:`solve_dependent`).
    assembly_steps : int
        Newton steps at the reference before the continuation, when ``q_ref`` is only a guess.
    """
    q, qd, qdd = d.q, d.qd, d.qdd
    n, k = q.numel(), len(ind)
    ind_l, dep_l = list(ind), list(dep)
    kin = d.kinematics
    G = kin.resolve([ca.jacobian(g_dot, qd)])[0]                       # velocity constraint G q̇ = 0
    Gi, Gd = G[:, ind_l], G[:, dep_l]
    Ars = -ca.solve(Gd, Gi)
    C = ca.SX.zeros(n, k)
    C[ind_l, :] = ca.SX.eye(k)
    C[dep_l, :] = Ars
    qd_i, qdd_i = qd[ind_l], qdd[ind_l]
    qd_full = C @ qd_i
    n_all = kin.q_all.numel()
    rate = kin.rate(g_dot, ca.vertcat(kin.q_all, kin.qd_all), ca.vertcat(kin.qd_all, ca.SX.zeros(n_all)))
    gamma = ca.substitute(kin.resolve([rate])[0], qd, qd_full)        # Ġ q̇ along the constrained motion
    c0 = ca.SX.zeros(n, 1)
    c0[dep_l] = -ca.solve(Gd, gamma)
    M = d.M
    F, T, power = ca.substitute([d.F, d.T, d.power], [qd], [qd_full])
    Mr = C.T @ M @ C
    Fr = C.T @ (F - M @ c0)
    qdd_full = C @ qdd_i + c0
    lam = ca.solve(Gd.T, (M @ qdd_full - F)[dep_l])
    qd_dep = Ars @ qd_i
    z = solve_dependent(g, q, d.p, ind, dep, q_ref, periodic, stages, newton_steps, final_steps, references,
                        assembly_steps)
    res = ca.mmax(ca.fabs(g))
    q_dep = q[dep_l]
    out = ca.substitute([Mr, Fr, T, d.V, power, qd_dep, lam, res, C, c0], [q_dep], [z])
    Mr, Fr, T, V, power, qd_dep, lam, res, C, c0 = out
    return Reduction(ca.tril2symm(ca.tril(Mr)), Fr, T, V, power, z, qd_dep, lam, res, C, c0)


def solve_dependent(g: ca.SX, q: ca.SX, p: ca.SX, ind, dep, q_ref: np.ndarray, periodic: list[bool],
                    stages: int, newton_steps: int, final_steps: int = 2, references: dict | None = None,
                    assembly_steps: int = 0) -> ca.SX:
    """``q_d`` as an SX expression of ``q_i`` and ``p``: continuation from ``q_ref`` (module docstring).

    Each stage takes an Euler predictor step along the tangent ``A_rs`` and ``newton_steps`` Newton
    corrections; the last stage ``final_steps`` more. With ``references`` (one independent
    coordinate that turns fully: a Fourier series of the dependent coordinates over a turn,
    :func:`mbsym.loops.assembly.turn_series`) the series predicts ``q_d`` and ``newton_steps``
    Newton steps correct it: no path to follow.
    """
    ind_l, dep_l = list(ind), list(dep)
    qi, qdep = q[ind_l], q[dep_l]
    Gd = ca.jacobian(g, qdep)
    newton = ca.Function("newton_step", [qi, qdep, p], [qdep - ca.solve(Gd, g)])
    dqi = ca.SX.sym("dqi", len(ind_l))
    tangent = ca.Function("tangent_step", [qi, qdep, p, dqi], [qdep - ca.solve(Gd, ca.jtimes(g, qi, dqi))])
    qi_ref = ca.DM(q_ref[ind_l])
    delta = qi - qi_ref
    if references is not None:                                         # one stage from the Fourier predictor
        z = _fourier_predictor(references, delta[0])                   # unwrapped: outputs continuous over turns
        return _newton_steps(newton, qi, z, p, newton_steps)
    wrapped = [ca.atan2(ca.sin(delta[j]), ca.cos(delta[j])) if periodic[j] else delta[j] for j in range(len(ind))]
    delta = ca.vertcat(*wrapped)
    z = ca.SX(ca.DM(q_ref[dep_l]))
    z = _newton_steps(newton, qi_ref, z, p, assembly_steps)          # q_ref not assembled (no parameter values)
    for s in range(stages):
        z = tangent(qi_ref + (s / stages) * delta, z, p, delta / stages)     # Euler predictor along the path
        qs = qi_ref + ((s + 1) / stages) * delta
        z = _newton_steps(newton, qs, z, p, newton_steps + (final_steps if s == stages - 1 else 0))
    return z


def _newton_steps(newton: ca.Function, qs, z, p, count: int):
    for _ in range(count):
        z = newton(qs, z, p)
    return z


def _fourier_predictor(series: dict, delta: ca.SX) -> ca.SX:
    """``w δ + a₀ + Σ_n (a_n cos nδ + b_n sin nδ)`` per dependent coordinate.

    ``series`` comes from :func:`mbsym.loops.assembly.turn_series`.
    """
    c1, s1 = ca.cos(delta), ca.sin(delta)
    out = series["winding"] * delta + ca.DM(series["a"][0])
    cn, sn = c1, s1
    for n in range(1, series["a"].shape[0]):
        out = out + ca.DM(series["a"][n]) * cn + ca.DM(series["b"][n]) * sn
        cn, sn = cn * c1 - sn * s1, sn * c1 + cn * s1
    return out


def periodic_coordinates(g_fn: ca.Function, q_ref: np.ndarray, p: np.ndarray, ind, seed: int = 0) -> list[bool]:
    """Per independent coordinate: is ``g`` unchanged by a shift of 2π in it (checked at random points)?

    ``g_fn`` is ``(q, p) -> g``. Revolute coordinates enter the kinematics through sines and
    cosines only, so ``g`` repeats after a full turn; translations and elastic coordinates do not.
    """
    rng = np.random.default_rng(seed)
    points = [q_ref + rng.uniform(-1.0, 1.0, q_ref.size) for _ in range(3)]
    out = []
    for j in ind:
        same = True
        for x in points:
            x2 = x.copy()
            x2[j] += 2 * np.pi
            a, b = (np.array(g_fn(v, p)).reshape(-1) for v in (x, x2))
            same &= bool(np.max(np.abs(a - b)) <= 1e-9 * max(1.0, np.max(np.abs(a))))
        out.append(same)
    return out
