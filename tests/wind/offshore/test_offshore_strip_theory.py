"""Buoyancy, added mass and wave inertia of strip-theory members (mbsym.wind.offshore.strip_theory; issue 20, item 2).

References, each independent of the code under test:
- closed forms: Archimedes' force ``ρ g V`` of a submerged cylinder and of a frustum (``π L (r₁² + r₁r₂ + r₂²)/3``)
  through the volume's centroid, turning with the platform; a cylinder's transverse added mass ``ρ C_a π R² L`` and
  its two end plates' axial ``2 ρ C_{a,ax} (2π/3) R³``; the Froude–Krylov force of a uniformly accelerating flow on
  a closed body, ``ρ V a`` (its pressure ``−ρ a·x``), which only the side and end-plate terms together give;
- an invariant: with ``C_p = 0`` the wave inertia of a uniform acceleration ``a`` equals the added-mass force of the
  body accelerating by ``−a`` (the diffraction and added-mass terms share ``C_a``);
- OpenFAST v5.0.0 free decays of the shared ``fl_decay_a`` with three submerged strip-theory members added
  (``strip`` of test_offshore_morison.write_deck and more; tests/data/openfast_morison/README.md): the members
  change OpenFAST's own decay by ε 3.5 % (heave) to 53 % (roll); mbsym's ε 0.3–1.3 % on surge, heave, roll and
  pitch (measured): bound 1.5 %, as for the drag-only members.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mbsym.exceptions import UnsupportedFeatureError
from mbsym.wind.deck.hydrodyn import read_hydrodyn
from mbsym.wind.offshore.strip_theory import StripTheory, _joints, _member, strip_problems, strip_theory

from .test_offshore_morison import _reference, needs_deck, write_deck

RHO, G = 1025.0, 9.80665


def _simple(ca=1.0, cp=1.0, axca=1.0, axcp=1.0, cb=1.0):
    return lambda s, z, mg: {"Cd": 0 * s, "Ca": ca + 0 * s, "Cp": cp + 0 * s, "AxCd": 0 * s, "AxCa": axca + 0 * s,
                             "AxCp": axcp + 0 * s, "Cb": cb + 0 * s}


def _strip(parts: list[dict], ends: dict, joints: dict, axial: dict) -> StripTheory:
    """A StripTheory from members built by ``_member`` and their joints, as strip_theory assembles them."""
    joint = _joints(ends, joints, axial, np.zeros(3), RHO)
    volume = sum(p["volume"] for p in parts)
    centroid = sum(p["volume"] * p["centroid"] for p in parts) / volume
    cat = {k: np.concatenate([p[k] for p in parts] + [joint[k]]) for k in ("points", "axis", "offset", "inertia",
                                                                          "pressure")}
    return StripTheory(volume, centroid, sum(p["added_mass"] for p in parts) + joint["added_mass"], **cat,
                       water_density=RHO, gravity=G)


def _cylinder(p1, p2, r1, r2, div=1.0, coefficients=None, axca=1.0, axcp=1.0):
    p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
    part = _member(p1, p2, r1, r2, div, coefficients or _simple(axca=axca, axcp=axcp), True, RHO)
    k = (p2 - p1) / np.linalg.norm(p2 - p1)
    return _strip([part], {1: [(-k, r1, 0.0, 0.0)], 2: [(k, r2, 0.0, 0.0)]}, {1: (p1, 2), 2: (p2, 2)},
                  {2: (2, 0.0, axca, axcp, 0, 0.0, 1.0)})


def test_buoyancy_of_a_cylinder_and_a_frustum_through_their_centroids():
    """ρ g V through the volume's centroid, displaced with the platform (a closed form per shape)."""
    cyl = _cylinder((-10, 5, -20), (10, 5, -20), 1.5, 1.5)
    assert cyl.volume == pytest.approx(math.pi * 1.5 ** 2 * 20)
    assert np.allclose(cyl.centroid, (0, 5, -20))
    frustum = _cylinder((0, 0, -30), (0, 0, -10), 2.0, 1.0)
    assert frustum.volume == pytest.approx(math.pi * 20 * (4 + 2 + 1) / 3)
    z_bar = -30 + 20 * (4 + 2 * 2 + 3 * 1) / (4 * (4 + 2 + 1))            # a frustum's centroid from its base
    assert frustum.centroid[2] == pytest.approx(z_bar)
    q = np.array([1.0, 2.0, 0.5, 0.03, -0.05, 0.1])
    load = cyl.load(q)
    from mbsym.wind.offshore._casadi import euler_zyx

    arm = np.array(euler_zyx(q[3:6])) @ cyl.centroid
    force = np.array([0, 0, RHO * G * cyl.volume])
    assert np.allclose(load[:3], force) and np.allclose(load[3:], np.cross(arm, force), rtol=1e-12)


