"""State and rotor-effective wind estimation of an operating turbine (EKF or MHE from ``mbsym.control``).

The estimator runs on the prediction model's *estimation* form (:class:`~.prediction.PredictionModel`):
the structure and inflow states of the reduced turbine driven by the **measured** pitch and
generator torque, with the hub-height (rotor-effective) wind as a random-walk unknown input.
Measurements: the generator speed ``GenSpeed`` [rpm] and the tower-top fore-aft acceleration
``YawBrTAxp`` [m/s²] (outputs of the model), with the measured pitch ``BldPitch1`` and torque
``GenTq`` as its known inputs — what a turbine measures.

The estimate ``z`` holds the estimation states (tower, rotor speed, inflow), then ``Wind1VelX``.
With the measured pitch and torque, :meth:`TurbineEstimator.control_state` completes it to the
NMPC's state.

The estimator's model carries the **first side-side tower mode** even where the NMPC's does not
(:data:`ESTIMATOR_DOFS`, :func:`estimation_model`): the generator torque reacts on the tower
side-side, and the nacelle's roll enters the measured generator speed (relative to the nacelle).
An NMPC moving the torque on its own estimate excites that mode (0.31 Hz); without it in the
model, the estimator took the roll for wind, the estimate and the torque oscillated with a 3 s
period and, in one 8 m/s run, ran away (wind RMS error 0.82 m/s, correlation 0.88 over 600 s; with
the mode 0.14 m/s, 0.996; measured, docs/turbine_nmpc.md).

It carries the **drivetrain torsion** too where the plant has it (``DrTrDOF``): the measured
generator speed then rings in the drivetrain's torsional mode (2.2 Hz on the NREL 5 MW, ±30 rpm
after a start and ~1 rpm between 20 Hz samples in turbulence), which a rigid drivetrain can only
explain as wind. On OpenFAST's own ``ff14_flex`` record (660 s of full-field turbulence, flexible
blades and drivetrain, ROSCO) the EKF without it lost the wind within 0.2 s for good (estimate
below 0 m/s; an NMPC on it overspeeds the rotor); with it, RMS error 0.47 m/s against the
disk-averaged wind over 60-200 s (0.49 m/s on the rigid ``ff14_rigid`` record). For an NMPC whose
model has a rigid drivetrain, :meth:`TurbineEstimator.control_state` gives the drivetrain's rigid
speed, the inertia-weighted mean of the generator and rotor speeds, which the torsion leaves
unchanged (:func:`rigid_speed_weight`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, fields
from typing import Any, Mapping, Sequence

import numpy as np

from ...exceptions import ControlDefinitionError
from .harmonics import with_blade_passing

__all__ = ["TurbineEstimator", "EstimatorTuning", "ESTIMATORS", "ESTIMATOR_MEASUREMENTS", "ESTIMATOR_DOFS",
           "NACELLE_MODES", "FLOATING_MEASUREMENTS", "estimator_measurements",
           "estimation_model", "rigid_speed_weight", "control_values", "steady_estimate"]

#: Estimator kinds.
ESTIMATORS = ("ekf", "mhe")
#: Model outputs measured (OpenFAST units).
ESTIMATOR_MEASUREMENTS = ("GenSpeed", "YawBrTAxp")
#: Added for a model with the platform's pitch: the nacelle IMU's rotational acceleration [deg/s²] (the sensor
#: of ROSCO's floating feedback, ``Fl_Mode 2``), the platform's pitch [deg] and surge [m] (a motion reference
#: unit and GNSS; ServoDyn gives a DISCON library records 83, 1005 and 1001). See :func:`estimator_measurements`.
FLOATING_MEASUREMENTS = ("NcIMURAys", "PtfmPitch", "PtfmSurge")
#: Measurements whose blade-passing ripple is estimated (:attr:`EstimatorTuning.blade_passing`).
RIPPLE_CHANNELS = ("GenSpeed", "YawBrTAxp")
#: ElastoDyn DOFs of the default estimation model (those the plant has; see the module docstring).
ESTIMATOR_DOFS = ("GenDOF", "TwFADOF1", "TwSSDOF1", "DrTrDOF", "PtfmSgDOF", "PtfmPDOF")
#: ElastoDyn DOFs that move the nacelle at frequencies above the estimator's model (which holds the first
#: tower modes and rigid blades): a plant with any on gets :meth:`EstimatorTuning.flexible_floating` when floating.
NACELLE_MODES = ("TwFADOF2", "TwSSDOF2", "FlapDOF1", "FlapDOF2", "EdgeDOF")


def estimation_model(plant, dofs: Sequence[str] = ESTIMATOR_DOFS):
    """The :class:`~.prediction.PredictionModel` a :class:`TurbineEstimator` of ``plant`` should use.

    Parameters
    ----------
    plant : OperatingTurbine
        The turbine observed.
    dofs : sequence of str, optional
        ElastoDyn DOF flags wanted; those the plant does not have are left out (default
        :data:`ESTIMATOR_DOFS`).
    """
    from .prediction import PredictionModel

    on = plant.dofs
    return PredictionModel(plant, dofs=tuple(d for d in dofs if on.get(d, False)))


def estimator_measurements(prediction) -> tuple[str, ...]:
    """What an estimator on ``prediction`` measures: :data:`ESTIMATOR_MEASUREMENTS`, and
    :data:`FLOATING_MEASUREMENTS` when its model carries the platform's pitch.

    With one tower-top accelerometer the platform's surge, its pitch and the tower's bending are
    not told apart: on the floating IEA 15 MW in 4 m JONSWAP waves the EKF's surge velocity came out
    anti-correlated with the plant's (−0.35) and the waves' motion went into the wind estimate (RMS
    error 2.4 m/s, 91 % of it at 0.08–0.2 Hz). With the nacelle's rotational acceleration alone the
    estimate diverged; with the platform's pitch and surge too, and the waves' loads estimated
    (:attr:`~.prediction.PredictionModel.wave_inputs`), 0.81 m/s (still water: 0.56 m/s).
    """
    return ESTIMATOR_MEASUREMENTS + (FLOATING_MEASUREMENTS if "P" in prediction.estimation_states else ())


def steady_estimate(prediction, wind: float, *, settings=None) -> np.ndarray:
    """The estimate of steady operation at ``wind`` [m/s]: the estimation states, still water's zero wave
    loads (floating), then the wind.

    The plant's steady guess (:func:`mbsym.wind.operation.steady.steady_guess`: the controller's
    targets, the tower and drivetrain deflected by the steady loads, the inflow at equilibrium)
    picked by name: the estimator's prior where the operation is known to be near steady.

    Parameters
    ----------
    prediction : PredictionModel
        The estimator's model (its ``plant`` gives the steady operation).
    wind : float
        Hub-height wind [m/s].
    settings : BaselineSettings, optional, keyword-only
        The controller's targets (rated speed and power, optimal tip-speed ratio); default the
        built-in NREL 5 MW's.
    """
    from ..operation.steady import steady_guess

    plant = prediction.plant
    x = dict(zip(plant.dynamics().states, steady_guess(plant, float(wind), settings=settings).state))
    return np.array([x[s] for s in prediction.estimation_states] + [0.0] * len(prediction.wave_inputs) + [float(wind)])


def rigid_speed_weight(prediction) -> float:
    """``w`` of the drivetrain's rigid speed ``GeAz_d + w DrTr_d`` (0 without ``DrTr``).

    The rotor turns at ``GeAz_d + DrTr_d`` and the generator at ``GeAz_d`` (ElastoDyn's
    coordinates, rotor side); their angular momentum is ``(I_r + I_g) GeAz_d + I_r DrTr_d``, so the
    speed of the rigid drivetrain with the same momentum, which the torsion leaves unchanged, has
    ``w = I_r / (I_r + I_g)``: ``I_r`` the rotor's inertia about the shaft (ElastoDyn's rotor mass
    summary, hub included), ``I_g`` the generator's referred to the low-speed shaft (``GenIner N²``).

    Parameters
    ----------
    prediction : PredictionModel
        The estimator's model.
    """
    from ..structure.elastodyn_nodes import rotor_mass_properties

    if "DrTr" not in prediction.estimation_states:
        return 0.0
    turbine = prediction.plant.turbine
    i_r = rotor_mass_properties(turbine).rotor_inertia
    i_g = turbine.generator_inertia * turbine.gearbox_ratio ** 2
    return float(i_r / (i_r + i_g))


def control_values(names: Sequence[str], z, pitch, torque, states: Sequence[str], weight: float) -> list:
    """The NMPC state ``states`` from an estimate ``z`` (named ``names``) and the measured pitch and torque.

    Works on numbers and on CasADi expressions alike. Where the estimate has the drivetrain twist
    and ``states`` do not, ``GeAz_d`` is the drivetrain's rigid speed ``GeAz_d + weight DrTr_d``
    (:func:`rigid_speed_weight`).
    """
    est = {name: z[i] for i, name in enumerate(names)}
    est.update(BlPitch=pitch, GenTq=torque)
    if "DrTr_d" in est and "DrTr_d" not in states and "GeAz_d" in est:
        est["GeAz_d"] = est["GeAz_d"] + weight * est["DrTr_d"]
    missing = [s for s in states if s not in est]
    if missing:
        raise ControlDefinitionError(f"the estimator does not estimate {missing}; give it a prediction model "
                                     f"with those states (estimated: {list(names)}).")
    return [est[s] for s in states]


@dataclass(frozen=True)
class EstimatorTuning:
    """Sample time, window and noise levels (standard deviations) of :class:`TurbineEstimator`.

    Attributes
    ----------
    dt : float
        Sample time [s] (20 Hz by default).
    window : int
        MHE window (intervals).
    wind_walk : float
        Random-walk step of the wind per sample [m/s] (0.25 m/s: about 1.1 m/s per √s at 20 Hz).
    speed_noise : float
        Process noise of the rotor speed per sample [rad/s].
    tower_noise : float
        Process noise of the tower-top fore-aft velocity per sample [m/s].
    inflow_noise : float
        Process noise of the dynamic-inflow states per sample [m/s].
    platform_translation_noise : float
        Process noise of a floating platform's surge, sway and heave velocities per sample [m/s]: the
        waves' force, which the estimator does not know.
    platform_rotation_noise : float
        Process noise of the platform's roll, pitch and yaw rates per sample [rad/s].
    gen_speed_sd : float
        Measurement noise of the generator speed [rpm].
    accel_sd : float
        Measurement noise of the tower-top acceleration [m/s²].
    rotational_accel_sd : float
        Measurement noise of the nacelle's rotational acceleration [deg/s²] (floating platforms).
    wave_force_walk, wave_moment_walk : float
        Random-walk steps per sample of the waves' force [N] and moment [N m] on the platform
        (floating platforms: :attr:`PredictionModel.wave_inputs`, estimated like the wind).
    blade_passing : bool
        Estimate the blade-passing ripple of the generator speed and tower-top acceleration as states
        (:mod:`.harmonics`), so that it stays out of the wind and tower estimates.
    harmonic_speed_walk, harmonic_accel_walk : float
        Random-walk steps per sample of the ripple's states: generator speed [rpm], tower-top
        acceleration [m/s²] (with ``blade_passing``).
    """

    dt: float = 0.05
    window: int = 20
    wind_walk: float = 0.25
    speed_noise: float = 2e-4
    tower_noise: float = 2e-3
    inflow_noise: float = 1e-3
    platform_translation_noise: float = 2e-2
    platform_rotation_noise: float = 5e-4
    gen_speed_sd: float = 0.5
    accel_sd: float = 0.02
    rotational_accel_sd: float = 0.02
    platform_pitch_sd: float = 0.02
    platform_surge_sd: float = 0.1
    wave_force_walk: float = 3e5
    wave_moment_walk: float = 3e7
    blade_passing: bool = False
    harmonic_speed_walk: float = 1.0
    harmonic_accel_walk: float = 0.01

    @classmethod
    def full_field(cls, **changes) -> "EstimatorTuning":
        """For a turbine in a full-field wind: the blade-passing ripple as states (:mod:`.harmonics`) and a
        wind random walk of 0.1 m/s per sample.

        The estimated wind is the rotor's effective wind, which a full field averages over the disk, and
        the rotor sweeping the sheared field ripples at 3P. Measured on OpenFAST's flexible NREL 5 MW
        (benchmarks/README.md, "The NMPC judged inside OpenFAST"): without the ripple's states the EKF
        read the 3P ripple of the generator speed and tower-top acceleration as wind and tower motion,
        and the NMPC pitched at 3P (0.43-0.45 deg/s RMS between 0.45 and 0.75 Hz against ROSCO's 0.15-0.19
        at 16 and 18 m/s); the wind walk had been lowered to 0.05 m/s to keep the ripple out of the
        estimate (0.25, the uniform-wind default, let 0.44 m/s of vibration and 3P in), which made the
        estimate lag: at 16 m/s (TurbSim seed 1618) the speed RMS error was 1.079x ROSCO's. With the
        ripple's states (walks 1 rpm and 0.01 m/s² per sample) and a 0.1 m/s walk, on the two fields
        that had missed a target (16 m/s seed 1618, 18 m/s seed 2718) and the NMPC of
        :meth:`NMPCTuning.full_field <mbsym.wind.mpc.NMPCTuning.full_field>`: speed RMS error 0.94 and
        0.80x ROSCO's, pitch-rate RMS 1.00 and 1.14x, tower fore-aft DEL 0.84 and 0.83x. Tried (with the
        NMPC's tower-velocity scale at 0.05 m/s): ripple walks 2 rpm and 0.005-0.02 m/s² (the narrower the acceleration's notch, the better the tower's
        estimate and DEL, and the more 3P in the pitch: 0.80 DEL at 1.40x pitch rate with 0.005 m/s²,
        0.84 at 0.97x with 0.02), wind walks 0.05-0.1 m/s (0.07: speed RMS error 1.14x at 16 m/s).
        """
        return cls(**{"wind_walk": 0.1, "blade_passing": True, **changes})

    @classmethod
    def flexible_floating(cls, **changes) -> "EstimatorTuning":
        """For a floating turbine whose nacelle moves in modes the estimator's model does not hold
        (:data:`NACELLE_MODES`: second tower modes, flexible blades): the tower-top and rotational
        accelerations trusted to 0.2 m/s² and 1 deg/s² instead of 0.02 and 0.02.

        Those modes are in the accelerations and not in the model. On the ROSCO wheel's IEA 15 MW
        semi-submersible (both tower modes, flexible blades), started from its deck's initial conditions at
        a steady 16 m/s, the nacelle's pitch acceleration rings at ±25 deg/s² for the first seconds (OpenFAST
        v5 and mbsym's plant alike; 0.05 deg/s² above 0.7 Hz once settled) and the default EKF, replayed on
        OpenFAST's run with ROSCO (tests/data/openfast_semi_start16), was 63 m/s off within 2 s
        (RMS error 5.2 m/s over 5-60 s; in mbsym's loop the NMPC overspeeded the rotor by 33 % with 11 failed
        QPs). Replayed on the same run: these noise levels 0.46 m/s RMS error, at most 6.5 m/s off during the
        start (in mbsym's loop no failed QP); on OpenFAST's 0.025 s samples 0.47 m/s, and 0.46-0.48 m/s with
        0.1-0.5 m/s² and 0.5-5 deg/s²; tighter accelerations (0.02-0.05 m/s² with 1 deg/s², 0.1 m/s² with
        2 deg/s², 0.2 m/s² with 0.3 deg/s²) lost the estimate for good (wind below zero or beyond 30 m/s,
        16-37 m/s RMS error).
        """
        return cls(**{"accel_sd": 0.2, "rotational_accel_sd": 1.0, **changes})

    def __post_init__(self) -> None:
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name == "blade_passing":
                if not isinstance(v, bool):
                    raise ControlDefinitionError(f"EstimatorTuning.blade_passing must be True or False; got {v!r}.")
                continue
            ok = (isinstance(v, (int, np.integer)) and not isinstance(v, bool) and v >= 1) if f.name == "window" \
                else (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) and v > 0)
            if not ok:
                raise ControlDefinitionError(f"EstimatorTuning.{f.name} must be a positive "
                                             f"{'integer' if f.name == 'window' else 'number'}; got {v!r}.")


class TurbineEstimator:
    """EKF or MHE of the reduced turbine's states and the rotor-effective wind (module docstring).

    Parameters
    ----------
    prediction : PredictionModel
    kind : {"ekf", "mhe"}
    tuning : EstimatorTuning, optional, keyword-only
    x0 : array, optional, keyword-only
        Initial estimate (estimation states then wind); default the model's initial state at 10 m/s.
    p : dict, optional, keyword-only
        Parameter values of the prediction model by name.
    compile : bool, optional, keyword-only
        Compile the model's step and linearization and, for the MHE, its solver (default True).

    Attributes
    ----------
    names : tuple of str
        Names of the estimate.
    walls : list of float
        Wall time of every step [s].
    """

    def __init__(self, prediction, kind: str = "ekf", *, tuning: EstimatorTuning | None = None, x0=None,
                 p: Mapping[str, float] | None = None, compile: bool = True) -> None:
        from ...control import EKF, MHE, EstimationModel
        from .prediction import PredictionModel

        if not isinstance(prediction, PredictionModel):
            raise TypeError(f"prediction must be a PredictionModel; got {type(prediction).__name__}.")
        if kind not in ESTIMATORS:
            raise ControlDefinitionError(f"estimator must be one of {list(ESTIMATORS)}; got {kind!r}.")
        tuning = EstimatorTuning() if tuning is None else tuning
        if not isinstance(tuning, EstimatorTuning):
            raise TypeError(f"tuning must be an EstimatorTuning; got {type(tuning).__name__}.")
        self.prediction, self.kind, self.tuning = prediction, kind, tuning
        dyn = prediction.estimation
        if tuning.blade_passing:
            dyn = with_blade_passing(dyn, RIPPLE_CHANNELS, prediction.plant.turbine.number_of_blades)
        #: The model the filter runs: the prediction model's estimation form (with the ripple's states).
        self.dynamics = dyn
        self.measurements = estimator_measurements(prediction)
        self.model = EstimationModel(dyn, dt=tuning.dt, measurements=self.measurements,
                                     unknown_inputs=[*prediction.wave_inputs, "Wind1VelX"], p=p, compile=compile)
        self.p_vector = dyn.parameter_vector(p)
        Q = self._process_noise(dyn.states)
        R = {"GenSpeed": tuning.gen_speed_sd, "YawBrTAxp": tuning.accel_sd,
             "NcIMURAys": tuning.rotational_accel_sd, "PtfmPitch": tuning.platform_pitch_sd,
             "PtfmSurge": tuning.platform_surge_sd}
        R = {k: R[k] for k in self.measurements}
        z0 = self.model.state_vector({"Wind1VelX": 10.0}) if x0 is None else self.model.state_vector(
            x0 if isinstance(x0, Mapping) else self.complete(x0))
        P0 = self._prior(dyn.states)
        common = dict(process_noise=Q, measurement_noise=R, x0=z0, P0=P0)
        if kind == "ekf":
            self.filter = EKF(self.model, dt=tuning.dt, measurements=self.measurements, **common)
        else:
            self.filter = MHE(self.model, window=tuning.window, compile=compile,
                              bounds={"Wind1VelX": (0.5, 60.0)}, **common)
        self._P0 = np.array(self.filter.P, dtype=float) if kind == "ekf" else None       # restart's covariance
        self.names = self.model.names
        self.rigid_speed_weight = rigid_speed_weight(prediction)
        self.x = np.asarray(z0, dtype=float).copy()
        self.walls: list[float] = []

    def _process_noise(self, states) -> dict[str, float]:
        t = self.tuning
        q = {"Wind1VelX": t.wind_walk}
        q.update({n: t.wave_force_walk if "F" in n else t.wave_moment_walk for n in self.prediction.wave_inputs})
        for s in states:
            if s in self._ripple:
                q[s] = t.harmonic_speed_walk if s.endswith("GenSpeed") else t.harmonic_accel_walk
            elif s == "GeAz_d":
                q[s] = t.speed_noise
            elif s in ("Sg_d", "Sw_d", "Hv_d"):
                q[s] = t.platform_translation_noise
            elif s in ("R_d", "P_d", "Y_d"):
                q[s] = t.platform_rotation_noise
            elif s.endswith("_d"):
                q[s] = t.tower_noise
            elif s.startswith("DBEMT"):
                q[s] = t.inflow_noise
        return q

    def _prior(self, states) -> dict[str, float]:
        sd = {"Wind1VelX": 2.0, "GeAz_d": 0.05}
        sd.update({n: 1e6 if "F" in n else 1e8 for n in self.prediction.wave_inputs})
        sd.update({s: 3.0 if s.endswith("GenSpeed") else 0.2 for s in self._ripple})
        for s in states:
            sd.setdefault(s, 0.3 if s.startswith("DBEMT") else 0.1)
        return sd

    @property
    def _ripple(self) -> tuple[str, ...]:
        return self.dynamics.states[len(self.prediction.estimation_states):]

    def complete(self, z) -> np.ndarray:
        """An estimate of the prediction model's estimation form (:func:`steady_estimate`) with the ripple's
        states (zero) inserted after its states when :attr:`EstimatorTuning.blade_passing` adds them."""
        z = np.asarray(z, dtype=float).reshape(-1)
        n, m = len(self.prediction.estimation_states), len(self._ripple)
        names = self.model.names
        if m == 0 or z.size == len(names):
            return z
        if z.size != len(names) - m:
            raise ControlDefinitionError(f"an estimate has {len(names) - m} values (estimation states, wave loads, "
                                         f"wind) or {len(names)} with the ripple's states; got {z.size}.")
        return np.concatenate([z[:n], np.zeros(m), z[n:]])

    @property
    def dt(self) -> float:
        return self.tuning.dt

    def step(self, gen_speed_rpm: float, accel: float, pitch: float, torque: float, *more: float) -> np.ndarray:
        """One sample: measurements ``GenSpeed`` [rpm], ``YawBrTAxp`` [m/s²] at this sample; ``pitch`` [rad]
        and ``torque`` [N m] measured over the interval that just ended (their mean); ``more``: the
        rest of :attr:`measurements` in order (``NcIMURAys`` [deg/s²] on a floating platform).
        Returns the estimate."""
        if len(more) != len(self.measurements) - 2:
            raise ControlDefinitionError(f"the estimator measures {list(self.measurements)}: give "
                                         f"{list(self.measurements[2:])} after pitch and torque; got {len(more)} "
                                         "more values.")
        t0 = time.perf_counter()
        y = np.array([gen_speed_rpm, accel, *more], dtype=float)
        u = np.array([pitch, torque], dtype=float)
        self.x = np.asarray(self.filter.step(y, u), dtype=float)
        self.walls.append(time.perf_counter() - t0)
        return self.x.copy()

    @property
    def wind(self) -> float:
        """Estimated hub-height wind [m/s]."""
        return float(self.x[-1])

    def restart(self, z) -> None:
        """Start the EKF again from the estimate ``z`` (as :func:`steady_estimate` gives it; the ripple's states
        are inserted, :meth:`complete`) with its prior covariance: what the exported library does with an
        implausible estimate (:mod:`.sample`).

        Raises
        ------
        ControlDefinitionError
            The estimator is an MHE (its wind is bounded instead) or ``z`` has the wrong size.
        """
        if self.kind != "ekf":
            raise ControlDefinitionError("restart is for the EKF; the MHE bounds its wind instead.")
        x = np.asarray(self.model.state_vector(self.complete(z)), dtype=float).reshape(-1)
        self.filter.x, self.filter.P = x.copy(), self._P0.copy()
        self.x = x.copy()

    def control_state(self, pitch: float, torque: float, states: Sequence[str] | None = None) -> np.ndarray:
        """The NMPC state from the estimate and the measured pitch [rad] and torque [N m].

        ``states``: the NMPC prediction model's state names (default: this estimator's prediction
        model's); each must be estimated here or be ``BlPitch``/``GenTq``. With the drivetrain
        estimated and not in ``states``, ``GeAz_d`` is its rigid speed (:func:`control_values`).
        """
        names = self.prediction.states if states is None else tuple(states)
        return np.array(control_values(self.names, self.x, pitch, torque, names, self.rigid_speed_weight),
                        dtype=float)

    def failures(self) -> int:
        return int(getattr(self.filter, "failures", 0))

    def summary(self) -> dict[str, Any]:
        """Step times [s] (MHE: solves after the first, which converges from the EKF's window), failures."""
        if self.kind == "mhe":
            s = self.filter.summary()
            return {"kind": self.kind, "steps": s["steps"], "failures": s["failures"],
                    "step_median_s": s["step_median_s"], "step_max_s": s["step_max_s"],
                    "first_solve_s": s["first_solve_s"]}
        w = np.array(self.walls[1:] if len(self.walls) > 1 else [0.0])
        return {"kind": self.kind, "steps": len(self.walls), "failures": 0, "step_median_s": float(np.median(w)),
                "step_max_s": float(np.max(w))}
