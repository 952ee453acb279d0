"""Speed vs accuracy: work-precision charts of every integration method on three scenes.

Scenes (``SCENES``):

- ``paper45``: NREL 5 MW, tower FA1 + SS1 + generator azimuth (OpenFAST deck
  ``paper45_fa_ss_gen``), free decay from TTDspFA = TTDspSS = 1 m at 5 rpm, 60 s;
- ``paper46``: the floating case (platform surge + pitch + tower FA1, deck
  ``paper46_floating``), PtfmPitch = 2 deg, TTDspFA = 1 m, 60 s;
- ``stiff_rotor``: a rotor built directly from flexible bodies: hub on a drivetrain
  (generator azimuth through the 97:1 gearbox, torsion spring DTTorSpr and damper
  DTTorDmp) carrying three NREL 5 MW blades with their first edgewise mode
  (``mb.FlexibleBody`` + ``blade_shape_integrals(turbine, dofs=("EdgeDOF",))``),
  gravity on, 12.1 rpm, blade 1 released from a 0.5 m edgewise tip deflection, 20 s.
  Eigenvalues at t = 0 up to |lambda| = 22.1 rad/s (drivetrain-edge mode, 3.5 Hz)
  against a 1P of 1.27 rad/s: rk4 is stable only for dt < 2.78 / 22.1 = 0.126 s.

Every method of ``mbsym.simulate.METHODS`` runs over a range of steps (fixed-step
methods) or tolerances (adaptive methods, ``atol = rtol / 100``), with compiled C
(``compile=True``: the step, or the rhs/residual and its Jacobian); rk4 and cvodes
also in CasADi's virtual machine ("VM" lines). The accuracy-driven default of
``simulate`` (no method, step or tolerance; ``accuracy`` = 1e-2 ... 1e-6) is the black
line: its points show the accuracy requested, the error achieved and the cost, the
step-doubling check included (its disk cache warmed first, as after a first run). Error: ``ε = max over states
of mean|x - x_ref| / range(x_ref)`` on a 0.02 s output grid (OpenFAST's DT_Out;
off-step outputs by each method's own interpolation). Reference: cvodes at rtol =
atol = 1e-12; its own error is bounded by its distance to an independent solver
(scipy Radau IIA at rtol = 1e-10, atol = 1e-12), printed per scene. Cost:
``integration_wall_s`` (integration alone; preparation and compilation excluded),
median of ``--repeat`` runs after a warm-up run. The performance section also gives
the whole warm ``simulate()`` call (cache lookup, input sampling, integration and
the model's output channels at every output time), the time a user waits, and
compares both with OpenFAST's whole run.

Writes ``benchmarks/figures/work_precision_<scene>.png`` (ε vs integration wall
time, log-log, one line per method; failed runs as crosses at ε = 1, at their time
to failure) and the tables into ``benchmarks/README.md``
between the ``work_precision`` markers, plus the performance-target section
(paper45, fastest method with ε <= 0.1 %) between the ``performance`` markers.

Run: ``python benchmarks/work_precision.py [--scenes paper45 ...] [--quick] [--no-write]``;
``--performance-only`` runs paper45 alone and rewrites only the performance section.
"""

from __future__ import annotations

import argparse
import statistics
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from _report import write_section

import mbsym as mb
from mbsym import codegen
from mbsym.exceptions import IntegrationError
from mbsym.simulate import METHODS, simulate

HERE = Path(__file__).resolve().parent
SHARED = HERE.parent.parent / "shared" / "openfast" / "cases"
DT_OUT = 0.02
OPENFAST_PAPER45_S = 2.21     # OpenFAST v5 (ElastoDyn only) wall time for paper45, 60 s (issue 4)
TARGET_EPS = 1e-3             # 0.1 %
FAILED_EPS = 1.0              # where failed runs are drawn
STIFF_RPM = 12.1


# ---------------------------------------------------------------------------------------------- scenes
@dataclass
class Scene:
    name: str
    model: object
    tmax: float
    label: str
    x0: np.ndarray | None = None


class RotorModel:
    """Simulation-protocol wrapper: an EquationsOfMotion with its initial state."""

    def __init__(self, eom, x0):
        self.eom, self._x0 = eom, np.asarray(x0, dtype=float)

    def default_state(self):
        return self._x0


