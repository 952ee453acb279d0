"""Adams multistep methods with the dynamics' held part, in a compiled closed loop: ``"abm4-held"``, ``"ab4-held"``.

ElastoDyn integrates the structure with the method of its deck's ``Method`` key (1 RK4, 2 AB4, 3 ABM4; the
NREL 5 MW decks say 3). These are the multistep ones, for a plant with a :class:`~mbsym.held.HeldPart`
(``ẋ = f(x, u, p, z)``, ``z = g(x, u, p)``, e.g. blade-element aerodynamics) and a CasADi controller in the loop,
one step per controller sample of length ``h``, with ``f_k = f(x_k, u_k, p, z(t_k))``:

* ``"ab4-held"`` (Adams-Bashforth 4, explicit)::

      x_{n+1} = x_n + h/24 (55 f_n - 59 f_{n-1} + 37 f_{n-2} - 9 f_{n-3})

  one right-hand side per step (``f_n``);
* ``"abm4-held"`` (the AB4 predictor ``x^p``, one evaluation ``f^p = f(x^p, u_{n+1}, p, z(t_{n+1}))`` with the
  exogenous inputs at t_{n+1} and the commands of sample n, and the Adams-Moulton 4 corrector)::

      x_{n+1} = x_n + h/24 (9 f^p + 19 f_n - 5 f_{n-1} + f_{n-2})

  two right-hand sides per step (RK4: four).

Coefficients and start-up as OpenFAST's ElastoDyn (modules/elastodyn/src/ElastoDyn.f90, ``ED_AB4``/``ED_ABM4``,
OpenFAST commit 2895884d, read for the facts, not copied): the derivative at the step start is stored every
step, steps ``n <= 2`` (the first three) are RK4 steps, and from the fourth step on the four stored derivatives
``f_n .. f_{n-3}`` drive the predictor. Here a start-up step is a full RK4 step with the held part evaluated at
each stage (4 evaluations of ``g``, three times per run), so the history starts fourth-order accurate; a step
shorter than the sample (the run's last, ending at ``tmax``) is an RK4 step too (the formulas assume equal steps).
Both branches live in one generated body, a ``casadi.Function.conditional`` that runs only the taken one.

The history ``[f_{n-1}; f_{n-2}; f_{n-3}; count]`` (``3 n_x + 1`` values) is carried from sample to sample in the
body's carried vector, after the held part's own history (:mod:`.held_carry`); the held part is refreshed every
``held_dt`` and extrapolated (``held_order``) at the times the method needs: ``t_n`` (both) and ``t_{n+1}``
(``"abm4-held"``).

Commands: the controller's commands are held over a sample (zero-order hold), so the derivatives of the history
were evaluated under the commands of their own samples; the formulas see the commands as varying smoothly across
the samples (as ElastoDyn sees ServoDyn's extrapolated commands), a first-order difference in the commands'
change per sample from the zero-order hold integrated exactly. With the commands constant over a run (and the held
part fresh at ``t_n``) both methods are fourth order; the held part extrapolated at ``t_{n+1}`` with
``held_order`` k adds an error of order ``k + 1`` to ``"abm4-held"``'s corrector.

Stability (one mode ``ẍ + 2ζωẋ + ω²x = 0``, step ``h``; from the methods' characteristic polynomials): AB4 is
stable for ``ω h`` below ~0.43 (ζ ≤ 5 %) and for real eigenvalues ``|λ| h < 0.30``; ABM4 as here
(predict-evaluate-correct) is weakly anti-damping on the imaginary axis (an amplitude growth ~(ω h)^6 per step:
+0.009 % per period at ω h = 0.157), so a mode needs some damping: stable up to ω h ≈ 0.57 at ζ = 0.5 %, 0.92 at
ζ = 2 %, and ``|λ| h < 1.29`` on the real axis; RK4 up to 2.8 (:func:`stability_limit`). At 6.25 ms the NREL 5 MW's
structural modes (≤ ~4 Hz: ω h ≤ 0.16) are well inside; the operating turbine's generator-torque lag (τ = 0.01 s:
|λ| h = 0.63) is outside AB4's interval, so :func:`mbsym.wind.operation.simulate_turbine` refuses ``"ab4-held"``
there. The held part extrapolated to t_{n+1} enters the corrector explicitly: a mode it drives strongly and fast
narrows ABM4's interval further (a held damping force of ζ = 0.7 diverged at ω h = 0.88 in the tests, inside the
method's own 0.93).
"""

from __future__ import annotations

from functools import lru_cache
from typing import ClassVar

import casadi as ca
import numpy as np

from .checks import SimulationOptionError
from .held_rk4 import HeldRK4

