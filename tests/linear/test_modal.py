"""Modal analysis: closed forms, rigid-body modes, eigenvalue sensitivities.

References
----------
- Two-mass chain without damping: ω² are the eigenvalues of M⁻¹K (closed form of the
  2×2 generalized problem); single damped oscillator: ω_n = sqrt(k/m), ζ = c/(2 sqrt(k m)).
  Exact to 1e-12.
- Rigid-body counting: a free DOF gives one mode (double zero, or a zero and -c/m when
  damped); two free DOFs give two.
- Eigenvalue derivatives against central differences of the eigenvalues of A + h dA
  (h = 1e-7): 1e-6 relative.
"""

from __future__ import annotations

import numpy as np
import pytest

from mbsym.exceptions import DimensionError
from mbsym.modal import modal_analysis, mode_sensitivities


def _state_matrix(M, C, K):
    Minv = np.linalg.inv(M)
    n = M.shape[0]
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])


def test_two_mass_closed_form():
    m1, m2, k1, k2 = 2.0, 1.0, 40.0, 15.0
    M = np.array([[m1, 0], [0, m2]])
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    w2 = np.sort(np.linalg.eigvals(np.linalg.solve(M, K)).real)
    modes = modal_analysis(_state_matrix(M, np.zeros((2, 2)), K), ["x1", "x2"])
    np.testing.assert_allclose([m.freq_hz for m in modes], np.sqrt(w2) / (2 * np.pi), rtol=1e-12)
    assert all(m.oscillatory and not m.rigid_body and abs(m.damping_ratio) < 1e-12 for m in modes)
    # the mode shape solves (K - ω² M) φ = 0 and is scaled to 1 at the dominant DOF
    for m in modes:
        phi = m.shape.real
        np.testing.assert_allclose((K - (2 * np.pi * m.freq_hz) ** 2 * M) @ phi, 0.0, atol=1e-10)
        assert phi[["x1", "x2"].index(m.dominant_dof)] == pytest.approx(1.0)


def test_damped_oscillator_and_overdamped():
    m, k, c = 2.0, 50.0, 0.4
    mode, = modal_analysis(np.array([[0, 1], [-k / m, -c / m]]), ["x"])
    assert mode.freq_hz == pytest.approx(np.sqrt(k / m) / (2 * np.pi), rel=1e-12)
    assert mode.damping_ratio == pytest.approx(c / (2 * np.sqrt(k * m)), rel=1e-12)
    assert mode.damped_freq_hz == pytest.approx(mode.freq_hz * np.sqrt(1 - mode.damping_ratio**2), rel=1e-12)
    over = modal_analysis(np.array([[0, 1], [-1.0, -5.0]]), ["x"])         # two real eigenvalues
    assert [m.oscillatory for m in over] == [False, False]
    assert all(m.damping_ratio == pytest.approx(1.0) for m in over)


@pytest.mark.parametrize("damping", [0.0, 0.3])
def test_rigid_body_modes_counted_once_per_free_dof(damping):
    # x free (damped or not), y free, z on a spring: two rigid-body modes, one oscillatory
    M, K = np.diag([1.0, 2.0, 3.0]), np.diag([0.0, 0.0, 12.0])
    C = np.diag([damping, 0.0, 0.0])
    modes = modal_analysis(_state_matrix(M, C, K), ["x", "y", "z"])
    rigid = [m for m in modes if m.rigid_body]
    assert len(rigid) == 2 and {m.dominant_dof for m in rigid} == {"x", "y"}
    assert all(m.freq_hz == 0.0 and m.damping_ratio == 0.0 for m in rigid)
    osc = [m for m in modes if m.oscillatory]
    assert len(osc) == 1 and osc[0].freq_hz == pytest.approx(np.sqrt(4.0) / (2 * np.pi))
    assert len(modes) == 3 + (damping > 0)          # the damped free DOF adds a real decay rate -c/m
    assert modes[0].rigid_body and modes[1].rigid_body


def test_mode_sensitivities_against_finite_differences():
    rng = np.random.default_rng(7)
    n = 3
    L = rng.normal(size=(n, n))
    M = L @ L.T + n * np.eye(n)
    K = np.diag([10.0, 30.0, 55.0]) + 0.5 * (L + L.T)
    C = 0.02 * K + 0.01 * M
    A = _state_matrix(M, C, K)
    dA = rng.normal(size=(2, 2 * n, 2 * n))
    dA[:, :n] = 0.0
    modes = modal_analysis(A, ["a", "b", "c"])
    dfreq, dzeta = mode_sensitivities(A, dA, modes)
    h = 1e-7
    for s in range(2):
        plus = modal_analysis(A + h * dA[s], ["a", "b", "c"])
        minus = modal_analysis(A - h * dA[s], ["a", "b", "c"])
        fd_f = (np.array([m.freq_hz for m in plus]) - np.array([m.freq_hz for m in minus])) / (2 * h)
        fd_z = (np.array([m.damping_ratio for m in plus]) - np.array([m.damping_ratio for m in minus])) / (2 * h)
        np.testing.assert_allclose(dfreq[s], fd_f, rtol=1e-6, atol=1e-9)
        np.testing.assert_allclose(dzeta[s], fd_z, rtol=1e-5, atol=1e-9)


