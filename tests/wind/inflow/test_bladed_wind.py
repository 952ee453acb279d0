"""Bladed-style boxes (InflowWind WindType 4 and 7): mbsym.wind.inflow.bladed against OpenFAST and TurbSim.

References:
- OpenFAST v5.0.0's InflowWind: ``Wind1..9VelX/Y/Z`` at 9 points of 8 cases (``bladed_reference.py``, stored in
  ``tests/data/openfast_bladed_wind/``, see its README.md): TurbSim's periodic box with tower points (plain and
  rotated), TurbSim's non-periodic box with a height offset and the Clockwise flag, the same data behind an old-style
  header, and four native Bladed summaries (TurbType 4, 7, 8 and old-style boxes; linear shears, XOffset, angles).
  OpenFAST writes its outputs as float32: mbsym's values rounded to float32 equal every stored value (measured on all
  8 cases: 0 float32 ulps apart; largest |difference| before rounding 9.5e-7 m/s, half a float32 ulp of a value
  between 16 and 32 m/s). The tests assert this equality and ``|Δ| <= 1e-6 max(1, |v|)``.
- TurbSim's .bts of the same runs: the same field, equal within half an int16 step of each file (both quantize);
  tower points equal except v, whose sign InflowWind does not turn for the tower file (TurbSim writes it left-handed).
- InflowWind's rules for the files, case by case (summary keys, header layouts, errors).
"""

from __future__ import annotations

import re
import shutil
import struct
import warnings

import numpy as np
import pytest

from mbsym.exceptions import OpenFASTFormatError, WindInputError
from mbsym.wind.inflow import read_turbsim_bts
from mbsym.wind.inflow.bladed import read_bladed_native, read_bladed_wnd
from mbsym.wind.inflow.profile import MeanProfile

from .bladed_reference import CASES, DATA, read_case, turbsim_header, write_box
from .ifw_reference import DATA as IFW_DATA

DEG = np.pi / 180.0
#: A minimal native Bladed summary (over mann.wnd).
NATIVE = "UBAR 12\nREFHT 90\nTI .1\nTI_V .1\nTI_W .1\nWDIR 0\nFLINC 0\nWINDF mann.wnd\nWSHEAR 0.2\n"


def field_of(name: str):
    """The field of case ``name`` read as InflowWind's deck of that case reads it."""
    c = CASES[name]
    root = c["FileNameRoot"].strip('"')
    if c["WindType"] == 4:
        return read_bladed_wnd(DATA / f"{root}.wnd", tower_file=c["TowerFile"] == "True",
                               propagation_direction=c["PropagationDir"] * DEG, upflow_angle=c["VFlowAng"] * DEG)
    return read_bladed_native(DATA / root)


@pytest.fixture(scope="module")
def fields():
    return {name: field_of(name) for name in CASES}


def _quantum_bts(path):
    """Half an int16 step of a .bts file per component [m/s] (its slopes at byte 42)."""
    scale = struct.unpack_from("<6f", path.read_bytes(), 42)
    return 0.5 / np.array(scale[0::2])


def _quantum_wnd(field, ti):
    return 0.5 * 0.001 * field.mean_speed * np.asarray(ti) / 100.0


# ---------------------------------------------------------------------------------------------- OpenFAST
@pytest.mark.parametrize("name", list(CASES))
def test_velocity_equals_openfast(fields, name):
    t, ref = read_case(name)
    v = fields[name].velocity(t, CASES[name]["points"])
    assert v.shape == ref.shape
    assert np.abs(v - ref).max() <= 1e-6 * max(1.0, np.abs(ref).max())
    assert np.array_equal(v.astype(np.float32), ref.astype(np.float32))      # OpenFAST's outputs are float32


