"""The `rosco` 2.10.6 wheel's own OpenFAST decks, as shipped, in mbsym and in OpenFAST: accuracy and speed.

Each deck is copied and changed only where it cannot run as shipped (ServoDyn's placeholder ``DLL_FileName`` = the
wheel's ``libdiscon.so``; BAR_10 ``CompElast`` 2 → 1, ElastoDyn blades instead of BeamDyn, and ROSCO's
``Flp_Mode`` 2 → 0: with ServoDyn's ``AfCmode`` 0 the library's flap control stops with a segmentation fault in
OpenFAST as in mbsym) and where the run is set up (``TMax``, text output ``ES15.7E2``). OpenFAST (the baseline,
the same run) and ``mbsym simulate DECK`` with the deck's defaults (the IEA 15 MW monopile's HydroDyn and SeaState
files brought to OpenFAST v5's format, which both tools need) run one after the other; the table gives per
channel the means over ``[T0, TMax]`` (mbsym's relative to OpenFAST's) and ε = mean|y − y_OF| / range(y_OF), and
per deck the wall times: OpenFAST's whole run, mbsym's whole run (with compilation unless cached on disk) and its
integration.

Usage::

    python benchmarks/stock_decks.py --wheel DIR [--openfast BIN] [--tmax 60] [--t0 10] [--work /tmp/stock_decks]
        [--cases NREL_2p8_127 BAR_10 UMaineSemi NREL-5MW] [--readme]

``DIR`` holds the unzipped wheel (``Examples/Test_Cases`` and ``rosco/lib/libdiscon.so`` with ``rosco.libs``:
``pip download --no-deps rosco==2.10.6`` and unzip it).
"""

from __future__ import annotations

import argparse
import json
import math
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _report import write_section  # noqa: E402

CASES = {
    "NREL_2p8_127": ("NREL_2p8_127", "NREL-2p8-127.fst", {}, ("RotSpeed", "GenPwr", "RootMyc1", "RootMxc1")),
    "BAR_10": ("BAR_10", "BAR_10.fst", {"CompElast": "1"}, ("RotSpeed", "GenPwr", "BldPitch1", "RootMyc1",
                                                              "RootMxc1", "TwrBsMyt")),
    "UMaineSemi": ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi/IEA-15-240-RWT-UMaineSemi.fst", {},
                   ("PtfmSurge", "PtfmHeave", "PtfmPitch", "RotSpeed", "BldPitch1", "GenPwr", "TwrBsMyt")),
    "NREL-5MW": ("NREL-5MW", "NREL-5MW.fst", {}, ("RotSpeed", "GenPwr", "RootMyc1", "RootMxb1", "TTDspFA",
                                                  "TwrBsMyt", "YawBrMyp")),
    # the IEA 15 MW monopile on SubDyn with HydroDyn's member in its JONSWAP sea (the wheel's HydroDyn and SeaState
    # files brought to OpenFAST v5's format: both OpenFAST and mbsym stop on them as shipped)
    "Monopile": ("IEA-15-240-RWT", "IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst", {},
                 ("PtfmSurge", "PtfmPitch", "RotSpeed", "BldPitch1", "GenPwr", "TwrBsMyt", "ReactMYss")),
}
#: Cases whose HydroDyn and SeaState files predate OpenFAST v5 (``upgrade_to_v5``).
V5_UPGRADE = ("Monopile",)


def _set(path: Path, key: str, value: str) -> None:
    text, n = re.subn(rf"^(\s*)\S+(\s+{re.escape(key)}\b)", rf"\g<1>{value}\2", path.read_text(encoding="latin-1"),
                      count=1, flags=re.M)
    if n != 1:
        raise SystemExit(f"{path}: no key {key}")
    path.write_text(text, encoding="latin-1")


