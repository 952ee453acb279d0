"""Accuracy and speed side by side: mbsym TurbineModel vs OpenFAST v5 ElastoDyn free decays.

For the shared cases (the 60 s free decays paper44_fa_gen, paper45_fa_ss_gen, paper46_floating and
the 30 s large-motion cases of issue 10, platform_rpy_gen and blades_large_deflection) this builds
the model from the deck, simulates the reference duration with cvodes (rtol 1e-8) and with rk4
(dt = 0.01 s, the deck's DT), and reports per channel ε = mean|y − y_OF| / range(y_OF) and
R² (wrap-aware for Azimuth), the largest ε over every channel the model outputs, plus model
build time, integration wall time and the whole warm ``simulate()`` call (integration plus the
OpenFAST output channels at the output times), against OpenFAST's 2.21 s whole-run wall for
paper45 on this machine kind (quoted in issue 4; OpenFAST is not run here). Times are medians
of 5 warm calls. Also: build time of the model with all 13 platform/tower/yaw/drivetrain DOFs.
Writes overlay plots to benchmarks/figures/ and the tables into benchmarks/README.md
between the ``openfast`` markers.

Needs ../shared/openfast (the reference data). Run: ``python benchmarks/openfast_validation.py``.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

import numpy as np
from _report import write_section

import mbsym as mb
from mbsym.wind import nrel5mw, read_openfast
from mbsym.wind.analysis.compare import TimeSeries, compare, overlay_plot, read_csv
from mbsym.wind.structure.turbine import SUPPORTED_DOFS, TurbineModel

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared" / "openfast" / "cases"
CASES = ["paper44_fa_gen", "paper45_fa_ss_gen", "paper46_floating", "platform_rpy_gen", "blades_large_deflection"]
OPENFAST_PAPER45_S = 2.21     # OpenFAST v5 (ElastoDyn only) wall time, paper45, quoted in issue 4


def _series(result, model) -> TimeSeries:
    ch = model.output_function()
    units = dict(zip(ch.names, ch.units))
    return TimeSeries(result.t, result.output_names, tuple(units[n] for n in result.output_names), result.y)


def _median_time(fn, repeats=5):
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out)


def run_case(case: str):
    fst, csv = SHARED / case / f"{case}.fst", SHARED / case / f"{case}.csv"
    turbine, ref = read_openfast(fst), read_csv(csv)
    t_build = _median_time(lambda: TurbineModel(turbine).eom)
    model = TurbineModel(turbine)
    runs, tmax = {}, float(ref.time[-1])
    for method, kw in (("cvodes", dict(rtol=1e-8, atol=1e-10)), ("rk4", dict(dt=0.01))):
        mb.simulate(model, tmax, method=method, t_out=ref.time, **kw)           # warm the cache
        results = []
        call = _median_time(lambda: results.append(mb.simulate(model, tmax, method=method, t_out=ref.time, **kw)))
        integration = statistics.median(r.statistics["integration_wall_s"] for r in results)
        runs[method] = (results[-1], compare(_series(results[-1], model), ref), integration, call)
    overlay_plot(HERE / "figures" / f"{case}.png", _series(runs["cvodes"][0], model), ref,
                 title=f"{case}: mbsym (cvodes) vs OpenFAST v5")
    return model, t_build, runs


def all_dofs_build_time() -> tuple[float, float]:
    t = dataclasses.replace(nrel5mw(), platform_mass=7.5e6, platform_roll_inertia=4.2e9,
                            platform_pitch_inertia=4.2e9, platform_yaw_inertia=1.6e8,
                            platform_cm=(0.0, 0.0, -90.0), platform_reference=(0.0, 0.0, 20.0),
                            tower_base_height=20.0)
    dofs = list(SUPPORTED_DOFS)
    build = _median_time(lambda: TurbineModel(t, dofs=dofs).eom, repeats=3)
    eom = TurbineModel(t, dofs=dofs).eom
    x, u, p = np.zeros(eom.n_x), np.zeros(eom.n_u), eom.parameter_vector({})
    f = eom.functions.rhs
    t0 = time.perf_counter()
    for _ in range(500):
        f(x, u, p)
    return build, (time.perf_counter() - t0) / 500


def tables() -> str:
    (HERE / "figures").mkdir(exist_ok=True)
    acc = ["| case | channel | ε cvodes [%] | R² cvodes | ε rk4 [%] | R² rk4 |", "|---|---|---:|---:|---:|---:|"]
    speed = ["| case | DOFs | build [ms] | cvodes: integration / whole call [ms] (steps) | "
             "rk4 (dt 0.01 s): integration / whole call [ms] | "
             f"vs OpenFAST {OPENFAST_PAPER45_S} s (paper45): integration / whole call |",
             "|---|---|---:|---:|---:|---:|"]
    for case in CASES:
        model, t_build, runs = run_case(case)
        (rc, cc, tc, wc), (rr, cr, tr, wr) = runs["cvodes"], runs["rk4"]
        by_name = {row["channel"]: row for row in cr}
        for row in cc:
            name = row["channel"]
            if not (name.startswith("Q_") or name in ("Azimuth", "RotSpeed") or name.startswith("Ptfm")):
                continue
            other = by_name[name]
            fmt = lambda v, pct=False: "const" if np.isnan(v) else (f"{100 * v:.4f}" if pct else f"{v:.6f}")
            acc.append(f"| {case} | {name} | {fmt(row['epsilon'], True)} | {fmt(row['r2'])} | "
                       f"{fmt(other['epsilon'], True)} | {fmt(other['r2'])} |")
        worst = lambda rows: max((r["epsilon"] for r in rows if not np.isnan(r["epsilon"])), default=np.nan)  # noqa: E731
        acc.append(f"| {case} | max over all {len(cc)} channels | {100 * worst(cc):.4f} | | {100 * worst(cr):.4f} | |")
        ratio = (f"cvodes {OPENFAST_PAPER45_S / tc:.0f}× / {OPENFAST_PAPER45_S / wc:.0f}×, "
                 f"rk4 {OPENFAST_PAPER45_S / tr:.0f}× / {OPENFAST_PAPER45_S / wr:.0f}×") if "45" in case else "—"
        speed.append(f"| {case} ({rr.t[-1]:.0f} s) | {', '.join(model.eom.coordinates)} | {1e3 * t_build:.0f} | "
                     f"{1e3 * tc:.1f} / {1e3 * wc:.1f} ({rc.statistics['steps']}) | {1e3 * tr:.1f} / {1e3 * wr:.1f} | "
                     f"{ratio} |")
        print(speed[-1], flush=True)
    build, rhs = all_dofs_build_time()
    speed.append(f"| all 13 platform/tower/yaw/drivetrain DOFs | 13 | {1e3 * build:.0f} | "
                 f"one rhs call {1e6 * rhs:.0f} µs | — | — |")
    return "\n".join(speed) + "\n\n" + "\n".join(acc)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    args = parser.parse_args()
    if not SHARED.exists():
        raise SystemExit(f"reference data not found at {SHARED}")
    table = tables()
    print("\n" + table)
    if not args.no_write:
        write_section("openfast", table)


if __name__ == "__main__":
    main()
