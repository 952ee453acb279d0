"""Linearized equations of motion (paper Sect. 2.5): models, batches, sensitivities, operating points.

Modules depend downward only::

    _cache, model, point                      records and the per-model Function cache
    functions, target, fd                     residual Jacobians; model resolution; central differences
    outputs                                   output channels (Cy, Dy)
    linearize                                 linearize() → LinearModel
    batch, sensitivity, operating             linearize_batch, sensitivities, static_equilibrium, steady_rotation
    azimuth                                   linearize_azimuths → AzimuthSweep
    frequency                                 frequency_response → FrequencyResponse (Bode phase)

Every public name is re-exported here (``from mbsym.linear import linearize``).
"""

from .azimuth import AzimuthSweep, linearize_azimuths
from .batch import MAP_CHUNK, LinearBatch, compiled, linearize_batch
from .fd import elastodyn_steps
from .frequency import FrequencyResponse, anchored_phase_deg, frequency_response
from .functions import jacobian_function, linear_function
from .linearize import METHODS, linearize
from .model import LinearModel
from .operating import static_equilibrium, steady_rotation
from .point import OperatingPoint
from .sensitivity import Sensitivity, sensitivities

__all__ = ["LinearModel", "LinearBatch", "Sensitivity", "linearize", "linearize_batch", "sensitivities",
           "jacobian_function", "linear_function", "elastodyn_steps", "METHODS", "MAP_CHUNK", "compiled",
           "OperatingPoint", "static_equilibrium", "steady_rotation", "AzimuthSweep", "linearize_azimuths",
           "FrequencyResponse", "frequency_response", "anchored_phase_deg"]
