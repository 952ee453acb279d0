"""Second-order wave loads of a floating platform, as HydroDyn makes them (docs/offshore.md §7f).

Reads a HydroDyn file with its WAMIT data and a SeaState file with irregular waves, and compares the first-order
excitation with the second-order loads of each method HydroDyn offers (mean drift, Newman's approximation, the
full difference- and sum-frequency QTFs), by switching them in copies of the HydroDyn file. The `rosco` 2.10.6
wheel's VolturnUS-S deck (``Examples/Test_Cases/IEA-15-240-RWT/IEA-15-240-RWT-UMaineSemi``) has the `.12d` and
`.12s` files these need::

    python examples/second_order_waves.py <case>/IEA-15-240-RWT-UMaineSemi_HydroDyn.dat \\
        <case>/IEA-15-240-RWT-UMaineSemi_SeaState.dat [--plot second_order.png]
"""

from __future__ import annotations

import argparse
import re
import tempfile
import warnings
from pathlib import Path

import numpy as np

from mbsym.wind.offshore.platform import platform_hydrodynamics

METHODS = {"first order only": {},
           "mean drift (MnDrift 12)": {"MnDrift": 12},
           "Newman (NewmanApp 12)": {"NewmanApp": 12},
           "full difference QTF (DiffQTF 12)": {"DiffQTF": 12},
           "difference + sum QTFs (DiffQTF, SumQTF 12)": {"DiffQTF": 12, "SumQTF": 12}}


def excitation(hydrodyn: Path, seastate: Path, switches: dict, folder: Path) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] and the surge force [N] of the excitation with the second-order ``switches`` (the others 0)."""
    text = hydrodyn.read_text()
    for key in ("MnDrift", "NewmanApp", "DiffQTF", "SumQTF"):
        text = re.sub(rf"^\s*\S+(\s+{key}\b)", rf"{switches.get(key, 0)}\1", text, count=1, flags=re.M)
    copy = folder / hydrodyn.name
    copy.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        waves = platform_hydrodynamics(copy, water_density=1025.0, gravity=9.81, seastate=seastate,
                                       water_depth=200.0).waves
    return waves.waves.times(), waves.forces[:, 0]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("hydrodyn", type=Path)
    p.add_argument("seastate", type=Path)
    p.add_argument("--plot", type=Path)
    args = p.parse_args()
    results = {}
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for item in args.hydrodyn.parent.iterdir():            # the WAMIT files, relative to the HydroDyn file
            if item.is_dir():
                (folder / item.name).symlink_to(item.resolve())
        for name, switches in METHODS.items():
            results[name] = excitation(args.hydrodyn, args.seastate, switches, folder)
    t, first = results["first order only"]
    print(f"{'method':45s} {'mean [kN]':>10s} {'std [kN]':>10s}   (second order alone, surge)")
    for name, (_, f) in results.items():
        second = f - first
        print(f"{name:45s} {second.mean() / 1e3:10.2f} {second.std() / 1e3:10.2f}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 4))
        keep = t <= 300.0
        for name, (_, f) in list(results.items())[1:]:
            ax.plot(t[keep], (f - first)[keep] / 1e3, label=name, lw=1)
        ax.set_xlabel("time [s]")
        ax.set_ylabel("second-order surge force [kN]")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
