"""ServoDyn's high-speed shaft brake (``HSSBrMode = 1``) on the operating turbine.

ServoDyn (OpenFAST v5.0.0, ``DriveTrain_CalcOutput``) commands the brake torque magnitude

    HSSBrTrqC(t) = HSSBrTqF · min(max((t − THSSBrDp) / HSSBrDT, 0), 1)        [N m, on the high-speed shaft]

(0 up to ``THSSBrDp``, a linear ramp over ``HSSBrDT``, then ``HSSBrTqF``), and ElastoDyn applies it against the
generator's rotation, ``HSSBrTrq = sign(QDT(GeAz)) HSSBrTrqC``, where the generator torque acts (its gearbox torque
is ``(GenTrq + HSSBrTrq) GBRatio``, through the same gearbox efficiency). When a step would reverse the shaft,
ElastoDyn (``FixHSSBrTq``) lowers the torque to what stops it: the brake then holds the shaft (Coulomb friction with
sticking).

mbsym gives the model the input ``HSSBrTqC`` [N m] (fed ServoDyn's ramp by :func:`~.simulation.simulate_turbine`,
zero in trims and linear models, as ServoDyn ignores the brake when linearizing) and applies

    HSSBrTrq = HSSBrTrqC · sat(ω_G / ω_s),   sat(x) = min(max(x, −1), 1),

with ``ω_G = |GBRatio| GeAz_d`` the generator speed [rad/s] and ``ω_s`` the slip speed: the sign law wherever the
generator turns faster than ``ω_s``, and below it a stiff viscous brake that stops and holds the shaft without the
events of ElastoDyn's fix. ``ω_s = τ_s HSSBrTqF / J_G`` (:meth:`HssBrake.slip_speed`) gives that viscous zone the
time constant ``τ_s`` (:attr:`HssBrake.slip_time`, default 20 ms: stable for explicit steps up to 55 ms), with
``J_G`` the inertia the brake turns against, about the high-speed shaft (the whole drivetrain with a rigid shaft,
the generator alone with ``DrTrDOF``; :class:`~.model.OperatingTurbine` takes it from its mass matrix). The price: a
shaft held against a driving torque ``T_d`` creeps at ``ω_s T_d / HSSBrTqF`` (measured on the NREL 5 MW parked at
8 m/s: 0.01° of rotor azimuth in 30 s with a rigid shaft; ElastoDyn holds it exactly).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import casadi as ca
import numpy as np

from ...exceptions import ParameterError

__all__ = ["HssBrake", "BRAKE_INPUT", "DEFAULT_SLIP_TIME"]

#: The model input of the commanded brake torque [N m] (ServoDyn's ``HSSBrTrqC``).
BRAKE_INPUT = "HSSBrTqC"
#: Default time constant τ_s [s] of the brake's slip zone (module docstring).
DEFAULT_SLIP_TIME = 0.02


@dataclass(frozen=True)
class HssBrake:
    """ServoDyn's ``HSSBrMode = 1`` brake (module docstring).

    Parameters
    ----------
    start : float
        ``THSSBrDp`` [s].
    deploy_time : float
        ``HSSBrDT`` [s] (0: applied at once).
    torque : float
        ``HSSBrTqF`` [N m] on the high-speed shaft.
    slip_time : float
        τ_s [s], the time constant of the slip zone (module docstring).
    """

    start: float
    deploy_time: float
    torque: float
    slip_time: float = DEFAULT_SLIP_TIME

    def __post_init__(self) -> None:
        bad = [f"{k} = {getattr(self, k)!r}" for k in ("start", "deploy_time", "torque")
               if not (math.isfinite(getattr(self, k)) and getattr(self, k) >= 0.0)]
        if not (math.isfinite(self.slip_time) and self.slip_time > 0.0):
            bad.append(f"slip_time = {self.slip_time!r}")
        if bad:
            raise ParameterError(f"HssBrake: {', '.join(bad)}; expected THSSBrDp, HSSBrDT, HSSBrTqF >= 0 and a "
                                 "positive slip time [s].")

    def slip_speed(self, inertia: float) -> float:
        """ω_s = τ_s HSSBrTqF / J_G [rad/s] for the inertia ``inertia`` J_G [kg m²] about the high-speed shaft."""
        if not (math.isfinite(inertia) and inertia > 0.0):
            raise ParameterError(f"HssBrake.slip_speed: the inertia must be positive [kg m^2]; got {inertia!r}.")
        return max(self.slip_time * self.torque / inertia, 1e-9)

    def command(self, t) -> np.ndarray:
        """ServoDyn's ``HSSBrTrqC`` [N m] at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        if self.deploy_time == 0.0:
            return np.where(t > self.start, self.torque, 0.0)
        return self.torque * np.clip((t - self.start) / self.deploy_time, 0.0, 1.0)

    def table(self, t_end: float) -> tuple[np.ndarray, np.ndarray]:
        """``(t, HSSBrTrqC)`` over ``[0, t_end]``: ServoDyn's ramp exactly, linear between its corners."""
        end = self.start + self.deploy_time
        corners = [0.0, self.start, end if self.deploy_time > 0.0 else self.start * (1 + 1e-12) + 1e-9,
                   max(t_end, end) + 1.0]
        t = np.unique(np.clip(corners, 0.0, None))
        return t, self.command(t)

    def torque_on_shaft(self, command: Any, generator_speed: Any, slip_speed: float) -> Any:
        """``HSSBrTrq = command · sat(ω_G / ω_s)`` [N m] (CasADi or numbers); ``generator_speed`` ω_G and
        ``slip_speed`` ω_s [rad/s]."""
        x = generator_speed / slip_speed
        if isinstance(x, (ca.SX, ca.MX, ca.DM)):
            return command * ca.fmin(ca.fmax(x, -1.0), 1.0)
        return command * np.clip(x, -1.0, 1.0)

    @classmethod
    def from_servodyn(cls, servodyn, *, slip_time: float = DEFAULT_SLIP_TIME) -> "HssBrake":
        """From ServoDyn's settings (``THSSBrDp``, ``HSSBrDT``, ``HSSBrTqF``)."""
        return cls(float(servodyn.hss_brake_start_time), float(servodyn.hss_brake_deploy_time),
                   float(servodyn.hss_brake_torque), slip_time)
