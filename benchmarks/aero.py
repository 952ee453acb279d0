"""Rotor aerodynamics: BEM accuracy vs AeroDyn, the ROSCO table, surface and interpolant cost.

Sections (each prints a Markdown table; ``--write`` also rewrites the ``aero`` section
of benchmarks/README.md and saves ``figures/aero_steady_coefficients.png``):

1. **Accuracy vs AeroDyn 15** at the 17 steady OpenFAST v5 runs of the NREL 5 MW
   (``../shared/openfast/aero/steady_states.csv``): mbsym's BEM at AeroDyn's own RtTSR,
   blade pitch and skew (RtSkew) vs RtAeroCp/RtAeroCt; the built-in rotor
   (``nrel5mw_rotor()``: packaged surfaces, nominal 5 deg tilt, cubic spline) at
   (RtVAvgxh, RotSpeed, BldPitch1) vs RtAeroFxh/RtAeroMxh; ROSCO's ``Cp_Ct_Cq.NREL5MW.txt``
   at the same point (as in ``steady_summary.json``, its own conventions).
2. **Why ROSCO's table is lower**: the region-2 point (TSR 7.5 on ROSCO's axis, pitch 0)
   recomputed with mbsym's BEM step by step towards ROSCO's CCBlade set-up.
3. **Surface cost**: ``performance_surface`` on 50 TSR x 40 pitch.
4. **Interpolant cost**: value, gradient and Hessian of cp + ct at 20000 random points,
   CasADi virtual machine and compiled C, for the SX cell-polynomial spline (cubic,
   quintic) and CasADi's ``bspline`` interpolant; best of ``--repeat`` runs, ratios
   against the bspline value in the same run.

Measured numbers are never asserted anywhere.  Run: ``python benchmarks/aero.py [--write]``.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import tempfile
import time
from pathlib import Path

import casadi as ca
import numpy as np
from scipy.interpolate import RectBivariateSpline

from mbsym.codegen import compile_function
from mbsym.wind.aero import (
    BEMRotor, SurfaceSpline, nrel5mw_bem_rotor, nrel5mw_rotor, performance_surface, solve_bem,
)
from mbsym.wind.deck.performance import read_performance_table

HERE = Path(__file__).resolve().parent


def _shared() -> Path:
    for parent in HERE.parents:
        if (parent / "shared" / "openfast").is_dir():
            return parent / "shared" / "openfast" / "aero"
    raise SystemExit("shared OpenFAST reference data not found (../shared/openfast/aero)")


AERO = _shared()


def _states() -> list[dict[str, float]]:
    with open(AERO / "steady_states.csv", newline="") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


# ----------------------------------------------------------------------------- 1. accuracy
def accuracy() -> tuple[str, dict]:
    states = _states()
    summary = json.loads((AERO / "steady_summary.json").read_text())
    rotor = BEMRotor.from_openfast(AERO / "openfast_inputs" / "steady_12" / "steady_12.fst")
    builtin = nrel5mw_rotor()
    rows, curves = [], {k: [] for k in ("U", "cp_ad", "cp_bem", "cp_rosco", "ct_ad", "ct_bem",
                                        "ct_rosco")}
    worst = dict(cp=0.0, ct=0.0, fx=0.0, mx=0.0)
    for s, summ in zip(states, summary):
        sol = solve_bem(rotor, s["RtTSR_[-]"], math.radians(s["BldPitch1_[deg]"]),
                        skew=math.radians(s["RtSkew_[deg]"]))
        loads = builtin.steady(s["RtVAvgxh_[m/s]"], s["RotSpeed_[rpm]"] * math.pi / 30,
                               math.radians(s["BldPitch1_[deg]"]))
        e = {"cp": 100 * (float(sol.cp) / s["RtAeroCp_[-]"] - 1),
             "ct": 100 * (float(sol.ct) / s["RtAeroCt_[-]"] - 1),
             "fx": 100 * (float(loads["thrust"]) / s["RtAeroFxh_[N]"] - 1),
             "mx": 100 * (float(loads["torque"]) / s["RtAeroMxh_[N-m]"] - 1)}
        for key in worst:
            worst[key] = max(worst[key], abs(e[key]))
        rosco = 100 * (summ["Cp_table"] / summ["Cp_Uinf"] - 1)
        rows.append(f"| {s['WindSpeed_[m/s]']:g} | {s['RtTSR_[-]']:.3f} | {s['BldPitch1_[deg]']:.2f} "
                    f"| {s['RtSkew_[deg]']:.2f} | {s['RtAeroCp_[-]']:.4f} | {float(sol.cp):.4f} "
                    f"| {e['cp']:+.2f} | {s['RtAeroCt_[-]']:.4f} | {float(sol.ct):.4f} | {e['ct']:+.2f} "
                    f"| {e['fx']:+.2f} | {e['mx']:+.2f} | {rosco:+.1f} |")
        for key, value in (("U", s["WindSpeed_[m/s]"]), ("cp_ad", s["RtAeroCp_[-]"]),
                           ("cp_bem", float(sol.cp)), ("ct_ad", s["RtAeroCt_[-]"]),
                           ("ct_bem", float(sol.ct)),
                           ("cp_rosco", summ["Cp_table"]), ("ct_rosco", summ["Ct_table"])):
            curves[key].append(value)
    head = ("| U m/s | RtTSR | pitch deg | skew deg | Cp AeroDyn | Cp mbsym | err % | Ct AeroDyn "
            "| Ct mbsym | err % | RtAeroFxh err % (built-in) | RtAeroMxh err % (built-in) "
            "| ROSCO table Cp vs AeroDyn (U∞ conventions) % |\n"
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    text = head + "\n" + "\n".join(rows) + (
        f"\n\nWorst: Cp {worst['cp']:.2f} %, Ct {worst['ct']:.2f} % (BEM at AeroDyn's TSR, pitch, "
        f"skew); thrust {worst['fx']:.2f} %, torque {worst['mx']:.2f} % (built-in rotor through "
        "the spline, nominal 5° skew).")
    return text, curves


# ----------------------------------------------------------------------------- 2. ROSCO
def _smoothed(polar, s_cl: float = 0.1, s_cd: float = 0.001):
    """Polars smoothed the way CCBlade's CCAirfoil fits them (bivariate spline, s > 0)."""
    if polar.alpha.size < 10:
        return polar
    re = np.array([1.0, 2.0])
    cl = RectBivariateSpline(polar.alpha, re, np.c_[polar.cl, polar.cl], kx=3, ky=1, s=s_cl)
    cd = RectBivariateSpline(polar.alpha, re, np.c_[polar.cd, polar.cd], kx=3, ky=1, s=s_cd)
    grid = np.linspace(-math.pi, math.pi, 3601)
    return dataclasses.replace(polar, alpha=grid, cl=cl.ev(grid, np.ones_like(grid)),
                               cd=cd.ev(grid, np.ones_like(grid)),
                               cm=np.interp(grid, polar.alpha, polar.cm))


