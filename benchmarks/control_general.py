"""Benchmark of the general NMPC layer (issue 13, point 7, general part): step times and build times.

Two models built with mbsym.System (``mbsym.control.models``):

- ``rotor_tower`` (6 states): tower fore-aft mode, rotor, aero-torque lag, pitch actuator; NMPC of
  generator speed and power with tower-velocity and pitch/torque-rate penalties, pitch and torque
  bounds, a pitch-rate limit, and the wind previewed over the horizon (ideal preview) of a
  60 s synthetic turbulent wind at 18 m/s mean (turbulence intensity 10 %);
- ``hanging_chain`` (14 states): a cart carrying a 6-link hanging chain, moved by 0.5 m with little
  swing.

Horizon N = 40 for both. Solvers: real-time iterations (Gauss–Newton SQP, one hpipm QP per step,
compiled preparation), converged ipopt and fatrop (exact Hessians, compiled NLP Functions), and —
side by side on the *same* discrete OCP (our stage map as acados ``DISCRETE`` dynamics, our residuals
as ``NONLINEAR_LS``, our constraints as ``BGH``) — acados SQP-RTI (Gauss–Newton, HPIPM), when an
acados Python interface is available (``--acados-python``; see ``benchmarks/README.md``).

Step times are wall times of one controller step in Python (measured with ``perf_counter``; the
first step, which converges from a cold start, is reported separately). Build time: from the OCP
description to a ready solver, with an empty compilation cache.

The section also measures CasADi's ``sqpmethod`` with hpipm (why it "returned after 0 iterations").

Run: ``python benchmarks/control_general.py [--quick] [--acados-python PATH] [--no-readme]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

sys.path.insert(0, str(Path(__file__).resolve().parent))

from mbsym.control import NMPC, OCP  # noqa: E402
from mbsym.control.models import hanging_chain, rotor_tower  # noqa: E402

N = 40
GEAR, OMEGA_RATED, TORQUE_RATED = 97.0, 1.2671, 43093.55      # NREL 5 MW (Jonkman et al. 2009, Table 1-1)
RPM_RATED = OMEGA_RATED * GEAR * 60 / (2 * np.pi)


# ------------------------------------------------------------------ problems
def wind_series(t: np.ndarray, mean: float = 18.0, seed: int = 1) -> np.ndarray:
    """Synthetic turbulence: 30 sinusoids, Kaimal-like amplitudes, turbulence intensity ~ 10 %."""
    rng = np.random.default_rng(seed)
    f = np.geomspace(0.01, 1.0, 30)
    amp = 1.0 / (1.0 + 20 * f) ** (5 / 6)
    amp *= 0.10 * mean / np.sqrt(0.5 * np.sum(amp ** 2))
    ph = rng.uniform(0, 2 * np.pi, f.size)
    return mean + np.sum(amp[:, None] * np.sin(2 * np.pi * f[:, None] * t[None, :] + ph[:, None]), axis=0)


def turbine_trim(dyn, wind: float = 18.0):
    """Equilibrium at rated speed and torque: the pitch where the quasi-steady aero torque equals the load."""
    load = GEAR * TORQUE_RATED

    def residual(pitch):          # (T_qs − Ta)/τ at Ta = load
        x = np.array([0.0, 0.0, 0.0, OMEGA_RATED, pitch, load])
        return dyn.rhs_value(x, [pitch, TORQUE_RATED, wind])[5]

    pitch = brentq(residual, 0.0, 0.5)
    thrust = dyn.output_value([0, 0, 0, OMEGA_RATED, pitch, load], [pitch, TORQUE_RATED, wind])[5]
    k = 3.5e5 * (2 * np.pi * 0.32) ** 2
    return np.array([thrust / k, 0.0, 0.0, OMEGA_RATED, pitch, load])


def turbine_ocp(dyn) -> OCP:
    deg = np.pi / 180
    return (OCP(dyn, horizon=N, dt=0.1, controls=["pitch_cmd", "gen_torque"])
            .track({"gen_speed": 1 / 20.0 ** 2, "power": 1 / 0.5e6 ** 2, "tower_d": 1 / 0.05 ** 2},
                   reference={"gen_speed": RPM_RATED, "power": 5e6})
            .track({"gen_speed": 10 / 20.0 ** 2, "tower_d": 10 / 0.05 ** 2}, terminal=True)
            .penalize_rates({"pitch_cmd": 1 / (2 * deg) ** 2, "gen_torque": 1 / 2000.0 ** 2})
            .bound("pitch_cmd", 0.0, 30 * deg).bound("gen_torque", 0.0, 1.1 * TORQUE_RATED)
            .limit_rate("pitch_cmd", -8 * deg, 8 * deg))


def chain_ocp(dyn) -> OCP:
    weights = {"s": 10.0, **{f"a{i}": 1.0 for i in range(1, 7)}, "s_d": 0.1, "F": 1e-3}
    return (OCP(dyn, horizon=N, dt=0.05).track(weights, reference={"s": 0.5})
            .track({"s": 100.0, "s_d": 10.0, **{f"a{i}_d": 1.0 for i in range(1, 7)}}, terminal=True)
            .bound("F", -5.0, 5.0))


def case(name: str):
    """``(dyn, ocp, x0, steps, preview(k) -> dict or None)``."""
    if name == "rotor_tower":
        dyn = rotor_tower()
        x0 = turbine_trim(dyn)
        t = np.arange(0, 70.0, 0.1)
        wind = wind_series(t)
        return dyn, turbine_ocp(dyn), x0, 600, (lambda k: {"wind": wind[k:k + N + 1]}), wind
    dyn = hanging_chain(6)
    return dyn, chain_ocp(dyn), np.zeros(dyn.n_x), 100, (lambda k: None), None


_PLANTS: dict = {}


def plant_step(dyn, x, u_full, dt, substeps=10):
    """The plant: RK4 with 10 sub-steps per sample (finer than the controllers' model), a CasADi Function."""
    key = (dyn.name, dt)
    if key not in _PLANTS:
        from mbsym.control.discretize import discretize
        _PLANTS[key] = (discretize(dyn.rhs, dt, substeps=substeps).step, dyn.parameter_vector())
    step, p = _PLANTS[key]
    return np.asarray(step(x, [], u_full, p)).ravel()


def full_input(name, u, k, wind):
    return np.array([u[0], u[1], wind[k]]) if name == "rotor_tower" else np.asarray(u)


# ------------------------------------------------------------------ our solvers
def run_ours(name: str, solver: str, steps: int | None = None) -> dict:
    dyn, ocp, x0, n_steps, preview, wind = case(name)
    n_steps = steps or n_steps
    with tempfile.TemporaryDirectory() as cache:       # cold compilation cache: honest build times
        os.environ["MBSYM_CACHE_DIR"] = cache
        t0 = time.perf_counter()
        mpc = NMPC(ocp, solver=solver, u_prev=[x0[4], TORQUE_RATED] if name == "rotor_tower" else None)
        build = time.perf_counter() - t0
        x, track, cpu = x0.copy(), [], []
        for k in range(n_steps):
            c0 = time.process_time()
            u = mpc.step(x, preview=preview(k))
            cpu.append(time.process_time() - c0)
            x = plant_step(dyn, x, full_input(name, u, k, wind), ocp.dt)
            track.append(dyn.output_value(x, full_input(name, u, k, wind))[0])
    walls = np.array([s.wall_s for s in mpc.stats[1:]])
    ref = RPM_RATED if name == "rotor_tower" else 0.5
    st = mpc.stats[1:]
    breakdown = {"prep_median_s": float(np.median([s.preparation_s for s in st])),
                 "qp_solver_median_s": float(np.median([s.qp_solver_s for s in st]))} if solver == "rti" else {}
    return {**breakdown, "cpu_median_s": float(np.median(cpu[1:])), "cpu_max_s": float(np.max(cpu[1:])),
            "solver": solver, "build_s": build, "compiled": mpc.compiled, "first_s": mpc.stats[0].wall_s,
            "median_s": float(np.median(walls)), "max_s": float(walls.max()), "p99_s": float(np.percentile(walls, 99)),
            "failures": mpc.failures, "steps": n_steps,
            "track_rms": float(np.sqrt(np.mean((np.array(track) - ref) ** 2))),
            "iterations_median": float(np.median([s.iterations for s in mpc.stats[1:]]))}


# ------------------------------------------------------------------ acados (worker)
def acados_classes():
    """``(AcadosModel, AcadosOcp, AcadosOcpSolver)`` of an installed acados Python interface (the package
    ``comma-deps-acados``: a symlinked ``ACADOS_SOURCE_DIR`` layout and its libraries preloaded)."""
    import acados
    root = Path(tempfile.mkdtemp(prefix="acados_root_"))
    (root / "interfaces" / "acados_template").mkdir(parents=True)
    for sub in ("include", "lib", "bin"):
        (root / sub).symlink_to(Path(acados.DIR) / sub)
    (root / "interfaces" / "acados_template" / "acados_template").symlink_to(acados.TEMPLATE_DIR)
    os.environ["ACADOS_SOURCE_DIR"] = str(root)
    import ctypes
    for lib in ("libblasfeo.so", "libhpipm.so", "libqpOASES_e.so.3.1"):     # libacados finds them loaded
        ctypes.CDLL(str(Path(acados.DIR) / "lib" / lib), mode=ctypes.RTLD_GLOBAL)
    from acados.acados_template import AcadosModel, AcadosOcp, AcadosOcpSolver
    return AcadosModel, AcadosOcp, AcadosOcpSolver


def acados_solver(tr, dyn, x_aug: np.ndarray, name: str, *, discrete: bool = False):
    """acados SQP-RTI (Gauss–Newton, partial-condensing HPIPM) of a transcribed OCP ``tr`` of ``dyn``: our
    residuals as ``NONLINEAR_LS``, our constraints as ``BGH``; the dynamics our stage map (``DISCRETE``, always
    with rate controls) or acados' own RK4 with forward sensitivities and the same sub-steps."""
    import casadi as ca
    AcadosModel, AcadosOcp, AcadosOcpSolver = acados_classes()
    root = Path(os.environ["ACADOS_SOURCE_DIR"])
    P = tr.problem
    x, u = ca.SX.sym("x", P.n_x), ca.SX.sym("u", P.n_u)
    d, p = ca.SX.sym("d", P.n_d), ca.SX.sym("p", P.n_p)
    f, c, r, _ = P.path(x, u, d, p)
    cN, rN, _ = P.terminal(x, d, p)
    m = AcadosModel()
    m.name = f"mbsym_{name}"
    m.x, m.u, m.p = x, u, ca.vertcat(d, p)
    m.cost_y_expr, m.cost_y_expr_e = r, rN
    oc = AcadosOcp()
    oc.model = m
    oc.dims.N = P.N
    oc.solver_options.tf = P.N * tr.dt
    if discrete or tr.rate_controls or tr.discretization.method != "rk4":
        m.disc_dyn_expr = f                            # our stage map as it is (augmented states)
        oc.solver_options.integrator_type = "DISCRETE"
    else:                                              # acados' own RK4 with forward sensitivities
        dist = d[: len(tr.disturbances)]
        u_full = ca.vertcat(*[u[tr.controls.index(n)] if n in tr.controls else dist[tr.disturbances.index(n)]
                              for n in dyn.inputs])
        m.f_expl_expr = dyn.rhs(x, u_full, p)
        m.xdot = ca.SX.sym("xdot", P.n_x)
        m.f_impl_expr = m.xdot - m.f_expl_expr
        oc.solver_options.integrator_type = "ERK"
        oc.solver_options.sim_method_num_stages = 4
        oc.solver_options.sim_method_num_steps = tr.discretization.substeps
    oc.solver_options.nlp_solver_type = "SQP_RTI"
    oc.solver_options.hessian_approx = "GAUSS_NEWTON"
    oc.solver_options.qp_solver = "PARTIAL_CONDENSING_HPIPM"
    oc.cost.cost_type = oc.cost.cost_type_e = "NONLINEAR_LS"
    oc.cost.W, oc.cost.W_e = 2 * np.eye(r.numel()), 2 * np.eye(max(rN.numel(), 1))     # ½ yᵀWy = ‖r‖²
    oc.cost.yref, oc.cost.yref_e = np.zeros(r.numel()), np.zeros(rN.numel())
    nc = tr.n_controls
    oc.constraints.idxbu = np.arange(nc)
    oc.constraints.lbu, oc.constraints.ubu = P.lbu[:nc], P.ubu[:nc]
    if c.numel():
        m.con_h_expr = c
        oc.constraints.lh, oc.constraints.uh = P.lbc, P.ubc
    oc.constraints.x0 = x_aug
    oc.parameter_values = np.zeros(P.n_d + P.n_p)
    oc.code_export_directory = str(root / "c_generated")
    return AcadosOcpSolver(oc, json_file=str(root / "ocp.json"), verbose=False)


def run_acados(name: str, steps: int | None = None) -> dict:
    """The same discrete OCP in acados SQP-RTI (runs inside a Python that has an acados interface)."""
    dyn, ocp_desc, x0, n_steps, preview, wind = case(name)
    n_steps = steps or n_steps
    t0 = time.perf_counter()
    tr = ocp_desc.transcribe()
    P = tr.problem
    nc = tr.n_controls
    solver = acados_solver(tr, dyn, tr.augmented_state(x0, [x0[4], TORQUE_RATED] if name == "rotor_tower"
                                                        else [0.0]), name)
    build = time.perf_counter() - t0
    pv = dyn.parameter_vector()
    u_prev = np.array([x0[4], TORQUE_RATED]) if name == "rotor_tower" else np.zeros(1)
    xs, walls, internal, status, track, cpu = x0.copy(), [], [], [], [], []
    for k in range(n_steps):
        D = tr.stage_parameters(preview(k))
        t1, c1 = time.perf_counter(), time.process_time()
        for j in range(P.N + 1):
            solver.set(j, "p", np.concatenate([D[:, j], pv]))
        xa = tr.augmented_state(xs, u_prev)
        solver.set(0, "lbx", xa)
        solver.set(0, "ubx", xa)
        for _ in range(1 if k else 30):               # first step: iterate from the cold start
            st = solver.solve()
        uk = solver.get(0, "u")[:nc]
        walls.append(time.perf_counter() - t1)
        cpu.append(time.process_time() - c1)
        internal.append(solver.get_stats("time_tot"))
        status.append(int(st))
        u_prev = uk
        xs = plant_step(dyn, xs, full_input(name, uk, k, wind), tr.dt)
        track.append(dyn.output_value(xs, full_input(name, uk, k, wind))[0])
    w = np.array(walls[1:])
    ref = RPM_RATED if name == "rotor_tower" else 0.5
    return {"cpu_median_s": float(np.median(cpu[1:])), "cpu_max_s": float(np.max(cpu[1:])),
            "solver": "acados SQP-RTI", "build_s": build, "compiled": True, "first_s": walls[0],
            "median_s": float(np.median(w)), "max_s": float(w.max()), "p99_s": float(np.percentile(w, 99)),
            "internal_median_s": float(np.median(internal[1:])), "failures": int(np.sum(np.array(status) != 0)),
            "steps": n_steps, "track_rms": float(np.sqrt(np.mean((np.array(track) - ref) ** 2))),
            "iterations_median": 1.0}


# ------------------------------------------------------------------ sqpmethod
def sqpmethod_study(steps: int = 60) -> list[dict]:
    """CasADi sqpmethod in an NMPC loop (own warm start, shifted, with multipliers) on the rotor-tower OCP.

    For each configuration: steps that return after 0 iterations, the return statuses, and the
    largest error of the applied input against converged ipopt at the same state (scaled by 0.01 rad
    and 1000 N m).
    """
    import casadi as ca
    from collections import Counter
    from mbsym.control.nlp import horizon_nlp
    from mbsym.control.nlpsolvers import NlpSolver

    dyn, ocp, x0, _, preview, wind = case("rotor_tower")
    tr = ocp.transcribe()
    P = tr.problem
    ref_solver = NlpSolver(P, "ipopt", compile=False)
    gn = NlpSolver(P, "sqpmethod", hessian="gauss-newton", compile=False)._gauss_newton(triu=False)
    structure = {"N": P.N, "nx": [P.n_x] * (P.N + 1), "nu": [P.n_u] * P.N + [0], "ng": [P.n_c] * P.N + [P.n_cN]}
    hp_default = {"qpsol": "hpipm", "qpsol_options": {**structure, "error_on_fail": False}}
    hp_ours = {"qpsol": "hpipm", "qpsol_options": {**structure, "error_on_fail": False,
                                                   "hpipm": {"mode": "speed_abs", "iter_max": 50}}}
    qrqp = {"qpsol": "qrqp", "qpsol_options": {"print_iter": False, "print_header": False, "error_on_fail": False}}
    configs = {
        "exact Hessian, hpipm as CasADi sets it (mode robust, inf 1e8)": hp_default,
        "exact Hessian, hpipm speed_abs": hp_ours,
        "Gauss-Newton (hess_lag), hpipm as CasADi sets it": {**hp_default, "hess_lag": gn},
        "Gauss-Newton (hess_lag), hpipm speed_abs": {**hp_ours, "hess_lag": gn},
        "Gauss-Newton (hess_lag), qrqp": {**qrqp, "hess_lag": gn},
    }
    nlp = horizon_nlp(P)
    pv = dyn.parameter_vector()
    rows = []
    for label, opts in configs.items():
        S = ca.nlpsol("s", "sqpmethod", nlp.as_dict(), {**opts, "print_header": False, "print_iteration": False,
                                                         "print_status": False, "print_time": False, "max_iter": 50})
        x, u_prev = x0.copy(), np.array([x0[4], TORQUE_RATED])
        w = tr.initial_guess(tr.augmented_state(x, u_prev), u_prev)
        lam_g, lam_x = np.zeros(P.layout.n_g), np.zeros(P.layout.n_w)
        zero, errs, statuses = 0, [], Counter()
        for k in range(steps):
            D = tr.stage_parameters(preview(k))
            xa = tr.augmented_state(x, u_prev)
            lbw, ubw, lbg, ubg = P.bounds(xa)
            res = S(x0=w, p=nlp.parameters(D, pv), lbx=lbw, ubx=ubw, lbg=lbg, ubg=ubg, lam_g0=lam_g, lam_x0=lam_x)
            st = S.stats()
            zero += st["iter_count"] == 0
            statuses[st["return_status"]] += 1
            wk = np.asarray(res["x"]).ravel()
            ref = ref_solver.solve(w, D, pv, P.bounds(), xa)
            uk = P.layout.split(wk)[1][:2, 0]
            uref = P.layout.split(ref.w)[1][:2, 0]
            errs.append(float(np.abs((uk - uref) / np.array([0.01, 1000.0])).max()) if np.all(np.isfinite(uk))
                        else np.inf)
            u_apply = uk if np.all(np.isfinite(uk)) else u_prev
            x = plant_step(dyn, x, full_input("rotor_tower", u_apply, k, wind), tr.dt)
            u_prev = u_apply
            w = P.layout.shift(wk) if np.all(np.isfinite(wk)) else P.layout.shift(ref.w)
            lam_g = np.asarray(res["lam_g"]).ravel() if np.all(np.isfinite(np.asarray(res["lam_g"]))) else 0 * lam_g
            lam_x = np.asarray(res["lam_x"]).ravel() if np.all(np.isfinite(np.asarray(res["lam_x"]))) else 0 * lam_x
        rows.append({"config": label, "zero_iteration_steps": int(zero), "statuses": dict(statuses), "steps": steps,
                     "max_u_error_scaled": float(np.max(errs)), "median_u_error_scaled": float(np.median(errs))})
    return rows


# ------------------------------------------------------------------ report
def table(results: dict) -> str:
    lines = ["| model | solver | build [s] | first step [s] | step median [ms] | step max [ms] | p99 [ms] | "
             "CPU median / max [ms] | failures / steps | tracking RMS |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for model, rows in results.items():
        base = next((r for r in rows if r["solver"] == "rti"), None)
        for r in rows:
            if "internal_median_s" in r:
                detail = f" (C: {1e3 * r['internal_median_s']:.2f})"
            elif "prep_median_s" in r:
                detail = f" (prep {1e3 * r['prep_median_s']:.2f}, hpipm {1e3 * r['qp_solver_median_s']:.2f})"
            else:
                detail = ""
            ratio = f" ({r['median_s'] / base['median_s']:.1f}× RTI)" if base is not None and r is not base else ""
            lines.append(f"| {model} | {r['solver']} | {r['build_s']:.1f} | {r['first_s']:.3f} | "
                         f"{1e3 * r['median_s']:.2f}{detail}{ratio} | {1e3 * r['max_s']:.2f} | {1e3 * r['p99_s']:.2f} | "
                         f"{1e3 * r['cpu_median_s']:.2f} / {1e3 * r['cpu_max_s']:.2f} | {r['failures']} / {r['steps']} | "
                         f"{r['track_rms']:.4g} |")
    return "\n".join(lines)


def sqp_table(rows: list[dict]) -> str:
    lines = ["| sqpmethod configuration | steps with 0 iterations | return statuses | u error vs ipopt: "
             "median / max (scaled) |", "|---|---:|---|---:|"]
    for r in rows:
        st = ", ".join(f"{k} {v}" for k, v in sorted(r["statuses"].items(), key=lambda kv: -kv[1]))
        lines.append(f"| {r['config']} | {r['zero_iteration_steps']} / {r['steps']} | {st} | "
                     f"{r['median_u_error_scaled']:.2g} / {r['max_u_error_scaled']:.2g} |")
    return "\n".join(lines)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer steps, no sqpmethod study")
    ap.add_argument("--acados-python", default=os.environ.get("MBSYM_ACADOS_PYTHON"),
                    help="a Python with an acados interface (e.g. a venv with comma-deps-acados)")
    ap.add_argument("--acados-worker", help=argparse.SUPPRESS)
    ap.add_argument("--steps", type=int, default=None, help=argparse.SUPPRESS)
    ap.add_argument("--sqpmethod-only", action="store_true", help="run only the sqpmethod study")
    ap.add_argument("--no-readme", action="store_true", help="print only; do not rewrite benchmarks/README.md")
    args = ap.parse_args(argv)
    if args.acados_worker:
        print(json.dumps(run_acados(args.acados_worker, args.steps)))
        return
    if args.sqpmethod_only:
        print(sqp_table(sqpmethod_study()))
        return
    results = {}
    for model in ("rotor_tower", "hanging_chain"):
        steps = 150 if args.quick else None
        rows = [run_ours(model, "rti", steps)]
        nlp_steps = 40 if args.quick else 100
        if model == "rotor_tower":     # exact Hessians of the 14-state chain: generated code far too large
            rows += [run_ours(model, s, nlp_steps) for s in ("ipopt", "fatrop")]
        if args.acados_python:
            proc = subprocess.run([args.acados_python, __file__, "--acados-worker", model,
                                   *(["--steps", str(steps)] if steps else [])],
                                  capture_output=True, text=True, timeout=1800)
            if proc.returncode == 0:
                rows.append(json.loads(proc.stdout.strip().splitlines()[-1]))
            else:
                print(f"acados ({model}) failed: {proc.stderr.strip()[-800:]}")
        results[f"{model} ({case(model)[0].n_x} states)"] = rows
        print(table({f"{model}": rows}), flush=True)
    text = table(results)
    if not args.quick:
        text += "\n\n" + sqp_table(sqpmethod_study())
    print(text)
    if not args.no_readme:
        from _report import write_section
        write_section("control_general", text)


if __name__ == "__main__":
    main()
