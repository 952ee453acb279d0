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
* the frequency-dependent A(ω), B(ω) (for the radiation fit);
* the sea, when SeaState has waves: the first-order excitation HydroDyn computes from the ``.3`` data
  (:class:`~.excitation.WaveExcitation`, from :func:`~.waves.incident_waves`).

**Modelled**: still water or first-order waves (``WaveMod`` 1, ``1P#``, 2, 3, 5; ``ExctnMod`` 1 at the
undisplaced position), first-order potential flow (``PotMod`` 1) or none (0: the members carry the platform), one
rigid body, the viscous drag of its Morison members (:mod:`.morison`) in still water or in the waves' velocity at
their undisplaced nodes (:mod:`.wave_kinematics`), the buoyancy, added mass, marine growth and wave inertia of the
members without potential flow (:mod:`.strip_theory`). What the deck asks for beyond that
is refused (:class:`~mbsym.exceptions.UnsupportedFeatureError`) or, when it does not change the loads,
named in a :class:`~mbsym.exceptions.ModelWarning`: radiation memory here (``RdtnMod`` > 0: modelled by
:mod:`.operating` as states), second-order forces (the full difference- and sum-frequency QTFs, ``DiffQTF`` and
``SumQTF``, are modelled: :mod:`.second_order`; the others are refused with waves; all are zero in still water),
SeaState's current (``CurrMod = 1``: on the Morison members' drag, :mod:`.current`; it loads nothing else in
HydroDyn; named when the deck has no members), SeaState's second-order elevation (``WvDiffQTF``/``WvSumQTF``: in its
``Wave1Elev`` only; the potential-flow loads use the first-order sea).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field, replace
from pathlib import Path

import casadi as ca
import numpy as np

from ...exceptions import ModelWarning, ParameterError, UnsupportedFeatureError
from ..deck.hydrodyn import HydroDynInput, read_hydrodyn
from ..deck.seastate import SeaStateInput, read_seastate
from ..deck.wamit import ExcitationFit, WamitHydrodynamics, read_wamit, read_wamit_ssexctn
from ..deck.wamit_qtf import read_wamit_qtf
from ._casadi import _in, _out
from .current import current_at, sea_current
from .excitation import WaveExcitation, wave_excitation
from .hydrostatics import AdditionalLoads, PlatformHydrostatics
from .morison import MorisonDrag, morison_drag, morison_problems
from .second_order import difference_frequency_forces, mean_drift_forces, newman_forces, sum_frequency_forces
from .strip_theory import StripTheory, StripWaves, strip_problems, strip_theory, strip_waves
from .wave_kinematics import WaveFlow, wave_flow
from .waves import grid_elevation, incident_waves

__all__ = ["PlatformHydrodynamics", "platform_hydrodynamics"]


@dataclass(frozen=True, eq=False)
class PlatformHydrodynamics:
    """Still-water hydrodynamics of one potential-flow platform (see the module docstring).

    Attributes
    ----------
    hydrostatics : PlatformHydrostatics
    additional : AdditionalLoads
    added_mass : (6, 6) ndarray
        A∞ [kg, kg m, kg m²] about the WAMIT reference point, with the strip-theory members' added mass.
    wamit : WamitHydrodynamics
        The dimensional WAMIT data (A(ω), B(ω), excitation).
    notes : tuple of str
        What the deck asks for that is not modelled (also issued as warnings).
    waves : WaveExcitation or None
        The sea's first-order excitation and elevation (None: still water).
    excitation_fit : ExcitationFit or None
        HydroDyn's state-space excitation (``ExctnMod = 2``).
    morison : MorisonDrag or None
        The members' viscous drag (:mod:`.morison`).
    flow : WaveFlow or None
        The waves' velocity at the members (:mod:`.wave_kinematics`; None in still water or without members).
    strip : StripTheory or None
        The buoyancy of the members not modelled by potential flow (``PropPot = FALSE``, :mod:`.strip_theory`);
        their added mass is in :attr:`added_mass`.
    strip_waves : StripWaves or None
        Their wave inertia (None in still water or without them).
    """

    hydrostatics: PlatformHydrostatics
    additional: AdditionalLoads
    added_mass: np.ndarray
    wamit: WamitHydrodynamics
    notes: tuple[str, ...] = field(default=())
    waves: WaveExcitation | None = None
    excitation_fit: ExcitationFit | None = None
    morison: MorisonDrag | None = None
    flow: WaveFlow | None = None
    strip: StripTheory | None = None
    strip_waves: StripWaves | None = None

    def load(self, q, qd, flow=None, strip=None):
        """Load at the reference point, inertial axes [N, N m]: hydrostatics and buoyancy, the additional
        loads, the members' viscous drag (:mod:`.morison`) in the water's velocity ``flow`` at the
        members (``3 morison.n_flow`` values [m/s]; default still water) and the strip-theory members'
        buoyancy and wave inertia (``strip``: the 15 values of
        :data:`~.strip_theory.WAVE_INERTIA_INPUTS`; default none); no radiation memory, no excitation."""
        x, v = _in(q, 6, "q"), _in(qd, 6, "qd")
        out = _in(self.hydrostatics.load(x), 6, "q") + _in(self.additional.load(x, v), 6, "qd")
        if self.morison is not None:
            out = out + _in(self.morison.load(x, v, flow), 6, "qd")
        if self.strip is not None:
            out = out + _in(self.strip.load(x), 6, "q")
            if strip is not None:
                out = out + _in(self.strip.wave_load(x, strip), 6, "strip")
        return _out(out, q, qd, flow, strip)

    def added_mass_load(self, qdd):
        """``−A∞ a`` [N, N m] for the reference point's acceleration ``a`` (translational, angular) [m/s², rad/s²]."""
        return _out(-ca.mtimes(ca.DM(self.added_mass), _in(qdd, 6, "qdd")), qdd)

    @property
    def stiffness(self) -> np.ndarray:
        """Linear stiffness about q = 0 of :meth:`load` (hydrostatics + ``AddCLin``) [SI]."""
        return self.hydrostatics.stiffness + self.additional.stiffness


