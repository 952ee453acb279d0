"""Simulation speed: the whole RK4 loop inside CasADi vs Python-side loops.

Double pendulum of the quick start (``mbsym.demo.double_pendulum``, m1 = 2 kg,
m2 = 1 kg, l1 = 1 m, l2 = 0.5 m), released from q = (1.0, -0.5) rad at rest,
60 s. Rows:

- ``simulate(method="rk4")``, dt = 0.01 s: one ``Function.mapaccum`` of an RK4
  step (6000 steps); cold (building the Functions) and warm (cached);
- the same RK4 written as a Python loop calling ``eom.functions.rhs`` (4 calls
  per step, ~30 us each through CasADi's DM conversion);
- ``scipy.integrate.solve_ivp`` (RK45 and DOP853) on ``eom.functions.rhs``;
- ``simulate(method="cvodes")`` and ``simulate(method="scipy-radau")``.

Accuracy: max |q - q_ref| over the output grid (every 0.01 s), q_ref from DOP853
at rtol = atol = 1e-12. Wall times are medians of ``--repeat`` runs (one run
for rows slower than 1 s). Ratios are against the warm rk4 row of the same
run. Prints a Markdown table; measured numbers are never asserted anywhere.

Run: ``python benchmarks/simulate_basic.py [--repeat 5]``.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
from scipy.integrate import solve_ivp

from mbsym.demo import DEMO_PARAMETERS, double_pendulum
from mbsym.simulate import clear_cache, simulate

TMAX, DT = 60.0, 0.01
X0 = np.array([1.0, -0.5, 0.0, 0.0])


def _timed(fn, repeat: int):
    """Median wall time [s] of ``fn()`` and its last result (one run if the first takes > 1 s)."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
        if times[-1] > 1.0:
            break
    return statistics.median(times), out


def python_rk4(rhs, p, t):
    """Classical RK4 in a Python loop, one CasADi call per stage."""
    h = t[1] - t[0]
    X = np.empty((t.size, X0.size))
    X[0] = x = X0
    u = np.zeros(0)
    f = lambda x: np.asarray(rhs(x, u, p)).reshape(-1)   # noqa: E731
    for k in range(t.size - 1):
        k1 = f(x)
        k2 = f(x + h / 2 * k1)
        k3 = f(x + h / 2 * k2)
        k4 = f(x + h * k3)
        X[k + 1] = x = x + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return X


def main(repeat: int) -> list[dict]:
    eom = double_pendulum().equations()
    p = eom.parameter_vector(DEMO_PARAMETERS)
    rhs = eom.functions.rhs
    t = np.linspace(0.0, TMAX, int(round(TMAX / DT)) + 1)
    fun = lambda _t, x: np.asarray(rhs(x, [], p)).reshape(-1)   # noqa: E731
    ref = solve_ivp(fun, (0.0, TMAX), X0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t).y.T

    rows = []

    def add(name, wall, X, *, prepare=None, n_rhs=None):
        err = float(np.max(np.abs(X[:, :2] - ref[:, :2])))
        rows.append({"name": name, "wall": wall, "prepare": prepare, "n_rhs": n_rhs, "err": err})

    clear_cache()
    t0 = time.perf_counter()
    cold = simulate(eom, TMAX, X0, p=DEMO_PARAMETERS, method="rk4", dt=DT)
    add("simulate rk4, cold (build + run)", time.perf_counter() - t0, cold.x,
        prepare=cold.statistics["prepare_wall_s"], n_rhs=cold.statistics["n_rhs"])
    wall, warm = _timed(lambda: simulate(eom, TMAX, X0, p=DEMO_PARAMETERS, method="rk4", dt=DT), repeat)
    add("simulate rk4, warm (cached)", wall, warm.x, prepare=warm.statistics["prepare_wall_s"],
        n_rhs=warm.statistics["n_rhs"])
    wall, X = _timed(lambda: python_rk4(rhs, p, t), repeat)
    add("Python loop RK4 on eom.functions.rhs", wall, X, n_rhs=4 * (t.size - 1))
    for m, tol in (("RK45", 1e-8), ("DOP853", 1e-8)):
        wall, sol = _timed(lambda: solve_ivp(fun, (0.0, TMAX), X0, method=m, rtol=tol, atol=tol, t_eval=t), repeat)
        add(f"scipy solve_ivp {m} (rtol = atol = {tol:g})", wall, sol.y.T, n_rhs=sol.nfev)
    for m, tol in (("cvodes", 1e-8), ("scipy-radau", 1e-8)):
        simulate(eom, TMAX, X0, p=DEMO_PARAMETERS, method=m, rtol=tol, atol=tol, t_out=t)   # warm the cache
        wall, res = _timed(lambda: simulate(eom, TMAX, X0, p=DEMO_PARAMETERS, method=m, rtol=tol, atol=tol,
                                            t_out=t), repeat)
        add(f"simulate {m} (rtol = atol = {tol:g})", wall, res.x, prepare=res.statistics["prepare_wall_s"],
            n_rhs=res.statistics["n_rhs"])
    return rows


def table(rows: list[dict]) -> str:
    base = rows[1]["wall"]
    lines = ["| run (double pendulum, 60 s, output every 0.01 s) | wall [ms] | vs rk4 warm | rhs evals | "
             "prepare [ms] | max abs error q [rad] |",
             "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        prep = "—" if r["prepare"] is None else f"{r['prepare'] * 1e3:.2f}"
        n_rhs = "—" if r["n_rhs"] is None else f"{r['n_rhs']}"
        lines.append(f"| {r['name']} | {r['wall'] * 1e3:.1f} | {r['wall'] / base:.1f}× | {n_rhs} | {prep} | "
                     f"{r['err']:.1e} |")
    return "\n".join(lines)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per row (median)")
    print(table(main(parser.parse_args().repeat)))
