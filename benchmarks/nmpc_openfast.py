"""The turbine NMPC judged where users judge it: exported as a DISCON library, inside OpenFAST, against ROSCO.

Issue 21 item 5. The NREL 5 MW with flexible blades, drivetrain and tower (``../shared/openfast/aero/ff14_flex``:
OpenFAST v5.0.0, ElastoDyn with FlapDOF1/2, EdgeDOF, DrTrDOF, TwFADOF1/2, TwSSDOF1/2, GenDOF, AeroDyn 15 BEM with
DBEMT, a 14 m/s TurbSim full field with shear, 660 s), its controller replaced by

1. ``mbsym export-discon ff14_flex.fst --controller nmpc --out lib`` (the CLI as a user runs it: the deck's
   DISCON.IN for the fallback baseline and the set-points, its controller sample time, the NMPC without preview
   with its EKF on the deck's rotor-effective model, GenDOF + TwFADOF1 for the NMPC, + TwSSDOF1 + DrTrDOF for the
   EKF), the two paths of its JSON line put into the copied ServoDyn file, nothing else changed;
2. OpenFAST run to the end (text output at 8 digits);

against the deck's own run with the real ROSCO 2.10.6 library in the same OpenFAST build (``ff14_flex.csv``; or,
with ``--bts`` for another TurbSim field, a ROSCO run made here from ``--rosco DIR``: a directory holding the
wheel's ``rosco/`` and ``rosco.libs/``). Measured over t >= 60 s (the first minute is the start's transient):
damage-equivalent loads (rainflow, 1 Hz, Wöhler m = 4 for the tower base TwrBsMyt/TwrBsMxt, 10 for the blade root
RootMyc1), the rotor-speed RMS error about the rated 12.1 rpm (region 3 here), the RMS pitch rate, the energy and
the peaks of power and rotor speed; each as a ratio to ROSCO's, checked against issue 21's targets.

``--mbsym-plant``: the same exported library and our baseline (ROSCO's scheme, equal to ROSCO's library to
1e-6 deg of pitch in OpenFAST, benchmarks/README.md) closed on mbsym's blade-element plant of the same deck
(``mbsym simulate ff14_flex.fst --controller discon|baseline``), with the same measures beside OpenFAST's: the
plant gap.

Run: ``python benchmarks/nmpc_openfast.py run [--case ff14_flex] [--seconds 660] [--work DIR] [--mbsym-plant]
[--estimator ekf|mhe] [--preview lidar [--lidar-distance D]] [--tuning FIELD=VALUE ...]
[--set KEY=VALUE ...]``
(``--tuning``: an ``NMPCTuning`` field changed in the tuning the export gives the deck, e.g.
``tower_deflection_scale=0.05`` to compile a term in; ``--set``: a run-time setting of the library's input file
edited before the OpenFAST run, e.g. ``TowerDeflectionScale=0.02``, docs/discon_export.md)
(``plant --work DIR`` adds the mbsym plant runs to a finished ``run``)
(needs ../shared, ``../shared/tools/openfast/openfast`` and a C compiler; 5-8 min wall for 660 s of OpenFAST, the
mbsym plant with the library from Python about 1x real time), then ``report --work DIR`` prints the table again
and draws ``benchmarks/figures/nmpc_openfast_<case>[_<bts stem>][_lidar][_mhe].png``; ``run`` writes ``DIR/metrics.json``.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE.parent), str(HERE)]
from discon_export_openfast import _read_csv, _read_out  # noqa: E402  (the benchmarks' OpenFAST readers)
from discon_export_openfast import _set_value as _set  # noqa: E402
SHARED = HERE.parent.parent / "shared"
SERVODYN = "NRELOffshrBsline5MW_Onshore_ServoDyn.dat"
#: Issue 21's targets without preview: measure -> (ratio bound, "le" or "ge").
TARGETS = {"DEL TwrBsMyt": (0.90, "le"), "speed RMS error": (1.0, "le"), "energy": (0.995, "ge"),
           "pitch-rate RMS": (1.25, "le"), "DEL RootMyc1": (1.05, "le")}
#: With the lidar preview: tower FA DEL <= 0.80, the other limits the same.
PREVIEW_TARGETS = {**TARGETS, "DEL TwrBsMyt": (0.80, "le")}
T_START = 60.0
RATED_RPM = 12.1            # the deck's DISCON.IN: PC_RefSpd 122.91 rad/s / GBRatio 97


def measures(c: dict[str, np.ndarray], seconds: float) -> dict[str, float]:
    """The judged quantities of one run over ``T_START <= t <= seconds``, resampled to 20 Hz."""
    from mbsym.sweep.stats import damage_equivalent_load

    grid = np.arange(T_START, seconds + 1e-9, 0.05)
    g = {n: np.interp(grid, c["Time"], c[n]) for n in ("TwrBsMyt", "TwrBsMxt", "RootMyc1", "RotSpeed", "BldPitch1",
                                                     "GenPwr")}
    dur = grid[-1] - grid[0]
    rate = np.gradient(g["BldPitch1"], grid)
    return {"DEL TwrBsMyt": damage_equivalent_load(g["TwrBsMyt"], dur, 4),
            "DEL TwrBsMxt": damage_equivalent_load(g["TwrBsMxt"], dur, 4),
            "DEL RootMyc1": damage_equivalent_load(g["RootMyc1"], dur, 10),
            "speed RMS error": float(np.sqrt(np.mean((g["RotSpeed"] - RATED_RPM) ** 2))),
            "pitch-rate RMS": float(np.sqrt(np.mean(rate ** 2))),
            "energy": float(np.trapezoid(g["GenPwr"], grid) / 3600.0),
            "max GenPwr": float(np.max(g["GenPwr"])), "max RotSpeed": float(np.max(g["RotSpeed"]))}


UNITS = {"DEL TwrBsMyt": "kN m", "DEL TwrBsMxt": "kN m", "DEL RootMyc1": "kN m", "speed RMS error": "rpm",
         "pitch-rate RMS": "deg/s", "energy": "kWh", "max GenPwr": "kW", "max RotSpeed": "rpm"}


def _copy_case(work: Path, case: str) -> Path:
    aero = SHARED / "openfast" / "aero"
    for name in ("deck", case):
        dst = work / "openfast_inputs" / name
        if dst.exists():
            shutil.rmtree(dst)
        shutil.copytree(aero / "openfast_inputs" / name, dst)
        for p in dst.rglob("*"):
            p.chmod(0o644 if p.is_file() else 0o755)
    if not (work / "wind").exists():
        (work / "wind").symlink_to(aero / "wind")
    return work / "openfast_inputs" / case / f"{case}.fst"


def _openfast(fst: Path, seconds: float, library: str | None, infile: str | None,
              bts: str | None) -> tuple[Path, float]:
    """Run the copied deck (its ServoDyn's library replaced when ``library`` is given)."""
    if library is not None:
        _set(fst.parent.parent / "deck" / SERVODYN, "DLL_FileName", f'"{library}"')
        _set(fst.parent.parent / "deck" / SERVODYN, "DLL_InFile", f'"{infile}"')
    _set(fst, "OutFileFmt", "1")
    _set(fst, "OutFmt", '"ES15.7E2"')
    _set(fst, "TMax", f"{seconds:g}")
    if bts:
        _set(fst.parent / f"{fst.stem}_IfW.dat", "FileName_BTS", f'"{Path(bts).resolve()}"')
    c0 = time.perf_counter()
    run = subprocess.run([str(SHARED / "tools" / "openfast" / "openfast"), fst.name], capture_output=True, text=True,
                         cwd=fst.parent)
    wall = time.perf_counter() - c0
    if run.returncode != 0 or "terminated normally" not in run.stdout:
        sys.exit(f"OpenFAST failed after {wall:.0f} s:\n{run.stdout[-3000:]}\n{run.stderr[-2000:]}")
    return fst.with_suffix(".out"), wall


def _mbsym_run(fst: Path, seconds: float, out: Path, args: list[str]) -> float:
    c0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "mbsym", "simulate", str(fst), "--tmax", f"{seconds:g}", "--out",
                           str(out), *args], capture_output=True, text=True, cwd=HERE.parent)
    if proc.returncode != 0:
        sys.exit(f"mbsym simulate {' '.join(args)} failed: {proc.stderr[-2000:]}")
    return time.perf_counter() - c0


