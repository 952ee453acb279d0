"""One real-time iteration of the turbine NMPC as CasADi Functions of fixed work (:mod:`.sample`'s ``qp_data``, ``qp``,
``finish`` and ``startup``), with the run-time settings (:mod:`.runtime_settings`) as an input.

Every Function takes the settings vector ``s`` (cost scales, then limits): the OCP's residual rows are scaled by
factors of ``s`` appended to the stage parameters (:func:`~.runtime_settings.weighted_problem`) and its bounds are
built from ``s`` (:func:`~.runtime_settings.symbolic_bounds`), so one generated QP serves every run-time setting.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import ControlDefinitionError
from .estimator import control_values
from .runtime_settings import symbolic_bounds, weighted_problem

__all__ = ["STARTUP_ITERATIONS", "QP_MAX_ITER", "QP_MAX_ITER_LARGE", "QP_CAP_STATES", "qp_max_iter", "qp_scaling",
           "rti_function"]

#: Full Gauss–Newton iterations of the first sample (fixed work; see the module docstring).
STARTUP_ITERATIONS = 10
#: qrqp's iteration cap in the exported step (bounds its worst case). Warm-started from the previous active set,
#: qrqp reaches the QP's solution within a few iterations and may spend more fixing multiplier signs: on the
#: NREL 5 MW OCP (300 samples at 14 m/s) 3 QPs needed more than 8 (up to 15); stopped at 8 their steps were
#: primal feasible to 5e-15 and within 3e-7 of the converged step (measured). But in the 20 s loop of
#: benchmarks/nmpc_discon_export.py the first QP after the start-up, stopped at 8, was infeasible (violation
#: 0.033: a fallback to the baseline); at 10 it converges. Each iteration costs ~0.33 ms.
QP_MAX_ITER = 10
#: The cap of OCPs with more than :data:`QP_CAP_STATES` states per stage (the floating NMPC's 11: the platform's surge
#: and pitch): started in OpenFAST at 18 m/s from the deck's 13 m/s initial conditions, capped at 10 its first 39 QPs
#: after the start-up failed (violation 0.01-0.25) until the baseline took over; in the mirror on those start
#: measurements 15 and 20 converge, at 24 m/s 20 does (10: 10 holds).
QP_MAX_ITER_LARGE = 20
QP_CAP_STATES = 8


def qp_max_iter(n_x: int) -> int:
    """qrqp's iteration cap in the exported step of an OCP with ``n_x`` states per stage."""
    return QP_MAX_ITER if n_x <= QP_CAP_STATES else QP_MAX_ITER_LARGE


