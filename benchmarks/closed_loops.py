"""Closed loops: what closing a loop costs, and how fast a 1-DOF four-bar simulates.

Models (rigid links, revolute joints about z, gravity -y):

- four-bar: crank 1, coupler 2, rocker 2, ground link 2.5 m (a Grashof crank–rocker); the loop
  (3 coordinates, 2 closure rows, 1 DOF, ``add_closure(..., directions="xy")``) against the same
  three bodies as a tree with the loop cut (the open 3-link chain, 3 DOF);
- five-bar: links 1, 2, 2, 1 m, ground link 2 m (``examples/five_bar_nmpc.py``); the loop (4
  coordinates, 2 rows, 2 DOF) against the open 4-link chain.

Columns: derivation = empty ``System`` → ready CasADi Functions (best of 7); SX instructions of
the first-order rhs; evaluation = one rhs evaluation, compiled (generated C, gcc -O1), measured over
a ``map`` of 20 000 points called through ``Function.buffer()`` (best of 7 calls), so that neither
Python's call overhead nor array conversions are counted. The
loop's rhs contains the dependent-coordinate solver besides the reduced Kane equations (four-bar:
the crank's Fourier predictor + 3 Newton steps; five-bar, two independent coordinates: 2
continuation stages, tangent predictor + 3 Newton steps each, 2 more at the end).

Real-time factor: the four-bar released at q1 = 0.3 rad, q1_d = 4 rad/s (the crank turns ~6 times in
10 s), ``mb.simulate(eom, 10.0, x0=..., compile=True)`` with its default output times (rk4 at three
steps; the accuracy-driven default); wall time of the whole call (checks, integration, outputs) =
best of 15 runs after a warm-up (the compiled library cached); real-time factor = 10 s / wall.
Accuracy: max |q1 - q1_ref| at the output times, q1_ref from CVODES at rtol 1e-12.

Run: ``python benchmarks/closed_loops.py`` (rewrites its section of benchmarks/README.md).
Numbers are measured, never asserted.
"""

from __future__ import annotations

import os
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import mbsym as mb                                                    # noqa: E402
from mbsym.codegen import compile_function                            # noqa: E402

from _report import write_section                                     # noqa: E402

FOUR = (1.0, 2.0, 2.0)
FIVE = (1.0, 2.0, 2.0, 1.0)
N_EVAL = 20000


def chain(lengths, closure=None, guess=None, independent=None, **options):
    """Open chain of links from the ground origin; ``closure``: the ground point its tip closes on."""
    s = mb.System(gravity=[0.0, -9.81, 0.0])
    qs = s.coordinates([f"q{i + 1}" for i in range(len(lengths))])
    parent, offset = s.ground, [0.0, 0.0, 0.0]
    for i, (q, l) in enumerate(zip(qs, lengths)):
        body = mb.RigidBody(f"link{i + 1}", 1.0, com=[l / 2, 0, 0], inertia=np.diag([0.01, 0.1, 0.1]))
        s.add_joint(mb.Revolute(parent, body, axis=[0, 0, 1], coordinate=q, offset=offset))
        parent, offset = body, [l, 0.0, 0.0]
    if closure is None:
        return s.equations()
    s.add_closure(parent, [lengths[-1], 0, 0], s.ground, [closure, 0, 0], directions="xy")
    return s.equations(independent=independent, guess=guess, **options)


CASES = {
    "four-bar": (lambda: chain(FOUR, 2.5, {"q2": 1.2, "q3": -2.4}, ["q1"]), lambda: chain(FOUR)),
    "five-bar": (lambda: chain(FIVE, 2.0, {"q1": 1.2, "q2": -0.6, "q3": -1.6, "q4": -1.0}, ["q1", "q4"]),
                 lambda: chain(FIVE)),
}


def best_time(fn, repeat=7):
    """Shortest wall time [s] of ``repeat`` runs (the machine is shared: the minimum is the least disturbed)."""
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def eval_cost(eom) -> float:
    """Seconds per compiled rhs evaluation: a map over N_EVAL points called through its buffer (no copies)."""
    g = compile_function(eom.functions.rhs.map(N_EVAL, "serial")).function
    rng = np.random.default_rng(0)
    X = rng.uniform(-0.3, 0.3, (N_EVAL, eom.n_x))            # row-major (N, n) is CasADi's (n, N)
    X[:, : eom.n_q] += eom.default_state()[: eom.n_q] if hasattr(eom, "default_state") else 0.0
    U = np.zeros(N_EVAL * eom.n_u)
    P = np.tile(eom.parameter_vector(), N_EVAL)
    Y = np.zeros(N_EVAL * eom.n_x)
    buf, trigger = g.buffer()
    for i, a in enumerate((X.reshape(-1), U, P)):
        buf.set_arg(i, memoryview(a))
    buf.set_res(0, memoryview(Y))
    trigger()
    return best_time(trigger)[0] / N_EVAL


def cost_rows() -> list[str]:
    rows = []
    for name, (loop, tree) in CASES.items():
        t_loop, eom_loop = best_time(loop)
        t_tree, eom_tree = best_time(tree)
        e_loop, e_tree = eval_cost(eom_loop), eval_cost(eom_tree)
        n_loop, n_tree = eom_loop.functions.rhs.n_instructions(), eom_tree.functions.rhs.n_instructions()
        rows.append(f"| {name} | {t_loop * 1e3:.1f} / {t_tree * 1e3:.1f} | {t_loop / t_tree:.1f}× | "
                    f"{n_loop} / {n_tree} | {e_loop * 1e9:.0f} / {e_tree * 1e9:.0f} | {e_loop / e_tree:.1f}× |")
    return rows


def rtf_rows() -> list[str]:
    eom = CASES["four-bar"][0]()
    x0 = {"q1": 0.3, "q1_d": 4.0}
    rows = []
    runs = [("rk4, dt = 10 ms", dict(method="rk4", dt=0.01)), ("rk4, dt = 5 ms", dict(method="rk4", dt=0.005)),
            ("rk4, dt = 1 ms", dict(method="rk4", dt=0.001)), ("default (accuracy-driven)", {})]
    for label, kw in runs:
        def run(kw=kw):
            return mb.simulate(eom, 10.0, x0=x0, compile=True, **kw)
        run()
        wall, res = best_time(run, 15)
        ref = mb.simulate(eom, 10.0, x0=x0, method="cvodes", rtol=1e-12, atol=1e-12, t_out=res.t)
        err = np.max(np.abs(res.state("q1") - ref.state("q1")))
        rows.append(f"| {label} | {res.t.size} | {wall * 1e3:.2f} | {10.0 / wall:,.0f}× | {err:.1e} |")
    return rows


def main() -> None:
    header = ("| model | derivation loop / tree [ms] | ratio | rhs SX instructions loop / tree | "
              "one rhs eval loop / tree, compiled [ns] | ratio |")
    cost = [header, "|---|---:|---:|---:|---:|---:|", *cost_rows()]
    rtf = ["| four-bar, 10 s, compile=True | output samples | wall [ms] | real-time factor | max abs error q1 [rad] |",
           "|---|---:|---:|---:|---:|", *rtf_rows()]
    load = os.getloadavg()[0]
    table = "\n".join(cost) + "\n\n" + "\n".join(rtf) + f"\n\nLoad average during the run: {load:.1f} (2 cores)."
    print(table)
    write_section("closed-loops", table)


if __name__ == "__main__":
    main()
