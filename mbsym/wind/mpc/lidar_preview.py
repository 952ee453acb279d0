"""The NMPC's wind over its horizon from a nacelle lidar and the estimator: a realistic preview.

A lidar (:class:`~mbsym.wind.inflow.PointLidar`) measures the wind ``d`` metres upstream; that wind
reaches the rotor about ``d / U`` seconds later. :class:`LidarPreview` turns the measurements into
the stage winds of the NMPC, the same arithmetic in Python (:class:`~.sample.SampledLoop`) and in
the exported library's C (:mod:`.discon_nmpc`):

1. at every NMPC sample ``t``, the mean ``m`` of the beams' speeds (beams whose speed is not finite
   and positive are left out; none left: no new sample);
2. the advection speed ``Ū``: the first ``m``, then a first-order filter of ``m`` with time
   constant :attr:`PreviewSettings.advection_time`;
3. a moving average of the last ``M`` means (``M`` = :attr:`PreviewSettings.window` / NMPC sample
   time, rounded, at least 1): the beams see a few points, the rotor the whole disk, so the fast
   part of the signal is not shared (a TurbSim field has no coherence beyond the eddies that span
   the rotor); the average is ``(M - 1) / 2`` samples late, which its arrival time takes back;
4. that value is expected at the rotor at ``a = t + d / max(Ū, 1 m/s) - (M - 1) dt / 2`` and kept
   in a ring of :data:`CAPACITY` samples (arrival times kept increasing);
5. the stage winds ``w_k = ŵ + L(t + k dt) - L(t)``, k = 0..N: the estimator's wind ``ŵ`` now, and
   the lidar's *change* from now to each stage, ``L`` interpolating the ring linearly in arrival
   time and holding its ends (beyond the latest arrival: the latest value). So stage 0 is the
   estimate, a lidar with an offset or a gain error to the rotor-effective wind (a few points
   against the disk, ``|v|`` against the axial speed) only scales the changes, and no measurement
   at all gives the estimate held, as without preview. Stage winds are clipped to the estimator's
   plausible range.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import ControlDefinitionError

__all__ = ["CAPACITY", "PreviewSettings", "LidarPreview", "PREVIEW_C", "preview_c"]

#: Samples the arrival ring holds (at 0.1 s a lead of up to 102 s).
CAPACITY = 1024
#: Largest moving-average length [samples].
MAX_WINDOW = 128


@dataclass(frozen=True)
class PreviewSettings:
    """How lidar measurements become the NMPC's stage winds (module docstring).

    Attributes
    ----------
    distance : float
        Mean distance of the focal points upstream of the rotor [m]
        (:attr:`PointLidar.upstream_distance <mbsym.wind.inflow.PointLidar.upstream_distance>`).
    n_beams : int
        Number of beams the library reads (1-5).
    window : float
        Moving-average length [s] (default 4 s: on the shared 14 m/s TurbSim field with 5 beams 60 m
        upstream, the best of 0.1-6 s for the 1-4 s changes of the rotor's disk-averaged wind: their
        prediction error 0.83, 0.74, 0.64, 0.66 of persistence's at 1, 2, 3, 4 s ahead, against 1.63,
        1.25, 1.0, 0.82 with 1 s; tests/wind/control/test_lidar_preview.py).
    advection_time : float
        Time constant of the advection-speed filter [s] (default 60 s).
    """

    distance: float
    n_beams: int
    window: float = 4.0
    advection_time: float = 60.0

    def __post_init__(self) -> None:
        for name in ("distance", "window", "advection_time"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
                raise ControlDefinitionError(f"PreviewSettings.{name} must be a number > 0; got {v!r}.")
        if not (isinstance(self.n_beams, int) and 1 <= self.n_beams <= 5):
            raise ControlDefinitionError(f"PreviewSettings.n_beams must be 1 to 5; got {self.n_beams!r}.")

    @classmethod
    def for_lidar(cls, lidar, **changes) -> "PreviewSettings":
        """The settings of a :class:`~mbsym.wind.inflow.PointLidar` (its distance and beams)."""
        if lidar.upstream_distance <= 0:
            raise ControlDefinitionError(f"the lidar's focal points are {lidar.upstream_distance:g} m upstream of the "
                                         "hub on average: a preview needs them upstream (negative FocalDistanceX).")
        return cls(distance=lidar.upstream_distance, n_beams=lidar.n_beams, **changes)

    def samples(self, dt: float) -> int:
        """Moving-average length at the NMPC sample time ``dt`` [s]."""
        return int(min(max(round(self.window / dt), 1), MAX_WINDOW))


class LidarPreview:
    """Stage winds from lidar measurements and the estimate (module docstring).

    Parameters
    ----------
    settings : PreviewSettings
    dt : float
        NMPC sample time [s].
    horizon : int
        NMPC stages N.
    wind_range : tuple of float
        Clip of the stage winds [m/s].
    """

    def __init__(self, settings: PreviewSettings, dt: float, horizon: int, wind_range: tuple) -> None:
        self.s, self.dt, self.n = settings, float(dt), int(horizon)
        self.lo, self.hi = (float(v) for v in wind_range)
        self.m = settings.samples(self.dt)
        self.raw = np.zeros(self.m)
        self.arrival, self.value = np.zeros(CAPACITY), np.zeros(CAPACITY)
        self.count = 0          # samples pushed (ring position = count % CAPACITY)
        self.ubar = 0.0

    def push(self, t: float, speeds) -> None:
        """One NMPC sample's beam speeds [m/s] at time ``t`` [s]."""
        s = [float(v) for v in np.asarray(speeds, dtype=float).reshape(-1) if math.isfinite(v) and v > 0.0]
        if not s:
            return
        mean = 0.0
        for v in s:                              # the C loop's order of summation
            mean += v
        mean /= len(s)
        k = self.count
        self.ubar = mean if k == 0 else self.ubar + (mean - self.ubar) * (self.dt / self.s.advection_time)
        self.raw[k % self.m] = mean
        used = min(k + 1, self.m)
        avg = 0.0
        for i in range(used):
            avg += self.raw[(k - i) % self.m]
        avg /= used
        a = t + self.s.distance / max(self.ubar, 1.0) - 0.5 * (self.m - 1) * self.dt
        if k > 0:
            a = max(a, self.arrival[(k - 1) % CAPACITY] + 1e-9)
        self.arrival[k % CAPACITY], self.value[k % CAPACITY] = a, avg
        self.count = k + 1

    def at(self, tau: float) -> float:
        """The lidar's rotor wind at time ``tau`` [s] (requires a sample)."""
        k = self.count
        first = max(k - CAPACITY, 0)
        newest = (k - 1) % CAPACITY
        if tau >= self.arrival[newest]:
            return float(self.value[newest])
        j = k - 1
        while j > first and self.arrival[(j - 1) % CAPACITY] > tau:
            j -= 1
        if j == first:
            return float(self.value[first % CAPACITY])
        i0, i1 = (j - 1) % CAPACITY, j % CAPACITY
        f = (tau - self.arrival[i0]) / (self.arrival[i1] - self.arrival[i0])
        return float(self.value[i0] + f * (self.value[i1] - self.value[i0]))

    def horizon(self, t: float, estimate: float) -> np.ndarray:
        """Stage winds k = 0..N [m/s] at time ``t`` [s] from the estimator's wind ``estimate`` [m/s]."""
        out = np.empty(self.n + 1)
        if self.count == 0:
            out[:] = min(max(estimate, self.lo), self.hi)
            return out
        now = self.at(t)
        for k in range(self.n + 1):
            out[k] = min(max(estimate + (self.at(t + k * self.dt) - now), self.lo), self.hi)
        return out


