"""Full-field wind: the TurbSim .bts reader and FullFieldWind.velocity against InflowWind.

References:
- TurbSim's own hub-point series of the shared ff14 field (``ff14.hh``: HorSpd = |(u, v)|, WndDir =
  -atan2(v, u), VerSpd = w at the hub grid point, row i at i dt; TS_FileIO.f90 ``WrHH_ADtxtfile``);
- OpenFAST v5.0.0's InflowWind itself: ``Wind1VelX/Y/Z`` of the shared ff14_rigid run at the hub, and
  9 points per case written by OpenFAST (``ifw_reference.py``; stored in ``data/``): off-node points,
  upwind/downwind, rotated box, a periodic TurbSim field with tower points (below the grid, below the last
  tower point, grid tolerance, wrap-around);
- closed forms: a field linear in y, z and time is interpolated exactly; Taylor's advection shifts time by
  x / URef.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, WindFieldDomainError
from mbsym.wind.inflow import FullFieldWind, read_turbsim_bts, write_turbsim_bts
from mbsym.wind.inflow.field import GRID_TOLERANCE

from .conftest import need
from .ifw_reference import CASES, DATA, read_reference

DEG = np.pi / 180.0


@pytest.fixture(scope="module")
def ff14(aero):
    return read_turbsim_bts(need(aero / "wind" / "ff14.bts"))


@pytest.fixture(scope="module")
def tower_field():
    return read_turbsim_bts(DATA / "tower_periodic.bts")


def _linear_field(n_t=30, n_z=5, n_y=7, dt=0.5, periodic=False, tower=0):
    """u = 8 + 0.05 y + 0.02 (z - 90) + 0.3 τ, v = 0.1 y - 0.2 τ, w = -0.03 (z - 90) + 0.01 τ at the nodes."""
    dy, dz, bottom = 10.0, 15.0, 60.0
    tau = dt * np.arange(n_t)[:, None, None]
    y = (-(n_y - 1) * dy / 2 + dy * np.arange(n_y))[None, None, :]
    z = (bottom + dz * np.arange(n_z))[None, :, None]
    g = np.stack(np.broadcast_arrays(8 + 0.05 * y + 0.02 * (z - 90) + 0.3 * tau, 0.1 * y - 0.2 * tau + 0 * z,
                                     -0.03 * (z - 90) + 0.01 * tau + 0 * y), axis=-1)
    tw = None
    if tower:
        zt = bottom - dz * np.arange(tower)
        tw = np.stack(np.broadcast_arrays(5 + 0.1 * zt[None] + 0.3 * tau[:, :, 0], 0 * zt[None] + 1.0 + 0 * tau[:, :, 0],
                                          0.02 * zt[None] + 0 * tau[:, :, 0]), axis=-1)
    return FullFieldWind(g, dy=dy, dz=dz, dt=dt, mean_speed=10.0, reference_height=90.0, grid_bottom=bottom,
                         tower=tw, periodic=periodic)


def _linear_value(tau, y, z):
    return np.array([8 + 0.05 * y + 0.02 * (z - 90) + 0.3 * tau, 0.1 * y - 0.2 * tau, -0.03 * (z - 90) + 0.01 * tau])


def test_ff14_header_and_memory(ff14):
    assert (ff14.n_y, ff14.n_z, ff14.n_t, ff14.n_tower, ff14.periodic) == (25, 25, 13400, 0, False)
    assert ff14.grid.dtype == np.float32 and not ff14.grid.flags.writeable
    assert ff14.nbytes == 13400 * 25 * 25 * 3 * 4          # 100.5 MB: float32 only, no float64 copy kept
    assert ff14.y[0] == pytest.approx(-70.0) and ff14.z[12] == pytest.approx(90.0)
    # InflowWind's summary range for a non-periodic file: [-YHWid/URef, (NSteps-1) dt - YHWid/URef]
    assert ff14.time_range == pytest.approx((-5.0, 669.95 - 5.0), abs=1e-5)


def test_ff14_hub_point_is_turbsims_hub_series(aero, ff14):
    hh = np.loadtxt(need(aero / "wind" / "ff14.hh"), comments="!")
    with open(aero / "wind" / "ff14.bts", "rb") as fh:
        slopes = np.array(struct.unpack("<h4i12fi", fh.read(70))[7:][6:12:2])
    assert hh.shape[0] == ff14.n_t and np.allclose(hh[:, 0], 0.05 * np.arange(ff14.n_t), atol=1e-9)
    u, v, w = ff14.grid[:, 12, 12].T.astype(float)        # the hub (0, 90 m) is grid node (12, 12)
    # tolerance: .hh values have 2 decimals (0.005) + half an int16 step of the .bts (0.5/slope) per component
    q = 0.5 / slopes
    assert np.abs(np.hypot(u, v) - hh[:, 1]).max() <= 0.005 + q[0] + q[1]
    assert np.abs(w - hh[:, 3]).max() <= 0.005 + q[2]
    direction_tol = 0.005 + np.degrees((q[0] + q[1]) / np.hypot(u, v).min())
    assert np.abs(-np.degrees(np.arctan2(v, u)) - hh[:, 2]).max() <= direction_tol


def test_ff14_hub_velocity_is_openfasts_wind1vel(aero, ff14):
    """OpenFAST's Wind1VelX/Y/Z at (0, 0, 90) of the ff14_rigid run (CSV with 7 significant digits)."""
    data = np.genfromtxt(need(aero / "ff14_rigid.csv"), delimiter=",", names=True,
                         usecols=(0, 1, 2, 3))
    v = ff14.velocity(data["Time_s"], [0.0, 0.0, 90.0])
    for k, c in enumerate("XYZ"):
        ref = data[f"Wind1Vel{c}_ms"]
        assert np.abs(v[:, k] - ref).max() <= 1e-5 + 5e-7 * np.abs(ref).max()


