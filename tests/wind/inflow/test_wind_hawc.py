"""HAWC boxes (InflowWind WindType = 5): the reader, the mean profile added after interpolation, the deck keys.

References:
- OpenFAST v5.0.0's InflowWind: 9 points per case written by OpenFAST (``ifw_reference.py``, stored in
  ``data/ifw_hawc_*.csv``) on TurbSim's HAWC output of ``data/tower_periodic.inp``: direct scaling factors with a
  power-law profile; target standard deviations with a logarithmic profile, ``XOffset`` and a rotated box;
  no scaling with a constant profile. Points inside the grid, below it (interpolated to zero at the ground),
  at the grid tolerance and upwind;
- TurbSim's ``.bts`` of the same run: the HAWC files hold ``(V - UHub) / factor_scaling`` of the same velocities
  (TS_FileIO.f90 ``WrBinHAWC``), so the box read without scaling, times ``factor_scaling``, plus ``UHub`` is the
  ``.bts`` grid (an independent check of the file layout and its reversed lateral order);
- closed forms: a box linear in y, z and time with a power-law profile; the invariants of ``ScaleMethod = 2``
  (the centre point's standard deviations are the targets, ``u`` has zero mean at every grid point).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mbsym.codegen import find_compiler
from mbsym.exceptions import OpenFASTFormatError, WindInputError
from mbsym.wind.deck.inflowwind import read_inflowwind
from mbsym.wind.inflow import FullFieldWind, read_turbsim_bts
from mbsym.wind.inflow.hawc import HawcBox, read_hawc, write_hawc
from mbsym.wind.inflow.profile import MeanProfile

from .ifw_reference import CASES, DATA, HAWC, read_reference, write_case

HAWC_CASES = ("hawc_direct", "hawc_sigma_log", "hawc_raw")
FILES = tuple(DATA / f"tower_periodic-{c}.bin" for c in "uvw")
#: TurbSim's .hawc file of the run: "factor_scaling 1.04056 1.65162 1.97520" (F15.5).
FACTOR_SCALING = (1.04056, 1.65162, 1.97520)


def _box(**kw) -> HawcBox:
    base = dict(files=FILES, nx=200, ny=5, nz=15, dx=1.4, dy=32.5, dz=HAWC["dz"], reference_height=90.0,
                mean_speed=14.0)
    return HawcBox(**{**base, **kw})


@pytest.fixture(scope="module")
def deck_fields(tmp_path_factory):
    """The field of each case read through its InflowWind file (as OpenFAST read it)."""
    out = {}
    for name in HAWC_CASES:
        folder = tmp_path_factory.mktemp(name)
        write_case(folder, name)
        out[name] = read_inflowwind(folder / f"{name}_IfW.dat").field()
    return out


@pytest.mark.parametrize("case", HAWC_CASES)
def test_points_against_openfast(case, deck_fields):
    """Measured: at most 1.2e-6 m/s from OpenFAST (its 9 significant digits; float32 data as InflowWind)."""
    t, ref = read_reference(case)
    v = deck_fields[case].velocity(t, np.array(CASES[case]["points"]))
    assert np.abs(v - ref).max() <= 2e-6 * max(1.0, np.abs(ref).max() / 10)


def test_deck_keys_are_read(deck_fields):
    f = deck_fields["hawc_sigma_log"]
    assert f.periodic and f.interpolate_to_ground and f.x_offset == 20.0 and f.tower is None
    assert f.mean_profile == MeanProfile(1, 11.0, 90.0, exponent=0.2, roughness=0.1)
    assert f.dt == pytest.approx(1.4 / 11.0) and f.grid_bottom == pytest.approx(90.0 - 7 * HAWC["dz"])
    assert f.propagation_direction == pytest.approx(np.radians(10.0))


def test_layout_against_turbsims_bts_of_the_same_run():
    """HAWC u = (u_bts - UHub) / factor, v = v_bts / factor, w = w_bts / factor, lateral order reversed in the file.
    Tolerance: half an int16 step of the .bts per component + the 6 significant digits of factor_scaling."""
    bts = read_turbsim_bts(DATA / "tower_periodic.bts")
    box = read_hawc(_box(scale_method=0, profile=0))
    slope = (64000.0 / np.ptp(np.concatenate([bts.grid.reshape(-1, 3), bts.tower.reshape(-1, 3)]), axis=0))
    for c in range(3):
        rebuilt = box.grid[..., c].astype(float) * FACTOR_SCALING[c] + (14.0 if c == 0 else 0.0)
        tol = 0.5 / slope[c] + 5e-6 * np.abs(rebuilt).max() + 1e-5
        assert np.abs(rebuilt - bts.grid[..., c]).max() <= tol
    mirrored = box.grid[..., ::-1, 0].astype(float) * FACTOR_SCALING[0] + 14.0
    assert np.abs(mirrored - bts.grid[..., 0]).max() > 0.5                # the reversal matters


def _linear_box(tmp_path, nx=12, ny=5, nz=4) -> tuple[HawcBox, np.ndarray]:
    """Fluctuations u = 0.05 y + 0.02 (z - 90) + 0.3 τ, v = 0.1 y, w = -0.01 τ on a box centred at 90 m."""
    dy, dz, dt = 10.0, 15.0, 0.5
    tau = dt * np.arange(nx)[:, None, None]
    y = (-(ny - 1) * dy / 2 + dy * np.arange(ny))[None, None, :]
    z = (90.0 - (nz - 1) * dz / 2 + dz * np.arange(nz))[None, :, None]
    g = np.stack(np.broadcast_arrays(0.05 * y + 0.02 * (z - 90) + 0.3 * tau, 0.1 * y + 0 * z + 0 * tau,
                                     -0.01 * tau + 0 * y + 0 * z), axis=-1)
    grid = FullFieldWind(g, dy=dy, dz=dz, dt=dt, mean_speed=10.0, reference_height=90.0, grid_bottom=67.5)
    files = write_hawc(tmp_path / "lin", grid)
    return HawcBox(files, nx, ny, nz, dt * 10.0, dy, dz, 90.0, mean_speed=10.0, profile=2, exponent=0.14,
                   x_offset=5.0), g


def test_linear_box_with_power_law_is_exact(tmp_path):
    box, _ = _linear_box(tmp_path)
    f = read_hawc(box)
    rng = np.random.default_rng(3)
    pts = np.column_stack([rng.uniform(-20, 4, 30), rng.uniform(-20, 20, 30), rng.uniform(68, 112, 30)])
    t = 1.3
    tau = t + (5.0 - pts[:, 0]) / 10.0        # XOffset = 5 m: τ = t + (XOffset - x) / URef, within one period
    y, z = pts[:, 1], pts[:, 2]
    ref = np.column_stack([0.05 * y + 0.02 * (z - 90) + 0.3 * tau + 10.0 * (z / 90.0) ** 0.14, 0.1 * y, -0.01 * tau])
    assert np.abs(f.velocity(t, pts) - ref).max() < 2e-6      # float32 nodes, float64 interpolation
    # below the grid (bottom 67.5 m) the fluctuations go linearly to zero at the ground, the profile is exact
    low = np.array([[0.0, 10.0, 30.0]])
    u_bottom = 0.05 * 10.0 + 0.02 * (67.5 - 90) + 0.3 * (t + 0.5)
    assert f.velocity(t, low)[0, 0] == pytest.approx(u_bottom * 30.0 / 67.5 + 10.0 * (30.0 / 90.0) ** 0.14, abs=2e-6)


def test_standard_deviation_scaling_invariants():
    f = read_hawc(_box(scale_method=2, target_sigmas=(1.5, 1.2, 0.8)))
    centre = f.grid[:, 7, 2].astype(float)                    # ((15 + 1) // 2, (5 + 1) // 2), 1-based
    assert centre.std(axis=0) == pytest.approx([1.5, 1.2, 0.8], rel=1e-5)
    assert np.abs(f.grid[..., 0].astype(float).mean(axis=0)).max() < 1e-5
    direct = read_hawc(_box(scale_method=1, scale_factors=(2.0, 1.0, 0.5)))
    raw = read_hawc(_box(scale_method=0))
    assert np.allclose(direct.grid[..., 2], 0.5 * raw.grid[..., 2], rtol=1e-6, atol=0)
    assert np.abs(raw.grid[..., 0].astype(float).mean(axis=0)).max() > 0.01   # ScaleMethod 0 keeps the mean


def test_file_errors(tmp_path):
    with pytest.raises(OpenFASTFormatError, match="HAWC v-component file not found.*FileName_v"):
        read_hawc(_box(files=(FILES[0], tmp_path / "nowhere.bin", FILES[2])))
    short = tmp_path / "short.bin"
    short.write_bytes(FILES[0].read_bytes()[:1000])
    with pytest.raises(OpenFASTFormatError, match=r"1000 bytes, fewer than the nx \* ny \* nz = 200 x 5 x 15"):
        read_hawc(_box(files=(short, FILES[1], FILES[2])))
    with pytest.warns(UserWarning, match="more than the nx"):
        read_hawc(_box(nx=100))
    with pytest.raises(WindInputError, match="URef = 0"):
        read_hawc(_box(mean_speed=0.0))
    with pytest.raises(WindInputError, match="Z0 = 0"):
        read_hawc(_box(profile=1, roughness=0.0))


def _mutated(tmp_path: Path, name: str, key: str, value: str) -> Path:
    folder = tmp_path / key
    write_case(folder, name, {**CASES[name], key: value})
    return folder / f"{name}_IfW.dat"


@pytest.mark.parametrize("key, value, match", [
    ("nx", "1", "must be at least 2"), ("ScaleMethod", "3", "must be 0 .none., 1"),
    ("WindProfile", "4", "must be 0 .constant."), ("URef", "0", "must be greater than 0 m/s"),
    ("Z0", "0", "must be greater than 0 m for WindProfile = 1"),
])
def test_deck_errors_name_file_line_key(tmp_path, key, value, match):
    path = _mutated(tmp_path, "hawc_sigma_log", key, value)
    with pytest.raises(OpenFASTFormatError, match=match) as info:
        read_inflowwind(path)
    assert f"key '{key}'" in str(info.value) and str(path) in str(info.value)


def test_missing_file_is_reported_when_the_field_is_read(tmp_path):
    path = _mutated(tmp_path, "hawc_raw", "FileName_w", '"nowhere-w.bin"')
    ifw = read_inflowwind(path)
    with pytest.raises(OpenFASTFormatError, match="w-component file not found.*nowhere-w.bin"):
        ifw.field()


def test_hub_signal_is_refused_without_allow_unmodelled(deck_fields, tmp_path):
    path = _mutated(tmp_path, "hawc_raw", "NWindVel", "9")
    ifw = read_inflowwind(path)
    with pytest.raises(WindInputError, match="WindType = 5"):
        ifw.wind()
    hub = ifw.wind(allow_unmodelled=True)
    assert hub(3.0) == pytest.approx(deck_fields["hawc_raw"].velocity(3.0, [0.0, 0.0, 95.0])[0], abs=1e-9)


@pytest.mark.skipif(find_compiler() is None, reason="no C compiler on this machine")
def test_compiled_external_adds_the_profile_as_numpy(deck_fields, tmp_path, monkeypatch):
    """The generated C adds the same mean profile (rotated box, logarithmic profile, XOffset): 1e-12 relative."""
    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    for name in ("hawc_sigma_log", "hawc_direct"):
        field = deck_fields[name]
        pts = np.array(CASES[name]["points"])
        f = field.casadi_function(pts.shape[0])
        assert f.class_name() == "External"
        for t in (0.0, 7.3, 31.9):
            ref = field.velocity(t, pts)
            assert np.abs(np.array(f(t, pts.T)).T - ref).max() <= 1e-12 * np.abs(ref).max()


def test_memory_budget_prices_the_box(tmp_path):
    """The deck budget reads nx, ny, nz: 3 components x 200 x 5 x 15 float32 + one component while reading."""
    from mbsym.wind.deck.budget import deck_memory_estimate

    fst = write_case(tmp_path, "hawc_raw")
    item = next(i for i in deck_memory_estimate(fst).items if i.what.startswith("HAWC box"))
    assert item.bytes == 4 * 4 * 200 * 5 * 15 and item.key == "nx"
