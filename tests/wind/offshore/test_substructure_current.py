"""SeaState's steady current on HydroDyn's members over a SubDyn substructure (mbsym.wind.offshore.substructure_current,
substructure_water, bottom_fixed).

References:
- OpenFAST v5.0.0 on the rosco 2.10.6 IEA 15 MW monopile deck with a current (CurrSSV0 0.8 m/s along x, CurrNSV0
  0.5 m/s at 45 deg, CurrDIV 0.2 m/s at -90 deg; tests/data/openfast_subdyn_current/README.md): the structure held
  (every ElastoDyn DOF off) in still water and in the deck's JONSWAP sea — HydroDyn's HydroFxi … HydroMzi, SubDyn's
  Intf1*ss and React*ss; measured (largest |Δ| over each channel's largest |value|) ≤ 1.3e-6 (1.1e-7 but for
  Intf1MXss, a 1.7 kN m channel: 2e-3 N m) in still water, ≤ 1.0e-6 in waves. The tests allow 2e-7 / 1.5e-6 plus
  0.05 N or N m, as tests/wind/offshore/test_substructure_water.py does without a current;
- closed forms: a uniform current U on the vertical pile (D 10 m, C_d 1, 30 m wet): the drag ½ ρ C_d D U² · 30 m
  at mid-depth, and the damping of a rigid surge along the current ρ C_d D |U| · 30 m, across it half that;
- slow: the released structure (TTDspFA 1 m, TTDspSS 0.5 m) in still water and in waves with the current, 0-30 s
  against OpenFAST's (ε = mean|Δ|/range; measured over 60 s in README.md).
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelWarning
from mbsym.wind.deck.hydrodyn import read_hydrodyn
from mbsym.wind.deck.seastate import read_seastate
from mbsym.wind.deck.subdyn import read_subdyn
from mbsym.wind.offshore.current import current_at, sea_current
from mbsym.wind.offshore.frame_fem import rigid_transform
from mbsym.wind.offshore.substructure import Substructure
from mbsym.wind.offshore.substructure_current import grid_current
from mbsym.wind.offshore.substructure_water import rest_reactions, substructure_hydrodynamics

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_subdyn_current"
RHO, G, DEPTH, D, CD = 1025.0, 9.81, 30.0, 10.0, 1.0
CHANNELS = ("FX", "FY", "FZ", "MX", "MY", "MZ")
_BUILT: dict = {}


def _sub() -> Substructure:
    if "sub" not in _BUILT:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            _BUILT["sub"] = Substructure(read_subdyn(DATA / "held_still_SubDyn.dat"), reference_point=(0.0, 0.0, 15.0),
                                         gravity=G, water_depth=DEPTH)
    return _BUILT["sub"]


def _water(case: str, **sea_edits):
    key = (case, tuple(sorted(sea_edits.items())))
    if key not in _BUILT:
        sea = dataclasses.replace(read_seastate(DATA / f"{case}_SeaState.dat"), **sea_edits)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ModelWarning)
            _BUILT[key] = substructure_hydrodynamics(read_hydrodyn(DATA / f"{case}_HydroDyn.dat"), sea, _sub(),
                                                     water_density=RHO, gravity=G, water_depth=DEPTH)
    return _BUILT[key]


def _compare(ours: np.ndarray, theirs: np.ndarray, rel: float, what: str) -> None:
    scale = np.abs(theirs).max(axis=0)
    error = np.abs(ours - theirs).max(axis=0)
    assert np.all(error <= rel * scale + 0.05), f"{what}: {error} vs {scale}"


@pytest.mark.parametrize("case, rel", [("held_still", 2e-7), ("held_waves", 1.5e-6)])
def test_held_structure_in_a_current_is_openfasts(case, rel):
    """HydroDyn's sum about the origin, SubDyn's TP load Φ_TPᵀ(F_g + F_ext) and base reactions with the current's
    drag (still water: a constant load; waves: the drag of the sum, every 0.5 s of 100 s)."""
    water, sub = _water(case), _sub()
    data = np.genfromtxt(DATA / f"{case}.csv", delimiter=",", names=True)
    t = data["Time"]
    loads = water.static_loads + (water.wave_loads(t) if water.waves is not None else np.zeros((len(t), 1)))
    hydro = np.column_stack([data[f"Hydro{c[0]}{c[1].lower()}i"] for c in CHANNELS])
    _compare(water.resultant(loads), hydro, rel, "HydroDyn's sum about the origin")
    tp = water.tp_static_load + sub.guyan().gravity_load + (water.tp_wave_loads(t) if water.waves is not None else 0.0)
    _compare(np.broadcast_to(tp, (len(t), 6)), -np.column_stack([data[f"Intf1{c}ss"] for c in CHANNELS]), rel,
             "SubDyn's interface load")
    _compare(rest_reactions(sub, loads), np.column_stack([data[f"React{c}ss"] for c in CHANNELS]), rel,
             "SubDyn's base reaction")


def test_current_drag_is_a_static_part_and_the_waves_share_excludes_it():
    """In still water the current's drag is ``parts['current']`` of the static loads (108 kN along x); in waves the
    waves' loads are the drag of the sum less that part, so their mean is not zero (the drag is not linear)."""
    still, waves = _water("held_still"), _water("held_waves")
    drag = still.resultant(still.parts["current"])
    assert drag[0] == pytest.approx(108420.8, rel=1e-6) and drag[2] == 0.0
    assert np.allclose(waves.parts["current"], still.parts["current"])
    mean = waves.resultant(waves.wave_loads(waves.times()[:4000], inertia=False)).mean(axis=0)
    assert mean[0] > 0.05 * drag[0]
    calm = _water("held_waves", current_model=0)
    assert np.allclose(calm.resultant(calm.wave_loads(calm.times()[:4000], inertia=False)).mean(axis=0)[0], 0.0,
                       atol=0.02 * drag[0])


