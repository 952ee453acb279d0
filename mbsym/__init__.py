"""mbsym: multibody systems to CasADi equations of motion (Kane's method).

Describe a system (:class:`System`, bodies, joints, loads), derive its
:class:`EquationsOfMotion`, then simulate, linearize or optimize with the same
CasADi Functions.
"""

from importlib.metadata import PackageNotFoundError, version

from .bodies import FlexibleBody, Ground, RigidBody
from .equations import EomFunctions, EquationsOfMotion
from .exceptions import (
    BeamDataError,
    DimensionError,
    IntegrationError,
    MbsymError,
    ModelDefinitionError,
    OpenFASTFormatError,
    ParameterError,
    SimulationOptionError,
    SingularMassMatrixError,
    SolverError,
)
from .joints import Fixed, Free, Joint, Prismatic, Revolute
from .linear import LinearModel, linearize
from .kinematics import rotation, rotation_about, rotation_sequence, skew, small_rotation
from .system import System
from .simulate import SimulationResult, simulate

try:
    __version__ = version("mbsym")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

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
    "linearize",
    "simulate",
    "SimulationResult",
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
    "__version__",
]
