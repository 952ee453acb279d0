"""The three solvers reach the same optimum; the RK4 sub-step rule.

References: the condensed Gauss–Newton and CasADi's ``sqpmethod`` / ``ipopt`` on the full
multiple-shooting NLP are independent implementations of the same problem (agreement to 1e-6
relative, their tolerances); the sub-step rule against its closed form (m = ceil(|λ| h / (120 tol)^¼)).
"""

from __future__ import annotations

import math

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.identify import choose_substeps

from .conftest import exact_decay


@pytest.fixture(scope="module")
def noisy():
    t = np.arange(0.0, 8.0, 0.05)
    rng = np.random.default_rng(11)
    return {"time": t, "pos": exact_decay(t, 5.0, 0.2) + 0.01 * rng.normal(size=t.size)}


@pytest.mark.parametrize("method", ["sqpmethod", "ipopt"])
def test_nlp_solvers_agree_with_gauss_newton(osc, noisy, method):
    kw = dict(initial={"k": 4.0, "c": 0.15}, estimate_x0=["v"], compile=False)
    gn = mb.identify(osc, noisy, ["k", "c"], **kw)
    other = mb.identify(osc, noisy, ["k", "c"], method=method, **kw)
    assert gn.success and other.success, (gn.message, other.message)
    for k in ("k", "c"):
        assert other.parameters[k] == pytest.approx(gn.parameters[k], rel=1e-6)
        assert other.std[k] == pytest.approx(gn.std[k], rel=1e-4)
    assert other.initial_states[0]["v"] == pytest.approx(gn.initial_states[0]["v"], abs=1e-6)


def test_bounds_are_respected(osc, noisy):
    res = mb.identify(osc, noisy, ["k", "c"], bounds={"c": (0.0, 0.15)}, initial={"c": 0.1}, compile=False)
    assert res.parameters["c"] == pytest.approx(0.15, abs=1e-12)          # unconstrained optimum ~0.2
    assert res.parameters["k"] == pytest.approx(5.0, rel=0.01)


def test_substep_rule():
    """|λ| = ω for an undamped oscillator: m from the frequency-error bound, and the stability cap."""
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 0), ca.SX.sym("p", 1)
    f = ca.Function("f", [x, u, p], [ca.vertcat(x[1], -p[0] * x[0])])
    dyn = mb.Dynamics(f, states=["q", "v"], parameters=["k"], defaults={"k": 1.0})
    for omega, h in ((2.0, 0.02), (40.0, 0.02), (300.0, 0.05)):
        m, lam = choose_substeps(dyn, np.zeros(2), np.zeros(0), np.array([omega ** 2]), h)
        assert lam == pytest.approx(omega, rel=1e-12)
        expected = max(1, math.ceil(omega * h / (120e-6) ** 0.25), math.ceil(omega * h / 2.5))
        assert m == expected
        assert (omega * h / m) ** 4 / 120 <= 1e-6
