"""InflowWind's single-point lidar (``SensorType = 1``): wind speeds at focal points upstream of the hub.

A nacelle lidar measures the wind at points ahead of the rotor; that wind reaches the rotor later
(``distance / speed`` seconds, Taylor's frozen turbulence), so a controller can act before it
arrives. :class:`PointLidar` is OpenFAST v5's simplest lidar (``modules/inflowwind/src/Lidar.f90``,
``Lidar_CalcOutput``, ``SensorType_SinglePoint``), so that the same deck gives the same measurement
in mbsym and in OpenFAST:

- up to 5 beams, each focused at the point ``hub + RotorApexOffsetPos + (FocalDistanceX, Y, Z)``
  [m, ground axes; x downwind, so an upstream focus has a negative ``FocalDistanceX``], plus the
  hub's displacement from its initial position when ``ConsiderHubMotion = 1``;
- each beam returns the magnitude of the wind velocity ``|(u, v, w)|`` [m/s] at its point (not a
  line-of-sight projection: the ideal point sensor of InflowWind), evaluated in the full field as
  any point (with the field's Taylor advection: a point ``d`` upstream sees the field ``d / URef``
  seconds ahead);
- a new measurement where ``t`` is a whole multiple of ``MeasurementInterval`` exactly as InflowWind
  tests it in double precision (``MeasurementInterval * INT(t / MeasurementInterval) == t``); between
  them the last one is held. With a time step that is not a binary fraction some multiples fail the
  test and are skipped (0.00625 s steps, 0.1 s interval: the measurement due at 18.2 s comes at 18.3 s,
  in OpenFAST v5.0.0's output and here alike).

A uniform wind (InflowWind ``WindType`` 1, 2) is not advected (the same instant everywhere), so a
lidar there reads the rotor's wind of now: no preview, as in OpenFAST.

What such a preview can and cannot see: a few points against the rotor's swept area, so the
rotor-effective wind it predicts is correlated, not equal. A TurbSim field is frozen (no wind
evolution between the focus and the rotor), so the correlation here is an upper bound on a real
lidar's.

OpenFAST hands the measurements to a ``DISCON`` library in its extended swap array (ServoDyn
``EXavrSWAP = True``; ``BladedInterface_EX.f90``): records 2001 sensor type, 2002 number of beams,
2003 number of range gates, 2004 zero, then for ``n`` beams the speeds (2005 …), the focal points'
x, y and z [m] (each block ``n`` long); :func:`lidar_records` writes that layout.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import WindInputError

__all__ = ["PointLidar", "LIDAR_RECORD_START", "MAX_BEAMS", "lidar_records", "lidar_measurements"]

#: First (1-based) swap record of OpenFAST's lidar measurements (``LidarMsr_StartIdx``).
LIDAR_RECORD_START = 2001
#: InflowWind's limit on single-point beams (``NumBeam`` 1 to 5).
MAX_BEAMS = 5


@dataclass(frozen=True)
class PointLidar:
    """A single-point lidar (module docstring).

    Parameters
    ----------
    focal : array (n, 3)
        Focal points relative to the lidar [m] (``FocalDistanceX/Y/Z``), ``1 <= n <= 5``.
    apex_offset : array (3,)
        The lidar's offset from the hub [m] (``RotorApexOffsetPos``).
    interval : float
        Time between measurements [s] (``MeasurementInterval``).
    hub_motion : bool
        Whether the hub's displacement moves the lidar (``ConsiderHubMotion``).

    Raises
    ------
    WindInputError
        A beam count outside 1-5, non-finite positions or a non-positive interval.
    """

    focal: np.ndarray
    apex_offset: np.ndarray
    interval: float
    hub_motion: bool = False

    def __post_init__(self) -> None:
        focal = np.atleast_2d(np.asarray(self.focal, dtype=float))
        apex = np.asarray(self.apex_offset, dtype=float).reshape(-1)
        if focal.ndim != 2 or focal.shape[1] != 3 or not 1 <= focal.shape[0] <= MAX_BEAMS:
            raise WindInputError(f"a single-point lidar has 1 to {MAX_BEAMS} beams with (x, y, z) focal distances "
                                 f"[m]; got an array of shape {np.shape(self.focal)}.")
        if apex.shape != (3,) or not (np.all(np.isfinite(focal)) and np.all(np.isfinite(apex))):
            raise WindInputError("the lidar's focal distances and apex offset (3 values) must be finite [m].")
        if not (isinstance(self.interval, (int, float)) and math.isfinite(self.interval) and self.interval > 0):
            raise WindInputError(f"the lidar's MeasurementInterval must be a time > 0 [s]; got {self.interval!r}.")
        object.__setattr__(self, "focal", focal)
        object.__setattr__(self, "apex_offset", apex)
        object.__setattr__(self, "interval", float(self.interval))
        object.__setattr__(self, "hub_motion", bool(self.hub_motion))

    @property
    def n_beams(self) -> int:
        """Number of beams."""
        return self.focal.shape[0]

    @property
    def upstream_distance(self) -> float:
        """Mean distance of the focal points upstream of the hub [m] (``-(FocalDistanceX + apex x)``)."""
        return float(-np.mean(self.focal[:, 0] + self.apex_offset[0]))

    def positions(self, hub_position, hub_displacement=None) -> np.ndarray:
        """Focal points in ground axes [m], ``(n, 3)``, for the hub's initial position [m] (and its displacement
        [m], used with :attr:`hub_motion`)."""
        base = np.asarray(hub_position, dtype=float).reshape(3) + self.apex_offset
        if self.hub_motion and hub_displacement is not None:
            base = base + np.asarray(hub_displacement, dtype=float).reshape(3)
        return base + self.focal

    def measures_at(self, t: float) -> bool:
        """Whether InflowWind takes a new measurement at time ``t`` [s] (module docstring)."""
        return self.interval * int(t / self.interval) == t

    def measure(self, wind, t: float, hub_position, hub_displacement=None) -> np.ndarray:
        """Speeds ``|v|`` [m/s] at the focal points at time ``t`` [s] in ``wind`` (anything with
        ``velocity(t, points)``: :class:`~mbsym.wind.inflow.FullFieldWind`, ``UniformFieldWind``).

        Raises
        ------
        WindFieldDomainError
            A focal point outside the field's time or space (as InflowWind stops there).
        """
        pts = self.positions(hub_position, hub_displacement)
        v = np.asarray(wind.velocity(float(t), pts), dtype=float).reshape(-1, 3)
        return np.sqrt(np.sum(v * v, axis=1))


def lidar_records(speeds, positions) -> dict[int, float]:
    """The extended swap records (1-based) of a single-point lidar's measurement (module docstring)."""
    s = np.asarray(speeds, dtype=float).reshape(-1)
    p = np.asarray(positions, dtype=float).reshape(-1, 3)
    n = s.size
    rec = {LIDAR_RECORD_START: 1.0, LIDAR_RECORD_START + 1: float(n), LIDAR_RECORD_START + 2: 1.0,
           LIDAR_RECORD_START + 3: 0.0}
    first = LIDAR_RECORD_START + 4
    for i in range(n):
        rec[first + i] = float(s[i])
        for axis in range(3):
            rec[first + (axis + 1) * n + i] = float(p[i, axis])
    return rec


def lidar_measurements(lidar: PointLidar, wind, hub_position):
    """``t -> (speeds, positions)``: the lidar's measurement held at time ``t`` [s] as InflowWind holds it (a new
    one at each whole multiple of the interval), for a caller of a ``DISCON`` library (:func:`lidar_records`).

    The lidar sits at the hub's initial position ``hub_position`` [m]; a lidar with
    ``ConsiderHubMotion = 1`` is measured from there too (the caller warns: the hub's displacement of
    well under a metre against focal distances of tens of metres).
    """
    hub = np.asarray(hub_position, dtype=float).reshape(3)
    positions = lidar.positions(hub)
    held: dict[str, object] = {}

    def measure(t: float) -> tuple[np.ndarray, np.ndarray]:
        t = float(t)
        if "v" not in held or lidar.measures_at(t):
            held["v"] = lidar.measure(wind, t, hub)
        return held["v"], positions

    return measure