#: The nacelle lidar of ``--preview lidar``: InflowWind single-point beams 60 m upstream of the hub, at the hub
#: and at 0.7 R (44 m) left, right, up and down, a measurement every 0.1 s (the NMPC's sample).
LIDAR_KEYS = {"SensorType": "1", "NumBeam": "5", "FocalDistanceX": "-60 -60 -60 -60 -60",
              "FocalDistanceY": "0 44 -44 0 0", "FocalDistanceZ": "0 0 0 44 -44", "MeasurementInterval": "0.1",
              "ConsiderHubMotion": "0"}


def _add_lidar(fst: Path, distance: float | None = None) -> None:
    """Write LIDAR_KEYS into the deck's InflowWind file; ``distance`` [m] moves every focal point that far
    upstream of the hub instead."""
    ifw = fst.parent / f"{fst.stem}_IfW.dat"
    keys = dict(LIDAR_KEYS)
    if distance is not None:
        keys["FocalDistanceX"] = " ".join([f"{-distance:g}"] * 5)
    for key, value in keys.items():
        _set(ifw, key, value)


def _export(fst: Path, out: Path, estimator: str, tuning: dict) -> dict:
    """``mbsym export-discon FST --controller nmpc --estimator E --out OUT`` (in this process, the deck's tuning with
    ``tuning``'s fields changed: ``NMPCTuning`` fields by name, ``EstimatorTuning`` fields as ``ekf.<name>``); its
    JSON line."""
    import contextlib
    import dataclasses
    import io

    import mbsym.cli.controller_model as cm
    import mbsym.cli.export_discon as ex
    from mbsym.cli import main as cli

    deck_tuning, deck_estimator = cm.nmpc_tuning, cm.estimator_tuning
    nmpc_changes = {k: v for k, v in tuning.items() if not k.startswith("ekf.")}
    ekf_changes = {k[4:]: bool(v) if k == "ekf.blade_passing" else v for k, v in tuning.items() if k.startswith("ekf.")}

    def changed(prediction, **options):
        return deck_tuning(prediction, **options).replace(**nmpc_changes)

    def changed_estimator(observed, **options):
        return dataclasses.replace(deck_estimator(observed, **options), **ekf_changes)

    buf = io.StringIO()
    cm.nmpc_tuning = ex.nmpc_tuning = changed
    cm.estimator_tuning = ex.estimator_tuning = changed_estimator
    try:
        with contextlib.redirect_stdout(buf):
            code = cli(["export-discon", str(fst), "--controller", "nmpc", "--estimator", estimator, "--out", str(out)])
    finally:
        cm.nmpc_tuning = ex.nmpc_tuning = deck_tuning
        cm.estimator_tuning = ex.estimator_tuning = deck_estimator
    if code != 0:
        sys.exit(f"mbsym export-discon failed (exit {code})")
    return json.loads(buf.getvalue().strip().splitlines()[-1])


