"""Standard errors, correlations and the identifiability warning.

Reference: a Monte-Carlo spread over independent noise realizations (the estimator's actual
scatter), the truth used to make the data, and a model whose two parameters enter only as a
product (exactly collinear). Tolerances: estimates within 3 standard errors; the reported standard
errors within 30 % of the Monte-Carlo spread (40 realizations: the spread itself is known to
~11 %, 1/sqrt(2·40)).
"""

from __future__ import annotations

import warnings

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import IdentifiabilityWarning

from .conftest import exact_decay


def test_standard_errors_match_a_monte_carlo_spread(osc):
    t = np.arange(0.0, 15.0, 0.05)
    q = exact_decay(t, 5.0, 0.2)
    sigma = 0.02
    rng = np.random.default_rng(2024)
    est, std = [], []
    for _ in range(40):
        res = mb.identify(osc, {"time": t, "pos": q + sigma * rng.normal(size=t.size)}, ["k", "c"],
                          initial={"k": 4.0, "c": 0.16}, substeps=4, compile=False)
        assert res.success, res.message
        est.append([res.parameters["k"], res.parameters["c"]])
        std.append([res.std["k"], res.std["c"]])
        assert res.residual_std == pytest.approx(sigma * res.weights["pos"], rel=0.15)   # weighted units
    est, std = np.array(est), np.array(std)
    within = np.abs(est - [5.0, 0.2]) <= 3 * std
    assert within.mean() >= 0.95                          # 3 sigma: 99.7 % expected
    spread = est.std(axis=0, ddof=1)
    np.testing.assert_allclose(std.mean(axis=0), spread, rtol=0.3)
    assert np.all(np.abs(est.mean(axis=0) - [5.0, 0.2]) < 3 * spread / np.sqrt(len(est)))   # unbiased


def test_correlation_is_symmetric_with_unit_diagonal(osc):
    t = np.arange(0.0, 8.0, 0.05)
    rng = np.random.default_rng(7)
    res = mb.identify(osc, {"time": t, "pos": exact_decay(t, 5.0, 0.2) + 0.01 * rng.normal(size=t.size)},
                      ["k", "c"], compile=False)
    C = res.correlation
    np.testing.assert_allclose(C, C.T, atol=1e-14)
    np.testing.assert_allclose(np.diag(C), 1.0)
    assert np.all(np.abs(C) <= 1.0 + 1e-12)
    np.testing.assert_allclose(np.sqrt(np.diag(res.covariance)), [res.std["k"], res.std["c"]], rtol=1e-12)


def test_collinear_parameters_warn():
    """q'' = -(a b) q: only the product a b is determined."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 0), ca.SX.sym("p", 2)
    f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] * p[1] * x[0] - 0.1 * x[1])])
    dyn = mb.Dynamics(f, states=["q", "v"], parameters=["a", "b"], defaults={"a": 2.0, "b": 2.0}, x0=[1.0, 0.0])
    t = np.arange(0.0, 8.0, 0.05)
    data = {"time": t, "q": exact_decay(t, 5.0, 0.1) + 1e-3 * np.random.default_rng(0).normal(size=t.size)}
    with pytest.warns(IdentifiabilityWarning, match="a.*b"):
        res = mb.identify(dyn, data, ["a", "b"], compile=False)
    assert res.parameters["a"] * res.parameters["b"] == pytest.approx(5.0, rel=1e-3)


def test_well_separated_parameters_do_not_warn(osc):
    t = np.arange(0.0, 10.0, 0.05)
    with warnings.catch_warnings():
        warnings.simplefilter("error", IdentifiabilityWarning)
        mb.identify(osc, {"time": t, "pos": exact_decay(t, 5.0, 0.2)}, ["k", "c"], compile=False)


def test_unobserved_initial_state_stays_and_warns():
    """A third state no channel sees: its initial value is kept, its standard error is inf, a warning says so."""
    x, u, p = ca.SX.sym("x", 3), ca.SX.sym("u", 0), ca.SX.sym("p", 2)
    f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0] - p[1] * x[1], 0.1 + 1e-14 * x[0])])
    dyn = mb.Dynamics(f, states=["q", "v", "a"], parameters=["k", "c"], defaults={"k": 4.0, "c": 0.1},
                      x0=[1.0, 0.0, 5.0])
    t = np.arange(0.0, 8.0, 0.05)
    with pytest.warns(IdentifiabilityWarning, match="initial states: \\['a'\\]"):
        res = mb.identify(dyn, {"time": t, "q": exact_decay(t, 5.0, 0.2)}, ["k", "c"], estimate_x0=True,
                          substeps=4, compile=False)
    assert res.success and res.iterations < 15, res.message
    assert res.initial_states[0]["a"] == pytest.approx(5.0, abs=1e-9)
    assert res.initial_state_std[0]["a"] == np.inf
    assert np.isfinite(res.initial_state_std[0]["q"])
    assert res.parameters["k"] == pytest.approx(5.0, rel=1e-7)
