"""Batch linearization and parameter sensitivities.

References
----------
- A batch must equal the same linearizations one by one (same Functions through
  ``map``): to 1e-12 relative.
- Sensitivities (automatic differentiation) against central finite differences in the
  parameter of the numeric linearization, step 1e-6 relative to the parameter (truncation
  O(h²) ~ 1e-12, round-off ~ eps/h ~ 1e-10): tolerance 1e-6 relative to the largest entry;
  frequency and damping derivatives (first-order eigenvalue perturbation) likewise, 1e-5.
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import DimensionError
from mbsym.linear import linearize_batch, sensitivities

from .conftest import chain


def _points(model, n, rng):
    x0 = model.initial_state()
    return x0 + rng.normal(scale=[0.2, 0.2, 0.5, 0.05, 0.05, 0.3], size=(n, 6))


def test_batch_equals_single_linearizations(paper45):
    rng = np.random.default_rng(3)
    X = _points(paper45, 7, rng)
    U = rng.normal(scale=[1e3, 1e5, 1e5], size=(7, 3))
    outs = ["TTDspFA", "QD2_TSS1", "GenSpeed"]
    for kw in ({}, {"qdd0": "rhs"}, {"method": "elastodyn-fd"}):
        batch = linearize_batch(paper45, X, U, outputs=outs, **kw)
        assert len(batch) == 7
        for i in (0, 3, 6):
            lin = mb.linearize(paper45, X[i, :3], X[i, 3:], U[i], outputs=outs, **{"method": "exact", **kw})
            for name in ("M", "C", "K", "Q", "A", "B", "Cy", "Dy"):
                ref = getattr(lin, name)
                np.testing.assert_allclose(getattr(batch, name)[i], ref, rtol=1e-12,
                                           atol=1e-12 * max(1.0, np.abs(ref).max()), err_msg=f"{name} {kw}")
            one = batch[i]
            np.testing.assert_array_equal(one.A, batch.A[i])
            np.testing.assert_allclose(one.operating_point["y"], lin.operating_point["y"], rtol=1e-12)


def test_batch_parameter_sweep(paper45):
    """Arrays of N values in p sweep a parameter: tower stiffness scale s scales K's tower block by s."""
    x0 = paper45.initial_state()
    scale = np.array([0.5, 1.0, 2.0])
    batch = linearize_batch(paper45, np.tile(x0, (3, 1)), p={"tower_stiffness_scale": scale})
    for i, s in enumerate(scale):
        single = mb.linearize(paper45, p={"tower_stiffness_scale": float(s)})
        np.testing.assert_allclose(batch.K[i], single.K, rtol=1e-12, atol=1e-6)
    f = batch.frequencies()
    assert f.shape == (3, 3)
    assert np.all(np.diff(f[:, -1]) > 0)                 # stiffer tower, higher frequency


def test_batch_errors(paper45):
    with pytest.raises(DimensionError, match=r"shape \(N, 6\)"):
        linearize_batch(paper45, np.zeros((4, 5)))
    with pytest.raises(DimensionError, match="expected 4"):
        linearize_batch(paper45, np.zeros((4, 6)), p={"nacelle_mass": np.ones(3)})
    with pytest.raises(DimensionError, match="u0 must have shape"):
        linearize_batch(paper45, np.zeros((4, 6)), np.zeros((3, 3)))


