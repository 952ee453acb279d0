"""Exception classes of mbsym.

Every error raised for bad user input derives from :class:`MbsymError` *and* from
the matching builtin (``ValueError``, ``TypeError`` or ``RuntimeError``), so that
callers may catch either.
"""

from __future__ import annotations

__all__ = [
    "MbsymError",
    "ModelDefinitionError",
    "DimensionError",
    "ParameterError",
    "SingularMassMatrixError",
    "BeamDataError",
    "OpenFASTFormatError",
    "IntegrationError",
    "SolverError",
    "SimulationOptionError",
    "ControlDefinitionError",
]


class MbsymError(Exception):
    """Base class of every error raised by mbsym."""


class ModelDefinitionError(MbsymError, ValueError):
    """The description of a system is inconsistent (names, tree, loads)."""


class DimensionError(MbsymError, ValueError):
    """An array has the wrong number of entries or the wrong shape."""


class ParameterError(MbsymError, ValueError):
    """A parameter value is missing, unknown, or not a finite number."""


class SingularMassMatrixError(ModelDefinitionError):
    """The mass matrix is singular: some coordinates move no mass."""


class BeamDataError(MbsymError, ValueError):
    """Distributed beam properties or shape functions are invalid."""


class OpenFASTFormatError(MbsymError, ValueError):
    """An OpenFAST input file is malformed (names the file, line and key)."""


class IntegrationError(MbsymError, RuntimeError):
    """A time integration diverged or produced non-finite values."""


class SolverError(MbsymError, RuntimeError):
    """A root finder or optimizer failed to converge."""


class SimulationOptionError(MbsymError, ValueError):
    """An option of :func:`mbsym.simulate` (time span, step, tolerances, output times) is invalid."""


class ControlDefinitionError(MbsymError, ValueError):
    """An optimal-control or estimation problem is ill-defined (unknown signal name, bad weight, horizon or bound)."""
