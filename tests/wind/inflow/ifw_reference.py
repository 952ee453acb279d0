"""OpenFAST v5 InflowWind as the reference for wind fields: run OpenFAST with 9 wind output points.

OpenFAST (ElastoDyn + InflowWind only: CompAero = CompServo = 0) writes ``WindNVelX/Y/Z`` at the
points of ``WindVxiList``/``WindVyiList``/``WindVziList`` (fixed in ground axes), which InflowWind
evaluates with the same routine as the rotor's points. :func:`run_points` runs one case;
``python tests/wind/inflow/ifw_reference.py`` regenerates the stored references in ``data/``
(``ifw_<case>.csv``: time, then 27 columns) from the shared decks and the binary in
``shared/tools/openfast``. Each run takes 2-4 s.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"


def _shared() -> Path:
    for parent in HERE.parents:
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared"
    return HERE.parents[3].parent / "shared"


SHARED = _shared()
OPENFAST = SHARED / "tools" / "openfast" / "openfast"
FF14 = SHARED / "openfast" / "aero" / "openfast_inputs" / "ff14_flex"

#: The cases: InflowWind settings and 9 points (x, y, z) [m] in ground axes.
FF_POINTS = [(0.0, 0.0, 90.0), (0.0, 17.3, 101.2), (-31.7, -44.1, 47.9), (25.0, 60.2, 150.3), (0.0, -69.99, 20.01),
             (-12.0, 69.0, 159.9), (40.0, 3.3, 33.3), (-55.5, -20.0, 120.0), (5.0, 0.0, 130.6)]
UNI_POINTS = [(0.0, 0.0, 90.0), (0.0, 30.0, 120.0), (10.0, -40.0, 40.0), (-20.0, 15.0, 140.0), (0.0, 0.0, 10.0),
              (3.0, 63.0, 90.0), (-8.0, -63.0, 27.0), (30.0, 0.0, 153.0), (0.0, 5.0, 0.5)]
#: Points of the periodic TurbSim field with 3 tower points (data/tower_periodic.inp: 5 x 15 grid, 130 m square
#: centred at 90 m, bottom 25 m, dz 9.29 m, tower points at 25, 15.7, 6.4 m; 200 steps of 0.1 s, periodic).
TOWER_POINTS = [(0.0, 0.0, 90.0), (0.0, 20.0, 100.0), (0.0, 0.0, 20.0), (0.0, 25.0, 12.0), (-10.0, -5.0, 8.0),
                (5.0, 0.0, 3.0), (0.0, 7.0, 24.995), (0.0, 64.99, 120.0), (-100.0, 0.0, 90.0)]
#: The HAWC files of the HAWC cases (TurbSim's output for data/tower_periodic.inp) and their layout.
HAWC = dict(WindType=5, FileName_u=f'"{(DATA / "tower_periodic-u.bin").as_posix()}"',
            FileName_v=f'"{(DATA / "tower_periodic-v.bin").as_posix()}"',
            FileName_w=f'"{(DATA / "tower_periodic-w.bin").as_posix()}"', nx=200, ny=5, nz=15, dx=1.4, dy=32.5,
            dz=9.285714285714286, RefHt_Hawc=90.0, PropagationDir=0.0, VFlowAng=0.0)
CASES = {
    "ff14": dict(WindType=3, PropagationDir=0.0, VFlowAng=0.0, points=FF_POINTS, tmax=3.0),
    "ff14_rotated": dict(WindType=3, PropagationDir=12.0, VFlowAng=4.0, points=[(x, 0.8 * y, 90.0 + 0.8 * (z - 90.0))
                                                                                 for x, y, z in FF_POINTS], tmax=3.0),
    "uniform": dict(WindType=2, PropagationDir=7.0, VFlowAng=2.0, points=UNI_POINTS, tmax=3.0, RefLength=125.0),
    "tower_periodic": dict(WindType=3, PropagationDir=0.0, VFlowAng=0.0, points=TOWER_POINTS, tmax=45.0, dt_out=0.25,
                           bts=DATA / "tower_periodic.bts"),
    # HAWC boxes (WindType 5): TurbSim's HAWC output of data/tower_periodic.inp (WrHAWCFF = True, the same seed:
    # data/tower_periodic-u/v/w.bin; its .hawc file gives factor_scaling 1.04056 1.65162 1.97520)
    "hawc_direct": dict(HAWC, ScaleMethod=1, SFx=1.04056, SFy=1.65162, SFz=1.97520, URef=14.0, WindProfile=2,
                        PLExp_Hawc=0.2, points=TOWER_POINTS, tmax=45.0, dt_out=0.25),
    "hawc_sigma_log": dict(HAWC, ScaleMethod=2, SigmaFx=1.5, SigmaFy=1.2, SigmaFz=0.8, URef=11.0, WindProfile=1,
                           Z0=0.1, XOffset=20.0, PropagationDir=10.0, VFlowAng=3.0,
                           points=[(x, 0.8 * y, 90.0 + 0.8 * (z - 90.0)) for x, y, z in TOWER_POINTS],
                           tmax=45.0, dt_out=0.25),
    "hawc_raw": dict(HAWC, ScaleMethod=0, URef=9.0, WindProfile=0, RefHt_Hawc=95.0, dx=0.9,
                     points=[(x, y, z + 5.0) for x, y, z in TOWER_POINTS], tmax=45.0, dt_out=0.25),
    "steady_shear": dict(WindType=1, PropagationDir=-15.0, VFlowAng=0.0, points=UNI_POINTS, tmax=0.2,
                         HWindSpeed=11.0, PLexp=0.2),
}
#: The uniform wind file of the "uniform_cubic" case: uneven rows, a step of the speed and a gust, every column
#: changing (VelInterpCubic: a clamped spline through each column, Hermite between rows).
UNIFORM_STEP_ROWS = """! mbsym test: uneven rows with a step and a gust (VelInterpCubic)
! Time HorSpd WndDir VerSpd HorShr VerShr LnVShr GstSpd Upflow
0.0  10.0  -8.0  0.4  0.10  0.12  0.05  0.0   1.5
0.7  10.4  -2.0  0.2  0.15  0.16  0.08  0.0   2.0
1.0  10.5   5.0 -0.3  0.25  0.20  0.15  0.0   3.0
1.1  14.0   6.0 -0.3  0.25  0.20  0.15  0.0   3.0
1.6  13.5  20.0  0.1 -0.10  0.30 -0.10  2.5  -2.0
2.1  13.0  18.0  0.0  0.00  0.25  0.00  0.4   0.0
3.0  12.0  15.0  0.0  0.05  0.14  0.02  0.0   0.5
"""
#: Points of the non-periodic TurbSim field with 3 tower points (data/tower_nonperiodic.inp: the grid of
#: tower_periodic, 193 steps of 0.1 s); the point 100 m upstream reaches InflowWind's last step (τ in
#: [19.2, 19.3) s) at t = 7.45 and 7.5 s.
TOWER_NP_POINTS = [*TOWER_POINTS[:8], (-100.0, 0.0, 90.0)]
#: VelInterpCubic = True (cubic in time): a uniform file with a step, TurbSim fields without tower points (ff14:
#: InflowWind then takes zero slopes), with tower points (spline slopes; periodic and not) and a HAWC box.
CUBIC_CASES = {
    "uniform_cubic": dict(WindType=2, PropagationDir=7.0, VFlowAng=2.0, points=UNI_POINTS, tmax=3.5, RefLength=125.0,
                          VelInterpCubic="True", uniform_rows=UNIFORM_STEP_ROWS),
    "ff14_cubic": dict(CASES["ff14"], VelInterpCubic="True"),
    "tower_periodic_cubic": dict(CASES["tower_periodic"], VelInterpCubic="True"),
    "tower_cubic": dict(WindType=3, PropagationDir=0.0, VFlowAng=0.0, points=TOWER_NP_POINTS, tmax=7.5,
                        bts=DATA / "tower_nonperiodic.bts", VelInterpCubic="True"),
    "hawc_direct_cubic": dict(CASES["hawc_direct"], VelInterpCubic="True"),
}
CASES.update(CUBIC_CASES)
#: The uniform wind file of the "uniform" case: every column non-zero and changing.
UNIFORM_ROWS = """! mbsym test: every column of a uniform wind file non-zero
! Time HorSpd WndDir VerSpd HorShr VerShr LnVShr GstSpd Upflow
0.0  10.0  -8.0  0.4  0.10  0.12  0.05  0.0   1.5
1.0  11.5   5.0 -0.3  0.25  0.20  0.15  0.8   3.0
2.0  13.0  20.0  0.1 -0.10  0.30 -0.10  1.2  -2.0
3.0  12.0  15.0  0.0  0.05  0.14  0.02  0.0   0.5
"""


def _set(text: str, key: str, value) -> str:
    pattern = re.compile(rf"^(\s*)(\S.*?)(\s+{re.escape(key)}\s)", re.MULTILINE)
    if not pattern.search(text):
        raise KeyError(key)
    return pattern.sub(lambda m: f"{m.group(1)}{value}{m.group(3)}", text, count=1)


#: Case entries that are not InflowWind keys.
_NOT_KEYS = ("points", "tmax", "dt_out", "bts", "files", "uniform_rows")


def write_case(folder: Path, name: str, case: dict | None = None) -> Path:
    """Write ``<name>.fst`` (+ IfW file, + uniform file) into ``folder``; return the .fst.

    ``case`` (default ``CASES[name]``): InflowWind keys and values (set in the IfW file as given: quote strings
    yourself), ``points`` (9 points (x, y, z) [m]), ``tmax`` [s], optional ``dt_out`` [s], ``bts`` (the TurbSim
    file of ``FileName_BTS``), ``files`` (paths copied into ``folder``) and ``uniform_rows`` (the text of the
    uniform wind file, default :data:`UNIFORM_ROWS`)."""
    import shutil

    case = CASES[name] if case is None else case
    folder.mkdir(parents=True, exist_ok=True)
    for f in case.get("files", ()):
        shutil.copy(f, folder / Path(f).name)
    pts = np.array(case["points"], dtype=float)
    ifw = (FF14 / "ff14_flex_IfW.dat").read_text()
    for key, value in case.items():
        if key not in _NOT_KEYS:
            ifw = _set(ifw, key, value)
    ifw = _set(ifw, "NWindVel", 9)
    for j, key in enumerate(("WindVxiList", "WindVyiList", "WindVziList")):
        ifw = _set(ifw, key, ", ".join(repr(float(v)) for v in pts[:, j]))
    bts = case.get("bts", SHARED / "openfast" / "aero" / "wind" / "ff14.bts")
    ifw = _set(ifw, "FileName_BTS", f'"{Path(bts).as_posix()}"')
    (folder / "uniform.hh").write_text(case.get("uniform_rows", UNIFORM_ROWS))
    ifw = _set(ifw, "Filename_Uni", '"uniform.hh"')
    channels = "\n".join(f'"Wind{i}Vel{c}"' for i in range(1, 10) for c in "XYZ")
    ifw = re.sub(r'OutList.*?\nEND', lambda m: m.group(0).split("\n")[0] + "\n" + channels + "\nEND", ifw,
                 flags=re.S)
    (folder / f"{name}_IfW.dat").write_text(ifw)
    fst = (FF14 / "ff14_flex.fst").read_text()
    for key, value in (("TMax", case["tmax"]), ("CompAero", 0), ("CompServo", 0), ("OutFileFmt", 1),
                       ("SumPrint", "False"), ("EDFile", f'"{(FF14 / "ff14_flex_ED.dat").as_posix()}"'),
                       ("InflowFile", f'"{name}_IfW.dat"'),
                       ("DT_Out", case.get("dt_out", 0.05)), ("OutFmt", '"ES16.8E3"'), ("TabDelim", "True")):
        fst = _set(fst, key, value)
    path = folder / f"{name}.fst"
    path.write_text(fst)
    return path


def run_points(folder: Path, name: str, case: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Run OpenFAST on case ``name`` (or the given ``case``, see :func:`write_case`) in ``folder``: times (M,)
    and velocities (M, 9, 3) [m/s]."""
    fst = write_case(folder, name, case)
    proc = subprocess.run([str(OPENFAST), fst.name], cwd=folder, capture_output=True, text=True, timeout=300)
    if proc.returncode != 0:
        raise RuntimeError(f"OpenFAST failed on {name}: {proc.stdout[-2000:]}")
    lines = (folder / f"{name}.out").read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith("Time"))
    names = lines[start].split()
    data = np.array([[float(v) for v in line.split()] for line in lines[start + 2:] if line.strip()])
    cols = [names.index(f"Wind{i}Vel{c}") for i in range(1, 10) for c in "XYZ"]
    return data[:, 0], data[:, cols].reshape(-1, 9, 3)


def read_reference(name: str) -> tuple[np.ndarray, np.ndarray]:
    """The stored reference of case ``name``: times (M,) and velocities (M, 9, 3)."""
    data = np.loadtxt(DATA / f"ifw_{name}.csv", delimiter=",", skiprows=1)
    return data[:, 0], data[:, 1:].reshape(-1, 9, 3)


def main(names=None) -> None:
    """Regenerate the stored references of ``names`` (default: every case; ``python ifw_reference.py [case ...]``)."""
    import tempfile

    DATA.mkdir(exist_ok=True)
    for name in names or CASES:
        with tempfile.TemporaryDirectory() as tmp:
            t, v = run_points(Path(tmp), name)
        header = "Time," + ",".join(f"Wind{i}Vel{c}" for i in range(1, 10) for c in "XYZ")
        rows = [",".join(repr(float(x)) for x in [ti, *vi.reshape(-1)]) for ti, vi in zip(t, v)]
        (DATA / f"ifw_{name}.csv").write_text(header + "\n" + "\n".join(rows) + "\n")
        print(f"{name}: {t.size} rows", file=sys.stderr)


if __name__ == "__main__":
    main(sys.argv[1:])