def test_cases_read_as_inflowwind(fields):
    tower, cw, old = fields["wnd_tower"], fields["wnd_clockwise"], fields["wnd_oldstyle"]
    assert (tower.n_t, tower.n_z, tower.n_y, tower.n_tower, tower.periodic) == (200, 15, 5, 3, True)
    assert tower.dt == float(np.float32(1.4)) / 14.0 != 0.1      # dx / U in float64 from the box's float32 values
    assert (cw.n_t, cw.periodic, cw.grid_bottom, cw.reference_height) == (207, False, 5.0, 90.0)  # offset 10 m
    assert cw.initial_x == cw.half_width == 65.0 and old.n_t == 207
    vk = fields["native_vk"]
    assert vk.periodic and vk.interpolate_to_ground and vk.x_offset == 15.0 and vk.dt == float(np.float32(1.4)) / 12.5
    assert vk.propagation_direction == pytest.approx(0.2, abs=1e-15) and vk.upflow_angle == pytest.approx(0.05)
    assert vk.mean_profile == MeanProfile(2, 12.5, 95.0, exponent=0.15, vertical_linear_shear=0.1,
                                          horizontal_linear_shear=0.05, reference_length=120.0)
    assert vk.grid_bottom == 95.0 - 0.5 * float(np.float32(130 / 14)) * 14
    assert fields["native_old"].propagation_direction == pytest.approx(3.5 - 2 * np.pi)      # MPi2Pi
    assert fields["native_kaimal"].x_offset == -12.0 and fields["native_kaimal"].n_t == 61    # 2 NStepsHalf + 1
    assert fields["native_mann"].n_t == 60 and fields["native_mann"].x_offset == 0.0


def test_native_scaling_hits_the_target_sigma_at_the_centre(fields):
    f = fields["native_vk"]                                       # TI 0.12, 0.10, 0.08 of UBAR 12.5
    centre = f.grid[:, 7, 2, :].astype(np.float64)
    assert np.allclose(centre.std(axis=0), np.array([0.12, 0.10, 0.08]) * 12.5, rtol=1e-6)
    raw = np.fromfile(DATA / "tower_periodic.wnd", dtype="<i2", offset=104).reshape(200, 15, 5, 3)
    sign = np.sign(f.grid[:, 7, 2, :] * raw[:, 7, 2, :])
    assert np.all(sign[:, [0, 2]] >= 0) and np.all(sign[:, 1] <= 0)     # v turned: left-handed, always


# ---------------------------------------------------------------------------------------------- TurbSim's .bts
def test_periodic_box_equals_bts_of_the_same_run(fields):
    wnd, bts_path = fields["wnd_tower"], IFW_DATA / "tower_periodic.bts"
    bts = read_turbsim_bts(bts_path)
    for k in ("n_t", "n_z", "n_y", "n_tower", "periodic", "dy", "mean_speed", "reference_height"):
        assert getattr(wnd, k) == getattr(bts, k)
    assert wnd.dz == pytest.approx(bts.dz, rel=1e-7)
    assert wnd.dt == pytest.approx(bts.dt, rel=6e-8)                  # dx/U vs dt: float32 values
    assert wnd.grid_bottom == pytest.approx(bts.grid_bottom, abs=1e-5)
    tol = _quantum_bts(bts_path) + _quantum_wnd(wnd, turbsim_header(DATA / "tower_periodic.wnd")["ti"]) + 1e-5
    assert np.all(np.abs(wnd.grid - bts.grid).max(axis=(0, 1, 2)) <= tol)
    flip = np.array([1.0, -1.0, 1.0], dtype=np.float32)          # InflowWind applies no left-hand rule to the .twr
    assert np.all(np.abs(wnd.tower * flip - bts.tower).max(axis=(0, 1)) <= tol)


def test_clockwise_reverses_y_and_old_header_reads_the_same_data(fields):
    bts_path = DATA / "nonperiodic.bts"
    bts = read_turbsim_bts(bts_path)
    cw, old = fields["wnd_clockwise"], fields["wnd_oldstyle"]
    assert (cw.grid_bottom, cw.periodic) == (bts.grid_bottom, bts.periodic)
    assert cw.time_range == pytest.approx(bts.time_range, rel=1e-7)          # dx/U vs dt: float32 values
    ti = turbsim_header(DATA / "nonperiodic.wnd")["ti"]
    tol = _quantum_bts(bts_path) + _quantum_wnd(cw, ti) + 1e-5
    assert np.all(np.abs(cw.grid[:, :, ::-1] - bts.grid).max(axis=(0, 1, 2)) <= tol)
    assert np.all(np.abs(old.grid - bts.grid).max(axis=(0, 1, 2)) <= tol)   # .sum TIs (4 decimals) scale it
    assert not np.allclose(cw.grid, bts.grid, atol=0.05)


