"""Full-field wind (TurbSim/Bladed grids) evaluated exactly as OpenFAST v5 InflowWind does.

A :class:`FullFieldWind` is a grid of velocities ``(u, v, w)`` [m/s] over ``y`` (lateral) and ``z``
(height) at ``n_t`` times ``dt`` apart, frozen and carried downwind at the mean speed ``URef``
(Taylor's hypothesis). :meth:`FullFieldWind.velocity` reproduces ``IfW_FlowField_GetVelAcc`` for a
``Grid3D`` field with linear interpolation (``VelInterpCubic = False``; OpenFAST v5.0.0,
``modules/inflowwind/src/IfW_FlowField.f90``):

1. *Rotation* (``PropagationDir`` = δ, ``VFlowAng`` = φ, both 0 unless set): a point ``p`` in
   ground axes is moved into the wind frame about the reference point ``r = (0, 0, RefHt)``,
   ``p' = M (p - r) + r`` with ``M = R_y(φ)ᵀ R_z(δ)ᵀ`` (:func:`rotation_to_wind`); the velocity found
   there is turned back, ``v = Mᵀ v'``.
2. *Ground*: a point with ``z' <= 0`` gets zero velocity (no error).
3. *Time (Taylor advection)*: the grid time of a point is ``τ = t + (x0 - x') / URef`` with
   ``x0 = (NY - 1) dy / 2`` (half the grid width) for a non-periodic file (ID 7) and ``x0 = 0`` for a
   periodic one (ID 8): at ``t = 0`` the slice of time 0 sits half a grid width downwind of the
   tower, so a point upwind (``x' < 0``) sees later slices. Periodic fields wrap ``τ`` modulo
   ``n_t dt``. A non-periodic field has data for ``τ`` in ``[0, (n_t - 1) dt]`` (InflowWind's
   ``TotalTime``; at the hub, ``t`` in ``[-x0/URef, TotalTime - x0/URef]``), but InflowWind accepts
   ``τ`` up to ``n_t dt``: in that last step it holds the last slice while the fraction beyond it is
   at most ``(1 + 1e-3)/2`` and beyond that interpolates between the last two slices at that
   fraction (its ``GetBoundsT``; reproduced as is). ``τ < 0`` or ``τ >= n_t dt`` is an error.
4. *Space*: bilinear in ``(y', z')`` inside the grid (``y`` in ``[-(NY-1)dy/2, (NY-1)dy/2]``, ``z`` in
   ``[GridBase, GridBase + (NZ-1) dz]``), accepting points within ``1e-3`` of a cell outside (InflowWind's
   ``GridTol``, in cell units), and linear in ``τ``. Below the grid: with tower points (TurbSim ``NTwr > 0``)
   linear in ``z'`` along the tower column at ``y = 0`` whatever ``y'`` is, from tower point ``k`` at
   ``GridBase - k dz`` down to zero velocity at the ground (``IfW_FlowField.f90``, ``GetCellInTower``
   without extrapolation); for Bladed files without a tower file, linear from the bottom grid row to zero at
   the ground (``InterpTower``); otherwise an error. Above the grid or beside it (outside ``y``) is an error.

*Cubic in time* (``VelInterpCubic = True``, ``cubic=True``): the same cell and weights, the two times joined
by InflowWind's cubic Hermite step with zero slopes (what OpenFAST v5.0.0 computes; see
:mod:`mbsym.wind.inflow.cubic`).

Where InflowWind stops with an error, :meth:`~FullFieldWind.velocity` raises
:class:`~mbsym.exceptions.WindFieldDomainError` naming the point, the time and the ranges. InflowWind's
extrapolation outside the grid (``BoxExceedAllow``) is used only for lidar and OLAF points and is not
modelled here.

Arithmetic: the velocities are float32 as in InflowWind (``SiKi``); positions, weights and sums are float64
(the OpenFAST binary is built with ``DOUBLE_PRECISION``), so results agree with InflowWind to rounding.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING
import math
from dataclasses import dataclass, replace

import numpy as np

if TYPE_CHECKING:                      # casadi is imported where the Function is made
    import casadi as ca

from ...exceptions import DimensionError, WindFieldDomainError, WindInputError
from .profile import MeanProfile

__all__ = ["FullFieldWind", "rotation_to_wind", "GRID_TOLERANCE"]

#: InflowWind's ``GridTol``: points within this fraction of a cell outside the grid use the edge cell.
GRID_TOLERANCE = 1.0e-3
_OK, _TIME, _BELOW, _ABOVE, _BESIDE = 0, 1, 2, 3, 4


def rotation_to_wind(propagation_direction: float, upflow_angle: float) -> np.ndarray:
    """InflowWind's ``RotToWind`` (ground axes → wind axes) for ``PropagationDir`` δ and ``VFlowAng`` φ [rad].

    ``M = R_y(φ)ᵀ R_z(δ)ᵀ`` with ``R_z(δ)``, ``R_y(φ)`` the usual right-handed rotations; the file's
    x axis points, in ground axes, along ``Mᵀ e_x = (cos φ cos δ, -cos φ sin δ, sin φ)``: a positive
    ``PropagationDir`` turns the wind towards -y (meteorological sense), a positive ``VFlowAng`` tilts it
    upwards (InflowWind_Subs.f90, ``InflowWind_SetParameters``).
    """
    a, b = -float(propagation_direction), -float(upflow_angle)
    return np.array([[math.cos(b) * math.cos(a), math.cos(b) * math.sin(a), -math.sin(b)],
                     [-math.sin(a), math.cos(a), 0.0],
                     [math.sin(b) * math.cos(a), math.sin(b) * math.sin(a), math.cos(b)]])


def _positive(value, name: str) -> float:
    v = float(value)
    if not (math.isfinite(v) and v > 0.0):
        raise WindInputError(f"FullFieldWind: {name} must be a positive finite number; got {value!r}.")
    return v


def _finite(value, name: str) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise WindInputError(f"FullFieldWind: {name} must be finite; got {value!r}.")
    return v


def _velocity_array(a, name: str, ndim: int) -> np.ndarray:
    arr = np.asarray(a)
    if arr.dtype != np.float32:
        arr = arr.astype(np.float32)              # float32 storage, as InflowWind (never float64)
    arr = np.ascontiguousarray(arr)
    if arr.ndim != ndim or arr.shape[-1] != 3:
        raise DimensionError(f"FullFieldWind: {name} has shape {arr.shape}; expected {ndim} axes, the last of "
                             "length 3 (u, v, w).")
    step = max(1, (1 << 22) // max(1, arr[0].size))      # check in blocks: no full-size temporary
    if not all(np.isfinite(arr[i:i + step]).all() for i in range(0, arr.shape[0], step)):
        raise WindInputError(f"FullFieldWind: {name} must be finite.")
    arr = arr.view()                              # a read-only view: the caller's array stays writeable
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class FullFieldWind:
    """A full-field (grid) wind, evaluated as InflowWind does (see the module docstring).

    Parameters
    ----------
    grid : array (n_t, n_z, n_y, 3)
        Velocities ``(u, v, w)`` [m/s] in wind axes; stored as float32 (converted if needed, never as
        float64). ``grid[i, k, j]`` is at time ``i dt``, height ``z[k]``, lateral position ``y[j]``.
    dy, dz : float
        Grid spacing [m].
    dt : float
        Time step [s].
    mean_speed : float
        ``URef``, the advection speed of Taylor's hypothesis [m/s].
    reference_height : float
        Height [m] of the reference point (hub height of the file); rotations turn about ``(0, 0, it)``.
    grid_bottom : float
        Height of the lowest grid row [m].
    tower : array (n_t, n_tower, 3), optional
        Velocities at the tower points ``z = grid_bottom - k dz`` (``k = 0 .. n_tower - 1``) [m/s].
    periodic : bool
        Whether the field repeats with period ``n_t dt`` (TurbSim ID 8).
    propagation_direction, upflow_angle : float
        InflowWind's ``PropagationDir`` and ``VFlowAng`` [rad].
    interpolate_to_ground : bool
        Below the grid, interpolate from the bottom row to zero at the ground (InflowWind's
        ``InterpTower``, set for HAWC and native Bladed files); TurbSim files: False.
    source, description : str
        Where it came from; the file's description text.
    mean_profile : MeanProfile, optional
        The mean wind added to ``u`` after interpolation at the point's wind-frame height (InflowWind's
        ``AddMeanAfterInterp``, HAWC and native Bladed boxes: :class:`~mbsym.wind.inflow.profile.MeanProfile`);
        None: the grid holds the whole velocity (TurbSim).
    x_offset : float, optional
        InflowWind's ``InitXPosition`` [m] when a file sets it (HAWC and native Bladed ``XOffset``); None: 0
        for periodic fields, half the grid width otherwise.
    cubic : bool
        InflowWind's ``VelInterpCubic``: cubic in time between the slices (zero slopes, as OpenFAST v5.0.0;
        :mod:`mbsym.wind.inflow.cubic`) instead of linear.
    """

    grid: np.ndarray
    dy: float
    dz: float
    dt: float
    mean_speed: float
    reference_height: float
    grid_bottom: float
    tower: np.ndarray | None = None
    periodic: bool = False
    propagation_direction: float = 0.0
    upflow_angle: float = 0.0
    interpolate_to_ground: bool = False
    source: str = ""
    description: str = ""
    mean_profile: MeanProfile | None = None
    x_offset: float | None = None
    cubic: bool = False

    def __post_init__(self) -> None:
        grid = _velocity_array(self.grid, "grid", 4)
        if min(grid.shape[:3]) < 2:
            raise DimensionError(f"FullFieldWind: grid has shape {grid.shape}; expected at least 2 times, 2 heights "
                                 "and 2 lateral points.")
        object.__setattr__(self, "grid", grid)
        if self.tower is not None:
            tower = _velocity_array(self.tower, "tower", 3)
            if tower.shape[0] != grid.shape[0]:
                raise DimensionError(f"FullFieldWind: tower has {tower.shape[0]} times; the grid has {grid.shape[0]}.")
            object.__setattr__(self, "tower", tower if tower.shape[1] > 0 else None)
        for name in ("dy", "dz", "dt", "mean_speed"):
            object.__setattr__(self, name, _positive(getattr(self, name), name))
        for name in ("reference_height", "grid_bottom", "propagation_direction", "upflow_angle"):
            object.__setattr__(self, name, _finite(getattr(self, name), name))
        object.__setattr__(self, "periodic", bool(self.periodic))
        object.__setattr__(self, "interpolate_to_ground", bool(self.interpolate_to_ground))
        object.__setattr__(self, "cubic", bool(self.cubic))
        if self.interpolate_to_ground and self.tower is not None:
            raise WindInputError("FullFieldWind: interpolate_to_ground is for fields without tower points.")
        if self.mean_profile is not None and not isinstance(self.mean_profile, MeanProfile):
            raise WindInputError(f"FullFieldWind: mean_profile must be a MeanProfile or None; got "
                                 f"{type(self.mean_profile).__name__}.")
        if self.x_offset is not None:
            object.__setattr__(self, "x_offset", _finite(self.x_offset, "x_offset"))

    # ------------------------------------------------------------------ geometry (InflowWind's derived values)
    @property
    def n_t(self) -> int:
        """Number of time steps."""
        return self.grid.shape[0]

    @property
    def n_z(self) -> int:
        """Number of grid heights."""
        return self.grid.shape[1]

    @property
    def n_y(self) -> int:
        """Number of lateral grid points."""
        return self.grid.shape[2]

    @property
    def n_tower(self) -> int:
        """Number of tower points (0 without)."""
        return 0 if self.tower is None else self.tower.shape[1]

    @property
    def half_width(self) -> float:
        """``YHWid = (NY - 1) dy / 2`` [m], as InflowWind computes it (``0.5 (NY - 1) / (1/dy)``)."""
        return 0.5 * (self.n_y - 1) / (1.0 / self.dy)

    @property
    def y(self) -> np.ndarray:
        """Lateral grid positions [m] (centred on the tower)."""
        return -self.half_width + self.dy * np.arange(self.n_y)

    @property
    def z(self) -> np.ndarray:
        """Grid heights [m], bottom first."""
        return self.grid_bottom + self.dz * np.arange(self.n_z)

    @property
    def tower_z(self) -> np.ndarray:
        """Heights of the tower points [m] (top first: the first is at the grid bottom)."""
        return self.grid_bottom - self.dz * np.arange(self.n_tower)

    @property
    def initial_x(self) -> float:
        """InflowWind's ``InitXPosition`` [m]: ``x_offset`` if set, else 0 for periodic files and half the grid
        width otherwise."""
        if self.x_offset is not None:
            return self.x_offset
        return 0.0 if self.periodic else self.half_width

    @property
    def total_time(self) -> float:
        """InflowWind's ``TotalTime`` [s]: ``n_t dt`` (periodic) or ``(n_t - 1) dt``."""
        return (self.n_t if self.periodic else self.n_t - 1) * self.dt

    @property
    def time_range(self) -> tuple[float, float]:
        """Times [s] at ``x = 0`` covered by data (InflowWind's summary ``TRange``); periodic: one period."""
        shift = self.initial_x / self.mean_speed
        return -shift, self.total_time - shift

    @property
    def rotated(self) -> bool:
        """Whether ``PropagationDir`` or ``VFlowAng`` is non-zero (InflowWind's ``RotateWindBox``)."""
        return self.propagation_direction != 0.0 or self.upflow_angle != 0.0

    @property
    def nbytes(self) -> int:
        """Memory held by the velocities [bytes]."""
        return self.grid.nbytes + (0 if self.tower is None else self.tower.nbytes)

    def with_rotation(self, propagation_direction: float = 0.0, upflow_angle: float = 0.0) -> FullFieldWind:
        """The same field (data shared, not copied) with other ``PropagationDir``/``VFlowAng`` [rad]."""
        return self._sharing(replace(self, propagation_direction=propagation_direction, upflow_angle=upflow_angle))

    def with_cubic(self, cubic: bool = True) -> FullFieldWind:
        """The same field (data shared) interpolated cubically (``VelInterpCubic = True``) or linearly in time."""
        return self._sharing(replace(self, cubic=cubic))

    def _sharing(self, new: FullFieldWind) -> FullFieldWind:
        if "data_hash" in self.__dict__:                  # same data: keep the (0.2 s) hash
            new.__dict__["data_hash"] = self.__dict__["data_hash"]
        return new

    # ------------------------------------------------------------------ evaluation
    def velocity(self, t, points) -> np.ndarray:
        """Wind velocity ``(u, v, w)`` [m/s] in ground axes at ``points`` [m] and time(s) ``t`` [s].

        Parameters
        ----------
        t : float or array (M,)
            Time(s) [s].
        points : array (N, 3) or (3,)
            Positions ``(x, y, z)`` in ground axes [m] (x downwind, z up from the ground).

        Returns
        -------
        ndarray
            ``(N, 3)`` for a scalar ``t`` (``(3,)`` for one point), ``(M, N, 3)`` for M times.

        Raises
        ------
        WindFieldDomainError
            Where InflowWind stops with an error (the first such point, with its time and the ranges).
        DimensionError, WindInputError
            Points not of shape (N, 3), non-finite times or positions.

        Examples
        --------
        >>> import numpy as np
        >>> from mbsym.wind.inflow import FullFieldWind
        >>> g = np.ones((4, 3, 3, 3), dtype=np.float32)
        >>> f = FullFieldWind(g, dy=10.0, dz=10.0, dt=1.0, mean_speed=10.0, reference_height=20.0, grid_bottom=10.0)
        >>> f.velocity(0.0, [0.0, 0.0, 20.0]).tolist()
        [1.0, 1.0, 1.0]
        """
        pts = np.asarray(points, dtype=float)
        one_point = pts.ndim == 1
        pts = pts.reshape(1, -1) if one_point else pts
        if pts.ndim != 2 or pts.shape[1] != 3:
            raise DimensionError(f"points has shape {np.shape(points)}; expected (N, 3) positions (x, y, z) [m].")
        times = np.asarray(t, dtype=float)
        if times.ndim > 1:
            raise DimensionError(f"t has shape {times.shape}; expected a scalar or a 1-D array of times [s].")
        if not (np.all(np.isfinite(pts)) and np.all(np.isfinite(times))):
            raise WindInputError("FullFieldWind.velocity: times and positions must be finite.")
        tt = np.repeat(np.atleast_1d(times), pts.shape[0])
        pp = np.tile(pts, (np.atleast_1d(times).size, 1))
        v, code, wind_pos = self._evaluate(tt, pp)
        bad = np.flatnonzero(code)
        if bad.size:
            self._raise(int(bad[0]), tt, pp, wind_pos, int(code[bad[0]]))
        if times.ndim == 0:
            return v[0] if one_point else v
        return v.reshape(times.size, pts.shape[0], 3)[:, 0] if one_point else v.reshape(times.size, pts.shape[0], 3)

    def _evaluate(self, t: np.ndarray, p: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Velocities (K, 3) in ground axes, error codes (K,), wind-frame positions (K, 3)."""
        if self.rotated:
            rot = rotation_to_wind(self.propagation_direction, self.upflow_angle)
            ref = np.array([0.0, 0.0, self.reference_height])
            pw = (p - ref) @ rot.T + ref
        else:
            pw = p
        x, y, z = pw[:, 0], pw[:, 1], pw[:, 2]
        code = np.zeros(t.size, dtype=np.int8)
        it_lo, it_hi, xt = self._bounds_t(t, x, code)
        iz_lo, iz_hi, xz, mode = self._bounds_z(z, code)
        iy_lo, iy_hi, xy = self._bounds_y(y, code, mode)
        v = self._interpolate(mode, (it_lo, it_hi, xt), (iz_lo, iz_hi, xz), (iy_lo, iy_hi, xy))
        if self.mean_profile is not None:                  # InflowWind's AddMeanAfterInterp
            v[:, 0] += self.mean_profile(y, z)
        above_ground = z > 0.0
        v[~above_ground] = 0.0
        code[~above_ground] = _OK
        v[code != _OK] = np.nan
        if self.rotated:
            v = v @ rot                     # Mᵀ v' for each row
        return v, code, pw

    def _bounds_t(self, t, x, code):
        """InflowWind's ``GetBoundsT``: 1-based slice indices and the coordinate in [-1, 1]."""
        nt = self.n_t
        tg = (t + (self.initial_x - x) * (1.0 / self.mean_speed)) * (1.0 / self.dt)
        if self.periodic:
            tg = _modulo(_modulo(tg, float(nt)), float(nt))
        lo = np.floor(tg).astype(np.int64) + 1
        hi = lo + 1
        xt = 2.0 * (tg - np.trunc(tg)) - 1.0
        last = lo == nt
        inside = (lo >= 1) & (hi <= nt)
        if self.periodic:
            hi[last] = 1
        else:
            hold = last & (xt <= GRID_TOLERANCE)
            hi[hold], xt[hold] = lo[hold], -1.0
            stretch = last & ~hold                  # InflowWind's "extrapolate": the last interval again
            lo[stretch], hi[stretch] = nt - 1, nt
        code[~(inside | last)] = _TIME
        if self.cubic:                                  # Grid3DField_GetVelAccCubic with zero slopes
            from .cubic import smooth_step_coordinate

            xt = smooth_step_coordinate(xt)
        return lo, hi, xt

    def _bounds_z(self, z, code):
        """InflowWind's ``GetBoundsZ``: indices, coordinate and mode (0 grid, 1 tower, 2 grid-to-ground)."""
        nz, tol = self.n_z, GRID_TOLERANCE
        zg = (z - self.grid_bottom) * (1.0 / self.dz) + 1.0
        lo = np.floor(zg).astype(np.int64)
        hi = lo + 1
        xz = zg - np.trunc(zg)
        mode = np.zeros(z.size, dtype=np.int8)
        inside = (lo >= 1) & (hi <= nz)
        xz[inside] = 2.0 * xz[inside] - 1.0
        below = lo < 1
        snap = below & (lo == 0) & (xz >= 1.0 - tol)
        lo[snap], hi[snap], xz[snap] = 1, 2, -1.0
        rest = below & ~snap
        if self.interpolate_to_ground:
            mode[rest] = 2
            lo[rest], hi[rest], xz[rest] = 0, 1, 2.0 * (z[rest] / self.grid_bottom) - 1.0
        elif self.n_tower > 0:
            mode[rest] = 1
            k = np.trunc(-(zg[rest] - 1.0)).astype(np.int64) + 1
            end = k >= self.n_tower
            k[end] = self.n_tower
            zr = zg[rest]
            xr = 2.0 * ((2 - k) - zr) - 1.0
            base = self.grid_bottom - (self.n_tower - 1) / (1.0 / self.dz)
            xr[end] = 1.0 - 2.0 * (z[rest][end] / base)
            lo[rest], hi[rest], xz[rest] = k, k + 1, xr
        else:
            code[rest & (code == _OK)] = _BELOW
        above = hi > nz
        snap = above & (hi == nz + 1) & (xz <= tol)
        lo[snap], hi[snap], xz[snap] = nz - 1, nz, 1.0
        code[above & ~snap & (code == _OK)] = _ABOVE
        return lo, hi, xz, mode

    def _bounds_y(self, y, code, mode):
        """InflowWind's ``GetBoundsY`` (not used along the tower)."""
        ny, tol = self.n_y, GRID_TOLERANCE
        yg = (y + self.half_width) * (1.0 / self.dy) + 1.0
        lo = np.floor(yg).astype(np.int64)
        hi = lo + 1
        xy = yg - np.trunc(yg)
        inside = (lo >= 1) & (hi <= ny)
        xy[inside] = 2.0 * xy[inside] - 1.0
        first = (lo == 0) & (xy >= 1.0 - tol)
        lo[first], hi[first], xy[first] = 1, 2, -1.0
        last = (lo == ny) & (xy <= tol)
        lo[last], hi[last], xy[last] = ny - 1, ny, 1.0
        code[~(inside | first | last) & (mode != 1) & (code == _OK)] = _BESIDE
        return lo, hi, xy

    def _interpolate(self, mode, t_b, z_b, y_b) -> np.ndarray:
        """Trilinear (grid) or bilinear (tower: z, t) interpolation, InflowWind's shape functions."""
        (tl, th, xt), (zl, zh, xz), (yl, yh, xy) = t_b, z_b, y_b
        g = self.grid
        tl0, th0 = np.clip(tl - 1, 0, self.n_t - 1), np.clip(th - 1, 0, self.n_t - 1)
        zl0, zh0 = np.clip(zl - 1, 0, self.n_z - 1), np.clip(zh - 1, 0, self.n_z - 1)
        yl0, yh0 = np.clip(yl - 1, 0, self.n_y - 1), np.clip(yh - 1, 0, self.n_y - 1)
        ground_row = (mode == 2)[:, None]              # below the grid, InterpTower: lower row is the ground
        cells = [g[tl0, zl0, yl0], g[tl0, zl0, yh0], g[tl0, zh0, yl0], g[tl0, zh0, yh0],
                 g[th0, zl0, yl0], g[th0, zl0, yh0], g[th0, zh0, yl0], g[th0, zh0, yh0]]
        for k in (0, 1, 4, 5):
            cells[k] = np.where(ground_row, np.float32(0.0), cells[k])
        n_y = ((1.0 - xy), (1.0 + xy))
        n_z = ((1.0 - xz), (1.0 + xz))
        n_t = ((1.0 - xt) / 8.0, (1.0 + xt) / 8.0)
        v = np.zeros((mode.size, 3))
        for k, cell in enumerate(cells):
            w = n_y[k & 1] * n_z[(k >> 1) & 1] * n_t[k >> 2]
            v += cell * w[:, None]
        if self.n_tower > 0 and np.any(mode == 1):
            m = mode == 1
            v[m] = self._tower_interpolate(tl0[m], th0[m], zl[m], zh[m], xz[m], xt[m])
        return v

    def _tower_interpolate(self, tl0, th0, zl, zh, xz, xt) -> np.ndarray:
        tw = self.tower
        n = self.n_tower
        zl0 = np.clip(zl - 1, 0, n - 1)
        zh0 = np.clip(zh - 1, 0, n - 1)
        on_ground = (zh > n)[:, None]                   # between the lowest tower point and the ground
        c1, c3 = tw[tl0, zl0], tw[th0, zl0]
        c2 = np.where(on_ground, np.float32(0.0), tw[tl0, zh0])
        c4 = np.where(on_ground, np.float32(0.0), tw[th0, zh0])
        w1 = (1.0 - xz) * (1.0 - xt) / 4.0
        w2 = (1.0 + xz) * (1.0 - xt) / 4.0
        w3 = (1.0 - xz) * (1.0 + xt) / 4.0
        w4 = (1.0 + xz) * (1.0 + xt) / 4.0
        return c1 * w1[:, None] + c2 * w2[:, None] + c3 * w3[:, None] + c4 * w4[:, None]

    def _raise(self, k: int, t, p, pw, code: int) -> None:
        point = ", ".join(f"{c:g}" for c in p[k])
        where = f"point ({point}) m at t = {t[k]:g} s"
        if self.rotated:
            where += f" (wind axes: ({', '.join(f'{c:g}' for c in pw[k])}) m)"
        top = self.grid_bottom + (self.n_z - 1) * self.dz
        if code == _TIME:
            lag = (pw[k, 0] - self.initial_x) / self.mean_speed
            what = (f"the field has no data there: at this x it covers t in [{lag:g}, {lag + self.n_t * self.dt:g}) s "
                    f"({self.n_t} steps of {self.dt:g} s, non-periodic). Shorten the simulation or use a longer field")
        elif code == _BELOW:
            what = (f"the point is below the grid (bottom {self.grid_bottom:g} m) and the file has no tower points. "
                    "Keep the points within the grid or generate the field with tower points")
        elif code == _ABOVE:
            what = f"the point is above the grid (top {top:g} m). Use a taller grid"
        else:
            what = (f"the point is beside the grid (y in [{-self.half_width:g}, {self.half_width:g}] m). "
                    "Use a wider grid")
        raise WindFieldDomainError(f"full-field wind {self.source or ''}: InflowWind stops at {where}: {what}.")

    # ------------------------------------------------------------------ identity and CasADi
    @functools.cached_property
    def data_hash(self) -> str:
        """Hex digest of the velocities and the grid layout (not the rotation)."""
        import hashlib

        h = hashlib.blake2b(digest_size=20)
        meta = (self.grid.shape, self.n_tower, repr(self.dy), repr(self.dz), repr(self.dt), repr(self.mean_speed),
                repr(self.reference_height), repr(self.grid_bottom), self.periodic, self.interpolate_to_ground)
        h.update(repr(meta).encode())
        h.update(memoryview(self.grid).cast("B"))
        if self.tower is not None:
            h.update(memoryview(self.tower).cast("B"))
        return h.hexdigest()

    @property
    def content_hash(self) -> str:
        """Hex digest of everything :meth:`velocity` depends on (data, layout, rotation)."""
        import hashlib

        rot = f"{self.propagation_direction!r},{self.upflow_angle!r}"
        if self.mean_profile is not None or self.x_offset is not None:
            rot += f",{self.mean_profile!r},{self.x_offset!r}"
        if self.cubic:                                  # (linear fields keep their earlier hashes)
            rot += ",cubic"
        return hashlib.blake2b((self.data_hash + rot).encode(), digest_size=20).hexdigest()

    def casadi_function(self, n_points: int) -> "ca.Function":
        """CasADi Function ``(t [s], xyz [3 x n_points] m) -> uvw [3 x n_points] m/s`` of this field.

        A CasADi External in C generated for this field (constants baked in, the data read once from a
        float32 file in :func:`mbsym.codegen.cache_dir`), or, without a C compiler
        (``MBSYM_NO_COMPILE=1`` or none found), a ``casadi.Callback`` around :meth:`velocity` (with a
        :class:`~mbsym.codegen.CompilationWarning`). Derivatives by finite differences. Where InflowWind
        errors the call fails (CasADi raises ``RuntimeError``). See :mod:`mbsym.wind.inflow.field_casadi`.
        """
        from .field_casadi import full_field_function

        return full_field_function(self, n_points)

    def __repr__(self) -> str:
        return (f"FullFieldWind({self.n_y} x {self.n_z} grid, dy={self.dy:g} m, dz={self.dz:g} m, {self.n_t} steps of "
                f"{self.dt:g} s, URef={self.mean_speed:g} m/s, RefHt={self.reference_height:g} m, "
                f"bottom={self.grid_bottom:g} m, tower points={self.n_tower}, periodic={self.periodic}, "
                + (f"{self.mean_profile.describe()} added, " if self.mean_profile is not None else "")
                + (f"XOffset={self.x_offset:g} m, " if self.x_offset is not None else "")
                + ("cubic in time, " if self.cubic else "")
                + f"source={self.source!r})")


def _modulo(a: np.ndarray, p: float) -> np.ndarray:
    """Fortran ``MODULO`` for reals: ``a - floor(a / p) p``."""
    return a - np.floor(a / p) * p