@pytest.mark.parametrize("case", ["ff14", "ff14_rotated", "tower_periodic"])
def test_points_against_openfast(case, request):
    """9 points per case written by OpenFAST v5 (``ifw_reference.py``, 9 significant digits)."""
    spec = CASES[case]
    field = request.getfixturevalue("ff14" if case.startswith("ff14") else "tower_field")
    field = field.with_rotation(spec["PropagationDir"] * DEG, spec["VFlowAng"] * DEG)
    t, ref = read_reference(case)
    v = field.velocity(t, np.array(spec["points"]))
    assert np.abs(v - ref).max() <= 2e-6 * max(1.0, np.abs(ref).max() / 10)


def test_tower_field_layout(tower_field):
    assert tower_field.periodic and tower_field.n_tower == 3
    assert tower_field.tower_z == pytest.approx([25.0, 25.0 - 9.2857143, 25.0 - 2 * 9.2857143])
    assert tower_field.initial_x == 0.0 and tower_field.total_time == pytest.approx(20.0)


def test_linear_field_is_interpolated_exactly():
    f = _linear_field()
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(-20, 20, 40), rng.uniform(-30, 30, 40), rng.uniform(60, 120, 40)])
    t = 1.7
    tau = t + (f.initial_x - pts[:, 0]) / f.mean_speed              # Taylor: τ = t + (x0 - x) / URef
    ref = _linear_value(tau, pts[:, 1], pts[:, 2]).T
    # tolerance: float32 node values (|u| < 12: 1e-6) then float64 interpolation
    assert np.abs(f.velocity(t, pts) - ref).max() < 2e-6


def test_taylor_advection_sign():
    """A point upwind (x < 0) sees now what reaches x = 0 later: u(t, x) = u(t - x/URef, 0)."""
    f = _linear_field()
    p0, p = np.array([[0.0, 3.0, 80.0]]), np.array([[-12.0, 3.0, 80.0]])
    assert np.allclose(f.velocity(2.0, p), f.velocity(2.0 + 12.0 / f.mean_speed, p0), atol=1e-12)
    assert f.velocity(2.0, p)[0, 0] > f.velocity(2.0, p0)[0, 0]     # u grows with τ in this field


