"""Sweep executors: per-case cost and overhead, 1 -> 2 workers, and a 1000-case projection.

Case: NREL 5 MW (built-in data) with the paper45 degrees of freedom (tower fore-aft 1,
side-side 1, generator azimuth), free decay from the deck's initial conditions, fixed-step
RK4 (dt = 0.01 s) for ``--tmax`` seconds, OpenFAST channels summarized (mean, std, max, min);
swept parameter ``tower_stiffness_scale`` over ``--cases`` values in [0.8, 1.2].

Rows: the in-process executor (CasADi ``map`` over chunks of cases; the baseline), CasADi
threads, worker processes and a local Dask cluster (loopback), each with 1 and 2 workers.
Startup (spawning the pool or the cluster) is timed apart from the sweep itself: the Dask rows
pass a ``distributed.Client`` already connected. Per case = (sweep wall) / cases; overhead =
per case - the baseline's per case; in-worker = the evaluation alone, measured in the worker.
Prepare = building the plan and sampling the inputs in the calling process (per sweep). Ratios are against
the baseline of the same run; rows are run interleaved ``--repeat`` times and the fastest run of each is kept (the machine is shared); numbers are
never asserted.

Run: ``python benchmarks/sweep.py [--cases 16] [--tmax 20] [--repeat 3] [--write]``
(``--write`` updates the sweep section of benchmarks/README.md).
"""

from __future__ import annotations

import argparse
import logging
import os
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from mbsym.sweep import sweep
from mbsym.wind import TurbineModel, nrel5mw

DT = 0.01


def model():
    return TurbineModel(nrel5mw(), dofs=["TwFADOF1", "TwSSDOF1", "GenDOF"])


def _pid(_):
    return os.getpid()


def pool_startup(workers: int) -> float:
    """Wall time to start a process pool and run one trivial task per worker [s]."""
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=workers) as pool:
        list(pool.map(_pid, range(workers)))
    return time.perf_counter() - t0


def dask_clients():
    """Local Dask clusters of 1 and 2 workers, started and timed up front: {workers: (client, cluster, startup)}."""
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
        client.run(lambda: __import__("mbsym.sweep"))           # workers import mbsym before the clock starts
        out[w] = (client, cluster, time.perf_counter() - t0)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=16)
    ap.add_argument("--tmax", type=float, default=20.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args()
    turbine = model()
    cases = {"tower_stiffness_scale": np.linspace(0.8, 1.2, args.cases).tolist()}

    def go(executor, **kw):
        return sweep(turbine, cases, tmax=args.tmax, dt=DT, executor=executor, progress=False, **kw)

    clients = dask_clients()
    runs = [("in-process (CasADi map)", 1, 0.0, lambda: go("serial")),
            ("in-process, compiled RK4 step", 1, 0.0, lambda: go("serial", compile=True)),
            ("CasADi threads:1", 1, 0.0, lambda: go("threads:1")),
            ("CasADi threads:2", 2, 0.0, lambda: go("threads:2"))]
    for w in (1, 2):
        runs.append((f"processes:{w} (pool started per sweep; its startup subtracted)", w, pool_startup(w),
                     (lambda w=w: go(f"processes:{w}"))))
    for w, (client, _, startup) in clients.items():
        runs.append((f"Dask LocalCluster, {w} worker(s)", w, startup, (lambda c=client: go(c))))
    try:
        for _, _, _, fn in runs:                   # warm: caches, compilation, plans deserialized in workers
            fn()
        walls = {label: [] for label, *_ in runs}
        results = {}
        for _ in range(args.repeat):               # interleaved: the machine's load hits every row alike
            for label, w, startup, fn in runs:
                t0 = time.perf_counter()
                results[label] = fn()
                walls[label].append(time.perf_counter() - t0 - (startup if label.startswith("processes") else 0.0))
    finally:
        for client, cluster, _ in clients.values():
            client.close()
            cluster.close()
    base = results[runs[0][0]]
    identical = all(_same(base, r) for r in results.values())
    rows = [(label, w, min(walls[label]), startup, results[label]) for label, w, startup, _ in runs]
    print_table(rows, rows[0][2], args, identical)


def _same(a, b) -> bool:
    return all(np.array_equal(a.table[c], b.table[c], equal_nan=True) if c != "error" else a.table[c] == b.table[c]
               for c in a.table.columns)


def print_table(rows, base_wall, args, identical):
    n = args.cases
    base_case = base_wall / n
    lines = [f"{n} cases × {args.tmax:g} s of simulated time (dt = {DT} s, {int(round(args.tmax / DT))} RK4 steps "
             f"each), NREL 5 MW with TFA1, TSS1, GeAz; {os.cpu_count()} cores (shared). Results identical bit for "
             f"bit on every executor: **{'yes' if identical else 'NO'}**.", "",
             "| executor | workers | sweep wall [s] | per case [ms] | overhead per case vs in-process [ms] | "
             "in-worker per case [ms] | speed-up vs in-process | startup [s] | prepare in caller [s] |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    one: dict = {}
    for label, w, wall, startup, res in rows:
        per = wall / n
        inw = float(np.median(res.case_wall_s)) * 1e3
        kind = next((k for k in ("CasADi threads", "processes", "Dask LocalCluster") if label.startswith(k)), label)
        one.setdefault(kind, {})[w] = wall
        lines.append(f"| {label} | {w} | {wall:.3g} | {per * 1e3:.1f} | {(per - base_case) * 1e3:+.1f} | {inw:.1f} | "
                     f"{base_wall / wall:.2f} | {startup:.2f} | {res.prepare_wall_s:.3f} |")
    lines.append("")
    for kind in ("CasADi threads", "processes", "Dask LocalCluster"):
        walls = one.get(kind, {})
        if 1 in walls and 2 in walls:
            lines.append(f"- {kind}: 1 → 2 workers speed-up {walls[1] / walls[2]:.2f}×.")
    comp_case = next(r[2] for r in rows if "compiled" in r[0]) / n
    lines += projection(base_case, comp_case, args.tmax)
    text = "\n".join(lines)
    print(text)
    if args.write:
        from _report import write_section

        write_section("sweep", text)


def projection(vm_case, compiled_case, tmax):
    """1000 cases of 600 s each: measured per-case cost scaled by simulated time, divided among W workers."""
    scale = 600.0 / tmax
    out = ["", "Projection, 1000-case design load set of 600 s simulations of this model (per-case cost "
           "scaled linearly from the measured one; ideal division among W single-core workers plus the measured "
           "startup; a real cluster adds scheduler and network latency of a few ms per task):", "",
           "| per-case cost | 600 s case [s] | 1 worker [h] | W = 16 [min] | W = 64 [min] | W = 256 [min] |",
           "|---|---:|---:|---:|---:|---:|"]
    for label, c in (("VM (default)", vm_case), ("compiled step", compiled_case)):
        case = c * scale
        out.append(f"| {label} | {case:.2f} | {1000 * case / 3600:.2f} | {1000 * case / 16 / 60:.2f} | "
                   f"{1000 * case / 64 / 60:.2f} | {1000 * case / 256 / 60:.2f} |")
    return out


if __name__ == "__main__":
    main()
