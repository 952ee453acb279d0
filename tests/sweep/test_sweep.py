"""mb.sweep on small models with closed forms (in-process executor).

References: an undamped spring-mass x(t) = x0 cos(sqrt(k/m) t) (RK4 with dt = 0.01 s is exact
to ~1e-9 over 2 s: tolerance 1e-7); mb.simulate(method="rk4") (the same RK4 formula: equal to
1e-14); a spring-mass-damper's natural frequency and damping ratio (linearize, 1e-12); a
sinusoidal input's damage-equivalent load 2 A (f / f_eq)^(1/m) (rainflow, 1e-12).
"""

import csv
import math

import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import SweepError
from mbsym.sweep import grid, sweep


def oscillator(damping=0.0):
    sys = mb.System()
    x = sys.coordinates("x")
    m, k, c = sys.parameters("m k c", values={"m": 1.0, "k": 4.0, "c": damping})
    force = sys.inputs("F")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("body", m), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, k)
    sys.add_damper(x, c)
    sys.add_generalized_force(x, force)
    return sys.equations(name="oscillator")


@pytest.fixture(scope="module")
def eom():
    return oscillator()


def test_grid_order_and_columns(eom):
    assert grid({"k": [1, 2]}, m=[3, 4]) == [{"k": 1, "m": 3}, {"k": 1, "m": 4}, {"k": 2, "m": 3}, {"k": 2, "m": 4}]
    res = sweep(eom, {"k": [1.0, 9.0], "m": [1.0, 4.0]}, tmax=2.0, x0={"x": 1.0}, channels=["x", "F"])
    assert res.table.columns == ("k", "m", "x_mean", "x_std", "x_max", "x_min",
                                 "F_mean", "F_std", "F_max", "F_min", "error")
    assert len(res.table) == 4 and res.table.failed == []
    np.testing.assert_array_equal(res.table["k"], [1, 1, 9, 9])


def test_statistics_follow_the_closed_form(eom):
    ks = [1.0, 4.0, 9.0]
    res = sweep(eom, {"k": ks}, tmax=2.0, x0={"x": 1.0}, channels=["x"])
    t = 0.01 * np.arange(201)
    for i, k in enumerate(ks):
        x = np.cos(np.sqrt(k) * t)
        row = res.table.row(i)
        assert row["x_mean"] == pytest.approx(x.mean(), abs=1e-7)
        assert row["x_std"] == pytest.approx(x.std(), abs=1e-7)
        assert row["x_max"] == pytest.approx(1.0, abs=1e-12) and row["x_min"] == pytest.approx(x.min(), abs=1e-7)


