"""Implicit second-order methods for structural dynamics: Newmark and generalized-alpha.

Both integrate the residual form ``e(q, qd, qdd, u, p) = F - M qdd = 0``
directly (no first-order rhs, no inverse of M), in the generalized-alpha form of
Arnold & Bruls (Multibody Syst. Dyn. 18, 2007), which is second-order accurate
for nonlinear systems: with the acceleration-like variable ``a``,

    q1  = q + h qd + h^2 (1/2 - beta) a + h^2 beta a1
    qd1 = qd + h (1 - gamma) a + h gamma a1
    (1 - alpha_m) a1 + alpha_m a = (1 - alpha_f) qdd1 + alpha_f qdd
    e(q1, qd1, qdd1, u(t + h), p) = 0

solved for ``qdd1`` by Newton's method on the exact Jacobian of the residual,
``S = de/dqdd + gamma' h de/dqd + beta' h^2 de/dq`` (``gamma' = gamma (1 -
alpha_f) / (1 - alpha_m)``, ``beta'`` likewise), fresh at every iteration, from
the predictor ``qdd1 = qdd``. The iteration stops once a correction is below
``newton_stop`` (1e-8 relative to ``1 + |qdd1|``; what is left is of the order
of its square) or after ``max_newton_iterations`` (10); a step whose last
correction exceeds ``newton_tol`` (1e-6) raises
:class:`~mbsym.exceptions.IntegrationError`. The loop is MX glue around one
SX iteration Function: iterations after convergence are skipped at run time
(``Function.conditional``), so an easy step costs two iterations (measured: 2.0
per step at dt = 0.01 s on the turbine scenes, 3-4.5 at dt = 0.5-2 s). A fixed
number of modified-Newton corrections (one Jacobian per step) was cheaper at
small steps but failed to converge at dt >= 0.1 s on the stiff rotor scene.

- ``newmark``: the average-acceleration (trapezoidal) rule, alpha_m = alpha_f =
  0, gamma = 1/2, beta = 1/4: A-stable, no numerical damping, conserves the
  energy of linear undamped systems exactly.
- ``generalized-alpha``: Chung & Hulbert's parameters from the spectral radius
  at infinity ``rho_inf`` (0.8): alpha_m = (2 rho - 1)/(rho + 1), alpha_f =
  rho/(rho + 1), gamma = 1/2 + alpha_f - alpha_m, beta = (gamma + 1/2)^2 / 4;
  A-stable, damps the unresolved high frequencies.

The method state is ``z = [q; qd; qdd; a]``, so the loop and the output
interpolation (cubic Hermite with ``[qd; qdd]``) need no extra rhs calls. The
statistics count Newton iterations as ``n_jac`` (and residuals as ``n_rhs``).
"""

from __future__ import annotations

from typing import ClassVar

import casadi as ca
import numpy as np

from ..exceptions import IntegrationError
from .fixed import FixedStepMethod

__all__ = ["GeneralizedAlpha", "Newmark", "newton_jacobian_function"]


def newton_jacobian_function(eom) -> ca.Function:
    """``(q, qd, qdd, u, p, cv, cq) -> (e, S)`` with ``S = de/dqdd + cv de/dqd + cq de/dq`` (SX, cse)."""
    n = eom.n_q
    q, qd, qdd = ca.SX.sym("q", n), ca.SX.sym("qd", n), ca.SX.sym("qdd", n)
    u, p = ca.SX.sym("u", eom.n_u), ca.SX.sym("p", eom.n_p)
    cv, cq = ca.SX.sym("cv"), ca.SX.sym("cq")
    e = eom.functions.residual(q, qd, qdd, u, p)
    S = ca.jacobian(e, qdd) + cv * ca.jacobian(e, qd) + cq * ca.jacobian(e, q)
    return ca.Function(f"{eom.name}_newton", [q, qd, qdd, u, p, cv, cq], [e, ca.densify(S)],
                       ["q", "qd", "qdd", "u", "p", "cv", "cq"], ["e", "S"], {"cse": True})