def rosco_explanation() -> str:
    table = read_performance_table(AERO / "Cp_Ct_Cq.NREL5MW.txt")
    base = nrel5mw_bem_rotor()
    tilt, radius = abs(base.shaft_tilt), base.radius
    i, j = int(np.argmin(abs(table.tsr - 7.5))), int(np.argmin(abs(table.pitch_deg)))
    cache: dict[int, object] = {}
    smooth = dataclasses.replace(base, polars=tuple(cache.setdefault(id(p), _smoothed(p))
                                                    for p in base.polars))
    steps = [
        ("AeroDyn-like BEM, AeroDyn conventions (R = 62.94 m, wind along the shaft)", base, False),
        ("same BEM, ROSCO conventions (R = 63 m, free-stream U∞, TSR = Ω 63 / U∞)", base, True),
        ("+ polars smoothed as CCBlade's CCAirfoil (s = 0.1 on Cl, 0.001 on Cd)", smooth, True),
        ("+ drag in the induction (CCBlade usecd)", dataclasses.replace(
            smooth, axial_drag=True, tangential_drag=True), True),
        ("+ no pitching moment (CCBlade has none)", dataclasses.replace(
            smooth, axial_drag=True, tangential_drag=True, pitching_moment=False), True),
    ]
    rows = []
    for label, rotor, rosco in steps:
        c = math.cos(tilt) if rosco else 1.0
        ratio = radius / 63.0 if rosco else 1.0
        tsr = table.tsr[i] / ratio / c if rosco else table.tsr[i]
        sol = solve_bem(rotor, tsr, table.pitch[j])
        cp = float(sol.cp) * ratio**2 * c**3
        ct = float(sol.ct) * ratio**2 * c**2
        rows.append(f"| {label} | {cp:.4f} | {100 * (cp / table.cp[i, j] - 1):+.2f} | {ct:.4f} "
                    f"| {100 * (ct / table.ct[i, j] - 1):+.2f} |")
    return ("ROSCO table at TSR 7.5, pitch 0: Cp = "
            f"{table.cp[i, j]:.4f}, Ct = {table.ct[i, j]:.4f}.\n\n"
            "| mbsym BEM variant | Cp | vs ROSCO % | Ct | vs ROSCO % |\n|---|---|---|---|---|\n"
            + "\n".join(rows))


