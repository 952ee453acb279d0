"""Rotor performance surfaces Cp, Ct, Cq over tip-speed ratio × pitch from the steady BEM.

:func:`performance_surface` evaluates :func:`mbsym.wind.aero.bem.solve_bem` on a
grid and returns a :class:`~mbsym.wind.deck.performance.PerformanceTable`, which
:func:`~mbsym.wind.deck.performance.write_performance_table` writes in ROSCO's
``Cp_Ct_Cq`` format.  The coefficients follow AeroDyn's conventions (radius =
in-plane tip radius ``rotor.radius``, wind speed along the shaft), so ``cq`` is
exactly ``cp / tsr``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ...exceptions import ParameterError
from ..deck.performance import PerformanceTable
from .bem import BEMRotor, solve_bem

__all__ = ["performance_surface", "DEFAULT_TSR", "DEFAULT_PITCH"]

#: Default tip-speed-ratio grid: 1 to 16 in steps of 0.25 (61 values).
DEFAULT_TSR = np.round(np.arange(1.0, 16.0 + 1e-9, 0.25), 12)
#: Default pitch grid [rad]: -5 to 40 deg in steps of 1 deg (46 values).
DEFAULT_PITCH = np.deg2rad(np.arange(-5.0, 40.0 + 1e-9, 1.0))


def _axis(values: Any, name: str) -> np.ndarray:
    axis = np.asarray(values, dtype=float)
    if axis.ndim != 1 or axis.size < 2 or not np.all(np.isfinite(axis)) or \
            np.any(np.diff(axis) <= 0):
        raise ParameterError(f"{name} must be a 1-D array of at least 2 strictly increasing "
                             f"finite values; got {values!r}.")
    return axis


def performance_surface(rotor: BEMRotor, tsr: Any = None, pitch: Any = None, *,
                        skew: float | None = None, n_azimuth: int = 8,
                        wind_speed: float | None = None) -> PerformanceTable:
    """Cp, Ct, Cq of ``rotor`` on the grid ``tsr`` × ``pitch``.

    Parameters
    ----------
    rotor : BEMRotor
        The rotor (e.g. ``BEMRotor.from_openfast(fst)``).
    tsr : array_like, optional
        Strictly increasing tip-speed ratios [-]; default :data:`DEFAULT_TSR`.
    pitch : array_like, optional
        Strictly increasing collective pitch angles [rad]; default
        :data:`DEFAULT_PITCH`.
    skew, n_azimuth : optional
        As in :func:`~mbsym.wind.aero.bem.solve_bem` (default: the shaft tilt, 8).
    wind_speed : float, optional
        The informational "z axis" wind speed of ROSCO's format [m/s].

    Returns
    -------
    PerformanceTable
        ``cq = cp / tsr``; ``source`` describes the rotor and options.

    Raises
    ------
    ParameterError
        If a grid is not strictly increasing or a TSR is not positive.

    Examples
    --------
    >>> import numpy as np
    >>> from mbsym.wind.aero import nrel5mw_bem_rotor, performance_surface
    >>> table = performance_surface(nrel5mw_bem_rotor(), tsr=[6.0, 7.5],
    ...                             pitch=np.radians([0.0, 2.0]))
    >>> table.cp.shape
    (2, 2)
    """
    tsr_axis = _axis(DEFAULT_TSR if tsr is None else tsr, "tsr")
    pitch_axis = _axis(DEFAULT_PITCH if pitch is None else pitch, "pitch")
    grid_tsr, grid_pitch = np.meshgrid(tsr_axis, pitch_axis, indexing="ij")
    solution = solve_bem(rotor, grid_tsr, grid_pitch, skew=skew, n_azimuth=n_azimuth)
    used_skew = abs(rotor.shaft_tilt) if skew is None else abs(skew)
    source = (f"mbsym steady BEM of {rotor.source or 'a BEMRotor'} (R = {rotor.radius:.4f} m, "
              f"skew {math.degrees(used_skew):.3g} deg, {n_azimuth if used_skew else 1} azimuths)")
    return PerformanceTable(tsr=tsr_axis, pitch=pitch_axis, cp=solution.cp, ct=solution.ct,
                            cq=solution.cq, wind_speed=wind_speed, source=source)