def _edited(infile: str, settings: dict) -> str:
    """A copy of the library's input file with the run-time ``settings`` (key -> value) written in."""
    path = Path(infile).with_suffix(".set.IN")
    lines, done = [], set()
    for line in Path(infile).read_text().splitlines(True):
        parts = line.split()
        if len(parts) > 1 and parts[1] in settings:
            line, _ = f"{settings[parts[1]]:<24} {parts[1]} ! set by nmpc_openfast.py --set\n", done.add(parts[1])
        lines.append(line)
    missing = set(settings) - done
    if missing:
        sys.exit(f"--set {sorted(missing)}: not keys of {infile}")
    path.write_text("".join(lines))
    return str(path)


def run(case: str, seconds: float, work: Path, bts: str | None, rosco: str | None, mbsym_plant: bool,
        rosco_out: str | None = None, preview: str = "none", estimator: str = "ekf", tuning: dict | None = None,
        settings: dict | None = None, lidar_distance: float | None = None) -> None:
    if not (SHARED / "tools" / "openfast" / "openfast").is_file():
        sys.exit(f"needs {SHARED / 'tools' / 'openfast' / 'openfast'}")
    work.mkdir(parents=True, exist_ok=True)
    fst = _copy_case(work / "nmpc", case)
    if preview == "lidar":
        _add_lidar(fst, lidar_distance)
    c0 = time.perf_counter()
    if tuning:
        lib = _export(fst, work / "lib", estimator, tuning)
    else:
        proc = subprocess.run([sys.executable, "-m", "mbsym", "export-discon", str(fst), "--controller", "nmpc",
                               "--estimator", estimator, "--out", str(work / "lib")], capture_output=True, text=True,
                              cwd=HERE.parent)
        if proc.returncode != 0:
            sys.exit(f"mbsym export-discon failed: {proc.stderr.strip()}")
        lib = json.loads(proc.stdout.strip().splitlines()[-1])
    export_wall = time.perf_counter() - c0
    if settings:
        lib["input"] = _edited(lib["input"], settings)
    out, wall = _openfast(fst, seconds, lib["library"], lib["input"], bts)
    runs = {"OpenFAST + NMPC": {"file": str(out), "wall_s": wall}}
    ref_csv = SHARED / "openfast" / "aero" / f"{case}.csv"
    if rosco_out is not None:                     # a ROSCO run of the same deck and wind made before
        runs["OpenFAST + ROSCO"] = {"file": str(Path(rosco_out).resolve()), "wall_s": None}
    elif bts or not ref_csv.is_file():
        if rosco is None:
            sys.exit("a ROSCO reference for this wind needs --rosco DIR (the wheel's rosco/ and rosco.libs/)")
        rfst = _copy_case(work / "rosco", case)
        for sub in ("rosco", "rosco.libs"):
            if not (work / "rosco" / "openfast_inputs" / sub).exists():
                (work / "rosco" / "openfast_inputs" / sub).symlink_to(Path(rosco).resolve() / sub)
        ref_out, ref_wall = _openfast(rfst, seconds, None, None, bts)      # the deck's own ROSCO library
        runs["OpenFAST + ROSCO"] = {"file": str(ref_out), "wall_s": ref_wall}
    else:
        runs["OpenFAST + ROSCO"] = {"file": str(ref_csv), "wall_s": None}
    meta = {"case": case, "seconds": seconds, "bts": bts, "export_wall_s": export_wall, "runs": runs,
            "library": lib, "fst": str(fst), "preview": preview, "estimator": estimator, "tuning": tuning or {},
            "settings": settings or {}, "lidar_distance": lidar_distance}
    (work / "metrics.json").write_text(json.dumps(meta, indent=1))
    if mbsym_plant:
        plant(work)
    else:
        report(work)


