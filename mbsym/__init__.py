"""mbsym: multibody systems to CasADi equations of motion (Kane's method).

Describe a system (:class:`System`, bodies, joints, loads), derive its
:class:`EquationsOfMotion`, then simulate, linearize or optimize with the same
CasADi Functions.
"""

from ._lazy import lazy_attributes
from .bodies import FlexibleBody, Ground, RigidBody
from .codegen import CompilationWarning, compile_function
from .dynamics import Dynamics, as_dynamics
from .equations import EomFunctions, EquationsOfMotion
from .exceptions import (
    BeamDataError,
    DimensionError,
    IntegrationError,
    MbsymError,
    ModelDefinitionError,
    OpenFASTFormatError,
    ParameterError,
    ExportError,
    SimulationOptionError,
    SingularMassMatrixError,
    SolverError,
    SweepError,
    ControlDefinitionError,
    ConstraintError,
    DataError,
    IdentificationOptionError,
    IdentifiabilityWarning,
)
from .joints import Fixed, Free, Joint, Prismatic, Revolute
from .kinematics import rotation, rotation_about, rotation_sequence, skew, small_rotation
from .system import System
from .loops import ClosedLoopEquations
from .simulate import SimulationResult, simulate
from .sweep import sweep
from .identify import IdentificationResult, identify

#: Public names imported on first use (they pull in scipy): name -> modules to look in, first match wins
#: (``linear`` first, so that the names keep resolving once operating/sensitivity move into mbsym/linear/).
_LAZY = {
    **{n: ("linear",) for n in ("LinearBatch", "LinearModel", "Sensitivity", "linearize", "linearize_batch",
                                "sensitivities")},
    **{n: ("linear", "modal") for n in ("Mode", "modal_analysis")},
    **{n: ("linear", "operating") for n in ("AzimuthSweep", "OperatingPoint", "linearize_azimuths",
                                            "static_equilibrium", "steady_rotation")},
    "__version__": ("__version__",),
}
__getattr__, __dir__ = lazy_attributes(__name__, _LAZY, globals())

__all__ = [
    "System",
    "RigidBody",
    "Ground",
    "Joint",
    "Fixed",
    "Revolute",
    "Prismatic",
    "Free",
    "EquationsOfMotion",
    "EomFunctions",
    "Dynamics",
    "as_dynamics",
    "linearize",
    "linearize_batch",
    "sensitivities",
    "LinearBatch",
    "Sensitivity",
    "Mode",
    "modal_analysis",
    "OperatingPoint",
    "AzimuthSweep",
    "static_equilibrium",
    "steady_rotation",
    "linearize_azimuths",
    "simulate",
    "SimulationResult",
    "identify",
    "IdentificationResult",
    "compile_function",
    "CompilationWarning",
    "LinearModel",
    "FlexibleBody",
    "rotation",
    "rotation_about",
    "rotation_sequence",
    "small_rotation",
    "skew",
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
    "ExportError",
    "SweepError",
    "ControlDefinitionError",
    "ConstraintError",
    "ClosedLoopEquations",
    "sweep",
    "DataError",
    "IdentificationOptionError",
    "IdentifiabilityWarning",
    "__version__",
]