__all__ = ["MULTISTEP_METHODS", "HELD_METHODS", "ELASTODYN_METHODS", "MultistepHistory", "HeldABM4", "HeldAB4",
           "AB4", "ABM4_CORRECTOR", "stability_limit"]

#: Adams-Bashforth 4 weights of f_n, f_{n-1}, f_{n-2}, f_{n-3}, over 24 (ED_AB4).
AB4 = (55.0, -59.0, 37.0, -9.0)
#: Adams-Moulton 4 weights of f^p (at t_{n+1}), f_n, f_{n-1}, f_{n-2}, over 24 (ED_ABM4).
ABM4_CORRECTOR = (9.0, 19.0, -5.0, 1.0)
#: Derivatives stored before the multistep formula takes over (ElastoDyn: steps n <= 2 are RK4 steps).
START_STEPS = 3
#: Closed-loop multistep methods with a held part -> right-hand sides per step after the start-up.
MULTISTEP_METHODS = {"abm4-held": 2, "ab4-held": 1}
#: Methods that treat the plant's held part apart (the carried-held closed loop).
HELD_METHODS = ("rk4-held", *MULTISTEP_METHODS)
#: ElastoDyn's Method key -> the closed-loop method of a plant with a held part.
ELASTODYN_METHODS = {1: "rk4-held", 2: "ab4-held", 3: "abm4-held"}


class MultistepHistory:
    """The carried derivative history of one closed-loop multistep method (module docstring).

    Parameters
    ----------
    plant : Plant
        With a held part ``plant.held``.
    method : str
        ``"abm4-held"`` or ``"ab4-held"``.
    h_nominal : float
        The controller's sample time [s]: a step of another length is taken by RK4.
    """

    def __init__(self, plant, method: str, h_nominal: float) -> None:
        self.plant, self.method, self.h_nominal = plant, method, float(h_nominal)
        self.n_x = plant.n_x
        self.n_carry = START_STEPS * self.n_x + 1
        self.corrects = method == "abm4-held"
        self.step = self._step_function()

    def initial(self) -> np.ndarray:
        """The history before the first sample: empty (count 0)."""
        return np.zeros(self.n_carry)

    def rhs_per_step(self) -> int:
        """Right-hand sides per step once the history is full."""
        return MULTISTEP_METHODS[self.method]

    # ------------------------------------------------------------------ graph
    def index(self, hist, h):
        """The branch of :attr:`step`: 1 (multistep) when the history is full and the step nominal, else 0 (RK4)."""
        full = hist[-1] >= START_STEPS - 0.5
        nominal = ca.fabs(h - self.h_nominal) <= 1e-9 * self.h_nominal
        return ca.if_else(ca.logic_and(full, nominal), 1, 0)

    def _step_function(self) -> ca.Function:
        """``(index, x, U, p, h, z0, z1, hist) -> (x_next, f_n, hist_next)``: index 0 an RK4 step with the held
        part evaluated at each stage, 1 the multistep step with the held values ``z0`` (t_n) and ``z1``
        (t_{n+1}); ``U`` the inputs at t_n, t_n + h/2, t_n + h (columns); ``f_n`` the derivative the method takes
        at t_n (also the dense output's start derivative)."""
        plant, held, n = self.plant, self.plant.held, self.n_x
        tag = self.method.replace("-", "_")
        x, p, h = ca.MX.sym("x", n), ca.MX.sym("p", plant.n_p), ca.MX.sym("h")
        U = ca.MX.sym("U", plant.n_u, 3)
        z0, z1 = ca.MX.sym("z0", held.n_z), ca.MX.sym("z1", held.n_z)
        hist = ca.MX.sym("hist", self.n_carry)
        args, names = [x, U, p, h, z0, z1, hist], ["x", "U", "p", "h", "z0", "z1", "hist"]
        outs = ["x_next", "f_n", "hist_next"]
        start = ca.Function(f"{plant.name}_{tag}_start", args, list(self._rk4(x, U, p, h, hist)), names, outs)
        multi = ca.Function(f"{plant.name}_{tag}_step", args, list(self._adams(x, U, p, h, z0, z1, hist)),
                            names, outs)
        return ca.Function.conditional(f"{plant.name}_{tag}", [start], multi)

    def _rk4(self, x, U, p, h, hist):
        """A classical RK4 step of the full dynamics (the held part evaluated at each stage)."""
        held = self.plant.held

        def f(xs, u):
            return held.rhs(xs, u, p, held.part(xs, u, p))

        k1 = f(x, U[:, 0])
        k2 = f(x + (h / 2) * k1, U[:, 1])
        k3 = f(x + (h / 2) * k2, U[:, 1])
        k4 = f(x + h * k3, U[:, 2])
        return x + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4), k1, self._pushed(hist, k1)

    def _adams(self, x, U, p, h, z0, z1, hist):
        """AB4 (and the AM4 corrector for abm4-held) from the history and the derivative at t_n."""
        rhs, n = self.plant.held.rhs, self.n_x
        old = [hist[i * n:(i + 1) * n] for i in range(START_STEPS)]
        f_n = rhs(x, U[:, 0], p, z0)
        fs = [f_n, *old]
        x_next = x + (h / 24) * sum(c * v for c, v in zip(AB4, fs))
        if self.corrects:
            f_p = rhs(x_next, U[:, 2], p, z1)
            x_next = x + (h / 24) * sum(c * v for c, v in zip(ABM4_CORRECTOR, [f_p, *fs[:3]]))
        return x_next, f_n, self._pushed(hist, f_n)

    def _pushed(self, hist, f_n):
        """The history with ``f_n`` the newest derivative (one more counted, at most :data:`START_STEPS`)."""
        n = self.n_x
        return ca.vertcat(f_n, hist[:(START_STEPS - 1) * n], ca.fmin(hist[-1] + 1, START_STEPS))