# ---------------------------------------------------------------------------------------------- InflowWind's rules
def _copy(tmp_path, *names):
    for n in names:
        shutil.copy(DATA / n, tmp_path / n)
    return tmp_path


def test_summary_details_change_the_wind(tmp_path):
    _copy(tmp_path, "oldstyle.wnd", "oldstyle.sum")
    text = (tmp_path / "oldstyle.sum").read_text()
    base = read_bladed_wnd(tmp_path / "oldstyle.wnd")
    (tmp_path / "oldstyle.sum").write_text(text.replace("Creating a BLADED LEFT-HAND RULE output file.", ""))
    right = read_bladed_wnd(tmp_path / "oldstyle.wnd")                  # no left-hand rule: v not turned
    assert np.array_equal(right.grid[..., 1], -base.grid[..., 1])
    assert np.array_equal(right.grid[..., 0], base.grid[..., 0])
    periodic = text.replace("Creating a BLADED", "Creating a PERIODIC output file.\nCreating a BLADED")
    (tmp_path / "oldstyle.sum").write_text(periodic)
    assert read_bladed_wnd(tmp_path / "oldstyle.wnd").periodic
    early = periodic.replace("Creating a PERIODIC output file.\n", "").replace("Runtime Options:", "PERIODIC\n")
    (tmp_path / "oldstyle.sum").write_text(early)                      # before HEIGHT OFFSET: not seen
    assert not read_bladed_wnd(tmp_path / "oldstyle.wnd").periodic
    (tmp_path / "oldstyle.sum").write_text(text.replace("Runtime Options:", "Runtime Options:\nYes  Clockwise"))
    assert np.array_equal(read_bladed_wnd(tmp_path / "oldstyle.wnd").grid, base.grid[:, :, ::-1])
    (tmp_path / "oldstyle.sum").write_text(re.sub(r"TI\(u\) = *[\d.]+", "TI(u) = 20.0", text))
    scaled = read_bladed_wnd(tmp_path / "oldstyle.wnd")                # old header: the .sum's TI scales u
    assert not np.allclose(scaled.grid[..., 0], base.grid[..., 0])


def test_turbsim_box_takes_its_own_ti(tmp_path):
    _copy(tmp_path, "nonperiodic.wnd", "nonperiodic.sum")
    base = read_bladed_wnd(tmp_path / "nonperiodic.wnd")
    text = (tmp_path / "nonperiodic.sum").read_text()
    (tmp_path / "nonperiodic.sum").write_text(re.sub(r"TI\(u\) = *[\d.]+", "TI(u) = 20.0", text))
    assert np.array_equal(read_bladed_wnd(tmp_path / "nonperiodic.wnd").grid, base.grid)


def test_header_layouts_give_the_same_box(tmp_path):
    h = turbsim_header(DATA / "nonperiodic.wnd")
    data = h["data"][:20]
    fields = []
    for style in (3, 5, 7, 8, -3):
        box = tmp_path / f"box{style}.wnd"
        if style in (3, 5):                                            # no type block; Sub1, Sub2, data
            grid = struct.pack("<3fi4f4i", h["dz"], h["dy"], h["dx"], 10, h["u"], 0, 0, 0, 0, 1, h["nz"], h["ny"])
            box.write_bytes(struct.pack("<hh", -99, style) + grid + bytes(24) + data.tobytes())
        else:
            write_box(box, h, style, data)
        (tmp_path / f"s{style}.txt").write_text(NATIVE.replace("mann.wnd", box.name))
        fields.append(read_bladed_native(tmp_path / f"s{style}.txt"))
    *new, old = fields
    for f in new[1:]:
        assert np.array_equal(f.grid, new[0].grid) and f.dz == new[0].dz and f.dt == new[0].dt
    assert np.array_equal(old.grid, new[0].grid)                      # old style: dx in mm, 1.2 m, not float32(1.2)
    assert old.dt == 0.001 * 1200 / 12.0 != new[0].dt and old.n_t == new[0].n_t == 20