def prepare(wheel: Path, work: Path, name: str, tmax: float) -> Path:
    """A copy of the case with the edits of the module docstring; its ``.fst``."""
    folder, fst_name, edits, _ = CASES[name]
    dst = work / name
    if dst.exists():
        shutil.rmtree(dst)
    shutil.copytree(wheel / "Examples" / "Test_Cases" / folder, dst)
    fst = dst / fst_name
    lib = (wheel / "rosco" / "lib" / "libdiscon.so").resolve()
    for servo in fst.parent.glob("*ServoDyn*.dat"):
        text = servo.read_text(encoding="latin-1")
        servo.write_text(re.sub(r'^\s*"[^"]*"(\s+DLL_FileName)', f'"{lib}"\\1', text, count=1, flags=re.M),
                         encoding="latin-1")
    for key, value in {"TMax": f"{tmax:g}", "OutFileFmt": "1", "OutFmt": '"ES15.7E2"', **edits}.items():
        _set(fst, key, value)
    if name in V5_UPGRADE:
        sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests" / "data" / "openfast_subdyn_water"))
        import make_reference

        make_reference.upgrade_to_v5(fst.parent)
    for discon in fst.parent.glob("*DISCON.IN"):         # ROSCO's flap control crashes the library in both tools
        text = discon.read_text(encoding="latin-1")     # when ServoDyn passes no flap (AfCmode 0): BAR_10's
        discon.write_text(re.sub(r"^(\s*)\S+(\s+!\s*Flp_Mode\b)", r"\g<1>0\2", text, count=1, flags=re.M),
                          encoding="latin-1")
    return fst


def read_out(path: Path) -> tuple[list[str], np.ndarray]:
    lines = path.read_text().splitlines()
    i = next(k for k, line in enumerate(lines) if line.split()[:1] == ["Time"])
    return lines[i].split(), np.array([[float(x) for x in line.split()] for line in lines[i + 2:] if line.strip()])


def run(fst: Path, openfast: str) -> dict:
    t = time.perf_counter()
    subprocess.run([openfast, fst.name], cwd=fst.parent, check=True, capture_output=True)
    of_wall = time.perf_counter() - t
    out = fst.with_name("mbsym.csv")
    t = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "mbsym", "simulate", fst.name, "--out", out.name, "--stats"],
                          cwd=fst.parent, check=True, capture_output=True, text=True)
    mb_wall = time.perf_counter() - t
    stats = json.loads(proc.stdout.strip().splitlines()[-1])
    return {"of_wall": of_wall, "mb_wall": mb_wall, "integration": stats["integration_wall_s"], "csv": out,
            "out": fst.with_suffix(".out")}


def compare(result: dict, channels, t0: float) -> list[tuple[str, float, float, float]]:
    names, ref = read_out(result["out"])
    head = result["csv"].read_text().splitlines()[0].split(",")
    ours = np.loadtxt(result["csv"], delimiter=",", skiprows=1)
    cols = [h.split("_[")[0] for h in head]
    t = ref[:, 0]
    m = t >= t0
    rows = []
    for ch in channels:
        sign = -1.0 if ch not in names and f"-{ch}" in names else 1.0     # SubDyn's "-React*" (negated) channels
        y = sign * ref[m, names.index(ch if sign > 0 else f"-{ch}")]
        yo = np.interp(t[m], ours[:, cols.index("Time")], ours[:, cols.index(ch)])
        rel = float(yo.mean() / y.mean() - 1) if y.mean() != 0 else math.nan
        eps = float(np.mean(np.abs(yo - y)) / np.ptp(y)) if np.ptp(y) > 0 else math.nan
        rows.append((ch, float(y.mean()), rel, eps))
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--wheel", required=True, type=Path)
    p.add_argument("--openfast", default=str(Path(__file__).resolve().parents[2] / "shared" / "tools" / "openfast"
                                             / "openfast"))
    p.add_argument("--tmax", type=float, default=60.0)
    p.add_argument("--t0", type=float, default=10.0)
    p.add_argument("--work", type=Path, default=Path("/tmp/stock_decks"))
    p.add_argument("--cases", nargs="*", default=list(CASES))
    p.add_argument("--readme", action="store_true", help="rewrite the section of benchmarks/README.md")
    args = p.parse_args()
    args.work.mkdir(parents=True, exist_ok=True)
    lines = ["| deck | channel | OpenFAST mean | mbsym mean | ε | OpenFAST wall | mbsym wall (integration) |",
             "|---|---|---:|---:|---:|---:|---:|"]
    print("\n".join(lines), flush=True)
    for name in args.cases:
        done = len(lines)
        result = run(prepare(args.wheel, args.work, name, args.tmax), args.openfast)
        for k, (ch, mean, rel, eps) in enumerate(compare(result, CASES[name][3], args.t0)):
            walls = (f"{result['of_wall']:.0f} s", f"{result['mb_wall']:.0f} s ({result['integration']:.1f} s)") \
                if k == 0 else ("", "")
            lines.append(f"| {name if k == 0 else ''} | {ch} | {mean:.5g} | {rel:+.2%} | {eps:.2%} | "
                         f"{walls[0]} | {walls[1]} |")
        print("\n".join(lines[done:]), flush=True)
    if args.readme:
        write_section("stock-decks", "\n".join(lines))


if __name__ == "__main__":
    main()
