"""The floating IEA 15 MW in irregular waves (issue 20, items 2 and 7): mbsym against OpenFAST, accuracy and speed.

The shared ``fl_steady_13`` deck (13 m/s, ROSCO 2.10.6 library with the deck's DISCON.IN, HydroDyn, MoorDyn) with
a JONSWAP sea in its SeaState (``--hs``, ``--tp``; RANLUX seed as shared) and AeroDyn's unsteady aerodynamics and
tower influence off (what mbsym's rotor models), copied to a work folder. Runs ``mbsym simulate --aero rotor``
with the library and, when the OpenFAST binary is there (``../shared/tools/openfast``), OpenFAST on the same
files, timing both. Without OpenFAST it compares with the recorded run
(``tests/data/openfast_waves/fl_steady_13_jonswap.csv``, Hs 4 m, Tp 10 s only). Prints per channel the mean
difference, the standard deviations, ε = RMS(error)/range and R² after 100 s, then the wall times and their ratio.

    python benchmarks/floating_waves.py [--tmax 600] [--hs 4.0] [--tp 10.0] [--rosco DIR] [--keep DIR]
        [--no-openfast] [--plot FILE.png]

``--rosco DIR``: a folder holding the wheel's ``rosco/`` and ``rosco.libs/`` (default: the tests' cache,
``~/.cache/mbsym/rosco/2.10.6``, filled by ``pip download --no-deps rosco==2.10.6``).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))
from discon_export_openfast import _read_csv, _read_out, _set_value  # noqa: E402  (the OpenFAST deck helpers)
RECORDED = HERE.parent / "tests" / "data" / "openfast_waves" / "fl_steady_13_jonswap.csv"
CHANNELS = ("Wave1Elev", "PtfmSurge", "PtfmHeave", "PtfmPitch", "PtfmRoll", "PtfmYaw", "TTDspFA", "RotSpeed",
            "BldPitch1", "GenPwr", "FAIRTEN1", "FAIRTEN2")
AERO_EDITS = (("TwrPotent", "0"), ("TwrShadow", "0"), ("TwrAero", "False"), ("UA_Mod", "0"))


def _floating() -> Path:
    """The shared floating decks (``../shared/openfast/floating``)."""
    found = [parent / "shared" / "openfast" / "floating" for parent in HERE.parents
             if (parent / "shared" / "openfast" / "floating").is_dir()]
    if not found:
        sys.exit("benchmarks/floating_waves.py: ../shared/openfast/floating not found")
    return found[0]


def deck(work: Path, hs: float, tp: float, tmax: float, rosco: Path) -> Path:
    """The edited copy of the shared decks in ``work``; the case's .fst."""
    floating = _floating()
    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi", "cases"):
        if not (work / name).exists():
            shutil.copytree(floating / name, work / name)
            os.system(f"chmod -R u+w '{work / name}'")
    for name in ("rosco", "rosco.libs"):
        if not (work / name).exists() and (rosco / name).exists():
            (work / name).symlink_to((rosco / name).resolve())
    aerodyn = work / "IEA-15-240-RWT-UMaineSemi" / "IEA-15-240-RWT-UMaineSemi_AeroDyn15.dat"
    for key, value in AERO_EDITS:
        _set_value(aerodyn, key, value)
    case = work / "cases" / "fl_steady_13"
    sea = case / "fl_steady_13_SeaState.dat"
    for key, value in (("WaveMod", "2"), ("WaveHs", f"{hs}"), ("WaveTp", f"{tp}"), ("WvDiffQTF", "False"),
                       ("WvSumQTF", "False")):
        _set_value(sea, key, value)
    fst = case / "fl_steady_13.fst"
    _set_value(fst, "TMax", f"{tmax}")
    _set_value(fst, "OutFileFmt", "1")
    return fst