def _refuse(hd: HydroDynInput, sea: SeaStateInput | None, water_depth: float | None = None) -> list[str]:
    out = []
    if hd.potential_model not in (0, 1):
        out.append(f"PotMod = {hd.potential_model} (0, strip theory only, and 1, WAMIT potential flow, are modelled)")
    if hd.potential_model == 0 and not any(not r[10] for r in hd.tables["members"].rows):
        out.append("PotMod = 0 without members modelled by strip theory (PropPot = FALSE): nothing would float it")
    if hd.n_bodies != 1 or any(hd.n_additional_dofs):
        out.append(f"NBody = {hd.n_bodies}, NAddDOF = {list(hd.n_additional_dofs)} (one rigid body only)")
    if hd.reference_rotation and any(hd.reference_rotation):
        out.append("PtfmRefztRot /= 0 (a rotated WAMIT body frame)")
    out += morison_problems(hd, sea, water_depth=water_depth) + strip_problems(hd)
    if sea is not None and sea.msl_to_swl not in (0.0, "default"):
        out.append(f"MSL2SWL = {sea.msl_to_swl} (HydroDyn requires 0 with potential flow)")
    if sea is not None and sea.wave_model != 0:
        out += _refuse_waves(hd, sea)
    return out


def _potential(hd: HydroDynInput) -> bool:
    """Whether the deck has a potential-flow body (``PotMod = 1``; with 0 its WAMIT keys are unused)."""
    return hd.potential_model != 0


def _refuse_waves(hd: HydroDynInput, sea: SeaStateInput) -> list[str]:
    """What is not modelled of a deck with waves (the sea itself is checked by :func:`~.waves.incident_waves`)."""
    out = []
    if _potential(hd) and hd.excitation_model == 2 and sea.direction_model and int(sea.n_directions) > 1:
        out.append("ExctnMod = 2 with directional spreading (the .ssexctn fit is for one heading; use ExctnMod 1)")
    if _potential(hd) and hd.excitation_model and hd.excitation_displaced:
        out.append(f"ExctnDisp = {hd.excitation_displaced} (excitation at the displaced platform; use 0)")
    if hd.yaw_model or hd.reference_yaw:
        out.append(f"PtfmYMod = {hd.yaw_model}, PtfmRefY = {math.degrees(hd.reference_yaw):g} deg with waves "
                   "(a yawed reference frame; use 0 and 0)")
    methods = {k: v for k, v in (("MnDrift", hd.mean_drift), ("NewmanApp", hd.newman_approximation),
                                 ("DiffQTF", hd.difference_qtf)) if v}
    if _potential(hd) and len(methods) > 1:
        out.append(f"{methods} (HydroDyn allows one of MnDrift, NewmanApp and DiffQTF; keep one)")
    if _potential(hd) and (hd.difference_qtf or hd.sum_qtf) and sea.direction_model and int(sea.n_directions) > 1:
        out.append("DiffQTF/SumQTF with directional spreading (the second-order forces are modelled for a "
                   "unidirectional sea; set WaveDirMod = 0)")
    if sea.current_model and sea.wave_current_model:
        out.append(f"WvCrntMod = {sea.wave_current_model} with a current (wave-current interaction; use 0)")
    return out