def test_compiled_batch_equals_virtual_machine(paper45):
    pytest.importorskip("mbsym.codegen")
    X = _points(paper45, 5, np.random.default_rng(5))
    vm = linearize_batch(paper45, X)
    compiled = linearize_batch(paper45, X, compile=True)       # falls back to the VM without a compiler
    np.testing.assert_allclose(compiled.A, vm.A, rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(compiled.K, vm.K, rtol=1e-10, atol=1e-6)


def _fd_parameter(model, name, p0, fun, rel=1e-6):
    h = rel * max(abs(p0), 1.0)
    return (fun({name: p0 + h}) - fun({name: p0 - h})) / (2 * h)


@pytest.mark.parametrize("method", ["exact", "elastodyn-fd"])
def test_sensitivities_against_finite_differences_turbine(paper46, method):
    """Floating paper46: tower stiffness scale, nacelle mass, platform pitch inertia."""
    names = ["tower_stiffness_scale", "nacelle_mass", "platform_pitch_inertia"]
    sens = sensitivities(paper46, names, method=method, qdd0="rhs")
    defaults = paper46.eom.defaults
    for k, name in enumerate(names):
        p0 = defaults[name]
        for attr in ("M", "C", "K", "Q", "A", "B"):
            fd = _fd_parameter(paper46, name, p0,
                               lambda p: getattr(mb.linearize(paper46, p=p, method=method, qdd0="rhs"), attr))
            got = getattr(sens, f"d{attr}")[k]
            np.testing.assert_allclose(got, fd, rtol=0, atol=1e-6 * max(1.0, np.abs(fd).max()),
                                       err_msg=f"d{attr}/d{name}")
        osc = [i for i, m in enumerate(sens.modes) if not m.rigid_body]

        def freqs(p, osc=osc):
            modes = mb.linearize(paper46, p=p, method=method).modes()
            return np.array([[modes[i].freq_hz, modes[i].damping_ratio] for i in osc])

        fd = _fd_parameter(paper46, name, p0, freqs)
        np.testing.assert_allclose(sens.dfreq[k, osc], fd[:, 0], rtol=1e-5, atol=1e-12)
        np.testing.assert_allclose(sens.dzeta[k, osc], fd[:, 1], rtol=1e-4, atol=1e-13)
        assert np.all(sens.dfreq[k, [i for i in range(len(sens.modes)) if i not in osc]] == 0.0)


def test_sensitivities_closed_form():
    """Chain: ∂K/∂k1 = e1 e1ᵀ, ∂M/∂m2 = ones, ∂Q/∂anything = 0; f = sqrt(k/m)/2π for one mass."""
    eom = chain()
    s = sensitivities(eom, ["k1", "m2", "c2"], [0.0, 0.0])
    np.testing.assert_allclose(s.of("k1")["K"], [[1, 0], [0, 0]], atol=1e-14)
    np.testing.assert_allclose(s.of("m2")["M"], [[1, 1], [1, 1]], atol=1e-14)
    np.testing.assert_allclose(s.of("c2")["C"], [[0, 0], [0, 1]], atol=1e-14)
    np.testing.assert_allclose(s.dQ, 0.0, atol=1e-14)
    with pytest.raises(KeyError, match="computed for"):
        s.of("k2")
    with pytest.raises(DimensionError, match="unknown parameters"):
        sensitivities(eom, ["stiffness"], [0.0, 0.0])


def test_batch_larger_than_one_map_chunk(pendulum_eom):
    """Batches run as maps of MAP_CHUNK points; the pieces are stitched back in order."""
    from mbsym import linear

    rng = np.random.default_rng(11)
    N = linear.MAP_CHUNK * 2 + 3
    X = rng.normal(size=(N, 4))
    U = rng.normal(size=(N, 1))
    batch = linearize_batch(pendulum_eom, X, U, outputs=["q1", "q2_d"])
    for i in (0, linear.MAP_CHUNK - 1, linear.MAP_CHUNK, N - 1):
        lin = mb.linearize(pendulum_eom, X[i, :2], X[i, 2:], U[i])
        np.testing.assert_allclose(batch.A[i], lin.A, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(batch.K[i], lin.K, rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(batch.y[i], X[i, [0, 3]])


def test_batch_with_given_accelerations_and_no_inputs():
    """qdd0 as an (N, n_q) array gives K, Q at those accelerations; a model without inputs works."""
    sys = mb.System(gravity=[0, 0, -9.81])
    q1, q2 = sys.coordinates("q1 q2")
    b1 = mb.RigidBody("b1", 1.0, com=[0, 0, -1.0])
    sys.add_joint(mb.Revolute(sys.ground, b1, axis=[0, 1, 0], coordinate=q1))
    sys.add_joint(mb.Revolute(b1, mb.RigidBody("b2", 0.5, com=[0, 0, -0.5]), axis=[1, 0, 0], coordinate=q2,
                              offset=[0, 0, -1.0]))
    eom = sys.equations()
    rng = np.random.default_rng(2)
    X, qdd = rng.normal(size=(4, 4)), rng.normal(size=(4, 2))
    batch = linearize_batch(eom, X, qdd0=qdd)
    for i in range(4):
        lin = mb.linearize(eom, X[i, :2], X[i, 2:], qdd0=qdd[i])
        np.testing.assert_allclose(batch.K[i], lin.K, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(batch.A[i], lin.A, rtol=1e-12, atol=1e-12)
    assert batch.B.shape == (4, 4, 0) and batch.u.shape == (4, 0)


def _oscillator():
    """x: m x'' + c x' + k x = 0, parameters m, c, k without defaults."""
    sys = mb.System()
    x = sys.coordinates("x")
    m, c, k = sys.parameters("m c k")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("b", m), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, k)
    sys.add_damper(x, c)
    return sys.equations(name="oscillator")


def test_batch_sweep_of_parameters_without_default():
    """Sweeping m (no default) works; closed form A = [[0, 1], [-k/m, -c/m]] to 1e-14."""
    from mbsym.exceptions import ParameterError

    eom = _oscillator()
    m = np.array([1.0, 2.0, 4.0])
    batch = linearize_batch(eom, np.zeros((3, 2)), p={"m": m, "c": 0.5, "k": 4.0})
    np.testing.assert_allclose(batch.A[:, 1, 0], -4.0 / m, rtol=1e-14)
    np.testing.assert_allclose(batch.A[:, 1, 1], -0.5 / m, rtol=1e-14)
    np.testing.assert_array_equal(batch.p[:, eom.parameters.index("m")], m)
    for p in ({"m": m, "c": 0.5, "k": 4.0, "mass": [1.0, 2.0, 3.0]}, {"m": m, "c": 0.5, "k": 4.0, "mass": 1.0}):
        with pytest.raises(ParameterError, match=r"unknown parameters \['mass'\]"):
            linearize_batch(eom, np.zeros((3, 2)), p=p)
    with pytest.raises(ParameterError, match=r"missing values for parameters \['k'\]"):
        linearize_batch(eom, np.zeros((3, 2)), p={"m": m, "c": 0.5})
    with pytest.raises(ParameterError, match=r"'m' has non-finite values at points \[1\]"):
        linearize_batch(eom, np.zeros((3, 2)), p={"m": [1.0, np.nan, 2.0], "c": 0.5, "k": 4.0})
    with pytest.raises(DimensionError, match="'m' has 2 values; expected 3"):
        linearize_batch(eom, np.zeros((3, 2)), p={"m": [1.0, 2.0], "c": 0.5, "k": 4.0})


def test_batch_frequencies_follow_the_single_model_rule():
    """Underdamped (c = 0.5) and overdamped (c = 5) points, m = k = 1.

    Closed form: λ = (-c ± sqrt(c² - 4))/2: one pair |λ| = 1 at c = 0.5; two real
    |λ| = (5 ∓ sqrt(21))/2 at c = 5 (then the row has two entries, the other NaN). To 1e-12.
    """
    batch = linearize_batch(_oscillator(), np.zeros((2, 2)), p={"m": 1.0, "c": [0.5, 5.0], "k": 1.0})
    f = batch.frequencies()
    expected = np.array([[1.0, np.nan], [(5 - np.sqrt(21)) / 2, (5 + np.sqrt(21)) / 2]]) / (2 * np.pi)
    np.testing.assert_allclose(f, expected, rtol=1e-12)
    for i in range(2):
        single = batch[i].frequencies()[0]
        np.testing.assert_array_equal(f[i, :single.size], single)
        assert np.all(np.isnan(f[i, single.size:]))


def test_batch_item_keeps_the_rhs(pendulum_eom):
    """batch[i].operating_point['xd'] is linearize's [qd; M⁻¹F] (same Function), to 1e-12."""
    rng = np.random.default_rng(8)
    X, U = rng.normal(size=(3, 4)), rng.normal(size=(3, 1))
    batch = linearize_batch(pendulum_eom, X, U)
    for i in range(3):
        lin = mb.linearize(pendulum_eom, X[i, :2], X[i, 2:], U[i])
        np.testing.assert_allclose(batch[i].operating_point["xd"], lin.operating_point["xd"], rtol=1e-12,
                                   atol=1e-12)
        assert set(batch[i].operating_point) == set(lin.operating_point)
