"""Where methods fail: the largest stable step of every fixed-step method on the stiff rotor scene.

Scene: ``stiff_rotor`` of ``work_precision.py`` (hub on a geared drivetrain with torsion
spring and damper, three NREL 5 MW blades with their first edgewise mode, gravity, 12.1
rpm, blade 1 released from 0.5 m). The linearization at t = 0 (Jacobian of the rhs)
has |lambda|max = 22.1 rad/s, so classical RK4 should be stable only for dt below
about 2.78 / |lambda|max (2.83 / |lambda|max on the imaginary axis).

1. Largest stable step, by bisection on the number of steps over a 200 s run (long
   enough that an amplification of 1 % per step grows a mode ~1e6-fold): a step counts
   as unstable when the method raises ``IntegrationError`` (divergence, NaN, Newton
   failure) or when a state grows beyond 100 times its largest magnitude in the
   reference (an inaccurate but stable method stays well below; an unstable one passes
   it within a few hundred steps). Search between 1 ms and 2 s (the cap: a method stable
   at 2 s is reported as "stable up to the cap"). Resolution 0.5 % in dt.
2. Error at steps around it, over the 20 s scene (ε as in ``work_precision.py``, on a
   0.02 s output grid, against cvodes at rtol = atol = 1e-12). Failures are reported
   with the method's own message, not hidden.
3. The adaptive explicit method (``adams``) against BDF (``cvodes``): steps taken as the
   tolerance loosens (down to rtol = 1, far looser than anyone would run, to expose the
   limit). Explicit: the step count stops falling at the stability limit.

All runs use compiled C (``compile=True``). Writes
``benchmarks/figures/stability_stiff_rotor.png`` and the tables into
``benchmarks/README.md`` between the ``stability`` markers.

Run: ``python benchmarks/stability.py [--no-write]``.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from mbsym.exceptions import IntegrationError
from mbsym.simulate import METHODS, simulate
from mbsym.simulate.base import jacobian_function

from work_precision import DT_OUT, HERE, epsilon, stiff_rotor_scene, write_readme

T_LONG = 200.0
DT_MIN, DT_CAP = 1e-3, 2.0
FACTORS = (0.25, 0.5, 0.9, 0.99, 1.01, 1.1, 2.0)


def rho_max(scene) -> float:
    eom = scene.model.eom
    J = np.array(jacobian_function(eom)(scene.x0, np.zeros(eom.n_u), eom.parameter_vector({})))
    return float(np.max(np.abs(np.linalg.eigvals(J))))


class Judge:
    """Runs a fixed-step method and classifies the result as stable or not (see the module docstring)."""

    def __init__(self, scene):
        self.scene = scene
        self.t_out = np.round(np.arange(0.0, T_LONG + 0.05, 0.1), 10)
        self.ref = simulate(scene.model, T_LONG, scene.x0, method="cvodes", rtol=1e-10, atol=1e-10,
                            t_out=self.t_out)

    def stable(self, method: str, n: int) -> bool:
        try:
            res = simulate(self.scene.model, T_LONG, self.scene.x0, method=method, dt=T_LONG / n,
                           t_out=self.t_out, compile=True)
        except IntegrationError:
            return False
        growth = np.max(np.abs(res.x), axis=0) / (np.max(np.abs(self.ref.x), axis=0) + 1e-12)
        return bool(np.max(growth) <= 100.0)


def largest_stable_step(judge: Judge, method: str) -> tuple[float, bool]:
    """(largest stable dt [s], capped) by bisection on the number of steps over T_LONG."""
    n_cap = int(round(T_LONG / DT_CAP))
    if judge.stable(method, n_cap):
        return DT_CAP, True
    n_bad, n_good = n_cap, n_cap * 2
    while not judge.stable(method, n_good):
        n_bad, n_good = n_good, n_good * 2
        if T_LONG / n_good < DT_MIN:
            return float("nan"), False
    while n_good - n_bad > max(1, int(0.005 * n_bad)):
        mid = (n_good + n_bad) // 2
        if judge.stable(method, mid):
            n_good = mid
        else:
            n_bad = mid
    return T_LONG / n_good, False


def errors_around(scene, ref, method: str, dts) -> list[tuple[float, float, str]]:
    t_out = np.round(np.arange(0.0, scene.tmax + DT_OUT / 2, DT_OUT), 10)
    out = []
    for dt in dts:
        try:
            res = simulate(scene.model, scene.tmax, scene.x0, method=method, dt=dt, t_out=t_out, compile=True)
            out.append((res.statistics["dt"], epsilon(res.x, ref.x), ""))
        except IntegrationError as exc:
            out.append((dt, float("inf"), str(exc)))
    return out


def adams_vs_bdf(scene) -> list[tuple[float, float, float]]:
    """Steps of adams and cvodes per rtol (NaN: the run failed, reported in the table)."""
    rows = []
    for rtol in (1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6):
        kw = {"rtol": rtol, "atol": rtol / 100, "compile": True}
        steps = []
        for method in ("adams", "cvodes"):
            try:
                steps.append(simulate(scene.model, scene.tmax, scene.x0, method=method, **kw).statistics["steps"])
            except IntegrationError:
                steps.append(float("nan"))
        rows.append((rtol, *steps))
    return rows


def _n(v: float) -> str:
    return "failed" if not np.isfinite(v) else f"{int(v)}"


def plot(path: Path, curves, limits, predicted, adams_rows) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.6))
    ceiling = 10.0
    for i, (method, pts) in enumerate(curves.items()):
        color = f"C{i}"
        ok = [(dt, e) for dt, e, msg in pts if not msg and np.isfinite(e)]
        bad = [dt for dt, e, msg in pts if msg or not np.isfinite(e)]
        if ok:
            ax.loglog(*zip(*sorted(ok)), "o-", color=color, label=method, ms=4)
        if bad:
            ax.loglog(bad, [ceiling] * len(bad), "x", color=color, ms=9, mew=2,
                      label=f"{method}: failed (IntegrationError)")
        dt_max, capped = limits[method]
        if not capped:
            ax.axvline(dt_max, color=color, ls="--", lw=1)
    ax.axvline(predicted, color="0.3", ls=":", lw=1, label=f"2.78/|λ|max = {predicted:.3f} s")
    ax.set_xlabel("step dt [s]")
    ax.set_ylabel("ε (20 s run, vs cvodes 1e-12)")
    ax.set_title("fixed-step methods on the stiff rotor (dashed: largest stable dt)", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    r, a, b = zip(*adams_rows)
    bx.loglog(r, a, "o-", label="adams (explicit)")
    bx.loglog(r, b, "s-", label="cvodes (BDF)")
    bx.set_xlabel("rtol")
    bx.set_ylabel("steps (20 s)")
    bx.set_title("adaptive: adams levels off at its stability limit, BDF keeps falling", fontsize=9)
    bx.grid(True, which="both", alpha=0.3)
    bx.legend(fontsize=8)
    fig.tight_layout()
    path.parent.mkdir(exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-write", action="store_true", help="do not update benchmarks/README.md")
    args = parser.parse_args()
    scene = stiff_rotor_scene()
    rho = rho_max(scene)
    predicted = 2.78 / rho
    print(f"|lambda|max at t = 0: {rho:.2f} rad/s; rk4 linear limit 2.78/|lambda| = {predicted:.4f} s")
    judge = Judge(scene)
    t_out = np.round(np.arange(0.0, scene.tmax + DT_OUT / 2, DT_OUT), 10)
    ref = simulate(scene.model, scene.tmax, scene.x0, method="cvodes", rtol=1e-12, atol=1e-12, t_out=t_out)
    fixed = [m for m, c in METHODS.items() if c.kind == "fixed-step"]
    limits, curves = {}, {}
    lim_rows = ["| method | explicit | largest stable dt [s] | ρ · dt (ρ = &#124;λ&#124;max) | verdict |",
                "|---|---|---:|---:|---|"]
    err_rows = ["| method | dt [s] | dt / dt_ref | ε (20 s) | result |", "|---|---:|---:|---:|---|"]
    for m in fixed:
        dt_max, capped = largest_stable_step(judge, m)
        limits[m] = (dt_max, capped)
        explicit = not METHODS[m].implicit
        verdict = (f"stable up to the {DT_CAP:g} s cap" if capped
                   else f"unstable beyond {dt_max:.4g} s (predicted {predicted:.4g} s)")
        lim_rows.append(f"| {m} | {'yes' if explicit else 'no'} | {'≥ ' if capped else ''}{dt_max:.4g} | "
                        f"{rho * dt_max:.3g} | {verdict} |")
        print(lim_rows[-1], flush=True)
        base = dt_max if not capped else predicted
        dts = [f * base for f in FACTORS] + ([0.5, 1.0, 2.0] if capped else [])
        curves[m] = errors_around(scene, ref, m, sorted(set(dts)))
        for dt, e, msg in curves[m]:
            result = "failed: " + msg.split(". ")[0] if msg else "stable"
            err_rows.append(f"| {m} | {dt:.4g} | {dt / base:.2f} | {'—' if msg else f'{e:.2e}'} | {result} |")
    adams_rows = adams_vs_bdf(scene)
    ad_rows = ["| rtol | adams steps | cvodes steps |", "|---:|---:|---:|"]
    ad_rows += [f"| {r:.0e} | {_n(a)} | {_n(b)} |" for r, a, b in adams_rows]
    plot(HERE / "figures" / "stability_stiff_rotor.png", curves, limits, predicted, adams_rows)
    text = (f"|λ|max at t = 0: {rho:.2f} rad/s (linearization of the rhs); RK4's linear stability limit "
            f"2.78 / |λ|max = {predicted:.4f} s.\n\n" + "\n".join(lim_rows)
            + "\n\ndt_ref: the method's largest stable step, or RK4's predicted limit for a method stable up to "
            "the cap.\n\n" + "\n".join(err_rows)
            + "\n\n" + "\n".join(ad_rows))
    print("\n" + text)
    if not args.no_write:
        write_readme("stability", text)


if __name__ == "__main__":
    main()
