"""InflowWind's ``VelInterpCubic = True`` (cubic in time) against OpenFAST v5.0.0.

References: OpenFAST v5.0.0 runs with 9 output points (``ifw_reference.py``, cases ``*_cubic``; 9 significant
digits): a uniform file with uneven rows, a step and a gust (every column changing); TurbSim fields without tower
points (ff14), with 3 tower points (periodic and not, the latter into InflowWind's last time step) and a HAWC box
with its mean profile. Measured: at most 9.6e-7 m/s (uniform), 1.14e-6 m/s (full fields: u and v everywhere, all
components along the tower). Inside a full field's grid OpenFAST's w uses uninitialised slopes (see
``mbsym/wind/inflow/cubic.py``) and is not compared. Independent checks: the slopes against scipy's clamped spline,
the C External and the hub signals against the numpy evaluation.
"""

from __future__ import annotations

import numpy as np
import pytest

from mbsym.codegen import find_compiler
from mbsym.exceptions import ModelWarning
from mbsym.wind.deck.inflowwind import deck_inflowwind, read_inflowwind
from mbsym.wind.inflow import (HermiteTableWind, UniformFieldWind, UniformWind, read_turbsim_bts,
                               read_uniform_wind)
from mbsym.wind.inflow.cubic import uniform_slopes

from .conftest import AERO, need
from .ifw_reference import CASES, DATA, read_reference, write_case

DEG = np.pi / 180.0
TOL = 1.2e-6                                            # OpenFAST's 9 significant digits of ~10 m/s, float32 data
FULL = {"ff14_cubic": None, "tower_periodic_cubic": "tower_periodic.bts", "tower_cubic": "tower_nonperiodic.bts"}
TOWER_ROWS = [2, 3, 4, 5]                               # points along the tower (2-D cells) of the tower cases


def _deck_field(tmp_path, case):
    write_case(tmp_path, case)
    settings = read_inflowwind(tmp_path / f"{case}_IfW.dat")
    if CASES[case]["WindType"] == 2:
        return settings, settings.field()
    with pytest.warns(ModelWarning, match="key 'VelInterpCubic'.*uninitialised slopes"):
        return settings, settings.field()


def test_uniform_file_with_a_step_against_openfast(tmp_path):
    settings, field = _deck_field(tmp_path, "uniform_cubic")
    assert isinstance(field, UniformFieldWind) and field.cubic
    t, ref = read_reference("uniform_cubic")
    pts = np.array(CASES["uniform_cubic"]["points"])
    v = field.velocity(t, pts, below_ground="zero")
    assert np.abs(v - ref).max() <= TOL
    linear = UniformFieldWind(field.table, 90.0, 125.0, 7.0 * DEG, 2.0 * DEG).velocity(t, pts, below_ground="zero")
    assert np.abs(linear - ref).max() > 1.0            # between rows linear and cubic differ by metres per second


@pytest.mark.parametrize("case", list(FULL))
def test_turbsim_fields_against_openfast(case):
    bts = need(AERO / "wind" / "ff14.bts") if FULL[case] is None else DATA / FULL[case]
    field = read_turbsim_bts(bts).with_cubic()
    t, ref = read_reference(case)
    v = field.velocity(t, np.array(CASES[case]["points"]))
    assert np.abs(v - ref)[..., :2].max() <= TOL
    if case != "ff14_cubic":
        assert np.abs(v - ref)[:, TOWER_ROWS].max() <= TOL
    linear = field.with_cubic(False).velocity(t, np.array(CASES[case]["points"]))
    assert np.abs(linear - ref)[..., 0].max() > 0.05    # a linear interpolation fails this case


def test_hawc_box_with_mean_profile_against_openfast(tmp_path):
    _, field = _deck_field(tmp_path, "hawc_direct_cubic")
    assert field.cubic and field.mean_profile is not None
    t, ref = read_reference("hawc_direct_cubic")
    v = field.velocity(t, np.array(CASES["hawc_direct_cubic"]["points"]))
    assert np.abs(v - ref)[..., :2].max() <= TOL


def test_value_between_samples_is_the_cubic_not_the_linear():
    """Fast: a three-row table, hand-computed clamped spline (0, 1, 3 m/s at 0, 1, 2 s; zero end slopes:
    m0 + 4 m1 + m2 = 3 (y2 - y0) / h gives m1 = 9/4 m/s²)."""
    table = UniformWind([0.0, 1.0, 2.0], [0.0, 1.0, 3.0])
    assert np.allclose(uniform_slopes(table.time, table.speed), [0.0, 2.25, 0.0], atol=1e-7)
    cubic = UniformFieldWind(table, 90.0, 100.0, cubic=True)
    # t = 1.5: C1 = C3 = 1/2, C2 = h/8, C4 = -h/8: 2 + 2.25/8 (linear: 2)
    assert cubic.columns_at(1.5)["speed"] == pytest.approx(2.0 + 2.25 / 8.0, abs=1e-7)
    assert UniformFieldWind(table, 90.0, 100.0).columns_at(1.5)["speed"] == 2.0
    assert cubic.columns_at(-1.0)["speed"] == 0.0 and cubic.columns_at(9.0)["speed"] == 3.0   # held at the ends


