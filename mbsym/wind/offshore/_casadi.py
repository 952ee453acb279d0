"""Numbers or CasADi expressions through one code path (private).

The platform loads are written once with CasADi operations; :func:`_in` turns a numeric
argument into a ``DM`` column (checking its size and finiteness) and leaves ``SX``/``MX``
alone; :func:`_out` gives numpy back for numeric input and the expression otherwise.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, ParameterError


def _symbolic(value) -> bool:
    return isinstance(value, (ca.SX, ca.MX))


def _in(value, n: int, what: str):
    """``value`` as an ``n``-column CasADi vector (SX/MX kept; numbers → DM, checked)."""
    if _symbolic(value):
        if value.numel() != n:
            raise DimensionError(f"{what} has {value.numel()} entries; expected {n}.")
        return ca.reshape(value, n, 1)
    arr = np.asarray(value, dtype=float).ravel()
    if arr.size != n:
        raise DimensionError(f"{what} has {arr.size} entries; expected {n} (surge, sway, heave, roll, pitch, yaw).")
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"All entries of {what} must be finite numbers; got {arr.tolist()}.")
    return ca.DM(arr)


def _out(value, *args):
    """numpy for numeric arguments, the CasADi expression when any argument is symbolic."""
    if any(_symbolic(a) for a in args):
        return value
    return np.array(ca.evalf(value), dtype=float).ravel()


def euler_zyx(angles) -> "ca.SX | ca.MX | ca.DM":
    """Body-to-inertial rotation R = Rz(yaw) Ry(pitch) Rx(roll) of angles ``(roll, pitch, yaw)`` [rad].

    ElastoDyn v4+/v5's platform rotation (mbsym's platform joint) and HydroDyn's
    ``EulerExtractZYX`` use this sequence, so the angles are the platform DOFs R, P, Y.
    """
    r, p, y = angles[0], angles[1], angles[2]
    cr, sr, cp, sp, cy, sy = ca.cos(r), ca.sin(r), ca.cos(p), ca.sin(p), ca.cos(y), ca.sin(y)
    return ca.vertcat(
        ca.horzcat(cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        ca.horzcat(sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        ca.horzcat(-sp, cp * sr, cp * cr))
