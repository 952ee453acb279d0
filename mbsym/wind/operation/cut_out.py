"""The cut-out wind speed: a run whose wind is above it is not a real operating state.

A turbine shuts down (feathers, brakes) when the wind exceeds its cut-out speed ``V_out``; mbsym's
baseline controller has no shutdown logic, so it keeps the turbine operating in any wind. Such a run
can still be wanted (a model check), but its results are not those of the turbine: :func:`above_cut_out`
says when the wind of a run is above ``V_out``, and :func:`warn_above_cut_out` warns.

Where ``V_out`` comes from: the built-in NREL 5 MW's 25 m/s (Jonkman et al. 2009, NREL/TP-500-38060,
Table 1-1), :data:`NREL5MW_CUT_OUT`. An OpenFAST deck states none (neither ElastoDyn, ServoDyn,
InflowWind nor ROSCO's DISCON.IN has a cut-out wind speed key), so a deck run gets no check unless the
caller gives a value.

Which wind is compared (IEC 61400-1 defines ``V_out`` on 10-min means): a steady, step or ramp wind by its
largest value over the run; an extreme operating gust by its hub speed (the gust is a transient); any
other wind (turbulence, tables, files) by its largest mean over :data:`MEAN_WINDOW_S` (the whole run when
shorter).
"""

from __future__ import annotations

import warnings

import numpy as np

from ...exceptions import ModelWarning

__all__ = ["NREL5MW_CUT_OUT", "MEAN_WINDOW_S", "above_cut_out", "warn_above_cut_out"]

#: The NREL 5 MW's cut-out wind speed [m/s] and its source.
NREL5MW_CUT_OUT = (25.0, "the NREL 5 MW's cut-out wind speed (Jonkman et al. 2009, NREL/TP-500-38060, Table 1-1)")
#: Averaging window [s] of a turbulent or tabulated wind against the cut-out (IEC 61400-1: 10-min means).
MEAN_WINDOW_S = 600.0
_GRID_DT = 0.05


def above_cut_out(wind, tmax: float, cut_out: float) -> str | None:
    """Words for the wind above ``cut_out`` [m/s] in ``[0, tmax]`` [s] (module docstring), or None.

    Examples
    --------
    >>> from mbsym.wind.inflow import SteadyWind
    >>> above_cut_out(SteadyWind(30.0), 60.0, 25.0)
    'the wind is 30 m/s'
    >>> above_cut_out(SteadyWind(20.0), 60.0, 25.0) is None
    True
    """
    from ..inflow import ExtremeOperatingGust, RampWind, SteadyWind, StepWind

    if isinstance(wind, ExtremeOperatingGust):
        return f"the wind is {wind.hub_speed:g} m/s before the gust" if wind.hub_speed > cut_out else None
    t = np.linspace(0.0, tmax, max(int(np.ceil(tmax / _GRID_DT)), 1) + 1)
    u = np.asarray(wind(t), dtype=float).reshape(t.size, -1)[:, 0]
    if isinstance(wind, (SteadyWind, StepWind, RampWind)):
        k = int(np.argmax(u))
        if u[k] <= cut_out:
            return None
        return f"the wind is {u[k]:g} m/s" + (f" from t = {t[k]:g} s" if t[k] > 0 else "")
    n = min(int(round(MEAN_WINDOW_S / _GRID_DT)), t.size - 1)
    trapezoids = np.concatenate([[0.0], np.cumsum(0.5 * (u[1:] + u[:-1]) * np.diff(t))])
    means = (trapezoids[n:] - trapezoids[:-n]) / (t[n:] - t[:-n]) if n > 0 else u
    k = int(np.argmax(means))
    if means[k] <= cut_out:
        return None
    span = "the run" if n == t.size - 1 else f"{t[n] - t[0]:g} s from t = {t[k]:g} s"
    return f"the mean wind over {span} is {means[k]:.3g} m/s"


def warn_above_cut_out(wind, tmax: float, cut_out: float | None, source: str) -> str | None:
    """Warn (:class:`~mbsym.exceptions.ModelWarning`) when the wind of a run is above ``cut_out`` [m/s]
    (``source`` names where the value comes from); None ``cut_out`` (unknown) checks nothing. Returns the
    message, or None."""
    if cut_out is None or wind is None:
        return None
    where = above_cut_out(wind, tmax, cut_out)
    if where is None:
        return None
    message = (f"{where}, above {source}, {cut_out:g} m/s: a real turbine would be shut down. This run keeps it "
               "operating unless its controller shuts it down (the baseline controller and the NMPC have no shutdown "
               "logic): results beyond cut-out are not a real operating state.")
    warnings.warn(message, ModelWarning, stacklevel=2)
    return message
