"""Stop runs of an operating turbine that leave the physics its models hold for.

A run that goes unphysical stops with :class:`~mbsym.exceptions.UnphysicalRunError` naming the
first time and channel, instead of ending with numbers nobody should use:

* a channel of the plant that is not finite;
* the rotor turning backwards: ``RotSpeed`` below :data:`MIN_ROTOR_SPEED_RPM` (the surfaces and
  blade-element tables describe a rotor turning forwards; a parked rotor shakes by far less);
* the nacelle yawed more than a full turn from where it started (``NacYaw``): no yaw drive lets
  it, and the rotor is then far outside the yawed inflow the aerodynamics hold for;
* a rotor described by performance surfaces outside its table: ``RtAeroCp`` beyond the table's
  range of Cp by more than :data:`CP_MARGIN` of that range (the surfaces are extrapolated there,
  e.g. at tip-speed ratios of 10⁶ when the wind along the shaft vanishes).
"""

from __future__ import annotations

import numpy as np

from ...exceptions import UnphysicalRunError

__all__ = ["check_physical", "MIN_ROTOR_SPEED_RPM", "MAX_YAW_TRAVEL_DEG", "CP_MARGIN"]

#: Lowest rotor speed accepted [rpm].
MIN_ROTOR_SPEED_RPM = -1.0
#: Largest yaw travel from the initial yaw [deg].
MAX_YAW_TRAVEL_DEG = 360.0
#: Allowed excursion of RtAeroCp beyond the table's Cp range, as a fraction of that range.
CP_MARGIN = 0.1


def check_physical(result, model) -> None:
    """Raise if the run ``result`` of ``model`` went unphysical (module docstring).

    Parameters
    ----------
    result : SimulationResult
        With the OpenFAST channels as outputs (``RotSpeed`` [rpm], ``NacYaw`` [deg], ``RtAeroCp``).
    model : OperatingTurbine

    Raises
    ------
    UnphysicalRunError
        At the first violation: ``time``, ``channel``, ``value``, ``result`` set on the error.
    """
    names = list(result.output_names)
    t = np.asarray(result.t, dtype=float)
    y = np.asarray(result.y, dtype=float)
    found = []                                    # (index, channel, value, why)
    plant = set(model.dynamics().output_names) if hasattr(model, "dynamics") else set(names)
    cols = [j for j, n in enumerate(names) if n in plant]        # not the estimators' or controllers' columns
    bad = ~np.isfinite(y[:, cols])
    if bad.any():
        i, j = np.argwhere(bad)[0]
        found.append((i, names[cols[j]], y[i, cols[j]], "is not finite (the integration diverged)"))
    for channel, test, why in _limits(model, y, names):
        hits = np.flatnonzero(test)
        if hits.size:
            i = hits[0]
            found.append((i, channel, y[i, names.index(channel)], why))
    if not found:
        return
    i, channel, value, why = min(found, key=lambda f: f[0])
    error = UnphysicalRunError(f"the run went unphysical at t = {t[i]:.4g} s: {channel} = {value:.4g} {why}. "
                               "Check the deck's settings for the DOFs that move (e.g. a yaw DOF without "
                               "ServoDyn's yaw spring and damper), the wind and the controller.")
    error.time, error.channel, error.value, error.result = float(t[i]), channel, float(value), result
    raise error


def _limits(model, y: np.ndarray, names: list[str]):
    """(channel, boolean mask over time, reason) for each bound that applies to ``model``."""
    out = []
    if "RotSpeed" in names:
        out.append(("RotSpeed", y[:, names.index("RotSpeed")] < MIN_ROTOR_SPEED_RPM,
                    f"rpm: the rotor turns backwards (below {MIN_ROTOR_SPEED_RPM:g} rpm)"))
    if "NacYaw" in names:
        yaw = y[:, names.index("NacYaw")]
        out.append(("NacYaw", np.abs(yaw - yaw[0]) > MAX_YAW_TRAVEL_DEG,
                    f"deg: the nacelle yawed more than a full turn from {yaw[0]:.4g} deg"))
    table = getattr(getattr(model, "rotor", None), "table", None)
    if table is not None and "RtAeroCp" in names:
        lo, hi = float(np.min(table.cp)), float(np.max(table.cp))
        margin = CP_MARGIN * (hi - lo)
        cp = y[:, names.index("RtAeroCp")]
        out.append(("RtAeroCp", (cp < lo - margin) | (cp > hi + margin),
                    f"is beyond the rotor's table (Cp {lo:.3g} to {hi:.3g}): the surfaces are extrapolated"))
    return out
