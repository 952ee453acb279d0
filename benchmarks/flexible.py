"""Derivation and evaluation speed of the paper's flexible turbine models.

- 2-DOF: tower fore-aft + azimuth (paper Sect. 4.4, ``examples/paper_4_4_two_dof.py``);
- 3-DOF: tower fore-aft + side-side + azimuth (paper Sect. 4.5).

For each: time from an empty System to ready CasADi Functions (median of 7, the
beam preprocessing excluded and timed separately), and one M + F evaluation
(CasADi virtual machine, Python call overhead included). Same-run baseline:
the rigid double pendulum of the quick start. Quoted reference: the SymPy
implementation of the paper needs about 8 s for the 3-DOF model (issue text;
not measured here). Prints a Markdown table and writes it into
``benchmarks/README.md`` between the ``flexible`` markers.

Run: ``python benchmarks/flexible.py [--no-write]``.
"""

from __future__ import annotations

import argparse
import importlib.util
import statistics
import time
from pathlib import Path

import numpy as np
from _report import write_section

import mbsym as mb
from mbsym.beam import PolynomialShape, shape_integrals
from mbsym.demo import double_pendulum

HERE = Path(__file__).resolve().parent
_spec = importlib.util.spec_from_file_location("paper44", HERE.parent / "examples" / "paper_4_4_two_dof.py")
paper44 = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(paper44)
SYMPY_3DOF_S = 8.0   # quoted: SymPy implementation of the paper, 3-DOF model


def tower_sid_fa_ss():
    """NREL 5 MW tower with its first fore-aft and side-side ElastoDyn shapes."""
    t = paper44.nrel5mw()
    length = t.tower_height - t.tower_base_height
    z = np.asarray(t.tower.station_fraction) * length
    shapes = [PolynomialShape(t.tower.fa_mode_shapes[0], length, direction="x"),
              PolynomialShape(t.tower.ss_mode_shapes[0], length, direction="y")]
    return shape_integrals(z, t.tower.mass_density, t.tower.fa_stiffness, t.tower.ss_stiffness, shapes,
                           quadrature="simpson", n_points=400), length


def build_3dof(sid, length):
    sys = mb.System(gravity=[0.0, 0.0, -paper44.G])
    q1, q2, psi = sys.coordinates("q1 q2 psi")
    tower = mb.FlexibleBody("tower", sid, [q1, q2], top_mass=paper44.M_RNA, end_rotation_order=2)
    nacelle = mb.RigidBody("nacelle", mass=paper44.M_N, com=[paper44.X_NG, 0, paper44.Z_NG],
                           inertia=[0, paper44.JY_N, 0])
    rotor = mb.RigidBody("rotor", mass=paper44.M_R, inertia=[paper44.JX_R, paper44.JO_R, paper44.JO_R])
    sys.add_joint(mb.Fixed(sys.ground, tower))
    sys.add_joint(mb.Fixed(tower, nacelle, offset=[0, 0, length]))
    sys.add_joint(mb.Revolute(nacelle, rotor, axis=[1, 0, 0], coordinate=psi,
                              offset=[paper44.X_NR, 0, paper44.Z_NR], rotation=mb.rotation("y", paper44.TILT)))
    return sys.equations()


def _time(fn, repeats=7):
    out = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        res = fn()
        out.append(time.perf_counter() - t0)
    return statistics.median(out), res


def _eval_time(eom, calls=3000):
    f = eom.functions
    n = eom.n_q
    q, qd = np.full(n, 0.1), np.full(n, 0.2)
    t0 = time.perf_counter()
    for _ in range(calls):
        f.mass_matrix(q, [])
        f.forcing(q, qd, [], [])
    return (time.perf_counter() - t0) / calls


def run() -> str:
    t_pre2, (sid2, len2) = _time(paper44.tower_sid)
    t_pre3, (sid3, len3) = _time(tower_sid_fa_ss)
    t_dp, eom_dp = _time(lambda: double_pendulum().equations())
    t2, eom2 = _time(lambda: paper44.build()[0].equations())
    t3, eom3 = _time(lambda: build_3dof(sid3, len3))
    rows = ["| model | beam preprocessing [ms] | derivation → Functions [ms] | one M+F eval [µs] | "
            "vs double pendulum (derivation) | vs SymPy ≈ 8 s (quoted) |",
            "|---|---:|---:|---:|---:|---:|"]
    for name, pre, t, eom in [("rigid double pendulum (baseline)", 0.0, t_dp, eom_dp),
                              ("2-DOF FA + azimuth (Sect. 4.4)", t_pre2, t2, eom2),
                              ("3-DOF FA + SS + azimuth (Sect. 4.5)", t_pre3, t3, eom3)]:
        quoted = f"{SYMPY_3DOF_S / t:.0f}× faster" if "3-DOF" in name else "—"
        rows.append(f"| {name} | {pre * 1e3:.1f} | {t * 1e3:.1f} | {_eval_time(eom) * 1e6:.0f} | "
                    f"{t / t_dp:.1f}× | {quoted} |")
    return "\n".join(rows)




def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    args = parser.parse_args()
    table = run()
    print(table)
    if not args.no_write:
        write_section("flexible", table)


if __name__ == "__main__":
    main()
