"""The turbine MHE as CasADi Functions of fixed work: the estimator of an exported NMPC with ``--estimator mhe``.

:class:`mbsym.control.MHE` with real-time iterations (its default solver) does a bounded amount of
work per sample: an EKF step, the arrival cost's EKF update, and one Gauss–Newton QP over the
window. :func:`mhe_functions` writes that sample as Functions with no Python in between, so it can
be generated as C (:mod:`.discon_nmpc`) and mirrored in Python (:class:`MHEMirror`):

- ``push(s, y, u, predict) -> (s_next, z_ekf)``: the EKF sample (:meth:`mbsym.control.EKF.step`),
  then, with the window full, the arrival cost's update (its prior corrected with the dropped
  measurement and propagated over the dropped interval, as :class:`~mbsym.control.MHE` does), then
  the measurement ``y``, the known inputs ``u`` (mean measured pitch [rad] and torque [N m] of the
  interval) and the EKF's estimate pushed into the window's buffers. ``s`` is the estimator's whole
  memory (:attr:`MHEFunctions.n_s` values, layout in :func:`memory_layout`);
- ``first(s) -> (W, z, violation)``: the first solve of a full window: the window from the EKF's
  estimates, the noise fitted to their differences, then :data:`FIRST_ITERATIONS` full Gauss–Newton
  steps (the Python MHE converges a line-search SQP there; measured agreement in the tests);
- ``rti(W, s) -> (W_next, z, violation)``: one real-time iteration: the previous window shifted one interval
  (the new last node predicted with the last inputs, zero noise), the Gauss–Newton QP there (scaled:
  every state by its prior standard deviation) solved with its dynamics as the only constraints, from
  its KKT system by a sparse QR factorization (CasADi's ``qr`` linear solver), and the full step.
  ``z`` is the window's last node: the estimate. ``violation`` is the step's largest bound or
  constraint violation divided by ``1 + ‖Δw‖∞`` (accepted up to :data:`~.sample.QP_ACCEPT`);
- when that step leaves a bound (the wind's, [0.5, 60] m/s), the same QP with its bounds:
  ``qp_data(W, s) -> (w0, h, g, a, lba, uba, lbx, ubx)``, ``qp`` (``qrqp``), ``finish(w0, dw, a, lba, uba,
  lbx, ubx) -> (W, z, violation)``. The bounds are left out first because qrqp costs ten times the
  KKT solve on this QP even when no bound is active (measured: 3.0 ms against 0.27 ms for the NREL 5 MW's
  20-interval window, one qrqp iteration, the same step to 4e-12).

While the window fills the estimate is the EKF's; a rejected solve falls back to the EKF's estimate
and the next full window starts again with ``first`` (as :class:`~mbsym.control.MHE`).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ControlDefinitionError

__all__ = ["FIRST_ITERATIONS", "MHEFunctions", "MHEMirror", "memory_layout", "mhe_functions", "small_solve"]

#: Full Gauss–Newton iterations of the first solve of a full window (fixed work).
FIRST_ITERATIONS = 6
#: qrqp's iteration cap where the window's QP is solved with its bounds (a cold start: one iteration per bound that
#: becomes active, at most one per window node for the wind's).
MHE_QP_MAX_ITER = 50


def memory_layout(n_z: int, n_u: int, n_y: int, window: int) -> dict[str, slice]:
    """Where each part of the estimator's memory ``s`` sits: the EKF's estimate ``z`` and covariance ``P``
    (column-major), the arrival cost's ``zbar`` and ``Pbar``, the window's inputs ``U`` (n_u × (M+1)),
    measurements ``Y`` (n_y × (M+1)) and EKF estimates ``Z`` (n_z × (M+1)), oldest first, right-aligned
    while the window fills, and ``count`` (samples in the window, at most M + 1)."""
    sizes = (("z", n_z), ("P", n_z * n_z), ("zbar", n_z), ("Pbar", n_z * n_z), ("U", n_u * (window + 1)),
             ("Y", n_y * (window + 1)), ("Z", n_z * (window + 1)), ("count", 1))
    out, k = {}, 0
    for name, n in sizes:
        out[name] = slice(k, k + n)
        k += n
    return out


@dataclass(frozen=True)
class MHEFunctions:
    """The Functions of :func:`mhe_functions` (module docstring) and their sizes."""

    push: ca.Function
    first: ca.Function
    rti: ca.Function
    shift: ca.Function
    window0: ca.Function
    qp_data: ca.Function
    qp: ca.Function
    finish: ca.Function
    window: int
    n_s: int
    n_W: int
    P0: np.ndarray           # the prior covariance a (re)start puts in ``P`` and ``Pbar`` (n_z × n_z)
    layout: dict

    def start(self, z0: np.ndarray) -> np.ndarray:
        """The memory of a (re)start at the estimate ``z0``: covariance and arrival prior ``P0``, empty window."""
        P0 = self.P0
        s = np.zeros(self.n_s)
        L = self.layout
        s[L["z"]], s[L["P"]] = z0, P0.reshape(-1, order="F")
        s[L["zbar"]], s[L["Pbar"]] = z0, P0.reshape(-1, order="F")
        return s

    def functions(self) -> tuple:
        """The Functions to generate, in the C wrapper's order."""
        return self.push, self.first, self.rti, self.shift, self.window0, self.qp_data, self.qp, self.finish


