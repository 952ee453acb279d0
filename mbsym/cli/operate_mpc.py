"""``mbsym simulate --controller nmpc`` and ``--estimator``: the NMPC and the state estimators in the loop.

Contract (kept for acceptance checks)::

    mbsym simulate [DECK] --wind SPEC --controller nmpc|baseline [--preview S] [--estimator ekf|mhe]
                   [--deadline S] [--out F.csv] [--stats]

* ``--controller nmpc``: the turbine NMPC (:class:`mbsym.wind.mpc.TurbineNMPC`: real-time
  iterations, 0.1 s, 40 stages) on the prediction model chosen with the fidelity ladder (GenDOF +
  TwFADOF1 + the dynamic inflow + the actuators as rates; a floating deck adds the platform's surge
  and pitch and a cost on the platform's pitch rate, :meth:`~mbsym.wind.mpc.NMPCTuning.floating`),
  running against the full plant. The cost scales are carried to the deck's turbine in proportion
  to its rated speed, power and torque (:meth:`~mbsym.wind.mpc.NMPCTuning.for_turbine`). A deck whose
  plant is blade-element (full field, shear, blade or yaw DOFs) gets the controller ``mbsym
  export-discon`` compiles for it: prediction and estimation on the deck's rotor-effective model
  (:mod:`.controller_model`), the full-field tunings for a full field, always with an estimator.
* ``--preview S``: an ideal lidar: the NMPC knows the true hub wind for the next S seconds (held
  after that) and, without ``--estimator``, the plant's true state (ideal state feedback).
* ``--estimator ekf|mhe``: the state and rotor-effective wind estimated at 20 Hz from generator speed,
  tower-top acceleration, pitch and torque (on the prediction model with the first side-side tower
  mode added, :func:`mbsym.wind.mpc.estimation_model`; on a floating deck also the nacelle IMU's
  rotational acceleration and the platform's pitch and surge, with the waves' loads estimated); the NMPC
  uses the estimate (and the estimated wind when
  there is no preview). With ``--controller baseline`` the baseline keeps its own measurements and
  the estimates are only reported.
* ``--deadline S``: the NMPC's wall time per step (default its sample time, 0.1 s; ``inf``: none).
  A step computed later applies the previous plan's next rates (zero rates when none is left); the
  misses are counted (``--stats``: ``controller_deadline_s``, ``controller_deadline_misses``) and a
  one-line warning at the end says how many.
* ``--controller nmpc`` with neither ``--preview`` nor ``--estimator`` uses the EKF (a turbine
  has no lidar by default). A deck with an InflowWind single-point lidar (``SensorType = 1``) gives
  the NMPC without ``--preview`` the lidar's preview (:mod:`mbsym.wind.mpc.lidar_preview`), as the
  exported library (``mbsym export-discon``) does in OpenFAST.
* With an estimator the CSV adds ``<channel>_est`` (same units) for the channels of
  :data:`mbsym.wind.mpc.simulation.ESTIMATED_CHANNELS` (``Wind1VelX``, ``RtVAvgxh``,
  ``RotSpeed``, ``GenSpeed``, ``TTDspFA``, ...). ``--stats`` adds ``controller_step_median_s``,
  ``controller_step_max_s`` (NMPC steps after the first, which converges from a cold start and is
  ``controller_first_step_s``), ``controller_failures`` and, with an estimator,
  ``estimator_step_median_s``, ``estimator_step_max_s``.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass

__all__ = ["add_arguments", "MpcOptions", "check_options", "ESTIMATOR_CHOICES"]

ESTIMATOR_CHOICES = ("ekf", "mhe")
#: The estimator ``--controller nmpc`` uses without --preview or --estimator.
DEFAULT_ESTIMATOR = "ekf"


def add_arguments(p: argparse.ArgumentParser) -> None:
    """``--preview`` and ``--estimator``."""
    p.add_argument("--preview", type=float, metavar="S",
                   help="NMPC: ideal wind preview (a perfect lidar) of S seconds; without --estimator also the "
                        "plant's true state")
    p.add_argument("--deadline", type=float, metavar="S",
                   help="NMPC: wall time allowed per step in seconds (default: its sample time, 0.1 s; inf: none); a "
                        "later step applies the previous plan's next rates, misses are counted (--stats "
                        "controller_deadline_misses) and reported at the end")
    p.add_argument("--estimator", choices=ESTIMATOR_CHOICES,
                   help="estimate the state and rotor-effective wind at 20 Hz from generator speed, tower-top "
                        "acceleration, pitch and torque (the CSV adds <channel>_est); default for --controller "
                        "nmpc without --preview: ekf")


@dataclass(frozen=True)
class MpcOptions:
    """What the flags ask for (checked before any model is built)."""

    controller: str
    preview: float | None
    estimator: str | None
    deadline: float | None = None

    @property
    def active(self) -> bool:
        """Whether the run needs the Python loop (NMPC or an estimator)."""
        return self.controller == "nmpc" or self.estimator is not None

    def loop(self, deck, model, wind, lidar=None, say=None):
        """The :class:`~mbsym.wind.mpc.loop.TurbineLoop` of these options for ``model`` (``lidar``: the deck's
        lidar measurement, :meth:`OperatingDeck.lidar_measurement`, previewing for the NMPC; ``say``: told one
        line when the controller's model is not the plant).

        A blade-element plant gets the controller of ``mbsym export-discon`` for the same deck: the NMPC and
        the estimator predict with the deck's rotor-effective model (:func:`.controller_model.controller_model`),
        with the full-field tunings when the deck's wind is a full field."""
        from ..wind.control.baseline import BaselineController
        from ..wind.mpc.estimator import TurbineEstimator, estimation_model
        from ..wind.mpc.lidar_preview import PreviewSettings
        from ..wind.mpc.loop import TurbineLoop
        from ..wind.mpc.nmpc import TurbineNMPC
        from ..wind.mpc.prediction import PredictionModel
        from ..wind.mpc.setpoints import SetPoints
        from .controller_model import (
            blade_element_plant,
            controller_model,
            estimator_tuning,
            flexible_nacelle,
            nmpc_tuning,
        )

        blade = model.aero == "blade"
        own = controller_model(deck, say=say) if blade else model
        field = blade and blade_element_plant(deck)
        prediction = PredictionModel(own)
        estimator = nmpc = baseline = None
        settings = deck.baseline_settings()
        if self.estimator is not None:
            observed = estimation_model(own)
            start = _start_speed(model, wind)
            est_tuning = estimator_tuning(observed, field=field, flexible=flexible_nacelle(model.dofs))
            estimator = TurbineEstimator(observed, self.estimator, tuning=est_tuning,
                                         x0=_initial_estimate(own, observed, lambda t: start, settings))
        if self.controller == "nmpc":
            previewing = lidar is not None and self.preview is None and estimator is not None
            tuning = nmpc_tuning(prediction, field=field, preview=self.preview, lidar=previewing)
            setpoints = SetPoints.from_settings(settings, own.rotor)
            nmpc = TurbineNMPC(prediction, setpoints, tuning=tuning.for_turbine(setpoints), deadline=self.deadline)
        else:
            baseline = BaselineController(settings)
        lidar = lidar if nmpc is not None and self.preview is None and estimator is not None else None
        restart = None if estimator is None else (lambda w: _initial_estimate(own, observed, lambda t: w, settings))
        return TurbineLoop(model, deck.controller_dt, nmpc=nmpc, baseline=baseline, estimator=estimator,
                           preview=self.preview, wind=wind, lidar=lidar, restart=restart,
                           lidar_preview=None if lidar is None else PreviewSettings.for_lidar(deck.inflow.lidar))


def _start_speed(model, wind) -> float:
    """The plant's hub-height wind [m/s] at t = 0 (a speed, uniform-wind inputs, or the full field the model
    carries, at the hub)."""
    import numpy as np

    from ..wind.operation.simulation import wind_at_start

    start = wind_at_start(model, wind)
    if not isinstance(start, dict):
        return float(np.asarray(start, dtype=float).reshape(-1)[0])
    if "Wind1VelX" in start:
        return float(start["Wind1VelX"])
    field = model.wind.field
    return float(field.velocity(0.0, np.array([[0.0, 0.0, float(field.reference_height)]]))[0, 0])


def _initial_estimate(model, prediction, wind, settings=None):
    """The estimator's prior: the plant's steady guess at the first wind sample (the run starts there)."""
    import numpy as np

    from ..wind.mpc.estimator import steady_estimate

    if prediction.plant is not model:
        raise TypeError("the estimator's prediction model must be built on the plant (estimation_model(plant)).")
    return steady_estimate(prediction, float(np.asarray(wind(0.0), dtype=float).reshape(-1)[0]), settings=settings)


def check_options(args: argparse.Namespace, controller: str) -> MpcOptions:
    """The NMPC/estimator options of ``args`` for the chosen controller.

    Raises
    ------
    SimulationOptionError
        ``--preview`` without ``--controller nmpc`` or not a finite number >= 0; ``--estimator`` with
        a controller other than nmpc or baseline; ``--accuracy`` or ``--method`` with the NMPC or an
        estimator (they run one RK4 step per controller sample).
    """
    from ..exceptions import SimulationOptionError

    preview, estimator = getattr(args, "preview", None), getattr(args, "estimator", None)
    deadline = getattr(args, "deadline", None)
    if deadline is not None:
        if controller != "nmpc":
            raise SimulationOptionError(f"--deadline is the NMPC's time per step; it needs --controller nmpc (the "
                                        f"controller is {controller}).")
        if not deadline >= 0:
            raise SimulationOptionError(f"--deadline {deadline:g}: give the wall time per step in seconds >= 0 "
                                        "(e.g. --deadline 0.1, or inf for none).")
    if preview is not None:
        if controller != "nmpc":
            raise SimulationOptionError(f"--preview is the NMPC's wind preview; it needs --controller nmpc (the "
                                        f"controller is {controller}).")
        if not (math.isfinite(preview) and preview >= 0):
            raise SimulationOptionError(f"--preview {preview:g}: the preview must be a finite number of seconds "
                                        ">= 0 (e.g. --preview 5).")
    if estimator is not None and controller not in ("nmpc", "baseline"):
        raise SimulationOptionError(f"--estimator runs beside --controller nmpc or baseline; the controller is "
                                    f"{controller}.")
    if controller == "nmpc" and preview is None and estimator is None:
        estimator = DEFAULT_ESTIMATOR
    options = MpcOptions(controller, preview, estimator, deadline)
    if options.active:
        given = [f for f, v in (("--accuracy", args.accuracy), ("--method", args.method)) if v is not None]
        if given:
            raise SimulationOptionError(f"{' and '.join(given)}: the NMPC and the estimators run one RK4 step per "
                                        "controller sample of the deck (0.01 s built in); leave these flags out.")
    return options
