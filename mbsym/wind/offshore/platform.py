"""The potential-flow platform of a HydroDyn deck: hydrostatics, additional loads, A∞.

:class:`PlatformHydrodynamics` gathers what a floating deck says about the water's loads on
the platform, read through :mod:`mbsym.wind.deck` (HydroDyn, SeaState, WAMIT) and
redimensionalized with the ``.fst``'s water density and gravity:

* :class:`~.hydrostatics.PlatformHydrostatics` (HydroDyn's restoring and buoyancy);
* :class:`~.hydrostatics.AdditionalLoads` (``AddF0``, ``AddCLin``, ``AddBLin``, ``AddBQuad``);
* the infinite-frequency added mass A∞ (the ``.1`` file's period-0 rows), the part of the
  radiation load proportional to the platform's acceleration: HydroDyn applies
  ``−A∞ a`` with ``a`` the reference point's translational and angular acceleration; it belongs
  in the mass matrix (:meth:`PlatformHydrodynamics.added_mass_load`);
* the frequency-dependent A(ω), B(ω) and the excitation, for what comes next.

**Modelled now**: still water, first-order potential flow, one rigid body. What the deck asks
for beyond that is refused (:class:`~mbsym.exceptions.UnsupportedFeatureError`) or, when it
does not change still-water loads, named in a :class:`~mbsym.exceptions.ModelWarning`:
radiation memory (``RdtnMod`` > 0: the convolution/state-space damping, not yet modelled —
free decays would be less damped than OpenFAST's), second-order forces (zero in still water),
a current (``CurrMod`` > 0: HydroDyn applies it to Morison members only, none here).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import casadi as ca
import numpy as np

from ...exceptions import ModelWarning, ParameterError, UnsupportedFeatureError
from ..deck.hydrodyn import HydroDynInput, read_hydrodyn
from ..deck.seastate import SeaStateInput, read_seastate
from ..deck.wamit import WamitHydrodynamics, read_wamit
from ._casadi import _in, _out
from .hydrostatics import AdditionalLoads, PlatformHydrostatics

__all__ = ["PlatformHydrodynamics", "platform_hydrodynamics"]


@dataclass(frozen=True, eq=False)
class PlatformHydrodynamics:
    """Still-water hydrodynamics of one potential-flow platform (see the module docstring).

    Attributes
    ----------
    hydrostatics : PlatformHydrostatics
    additional : AdditionalLoads
    added_mass : (6, 6) ndarray
        A∞ [kg, kg m, kg m²] about the WAMIT reference point.
    wamit : WamitHydrodynamics
        The dimensional WAMIT data (A(ω), B(ω), excitation).
    notes : tuple of str
        What the deck asks for that is not modelled (also issued as warnings).
    """

    hydrostatics: PlatformHydrostatics
    additional: AdditionalLoads
    added_mass: np.ndarray
    wamit: WamitHydrodynamics
    notes: tuple[str, ...] = field(default=())

    def load(self, q, qd):
        """Still-water load at the reference point, inertial axes [N, N m]: hydrostatics and
        buoyancy plus the additional loads (no radiation memory, no waves)."""
        return _out(_in(self.hydrostatics.load(_in(q, 6, "q")), 6, "q")
                    + _in(self.additional.load(_in(q, 6, "q"), _in(qd, 6, "qd")), 6, "qd"), q, qd)

    def added_mass_load(self, qdd):
        """``−A∞ a`` [N, N m] for the reference point's acceleration ``a`` (translational, angular) [m/s², rad/s²]."""
        return _out(-ca.mtimes(ca.DM(self.added_mass), _in(qdd, 6, "qdd")), qdd)

    @property
    def stiffness(self) -> np.ndarray:
        """Linear stiffness about q = 0 of :meth:`load` (hydrostatics + ``AddCLin``) [SI]."""
        return self.hydrostatics.stiffness + self.additional.stiffness


def _refuse(hd: HydroDynInput, sea: SeaStateInput | None) -> list[str]:
    out = []
    if hd.potential_model != 1:
        out.append(f"PotMod = {hd.potential_model} (only 1, WAMIT potential flow, is modelled)")
    if hd.n_bodies != 1 or any(hd.n_additional_dofs):
        out.append(f"NBody = {hd.n_bodies}, NAddDOF = {list(hd.n_additional_dofs)} (one rigid body only)")
    if hd.reference_rotation and any(hd.reference_rotation):
        out.append("PtfmRefztRot /= 0 (a rotated WAMIT body frame)")
    if hd.has_morison_members:
        out.append(f"{len(hd.tables['members'])} Morison (strip-theory) members (NMembers > 0)")
    if sea is not None and sea.wave_model != 0:
        out.append(f"WaveMod = {sea.wave_model} ({sea.wave_model_name}): wave excitation is not modelled yet")
    if sea is not None and sea.msl_to_swl not in (0.0, "default"):
        out.append(f"MSL2SWL = {sea.msl_to_swl} (HydroDyn requires 0 with potential flow)")
    return out


