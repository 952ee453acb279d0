"""Linear models of the floating IEA 15 MW against OpenFAST v5 linearizations of the same deck (issue 20, item 6).

Four steps, each a subcommand::

    python benchmarks/floating_linear.py decks DIR [--wind 5,8,10,12,13,15,18,22]
    python benchmarks/floating_linear.py run DIR [--jobs 2]        # every DIR/cases/oflin_*/ with OpenFAST v5.0.0
    python benchmarks/floating_linear.py modes DIR                 # .lin -> tests/data/openfast_floating_linear/modes.json
    python benchmarks/floating_linear.py compare [--plot F.png] [--readme]

**The set-up** is the one of the linearizations the rosco wheel ships for this turbine (``lin_*.1.lin``, made in
2021: ElastoDyn surge, heave, pitch, tower fore-aft 1 and generator; MAP++; HydroDyn with its state-space radiation)
applied to the shared v5 deck (``shared/openfast/floating``): ``decks`` copies the shared turbine and platform
folders into DIR and writes ``DIR/cases/mbsym/`` — the shared ``fl_steady_13`` case with those DOFs, ``CompMooring
= 1`` (the deck's MAP++ file), HydroDyn ``RdtnMod = 2`` (the deck's ``.ss``, as linearization needs) and
``ExctnMod = 0``, SeaState without second-order kinematics, AeroDyn without tower influence and unsteady airfoil
aerodynamics (what the rotor-effective model has) — and, for every wind speed, ``DIR/cases/oflin_<U>/``: the same
case with steady wind ``U`` at 150 m, linearization on (``CalcSteady``, ``TrimCase = 2`` generator torque,
``TrimGain = 3e4`` N m s/rad, ``TrimTol = 1e-3``, ``NLinTimes = 12``, ``LinOutputs = 0``, ``TMax = 300`` s), AeroDyn
``DBEMT_Mod = -1`` (frozen wake), ServoDyn without the library (``PCMode = 0`` with ``PitNeut`` the trim pitch;
``VSContrl = 1`` with the trim torque constant from 50 % of the trim speed) and the initial conditions of mbsym's
trim at ``U`` (the deck's controller settings: platform offsets, tower-top deflection, rotor speed, pitch).
The platform's slow surge never makes every output periodic to ``TrimTol`` within a revolution, so OpenFAST
linearizes at ``TMax`` (its forced linearization: one azimuth, the rotor speed within 0.1 % of the target); starting
from mbsym's trim, the platform is within 0.1 % of OpenFAST's own equilibrium by then (``modes`` records the
operating point of every case, beside mbsym's). The constant torque must hold over ServoDyn's finite-difference step on the generator speed, 0.1 rad/s
(``ServoDyn.f90``, its ``HSS_Spd`` variable): with region 3 starting at 90 % of the speed, the lower step fell into
region 2 and the Jacobian carried a spurious generator-torque slope (−0.092 1/s on the rotor speed at 8 m/s, as
much as the aerodynamics'). The torque, not the pitch, is trimmed: a pitch trim acts as a fast pitch controller and destabilizes the
platform-pitch mode (the classic floating "negative damping"; tried: 13 m/s drifted to 8.5 deg of platform pitch).

``modes`` averages each case's A over its azimuths (no rotating-frame states: nothing for MBC3 to do), drops the
azimuth and labels each oscillatory eigenvalue by its largest platform or tower coordinate (rates divided by |λ|,
pitch in centiradians against metres). ``compare`` linearizes mbsym's operating turbine of ``DIR/cases/mbsym``
(rebuilt in a temporary folder from the shared deck when no DIR is given) about its trims, frozen inflow, and
prints the platform frequencies and damping beside OpenFAST's and beside the 2021 files'.
"""

from __future__ import annotations

import argparse
import json
import re
import shutil
import subprocess
import sys
import tempfile
import warnings
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from openfast_linear_inflow import _set, read_lin  # noqa: E402