def test_added_mass_of_a_cylinder_with_its_end_plates():
    """Transverse ``ρ C_a π R² L`` (C_a = 1), axial ``2 ρ C_{a,ax} (2π/3) R³`` from the two end plates, and the
    moments of the transverse part about a reference below the member."""
    R, L, z = 1.5, 20.0, -20.0
    cyl = _cylinder((-10, 0, z), (10, 0, z), R, R, axca=0.7)
    A = cyl.added_mass
    transverse = RHO * math.pi * R ** 2 * L
    assert A[1, 1] == pytest.approx(transverse) and A[2, 2] == pytest.approx(transverse)
    assert A[0, 0] == pytest.approx(2 * RHO * 0.7 * 2 * math.pi / 3 * R ** 3)
    assert A[1, 3] == pytest.approx(-z * transverse)           # sway acceleration → roll moment of a force at z
    assert A[3, 3] == pytest.approx(z ** 2 * transverse)        # roll about the reference point
    assert A[5, 5] == pytest.approx(transverse * L ** 2 / 12, rel=0.01)     # yaw: the strips' lumping, 1 m apart
    sym = 0.5 * (A + A.T)
    assert np.min(np.linalg.eigvalsh(sym)) > -1e-6 * np.max(np.abs(A))


def test_froude_krylov_force_of_a_uniform_acceleration_is_rho_v_a():
    """A uniformly accelerating flow's pressure ``−ρ a·x`` and acceleration on a closed tapered inclined member:
    the sides' ``C_p`` and taper terms and the end plates' ``C_{p,ax}`` give ``ρ V a`` together (C_a = 0)."""
    strip = _cylinder((-8, 3, -30), (6, -4, -12), 2.0, 1.2, div=0.25,
                      coefficients=_simple(ca=0.0, cp=1.0, axca=0.0, axcp=1.0), axca=0.0, axcp=1.0)
    a = np.array([0.3, -0.2, 0.5])
    points = strip.wave_points()
    terms = strip.wave_terms(np.tile(a, (1, len(points), 1)), -RHO * (points @ a)[None, :])
    volume = math.pi * np.linalg.norm([14, -7, 18]) * (4 + 2.4 + 1.44) / 3
    assert np.allclose(terms[0, :3], RHO * volume * a, rtol=1e-4)       # the strips' lumping of the taper: 1e-5


def test_diffraction_equals_added_mass_reaction():
    """With C_p = 0 the wave inertia of a uniform acceleration is the added-mass force of the body accelerating
    the other way: F = −(−A a) (the same C_a in both, sides and end plates)."""
    strip = _cylinder((-10, 5, -25), (8, -3, -15), 1.5, 1.0, coefficients=_simple(ca=0.8, cp=0.0, axca=0.6, axcp=0.0),
                      axca=0.6, axcp=0.0)
    a = np.array([0.2, 0.4, -0.3])
    terms = strip.wave_terms(np.tile(a, (1, len(strip.points), 1)), np.zeros((1, len(strip.points))))
    assert np.allclose(terms[0, :3], strip.added_mass[:3, :3] @ a, rtol=1e-12)
    assert np.allclose(terms[0, 3:6], strip.added_mass[3:, :3] @ a, rtol=1e-12)


