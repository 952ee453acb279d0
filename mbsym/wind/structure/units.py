"""Units of the structural model's inputs (SI; docs/units.md): loads on the structure and prescribed motions.

The coordinates carry the units of their joints (:attr:`mbsym.EquationsOfMotion.units`); the inputs are
named here: generator and rotor torques and hub moments [N m], thrust and platform forces [N], blade-root
loads of the blade-element rotor [N, N m], generalized forces of blade modes (scaled by their tip
displacement) [N], prescribed pitch and azimuth [rad] with their rates [rad/s, rad/s^2].
"""

from __future__ import annotations

import re

__all__ = ["STRUCTURAL_INPUT_UNITS", "structural_input_unit"]

#: Structural inputs by name -> unit.
STRUCTURAL_INPUT_UNITS = {"GenTq": "N m", "RotTorq": "N m", "RotThrust": "N", "RotMomY": "N m", "RotMomZ": "N m",
                          "RotFrcY": "N", "RotFrcZ": "N",
                          "PtfmFx": "N", "PtfmFy": "N", "PtfmFz": "N", "PtfmMx": "N m", "PtfmMy": "N m",
                          "PtfmMz": "N m", "YawPosCom": "rad", "YawRateCom": "rad/s"}

_ANGLE = re.compile(r"^(BlPitch\d?|GeAz)(_d|_dd)?$")
_BLADE_LOAD = re.compile(r"^(?:B\d+|Twr|Nac)Aero([FM])[xyz]$")     # blade, tower, nacelle loads
_MODE_LOAD = re.compile(r"^.+AeroQ$")
_RATE_SUFFIX = {None: "", "_d": "/s", "_dd": "/s^2"}


def structural_input_unit(name: str) -> str:
    """The unit of a structural input, "" if not one of the structure's.

    Examples
    --------
    >>> [structural_input_unit(n) for n in ("RotThrust", "BlPitch_d", "B2AeroMy", "B1F1AeroQ", "x")]
    ['N', 'rad/s', 'N m', 'N', '']
    """
    if name in STRUCTURAL_INPUT_UNITS:
        return STRUCTURAL_INPUT_UNITS[name]
    angle = _ANGLE.match(name)
    if angle:
        return "rad" + _RATE_SUFFIX[angle.group(2)]
    load = _BLADE_LOAD.match(name)
    if load:
        return "N" if load.group(1) == "F" else "N m"
    return "N" if _MODE_LOAD.match(name) else ""
