"""ElastoDyn DOF flags the turbine template models, their coordinate names and state order.

The tables that map ElastoDyn's flag names (``PtfmSgDOF`` … ``FlapDOF2``) to the template's
coordinate names (``Sg`` … ``B1F2``) in ElastoDyn's state order (docs/elastodyn_notes.md §7),
the resolution of a requested DOF list, and the deck features the template does not model.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np

from ...exceptions import ArgumentTypeError, ModelDefinitionError
from ..deck.parameters import DOF_NAMES, TurbineParameters

__all__ = ["STATE_ORDER", "NON_BLADE_DOFS", "SUPPORTED_DOFS", "BLADE_FLAGS", "MODELLED_DOFS", "PLATFORM_FLAGS",
           "TOWER_FLAGS", "blade_coordinate", "resolve_dofs", "unsupported_features"]

#: ElastoDyn flag -> coordinate name, in ElastoDyn's state order (notes §7).
STATE_ORDER = {
    "PtfmSgDOF": "Sg", "PtfmSwDOF": "Sw", "PtfmHvDOF": "Hv", "PtfmRDOF": "R", "PtfmPDOF": "P",
    "PtfmYDOF": "Y", "TwFADOF1": "TFA1", "TwSSDOF1": "TSS1", "TwFADOF2": "TFA2", "TwSSDOF2": "TSS2",
    "YawDOF": "Yaw", "GenDOF": "GeAz", "DrTrDOF": "DrTr",
}
#: Platform, tower, yaw and drivetrain flags (the 13 non-blade flags, state order): with only
#: these the blades are rigid.
NON_BLADE_DOFS = tuple(STATE_ORDER)
#: Former name of :data:`NON_BLADE_DOFS`, kept for compatibility (it is *not* every flag the
#: template models: see :data:`MODELLED_DOFS`).
SUPPORTED_DOFS = NON_BLADE_DOFS
#: Blade flags in ElastoDyn's state order (all blades' F1, then E1, then F2) and the
#: suffix of their coordinates (``B<k>F1`` …).
BLADE_FLAGS = {"FlapDOF1": "F1", "EdgeDOF": "E1", "FlapDOF2": "F2"}
#: Every flag the template models: 13 non-blade flags + 3 blade flags (22 DOFs for 3 blades).
MODELLED_DOFS = NON_BLADE_DOFS + tuple(BLADE_FLAGS)
PLATFORM_FLAGS = ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF")
TOWER_FLAGS = ("TwFADOF1", "TwSSDOF1", "TwFADOF2", "TwSSDOF2")


def blade_coordinate(blade: int, flag: str) -> str:
    """Coordinate name of a blade DOF: ``blade_coordinate(0, "FlapDOF1") == "B1F1"`` (blade 0-based)."""
    return f"B{blade + 1}{BLADE_FLAGS[flag]}"



def unsupported_features(turbine: TurbineParameters, dofs: dict[str, bool]) -> list[str]:
    """Deck data that would change the dynamics of the enabled DOFs but that the template ignores.

    Checked: yaw-bearing friction (YawFrctMod != 0, with YawDOF) and, for two-bladed
    rotors, UndSling, Delta3, a fixed teeter angle TeetDefl and ElastoDyn's two-bladed hub
    inertia (``Hubg1Iner = Hubg2Iner = (HubIner - HubMass (UndSling - HubCM)²) / cos² Delta3``
    about the shaft and the teeter axis; the template has HubIner about the shaft only).

    Parameters
    ----------
    turbine : TurbineParameters
    dofs : dict
        ElastoDyn flag -> enabled.

    Returns
    -------
    list of str
        One message per unsupported feature (empty if none), saying what to change.

    Examples
    --------
    >>> import dataclasses
    >>> from mbsym.wind import nrel5mw
    >>> t = dataclasses.replace(nrel5mw(), extra={"YawFrctMod": "1"})
    >>> unsupported_features(t, {"YawDOF": True})    # doctest: +ELLIPSIS
    ['YawFrctMod = 1 (yaw-bearing friction on the yaw DOF): set YawFrctMod = 0 or disable YawDOF']
    """
    out = []
    on = {f for f, v in dofs.items() if v}
    platform, tower = on & set(PLATFORM_FLAGS), on & set(TOWER_FLAGS)
    friction = str(turbine.extra.get("YawFrctMod", "0")).strip()
    if "YawDOF" in on and friction not in ("0", "0.0"):
        out.append(f"YawFrctMod = {friction} (yaw-bearing friction on the yaw DOF): set YawFrctMod = 0 or disable "
                   "YawDOF")
    if turbine.number_of_blades == 2:
        out += _two_blade_features(turbine, bool(platform or tower or "YawDOF" in on))
    return out


def _two_blade_features(t: TurbineParameters, support_moves: bool) -> list[str]:
    """Teetering-hub data of a two-bladed deck that the template (hub at the apex, no teeter) ignores."""
    out = []
    if t.undersling != 0:
        out.append(f"UndSling = {t.undersling:.6g} m (2-bladed rotor off the teeter pin): set UndSling = 0")
    if t.delta3 != 0:
        out.append(f"Delta3 = {np.rad2deg(t.delta3):.6g} deg (teeter axis; divides the hub inertia by cos^2 Delta3): "
                   "set Delta3 = 0")
    if t.initial_conditions.teeter_angle != 0:
        out.append(f"TeetDefl = {np.rad2deg(t.initial_conditions.teeter_angle):.6g} deg (a fixed teeter angle): "
                   "set TeetDefl = 0")
    g1 = (t.hub_inertia - t.hub_mass * (t.undersling - t.hub_cm) ** 2) / np.cos(t.delta3) ** 2
    if not np.isclose(g1, t.hub_inertia, rtol=1e-12, atol=0.0) or (support_moves and g1 != 0):
        out.append(f"2-bladed hub inertia: ElastoDyn's Hubg1Iner = Hubg2Iner = {g1:.6g} kg m^2 about the shaft and "
                   f"the teeter axis; the template has HubIner = {t.hub_inertia:.6g} kg m^2 about the shaft only "
                   "(set HubIner = 0, or disable the tower, platform and yaw DOFs and make "
                   "HubMass (UndSling - HubCM)^2 = 0)")
    return out


def resolve_dofs(turbine: TurbineParameters, dofs: Sequence[str] | None) -> tuple[dict[str, bool], list[str]]:
    """Enabled flags (every modelled flag -> bool) and a message for requested flags that are not modelled."""
    if dofs is None:
        chosen = {f for f, on in turbine.dofs.items() if on}
    else:
        if isinstance(dofs, str):
            raise ArgumentTypeError(f"dofs must be a list of ElastoDyn flag names, e.g. ['TwFADOF1', 'GenDOF']; got {dofs!r}.")
        chosen = set(dofs)
        unknown = sorted(chosen - set(DOF_NAMES))
        if unknown:
            raise ModelDefinitionError(f"unknown ElastoDyn DOF flags {unknown}; valid flags are {list(DOF_NAMES)}.")
    unsupported = sorted(chosen - set(MODELLED_DOFS))
    problems = []
    if unsupported:
        problems.append(f"DOFs {unsupported} are not modelled by this template yet (supported: {list(MODELLED_DOFS)}); "
                        "disable them (dofs=[...]) to build the rest")
    return {f: (f in chosen) for f in MODELLED_DOFS}, problems