def _notes(hd: HydroDynInput, sea: SeaStateInput | None) -> list[str]:
    out = []
    if sea is not None and sea.current_model != 0 and not _has_members(hd):
        out.append(f"CurrMod = {sea.current_model}: the deck has no Morison members, so the current loads nothing (in "
                   "HydroDyn too: it acts through the members' drag alone)")
    if not _potential(hd):
        return out + _unused_without_potential_flow(hd)
    if hd.radiation_model != 0:
        out.append(f"RdtnMod = {hd.radiation_model}: the radiation memory (wave-radiation damping) is not modelled "
                   "yet; only the infinite-frequency added mass acts, so free decays are less damped than HydroDyn's")
    if hd.second_order and (sea is None or sea.wave_model == 0):
        out.append(f"second-order wave forces {hd.second_order} are not modelled (they vanish in still water)")
    if sea is not None and sea.wave_model != 0 and (sea.difference_qtf or sea.sum_qtf):
        out.append("WvDiffQTF/WvSumQTF: SeaState adds the second-order elevation to its Wave1Elev output; mbsym's "
                   "Wave1Elev is the first-order sea (the potential-flow loads use only that, as HydroDyn's)")
    if sea is not None and sea.wave_model != 0 and hd.excitation_model == 0:
        out.append("ExctnMod = 0: the waves exert no force on the platform (only Wave1Elev shows them)")
    return out


def _unused_without_potential_flow(hd: HydroDynInput) -> list[str]:
    """The additional loads a ``PotMod = 0`` deck gives: HydroDyn does not apply them (only with WAMIT data)."""
    given = [name for name, value in (("AddF0", hd.add_force), ("AddCLin", hd.add_stiffness),
                                      ("AddBLin", hd.add_damping), ("AddBQuad", hd.add_quadratic_damping))
             if np.any(np.asarray(value, dtype=float) != 0)]
    if not given:
        return []
    return [f"{', '.join(given)} with PotMod = 0: HydroDyn applies the additional loads only with potential flow "
            "(PotMod = 1), so they act neither in OpenFAST nor here"]


