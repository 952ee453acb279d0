"""Named physical parameters of the turbine template: ElastoDyn key ↔ descriptive name ↔ unit.

The template (:class:`~mbsym.wind.structure.turbine.TurbineModel`) keeps these deck
quantities as **symbolic parameters** of its equations, with the deck's values as
defaults, so that the same CasADi Functions serve simulation, identification
(:func:`mbsym.identify`), gradients and design optimization. Inside the equations each
parameter has a descriptive name in SI units (``tower_fa1_damping_ratio``, a
fraction); users may also address it by its ElastoDyn key **in the deck's units**
(``TwrFADmp(1)`` in %). This module is the one documented mapping between the two
(:data:`NAMED_PARAMETERS`, printed by :func:`parameter_table`), and builds the
tower and blade stiffness and damping matrices as expressions of the parameters.

Where they enter (ElastoDyn's ``Coeff``, docs/elastodyn_notes.md §1.3-1.5, §3.3):

* stiffness of tower modes ``I, L`` of one family (FA or SS),
  ``K_IL = Adj · sqrt(τ_I τ_L) · K̂_IL`` with ``K̂`` the curvature integral of the
  deck's unadjusted EI (tuner and factor 1), ``Adj`` = AdjFASt/AdjSSSt and ``τ`` the
  tuners FAStTunr/SSStTunr; blades: ``sqrt(τ_I τ_L) K̂`` (FlStTunr; EdgStff has no tuner);
* damping, column convention: ``C_IL = 2 ζ_L K_IL / ω_L`` with
  ``ω_L = sqrt(K_LL / M_LL)`` and ``M_LL`` the modal mass of the beam alone
  (tower: ``AdjTwMa · M̂_LL``), written as ``2 ζ_L sqrt(M_LL Adj τ_I / K̂_LL) K̂_IL`` so
  that it stays finite at a zero tuner;
* AdjTwMa also scales every inertial shape integral of the tower (``mass_scale`` of
  :class:`~mbsym.bodies.flexible.FlexibleBody`, including its self-weight stiffening);
* masses and inertias enter the rigid bodies (nacelle, yaw bearing, hub, generator,
  platform) and the tower-top mass that loads the tower; PtfmCMzt the platform's
  centre of mass; DTTorSpr/DTTorDmp the drivetrain spring and damper.

Blade keys are shared by all blades (one parameter); if the deck's blades differ in
a value, that key stays numeric (per blade) and is not a parameter of the model.

Other layers add their own entries with :func:`register` (e.g. the aerodynamic
turbine's air density and Cp/Ct scale factors): a key resolves for a model when its
descriptive name is one of the model's parameters.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from typing import Callable, Mapping, Sequence

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from ..deck.parameters import TurbineParameters

__all__ = ["NamedParameter", "NAMED_PARAMETERS", "register", "lookup", "canonical_key", "parameter_defaults",
           "deck_value", "tower_matrices", "blade_matrices", "parameter_table", "resolve"]


@dataclass(frozen=True)
class NamedParameter:
    """One named physical parameter.

    Attributes
    ----------
    key : str
        ElastoDyn/deck key as ElastoDyn spells it (``"TwrFADmp(1)"``).
    name : str
        Descriptive name of the symbolic parameter in the equations (SI units).
    unit : str
        Unit of the key's value (the deck's unit, e.g. ``"%"``).
    factor : float
        ``key value = factor * parameter value`` (100 for a damping ratio in %).
    description : str
    enters : str
        Where the parameter enters the equations.
    requires : tuple of str
        ElastoDyn DOF flags of which at least one must be enabled for the template to
        make it a parameter (empty: always).
    lower : float
        Smallest physical value in key units (identification bound), default 0.
    value : callable or None
        ``TurbineParameters -> value in SI units`` (the deck's value); None for entries
        other layers register (their model supplies the default).
    """

    key: str
    name: str
    unit: str
    factor: float
    description: str
    enters: str
    requires: tuple[str, ...] = ()
    lower: float = 0.0
    value: Callable[[TurbineParameters], float] | None = None


_TOWER = ("TwFADOF1", "TwFADOF2", "TwSSDOF1", "TwSSDOF2")
_PLATFORM = ("PtfmSgDOF", "PtfmSwDOF", "PtfmHvDOF", "PtfmRDOF", "PtfmPDOF", "PtfmYDOF")
_KE, _DE = "tower Ke (and De through ω)", "tower De"


def _entries() -> list[NamedParameter]:
    P = NamedParameter
    out = [
        P("Gravity", "gravity", "m/s^2", 1.0, "gravitational acceleration", "gravity field",
          value=lambda t: t.simulation.gravity),
        P("NacMass", "nacelle_mass", "kg", 1.0, "nacelle mass", "nacelle body; tower-top mass",
          value=lambda t: t.nacelle_mass),
        P("NacYIner", "nacelle_yaw_inertia", "kg m^2", 1.0, "nacelle inertia about the yaw axis",
          "nacelle body", value=lambda t: t.nacelle_yaw_inertia),
        P("YawBrMass", "yaw_bearing_mass", "kg", 1.0, "yaw bearing mass", "yaw-bearing body; tower-top mass",
          value=lambda t: t.yaw_bearing_mass),
        P("HubMass", "hub_mass", "kg", 1.0, "hub mass", "hub body; tower-top mass",
          value=lambda t: t.hub_mass),
        P("HubIner", "hub_inertia", "kg m^2", 1.0, "hub inertia about the shaft", "hub body",
          value=lambda t: t.hub_inertia),
        P("GenIner", "generator_inertia", "kg m^2", 1.0, "generator inertia about the HSS", "generator body",
          value=lambda t: t.generator_inertia),
        P("DTTorSpr", "drivetrain_stiffness", "N m/rad", 1.0, "drivetrain torsional spring", "DrTr spring",
          ("DrTrDOF",), value=lambda t: t.drivetrain_stiffness),
        P("DTTorDmp", "drivetrain_damping", "N m s/rad", 1.0, "drivetrain torsional damper", "DrTr damper",
          ("DrTrDOF",), value=lambda t: t.drivetrain_damping),
        P("PtfmMass", "platform_mass", "kg", 1.0, "platform mass", "platform body", _PLATFORM,
          value=lambda t: t.platform_mass),
        P("PtfmRIner", "platform_roll_inertia", "kg m^2", 1.0, "platform roll inertia about its CM",
          "platform body", _PLATFORM, value=lambda t: t.platform_roll_inertia),
        P("PtfmPIner", "platform_pitch_inertia", "kg m^2", 1.0, "platform pitch inertia about its CM",
          "platform body", _PLATFORM, value=lambda t: t.platform_pitch_inertia),
        P("PtfmYIner", "platform_yaw_inertia", "kg m^2", 1.0, "platform yaw inertia about its CM",
          "platform body", _PLATFORM, value=lambda t: t.platform_yaw_inertia),
        P("PtfmCMzt", "platform_cm_height", "m", 1.0, "height of the platform CM above ground/MSL",
          "platform body (CM)", _PLATFORM, lower=-math.inf, value=lambda t: t.platform_cm[2]),
        P("AdjTwMa", "tower_mass_factor", "-", 1.0, "tower mass-density factor",
          "tower inertial shape integrals, tower De", _TOWER, value=lambda t: t.tower.mass_factor),
        P("AdjFASt", "tower_fa_stiffness_factor", "-", 1.0, "tower fore-aft EI factor", _KE,
          ("TwFADOF1", "TwFADOF2"), value=lambda t: t.tower.fa_stiffness_factor),
        P("AdjSSSt", "tower_ss_stiffness_factor", "-", 1.0, "tower side-side EI factor", _KE,
          ("TwSSDOF1", "TwSSDOF2"), value=lambda t: t.tower.ss_stiffness_factor),
    ]
    for i in (1, 2):
        out += [
            P(f"FAStTunr({i})", f"tower_fa{i}_stiffness_tuner", "-", 1.0, f"tower FA mode {i} stiffness tuner",
              _KE, (f"TwFADOF{i}",), value=lambda t, i=i: t.tower.fa_stiffness_tuner[i - 1]),
            P(f"SSStTunr({i})", f"tower_ss{i}_stiffness_tuner", "-", 1.0, f"tower SS mode {i} stiffness tuner",
              _KE, (f"TwSSDOF{i}",), value=lambda t, i=i: t.tower.ss_stiffness_tuner[i - 1]),
            P(f"TwrFADmp({i})", f"tower_fa{i}_damping_ratio", "%", 100.0, f"tower FA mode {i} damping ratio",
              _DE, (f"TwFADOF{i}",), value=lambda t, i=i: t.tower.fa_damping_ratio[i - 1]),
            P(f"TwrSSDmp({i})", f"tower_ss{i}_damping_ratio", "%", 100.0, f"tower SS mode {i} damping ratio",
              _DE, (f"TwSSDOF{i}",), value=lambda t, i=i: t.tower.ss_damping_ratio[i - 1]),
            P(f"FlStTunr({i})", f"blade_flap{i}_stiffness_tuner", "-", 1.0,
              f"blade flap mode {i} stiffness tuner (all blades)", "blade Ke (and De through ω)",
              (f"FlapDOF{i}",), value=lambda t, i=i: _blade_value(t, "flap_stiffness_tuner", i - 1)),
            P(f"BldFlDmp({i})", f"blade_flap{i}_damping_ratio", "%", 100.0,
              f"blade flap mode {i} damping ratio (all blades)", "blade De", (f"FlapDOF{i}",),
              value=lambda t, i=i: _blade_value(t, "flap_damping_ratio", i - 1)),
        ]
    out.append(P("BldEdDmp(1)", "blade_edge_damping_ratio", "%", 100.0, "blade edge mode damping ratio "
                 "(all blades)", "blade De", ("EdgeDOF",),
                 value=lambda t: _blade_value(t, "edge_damping_ratio", 0)))
    return out


#: Every named parameter by canonical key (ElastoDyn's spelling), in table order.
NAMED_PARAMETERS: dict[str, NamedParameter] = {}
_BY_NAME: dict[str, NamedParameter] = {}
_KEY_RE = re.compile(r"\s*([A-Za-z_][A-Za-z_]*?)\s*(?:\(\s*(\d+)\s*\)|(\d+))?\s*")


def canonical_key(key: str) -> str:
    """Lower-case ``base(i)`` form of a key: ``TwrFADmp1``, ``twrfadmp(1)`` → ``twrfadmp(1)``.

    A key without an index that has only an index-1 form (``BldEdDmp``) maps to ``(1)``.

    Examples
    --------
    >>> canonical_key("TwrFADmp1"), canonical_key("BldEdDmp"), canonical_key("NacMass")
    ('twrfadmp(1)', 'bldeddmp(1)', 'nacmass')
    """
    m = _KEY_RE.fullmatch(str(key))
    if m is None:
        return str(key).strip().lower()
    base, idx = m.group(1).lower(), m.group(2) or m.group(3)
    if idx is None and f"{base}(1)" in _CANONICAL and f"{base}(2)" not in _CANONICAL:
        idx = "1"
    return f"{base}({int(idx)})" if idx is not None else base


_CANONICAL: dict[str, str] = {}


def register(entry: NamedParameter) -> None:
    """Add a named parameter (for layers that add parameters, e.g. aerodynamics).

    Raises
    ------
    ParameterError
        If the key or the name is already registered for another entry.
    """
    if not isinstance(entry, NamedParameter):
        raise TypeError(f"entry must be a NamedParameter; got {type(entry).__name__}.")
    ck = entry.key.strip().lower().replace(" ", "")
    old = NAMED_PARAMETERS.get(_CANONICAL.get(ck, ""))
    if (old is not None and old != entry) or (entry.name in _BY_NAME and _BY_NAME[entry.name] != entry):
        raise ParameterError(f"named parameter {entry.key!r} / {entry.name!r} is already registered differently.")
    _CANONICAL[ck] = entry.key
    NAMED_PARAMETERS[entry.key] = entry
    _BY_NAME[entry.name] = entry


for _e in _entries():
    register(_e)


def lookup(key_or_name: str) -> NamedParameter:
    """The entry of a deck key (any spelling :func:`canonical_key` accepts) or a descriptive name.

    Raises
    ------
    ParameterError
        Unknown key or name (lists the known keys).

    Examples
    --------
    >>> e = lookup("TwrFADmp1")
    >>> e.key, e.name, e.unit, e.factor
    ('TwrFADmp(1)', 'tower_fa1_damping_ratio', '%', 100.0)
    """
    if not isinstance(key_or_name, str):
        raise ParameterError(f"a parameter key must be a string; got {key_or_name!r}.")
    if key_or_name in _BY_NAME:
        return _BY_NAME[key_or_name]
    key = _CANONICAL.get(canonical_key(key_or_name))
    if key is None:
        raise ParameterError(f"unknown parameter key {key_or_name!r}; known ElastoDyn keys: "
                             f"{', '.join(NAMED_PARAMETERS)} (or their descriptive names, e.g. 'nacelle_mass').")
    return NAMED_PARAMETERS[key]


def _blade_value(t: TurbineParameters, field: str, i: int) -> float:
    values = {float(np.asarray(getattr(b, field))[i]) for b in t.blades}
    if len(values) != 1:
        raise _BladesDiffer(field)
    return values.pop()


class _BladesDiffer(Exception):
    """The blades of a deck differ in a value (that key then stays numeric)."""


def deck_value(turbine: TurbineParameters, key_or_name: str) -> float:
    """The deck's value of a key **in the key's units** (``TwrFADmp(1)`` → 1.0 for 1 %).

    Raises
    ------
    ParameterError
        Unknown key, an entry without a deck value, or blades that differ in the value.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> deck_value(nrel5mw(), "TwrFADmp(1)"), deck_value(nrel5mw(), "NacMass")
    (1.0, 240000.0)
    """
    e = lookup(key_or_name)
    if e.value is None:
        raise ParameterError(f"{e.key} has no value in an ElastoDyn deck; its model supplies the default.")
    try:
        return e.factor * float(e.value(turbine))
    except _BladesDiffer:
        raise ParameterError(f"{e.key}: the deck's blades have different values; it is not one parameter.") from None


def parameter_defaults(turbine: TurbineParameters, dofs: Mapping[str, bool]) -> dict[str, float]:
    """``{name: deck value [SI]}`` of every table entry the template makes symbolic for ``dofs``.

    Entries whose ``requires`` flags are all off, and blade entries whose blades differ,
    are left out.
    """
    out = {}
    for e in NAMED_PARAMETERS.values():
        if e.value is None or (e.requires and not any(dofs.get(f) for f in e.requires)):
            continue
        try:
            out[e.name] = float(e.value(turbine))
        except _BladesDiffer:
            continue
    return out


def _unit_tower(turbine: TurbineParameters):
    """ElastoDyn tower data with tuners and factors 1 (``K̂``, ``M̂``)."""
    from .elastodyn_bodies import tower_elastodyn_data

    tw = dataclasses.replace(turbine.tower, mass_factor=1.0, fa_stiffness_factor=1.0, ss_stiffness_factor=1.0,
                             fa_stiffness_tuner=np.ones(2), ss_stiffness_tuner=np.ones(2))
    return tower_elastodyn_data(dataclasses.replace(turbine, tower=tw))


def _family_matrices(k_hat: np.ndarray, m_hat: np.ndarray, adj, tuners: Sequence, ratios: Sequence,
                     mass_factor) -> tuple[ca.SX, ca.SX]:
    """``K_IL = adj sqrt(τ_I τ_L) K̂_IL``, ``C_IL = 2 ζ_L sqrt(mf M̂_LL adj τ_I / K̂_LL) K̂_IL``."""
    n = len(tuners)
    K, C = ca.SX.zeros(n, n), ca.SX.zeros(n, n)
    for i in range(n):
        for j in range(n):
            if k_hat[i, j] == 0.0:
                continue
            K[i, j] = adj * ca.sqrt(tuners[i] * tuners[j]) * k_hat[i, j]
            C[i, j] = 2.0 * ratios[j] * ca.sqrt(mass_factor * m_hat[j] * adj * tuners[i] / k_hat[j, j]) * k_hat[i, j]
    return K, C


def tower_matrices(turbine: TurbineParameters, active: Sequence[str],
                   p: Mapping[str, ca.SX]) -> tuple[ca.SX, ca.SX, ca.SX]:
    """Tower stiffness, damping (modes ``active``, in that order) and mass scale, symbolic.

    Parameters
    ----------
    turbine : TurbineParameters
    active : sequence of str
        Enabled tower flags in body order (e.g. ``["TwFADOF1", "TwSSDOF1"]``).
    p : dict
        The template's parameter symbols by name (:func:`parameter_defaults` names).

    Returns
    -------
    (Ke, De, mass_scale)
        ``Ke``, ``De`` (n × n SX) [N/m], [N s/m]; ``mass_scale = AdjTwMa / AdjTwMa_deck``
        (the shape integrals are built with the deck's AdjTwMa).
    """
    unit = _unit_tower(turbine)
    families = {"FA": (unit.fa_stiffness, unit.fa_mass, "fa"), "SS": (unit.ss_stiffness, unit.ss_mass, "ss")}
    n = len(active)
    K, C = ca.SX.zeros(n, n), ca.SX.zeros(n, n)
    for fam, (k_hat, m_hat, tag) in families.items():
        idx = [a for a, f in enumerate(active) if f.startswith(f"Tw{fam}")]
        modes = [int(active[a][-1]) - 1 for a in idx]
        if not idx:
            continue
        tuners = [p[f"tower_{tag}{m + 1}_stiffness_tuner"] for m in modes]
        ratios = [p[f"tower_{tag}{m + 1}_damping_ratio"] for m in modes]
        sub = np.ix_(modes, modes)
        Kf, Cf = _family_matrices(k_hat[sub], m_hat[modes], p[f"tower_{tag}_stiffness_factor"], tuners, ratios,
                                  p["tower_mass_factor"])
        for a, ia in enumerate(idx):
            for b, ib in enumerate(idx):
                K[ia, ib], C[ia, ib] = Kf[a, b], Cf[a, b]
    return K, C, p["tower_mass_factor"] / float(turbine.tower.mass_factor)


def blade_matrices(turbine: TurbineParameters, blade: int, flags: Sequence[str],
                   p: Mapping[str, ca.SX]) -> tuple[ca.SX, ca.SX] | None:
    """Blade stiffness and damping (shapes ``flags`` in body order), symbolic; None if not shared.

    ``flags`` from ``("FlapDOF1", "FlapDOF2", "EdgeDOF")``. Returns None when a needed
    parameter is absent from ``p`` (blades that differ: the numeric matrices apply).
    """
    from .elastodyn_bodies import blade_elastodyn_data

    names = {"FlapDOF1": ("blade_flap1_stiffness_tuner", "blade_flap1_damping_ratio"),
             "FlapDOF2": ("blade_flap2_stiffness_tuner", "blade_flap2_damping_ratio"),
             "EdgeDOF": (None, "blade_edge_damping_ratio")}
    needed = [n for f in flags for n in names[f] if n is not None]
    if any(n not in p for n in needed):
        return None
    b = turbine.blades[blade]
    unit_blade = dataclasses.replace(b, flap_stiffness_tuner=np.ones(2))
    d = blade_elastodyn_data(dataclasses.replace(turbine, blades=tuple(
        unit_blade if k == blade else x for k, x in enumerate(turbine.blades))), blade)
    n = len(flags)
    K, C = ca.SX.zeros(n, n), ca.SX.zeros(n, n)
    flap = [a for a, f in enumerate(flags) if f.startswith("Flap")]
    if flap:
        modes = [int(flags[a][-1]) - 1 for a in flap]
        sub = np.ix_(modes, modes)
        Kf, Cf = _family_matrices(d.flap_stiffness[sub], (d.flap_mass - d.tip_mass)[modes], 1.0,
                                  [p[names[flags[a]][0]] for a in flap], [p[names[flags[a]][1]] for a in flap], 1.0)
        for a, ia in enumerate(flap):
            for c, ic in enumerate(flap):
                K[ia, ic], C[ia, ic] = Kf[a, c], Cf[a, c]
    if "EdgeDOF" in flags:
        e = flags.index("EdgeDOF")
        Ke, Ce = _family_matrices(d.edge_stiffness, d.edge_mass - d.tip_mass, 1.0, [1.0],
                                  [p["blade_edge_damping_ratio"]], 1.0)
        K[e, e], C[e, e] = Ke[0, 0], Ce[0, 0]
    return K, C


def resolve(parameter_names: Sequence[str], key: str, *, dofs: Mapping[str, bool] | None = None) -> NamedParameter:
    """The entry of ``key`` if the model (its ``parameter_names``) has it.

    ``dofs`` (the model's enabled flags) makes the message say why a key is absent.

    Raises
    ------
    ParameterError
        Unknown key, or a key the model does not have (says which DOF enables it).
    """
    e = lookup(key)
    if e.name not in parameter_names:
        enabled = dofs is not None and any(dofs.get(f) for f in e.requires)
        if e.requires and not enabled:
            why = f"enable one of the DOFs {list(e.requires)}"
        elif e.key[:3] in ("FlS", "Bld"):
            why = "the deck's blades have different values, so it stays numeric per blade"
        else:
            why = "this model does not have it"
        raise ParameterError(f"{key!r} ({e.name}) is not a parameter of this model: {why}. "
                             f"Its parameters are {list(parameter_names)}.")
    return e


def parameter_table() -> str:
    """The mapping as a Markdown table (key, name, unit of the key, factor, where it enters).

    Examples
    --------
    >>> print(parameter_table().splitlines()[2])
    | Gravity | gravity | m/s^2 | 1 | gravity field | always |
    """
    rows = ["| key | name | unit (key) | key / value | enters | present when |", "|---|---|---|---|---|---|"]
    for e in NAMED_PARAMETERS.values():
        when = "any of " + ", ".join(e.requires) if e.requires else "always"
        rows.append(f"| {e.key} | {e.name} | {e.unit} | {e.factor:g} | {e.enters} | {when} |")
    return "\n".join(rows)
