"""The discrete multistage problem every solver of :mod:`mbsym.control` works on.

A :class:`StageProblem` is the NLP

    min   ‖r₀(x₀, p)‖² + Σₖ₌₀ᴺ⁻¹ (‖r(xₖ, uₖ, dₖ, p)‖² + l(xₖ, uₖ, dₖ, p)) + ‖r_N(x_N, d_N, p)‖² + l_N(x_N, d_N, p)
    s.t.  xₖ₊₁ = f(xₖ, uₖ, dₖ, p),   lc ≤ c(xₖ, uₖ, dₖ, p) ≤ uc,   lc_N ≤ c_N(x_N, d_N, p) ≤ uc_N,
          lx ≤ xₖ ≤ ux,   lu ≤ uₖ ≤ uu

with decision variables in stage order ``w = [x₀, u₀, x₁, u₁, …, x_N]``,
per-stage parameters ``dₖ`` (previews, references, measurements) and global
parameters ``p``. ``r`` are least-squares residuals (Gauss–Newton Hessians), ``l``
general costs. :class:`~mbsym.control.ocp.OCP` (NMPC) and
:class:`~mbsym.control.mhe.MHE` both build one; the solvers never see a model.

Constraint vector order (what fatrop and hpipm expect): ``[gap₀; c₀; gap₁; c₁; …;
gap_{N-1}; c_{N-1}; c_N]`` with ``gapₖ = xₖ₊₁ − f(xₖ, uₖ, dₖ, p)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from ..exceptions import DimensionError

__all__ = ["StageProblem", "Layout"]


@dataclass(frozen=True)
class Layout:
    """Index arithmetic of ``w = [x₀, u₀, …, x_{N-1}, u_{N-1}, x_N]`` and of the constraint vector."""

    N: int
    n_x: int
    n_u: int
    n_c: int
    n_cN: int

    @property
    def n_w(self) -> int:
        return self.N * (self.n_x + self.n_u) + self.n_x

    @property
    def n_g(self) -> int:
        return self.N * (self.n_x + self.n_c) + self.n_cN

    def split(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """States ``(nx, N+1)`` and controls ``(nu, N)`` of ``w``."""
        w = np.asarray(w, dtype=float).reshape(-1)
        body = w[: self.N * (self.n_x + self.n_u)].reshape(self.N, self.n_x + self.n_u).T
        X = np.concatenate([body[: self.n_x], w[-self.n_x:].reshape(-1, 1)], axis=1) if self.n_x else \
            np.zeros((0, self.N + 1))
        return X, body[self.n_x:]

    def join(self, X: np.ndarray, U: np.ndarray) -> np.ndarray:
        """``w`` from states ``(nx, N+1)`` and controls ``(nu, N)``."""
        body = np.concatenate([np.asarray(X)[:, : self.N], np.asarray(U)], axis=0).T.reshape(-1)
        return np.concatenate([body, np.asarray(X)[:, self.N]])

    def shift(self, w: np.ndarray) -> np.ndarray:
        """``w`` moved one stage ahead; the last state and control are repeated."""
        X, U = self.split(w)
        X = np.concatenate([X[:, 1:], X[:, -1:]], axis=1)
        U = np.concatenate([U[:, 1:], U[:, -1:]], axis=1) if self.N > 1 else U
        return self.join(X, U)

    def x_index(self, k: int) -> slice:
        """Slice of ``xₖ`` in ``w``."""
        start = k * (self.n_x + self.n_u)
        return slice(start, start + self.n_x)

    def u_index(self, k: int) -> slice:
        """Slice of ``uₖ`` in ``w``."""
        start = k * (self.n_x + self.n_u) + self.n_x
        return slice(start, start + self.n_u)


@dataclass(frozen=True)
class StageProblem:
    """A discrete multistage NLP (see the module docstring).

    Attributes
    ----------
    N : int
        Number of stages (intervals).
    path : casadi.Function
        ``(x, u, d, p) -> (f, c, r, l)``.
    terminal : casadi.Function
        ``(x, d, p) -> (c, r, l)``.
    initial : casadi.Function or None
        ``(x, p) -> r₀`` (an arrival cost), or None.
    lbx, ubx : array (nx)
        State bounds (every stage; the solvers replace them at a fixed initial state).
    lbu, ubu : array (nu)
    lbc, ubc : array (nc)
        Path-constraint bounds.
    c0_rows : array of bool (nc)
        Path-constraint rows imposed at stage 0 (rows that ``u₀`` cannot change are
        dropped there: the initial state is given).
    lbcN, ubcN : array (ncN)
    names : dict
        ``"x"``, ``"u"``, ``"d"``, ``"p"``: names of every entry (messages, results).
    dynamics_jacobian : casadi.Function or None
        ``(x, u, d, p) -> (f, ∂f/∂[x; u])`` computed without expanding the stage map
        (chained RK4 sensitivities); the Gauss–Newton SQP uses it instead of
        differentiating ``path``.
    """

    N: int
    path: ca.Function
    terminal: ca.Function
    initial: ca.Function | None
    lbx: np.ndarray
    ubx: np.ndarray
    lbu: np.ndarray
    ubu: np.ndarray
    lbc: np.ndarray
    ubc: np.ndarray
    c0_rows: np.ndarray
    lbcN: np.ndarray
    ubcN: np.ndarray
    names: dict = field(default_factory=dict)
    dynamics_jacobian: ca.Function | None = None

    def __post_init__(self) -> None:
        checks = [("lbx", self.n_x), ("ubx", self.n_x), ("lbu", self.n_u), ("ubu", self.n_u), ("lbc", self.n_c),
                  ("ubc", self.n_c), ("c0_rows", self.n_c), ("lbcN", self.n_cN), ("ubcN", self.n_cN)]
        for name, n in checks:
            if np.asarray(getattr(self, name)).size != n:
                raise DimensionError(f"StageProblem.{name} has {np.asarray(getattr(self, name)).size} entries; "
                                     f"expected {n}.")

    n_x = property(lambda self: self.path.size1_in(0), doc="States per stage.")
    n_u = property(lambda self: self.path.size1_in(1), doc="Controls per stage (with collocation variables).")
    n_d = property(lambda self: self.path.size1_in(2), doc="Stage parameters per stage.")
    n_p = property(lambda self: self.path.size1_in(3), doc="Global parameters.")
    n_c = property(lambda self: self.path.size1_out(1), doc="Path constraints per stage.")
    n_cN = property(lambda self: self.terminal.size1_out(0), doc="Terminal constraints.")

    @property
    def layout(self) -> Layout:
        return Layout(self.N, self.n_x, self.n_u, self.n_c, self.n_cN)

    def bounds(self, x0: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(lbw, ubw, lbg, ubg)`` of the whole NLP; ``x0`` given: ``x₀`` fixed to it."""
        L = self.layout
        X_lo = np.tile(self.lbx.reshape(-1, 1), (1, self.N + 1))
        X_hi = np.tile(self.ubx.reshape(-1, 1), (1, self.N + 1))
        if x0 is not None:
            X_lo[:, 0] = X_hi[:, 0] = x0
        U_lo = np.tile(self.lbu.reshape(-1, 1), (1, self.N))
        U_hi = np.tile(self.ubu.reshape(-1, 1), (1, self.N))
        C_lo = np.tile(self.lbc.reshape(-1, 1), (1, self.N))
        C_hi = np.tile(self.ubc.reshape(-1, 1), (1, self.N))
        C_lo[~self.c0_rows, 0], C_hi[~self.c0_rows, 0] = -np.inf, np.inf
        zeros = np.zeros((self.n_x, self.N))
        G_lo = np.concatenate([zeros, C_lo], axis=0).T.reshape(-1)
        G_hi = np.concatenate([zeros, C_hi], axis=0).T.reshape(-1)
        return (L.join(X_lo, U_lo), L.join(X_hi, U_hi), np.concatenate([G_lo, self.lbcN]),
                np.concatenate([G_hi, self.ubcN]))

    def stage_parameters(self, D: np.ndarray | None) -> np.ndarray:
        """Per-stage parameters as an ``(nd, N+1)`` array (zeros when None)."""
        if D is None:
            return np.zeros((self.n_d, self.N + 1))
        D = np.asarray(D, dtype=float)
        if D.shape != (self.n_d, self.N + 1):
            raise DimensionError(f"stage parameters have shape {D.shape}; expected {(self.n_d, self.N + 1)} "
                                 f"(names {self.names.get('d', [])}, one column per stage 0..N).")
        return D
