"""Build and evaluation speed of turbine models with flexible blades; Campbell diagram wall time.

Models (NREL 5 MW data, ``mbsym.wind.deck.nrel5mw``; deck already read):

- 22 DOFs: ElastoDyn's whole set, platform 6 (paper46 spar values), tower 4, yaw, generator,
  drivetrain, 3 x 3 blade DOFs (FlapDOF1, EdgeDOF, FlapDOF2);
- 16 DOFs: the onshore set, tower 4, yaw, generator, drivetrain, 9 blade DOFs;
- 9 DOFs: three blades on a hub turning through a prescribed azimuth (blade_campbell);
- 13 DOFs, rigid blades (platform, tower, yaw, drivetrain): same-run baseline.

For each: build time from TurbineParameters to ready CasADi Functions (``TurbineModel(...).eom``,
median of 5), one M + F evaluation (CasADi virtual machine, Python call overhead included,
median over 2000 calls) and the SX instruction counts of M and F. Campbell: ``campbell()``
at 6 speeds x 12 azimuths (72 linearizations), model build included. Quoted reference (issue
text, not measured here): the SymPy implementation needs 332 s for a 7-DOF model. Prints a
Markdown table and writes it into ``benchmarks/README.md`` between the ``blades`` markers.

Run: ``python benchmarks/blades.py [--no-write]``.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import time
from pathlib import Path

import numpy as np
from _report import README, write_section

from mbsym.wind import nrel5mw, read_openfast
from mbsym.wind.analysis.campbell_diagram import campbell
from mbsym.wind.structure.turbine import MODELLED_DOFS, SUPPORTED_DOFS, TurbineModel

HERE = Path(__file__).resolve().parent
DECK = HERE.parent.parent / "shared" / "openfast" / "cases" / "blade_campbell" / "blade_campbell_rpm00.fst"
SYMPY_7DOF_S = 332.0      # quoted: SymPy implementation, 7-DOF model (issue text)
RPM = [0, 3, 6, 9, 12, 15]
HEADING = """
## Flexible blades and ElastoDyn's whole DOF set (`blades.py`)

Turbine templates with flexible blades (FlapDOF1, EdgeDOF, FlapDOF2 per blade) built from the NREL 5 MW
data: build = TurbineParameters → ready CasADi Functions (`TurbineModel(...).eom`, one derivation, one
CSE; median of 5); one M + F evaluation in CasADi's virtual machine, Python call overhead included;
SX instruction counts of M and F. Campbell = `mbsym.wind.campbell` at 6 rotor speeds × 12 azimuths
(72 linearizations, MBC, labelling), model build included. Baseline in the same run: the 13-DOF
rigid-blade model. Aim (issue): the 22-DOF model ready in < 2 s; the SymPy implementation needs
332 s for a 7-DOF model (quoted, not re-measured).
"""


def _floating(t):
    return dataclasses.replace(t, platform_mass=7.5e6, platform_roll_inertia=4.2e9, platform_pitch_inertia=4.2e9,
                               platform_yaw_inertia=1.6e8, platform_cm=(0.0, 0.0, -90.0),
                               platform_reference=(0.0, 0.0, 20.0), tower_base_height=20.0)


def _median_time(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def measure(name: str, turbine, dofs, **kw) -> dict:
    build = _median_time(lambda: TurbineModel(turbine, dofs=dofs, **kw).eom, repeats=5)
    eom = TurbineModel(turbine, dofs=dofs, **kw).eom
    f = eom.functions
    q, qd, u, p = np.zeros(eom.n_q), np.zeros(eom.n_q), np.zeros(eom.n_u), eom.parameter_vector({})
    presc = bool(eom.prescribed)

    def mf():
        f.mass_matrix(q, u, p) if presc else f.mass_matrix(q, p)
        f.forcing(q, qd, u, p)

    for _ in range(50):
        mf()
    calls = []
    for _ in range(20):
        t0 = time.perf_counter()
        for _ in range(100):
            mf()
        calls.append((time.perf_counter() - t0) / 100)
    return {"name": name, "n_q": eom.n_q, "build_s": build, "mf_us": 1e6 * statistics.median(calls),
            "instr_M": f.mass_matrix.n_instructions(), "instr_F": f.forcing.n_instructions()}


def campbell_time(turbine) -> float:
    t0 = time.perf_counter()
    campbell(turbine, RPM)
    return time.perf_counter() - t0


def tables() -> str:
    t = nrel5mw()
    rows = [
        measure("22 DOFs: platform 6, tower 4, yaw, generator, drivetrain, 9 blade", _floating(t), list(MODELLED_DOFS)),
        measure("16 DOFs onshore: tower 4, yaw, generator, drivetrain, 9 blade", t,
                [f for f in MODELLED_DOFS if not f.startswith("Ptfm")]),
        measure("9 blade DOFs on a prescribed-azimuth hub", t, ["FlapDOF1", "EdgeDOF", "FlapDOF2"],
                prescribed_azimuth=True),
        measure("13 DOFs, rigid blades (baseline)", _floating(t), list(SUPPORTED_DOFS)),
    ]
    base = rows[-1]["build_s"]
    out = ["| model | n_q | build [s] | vs 13-DOF rigid-blade build | one M+F eval [µs] | SX instructions M / F "
           "| vs SymPy 7-DOF 332 s (quoted) |", "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['name']} | {r['n_q']} | {r['build_s']:.3f} | {r['build_s'] / base:.1f}× | {r['mf_us']:.0f} "
                   f"| {r['instr_M']} / {r['instr_F']} | {SYMPY_7DOF_S / r['build_s']:.0f}× faster |")
    out += ["", "| Campbell diagram (6 speeds × 12 azimuths, build included) | n_q | wall [s] |", "|---|---:|---:|"]
    if DECK.exists():
        out.append(f"| blade_campbell deck (9 blade DOFs, hub held) | 9 | {campbell_time(read_openfast(DECK)):.2f} |")
    out.append(f"| NREL 5 MW onshore (16 DOFs, free generator) | 16 | {campbell_time(t):.2f} |")
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--no-write", action="store_true", help="print only; do not rewrite benchmarks/README.md")
    args = ap.parse_args()
    table = tables()
    print(table)
    if not args.no_write:
        if "<!-- blades:start -->" not in README.read_text():
            README.write_text(README.read_text().rstrip("\n") + "\n" + HEADING)
        write_section("blades", table)
        print(f"wrote {README}")


if __name__ == "__main__":
    main()
