"""AeroDyn settings that change loads on DOFs mbsym models but that its rotor models leave out: refused.

mbsym's rotors load the hub (rotor-effective performance surfaces) or the blades (blade-element
rotor); the tower's drag (``TwrAero``) loads the tower with either, the nacelle's drag (``NacelleDrag``,
:mod:`mbsym.wind.aero.nacelle`) the tower top with either, and the tower's disturbance of the blade
inflow (``TwrPotent``, ``TwrShadow``) enters the blade-element rotor node by node (:mod:`mbsym.wind.aero.tower`)
and the rotor-effective surfaces as its azimuth average (:mod:`mbsym.wind.aero.tower_average`).
AeroDyn switches that add loads on other DOFs or change the blade inflow in ways a model leaves out
are refused with the file, line and key, never ignored:

==================  ==========================================================================
Key                 Why it is refused
==================  ==========================================================================
TFinAero = True     tail-fin aerodynamics (loads the yaw DOF)
SectAvg = True      (rotor-effective rung only) sector-averaged inflow needs blade nodes
MHK ≠ 0             marine hydrokinetic turbine (buoyancy, added mass, cavitation)
Buoyancy = True     buoyant loads (MHK)
==================  ==========================================================================

Output-only settings (``CompAA`` acoustics, ``CavitCheck``, the output lists) and the settings
the rotors honour (BEM, skew, DBEMT, tip and hub losses, drag in the induction) are not listed;
nor is ``UA_Mod``: the blade-element rotor runs ``UA_Mod = 3`` step by step, the rotor-effective
surfaces hold its steady state (:mod:`mbsym.wind.aero.blade.ua_steady`), and both refuse the other
models (:func:`mbsym.wind.aero.blade.unsteady.unsteady_nodes`).
"""

from __future__ import annotations

from pathlib import Path

from ...exceptions import OpenFASTFormatError

__all__ = ["aerodyn_problems", "check_aerodyn"]

_TRUE = ("true", "t", ".true.")
#: key -> (is it on?, why it is refused)
_SWITCHES = {
    "TFinAero": (lambda v: v.lower() in _TRUE, "tail-fin aerodynamics are not modelled"),
    "SectAvg": (lambda v: v.lower() in _TRUE, "sector-averaged blade inflow needs blade nodes: the rotor-effective "
                "rung's wind is one hub-height speed, uniform over the disk, which no sector average changes (run "
                "the blade-element rung, --aero blade)"),
    "MHK": (lambda v: _int(v) != 0, "marine hydrokinetic turbines are not modelled"),
    "Buoyancy": (lambda v: v.lower() in _TRUE, "buoyancy is not modelled"),
}


#: Switches the blade-element rotor models (refused on the rotor-effective rung only).
_BLADE_MODELLED = ("SectAvg",)


def _int(text: str) -> int:
    try:
        return int(float(text))
    except ValueError:
        return 0


def aerodyn_problems(aerodyn, *, rotor_effective: bool) -> list[str]:
    """One message (file, line, key, what to set) per refused AeroDyn setting (module docstring).

    Parameters
    ----------
    aerodyn : AeroDynInput
        From :func:`~mbsym.wind.deck.aerodyn.read_aerodyn` (its ``extra`` keys and ``source`` file).
    rotor_effective : bool, keyword-only
        The rotor-effective model (performance surfaces): it also refuses ``SectAvg``, which the blade-element
        rotor models.
    """
    lines = _lines(aerodyn.source)
    found = [(key, why) for key, (on, why) in _SWITCHES.items()
             if key in aerodyn.extra and on(str(aerodyn.extra[key]).strip().strip("\"'"))
             and (rotor_effective or key not in _BLADE_MODELLED)]
    return [f"{aerodyn.source}, line {lines.get(key.lower(), '?')}, key '{key}': {why}; set {key} = {_off(key)} "
            "to run the deck" for key, why in found]


def check_aerodyn(aerodyn, *, rotor_effective: bool) -> None:
    """Raise :class:`OpenFASTFormatError` listing every refused setting (:func:`aerodyn_problems`)."""
    problems = aerodyn_problems(aerodyn, rotor_effective=rotor_effective)
    if len(problems) == 1:
        raise OpenFASTFormatError(problems[0])
    if problems:
        raise OpenFASTFormatError(f"{len(problems)} AeroDyn settings mbsym does not model:\n  - "
                                  + "\n  - ".join(problems))


def _off(key: str) -> str:
    return {"TwrPotent": "0", "TwrShadow": "0", "MHK": "0", "UA_Mod": "0", "UAMod": "0",
            "AFAeroMod": "1"}.get(key, "False")


def _lines(source) -> dict[str, int]:
    """Line number of each ``value key`` line of the file (lower-case key)."""
    out: dict[str, int] = {}
    if source is None or not Path(source).is_file():
        return out
    for number, text in enumerate(Path(source).read_text(encoding="latin-1").splitlines(), 1):
        tokens = text.split()
        if len(tokens) >= 2:
            out.setdefault(tokens[1].lower(), number)
    return out
