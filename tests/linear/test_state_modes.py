"""Modes of first-order models named by participation factors (mbsym.linear.state_modes).

References: participation factors are invariant to a rescaling of the states (a change of units,
T = diag(s): l and r scale by 1/s and s) to round-off (1e-12); they sum to 1 per mode; for a block
triangular A (an oscillator driven by a first-order lag) the lag's eigenvalue is the lag's rate in closed
form and belongs entirely to the lag state (its left eigenvector has no oscillator part).
"""

from __future__ import annotations

import numpy as np
import pytest

from mbsym.exceptions import DimensionError
from mbsym.linear.state_modes import participation_factors, state_groups, state_modes


def _driven_oscillator(k=4.0, c=0.4, rate=50.0):
    return np.array([[0, 1.0, 0], [-k, -c, 1.0], [0, 0, -rate]])


def test_lag_mode_belongs_to_the_lag_state():
    modes = state_modes(_driven_oscillator(), ["x", "x_d", "F"])
    lag = [m for m in modes if m.dominant_dof == "F"]
    assert len(lag) == 1 and lag[0].eigenvalue == pytest.approx(-50.0, rel=1e-12)
    assert lag[0].participation["F"] == pytest.approx(1.0, abs=1e-12)
    osc = [m for m in modes if m.dominant_dof == "x"][0]
    assert osc.freq_hz == pytest.approx(2.0 / (2 * np.pi), rel=1e-12)
    assert osc.damping_ratio == pytest.approx(0.4 / (2 * 2.0), rel=1e-12)
    assert osc.oscillatory and not lag[0].oscillatory


def test_participation_is_unit_invariant():
    rng = np.random.default_rng(3)
    A = rng.normal(size=(6, 6)) - 3 * np.eye(6)
    s = np.array([1e-3, 1.0, 1e4, 57.3, 1e6, 0.1])        # m -> mm, N m -> kN m, ...
    lam1, P1 = participation_factors(A)
    lam2, P2 = participation_factors(np.diag(s) @ A @ np.diag(1 / s))
    order1, order2 = np.argsort(lam1.real + 1e-3 * lam1.imag), np.argsort(lam2.real + 1e-3 * lam2.imag)
    np.testing.assert_allclose(lam1[order1], lam2[order2], rtol=1e-10)
    np.testing.assert_allclose(P1[:, order1], P2[:, order2], atol=1e-9)
    np.testing.assert_allclose(P1.sum(axis=0), 1.0, atol=1e-12)


def test_groups_and_bad_input():
    assert state_groups(["a", "a_d", "b_d", "c"]) == ["a", "a", "b_d", "c"]
    with pytest.raises(DimensionError, match="must be"):
        state_modes(np.eye(2), ["x"])
    with pytest.raises(DimensionError, match="square finite"):
        participation_factors(np.array([[np.nan]]))


def test_rigid_body_mode():
    A = np.array([[0, 1.0], [0, 0]])                          # a free coordinate: double zero
    modes = state_modes(A, ["psi", "psi_d"])
    assert all(m.rigid_body and m.freq_hz == 0 for m in modes) and modes[0].dominant_dof == "psi"
