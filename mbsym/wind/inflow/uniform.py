"""Steady and uniform-file wind over space, as OpenFAST v5 InflowWind evaluates it (WindType 1 and 2).

InflowWind's uniform field (``IfW_FlowField.f90``, ``UniformField_GetVel``): at time ``t`` the eight
columns of the file (:data:`~mbsym.wind.inflow.files.UNIFORM_COLUMNS`) are interpolated linearly in time
(or, with ``VelInterpCubic = True``, cubically: :mod:`mbsym.wind.inflow.cubic`)
(held beyond the ends; the direction first unwrapped so that consecutive rows differ by less than 180°),
then at a point ``(x, y, z)`` in wind axes (ground axes turned by ``PropagationDir``/``VFlowAng`` about
``(0, 0, RefHt)`` exactly as for full fields, :func:`~mbsym.wind.inflow.field.rotation_to_wind`)::

    V1 = HorSpd ((z/H)^VerShr + (HorShr (y cos δ + x sin δ) + LnVShr (z - H)) / L) + GstSpd
    (u, v, w) = (Vh cos δ, -Vh sin δ, sin(Upflow) V1 + cos(Upflow) VerSpd),
    Vh = cos(Upflow) V1 - sin(Upflow) VerSpd

with ``δ = WndDir``, ``H`` the reference height (``RefHt`` or ``RefHt_Uni``) and ``L`` the reference
length (``RefLength``; 1 m for steady wind, where no linear shear exists). A point at ``z <= 0`` (wind
axes) gets zero velocity in InflowWind.

**No time shift**: InflowWind evaluates a uniform field at the same instant everywhere (unlike full
fields, there is no Taylor advection): the columns at ``t`` hold for every ``x``; ``x`` enters only the
horizontal shear through ``sin δ``. So :func:`uniform_velocity_expr` with the instantaneous columns is
exact, and :meth:`UniformFieldWind.columns_at` gives those columns (e.g. as a model's inputs).

Steady wind (``WindType = 1``) is the one-row case: ``HorSpd = HWindSpeed``, ``VerShr = PLexp``, all
else zero, ``L = 1``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, WindFieldDomainError, WindInputError
from .field import rotation_to_wind
from .files import UNIFORM_COLUMNS, UniformWind

__all__ = ["UniformFieldWind", "uniform_velocity_expr", "COLUMN_NAMES", "POWER_LAW_MIN_HEIGHT"]

#: Column names of :meth:`UniformFieldWind.columns_at` and :func:`uniform_velocity_expr` (SI, angles in rad).
COLUMN_NAMES = tuple(v for v in UNIFORM_COLUMNS.values() if v != "time")
#: Height [m] below which :func:`uniform_velocity_expr` holds the power law at its value there (SX guard).
POWER_LAW_MIN_HEIGHT = 1.0e-3


def _unwrap_like_inflowwind(direction: np.ndarray, source: str = "") -> np.ndarray:
    """InflowWind's unwrapping of ``WndDir``: shift each row by 2π until it is within π of the previous
    (at most 100 tries, as ``IfW_UniformWind_Init``)."""
    a = np.array(direction, dtype=float)
    for i in range(1, a.size):
        for _ in range(100):
            d = a[i] - a[i - 1]
            if abs(d) < math.pi:
                break
            a[i] -= math.copysign(2.0 * math.pi, d)
        else:
            raise WindInputError(f"uniform wind {source}: the wind direction of row {i + 1} cannot be brought within "
                                 "180 deg of the previous row (InflowWind stops here). Fix the WndDir column.")
    return a


@dataclass(frozen=True, eq=False)
class UniformFieldWind:
    """Steady or uniform-file wind as a field over space (see the module docstring).

    Parameters
    ----------
    table : UniformWind
        The columns (one row for steady wind).
    reference_height : float
        ``H`` [m] (``RefHt`` / ``RefHt_Uni``); also the centre of the box rotation.
    reference_length : float
        ``L`` [m] of the linear shears (``RefLength``; 1 for steady wind).
    propagation_direction, upflow_angle : float
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad] (box rotation).
    source : str
        Where it came from.
    cubic : bool
        InflowWind's ``VelInterpCubic``: the columns are cubic in time between rows (a clamped spline's
        slopes, :mod:`mbsym.wind.inflow.cubic`) instead of linear.

    Examples
    --------
    >>> from mbsym.wind.inflow import UniformFieldWind
    >>> w = UniformFieldWind.steady(10.0, reference_height=90.0, power_law_exponent=0.2)
    >>> round(float(w.velocity(0.0, [0.0, 0.0, 45.0])[0]), 6)
    8.705506
    """

    table: UniformWind
    reference_height: float
    reference_length: float = 1.0
    propagation_direction: float = 0.0
    upflow_angle: float = 0.0
    source: str = ""
    cubic: bool = False

    def __post_init__(self) -> None:
        if not isinstance(self.table, UniformWind):
            raise TypeError(f"table must be a UniformWind; got {type(self.table).__name__}.")
        for name, positive in (("reference_height", True), ("reference_length", True),
                               ("propagation_direction", False), ("upflow_angle", False)):
            value = float(getattr(self, name))
            if not math.isfinite(value) or (positive and value <= 0.0):
                raise WindInputError(f"UniformFieldWind: {name} must be {'positive and ' if positive else ''}finite; "
                                     f"got {getattr(self, name)!r}.")
            object.__setattr__(self, name, value)
        object.__setattr__(self, "_direction", _unwrap_like_inflowwind(self.table.direction, self.source))
        object.__setattr__(self, "cubic", bool(self.cubic))
        if self.cubic:                                 # IfW_UniformField_CalcAccel: the slopes, once
            from .cubic import uniform_slopes

            cols = np.stack([self._column(name) for name in COLUMN_NAMES], axis=1)
            object.__setattr__(self, "_slopes", uniform_slopes(self.table.time, cols))

    def _column(self, name: str) -> np.ndarray:
        return self._direction if name == "direction" else getattr(self.table, name)

    @classmethod
    def steady(cls, speed: float, *, reference_height: float, power_law_exponent: float = 0.0,
               propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> UniformFieldWind:
        """Steady wind (``WindType = 1``): ``HWindSpeed`` [m/s], ``RefHt`` [m], ``PLexp`` [-]; ``L = 1`` m."""
        table = UniformWind([0.0], [speed], power_law_exponent=[power_law_exponent], path="steady wind")
        return cls(table, reference_height, 1.0, propagation_direction, upflow_angle, source="steady wind")

    @property
    def rotated(self) -> bool:
        """Whether ``PropagationDir`` or ``VFlowAng`` is non-zero."""
        return self.propagation_direction != 0.0 or self.upflow_angle != 0.0

    def columns_at(self, t) -> dict[str, np.ndarray | float]:
        """The columns at time(s) ``t`` [s] (InflowWind's linear interpolation, or cubic with ``cubic``; held
        beyond the ends).

        Returns a dict with keys :data:`COLUMN_NAMES` (angles in rad), floats for a scalar ``t``.
        """
        times = np.asarray(t, dtype=float)
        if not np.all(np.isfinite(times)):
            raise WindInputError("UniformFieldWind.columns_at: times must be finite.")
        out = {}
        for k, name in enumerate(COLUMN_NAMES):
            values = self._column(name)
            if self.cubic:
                from .cubic import hermite_value

                v = hermite_value(self.table.time, values, self._slopes[:, k], times)
            else:
                v = np.interp(times, self.table.time, values)           # = InflowWind's rule, ends held
            out[name] = float(v) if v.ndim == 0 else v
        return out

    def hub_signal(self, *, allow_unmodelled: bool = False):
        """The longitudinal wind at the hub, ``(HorSpd + GstSpd) cos(Upflow) cos(WndDir)`` of the interpolated
        columns, as a :class:`~mbsym.wind.inflow.WindSignal` [m/s] of time [s]: the file's
        :meth:`~mbsym.wind.inflow.UniformWind.signal` (a linear table) or, with ``cubic``, a
        :class:`~mbsym.wind.inflow.cubic_signal.CubicUniformHubWind`. ``allow_unmodelled`` as there."""
        linear = self.table.signal(allow_unmodelled=allow_unmodelled)      # checks the unmodelled columns
        if not self.cubic:
            return linear
        from .cubic_signal import CubicUniformHubWind

        return CubicUniformHubWind(self)

    def velocity(self, t, points, *, below_ground: str = "error") -> np.ndarray:
        """Wind velocity ``(u, v, w)`` [m/s] in ground axes at ``points`` (N, 3) [m] and time(s) ``t`` [s].

        Returns ``(N, 3)`` for a scalar ``t`` (``(3,)`` for one point), ``(M, N, 3)`` for M times.
        ``below_ground``: ``"error"`` (default) raises :class:`~mbsym.exceptions.WindFieldDomainError` for a
        point at ``z <= 0`` in wind axes (the power law is undefined there); ``"zero"`` returns zero velocity
        there, as InflowWind does.
        """
        if below_ground not in ("error", "zero"):
            raise WindInputError(f"below_ground must be 'error' or 'zero'; got {below_ground!r}.")
        pts = np.asarray(points, dtype=float)
        one = pts.ndim == 1
        pts = pts.reshape(1, -1) if one else pts
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise DimensionError(f"points has shape {np.shape(points)}; expected (N, 3) positions (x, y, z) [m].")
        times = np.asarray(t, dtype=float)
        if times.ndim > 1 or not (np.all(np.isfinite(pts)) and np.all(np.isfinite(times))):
            raise WindInputError("UniformFieldWind.velocity: t must be a finite scalar or 1-D array and points finite.")
        rot = rotation_to_wind(self.propagation_direction, self.upflow_angle)
        ref = np.array([0.0, 0.0, self.reference_height])
        pw = (pts - ref) @ rot.T + ref if self.rotated else pts
        low = pw[:, 2] <= 0.0
        if np.any(low) and below_ground == "error":
            k = int(np.flatnonzero(low)[0])
            raise WindFieldDomainError(f"uniform wind {self.source}: point ({', '.join(f'{c:g}' for c in pts[k])}) m "
                                       "is at or below the ground (z <= 0 in wind axes): the power-law profile is "
                                       "undefined there (InflowWind returns zero velocity; pass below_ground='zero').")
        cols = self.columns_at(np.atleast_1d(times))
        c = {k: np.asarray(v)[:, None] for k, v in cols.items()}          # (M, 1) against points (1, N)
        x, y, z = pw[:, 0][None], pw[:, 1][None], np.where(low, self.reference_height, pw[:, 2])[None]
        v = _uniform_numpy(c, x, y, z, self.reference_height, self.reference_length)
        v[:, low, :] = 0.0
        if self.rotated:
            v = v @ rot
        if times.ndim == 0:
            return v[0, 0] if one else v[0]
        return v[:, 0] if one else v

    def __repr__(self) -> str:
        return (f"UniformFieldWind({self.table.time.size} rows, RefHt={self.reference_height:g} m, "
                f"RefLength={self.reference_length:g} m, {'cubic' if self.cubic else 'linear'} in time, "
                f"source={self.source!r})")


def _uniform_numpy(c, x, y, z, height, length):
    cd, sd = np.cos(c["direction"]), np.sin(c["direction"])
    cu, su = np.cos(c["upflow"]), np.sin(c["upflow"])
    v1 = c["speed"] * ((z / height) ** c["power_law_exponent"]
                       + (c["horizontal_shear"] * (y * cd + x * sd)
                          + c["linear_vertical_shear"] * (z - height)) / length) + c["gust_speed"]
    vh = cu * v1 - su * c["vertical_speed"]
    vz = su * v1 + cu * c["vertical_speed"]
    return np.stack(np.broadcast_arrays(vh * cd, -vh * sd, vz), axis=-1)


def uniform_velocity_expr(columns: dict, points, *, ref_height: float, ref_length: float,
                          propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> ca.SX:
    """InflowWind's uniform-wind velocity as a CasADi SX expression (3 x N, ground axes) [m/s].

    Parameters
    ----------
    columns : dict
        The *instantaneous* columns (no time shift exists for uniform wind, see the module docstring):
        ``"speed"`` (HorSpd, m/s), ``"direction"`` (WndDir, rad), ``"vertical_speed"`` (m/s),
        ``"horizontal_shear"``, ``"power_law_exponent"``, ``"linear_vertical_shear"`` (-),
        ``"gust_speed"`` (m/s), ``"upflow"`` (rad); SX or float each. Missing keys are 0, unknown keys
        raise.
    points : SX, MX-free array 3 x N
        Positions in ground axes [m].
    ref_height, ref_length : float, keyword-only
        ``H`` and ``L`` [m].
    propagation_direction, upflow_angle : float, keyword-only
        InflowWind's box rotation [rad] (``PropagationDir``, ``VFlowAng``).

    Returns
    -------
    casadi.SX
        3 x N velocities. Smooth in the columns and the points for ``z >`` :data:`POWER_LAW_MIN_HEIGHT`;
        below it the height in the power law is held at that value (``fmax``), so the expression stays finite
        (InflowWind returns zero velocity at ``z <= 0``).

    Examples
    --------
    >>> import casadi as ca
    >>> u = ca.SX.sym("u")
    >>> v = uniform_velocity_expr({"speed": u}, ca.DM([[0.0], [0.0], [90.0]]), ref_height=90.0, ref_length=126.0)
    >>> [abs(float(c)) for c in ca.Function("f", [u], [v])(12.0).full().ravel()]
    [12.0, 0.0, 0.0]
    """
    unknown = set(columns) - set(COLUMN_NAMES)
    if unknown:
        raise WindInputError(f"uniform_velocity_expr: unknown column(s) {sorted(unknown)}; expected {list(COLUMN_NAMES)}.")
    for name, value in (("ref_height", ref_height), ("ref_length", ref_length)):
        if not (math.isfinite(float(value)) and float(value) > 0.0):
            raise WindInputError(f"uniform_velocity_expr: {name} must be positive and finite; got {value!r}.")
    c = {k: ca.SX(columns.get(k, 0.0)) for k in COLUMN_NAMES}
    for k, v in c.items():
        if v.shape != (1, 1):
            raise DimensionError(f"uniform_velocity_expr: column {k!r} must be a scalar; got shape {v.shape}.")
    p = ca.SX(points)
    if p.shape[0] != 3:
        raise DimensionError(f"uniform_velocity_expr: points must be 3 x N; got {p.shape}.")
    rotated = propagation_direction != 0.0 or upflow_angle != 0.0
    rot = ca.DM(rotation_to_wind(propagation_direction, upflow_angle))
    ref = ca.DM([0.0, 0.0, ref_height])
    if rotated:
        p = ca.mtimes(rot, p - ca.repmat(ref, 1, p.shape[1])) + ca.repmat(ref, 1, p.shape[1])
    x, y, z = p[0, :], p[1, :], p[2, :]
    zp = ca.fmax(z, POWER_LAW_MIN_HEIGHT)
    cd, sd = ca.cos(c["direction"]), ca.sin(c["direction"])
    cu, su = ca.cos(c["upflow"]), ca.sin(c["upflow"])
    v1 = c["speed"] * ((zp / ref_height) ** c["power_law_exponent"]
                       + (c["horizontal_shear"] * (y * cd + x * sd)
                          + c["linear_vertical_shear"] * (z - ref_height)) / ref_length) + c["gust_speed"]
    vh = cu * v1 - su * c["vertical_speed"]
    vz = su * v1 + cu * c["vertical_speed"]
    v = ca.vertcat(vh * cd, -vh * sd, vz)
    return ca.mtimes(rot.T, v) if rotated else v