def plant(work: Path) -> None:
    """The exported library and our baseline closed on mbsym's blade-element plant of the run's deck (the copy
    whose ServoDyn names the library: ``mbsym simulate`` reads the settings its input file records)."""
    meta = json.loads((work / "metrics.json").read_text())
    fst, lib, seconds = Path(meta["fst"]), meta["library"], meta["seconds"]
    mb = work / "mbsym"
    mb.mkdir(exist_ok=True)
    w1 = _mbsym_run(fst, seconds, mb / "nmpc.csv", ["--controller", "discon", "--discon", lib["library"],
                                                    "--discon-input", lib["input"]])
    meta["runs"]["mbsym blade plant + NMPC"] = {"file": str(mb / "nmpc.csv"), "wall_s": w1}
    w2 = _mbsym_run(fst, seconds, mb / "baseline.csv", ["--controller", "baseline"])
    meta["runs"]["mbsym blade plant + baseline"] = {"file": str(mb / "baseline.csv"), "wall_s": w2}
    (work / "metrics.json").write_text(json.dumps(meta, indent=1))
    report(work)


def _load(path: str) -> dict[str, np.ndarray]:
    p = Path(path)
    return _read_out(p) if p.suffix == ".out" else _read_csv(p)


def report(work: Path) -> None:
    meta = json.loads((work / "metrics.json").read_text())
    seconds = meta["seconds"]
    data = {name: _load(r["file"]) for name, r in meta["runs"].items()}
    table = {name: measures(c, seconds) for name, c in data.items()}
    ref = table["OpenFAST + ROSCO"]
    targets = PREVIEW_TARGETS if meta.get("preview") == "lidar" else TARGETS
    walls = ", ".join(f"{name} {r['wall_s']:.0f} s" for name, r in meta["runs"].items() if r["wall_s"] is not None)
    print(f"{meta['case']}{' (' + meta['bts'] + ')' if meta['bts'] else ''}, {T_START:g}-{seconds:g} s; wall: "
          f"export {meta['export_wall_s']:.0f} s, {walls}")
    names = list(table)
    print(f"| measure | {' | '.join(names)} | NMPC / ROSCO in OpenFAST | target |")
    print("|---" * (len(names) + 3) + "|")
    verdict = {}
    for key in ref:
        ratio = table["OpenFAST + NMPC"][key] / ref[key]
        bound = targets.get(key)
        ok = None if bound is None else (ratio <= bound[0] if bound[1] == "le" else ratio >= bound[0])
        verdict[key] = ok
        target = "" if bound is None else f"{'≤' if bound[1] == 'le' else '≥'} {bound[0]:g} {'✓' if ok else '✗'}"
        cells = " | ".join(f"{table[n][key]:.4g}" for n in names)
        print(f"| {key} [{UNITS[key]}] | {cells} | {ratio:.3f} | {target} |")
    if "mbsym blade plant + NMPC" in table:
        print("plant gap (mbsym blade plant / OpenFAST), NMPC: " + ", ".join(
            f"{k} {table['mbsym blade plant + NMPC'][k] / table['OpenFAST + NMPC'][k]:.3f}" for k in ref))
        print("plant gap (mbsym blade plant baseline / OpenFAST ROSCO): " + ", ".join(
            f"{k} {table['mbsym blade plant + baseline'][k] / ref[k]:.3f}" for k in ref))
    (work / "table.json").write_text(json.dumps({"table": table, "targets_met": verdict}, indent=1))
    estimator = meta.get("estimator", "ekf")
    tag = meta["case"] + (f"_{Path(meta['bts']).stem}" if meta["bts"] else "") + \
        ("_lidar" if meta.get("preview") == "lidar" else "") + ("_mhe" if estimator == "mhe" else "") + \
        ("_tuned" if meta.get("tuning") or meta.get("settings") else "")
    _figure(tag, data, table, seconds, estimator.upper())


