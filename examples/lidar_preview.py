"""What a nacelle lidar can tell the NMPC: InflowWind's single-point lidar on a TurbSim field, and its preview.

A 5-beam lidar 60 m upstream of the NREL 5 MW hub (at the hub and 0.7 R left, right, up, down) reads a TurbSim
full field as OpenFAST's InflowWind does (``SensorType = 1``); :class:`~mbsym.wind.mpc.lidar_preview.LidarPreview`
turns its speeds into the NMPC's stage winds (the estimate now plus the change the lidar saw coming). Here the
"estimate" is the rotor's true disk-averaged wind, so the table shows the preview alone: how well it predicts
the disk average's change 1-4 s ahead, against persistence (no change), for moving averages of 1 and 4 s.

Run: ``python examples/lidar_preview.py [FIELD.bts] [--plot F.png]`` (default field: the shared
``../shared/openfast/aero/wind/ff14.bts`` when present). To put the same lidar in an OpenFAST deck and export
the NMPC that previews from it::

    # in the deck's InflowWind file: SensorType 1, NumBeam 5, FocalDistanceX -60 -60 -60 -60 -60,
    # FocalDistanceY 0 44 -44 0 0, FocalDistanceZ 0 0 0 44 -44, MeasurementInterval 0.1
    mbsym export-discon DECK.fst --controller nmpc --out lib      # the lidar turns the preview on
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from mbsym.wind.inflow import PointLidar, read_turbsim_bts, rotor_effective_wind
from mbsym.wind.mpc.lidar_preview import LidarPreview, PreviewSettings

HUB = np.array([-5.0, 0.0, 90.0])        # NREL 5 MW: OverHang along the tilted shaft, hub height [m]
RADIUS = 63.0
DT = 0.1                                 # NMPC sample time [s]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    shared = Path(__file__).resolve().parents[2] / "shared" / "openfast" / "aero" / "wind" / "ff14.bts"
    ap.add_argument("field", nargs="?", default=str(shared), help="TurbSim full field (.bts)")
    ap.add_argument("--plot", help="write a figure of the 3 s ahead prediction")
    args = ap.parse_args()
    if not Path(args.field).is_file():
        print(f"no field at {args.field}: give a TurbSim .bts file", file=sys.stderr)
        return 2
    field = read_turbsim_bts(args.field)
    lidar = PointLidar(focal=[[-60, 0, 0], [-60, 44, 0], [-60, -44, 0], [-60, 0, 44], [-60, 0, -44]],
                       apex_offset=[0, 0, 0], interval=DT)
    lead = lidar.upstream_distance / field.mean_speed
    t0, t1 = field.time_range
    times = np.arange(max(t0, 0.0) + 20.0, t1 - lead - 10.0, DT)
    v = field.velocity(times, lidar.positions(HUB))                       # (M, 5, 3)
    speeds = np.sqrt(np.sum(v * v, axis=2))
    disk = rotor_effective_wind(field, times=times, radius=RADIUS, hub_height=HUB[2], hub_x=HUB[0])["average"]
    print(f"{args.field}: mean {field.mean_speed:g} m/s, lidar {lidar.upstream_distance:g} m upstream "
          f"(the wind arrives {lead:.1f} s later)")
    print("moving average | RMS error of the predicted disk-average change / persistence's, 1 2 3 4 s ahead")
    predicted = {}
    for window in (1.0, 4.0):
        pv = LidarPreview(PreviewSettings.for_lidar(lidar, window=window), DT, 40, (1.0, 40.0))
        pred, true = [], []
        for i, t in enumerate(times):
            pv.push(t, speeds[i])
            if t > times[0] + 20.0 and i + 40 < len(times):
                w = pv.horizon(t, disk[i])
                pred.append(w[[10, 20, 30, 40]] - w[0])
                true.append(disk[i + np.array([10, 20, 30, 40])] - disk[i])
        pred, true = np.array(pred), np.array(true)
        ratio = np.sqrt(np.mean((pred - true) ** 2, axis=0) / np.mean(true ** 2, axis=0))
        print(f"{window:>11g} s  | " + "  ".join(f"{r:.2f}" for r in ratio))
        predicted[window] = (pred[:, 2], true[:, 2])
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 3.5))
        pred, true = predicted[4.0]
        ax.plot(true[:1200], "k", lw=0.8, label="disk-average change over the next 3 s")
        ax.plot(pred[:1200], "tab:red", lw=0.8, label="lidar preview (4 s moving average)")
        ax.set_xlabel(f"sample ({DT:g} s)")
        ax.set_ylabel("m/s")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print(f"wrote {args.plot}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