def rti_function(nmpc, estimator, layout, *, startup: bool, preview: bool = False):
    """``startup``: ``(z, pitch, torque, settings[, wind]) -> (w, rates, violation, lam)``; else the real-time
    iteration's three parts ``(qp_data, qp, finish)`` (:mod:`.sample`; ``layout`` a
    :class:`~.runtime_settings.RuntimeLayout` of ``nmpc``)."""
    from ...control.nlp import split_w
    from ...control.qp import conic, preparation_function

    ctl = nmpc.nmpc
    tr = ctl.transcription
    P = tr.problem
    L, nc = P.layout, tr.n_controls
    if P.n_u != nc:
        raise ControlDefinitionError("the exported NMPC needs an OCP without slacks or collocation variables (the "
                                     f"turbine NMPC's own); this one has {P.n_u - nc} extra stage variables.")
    Pw = weighted_problem(P, layout)
    prep = preparation_function(Pw)
    qp = conic("qrqp", P, prep.sparsity_out(0), prep.sparsity_out(2),
               {"max_iter": 200 if startup else qp_max_iter(P.n_x)}, label="qp_qrqp" if startup else "nmpc_qp")
    p = ca.DM(ctl._p)
    s = ca.MX.sym("settings", layout.exported.size)
    bounds = symbolic_bounds(P, layout, s)
    a_r, b_r = layout.factors(s)
    z, pitch, torque = ca.MX.sym("z", len(estimator.names)), ca.MX.sym("pitch"), ca.MX.sym("torque")
    x0 = ca.vertcat(*control_values(estimator.names, z, pitch, torque, tr.dynamics.states,
                                    estimator.rigid_speed_weight))
    if preview:
        wind = ca.MX.sym("wind", P.N + 1)
        ws = ca.MX.sym("ws")
        column = ca.Function("stage_column", [ws], [_stage_column(nmpc, ws)])
        D = column.map(P.N + 1)(wind.T)
    else:
        D = ca.repmat(_stage_column(nmpc, z[estimator.names.index("Wind1VelX")]), 1, P.N + 1)
    D = ca.vertcat(D, ca.repmat(ca.vertcat(a_r, b_r), 1, P.N + 1))       # the residual rows' factors
    n_a = prep.sparsity_out(2).size1()

    n_prev = P.n_x - x0.size1()            # the previous rates of the rate-penalized controls (augmented state)

    col, row = qp_scaling(nmpc, prep, [ca.DM(b) for b in P.bounds()], p, n_prev, layout)
    S, Rs = ca.diag(ca.DM(col)), ca.diag(ca.DM(row))
    cs, rs = ca.DM(col), ca.DM(row)

    def qp_data(w):             # the QP in the scaled step dw / col, its rows divided by row (qp_scaling)
        H, g, A, lba, uba, lbdw, ubdw, _, _ = prep(w, D, p, *bounds)
        x_w = w[L.x_index(0)]
        fixed = ca.vertcat(x0, x_w[x0.size1():]) - x_w     # the plan's own previous rates: those last applied
        lbdw, ubdw = ca.vertcat(fixed, lbdw[P.n_x:]), ca.vertcat(fixed, ubdw[P.n_x:])
        return (ca.mtimes([S, H, S]), g * cs, ca.mtimes([Rs, A, S]), lba * rs, uba * rs, lbdw / cs, ubdw / cs)

    def finish(w, dws, lam, A, lba, uba, lbdw, ubdw):   # violation of the unscaled QP (its bounds: from s)
        dw = dws * cs
        Ad = ca.mtimes(A, dws) / rs
        viol = ca.mmax(ca.vertcat(0, lbdw * cs - dw, dw - ubdw * cs, lba / rs - Ad, Ad - uba / rs)) \
            / (1 + ca.norm_inf(dw))
        return w + dw, viol, lam

    def ending(w, viol, lam):
        X, U, xN = split_w(P, w)
        rates = ca.fmin(ca.fmax(U[:nc, 0], bounds[0][P.n_x:P.n_x + nc]), bounds[1][P.n_x:P.n_x + nc])
        Xs = ca.horzcat(X[:, 1:], xN, xN) if P.N > 1 else ca.horzcat(xN, xN)
        Us = ca.horzcat(U[:, 1:], U[:, -1:]) if P.N > 1 else U
        shifted = ca.vertcat(ca.vec(ca.vertcat(Xs[:, : P.N], Us)), Xs[:, P.N])
        lam_next = ca.vertcat(_shift_stages(lam[:L.n_w], P.N, P.n_x + P.n_u),
                              _shift_stages(lam[L.n_w:], P.N, P.n_x + P.n_c))
        return [shifted, rates, viol, lam_next]

    outs = ["w_next", "rates", "violation", "lam_next"]
    extra, extra_names = ([wind], ["wind"]) if preview else ([], [])
    if startup:
        u0 = np.clip(np.zeros(nc), P.lbu[:nc], P.ubu[:nc])
        xa = ca.vertcat(x0, ca.DM.zeros(n_prev))         # no rate applied before the first sample
        w = ca.vertcat(ca.repmat(ca.vertcat(xa, u0), P.N, 1), xa)
        lam = ca.MX(L.n_w + n_a, 1)
        worst = ca.MX(0)
        for _ in range(STARTUP_ITERATIONS):
            H, g, A, lba, uba, lbdw, ubdw = qp_data(w)
            sol = qp(h=H, g=g, a=A, lba=lba, uba=uba, lbx=lbdw, ubx=ubdw, lam_x0=lam[:L.n_w], lam_a0=lam[L.n_w:])
            w, viol, lam = finish(w, sol["x"], ca.vertcat(sol["lam_x"], sol["lam_a"]), A, lba, uba, lbdw, ubdw)
            worst = ca.fmax(worst, viol)
        return ca.Function("nmpc_startup", [z, pitch, torque, s, *extra], ending(w, worst, lam),
                           ["z", "pitch", "torque", "settings", *extra_names], outs)
    w_in = ca.MX.sym("w", L.n_w)
    data = ca.Function("nmpc_qp_data", [w_in, z, pitch, torque, s, *extra], list(qp_data(w_in)),
                       ["w", "z", "pitch", "torque", "settings", *extra_names],
                       ["h", "g", "a", "lba", "uba", "lbx", "ubx"])
    dw, lam_in = ca.MX.sym("dw", L.n_w), ca.MX.sym("lam", L.n_w + n_a)
    A = ca.MX.sym("a", prep.sparsity_out(2))
    lim = [ca.MX.sym(n, k) for n, k in (("lba", n_a), ("uba", n_a), ("lbx", L.n_w), ("ubx", L.n_w))]
    end = ca.Function("nmpc_finish", [w_in, dw, lam_in, A, *lim, s], ending(*finish(w_in, dw, lam_in, A, *lim)),
                      ["w", "dw", "lam", "a", "lba", "uba", "lbx", "ubx", "settings"], outs)
    return data, qp, end