def test_wave_load_turns_the_moment_arms_with_the_platform():
    """The 15 terms give Σ (R p) × F + Σ (h k) × F exactly: against the sum over the points."""
    from mbsym.wind.offshore._casadi import euler_zyx

    strip = _cylinder((-10, 5, -25), (8, -3, -15), 1.5, 1.0)
    rng = np.random.default_rng(3)
    acc = rng.normal(size=(1, len(strip.points), 3))
    p = rng.normal(size=(1, len(strip.points))) * 1e3
    terms = strip.wave_terms(acc, p)
    q = np.array([0.0, 0.0, 0.0, 0.05, -0.08, 0.12])
    R = np.array(euler_zyx(q[3:6]))
    f = np.einsum("nij,nj->ni", strip.inertia, acc[0]) + p[0][:, None] * strip.pressure
    expected = sum(np.cross(R @ pt + h * k, fi) for pt, h, k, fi in zip(strip.points, strip.offset, strip.axis, f))
    assert np.allclose(strip.wave_load(q, terms[0])[3:], expected, rtol=1e-9)


def test_marine_growth_shell_and_plates_as_a_rigid_body():
    """Uniform growth t on a vertical cylinder (R, L, density ρ_MG): the shell's mass ``ρ_MG π ((R+t)² − R²) L``
    and its inertia (axial ``½ m (R_o² + R_i²)``, transverse ``¼ m (R_o² + R_i²) + m L²/12`` about its centre, moved
    to the reference point), two end plates of ``ρ_MG t π (R+t)²`` each; the weight at the displaced centroid."""
    R, t, rho_mg, L, x0 = 2.0, 0.1, 1100.0, 20.0, 7.0
    growth = [(0.0, t, rho_mg), (-100.0, t, rho_mg)]
    part = _member(np.array([x0, 0, -30.0]), np.array([x0, 0, -10.0]), R, R, 1.0, _simple(), True, RHO, 0.0, growth)
    shell = rho_mg * math.pi * ((R + t) ** 2 - R ** 2) * L
    assert part["growth_mass"] == pytest.approx(shell, rel=1e-12)
    assert np.allclose(part["growth_first"], shell * np.array([x0, 0, -20.0]))
    bare = _member(np.array([x0, 0, -30.0]), np.array([x0, 0, -10.0]), R, R, 1.0, _simple(), True, RHO)
    M = part["added_mass"] - bare["added_mass"] * ((R + t) / R) ** 2      # the grown radius' added mass taken out
    square = (R + t) ** 2 + R ** 2
    assert M[5, 5] == pytest.approx(0.5 * shell * square + shell * x0 ** 2, rel=1e-10)
    assert M[3, 3] == pytest.approx(0.25 * shell * square + shell * (L ** 2 / 12 + 20.0 ** 2), rel=1e-10)
    assert M[0, 0] == pytest.approx(shell, rel=1e-10) and M[2, 2] == pytest.approx(shell, rel=1e-10)
    k = np.array([0.0, 0.0, 1.0])
    plates = _joints({1: [(-k, R + t, t, rho_mg)], 2: [(k, R + t, t, rho_mg)]},
                     {1: (np.array([x0, 0, -30.0]), 2), 2: (np.array([x0, 0, -10.0]), 2)},
                     {2: (2, 0.0, 0.0, 0.0, 0, 0.0, 1.0)}, np.zeros(3), RHO)
    assert plates["growth_mass"] == pytest.approx(2 * rho_mg * t * math.pi * (R + t) ** 2)
    strip = StripTheory(0.0, np.zeros(3), np.zeros((6, 6)), np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0),
                        np.zeros((0, 3, 3)), np.zeros((0, 3)), RHO, G, growth_mass=shell,
                        growth_centroid=np.array([x0, 0, -20.0]))
    q = np.array([0, 0, 0, 0.0, 0.1, 0.0])
    from mbsym.wind.offshore._casadi import euler_zyx

    arm = np.array(euler_zyx(q[3:6])) @ np.array([x0, 0, -20.0])
    assert np.allclose(strip.load(q), np.r_[0, 0, -shell * G, np.cross(arm, [0, 0, -shell * G])])


@needs_deck
def test_unmodelled_strip_members_are_named(tmp_path):
    fst = write_deck(tmp_path, "strip")
    path = fst.parent / "fl_decay_a_HydroDyn.dat"
    assert strip_problems(read_hydrodyn(path)) == []
    text = path.read_text()
    piercing = path.with_name("piercing_HydroDyn.dat")          # the vertical member 3 up through the surface
    piercing.write_text(text.replace("-20 -20 -15  2  0", "-20 -20 5  2  0"))
    assert strip_problems(read_hydrodyn(piercing)) == []
    flat = path.with_name("flat_HydroDyn.dat")                  # member 1 rising 10 m over 60 m through it
    flat.write_text(text.replace("1  -30 20 -25  2  0", "1  -30 20 -5  2  0").replace("2  30 20 -25  2  0",
                                                                                          "2  30 20 5  2  0"))
    problems = strip_problems(read_hydrodyn(flat))
    assert len(problems) == 1 and "member 1" in problems[0] and "9.5 deg" in problems[0]
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    with pytest.raises(UnsupportedFeatureError, match="still-water level"):
        platform_hydrodynamics(flat, water_density=RHO, gravity=G)


