"""OpenFAST v5 InflowWind as the reference for Bladed-style boxes (``WindType = 4`` and ``7``).

``python tests/wind/inflow/bladed_reference.py`` regenerates ``tests/data/openfast_bladed_wind/`` (see its
README.md): it runs TurbSim on the two stored inputs, derives the other boxes and the native Bladed summaries from
TurbSim's output (:func:`derive_files`), then runs OpenFAST (ElastoDyn + InflowWind, :func:`ifw_reference.run_points`)
on each case of :data:`CASES` and stores the 9 points' velocities as ``<case>.csv`` (time, then 27 columns).
``--reuse`` skips TurbSim and the derived files and only reruns OpenFAST on the stored files.
"""

from __future__ import annotations

import shutil
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ifw_reference  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_bladed_wind"
TURBSIM = ifw_reference.SHARED / "tools" / "openfast" / "turbsim"

#: The line added to TurbSim's nonperiodic.sum (TurbSim v2 has no Clockwise input; older TurbSim versions wrote such
#: a line, and InflowWind's Bladed_ReadTurbSimSummary still reads it before the hub height).
CLOCKWISE_LINE = "         T  Clockwise rotation looking downwind?"

#: Native Bladed summaries (WindType = 7): file name -> text.
NATIVE = {
    "native_vk.txt": """! mbsym test: native Bladed summary over TurbSim's tower_periodic.wnd (TurbType 4), every key
UBAR       12.5
REFHT      95.0
TI         0.12
TI_V       0.10
TI_W       0.08
WDIR       0.2      ! rad
FLINC      0.05     ! rad
WINDF      tower_periodic.wnd
WSHEAR     0.15
VLINSHEAR  0.1
HLINSHEAR  0.05
REFLENGTH  120.0
XOffset    15.0
""",
    "native/native_mann.txt": """# mbsym test: Mann header (TurbType 8), WINDF relative to this folder, no optional key
UBAR 10.0
REFHT 90.0
TI 0.15
TI_V 0.12
TI_W 0.10
WDIR 0.0
FLINC 0.0
WINDF "../mann.wnd"
WSHEAR 0.2
""",
    "native_kaimal.txt": """% mbsym test: general Kaimal header (TurbType 7), value-first lines, XOffset without shears

   11.0   UBAR
   85.0   REFHT
   0.1,   TI
   0.09   TI_V
   0.07   TI_W
  -0.3    WDIR
  -0.02   FLINC
 kaimal.wnd WINDF
   0.12   WSHEAR
  -12.0   XOffset
""",
    "native_old.txt": """! mbsym test: old-style box (file id -3) in native mode, WDIR beyond pi
UBAR 9.0
REFHT 92.0
TI 0.2
TI_V 0.15
TI_W 0.1
WDIR 3.5
FLINC 0.03
WINDF oldstyle.wnd
WSHEAR 0.1
REFLENGTH 100.0
""",
}

_TOWER = ["tower_periodic.wnd", "tower_periodic.sum", "tower_periodic.twr"]
_NONPERIODIC_POINTS = [(0.0, 0.0, 90.0), (0.0, -35.0, 100.0), (20.0, 10.0, 40.0), (-56.8, 0.0, 75.0),
                       (0.0, 64.99, 154.99), (0.0, -65.01, 31.0), (10.0, 5.0, 4.99), (5.0, 5.0, 0.0),
                       (-10.0, 12.0, 63.0)]