def qp_scaling(nmpc, prep, bounds, p, n_prev: int, layout) -> tuple[np.ndarray, np.ndarray]:
    """Constant column and row scales of the exported QP: ``col`` = 1/sqrt of the Hessian's diagonal (1 where it is
    zero), each dynamics row divided by the ``col`` of the state it defines (its identity block stays one), at the
    NMPC's steady reference at the middle of its wind table (Gauss–Newton: the diagonal hardly moves with the
    operating point). qrqp's tolerances are absolute: on the IEA 15 MW (torque ~2e7 N m, its rate's Hessian
    ~1e-10) the unscaled QP stopped warm-started at a non-optimal point, 71 kN m off hpipm's (measured)."""
    P = nmpc.nmpc.transcription.problem
    grid = np.asarray(nmpc.references.winds, dtype=float)
    wind = 0.5 * (grid[0] + grid[-1])
    xs = np.concatenate([nmpc.references.state(wind), np.zeros(n_prev)])
    u0 = np.clip(np.zeros(P.n_u), P.lbu[:P.n_u], P.ubu[:P.n_u])
    w = np.concatenate([np.tile(np.concatenate([xs, u0]), P.N), xs])
    ws = ca.MX.sym("ws")
    column = ca.Function("stage_column", [ws], [_stage_column(nmpc, ws)])
    ones = np.ones((len(layout.stage_rows) + len(layout.terminal_rows), 1))          # the exported weights
    stages = np.tile(np.vstack([np.asarray(column(wind), dtype=float), ones]), (1, P.N + 1))
    h = np.asarray(ca.diag(prep(w, stages, p, *bounds)[0]), dtype=float).ravel()
    col = np.where(h > 0.0, 1.0 / np.sqrt(np.where(h > 0.0, h, 1.0)), 1.0)
    row = np.ones(prep.sparsity_out(2).size1())
    nv = P.n_x + P.n_u
    for k in range(P.N):                      # rows x_{k+1} - F(x_k, u_k): divided by x_{k+1}'s scale
        r0 = k * (P.n_x + P.n_c)
        row[r0:r0 + P.n_x] = 1.0 / col[(k + 1) * nv:(k + 1) * nv + P.n_x]
    return col, row


def _shift_stages(v: ca.MX, n_stages: int, block: int) -> ca.MX:
    """``v`` = N blocks of ``block`` then a terminal part, moved one stage earlier (the last block repeated, the
    terminal part kept): the shifted plan's multipliers, the next QP's active-set guess."""
    if n_stages < 2:
        return v
    return ca.vertcat(v[block:n_stages * block], v[(n_stages - 1) * block:n_stages * block], v[n_stages * block:])


def _stage_column(nmpc, wind: ca.MX) -> ca.MX:
    """The stage parameters of one stage at the wind (disturbances, then references): :meth:`TurbineNMPC.step`."""
    tr = nmpc.nmpc.transcription
    table = nmpc.references
    grid = np.asarray(table.winds, dtype=float)
    w = ca.fmin(ca.fmax(wind, grid[0]), grid[-1])          # np.interp holds the end values beyond the grid
    rows = []
    for name in tr.disturbances:
        if name != "Wind1VelX":
            raise ControlDefinitionError(f"the exported NMPC knows the disturbance Wind1VelX only; got {name!r}.")
        rows.append(wind)
    for name in tr.references:
        if name in nmpc._tracked:
            channel = name.split(":")[-1]
            if channel == "GenPwr" and nmpc.tuning.power_reference == "rated":
                rows.append(ca.MX(nmpc.setpoints.rated_power / 1e3))
                continue
            interp = ca.interpolant(f"ref_{channel}", "linear", [grid], np.asarray(table.channels[channel], float))
            rows.append(interp(w))
        else:
            rows.append(ca.MX(float(tr.default_references[name])))
    return ca.vertcat(*rows)
