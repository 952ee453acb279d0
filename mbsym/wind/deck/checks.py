"""What an OpenFAST deck asks for that mbsym does not model, and physically doubtful settings.

The one place that decides **which OpenFAST modules are modelled** (:data:`MODELLED`): a deck
that switches on any other module (``CompAero = 2``, ``CompServo = 1``, …) is refused by the
``mbsym`` commands, or run as structure only with ``--structure-only`` and a warning
(:func:`check_modules`). When a module becomes honoured (e.g. aerodynamics reading the AeroDyn
file named on the parameters record, ``TurbineParameters.source_files["aerodyn"]``), add its
switch values to :data:`MODELLED`.

Also here, as warnings (:class:`~mbsym.exceptions.ModelWarning`) issued when a deck is read
(:func:`deck_notes`): settings ElastoDyn itself ignores or warns about (TeetDOF on a rotor that
is not two-bladed, a second tower or flap mode without the first) and platform DOFs that
nothing holds (heave without hydrostatics or mooring: a free fall; a platform without mass);
and the bound on rotor speeds (:data:`MAX_TIP_SPEED`).
"""

from __future__ import annotations

import math
import warnings
from typing import Mapping

from ...exceptions import ModelWarning, OptionError, UnsupportedFeatureError

__all__ = ["MODULE_SWITCHES", "MODULE_FILES", "MODELLED", "FLOATING_MODELLED", "unmodelled_modules", "check_modules",
           "deck_notes",
           "ignored_dofs", "warn", "MAX_TIP_SPEED", "check_rotor_speed", "max_rotor_speed_rpm"]

#: OpenFAST module switch -> (SimulationSettings attribute, module name by switch value).
MODULE_SWITCHES: dict[str, tuple[str, dict[int, str]]] = {
    "CompInflow": ("inflow_model", {1: "InflowWind", 2: "external inflow"}),
    "CompAero": ("aerodynamics_model", {1: "AeroDisk or AeroDyn v14", 2: "AeroDyn", 3: "ExtLoads"}),
    "CompServo": ("servo_model", {1: "ServoDyn"}),
    "CompHydro": ("hydrodynamics_model", {1: "HydroDyn"}),
    "CompSub": ("substructure_model", {1: "SubDyn", 2: "external platform MCKF"}),
    "CompMooring": ("mooring_model", {1: "MAP++", 2: "FEAMooring", 3: "MoorDyn", 4: "OrcaFlex"}),
    "CompIce": ("ice_model", {1: "IceFloe", 2: "IceDyn"}),
    "CompSoil": ("soil_model", {1: "SoilDyn"}),
}
#: Switch -> (the ``.fst`` key naming the module's input file, its name in
#: ``TurbineParameters.source_files`` (resolved path, kept when the switch is on), the
#: SimulationSettings attribute of the switch). CompSeaSt's
#: SeaState applies no load by itself (HydroDyn does), so it is not a switch of its own here.
MODULE_FILES: dict[str, tuple[str, str, str]] = {
    "CompInflow": ("InflowFile", "inflowwind", "inflow_model"), "CompAero": ("AeroFile", "aerodyn", "aerodynamics_model"),
    "CompServo": ("ServoFile", "servodyn", "servo_model"), "CompHydro": ("HydroFile", "hydrodyn", "hydrodynamics_model"),
    "CompSub": ("SubFile", "subdyn", "substructure_model"), "CompMooring": ("MooringFile", "mooring", "mooring_model"),
    "CompIce": ("IceFile", "ice", "ice_model"), "CompSoil": ("SoilFile", "soildyn", "soil_model"),
    "CompSeaSt": ("SeaStFile", "seastate", "sea_state_model"),
}
#: Switch values mbsym models; 0 (module off) always. Aerodynamics, inflow and control add
#: their values here once they honour the deck's files (e.g. ``MODELLED["CompAero"] = {0, 2}``).
MODELLED: dict[str, set[int]] = {key: {0} for key in MODULE_SWITCHES}

#: Switch values the *operating* turbine models as its platform (mbsym.wind.offshore: HydroDyn's potential flow,
#: MAP++ or MoorDyn lines as quasi-static catenaries; SubDyn's bottom-fixed substructure, Guyan-reduced); the
#: structure-only commands still refuse them (:data:`MODELLED`), since the structure alone has no water.
FLOATING_MODELLED: dict[str, set[int]] = {"CompHydro": {1}, "CompMooring": {1, 3}, "CompSub": {1}}

#: Largest blade-tip speed accepted [m/s]: the speed of sound in air at 15 °C (ISA sea level,
#: 340.3 m/s) rounded up. Real rotors stay below about 100 m/s; beyond Mach 1 no model of
#: ours (nor ElastoDyn's) applies, and such speeds are a unit slip (rad/s vs rpm) or a typo.
MAX_TIP_SPEED = 343.0


def unmodelled_modules(simulation, modelled: Mapping[str, set[int]] | None = None) -> list[str]:
    """``["CompAero = 2 (AeroDyn)", …]``: modules the deck switches on that mbsym does not model.

    Parameters
    ----------
    simulation : SimulationSettings
        ``TurbineParameters.simulation``.
    modelled : dict, optional
        Switch -> modelled values (default :data:`MODELLED`).
    """
    modelled = MODELLED if modelled is None else modelled
    out = []
    for key, (attr, names) in MODULE_SWITCHES.items():
        value = getattr(simulation, attr, 0) or 0
        if value not in modelled.get(key, {0}):
            out.append(f"{key} = {value} ({names.get(value, 'unknown module')})")
    return out