TABLE = HERE.parent / "tests" / "data" / "openfast_floating_linear" / "modes.json"
WINDS = (5.0, 8.0, 10.0, 12.0, 13.0, 15.0, 18.0, 22.0)
LABELS = {"Sg": "platform surge", "Hv": "platform heave", "P": "platform pitch", "TFA1": "1st tower fore-aft"}
#: Weights of the coordinates when labelling a mode: pitch [rad] ~ 100 x the translations [m].
_WEIGHT = {"Sg": 1.0, "Hv": 1.0, "P": 100.0, "TFA1": 1.0}
_DISABLED = ("TwSSDOF1", "PtfmSwDOF", "PtfmRDOF", "PtfmYDOF")
#: Case-name suffixes of the one-key variants (tests/data/openfast_floating_linear/README.md) and what they change.
VARIANTS = {"_nobq": "HydroDyn AddBQuad = 0", "_noaero": "CompAero = 0 (no aerodynamic loads)"}


def _shared() -> Path:
    for root in (HERE.parent.parent / "shared", HERE.parent.parent.parent / "shared"):
        if (root / "openfast" / "floating").is_dir():
            return root / "openfast" / "floating"
    raise SystemExit("shared/openfast/floating not found beside the repository")


def _edit(path: Path, keys: dict[str, str]) -> None:
    text = path.read_text()
    for key, value in keys.items():
        text = _set(text, key, value)
    path.write_text(text)


def mbsym_deck(root: Path) -> Path:
    """``root/cases/mbsym/fl_steady_13.fst``: the shared fl_steady_13 case in the 2021 set-up (module docstring)."""
    src = _shared()
    for folder in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi"):
        if not (root / folder).is_dir():
            shutil.copytree(src / folder, root / folder, ignore=shutil.ignore_patterns("linearizations"))
    semi = root / "IEA-15-240-RWT-UMaineSemi"
    ad = semi / "IEA-15-240-RWT-UMaineSemi_AeroDyn15.dat"
    _edit(ad, {"TwrPotent": "0", "TwrShadow": "0", "TwrAero": "False", "UA_Mod": "0"})
    lin = _set(ad.read_text(), "DBEMT_Mod", "-1")
    (semi / "AeroDyn_lin.dat").write_text(lin)
    case = root / "cases" / "mbsym"
    case.mkdir(parents=True, exist_ok=True)
    for f in (src / "cases" / "fl_steady_13").iterdir():
        shutil.copy(f, case / f.name)
    fst = case / "fl_steady_13.fst"
    fst.write_text(_set(fst.read_text(), "CompMooring", "1").replace(
        "IEA-15-240-RWT-UMaineSemi_MoorDyn.dat", "IEA-15-240-RWT-UMaineSemi_MAP.dat"))
    _edit(case / "fl_steady_13_ED.dat", {k: "False" for k in _DISABLED})
    _edit(case / "fl_steady_13_HydroDyn.dat", {"RdtnMod": "2", "ExctnMod": "0"})
    _edit(case / "fl_steady_13_SeaState.dat", {"WvDiffQTF": "False", "WvSumQTF": "False"})
    return fst


def _trims(fst: Path, winds):
    from mbsym.wind.analysis.operating_points import operating_points, turbine_and_control

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model, control, label = turbine_and_control(str(fst), aero="rotor")
        return operating_points(model, list(winds), control, label=label)


def _zero_quadratic_drag(path: Path) -> None:
    """Set HydroDyn's ``AddBQuad`` (the 6 x 6 table starting on its key's line) to zero."""
    lines = path.read_text().splitlines()
    first = next(k for k, line in enumerate(lines) if "AddBQuad" in line.split())
    for k in range(first, first + 6):
        tail = lines[k].split()[6:]
        lines[k] = "  ".join(["0.0"] * 6) + ("   " + " ".join(tail) if tail else "")
    path.write_text("\n".join(lines) + "\n")


