"""Region-2/3 NMPC of a wind turbine on a :class:`~.prediction.PredictionModel` (``mbsym.control``).

The optimal control problem (:class:`mbsym.control.OCP`, sample ``dt``, ``N`` stages) on the
prediction model's control form (inputs: the pitch and torque *rates*; the wind a previewed
disturbance)::

    min Σₖ  w_ω (ω_gen − ω_ref,k)² + w_P (P − P_ref,k)² + w_v ẋ_tower² + w_M (M_base − M_ref,k)²
            + w_β̇ β̇² + w_Ṫ Ṫ² + w_β̈ ((β̇ₖ − β̇ₖ₋₁)/dt)²
                                              (stages 0..N-1; terminal: speed and tower velocity;
                                               β̇₋₁ the rate applied before; w_β̈ = 0 by default)
    s.t.  β in [β_min, β_max], T in [T_min, T_max]                  (the plant's actuator limits)
          β̇ in [β̇_min, β̇_max], |Ṫ| ≤ Ṫ_max                          (the plant's actuator rates)

with the generator speed ``GenSpeed`` [rpm], electrical power ``GenPwr`` [kW], tower-top fore-aft
velocity ``QD_TFA1`` [m/s] and tower-base fore-aft moment ``TwrBsMyt`` [kN m], the prediction
model's own OpenFAST channels, and the limits of the plant (``OperatingTurbine.bounds()``).
The speed and tower-load references are the steady reference operation at each stage's wind
(:func:`~.setpoints.reference_table`): region 2 the best tip-speed ratio at fine pitch, region 3
the rated speed; ``M_ref`` is the steady tower-base moment, so that term penalizes the
*fluctuation* of the tower load, not its mean. The power reference is the **rated power at every
wind**: above rated it holds the power there; below rated the term is a convex reward for power
(its gradient always asks for more), which keeps the pitch at fine pitch in region 2 — tracking the
steady power of each stage's wind instead made the NMPC pitch in lulls to slow the rotor down and
lost 8 % of the energy at 8 m/s (measured, benchmarks/README.md).
With an *estimated* wind (no preview) the steady operation of that wind is tracked instead
(:meth:`NMPCTuning.estimated_wind`): the reward made the loop of estimator and NMPC run away.

Weights are given as the inverse square of an acceptable deviation (:class:`NMPCTuning`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, Mapping

import numpy as np

from ...exceptions import ControlDefinitionError
from .setpoints import ReferenceTable, SetPoints, reference_table

__all__ = ["NMPCTuning", "TurbineNMPC", "TRACKED"]

#: Channels the NMPC tracks (the reference table's names) and the cost scale of each in NMPCTuning.
TRACKED = {"GenSpeed": "speed_scale", "GenPwr": "power_scale", "BldPitch1": "pitch_scale", "y:GenTq": "torque_scale",
           "QD_TFA1": "tower_velocity_scale", "QD_P": "platform_pitch_rate_scale",
           "TwrBsMyt": "tower_moment_scale", "TTDspFA": "tower_deflection_scale", "BlPitchRate": "pitch_rate_scale",
           "GenTqRate": "torque_rate_scale"}


@dataclass(frozen=True)
class NMPCTuning:
    """Sample time, horizon and cost scales of :class:`TurbineNMPC`.

    Each ``*_scale`` is the deviation that costs as much as one unit (weight ``1/scale²``);
    ``math.inf`` removes the term. The defaults are for an ideally previewed wind;
    :meth:`estimated_wind` for a wind estimated by the EKF/MHE.

    Attributes
    ----------
    dt : float
        OCP sample time [s].
    horizon : int
        Stages N.
    speed_scale : float
        Generator speed [rpm].
    power_scale : float
        Electrical power [kW].
    pitch_scale : float
        Blade pitch about the steady reference of the stage's wind [deg] (default: no term).
    torque_scale : float
        Generator torque about the steady reference [kN m] (default: no term).
    power_reference : {"rated", "steady"}
        The power reference: the rated power at every wind (a reward for power below rated), or the
        steady reference power of the stage's wind.
    tower_velocity_scale : float
        Tower-top fore-aft velocity [m/s].
    tower_moment_scale : float
        Tower-base fore-aft moment about its steady value [kN m].
    tower_deflection_scale : float
        Tower-top fore-aft displacement ``TTDspFA`` about its steady value at the stage's wind [m] (default: no
        term). Unlike the moment, which carries the thrust's changes at once, the deflection is the thrust seen
        through the tower's own dynamics: its 3P content (above the first tower mode) is small.
    platform_pitch_rate_scale : float
        A floating platform's pitch rate ``QD_P`` [rad/s] (no term on land).
    pitch_rate_scale : float
        Pitch rate [rad/s].
    torque_rate_scale : float
        Generator torque rate [N m/s].
    pitch_acceleration_scale : float
        Change of the pitch rate from one stage to the next, per sample time [rad/s²] (default: no
        term). The rates are held over each sample, so without it a noisy estimate makes the applied
        rate jump from sample to sample: broadband pitch activity up to the sample rate's Nyquist
        frequency, which moves no load. The first stage's change is from the rate applied before.
    terminal_factor : float
        Terminal weights of speed and tower velocity, in stage weights.
    peak_shaving : bool
        The steady reference operation keeps the pitch at or above the controller's peak-shaving minimum
        (:meth:`SetPoints.min_pitch <mbsym.wind.mpc.setpoints.SetPoints.min_pitch>`; ROSCO's ``PS_Mode`` 1 and
        ``PS_BldPitchMin``), so near rated the NMPC tracks the lower power and thrust of that pitch. Default
        off: the steady operation at fine pitch.
    """

    dt: float = 0.1
    horizon: int = 40
    speed_scale: float = 20.0
    power_scale: float = 400.0
    tower_velocity_scale: float = 0.05
    tower_moment_scale: float = math.inf
    tower_deflection_scale: float = math.inf
    platform_pitch_rate_scale: float = math.inf
    pitch_scale: float = math.inf
    torque_scale: float = math.inf
    power_reference: str = "rated"
    pitch_rate_scale: float = math.radians(2.5)
    torque_rate_scale: float = 3000.0
    terminal_factor: float = 5.0
    pitch_acceleration_scale: float = math.inf
    peak_shaving: bool = False

    def __post_init__(self) -> None:
        if self.power_reference not in ("rated", "steady"):
            raise ControlDefinitionError(f"NMPCTuning.power_reference must be 'rated' or 'steady'; got "
                                         f"{self.power_reference!r}.")
        if not isinstance(self.peak_shaving, (bool, np.bool_)):
            raise ControlDefinitionError(f"NMPCTuning.peak_shaving must be True or False; got {self.peak_shaving!r}.")
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("power_reference", "peak_shaving"):
                continue
            if f.name == "horizon":
                if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                    raise ControlDefinitionError(f"NMPCTuning.horizon must be an integer >= 1; got {v!r}.")
            elif isinstance(v, bool) or not isinstance(v, (int, float)) or not v > 0 or (math.isinf(v) and f.name in
                                                                                       ("dt", "terminal_factor")):
                raise ControlDefinitionError(f"NMPCTuning.{f.name} must be a positive number; got {v!r}.")

    def replace(self, **changes) -> "NMPCTuning":
        return replace(self, **changes)

    @classmethod
    def estimated_wind(cls, **changes) -> "NMPCTuning":
        """The default tuning for an *estimated* wind (no preview).

        A pitch-rate scale of 0.57 deg/s: a wind estimate held over the horizon carries its
        high-frequency content as if it lasted, and with the preview tuning the pitch moved about
        twice as fast as ROSCO's. The steady reference operation of the estimated wind is tracked
        (power, pitch within 2 deg, torque within 5 kN m) instead of the rated-power reward: with the
        reward, the NMPC swung the torque between 0 and 19 kN m in region 2, ran the rotor on the
        stall side (TSR 5), where the torque balance hardly tells the wind, and the estimate and the
        rotor speed ran away (8 m/s, measured, benchmarks/README.md). Both defaults put the pitch-rate
        RMS near ROSCO's at 14 m/s (tuned on Kaimal seed 1 with the EKF: ROSCO 1.67 deg/s; scales of 0.5
        and 0.6 deg/s gave 1.53 and 1.74 deg/s; the benchmark uses seeds 11-13).
        """
        return cls(**{"pitch_rate_scale": math.radians(0.57), "power_reference": "steady", "pitch_scale": 2.0,
                      "torque_scale": 5.0, **changes})

    def for_turbine(self, setpoints: SetPoints) -> "NMPCTuning":
        """These scales, given for the NREL 5 MW, carried to another turbine in proportion to its rated values.

        The speed scale goes with the rated generator speed, the power scale with the rated power, the
        torque and torque-rate scales with the rated torque; angles, the tower's and the platform's
        velocities and the horizon stay. The NREL 5 MW (1173.7 rpm, 5 MW, 43.09 kN m) gets the same
        tuning back. Without it a 15 MW direct-drive rotor (7.56 rpm) would have its speed scale of
        20 rpm at 265 % of rated, and its torque scale at 0.03 % of rated torque.
        """
        rpm = setpoints.rated_generator_speed * 30.0 / math.pi
        k_speed, k_power = rpm / _NREL5MW_RPM, setpoints.rated_power / _NREL5MW_POWER
        k_torque = setpoints.rated_torque / _NREL5MW_TORQUE
        if max(abs(k - 1.0) for k in (k_speed, k_power, k_torque)) < 1e-3:      # the NREL 5 MW: unchanged
            return self
        return replace(self, speed_scale=self.speed_scale * k_speed, power_scale=self.power_scale * k_power,
                       torque_scale=self.torque_scale * k_torque, torque_rate_scale=self.torque_rate_scale * k_torque)

    @classmethod
    def floating(cls, **changes) -> "NMPCTuning":
        """:meth:`estimated_wind` with a term on the platform's pitch rate (``QD_P``, scale 5e-4 rad/s) and a
        pitch-rate scale of 0.15 deg/s, for a prediction model that holds the platform
        (:data:`~.prediction.FLOATING_PREDICTION_DOFS`); give it to :meth:`for_turbine` as the others.

        Without the platform term the NMPC's 4 s horizon does not reach the platform's pitch period (28 s on
        the VolturnUS-S) and the speed loop pumps it. Tuned on the IEA 15 MW on VolturnUS-S at 13 m/s (Kaimal
        TI 10 % seed 1, JONSWAP Hs 4 m Tp 10 s, 100-300 s, against the baseline with ROSCO's floating
        feedback, benchmarks/floating_nmpc.py); ratios to the baseline of platform-pitch std, tower-base DEL,
        speed RMS error, pitch-rate RMS:

        ======================================  =====  =====  =====  =====
        pitch-rate scale, platform scale         ptfm   DEL    speed  rate
        ======================================  =====  =====  =====  =====
        0.57 deg/s, 3e-4 rad/s                   0.26   0.71   0.71   2.62
        0.30 deg/s, 3e-4 rad/s                   0.28   0.67   0.67   2.06
        0.20 deg/s, 3e-4 rad/s                   0.30   0.66   0.67   1.72
        0.15 deg/s, 3e-4 rad/s                   0.32   0.66   0.68   1.49
        0.20 deg/s, 5e-4 rad/s                   0.45   0.71   0.66   1.28
        **0.15 deg/s, 5e-4 rad/s**               0.48   0.72   0.68   1.05
        0.20 deg/s, 1e-3 rad/s                   0.76   0.88   0.61   0.87
        ======================================  =====  =====  =====  =====
        """
        return cls.estimated_wind(**{"platform_pitch_rate_scale": 5e-4, "pitch_rate_scale": math.radians(0.15),
                                     **changes})

    @classmethod
    def full_field(cls, **changes) -> "NMPCTuning":
        """:meth:`estimated_wind` for a turbine in a full-field wind, with its EKF tuned by
        :meth:`EstimatorTuning.full_field <mbsym.wind.mpc.EstimatorTuning.full_field>`.

        The speed is tracked twice as tightly (scale 10 rpm), the tower-top velocity a little less
        tightly (0.07 m/s) and the pitch rate a little more (0.45 deg/s). Tuned inside OpenFAST v5 on the
        NREL 5 MW with flexible blades and drivetrain in TurbSim fields, against the ROSCO 2.10.6
        library in the same set-up (benchmarks/nmpc_openfast.py, 60-660 s; ratios NMPC/ROSCO of
        tower fore-aft DEL, speed RMS error, pitch-rate RMS). At 14 m/s (the shared ``ff14_flex``):
        :meth:`estimated_wind` with the uniform-wind EKF 0.59, 0.80, 2.2; the smoother EKF alone
        0.64, 1.30, 1.22; speed at 10 rpm 0.60, 0.86, 1.33; tower velocity at 0.1 m/s 0.60, 0.80,
        0.93 (the tower's damping comes through the speed loop's thrust without the pitch chasing
        the tower's velocity sample by sample), but 1.41 in pitch rate at 18 m/s; pitch rate at
        0.45 deg/s: 0.60, 0.86, 0.78 at 14 m/s and 0.78, 0.92, 1.17 at 18 m/s (seed 3141). On two fields
        made afterwards (16 m/s seed 1618, 18 m/s seed 2718) the speed RMS error was 1.079x at 16 m/s;
        with the EKF's blade-passing states and faster wind walk (:meth:`EstimatorTuning.full_field
        <mbsym.wind.mpc.EstimatorTuning.full_field>`) the pitch had budget left, and the tower velocity's
        scale went to 0.07 m/s: 0.84, 0.94, 1.00 at 16 m/s and 0.83, 0.80, 1.14 at 18 m/s (0.05 m/s:
        tower DEL 0.82-0.83 but speed RMS error 1.03-1.07x at 16 m/s). The references hold the controller's
        peak-shaving minimum pitch (``peak_shaving``, since 2026-11-30): on a 13 m/s field (seed 1313) the
        blade-root DEL was 1.09x ROSCO's without it (target 1.05), 1.01x with it, tower DEL 0.50 -> 0.45x. The
        pitch rate at 0.43 deg/s (since 2026-11-30, was 0.45): on a 20 m/s field (seed 2020) the pitch-rate RMS was
        1.251x ROSCO's (target 1.25), 1.213x at 0.43 deg/s, at 16 m/s seed 1618 speed RMS error 0.939 -> 0.952x.
        """
        return cls.estimated_wind(**{"speed_scale": 10.0, "tower_velocity_scale": 0.07,
                                     "pitch_rate_scale": math.radians(0.43), "peak_shaving": True, **changes})

    @classmethod
    def full_field_lidar(cls, **changes) -> "NMPCTuning":
        """:meth:`full_field` for an NMPC whose stage winds come from a nacelle lidar
        (:mod:`~mbsym.wind.mpc.lidar_preview`): sample 0.05 s with 80 stages (the same 4 s), speed scale
        15 rpm, tower-top velocity 0.04 m/s, pitch rate 0.38 deg/s.

        The preview takes over part of the speed regulation, so the tower gets more of the pitch. Tuned
        inside OpenFAST v5 on the NREL 5 MW with flexible blades and drivetrain and a 5-beam lidar 60 m
        upstream, in two TurbSim fields not used for :meth:`full_field` (16 m/s seed 1618, 18 m/s seed 2718),
        against the ROSCO 2.10.6 library (benchmarks/nmpc_openfast.py, 60-660 s; ratios of tower fore-aft
        DEL, speed RMS error, pitch-rate RMS):

        ======================================================  ===================  ===================
        candidate                                               16 m/s               18 m/s
        ======================================================  ===================  ===================
        :meth:`full_field` (0.1 s, 40 stages)                   0.833, 0.730, 0.985  0.836, 0.582, 1.126
        0.05 s, 80 stages                                       0.826, 0.708, 0.992  0.829, 0.563, 1.135
        and tower 0.04 m/s, speed 15 rpm                        0.798, 0.929, 1.151  0.788, 0.729, 1.316
        and a pitch-acceleration scale of 8 deg/s²              0.808, 0.940, 1.084  0.798, 0.735, 1.236
        and instead a pitch-rate scale of 0.4 deg/s             0.795, 0.956, 1.045  0.784, 0.748, 1.191
        **and 0.38 deg/s** (1.27x pitch rate at 20 m/s before)  0.793, 0.969, 1.000  (20 m/s: 0.777, 0.681, 1.222)
        ======================================================  ===================  ===================

        Measured on all eight fields of benchmarks/README.md (12-20 m/s, with the peak shaving of :meth:`full_field`):
        tower DEL 0.39-0.79x, speed RMS error at most 0.96x, pitch-rate RMS 0.47-1.19x but 1.27x at 20 m/s.
        What the runs of :meth:`full_field` showed: at 0.40-0.50 Hz the tower-base moment was 1.3x ROSCO's, the
        pitch 2-3x and coherent with the tower's motion 35-39 deg ahead of its displacement (not with its
        velocity): the loop damps the tower but also stiffens it, its mode moving from 0.32 to about 0.40 Hz.
        The shorter sample, or the initial state predicted 0.1-0.2 s ahead, moves that phase by a few degrees
        (DEL -0.01); the larger tower weight, which the preview can afford, did the rest.
        """
        return cls.full_field(**{"dt": 0.05, "horizon": 80, "speed_scale": 15.0, "tower_velocity_scale": 0.04,
                                 "pitch_rate_scale": math.radians(0.38), **changes})


#: The NREL 5 MW's rated generator speed [rpm], electrical power [W] and generator torque [N m]
#: (Jonkman et al. 2009, NREL/TP-500-38060, Table 7-1), which the scales of NMPCTuning are given for.
_NREL5MW_RPM, _NREL5MW_POWER, _NREL5MW_TORQUE = 1173.7, 5.0e6, 43093.55


def _weight(scale: float) -> float:
    return 0.0 if math.isinf(scale) else 1.0 / scale ** 2


class TurbineNMPC:
    """NMPC of pitch and generator torque on a prediction model (see the module docstring).

    Parameters
    ----------
    prediction : PredictionModel
    setpoints : SetPoints
        Rated values and the region-2 optimum (:meth:`SetPoints.from_settings`).
    tuning : NMPCTuning, optional, keyword-only
    references : ReferenceTable, optional, keyword-only
        Default: :func:`~.setpoints.reference_table` of the prediction model, with ``tuning.peak_shaving`` (about 1 s).
    solver, qp_solver, compile, warmup_iterations : optional, keyword-only
        Of :class:`mbsym.control.NMPC` (default real-time iterations with hpipm, compiled).
    p : dict, optional, keyword-only
        Parameter values of the prediction model by name.
    deadline : float, optional, keyword-only
        Wall time allowed per step [s]; default the sample time (0.1 s); ``math.inf``: none. A step
        computed later applies the previous plan's next rates instead (zero rates, the demands held, when
        there is no plan); its late solution is the next step's warm start; misses are counted (:meth:`summary`,
        ``--stats`` ``controller_deadline_misses``) and :func:`~.simulation.simulate_with_loop` warns.
        The first step (the start-up, a converged SQP) is not held to it.

    Attributes
    ----------
    ocp : mbsym.control.OCP
    nmpc : mbsym.control.NMPC
    references : ReferenceTable
    residual_scales : tuple of (tuple of str, tuple of str)
        The :class:`NMPCTuning` field whose scale weights each least-squares residual row of the OCP: its stage rows
        (tracked terms, then the pitch-acceleration term) and its terminal rows (each also weighted by
        ``terminal_factor``). An exported NMPC's run-time cost scales act on these rows (:mod:`.runtime_settings`).
    """

    CONTROLS = ("BlPitchRate", "GenTqRate")

    def __init__(self, prediction, setpoints: SetPoints, *, tuning: NMPCTuning | None = None,
                 references: ReferenceTable | None = None, solver: str = "rti", qp_solver: str = "hpipm",
                 compile: bool = True, warmup_iterations: int = 200, p: Mapping[str, float] | None = None,
                 deadline: float | None = None) -> None:
        from ...control import NMPC
        from .prediction import PredictionModel

        if not isinstance(prediction, PredictionModel):
            raise TypeError(f"prediction must be a PredictionModel; got {type(prediction).__name__}.")
        if not isinstance(setpoints, SetPoints):
            raise TypeError(f"setpoints must be a SetPoints; got {type(setpoints).__name__}.")
        tuning = NMPCTuning() if tuning is None else tuning
        if not isinstance(tuning, NMPCTuning):
            raise TypeError(f"tuning must be an NMPCTuning; got {type(tuning).__name__}.")
        if references is not None and not isinstance(references, ReferenceTable):
            raise TypeError(f"references must be a ReferenceTable; got {type(references).__name__}.")
        self.prediction, self.setpoints, self.tuning = prediction, setpoints, tuning
        self.references = reference_table(prediction, setpoints, p=p, peak_shaving=tuning.peak_shaving) \
            if references is None else references
        self.ocp = self._ocp()
        if deadline is None:
            deadline = tuning.dt
        if isinstance(deadline, bool) or not isinstance(deadline, (int, float)) or not deadline >= 0:
            raise ControlDefinitionError(f"deadline must be a number of seconds >= 0 (math.inf: none); got "
                                         f"{deadline!r}.")
        self.nmpc = NMPC(self.ocp, solver=solver, qp_solver=qp_solver, compile=compile,
                         warmup_iterations=warmup_iterations, p=p, u_prev=np.zeros(2), hold=np.zeros(2),
                         deadline=None if math.isinf(deadline) else float(deadline))
        self._tracked = tuple(n for n in self.nmpc.transcription.references
                              if n.split(":")[-1] in self.references.channels)

    def _ocp(self):
        from ...control import OCP

        t, pr = self.tuning, self.prediction
        b = pr.plant.bounds()
        d = pr.control
        known = set(d.output_names) | set(d.inputs)          # a rigid tower has no QD_TFA1: no tower term
        terms = {k: _weight(getattr(t, scale)) for k, scale in TRACKED.items() if k.split(":")[-1] in known}
        terms = {k: v for k, v in terms.items() if v > 0}
        refs = {k: 0.0 for k in terms}
        ocp = OCP(pr.control, horizon=t.horizon, dt=t.dt, controls=self.CONTROLS)
        ocp.track(terms, reference=refs)
        final = {k: t.terminal_factor * terms[k] for k in ("GenSpeed", "QD_TFA1", "QD_P") if k in terms}
        if final:
            ocp.track(final, terminal=True)
        ocp.bound("BlPitchRate", *b["BlPitch_d"]).bound("GenTqRate", *b["GenTq_d"])
        ocp.bound("x:BlPitch", *b["BlPitch"]).bound("x:GenTq", *b["GenTq"])
        stage_rows = [TRACKED[k] for k in terms]
        if not math.isinf(t.pitch_acceleration_scale):
            ocp.penalize_rates({"BlPitchRate": _weight(t.pitch_acceleration_scale)})
            stage_rows.append("pitch_acceleration_scale")
        self.residual_scales = (tuple(stage_rows), tuple(TRACKED[k] for k in final))
        return ocp

    @property
    def dt(self) -> float:
        return self.tuning.dt

    @property
    def horizon(self) -> int:
        return self.tuning.horizon

    def step(self, state, wind) -> np.ndarray:
        """Pitch and torque rates ``[rad/s, N m/s]`` for the state (prediction-model order) and stage winds.

        Parameters
        ----------
        state : array
            State of :attr:`PredictionModel.control`.
        wind : float or array (N+1)
            Hub-height wind [m/s] at stages 0..N (one value: constant over the horizon).
        """
        w = np.asarray(wind, dtype=float).reshape(-1)
        if w.size not in (1, self.horizon + 1) or not np.all(np.isfinite(w)):
            raise ControlDefinitionError(f"wind must be one finite value or {self.horizon + 1} (stages 0..N) [m/s]; "
                                         f"got {w.size} values{'' if np.all(np.isfinite(w)) else ' with NaN/inf'}.")
        w = np.broadcast_to(w, (self.horizon + 1,))
        refs = {k: self.references(k.split(":")[-1], w) for k in self._tracked}
        if "GenPwr" in refs and self.tuning.power_reference == "rated":      # see the module docstring
            refs["GenPwr"] = np.full(w.shape, self.setpoints.rated_power / 1e3)
        return self.nmpc.step(state, preview={"Wind1VelX": w}, reference=refs)

    def reset(self) -> None:
        """Forget the warm start and the statistics (the next step converges from a cold start)."""
        self.nmpc.reset(u_prev=np.zeros(2))

    def summary(self) -> dict[str, Any]:
        """Step times [s] after the first step (which converges from a cold start), the first step, failures."""
        walls = np.array([s.wall_s for s in self.nmpc.stats[1:]]) if len(self.nmpc.stats) > 1 else np.zeros(1)
        first = self.nmpc.stats[0].wall_s if self.nmpc.stats else float("nan")
        return {"steps": len(self.nmpc.stats), "failures": self.nmpc.failures, "step_median_s": float(np.median(walls)),
                "step_max_s": float(np.max(walls)), "first_step_s": float(first),
                "build_s": float(self.nmpc.build_time), "deadline_s": self.deadline,
                "deadline_misses": self.nmpc.deadline_misses}

    @property
    def deadline(self) -> float:
        """Wall time allowed per step [s] (``math.inf``: none)."""
        return math.inf if self.nmpc.deadline is None else self.nmpc.deadline
