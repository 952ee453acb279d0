"""SeaState's steady current (``CurrMod = 1``) at the points where HydroDyn's Morison members read the water.

SeaState's standard current (OpenFAST v5.0.0; read for the facts in ``Current.f90``, ``SeaState_Input.f90`` and
``Waves.f90``) is the sum of three horizontal parts at the height ``z`` below the still-water level, each along its
own heading (degrees counter-clockwise from the x axis, the direction the water flows to):

* sub-surface ``CurrSSV0 ((z + h)/h)^(1/7)`` along ``CurrSSDir`` (``DEFAULT``: the waves' ``WaveDir``; refused in
  still water, as SeaState does), ``h`` the
  effective water depth (``WtrDpth + MSL2SWL``);
* near-surface ``max(CurrNSV0 (1 + z/CurrNSRef), 0)`` along ``CurrNSDir``;
* depth-independent ``CurrDIV`` along ``CurrDIDir``;

zero below the seabed and above the still-water level. SeaState evaluates it **at the nodes of its kinematics grid**
and adds it to the waves' velocity there (in still water the grid's velocity is the current alone); HydroDyn reads
the sum at a member's node with the grid's interpolation (cubic in the cosine-spaced depth coordinate,
:mod:`.wave_kinematics`), so between grid levels the profile is the interpolant, not the power law.
:func:`current_at` reproduces that; :meth:`SeaCurrent.velocity` is the profile itself.

The current is steady, so it adds no acceleration or pressure: in HydroDyn it acts through the members' viscous drag
alone (the relative velocity of :mod:`.morison`; potential-flow bodies feel no current). MoorDyn's lines feel it only
with MoorDyn's own water-kinematics option (``WaterKin``), which :mod:`.mooring` refuses.

**Refused**: ``CurrMod = 2`` (SeaState's ``UserCurrent`` routine compiled into the OpenFAST executable; its
stock version returns zero, so the effect depends on a build mbsym cannot see); wave-current interaction
(``WvCrntMod`` > 0) is refused by the waves' checks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import ParameterError, UnsupportedFeatureError
from .wave_kinematics import _grid_depth, _stencil

__all__ = ["SeaCurrent", "sea_current", "current_at", "current_problems"]


@dataclass(frozen=True)
class SeaCurrent:
    """SeaState's standard current profile (``CurrMod = 1``), SI units, headings in rad.

    Attributes
    ----------
    subsurface_speed, subsurface_direction : float
        ``CurrSSV0`` [m/s] at the still-water level and its heading [rad].
    near_surface_depth, near_surface_speed, near_surface_direction : float
        ``CurrNSRef`` [m] where the near-surface current vanishes, ``CurrNSV0`` [m/s], ``CurrNSDir`` [rad].
    uniform_speed, uniform_direction : float
        ``CurrDIV`` [m/s], ``CurrDIDir`` [rad].
    water_depth : float
        The effective water depth ``h`` [m] (``WtrDpth + MSL2SWL``).
    """

    subsurface_speed: float
    subsurface_direction: float
    near_surface_depth: float
    near_surface_speed: float
    near_surface_direction: float
    uniform_speed: float
    uniform_direction: float
    water_depth: float

    def velocity(self, z) -> np.ndarray:
        """``(n, 3)`` current [m/s] at heights ``z`` [m] from the still-water level (inertial axes; zero below the
        seabed and above the water)."""
        z = np.atleast_1d(np.asarray(z, dtype=float))
        h = self.water_depth
        wet = (z >= -h) & (z <= 0.0)
        zc = np.where(wet, z, 0.0)
        parts = (
            (self.subsurface_speed * np.power(np.maximum((zc + h) / h, 0.0), 1.0 / 7.0), self.subsurface_direction),
            (np.maximum(self.near_surface_speed * (zc + self.near_surface_depth) / self.near_surface_depth, 0.0),
             self.near_surface_direction),
            (np.full_like(zc, self.uniform_speed), self.uniform_direction),
        )
        out = np.zeros((z.size, 3))
        for speed, heading in parts:
            out[:, 0] += speed * math.cos(heading)
            out[:, 1] += speed * math.sin(heading)
        out[~wet] = 0.0
        return out


def current_problems(sea, where: str = "") -> list[str]:
    """What of a SeaState current is not modelled (empty: all of it), one phrase each (wave-current interaction,
    ``WvCrntMod``, is a matter of the waves: the callers check it with them)."""
    if sea is None or sea.current_model != 2:
        return []
    return [f"{where}CurrMod = 2 (SeaState's UserCurrent routine compiled into the OpenFAST executable; its effect "
            "depends on that build): give the profile as CurrMod = 1's three parts"]


def sea_current(sea, water_depth: float) -> SeaCurrent | None:
    """The current of a SeaState input (None with ``CurrMod = 0``).

    Parameters
    ----------
    sea : SeaStateInput
    water_depth : float
        The water depth [m] (SeaState's own ``WtrDpth`` when it gives one, else the ``.fst``'s).

    Raises
    ------
    UnsupportedFeatureError
        ``CurrMod = 2`` (:func:`current_problems`).
    ParameterError
        The values SeaState itself refuses (negative speeds, ``CurrNSRef ≤ 0``, headings outside (−180, 180] deg),
        or a water depth that is not finite and positive.
    """
    if sea is None or not sea.current_model:
        return None
    problems = current_problems(sea)
    if problems:
        raise UnsupportedFeatureError(f"{sea.path}: " + "; ".join(problems) + ".")
    h = float(water_depth) + _msl_to_swl(sea)
    if not (math.isfinite(h) and h > 0):
        raise ParameterError(f"{sea.path}: the current's profile needs a finite, positive water depth; got {h} m.")
    direction = sea.current_subsurface_direction
    if direction in (None, "default"):
        if not sea.wave_model:
            raise ParameterError(f"{sea.path}: CurrSSDir = DEFAULT (the waves' heading) with WaveMod = 0: give the "
                                 "sub-surface current's heading in degrees (SeaState refuses DEFAULT in still water).")
        direction = float(sea.wave_direction or 0.0)
    current = SeaCurrent(float(sea.current_subsurface_speed or 0.0), float(direction),
                         float(sea.current_near_surface_depth or 0.0), float(sea.current_near_surface_speed or 0.0),
                         float(sea.current_near_surface_direction), float(sea.current_uniform_speed or 0.0),
                         float(sea.current_uniform_direction), h)
    _check(current, sea.path)
    return current


def _msl_to_swl(sea) -> float:
    value = getattr(sea, "msl_to_swl", 0.0)
    return 0.0 if value in (None, "default") else float(value)


def _check(c: SeaCurrent, path) -> None:
    bad = [f"{key} = {value:g} m/s must be >= 0" for key, value in
           (("CurrSSV0", c.subsurface_speed), ("CurrNSV0", c.near_surface_speed), ("CurrDIV", c.uniform_speed))
           if not value >= 0]
    if not c.near_surface_depth > 0:
        bad.append(f"CurrNSRef = {c.near_surface_depth:g} m must be > 0")
    for key, value in (("CurrSSDir", c.subsurface_direction), ("CurrNSDir", c.near_surface_direction),
                       ("CurrDIDir", c.uniform_direction)):
        deg = math.degrees(value)
        if not -180.0 < deg <= 180.0 + 1e-9:
            bad.append(f"{key} = {deg:g} deg must be in (-180, 180]")
    if bad:
        raise ParameterError(f"{path}: the current (CurrMod = 1): " + "; ".join(bad) + " (SeaState refuses it too).")


def current_at(current: SeaCurrent | None, sea, points) -> np.ndarray:
    """``(n, 3)`` current [m/s] at ``points`` (n, 3) [m; undisplaced, inertial, z from the still-water level], read
    off SeaState's kinematics grid as HydroDyn reads it (module docstring); zero above the water and without a
    current."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    out = np.zeros((len(pts), 3))
    if current is None:
        return out
    depth = _grid_depth(sea, current.water_depth)      # Z_Depth, default WtrDpth + MSL2SWL
    nz = int(sea.nz)
    for j, (x, y, z) in enumerate(pts):
        if z > 0.0:
            continue
        # the grid's heights in single precision, as SeaState keeps them: its deepest level is then exactly the
        # seabed, where the 1/7-power current is zero (in double it would sit 2e-15 m above it, at 0.5 % of CurrSSV0)
        out[j] = sum(a * b * c * current.velocity(float(np.float32(zi)))[0] for (_, a), (_, b), (zi, c) in
                     _stencil(sea, depth, nz, x, y, z))
    return out