def small_solve(S: ca.MX, B: ca.MX) -> ca.MX:
    """``S⁻¹ B`` for a small dense ``S`` by an SX Function (expanded LU: plain arithmetic in C)."""
    Ss, Bs = ca.SX.sym("S", *S.shape), ca.SX.sym("B", *B.shape)
    return ca.Function("small_solve", [Ss, Bs], [ca.solve(Ss, Bs)])(S, B)


def _ekf_parts(lin, Q: np.ndarray, R: np.ndarray, pr: ca.DM):
    """``predict(z, P, u)`` and ``correct(z, P, y, u)`` as expressions (:class:`mbsym.control.EKF`, Joseph form)."""
    def predict(z, P, u):
        zn, F, _, _ = lin(z, u, pr)
        return zn, ca.mtimes([F, P, F.T]) + ca.DM(Q)

    def correct(z, P, y, u):
        _, _, yh, H = lin(z, u, pr)
        S = ca.mtimes([H, P, H.T]) + ca.DM(R)
        K = small_solve(S, ca.mtimes(H, P)).T
        I_KH = ca.DM.eye(z.size1()) - ca.mtimes(K, H)
        return z + ca.mtimes(K, y - yh), ca.mtimes([I_KH, P, I_KH.T]) + ca.mtimes([K, ca.DM(R), K.T])

    return predict, correct