class GeneralizedAlpha(FixedStepMethod):
    """Generalized-alpha (Chung & Hulbert; Arnold & Bruls form), ``rho_inf = 0.8``, order 2, A-stable."""

    name: ClassVar[str] = "generalized-alpha"
    order: ClassVar[int] = 2
    implicit: ClassVar[bool] = True
    second_order: ClassVar[bool] = True
    nodes: ClassVar[tuple[float, ...]] = (1.0,)
    stability_radius: ClassVar[float] = float("inf")
    #: Spectral radius of the amplification matrix at infinite frequency [-].
    rho_inf: ClassVar[float] = 0.8
    #: Largest number of Newton iterations per step (each with a fresh Jacobian).
    max_newton_iterations: ClassVar[int] = 10
    #: Newton stops once a correction is below this, relative to 1 + |qdd| [-] (what is left is ~ its square).
    newton_stop: ClassVar[float] = 1e-8
    #: A step whose last correction exceeds this raises IntegrationError [-].
    newton_tol: ClassVar[float] = 1e-6

    @classmethod
    def settings(cls) -> tuple:
        return cls.coefficients(), cls.max_newton_iterations, cls.newton_stop, cls.newton_tol

    @classmethod
    def coefficients(cls) -> tuple[float, float, float, float]:
        """``(alpha_m, alpha_f, gamma, beta)``."""
        r = cls.rho_inf
        am, af = (2 * r - 1) / (r + 1), r / (r + 1)
        gamma = 0.5 + af - am
        return am, af, gamma, 0.25 * (gamma + 0.5) ** 2

    def _state_size(self) -> int:
        return 2 * self.problem.eom.n_x

    def _initial(self) -> np.ndarray:
        pr, n = self.problem, self.problem.eom.n_q
        xd = np.array(pr.eom.functions.rhs(pr.x0, pr.inputs.at(0.0), pr.p)).reshape(-1)
        return np.concatenate([pr.x0, xd[n:], xd[n:]])            # a(0) = qdd(0)

    def _symbol_class(self) -> type:
        return ca.MX          # the Newton loop is MX glue with conditional (skipped) iterations

    def _newton_iteration(self) -> ca.Function:
        """``(z, A, u, p, h, c) -> (A - S^-1 e, |correction| / (1 + |A|))`` at the step's end state for ``A``."""
        eom = self.problem.eom
        n = eom.n_q
        sym = ca.SX if n <= 8 else ca.MX      # as the model's rhs: symbolic solve up to 8 DOFs, else numeric QR
        z, A, u = sym.sym("z", 4 * n), sym.sym("A", n), sym.sym("u", eom.n_u)
        p, h, c = sym.sym("p", eom.n_p), sym.sym("h"), sym.sym("c")
        q, v, qdd, a = z[:n], z[n:2 * n], z[2 * n:3 * n], z[3 * n:]
        am, af, gamma, beta = self.coefficients()
        scale = (1 - af) / (1 - am)
        a1 = (af * qdd - am * a + (1 - af) * A) / (1 - am)
        q1, v1 = q + h * v + h * h * ((0.5 - beta) * a + beta * a1), v + h * ((1 - gamma) * a + gamma * a1)
        e, S = newton_jacobian_function(eom)(q1, v1, A, u, p, gamma * scale * h, beta * scale * h * h)
        delta = ca.solve(S, e) if sym is ca.SX else ca.solve(S, e, "qr")
        A_new = A - delta
        opts = {"cse": True} if sym is ca.SX else {}
        return ca.Function(f"{eom.name}_{self.name.replace('-', '_')}_newton", [z, A, u, p, h, c],
                           [A_new, ca.norm_inf(delta) / (1 + ca.norm_inf(A_new))], opts)

    def _step(self, z, U, p, h):
        n = self.problem.eom.n_q
        q, v, qdd, a = z[:n], z[n:2 * n], z[2 * n:3 * n], z[3 * n:]
        u = U[:, 0]
        it = self._newton_iteration()
        A_, c_ = ca.MX.sym("A", n), ca.MX.sym("c")
        skip = ca.Function("skip", [ca.MX.sym("z", 4 * n), A_, ca.MX.sym("u", u.numel()), ca.MX.sym("p", p.numel()),
                                    ca.MX.sym("h"), c_], [A_, c_])
        switch = ca.Function.conditional(f"{it.name()}_or_skip", [skip], it)   # index 0: converged, skip
        A, corr = it(z, qdd, u, p, h, 1.0)                                       # predictor A = qdd
        iterations = 1
        for _ in range(self.max_newton_iterations - 1):
            more = corr > self.newton_stop
            A, corr = switch(more, z, A, u, p, h, corr)
            iterations = iterations + more
        am, af, gamma, beta = self.coefficients()
        a1 = (af * qdd - am * a + (1 - af) * A) / (1 - am)
        q1, v1 = q + h * v + h * h * ((0.5 - beta) * a + beta * a1), v + h * ((1 - gamma) * a + gamma * a1)
        return ca.vertcat(q1, v1, A, a1), ca.vertcat(corr, iterations)

    def _derivatives(self, Zr, Ar, t_grid, need_end):
        n = self.problem.eom.n_q
        return Zr[:, n: 3 * n], 0               # [qd; qdd] at every grid point

    def _counts(self, A: np.ndarray) -> tuple[int, int]:
        n_it = int(np.sum(A[1]))
        return n_it, n_it               # each iteration: one residual and one Jacobian

    def _aux_failure(self, A: np.ndarray) -> int | None:
        bad = np.flatnonzero(~(A[0] <= self.newton_tol))        # NaN counts as a failure
        return int(bad[0]) if bad.size else None

    def _raise_aux_failure(self, k: int, A: np.ndarray, Z: np.ndarray, t_grid: np.ndarray, offset: int = 0) -> None:
        pr = self.problem
        x = Z[: pr.plant.n_x, k + 1]
        i = int(np.argmax(np.abs(x) / (1.0 + np.abs(pr.x0))))
        raise IntegrationError(
            f"method {self.name!r} failed at t = {t_grid[k + 1]:.6g} s (step {offset + k + 1} of {pr.n_steps}, step size "
            f"dt = {pr.dt:.6g} s): the Newton iteration did not converge in {self.max_newton_iterations} iterations "
            f"(last correction {A[0, k]:.3g} relative to 1 + |qdd|, tolerance {self.newton_tol:g}). "
            f"State {pr.plant.states[i]!r} = {x[i]:.4g} (largest relative to x0). Reduce dt; if the failure "
            "stays, the solution may grow without bound or the residual may be undefined there."
        )


class Newmark(GeneralizedAlpha):
    """Newmark's average-acceleration rule (gamma = 1/2, beta = 1/4): order 2, A-stable, energy-conserving."""

    name: ClassVar[str] = "newmark"

    @classmethod
    def coefficients(cls) -> tuple[float, float, float, float]:
        return 0.0, 0.0, 0.5, 0.25
