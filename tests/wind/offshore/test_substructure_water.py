"""HydroDyn's Morison loads on a bottom-fixed SubDyn substructure (mbsym.wind.offshore.substructure_water).

Reference: OpenFAST v5.0.0 with every ElastoDyn DOF off (the structure held undisplaced) on the rosco 2.10.6 IEA 15 MW
monopile deck and three HydroDyn variants of it, in still water and in the deck's JONSWAP sea
(``tests/data/openfast_subdyn_water``, see its README): HydroDyn's ``HydroFxi … HydroMzi`` (the Morison loads summed
about the origin), SubDyn's interface loads ``Intf1F*ss`` (``−Y1 = −Φ_TPᵀ (F_g + F_ext)`` at rest) and base reactions
``React*ss``.

Measured (each channel's largest |difference| over its largest |value|): still water ≤ 5e-8 (HydroDyn's sums,
interface and base loads); waves ≤ 5.6e-7 on every channel of the four variants (OpenFAST prints 8 digits; SeaState
holds its kinematics in single precision). The tests allow 2e-7 (still) and 1.5e-6 (waves), plus 0.05 N or N m on
channels that are zero.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning, UnsupportedFeatureError
from mbsym.wind.deck.hydrodyn import HydroDynTable, read_hydrodyn
from mbsym.wind.deck.seastate import read_seastate
from mbsym.wind.deck.subdyn import read_subdyn
from mbsym.wind.offshore.frame_fem import rigid_transform
from mbsym.wind.offshore.substructure import Substructure
from mbsym.wind.offshore.substructure_water import rest_reactions, substructure_hydrodynamics

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_subdyn_water"
RHO, G, DEPTH = 1025.0, 9.81, 30.0
CHANNELS = ("FX", "FY", "FZ", "MX", "MY", "MZ")
R, R_IN = 5.0, 5.0 - 0.055341          # the deck's member: D 10 m, thickness 0.055341 m


@pytest.fixture(scope="module")
def sub():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Substructure(read_subdyn(DATA / "SubDyn.dat"), reference_point=(0.0, 0.0, 15.0), gravity=G,
                            water_depth=DEPTH)


_BUILT: dict = {}


def _water(sub, variant: str, sea: str):
    key = (variant, sea)
    if key not in _BUILT:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            _BUILT[key] = substructure_hydrodynamics(read_hydrodyn(DATA / f"{variant}_HydroDyn.dat"),
                                                     read_seastate(DATA / f"{sea}_SeaState.dat"), sub,
                                                     water_density=RHO, gravity=G, water_depth=DEPTH)
    return _BUILT[key]


def _case(variant: str, sea: str) -> str:
    return sea if variant == "monopile" else f"{variant}_{sea}"


def _compare(ours: np.ndarray, theirs: np.ndarray, rel: float, what: str) -> None:
    scale = np.abs(theirs).max(axis=0)
    error = np.abs(ours - theirs).max(axis=0)
    assert np.all(error <= rel * scale + 0.05), f"{what}: {error} vs {scale}"


def _check_against_openfast(sub, variant: str, sea: str, rel: float) -> None:
    water = _water(sub, variant, sea)
    data = np.genfromtxt(DATA / f"{_case(variant, sea)}.csv", delimiter=",", names=True)
    t = data["Time"]
    loads = water.static_loads + (water.wave_loads(t) if water.waves is not None else np.zeros((len(t), 1)))
    hydro = np.column_stack([data[f"Hydro{c[0]}{c[1].lower()}i"] for c in CHANNELS])
    _compare(water.resultant(loads), hydro, rel, "HydroDyn's sum about the origin")
    reduced = sub.guyan()
    tp = water.tp_static_load + reduced.gravity_load + (water.tp_wave_loads(t) if water.waves is not None else 0.0)
    interface = -np.column_stack([data[f"Intf1{c}ss"] for c in CHANNELS])
    _compare(np.broadcast_to(tp, interface.shape), interface, rel, "SubDyn's interface load")
    y1 = reduced.tp_loads(np.zeros(6), np.zeros(6), np.zeros(6), nodal_loads=loads[len(t) // 2])[0]
    assert np.allclose(y1, np.broadcast_to(tp, interface.shape)[len(t) // 2], rtol=0, atol=1e-6 * np.abs(y1).max())
    reaction = np.column_stack([data[f"React{c}ss"] for c in CHANNELS])
    _compare(rest_reactions(sub, loads), reaction, rel, "SubDyn's base reaction")


@pytest.mark.parametrize("variant", ["monopile", "raised", "cone", "cone_cut"])
def test_still_water_loads_are_openfasts(sub, variant):
    """The static loads: HydroDyn's sum about the origin, SubDyn's TP load Φ_TPᵀ(F_g + F_ext) and base reaction."""
    _check_against_openfast(sub, variant, "still", 2e-7)


@pytest.mark.parametrize("variant", ["monopile", "raised", "cone", "cone_cut"])
def test_wave_loads_are_openfasts(sub, variant):
    """100 s of the deck's JONSWAP sea, every 0.2 s (monopile, cone: mostly between SeaState's 0.25 s samples) or
    1 s (raised, cone_cut)."""
    _check_against_openfast(sub, variant, "waves", 1.5e-6)


def test_monopile_cut_by_the_seabed_has_no_buoyancy_and_a_weightless_fill(sub):
    """The deck's pile reaches 0.1 m below the seabed: no bottom plate, so no buoyancy (a vertical cylinder's sides
    carry none); its fluid, open to the sea, weighs nothing net but for HydroDyn's pressure on the cut element's part
    below the seabed, ρ g π r_in² · 0.1 m upward."""
    water = _water(sub, "monopile", "still")
    assert np.allclose(water.resultant(water.parts["buoyancy"]), 0.0, atol=1e-6)
    assert np.allclose(water.resultant(water.parts["growth"]), 0.0)
    fill = water.resultant(water.parts["fill"])
    assert fill[2] == pytest.approx(RHO * G * math.pi * R_IN ** 2 * 0.1, rel=1e-9)
    assert np.allclose(fill[[0, 1, 3, 4, 5]], 0.0, atol=1e-6)


def test_buoyancy_and_filled_weight_closed_forms(sub):
    """HydroDyn's joint 1 raised to −29 m: the bottom plate carries Archimedes' ρ g π R² · 29 m, the closed fluid
    column weighs ρ g π r_in² · 29 m (filled to the still-water level), both on the axis."""
    water = _water(sub, "raised", "still")
    buoyancy, fill = (water.resultant(water.parts[k]) for k in ("buoyancy", "fill"))
    assert buoyancy[2] == pytest.approx(RHO * G * math.pi * R ** 2 * 29.0, rel=1e-12)
    assert fill[2] == pytest.approx(-RHO * G * math.pi * R_IN ** 2 * 29.0, rel=1e-12)
    assert np.allclose(np.r_[buoyancy[[0, 1, 3, 4, 5]], fill[[0, 1, 3, 4, 5]]], 0.0, atol=1e-6)


def _rigid_mass(water, point=(0.0, 0.0, 0.0)) -> np.ndarray:
    t = np.vstack([rigid_transform(p - np.asarray(point)) for p in water.positions])
    return t.T @ water.added_mass @ t


def test_added_mass_closed_form(sub):
    """Per metre from the seabed to the still-water level: ρ π R² C_a (C_a = 1) across the axis and the fluid
    ρ π r_in² in every direction; as a rigid body about the origin the pitch moment per surge acceleration is
    ∫ m′ z dz (the reverse term takes the strips' acceleration at their nodes: 1.4e-5 off)."""
    water = _water(sub, "monopile", "still")
    rigid = _rigid_mass(water)
    across, fluid = RHO * math.pi * R ** 2, RHO * math.pi * R_IN ** 2
    assert rigid[0, 0] == pytest.approx((across + fluid) * 30.0, rel=1e-12)
    assert rigid[1, 1] == pytest.approx((across + fluid) * 30.0, rel=1e-12)
    assert rigid[2, 2] == pytest.approx(fluid * 30.0, rel=1e-12)
    assert rigid[4, 0] == pytest.approx(-(across + fluid) * 450.0, rel=1e-12)     # ∫₋₃₀⁰ m′ z dz
    assert rigid[0, 4] == pytest.approx(rigid[4, 0], rel=3e-5)
    tp = water.tp_added_mass()
    assert np.abs(tp - tp.T).max() <= 2e-5 * np.abs(tp).max()                       # measured 1.0e-5
    assert np.all(np.linalg.eigvalsh(water.tp_added_mass(symmetric=True))[[1, 2, 3, 4, 5]] > 0)


def test_damping_at_rest_and_drag_slope(sub):
    """Quadratic drag: no damping at rest in still water; the drag's mean slope about the wave velocity is
    symmetric, non-negative and along the waves (x) twice the cross-wave one."""
    assert not np.any(_water(sub, "monopile", "still").still_water_damping)
    assert not np.any(_water(sub, "monopile", "still").drag_damping())
    water = _water(sub, "monopile", "waves")
    b = water.tp_drag_damping()
    assert np.allclose(b, b.T, rtol=0, atol=1e-3 * np.abs(b).max())
    assert np.linalg.eigvalsh(0.5 * (b + b.T)).min() >= -1e-9 * np.abs(b).max()
    assert b[0, 0] == pytest.approx(2.0 * b[1, 1], rel=1e-9)


def test_wave_terms_and_time_grid(sub):
    """The waves' loads are inertia-dominated here (drag ~4 % RMS); on SeaState's grid no interpolation."""
    water = _water(sub, "monopile", "waves")
    t = water.times()[:401]
    total = water.tp_wave_loads(t)
    parts = water.tp_wave_loads(t, drag=False) + water.tp_wave_loads(t, inertia=False)
    assert np.allclose(total, parts, rtol=0, atol=1e-6 * np.abs(total).max())
    assert np.allclose(water.wave_loads()[:401], water.wave_loads(t), rtol=0, atol=1e-6 * np.abs(total).max())
    drag = water.tp_wave_loads(t, inertia=False)
    assert 0.01 < np.sqrt(np.mean(drag[:, 0] ** 2) / np.mean(total[:, 0] ** 2)) < 0.1


def test_flipped_member_warns(sub):
    """A member written from its upper joint: HydroDyn gives its end plates the other end's radius and growth."""
    with pytest.warns(ModelWarning, match="other end"):
        substructure_hydrodynamics(read_hydrodyn(DATA / "cone_HydroDyn.dat"), None, sub, water_density=RHO,
                                   gravity=G, water_depth=DEPTH)


def _with_row(hd, table: str, column: int, value, rows=(0,)):
    old = hd.tables[table]
    new = [list(r) for r in old.rows]
    for k in rows:
        new[k][column] = value
    tables = dict(hd.tables) | {table: HydroDynTable(old.columns, tuple(tuple(r) for r in new), old.lines)}
    return dataclasses.replace(hd, tables=tables)


@pytest.mark.parametrize("edit, match", [
    (lambda hd, sea: (dataclasses.replace(hd, potential_model=1), sea), r"line 5, key 'PotMod'"),
    (lambda hd, sea: (_with_row(hd, "members", 5, 2), sea), r"line 110, member 1: MSecGeom = 2"),
    (lambda hd, sea: (_with_row(hd, "members", 8, 4), sea), r"MCoefMod = 4"),
    (lambda hd, sea: (_with_row(hd, "members", 9, 2), sea), r"MHstLMod = 2"),
    (lambda hd, sea: (_with_row(hd, "members", 10, True), sea), r"PropPot = TRUE"),
    (lambda hd, sea: (_with_row(hd, "axial_coefficients", 5, 0.1), sea), r"AxVnCOff"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, stretching_model=1)), r"line 17, key 'WaveStMod'"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, current_model=2)), r"key 'CurrMod': CurrMod = 2"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, current_model=1, wave_current_model=1)), r"key 'WvCrntMod'"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, sum_qtf=True)), r"key 'WvSumQTF'"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, maccamy_fuchs_radius=10.0)), r"key 'MCFD'"),
    (lambda hd, sea: (hd, dataclasses.replace(sea, msl_to_swl=1.0)), r"key 'MSL2SWL'"),
    (lambda hd, sea: (_with_row(hd, "joints", 1, 12.0, rows=(0, 1)), sea), r"member 1: its node .* SubDyn's frame"),
])
def test_refusals(sub, edit, match):
    """What is not modelled is refused, naming the file, line and key."""
    hd, sea = edit(read_hydrodyn(DATA / "monopile_HydroDyn.dat"), read_seastate(DATA / "waves_SeaState.dat"))
    with pytest.raises(UnsupportedFeatureError, match=match):
        substructure_hydrodynamics(hd, sea, sub, water_density=RHO, gravity=G, water_depth=DEPTH)