def mhe_functions(estimator) -> MHEFunctions:
    """The fixed-work Functions of ``estimator`` (a :class:`~.estimator.TurbineEstimator` of kind ``"mhe"``).

    Raises
    ------
    ControlDefinitionError
        An estimator of another kind, or an MHE whose solver is not ``"rti"``.
    """
    from ...control import MHE, EstimationModel
    from ...control.qp import preparation_function

    f = estimator.filter
    if estimator.kind != "mhe" or not isinstance(f, MHE):
        raise ControlDefinitionError(f"mhe_functions needs an MHE estimator; got {estimator.kind!r}.")
    if f.solver != "rti":
        raise ControlDefinitionError(f"only real-time iterations have a fixed-work sample; the MHE's solver is "
                                     f"{f.solver!r}.")
    m = estimator.model
    # fresh, uncompiled copies: the filter's own Functions may be compiled libraries (no graph to generate)
    model = EstimationModel(estimator.dynamics, dt=m.dt, measurements=m.measurements,
                            unknown_inputs=m.unknown_inputs, compile=False)
    bounds = {n: (float(lo), float(hi)) for n, lo, hi in zip(m.names, f._lb, f._ub) if np.isfinite([lo, hi]).any()}
    twin = MHE(model, window=f.window, process_noise=f._ekf.Q, measurement_noise=f._ekf.R, x0=f._arrival[0],
               P0=f._arrival[1], bounds=bounds, compile=False)
    n, nu, ny, M = m.n_z, len(m.known_inputs), m.n_y, f.window
    L = memory_layout(n, nu, ny, M)
    n_s = L["count"].stop
    P = twin._P
    prep = preparation_function(P)
    pr = ca.DM(m.p_rest)
    predict, correct = _ekf_parts(model.linearization, f._ekf.Q, f._ekf.R, pr)
    scale = np.concatenate([np.sqrt(np.diag(f._arrival[1])), np.ones(P.n_u)])      # prior sd; noise is unit
    push = _push_function(L, n, nu, ny, M, predict, correct)
    s = ca.MX.sym("s", n_s)
    D, p = _window_data(s, L, n, nu, ny, M, pr)
    bnds = [ca.DM(b) for b in P.bounds()]
    col = np.concatenate([np.tile(scale, M), scale[:n]])
    row = np.ones(prep.sparsity_out(2).size1())
    for k in range(M):                      # the dynamics rows x_{k+1} - f(x_k, ξ_k), divided by x_{k+1}'s scale
        r0 = k * (P.n_x + P.n_c)
        row[r0:r0 + P.n_x] = 1.0 / scale[:n]
    cs, rs, S, Rs = ca.DM(col), ca.DM(row), ca.diag(ca.DM(col)), ca.diag(ca.DM(row))

    def qp_at(w):
        H, g, A, lba, uba, lbdw, ubdw, _, _ = prep(w, D, p, *bnds)
        return ca.mtimes([S, H, S]), g * cs, ca.mtimes([Rs, A, S]), lba * rs, uba * rs, lbdw / cs, ubdw / cs

    def step(w, dws, A, lba, uba, lbdw, ubdw):
        dw = dws * cs
        Ad = ca.mtimes(A, dws) / rs
        viol = ca.mmax(ca.vertcat(0, lbdw * cs - dw, dw - ubdw * cs, lba / rs - Ad, Ad - uba / rs)) \
            / (1 + ca.norm_inf(dw))
        return w + dw, viol

    n_W, n_a = P.layout.n_w, prep.sparsity_out(2).size1()
    if P.n_c or P.n_cN:
        raise ControlDefinitionError("the exported MHE solves the window's QP with its dynamics as the only "
                                     f"constraints; this problem has {P.n_c} path and {P.n_cN} terminal ones.")
    kkt = _kkt_solver(qp_at, n_W, n_a)

    def direct(w):                  # the QP's bounds left out, then checked by the violation
        H, g, A, lba, uba, lbdw, ubdw = qp_at(w)
        return step(w, kkt(H, g, A, lba), A, lba, uba, lbdw, ubdw)

    w = _initial_window(twin, s, L, D, pr)
    worst = ca.MX(0)
    for _ in range(FIRST_ITERATIONS):
        w, viol = direct(w)
        worst = ca.fmax(worst, viol)
    first = ca.Function("mhe_first", [s], [w, w[n_W - n:], worst], ["s"], ["W", "z", "violation"])
    W = ca.MX.sym("W", n_W)
    w0 = _shifted_window(twin, W, D, pr)
    w_direct, viol_direct = direct(w0)
    rti = ca.Function("mhe_rti", [W, s], [w_direct, w_direct[n_W - n:], viol_direct], ["W", "s"],
                      ["W_next", "z", "violation"])
    shift = ca.Function("mhe_shift", [W, s], [w0], ["W", "s"], ["w0"])
    window0 = ca.Function("mhe_window0", [s], [_initial_window(twin, s, L, D, pr)], ["s"], ["w0"])
    return MHEFunctions(push=push, first=first, rti=rti, shift=shift, window0=window0,
                        **_bounded_parts(P, prep, qp_at, step, n, s), window=M, n_s=n_s, n_W=n_W,
                        P0=np.array(f._arrival[1], dtype=float), layout=L)


def _bounded_parts(P, prep, qp_at, step, n: int, s: ca.MX) -> dict:
    """The QP with its bounds at a given window ``w0`` of the memory ``s`` (``qp_data``, ``qp``, ``finish``; module
    docstring)."""
    from ...control.qp import conic

    n_W, n_a = P.layout.n_w, prep.sparsity_out(2).size1()
    w0 = ca.MX.sym("w0", n_W)
    data = ca.Function("mhe_qp_data", [w0, s], list(qp_at(w0)), ["w0", "s"],
                       ["h", "g", "a", "lba", "uba", "lbx", "ubx"])
    qp = conic("qrqp", P, prep.sparsity_out(0), prep.sparsity_out(2), {"max_iter": MHE_QP_MAX_ITER}, label="mhe_qp")
    dw = ca.MX.sym("dw", n_W)
    A = ca.MX.sym("a", prep.sparsity_out(2))
    lim = [ca.MX.sym(k, j) for k, j in (("lba", n_a), ("uba", n_a), ("lbx", n_W), ("ubx", n_W))]
    w_next, viol = step(w0, dw, A, *lim)
    finish = ca.Function("mhe_finish", [w0, dw, A, *lim], [w_next, w_next[n_W - n:], viol],
                         ["w0", "dw", "a", "lba", "uba", "lbx", "ubx"], ["W", "z", "violation"])
    return {"qp_data": data, "qp": qp, "finish": finish}


