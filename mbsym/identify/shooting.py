"""CasADi Functions of multiple shooting on the measurement grid.

Each sample interval is integrated with ``m`` classical RK4 sub-steps, inputs
interpolated linearly between the two samples (stage inputs at ``t``, ``t + h/2``,
``t + h`` of each sub-step).

The Gauss–Newton iteration (:mod:`mbsym.identify.gauss_newton`) needs, per
interval, the state at the next sample and its exact Jacobians ``A`` (state) and
``B`` (estimated parameters). The *interval Jacobian* Function propagates them
through the RK4 stages by the chain rule, evaluating the model's sparse rhs
Jacobian ``∂f/∂[x; θ]`` once per stage (an MX graph calling one SX Function four
times per sub-step): 39k instructions per interval for the paper45 turbine (3
DOFs, 3 parameters) against 81k for CasADi's forward AD of the unrolled SX step,
and small C to compile. The intervals are independent, so they are mapped over
the samples (``"thread"`` parallelization on machines with several cores). A tiny
*condensing* Function ``Z_{k+1} = A_k Z_k + [0 | B_k | g_k]`` is accumulated over
the samples. Output Functions return the fitted channels and their Jacobians.

By default every Function is compiled to C through :mod:`mbsym.codegen` (cached
on disk; none depends on the length of the record). Numeric calls go through
``Function.buffer()`` on numpy arrays.

Sub-steps (:func:`choose_substeps`): RK4 applied to an oscillation of angular
frequency ``ω`` with step ``h`` has a relative frequency error ``(ωh)⁴/120`` and
a numerical damping ratio ``(ωh)⁵/144`` (leading terms of its amplification
factor). ``m`` is the smallest number of sub-steps giving
``(|λ|_max h/m)⁴ / 120 ≤ tol`` (default 1e-6) for the largest eigenvalue modulus of
the model linearized at the initial state with the starting parameters, and
``|λ|_max h/m ≤ 2.5`` (inside RK4's stability region on both axes). At 0.02 s
samples this is one sub-step for tower and platform modes (``ωh ≈ 0.04``,
frequency error 2e-8) and a few for drivetrain torsion or blade edge modes.
"""

from __future__ import annotations

import math
import weakref
from collections import OrderedDict
from typing import Sequence

import casadi as ca
import numpy as np

from ..codegen import compile_function
from ..dynamics import Dynamics

__all__ = ["ShootingFunctions", "choose_substeps", "shooting_functions", "COMPILE_FLAGS"]

#: Steps per accumulated call of the sequential loops (simulation, condensing): building ``mapaccum``
#: costs ~46 µs per step, so loops of any length run as repeated calls of one 128-step loop.
CHUNK = 128

#: Compiler flags of the identification Functions: -O2 runs the sweep 1.6x faster than the codegen
#: default -O1 for a similar compile time (paper45: 166 vs 262 ms per 3000-interval sweep, 17 vs 14 s).
COMPILE_FLAGS: tuple[str, ...] = ("-O2",)


def choose_substeps(dyn: Dynamics, x0: np.ndarray, u0: np.ndarray, p: np.ndarray, h: float, *,
                    tol: float = 1e-6) -> tuple[int, float]:
    """RK4 sub-steps per sample interval ``h`` [s] and the largest eigenvalue modulus [1/s] (module docstring)."""
    x = ca.MX.sym("x", dyn.n_x)
    jac = ca.Function("ident_rhs_jac", [x], [ca.jacobian(dyn.rhs(x, ca.DM(u0), ca.DM(p)), x)])
    A = np.array(jac(x0), dtype=float)
    lam = float(np.max(np.abs(np.linalg.eigvals(A)))) if A.size and np.all(np.isfinite(A)) else 0.0
    m_acc = math.ceil(lam * h / (120.0 * tol) ** 0.25) if lam > 0 else 1
    m_stab = math.ceil(lam * h / 2.5) if lam > 0 else 1
    return max(1, m_acc, m_stab), lam


