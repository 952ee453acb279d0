"""Units of an operating turbine's states and inputs (SI; docs/units.md states the whole convention).

Outputs are OpenFAST channels in OpenFAST's units (:mod:`.channels`); states and inputs are SI, the
units the equations are written in: angles in rad, rates in rad/s, torques in N m, forces in N. The
structural coordinates have the units of their joints (:attr:`mbsym.EquationsOfMotion.units`: m or
rad; blade and tower modes by their tip displacement, m); this module names the units of the
states and inputs the composition adds (actuators, azimuth, inflow, wind, commands, loads).
"""

from __future__ import annotations

import re
from typing import Mapping, Sequence

from ..offshore.operating import SEA_INPUT_UNITS, sea_input_unit
from ..structure.units import structural_input_unit

__all__ = ["STATE_UNITS", "INPUT_UNITS", "state_units", "input_units", "RADIATION_UNIT"]

#: States the composition adds, by name -> unit.
STATE_UNITS = {"GenTq": "N m", "GeAz": "rad", "DBEMT_w": "m/s", "DBEMT_v": "m/s", "RotThrustLag": "N",
               "RotTorqLag": "N m"}
#: Inputs by name -> unit: commands, the hub wind, a floating platform's sea (structural inputs:
#: :mod:`mbsym.wind.structure.units`).
INPUT_UNITS = {"Wind1VelX": "m/s", "Wind1VelY": "m/s", "Wind1VelZ": "m/s", "BlPitchCom": "rad",
               "BlPitchCom1": "rad", "BlPitchCom2": "rad", "BlPitchCom3": "rad", "GenTqCom": "N m",
               "YawCom": "rad", **SEA_INPUT_UNITS}
#: Unit of the radiation states of a floating platform: those of the fitted state-space realization
#: (HydroDyn's ``.ss`` file), which the fit chooses (its ``C`` maps them to N and N m).
RADIATION_UNIT = "fit"

_ANGLE = re.compile(r"^(BlPitch\d?|GeAz)(_d|_dd)?$")
_WAKE = re.compile(r"^B\d+N\d+_vind1?_[xy]$")
_RADIATION = re.compile(r"^(Rdtn|Exctn)\d+$")
_RATE_SUFFIX = {None: "", "_d": "/s", "_dd": "/s^2"}


def state_units(states: Sequence[str], coordinate_units: Mapping[str, str]) -> tuple[str, ...]:
    """The unit of every state (``""`` for a name this module does not know).

    Parameters
    ----------
    states : sequence of str
    coordinate_units : mapping
        Units of the structural coordinates (``EquationsOfMotion.units``); their speeds ``<q>_d`` get ``/s``.

    Examples
    --------
    >>> state_units(["TFA1", "TFA1_d", "BlPitch", "BlPitch_d", "GenTq", "DBEMT_v"], {"TFA1": "m"})
    ('m', 'm/s', 'rad', 'rad/s', 'N m', 'm/s')
    """
    return tuple(_state_unit(s, coordinate_units) for s in states)


def _state_unit(name: str, coordinate_units: Mapping[str, str]) -> str:
    if name in coordinate_units:
        return coordinate_units[name]
    if name.endswith("_d") and name[:-2] in coordinate_units:
        return coordinate_units[name[:-2]] + "/s"
    if name in STATE_UNITS:
        return STATE_UNITS[name]
    angle = _ANGLE.match(name)
    if angle:
        return "rad" + _RATE_SUFFIX[angle.group(2)]
    if _WAKE.match(name):
        return "m/s"                                  # AeroDyn's DBEMT induced velocities per node
    return RADIATION_UNIT if _RADIATION.match(name) else ""


def input_units(inputs: Sequence[str], wind_units: Mapping[str, str] | None = None) -> tuple[str, ...]:
    """The unit of every input (``""`` for a name this module does not know).

    Parameters
    ----------
    inputs : sequence of str
    wind_units : mapping, optional
        Units of the wind inputs of a blade-element rotor (:mod:`.wind_inputs`).

    Examples
    --------
    >>> input_units(["Wind1VelX", "BlPitchCom", "GenTqCom", "B1AeroFx", "Q_BF1_1AeroQ"])
    ('m/s', 'rad', 'N m', 'N', 'N')
    """
    wind = dict(wind_units or {})
    return tuple(_input_unit(n, wind) for n in inputs)


_STC_INPUT = re.compile(r"^[NTS]StC\d+_([FM])[xyz]$")       # ServoDyn's prescribed StC loads


def _input_unit(name: str, wind: Mapping[str, str]) -> str:
    if name in wind:
        return wind[name]
    stc = _STC_INPUT.match(name)
    if stc:
        return "N" if stc.group(1) == "F" else "N m"
    return INPUT_UNITS.get(name) or sea_input_unit(name) or structural_input_unit(name)