def make_decks(root: Path, winds, *, quadratic_drag: bool = True) -> list[Path]:
    """The mbsym deck and one OpenFAST linearization case per wind speed (module docstring); without
    ``quadratic_drag``, cases ``oflin_<U>_nobq`` with HydroDyn's ``AddBQuad`` zero (see ``lin_modes``' note)."""
    fst = mbsym_deck(root)
    cases = []
    for U, pt in zip(winds, _trims(fst, winds)):
        x, u = pt.x(), pt.u()
        case = root / "cases" / (f"oflin_{U:04.1f}" + ("" if quadratic_drag else "_nobq"))
        shutil.copytree(fst.parent, case, dirs_exist_ok=True)
        if not quadratic_drag:
            _zero_quadratic_drag(case / "fl_steady_13_HydroDyn.dat")
        _edit(case / "fl_steady_13.fst", {
            "TMax": "300", "Linearize": "True", "CalcSteady": "True", "TrimCase": "2", "TrimTol": "0.001",
            "TrimGain": "3e4", "NLinTimes": "12", "LinOutputs": "0", "OutFileFmt": "1", "DT_Out": "0.5",
            "AeroFile": '"../../IEA-15-240-RWT-UMaineSemi/AeroDyn_lin.dat"'})
        _edit(case / "fl_steady_13_IfW.dat", {"WindType": "1", "HWindSpeed": f"{U:.6f}"})
        pitch, rpm, torque = pt["BldPitch1"], pt["RotSpeed"], u["GenTqCom"]
        _edit(case / "fl_steady_13_ED.dat", {
            "RotSpeed": f"{rpm:.6f}", "TTDspFA": f"{pt['TTDspFA']:.6f}", "PtfmSurge": f"{x['Sg']:.6f}",
            "PtfmHeave": f"{x['Hv']:.6f}", "PtfmPitch": f"{np.degrees(x['P']):.6f}",
            **{f"BlPitch({b})": f"{pitch:.6f}" for b in (1, 2, 3)}})
        _edit(case / "fl_steady_13_SrvD.dat", {
            "PCMode": "0", "VSContrl": "1", "VS_RtGnSp": f"{0.5 * rpm:.6f}", "VS_RtTq": f"{torque:.6f}",
            "VS_Rgn2K": f"{0.5 * torque / (0.5 * rpm) ** 2:.6f}", "VS_SlPc": "2.",
            **{f"PitNeut({b})": f"{pitch:.6f}" for b in (1, 2, 3)}})
        cases.append(case)
        print(f"{case}: pitch {pitch:.3f} deg, {rpm:.3f} rpm, torque {torque / 1e6:.3f} MN m", flush=True)
    return cases


def run_cases(root: Path, jobs: int) -> None:
    binary = _shared().parent.parent / "tools" / "openfast" / "openfast"

    def one(case: Path) -> None:
        with open(case / "of.log", "w") as log:
            subprocess.run([str(binary), "fl_steady_13.fst"], cwd=case, stdout=log, stderr=subprocess.STDOUT)
        print(f"{case.name}: {len(list(case.glob('*.lin')))} .lin files", flush=True)

    with ThreadPoolExecutor(jobs) as pool:
        list(pool.map(one, sorted((root / "cases").glob("oflin_*"))))


def _short(description: str) -> str:
    m = re.search(r"DOF_(\w+)\)", description)
    base = m.group(1) if m else description.split(",")[0].strip()
    return base + "_d" if "First time derivative" in description else base


def lin_modes(files) -> dict:
    """Azimuth-averaged platform and tower modes of the ``.lin`` files of one case (module docstring)."""
    lins = [read_lin(f) for f in files]
    names = [_short(s["description"]) for s in lins[0]["states"]]
    keep = [i for i, n in enumerate(names) if n != "GeAz"]
    A = np.mean([lin["A"] for lin in lins], axis=0)[np.ix_(keep, keep)]
    names = [names[i] for i in keep]
    lam, V = np.linalg.eig(A)
    pos = {d: names.index(d) for d in _WEIGHT if d in names}
    rate = {d: names.index(d + "_d") for d in pos}
    best: dict = {}
    for k in np.flatnonzero(lam.imag > 1e-9):
        v = V[:, k]
        w = {d: (abs(v[pos[d]]) + abs(v[rate[d]]) / abs(lam[k])) * _WEIGHT[d] for d in pos}
        rest = np.linalg.norm([abs(v[i]) for i in range(len(v)) if i not in rate.values()])
        if sum(w.values()) == 0.0:             # a radiation-only eigenvector
            continue
        dom = max(w, key=w.get)
        score = w[dom] / sum(w.values()) * min(1.0, w[dom] / rest)
        if dom not in best or score > best[dom]["score"]:
            best[dom] = {"freq_hz": float(abs(lam[k]) / (2 * np.pi)), "damping_ratio": float(-lam[k].real / abs(lam[k])),
                         "score": float(score)}
    op = {n: s["op"] for n, s in zip([_short(s["description"]) for s in lins[0]["states"]], lins[0]["states"])}
    spin = names.index("GeAz_d")
    return {"wind_speed": lins[0]["wind_speed"], "n_azimuths": len(lins),
            "rotor_speed_rpm": float(np.mean([x["rotor_speed"] for x in lins]) * 30 / np.pi),
            "linearization_time_s": float(lins[0]["time"]),
            "rotor_speed_damping_per_s": float(A[spin, spin]),
            "operating_point": {"PtfmSurge_m": op["Sg"], "PtfmHeave_m": op["Hv"], "PtfmPitch_deg": float(np.degrees(op["P"])),
                                "TFA1_m": op["TFA1"]},
            "modes": {LABELS[d]: {k: round(v, 6) for k, v in m.items()} for d, m in best.items()}}