def _figure(case: str, data, table, seconds: float, estimator: str = "EKF") -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(5, 1, figsize=(10, 11), sharex=True)
    styles = {"OpenFAST + ROSCO": ("k", "-"), "OpenFAST + NMPC": ("tab:red", "-"),
              "mbsym blade plant + NMPC": ("tab:orange", "--"), "mbsym blade plant + baseline": ("tab:blue", "--")}
    for ax, (ch, unit) in zip(axes, (("Wind1VelX", "m/s"), ("RotSpeed", "rpm"), ("BldPitch1", "deg"),
                                     ("GenPwr", "kW"), ("TwrBsMyt", "kN m"))):
        for name, c in data.items():
            if ch in c:
                color, ls = styles.get(name, ("gray", ":"))
                ax.plot(c["Time"], c[ch], color=color, ls=ls, lw=0.7, label=name)
        ax.set_ylabel(f"{ch} [{unit}]")
        ax.set_xlim(T_START, min(seconds, T_START + 180.0))
    axes[0].legend(loc="upper right", fontsize=7, ncol=2)
    axes[-1].set_xlabel("time [s]")
    r = table["OpenFAST + NMPC"]
    ref = table["OpenFAST + ROSCO"]
    fig.suptitle(f"{case}: exported NMPC + {estimator}{' + lidar preview' if '_lidar' in case else ''} vs ROSCO 2.10.6 inside OpenFAST v5\n(NMPC/ROSCO: tower FA DEL "
                 f"{r['DEL TwrBsMyt'] / ref['DEL TwrBsMyt']:.2f}, speed RMS {r['speed RMS error'] / ref['speed RMS error']:.2f}, "
                 f"pitch rate {r['pitch-rate RMS'] / ref['pitch-rate RMS']:.2f}, energy {r['energy'] / ref['energy']:.3f})",
                 fontsize=9)
    fig.tight_layout()
    path = HERE / "figures" / f"nmpc_openfast_{case}.png"
    fig.savefig(path, dpi=110)
    print(f"wrote {path}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="what", required=True)
    p = sub.add_parser("run")
    p.add_argument("--case", default="ff14_flex")
    p.add_argument("--seconds", type=float, default=660.0)
    p.add_argument("--work", default="/tmp/mbsym_nmpc_openfast")
    p.add_argument("--bts", help="another TurbSim full field (.bts) for both runs")
    p.add_argument("--rosco", help="directory with the rosco wheel's rosco/ and rosco.libs/ (for --bts)")
    p.add_argument("--mbsym-plant", action="store_true", help="also close both controllers on mbsym's plant")
    p.add_argument("--rosco-out", help="an earlier ROSCO run (.out) of the same deck and wind, instead of a new one")
    p.add_argument("--preview", choices=("none", "lidar"), default="none",
                   help="lidar: add a 5-beam lidar 60 m upstream to the deck (LIDAR_KEYS); the export previews from it")
    p.add_argument("--lidar-distance", type=float, help="with --preview lidar: the focal points this far upstream [m]")
    p.add_argument("--estimator", choices=("ekf", "mhe"), default="ekf", help="the exported NMPC's estimator")
    p.add_argument("--tuning", nargs="*", default=[], metavar="FIELD=VALUE",
                   help="NMPCTuning fields (and EstimatorTuning fields as ekf.<name>) changed in the deck's tunings at "
                        "export (floats; horizon an integer)")
    p.add_argument("--set", nargs="*", default=[], metavar="KEY=VALUE", dest="settings",
                   help="run-time settings written into the library's input file before the run")
    for name in ("plant", "report"):
        p = sub.add_parser(name)
        p.add_argument("--work", default="/tmp/mbsym_nmpc_openfast")
    args = parser.parse_args()
    if args.what == "run":
        tuning = {k: int(v) if k == "horizon" else float(v) for k, v in (a.split("=", 1) for a in args.tuning)}
        settings = dict(a.split("=", 1) for a in args.settings)
        run(args.case, args.seconds, Path(args.work), args.bts, args.rosco, args.mbsym_plant, args.rosco_out,
            args.preview, args.estimator, tuning, settings, args.lidar_distance)
    elif args.what == "plant":
        plant(Path(args.work))
    else:
        report(Path(args.work))


if __name__ == "__main__":
    main()