def deck_scene(case: str, label: str) -> Scene:
    from mbsym.wind import read_openfast
    from mbsym.wind.structure.turbine import TurbineModel

    model = TurbineModel(read_openfast(SHARED / case / f"{case}.fst"))
    return Scene(case.split("_")[0], model, 60.0, label)


def stiff_rotor_eom(turbine=None):
    """Hub + drivetrain + three edgewise-flexible blades (see the module docstring)."""
    from mbsym.wind import blade_shape_integrals, nrel5mw
    from mbsym.wind.structure.turbine import blade_rotation

    t = turbine or nrel5mw()
    sys = mb.System(gravity=[0.0, 0.0, -t.simulation.gravity])
    psi, twist = sys.coordinates("GeAz DrTr")
    edge = sys.coordinates([f"B{k + 1}E1" for k in range(3)])
    shaft = mb.RigidBody("shaft", mass=0.0)
    sys.add_joint(mb.Fixed(sys.ground, shaft, offset=[0.0, 0.0, t.tower_height]))
    gen = mb.RigidBody("generator", mass=0.0, inertia=[t.generator_inertia, 0.0, 0.0])
    sys.add_joint(mb.Revolute(shaft, gen, axis=[1, 0, 0], coordinate=psi, gear_ratio=abs(t.gearbox_ratio)))
    lss = mb.RigidBody("lss", mass=0.0)
    sys.add_joint(mb.Revolute(shaft, lss, axis=[1, 0, 0], coordinate=psi))
    hub = mb.RigidBody("hub", mass=t.hub_mass, com=[t.hub_cm, 0.0, 0.0], inertia=[t.hub_inertia, 0.0, 0.0])
    sys.add_joint(mb.Revolute(lss, hub, axis=[1, 0, 0], coordinate=twist))
    sys.add_spring(twist, t.drivetrain_stiffness)
    sys.add_damper(twist, t.drivetrain_damping)
    for k in range(3):
        sid = blade_shape_integrals(t, k, dofs=("EdgeDOF",))
        R = blade_rotation(2 * np.pi * k / 3, t.precone[k], t.initial_conditions.blade_pitch[k])
        blade = mb.FlexibleBody(f"blade{k + 1}", sid, [edge[k]])
        sys.add_joint(mb.Fixed(hub, blade, offset=(t.hub_radius * R[:, 2]).tolist(), rotation=R.tolist()))
    return sys.equations(name="stiff_rotor")


def stiff_rotor_scene() -> Scene:
    eom = stiff_rotor_eom()
    x0 = np.zeros(eom.n_x)
    x0[eom.states.index("B1E1")] = 0.5
    x0[eom.states.index("GeAz_d")] = STIFF_RPM * np.pi / 30.0
    return Scene("stiff_rotor", RotorModel(eom, x0), 20.0,
                 f"stiff rotor: drivetrain torsion + 3 edgewise blades, {STIFF_RPM} rpm, 20 s", x0)


def build_scene(name: str) -> Scene:
    if name == "paper45":
        return deck_scene("paper45_fa_ss_gen", "paper45: tower FA + SS + generator, 60 s free decay")
    if name == "paper46":
        return deck_scene("paper46_floating", "paper46: floating surge + pitch + tower FA, 60 s free decay")
    return stiff_rotor_scene()


SCENES = ("paper45", "paper46", "stiff_rotor")


# ---------------------------------------------------------------------------------------------- runs
def settings(quick: bool) -> list[tuple[str, str, dict]]:
    """(line label, method, keyword arguments) of every run."""
    dts = (0.005, 0.01, 0.02, 0.05, 0.1, 0.125, 0.2) if not quick else (0.01, 0.05, 0.1)
    dts2 = (0.0025, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2) if not quick else (0.01, 0.05)
    tols = 10.0 ** -np.arange(3, 11) if not quick else (1e-4, 1e-7)
    tols_py = 10.0 ** -np.arange(3, 9) if not quick else (1e-4,)
    out = []
    for m, cls in METHODS.items():
        if cls.kind == "fixed-step":
            for dt in (dts if m == "rk4" else dts2):
                out.append((m, m, {"dt": dt, "compile": True}))
        else:
            for r in (tols_py if m.startswith("scipy") else tols):
                out.append((m, m, {"rtol": float(r), "atol": float(r) / 100, "compile": True}))
    out += [("rk4 (VM)", "rk4", {"dt": dt}) for dt in dts]
    out += [("cvodes (VM)", "cvodes", {"rtol": float(r), "atol": float(r) / 100}) for r in tols]
    out += [(DEFAULT_LABEL, None, {"accuracy": a}) for a in ACCURACIES[quick]]
    return out