def _notes(hd: HydroDynInput, sea: SeaStateInput | None) -> list[str]:
    out = []
    if sea is not None and sea.current_model != 0:
        out.append(f"CurrMod = {sea.current_model}: the current is not modelled (in HydroDyn it loads Morison members "
                   "only, and MoorDyn's line drag; neither is modelled here)")
    if hd.radiation_model != 0:
        out.append(f"RdtnMod = {hd.radiation_model}: the radiation memory (wave-radiation damping) is not modelled "
                   "yet; only the infinite-frequency added mass acts, so free decays are less damped than HydroDyn's")
    if hd.second_order:
        out.append(f"second-order wave forces {hd.second_order} are not modelled (they vanish in still water)")
    return out


def platform_hydrodynamics(hydrodyn, *, water_density: float, gravity: float, seastate=None) -> PlatformHydrodynamics:
    """The still-water hydrodynamics of a HydroDyn deck (see the module docstring).

    Parameters
    ----------
    hydrodyn : str, Path or HydroDynInput
        The HydroDyn file (or its reading); ``PotFile`` names the WAMIT files.
    water_density, gravity : float, keyword-only
        ρ [kg/m³] and g [m/s²] (the ``.fst``'s ``WtrDens``, ``Gravity``; SeaState's own
        ``WtrDens`` wins when it is not ``"default"``).
    seastate : str, Path or SeaStateInput, optional, keyword-only
        The SeaState file: checked for still water.

    Raises
    ------
    UnsupportedFeatureError
        Naming every deck setting that is not modelled (waves, Morison members, several bodies…).
    OpenFASTFormatError
        From the readers.

    Warns
    -----
    ModelWarning
        Radiation memory and second-order forces left out.

    Examples
    --------
    >>> ph = platform_hydrodynamics("fl_decay_a_HydroDyn.dat", water_density=1025.0,
    ...                             gravity=9.81, seastate="fl_decay_a_SeaState.dat")  # doctest: +SKIP
    >>> round(ph.hydrostatics.buoyancy / 1e6, 2)  # doctest: +SKIP
    203.18
    """
    hd = hydrodyn if isinstance(hydrodyn, HydroDynInput) else read_hydrodyn(Path(hydrodyn))
    sea = seastate if isinstance(seastate, SeaStateInput) or seastate is None else read_seastate(Path(seastate))
    refused = _refuse(hd, sea)
    if refused:
        raise UnsupportedFeatureError(f"{hd.path}: the deck asks for what mbsym does not model yet: "
                                      + "; ".join(refused) + ". Change these settings or leave the module out.")
    rho = float(water_density)
    if sea is not None and sea.water_density != "default":
        rho = float(sea.water_density)
    if not (math.isfinite(rho) and rho > 0 and math.isfinite(gravity) and gravity > 0):
        raise ParameterError(f"water density {rho} kg/m^3 and gravity {gravity} m/s^2 must be finite and > 0.")
    wamit = read_wamit(hd.potential_files[0]).redimensionalize(rho, float(gravity), hd.wamit_length[0])
    if wamit.added_mass_infinite is None:
        raise UnsupportedFeatureError(f"{hd.potential_files[0]}.1 has no infinite-frequency rows (period 0); HydroDyn "
                                      "needs them too. Rerun WAMIT with the infinite-frequency limit.")
    statics = PlatformHydrostatics(wamit.restoring[:6, :6], rho, float(gravity), hd.displaced_volume[0],
                                   (hd.buoyancy_center_x[0], hd.buoyancy_center_y[0]),
                                   (hd.reference_x[0], hd.reference_y[0], hd.reference_z[0]))
    extra = AdditionalLoads(hd.add_force, hd.add_stiffness, hd.add_damping, hd.add_quadratic_damping)
    notes = _notes(hd, sea)
    for note in notes:
        warnings.warn(note, ModelWarning, stacklevel=2)
    return PlatformHydrodynamics(statics, extra, wamit.added_mass_infinite[:6, :6], wamit, tuple(notes))
