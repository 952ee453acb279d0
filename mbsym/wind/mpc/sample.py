"""The turbine NMPC and its EKF as CasADi Functions of fixed work: what an exported DISCON library runs.

:func:`sample_functions` turns a :class:`~.nmpc.TurbineNMPC` (solver ``"rti"``) and an EKF
:class:`~.estimator.TurbineEstimator` into Functions with no Python in between, each a fixed
amount of work, so they can be generated as C (:mod:`.discon_nmpc`):

- with an MHE instead of the EKF, its sample (:mod:`.sample_mhe`: the EKF, the arrival cost, one QP over the
  window);
- ``ekf(z, P, y, u, predict) -> (z, P)``: one EKF sample, exactly :meth:`mbsym.control.EKF.step`:
  the time update over the last estimator interval with the mean measured pitch and torque ``u``
  (skipped when ``predict`` is 0, the first sample), then the measurement update with ``y`` =
  (``GenSpeed`` [rpm], ``YawBrTAxp`` [m/s²]; on a floating platform also ``NcIMURAys`` [deg/s²],
  ``PtfmPitch`` [deg], ``PtfmSurge`` [m], :data:`~.estimator.FLOATING_MEASUREMENTS`);
- ``rti(w, z, pitch, torque, lam) -> (w, rates, violation, lam)`` (:meth:`SampleFunctions.rti`, three
  generated parts ``qp_data``, ``qp``, ``finish``): one real-time iteration of
  :class:`mbsym.control.NMPC`: the NMPC state from the estimate and the measured pitch [rad] and
  torque [N m] (:meth:`~.estimator.TurbineEstimator.control_state`; with a cost on the rates' changes,
  :attr:`~.nmpc.NMPCTuning.pitch_acceleration_scale`, the OCP's augmented state also holds the rates
  applied before, taken from the shifted plan ``w``: its stage 0 is the last plan's first rates, or the
  held ones after a hold; zero at the start-up), the stage parameters of the
  estimated wind held over the horizon (its references from the steady reference table, as
  :meth:`~.nmpc.TurbineNMPC.step` sets them), the Gauss–Newton QP at the shifted plan ``w``
  (:func:`mbsym.control.qp.preparation_function`), one QP solve by CasADi's ``qrqp`` (an
  active-set solver whose C CasADi generates; at most 200 iterations) started from the multipliers
  ``lam`` (bounds, then constraints) of the previous sample's QP shifted one stage, the full step,
  the rates to apply (the plan's first controls, clipped to their bounds) and the plan and
  multipliers shifted one stage: the next sample's warm start. The multipliers' guess makes qrqp
  start from the previous active set: 1.4 against 7.8 ms median per QP on the NREL 5 MW OCP
  (CasADi's virtual machine, same solutions; benchmarks/nmpc_acados.py measures the generated
  step); its iterations are capped at :data:`QP_MAX_ITER` (:data:`QP_MAX_ITER_LARGE` for the floating
  NMPC's larger OCP, :func:`qp_max_iter`; a step stopped there is accepted when
  it passes the violation test below: the bounded worst case of a real-time step; the QP is a
  part of its own because CasADi's generated code returns an error from a capped QP, which would
  end the enclosing Function before its step is computed). ``violation`` is the QP solution's largest bound or constraint
  violation divided by ``1 + ‖Δw‖∞`` (:class:`mbsym.control.qp.QPCall`'s acceptance test:
  accepted up to 1e-6);
- ``init(wind) -> z``: the estimate of steady operation at the hub wind [m/s] (the estimator's
  states at the plant's steady guess, tabulated every :data:`INIT_STEP` m/s over the NMPC's
  reference winds and interpolated linearly, the wind clipped to that range): the estimator's
  start and restart;
- ``startup(z, pitch, torque) -> (w, rates, violation, lam)``: the first sample: from the initial guess
  (every stage at the NMPC state, zero rates, zero multipliers) :data:`STARTUP_ITERATIONS` full Gauss–Newton steps
  (the Python NMPC converges a line-search SQP instead: on the NREL 5 MW at 12 m/s the full steps
  reach its solution to 1e-12 relative in 3 iterations, measured), then the same ending as ``rti``.

:class:`SampledLoop` runs them on the schedule of :class:`~.loop.TurbineLoop` (estimator every
``ke``, NMPC every ``kn`` loop samples; demands ramped at the rates with the actuators' lead between
NMPC samples): the Python mirror of the exported library's C wrapper, and the reference the
library is tested against.

**Start and restarts of the estimator.** With ``initial="hub-wind"`` the estimate starts at the
first sample from ``init`` at the measured hub wind (a nacelle anemometer; OpenFAST's record 27),
as :class:`~.loop.TurbineLoop` starts from the steady operation at the wind of its first sample;
with ``initial="fixed"`` from the estimator's own prior ``z0`` (an export-time wind). A start from
a fixed 10 m/s on OpenFAST's 14 m/s full-field case with flexible blades and drivetrain (whose
start rings the tower and drivetrain: −1.2 m/s² at the tower top, ±30 rpm) sent the wind estimate
to 6 m/s within 0.2 s and it stayed near 3-8 m/s (the NMPC then overspeeded the rotor); from the
measured 15.2 m/s it tracked (12-16 m/s while the disk-averaged wind was 14-16 m/s; measured on
the library's own logged inputs). An estimate whose wind leaves :attr:`SampleFunctions.wind_range`
(half the lowest to 1.5 times the highest reference wind) or turns non-finite restarts the
estimator the same way; the sample then applies the baseline's commands, and the next NMPC sample
starts with the start-up iterations (the library counts and reports it).
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ControlDefinitionError
from .lidar_preview import LidarPreview, PreviewSettings
from .runtime_settings import RuntimeLayout, RuntimeSettings, runtime_layout
from .sample_ekf import INIT_STEP, ekf_function, init_function
from .sample_mhe import MHEMirror
from .sample_rti import QP_MAX_ITER, QP_MAX_ITER_LARGE, STARTUP_ITERATIONS, qp_max_iter, rti_function

__all__ = ["QP_ACCEPT", "QP_MAX_ITER", "QP_MAX_ITER_LARGE", "qp_max_iter", "STARTUP_ITERATIONS", "INIT_STEP",
           "INITIAL_ESTIMATES", "SampleFunctions", "SampledLoop", "sample_functions"]

#: Largest accepted QP violation relative to ``1 + ‖Δw‖∞`` (:attr:`mbsym.control.qp.QPCall.FEAS_TOL`).
QP_ACCEPT = 1e-6
#: How the estimator starts (module docstring).
INITIAL_ESTIMATES = ("hub-wind", "fixed")


@dataclass(frozen=True)
class SampleFunctions:
    """The Functions of :func:`sample_functions` and the constants of their schedule.

    Attributes
    ----------
    ekf, startup, init : casadi.Function
        See the module docstring.
    qp_data, qp, finish : casadi.Function
        The real-time iteration in three parts, as the library calls them (:meth:`rti`): the QP at the
        shifted plan (``(w, z, pitch, torque[, wind]) -> (h, g, a, lba, uba, lbx, ubx)``), the QP solver
        (CasADi's ``qrqp`` conic, at most :func:`qp_max_iter` iterations) and the step
        (``(w, dw, lam, a, lba, uba, lbx, ubx) -> (w_next, rates, violation, lam_next)``).
    z0, P0 : ndarray
        The estimator's prior estimate (its start with ``initial="fixed"``) and covariance.
    initial : {"hub-wind", "fixed"}
        How the estimator starts and restarts (module docstring).
    wind_range : tuple of float
        Winds [m/s] beyond which an estimate restarts the estimator.
    preview : PreviewSettings or None
        With a lidar preview (:mod:`.lidar_preview`), ``rti`` and ``startup`` take the stage winds
        ``wind`` (N + 1) [m/s] as their last input.
    nmpc_dt : float
        NMPC sample time [s].
    n_lam : int
        Length of the multipliers ``lam`` (the QP's bounds, then its constraints).
    horizon : int
        NMPC stages N.
    n_w : int
        Length of the plan ``w``.
    loop_dt : float
        Loop (and exported library) sample time [s].
    ke, kn : int
        Loop samples per estimator and per NMPC sample.
    lead : tuple of float
        Lead of the pitch and torque demands [s] (:meth:`~.prediction.PredictionModel.commands`).
    limits : tuple of (float, float)
        Pitch [rad] and torque [N m] demand limits.
    measurements : tuple of str
        What ``ekf``'s ``y`` holds, in the estimator's units: ``GenSpeed`` [rpm], ``YawBrTAxp`` [m/s²], and on a
        floating platform ``NcIMURAys`` [deg/s²], ``PtfmPitch`` [deg], ``PtfmSurge`` [m].
    mhe : MHEFunctions or None
        With an MHE estimator (:mod:`.sample_mhe`), its Functions; the estimator's sample is then the MHE's
        (``ekf`` stays for reference; ``z0``, ``P0`` are the MHE's prior).
    layout : RuntimeLayout
        The run-time settings (:mod:`.runtime_settings`): ``qp_data``, ``startup`` and ``finish`` take a settings
        vector (``layout.exported``: the exported ones; :meth:`RuntimeLayout.settings` for others).
    """

    ekf: ca.Function
    qp_data: ca.Function
    qp: ca.Function
    finish: ca.Function
    startup: ca.Function
    z0: np.ndarray
    P0: np.ndarray
    n_w: int
    loop_dt: float
    ke: int
    kn: int
    lead: tuple
    limits: tuple
    init: ca.Function
    initial: str
    wind_range: tuple
    preview: object = None
    nmpc_dt: float = 0.0
    horizon: int = 0
    n_lam: int = 0
    stage: tuple = (0, 0, 0)
    rate_bounds: tuple = ()
    measurements: tuple = ("GenSpeed", "YawBrTAxp")
    mhe: object = None
    layout: RuntimeLayout | None = None

    def hold(self, w: np.ndarray, lam: np.ndarray, rate_bounds: tuple | None = None) -> tuple:
        """After a failed QP: the stored (shifted) plan's first rates, clipped to their bounds (default the
        exported ones), and the plan and multipliers shifted one more stage (the library's hold)."""
        nx, nu, nc = self.stage
        bounds = self.rate_bounds if rate_bounds is None else rate_bounds
        rates = np.array([min(max(w[nx + i], lo), hi) for i, (lo, hi) in enumerate(bounds)])
        block, n = nx + nu, self.horizon
        w = w.copy()
        w[: (n - 1) * block] = w[block: n * block]
        w[(n - 1) * block: (n - 1) * block + nx] = w[n * block:]
        lam = lam.copy()
        lam[: (n - 1) * block] = lam[block: n * block]
        lam[self.n_w: self.n_w + (n - 1) * (nx + nc)] = lam[self.n_w + nx + nc: self.n_w + n * (nx + nc)]
        return rates, w, lam

    def rti(self, w, z, pitch: float, torque: float, *rest, settings=None) -> tuple:
        """One real-time iteration ``(w_next, rates, violation, lam_next)`` from the plan ``w``, the estimate,
        the measured pitch [rad] and torque [N m], (with a preview) the stage winds, and the multipliers
        ``lam``: :attr:`qp_data`, :attr:`qp` and :attr:`finish` in turn, as the library calls them. A QP
        stopped at its iteration cap is used as it is (its step is judged by the violation). ``settings``: a
        settings vector (default the exported one, :mod:`.runtime_settings`)."""
        *extra, lam = rest
        s = self.layout.exported if settings is None else settings
        h, g, a, lba, uba, lbx, ubx = self.qp_data(w, z, pitch, torque, s, *extra)
        n_w = self.n_w
        sol = self.qp(h=h, g=g, a=a, lba=lba, uba=uba, lbx=lbx, ubx=ubx, lam_x0=lam[:n_w], lam_a0=lam[n_w:])
        lam_qp = ca.vertcat(sol["lam_x"], sol["lam_a"])
        return self.finish(w, sol["x"], lam_qp, a, lba, uba, lbx, ubx, s)

    def restart(self, hub_wind: float | None) -> np.ndarray:
        """The estimate the estimator (re)starts from at the measured hub wind [m/s] (``initial="hub-wind"``)."""
        if self.initial == "fixed":
            return self.z0.copy()
        if hub_wind is None or not np.isfinite(hub_wind):
            raise ControlDefinitionError(f"initial='hub-wind' starts the estimator from the measured hub wind; got "
                                         f"hub_wind={hub_wind!r}. Pass it to SampledLoop.step (or use "
                                         "initial='fixed').")
        return np.asarray(self.init(hub_wind), dtype=float).ravel()

    def plausible(self, z: np.ndarray) -> bool:
        """Whether an estimate is finite with its wind inside :attr:`wind_range`."""
        lo, hi = self.wind_range
        return bool(np.all(np.isfinite(z)) and lo <= z[-1] <= hi)


def _multiple(period: float, base: float, what: str) -> int:
    m = period / base
    if abs(m - round(m)) > 1e-9 * max(m, 1.0) or round(m) < 1:
        raise ControlDefinitionError(f"the {what} sample time {period:g} s must be a whole multiple of the loop sample "
                                     f"time {base:g} s.")
    return int(round(m))


def sample_functions(nmpc, estimator, loop_dt: float, *, initial: str = "hub-wind",
                     settings=None, preview=None) -> SampleFunctions:
    """The fixed-work Functions of ``nmpc`` with ``estimator`` (module docstring).

    Parameters
    ----------
    nmpc : TurbineNMPC
        Solver ``"rti"`` (its QP solver is replaced by ``qrqp`` here).
    estimator : TurbineEstimator
        Kind ``"ekf"``, or ``"mhe"`` with real-time iterations (:mod:`.sample_mhe`).
    loop_dt : float
        Loop sample time [s]; the estimator's and the NMPC's sample times are multiples of it, the
        NMPC's of the estimator's.
    initial : {"hub-wind", "fixed"}, keyword-only
        How the estimator starts and restarts (module docstring; default ``"hub-wind"``).
    settings : BaselineSettings, optional, keyword-only
        The controller's targets for the steady estimates of ``init`` (default the built-in NREL 5 MW's).
    preview : PreviewSettings, optional, keyword-only
        A lidar preview (:mod:`.lidar_preview`): the stage winds become an input of ``rti`` and
        ``startup`` (default None: the estimated wind held over the horizon).

    Raises
    ------
    ControlDefinitionError
        Another solver or estimator kind, sample times that are not multiples, an estimator that
        does not estimate the NMPC's states, an OCP with slacks or collocation variables, or an
        unknown ``initial``.
    UnsupportedFeatureError
        An estimator measuring other than :data:`~.estimator.ESTIMATOR_MEASUREMENTS` (land) or those and
        :data:`~.estimator.FLOATING_MEASUREMENTS` (floating).
    """
    from ...exceptions import UnsupportedFeatureError
    from .estimator import ESTIMATOR_MEASUREMENTS, FLOATING_MEASUREMENTS, TurbineEstimator
    from .nmpc import TurbineNMPC

    if not isinstance(nmpc, TurbineNMPC):
        raise TypeError(f"nmpc must be a TurbineNMPC; got {type(nmpc).__name__}.")
    if not isinstance(estimator, TurbineEstimator):
        raise TypeError(f"estimator must be a TurbineEstimator; got {type(estimator).__name__}.")
    known = (ESTIMATOR_MEASUREMENTS, ESTIMATOR_MEASUREMENTS + FLOATING_MEASUREMENTS)
    if tuple(estimator.measurements) not in known:
        raise UnsupportedFeatureError(f"the sampled loop (the exported NMPC) reads {list(known[0])} (land) or "
                                      f"{list(known[1])} (floating); this estimator measures "
                                      f"{list(estimator.measurements)}. Use the estimator of estimation_model(plant).")
    mhe = None
    if estimator.kind == "mhe":                      # real-time iterations only (mhe_functions refuses others)
        from .sample_mhe import mhe_functions

        mhe = mhe_functions(estimator)
    if initial not in INITIAL_ESTIMATES:
        raise ControlDefinitionError(f"initial must be one of {list(INITIAL_ESTIMATES)}; got {initial!r}.")
    if nmpc.nmpc.solver != "rti":
        raise ControlDefinitionError(f"only real-time iterations have a fixed-work sample; the NMPC's solver is "
                                     f"{nmpc.nmpc.solver!r} (give solver='rti').")
    ke = _multiple(estimator.dt, loop_dt, "estimator")
    kn = _multiple(nmpc.dt, loop_dt, "NMPC")
    if kn % ke:
        raise ControlDefinitionError(f"the NMPC sample time {nmpc.dt:g} s must be a multiple of the estimator's "
                                     f"{estimator.dt:g} s.")
    f = estimator.filter
    pred = nmpc.prediction
    grid = np.asarray(nmpc.references.winds, dtype=float)
    init = init_function(estimator, grid, settings)
    if preview is not None and not isinstance(preview, PreviewSettings):
        raise TypeError(f"preview must be a PreviewSettings or None; got {type(preview).__name__}.")
    on = preview is not None
    layout = runtime_layout(nmpc, estimator, preview)
    data, qp, finish = rti_function(nmpc, estimator, layout, startup=False, preview=on)
    return SampleFunctions(ekf=ekf_function(estimator), qp_data=data, qp=qp, finish=finish, mhe=mhe,
                           n_lam=finish.size1_in("lam"), layout=layout,
                           startup=rti_function(nmpc, estimator, layout, startup=True, preview=on),
                           preview=preview, nmpc_dt=float(nmpc.dt), horizon=int(nmpc.horizon),
                           z0=np.array(f._arrival[0] if mhe else f.x, dtype=float),      # an MHE's prior
                           P0=np.array(f._arrival[1] if mhe else f.P, dtype=float),
                           n_w=nmpc.nmpc.transcription.problem.layout.n_w,
                           loop_dt=float(loop_dt), ke=ke, kn=kn, lead=tuple(float(v) for v in pred._lead),
                           limits=tuple(tuple(float(v) for v in b) for b in pred._demand_limits), init=init,
                           initial=initial, wind_range=(0.5 * float(grid[0]), 1.5 * float(grid[-1])),
                           stage=_stage_sizes(nmpc), rate_bounds=_rate_bounds(nmpc),
                           measurements=tuple(estimator.measurements))


def _stage_sizes(nmpc) -> tuple[int, int, int]:
    """States, controls and path constraints per stage of the NMPC's OCP (the plan's and multipliers' blocks)."""
    P = nmpc.nmpc.transcription.problem
    return int(P.n_x), int(P.n_u), int(P.n_c)


def _rate_bounds(nmpc) -> tuple:
    """Bounds of the NMPC's rates (pitch [rad/s], torque [N m/s])."""
    P, nc = nmpc.nmpc.transcription.problem, nmpc.nmpc.transcription.n_controls
    return tuple((float(P.lbu[i]), float(P.ubu[i])) for i in range(nc))


class SampledLoop:
    """The Functions of :func:`sample_functions` on :class:`~.loop.TurbineLoop`'s schedule (module docstring).

    Parameters
    ----------
    functions : SampleFunctions
    settings : dict, optional
        Run-time settings by input-file key (:meth:`~.runtime_settings.RuntimeLayout.settings`, as the library reads
        them from its input file; default the exported ones).

    Attributes
    ----------
    rti_walls : list of float
        Wall time of every NMPC sample's Function call [s] (CasADi's virtual machine).
    restarts : list of float
        Times [s] at which the estimator was restarted (an implausible estimate).
    holds : list of float
        Times [s] of NMPC samples whose QP was not accepted and that applied the previous plan's next rates
        (:meth:`SampleFunctions.hold`; at most ``horizon - 1`` in a row).
    failures : list of float
        Times [s] of NMPC samples whose QP was not accepted with no plan left to hold: the library's baseline
        from there to the next NMPC sample (:meth:`step` returns None), then the start-up iterations.
    """

    def __init__(self, functions: SampleFunctions, settings: dict | None = None) -> None:
        self.f = functions
        self.settings: RuntimeSettings = functions.layout.settings(settings)
        self.k = 0
        self.z, self.P = functions.z0.copy(), functions.P0.copy()
        self.w: np.ndarray | None = None
        self.lam: np.ndarray | None = None
        self._acc, self._n = np.zeros(2), 0
        self._anchor = None
        self.rti_walls: list[float] = []
        self.restarts: list[float] = []
        self.holds: list[float] = []
        self.failures: list[float] = []
        self._streak = 0
        self.preview = None if functions.preview is None else LidarPreview(
            self.settings.preview or functions.preview, functions.nmpc_dt, functions.horizon, functions.wind_range)
        self.stage_winds: np.ndarray | None = None
        self.mhe = None if functions.mhe is None else MHEMirror(functions.mhe, functions.z0, QP_ACCEPT)

    @staticmethod
    def _after_failure(held: np.ndarray, capped: np.ndarray) -> np.ndarray:
        """The next QP's multipliers after a failed one: the failed (capped) QP's, so that its active-set search
        goes on from where the cap stopped it, or the held plan's when they are not finite (the library's C)."""
        return capped if np.all(np.isfinite(capped)) else held

    def step(self, t: float, gen_speed_rpm: float, accel: float, pitch: float, torque: float,
             hub_wind: float | None = None, lidar=None, more=()) -> tuple[float, float] | None:
        """Pitch [rad] and torque [N m] demands at loop sample ``t`` [s] from the measurements.

        ``more``: the estimator's further measurements (:attr:`SampleFunctions.measurements` after the first
        two; a floating platform's ``NcIMURAys`` [deg/s²], ``PtfmPitch`` [deg], ``PtfmSurge`` [m]).

        ``hub_wind`` [m/s]: the measured hub wind, read where the estimator starts or restarts
        (``initial="hub-wind"``). ``lidar``: the beams' speeds [m/s] (with a preview; None: no
        measurement this sample). ``None`` where the library applies its baseline's commands: from
        a restart of the estimator (:attr:`restarts`) or a failed QP with no plan to hold
        (:attr:`failures`) to the next NMPC sample.
        """
        import time

        f, k = self.f, self.k
        if len(more) != len(f.measurements) - 2:
            raise ControlDefinitionError(f"the estimator measures {list(f.measurements)}: give the last "
                                         f"{len(f.measurements) - 2} as more=; got {len(more)} values.")
        self.k += 1
        if k == 0:
            self.z = f.restart(hub_wind)
            self._restart_mhe()
        else:
            self._acc += (pitch, torque)
            self._n += 1
        restarted = False
        if k % f.ke == 0:
            mean = self._acc / self._n if self._n else np.array([pitch, torque])
            y = [gen_speed_rpm, accel, *more]
            if self.mhe is None:
                z, P = f.ekf(self.z, self.P, y, mean, 0.0 if k == 0 else 1.0)
            else:
                z, P = self.mhe.step(y, mean, 0.0 if k == 0 else 1.0), self.mhe.P
            self.z, self.P = np.asarray(z).ravel(), np.asarray(P)
            self._acc[:], self._n = 0.0, 0
            if not (f.plausible(self.z) and np.all(np.isfinite(self.P))):
                self.z, self.P = f.restart(hub_wind), f.P0.copy()
                self._restart_mhe()
                self.w = self._anchor = None
                self._streak = 0
                self.restarts.append(t)
                restarted = True
        extra = []
        if self.preview is not None and k % f.kn == 0:     # the library's clock: k loop samples from 0
            if lidar is not None and self.settings.preview is not None:     # PreviewSource none: no lidar
                self.preview.push(k * f.loop_dt, lidar)
            self.stage_winds = self.preview.horizon(k * f.loop_dt, float(self.z[-1]))
            extra = [self.stage_winds]
        if k % f.kn == 0 and not restarted:
            c0 = time.perf_counter()
            s = self.settings.vector
            out = f.startup(self.z, pitch, torque, s, *extra) if self.w is None else \
                f.rti(self.w, self.z, pitch, torque, *extra, self.lam, settings=s)
            self.rti_walls.append(time.perf_counter() - c0)
            w, rates, viol, lam = (np.asarray(v).ravel() for v in out)
            if np.all(np.isfinite(w)) and np.all(np.isfinite(rates)) and viol[0] <= QP_ACCEPT:
                self.w, self.lam, self._streak = w, lam, 0
            elif self.w is not None and self._streak < f.horizon - 1:         # hold the previous plan
                rates, self.w, held = f.hold(self.w, self.lam, self.settings.rate_bounds)
                self.lam = self._after_failure(held, lam)
                self._streak += 1
                self.holds.append(t)
            else:                                                              # the library's baseline
                self.w = self.lam = self._anchor = None
                self._streak = 0
                self.failures.append(t)
                return None
            self._anchor = (t, *self._ramp_start(t, pitch, torque), rates)
        if self._anchor is None:
            return None
        t_a, p_a, q_a, r = self._anchor
        (b0, b1), (q0, q1) = self.settings.limits
        el = t - t_a
        return (min(max(p_a + r[0] * (el + self.f.lead[0]), b0), b1),
                min(max(q_a + r[1] * (el + self.f.lead[1]), q0), q1))

    def _restart_mhe(self) -> None:
        if self.mhe is not None:
            self.mhe.restart(self.z)

    def _ramp_start(self, t: float, pitch: float, torque: float) -> tuple[float, float]:
        if self._anchor is None:
            return pitch, torque
        t_a, p_a, q_a, r = self._anchor
        (b0, b1), (q0, q1) = self.settings.limits
        return min(max(p_a + r[0] * (t - t_a), b0), b1), min(max(q_a + r[1] * (t - t_a), q0), q1)