def test_slopes_are_a_clamped_spline():
    from scipy.interpolate import CubicSpline

    rng = np.random.default_rng(3)
    x = np.cumsum(rng.uniform(0.05, 1.0, 12))
    y = rng.normal(size=(12, 3))
    ref = CubicSpline(x, y, bc_type="clamped")(x, 1)
    ref[-1] = 0.0                                       # InflowWind sets the last row's slope to 0
    assert np.allclose(uniform_slopes(x, y), ref, rtol=1e-6, atol=1e-6)


def test_full_field_cubic_is_a_zero_slope_step_between_slices():
    field = read_turbsim_bts(DATA / "tower_periodic.bts")
    p = np.array([[0.0, 10.0, 95.0]])
    lo, hi = field.velocity(0.0, p), field.velocity(0.1, p)
    s = 0.3
    c3 = 3 * s * s - 2 * s ** 3
    assert np.allclose(field.with_cubic().velocity(0.1 * s, p), (1 - c3) * lo + c3 * hi, atol=1e-12)


@pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")
def test_compiled_external_equals_numpy(tmp_path, monkeypatch):
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    field = read_turbsim_bts(DATA / "tower_nonperiodic.bts").with_rotation(0.2, 0.03).with_cubic()
    pts = np.array(CASES["tower_cubic"]["points"])
    f = field.casadi_function(pts.shape[0])
    for t in (0.0, 0.37, 3.91, 7.45):
        assert np.allclose(np.array(f(t, pts.T)).T, field.velocity(t, pts), rtol=1e-12, atol=1e-12)
    linear = field.with_cubic(False)
    assert linear.content_hash != field.content_hash
    from mbsym.wind.inflow.field_casadi import full_field_c_source

    assert "2.0 * s * s * s" not in full_field_c_source(linear, 3, "f", tmp_path / "d.f32")


def test_hub_signals_follow_the_field(tmp_path):
    settings, field = _deck_field(tmp_path, "uniform_cubic")
    hub = settings.wind(allow_unmodelled=True)
    t = np.linspace(-0.5, 3.6, 83)
    c = field.columns_at(t)
    expected = (c["speed"] + c["gust_speed"]) * np.cos(c["upflow"]) * np.cos(c["direction"])
    assert np.allclose(hub(t), expected, atol=1e-12)
    casadi = hub.to_casadi()
    assert np.allclose([float(casadi(x)) for x in t], expected, atol=1e-12)
    ff = read_turbsim_bts(DATA / "tower_periodic.bts").with_cubic()
    times = ff.dt * np.arange(ff.n_t)
    table = HermiteTableWind(times, ff.velocity(times, [0.0, 0.0, 90.0])[:, 0], np.zeros(ff.n_t))
    tt = np.linspace(0.0, 19.9, 97)
    assert np.allclose(table(tt), ff.velocity(tt, [0.0, 0.0, 90.0])[:, 0], atol=1e-12)
    assert np.allclose([float(table.to_casadi()(x)) for x in tt], table(tt), atol=1e-12)


def test_linearization_turns_cubic_off_as_inflowwind(tmp_path):
    fst = write_case(tmp_path, "uniform_cubic")
    text = fst.read_text()
    fst.write_text(text.replace("False         Linearize", "True          Linearize", 1))
    assert "True          Linearize" in fst.read_text()
    with pytest.warns(ModelWarning, match="disables cubic interpolation of the wind for linearization"):
        settings = deck_inflowwind(fst)
    assert not settings.cubic_interpolation and not settings.field().cubic


def test_hub_series_of_a_non_periodic_field(tmp_path):
    """The hub-height series of a non-periodic field starts at t = -x0/URef, where the field's first slice is; read
    there it once fell a rounding error outside the data (τ < 0) and was refused. Now it is the field's own hub
    series (linear and cubic in time), within a billionth of a step of its ends."""
    _, field = _deck_field(tmp_path, "tower_cubic")
    settings = read_inflowwind(tmp_path / "tower_cubic_IfW.dat")
    with pytest.warns(ModelWarning):
        hub = settings.wind(allow_unmodelled=True)
    t0, t1 = field.time_range
    t = np.linspace(t0 + 0.05, t1 - 0.05, 57)
    assert np.allclose(hub(t), field.velocity(t, [0.0, 0.0, field.reference_height])[:, 0], atol=1e-6)