def write_table(root: Path, path: Path = TABLE) -> dict:
    cases = []
    for case in sorted((root / "cases").glob("oflin_*")):
        files = sorted(case.glob("*.lin"), key=lambda p: int(p.suffixes[-2][1:]))
        if files:
            variant = next((v for k, v in VARIANTS.items() if case.name.endswith(k)), "as the deck")
            cases.append({"case": case.name, "variant": variant, **lin_modes(files)})
    table = {"source": "OpenFAST v5.0.0 linearizations of the shared floating IEA 15 MW deck in the 2021 set-up; see "
                       "README.md here and benchmarks/floating_linear.py",
             "units": {"freq_hz": "Hz", "damping_ratio": "-", "rotor_speed_rpm": "rpm"}, "cases": cases}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(table, indent=1) + "\n")
    return table


def shipped_modes() -> dict[float, dict]:
    """The 2021 files' modes by wind speed (their azimuth 1: the only one stored here)."""
    out = {}
    for f in sorted((_shared() / "IEA-15-240-RWT-UMaineSemi" / "linearizations").glob("lin_*.1.lin")):
        m = lin_modes([f])
        out[round(m["wind_speed"], 1)] = m
    return out


def mbsym_modes(fst: Path, winds, inflow: str = "frozen") -> dict[float, dict]:
    """mbsym's linear models about its trims: platform and tower modes by label."""
    from mbsym.cli.linearize_operating import operating_report

    ops = _trims(fst, winds)
    out = {}
    for U, lin, pt in zip(winds, ops.linearize(inflow=inflow), ops):
        modes = {}
        for m in operating_report(lin, pt)["modes"]:
            if m["label"] in LABELS.values() and m["label"] not in modes:
                modes[m["label"]] = {"freq_hz": m["freq_hz"], "damping_ratio": m["damping_ratio"]}
        x = pt.x()
        out[U] = {"modes": modes, "operating_point": {"PtfmSurge_m": x["Sg"], "PtfmHeave_m": x["Hv"],
                                                      "PtfmPitch_deg": float(np.degrees(x["P"]))}}
    return out


def compare(table: dict, fst: Path) -> tuple[str, dict]:
    """The comparison table (markdown) and its numbers: mbsym (frozen inflow, the deck's .ss radiation and
    mbsym's fit of the .1 data) against OpenFAST v5 (same deck) and the 2021 files."""
    of = {round(c["wind_speed"], 1): c for c in table["cases"] if c["variant"] == "as the deck"}
    winds = sorted(of)
    ss = mbsym_modes(fst, winds)
    fit_fst = fst.parent.parent / "mbsym_fit" / fst.name
    shutil.copytree(fst.parent, fit_fst.parent, dirs_exist_ok=True)
    _edit(fit_fst.parent / "fl_steady_13_HydroDyn.dat", {"RdtnMod": "1"})
    fit = mbsym_modes(fit_fst, winds)
    shipped = shipped_modes()
    rows, numbers = [], {}
    head = ("| U [m/s] | mode | OpenFAST v5 f [Hz] | mbsym (.ss) | Δf | mbsym (fit) | Δf | ζ OpenFAST | ζ mbsym (.ss) | "
            "ζ mbsym (fit) | 2021 file f [Hz] | ζ 2021 |")
    rows += [head, "|" + "---|" * 12]
    for U in winds:
        for label in ("platform surge", "platform heave", "platform pitch"):
            o = of[U]["modes"].get(label)
            a, b = ss[U]["modes"].get(label), fit[U]["modes"].get(label)
            s21 = shipped.get(U, {}).get("modes", {}).get(label)
            if o is None or a is None or b is None:
                continue
            da, db = a["freq_hz"] / o["freq_hz"] - 1, b["freq_hz"] / o["freq_hz"] - 1
            numbers.setdefault(label, []).append({"wind_speed": U, "openfast": o, "mbsym_ss": a, "mbsym_fit": b,
                                                  "openfast_2021": s21})
            rows.append(f"| {U:g} | {label} | {o['freq_hz']:.5f} | {a['freq_hz']:.5f} | {100 * da:+.2f} % | "
                        f"{b['freq_hz']:.5f} | {100 * db:+.2f} % | {o['damping_ratio']:.3f} | {a['damping_ratio']:.3f} | "
                        f"{b['damping_ratio']:.3f} | " + (f"{s21['freq_hz']:.5f} | {s21['damping_ratio']:.3f} |" if s21
                                                           else "— | — |"))
    return "\n".join(rows), numbers