def test_bad_state_matrix():
    with pytest.raises(DimensionError, match=r"must be \(4, 4\)"):
        modal_analysis(np.zeros((3, 3)), ["a", "b"])
    with pytest.raises(DimensionError, match="finite"):
        modal_analysis(np.full((2, 2), np.nan), ["a"])


# --------------------------------------------------------------------------- repeated eigenvalues
def _identical_oscillators(damping: float):
    """Two uncoupled oscillators m = 1, k1 = k2 = 100 (x along x, y along y): ω = 10 rad/s, twice."""
    import mbsym as mb

    sys = mb.System()
    x, y = sys.coordinates("x y")
    k1, k2 = sys.parameters("k1 k2", values=[100.0, 100.0])
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("a", 1.0), axis=[1, 0, 0], coordinate=x))
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", 1.0), axis=[0, 1, 0], coordinate=y))
    sys.add_spring(x, k1)
    sys.add_spring(y, k2)
    if damping:
        sys.add_damper(x, damping)
        sys.add_damper(y, damping)
    return sys.equations(name="twins")


@pytest.mark.parametrize("damping", [0.0, 0.4])
def test_repeated_eigenvalue_of_identical_oscillators(damping):
    """Each mode moves with its own spring only: ∂f/∂k is diagonal.

    Closed form for m x'' + c x' + k x = 0: f = sqrt(k/m)/2π, ζ = c/(2 sqrt(k m)), so
    ∂f/∂k = 1/(4π sqrt(k m)) = 0.0079577 and ∂ζ/∂k = -ζ/(2k); to 1e-10 relative.
    """
    from mbsym.linear import sensitivities

    m, k = 1.0, 100.0
    s = sensitivities(_identical_oscillators(damping), ["k1", "k2"], [0.0, 0.0])
    assert [mode.dominant_dof for mode in s.modes] in (["x", "y"], ["y", "x"])
    assert s.modes[0].freq_hz == s.modes[1].freq_hz                  # exactly repeated
    own = np.array([[1.0 if mode.dominant_dof == dof else 0.0 for mode in s.modes] for dof in ("x", "y")])
    zeta = damping / (2 * np.sqrt(k * m))
    np.testing.assert_allclose(s.dfreq, own / (4 * np.pi * np.sqrt(k * m)), rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(s.dzeta, -own * zeta / (2 * k), rtol=1e-10, atol=1e-14)


def test_repeated_eigenvalue_of_three_identical_blades():
    """Three identical blades (m, k) on a hub on a spring: the cyclic pair is a double ω² = k/m.

    Degenerate perturbation theory (closed form): on the cyclic subspace Σ y_i = 0 (the hub
    at rest), a change δk of blade 1's spring moves ω² by δk y_1²/(m Σ y_i²), whose extremes
    over the subspace are 2/3 (y = (2, -1, -1)) and 0 (y = (0, 1, -1)): ∂f/∂k1 ∈
    {1/(6π m ω), 0}. Blade 2 and 3 give the same pair; to 1e-10 relative.
    """
    import mbsym as mb
    from mbsym.linear import sensitivities

    m, k = 1.0, 100.0
    sys = mb.System()
    x = sys.coordinates("x")
    ys = sys.coordinates("y1 y2 y3")
    ks = sys.parameters("k1 k2 k3", values=[k, k, k])
    hub = mb.RigidBody("hub", 5.0)
    sys.add_joint(mb.Prismatic(sys.ground, hub, axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, 700.0)
    for i, (y, kb) in enumerate(zip(ys, ks)):
        sys.add_joint(mb.Prismatic(hub, mb.RigidBody(f"blade{i}", m), axis=[1, 0, 0], coordinate=y))
        sys.add_spring(y, kb)
    s = sensitivities(sys.equations(name="rotor"), ["k1", "k2", "k3"], np.zeros(4))
    f = np.array([mode.freq_hz for mode in s.modes])
    pair = np.flatnonzero(np.abs(f - np.sqrt(k / m) / (2 * np.pi)) < 1e-9)
    assert pair.size == 2
    expected = [0.0, 1.0 / (6 * np.pi * m * np.sqrt(k / m))]
    for j in range(3):
        np.testing.assert_allclose(np.sort(s.dfreq[j, pair]), expected, rtol=1e-10, atol=1e-13)


def test_defective_repeated_eigenvalue_is_reported():
    """Critically damped x'' + 2x' + x = 0: λ = -1 is a Jordan block, ∂λ does not exist."""
    from mbsym.exceptions import SolverError

    A = np.array([[0.0, 1.0], [-1.0, -2.0]])
    modes = modal_analysis(A, ["x"])
    with pytest.raises(SolverError, match=r"dominant DOF x\) is repeated 2 times and defective"):
        mode_sensitivities(A, np.ones((1, 2, 2)), modes)


def test_modes_keep_their_eigenvector_index():
    """mode.eigen_index points at the mode's own eigenvalue of scipy.linalg.eig(A) (exact)."""
    import scipy.linalg

    A = _state_matrix(np.diag([1.0, 1.0]), np.zeros((2, 2)), np.diag([100.0, 100.0]))
    lam = scipy.linalg.eig(A, left=True, right=True)[0]
    modes = modal_analysis(A, ["x", "y"])
    assert len({m.eigen_index for m in modes}) == 2
    for m in modes:
        assert lam[m.eigen_index] == m.eigenvalue