#: The cases: IfW keys, the 9 points (x, y, z) [m], tmax and dt_out [s], the files copied into the run folder.
CASES = {
    # TurbSim's periodic box with 3 tower points (grid 5 x 15, 130 m square, bottom 25 m, tower at 25, 15.7, 6.4 m)
    "wnd_tower": dict(WindType=4, FileNameRoot='"tower_periodic"', TowerFile="True", PropagationDir=0.0, VFlowAng=0.0,
                      points=[(0.0, 0.0, 90.0), (35.0, -40.0, 140.0), (0.0, 0.0, 20.0), (0.0, 25.0, 12.0),
                              (-10.0, -5.0, 8.0), (5.0, 0.0, 3.0), (0.0, 7.0, 24.995), (0.0, 64.99, 155.005),
                              (-100.0, 0.0, 90.0)], tmax=28.0, dt_out=0.35, files=_TOWER),
    "wnd_tower_rotated": dict(WindType=4, FileNameRoot='"tower_periodic"', TowerFile="True", PropagationDir=-20.0,
                              VFlowAng=5.0, points=[(0.0, 0.0, 90.0), (10.0, 15.0, 110.0), (-20.0, -30.0, 60.0),
                                                    (5.0, 0.0, 40.0), (0.0, 0.0, 22.0), (0.0, 10.0, 12.0),
                                                    (15.0, -40.0, 130.0), (-40.0, 20.0, 100.0), (3.0, 2.0, 4.0)],
                              tmax=28.0, dt_out=0.35, files=_TOWER),
    # TurbSim's non-periodic box (5 x 7, bottom 5 m: Height Offset 10 m, 207 steps) with Clockwise added to its .sum
    "wnd_clockwise": dict(WindType=4, FileNameRoot='"nonperiodic"', TowerFile="False", PropagationDir=0.0,
                          VFlowAng=0.0, points=_NONPERIODIC_POINTS, tmax=10.5, dt_out=0.35,
                          files=["nonperiodic.wnd", "nonperiodic.sum"]),
    # the same data behind an old-style header (-3) with TurbSim's unedited summary (counter-clockwise)
    "wnd_oldstyle": dict(WindType=4, FileNameRoot='"oldstyle"', TowerFile="False", PropagationDir=0.0, VFlowAng=0.0,
                         points=_NONPERIODIC_POINTS, tmax=10.5, dt_out=0.35, files=["oldstyle.wnd", "oldstyle.sum"]),
    # native Bladed (WindType 7): PropagationDir/VFlowAng of the IfW file are replaced by WDIR/FLINC
    "native_vk": dict(WindType=7, FileNameRoot='"native_vk.txt"', PropagationDir=0.0, VFlowAng=0.0,
                      points=[(0.0, 0.0, 95.0), (10.0, 20.0, 120.0), (0.0, 0.0, 20.0), (-15.0, -10.0, 5.0),
                              (30.0, 40.0, 70.0), (0.0, 5.0, 30.0), (-50.0, 0.0, 100.0), (0.0, 30.0, 150.0),
                              (20.0, -50.0, 45.0)], tmax=28.0, dt_out=0.35,
                      files=["native_vk.txt", "tower_periodic.wnd"]),
    "native_mann": dict(WindType=7, FileNameRoot='"native/native_mann.txt"', PropagationDir=0.0, VFlowAng=0.0,
                        points=[(0.0, 0.0, 90.0), (0.0, 30.0, 120.0), (0.0, 0.0, 10.0), (12.0, -20.0, 14.0),
                                (-25.0, 64.99, 164.99), (8.0, -8.0, 50.0), (0.0, 0.0, 15.0), (40.0, 0.0, 85.0),
                                (-5.0, 3.0, 2.0)], tmax=9.8, dt_out=0.35, files=["native/native_mann.txt", "mann.wnd"]),
    "native_kaimal": dict(WindType=7, FileNameRoot='"native_kaimal.txt"', PropagationDir=0.0, VFlowAng=0.0,
                          points=[(0.0, 0.0, 85.0), (0.0, -30.0, 100.0), (0.0, 0.0, 5.0), (10.0, 25.0, 50.0),
                                  (-30.0, -10.0, 110.0), (5.0, 0.0, 8.0), (0.0, 20.0, 70.0), (25.0, 5.0, 150.0),
                                  (-8.0, -3.0, 1.0)], tmax=9.8, dt_out=0.35, files=["native_kaimal.txt", "kaimal.wnd"]),
    "native_old": dict(WindType=7, FileNameRoot='"native_old.txt"', PropagationDir=0.0, VFlowAng=0.0,
                       points=[(0.0, 0.0, 92.0), (0.0, 20.0, 110.0), (0.0, 0.0, 12.0), (10.0, -15.0, 60.0),
                               (-20.0, 10.0, 95.0), (5.0, 3.0, 16.0), (0.0, -30.0, 70.0), (30.0, 0.0, 85.0),
                               (-2.0, 2.0, 5.0)], tmax=9.8, dt_out=0.35, files=["native_old.txt", "oldstyle.wnd"]),
}


def read_case(name: str) -> tuple[np.ndarray, np.ndarray]:
    """The stored reference of case ``name``: times (M,) and velocities (M, 9, 3) [m/s]."""
    data = np.loadtxt(DATA / f"{name}.csv", delimiter=",", skiprows=1, ndmin=2)
    return data[:, 0], data[:, 1:].reshape(-1, 9, 3)


# ---------------------------------------------------------------------------------------------- box variants
def turbsim_header(path: Path) -> dict:
    """The values of TurbSim's -99/TurbType 4 header (104 bytes) and the int16 data (steps, NZ, NY, 3)."""
    raw = path.read_bytes()
    fid, turb, ncomp = struct.unpack_from("<hhi", raw, 0)
    assert (fid, turb, ncomp) == (-99, 4, 3), (fid, turb, ncomp)
    lat, z0, zref, *ti = struct.unpack_from("<6f", raw, 8)
    dz, dy, dx, half, u, _, _, _, _, seed, nz, ny = struct.unpack_from("<3fi4f4i", raw, 32)
    data = np.frombuffer(raw[104:], dtype="<i2").reshape(-1, nz, ny, 3)
    return dict(dz=dz, dy=dy, dx=dx, half=half, u=u, seed=seed, nz=nz, ny=ny, ti=ti, data=data)


