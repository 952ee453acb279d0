"""Linearization speed: single calls and batches of N = 10 000 operating points.

Models (built-in NREL 5 MW, ElastoDyn-equivalent templates):

- the paper45 model (TFA1, TSS1, GeAz; the shared ``paper45_fa_ss_gen`` decks are this base
  deck with these DOFs);
- 7 DOFs onshore with rigid blades: tower FA/SS modes 1-2, yaw (NREL 5 MW yaw spring), generator
  azimuth, drivetrain torsion;
- 16 DOFs onshore: the same plus the 9 blade DOFs (flap 1, edge 1, flap 2 per blade), when the
  template models flexible blades (otherwise a TODO row).

Measured: time to build the linearization Function from ready equations
(:func:`mbsym.linear.linear_function`); one ``mbsym.linearize(model)`` call from Python
(median of repeated calls; M, C, K, Q, A, B with the model's defaults); one
:func:`mbsym.linear.linearize_batch` of N = 10 000 operating points (initial state plus a small
random perturbation) in CasADi's virtual machine (``map``, serial) and compiled
(``compile=True``: generated C, gcc -O1; the cold compile time with an empty cache is listed
separately, the batch time is a warm call). Aim (issue): 10 000 batched linearizations of the
paper45 model in under 1 s.

Run: ``python benchmarks/linearization.py [--no-write] [--n N]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time

import numpy as np

from _report import README, write_section

from mbsym.cli.simulate import NREL5MW_YAW_DAMPING, NREL5MW_YAW_SPRING
from mbsym.exceptions import ModelDefinitionError
from mbsym.linear import linear_function, linearize, linearize_batch
from mbsym.wind import nrel5mw
from mbsym.wind.structure.turbine import TurbineModel

ONSHORE_7 = ["TwFADOF1", "TwSSDOF1", "TwFADOF2", "TwSSDOF2", "YawDOF", "GenDOF", "DrTrDOF"]
BLADES = ["FlapDOF1", "EdgeDOF", "FlapDOF2"]
HEADING = """
## Linearization (`linearization.py`)

`mbsym.linearize` (M, C, K, Q, A, B by automatic differentiation of the residual, paper Sect. 2.5)
and `mbsym.linear.linearize_batch` (one CasADi `map` over the same Function) on built-in NREL 5 MW
templates. Build = ready equations → linearization Function; single = one `linearize(model)` call
from Python; batch = N = 10 000 operating points in one call, in CasADi's virtual machine (VM) and
compiled (generated C, gcc -O1, cached on disk; cold compile time listed separately). Aim (issue):
10 000 batched linearizations of the paper45 model in under 1 s.
"""


def _model(dofs):
    return TurbineModel(nrel5mw(), dofs=dofs, yaw_spring=NREL5MW_YAW_SPRING, yaw_damping=NREL5MW_YAW_DAMPING)


def measure(name: str, dofs, n: int) -> dict | str:
    try:
        model = _model(dofs)
        eom = model.eom
    except ModelDefinitionError as exc:
        return f"| {name} | — | TODO: not buildable yet ({str(exc).split(';')[0]}) | | | | |"
    t0 = time.perf_counter()
    linear_function(eom)
    build = time.perf_counter() - t0
    linearize(model)
    calls = []
    for _ in range(7):
        t0 = time.perf_counter()
        for _ in range(20):
            linearize(model)
        calls.append((time.perf_counter() - t0) / 20)
    single = statistics.median(calls)
    rng = np.random.default_rng(0)
    X = model.initial_state() + rng.normal(scale=1e-3, size=(n, eom.n_x))
    t0 = time.perf_counter()
    linearize_batch(model, X)
    vm = time.perf_counter() - t0
    with tempfile.TemporaryDirectory() as cache:
        old = os.environ.get("MBSYM_CACHE_DIR")
        os.environ["MBSYM_CACHE_DIR"] = cache
        try:
            t0 = time.perf_counter()
            linearize_batch(model, X[:2], compile=True)
            cold = time.perf_counter() - t0
            t0 = time.perf_counter()
            linearize_batch(model, X, compile=True)
            warm = time.perf_counter() - t0
        finally:
            if old is None:
                os.environ.pop("MBSYM_CACHE_DIR", None)
            else:
                os.environ["MBSYM_CACHE_DIR"] = old
    return {"name": name, "n_q": eom.n_q, "build": build, "single": single, "vm": vm, "compiled": warm, "cold": cold}


def tables(n: int) -> str:
    rows = [measure("paper45 model: TFA1, TSS1, GeAz", ["TwFADOF1", "TwSSDOF1", "GenDOF"], n),
            measure("7 DOFs onshore, rigid blades: tower 4, yaw, generator, drivetrain", ONSHORE_7, n),
            measure("16 DOFs onshore: tower 4, yaw, generator, drivetrain, 9 blade", ONSHORE_7 + BLADES, n)]
    out = [f"| model | n_q | build [s] | single linearize() [µs] (per s) | batch N = {n} VM [s] (per s) "
           f"| batch N = {n} compiled [s] (per s) | compile, cold cache [s] |",
           "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        if isinstance(r, str):
            out.append(r)
            continue
        out.append(f"| {r['name']} | {r['n_q']} | {r['build']:.2f} | {1e6 * r['single']:.0f} ({1 / r['single']:.0f}) "
                   f"| {r['vm']:.2f} ({n / r['vm']:.0f}) | {r['compiled']:.3f} ({n / r['compiled']:.0f}) "
                   f"| {r['cold']:.1f} |")
    out.append("")
    out.append("The 16-DOF row needs the flexible-blade template (FlapDOF1, EdgeDOF, FlapDOF2); when the template "
               "cannot build it, the script writes a TODO row instead. Rerun after template changes.")
    return "\n".join(out)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--no-write", action="store_true", help="print only; do not rewrite benchmarks/README.md")
    ap.add_argument("--n", type=int, default=10_000, help="batch size (default 10 000)")
    args = ap.parse_args()
    table = tables(args.n)
    print(table)
    if not args.no_write:
        if "<!-- linearization:start -->" not in README.read_text():
            README.write_text(README.read_text().rstrip("\n") + "\n" + HEADING)
        write_section("linearization", table)
        print(f"wrote {README}")


if __name__ == "__main__":
    main()
