"""Turbine sweeps (``sweep_turbine`` / ``mbsym sweep``): executors, 1 -> 2 workers, per-case overhead, projection.

Two sweeps of the built-in NREL 5 MW, each through every executor:

* **wind**: 8 closed-loop cases (Kaimal turbulence, 4 mean speeds x 2 seeds, TI 0.14) of ``--tmax``
  seconds under the baseline controller (the operating turbine of ``mbsym simulate --wind``:
  GenDOF, TwFADOF1, TwSSDOF1, DBEMT, actuators), one RK4 step per 0.01 s controller sample,
  the loop compiled (generated C, loaded from the disk cache in every worker);
* **structural**: 8 free decays (``FAStTunr(1)`` x ``TwrFADmp(1)``, 2 x 4 values) of ``--tmax``
  seconds of the structural model of ``mbsym simulate`` (rigid blades; 7 DOFs), RK4 at 0.01 s.

Executors: in-process (``serial``: the baseline), ``processes:1/2`` (a pool started per sweep; its
startup measured apart and subtracted), Dask ``LocalCluster`` of 1 and 2 single-threaded workers
on 127.0.0.1 (started once, passed as a ``distributed.Client``; startup reported apart). Per case
wall = execution wall / cases; the overhead per case against in-process is ``(W x wall_W -
wall_in-process) / cases``: worker time spent on anything but the in-process work (shipping,
deserializing, loading compiled code, scheduling, waiting for the other core). The machine has 2
cores shared with other developers: the load average is printed with the timings, and rows run
interleaved ``--repeat`` times, the fastest kept. Numbers are never asserted.

Run: ``python benchmarks/wind_sweep.py [--tmax 60] [--repeat 2] [--write]`` (``--write`` updates the
wind-sweep section of benchmarks/README.md).
"""

from __future__ import annotations

import argparse
import logging
import os
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from mbsym.wind.analysis.sweep import sweep_turbine

WINDS = [f"kaimal:{u}:0.14:{seed}" for u in (6, 10, 14, 20) for seed in (1, 2)]
STRUCTURAL = {"FAStTunr(1)": [0.9, 1.1], "TwrFADmp(1)": [0.5, 1.0, 2.0, 4.0]}


def _pid(_):
    return os.getpid()


def pool_startup(workers: int) -> float:
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        list(pool.map(_pid, range(workers)))
    return time.perf_counter() - t0


def dask_clients() -> dict:
    try:
        import distributed
    except ImportError:
        print("distributed is not installed: no Dask rows (pip install 'mbsym[dask]').")
        return {}
    out = {}
    for w in (1, 2):
        t0 = time.perf_counter()
        cluster = distributed.LocalCluster(n_workers=w, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None, silence_logs=logging.ERROR)
        client = distributed.Client(cluster)
        client.run(lambda: __import__("mbsym.wind.analysis.sweep"))
        out[w] = (client, cluster, time.perf_counter() - t0)
    return out


def runs(clients: dict) -> list:
    """(label, workers, startup [s], executor)."""
    out = [("in-process (serial)", 1, 0.0, "serial")]
    out += [(f"processes:{w}", w, pool_startup(w), f"processes:{w}") for w in (1, 2)]
    out += [(f"Dask LocalCluster, {w} worker(s)", w, s, c) for w, (c, _, s) in clients.items()]
    return out


def measure(go, rows: list, repeat: int):
    """Fastest execution wall (engine wall minus its preparation, minus pool startup), total wall, CPU in the
    workers, per row; and whether every row gave the in-process table bit for bit."""
    go("serial")                                            # warm: models, compiled loops, disk cache
    best: dict = {}
    tables = {}
    cold: dict = {}
    for k in range(repeat):
        for label, w, startup, ex in rows:
            t0 = time.perf_counter()
            res = go(ex)
            total = time.perf_counter() - t0
            run = res.wall_s - res.prepare_wall_s - (startup if label.startswith("processes") else 0.0)
            tables[label] = res.table
            if k == 0:
                cold[label] = run
            prev = best.get(label)
            if prev is None or run < prev[0]:
                best[label] = (run, total, float(np.sum(res.case_cpu_s)), float(np.sum(res.case_wall_s)))
    base = tables[rows[0][0]]
    same = all(_same(base, t) for t in tables.values())
    return best, cold, same


def _same(a, b) -> bool:
    return a.columns == b.columns and all(
        np.array_equal(a[c], b[c], equal_nan=True) if c not in ("error", "wind") else a[c] == b[c] for c in a.columns)