def write_box(path: Path, h: dict, style: int, data: np.ndarray) -> Path:
    """Write ``data`` (steps, NZ, NY, 3 int16) behind a header of ``style``: -3 (old style), 7 or 8 (new style,
    general Kaimal or Mann); ``NStepsHalf = steps // 2``."""
    half = data.shape[0] // 2
    if style == -3:
        head = struct.pack("<13h", -3, round(1000 * h["dz"]), round(1000 * h["dy"]), round(1000 * h["dx"]), half,
                           round(10 * h["u"]), 0, 0, 0, 0, 1, 1000 * h["nz"], 1000 * h["ny"])
        head += struct.pack("<6h", *[0] * 6)                          # v and w length scales (3 components)
    else:
        grid = struct.pack("<3fi4f4i", h["dz"], h["dy"], h["dx"], half, h["u"], 30.0, 20.0, 100.0, 0, 1,
                           h["nz"], h["ny"])
        if style == 7:                                                # coherence decay and scale
            tail = struct.pack("<2f", 12.0, 0.5)
        else:                                                         # Mann: 16 values InflowWind skips
            tail = struct.pack("<6f3i2f3i2f", *[1.0] * 6, 1, 2, 3, 0.5, 0.5, 4, 5, 6, 2.0, 3.0)
        head = struct.pack("<hh2i", -99, style, 0, 3) + grid + struct.pack("<6f", *[10.0] * 6) + tail
    path.write_bytes(head + np.ascontiguousarray(data, dtype="<i2").tobytes())
    return path


def run_turbsim(work: Path) -> None:
    """TurbSim on the two stored inputs in ``work``; copy its outputs (and the edited summary) into DATA."""
    for name in ("tower_periodic", "nonperiodic"):
        shutil.copy(DATA / f"{name}.inp", work / f"{name}.inp")
        proc = subprocess.run([str(TURBSIM), f"{name}.inp"], cwd=work, capture_output=True, text=True, timeout=300)
        if proc.returncode != 0:
            raise RuntimeError(f"TurbSim failed on {name}.inp: {proc.stdout[-2000:]}")
    for f in _TOWER + ["nonperiodic.wnd", "nonperiodic.bts"]:
        shutil.copy(work / f, DATA / f)
    text = (work / "nonperiodic.sum").read_text()
    (DATA / "oldstyle.sum").write_text(text)
    anchor = "Output coherent turbulence time step file?\n"
    assert anchor in text
    (DATA / "nonperiodic.sum").write_text(text.replace(anchor, anchor + CLOCKWISE_LINE + "\n", 1))


def derive_files() -> None:
    """The boxes with other headers and the native summaries, from TurbSim's nonperiodic.wnd."""
    h = turbsim_header(DATA / "nonperiodic.wnd")
    write_box(DATA / "oldstyle.wnd", h, -3, h["data"])
    write_box(DATA / "mann.wnd", h, 8, h["data"][:60])                # 60 steps (even)
    write_box(DATA / "kaimal.wnd", h, 7, h["data"][60:121])           # 61 steps (odd: 2 NStepsHalf + 1)
    for name, text in NATIVE.items():
        (DATA / name).parent.mkdir(exist_ok=True)
        (DATA / name).write_text(text)


def run_case(name: str, folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """OpenFAST on case ``name`` in ``folder`` (its files copied there, keeping sub-folders)."""
    case = dict(CASES[name])
    for f in case.pop("files"):
        (folder / f).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(DATA / f, folder / f)
    return ifw_reference.run_points(folder, name, case)


def main(argv: list[str]) -> None:
    DATA.mkdir(parents=True, exist_ok=True)
    if "--reuse" not in argv:
        with tempfile.TemporaryDirectory() as tmp:
            run_turbsim(Path(tmp))
        derive_files()
    header = "Time," + ",".join(f"Wind{i}Vel{c}" for i in range(1, 10) for c in "XYZ")
    for name in CASES:
        with tempfile.TemporaryDirectory() as tmp:
            t, v = run_case(name, Path(tmp))
        rows = [",".join(repr(float(x)) for x in [ti, *vi.reshape(-1)]) for ti, vi in zip(t, v)]
        (DATA / f"{name}.csv").write_text(header + "\n" + "\n".join(rows) + "\n")
        print(f"{name}: {t.size} rows", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
