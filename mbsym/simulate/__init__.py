"""Time simulation of :class:`~mbsym.equations.EquationsOfMotion`.

:func:`simulate` is the one call; :data:`METHODS` lists the integration
methods (each a :class:`Method` subclass declaring ``order`` and ``kind``);
:class:`SimulationResult` holds named time series and statistics. Modules:
``api`` (simulate), ``inputs`` (u(t)), ``model`` (the protocol for model
objects), ``checks`` (input checks, divergence), ``base`` (solver base class,
cache, compiled evaluation switch), ``fixed`` (fixed-step loop in CasADi; rk4),
``second_order`` (newmark, generalized-alpha), ``casadi_methods`` (adams,
cvodes, idas), ``scipy_methods`` (scipy-radau, scipy-bdf), ``result``.
``compile=True`` evaluates through :mod:`mbsym.codegen` (generated C, disk cache).
``auto`` is the accuracy-driven default (method, step and compilation from
``accuracy``), ``controller`` and ``closed_loop`` run discrete controllers in the loop
(:class:`DiscreteController`), ``monitor`` handles progress, Ctrl-C and resource limits.
"""

from .api import simulate
from .base import Method, clear_cache
from .checks import DIVERGENCE_LIMIT, SimulationOptionError, SimulationOptionWarning
from .controller import DiscreteController
from .methods import METHODS, get_method
from .model import SimulationModel
from .monitor import MEMORY_LIMIT_BYTES, ProgressPrinter, SimulationInterrupted
from .result import SimulationResult

__all__ = [
    "simulate",
    "SimulationResult",
    "METHODS",
    "Method",
    "get_method",
    "SimulationModel",
    "SimulationOptionError",
    "SimulationOptionWarning",
    "DIVERGENCE_LIMIT",
    "clear_cache",
    "DiscreteController",
    "SimulationInterrupted",
    "ProgressPrinter",
    "MEMORY_LIMIT_BYTES",
]