#: The accuracy-driven default of simulate() (no method, dt, rtol or atol): one point per requested accuracy.
DEFAULT_LABEL = "default (accuracy=...)"
ACCURACIES = {False: (1e-2, 1e-3, 1e-4, 1e-5, 1e-6), True: (1e-3, 1e-5)}


@dataclass
class Run:
    label: str
    method: str
    kwargs: dict
    eps: float = float("nan")
    wall: float = float("nan")
    call: float = float("nan")            # whole simulate() call [s]
    prepare: float = float("nan")
    steps: int | None = None
    n_rhs: int | None = None
    error: str = ""
    stats: dict = field(default_factory=dict)

    @property
    def setting(self) -> str:
        if "accuracy" in self.kwargs:
            return f"accuracy = {self.kwargs['accuracy']:.0e}"
        return f"dt = {self.kwargs['dt']:g} s" if "dt" in self.kwargs else f"rtol = {self.kwargs['rtol']:.0e}"


def epsilon(x: np.ndarray, ref: np.ndarray) -> float:
    """max over states of mean|x - x_ref| / range(x_ref) (states with zero range skipped)."""
    rng = np.ptp(ref, axis=0)
    keep = rng > 1e-12 * np.maximum(1.0, np.max(np.abs(ref), axis=0))
    return float(np.max(np.mean(np.abs(x - ref), axis=0)[keep] / rng[keep]))


def run_one(scene: Scene, t_out, ref, label, method, kwargs, repeat) -> Run:
    run = Run(label, method, kwargs)
    if method is None:
        kwargs = dict(kwargs)                    # the accuracy-driven default: no method argument at all
    else:
        kwargs = {"method": method, **kwargs}
    try:
        first = simulate(scene.model, scene.tmax, scene.x0, t_out=t_out, **kwargs)   # prepares
        if method is None:                       # a background compilation warms the disk cache: let it end
            codegen.wait_for_background()
            first = simulate(scene.model, scene.tmax, scene.x0, t_out=t_out, **kwargs)
        run.prepare = first.statistics["prepare_wall_s"]
        walls, calls, res = [], [], first
        for _ in range(repeat if first.statistics["integration_wall_s"] < 0.5 else 1):
            t0 = time.perf_counter()
            res = simulate(scene.model, scene.tmax, scene.x0, t_out=t_out, **kwargs)
            calls.append(time.perf_counter() - t0)
            walls.append(res.statistics["integration_wall_s"])
    except IntegrationError as exc:
        run.error = str(exc)
        t0 = time.perf_counter()                 # time to failure (prepared Functions cached)
        try:
            simulate(scene.model, scene.tmax, scene.x0, t_out=t_out, **kwargs)
        except IntegrationError:
            run.wall = time.perf_counter() - t0
        return run
    run.wall, run.call, run.eps = statistics.median(walls), statistics.median(calls), epsilon(res.x, ref.x)
    run.steps, run.n_rhs, run.stats = res.statistics["steps"], res.statistics["n_rhs"], res.statistics
    return run


def run_scene(scene: Scene, quick: bool, repeat: int):
    t_out = np.round(np.arange(0.0, scene.tmax + DT_OUT / 2, DT_OUT), 10)
    ref = simulate(scene.model, scene.tmax, scene.x0, method="cvodes", rtol=1e-12, atol=1e-12, t_out=t_out)
    check = simulate(scene.model, scene.tmax, scene.x0, method="scipy-radau", rtol=1e-10, atol=1e-12,
                     t_out=t_out, compile=True)
    ref_eps = epsilon(check.x, ref.x)
    print(f"\n{scene.label}: reference cvodes 1e-12 vs scipy-radau 1e-10: ε = {ref_eps:.1e}", flush=True)
    runs = []
    for label, method, kw in settings(quick):
        r = run_one(scene, t_out, ref, label, method, kw, repeat)
        runs.append(r)
        status = r.error.split(":")[0] if r.error else f"ε = {r.eps:.2e}, {1e3 * r.wall:8.2f} ms, {r.steps} steps"
        print(f"  {label:<18} {r.setting:<14} {status}", flush=True)
    return runs, ref_eps, ref


