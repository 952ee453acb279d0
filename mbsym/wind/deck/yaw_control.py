"""ServoDyn's commanded yaw: the override yaw maneuver and the yaw rate of a DISCON library (``YCMode = 5``).

ServoDyn's yaw drive is a spring and damper about a *commanded* yaw (OpenFAST v5.0.0, ``ServoDyn.f90``,
``Yaw_CalcOutput``)::

    YawMom = −YawSpr (NacYaw − YawPosCom) − YawDamp (YawRate − YawRateCom)

Without yaw control the command is ``YawPosCom = YawNeut``, ``YawRateCom = 0`` (``CalculateStandardYaw``), which
:class:`~mbsym.wind.structure.turbine.TurbineModel` models as its spring about ``yaw_neutral``. With a
``yaw_control`` the operating turbine takes the command as the inputs :data:`YAW_INPUTS` (``YawPosCom`` [rad],
``YawRateCom`` [rad/s]) and adds ``YawSpr (YawPosCom − YawNeut) + YawDamp YawRateCom`` to the yaw equation:

* :class:`YawManeuver` — the override maneuver (``TYawManS``, ``YawManRat``, ``NacYawF``). Facts from
  ``Yaw_UpdateStates``: at the first step with ``t ≥ TYawManS`` ServoDyn stores the standard command
  ``NacYawI`` (``YawNeut`` with ``YCMode = 0``), takes the rate ``sign(NacYawF − NacYawI) |YawManRat|`` and ends
  the maneuver at ``TYawManE = TYawManS + (NacYawF − NacYawI) / rate`` (the input file's ``TYawManE`` is not
  used); ``Yaw_CalcOutput`` then commands ``NacYawI + rate (t − TYawManS)`` at that rate until ``TYawManE``, and
  ``NacYawF`` at zero rate after. That is a function of time (:meth:`YawManeuver.command`, fed as a table by
  :func:`~.simulation.simulate_turbine`).
* :class:`DllYaw` — ``YCMode = 5``: the library's yaw-rate demand (swap record 48, ``BladedInterface.f90``)
  integrated by ServoDyn. Facts from ``SrvD_UpdateStates`` and ``CalculateStandardYaw``: the library is called
  at ``t + DT`` before ``Yaw_UpdateStates``, which adds ``rate · DT`` to the integrated command
  ``YawPosComInt`` (initially ``YawNeut``; the initial call at t = 0 is not integrated); the output at ``t``
  commands ``YawPosComInt + rate · DT`` at the library's rate; before ``TYCOn`` the command is ``YawNeut`` at zero
  rate. :func:`~.controllers.discon_in_loop` holds that command over each sample (:meth:`DllYaw.step`) and gives
  the library the measured yaw error (record 24, ``YawErr = WindDir − NacYaw`` with ``WindDir`` the direction of
  the hub-height wind, ``atan2(Wind1VelY, Wind1VelX)``, as OpenFAST's glue code fills ServoDyn's inputs).

Not modelled (refused by :func:`~mbsym.wind.deck.servo_audit.servo_audit`): ``YCMode`` 3 and 4, a maneuver
after library yaw control started, and a library's yaw-torque demand (ServoDyn refuses it too).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import ParameterError

__all__ = ["YAW_INPUTS", "YawManeuver", "DllYaw", "checked_yaw_control"]

#: The model inputs of ServoDyn's commanded yaw [rad] and yaw rate [rad/s].
YAW_INPUTS = ("YawPosCom", "YawRateCom")


@dataclass(frozen=True)
class YawManeuver:
    """ServoDyn's override yaw maneuver (module docstring).

    Parameters
    ----------
    neutral : float
        The command before the maneuver, ``NacYawI`` [rad] (``YawNeut`` with ``YCMode = 0``).
    final : float
        ``NacYawF`` [rad].
    rate : float
        ``YawManRat`` [rad/s] (its magnitude is used, as ServoDyn does).
    start : float
        ``TYawManS`` [s].
    """

    neutral: float
    final: float
    rate: float
    start: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.rate) and self.rate != 0.0):
            raise ParameterError(f"YawManeuver: YawManRat must be finite and non-zero (as ServoDyn requires); got "
                                 f"{self.rate!r} rad/s.")
        if not all(math.isfinite(v) for v in (self.neutral, self.final, self.start)):
            raise ParameterError(f"YawManeuver: YawNeut, NacYawF and TYawManS must be finite; got {self.neutral!r}, "
                                 f"{self.final!r}, {self.start!r}.")

    @property
    def signed_rate(self) -> float:
        """``sign(NacYawF − NacYawI) |YawManRat|`` [rad/s]."""
        return math.copysign(abs(self.rate), self.final - self.neutral)

    @property
    def end(self) -> float:
        """``TYawManE = TYawManS + (NacYawF − NacYawI) / rate`` [s]."""
        return self.start + abs(self.final - self.neutral) / abs(self.rate)

    def command(self, t) -> tuple[np.ndarray, np.ndarray]:
        """``(YawPosCom [rad], YawRateCom [rad/s])`` at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        moving = (t >= self.start) & (t < self.end)
        position = np.where(t < self.start, self.neutral,
                            np.where(moving, self.neutral + self.signed_rate * (t - self.start), self.final))
        return position, np.where(moving, self.signed_rate, 0.0)

    def tables(self, t_end: float) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """``{"YawPosCom": (t, values), "YawRateCom": (t, values)}`` over ``[0, t_end]``, exact when interpolated
        linearly (the rate's steps at ``TYawManS`` and ``TYawManE`` over 1 ns)."""
        eps = 1e-9
        corners = [0.0, self.start - eps, self.start, self.end - eps, self.end, max(t_end, self.end) + 1.0]
        t = np.unique(np.clip(corners, 0.0, None))
        position, rate = self.command(t)
        return {YAW_INPUTS[0]: (t, position), YAW_INPUTS[1]: (t, rate)}

    @classmethod
    def from_servodyn(cls, servodyn) -> "YawManeuver":
        """From ServoDyn's ``YawNeut``, ``NacYawF``, ``YawManRat``, ``TYawManS`` (with ``YCMode = 0``)."""
        return cls(float(servodyn.yaw_neutral), float(servodyn.yaw_maneuver_final),
                   float(servodyn.yaw_maneuver_rate), float(servodyn.yaw_maneuver_start_time))


