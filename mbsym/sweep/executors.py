"""Where the cases of a sweep run: in this process, in worker processes, or on a Dask cluster.

Executor specifications (``executor=`` of :func:`mbsym.sweep`; the CLI's ``--executor``):

``"serial"``
    This process; the cases sharing a plan go through one CasADi ``map`` of the case
    Function per chunk (no Python loop between cases).
``"threads:N"``
    This process, CasADi's ``map`` with N threads (parallel C++ evaluation, no
    pickling); callable runners run one by one.
``"processes:N"``
    N worker processes (:class:`concurrent.futures.ProcessPoolExecutor`); each receives
    the plans once (serialized CasADi Functions) when it starts.
``"dask:N"``
    A local Dask cluster of N single-threaded worker processes on the loopback
    interface, started and closed by the sweep (needs ``mbsym[dask]``).
``"dask:ADDRESS"`` or a ``distributed.Client``
    An existing Dask scheduler (e.g. ``"dask:tcp://10.0.0.5:8786"``); the workers need
    mbsym installed. Plans are broadcast to every worker once (``Client.scatter``).

Every executor evaluates the same Functions on the same numbers: results are identical
bit for bit. A chunk whose worker fails (e.g. a crashed process) records the error in
each of its cases' rows.
"""

from __future__ import annotations

import logging
import math
import sys
import time
from dataclasses import dataclass
from typing import Any, Callable

from ..exceptions import SweepError
from .plans import Outcome, evaluate_mapped, run_chunk

__all__ = ["ExecutorSpec", "parse_executor", "execute", "Progress"]

#: Seconds to wait for a Dask cluster to start or a scheduler to answer.
DASK_TIMEOUT_S = 60.0


@dataclass(frozen=True)
class ExecutorSpec:
    """A parsed executor: ``kind`` in serial, threads, processes, dask; workers; address; client."""

    kind: str
    workers: int = 1
    address: str | None = None
    client: Any = None

    def __str__(self) -> str:
        if self.client is not None:
            return "dask:client"
        return self.kind if self.kind == "serial" else f"{self.kind}:{self.address or self.workers}"


def parse_executor(spec: Any) -> ExecutorSpec:
    """An :class:`ExecutorSpec` from a string (module docstring) or a ``distributed.Client``.

    Raises
    ------
    SweepError
        An unknown form, or a worker count that is not a positive integer.
    """
    if type(spec).__name__ == "Client" and hasattr(spec, "scatter"):
        return ExecutorSpec("dask", client=spec)
    if not isinstance(spec, str):
        raise SweepError(f"executor must be 'serial', 'threads:N', 'processes:N', 'dask:N', 'dask:ADDRESS' or a "
                         f"distributed.Client; got {spec!r}.")
    kind, _, arg = spec.partition(":")
    if kind == "serial" and not arg:
        return ExecutorSpec("serial")
    if kind in ("threads", "processes", "dask") and arg:
        if arg.isdigit() and int(arg) > 0:
            return ExecutorSpec(kind, workers=int(arg))
        if kind == "dask" and ("://" in arg or ":" in arg):
            return ExecutorSpec("dask", address=arg)
    raise SweepError(f"executor {spec!r} is not understood; use 'serial', 'threads:N', 'processes:N', 'dask:N' "
                     "(N a positive integer) or 'dask:ADDRESS' (e.g. 'dask:tcp://127.0.0.1:8786').")


class Progress:
    """A one-line progress bar on a terminal: ``sweep [####----] 12/40 cases, 1 failed, 3.2 s, ETA 7 s``."""

    def __init__(self, total: int, enabled: bool | None, stream=None) -> None:
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", lambda: False)
        self.enabled = bool(isatty()) if enabled is None else bool(enabled)
        self.total, self.done, self.failed = total, 0, 0
        self.t0 = time.perf_counter()
        self._last = 0.0

    def update(self, outcomes: list[Outcome]) -> None:
        self.done += len(outcomes)
        self.failed += sum(o.error is not None for o in outcomes)
        now = time.perf_counter()
        if self.enabled and (now - self._last > 0.1 or self.done == self.total):
            self._last = now
            elapsed = now - self.t0
            eta = f"{elapsed / self.done * (self.total - self.done):.0f} s" if self.done else "?"
            width = 24
            fill = int(width * self.done / max(self.total, 1))
            self.stream.write(f"\rsweep [{'#' * fill}{'-' * (width - fill)}] {self.done}/{self.total} cases, "
                              f"{self.failed} failed, {elapsed:.1f} s, ETA {eta} ")
            self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


def _chunks(jobs: list, size: int) -> list[list]:
    """Consecutive chunks of at most ``size`` jobs that share a plan."""
    out: list[list] = []
    for job in jobs:
        if out and out[-1][0][1] == job[1] and len(out[-1]) < size:
            out[-1].append(job)
        else:
            out.append([job])
    return out


