"""Per-case statistics and damage-equivalent loads against closed forms.

References: a cosine of amplitude A sampled at its peaks has mean 0, population std A/sqrt(2),
max A, min -A; over a whole number of periods it is f T full cycles of range 2A, so
DEL = (f T (2A)^m / (f_eq T))^(1/m) = 2 A (f / f_eq)^(1/m) (rainflow counting, Wöhler exponent m).
Modal summary: a spring-mass-damper has wn = sqrt(k/m), zeta = c / (2 sqrt(k m)).
"""

import numpy as np
import pytest

from mbsym.sweep import channel_statistics, damage_equivalent_load, modal_summary

pytest.importorskip("rainflow")

A, F, T = 2.5, 0.5, 40.0


def cosine(samples_per_period=40):
    t = np.linspace(0.0, T, int(T * F * samples_per_period) + 1)
    return t, A * np.cos(2 * np.pi * F * t)


@pytest.mark.parametrize("m", [3.0, 4.0, 10.0])
@pytest.mark.parametrize("f_eq", [1.0, 0.1])
def test_del_of_a_pure_sine(m, f_eq):
    t, y = cosine()
    expected = 2 * A * (F * T / (f_eq * T)) ** (1 / m)
    assert damage_equivalent_load(y, T, m, frequency=f_eq) == pytest.approx(expected, rel=1e-12)


def test_statistics_and_del_columns_and_t_start():
    t, y = cosine()
    ramp = np.where(t < 10.0, 100.0, y)                  # a transient the statistics must drop
    out = channel_statistics(t, {"y": ramp}, channels=["y"], del_channels=["y"], wohler=(4.0, 10.0), t_start=10.0)
    assert list(out) == ["y_mean", "y_std", "y_max", "y_min", "y_del_m4", "y_del_m10"]
    assert out["y_mean"] == pytest.approx(0.0, abs=0.1 * A / t.size * 40)   # one extra peak sample in the window
    assert out["y_max"] == A and out["y_min"] == -A
    keep = t >= 10.0
    assert out["y_std"] == pytest.approx(np.sqrt(np.mean(y[keep] ** 2) - np.mean(y[keep]) ** 2), rel=1e-12)
    assert out["y_std"] == pytest.approx(A / np.sqrt(2), rel=1e-3)
    assert out["y_del_m4"] == pytest.approx(2 * A * F ** 0.25, rel=1e-12)


def test_modal_summary_of_a_spring_mass_damper():
    m, k, c = 2.0, 50.0, 1.5
    A_ = np.array([[0.0, 1.0], [-k / m, -c / m]])
    cols, lam = modal_summary(A_, 2)
    assert cols["mode1_freq_hz"] == pytest.approx(np.sqrt(k / m) / (2 * np.pi), rel=1e-12)
    assert cols["mode1_damping"] == pytest.approx(c / (2 * np.sqrt(k * m)), rel=1e-12)
    assert np.isnan(cols["mode2_freq_hz"]) and lam.size == 2