def _rigid(water, matrix) -> np.ndarray:
    t = np.vstack([rigid_transform(p) for p in water.positions])
    return t.T @ matrix @ t


def test_uniform_current_closed_forms():
    """A depth-independent current U = 0.2 m/s along −y on the pile (30 m wet from the seabed, D 10 m, C_d 1): the
    drag ½ ρ C_d D U² · 30 m at mid-depth (OpenFAST: 6150.0005 N, −92250.008 N m), the rigid-body damping
    ρ C_d D |U| · 30 m along the current and half across (rel. 1e-12); no damping without a current."""
    edits = dict(current_subsurface_speed=0.0, current_near_surface_speed=0.0)
    water = _water("held_still", **edits)
    drag = water.resultant(water.parts["current"])
    force = 0.5 * RHO * CD * D * 0.2 ** 2 * DEPTH
    assert drag[1] == pytest.approx(-force, rel=1e-12)
    assert drag[3] == pytest.approx(-15.0 * force, rel=1e-12)                      # −z F_y at z = −15 m
    assert np.allclose(drag[[0, 2, 4, 5]], 0.0, atol=1e-6)
    b = _rigid(water, water.drag_damping())
    assert b[1, 1] == pytest.approx(RHO * CD * D * 0.2 * DEPTH, rel=1e-12)
    assert b[0, 0] == pytest.approx(0.5 * b[1, 1], rel=1e-12)
    assert b[3, 1] == pytest.approx(15.0 * b[1, 1], rel=1e-12)                      # at mid-depth
    assert not np.any(_water("held_still", current_model=0).drag_damping())


def test_grid_current_in_single_precision():
    """SeaState's grid heights are single precision: the bottom node sits at −Z_Depth exactly and its sub-surface
    current is zero (in double precision it would be 0.0053 CurrSSV0); current_at reads the grid so (.current), and
    grid_current is current_at."""
    sea = read_seastate(DATA / "held_still_SeaState.dat")
    current = sea_current(sea, DEPTH)
    bottom = -(1.0 - math.cos(math.pi / 2)) * DEPTH
    assert current.velocity(bottom)[0, 0] == pytest.approx(0.8 * ((bottom + DEPTH) / DEPTH) ** (1 / 7), rel=1e-9)
    assert current.velocity(bottom)[0, 0] > 0.005 * 0.8
    points = np.array([[0.0, 0.0, z] for z in (bottom, -29.6, -20.0, -5.0, 0.0)])
    single, double = grid_current(sea, DEPTH, points), current_at(current, sea, points)
    assert single[0, 0] == pytest.approx(0.0, abs=1e-9) and single[0, 1] == pytest.approx(-0.2, rel=1e-6)
    assert np.array_equal(single, double)