def execute(spec: ExecutorSpec, plans: dict, jobs: list[tuple[int, str, Any]], *, chunk_size: int | None,
            progress: Progress) -> dict[int, Outcome]:
    """Run every job ``(case index, plan key, payload)``; return the outcomes by case index."""
    jobs = sorted(jobs, key=lambda j: (list(plans).index(j[1]), j[0]))
    workers = spec.workers if spec.client is None and spec.address is None else 4
    size = chunk_size or (16 if spec.kind in ("serial", "threads") else
                          max(1, min(16, math.ceil(len(jobs) / (4 * max(workers, 1))))))
    chunks = _chunks(jobs, size)
    results: dict[int, Outcome] = {}

    def record(chunk: list, outcomes: list[Outcome]) -> None:
        for (index, _, _), outcome in zip(chunk, outcomes):
            results[index] = outcome
        progress.update(outcomes)

    runner: Callable = {"serial": _serial, "threads": _serial, "processes": _processes, "dask": _dask}[spec.kind]
    runner(spec, plans, chunks, record)
    return results


def _serial(spec: ExecutorSpec, plans: dict, chunks: list, record: Callable) -> None:
    par = "thread" if spec.kind == "threads" else "serial"
    for chunk in chunks:
        record(chunk, evaluate_mapped(plans[chunk[0][1]], [j[2] for j in chunk], parallelization=par,
                                      workers=spec.workers))


def _failed_chunk(chunk: list, exc: BaseException) -> list[Outcome]:
    return [Outcome({}, f"{type(exc).__name__}: {exc} (the worker running this case failed)") for _ in chunk]


# ---------------------------------------------------------------------------- processes
_WORKER_PLANS: dict = {}


def _init_worker(plans: list) -> None:
    """Process-pool initializer: keep the plans (serialized Functions) sent once per worker."""
    _WORKER_PLANS.update({p.key: p for p in plans})


def _run_keyed(key: str, payloads: list) -> list[Outcome]:
    return run_chunk(_WORKER_PLANS[key], payloads)


def _processes(spec: ExecutorSpec, plans: dict, chunks: list, record: Callable) -> None:
    from concurrent.futures import ProcessPoolExecutor, as_completed   # on use: ~20 ms of imports

    with ProcessPoolExecutor(max_workers=spec.workers, initializer=_init_worker,
                             initargs=(list(plans.values()),)) as pool:
        futures = {pool.submit(_run_keyed, chunk[0][1], [j[2] for j in chunk]): chunk for chunk in chunks}
        for fut in as_completed(futures):
            chunk = futures[fut]
            try:
                record(chunk, fut.result())
            except Exception as exc:  # noqa: BLE001 - a broken worker fails its chunk, not the sweep
                record(chunk, _failed_chunk(chunk, exc))


# ---------------------------------------------------------------------------- dask
def _dask(spec: ExecutorSpec, plans: dict, chunks: list, record: Callable) -> None:
    try:
        import distributed
    except ImportError:
        raise SweepError("the Dask executor needs the 'distributed' package: pip install 'mbsym[dask]'.") from None
    client, closers = _client(spec, distributed)
    try:
        shipped = {key: client.scatter(plan, broadcast=True, hash=False) for key, plan in plans.items()}
        futures = {client.submit(run_chunk, shipped[chunk[0][1]], [j[2] for j in chunk], pure=False): i
                   for i, chunk in enumerate(chunks)}
        for fut in distributed.as_completed(list(futures)):
            chunk = chunks[futures[fut]]
            try:
                record(chunk, fut.result())
            except Exception as exc:  # noqa: BLE001 - a lost worker fails its chunk, not the sweep
                record(chunk, _failed_chunk(chunk, exc))
    finally:
        quiet = logging.getLogger("distributed")
        level = quiet.level
        quiet.setLevel(logging.ERROR)                # no INFO lines about workers closing
        try:
            for close in closers:
                close()
        finally:
            quiet.setLevel(level)


def _client(spec: ExecutorSpec, distributed) -> tuple[Any, list[Callable]]:
    """The client to use and what to close afterwards (nothing for a client the user passed)."""
    if spec.client is not None:
        return spec.client, []
    if spec.address is not None:
        try:
            client = distributed.Client(spec.address, timeout=DASK_TIMEOUT_S)
        except OSError as exc:
            raise SweepError(f"cannot reach the Dask scheduler at {spec.address}: {exc}.") from exc
        return client, [client.close]
    cluster = distributed.LocalCluster(n_workers=spec.workers, threads_per_worker=1, processes=True,
                                       host="127.0.0.1", dashboard_address=None, silence_logs=logging.ERROR)
    client = distributed.Client(cluster, timeout=DASK_TIMEOUT_S)
    return client, [client.close, cluster.close]