def platform_hydrodynamics(hydrodyn, *, water_density: float, gravity: float, seastate=None,
                           water_depth: float | None = None, platform_reference=(0.0, 0.0, 0.0)
                           ) -> PlatformHydrodynamics:
    """The hydrodynamics of a HydroDyn deck, with its SeaState's waves (see the module docstring).

    Parameters
    ----------
    hydrodyn : str, Path or HydroDynInput
        The HydroDyn file (or its reading); ``PotFile`` names the WAMIT files.
    water_density, gravity : float, keyword-only
        ρ [kg/m³] and g [m/s²] (the ``.fst``'s ``WtrDens``, ``Gravity``; SeaState's own
        ``WtrDens`` wins when it is not ``"default"``).
    seastate : str, Path or SeaStateInput, optional, keyword-only
        The SeaState file: its waves (none without it).
    water_depth : float, optional, keyword-only
        [m] for the dispersion relation of waves (the ``.fst``'s ``WtrDpth``; SeaState's own wins when
        it is not ``"default"``); needed only with waves and an elevation output point off the origin, and
        for the seabed of Morison members.
    platform_reference : sequence of 3 floats, optional, keyword-only
        The platform reference point's undisplaced position (ElastoDyn's ``PtfmRefxt/yt/zt``) [m]: the
        members' drag acts about it (:mod:`.morison`).

    Raises
    ------
    UnsupportedFeatureError
        Naming every deck setting that is not modelled (waves, what of the Morison members
        :func:`~.morison.morison_problems` names, several bodies…).
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
    depth = _depth(sea, water_depth)
    refused = _refuse(hd, sea, depth)
    if refused:
        raise UnsupportedFeatureError(f"{hd.path}: the deck asks for what mbsym does not model yet: "
                                      + "; ".join(refused) + ". Change these settings or leave the module out.")
    rho = float(water_density)
    if sea is not None and sea.water_density != "default":
        rho = float(sea.water_density)
    if not (math.isfinite(rho) and rho > 0 and math.isfinite(gravity) and gravity > 0):
        raise ParameterError(f"water density {rho} kg/m^3 and gravity {gravity} m/s^2 must be finite and > 0.")
    wamit, statics, infinite, extra = _potential_flow(hd, rho, float(gravity))
    notes = _notes(hd, sea)
    for note in notes:
        warnings.warn(note, ModelWarning, stacklevel=2)
    waves = _waves(hd, sea, wamit, float(gravity), water_depth, rho)
    fit = _excitation_fit(hd, sea) if waves is not None and wamit is not None and hd.excitation_model == 2 else None
    morison = _with_current(morison_drag(hd, water_density=rho, reference=platform_reference, water_depth=depth),
                            sea, depth, hd.path)
    flow = None
    if morison is not None and morison.n_flow and waves is not None:
        if depth is None:
            raise ParameterError(f"{hd.path}: the waves' velocity at the Morison members needs the water depth; give "
                                 "water_depth (the .fst's WtrDpth).")
        flow = wave_flow(waves.waves, sea, morison.flow_points())
    strip = strip_theory(hd, water_density=rho, gravity=float(gravity), reference=platform_reference)
    added = infinite + (0.0 if strip is None else strip.added_mass)
    inertia = None
    if strip is not None and waves is not None:
        if depth is None:
            raise ParameterError(f"{hd.path}: the waves' kinematics at the strip-theory members need the water depth; "
                                 "give water_depth (the .fst's WtrDpth).")
        inertia = strip_waves(strip, waves.waves, sea)
    return PlatformHydrodynamics(statics, extra, added, wamit, tuple(notes), waves, fit, morison, flow, strip,
                                 inertia)


def _with_current(morison: MorisonDrag | None, sea: SeaStateInput | None, depth: float | None,
                  path) -> MorisonDrag | None:
    """The members' drag with SeaState's current at their strip nodes and end plates (:mod:`.current`)."""
    if morison is None or sea is None or not sea.current_model or not morison.n_flow:
        return morison
    if depth is None:
        raise ParameterError(f"{path}: the current's profile at the Morison members needs the water depth; give "
                             "water_depth (the .fst's WtrDpth).")
    return replace(morison, current=current_at(sea_current(sea, depth), sea, morison.flow_points()))


def _potential_flow(hd: HydroDynInput, rho: float, gravity: float):
    """``(wamit, hydrostatics, A∞, additional loads)`` of the potential-flow body; with ``PotMod = 0`` none of them
    act (HydroDyn applies ``AddF0`` … ``AddBQuad`` only with WAMIT data): no WAMIT data, zero hydrostatics, A∞ and
    additional loads (the members carry the platform, :mod:`.strip_theory`)."""
    if hd.potential_model == 0:
        zero = np.zeros((6, 6))
        return (None, PlatformHydrostatics(zero, rho, gravity, 0.0),
                zero, AdditionalLoads(np.zeros(6), zero, zero, zero))
    wamit = read_wamit(hd.potential_files[0]).redimensionalize(rho, gravity, hd.wamit_length[0])
    if wamit.added_mass_infinite is None:
        raise UnsupportedFeatureError(f"{hd.potential_files[0]}.1 has no infinite-frequency rows (period 0); HydroDyn "
                                      "needs them too. Rerun WAMIT with the infinite-frequency limit.")
    statics = PlatformHydrostatics(wamit.restoring[:6, :6], rho, gravity, hd.displaced_volume[0],
                                   (hd.buoyancy_center_x[0], hd.buoyancy_center_y[0]),
                                   (hd.reference_x[0], hd.reference_y[0], hd.reference_z[0]))
    extra = AdditionalLoads(hd.add_force, hd.add_stiffness, hd.add_damping, hd.add_quadratic_damping)
    return wamit, statics, wamit.added_mass_infinite[:6, :6], extra


def _drift_file(hd: HydroDynInput, number: int):
    """The WAMIT data of a mean-drift or Newman switch (``<PotFile>.7`` … ``.9``, 3-D, or ``.10d`` … ``.12d``),
    checked for the components HydroDyn uses from it (surge, sway and yaw from a ``.8``, all six otherwise)."""
    qtf = read_wamit_qtf(f"{hd.potential_files[0]}.{number}" + ("d" if number >= 10 else ""))
    needed = (0, 1, 5) if number == 8 else range(6)
    missing = [m + 1 for m in needed if not qtf.components[m]]
    if missing:
        raise UnsupportedFeatureError(f"{qtf.source} gives no value for the components {missing}, which HydroDyn "
                                      "uses from this file. Regenerate it with WAMIT or choose another file.")
    return qtf


def _depth(sea: SeaStateInput | None, water_depth: float | None) -> float | None:
    """SeaState's water depth when it gives one, else the ``.fst``'s (None: unknown)."""
    if sea is not None and sea.water_depth != "default":
        return float(sea.water_depth)
    return None if water_depth is None else float(water_depth)


def _excitation_fit(hd: HydroDynInput, sea: SeaStateInput) -> ExcitationFit:
    """The deck's ``.ssexctn`` (``ExctnMod = 2``), checked against the sea's heading (the fit is for one)."""
    fit = read_wamit_ssexctn(f"{hd.potential_files[0]}.ssexctn")
    if not math.isclose(fit.heading, math.degrees(float(sea.wave_direction)), abs_tol=1e-6):
        raise UnsupportedFeatureError(f"{fit.path}: the state-space excitation was fitted for waves from "
                                      f"{fit.heading:g} deg; SeaState's WaveDir is {math.degrees(sea.wave_direction):g} "
                                      "deg (HydroDyn needs them equal). Refit it or use ExctnMod = 1.")
    return fit


def _waves(hd: HydroDynInput, sea: SeaStateInput | None, wamit, gravity: float,
           water_depth: float | None, rho: float) -> WaveExcitation | None:
    """The sea's excitation (zero force with ``ExctnMod = 0``; with ``DiffQTF`` the difference-frequency forces of
    :mod:`.second_order` added), or None in still water."""
    if sea is None or sea.wave_model == 0:
        return None
    depth = float(sea.water_depth) if sea.water_depth != "default" else water_depth
    point = sea.elevation_points[0] if sea.elevation_points else (0.0, 0.0)
    if depth is None:
        if tuple(point) != (0.0, 0.0):
            raise ParameterError(f"{sea.path}: the wave elevation point {tuple(point)} needs the water depth; give "
                                 "water_depth (the .fst's WtrDpth).")
        depth = math.inf
    waves = incident_waves(sea, gravity=gravity, water_depth=depth)
    if wamit is None:                     # PotMod = 0: the sea acts on the members only
        return WaveExcitation(waves, np.zeros((waves.n_steps + 1, 6)), grid_elevation(waves, sea, *point))
    excitation = wave_excitation(wamit, waves, elevation_point=tuple(point), sea=sea)
    if hd.excitation_model != 1:          # 0: no excitation; 2: HydroDyn's state space makes it (operating.py)
        excitation = WaveExcitation(excitation.waves, np.zeros_like(excitation.forces), excitation.elevation)
    second = np.zeros_like(excitation.forces)     # HydroDyn's WAMIT2: joins the excitation (B1WvsFxi = 1st + 2nd)
    if hd.difference_qtf:
        qtf = read_wamit_qtf(f"{hd.potential_files[0]}.{hd.difference_qtf}d")
        second += difference_frequency_forces(qtf.redimensionalize(rho, gravity, hd.wamit_length[0]), waves,
                                              band=(float(sea.low_cutoff), float(sea.high_cutoff)),
                                              difference_band=tuple(float(c) for c in sea.qtf_cutoffs[:2]))
    for number, method in ((hd.mean_drift, mean_drift_forces), (hd.newman_approximation, newman_forces)):
        if number:
            qtf = _drift_file(hd, number)
            dims = np.array([True, True, False, False, False, True]) if number == 8 else np.ones(6, dtype=bool)
            second += dims * method(qtf.redimensionalize(rho, gravity, hd.wamit_length[0]), waves,
                                    band=(float(sea.low_cutoff), float(sea.high_cutoff)))
    if hd.sum_qtf:
        qtf = read_wamit_qtf(f"{hd.potential_files[0]}.{hd.sum_qtf}s")
        second += sum_frequency_forces(qtf.redimensionalize(rho, gravity, hd.wamit_length[0]), waves,
                                       sum_band=tuple(float(c) for c in sea.qtf_cutoffs[2:4]))
    if hd.second_order:
        excitation = WaveExcitation(excitation.waves, excitation.forces + second, excitation.elevation)
    return excitation


def _has_members(hd: HydroDynInput) -> bool:
    table = hd.tables.get("members")
    return bool(table is not None and table.rows)
