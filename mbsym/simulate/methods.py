"""The registry of integration methods: ``METHODS[name] -> Method subclass``.

To add a method, subclass :class:`~mbsym.simulate.base.Method` (or
:class:`~mbsym.simulate.fixed.FixedStepMethod` for an explicit one-step scheme:
give ``nodes`` and ``_step``), declare ``name``, ``order``, ``kind`` and
``implicit``, and add it below.

=====================  ===========  =====  ========  =========================================
name                   kind         order  implicit  what
=====================  ===========  =====  ========  =========================================
``rk4``                fixed-step   4      no        classical Runge-Kutta, loop in CasADi
``rk4-held``           fixed-step   1      no        RK4, the dynamics' held part once per step
``abm4-held``          fixed-step   1      no        ElastoDyn's ABM4, held part; controlled loops
``ab4-held``           fixed-step   1      no        ElastoDyn's AB4, held part; controlled loops
``newmark``            fixed-step   2      yes       average acceleration, residual form
``generalized-alpha``  fixed-step   2      yes       Chung-Hulbert rho_inf = 0.8, residual form
``adams``              adaptive     5      no        CVODES Adams-Moulton, functional iteration
``cvodes``             adaptive     5      yes       CVODES BDF, exact Jacobian
``idas``               adaptive     5      yes       IDAS BDF on the residual form
``scipy-radau``        adaptive     5      yes       scipy Radau IIA, exact Jacobian
``scipy-bdf``          adaptive     5      yes       scipy BDF, exact Jacobian
=====================  ===========  =====  ========  =========================================
"""

from __future__ import annotations

from types import MappingProxyType
from typing import Mapping

from .base import Method
from .casadi_methods import Adams, Cvodes, Idas
from .checks import SimulationOptionError
from .fixed import RK4
from .held_multistep import HeldAB4, HeldABM4
from .held_rk4 import HeldRK4
from .scipy_methods import ScipyBDF, ScipyRadau
from .second_order import GeneralizedAlpha, Newmark

__all__ = ["METHODS", "get_method"]

#: Integration methods by name (read-only).
METHODS: Mapping[str, type[Method]] = MappingProxyType({m.name: m for m in (
    RK4, HeldRK4, HeldABM4, HeldAB4, Newmark, GeneralizedAlpha, Adams, Cvodes, Idas, ScipyRadau, ScipyBDF)})


def get_method(name) -> type[Method]:
    """The method class registered under ``name``.

    Raises
    ------
    SimulationOptionError
        If no method has that name (the message lists them).

    Examples
    --------
    >>> from mbsym.simulate import get_method
    >>> m = get_method("rk4")
    >>> m.order, m.kind
    (4, 'fixed-step')
    """
    if not isinstance(name, str) or name not in METHODS:
        raise SimulationOptionError(
            f"unknown method {name!r}; choose one of "
            + ", ".join(f"{n!r} ({m.kind}, order {m.order})" for n, m in METHODS.items()) + "."
        )
    return METHODS[name]