def test_refused_boxes(tmp_path):
    h = turbsim_header(DATA / "nonperiodic.wnd")
    one = tmp_path / "one.wnd"
    head = struct.pack("<13h", -1, 25000, 32500, 1200, 2, 120, 0, 0, 0, 0, 1, 7000, 5000)
    one.write_bytes(head + bytes(4 * 35 * 2))
    six = tmp_path / "six.wnd"
    write_box(six, h, 8, h["data"][:4])
    raw = bytearray(six.read_bytes())
    raw[2:4] = struct.pack("<h", 6)
    six.write_bytes(bytes(raw))
    for box, words in ((one, "1 wind component"), (six, "TurbType")):
        (tmp_path / "s.txt").write_text(NATIVE.replace("mann.wnd", box.name))
        with pytest.raises(OpenFASTFormatError, match=words) as err:
            read_bladed_native(tmp_path / "s.txt")
        assert box.name in str(err.value)


def test_constant_centre_cannot_be_scaled(tmp_path):
    h = turbsim_header(DATA / "nonperiodic.wnd")
    write_box(tmp_path / "flat.wnd", h, 8, np.zeros_like(h["data"][:6]))
    (tmp_path / "s.txt").write_text(NATIVE.replace("mann.wnd", "flat.wnd"))
    with pytest.raises(WindInputError, match=r"s\.txt \(box flat\.wnd\): component u is constant"):
        read_bladed_native(tmp_path / "s.txt")
    (tmp_path / "s.txt").write_text(NATIVE.replace("mann.wnd", "flat.wnd").replace("TI .1", "TI 0")
                                    .replace("TI_V .1", "TI_V 0").replace("TI_W .1", "TI_W 0"))
    f = read_bladed_native(tmp_path / "s.txt")                         # zero targets: factors 0, the mean alone
    assert not f.grid.any() and f.velocity(0.0, [0.0, 0.0, 90.0])[0] == 12.0


