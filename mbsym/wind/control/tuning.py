"""Tune the baseline controller the way ROSCO tunes: PI gains from ∂Q/∂β and ∂Q/∂ω over wind speed.

The rotor–drivetrain is reduced to one first-order equation in the generator speed
``ω_g`` (``J`` the drivetrain inertia on the rotor shaft, ``N`` the gearbox ratio)::

    δω̇_g = A δω_g + B_β δβ + B_τ δτ_g,   A = (∂Q/∂ω_g)/J,  B_β = (∂Q/∂β)/J,  B_τ = −N²/J

with ``Q`` the aerodynamic torque referred to the generator shaft (``Q = N · ½ρπR³U² Cp/λ``,
so ``∂Q/∂ω_g`` and ``∂Q/∂β`` come from ∂Cp/∂λ and ∂Cp/∂β of the performance table).
Above rated with constant power the generator torque ``P/ω_g`` adds ``N²/J · P/(N² ω_r²)`` to ``A``.
A PI controller ``u = −(K_p e + K_i ∫e)`` closed around it gives the characteristic
polynomial ``s² + (B K_p − A) s + B K_i``, so the closed-loop natural frequency ω
and damping ζ follow from

    K_p = (2ζω + A) / B,   K_i = ω² / B.                                (second_order_pi)

:func:`pi_gains` is that step for any ``A``, ``B`` (e.g. from mbsym's own linear
turbine models); :func:`tune_rosco` is ROSCO's whole procedure from a performance
table (as in the ROSCO toolbox's ``tune_controller``, whose documentation and code
were read to learn it): the operating schedule over wind speed (TSR tracking below
rated, constant rotor speed above; the pitch that gives the constant-power Cp), the
surface gradients (central differences of the table, interpolated with bicubic
splines), the pitch gain schedule on a straight-line fit of ``A`` and ``B_β`` over the
above-rated wind speeds, the torque gains at the last below-rated point, the EKF's
first-order poles (``A`` itself), ``k`` of k·ω² and the peak-shaving minimum pitch
(the thrust capped at ``ps_percent`` of its maximum).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import RectBivariateSpline

from ...exceptions import ParameterError
from .settings import BaselineSettings

__all__ = ["pi_gains", "tune_rosco", "RoscoTuning"]


def pi_gains(A, B, zeta, omega) -> tuple[np.ndarray, np.ndarray]:
    """PI gains placing the closed-loop poles of ``ẋ = A x + B u`` at natural frequency ``omega`` and damping ``zeta``.

    Returns ``(K_p, K_i)`` with ``K_p = (2ζω + A)/B`` and ``K_i = ω²/B`` (elementwise; for
    ``u = K_p e + K_i ∫e`` with ``e`` the reference minus ``x``).
    """
    A, B = np.asarray(A, dtype=float), np.asarray(B, dtype=float)
    if np.any(B == 0) or not np.all(np.isfinite(B)):
        raise ParameterError("pi_gains: B must be finite and non-zero.")
    return (2.0 * np.asarray(zeta) * np.asarray(omega) + A) / B, np.asarray(omega) ** 2 / B


@dataclass(frozen=True)
class RoscoTuning:
    """Result of :func:`tune_rosco` (arrays over ``wind_speed`` unless stated).

    Attributes
    ----------
    wind_speed : ndarray
        Operating points [m/s] (below rated without the rated point, then rated to cut-out).
    tsr, pitch, cp : ndarray
        Operating tip-speed ratio [-], pitch [rad] and power coefficient [-].
    A, B_pitch, B_torque : ndarray
        Linear model coefficients [1/s], [rad/s² per rad · s... = (rad/s)/s per rad], [(rad/s)/s per N m].
    schedule_pitch, schedule_kp, schedule_ki : ndarray
        Pitch gain schedule (above-rated points without rated): PC_GS_angles, PC_GS_KP, PC_GS_KI.
    torque_kp, torque_ki : float
        VS_KP, VS_KI.
    region2_gain : float
        k of k·ω_g² [N m/(rad/s)²] (VS_Rgn2K).
    min_pitch_schedule : ndarray
        Peak-shaving minimum pitch [rad] over ``wind_speed`` (PS_BldPitchMin).
    optimal_tsr, fine_pitch : float
        TSR and pitch of maximum Cp (VS_TSRopt, PC_FinePit).
    """

    wind_speed: np.ndarray
    tsr: np.ndarray
    pitch: np.ndarray
    cp: np.ndarray
    A: np.ndarray
    B_pitch: np.ndarray
    B_torque: np.ndarray
    schedule_pitch: np.ndarray
    schedule_kp: np.ndarray
    schedule_ki: np.ndarray
    torque_kp: float
    torque_ki: float
    region2_gain: float
    min_pitch_schedule: np.ndarray
    optimal_tsr: float
    fine_pitch: float
    rated_rotor_speed: float
    gearbox_ratio: float

    def settings(self, base: BaselineSettings) -> BaselineSettings:
        """``base`` with the tuned gains, schedules, estimator poles, k and peak-shaving table."""
        return base.replace(schedule_pitch=self.schedule_pitch, schedule_kp=self.schedule_kp,
                            schedule_ki=self.schedule_ki, torque_kp=self.torque_kp, torque_ki=self.torque_ki,
                            region2_gain=self.region2_gain, estimator_wind_speeds=self.wind_speed,
                            estimator_poles=self.A, min_pitch_wind_speeds=self.wind_speed,
                            min_pitch_schedule=self.min_pitch_schedule, optimal_tsr=self.optimal_tsr,
                            fine_pitch=self.fine_pitch)


class _Surface:
    """Bicubic spline of a table over (pitch, TSR) and of its central-difference gradients."""

    def __init__(self, pitch: np.ndarray, tsr: np.ndarray, table: np.ndarray) -> None:
        self.pitch, self.tsr = pitch, tsr
        self.value = RectBivariateSpline(pitch, tsr, table.T)
        d_tsr, d_pitch = np.gradient(table)     # per grid step, along rows (TSR) and columns (pitch)
        self.d_pitch = RectBivariateSpline(pitch, tsr, d_pitch.T)
        self.d_tsr = RectBivariateSpline(pitch, tsr, d_tsr.T)
        self.step_pitch, self.step_tsr = float(np.diff(pitch)[0]), float(np.diff(tsr)[0])

    def at(self, pitch, tsr):
        return np.squeeze(self.value(pitch, tsr).T)

    def gradient(self, pitch: float, tsr: float) -> tuple[float, float]:
        """(∂C/∂β [1/rad], ∂C/∂λ) at one point (grid-step gradients over the first grid steps)."""
        return (float(self.d_pitch(pitch, tsr)[0, 0]) / self.step_pitch,
                float(self.d_tsr(pitch, tsr)[0, 0]) / self.step_tsr)


def _inverse(values: np.ndarray, x: np.ndarray, q: float, fill: tuple[float, float] | None = None) -> float:
    """Linear interpolation of ``x`` at ``values == q`` (pairs sorted by value, as scipy's interp1d does)."""
    order = np.argsort(values, kind="stable")
    v, xs = values[order], x[order]
    if fill is not None and (q < v[0] or q > v[-1]):
        return fill[0] if q < v[0] else fill[1]
    return float(np.interp(q, v, xs))


def tune_rosco(table, *, rotor_radius: float, drivetrain_inertia: float, gearbox_ratio: float,
               rated_rotor_speed: float, rated_power: float, air_density: float = 1.225,
               cut_in: float = 3.0, rated_wind_speed: float, cut_out: float = 25.0,
               pitch_frequency=0.6, pitch_damping=0.7, torque_frequency: float = 0.15,
               torque_damping: float = 0.7, constant_power: bool = True, peak_shaving: float | None = 0.8,
               gearbox_efficiency: float = 1.0, optimal_tsr: float | None = None, fine_pitch: float | None = None,
               n_points: int = 60, n_pitch_points: int = 30) -> RoscoTuning:
    """ROSCO's tuning procedure (see the module docstring) from a performance table.

    Parameters
    ----------
    table : PerformanceTable
        Cp and Ct over TSR × pitch (:mod:`mbsym.wind.deck.performance`); uniform grids.
    rotor_radius : float
        R [m].
    drivetrain_inertia : float
        J [kg m²], rotor plus generator inertia referred to the rotor shaft.
    gearbox_ratio : float
        N [-].
    rated_rotor_speed : float
        [rad/s].
    rated_power : float
        [W].
    air_density : float, optional
        [kg/m³].
    cut_in, rated_wind_speed, cut_out : float
        [m/s].
    pitch_frequency, pitch_damping : float or array
        Closed-loop ω [rad/s] and ζ of the pitch loop (scalars, or one per above-rated point).
    torque_frequency, torque_damping : float
        Closed-loop ω [rad/s] and ζ of the torque loop.
    constant_power : bool, optional
        Constant power above rated (adds the generator-torque term to ``A``).
    peak_shaving : float or None, optional
        Thrust cap as a fraction of the unshaved maximum (ROSCO ``ps_percent``); None: no cap.
    gearbox_efficiency : float, optional
        Fraction, in k of k·ω².
    optimal_tsr, fine_pitch : float, optional
        Default: the table's Cp-maximizing grid point.
    n_points, n_pitch_points : int, optional
        Operating points in total and above rated (ROSCO: 60 and 30).
    """
    R, J, N, w_r, rho = (float(v) for v in (rotor_radius, drivetrain_inertia, gearbox_ratio, rated_rotor_speed,
                                             air_density))
    if min(R, J, N, w_r, rho, rated_power) <= 0 or not cut_in < rated_wind_speed < cut_out:
        raise ParameterError("tune_rosco: radius, inertia, gearbox ratio, rated speed and power, density must be "
                             "> 0 and cut_in < rated_wind_speed < cut_out.")
    area = math.pi * R**2
    cp, ct = _Surface(table.pitch, table.tsr, table.cp), _Surface(table.pitch, table.tsr, table.ct)
    i_tsr, i_pitch = np.unravel_index(int(np.argmax(table.cp)), table.cp.shape)
    tsr_opt = float(table.tsr[i_tsr]) if optimal_tsr is None else float(optimal_tsr)
    beta_min = float(table.pitch[i_pitch]) if fine_pitch is None else float(fine_pitch)

    v_below = np.linspace(cut_in, rated_wind_speed, n_points - n_pitch_points)[:-1]
    v_above = np.linspace(rated_wind_speed, cut_out, n_pitch_points + 1)
    v = np.concatenate([v_below, v_above])
    tsr_below = np.minimum(tsr_opt, w_r * R / v_below)
    tsr_above = w_r * R / v_above
    tsr = np.concatenate([tsr_below, tsr_above])
    cp_rated = float(cp.at(beta_min, tsr_above[0]))
    cp_op = np.concatenate([[float(cp.at(beta_min, x)) for x in tsr_below],
                            cp_rated * (tsr_above / tsr_above[0]) ** 3])
    pitch = np.empty(v.size)
    grad = np.empty((v.size, 2))
    for i in range(v.size):
        row = np.ravel(cp.at(table.pitch, tsr[i]))
        k = int(np.argmax(row))
        cp_op[i] = np.clip(cp_op[i], row[k:].min(), row[k:].max())
        found = _inverse(row[k:], table.pitch[k:], cp_op[i])
        pitch[i] = min(beta_min, found) if v[i] <= rated_wind_speed else max(beta_min, found)
        grad[i] = cp.gradient(pitch[i], tsr[i])
    dq_dpitch = N / 2 * rho * area * R * (1 / tsr) * grad[:, 0] * v**2
    dq_dtsr = N / 2 * rho * area * R * v**2 * (1 / tsr**2) * (grad[:, 1] * tsr - cp_op)
    A = dq_dtsr * (R / v / N) / J
    n_above = v_above.size - 1
    if constant_power:
        A[-n_above:] += N**2 / J * rated_power / (N**2 * w_r**2)
    B_pitch, B_torque = dq_dpitch / J, -N**2 / J * np.ones(v.size)
    va = v[-n_above:]
    fit_A = np.polyval(np.polyfit(va, A[-n_above:], 1), va)              # straight lines over wind speed
    fit_B = np.polyval(np.polyfit(va, B_pitch[-n_above:], 1), va)
    kp, ki = pi_gains(fit_A, fit_B, pitch_damping, pitch_frequency)
    kp_vs, ki_vs = pi_gains(A[:v_below.size], B_torque[:v_below.size], torque_damping, torque_frequency)
    k2 = math.pi * rho * R**5 * float(np.max(table.cp)) * gearbox_efficiency / (2.0 * tsr_opt**3 * N**3)
    min_pitch = _peak_shaving(ct, table, v, tsr, pitch, beta_min, rho * area, peak_shaving)
    return RoscoTuning(wind_speed=v, tsr=tsr, pitch=pitch, cp=cp_op, A=A, B_pitch=B_pitch, B_torque=B_torque,
                       schedule_pitch=pitch[-n_above:], schedule_kp=kp, schedule_ki=ki, torque_kp=float(kp_vs[-1]),
                       torque_ki=float(ki_vs[-1]), region2_gain=k2, min_pitch_schedule=min_pitch,
                       optimal_tsr=tsr_opt, fine_pitch=beta_min, rated_rotor_speed=w_r, gearbox_ratio=N)


def _peak_shaving(ct: _Surface, table, v, tsr, pitch, beta_min, rho_area, fraction) -> np.ndarray:
    """Minimum pitch keeping the thrust below ``fraction`` of its unshaved maximum (ROSCO's peak shaving)."""
    out = np.full(v.size, beta_min)
    if fraction is None:
        return out
    thrust = 0.5 * rho_area * v**2 * np.array([float(ct.at(b, x)) for b, x in zip(pitch, tsr)])
    cap = fraction * thrust.max()
    for i in range(v.size):
        row = np.ravel(ct.at(table.pitch, tsr[i]))
        ct_max = cap / (0.5 * rho_area * v[i] ** 2)
        if thrust[i] <= cap:
            ct_max = min(row.max(), ct_max)
        out[i] = max(beta_min, _inverse(row, table.pitch, ct_max, fill=(table.pitch[0], table.pitch[-1])))
    return out