def _kkt_solver(qp_at, n_w: int, n_a: int):
    """``(H, g, A, b) -> dw``: the minimizer of ``½ dwᵀ H dw + gᵀ dw`` subject to ``A dw = b``, from the KKT system
    by a sparse QR factorization (CasADi's ``qr`` linear solver, generated as C)."""
    w = ca.MX.sym("w", n_w)
    H, _, A, _, _, _, _ = qp_at(w)
    K = ca.blockcat([[H, A.T], [A, ca.MX(n_a, n_a)]])
    solver = ca.Linsol("mhe_kkt", "qr", K.sparsity())

    def solve(H, g, A, b):
        return solver.solve(ca.blockcat([[H, A.T], [A, ca.MX(n_a, n_a)]]), ca.vertcat(-g, b))[:n_w]

    return solve


def _push_function(L, n, nu, ny, M, predict, correct) -> ca.Function:
    """``(s, y, u, predict) -> (s_next, z_ekf)`` (module docstring)."""
    s, y, u, flag = ca.MX.sym("s", L["count"].stop), ca.MX.sym("y", ny), ca.MX.sym("u", nu), ca.MX.sym("predict")
    z, P = s[L["z"]], ca.reshape(s[L["P"]], n, n)
    zp, Pp = predict(z, P, u)
    z1, P1 = correct(ca.if_else(flag, zp, z), ca.if_else(flag, Pp, P), y, u)
    U, Y = ca.reshape(s[L["U"]], nu, M + 1), ca.reshape(s[L["Y"]], ny, M + 1)
    Z = ca.reshape(s[L["Z"]], n, M + 1)
    count = s[L["count"]]
    full = count >= M + 1
    zb, Pb = s[L["zbar"]], ca.reshape(s[L["Pbar"]], n, n)
    za, Pa = correct(zb, Pb, Y[:, 0], U[:, 0])                     # the dropped node's measurement
    za, Pa = predict(za, Pa, U[:, 1] if M >= 1 else U[:, 0])       # the dropped interval's inputs
    zb, Pb = ca.if_else(full, za, zb), ca.if_else(full, Pa, Pb)
    s_next = ca.vertcat(z1, ca.vec(P1), zb, ca.vec(Pb), ca.vec(ca.horzcat(U[:, 1:], u)),
                        ca.vec(ca.horzcat(Y[:, 1:], y)), ca.vec(ca.horzcat(Z[:, 1:], z1)), ca.fmin(count + 1, M + 1))
    return ca.Function("mhe_push", [s, y, u, flag], [s_next, z1], ["s", "y", "u", "predict"], ["s_next", "z_ekf"])


def _window_data(s, L, n, nu, ny, M, pr):
    """The stage data ``D`` and parameters ``p`` of the MHE's problem from the memory (``MHE._parameters``)."""
    U, Y = ca.reshape(s[L["U"]], nu, M + 1), ca.reshape(s[L["Y"]], ny, M + 1)
    u_dyn = ca.horzcat(U[:, 1:], U[:, M:])                            # interval k: the inputs given with y_{k+1}
    D = ca.vertcat(u_dyn, U, Y)
    Pb = ca.reshape(s[L["Pbar"]], n, n)
    return D, ca.vertcat(pr, s[L["zbar"]], ca.vec(_arrival_root(0.5 * (Pb + Pb.T))))


def _arrival_root(P: ca.MX) -> ca.MX:
    """``L0`` with ``L0ᵀ L0 = P⁻¹`` (the arrival cost's weight): ``C⁻ᵀ`` of the Cholesky factor ``P = Cᵀ C``
    (expanded SX: plain arithmetic in C). The Python MHE takes the Cholesky factor of ``P⁻¹`` itself; the QP sees
    ``L0ᵀ L0`` only, and inverting the triangular factor keeps a floating estimator's covariance (variances from
    1e-8 to 1e16: the waves' moment in N m) finite, where inverting ``P`` first did not."""
    Ps = ca.SX.sym("P", *P.shape)
    C = ca.chol(Ps)
    return ca.Function("arrival_root", [Ps], [ca.solve(C.T, ca.SX.eye(P.size1()))])(P)


