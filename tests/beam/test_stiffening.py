"""Geometric stiffness (paper App. C), spin softening and Southwell coefficients.

References: closed-form integrals for the shape (z/L)^2 on a uniform beam; the exact
Southwell coefficients of a uniform rotating cantilever (REFERENCE_NUMBERS.md: 1.193336,
6.478225, 17.859520); an independent FEM assembly of the centrifugal geometric stiffness
(``cantilever_modes(rotor_speed=...)``); OpenFAST linearization of the NREL 5 MW blade.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from mbsym.beam import (
    HermiteShape,
    PolynomialShape,
    cantilever_modes,
    rotating_stiffness,
    shape_integrals,
    southwell_coefficients,
    spin_softening,
)


@pytest.fixture(scope="module")
def uniform_exact_modes():
    """Uniform beam L = 1, m = EI = 1, first three FEM modes (60 elements) as x shapes."""
    modes = cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=3, n_elements=60)
    sid = shape_integrals([0.0, 1.0], 1.0, 1.0, 1.0, modes.shapes(), quadrature="simpson", n_points=2001)
    return modes, sid


def test_southwell_uniform_beam_exact_modes(uniform_exact_modes):
    """Exact modes, zero hub radius: k_Omega = 1.193336, 6.478225, 17.859520 (rel 1e-5; measured
    1.1933364, 6.4782249, 17.859520)."""
    _, sid = uniform_exact_modes
    np.testing.assert_allclose(southwell_coefficients(sid), [1.193336, 6.478225, 17.859520], rtol=1e-5)
    np.testing.assert_allclose(southwell_coefficients(sid, axis="y"), southwell_coefficients(sid), rtol=1e-14)


def test_unit_matrices_closed_form():
    """Shape (z/L)^2, uniform m: kg_omega[x,x] = kg_omega[y,y] = 4 m L / 15 (centrifugal, > 0),
    kg_t[z] = -m / 3 (unit a - g along z compresses), kg_tip[z] = 4 / (3 L); all other entries 0 (1e-9)."""
    L, m = 2.0, 3.0
    sid = shape_integrals([0, L], m, 1.0, 1.0, PolynomialShape([1.0], L), quadrature="simpson", n_points=2001)
    expected_w = np.zeros((3, 3))
    expected_w[0, 0] = expected_w[1, 1] = 4 * m * L / 15
    np.testing.assert_allclose(sid.kg_omega[:, :, 0, 0], expected_w, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sid.kg_t[:, 0, 0], [0, 0, -m / 3], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sid.kg_tip[:, 0, 0], [0, 0, 4 / (3 * L)], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sid.kg_r, 0.0, atol=1e-14)
    # Southwell with hub radius r: (4 m L / 15 + r m / 3) / (m L / 5) = 4/3 + 5 r / (3 L)
    for r in (0.0, 0.7):
        assert southwell_coefficients(sid, hub_radius=r)[0] == pytest.approx(4 / 3 + 5 * r / (3 * L), rel=1e-9)


def test_signs_of_geometric_stiffness():
    """Upright beam under gravity (g along -z): K_g < 0; weight of a top mass: < 0; spin about x: > 0;
    pulling the tip (+z): > 0; an upward acceleration a_z adds compression like gravity."""
    L = 10.0
    sid = shape_integrals([0, L], 5.0, 1e5, 1e5, PolynomialShape([1.0], L), n_points=101)
    assert sid.geometric_stiffness(gravity=(0, 0, -9.81))[0, 0] < 0
    assert sid.geometric_stiffness(tip_force=(0, 0, -100.0))[0, 0] < 0
    assert sid.geometric_stiffness(angular_velocity=(1.0, 0, 0))[0, 0] > 0
    assert sid.geometric_stiffness(tip_force=(0, 0, 100.0))[0, 0] > 0
    np.testing.assert_allclose(sid.geometric_stiffness(acceleration=(0, 0, 9.81)),
                               sid.geometric_stiffness(gravity=(0, 0, -9.81)), rtol=1e-15)


def test_spin_softening_in_plane_only():
    """Rotation about x: a y (in-plane) shape gets -M_e, an x (out-of-plane) shape 0 (paper Sect. 4.3);
    rotation about the beam axis z softens both by -M_e; the x/y cross term is 0 (1e-12)."""
    L = 3.0
    shapes = [PolynomialShape([1.0], L, "x"), PolynomialShape([0.5, 0.5], L, "y")]
    sid = shape_integrals([0, L], 2.0, 1.0, 1.0, shapes, n_points=101)
    np.testing.assert_allclose(spin_softening(sid, "x"), np.diag([0.0, -sid.me[1, 1]]), atol=1e-12)
    np.testing.assert_allclose(spin_softening(sid, "y"), np.diag([-sid.me[0, 0], 0.0]), atol=1e-12)
    np.testing.assert_allclose(spin_softening(sid, "z"), -np.diag(np.diag(sid.me)), atol=1e-12)


def test_edge_is_flap_minus_one(uniform_exact_modes):
    """Same exact first mode as a flap (x) and an edge (y) shape, rotation about x, Omega = 0.8 omega_0:
    rotating_stiffness gives omega^2 = omega_0^2 + k Omega^2 (flap) and + (k - 1) Omega^2 (edge), 1e-10."""
    modes, _ = uniform_exact_modes
    flap = modes.shape(0)
    edge = HermiteShape(modes.nodes, modes.displacements[0], modes.slopes[0], "y")
    sid = shape_integrals([0.0, 1.0], 1.0, 1.0, 1.0, [flap, edge], quadrature="simpson", n_points=2001)
    k = southwell_coefficients(sid)
    np.testing.assert_allclose(k[0], k[1], rtol=1e-12)
    w0sq = sid.ke[0, 0] / sid.me[0, 0]
    om = 0.8 * np.sqrt(w0sq)
    kr = rotating_stiffness(sid, om, axis="x")
    assert abs(kr[0, 1]) < 1e-12 * kr[0, 0]
    assert kr[0, 0] / sid.me[0, 0] == pytest.approx(w0sq + k[0] * om**2, rel=1e-10)
    assert kr[1, 1] / sid.me[1, 1] == pytest.approx(w0sq + (k[1] - 1) * om**2, rel=1e-10)


@pytest.mark.parametrize("hub_radius", [0.0, 0.3])
def test_southwell_against_fem_centrifugal_assembly(uniform_exact_modes, hub_radius):
    """Independent check: FEM with the centrifugal tension assembled element by element, small spin
    (Omega = 0.05 omega_0): (omega^2 - omega_0^2) / Omega^2 equals k_Omega (flap) and k_Omega - 1 (edge,
    in_plane=True) within 1e-3 (the mode-shape change is O(Omega^4))."""
    modes, sid = uniform_exact_modes
    k = southwell_coefficients(sid, hub_radius=hub_radius)[0]
    w0 = 2 * np.pi * modes.frequencies_hz[0]
    om = 0.05 * w0
    for in_plane, expected in ((False, k), (True, k - 1)):
        rot = cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=1, n_elements=60, rotor_speed=om,
                               hub_radius=hub_radius, in_plane=in_plane)
        rise = ((2 * np.pi * rot.frequencies_hz[0]) ** 2 - w0**2) / om**2
        assert rise == pytest.approx(expected, rel=1e-3)


def test_nrel5mw_blade_campbell_slopes_vs_openfast(nrel_blade, nrel5mw_dir):
    """OpenFAST linearization (blade_campbell case, ElastoDyn only, HubRad = 1.5 m, no gravity):
    slope (f(12 rpm)^2 - f(0)^2) / (Omega/2pi)^2 = [1.789, 0.466, 5.695] for flap1, edge1, flap2.
    Our k_Omega with hub radius 1.5 m (flap) and k_Omega - 1 (edge): measured [1.779, 0.442, 5.680].
    Tolerance: flap rel 2 %; edge rel 6 % (the small difference k - 1 amplifies errors; ElastoDyn
    twists its shapes with the structural twist, we treat each shape alone, untwisted)."""
    path = nrel5mw_dir.parent / "cases" / "blade_campbell" / "blade_campbell_lin.json"
    if not path.exists():
        pytest.skip(f"{path} not available")
    rows = {r["RotSpeed_[rpm]"]: r for r in json.loads(path.read_text())["table"]}
    f_rot = 12 / 60.0
    of = [(rows[12][f"{n}_freq_[Hz]"] ** 2 - rows[0][f"{n}_freq_[Hz]"] ** 2) / f_rot**2 for n in ("flap1", "edge1", "flap2")]
    b = nrel_blade
    L = b["length"]
    shapes = [PolynomialShape(b["flap1"], L, "x"), PolynomialShape(b["edge1"], L, "y"),
              PolynomialShape(b["flap2"], L, "x")]
    sid = shape_integrals(b["z"], b["m"], b["ei_flap"], b["ei_edge"], shapes, n_points=2001)
    k = southwell_coefficients(sid, hub_radius=b["hub_radius"])
    ours = k + np.diag(spin_softening(sid, "x")) / np.diag(sid.me)  # -1 for the in-plane (edge) shape
    np.testing.assert_allclose(ours[[0, 2]], np.array(of)[[0, 2]], rtol=0.02)
    assert ours[1] == pytest.approx(of[1], rel=0.06)
