"""The operating turbine: structure, rotor aerodynamics, actuators and controllers in one model.

- :mod:`.actuators`: pitch (second order) and generator-torque (first order) actuators with
  smooth saturation, generator efficiency; :class:`ActuatorSettings` with the source of every number;
- :mod:`.model`: :class:`OperatingTurbine` (its :meth:`~OperatingTurbine.dynamics` is an
  :class:`mbsym.Dynamics`); :mod:`.compose` builds the graph, :mod:`.channels` the OpenFAST channels;
- :mod:`.dynamic_inflow`: rotor-averaged DBEMT on the performance surfaces;
- :mod:`.controllers`: controllers in the loop (:func:`baseline_in_loop`, :func:`discon_in_loop`);
- :mod:`.measured`: :class:`MeasuredInputTurbine` (measured pitch and torque as inputs: identification);
- :mod:`.measured_loads`: :class:`MeasuredLoadTurbine` (the structure driven by recorded rotor loads: identification);
- :mod:`.simulation`: :func:`simulate_turbine`; :mod:`.steady`: :func:`steady_guess` (initial states);
- :mod:`.deck`: :func:`operating_deck` (an OpenFAST deck), :func:`builtin_deck` (the NREL 5 MW);
  :mod:`.nrel5mw`: ROSCO's NREL 5 MW controller settings as package data.

See docs/operation.md.
"""

from .actuators import ACTUATOR_PARAMETERS, ActuatorSettings, smooth_clip
from .channels import OPERATION_CHANNELS
from .controllers import MEASUREMENTS, baseline_in_loop, discon_in_loop, held_commands
from .deck import OperatingDeck, builtin_deck, operating_deck
from .dynamic_inflow import DynamicInflow
from .measured import MeasuredInputTurbine
from .measured_loads import MeasuredLoadTurbine
from .model import AERO_PARAMETERS, COMMANDS, OPERATING_DOFS, OperatingTurbine
from .nrel5mw import nrel5mw_baseline_settings
from .simulation import simulate_turbine
from .steady import SteadyGuess, steady_guess

__all__ = ["OperatingTurbine", "OPERATING_DOFS", "COMMANDS", "AERO_PARAMETERS", "ActuatorSettings",
           "ACTUATOR_PARAMETERS", "smooth_clip", "OPERATION_CHANNELS", "DynamicInflow", "MEASUREMENTS",
           "baseline_in_loop", "discon_in_loop", "held_commands", "OperatingDeck", "operating_deck", "builtin_deck",
           "nrel5mw_baseline_settings", "simulate_turbine", "SteadyGuess", "steady_guess", "MeasuredInputTurbine",
           "MeasuredLoadTurbine"]

# --- trim and operating points (branch trim; kept as a separate block for easy merges) ---
from .steady_control import Regime, SteadyControl  # noqa: E402
from .trim import TrimPoint, Trimmer, trim  # noqa: E402

__all__ += ["SteadyControl", "Regime", "TrimPoint", "Trimmer", "trim"]