def test_platform_damping_from_the_current():
    """On the platform DOFs the current's drag slope is a damping of SubDyn's TP load, ``Y1(u̇) − Y1(0) =
    −Φ_TPᵀ B Φ_TP u̇`` (rel. 1e-9), positive semi-definite and symmetric within 5e-4 (measured 2.4e-4: HydroDyn's
    strip moments act at the strips' centroids, their velocity is the node's, as with the added mass); with CB
    modes the modes' equation gets ``−Φ_mᵀ B Φ_TP u̇`` (through N⁻¹)."""
    from mbsym.wind.offshore.bottom_fixed import BottomFixedPlatform, _base_reaction, _water_terms

    water = _water("held_still")
    for name in ("held_still_SubDyn.dat", "monopile_cb.dat"):
        folder = DATA if name.startswith("held") else DATA.parent / "openfast_subdyn"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sub = Substructure(read_subdyn(folder / name), reference_point=(0.0, 0.0, 15.0), gravity=G,
                               water_depth=DEPTH)
            water = substructure_hydrodynamics(read_hydrodyn(DATA / "held_still_HydroDyn.dat"),
                                               read_seastate(DATA / "held_still_SeaState.dat"), sub,
                                               water_density=RHO, gravity=G, water_depth=DEPTH)
        reduced = sub.reduce()
        R, r0, R_m = _base_reaction(sub, water.static_loads)
        platform = BottomFixedPlatform(reduced, R, r0, water=water, substructure=sub,
                                       water_terms=_water_terms(sub, reduced, water), modal_reaction=R_m)
        b = platform.water_terms["damping"]
        assert np.allclose(b, reduced.tp_shapes.T @ water.drag_damping() @ reduced.tp_shapes)
        assert np.allclose(b, b.T, rtol=0, atol=5e-4 * np.abs(b).max())
        assert np.linalg.eigvalsh(0.5 * (b + b.T)).min() >= -1e-9 * np.abs(b).max()
        ud = np.array([0.1, -0.05, 0.0, 0.002, 0.004, 0.0])
        rest, moving = (platform.loads(np.zeros(6), v) for v in (np.zeros(6), ud))
        change = np.array(moving["load"]).ravel() - np.array(rest["load"]).ravel()
        if not platform.n_modes:
            assert np.allclose(change, -b @ ud, rtol=0, atol=1e-9 * np.abs(b @ ud).max())
        else:
            n = platform.n_modes
            qdd = np.array(moving["xr_dot"]).ravel()[n:] - np.array(rest["xr_dot"]).ravel()[n:]
            expected = -platform.modal["N_inv"] @ platform.water_terms["B_mB"] @ ud
            assert np.allclose(qdd, expected, rtol=1e-9, atol=1e-12)
            assert np.abs(expected).max() > 0


# --- the released structure (slow) ------------------------------------------------------------------------------

def _reference():
    spec = importlib.util.spec_from_file_location("_current_reference", DATA / "make_reference.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _released_deck(tmp_path: Path, case: str) -> Path:
    """The wheel's deck brought to v5's format with the reference case's files (README.md), or skip."""
    reference = _reference()
    if not (reference.DECK / "IEA-15-240-RWT").is_dir():
        pytest.skip("the ROSCO 2.10.6 wheel's deck is not cached")
    run = reference.prepare(reference.DECK, tmp_path)
    return reference.case_files(run, case)


def _released(tmp_path: Path, case: str, t_end: float, tolerances: dict[str, float]) -> None:
    from mbsym import simulate
    from mbsym.wind import read_openfast
    from mbsym.wind.offshore.floating import floating_structure

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = floating_structure(read_openfast(_released_deck(tmp_path, case)))
    assert "damping" in model.platform.water_terms
    data = np.genfromtxt(DATA / f"{case}.csv", delimiter=",", names=True)
    t = data["Time"][data["Time"] <= t_end + 1e-9]
    inputs = model.sea_tables(t_end) if model.platform.waves is not None else {}
    res = simulate(model.dynamics(), t_end, t_out=t, method="cvodes", rtol=1e-8, atol=1e-10,
                   **({"inputs": inputs} if inputs else {}))
    names = list(res.output_names)
    for channel, tol in tolerances.items():
        y, ref = np.asarray(res.y)[:, names.index(channel)], data[channel][:len(t)]
        eps = np.mean(np.abs(y - ref)) / np.ptp(ref)
        assert eps <= tol, (channel, eps)


@pytest.mark.slow
def test_released_in_a_current_against_openfast(tmp_path):
    """Still water with the current: the structure oscillates about the current's mean offset, damped by the drag's
    slope; over 0-30 s the TP surge, sway, roll, pitch within ε ≤ 0.15 % and the base moments ≤ 0.3 % of OpenFAST's
    (measured over 60 s: 0.01-0.05 %, 0.05-0.11 %; without the damping term 0.08-0.09 %, 0.11-0.16 %)."""
    tolerances = {c: 1.5e-3 for c in ("PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch")}
    _released(tmp_path, "decay", 30.0, tolerances | {"ReactMXss": 3e-3, "ReactMYss": 3e-3})


@pytest.mark.slow
def test_released_in_waves_and_a_current_against_openfast(tmp_path):
    """The deck's JONSWAP sea with the current (the waves' loads the drag of the sum, the damping the drag's mean
    slope about it): over 0-30 s within ε ≤ 0.15 % (base moments 0.3 %) of OpenFAST's (measured over 60 s:
    0.02-0.05 %, 0.05-0.11 %; without the damping term 0.09-0.10 %, 0.12-0.16 %)."""
    tolerances = {c: 1.5e-3 for c in ("PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch", "Wave1Elev")}
    _released(tmp_path, "wdecay", 30.0, tolerances | {"ReactMXss": 3e-3, "ReactMYss": 3e-3})