@needs_deck
def test_the_deck_members_buoyancy_as_hydrodyn_sums_it(tmp_path):
    """The three members of the ``strip`` deck: their volume and the buoyancy load about the origin that HydroDyn's
    summary file (``HDSum``, OpenFAST v5.0.0, the deck's g = 9.81 m/s²) reports for them: 979.804 m³,
    Fz 9.852176e6 N, Mx 7.365619e6 N m, My 1.993886e7 N m (7 digits printed)."""
    hd = read_hydrodyn(write_deck(tmp_path, "strip").parent / "fl_decay_a_HydroDyn.dat")
    strip = strip_theory(hd, water_density=RHO, gravity=9.81)
    frustum = math.pi * np.linalg.norm([0, 60, 12]) * (1.5 ** 2 + 1.5 + 1) / 3
    assert strip.volume == pytest.approx(math.pi * 1.5 ** 2 * 60 + frustum + math.pi * 4 * 20, rel=1e-12)
    assert strip.volume == pytest.approx(979.804, abs=1e-3)
    load = strip.load(np.zeros(6))
    assert np.allclose(load, [0, 0, 9.852176e6, 7.365619e6, 1.993886e7, 0], rtol=1e-6, atol=1e-3)


@needs_deck
def test_the_grown_members_buoyancy_and_weight_as_hydrodyn_sums_them(tmp_path):
    """The ``strip_growth`` deck (the ``strip`` members with 0.3 → 0.2 m of growth at 1400 kg/m³): the volume with
    the growth, the buoyancy and the growth's weight about the origin as HydroDyn's summary file reports them
    (OpenFAST v5.0.0, g = 9.81 m/s²): 1333.21 m³; Fz 1.340571e7 N, Mx 1.673895e7, My 1.994870e7 N m; weight
    Fz −5.078719e6 N, Mx −1.134993e7, My −1.713155e6 N m (7 digits printed)."""
    hd = read_hydrodyn(write_deck(tmp_path, "strip_growth").parent / "fl_decay_a_HydroDyn.dat")
    strip = strip_theory(hd, water_density=RHO, gravity=9.81)
    assert strip.volume == pytest.approx(1333.21, abs=0.01)
    weight = -strip.growth_mass * 9.81
    assert weight == pytest.approx(-5.078719e6, rel=1e-6)
    assert np.allclose(np.cross(weight * strip.growth_centroid, [0, 0, 1])[:2], [-1.134993e7, -1.713155e6], rtol=1e-6)
    assert np.allclose(strip.load(np.zeros(6))[2:5], [1.340571e7 - 5.078719e6, 1.673895e7 - 1.134993e7,
                                                      1.994870e7 - 1.713155e6], rtol=2e-6)


@needs_deck
@pytest.mark.parametrize("q, expected", [
    ((10.0, 0.0, 1.5, 0.0, 4.0, 0.0), (1.9635685e8, -1.236424e8, -2.27832e8)),
    ((10.0, 0.0, 1.5, 3.0, 4.0, 0.0), (1.9673237e8, -2.322889e8, -2.3659253e8)),
])
def test_waterline_buoyancy_of_the_piercing_deck_as_hydrodyn_applies_it(tmp_path, q, expected):
    """The ``piercing`` deck's hydrostatic load (WAMIT's and the members', two of them cut by the surface) at a
    displaced position, against HydroDyn's in OpenFAST v5.0.0 with every DOF held at that position (``HydroFzi``,
    ``HydroMxi``, ``HydroMyi`` at t = 0; 8 digits printed; its horizontal forces and yaw moment are zero too)."""
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    case = write_deck(tmp_path, "piercing").parent
    hydro = platform_hydrodynamics(case / "fl_decay_a_HydroDyn.dat", water_density=RHO, gravity=9.81,
                                   seastate=case / "fl_decay_a_SeaState.dat", water_depth=200.0)
    x = np.array(q) * np.r_[1, 1, 1, np.pi / 180, np.pi / 180, np.pi / 180]
    load = hydro.load(x, np.zeros(6))
    assert np.allclose(load[[2, 3, 4]], expected, rtol=2e-7)
    assert np.allclose(load[[0, 1, 5]], 0.0, atol=1e-6)