def plot(numbers: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 3, figsize=(13, 6.5), sharex=True)
    for col, label in enumerate(("platform surge", "platform heave", "platform pitch")):
        rows = numbers.get(label, [])
        U = [r["wind_speed"] for r in rows]
        for key, style, name in (("openfast", "ko", "OpenFAST v5 (same deck)"), ("mbsym_ss", "C0s-", "mbsym (.ss)"),
                                 ("mbsym_fit", "C1^--", "mbsym (fit of .1)"), ("openfast_2021", "C3x", "2021 files")):
            pts = [(u, r[key]) for u, r in zip(U, rows) if r.get(key)]
            if not pts:
                continue
            axes[0, col].plot([u for u, _ in pts], [m["freq_hz"] for _, m in pts], style, label=name, mfc="none")
            axes[1, col].plot([u for u, _ in pts], [m["damping_ratio"] for _, m in pts], style, label=name, mfc="none")
        axes[0, col].set_title(label)
        axes[1, col].set_xlabel("wind speed [m/s]")
    axes[0, 0].set_ylabel("natural frequency [Hz]")
    axes[1, 0].set_ylabel("damping ratio [-]")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("IEA 15 MW on VolturnUS-S: linear platform modes over wind speed (open loop, frozen wake)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("step", choices=("decks", "run", "modes", "compare"))
    ap.add_argument("dir", nargs="?", type=Path, help="work folder (decks, run, modes; compare: optional)")
    ap.add_argument("--wind", default=",".join(f"{u:g}" for u in WINDS), help="wind speeds [m/s] (decks)")
    ap.add_argument("--jobs", type=int, default=2, help="OpenFAST runs at a time (run)")
    ap.add_argument("--no-quadratic-drag", action="store_true",
                    help="decks: cases oflin_<U>_nobq with HydroDyn's AddBQuad zero (how much of OpenFAST's "
                         "linear damping is its finite-difference step on the quadratic drag)")
    ap.add_argument("--plot", type=Path, default=HERE / "figures" / "floating_linear.png")
    ap.add_argument("--readme", action="store_true", help="write the table into benchmarks/README.md")
    args = ap.parse_args(argv)
    if args.step != "compare" and args.dir is None:
        ap.error(f"{args.step} needs DIR")
    if args.step == "decks":
        make_decks(args.dir, [float(u) for u in args.wind.split(",")], quadratic_drag=not args.no_quadratic_drag)
    elif args.step == "run":
        run_cases(args.dir, args.jobs)
    elif args.step == "modes":
        table = write_table(args.dir)
        print(f"{len(table['cases'])} cases -> {TABLE}")
    else:
        table = json.loads(TABLE.read_text())
        with tempfile.TemporaryDirectory() as tmp:
            fst = mbsym_deck(Path(tmp)) if args.dir is None else args.dir / "cases" / "mbsym" / "fl_steady_13.fst"
            text, numbers = compare(table, fst)
        print(text)
        plot(numbers, args.plot)
        print(f"figure: {args.plot}")
        if args.readme:
            from _report import write_section

            write_section("floating-linear", text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