class ShootingFunctions:
    """Interval, output and sweep Functions of one model, choice of channels and estimated parameters.

    Parameters
    ----------
    dyn : Dynamics
    rows : sequence of (str, int)
        The fitted channels: ``("y", i)`` output ``i`` of ``dyn.outputs`` or ``("x", i)``
        state ``i``.
    theta_index : sequence of int
        Indices of the estimated parameters in ``dyn.parameters``.
    n_free : int
        Number of estimated initial states (columns of the sensitivities).
    substeps : int
        RK4 sub-steps per sample interval.
    compile : bool
        Generate and compile C (cached); otherwise CasADi's virtual machine.
    threads : int
        Threads evaluating the interval Jacobians (1: serial).
    """

    def __init__(self, dyn: Dynamics, rows: Sequence[tuple[str, int]], theta_index: Sequence[int], n_free: int,
                 substeps: int, *, compile: bool = True, threads: int = 1) -> None:
        self.dyn, self.substeps = dyn, int(substeps)
        self.n_x, self.n_u, self.n_th, self.n_y = dyn.n_x, dyn.n_u, len(theta_index), len(rows)
        self.n_f = int(n_free)
        self.n_z = self.n_f + self.n_th + 1
        self.compiled, self.compile_s = False, 0.0
        self.threads = max(1, int(threads))
        self.parallelization = "thread" if self.threads > 1 else "serial"
        self.theta_index = np.asarray(theta_index, dtype=int)
        self.E = np.zeros((dyn.n_p, self.n_th))
        self.E[self.theta_index, np.arange(self.n_th)] = 1.0
        funcs = self._build(rows)
        self.sym_interval, self.sym_output = funcs["interval"], funcs["output"]     # uncompiled (for AD)
        if compile:
            out = {}
            for name, f in funcs.items():
                c = compile_function(f, flags=COMPILE_FLAGS)
                out[name] = c.function
                self.compiled = c.compiled
                self.compile_s += c.wall_s
            funcs = out
        self.interval, self.output = funcs["interval"], funcs["output"]
        self.output_jac, self.interval_jac = funcs["output_jac"], funcs["interval_jac"]
        self.condense_step = funcs["condense"]
        self._maps: dict = {}

    # ------------------------------------------------------------------ build
    def _build(self, rows) -> dict[str, ca.Function]:
        """The Functions take the full parameter vector ``p`` (estimates written into it) and, for the
        Jacobians, a selection ``E`` (n_p × n_θ) of the estimated columns: the generated code depends on how
        many parameters are estimated, not on which (one compilation serves every choice)."""
        dyn = self.dyn
        use_y = any(k == "y" for k, _ in rows)
        outputs = dyn.outputs
        if use_y and not outputs.is_a("SXFunction"):
            try:
                outputs = outputs.expand()
            except RuntimeError:             # e.g. a numeric linear solve inside: keep MX
                pass
        sx = dyn.rhs.is_a("SXFunction") and (not use_y or outputs.is_a("SXFunction"))
        S = ca.SX if sx else ca.MX
        opts = {"cse": True} if sx else {}
        x, u, p, E = S.sym("x", self.n_x), S.sym("u", self.n_u), S.sym("p", dyn.n_p), S.sym("E", dyn.n_p, self.n_th)
        f = dyn.rhs(x, u, p)
        y = self._channels(rows, outputs if use_y else None, x, u, p)
        args, names = [x, u, p], ["x", "u", "p"]
        f_jac = ca.Function("ident_rhs_jac", [*args, E], [ca.densify(v) for v in (
            f, ca.jacobian(f, x), ca.mtimes(ca.jacobian(f, p), E))], [*names, "E"], ["f", "Jx", "JpE"], opts)
        output = ca.Function("ident_output", args, [ca.densify(y)], names, ["y"], opts)
        output_jac = ca.Function("ident_output_jac", [*args, E], [ca.densify(v) for v in (
            y, ca.jacobian(y, x), ca.mtimes(ca.jacobian(y, p), E))], [*names, "E"], ["y", "C", "D"], opts)
        return {"interval": self._interval(dyn.rhs), "output": output, "output_jac": output_jac,
                "interval_jac": self._interval_jac(f_jac), "condense": self._condense_step()}

    def _interval(self, f: ca.Function) -> ca.Function:
        """``(x, u0, u1, p, h) -> x_next``: ``m`` RK4 sub-steps (an MX graph calling the rhs)."""
        x, u0, u1 = ca.MX.sym("x", self.n_x), ca.MX.sym("u0", self.n_u), ca.MX.sym("u1", self.n_u)
        p, h = ca.MX.sym("p", self.dyn.n_p), ca.MX.sym("h")
        m = self.substeps
        hs = h / m
        xk = x
        for j in range(m):
            ua, um, ub = (u0 + (u1 - u0) * (c / m) for c in (j, j + 0.5, j + 1.0))
            k1 = f(xk, ua, p)
            k2 = f(xk + hs / 2 * k1, um, p)
            k3 = f(xk + hs / 2 * k2, um, p)
            k4 = f(xk + hs * k3, ub, p)
            xk = xk + hs / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        return ca.Function("ident_interval", [x, u0, u1, p, h], [ca.densify(xk)], ["x", "u0", "u1", "p", "h"],
                           ["x_next"])

    def _interval_jac(self, f_jac: ca.Function) -> ca.Function:
        """``(x, u0, u1, p, h, E) -> (x_next, A, B)``: RK4 and its exact Jacobians, stage by stage.

        With ``X_i = ∂(stage state)/∂[x; θ]`` (n_x × (n_x + n_θ)), each stage's slope has the
        Jacobian ``K_i = ∂f/∂x X_i + [0 | ∂f/∂p E]`` (chain rule through the stage states), so
        the model's rhs Jacobian is evaluated once per stage (an MX graph calling one SX Function).
        """
        nx, nth, m = self.n_x, self.n_th, self.substeps
        x0, u0, u1 = ca.MX.sym("x", nx), ca.MX.sym("u0", self.n_u), ca.MX.sym("u1", self.n_u)
        p, h, E = ca.MX.sym("p", self.dyn.n_p), ca.MX.sym("h"), ca.MX.sym("E", self.dyn.n_p, nth)
        hs = h / m
        x, X = x0, ca.DM(np.hstack([np.eye(nx), np.zeros((nx, nth))]))

        def slope(xs, us, Xs):
            k, Jx, JpE = f_jac(xs, us, p, E)
            return k, ca.mtimes(Jx, Xs) + ca.horzcat(ca.MX.zeros(nx, nx), JpE)

        for j in range(m):
            ua, um, ub = (u0 + (u1 - u0) * (c / m) for c in (j, j + 0.5, j + 1.0))
            k1, K1 = slope(x, ua, X)
            k2, K2 = slope(x + hs / 2 * k1, um, X + hs / 2 * K1)
            k3, K3 = slope(x + hs / 2 * k2, um, X + hs / 2 * K2)
            k4, K4 = slope(x + hs * k3, ub, X + hs * K3)
            x = x + hs / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            X = X + hs / 6 * (K1 + 2 * K2 + 2 * K3 + K4)
        return ca.Function("ident_interval_jac", [x0, u0, u1, p, h, E],
                           [ca.densify(x), ca.densify(X[:, :nx]), ca.densify(X[:, nx:])],
                           ["x", "u0", "u1", "p", "h", "E"], ["x_next", "A", "B"])

    def _condense_step(self) -> ca.Function:
        """``(Z, A, B, g) -> A Z + [0 | B | g]``: one step of the condensing recursion."""
        nx, nz, nf, nth = self.n_x, self.n_z, self.n_f, self.n_th
        Z, A = ca.SX.sym("Z", nx, nz), ca.SX.sym("A", nx, nx)
        B, g = ca.SX.sym("B", nx, nth), ca.SX.sym("g", nx)
        add = ca.horzcat(ca.SX.zeros(nx, nf), B, g)
        return ca.Function("ident_condense", [Z, A, B, g], [ca.mtimes(A, Z) + add], ["Z", "A", "B", "g"], ["Z_next"])

    @staticmethod
    def _channels(rows, outputs, x, u, p):
        y_all = outputs(x, u, p) if outputs is not None else None
        parts = [y_all[i] if kind == "y" else x[i] for kind, i in rows]
        return ca.vertcat(*parts)

    # ------------------------------------------------------------------ evaluation
    def _cached(self, key, make):
        if key not in self._maps:
            self._maps[key] = make()
        return self._maps[key]

    def _p(self, theta: np.ndarray, p: np.ndarray) -> np.ndarray:
        q = np.array(p, dtype=float)
        q[self.theta_index] = theta
        return q

    def intervals(self, X: np.ndarray, U0: np.ndarray, U1: np.ndarray, theta: np.ndarray, p: np.ndarray,
                  H: np.ndarray) -> np.ndarray:
        """States after every interval from the rows of ``X`` (N, n_x)."""
        n = X.shape[0]
        f = self._cached(("interval", n), lambda: self.interval.map("ident_intervals", "serial", n, [3], []))
        (xn,) = _call(f, [X, U0, U1, self._p(theta, p), H])
        return xn.reshape(n, self.n_x)

    def outputs(self, X: np.ndarray, U: np.ndarray, theta: np.ndarray, p: np.ndarray, *, jac: bool = False):
        """Channels at the rows of ``X`` (N, n_y); with ``jac`` also C (N, n_y, n_x) and D (N, n_y, n_th)."""
        n = X.shape[0]
        if not jac:
            f = self._cached(("output", n), lambda: self.output.map("ident_outputs", "serial", n, [2], []))
            return _call(f, [X, U, self._p(theta, p)])[0].reshape(n, self.n_y)
        f = self._cached(("output_jac", n), lambda: self.output_jac.map("ident_outputs_jac", "serial", n, [2, 3], []))
        y, C, D = _call(f, [X, U, self._p(theta, p), self.E.T])
        C = C.reshape(n, self.n_x, self.n_y).transpose(0, 2, 1)
        D = D.reshape(n, self.n_th, self.n_y).transpose(0, 2, 1)
        return y.reshape(n, self.n_y), C, D

    def intervals_jac(self, X: np.ndarray, U0: np.ndarray, U1: np.ndarray, theta: np.ndarray, p: np.ndarray,
                      H: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """States after every interval (N, n_x) and the Jacobians A (N, n_x, n_x), B (N, n_x, n_th)."""
        n, nx, nth = X.shape[0], self.n_x, self.n_th
        f = self._cached(("interval_jac", n), lambda: self.interval_jac.map(
            "ident_intervals_jac", self.parallelization, n, [3, 5], [], {"max_num_threads": self.threads}))
        xn, A, B = _call(f, [X, U0, U1, self._p(theta, p), H, self.E.T])
        return (xn.reshape(n, nx), A.reshape(n, nx, nx).transpose(0, 2, 1), B.reshape(n, nth, nx).transpose(0, 2, 1))

    def condense(self, Z0: np.ndarray, A: np.ndarray, B: np.ndarray, g: np.ndarray) -> np.ndarray:
        """``Z_k`` (N + 1, n_x, n_z) of the recursion ``Z_{k+1} = A_k Z_k + [0 | B_k | g_k]`` from ``Z0``."""
        n, nx, nz = A.shape[0], self.n_x, self.n_z
        m = -(-n // CHUNK) * CHUNK                       # padded with A = I, B = 0, g = 0 (Z unchanged)
        At = np.zeros((m, nx, nx))
        At[:n] = A.transpose(0, 2, 1)
        At[n:] = np.eye(nx)
        Bt, gp = np.zeros((m, self.n_th, nx)), np.zeros((m, nx))
        Bt[:n], gp[:n] = B.transpose(0, 2, 1), g
        loop = self._cached(("condense",), lambda: self.condense_step.mapaccum("ident_condense_loop", CHUNK, [0], [0]))
        out, z = [], Z0.T
        for c in range(0, m, CHUNK):
            (Z,) = _call(loop, [z, At[c:c + CHUNK], Bt[c:c + CHUNK], gp[c:c + CHUNK]])
            Z = Z.reshape(CHUNK, nz, nx)
            out.append(Z)
            z = Z[-1]
        Z = np.concatenate(out)[:n]
        return np.concatenate([Z0[None], Z.transpose(0, 2, 1)])

    def simulate(self, x0: np.ndarray, U: np.ndarray, theta: np.ndarray, p: np.ndarray, H: np.ndarray) -> np.ndarray:
        """Single-shooting trajectory (N + 1, n_x) from ``x0`` on the sample grid (``U`` (N + 1, n_u))."""
        n = H.size
        m = -(-n // CHUNK) * CHUNK                       # padded with h = 0 (x unchanged)
        U0, U1, Hp = np.zeros((m, self.n_u)), np.zeros((m, self.n_u)), np.zeros(m)
        U0[:n], U1[:n], Hp[:n] = U[:-1], U[1:], H
        loop = self._cached(("loop",), lambda: _accumulated(self.interval, CHUNK, shared=(3,)))
        pv, x, out = self._p(theta, p), np.asarray(x0, dtype=float), []
        for c in range(0, m, CHUNK):
            (X,) = _call(loop, [x, U0[c:c + CHUNK], U1[c:c + CHUNK], pv, Hp[c:c + CHUNK]])
            X = X.reshape(CHUNK, self.n_x)
            out.append(X)
            x = X[-1]
        return np.vstack([np.asarray(x0, dtype=float)[None, :], np.concatenate(out)[:n]])


#: Built ShootingFunctions per model (weakly keyed on its equations, or on the Dynamics), least recently
#: used dropped beyond 8 per model: repeated identifications (Monte Carlo, benchmarks) build once.
_CACHE: "weakref.WeakKeyDictionary" = weakref.WeakKeyDictionary()


def shooting_functions(dyn: Dynamics, rows: Sequence[tuple[str, int]], theta_index: Sequence[int], n_free: int,
                       substeps: int, *, compile: bool = True, threads: int = 1) -> tuple[ShootingFunctions, bool]:
    """:class:`ShootingFunctions` for these arguments, from the in-process cache when built before;
    returns ``(functions, cache_hit)``."""
    owner = dyn.eom if dyn.eom is not None else dyn
    key = (hash(dyn.rhs), hash(dyn.outputs) if dyn.outputs is not None else 0, tuple(rows), tuple(theta_index),
           int(n_free), int(substeps), bool(compile), int(threads))
    entries = _CACHE.setdefault(owner, OrderedDict())
    if key in entries:
        entries.move_to_end(key)
        return entries[key], True
    fun = ShootingFunctions(dyn, rows, theta_index, n_free, substeps, compile=compile, threads=threads)
    entries[key] = fun
    while len(entries) > 8:
        entries.popitem(last=False)
    return fun, False


def _accumulated(f: ca.Function, n: int, shared: tuple[int, ...]) -> ca.Function:
    """``f.mapaccum`` over ``n`` steps (input 0 -> output 0), inputs ``shared`` passed once (not per step)."""
    loop = f.mapaccum(f"{f.name()}_loop", n, [0], [0])
    args = [ca.MX.sym(f.name_in(i), f.size1_in(i), f.size2_in(i) * (1 if i == 0 or i in shared else n))
            for i in range(f.n_in())]
    call = [ca.repmat(a, 1, n) if i in shared else a for i, a in enumerate(args)]
    return ca.Function(f"{f.name()}_loop", args, loop.call(call))


def _call(f: ca.Function, args: Sequence[np.ndarray]) -> list[np.ndarray]:
    """Evaluate ``f`` on numpy arrays through ``Function.buffer()`` (no DM conversions).

    A mapped argument is passed as rows (one row per sample): row-major (N, k) memory is
    the column-major (k, N) matrix CasADi expects. Outputs are dense, returned flat in
    column-major order (reshape (N, k) for mapped outputs).
    """
    buf, trigger = f.buffer()
    keep = []
    for i, a in enumerate(args):
        arr = np.ascontiguousarray(a, dtype=float).reshape(-1)
        if arr.size != f.nnz_in(i):
            raise ValueError(f"{f.name()}: argument {i} has {arr.size} values; expected {f.nnz_in(i)}.")
        keep.append(arr)
        buf.set_arg(i, memoryview(arr))
    outs = [np.empty(f.nnz_out(i)) for i in range(f.n_out())]
    for i, o in enumerate(outs):
        buf.set_res(i, memoryview(o))
    trigger()
    return outs
