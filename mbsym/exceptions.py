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
    "DeckMemoryError",
    "IntegrationError",
    "UnphysicalRunError",
    "SolverError",
    "SimulationOptionError",
    "WindInputError",
    "WindFieldDomainError",
    "ControllerError",
    "MassPropertyError",
    "UnsupportedFeatureError",
    "ArgumentTypeError",
    "OptionError",
    "OutputFileError",
    "MbsymWarning",
    "ModelWarning",
    "ExportError",
    "SweepError",
    "DataError",
    "IdentificationOptionError",
    "IdentifiabilityWarning",
    "ConvergenceWarning",
    "ControlDefinitionError",
    "ConstraintError",
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


class DeckMemoryError(OpenFASTFormatError):
    """A deck implies more memory than the limit (names the file, line and key of the largest size).

    Attribute ``estimate``: the :class:`~mbsym.wind.deck.budget.MemoryEstimate` (items, total, limit).
    """

    def __init__(self, message: str, *, estimate=None) -> None:
        super().__init__(message)
        self.estimate = estimate


class IntegrationError(MbsymError, RuntimeError):
    """A time integration diverged or produced non-finite values."""


class UnphysicalRunError(IntegrationError):
    """A simulation left the physics its models hold for (names the time and the channel).

    Attributes ``time`` [s], ``channel``, ``value`` and ``result`` (the run up to the end, for
    inspection) are set when raised by :func:`mbsym.wind.operation.sanity.check_physical`.
    """


class SolverError(MbsymError, RuntimeError):
    """A root finder or optimizer failed to converge."""


class SimulationOptionError(MbsymError, ValueError):
    """An option of :func:`mbsym.simulate` (time span, step, tolerances, output times) is invalid."""


class WindInputError(MbsymError, ValueError):
    """A wind input (specification string, signal parameters, wind file content) is invalid."""


class WindFieldDomainError(WindInputError):
    """A wind field was asked for a point or time where OpenFAST's InflowWind stops with an error
    (outside a full-field grid without tower points, beyond a non-periodic field's time range, a
    power-law profile at or below the ground)."""


class ControllerError(MbsymError, RuntimeError):
    """A controller could not be loaded, configured or called (e.g. a DISCON library failed)."""
class MassPropertyError(ModelDefinitionError, ParameterError):
    """Mass properties are not physical: a negative mass, an inertia tensor that is not symmetric
    positive semi-definite or violates the triangle inequality, or a mass matrix that is not
    positive definite. Raised at construction (numeric values) and when parameter values are bound."""


class UnsupportedFeatureError(ModelDefinitionError):
    """The input asks for physics mbsym does not model (e.g. an OpenFAST module switched on)."""


class ArgumentTypeError(MbsymError, TypeError):
    """An argument has the wrong type (e.g. a string where a list of names is expected)."""


class OptionError(MbsymError, ValueError):
    """An option (keyword argument or command-line flag) has an invalid value."""


class OutputFileError(MbsymError, OSError):
    """An output file cannot be written where asked, or would overwrite an input."""


class MbsymWarning(UserWarning):
    """Base class of the warnings issued by mbsym."""


class ModelWarning(MbsymWarning):
    """The model will not behave as its input seems to ask (a feature ignored, a DOF unrestrained)."""
class ExportError(MbsymError, ValueError):
    """A model cannot be exported as asked (an operation with no C/Python/LaTeX form, a model too large for LaTeX)."""


class SweepError(MbsymError, ValueError):
    """A sweep is ill-defined: unknown case keys, bad options, an executor that cannot be used."""
class DataError(MbsymError, ValueError):
    """Measured or reference data are unusable: a channel is missing, values are not finite, times do not increase."""


class IdentificationOptionError(MbsymError, ValueError):
    """An option of :func:`mbsym.identify` (method, tolerances, weights, bounds, initial values) is invalid."""


class IdentifiabilityWarning(UserWarning):
    """Identified parameters are poorly determined by the data (nearly collinear: large correlation)."""


class DeadlineWarning(MbsymWarning):
    """A real-time controller missed its deadline at some steps (each applied its fallback; the count says how many)."""


class ConvergenceWarning(MbsymWarning):
    """An iterative fit stopped before converging (iteration or time limit, failed line search); the
    result is returned with ``success = False`` and the message says what to try."""
class ControlDefinitionError(MbsymError, ValueError):
    """An optimal-control or estimation problem is ill-defined (unknown signal name, bad weight, horizon or bound)."""
class ConstraintError(ModelDefinitionError):
    """Loop-closure constraints cannot define the motion as asked: redundant or inconsistent at the
    assembled configuration (names the offending constraint), or a bad choice of independent
    coordinates or guess."""
