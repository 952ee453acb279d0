"""InflowWind's full-field formats in mbsym: reading and evaluating the same field as TurbSim, HAWC and Bladed boxes.

The baseline is the TurbSim ``.bts`` of the shared ``ff14`` field (25 x 25 grid, 13400 steps of 0.05 s, 50 MB),
read and evaluated in the same run. The same velocities are written as a HAWC box (``write_hawc``: u minus
URef, ``ScaleMethod`` 0, a constant profile at URef: the HAWC box then holds the .bts field to float32 rounding) and
read back; the Bladed boxes are the test data's (TurbSim's ``.wnd`` of a 5 x 15 field and a native Bladed box),
timed per megabyte. For each: reading [s] and [s per 100 MB of float32 field], one ``velocity`` call at 51 rotor
points (numpy) [ms] and one call of the generated C External (``casadi_function``) [µs], with ratios to the .bts;
and the largest velocity difference of the HAWC reading against the .bts [m/s] (accuracy: the readers are checked
against OpenFAST itself in tests/wind/inflow).

Usage::

    python benchmarks/wind_formats.py [--bts PATH] [--repeat 20]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from mbsym.wind.inflow import (FullFieldWind, HawcBox, read_bladed_native, read_bladed_wnd, read_hawc,
                               read_turbsim_bts, write_hawc)

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared"
BLADED = ROOT / "tests" / "data" / "openfast_bladed_wind"


def _best(f, repeat: int) -> float:
    best = float("inf")
    for _ in range(repeat):
        t = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t)
    return best


def _points(field: FullFieldWind) -> np.ndarray:
    """51 points, three rings of 17, on a disk of 80 % of the grid's half width and height about its centre."""
    r = 0.8 * min(field.half_width, 0.5 * (field.n_z - 1) * field.dz)
    zc = field.grid_bottom + 0.5 * (field.n_z - 1) * field.dz
    ang = np.linspace(0.0, 2 * np.pi, 17, endpoint=False)
    return np.array([(0.0, frac * r * np.sin(a), zc + frac * r * np.cos(a)) for frac in (1 / 3, 2 / 3, 1.0)
                     for a in ang])


def _costs(name: str, read, repeat: int) -> dict:
    t = time.perf_counter()
    field = read()
    read_s = time.perf_counter() - t
    pts = _points(field)
    t0 = field.time_range[0] + 1.0
    numpy_s = _best(lambda: field.velocity(t0, pts), repeat)
    f = field.casadi_function(len(pts))
    f(t0, pts.T)                                              # load the data once
    c_s = _best(lambda: f(t0, pts.T), repeat * 10)
    return {"name": name, "field": field, "read": read_s, "per100": read_s / (field.nbytes / 1e8), "numpy": numpy_s,
            "c": c_s, "mb": field.nbytes / 1e6}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--bts", type=Path, default=SHARED / "openfast" / "aero" / "wind" / "ff14.bts")
    p.add_argument("--repeat", type=int, default=20)
    args = p.parse_args()
    rows = [_costs("TurbSim .bts (baseline)", lambda: read_turbsim_bts(args.bts), args.repeat)]
    base = rows[0]["field"]
    with tempfile.TemporaryDirectory() as tmp:
        g = np.array(base.grid, dtype=np.float32)
        g[..., 0] -= np.float32(base.mean_speed)
        files = write_hawc(Path(tmp) / "ff", FullFieldWind(g, dy=base.dy, dz=base.dz, dt=base.dt,
                                                           mean_speed=base.mean_speed,
                                                           reference_height=base.reference_height,
                                                           grid_bottom=base.grid_bottom))
        del g
        half = 0.5 * (base.n_z - 1) * base.dz
        box = HawcBox(files, base.n_t, base.n_y, base.n_z, base.dt * base.mean_speed, base.dy, base.dz,
                      base.grid_bottom + half, scale_method=0, mean_speed=base.mean_speed, profile=0)
        rows.append(_costs("HAWC (the same field)", lambda: read_hawc(box), args.repeat))
        hawc = rows[-1]["field"]
        i = np.arange(0, base.n_t, 97)
        diff = float(np.abs(hawc.grid[i].astype(float) + [base.mean_speed, 0, 0] - base.grid[i]).max())
    rows.append(_costs("Bladed .wnd (TurbSim, 5 x 15, test data)",
                       lambda: read_bladed_wnd(BLADED / "tower_periodic.wnd", tower_file=True), args.repeat))
    rows.append(_costs("native Bladed (test data)", lambda: read_bladed_native(BLADED / "native_vk.txt"), args.repeat))
    ref = rows[0]
    print("| format | field MB | read s | read s / 100 MB | x .bts | velocity, 51 points, numpy ms | x .bts | "
          "C External µs | x .bts |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['name']} | {r['mb']:.3g} | {r['read']:.3g} | {r['per100']:.3g} | {r['per100'] / ref['per100']:.2f} | "
              f"{1e3 * r['numpy']:.3g} | {r['numpy'] / ref['numpy']:.2f} | {1e6 * r['c']:.3g} | "
              f"{r['c'] / ref['c']:.2f} |")
    print(f"\nHAWC box against the .bts grid (every 97th step): max |Δv| = {diff:.2e} m/s")


if __name__ == "__main__":
    main()
