"""The floating NMPC exported as a DISCON library, inside OpenFAST, in turbulence and waves, against ROSCO.

Issues 20 (item 5) and 21 (item 1) together: the IEA 15 MW on the VolturnUS-S (the shared ``fl_steady_13`` deck,
``../shared/openfast/floating``: six platform DOFs, tower FA1/SS1, generator, rigid blades, AeroDyn 15 with DBEMT,
UA and the tower's influence, HydroDyn potential flow with convolution radiation, MoorDyn) with

* its wind replaced by a TurbSim full field made here (IEC Kaimal NTM class ``--iec``, hub 150 m, power-law shear
  0.14, 25 × 25 points over 280 m, down to 10 m: AeroDyn reads the wind at the tower from 15 m; 0.05 s;
  ``--wind`` m/s, ``--seed``), InflowWind ``WindType 3``;
* its sea replaced by first-order JONSWAP waves (``--hs``, ``--tp``, SeaState ``WaveMod 2``, the deck's seeds);
* ``--seconds`` of simulation (660 by default), measured over t >= 60 s;

run twice by OpenFAST v5.0.0 (``../shared/tools/openfast``): with the ROSCO 2.10.6 library and the deck's
``DISCON.IN`` (floating feedback ``Fl_Mode 2``), and with ``mbsym export-discon DECK --controller nmpc`` (the deck
as modified: the NMPC with the platform's surge and pitch and ``NMPCTuning.floating``, its EKF with the nacelle IMU
and the platform's pitch and surge from the swap array, ``EstimatorTuning.full_field``; the two paths of its JSON
line put into the ServoDyn file, nothing else changed). The same wind and sea for both. Measures: platform pitch
and surge standard deviations, tower-base fore-aft and side-side DEL (rainflow, Wöhler m = 4, 1 Hz), blade-root
DEL (m = 10), rotor-speed RMS error about the rated 7.56 rpm, RMS pitch rate, energy, peaks of power and rotor
speed, fairlead-1 tension standard deviation; each NMPC / ROSCO.

Run: ``python benchmarks/floating_nmpc_openfast.py [--wind 13 --seed 1 --hs 4 --tp 10] [--work DIR] [--plot F]
[--set KEY=VALUE ...]`` (``--set``: run-time settings written into the library's input file before the run, e.g.
``PlatformPitchRateScale=0.001``; docs/discon_export.md)
(needs ../shared, the OpenFAST and TurbSim binaries, a C compiler and the ROSCO library, ``--rosco-lib``, default
the test cache's ``~/.cache/mbsym/rosco/2.10.6/rosco/lib/libdiscon.so``). About 7 min TurbSim, 1 min export, then
both OpenFAST runs side by side (4-6 min on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE)]
from discon_export_openfast import _read_out  # noqa: E402  (the benchmarks' OpenFAST reader)
from discon_export_openfast import _set_value as _set  # noqa: E402

SHARED = HERE.parent.parent / "shared"
FLOATING = SHARED / "openfast" / "floating"
TOOLS = SHARED / "tools" / "openfast"
ROSCO_LIB = Path.home() / ".cache" / "mbsym" / "rosco" / "2.10.6" / "rosco" / "lib" / "libdiscon.so"
T_START = 60.0
RATED_RPM = 7.56            # the deck's DISCON.IN: PC_RefSpd 0.7917 rad/s


def turbsim_input(template: Path, out: Path, *, wind: float, seed: int, seconds: float, iec: str) -> Path:
    """A TurbSim input for the IEA 15 MW (hub 150 m) from the shared ff14 one (same sections and formats)."""
    text = template.read_text()
    for key, value in (("RandSeed1", str(seed)), ("NumGrid_Z", "25"), ("NumGrid_Y", "25"), ("HubHt", "150"),
                       ("GridHeight", "280"), ("GridWidth", "280"), ("RefHt", "150"), ("URef", f"{wind:g}"),
                       ("PLExp", "0.14"), ("AnalysisTime", f"{seconds:g}"), ("UsableTime", f"{seconds:g}"),
                       ("IECturbc", f'"{iec}"'), ("WrADHH", "False")):
        text, n = re.subn(rf"^\s*\S+(\s+{key}\b)", lambda m, v=value: f"{v:>12}{m.group(1)}", text, count=1,
                          flags=re.M)
        if n != 1:
            sys.exit(f"{template}: key {key} not found")
    out.write_text(text)
    return out


def prepare(work: Path, args) -> Path:
    """The modified deck in ``work`` (shared turbine and platform files linked); its .fst."""
    if not (FLOATING / "cases" / "fl_steady_13").is_dir():
        sys.exit(f"needs the shared floating decks ({FLOATING})")
    work.mkdir(parents=True, exist_ok=True)
    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi"):
        if not (work / name).exists():
            (work / name).symlink_to(FLOATING / name)
    bts = work / f"ff{args.wind:g}_s{args.seed}.bts"
    if not bts.is_file():
        inp = turbsim_input(SHARED / "openfast" / "aero" / "wind" / "ff14.inp", bts.with_suffix(".inp"),
                            wind=args.wind, seed=args.seed, seconds=args.seconds, iec=args.iec)
        c0 = time.time()
        run = subprocess.run([str(TOOLS / "turbsim"), inp.name], cwd=work, capture_output=True, text=True)
        if run.returncode != 0 or not bts.is_file():
            sys.exit(f"TurbSim failed: {run.stdout[-1500:]}{run.stderr[-500:]}")
        print(f"TurbSim: {bts.name} in {time.time() - c0:.0f} s")
    cases = {}
    for tag in ("rosco", "nmpc"):
        case = work / "cases" / tag
        if case.exists():
            shutil.rmtree(case)
        shutil.copytree(FLOATING / "cases" / "fl_steady_13", case)
        fst = case / "fl_steady_13.fst"
        for key, value in (("TMax", f"{args.seconds:g}"), ("OutFileFmt", "1"), ("OutFmt", '"ES15.7E2"')):
            _set(fst, key, value)
        ifw = case / "fl_steady_13_IfW.dat"
        _set(ifw, "WindType", "3")
        _set(ifw, "FileName_BTS", f'"{bts}"')
        sea = case / "fl_steady_13_SeaState.dat"
        for key, value in (("WaveMod", "2"), ("WaveHs", f"{args.hs:g}"), ("WaveTp", f"{args.tp:g}"),
                           ("WaveTMax", f"{max(850.0, args.seconds + 100.0):g}")):
            _set(sea, key, value)
        cases[tag] = fst
    _set(cases["rosco"].parent / "fl_steady_13_SrvD.dat", "DLL_FileName", f'"{args.rosco_lib}"')
    return cases


def export(fst: Path, out: Path) -> tuple[dict, float]:
    c0 = time.time()
    run = subprocess.run([sys.executable, "-m", "mbsym", "export-discon", str(fst), "--controller", "nmpc", "--out",
                          str(out)], capture_output=True, text=True, cwd=HERE.parent)
    if run.returncode != 0:
        sys.exit(f"export failed: {run.stderr[-2000:]}")
    for line in run.stdout.splitlines()[:-1]:
        print(f"  {line}")
    return json.loads(run.stdout.strip().splitlines()[-1]), time.time() - c0


def measures(c: dict[str, np.ndarray], seconds: float) -> dict[str, float]:
    """The judged quantities of one run over ``T_START <= t <= seconds``, resampled to 20 Hz."""
    from mbsym.sweep.stats import damage_equivalent_load

    grid = np.arange(T_START, seconds + 1e-9, 0.05)
    g = {n: np.interp(grid, c["Time"], c[n]) for n in ("TwrBsMyt", "TwrBsMxt", "RootMyc1", "RotSpeed", "BldPitch1",
                                                     "GenPwr", "PtfmPitch", "PtfmSurge", "FAIRTEN1") if n in c}
    dur = grid[-1] - grid[0]
    root = {"DEL RootMyc1": damage_equivalent_load(g["RootMyc1"], dur, 10)} if "RootMyc1" in g else {}
    return {"platform pitch std": float(np.std(g["PtfmPitch"])), "platform surge std": float(np.std(g["PtfmSurge"])),
            "DEL TwrBsMyt": damage_equivalent_load(g["TwrBsMyt"], dur, 4),
            "DEL TwrBsMxt": damage_equivalent_load(g["TwrBsMxt"], dur, 4), **root,
            "speed RMS error": float(np.sqrt(np.mean((g["RotSpeed"] - RATED_RPM) ** 2))),
            "pitch-rate RMS": float(np.sqrt(np.mean(np.gradient(g["BldPitch1"], grid) ** 2))),
            "energy": float(np.trapezoid(g["GenPwr"], grid) / 3.6e6),
            "max GenPwr": float(np.max(g["GenPwr"]) / 1e3), "max RotSpeed": float(np.max(g["RotSpeed"])),
            "fairlead 1 tension std": float(np.std(g["FAIRTEN1"]) / 1e3)}


UNITS = {"platform pitch std": "deg", "platform surge std": "m", "DEL TwrBsMyt": "kN m", "DEL TwrBsMxt": "kN m",
         "DEL RootMyc1": "kN m", "speed RMS error": "rpm", "pitch-rate RMS": "deg/s", "energy": "MWh",
         "max GenPwr": "MW", "max RotSpeed": "rpm", "fairlead 1 tension std": "kN"}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--wind", type=float, default=13.0)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--iec", default="B", help='TurbSim IECturbc ("A", "B", "C" or a TI in percent)')
    p.add_argument("--hs", type=float, default=4.0)
    p.add_argument("--tp", type=float, default=10.0)
    p.add_argument("--seconds", type=float, default=660.0)
    p.add_argument("--work", default="/tmp/mbsym_floating_nmpc_openfast")
    p.add_argument("--rosco-lib", default=str(ROSCO_LIB))
    p.add_argument("--plot", help="figure path (.png)")
    p.add_argument("--reuse", action="store_true", help="report the runs already in --work (no export, no OpenFAST)")
    p.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", dest="settings",
                   help="run-time settings written into the library's input file before the run")
    args = p.parse_args()
    if args.reuse:
        return report(Path(args.work), args, {"rosco": None, "nmpc": None}, None, None)
    if not Path(args.rosco_lib).is_file():
        sys.exit(f"no ROSCO library at {args.rosco_lib} (pip download --no-deps rosco==2.10.6, unzip rosco/ and "
                 "rosco.libs/)")
    work = Path(args.work)
    cases = prepare(work, args)
    lib, export_wall = export(cases["nmpc"], work / "lib")
    if args.settings:
        from nmpc_openfast import _edited

        lib["input"] = _edited(lib["input"], dict(a.split("=", 1) for a in args.settings))
    srv = cases["nmpc"].parent / "fl_steady_13_SrvD.dat"
    _set(srv, "DLL_FileName", f'"{lib["library"]}"')
    _set(srv, "DLL_InFile", f'"{lib["input"]}"')
    c0 = time.time()
    procs = {tag: subprocess.Popen([str(TOOLS / "openfast"), fst.name], cwd=fst.parent, stdout=subprocess.PIPE,
                                   stderr=subprocess.STDOUT, text=True) for tag, fst in cases.items()}
    logs = {tag: proc.communicate()[0] for tag, proc in procs.items()}
    walls = time.time() - c0
    for tag, log in logs.items():
        if "terminated normally" not in log:
            sys.exit(f"OpenFAST ({tag}) failed: {log[-2000:]}")
    for tag, log in logs.items():
        (work / "cases" / tag / "log.txt").write_text(log)
    report(work, args, logs, export_wall, walls)


def report(work: Path, args, logs: dict, export_wall: float | None, walls: float | None) -> None:
    """Measures of both runs in ``work``, the table (and the figure with ``--plot``)."""
    saved = {tag: work / "cases" / tag / "log.txt" for tag in logs}
    logs = {tag: log if log is not None else saved[tag].read_text() if saved[tag].is_file() else ""
            for tag, log in logs.items()}
    holds = logs["nmpc"].count("previous plan's next rates applied")
    fallbacks = logs["nmpc"].count("baseline commands applied")
    data = {tag: _read_out(work / "cases" / tag / "fl_steady_13.out") for tag in ("rosco", "nmpc")}
    table = {tag: measures(c, args.seconds) for tag, c in data.items()}
    wall = "" if walls is None else f"; export {export_wall:.0f} s, both OpenFAST runs {walls:.0f} s (side by side)"
    print(f"{args.wind:g} m/s TurbSim seed {args.seed} (IEC {args.iec}), JONSWAP Hs {args.hs:g} m Tp {args.tp:g} s, "
          f"{T_START:g}-{args.seconds:g} s{wall}; NMPC holds {holds}, fallbacks {fallbacks}")
    print("| measure | OpenFAST + ROSCO | OpenFAST + exported NMPC | NMPC / ROSCO |")
    print("|---|---|---|---|")
    for key in table["rosco"]:
        r, n = table["rosco"][key], table["nmpc"][key]
        print(f"| {key} [{UNITS[key]}] | {r:.4g} | {n:.4g} | {n / r:.3f} |")
    (work / "table.json").write_text(json.dumps({"args": vars(args), "table": table, "holds": holds,
                                                 "fallbacks": fallbacks}, indent=1))
    if args.plot:
        _figure(Path(args.plot), data, args)


def _figure(path: Path, data, args) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(6, 1, figsize=(10, 12), sharex=True)
    for ax, (ch, unit) in zip(axes, (("Wind1VelX", "m/s"), ("RotSpeed", "rpm"), ("BldPitch1", "deg"),
                                     ("GenPwr", "kW"), ("PtfmPitch", "deg"), ("TwrBsMyt", "kN m"))):
        for tag, color in (("rosco", "k"), ("nmpc", "tab:red")):
            label = "ROSCO 2.10.6" if tag == "rosco" else "exported NMPC + EKF"
            ax.plot(data[tag]["Time"], data[tag][ch], color=color, lw=0.7, label=label)
        ax.set_ylabel(f"{ch} [{unit}]")
    axes[0].legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("time [s]")
    axes[-1].set_xlim(T_START, args.seconds)
    fig.suptitle(f"IEA 15 MW VolturnUS-S inside OpenFAST v5: TurbSim {args.wind:g} m/s seed {args.seed}, JONSWAP "
                 f"Hs {args.hs:g} m Tp {args.tp:g} s", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
