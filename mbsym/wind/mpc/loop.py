"""A turbine controller with an NMPC and/or a state estimator in the simulation loop.

:class:`TurbineLoop` is one Python law (:class:`mbsym.simulate.DiscreteController`) called at the
plant's controller sample time (the deck's, 0.01 s for the built-in NREL 5 MW). Inside it, at
their own rates:

* the **estimator** (:class:`~.estimator.TurbineEstimator`, every ``estimator.dt``) reads the
  generator speed and tower-top acceleration at the sample and the pitch and torque averaged
  over the interval that just ended;
* the **NMPC** (:class:`~.nmpc.TurbineNMPC`, every ``nmpc.dt``) gets the state — the plant's own
  state picked by name (*ideal* state feedback) or the estimate completed with the measured pitch
  and torque — and the wind over its horizon: an ideal **preview** of the true wind for
  ``preview`` seconds (a perfect lidar; held after that), the estimated wind with a real lidar's
  changes added (``lidar``, :mod:`.lidar_preview`), or the estimated wind held constant;
  its pitch and torque rates are applied until its next sample as **ramps** of the demands with
  the actuators' lead (:meth:`~.prediction.PredictionModel.commands`), so the plant's actuators
  move as the prediction model assumed;
* or the **baseline** controller (our ROSCO scheme) from its usual measurements, with an
  estimator running beside it for its estimates only.

The estimate is carried as the controller's state (named ``est.<name>``), so it appears in the
simulation result; :func:`~.simulation.simulate_with_loop` turns it into ``<channel>_est``
channels.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from ...exceptions import SimulationOptionError

__all__ = ["TurbineLoop", "SensorNoise", "LOOP_CHANNELS", "warn_failures"]

#: Plant channels the loop reads (OpenFAST units): the baseline controller's five, then torque and
#: tower-top acceleration for the estimator.
LOOP_CHANNELS = ("GenSpeed", "RotSpeed", "BldPitch1", "GenPwr", "Wind1VelX", "GenTq", "YawBrTAxp")
_DEG, _RPM = math.pi / 180.0, math.pi / 30.0


@dataclass(frozen=True)
class SensorNoise:
    """White Gaussian noise on the measurements the estimator (and the NMPC's measured pitch and torque) read.

    Attributes
    ----------
    gen_speed : float
        Generator speed [rpm].
    accel : float
        Tower-top fore-aft acceleration [m/s²].
    pitch : float
        Blade pitch [deg].
    torque : float
        Generator torque [N m].
    seed : int
        Seed of ``numpy.random.default_rng``.
    """

    gen_speed: float = 0.5
    accel: float = 0.02
    pitch: float = 0.05
    torque: float = 100.0
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("gen_speed", "accel", "pitch", "torque"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (math.isfinite(v) and v >= 0):
                raise SimulationOptionError(f"SensorNoise.{name} must be a standard deviation >= 0; got {v!r}.")


def _multiple(period: float, base: float, what: str) -> int:
    m = period / base
    if abs(m - round(m)) > 1e-9 * max(m, 1.0) or round(m) < 1:
        raise SimulationOptionError(f"the {what} sample time {period:g} s must be a whole multiple of the "
                                    f"controller sample time {base:g} s.")
    return int(round(m))


class TurbineLoop:
    """NMPC or baseline control with an optional estimator, as one law of the plant's samples.

    Parameters
    ----------
    plant : OperatingTurbine
        The simulated turbine (its state names give the ideal state feedback).
    sample_time : float
        Controller sample time of the loop [s] (the plant's RK4 step).
    nmpc : TurbineNMPC, optional, keyword-only
    baseline : BaselineController, optional, keyword-only
        Exactly one of ``nmpc`` and ``baseline``.
    estimator : TurbineEstimator, optional, keyword-only
    preview : float, optional, keyword-only
        Seconds of ideal wind preview for the NMPC (None: none).
    wind : callable, optional, keyword-only
        The true wind of time [m/s] (needed with ``preview``).
    noise : SensorNoise, optional, keyword-only
        Noise on the measurements of the estimator and the NMPC's measured pitch and torque
        (default none). The baseline controller reads the plant's channels as they are.
    lidar : callable, optional, keyword-only
        ``t -> (speeds, positions)``: a lidar's measurement (:func:`mbsym.wind.inflow.lidar_measurements`)
        for a realistic preview (:class:`~.lidar_preview.LidarPreview`, as the exported library runs
        it); needs ``lidar_preview`` and an estimator, excludes ``preview``.
    lidar_preview : PreviewSettings, optional, keyword-only
        How the lidar's measurements become the stage winds.
    restart : callable, optional, keyword-only
        ``hub wind [m/s] -> estimate`` (e.g. :func:`~.estimator.steady_estimate` with the turbine's settings):
        with an NMPC and an EKF, an estimate that is not finite or whose wind leaves 0.5 times the lowest to
        1.5 times the highest of the NMPC's reference winds restarts the EKF from ``restart`` of the measured
        hub wind (``Wind1VelX``, clipped to the reference winds) with its prior covariance, as the exported
        library does; the times are in :attr:`restarts` (``estimator_restarts`` in :meth:`statistics`).
        Default: no restart.

    Raises
    ------
    SimulationOptionError
        Sample times that are not multiples of ``sample_time``; an NMPC with neither preview nor
        estimator (it would have no wind); a negative preview; a preview without a wind.
    """

    def __init__(self, plant, sample_time: float, *, nmpc=None, baseline=None, estimator=None,
                 preview: float | None = None, wind: Callable | None = None,
                 noise: SensorNoise | None = None, lidar: Callable | None = None, lidar_preview=None,
                 restart: Callable[[float], Any] | None = None) -> None:
        if (nmpc is None) == (baseline is None):
            raise SimulationOptionError("give exactly one of nmpc= and baseline= to the loop.")
        if (lidar is None) != (lidar_preview is None):
            raise SimulationOptionError("a lidar preview needs both lidar= (the measurement) and lidar_preview= "
                                        "(PreviewSettings).")
        if lidar is not None and (nmpc is None or estimator is None or preview is not None):
            raise SimulationOptionError("a lidar preview is for an NMPC with an estimator (the preview adds the "
                                        "lidar's changes to the estimated wind), without an ideal preview.")
        if preview is not None:
            if not (isinstance(preview, (int, float)) and math.isfinite(preview) and preview >= 0):
                raise SimulationOptionError(f"preview must be a finite number of seconds >= 0; got {preview!r}.")
            if wind is None:
                raise SimulationOptionError("a wind preview needs the true wind (wind=...).")
            if nmpc is None:
                raise SimulationOptionError("a wind preview is for the NMPC; the baseline controller does not use it.")
        if nmpc is not None and preview is None and estimator is None:
            raise SimulationOptionError("the NMPC needs the wind: give a preview (ideal lidar) or an estimator.")
        if noise is not None and not isinstance(noise, SensorNoise):
            raise TypeError(f"noise must be a SensorNoise; got {type(noise).__name__}.")
        self.noise = noise
        self._rng = np.random.default_rng(noise.seed) if noise is not None else None
        self.plant, self.dt = plant, float(sample_time)
        self.nmpc, self.baseline, self.estimator = nmpc, baseline, estimator
        self.preview, self.wind = (None if preview is None else float(preview)), wind
        self.lidar = lidar
        self._lidar_preview = None
        if lidar is not None:
            from .lidar_preview import LidarPreview

            lo = 0.5 * float(nmpc.references.winds[0])
            hi = 1.5 * float(nmpc.references.winds[-1])
            self._lidar_preview = LidarPreview(lidar_preview, nmpc.dt, nmpc.horizon, (lo, hi))
        self._restart = restart if nmpc is not None and estimator is not None and estimator.kind == "ekf" else None
        #: Times [s] at which the EKF was restarted from an implausible estimate (``restart``).
        self.restarts: list[float] = []
        self._wind_range = (0.5 * float(nmpc.references.winds[0]), 1.5 * float(nmpc.references.winds[-1])) \
            if nmpc is not None else (0.0, math.inf)
        self._kn = _multiple(nmpc.dt, self.dt, "NMPC") if nmpc is not None else 0
        self._ke = _multiple(estimator.dt, self.dt, "estimator") if estimator is not None else 0
        self.prediction = nmpc.prediction if nmpc is not None else (estimator.prediction if estimator else None)
        dyn = plant.dynamics()
        # the NMPC reads the plant's own states only without an estimator (ideal state feedback): a plant with other
        # states (blade-element, per-node inflow) needs the estimator
        self._state_names = tuple(s for s in self.prediction.states if s != "GenTq") \
            if nmpc is not None and estimator is None else ()
        missing = [s for s in self._state_names if s not in dyn.states]
        if missing:
            raise SimulationOptionError(f"the plant has no states {missing} of the prediction model; without an "
                                        "estimator the NMPC reads the plant's state, so the prediction model's states "
                                        "must be a subset of the plant's (or give estimator=).")
        if nmpc is not None and estimator is not None:
            unseen = [s for s in nmpc.prediction.states if s not in estimator.names and s not in ("BlPitch", "GenTq")]
            if unseen:
                raise SimulationOptionError(f"the estimator does not estimate the NMPC's states {unseen}; give it a "
                                            "prediction model with the NMPC's DOFs (estimation_model(plant)).")
        self._law_time: list[float] = []
        self._base_fn = None
        self._xb0 = np.zeros(0)
        self._base_units: tuple[str, ...] = ()
        extra: tuple[str, ...] = ()
        if baseline is not None:
            from ..operation.controllers import baseline_in_loop

            dc = baseline_in_loop(baseline)
            self._base_fn, self._xb0 = dc.law, dc.x0
            self._base_names = dc.state_names
            self._base_units = dc.state_units
            extra = tuple(n for n in dc.measurements if n not in LOOP_CHANNELS)   # e.g. floating feedback's
        if estimator is not None:                             # e.g. a floating estimator's nacelle IMU
            extra += tuple(n for n in estimator.measurements[2:] if n not in LOOP_CHANNELS + extra)
        self.measurements = LOOP_CHANNELS + extra + self._state_names
        self._est_rows = [self.measurements.index(n) for n in estimator.measurements[2:]] if estimator else []
        if baseline is not None:
            self._base_rows = [self.measurements.index(n) for n in dc.measurements]
        self._n_b = self._xb0.size
        self._n_e = len(estimator.names) if estimator is not None else 0
        self.controller_times: list[float] = []
        self.estimates: list[tuple[float, np.ndarray]] = []
        self._reset()

    def _reset(self) -> None:
        self._anchor = None                      # (t, pitch, torque, rates)
        self._acc = np.zeros(2)                  # pitch, torque sums over the estimator interval
        self._n_acc = 0

    # ------------------------------------------------------------------ the law
    @property
    def state_names(self) -> tuple[str, ...]:
        names = tuple(self._base_names) if self.baseline is not None else ()
        if self.estimator is not None:
            names += tuple(f"est.{n}" for n in self.estimator.names)
        return names

    @property
    def state_units(self) -> tuple[str, ...]:
        """Units of :attr:`state_names` (SI: the baseline's states, the estimated states and wind)."""
        units = tuple(self._base_units) if self.baseline is not None else ()
        if self.estimator is not None:
            dyn = self.estimator.dynamics
            known = {**dict(zip(dyn.inputs, dyn.input_units)), **dict(zip(dyn.states, dyn.state_units))}
            units += tuple(known.get(n, "") for n in self.estimator.names)
        return units

    def controller(self):
        """The :class:`mbsym.simulate.DiscreteController` running this loop."""
        from ...simulate.controller import DiscreteController

        x0 = np.concatenate([self._xb0, self.estimator.x if self.estimator is not None else np.zeros(0)])
        law, actuates = self.law, ("BlPitchCom", "GenTqCom")
        plant = tuple(getattr(self.plant, "command_names", actuates))
        if "BlPitchCom" not in plant:                    # a plant pitched blade by blade: one collective command
            law, actuates = _collective(self.law, len(plant) - 1), plant
        return DiscreteController(law, self.dt, x0, measurements=self.measurements, actuates=actuates,
                                  state_names=self.state_names, state_units=self.state_units,
                                  name="nmpc" if self.nmpc is not None else "baseline")

    def law(self, t: float, xc: np.ndarray, y: np.ndarray):
        """``(xc_next, [BlPitchCom, GenTqCom])`` at time ``t`` [s] from the plant measurements ``y``."""
        k = int(round(t / self.dt))
        y_true = y
        if self._rng is not None:
            n = self.noise
            y = y.copy()
            y[[0, 2, 5, 6]] += self._rng.standard_normal(4) * (n.gen_speed, n.pitch, n.torque / 1e3, n.accel)
        pitch, torque = y[2] * _DEG, y[5] * 1e3
        xb = xc[: self._n_b]
        z = xc[self._n_b:]
        if self.estimator is not None:
            if k > 0:
                self._acc += (pitch, torque)
                self._n_acc += 1
            if k % self._ke == 0:
                mean = self._acc / self._n_acc if self._n_acc else np.array([pitch, torque])
                z = self.estimator.step(y[0], y[6], mean[0], mean[1], *y[self._est_rows])
                if self._restart is not None and not self._plausible(z):
                    winds = self.nmpc.references.winds                        # y[4]: the measured hub wind
                    self.estimator.restart(self._restart(min(max(float(y[4]), winds[0]), winds[-1])))
                    z = self.estimator.x.copy()
                    self.restarts.append(t)
                self.estimates.append((t, z.copy()))
                self._acc[:] = 0.0
                self._n_acc = 0
        if self.baseline is not None:
            c0 = time.perf_counter()
            xb_next, u = self._base_fn(xb, y_true[self._base_rows])
            xb, u = np.asarray(xb_next).ravel(), np.asarray(u).ravel()
            self._law_time.append(time.perf_counter() - c0)
        else:
            if k % self._kn == 0:
                c1 = time.perf_counter()
                state = self._nmpc_state(y, pitch, torque)
                rates = self.nmpc.step(state, self._horizon_wind(t))
                self._anchor = (t, *self._ramp_start(t, pitch, torque), rates)
                self.controller_times.append(time.perf_counter() - c1)
            t_a, p_a, q_a, r = self._anchor
            u = np.array(self.prediction.commands(p_a, q_a, r[0], r[1], t - t_a))
        return np.concatenate([xb, z]), u

    def _plausible(self, z: np.ndarray) -> bool:
        lo, hi = self._wind_range
        return bool(np.all(np.isfinite(z)) and lo <= z[-1] <= hi)

    def _ramp_start(self, t: float, pitch: float, torque: float) -> tuple[float, float]:
        """Where the new ramps start: the previous ramps' values now (continuous demands; the measured
        pitch and torque at the first step)."""
        if self._anchor is None:
            return pitch, torque
        t_a, p_a, q_a, r = self._anchor
        (b0, b1), (q0, q1) = self.prediction._demand_limits
        dt = t - t_a
        return min(max(p_a + r[0] * dt, b0), b1), min(max(q_a + r[1] * dt, q0), q1)

    def _nmpc_state(self, y, pitch: float, torque: float) -> np.ndarray:
        if self.estimator is not None:
            return self.estimator.control_state(pitch, torque, self.prediction.states)
        values = dict(zip(self._state_names, y[len(self.measurements) - len(self._state_names):]))
        values["GenTq"] = torque
        values["BlPitch"] = pitch
        return np.array([values[s] for s in self.prediction.states])

    def _horizon_wind(self, t: float) -> np.ndarray:
        n = self.nmpc.horizon
        if self._lidar_preview is not None:
            self._lidar_preview.push(t, self.lidar(t)[0])
            return self._lidar_preview.horizon(t, float(self.estimator.wind))
        if self.preview is None:
            return np.full(n + 1, self.estimator.wind)
        lead = np.minimum(np.arange(n + 1) * self.nmpc.dt, self.preview)
        return np.asarray(self.wind(t + lead), dtype=float).reshape(-1)

    # ------------------------------------------------------------------ statistics
    def statistics(self) -> dict[str, Any]:
        """Controller and estimator step times [s] and failures (``--stats`` keys)."""
        out: dict[str, Any] = {}
        if self.nmpc is not None:
            s = self.nmpc.summary()
            out.update(controller_step_median_s=s["step_median_s"], controller_step_max_s=s["step_max_s"],
                       controller_first_step_s=s["first_step_s"], controller_failures=s["failures"],
                       controller_steps=s["steps"], controller_build_s=s["build_s"],
                       controller_deadline_s=s["deadline_s"], controller_deadline_misses=s["deadline_misses"],
                       controller_dt=self.nmpc.dt, controller_horizon=self.nmpc.horizon)
        else:
            w = np.array(self._law_time[1:] or [0.0])
            out.update(controller_step_median_s=float(np.median(w)), controller_step_max_s=float(np.max(w)),
                       controller_failures=0, controller_steps=len(self._law_time))
        if self.estimator is not None:
            e = self.estimator.summary()
            out.update(estimator=e["kind"], estimator_step_median_s=e["step_median_s"],
                       estimator_step_max_s=e["step_max_s"], estimator_failures=e["failures"],
                       estimator_dt=self.estimator.dt, estimator_restarts=len(self.restarts))
        return out


def warn_failures(stats: dict[str, Any]) -> list[str]:
    """Warn (:class:`~mbsym.exceptions.ConvergenceWarning`) about the loop's failed solves in ``stats``
    (:meth:`TurbineLoop.statistics`): the run went on with a fallback there, which a user must know without
    asking for ``--stats``. Returns the messages (empty: no failure).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True):
    ...     warn_failures({"estimator": "mhe", "estimator_failures": 7})
    ['the mhe estimator failed 7 times; it fell back to the EKF estimate there (see estimator_failures in --stats)']
    """
    import warnings

    from ...exceptions import ConvergenceWarning

    messages = []
    n = int(stats.get("estimator_failures") or 0)
    if n:
        kind = stats.get("estimator", "state")
        fallback = "it fell back to the EKF estimate there" if kind == "mhe" else "its estimate was held there"
        messages.append(f"the {kind} estimator failed {n} time{'s' if n != 1 else ''}; {fallback} "
                        "(see estimator_failures in --stats)")
    n = int(stats.get("estimator_restarts") or 0)
    if n:
        messages.append(f"the EKF's wind estimate left its plausible range {n} time{'s' if n != 1 else ''}; it was "
                        "restarted from steady operation at the measured hub wind (see estimator_restarts in --stats)")
    n = int(stats.get("controller_failures") or 0)
    if n:
        steps = stats.get("controller_steps")
        of = f" of {steps} steps" if steps else ""
        messages.append(f"the NMPC failed {n}{of}; it applied its previous plan there, or held the last commands "
                        "after repeated failures (see controller_failures in --stats)")
    for message in messages:
        warnings.warn(message, ConvergenceWarning, stacklevel=3)
    return messages


def _collective(law, blades: int):
    """``law`` with its collective pitch command given to each of ``blades`` pitch inputs."""
    def spread(t, xc, y):
        xn, u = law(t, xc, y)
        return xn, np.concatenate([np.full(blades, u[0]), u[1:]])

    return spread