class _ClosedLoopMultistep(HeldRK4):
    """Registry entry of a closed-loop multistep method: refused outside a controlled loop (it carries its history
    from controller sample to sample inside the generated loop)."""

    order: ClassVar[int] = 1          # the held part held over a step (held_order 0): first order, as "rk4-held"

    def __init__(self, problem) -> None:
        raise SimulationOptionError(
            f"method {self.name!r} carries its derivative history from controller sample to sample inside the "
            "generated closed loop: give controller= (a DiscreteController with a CasADi law) and dt = its sample "
            "time; without a controller use 'rk4-held', 'rk4' or an adaptive method ('adams': CVODES' Adams-Moulton).")


class HeldABM4(_ClosedLoopMultistep):
    """``"abm4-held"`` (module docstring): controlled loops only."""

    name: ClassVar[str] = "abm4-held"
    rhs_per_step: ClassVar[int] = 2


class HeldAB4(_ClosedLoopMultistep):
    """``"ab4-held"`` (module docstring): controlled loops only."""

    name: ClassVar[str] = "ab4-held"
    rhs_per_step: ClassVar[int] = 1


def stability_limit(method: str, zeta: float) -> float:
    """The largest ``|λ| h`` for which ``method`` is stable on a mode ``λ = |λ| (-ζ + i √(1 - ζ²))`` (ζ = 1: a real
    eigenvalue): the first ``|λ| h`` at which a root of the method's characteristic polynomial for ``ẋ = λ x``
    leaves the unit circle (to 1e-4). E.g. AB4 0.30 (ζ = 1), 0.33 (0.7), 0.43 (0.02); ABM4 1.29, 0.93, 0.92."""
    return _stability_limit(method, round(float(min(max(zeta, 0.0), 1.0)), 6))


@lru_cache(maxsize=None)
def _stability_limit(method: str, zeta: float) -> float:
    direction = complex(-zeta, np.sqrt(max(1.0 - zeta * zeta, 0.0)))
    coarse = np.arange(1, 401) * 1e-2                                  # |λ| h up to 4, then bisection
    unstable = np.flatnonzero(_spectral_radius(method, coarse * direction) > 1.0 + 1e-9)
    if not unstable.size:
        return float(coarse[-1])
    lo, hi = (coarse[unstable[0] - 1] if unstable[0] else 0.0), coarse[unstable[0]]
    while hi - lo > 1e-4:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if _spectral_radius(method, np.array([mid * direction]))[0] > 1.0 + 1e-9 else (mid, hi)
    return float(lo)


def _spectral_radius(method: str, z: np.ndarray) -> np.ndarray:
    """Largest root modulus of the method's recurrence ``x_{n+1} = Σ c_i x_{n-i}`` for ``ẋ = λ x``, ``z = λ h``."""
    a = z / 24.0
    pred = np.stack([1.0 + AB4[0] * a, AB4[1] * a, AB4[2] * a, AB4[3] * a], axis=1)     # x^p on x_n .. x_{n-3}
    if method == "ab4-held":
        nxt = pred
    else:
        c = ABM4_CORRECTOR
        nxt = c[0] * a[:, None] * pred + np.stack([1.0 + c[1] * a, c[2] * a, c[3] * a, 0.0 * a], axis=1)
    companion = np.zeros((z.size, 4, 4), dtype=complex)
    companion[:, 0, :] = nxt
    companion[:, 1, 0] = companion[:, 2, 1] = companion[:, 3, 2] = 1.0
    return np.max(np.abs(np.linalg.eigvals(companion)), axis=1)