def compare(ref: dict[str, np.ndarray], ours: dict[str, np.ndarray], settle: float = 100.0) -> None:
    t = ref["Time"]
    keep = t >= settle - 1e-9
    print(f"{'channel':10s} {'mean ref':>11s} {'mean mbsym':>11s} {'Δ %':>7s} {'std ref':>10s} {'std mbsym':>10s} "
          f"{'ε %':>6s} {'R²':>7s}")
    for name in CHANNELS:
        if name not in ref or name not in ours:
            continue
        a = ref[name][keep]
        b = np.interp(t[keep], ours["Time"], ours[name])
        span = np.ptp(a) or 1.0
        eps = 100 * np.sqrt(np.mean((a - b) ** 2)) / span
        r2 = 1 - np.sum((a - b) ** 2) / (np.sum((a - a.mean()) ** 2) or 1.0)
        delta = 100 * (b.mean() - a.mean()) / (abs(a.mean()) or 1.0)
        print(f"{name:10s} {a.mean():11.4g} {b.mean():11.4g} {delta:7.2f} {a.std():10.4g} {b.std():10.4g} "
              f"{eps:6.2f} {r2:7.3f}")


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--tmax", type=float, default=600.0)
    p.add_argument("--hs", type=float, default=4.0)
    p.add_argument("--tp", type=float, default=10.0)
    p.add_argument("--rosco", type=Path, default=Path.home() / ".cache" / "mbsym" / "rosco" / "2.10.6")
    p.add_argument("--keep", type=Path, default=None)
    p.add_argument("--no-openfast", action="store_true")
    p.add_argument("--plot", type=Path, default=None)
    args = p.parse_args()
    lib = args.rosco / "rosco" / "lib" / "libdiscon.so"
    if not lib.is_file():
        sys.exit(f"ROSCO library not found at {lib}: pip download --no-deps rosco==2.10.6 and unzip rosco/ and "
                 "rosco.libs/ there, or give --rosco DIR")
    work = args.keep or Path(tempfile.mkdtemp(prefix="mbsym_waves_"))
    work.mkdir(parents=True, exist_ok=True)
    fst = deck(work, args.hs, args.tp, args.tmax, args.rosco)
    exe = _floating().parents[1] / "tools" / "openfast" / "openfast"
    ref, of_wall = None, None
    if exe.is_file() and not args.no_openfast:
        t0 = time.perf_counter()
        subprocess.run([str(exe), fst.name], cwd=fst.parent, check=True, stdout=subprocess.DEVNULL)
        of_wall = time.perf_counter() - t0
        ref = _read_out(fst.with_suffix(".out"))
    elif (args.hs, args.tp) == (4.0, 10.0):
        ref = _read_csv(RECORDED)
    from mbsym.cli import main as mbsym_main

    out = work / "mbsym_waves.csv"
    t0 = time.perf_counter()
    code = mbsym_main(["simulate", str(fst), "--aero", "rotor", "--discon", str(lib), "--tmax", f"{args.tmax}",
                       "--out", str(out)])
    mb_wall = time.perf_counter() - t0
    if code:
        sys.exit(f"mbsym simulate failed ({code})")
    ours = _read_csv(out)
    print(f"\nfloating IEA 15 MW, 13 m/s, JONSWAP Hs {args.hs} m Tp {args.tp} s, {args.tmax:g} s; work folder {work}")
    if ref is not None:
        compare(ref, ours)
    print(f"\nwall time: mbsym {mb_wall:.1f} s (model build, compilation, run, outputs)"
          + (f"; OpenFAST {of_wall:.1f} s; ratio OpenFAST/mbsym {of_wall / mb_wall:.1f}" if of_wall else ""))
    if args.plot and ref is not None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        names = ("Wave1Elev", "PtfmSurge", "PtfmHeave", "PtfmPitch", "TTDspFA", "FAIRTEN1")
        fig, axes = plt.subplots(len(names), 1, figsize=(9, 12), sharex=True)
        for ax, name in zip(axes, names):
            ax.plot(ref["Time"], ref[name], "k", lw=0.8, label="OpenFAST")
            ax.plot(ours["Time"], ours[name], "C1", lw=0.8, label="mbsym")
            ax.set_ylabel(name)
        axes[0].legend(loc="upper right")
        axes[-1].set_xlabel("time [s]")
        axes[-1].set_xlim(100, min(args.tmax, 400))
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print(f"wrote {args.plot}")


if __name__ == "__main__":
    main()