@dataclass(frozen=True)
class DllYaw:
    """ServoDyn's yaw command from a DISCON library's yaw-rate demand, ``YCMode = 5`` (module docstring).

    Parameters
    ----------
    neutral : float
        ``YawNeut`` [rad]: the command before ``TYCOn`` and the start of the integration.
    start : float
        ``TYCOn`` [s].
    """

    neutral: float
    start: float = 0.0

    def step(self, t: float, integrated: float, rate: float, dt: float, first: bool) -> tuple[float, float, float]:
        """One library sample at ``t`` [s]: the integrated command (``YawPosComInt`` [rad]) before it, the library's
        rate demand [rad/s] and the step ``dt`` [s] → ``(integrated, YawPosCom, YawRateCom)``; ``first``: the
        initial call (t = 0), which ServoDyn does not integrate."""
        if t < self.start:
            return integrated, self.neutral, 0.0
        if not first:
            integrated = integrated + rate * dt
        return integrated, integrated + rate * dt, rate

    @classmethod
    def from_servodyn(cls, servodyn) -> "DllYaw":
        """From ServoDyn's ``YawNeut`` and ``TYCOn`` (with ``YCMode = 5``)."""
        return cls(float(servodyn.yaw_neutral), float(servodyn.yaw_control_start_time))


def checked_yaw_control(control, structure):
    """``control`` (a :class:`YawManeuver`, :class:`DllYaw` or None), checked against the structure: it moves the
    yaw spring and damper of the yaw DOF."""
    if control is None:
        return None
    if not isinstance(control, (YawManeuver, DllYaw)):
        raise TypeError(f"yaw_control must be a YawManeuver or DllYaw (mbsym.wind.deck.yaw_control) or None; "
                        f"got {type(control).__name__}.")
    if not structure.dofs.get("YawDOF"):
        raise ParameterError("yaw_control commands the yaw spring and damper: enable YawDOF.")
    return control
