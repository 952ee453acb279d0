"""Cost of the blade-element operating turbine: per right-hand-side evaluation, per blade node, per DOF.

Compiled right-hand sides (``mbsym.codegen``, gcc -O1), timed through ``Function.buffer`` (no Python
conversions), median of repeated batches. Models from the shared ``ff14_flex`` deck (NREL 5 MW, 3 x 19 AeroDyn
nodes, DBEMT) with growing DOF sets; the baseline in the same run is the rotor-effective model of the same
deck (Cp/Ct surfaces, rotor-averaged DBEMT) with the rigid-blade DOFs. Also the aerodynamic Function alone
(every node's kinematics, wind, BEM with DBEMT, loads) and the structure's M and F alone.

    python benchmarks/blade_speed.py [--no-write]
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from _report import write_section  # noqa: E402

INPUTS = next((p / "shared" / "openfast" / "aero" / "openfast_inputs" for p in HERE.parents
               if (p / "shared" / "openfast" / "aero").is_dir()), None)
DOF_SETS = {
    "rigid (GenDOF, TwFA1, TwSS1)": ("GenDOF", "TwFADOF1", "TwSSDOF1"),
    "+ flap 1, edge": ("GenDOF", "TwFADOF1", "TwSSDOF1", "FlapDOF1", "EdgeDOF"),
    "ff14_flex (+ flap 2, drivetrain, tower 2)": None,
}


def per_call_us(f, args, batches: int = 7, n: int = 400, clock=time.perf_counter) -> float:
    """Median time of one call [µs] through the Function's buffer (``clock``: wall, or e.g. process CPU time)."""
    args = [np.ascontiguousarray(np.asarray(a, dtype=float).ravel()) for a in args]
    outs = [np.empty(f.numel_out(i)) for i in range(f.n_out())]
    buf, trigger = f.buffer()
    for i, a in enumerate(args):
        buf.set_arg(i, memoryview(a))
    for i, o in enumerate(outs):
        buf.set_res(i, memoryview(o))
    trigger()
    times = []
    for _ in range(batches):
        t0 = clock()
        for _ in range(n):
            trigger()
        times.append((clock() - t0) / n * 1e6)
    return float(np.median(times))


def point(model, wind: dict):
    from mbsym.wind.operation.controllers import held_commands

    d = model.dynamics()
    x = model.initial_state(wind)
    return d, x, d.input_vector({**wind, **held_commands(model, x)}), d.parameter_vector()


def aero_arguments(model, d, x) -> list:
    """Arguments of the model's ``blade_aero`` Function at the state ``x`` (no structural inputs, the field's 30 s)."""
    eom = model.structure.eom
    names = list(d.states)
    return [x[:eom.n_q], x[eom.n_q:2 * eom.n_q], np.zeros(len(eom.inputs)),
            np.array([dict(eom.defaults)[n] for n in eom.parameters]),
            x[[names.index(s) for s in model.rotor.state_names]], np.array([30.0]), np.array([1.225])]


def flex_deck(description: str):
    """``(--no-write flag, the shared ff14_flex OperatingDeck)`` from the command line of a benchmark."""
    from mbsym.wind.operation.deck import operating_deck

    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    if INPUTS is None:
        raise SystemExit("shared/openfast/aero not found")
    return args.no_write, operating_deck(INPUTS / "ff14_flex" / "ff14_flex.fst")


def main() -> None:
    from mbsym import codegen

    no_write, deck = flex_deck(__doc__.splitlines()[0])
    rows = []
    base = replace(deck, inflow=None).model(aero="rotor", dofs=DOF_SETS["rigid (GenDOF, TwFA1, TwSS1)"])
    d, x, u, p = point(base, {"Wind1VelX": 14.0})
    baseline = per_call_us(codegen.compile_function(d.rhs).function, (x, u, p))
    rows.append(("rotor-effective, rigid (baseline)", len(d.states), base.structure.eom.n_q, 0, baseline, None, None))
    for label, dofs in DOF_SETS.items():
        model = deck.model(aero="blade", dofs=dofs)
        t0 = time.perf_counter()
        d, x, u, p = point(model, {"WindTime": 30.0})
        build = time.perf_counter() - t0
        t0 = time.perf_counter()
        rhs = codegen.compile_function(d.rhs).function
        compile_s = time.perf_counter() - t0
        total = per_call_us(rhs, (x, u, p))
        aero = model._parts["blade_aero"]
        eom = model.structure.eom
        a_in = aero_arguments(model, d, x)
        aero_us = per_call_us(codegen.compile_function(aero).function, a_in)
        m_f = per_call_us(codegen.compile_function(eom.functions.mass_matrix).function,
                          (a_in[0], a_in[2], a_in[3]) if eom.functions.mass_matrix.n_in() == 3 else (a_in[0], a_in[3]))
        m_f += per_call_us(codegen.compile_function(eom.functions.forcing).function, a_in[:4])
        nodes = model.rotor.n_blades * model.rotor.n_nodes
        rows.append((f"blade-element, {label}", len(d.states), eom.n_q, nodes, total, aero_us, m_f,
                     build, compile_s))
        print(rows[-1], flush=True)
    table = ["| model | states | DOFs | nodes | rhs [µs] | vs baseline | aero [µs] (per node) | M + F [µs] "
             "(per DOF) | build + compile [s] |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        label, ns, nq, nodes, total = r[:5]
        if r[5] is None:
            table.append(f"| {label} | {ns} | {nq} | — | {total:.1f} | 1.0× | — | — | — |")
            continue
        aero_us, m_f, build, compile_s = r[5:]
        table.append(f"| {label} | {ns} | {nq} | {nodes} | {total:.1f} | {total / baseline:.0f}× | "
                     f"{aero_us:.1f} ({aero_us / nodes:.2f}) | {m_f:.1f} ({m_f / nq:.2f}) | "
                     f"{build:.1f} + {compile_s:.0f} |")
    text = "\n".join(table)
    print(text)
    if not no_write:
        write_section("blade-speed", text)


if __name__ == "__main__":
    main()