def check_modules(turbine, *, structure_only: bool = False, modelled: Mapping[str, set[int]] | None = None) -> None:
    """Refuse a deck whose modules mbsym does not model, or warn with ``structure_only=True``.

    Raises
    ------
    UnsupportedFeatureError
        One line naming the keys, unless ``structure_only``.

    Warns
    -----
    ModelWarning
        With ``structure_only=True``, naming the modules left out.
    """
    found = unmodelled_modules(turbine.simulation, modelled)
    if not found:
        return
    if not structure_only:
        raise UnsupportedFeatureError(
            f"the deck switches on modules mbsym does not model: {', '.join(found)}; set them to 0 in the .fst, "
            "or pass --structure-only to run the ElastoDyn structure alone (no aerodynamic, control, hydrodynamic "
            "or mooring loads).")
    warn(f"--structure-only: ignoring {', '.join(found)}; the results are those of the ElastoDyn structure "
         "alone (no aerodynamic, control, hydrodynamic or mooring loads).", stacklevel=3)


def warn(message: str, *, stacklevel: int = 2) -> None:
    """Issue a :class:`~mbsym.exceptions.ModelWarning`."""
    warnings.warn(message, ModelWarning, stacklevel=stacklevel + 1)


def ignored_dofs(dofs: Mapping[str, bool], n_blades: int) -> tuple[dict[str, bool], list[str]]:
    """DOF flags as ElastoDyn uses them, with a note per flag it ignores.

    ElastoDyn teeters only two-bladed rotors: TeetDOF is ignored for one or three blades.
    """
    out, notes = dict(dofs), []
    if out.get("TeetDOF") and n_blades != 2:
        out["TeetDOF"] = False
        notes.append(f"TeetDOF = True ignored: only two-bladed rotors teeter (NumBl = {n_blades}), as in ElastoDyn")
    return out, notes


def deck_notes(turbine) -> list[str]:
    """Doubtful settings of a deck (one message each): second modes without the first, platform
    DOFs that nothing holds. :func:`mbsym.wind.read_openfast` issues them as warnings."""
    dofs, notes = turbine.dofs, []
    for second, first, what in (("TwFADOF2", "TwFADOF1", "tower fore-aft"), ("TwSSDOF2", "TwSSDOF1", "tower side-side"),
                                ("FlapDOF2", "FlapDOF1", "blade flap")):
        if dofs.get(second) and not dofs.get(first):
            notes.append(f"{second} = True without {first}: the 2nd {what} mode without the 1st (ElastoDyn warns "
                         f"too); enable {first} or check the flags")
    platform = [f for f in ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF") if dofs.get(f)]
    if not platform:
        return notes
    restoring = [k for k in ("CompHydro", "CompMooring", "CompSub")
                 if (getattr(turbine.simulation, MODULE_SWITCHES[k][0], 0) or 0) in
                 (MODELLED[k] | FLOATING_MODELLED.get(k, set())) - {0}]
    if "PtfmHvDOF" in platform and not restoring:
        notes.append("PtfmHvDOF = True with no hydrostatics or mooring modelled: nothing carries the turbine's weight, "
                     "so it falls freely (heave accelerates at g); disable PtfmHvDOF or add a heave spring")
    inertias = (turbine.platform_mass, turbine.platform_roll_inertia, turbine.platform_pitch_inertia,
                turbine.platform_yaw_inertia)
    if all(v == 0 for v in inertias) and "CompSub" not in restoring:     # SubDyn's substructure has mass
        notes.append(f"platform DOFs {platform} with PtfmMass = 0 and zero platform inertias: the platform has no "
                     "mass; check PtfmMass/PtfmRIner/PtfmPIner/PtfmYIner or disable the platform DOFs")
    return notes


def max_rotor_speed_rpm(tip_radius: float) -> float:
    """Largest rotor speed [rpm] whose tip speed stays below :data:`MAX_TIP_SPEED` for ``tip_radius`` [m]."""
    return MAX_TIP_SPEED / max(tip_radius, 1e-9) * 30.0 / math.pi


def check_rotor_speed(rpm: float, tip_radius: float, what: str = "--rpm") -> float:
    """Return ``rpm`` if it is a finite, non-negative speed with a subsonic blade tip.

    Raises
    ------
    OptionError
        Naming ``what``, the bound and the tip speed.
    """
    try:
        value = float(rpm)
    except (TypeError, ValueError):
        raise OptionError(f"{what} must be a rotor speed in rpm; got {rpm!r}") from None
    if not (math.isfinite(value) and value >= 0):
        raise OptionError(f"{what} must be a finite rotor speed >= 0 [rpm]; got {rpm}")
    limit = max_rotor_speed_rpm(tip_radius)
    if value > limit:
        tip = value * math.pi / 30.0 * tip_radius
        raise OptionError(f"{what} {value:g} rpm is unphysical: the blade tip (TipRad {tip_radius:g} m) would move at "
                          f"{tip:.4g} m/s, beyond the speed of sound ({MAX_TIP_SPEED:g} m/s); the largest accepted "
                          f"speed is {limit:.4g} rpm for this rotor")
    return value
