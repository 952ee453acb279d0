"""NMPC and state estimation of an operating turbine, on ``mbsym.control``.

- :mod:`.prediction`: :class:`PredictionModel`, the reduced operating turbine the controller and the
  estimator predict with (rate inputs with the plant's actuators exact; measured-actuator form);
- :mod:`.setpoints`: :class:`SetPoints` and the steady :func:`reference_table` the references follow;
- :mod:`.nmpc`: :class:`TurbineNMPC` and its :class:`NMPCTuning`;
- :mod:`.estimator`: :class:`TurbineEstimator` (EKF or MHE of the states and the rotor-effective wind) on
  :func:`estimation_model` (the NMPC's DOFs and the first side-side tower mode);
- :mod:`.loop`: :class:`TurbineLoop`, the NMPC (or the baseline) and an estimator as one law per plant
  sample, with ideal preview or estimates, :class:`SensorNoise`;
- :mod:`.simulation`: :func:`simulate_with_loop` (every channel, and ``<channel>_est``);
- :mod:`.sample`: :func:`sample_functions`, the NMPC and its EKF as CasADi Functions of fixed work, and
  :class:`SampledLoop` running them on the loop's schedule;
- :mod:`.discon_nmpc`: :func:`export_nmpc_discon`, those Functions as C in a DISCON library.

The closed-loop fidelity ladder that chose the prediction model is
:func:`mbsym.wind.analysis.prediction_ladder.prediction_ladder`. See docs/turbine_nmpc.md.
"""

from .estimator import (ESTIMATOR_DOFS, ESTIMATOR_MEASUREMENTS, ESTIMATORS, FLOATING_MEASUREMENTS, EstimatorTuning,
                        TurbineEstimator, estimation_model, estimator_measurements)
from .loop import LOOP_CHANNELS, SensorNoise, TurbineLoop
from .nmpc import TRACKED, NMPCTuning, TurbineNMPC
from .prediction import CONTROL_INPUTS, ESTIMATION_INPUTS, FLOATING_PREDICTION_DOFS, PREDICTION_DOFS, PredictionModel
from .setpoints import REFERENCE_CHANNELS, ReferenceTable, SetPoints, reference_state, reference_table
from .discon_nmpc import export_nmpc_discon
from .sample import SampledLoop, SampleFunctions, sample_functions
from .simulation import ESTIMATED_CHANNELS, measurement_dynamics, simulate_with_loop

__all__ = ["PredictionModel", "PREDICTION_DOFS", "FLOATING_PREDICTION_DOFS", "CONTROL_INPUTS", "ESTIMATION_INPUTS", "SetPoints", "ReferenceTable",
           "reference_table", "reference_state", "REFERENCE_CHANNELS", "NMPCTuning", "TurbineNMPC", "TRACKED",
           "TurbineEstimator", "EstimatorTuning", "ESTIMATORS", "ESTIMATOR_MEASUREMENTS", "ESTIMATOR_DOFS",
           "FLOATING_MEASUREMENTS", "estimator_measurements", "estimation_model", "TurbineLoop",
           "SensorNoise", "LOOP_CHANNELS", "simulate_with_loop", "measurement_dynamics", "ESTIMATED_CHANNELS",
           "sample_functions", "SampleFunctions", "SampledLoop", "export_nmpc_discon"]
