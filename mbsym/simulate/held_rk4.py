"""RK4 with the dynamics' held part evaluated once per step: the method ``"rk4-held"``.

For dynamics that declare a :class:`~mbsym.held.HeldPart` (``ẋ = f(x, u, p, z)``, ``z = g(x, u, p)``
expensive), one step of length ``h`` from ``x_k`` is

    z_k = g(x_k, u(t_k), p),  then the classical RK4 stages of  ẋ = f(x, u(t), p, z_k).

``z`` is held over the step as OpenFAST's glue code holds AeroDyn's loads over an ElastoDyn step
(``InterpOrder = 0``): the held quantities carry a first-order error in their variation over a step,
the remainder keeps RK4's fourth order. Its cost per step is one evaluation of ``g`` and four of
``f``, against four of ``g`` and ``f`` with ``"rk4"``. Choose the step for the held part's variation
(for blade-element aerodynamics: the rotation and the wind's sampling; ≤ 25 ms for a 5 MW turbine,
see ``benchmarks/README.md``, "blade-speed").
"""

from __future__ import annotations

from typing import ClassVar

from .checks import SimulationOptionError
from .fixed import RK4

__all__ = ["HeldRK4", "held_rk4_step"]


def held_rk4_step(held, x, U, p, h, z):
    """One RK4 step of ``ẋ = held.rhs(x, u, p, z)``; returns ``(x_next, k1)``.

    ``U`` holds the inputs at the stage times ``t``, ``t + h/2``, ``t + h`` (columns); ``z`` is the held
    value, or a tuple of its values at those three times (an extrapolated held part,
    :mod:`mbsym.simulate.held_carry`).
    """
    f = held.rhs
    z0, zm, z1 = z if isinstance(z, tuple) else (z, z, z)
    k1 = f(x, U[:, 0], p, z0)
    k2 = f(x + (h / 2) * k1, U[:, 1], p, zm)
    k3 = f(x + (h / 2) * k2, U[:, 1], p, zm)
    k4 = f(x + h * k3, U[:, 2], p, z1)
    return x + (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4), k1


class HeldRK4(RK4):
    """Classical RK4 with the plant's held part evaluated once per step (see the module docstring).

    Raises
    ------
    SimulationOptionError
        If the dynamics declare no held part (use ``"rk4"``).
    """

    name: ClassVar[str] = "rk4-held"
    order: ClassVar[int] = 1
    needs_held: ClassVar[bool] = True
    rhs_per_step: ClassVar[int] = 4

    def __init__(self, problem) -> None:
        held = getattr(problem.plant, "held", None)
        if held is None:
            raise SimulationOptionError(
                f"method 'rk4-held' holds the part of the dynamics that {problem.plant.name!r} declares as held "
                "(mbsym.held.HeldPart, e.g. the blade-element aerodynamics of an operating turbine), but this "
                "model declares none; use method='rk4'.")
        super().__init__(problem)

    def _step(self, x, U, p, h):
        held = self.problem.plant.held
        z = held.part(x, U[:, 0], p)
        return held_rk4_step(held, x, U, p, h, z)
