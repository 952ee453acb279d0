"""AeroDyn's unsteady airfoil aerodynamics (UA_Mod 3) on the blade-element rotor: cost and accuracy side by side.

The IEA 15 MW rotor of the shared floating deck (``shared/openfast/floating``: 50 nodes per blade, UA on nodes 5-50)
with and without UA, measured in the same run:

* cost of the rotor's aerodynamics (every node of the three blades as one SX Function): instructions, build time,
  evaluation time in CasADi's virtual machine (the baseline is the same rotor without UA);
* accuracy of the recursion against OpenFAST v5.0.0's node outputs (``tests/data/openfast_ua_nodes``: tower
  passage, 1P shear and a pitch ramp; OpenFAST's own angle of attack and speed drive mbsym's recursion): per node
  the largest Cl error and the RMS error over the RMS of UA's own effect (static polars in its place: ratio 1).

With ``--run`` it also simulates the shared ``fl_steady_13`` deck as written (600 s, the baseline controller, from
the CLI) and the same deck with ``UA_Mod`` 0 at the same step, and prints the run times and the rotor's tilt-moment
1P against OpenFAST's (a first run compiles the loop: minutes; the compiled loops are cached on disk).

    python benchmarks/blade_unsteady.py [--calls 20] [--run]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import re
import shutil
import sys
import tempfile
import time
import warnings
from pathlib import Path

import casadi as ca
import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
FLOATING = HERE.parent.parent / "shared" / "openfast" / "floating"
FST = FLOATING / "cases" / "fl_steady_13" / "fl_steady_13.fst"
DATA = HERE.parent / "tests" / "data" / "openfast_ua_nodes"


def _rotor_function(rot):
    n = rot.n_blades * rot.n_nodes
    syms = [ca.SX.sym(k, n) for k in ("vx", "vy", "r", "theta")]
    states = ca.SX.sym("x", len(rot.state_names))
    out = rot.evaluate(*syms, np.zeros(rot.n_blades), states, rho=1.225)
    return ca.Function("rotor", [*syms, states], [out["fn"], out["ft"], out["m"], out["states_dot"]])


def cost(calls: int) -> None:
    from mbsym.wind.aero.blade import BladeElementRotor

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with_ua = BladeElementRotor.from_openfast(FST)
    rows = []
    for name, rot in (("without UA (baseline)", dataclasses.replace(with_ua, unsteady=None)), ("UA_Mod 3", with_ua)):
        t0 = time.perf_counter()
        f = _rotor_function(rot)
        build = time.perf_counter() - t0
        n = rot.n_blades * rot.n_nodes
        r = np.tile(np.asarray(rot.local_radius), rot.n_blades)
        args = [np.full(n, 11.0), 0.79 * r, r, np.radians(np.tile(np.degrees(rot.twist), rot.n_blades) + 8.0)]
        x = rot.steady_states(*args)
        f(*args, x)
        t0 = time.perf_counter()
        for _ in range(calls):
            f(*args, x)
        rows.append((name, len(rot.state_names), f.n_instructions(), build, (time.perf_counter() - t0) / calls))
    base = rows[0]
    print(f"{'rotor (IEA 15 MW, 150 nodes)':24s} {'states':>7s} {'instructions':>13s} {'build s':>8s} "
          f"{'VM call ms':>11s} {'ratio':>6s}")
    for name, ns, ni, b, c in rows:
        print(f"{name:24s} {ns:7d} {ni:13d} {b:8.2f} {1e3 * c:11.2f} {c / base[4]:6.2f}")


def accuracy() -> None:
    from mbsym.wind.aero.blade import BladeElementRotor
    from mbsym.wind.aero.blade import unsteady as ua

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rot = BladeElementRotor.from_openfast(FST, polar_method="linear")
    nodes = [n["aerodyn_node"] for n in json.loads((DATA / "nodes.json").read_text())["nodes"]]
    u = rot.unsteady
    k = [list(u.index).index(n - 1) for n in nodes]
    sub = dataclasses.replace(u, chord=u.chord[k], params={a: v[k] for a, v in u.params.items()}, index=u.index[k],
                              node=u.node[k])
    static = rot._static_polars(sub)
    m = sub.size
    a, s, z = ca.SX.sym("a", m), ca.SX.sym("u", m), ca.SX.sym("z", len(ua.STATE_SUFFIXES) * m)
    au, su = ca.SX.sym("au", m), ca.SX.sym("su", m)
    out = ua.kelvin_chain(sub, a, s, z, static, lambda x: static(x)["cm"], (au, su))
    step = ca.Function("step", [a, s, z, au, su], [out["next"], out["cl"]])
    rest = ca.Function("rest", [a, s], [ua.steady_states(sub, a, s, static)])
    print(f"\nUA_Mod 3 against OpenFAST v5.0.0 (blade-1 nodes {nodes}), t >= 1 s; the update's inputs as AeroDyn v5 "
          "(the wind of the step's end) or as the outputs'")
    for case in ("ua3_steady", "ua3_pitch"):
        rows = list(csv.reader((DATA / f"{case}.csv").open()))
        col = {h: np.array([float(r[i]) for r in rows[1:]]) for i, h in enumerate(rows[0])}
        alpha = np.column_stack([np.radians(col[f"AB1N{n:03d}Alpha_[deg]"]) for n in nodes])
        speed = np.column_stack([col[f"AB1N{n:03d}VRel_[m/s]"] for n in nodes])
        ref = np.column_stack([col[f"AB1N{n:03d}Cl_[-]"] for n in nodes])
        rows = list(csv.reader((DATA / f"{case}_update.csv").open()))
        upd = {h: np.array([float(r[i]) for r in rows[1:]]) for i, h in enumerate(rows[0])}
        d_alpha = np.column_stack([np.radians(upd[f"AB1N{n:03d}dAlphaUpd_[deg]"]) for n in nodes])
        d_speed = np.column_stack([upd[f"AB1N{n:03d}dVRelUpd_[m/s]"] for n in nodes])
        st = np.column_stack([rot.polars.numeric(alpha[:, j], int(sub.node[j]))["cl"] for j in range(m)])
        w = slice(40, None)
        print(f"  {case:11s} UA effect      " + " ".join(f"{v:.1e}" for v in np.abs(ref[w] - st[w]).max(0)))
        for label, scale in (("step-end wind", 1.0), ("outputs' wind", 0.0)):
            ours = np.full_like(ref, np.nan)
            state = rest(alpha[1] + scale * d_alpha[1], speed[1] + scale * d_speed[1])
            for i in range(2, len(alpha)):
                state, cl = step(alpha[i], speed[i], state, alpha[i] + scale * d_alpha[i],
                                 speed[i] + scale * d_speed[i])
                ours[i] = np.asarray(cl).ravel()
            print(f"  {'':11s} {label:14s} " + " ".join(f"{v:.1e}" for v in np.abs(ours[w] - ref[w]).max(0)))


def runs() -> None:
    from mbsym.cli import main
    from mbsym.wind.analysis.compare import read_csv

    tmp = Path(tempfile.mkdtemp())
    for name in ("IEA-15-240-RWT", "IEA-15-240-RWT-UMaineSemi", "cases"):
        shutil.copytree(FLOATING / name, tmp / name)
    aerodyn = tmp / "IEA-15-240-RWT-UMaineSemi" / "IEA-15-240-RWT-UMaineSemi_AeroDyn15.dat"
    aerodyn.write_text(re.sub(r"^\S+(\s+UA_Mod\s)", r"0\1", aerodyn.read_text(), count=1, flags=re.M))
    ref = read_csv(FLOATING / "fl_steady_13.csv")
    tr = np.asarray(ref.time)
    print(f"\nfl_steady_13, 600 s, baseline controller; OpenFAST's tilt-moment 1P "
          f"{np.asarray(ref.channel('RtFldMyh'))[tr >= 100].std() / 1e6:.3f} MN m (UA_Mod 3)")
    for label, fst, extra in (("UA_Mod 0 (baseline)", tmp / "cases" / "fl_steady_13" / "fl_steady_13.fst",
                               ["--aero-dt", "0.025", "--aero-order", "0"]), ("as written, UA_Mod 3", FST, [])):
        out = tmp / f"{len(extra)}.csv"
        t0 = time.perf_counter()
        assert main(["simulate", str(fst), "--controller", "baseline", "--tmax", "600", "--out", str(out),
                     *extra]) == 0
        ours = read_csv(out)
        t = np.asarray(ours.time)
        print(f"  {label:22s} wall {time.perf_counter() - t0:7.1f} s (compile included when not cached), tilt 1P "
              f"{np.asarray(ours.channel('RtAeroMyh'))[t >= 100].std() / 1e6:.3f} MN m")


def main_() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--calls", type=int, default=20)
    ap.add_argument("--run", action="store_true", help="also simulate the floating deck with and without UA")
    args = ap.parse_args()
    if not FST.is_file():
        sys.exit(f"shared floating deck not found at {FST}")
    cost(args.calls)
    accuracy()
    if args.run:
        runs()


if __name__ == "__main__":
    main_()