# ---------------------------------------------------------------------------------------------- errors
def test_missing_summary(tmp_path):
    _copy(tmp_path, "tower_periodic.wnd")
    with pytest.raises(OpenFASTFormatError, match=r"TurbSim summary file not found.*tower_periodic\.sum"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd")


def test_mean_speed_mismatch(tmp_path):
    _copy(tmp_path, "tower_periodic.wnd", "tower_periodic.sum")
    s = tmp_path / "tower_periodic.sum"
    s.write_text(s.read_text().replace("UBar  =  14.0000", "UBar  =  14.2000"))
    with pytest.raises(OpenFASTFormatError, match=r"tower_periodic\.wnd.*14.2.*tower_periodic\.sum"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd")
    s.write_text(s.read_text().replace("UBar  =  14.2000", "UBar  =  14.0900"))    # within InflowWind's 0.1 m/s
    read_bladed_wnd(tmp_path / "tower_periodic.wnd")


def test_missing_or_mismatched_tower_file(tmp_path):
    _copy(tmp_path, "tower_periodic.wnd", "tower_periodic.sum")
    assert read_bladed_wnd(tmp_path / "tower_periodic.wnd").tower is None
    with pytest.raises(OpenFASTFormatError, match=r"tower file not found.*tower_periodic\.twr.*TowerFile"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd", tower_file=True)
    raw = bytearray((DATA / "tower_periodic.twr").read_bytes())
    raw[12:16] = struct.pack("<i", 199)                                # steps
    (tmp_path / "tower_periodic.twr").write_bytes(bytes(raw))
    with pytest.raises(OpenFASTFormatError, match=r"tower_periodic\.twr.*does not match.*199 time steps"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd", tower_file=True)


def test_truncated_box_and_extra_bytes(tmp_path):
    _copy(tmp_path, "tower_periodic.sum")
    raw = (DATA / "tower_periodic.wnd").read_bytes()
    (tmp_path / "tower_periodic.wnd").write_bytes(raw[:-1000])
    with pytest.raises(OpenFASTFormatError, match=r"tower_periodic\.wnd.*holds 197 whole steps \(truncated\)"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd")
    (tmp_path / "tower_periodic.wnd").write_bytes(raw[:50])
    with pytest.raises(OpenFASTFormatError, match="ends inside its header"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd")
    (tmp_path / "tower_periodic.wnd").write_bytes(raw + raw[104:104 + 450 + 10])   # one more step + 10 bytes
    with pytest.warns(UserWarning, match="10 bytes after the 201 time steps"):
        f = read_bladed_wnd(tmp_path / "tower_periodic.wnd")
    assert f.n_t == 201                                                 # InflowWind reads 2 NStepsHalf + 1


def test_wrong_header_id(tmp_path):
    shutil.copy(IFW_DATA / "tower_periodic.bts", tmp_path / "tower_periodic.wnd")
    _copy(tmp_path, "tower_periodic.sum")
    with pytest.raises(OpenFASTFormatError, match=r"tower_periodic\.wnd: the first int16 is 8.*WindType = 3"):
        read_bladed_wnd(tmp_path / "tower_periodic.wnd")
    with pytest.raises(OpenFASTFormatError, match="not found"):
        read_bladed_wnd(tmp_path / "nothing.wnd")




@pytest.mark.parametrize("text, error, words", [
    (NATIVE.replace("REFHT 90\n", ""), OpenFASTFormatError, "REFHT expected at line 2"),
    (NATIVE + "XOffset 5\nVLINSHEAR 0.1\n", OpenFASTFormatError, "line 11: VLINSHEAR is not where InflowWind reads"),
    (NATIVE + "VLINSHEAR abc\n", OpenFASTFormatError, "line 10: VLINSHEAR has no valid number.*silently use 0"),
    (NATIVE + "@more.txt\n", OpenFASTFormatError, "line 10: '@' includes"),
    (NATIVE.replace("mann.wnd", "none.wnd"), OpenFASTFormatError, "WINDF names the box 'none.wnd', not found"),
    (NATIVE + "VLINSHEAR 0.1\n", WindInputError, "REFLENGTH = 0 m with linear shears"),
    (NATIVE.replace("REFHT 90", "REFHT 0"), WindInputError, "REFHT = 0 m"),
    (NATIVE.replace("TI_V .1", "TI_V -.1"), WindInputError, "must not be negative"),
])
def test_native_summary_errors(tmp_path, text, error, words):
    _copy(tmp_path, "mann.wnd")
    (tmp_path / "s.txt").write_text(text)
    with pytest.raises(error, match=words) as err:
        read_bladed_native(tmp_path / "s.txt")
    assert "s.txt" in str(err.value)


def test_native_summary_forms(tmp_path):
    _copy(tmp_path, "mann.wnd")
    (tmp_path / "plain.txt").write_text(NATIVE)
    base = read_bladed_native(tmp_path / "plain.txt")
    text = NATIVE.replace("UBAR 12", "12.0, ubar  # value first")
    text = text.replace("WSHEAR 0.2", "WSHEAR 0.2\nREFLENGTH 1d2\nXOffset 7.5 % last")
    (tmp_path / "s.txt").write_text("! comment\n\n" + text + "OTHER 3\n")
    f = read_bladed_native(tmp_path / "s.txt")
    assert f.mean_speed == 12.0 and f.x_offset == 7.5 and np.array_equal(f.grid, base.grid)
    assert f.mean_profile.reference_length == 100.0                  # Fortran's 1d2 (no linear shear: unused)
    with pytest.raises(OpenFASTFormatError, match="native Bladed summary file not found"):
        read_bladed_native(tmp_path / "none.txt")


def test_grid_below_ground_warns(tmp_path):
    _copy(tmp_path, "nonperiodic.wnd", "nonperiodic.sum")
    s = tmp_path / "nonperiodic.sum"
    s.write_text(s.read_text().replace("Height Offset =  10.0000", "Height Offset =  20.0000"))
    with pytest.warns(UserWarning, match="below the ground"):
        f = read_bladed_wnd(tmp_path / "nonperiodic.wnd")
    assert f.grid_bottom == -5.0
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert np.all(f.velocity(0.0, [[0.0, 0.0, 0.0], [0.0, 0.0, -1.0]]) == 0.0)


# ---------------------------------------------------------------------------------------------- CasADi
def test_casadi_function_of_a_native_field(fields, tmp_path_factory, monkeypatch):
    from mbsym.codegen import find_compiler

    monkeypatch.setenv("MBSYM_CACHE_DIR", str(tmp_path_factory.getbasetemp() / "bladed_cache"))
    monkeypatch.delenv("MBSYM_NO_COMPILE", raising=False)
    if find_compiler() is None:
        pytest.skip("no C compiler on this machine")
    f = fields["native_vk"]                            # rotated, mean profile with linear shears, XOffset, to ground
    pts = np.array(CASES["native_vk"]["points"])
    fun = f.casadi_function(pts.shape[0])
    assert fun.class_name() == "External"
    for t in (0.0, 3.37, 21.9, 27.65):
        ref = f.velocity(t, pts)
        assert np.abs(np.array(fun(t, pts.T)).T - ref).max() <= 1e-12 * np.abs(ref).max()


# ---------------------------------------------------------------------------------------------- the deck
@pytest.mark.parametrize("name", ["wnd_tower_rotated", "wnd_clockwise", "native_mann"])
def test_inflowwind_deck_reads_the_case_as_openfast(name, tmp_path):
    """The InflowWind file of the case (``ifw_reference.write_case``: FileNameRoot relative to it, TowerFile,
    the angles) through ``read_inflowwind(...).field()``: OpenFAST's numbers, as the readers give them."""
    from mbsym.wind.deck.inflowwind import read_inflowwind

    from .ifw_reference import write_case

    case = dict(CASES[name])
    for f in case.pop("files"):
        (tmp_path / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(DATA / f, tmp_path / f)
    write_case(tmp_path, name, case)
    ifw = read_inflowwind(tmp_path / f"{name}_IfW.dat")
    assert ifw.wind_type == case["WindType"] and ifw.bladed_file is not None
    t, ref = read_case(name)
    v = ifw.field().velocity(t, case["points"])
    assert np.abs(v - ref).max() <= 1e-6 * max(1.0, np.abs(ref).max())
    with pytest.raises(WindInputError, match=f"WindType = {case['WindType']}"):
        ifw.wind()


def test_native_deck_warns_that_its_own_angles_are_not_used(tmp_path):
    from mbsym.wind.deck.inflowwind import read_inflowwind

    from .ifw_reference import write_case

    case = dict(CASES["native_old"], PropagationDir=10.0)
    for f in case.pop("files"):
        shutil.copy(DATA / f, tmp_path / f)
    write_case(tmp_path, "native_old", case)
    with pytest.warns(UserWarning, match="WindType = 7 takes the propagation direction"):
        field = read_inflowwind(tmp_path / "native_old_IfW.dat").field()
    assert field.propagation_direction == read_bladed_native(DATA / "native_old.txt").propagation_direction


def test_missing_bladed_files_are_reported_with_file_line_key(tmp_path):
    from mbsym.wind.deck.inflowwind import read_inflowwind

    from .ifw_reference import write_case

    case = {k: v for k, v in CASES["wnd_clockwise"].items() if k != "files"}
    write_case(tmp_path, "gone", {**case, "FileNameRoot": '"nowhere"'})
    with pytest.raises(OpenFASTFormatError, match="key 'FileNameRoot'.*Bladed-style wind file not found: tried "
                       "'nowhere.wnd'"):
        read_inflowwind(tmp_path / "gone_IfW.dat").field()


def test_memory_budget_prices_the_box(tmp_path):
    """The deck budget prices TurbSim's Bladed-style box from its size: float32 (2x the int16 file) + the file."""
    from mbsym.wind.deck.budget import _BLOCK, deck_memory_estimate

    from .ifw_reference import write_case

    case = dict(CASES["wnd_clockwise"])
    for f in case.pop("files"):
        shutil.copy(DATA / f, tmp_path / f)
    fst = write_case(tmp_path, "priced", case)
    item = next(i for i in deck_memory_estimate(fst).items if i.what.startswith("Bladed-style full field"))
    assert item.bytes == 3 * (DATA / "nonperiodic.wnd").stat().st_size + _BLOCK and item.key == "FileNameRoot"
