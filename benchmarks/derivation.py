"""Derivation speed: mbsym vs SymPy mechanics' KanesMethod on a 3-D N-link chain.

For N = 5, 10, 20, 40 links this measures, in one run on this machine:

- mbsym: time from an empty ``System`` to ready CasADi Functions (median of
  repeats), and the time of one M + F evaluation (CasADi virtual machine,
  averaged over many calls, Python call overhead included);
- SymPy: time of ``KanesMethod.kanes_equations`` plus extracting M and F on the
  same system, for N <= 10, in a subprocess with a time limit.

It prints a Markdown table with the ratios and writes it into
``benchmarks/README.md`` between the ``derivation`` markers.

Run: ``python benchmarks/derivation.py [--sympy-timeout 300] [--no-write]``.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import statistics
import time

import numpy as np
from _report import write_section

AXES = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (0.6, 0.8, 0.0)]
LINK = 1.0  # link length [m]


def link_properties(i: int) -> tuple[float, list[float], list[float]]:
    """Mass [kg], centre of mass [m] and inertia (Jxx, Jyy, Jzz, Jxy, Jyz, Jxz) [kg m^2] of link i."""
    return 1.0 + 0.1 * i, [0.1, 0.05, -0.5], [0.3, 0.4, 0.2, 0.01, 0.02, 0.03]


def build_mbsym(n: int):
    """The N-link chain in mbsym; returns the EquationsOfMotion."""
    import mbsym as mb

    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    qs = sys.coordinates([f"q{i}" for i in range(n)])
    qs = qs if isinstance(qs, tuple) else (qs,)
    parent = sys.ground
    for i in range(n):
        m, com, inertia = link_properties(i)
        body = mb.RigidBody(f"link{i}", mass=m, com=com, inertia=inertia)
        offset = [0.0, 0.0, -LINK] if i else [0.0, 0.0, 0.0]
        sys.add_joint(mb.Revolute(parent, body, axis=AXES[i % 4], coordinate=qs[i], offset=offset))
        parent = body
    return sys.equations()


def derive_sympy(n: int) -> float:
    """Time [s] of SymPy's KanesMethod on the same chain (M and F extracted)."""
    import sympy as sm
    import sympy.physics.mechanics as me

    t0 = time.perf_counter()
    q = me.dynamicsymbols(f"q0:{n}")
    u = me.dynamicsymbols(f"u0:{n}")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    frames, bodies, loads = [], [], []
    parent_frame, joint_point = N, O
    for i in range(n):
        m, com, J = link_properties(i)
        A = me.ReferenceFrame(f"A{i}")
        axis = sum((c * v for c, v in zip(AXES[i % 4], (parent_frame.x, parent_frame.y, parent_frame.z))),
                   sm.S(0) * parent_frame.x)
        norm = float(np.linalg.norm(AXES[i % 4]))
        A.orient_axis(parent_frame, axis / norm, q[i])
        A.set_ang_vel(parent_frame, u[i] * axis / norm)
        P = joint_point if i == 0 else joint_point.locatenew(f"P{i}", -LINK * parent_frame.z)
        if i:
            P.v2pt_theory(joint_point, N, parent_frame)
        G = P.locatenew(f"G{i}", com[0] * A.x + com[1] * A.y + com[2] * A.z)
        G.v2pt_theory(P, N, A)
        I = me.inertia(A, J[0], J[1], J[2], J[3], J[4], J[5])
        bodies.append(me.RigidBody(f"B{i}", G, A, m, (I, G)))
        loads.append((G, -m * 9.81 * N.z))
        frames.append(A)
        parent_frame, joint_point = A, P
    kde = [q[i].diff() - u[i] for i in range(n)]
    km = me.KanesMethod(N, q_ind=q, u_ind=u, kd_eqs=kde)
    km.kanes_equations(bodies, loads)
    _ = km.mass_matrix, km.forcing
    return time.perf_counter() - t0


def _sympy_worker(n: int, queue) -> None:
    queue.put(derive_sympy(n))


def time_sympy(n: int, timeout: float) -> float | None:
    """SymPy derivation time in a subprocess; None if it exceeds ``timeout`` [s]."""
    ctx = mp.get_context("spawn")
    queue = ctx.Queue()
    proc = ctx.Process(target=_sympy_worker, args=(n, queue))
    proc.start()
    proc.join(timeout)
    if proc.is_alive():
        proc.terminate()
        proc.join()
        return None
    return queue.get() if not queue.empty() else None


def time_mbsym(n: int) -> tuple[float, float, int, int]:
    """(derivation [s], one M+F evaluation [s], instructions of M, of F)."""
    repeats = 5 if n <= 20 else 2
    builds = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        eom = build_mbsym(n)
        builds.append(time.perf_counter() - t0)
    f = eom.functions
    rng = np.random.default_rng(0)
    q, qd = rng.normal(size=n), rng.normal(size=n)
    calls = 2000 if n <= 10 else 300
    f.mass_matrix(q, [])
    t0 = time.perf_counter()
    for _ in range(calls):
        f.mass_matrix(q, [])
        f.forcing(q, qd, [], [])
    t_eval = (time.perf_counter() - t0) / calls
    return statistics.median(builds), t_eval, f.mass_matrix.n_instructions(), f.forcing.n_instructions()


def run(sympy_timeout: float) -> str:
    rows = ["| N links | mbsym derivation [s] | one M+F eval [µs] | SX instructions M / F | "
            "SymPy KanesMethod [s] | speed-up |",
            "|---:|---:|---:|---:|---:|---:|"]
    for n in (5, 10, 20, 40):
        t_build, t_eval, n_m, n_f = time_mbsym(n)
        t_sym = time_sympy(n, sympy_timeout) if n <= 10 else None
        if n <= 10:
            sym = f"{t_sym:.2f}" if t_sym is not None else f"> {sympy_timeout:.0f} (stopped)"
            ratio = f"{t_sym / t_build:.0f}×" if t_sym is not None else f"> {sympy_timeout / t_build:.0f}×"
        else:
            sym, ratio = "not run (N > 10)", "—"
        rows.append(f"| {n} | {t_build:.4f} | {t_eval * 1e6:.0f} | {n_m} / {n_f} | {sym} | {ratio} |")
        print(rows[-1], flush=True)
    return "\n".join(rows)




def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sympy-timeout", type=float, default=300.0, help="time limit per SymPy run [s]")
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    args = parser.parse_args()
    print("3-D N-link chain, revolute joints with alternating axes, full inertia tensors\n")
    table = run(args.sympy_timeout)
    print("\n" + table)
    if not args.no_write:
        write_section("derivation", table)


if __name__ == "__main__":
    main()
