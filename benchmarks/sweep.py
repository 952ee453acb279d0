"""Sweep executors: per-case cost and overhead, 1 -> 2 workers, and a 1000-case projection.

Case: NREL 5 MW (built-in data) with the paper45 degrees of freedom (tower fore-aft 1,
side-side 1, generator azimuth), free decay from the deck's initial conditions, fixed-step
RK4 (dt = 0.01 s) for ``--tmax`` seconds, OpenFAST channels summarized (mean, std, max, min);
swept parameter ``tower_stiffness_scale`` over ``--cases`` values in [0.8, 1.2].

Rows: the in-process executor (CasADi ``map`` over chunks of cases; the baseline), CasADi
threads, worker processes and a local Dask cluster (loopback), each with 1 and 2 workers.
Startup (spawning the pool or the cluster) is timed apart from the sweep itself: the Dask rows
pass a ``distributed.Client`` already connected. Wall times depend on the load of this shared
machine; CPU times (this process + the workers' evaluations) much less: the CPU overhead per
case against the in-process run is the executor's own work (shipping, scheduling). A second
table repeats the rows with near-empty cases, where everything is overhead. Ratios are against
the baseline of the same run; rows are run interleaved ``--repeat`` times and the fastest run of each is kept (the machine is shared); numbers are
never asserted.

Run: ``python benchmarks/sweep.py [--cases 8] [--tmax 10] [--repeat 7] [--write]``
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
#: Near-empty cases (5 steps), two counts: the slope is the per-case overhead, the rest the per-sweep cost.
TINY_COUNTS, TINY_TMAX = (8, 40), 0.05


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


def executor_runs(go, clients, *, compiled: bool = True) -> list:
    """(label, workers, startup [s], run) for every executor; ``go(executor, **kw)`` runs one sweep."""
    runs = [("in-process (CasADi map)", 1, 0.0, lambda: go("serial"))]
    if compiled:
        runs.append(("in-process, compiled RK4 step", 1, 0.0, lambda: go("serial", compile=True)))
    runs += [("CasADi threads:1", 1, 0.0, lambda: go("threads:1")),
             ("CasADi threads:2", 2, 0.0, lambda: go("threads:2"))]
    for w in (1, 2):
        runs.append((f"processes:{w} (pool started per sweep; its startup subtracted)", w, pool_startup(w),
                     (lambda w=w: go(f"processes:{w}"))))
    for w, (client, _, startup) in clients.items():
        runs.append((f"Dask LocalCluster, {w} worker(s)", w, startup, (lambda c=client: go(c))))
    return runs


def measure(runs, repeat: int) -> tuple[list, bool]:
    """Rows ``(label, workers, startup, fastest wall [s], fastest total CPU [s])`` and whether every executor gave
    the in-process numbers bit for bit. Total CPU = this process (plan, sampling, scheduling, summaries of
    in-process rows; the Dask scheduler runs here too) + the workers' evaluation CPU time. Rows run interleaved
    so that the machine's load hits all alike; the fastest of ``repeat`` runs is kept."""
    for _, _, _, fn in runs:                       # warm: caches, compilation, plans deserialized in workers
        fn()
    walls = {label: [] for label, *_ in runs}
    cpus = {label: [] for label, *_ in runs}
    results = {}
    for _ in range(repeat):
        for label, w, startup, fn in runs:
            t0, c0 = time.perf_counter(), time.process_time()
            res = results[label] = fn()
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            remote = not label.startswith(("in-process", "CasADi"))
            walls[label].append(wall - (startup if label.startswith("processes") else 0.0))
            cpus[label].append(cpu + (float(np.sum(res.case_cpu_s)) if remote else 0.0))
    base = results[runs[0][0]]
    identical = all(_same(base, r) for r in results.values())
    return [(label, w, startup, min(walls[label]), min(cpus[label])) for label, w, startup, _ in runs], identical


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=8)
    ap.add_argument("--tmax", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args()
    turbine = model()

    def sweeper(n_cases, tmax):
        cases = {"tower_stiffness_scale": np.linspace(0.8, 1.2, n_cases).tolist()}
        return lambda executor, **kw: sweep(turbine, cases, tmax=tmax, dt=DT, executor=executor, progress=False,
                                            **kw)

    clients = dask_clients()
    try:
        rows, identical = measure(executor_runs(sweeper(args.cases, args.tmax), clients), args.repeat)
        tiny = [measure(executor_runs(sweeper(k, TINY_TMAX), clients, compiled=False), args.repeat)[0]
                for k in TINY_COUNTS]
    finally:
        for client, cluster, _ in clients.values():
            client.close()
            cluster.close()
    print_table(rows, args, identical, tiny)


def _same(a, b) -> bool:
    return all(np.array_equal(a.table[c], b.table[c], equal_nan=True) if c != "error" else a.table[c] == b.table[c]
               for c in a.table.columns)


def print_table(rows, args, identical, tiny):
    n = args.cases
    base_wall, base_cpu = rows[0][3], rows[0][4]
    lines = [f"{n} cases × {args.tmax:g} s of simulated time (dt = {DT} s, {int(round(args.tmax / DT))} RK4 steps "
             f"each), NREL 5 MW with TFA1, TSS1, GeAz; {os.cpu_count()} cores shared with other users (load average "
             f"{os.getloadavg()[0]:.1f} at the end). Results identical bit for bit on every executor: "
             f"**{'yes' if identical else 'NO'}**.", "",
             "| executor | workers | sweep wall [s] | wall per case [ms] | speed-up (wall) vs in-process | "
             "CPU per case [ms] | CPU overhead per case vs in-process [ms] | startup [s] |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    per_kind: dict = {}
    for label, w, startup, wall, cpu in rows:
        kind = next((k for k in ("CasADi threads", "processes", "Dask LocalCluster") if label.startswith(k)), label)
        per_kind.setdefault(kind, {})[w] = wall
        lines.append(f"| {label} | {w} | {wall:.3g} | {wall / n * 1e3:.1f} | {base_wall / wall:.2f} | "
                     f"{cpu / n * 1e3:.1f} | {(cpu - base_cpu) / n * 1e3:+.1f} | {startup:.2f} |")
    lines.append("")
    for kind in ("CasADi threads", "processes", "Dask LocalCluster"):
        walls = per_kind.get(kind, {})
        if 1 in walls and 2 in walls:
            lines.append(f"- {kind}: 1 → 2 workers, wall speed-up {walls[1] / walls[2]:.2f}×.")
    (k1, k2), (small, large) = TINY_COUNTS, tiny
    lines += ["", f"Overheads, from near-empty cases ({TINY_TMAX} s, {int(round(TINY_TMAX / DT))} steps) swept {k1} "
              f"and {k2} at a time: per case = the slope between the two, per sweep = the rest (building the "
              "plan: Dynamics, RK4 step, serialization; starting tasks):", "",
              "| executor | workers | per case, wall [ms] | per case, CPU [ms] | per sweep, wall [ms] | "
              "per sweep, CPU [ms] |", "|---|---:|---:|---:|---:|---:|"]
    for (label, w, _, wall1, cpu1), (_, _, _, wall2, cpu2) in zip(small, large):
        dw, dc = (wall2 - wall1) / (k2 - k1), (cpu2 - cpu1) / (k2 - k1)
        lines.append(f"| {label} | {w} | {dw * 1e3:.2f} | {dc * 1e3:.2f} | {(wall1 - k1 * dw) * 1e3:.0f} | "
                     f"{(cpu1 - k1 * dc) * 1e3:.0f} |")
    comp_cpu = next(r[4] for r in rows if "compiled" in r[0]) / n
    lines += projection(base_cpu / n, comp_cpu, args.tmax)
    text = "\n".join(lines)
    print(text)
    if args.write:
        from _report import write_section

        write_section("sweep", text)


def projection(vm_case, compiled_case, tmax):
    """1000 cases of 600 s each: measured per-case CPU cost scaled by simulated time, divided among W workers."""
    scale = 600.0 / tmax
    out = ["", "Projection, 1000-case design load set of 600 s simulations of this model: the in-process CPU cost "
           "per case scaled linearly with simulated time, divided ideally among W single-core workers (add the "
           "cluster's startup and a few ms of scheduling and network latency per task):", "",
           "| per-case cost | 600 s case [s] | 1 worker [h] | W = 16 [min] | W = 64 [min] | W = 256 [min] |",
           "|---|---:|---:|---:|---:|---:|"]
    for label, c in (("VM (default)", vm_case), ("compiled step", compiled_case)):
        case = c * scale
        out.append(f"| {label} | {case:.2f} | {1000 * case / 3600:.2f} | {1000 * case / 16 / 60:.2f} | "
                   f"{1000 * case / 64 / 60:.2f} | {1000 * case / 256 / 60:.2f} |")
    return out


if __name__ == "__main__":
    main()