def test_bts_round_trip_within_quantisation(tmp_path):
    f = _linear_field(tower=3)
    path = write_turbsim_bts(tmp_path / "lin.bts", f)
    g = read_turbsim_bts(path)
    assert (g.n_t, g.n_z, g.n_y, g.n_tower, g.periodic) == (f.n_t, f.n_z, f.n_y, 3, False)
    spans = [np.ptp(np.concatenate([f.grid[..., c].ravel(), f.tower[..., c].ravel()])) for c in range(3)]
    for c in range(3):          # half an int16 step: span / 64000 / 2 (+ float32 rounding)
        assert np.abs(g.grid[..., c] - f.grid[..., c]).max() <= spans[c] / 128000 + 1e-5
        assert np.abs(g.tower[..., c] - f.tower[..., c]).max() <= spans[c] / 128000 + 1e-5


def test_periodic_and_non_periodic_time_conventions():
    f, p = _linear_field(periodic=False), _linear_field(periodic=True)
    hub = [0.0, 0.0, 90.0]
    # non-periodic: slice 0 at x = YHWid at t = 0, so the hub sees τ = t + YHWid/URef; periodic: τ = t
    assert f.velocity(0.0, hub)[0] == pytest.approx(_linear_value(f.half_width / 10.0, 0, 90)[0], abs=1e-5)
    assert p.velocity(0.0, hub)[0] == pytest.approx(8.0, abs=1e-6)
    period = p.n_t * p.dt
    assert np.allclose(p.velocity(1.3 + 2 * period, hub), p.velocity(1.3, hub), atol=1e-12)
    # periodic: between the last slice and the first again (wrap), linear
    mid = p.velocity((p.n_t - 0.5) * p.dt, hub)[0]
    assert mid == pytest.approx(0.5 * (p.grid[-1, 2, 3, 0] + p.grid[0, 2, 3, 0]), abs=1e-6)
    # non-periodic: defined for τ in [0, n_t dt); the last step holds the last slice for its first half ...
    t_last = (f.n_t - 1) * f.dt - f.half_width / 10.0
    last = f.grid[-1, 2, 3, 0]
    assert f.velocity(t_last + 0.4 * f.dt, hub)[0] == pytest.approx(last, abs=1e-6)
    # ... and then interpolates the last interval at the fraction beyond the end (InflowWind's GetBoundsT)
    expected = 0.3 * f.grid[-2, 2, 3, 0] + 0.7 * f.grid[-1, 2, 3, 0]
    assert f.velocity(t_last + 0.7 * f.dt, hub)[0] == pytest.approx(expected, abs=1e-6)
    for t in (t_last + 1.01 * f.dt, -f.half_width / 10.0 - 0.01):
        with pytest.raises(WindFieldDomainError, match="no data there"):
            f.velocity(t, hub)


def test_tower_points_and_ground():
    f = _linear_field(tower=3)                     # tower points at 60, 45, 30 m
    t = 1.0
    tau = t + f.initial_x / f.mean_speed
    col = lambda z: np.array([5 + 0.1 * z + 0.3 * tau, 1.0, 0.02 * z])  # noqa: E731 - the tower column
    # between tower points: linear along the column, whatever y is (InflowWind ignores y there)
    for y in (0.0, 25.0, -200.0):
        assert np.allclose(f.velocity(t, [0.0, y, 50.0]), col(50.0), atol=1e-5)
    # below the last tower point (30 m): linear to zero at the ground
    assert np.allclose(f.velocity(t, [0.0, 0.0, 12.0]), col(30.0) * 12.0 / 30.0, atol=1e-5)
    assert np.array_equal(f.velocity(t, [0.0, 0.0, -1.0]), np.zeros(3))     # z <= 0: zero, no error