def test_series_equal_mb_simulate_rk4(eom):
    res = sweep(eom, [{"k": 2.0, "x": 0.5, "F": 0.3}], tmax=1.5, dt=0.01, series=True)
    ref = mb.simulate(eom, 1.5, x0=[0.5, 0.0], inputs={"F": 0.3}, p={"k": 2.0}, method="rk4", dt=0.01)
    got = res.series[0]
    np.testing.assert_array_equal(got.t, ref.t)
    np.testing.assert_allclose(got.x, ref.x, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(got.u, ref.u)


def test_failures_are_recorded_per_case(eom):
    def setter(value):
        if value == "bad":
            raise ValueError("no such stiffness")
        return {"p": {"k": float(value)}}

    res = sweep(eom, [{"k": 4.0}, {"k": -1e12}, {"stiff": "bad"}, {"stiff": 9.0}, {"k": math.nan}],
                tmax=2.0, x0={"x": 1.0}, channels=["x"], setters={"stiff": setter})
    err = res.table["error"]
    assert err[0] == "" and err[3] == ""
    assert err[1].startswith("IntegrationError: the states are not finite")
    assert err[2] == "ValueError: no such stiffness"
    assert err[4].startswith("ParameterError") and "k" in err[4]
    assert res.table.failed == [1, 2, 4]
    assert np.isnan(res.table["x_mean"][[1, 2, 4]]).all() and np.isfinite(res.table["x_mean"][[0, 3]]).all()
    assert res.table["stiff"][3] == 9.0 and res.table["k"][3] is None


def test_inputs_per_case_and_damage_equivalent_loads(eom):
    pytest.importorskip("rainflow")
    amp, f = 2.0, 0.5
    cases = [{"F": (lambda a: (lambda t: a * np.cos(2 * np.pi * f * t)))(a)} for a in (amp, 2 * amp)]
    res = sweep(eom, cases, tmax=8.0, dt=0.025, channels=["F"], del_channels=["F"], wohler=(4, 10))
    for i, a in enumerate((amp, 2 * amp)):
        assert res.table["F_del_m4"][i] == pytest.approx(2 * a * f ** 0.25, rel=1e-12)
        assert res.table["F_del_m10"][i] == pytest.approx(2 * a * f ** 0.1, rel=1e-12)
        assert res.table["F_max"][i] == pytest.approx(a, rel=1e-15)


def test_linearize_gives_frequency_and_damping():
    eom = oscillator(damping=0.4)
    res = sweep(eom, {"k": [4.0, 16.0], "m": [1.0, 2.0]}, run="linearize", n_modes=1, series=True)
    for row, lin in zip(res.table.rows(), res.series):
        k, m = row["k"], row["m"]
        assert row["mode1_freq_hz"] == pytest.approx(np.sqrt(k / m) / (2 * np.pi), rel=1e-12)
        assert row["mode1_damping"] == pytest.approx(0.4 / (2 * np.sqrt(k * m)), rel=1e-12)
        np.testing.assert_allclose(lin["A"], [[0, 1], [-k / m, -0.4 / m]], rtol=1e-14)


def runner(case):
    if case.p.get("k", 0.0) < 0:
        raise RuntimeError("negative stiffness")
    return {"period_s": 2 * np.pi / np.sqrt(case.p["k"])}


def test_callable_runner(eom):
    res = sweep(eom, {"k": [4.0, -1.0]}, run=runner)
    assert res.table.columns == ("k", "period_s", "error")
    assert res.table["period_s"][0] == pytest.approx(np.pi)
    assert res.table["error"][1] == "RuntimeError: negative stiffness"


def test_csv_round_trips_exactly(eom, tmp_path):
    res = sweep(eom, {"TwrFADmp(1)": [0.1], "k": [1.0 / 3.0]}, tmax=1.0, channels=["x"],
                setters={"TwrFADmp(1)": lambda v: {"p": {"c": v}}})
    path = res.to_csv(tmp_path / "table.csv")
    with path.open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["TwrFADmp(1)", "k", "x_mean", "x_std", "x_max", "x_min", "error"]
    assert float(rows[1][1]) == 1.0 / 3.0 and float(rows[1][2]) == res.table["x_mean"][0] and rows[1][-1] == ""


def test_bad_sweeps_raise_before_running(eom):
    with pytest.raises(SweepError, match=r"case keys \['stiffness'\]"):
        sweep(eom, {"stiffness": [1.0]}, tmax=1.0)
    with pytest.raises(mb.SimulationOptionError, match="tmax"):
        sweep(eom, {"k": [1.0]}, tmax=-1.0)
    with pytest.raises(SweepError, match="need tmax"):
        sweep(eom, {"k": [1.0]})
    with pytest.raises(SweepError, match="executor 'gpu:2'"):
        sweep(eom, {"k": [1.0]}, tmax=1.0, executor="gpu:2")
    with pytest.raises(SweepError, match=r"channels \['y'\]"):
        sweep(eom, {"k": [1.0]}, tmax=1.0, channels=["y"])
    with pytest.raises(SweepError, match="wohler"):
        sweep(eom, {"k": [1.0]}, tmax=1.0, wohler=-3)
    with pytest.raises(SweepError, match="run must be"):
        sweep(eom, {"k": [1.0]}, run="identify")
    with pytest.raises(SweepError, match="cases is empty"):
        sweep(eom, [], tmax=1.0)
    with pytest.raises(TypeError):
        sweep(eom, {"k": [1.0]}, tmax=1.0, workers=2)


def test_progress_bar_on_request(eom, capsys):
    res = sweep(eom, {"k": [1.0, -1e12]}, tmax=0.5, channels=["x"], x0={"x": 1.0}, progress=True)
    err = capsys.readouterr().err
    assert "sweep [" in err and "2/2 cases, 1 failed" in err and len(res.table.failed) == 1
    sweep(eom, {"k": [1.0]}, tmax=0.5, channels=["x"])          # not a terminal: no bar by default
    assert capsys.readouterr().err == ""