def table(title: str, rows: list, best: dict, cold: dict, n: int, same: bool) -> list[str]:
    base = best[rows[0][0]][0]
    out = [f"**{title}** — identical to the in-process table bit for bit on every executor: "
           f"**{'yes' if same else 'NO'}**", "",
           "| executor | workers | execution wall [s] | wall per case [ms] | speed-up vs in-process | "
           "overhead per case vs in-process [ms] | worker CPU per case [ms] | startup [s] | first sweep, wall [s] |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for label, w, startup, _ in rows:
        run, _, cpu, _ = best[label]
        out.append(f"| {label} | {w} | {run:.3g} | {run / n * 1e3:.0f} | {base / run:.2f} | "
                   f"{(w * run - base) / n * 1e3:+.0f} | {cpu / n * 1e3:.0f} | {startup:.2f} | {cold[label]:.3g} |")
    for kind in ("processes", "Dask"):
        one = next((best[r[0]][0] for r in rows if r[0].startswith(kind) and r[1] == 1), None)
        two = next((best[r[0]][0] for r in rows if r[0].startswith(kind) and r[1] == 2), None)
        if one and two:
            out.append(f"\n- {kind}: 1 → 2 workers, wall speed-up {one / two:.2f}×.")
    return out


def projection(case_s: float, tmax: float, prep_s: float) -> list[str]:
    """1000 cases of 600 s: measured in-process cost per case scaled with simulated time, divided among W workers."""
    per = case_s * 600.0 / tmax
    lines = ["", f"Projection, 1000-case design load set (wind speeds × seeds × parameter variations, 600 s each) of "
             f"this operating model: {per:.2f} s per 600 s case (the in-process cost per {tmax:g} s case × "
             f"{600.0 / tmax:g}), divided ideally among W single-core workers, plus the serial preparation in the "
             f"calling process ({prep_s * 1e3:.0f} ms per case measured, a warm call: steady-state initial state, wind "
             "check, the runner's warm-up run):", "",
             "| workers W | cases per worker | wall [min] | of which serial preparation [min] |",
             "|---:|---:|---:|---:|"]
    for w in (1, 16, 64, 256, 1000):
        wall = 1000 * per / w + 1000 * prep_s
        lines.append(f"| {w} | {1000 / w:.3g} | {wall / 60:.2f} | {1000 * prep_s / 60:.2f} |")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tmax", type=float, default=60.0)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args()

    def wind(ex):
        return sweep_turbine(None, {}, wind=WINDS, tmax=args.tmax, channels=["GenPwr", "TwrBsMyt", "TTDspFA"],
                             del_channels=["TwrBsMyt"], wohler=4.0, executor=ex, progress=False, compile=True)

    def structural(ex):
        return sweep_turbine(None, STRUCTURAL, tmax=args.tmax, executor=ex, progress=False)

    load0 = os.getloadavg()
    clients = dask_clients()
    try:
        rows = runs(clients)
        wind("serial")                                      # builds the model, compiles the loop (disk cache)
        t0 = time.perf_counter()
        prep = wind("serial")
        prep_s = (time.perf_counter() - t0 - prep.wall_s) / len(WINDS)
        wind_best, wind_cold, wind_same = measure(wind, rows, args.repeat)
        struct_best, struct_cold, struct_same = measure(structural, rows, args.repeat)
    finally:
        for client, cluster, _ in clients.values():
            client.close()
            cluster.close()
    load1 = os.getloadavg()
    n = len(WINDS)
    lines = [f"Built-in NREL 5 MW, {args.tmax:g} s per case, {os.cpu_count()} cores shared with other developers: "
             f"load average (1 min) {load0[0]:.2f} before, {load1[0]:.2f} after; fastest of {args.repeat} "
             "interleaved runs per row.", ""]
    lines += table(f"Wind sweep: {n} closed-loop cases ({', '.join(WINDS[::2])}, seeds 1-2), baseline controller, "
                   "compiled loop", rows, wind_best, wind_cold, n, wind_same)
    lines += [""]
    lines += table(f"Structural sweep: {n} free decays (FAStTunr(1) × TwrFADmp(1)), 7 DOFs, RK4 at 0.01 s in "
                   "CasADi's VM", rows, struct_best, struct_cold, n, struct_same)
    lines += projection(wind_best[rows[0][0]][0] / n, args.tmax, prep_s)
    text = "\n".join(lines)
    print(text)
    if args.write:
        from _report import write_section

        write_section("wind-sweep", text)


if __name__ == "__main__":
    main()