# ---------------------------------------------------------------------------------------------- output
def plot_scene(scene: Scene, runs, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 5.2))
    labels = list(dict.fromkeys(r.label for r in runs))
    for i, label in enumerate(labels):
        pts = [(r.wall, r.eps) for r in runs if r.label == label and not r.error and r.eps > 0]   # setting order
        color = "k" if label == DEFAULT_LABEL else f"C{i % 10}"
        if pts and label == DEFAULT_LABEL:
            w, e = zip(*pts)
            ax.loglog(w, e, "-", marker="*", label="default: accuracy-driven (requested → achieved)", ms=11,
                      color=color, lw=2.2, zorder=5)
            for r in (r for r in runs if r.label == label and not r.error):
                ax.annotate(f"{r.kwargs['accuracy']:.0e}", (r.wall, r.eps), textcoords="offset points",
                            xytext=(6, -10), fontsize=7, color="k")
        elif pts:
            w, e = zip(*pts)
            style = "--" if "VM" in label else "-"
            ax.loglog(w, e, style, marker="os^vD<>ph*"[i % 10], label=label, ms=5, color=color)
        failed = [r.wall for r in runs if r.label == label and r.error and np.isfinite(r.wall)]
        if failed:
            ax.loglog(failed, [FAILED_EPS] * len(failed), "x", color=color, ms=9, mew=2)
    if any(r.error for r in runs):
        ax.text(ax.get_xlim()[0], FAILED_EPS * 1.3, " x: failed (IntegrationError), at the time to failure",
                fontsize=8, color="0.3")
    ax.axhline(TARGET_EPS, color="0.5", lw=0.8, ls=":")
    ax.text(ax.get_xlim()[0], TARGET_EPS * 1.15, " ε = 0.1 %", color="0.4", fontsize=8)
    ax.set_xlabel("integration wall time [s]")
    ax.set_ylabel("ε = max over states of mean|x − x_ref| / range(x_ref)")
    ax.set_title(f"{scene.label}\nreference: cvodes rtol = atol = 1e-12", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    path.parent.mkdir(exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary_rows(name: str, runs) -> list[str]:
    rows = []
    for label in dict.fromkeys(r.label for r in runs):
        mine = [r for r in runs if r.label == label]
        cells = []
        for tol in (1e-3, 1e-6):
            ok = [r for r in mine if not r.error and r.eps <= tol]
            best = min(ok, key=lambda r: r.wall) if ok else None
            cells.append(f"{1e3 * best.wall:.2f} ms ({best.setting})" if best else "—")
        failed = [r.setting for r in mine if r.error]
        rows.append(f"| {name} | {label} | {cells[0]} | {cells[1]} | {', '.join(failed) or '—'} |")
    return rows


def default_rows(name: str, runs) -> list[str]:
    """The accuracy-driven default: what it chose, predicted, estimated and achieved, and its cost against the
    cheapest swept setting (any method, compiled or not) that reached the same accuracy."""
    rows = []
    swept = [r for r in runs if r.label != DEFAULT_LABEL and not r.error]
    for r in (r for r in runs if r.label == DEFAULT_LABEL):
        acc = r.kwargs["accuracy"]
        if r.error:
            rows.append(f"| {name} | {acc:.0e} | failed: {r.error.split(':')[0]} | — | — | — | — | — | — |")
            continue
        s = r.stats
        chosen = (f"{s['method']}" + (f", dt = {s['dt']:.3g} s" if s.get("dt") else f", rtol = {s.get('rtol'):.0e}")
                  + (", compiled" if s.get("compiled") else ", VM"))
        ok = [q for q in swept if q.eps <= acc]
        best = min(ok, key=lambda q: q.wall) if ok else None
        vs = f"{best.label}, {best.setting}: {1e3 * best.wall:.2f} ms ({r.wall / best.wall:.1f}x)" if best else "—"
        pred = s.get("predicted_error")
        rows.append(f"| {name} | {acc:.0e} | {chosen} | {pred:.1e} | {s.get('error_estimate', float('nan')):.1e} | "
                    f"**{r.eps:.1e}** | {1e3 * r.wall:.2f} | {1e3 * r.call:.2f} | {vs} |"
                    if isinstance(pred, float) and np.isfinite(pred) else
                    f"| {name} | {acc:.0e} | {chosen} | — | {s.get('error_estimate', float('nan')):.1e} | "
                    f"**{r.eps:.1e}** | {1e3 * r.wall:.2f} | {1e3 * r.call:.2f} | {vs} |")
    return rows


def full_rows(name: str, runs) -> list[str]:
    rows = []
    for r in runs:
        if r.error:
            rows.append(f"| {name} | {r.label} | {r.setting} | failed: {r.error.split(':')[0]} | — | — | — |")
        else:
            rows.append(f"| {name} | {r.label} | {r.setting} | {r.eps:.2e} | {1e3 * r.wall:.3f} | {r.steps} | "
                        f"{r.n_rhs} |")
    return rows


DRIVER = r"""
int mbsym_plain_loop(const casadi_real* x0, const casadi_real* U, const casadi_real* p, casadi_real h, int n,
                     casadi_real* X) {
  static casadi_real w[SZ_W + 1];
  static casadi_int iw[SZ_IW + 1];
  casadi_real aux[NX];
  const casadi_real* arg[SZ_ARG];
  casadi_real* res[SZ_RES];
  const casadi_real* x = x0;
  for (int k = 0; k < n; ++k) {
    arg[0] = x; arg[1] = U + (casadi_int)k * NU * 3; arg[2] = p; arg[3] = &h;
    res[0] = X + (casadi_int)k * NX; res[1] = aux;
    if (STEP(arg, res, iw, w, 0)) return k;
    x = X + (casadi_int)k * NX;
  }
  return n;
}
"""


def plain_c_loop(scene: Scene, dt: float, repeat: int = 20) -> tuple[float, float]:
    """(wall [s], max |x - simulate's x|) of the RK4 loop as a plain C loop around the same generated step.

    The practical limit: no CasADi call machinery, no output interpolation; the model's default
    inputs are sampled at the stage times beforehand (outside the timing), as simulate() does.
    """
    import ctypes
    import subprocess
    import tempfile

    import casadi as ca

    from mbsym.codegen import DEFAULT_FLAGS, compiler_command

    from mbsym.simulate.base import Problem
    from mbsym.simulate.fixed import RK4
    from mbsym.simulate.inputs import input_signal
    from mbsym.simulate.model import plant_of

    plant = plant_of(scene.model)
    eom = plant
    n = int(round(scene.tmax / dt))
    x0 = plant.default_x if scene.x0 is None else scene.x0
    p = plant.parameter_vector(None)
    grid = dt * np.arange(n + 1)
    signal = input_signal(dict(plant.default_u) or None, plant.inputs, scene.tmax)
    prob = Problem(plant, x0, p, signal, grid, scene.tmax, dt=dt, n_steps=n)
    step, _ = RK4(prob)._build_step()
    t_stage = (grid[:-1, None] + np.asarray(RK4.nodes)[None, :] * dt).reshape(-1)
    cc = compiler_command()
    if cc is None:
        raise RuntimeError("no C compiler found (set MBSYM_CC or CC)")
    with tempfile.TemporaryDirectory() as tmp:
        cg = ca.CodeGenerator("plain.c", {"with_header": False})
        cg.add(step)
        cg.generate(tmp + "/")
        defs = {"SZ_W": step.sz_w(), "SZ_IW": step.sz_iw(), "SZ_ARG": step.sz_arg(), "SZ_RES": step.sz_res(),
                "NX": eom.n_x, "NU": eom.n_u, "STEP": step.name()}
        with open(f"{tmp}/plain.c", "a") as fh:
            fh.write("".join(f"#define {k} {v}\n" for k, v in defs.items()) + DRIVER)
        subprocess.run([*cc, *DEFAULT_FLAGS, "-shared", "-fPIC", "-o", f"{tmp}/plain.so", f"{tmp}/plain.c", "-lm"],
                       check=True)
        lib = ctypes.CDLL(f"{tmp}/plain.so")
        dp = ctypes.POINTER(ctypes.c_double)
        lib.mbsym_plain_loop.argtypes = [dp, dp, dp, ctypes.c_double, ctypes.c_int, dp]
        U = signal(t_stage).reshape(-1) if eom.n_u else np.zeros(1)      # (n_u, 3 n) column-major
        X = np.zeros(eom.n_x * n)
        args = [np.ascontiguousarray(a, dtype=float) for a in (x0, U, p)]
        ptr = [a.ctypes.data_as(dp) for a in args]
        walls = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            lib.mbsym_plain_loop(ptr[0], ptr[1], ptr[2], dt, n, X.ctypes.data_as(dp))
            walls.append(time.perf_counter() - t0)
    ref = simulate(scene.model, scene.tmax, scene.x0, method="rk4", dt=dt, compile=True)
    diff = float(np.max(np.abs(X.reshape(n, eom.n_x) - ref.x[1:])))
    return statistics.median(walls), diff


def output_epsilon(res, ref) -> tuple[float, str]:
    """Largest ε over the OpenFAST output channels (wrap-aware; constant channels skipped) and its channel."""
    from mbsym.wind.analysis.compare import WRAPPED, error_metrics

    worst = (0.0, "")
    for j, name in enumerate(ref.output_names):
        e, _ = error_metrics(res.t, res.y[:, j], ref.t, ref.y[:, j], period=WRAPPED.get(name))
        if np.isfinite(e) and e > worst[0]:
            worst = (e, name)
    return worst


def cold_preparation(scene: Scene, kwargs: dict) -> tuple[float, float]:
    """Preparation [s] with an empty disk cache (generate C + gcc -O1), then with the library cached."""
    import os
    import tempfile

    from mbsym.simulate import clear_cache

    old = os.environ.get("MBSYM_CACHE_DIR")
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["MBSYM_CACHE_DIR"] = tmp
        try:
            out = []
            for _ in range(2):
                clear_cache()
                out.append(simulate(scene.model, scene.tmax, scene.x0, method="rk4", **kwargs)
                           .statistics["prepare_wall_s"])
        finally:
            clear_cache()
            if old is None:
                os.environ.pop("MBSYM_CACHE_DIR", None)
            else:
                os.environ["MBSYM_CACHE_DIR"] = old
    return out[0], out[1]


def performance_section(runs, scene: Scene | None = None, ref=None) -> str:
    ok = [r for r in runs if not r.error and r.eps <= TARGET_EPS and r.label != DEFAULT_LABEL]
    default = [r for r in runs if r.label == DEFAULT_LABEL and not r.error and r.kwargs["accuracy"] == 1e-3]
    best = min(ok, key=lambda r: r.wall)
    vm = [r for r in runs if r.label == "rk4 (VM)" and not r.error and r.eps <= TARGET_EPS]
    vm_best = min(vm, key=lambda r: r.wall) if vm else None
    at_of_dt = [r for r in runs if r.label == "rk4 (VM)" and r.kwargs.get("dt") == 0.01]
    lines = [f"| run (paper45, 60 s) | ε | integration wall [ms] | whole simulate() call [ms] | preparation [ms] | "
             f"vs OpenFAST {OPENFAST_PAPER45_S} s: integration | vs OpenFAST: whole call |",
             "|---|---:|---:|---:|---:|---:|---:|"]

    def row(title, r):
        lines.append(f"| {title} | {r.eps:.1e} | {1e3 * r.wall:.2f} | {1e3 * r.call:.2f} | {1e3 * r.prepare:.0f} | "
                     f"{OPENFAST_PAPER45_S / r.wall:.0f}× | {OPENFAST_PAPER45_S / r.call:.0f}× |")

    if default:
        d = default[0]
        row(f"**default (accuracy 1e-3): {d.stats['method']}, dt = {d.stats.get('dt', float('nan')):.3g} s, "
            f"compiled: {d.stats.get('compiled')}; integration includes the step-doubling check**", d)
    row(f"fastest swept setting with ε ≤ 0.1 %: {best.label}, {best.setting}, compiled", best)
    if vm_best:
        row(f"same, virtual machine: rk4, {vm_best.setting}", vm_best)
    if at_of_dt:
        row("rk4, dt = 0.01 s (OpenFAST's DT), virtual machine", at_of_dt[0])
    if scene is not None and best.method == "rk4":
        wall, diff = plain_c_loop(scene, best.kwargs["dt"])
        lines.append(f"| same step as a plain C loop (the practical limit; no interpolation to the 0.02 s grid; "
                     f"states equal to {diff:.0e}) | {best.eps:.1e} | {1e3 * wall:.2f} | — | — | "
                     f"{OPENFAST_PAPER45_S / wall:.0f}× | — |")
    notes = [f"\n{best.label} at {best.setting} (compiled: {best.stats.get('compiled')}): {best.steps} steps, "
             f"{best.n_rhs} rhs evaluations. The integration time includes sampling the inputs at the stage "
             "times, the loop, the divergence check and the cubic Hermite interpolation to the 3001 output times. "
             "The whole simulate() call (median, warm caches) adds the cache lookups and the model's OpenFAST "
             "output channels at the 3001 output times (outputs_wall_s "
             f"{1e3 * best.stats.get('outputs_wall_s', float('nan')):.2f} ms in the last run). OpenFAST's "
             f"{OPENFAST_PAPER45_S} s is its whole run, so the whole-call ratio is the like-for-like comparison; the "
             "integration-only ratio is the target metric of issue 7."]
    if scene is not None and ref is not None:
        t_out = ref.t
        res = simulate(scene.model, scene.tmax, scene.x0, method=best.method, t_out=t_out, **best.kwargs)
        e_out, worst = output_epsilon(res, ref)
        notes.append(f"Over the OpenFAST output channels (Q_*, QD_*, QD2_*, Azimuth, RotSpeed, TTDsp*, "
                     f"YawBrTD*, wrap-aware) the largest ε is {e_out:.1e} ({worst}).")
    if scene is not None and best.kwargs.get("compile"):
        cold, warm = cold_preparation(scene, best.kwargs)
        notes.append(f"Preparation with an empty disk cache (C generation + gcc -O1 of the step): "
                     f"{1e3 * cold:.0f} ms; from the disk cache in a new session: {1e3 * warm:.1f} ms; "
                     f"in-process cache hit: {1e3 * best.prepare:.1f} ms.")
    return "\n".join(lines) + "\n" + " ".join(notes), best


def write_readme(marker: str, text: str) -> None:
    """Rewrite one marked section of benchmarks/README.md (shared writer in _report.py)."""
    write_section(marker, text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    parser.add_argument("--quick", action="store_true", help="a few settings per method (smoke test)")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    parser.add_argument("--performance-only", action="store_true",
                        help="run paper45 only and rewrite only the performance section")
    args = parser.parse_args()
    if args.performance_only:
        args.scenes = ["paper45"]
    summary = ["| scene | method | cheapest with ε ≤ 1e-3 | cheapest with ε ≤ 1e-6 | failed |",
               "|---|---|---|---|---|"]
    defaults = ["| scene | accuracy requested | chosen | predicted ε (linear) | estimated ε (step doubling) | "
                "**achieved ε** | integration [ms] (incl. check) | whole call [ms] | cheapest swept setting with the "
                "same ε |", "|---|---:|---|---:|---:|---:|---:|---:|---|"]
    full = ["| scene | method | setting | ε | integration [ms] | steps | rhs evals |",
            "|---|---|---|---:|---:|---:|---:|"]
    refs, perf = [], None
    for name in args.scenes:
        scene = build_scene(name)
        t0 = time.perf_counter()
        runs, ref_eps, ref = run_scene(scene, args.quick, args.repeat)
        refs.append(f"{name}: ε(reference) ≤ {ref_eps:.1e}")
        plot_scene(scene, runs, HERE / "figures" / f"work_precision_{name}.png")
        summary += summary_rows(name, runs)
        defaults += default_rows(name, runs)
        full += full_rows(name, runs)
        print(f"  ({time.perf_counter() - t0:.0f} s)")
        if name == "paper45":
            perf = performance_section(runs, scene, ref)
    text = ("Reference uncertainty (cvodes 1e-12 vs scipy-radau 1e-10): " + "; ".join(refs) + ".\n\n"
            + "**Accuracy-driven default** (`simulate(model, tmax, t_out=..., accuracy=...)`, no method or step "
            "given; `mbsym.simulate.auto`):\n\n" + "\n".join(defaults) + "\n\n"
            + "\n".join(summary) + "\n\n<details><summary>All runs</summary>\n\n" + "\n".join(full)
            + "\n\n</details>")
    print("\n" + text)
    if perf:
        print("\n" + perf[0])
    if not args.no_write and not args.quick:
        if not args.performance_only:
            write_readme("work_precision", text)
        if perf:
            write_readme("performance", perf[0])


if __name__ == "__main__":
    main()
