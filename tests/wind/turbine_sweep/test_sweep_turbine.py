"""``sweep_turbine``: values reach the model, wind runs reproduce ``simulate_turbine``, executors agree bit for bit.

References:
- one tower fore-aft DOF without gravity: ``K = τ K̂`` and ``C = 2 ζ sqrt(M τ K̂)`` (ElastoDyn's
  tuner and damping, mbsym.wind.structure.named_parameters), so the damped frequency scales as
  sqrt(τ) exactly (zero crossings of the free decay, tolerance 2e-4) and the damping ratio of the
  oscillator, from the logarithmic decrement, is proportional to TwrFADmp(1) (tolerance 1 %);
- a wind case of the sweep against ``mbsym.wind.operation.simulate_turbine`` run directly with
  the same controller, wind and initial state (the product path of ``mbsym simulate --wind``);
- serial, processes:2 and dask:2 (LocalCluster on 127.0.0.1) give equal tables bit for bit.
"""

import math

import numpy as np
import pytest

from mbsym.wind.analysis.sweep import sweep_turbine


@pytest.fixture(scope="module")
def one_dof():
    from mbsym.wind import TurbineModel, nrel5mw

    return TurbineModel(nrel5mw(), dofs=["TwFADOF1"])


def crossings(t, y):
    """Times of the downward zero crossings of y (linear interpolation)."""
    i = np.flatnonzero((y[:-1] > 0) & (y[1:] <= 0))
    return t[i] - y[i] * (t[i + 1] - t[i]) / (y[i + 1] - y[i])


def test_stiffness_tuner_scales_the_tower_frequency_as_its_square_root(one_dof):
    res = sweep_turbine(one_dof, {"Gravity": [0.0], "FAStTunr(1)": [0.9, 1.1], "TTDspFA": [0.5]}, tmax=20.0,
                        dt=0.005, channels=["TTDspFA"], series=True)
    assert res.table.failed == []
    assert [c.p["tower_fa1_stiffness_tuner"] for c in res.cases] == [0.9, 1.1]
    periods = []
    for s in res.series:
        tc = crossings(s.t, s.output("TTDspFA"))
        periods.append((tc[-1] - tc[0]) / (len(tc) - 1))
    assert periods[0] / periods[1] == pytest.approx(math.sqrt(1.1 / 0.9), rel=2e-4)


def test_damping_key_in_percent_scales_the_logarithmic_decrement(one_dof):
    res = sweep_turbine(one_dof, {"Gravity": [0.0], "TwrFADmp(1)": [2.0, 5.0], "TTDspFA": [0.5]}, tmax=12.0,
                        dt=0.005, channels=["TTDspFA"], series=True)
    assert [c.p["tower_fa1_damping_ratio"] for c in res.cases] == [0.02, 0.05]
    measured = []
    for s in res.series:
        y = s.output("TTDspFA")
        peaks = [k for k in range(1, len(y) - 1) if y[k] > y[k - 1] and y[k] >= y[k + 1] and y[k] > 0]
        delta = math.log(y[peaks[0]] / y[peaks[-1]]) / (len(peaks) - 1)
        measured.append(delta / math.sqrt(4 * math.pi ** 2 + delta ** 2))
    # ElastoDyn's damping refers to the beam's own modal mass (C = 2 ζ K / ω_beam), so with the tower-top mass
    # the oscillator's ratio is ζ sqrt(M_beam / M_total) < ζ; it stays proportional to TwrFADmp(1)
    assert measured[1] / measured[0] == pytest.approx(2.5, rel=1e-2)
    assert 0.0 < measured[0] < 0.02


def test_a_wind_case_equals_simulate_turbine_with_the_same_inputs():
    from mbsym.sweep import channel_statistics
    from mbsym.wind.control import BaselineController
    from mbsym.wind.inflow import parse_wind_spec
    from mbsym.wind.operation.controllers import baseline_in_loop
    from mbsym.wind.operation.deck import builtin_deck
    from mbsym.wind.operation.simulation import simulate_turbine
    from mbsym.wind.operation.steady import steady_guess

    spec, tmax = "step:9:11:1", 2.0
    res = sweep_turbine(None, {"TwrFADmp(1)": [3.0]}, wind=[spec], tmax=tmax, channels=["GenPwr", "TwrBsMyt"],
                        compile=False)
    assert res.table.failed == []
    deck = builtin_deck()
    model = deck.model()
    p = {"tower_fa1_damping_ratio": 0.03}
    wind = parse_wind_spec(spec, duration=tmax)
    x0 = steady_guess(model, 9.0, settings=deck.baseline_settings(), p=p).state
    ctrl = baseline_in_loop(BaselineController(deck.baseline_settings()))
    direct = simulate_turbine(model, wind, tmax, controller=ctrl, x0=x0, p=p, compile=False,
                              t_out=np.round(np.arange(41) * 0.05, 12))
    cols = {n: direct.output(n) for n in ("GenPwr", "TwrBsMyt")}
    want = channel_statistics(direct.t, cols, channels=["GenPwr", "TwrBsMyt"])
    for k, v in want.items():
        assert res.table[k][0] == pytest.approx(v, rel=1e-12, abs=1e-9), k


def _same(a, b):
    assert a.columns == b.columns
    for c in a.columns:
        if c in ("error", "wind"):
            assert a[c] == b[c]
        else:
            np.testing.assert_array_equal(a[c], b[c], err_msg=c)          # bit for bit (NaN = NaN)


def test_wind_sweep_is_the_same_bit_for_bit_on_every_executor():
    pytest.importorskip("distributed")
    kw = dict(wind=["steady:8", "kaimal:13:0.12:7"], tmax=1.5, channels=["GenPwr", "TTDspFA", "TwrBsMyt"],
              del_channels=["TwrBsMyt"], wohler=4.0)
    grid = {"TwrFADmp(1)": [1.0, -2.0], "air_density": [1.225]}
    serial = sweep_turbine(None, grid, **kw)
    assert len(serial.table) == 4 and len(serial.table.failed) == 2      # a negative damping ratio fails its rows
    assert serial.table.columns[:3] == ("TwrFADmp(1)", "air_density", "wind")
    assert "TwrBsMyt_del_m4" in serial.table.columns
    _same(serial.table, sweep_turbine(None, grid, executor="processes:2", **kw).table)
    _same(serial.table, sweep_turbine(None, grid, executor="dask:2", **kw).table)


def test_free_decay_sweep_is_the_same_bit_for_bit_on_dask():
    pytest.importorskip("distributed")
    kw = dict(tmax=1.0, channels=["TTDspFA", "GenSpeed"])
    grid = {"FAStTunr(1)": [0.9, 1.1], "NacMass": [2.0e5, 2.4e5]}
    _same(sweep_turbine(None, grid, **kw).table, sweep_turbine(None, grid, executor="dask:2", **kw).table)