def _initial_window(mhe, s, L, D, pr) -> ca.MX:
    """The window from the EKF's estimates, the noise fitted to their differences (``MHE._initial_window``)."""
    m = mhe.model
    n, nu, M = m.n_z, len(m.known_inputs), mhe.window
    Z = ca.reshape(s[L["Z"]], n, M + 1)
    G_pinv = ca.DM(np.linalg.pinv(mhe._G)) if mhe._G.shape[1] else None
    blocks = []
    for k in range(M):
        pred = m.step_function(Z[:, k], D[:nu, k], pr)
        xi = ca.mtimes(G_pinv, Z[:, k + 1] - pred) if G_pinv is not None else ca.MX(0, 1)
        blocks += [Z[:, k], xi]
    return ca.vertcat(*blocks, Z[:, M])


def _shifted_window(mhe, W, D, pr) -> ca.MX:
    """The previous window one interval on: its last node predicted with the last inputs, zero noise."""
    m = mhe.model
    n, nu, M = m.n_z, len(m.known_inputs), mhe.window
    nv = mhe._P.n_x + mhe._P.n_u
    x_last = W[M * nv:]
    x_new = m.step_function(x_last, D[:nu, M - 1], pr)
    xi0 = ca.MX.zeros(nv - n, 1)
    return ca.vertcat(W[nv:M * nv], x_last, xi0, x_new)


class MHEMirror:
    """The exported MHE's sample in Python (:class:`~.sample.SampledLoop`'s estimator with an MHE).

    Parameters
    ----------
    functions : MHEFunctions
    z0 : array
        The (re)start estimate.
    accept : float
        Largest accepted violation of a solve (:data:`~.sample.QP_ACCEPT`).

    Attributes
    ----------
    z : ndarray
        The current estimate.
    failures : int
        Rejected MHE solves (the EKF's estimate applied instead).
    bounded : int
        Samples whose step without the bounds violated them and was solved again with them (qrqp).
    """

    def __init__(self, functions: MHEFunctions, z0, accept: float) -> None:
        self.f, self.accept = functions, float(accept)
        self.restart(z0)
        self.failures = 0
        self.bounded = 0

    def restart(self, z0) -> None:
        """Start again at ``z0`` with the prior covariance and an empty window."""
        self.s = self.f.start(np.asarray(z0, dtype=float).ravel())
        self.W: np.ndarray | None = None
        self.z = np.asarray(z0, dtype=float).ravel().copy()

    @property
    def P(self) -> np.ndarray:
        """The EKF's covariance."""
        n = self.z.size
        return self.s[self.f.layout["P"]].reshape(n, n, order="F")

    def step(self, y, u, predict: float) -> np.ndarray:
        """One estimator sample (module docstring); the estimate."""
        f = self.f
        s, z_ekf = f.push(self.s, y, u, predict)
        self.s, z_ekf = np.asarray(s).ravel(), np.asarray(z_ekf).ravel()
        if self.s[f.layout["count"]][0] < f.window + 1:
            self.z = z_ekf
            return self.z.copy()
        if self.W is None:
            W, z, viol = f.first(self.s)
            if not self._accepted(W, viol):          # a bound active: the QP with its bounds
                W, z, viol = self._bounded(f.window0(self.s), FIRST_ITERATIONS)
        else:
            W, z, viol = f.rti(self.W, self.s)
            if not self._accepted(W, viol):
                W, z, viol = self._bounded(f.shift(self.W, self.s), 1)
        W, z = np.asarray(W).ravel(), np.asarray(z).ravel()
        if self._accepted(W, viol):
            self.W, self.z = W, z
        else:
            self.failures += 1
            self.W, self.z = None, z_ekf
        return self.z.copy()

    def _accepted(self, W, viol) -> bool:
        return bool(np.all(np.isfinite(np.asarray(W))) and float(viol) <= self.accept)

    def _bounded(self, w0, iterations: int) -> tuple:
        """``iterations`` full steps of the QP with its bounds (qrqp) from the window ``w0``; the largest violation."""
        f = self.f
        self.bounded += 1
        worst = []
        for _ in range(iterations):
            h, g, a, lba, uba, lbx, ubx = f.qp_data(w0, self.s)
            sol = f.qp(h=h, g=g, a=a, lba=lba, uba=uba, lbx=lbx, ubx=ubx)
            w0, z, viol = f.finish(w0, sol["x"], a, lba, uba, lbx, ubx)
            worst.append(float(viol))
        return w0, z, np.max(worst)