def _eps(run, ref, channel: str) -> float:
    from mbsym.wind.analysis.compare import error_metrics

    return error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])[0]


_MOTIONS = {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmRoll": 0.015, "PtfmPitch": 0.015}


@needs_deck
@pytest.mark.parametrize("variant, bounds", [
    ("strip", _MOTIONS),
    ("morison_only", {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmPitch": 0.015}),
    ("piercing", _MOTIONS),
    pytest.param("strip_growth_uniform", {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmPitch": 0.015},
                 marks=pytest.mark.slow),
])
def test_decay_with_strip_members_matches_openfast(tmp_path, variant, bounds):
    """300 s of the decay (quasi-static lines) against OpenFAST's with the same strip-theory members (module
    docstring): submerged ones (``strip``); the VolturnUS-S as strip-theory members without potential flow
    (``morison_only``, ``PotMod`` 0: all of its buoyancy, restoring and added mass from them); two members through
    the surface (``piercing``: the platform settles at −2.5° roll and −3.3° pitch); marine growth (``strip_growth_
    uniform``: 0.25 m at 1400 kg/m³). Measured ε: strip 0.33–0.59 %; morison_only 0.30–0.78 %; piercing 0.53–1.07 %
    (roll 1.9 % while A∞ took the DOF accelerations for the angular one, docs/offshore.md §6); growth 0.54–1.25 % (its
    roll and yaw, tenths of a degree, are not compared: OpenFAST's yaw swings ±0.3° against mbsym's ±0.05°,
    docs/offshore.md §2c)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    ref = _reference(variant)
    out = tmp_path / "run.csv"
    assert main(["simulate", str(write_deck(tmp_path / "deck", variant)), "--tmax", "300", "--mooring-lines",
                 "quasi-static", "--out", str(out)]) == 0          # the members on the fast rung (lines: §3c)
    run = read_csv(out)
    for channel, bound in bounds.items():
        assert _eps(run, ref, channel) <= bound, (channel, _eps(run, ref, channel))


@needs_deck
@pytest.mark.slow
@pytest.mark.parametrize("variant, bounds", [
    ("piercing", _MOTIONS | {"HydroFxi": 0.01, "HydroFzi": 0.01}),
    ("morison_only", {"PtfmSurge": 0.015, "PtfmHeave": 0.015, "PtfmPitch": 0.015, "HydroFxi": 0.01,
                      "HydroFzi": 0.01}),
])
def test_strip_members_in_waves_match_openfast(tmp_path, variant, bounds):
    """The ``piercing`` and ``morison_only`` decks in JONSWAP waves (test_offshore_morison.WAVE_EDITS: Hs 4 m, Tp
    10 s), 300 s: the members' wave inertia off the kinematics grid at their undisplaced wet nodes (on the
    ``morison_only`` deck all of the waves' load). Measured ε: piercing surge, heave, pitch 0.54–0.64 %, roll
    1.33 %, HydroFxi 0.16 %, HydroFzi 0.27 %; morison_only 0.29–1.06 %, HydroFxi 0.16 %, HydroFzi 0.27 %."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    from .test_offshore_morison import wave_deck

    ref = _reference(f"{variant}_waves")
    out = tmp_path / "run.csv"
    fst = wave_deck(write_deck(tmp_path / "deck", variant))
    assert main(["simulate", str(fst), "--tmax", "300", "--out", str(out)]) == 0
    run = read_csv(out)
    for channel, bound in bounds.items():
        assert _eps(run, ref, channel) <= bound, (channel, _eps(run, ref, channel))


@needs_deck
def test_a_deck_without_potential_flow(tmp_path):
    """``PotMod = 0``: the members alone float the platform (no WAMIT data read); HydroDyn's additional loads are
    unused there (named in a warning); no radiation; refused without strip-theory members."""
    from mbsym.exceptions import ModelWarning
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    case = write_deck(tmp_path, "morison_only").parent
    path = case / "fl_decay_a_HydroDyn.dat"
    hydro = platform_hydrodynamics(path, water_density=RHO, gravity=9.81, water_depth=200.0)
    assert hydro.wamit is None and hydro.hydrostatics.buoyancy == 0.0
    lift = hydro.load(np.zeros(6), np.zeros(6))[2]
    assert lift == pytest.approx(hydro.strip.buoyancy) and lift > 1.9e8          # the VolturnUS-S's ~2e8 N
    text = path.read_text().splitlines()
    k = next(j for j, line in enumerate(text) if "AddF0" in line)
    text[k + 2] = "-1.0E+06"
    loaded = path.with_name("loaded_HydroDyn.dat")
    loaded.write_text("\n".join(text) + "\n")
    with pytest.warns(ModelWarning, match="AddF0 with PotMod = 0"):
        hydro = platform_hydrodynamics(loaded, water_density=RHO, gravity=9.81, water_depth=200.0)
    assert hydro.load(np.zeros(6), np.zeros(6))[2] == pytest.approx(lift)        # HydroDyn does not apply it
    bare = path.with_name("bare_HydroDyn.dat")
    bare.write_text(path.read_text().replace("1  1  FALSE", "1  1  TRUE"))
    with pytest.raises(UnsupportedFeatureError, match="PotMod = 0 without members"):
        platform_hydrodynamics(bare, water_density=RHO, gravity=9.81)


def _submerged_numeric(p1, p2, r1, r2, slices=20000):
    """``(V, V c)`` below z = 0 of the frustum from p1 to p2 by integrating circular segments along its axis
    (each cross-section a disk perpendicular to the axis, cut by the plane along a chord)."""
    p1, p2 = np.asarray(p1, float), np.asarray(p2, float)
    length = np.linalg.norm(p2 - p1)
    k = (p2 - p1) / length
    w = np.array([0.0, 0.0, 1.0]) - k[2] * k
    sin = np.linalg.norm(w)
    up = w / sin if sin > 0 else np.zeros(3)
    volume, first = 0.0, np.zeros(3)
    ds = length / slices
    for s in (np.arange(slices) + 0.5) * ds:
        centre, r = p1 + s * k, r1 + (r2 - r1) * s / length
        d = -centre[2] / sin if sin > 0 else (np.inf if centre[2] < 0 else -np.inf)
        if d <= -r:
            continue
        if d >= r:
            area, offset = math.pi * r * r, 0.0
        else:
            area = r * r * math.acos(-d / r) + d * math.sqrt(r * r - d * d)
            offset = -2.0 / 3.0 * (r * r - d * d) ** 1.5 / area
        volume += area * ds
        first += area * ds * (centre + offset * up)
    return volume, first


@pytest.mark.parametrize("p1, p2, r1, r2", [
    ((3, -2, -12), (3, -2, 8), 2.0, 2.0),                       # vertical cylinder through the surface
    ((0, 0, -10), (6, 2, 7), 1.5, 1.5),                         # inclined cylinder (~20 deg from vertical)
    ((-4, 1, -9), (2, 5, 6), 2.5, 1.2),                         # inclined cone
    ((2, 5, 6), (-4, 1, -9), 1.2, 2.5),                         # the same, node 2 under water
    ((0, 0, -20), (4, 3, -6), 1.0, 1.6),                        # submerged
    ((0, 0, 2), (1, 1, 9), 1.0, 1.0),                           # dry
])
def test_cut_element_is_archimedes_of_its_submerged_part(p1, p2, r1, r2):
    """The element's buoyancy volume and its first moment against a numerical integration of the frustum below the
    still-water plane (to the integration's 1e-6)."""
    import casadi as ca

    from mbsym.wind.offshore.waterline import element_buoyancy

    a, b = ca.DM(p1), ca.DM(p2)
    v, vc = element_buoyancy(a, b, a[2], b[2], r1, r2, float(np.linalg.norm(np.subtract(p2, p1))))
    volume, first = _submerged_numeric(p1, p2, r1, r2)
    assert float(v) == pytest.approx(volume, rel=1e-6, abs=1e-9)
    assert np.allclose(np.array(vc).ravel(), first, rtol=1e-6, atol=1e-6 * max(volume, 1.0))
