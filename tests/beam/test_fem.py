"""Finite-element cantilever modes and ElastoDyn polynomial fits.

References: clamped-free uniform beam, omega = (beta L)^2 sqrt(EI / (m L^4)) with beta L
the roots of cos(x) cosh(x) = -1 (textbook; REFERENCE_NUMBERS.md); massless beam with
a tip mass and inertia: exact 2x2 tip stiffness EI/L^3 [[12, -6L], [-6L, 4L^2]].
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq

from mbsym.beam import (
    HermiteShape,
    PolynomialShape,
    cantilever_modes,
    fit_elastodyn_polynomial,
    shape_integrals,
)


def test_beta_l_roots_are_the_textbook_values(beta_l):
    """Independent root finding of cos x cosh x = -1 agrees with 1.875104, 4.694091, 7.854757 (1e-6)."""
    roots = [brentq(lambda x: np.cos(x) * np.cosh(x) + 1, a, b) for a, b in ((1, 3), (4, 6), (7, 9))]
    np.testing.assert_allclose(roots, beta_l, rtol=1e-12)
    np.testing.assert_allclose(roots, [1.875104, 4.694091, 7.854757], atol=1e-6)


@pytest.mark.parametrize("direction", ["x", "y"])
def test_uniform_cantilever_frequencies(direction, beta_l):
    """30 Hermite elements: first three frequencies within 1e-5 (measured 1.9e-8, 4.2e-7, 3.3e-6)."""
    L, m, ei = 12.0, 3.0, 5.0e4
    modes = cantilever_modes([0.0, L], m, ei, n_modes=3, n_elements=30, direction=direction)
    exact = beta_l**2 * np.sqrt(ei / (m * L**4)) / (2 * np.pi)
    np.testing.assert_allclose(modes.frequencies_hz, exact, rtol=1e-5)
    # normalised to unit tip deflection, clamped root
    np.testing.assert_allclose(modes.displacements[:, -1], 1.0)
    np.testing.assert_allclose(modes.displacements[:, 0], 0.0)
    shape = modes.shape(0)
    assert np.argmax(np.abs(shape.evaluate([L])[:, 0])) == (0 if direction == "x" else 1)


def test_fem_convergence_order_is_four(beta_l):
    """Hermite cubics: frequency error ~ h^4 (fitted log-log slope 4 +/- 0.3)."""
    exact = beta_l[2] ** 2 / (2 * np.pi)
    ns = np.array([4, 8, 16])
    err = [abs(cantilever_modes([0, 1], 1.0, 1.0, n_modes=3, n_elements=n).frequencies_hz[2] / exact - 1) for n in ns]
    slope = -np.polyfit(np.log(ns), np.log(err), 1)[0]
    assert abs(slope - 4) < 0.3, slope


def test_fem_mode_integrated_frequency_matches():
    """sqrt(Ke/Me) of the FEM first mode, by shape_integrals, equals the FEM frequency (1e-6)."""
    modes = cantilever_modes([0.0, 2.0], 1.5, 7.0, n_modes=1, n_elements=40)
    sid = shape_integrals([0.0, 2.0], 1.5, 7.0, 7.0, modes.shape(0), quadrature="simpson", n_points=2001)
    f = np.sqrt(sid.ke[0, 0] / sid.me[0, 0]) / (2 * np.pi)
    assert f == pytest.approx(modes.frequencies_hz[0], rel=1e-6)


def test_tip_mass_and_inertia_on_nearly_massless_beam():
    """Massless-beam limit (m L / M = 2e-8, effect ~1e-8): exact 2-DOF tip model, rel 1e-6.

    Also exercises near-singular mass matrices (interior nodes carry almost no mass).
    """
    L, ei, mt, jt = 10.0, 2.0e6, 500.0, 800.0
    modes = cantilever_modes([0.0, L], 1e-6, ei, n_modes=2, n_elements=10, tip_mass=mt, tip_inertia=jt)
    k = ei / L**3 * np.array([[12.0, -6 * L], [-6 * L, 4 * L**2]])
    exact = np.sqrt(eigh(k, np.diag([mt, jt]), eigvals_only=True)) / (2 * np.pi)
    np.testing.assert_allclose(modes.frequencies_hz, exact, rtol=1e-6)


def test_axial_tension_raises_frequency_compression_lowers():
    """Rayleigh bound: with tension N, omega^2 changes by ~ int N phi'^2 / M (first order, 1e-3 for small N)."""
    L, m, ei = 1.0, 1.0, 1.0
    base = cantilever_modes([0, L], m, ei, n_modes=1, n_elements=40)
    sid = shape_integrals([0, L], m, ei, ei, base.shape(0), n_points=2001, quadrature="simpson")
    for n_ax in (0.05, -0.05):
        pre = cantilever_modes([0, L], m, ei, n_modes=1, n_elements=40, axial_force=[n_ax, n_ax])
        d_om2 = (2 * np.pi) ** 2 * (pre.frequencies_hz[0] ** 2 - base.frequencies_hz[0] ** 2)
        predicted = n_ax * sid.kg_tip[2, 0, 0] / sid.me[0, 0]
        assert d_om2 == pytest.approx(predicted, rel=2e-3)


def test_fit_elastodyn_polynomial_recovers_exact_coefficients():
    """A polynomial already in ElastoDyn form is recovered to 1e-10."""
    c = np.array([0.7004, 2.1963, -5.6202, 6.2275, -2.504])
    z = np.linspace(0, 87.6, 41)
    shape = PolynomialShape(c, 87.6)
    got = fit_elastodyn_polynomial(z, shape.evaluate(z)[0])
    np.testing.assert_allclose(got, c, atol=1e-10)
    np.testing.assert_allclose(fit_elastodyn_polynomial(shape), c, atol=1e-10)


def test_fit_of_fem_mode_gives_near_exact_frequency(beta_l):
    """The x^2..x^6 fit of the exact first mode: sum = 1, Rayleigh frequency within 1e-5 of exact."""
    modes = cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=1, n_elements=40)
    c = fit_elastodyn_polynomial(modes.shape(0))
    assert c.sum() == pytest.approx(1.0, abs=1e-12)
    sid = shape_integrals([0.0, 1.0], 1.0, 1.0, 1.0, PolynomialShape(c, 1.0), quadrature="simpson", n_points=1001)
    omega = np.sqrt(sid.ke[0, 0] / sid.me[0, 0])
    assert omega / beta_l[0] ** 2 - 1 == pytest.approx(0.0, abs=1e-5)


def test_hermite_shape_reproduces_a_cubic():
    """Piecewise Hermite with exact nodal data of z^3 is exact (value, slope, curvature), 1e-12."""
    nodes = np.linspace(0, 2, 5)
    s = HermiteShape(nodes, nodes**3, 3 * nodes**2, "y")
    z = np.linspace(0, 2, 17)
    np.testing.assert_allclose(s.evaluate(z, 0)[1], z**3, atol=1e-12)
    np.testing.assert_allclose(s.evaluate(z, 1)[1], 3 * z**2, atol=1e-12)
    np.testing.assert_allclose(s.evaluate(z, 2)[1], 6 * z, atol=1e-12)
    assert np.all(s.evaluate(z)[0] == 0)