# ----------------------------------------------------------------------------- 3. surface
def surface_cost(repeat: int) -> str:
    rotor = nrel5mw_bem_rotor()
    tsr, pitch = np.linspace(2.0, 14.0, 50), np.radians(np.linspace(-5.0, 30.0, 40))
    rows = []
    for label, kw in (("8 azimuths (skew 5°, default)", {}), ("1 azimuth (no skew)", {"skew": 0.0})):
        times = []
        for _ in range(max(1, repeat // 2)):
            t0 = time.perf_counter()
            performance_surface(rotor, tsr, pitch, **kw)
            times.append(time.perf_counter() - t0)
        elements = 50 * 40 * 19 * (8 if not kw else 1)
        rows.append(f"| {label} | {min(times):.2f} | {min(times) / elements * 1e6:.2f} |")
    return ("| 50 TSR × 40 pitch, 19 nodes | wall s (best) | µs per element |\n|---|---|---|\n"
            + "\n".join(rows))


# ----------------------------------------------------------------------------- 4. interpolant
def interpolant_cost(repeat: int, n: int = 20000) -> str:
    table = nrel5mw_rotor().table
    rng = np.random.default_rng(0)
    points = np.vstack([rng.uniform(2.0, 14.0, n), rng.uniform(-0.08, 0.5, n)])
    folder = tempfile.mkdtemp()
    candidates = {}
    for label, spline in (("SX cells, cubic (default)", SurfaceSpline.from_table(table)),
                          ("SX cells, quintic", SurfaceSpline.from_table(table, degree=5)),
                          ("CasADi bspline, cubic", SurfaceSpline.from_table(table,
                                                                             method="bspline"))):
        z = ca.SX.sym("z", 2)
        out = spline(z[0], z[1])
        value = out["cp"] + out["ct"]
        hessian, gradient = ca.hessian(value, z)
        funcs = {"f": ca.Function("f", [z], [value]),
                 "f+grad": ca.Function("g", [z], [value, gradient]),
                 "f+grad+Hessian": ca.Function("h", [z], [value, gradient, hessian])}
        for what, fun in funcs.items():
            mapped = fun.map(n, "serial")
            compiled = compile_function(mapped, directory=folder).function
            for f in (mapped, compiled):
                for _ in range(3):  # warm up
                    f(points)
            candidates[(label, what)] = (fun.n_instructions(), mapped, compiled)
    best = {key: [math.inf, math.inf] for key in candidates}
    for _ in range(repeat):  # interleaved rounds: load changes hit every candidate alike
        for key, (_, mapped, compiled) in candidates.items():
            for k, f in enumerate((mapped, compiled)):
                t0 = time.perf_counter()
                f(points)
                best[key][k] = min(best[key][k], (time.perf_counter() - t0) / n * 1e6)
    results = {key: (candidates[key][0], *best[key]) for key in candidates}
    base = results[("CasADi bspline, cubic", "f")][2]
    rows = [f"| {label} | {what} | {instr} | {vm:.2f} | {cc:.2f} | {cc / base:.2f} |"
            for (label, what), (instr, vm, cc) in results.items()]
    return ("| interpolant | evaluates | SX instructions | VM µs/point | compiled µs/point "
            "| compiled / bspline f |\n|---|---|---|---|---|---|\n" + "\n".join(rows))


def figure(curves: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, q in zip(axes, ("cp", "ct")):
        ax.plot(curves["U"], curves[f"{q}_ad"], "ko-", label="AeroDyn 15 (OpenFAST v5)")
        ax.plot(curves["U"], curves[f"{q}_bem"], "r.--", label="mbsym BEM")
        ax.plot(curves["U"], curves[f"{q}_rosco"], "b^:", label="ROSCO table at the same TSR, pitch")
        ax.set_xlabel("wind speed [m/s]")
        ax.set_ylabel(f"{q.upper()} (RtVAvgxh based)")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("NREL 5 MW steady states: rotor coefficients")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--write", action="store_true",
                        help="rewrite the 'aero' section of benchmarks/README.md and the figure")
    args = parser.parse_args()
    acc, curves = accuracy()
    parts = [("### Accuracy vs AeroDyn 15 (17 steady states)", acc),
             ("### Where ROSCO's table differs", rosco_explanation()),
             ("### BEM surface computation", surface_cost(args.repeat)),
             ("### Interpolant cost (cp + ct, 20000 points)", interpolant_cost(args.repeat))]
    text = "\n\n".join(f"{title}\n\n{body}" for title, body in parts)
    print(text)
    if args.write:
        from _report import write_section

        figure(curves, HERE / "figures" / "aero_steady_coefficients.png")
        write_section("aero", "## Rotor aerodynamics: BEM vs AeroDyn, surfaces, interpolants "
                      "(`aero.py`)\n\n" + text
                      + "\n\n![steady coefficients](figures/aero_steady_coefficients.png)")


if __name__ == "__main__":
    main()