#: The same preview in C (the exported library, :mod:`.discon_nmpc`): ``PV_ON`` 0 compiles nothing. Reads the
#: extended swap records 129 (array size), 2001 (sensor type, must be 1), 2002 (beams) and 2005.. (speeds). The focal
#: distance ``pv_dist`` and the advection filter's ``pv_tadv`` are run-time settings (:mod:`.runtime_settings`).
PREVIEW_C = r"""
/* ---- the lidar preview (mbsym.wind.mpc.lidar_preview: the same arithmetic in Python) ---- */
#define PV_ON {on}
#if PV_ON
#define PV_CAP {capacity}
#define PV_M {m}
#define PV_NB {n_beams}
#define PV_N {horizon}
#define PV_DT {dt!r}
static double pv_raw[PV_M], pv_a[PV_CAP], pv_v[PV_CAP], pv_ubar, windv[PV_N + 1];
static long pv_count;
static int pv_missing;

static void pv_reset(void) {{ pv_count = 0; pv_ubar = 0.0; pv_missing = 0; }}

/* One NMPC sample's beam speeds; returns 1 when the records hold no single-point lidar of PV_NB beams. */
static int pv_push(const float *swap, double t)
{{
    double s, mean = 0.0, avg = 0.0, a;
    long k = pv_count, i;
    int n = 0, b;
    long used;
    if ((double)swap[128] < 2004.0 + PV_NB || swap[2000] != 1.0f || (int)swap[2001] != PV_NB) return 1;
    for (b = 0; b < PV_NB; ++b) {{
        s = (double)swap[2004 + b];
        if (isfinite(s) && s > 0.0) {{ mean += s; ++n; }}
    }}
    if (n == 0) return 0;
    mean /= n;
    pv_ubar = k == 0 ? mean : pv_ubar + (mean - pv_ubar) * (PV_DT / pv_tadv);
    pv_raw[k % PV_M] = mean;
    used = k + 1 < PV_M ? k + 1 : PV_M;
    for (i = 0; i < used; ++i) avg += pv_raw[(k - i) % PV_M];
    avg /= used;
    a = t + pv_dist / (pv_ubar > 1.0 ? pv_ubar : 1.0) - 0.5 * (PV_M - 1) * PV_DT;
    if (k > 0 && a < pv_a[(k - 1) % PV_CAP] + 1e-9) a = pv_a[(k - 1) % PV_CAP] + 1e-9;
    pv_a[k % PV_CAP] = a;
    pv_v[k % PV_CAP] = avg;
    pv_count = k + 1;
    return 0;
}}

static double pv_at(double tau)
{{
    long k = pv_count, first = pv_count > PV_CAP ? pv_count - PV_CAP : 0, j = pv_count - 1, i0, i1;
    if (tau >= pv_a[(k - 1) % PV_CAP]) return pv_v[(k - 1) % PV_CAP];
    while (j > first && pv_a[(j - 1) % PV_CAP] > tau) --j;
    if (j == first) return pv_v[first % PV_CAP];
    i0 = (j - 1) % PV_CAP; i1 = j % PV_CAP;
    return pv_v[i0] + (tau - pv_a[i0]) / (pv_a[i1] - pv_a[i0]) * (pv_v[i1] - pv_v[i0]);
}}

/* The stage winds windv[0..N] from the estimate: the lidar's change from now to each stage. */
static void pv_horizon(double t, double est)
{{
    double now;
    int k;
    if (pv_count == 0) {{
        for (k = 0; k <= PV_N; ++k) windv[k] = est < WIND_LO ? WIND_LO : (est > WIND_HI ? WIND_HI : est);
        return;
    }}
    now = pv_at(t);
    for (k = 0; k <= PV_N; ++k) {{
        double v = est + (pv_at(t + k * PV_DT) - now);
        windv[k] = v < WIND_LO ? WIND_LO : (v > WIND_HI ? WIND_HI : v);
    }}
}}
#endif
"""


def preview_c(settings: PreviewSettings | None, dt: float, horizon: int) -> str:
    """:data:`PREVIEW_C` for ``settings`` at the NMPC sample time ``dt`` [s] and ``horizon`` stages."""
    if settings is None:
        return "\n#define PV_ON 0\n"
    return PREVIEW_C.format(on=1, capacity=CAPACITY, m=settings.samples(dt), n_beams=settings.n_beams,
                            horizon=int(horizon), dt=float(dt))
