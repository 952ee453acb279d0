"""Exact Jacobians of the shooting Functions and the gradient of the fit objective vs central finite differences.

Reference: central differences of the same numeric Functions (step 1e-6 relative), tolerance ~sqrt(step)
scaled to the quantity (the practice of Pinocchio's derivative tests, shared/guide/TESTING.md).
"""

from __future__ import annotations

import numpy as np
import pytest

import mbsym as mb
from mbsym.identify.gauss_newton import ShootingRecord, condensed, linearize
from mbsym.identify.shooting import ShootingFunctions

THETA = ["tower_fa1_damping_ratio", "tower_fa1_stiffness_tuner", "nacelle_mass"]
CHANNELS = ["Q_TFA1", "QD_TFA1", "Q_TSS1", "YawBrTDxp"]


@pytest.fixture(scope="module")
def setup(tower_model):
    dyn = mb.as_dynamics(tower_model)
    rows = [("y", dyn.output_names.index(c)) for c in CHANNELS]
    idx = [dyn.parameters.index(n) for n in THETA]
    fun = ShootingFunctions(dyn, rows, idx, 2, 2, compile=False)      # two free initial states, 2 sub-steps
    return dyn, fun, idx


def _close(a, b, rtol=1e-5):
    """|a - b| <= rtol * (largest entry of b's column): FD roundoff scales with the column, not the entry."""
    scale = np.max(np.abs(b), axis=tuple(range(b.ndim - 1)), keepdims=True)
    assert np.all(np.abs(a - b) <= rtol * np.maximum(scale, 1e-300)), np.max(np.abs(a - b) / scale)


def _fd(f, z0, step):
    cols = []
    for j in range(z0.size):
        dz = np.zeros_like(z0)
        dz[j] = step[j]
        cols.append((f(z0 + dz) - f(z0 - dz)) / (2 * step[j]))
    return np.stack(cols, axis=-1)


def test_interval_and_output_jacobians_match_finite_differences(setup):
    dyn, fun, idx = setup
    rng = np.random.default_rng(1)
    X = dyn.x0 + 0.2 * rng.normal(size=(3, dyn.n_x))
    U = np.zeros((3, dyn.n_u))
    p = dyn.parameter_vector()
    th = p[idx] * np.array([0.9, 1.1, 1.05])
    H = np.full(3, 0.05)
    xn, A, B = fun.intervals_jac(X, U, U, th, p, H)
    np.testing.assert_allclose(xn, fun.intervals(X, U, U, th, p, H), rtol=1e-14, atol=1e-14)
    for k in range(3):
        fx = _fd(lambda x: fun.intervals(x[None], U[:1], U[:1], th, p, H[:1])[0], X[k], np.full(dyn.n_x, 1e-6))
        ft = _fd(lambda t: fun.intervals(X[k:k + 1], U[:1], U[:1], t, p, H[:1])[0], th, 1e-6 * np.abs(th))
        _close(A[k], fx)
        _close(B[k], ft)
    y, C, D = fun.outputs(X, U, th, p, jac=True)
    cx = _fd(lambda x: fun.outputs(x[None], U[:1], th, p)[0], X[1], np.full(dyn.n_x, 1e-6))
    ct = _fd(lambda t: fun.outputs(X[1:2], U[:1], t, p)[0], th, 1e-6 * np.abs(th))
    _close(C[1], cx)
    _close(D[1], ct)


def test_gradient_of_the_fit_objective_matches_finite_differences(setup):
    """Jᵀr of the condensed Jacobian (free initial states and parameters) = ∇ ½‖r(simulate(x0, θ))‖²."""
    dyn, fun, idx = setup
    n = 120
    t = 0.05 * np.arange(n + 1)
    p = dyn.parameter_vector()
    th = p[idx] * np.array([1.2, 0.9, 1.1])
    U = np.zeros((n + 1, dyn.n_u))
    H = np.diff(t)
    Y = fun.outputs(fun.simulate(dyn.x0, U, p[idx], p, H), U, p[idx], p)      # "data" at the deck's values
    rec = ShootingRecord(U, H, Y, np.array([1.0, 3.0, 1.0, 1.0]), np.zeros(4), dyn.x0.copy(), np.array([0, 2]))

    def objective(z):                       # z = (free x0 entries, theta)
        x0 = dyn.x0.copy()
        x0[rec.free0] = z[:2]
        S = fun.simulate(x0, U, z[2:], p, H)
        r = (fun.outputs(S, U, z[2:], p) - Y) * rec.w
        return np.array(0.5 * np.sum(r ** 2))

    x0 = dyn.x0.copy()
    S = fun.simulate(x0, U, th, p, H)       # nodes on the trajectory: zero gaps
    lin, r, g = linearize(fun, rec, S, th, p)
    assert np.max(np.abs(g)) < 1e-12
    _, J, rl = condensed(fun, rec, lin, r, g)
    grad = J.T @ r.reshape(-1)
    z0 = np.concatenate([x0[rec.free0], th])
    step = 1e-6 * np.maximum(np.abs(z0), 1e-2)
    fd = _fd(objective, z0, step)
    np.testing.assert_allclose(grad, fd, rtol=1e-5)
    np.testing.assert_allclose(rl, r.reshape(-1), atol=1e-12)        # no gaps: nothing to close