def test_outside_the_grid_raises_like_inflowwind():
    f = _linear_field()
    top = 60.0 + 4 * 15.0
    for point, what in (([0, 0, top + 1.0], "above the grid"), ([0, 31.0, 90.0], "beside the grid"),
                        ([0, 0, 50.0], "below the grid .* no tower points")):
        with pytest.raises(WindFieldDomainError, match=what) as info:
            f.velocity(0.5, np.array([[0.0, 0.0, 90.0], point]))
        assert f"point ({point[0]:g}, {point[1]:g}, {point[2]:g}) m at t = 0.5 s" in str(info.value)
    # within GridTol (1e-3 of a cell) outside: the edge value
    eps = 0.5 * GRID_TOLERANCE * 15.0
    assert np.allclose(f.velocity(0.5, [0, 0, top + eps]), f.velocity(0.5, [0, 0, top]), atol=1e-12)
    assert np.allclose(f.velocity(0.5, [0, 30.0 + eps * 10 / 15, 90]), f.velocity(0.5, [0, 30.0, 90]), atol=1e-12)


def test_several_times_at_once():
    f = _linear_field()
    pts = np.array([[0.0, 1.0, 70.0], [3.0, -2.0, 100.0]])
    times = np.array([0.0, 0.7, 2.2])
    v = f.velocity(times, pts)
    assert v.shape == (3, 2, 3)
    assert np.array_equal(v[1], f.velocity(0.7, pts))


@pytest.mark.parametrize("mutate, match", [
    (lambda b: b[:50], "fewer than the 70-byte header"),
    (lambda b: b[:-7], "truncated"),
    (lambda b: b + b"\0\0", "extra bytes"),
    (lambda b: struct.pack("<h", 9) + b[2:], "file identifier .* is 9"),
    (lambda b: b[:2] + struct.pack("<i", 1) + b[6:], "invalid header: nz = 1"),
    (lambda b: b[:26] + struct.pack("<f", -0.1) + b[30:], "invalid header: dt = -0.1"),
])
def test_bad_bts_files(tmp_path, mutate, match):
    good = write_turbsim_bts(tmp_path / "good.bts", _linear_field()).read_bytes()
    bad = tmp_path / "bad.bts"
    bad.write_bytes(mutate(good))
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_turbsim_bts(bad)
    assert str(bad) in str(info.value)


def test_missing_file_and_bad_arrays(tmp_path):
    with pytest.raises(OpenFASTFormatError, match="not found"):
        read_turbsim_bts(tmp_path / "none.bts")
    with pytest.raises(ValueError, match="expected 4 axes"):
        FullFieldWind(np.zeros((3, 3, 3)), dy=1, dz=1, dt=1, mean_speed=1, reference_height=1, grid_bottom=1)
    with pytest.raises(ValueError, match="mean_speed must be a positive"):
        FullFieldWind(np.zeros((3, 3, 3, 3)), dy=1, dz=1, dt=1, mean_speed=0, reference_height=1, grid_bottom=1)


@pytest.mark.slow
@pytest.mark.parametrize("case", list(CASES))
def test_stored_references_are_what_openfast_writes(case, tmp_path):
    """Rerun OpenFAST v5 on each stored case (~1-10 s each) and compare with ``data/ifw_<case>.csv``."""
    import subprocess

    from .ifw_reference import OPENFAST, run_points

    need(OPENFAST)
    if subprocess.run([str(OPENFAST), "-v"], capture_output=True).returncode != 0:
        pytest.skip("the OpenFAST binary does not run here (missing runtime libraries)")
    if case.startswith("ff14"):
        from .conftest import AERO
        need(AERO / "wind" / "ff14.bts")
    t, v = run_points(tmp_path, case)
    t_ref, v_ref = read_reference(case)
    assert np.array_equal(t, t_ref) and np.abs(v - v_ref).max() <= 1e-6 * max(1.0, np.abs(v_ref).max())
