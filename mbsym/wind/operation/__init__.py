"""The operating turbine: structure, rotor aerodynamics, actuators and controllers in one model.

- :mod:`.actuators`: pitch (second order) and generator-torque (first order) actuators with
  smooth saturation, generator efficiency; :class:`ActuatorSettings` with the source of every number;
- :mod:`.model`: :class:`OperatingTurbine` (its :meth:`~OperatingTurbine.dynamics` is an
  :class:`mbsym.Dynamics`); :mod:`.compose` builds the graph, :mod:`.channels` the OpenFAST channels.

See docs/operation.md.
"""

from .actuators import ACTUATOR_PARAMETERS, ActuatorSettings, smooth_clip
from .channels import OPERATION_CHANNELS
from .model import AERO_PARAMETERS, COMMANDS, OPERATING_DOFS, OperatingTurbine

__all__ = ["OperatingTurbine", "OPERATING_DOFS", "COMMANDS", "AERO_PARAMETERS", "ActuatorSettings",
           "ACTUATOR_PARAMETERS", "smooth_clip", "OPERATION_CHANNELS"]

# --- trim and operating points (branch trim; kept as a separate block for easy merges) ---
from .steady_control import Regime, SteadyControl  # noqa: E402
from .trim import TrimPoint, Trimmer, trim  # noqa: E402

__all__ += ["SteadyControl", "Regime", "TrimPoint", "Trimmer", "trim"]
