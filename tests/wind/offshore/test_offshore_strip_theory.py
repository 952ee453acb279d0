"""Buoyancy, added mass and wave inertia of strip-theory members (mbsym.wind.offshore.strip_theory; issue 20, item 2).

References, each independent of the code under test:
- closed forms: Archimedes' force ``ρ g V`` of a submerged cylinder and of a frustum (``π L (r₁² + r₁r₂ + r₂²)/3``)
  through the volume's centroid, turning with the platform; a cylinder's transverse added mass ``ρ C_a π R² L`` and
  its two end plates' axial ``2 ρ C_{a,ax} (2π/3) R³``; the Froude–Krylov force of a uniformly accelerating flow on
  a closed body, ``ρ V a`` (its pressure ``−ρ a·x``), which only the side and end-plate terms together give;
- an invariant: with ``C_p = 0`` the wave inertia of a uniform acceleration ``a`` equals the added-mass force of the
  body accelerating by ``−a`` (the diffraction and added-mass terms share ``C_a``);
- OpenFAST v5.0.0 free decays of the shared ``fl_decay_a`` with three submerged strip-theory members added
  (``strip`` of test_offshore_morison.write_deck; tests/data/openfast_morison/README.md): the members change
  OpenFAST's own decay by ε 3.5 % (heave) to 53 % (roll); mbsym's ε 0.2–0.5 % on surge, heave, roll and pitch
  (measured): bound 1.5 %, as for the drag-only members.
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
    return _strip([part], {1: [(-k, r1)], 2: [(k, r2)]}, {1: (p1, 2), 2: (p2, 2)},
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


@needs_deck
def test_unmodelled_strip_members_are_named(tmp_path):
    fst = write_deck(tmp_path, "strip")
    path = fst.parent / "fl_decay_a_HydroDyn.dat"
    assert strip_problems(read_hydrodyn(path)) == []
    text = path.read_text()
    piercing = path.with_name("piercing_HydroDyn.dat")
    piercing.write_text(text.replace("-20 -20 -15  2  0", "-20 -20 5  2  0"))
    problems = strip_problems(read_hydrodyn(piercing))
    assert len(problems) == 1 and "member 3" in problems[0] and "still-water level" in problems[0]
    growth = path.with_name("growth_HydroDyn.dat")
    lines = text.splitlines()
    k = next(j for j, line in enumerate(lines) if line.split()[1:2] == ["NMGDepths"])
    lines[k] = "2   NMGDepths   - marine growth"
    lines[k + 3:k + 3] = ["-10.0 0.2 1100", "-40.0 0.1 1100"]
    growth.write_text("\n".join(lines) + "\n")
    assert all("marine growth" in p for p in strip_problems(read_hydrodyn(growth)))
    from mbsym.wind.offshore.platform import platform_hydrodynamics

    with pytest.raises(UnsupportedFeatureError, match="still-water level"):
        platform_hydrodynamics(piercing, water_density=RHO, gravity=G)


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
def test_decay_with_strip_members_matches_openfast(tmp_path):
    """300 s of the decay on mbsym's default path against OpenFAST's with the same strip-theory members: ε ≤ 1.5 % on
    surge, heave, roll and pitch (module docstring)."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    ref = _reference("strip")
    out = tmp_path / "run.csv"
    assert main(["simulate", str(write_deck(tmp_path / "deck", "strip")), "--tmax", "300", "--out", str(out)]) == 0
    run = read_csv(out)
    for channel in ("PtfmSurge", "PtfmHeave", "PtfmRoll", "PtfmPitch"):
        eps, _ = error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])
        assert eps <= 0.015, (channel, eps)



@needs_deck
def test_strip_members_in_waves_match_openfast(tmp_path):
    """The same deck in JONSWAP waves (test_offshore_morison.WAVE_EDITS: Hs 4 m, Tp 10 s), 300 s: the members' wave
    inertia (off the kinematics grid at their undisplaced nodes) carries 130 % of the RMS of OpenFAST's HydroFyi and
    5 % of HydroFxi and HydroFzi. Measured ε: motions 0.5–0.75 %, HydroFxi 0.14 %, HydroFzi 0.26 %; bounds 1.5 % and
    1 %."""
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import error_metrics, read_csv

    from .test_offshore_morison import wave_deck

    ref = _reference("strip_waves")
    out = tmp_path / "run.csv"
    fst = wave_deck(write_deck(tmp_path / "deck", "strip"))
    assert main(["simulate", str(fst), "--tmax", "300", "--out", str(out)]) == 0
    run = read_csv(out)
    for channel, bound in (("PtfmSurge", 0.015), ("PtfmHeave", 0.015), ("PtfmRoll", 0.015), ("PtfmPitch", 0.015),
                           ("HydroFxi", 0.01), ("HydroFzi", 0.01)):
        eps, _ = error_metrics(run.time, run.channel(channel), ref["Time"], ref[channel])
        assert eps <= bound, (channel, eps)
