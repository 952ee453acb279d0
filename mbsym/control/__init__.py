"""Optimal control and estimation on any mbsym model: OCP transcription, NMPC, MHE, EKF/UKF.

General layer: works on anything :func:`mbsym.as_dynamics` accepts (never imports
:mod:`mbsym.wind`). See ``docs/control.md``.
"""

from .discretize import Discretization, discretize
from .estimation import EKF, UKF, EstimationModel
from .mhe import MHE
from .nlpsolvers import NLP_SOLVERS, NlpSolver
from .nmpc import NMPC, SOLVERS, StepStats
from .ocp import OCP, Transcription
from .qp import QP_SOLVERS
from .sqp import GaussNewtonSQP, SolveResult
from .stages import Layout, StageProblem

__all__ = [
    "OCP",
    "Transcription",
    "NMPC",
    "StepStats",
    "MHE",
    "EKF",
    "UKF",
    "EstimationModel",
    "SOLVERS",
    "QP_SOLVERS",
    "NLP_SOLVERS",
    "GaussNewtonSQP",
    "NlpSolver",
    "SolveResult",
    "StageProblem",
    "Layout",
    "Discretization",
    "discretize",
]
