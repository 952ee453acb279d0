"""Tables and charts of benchmarks/control.py from its stored results (JSON lines)."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
FIG = HERE / "figures"
ORDER = ("ROSCO", "baseline", "NMPC preview", "NMPC + MHE", "NMPC + EKF", "baseline + MHE", "ROSCO, no peak shaving")
METRICS = (("speed_rms_rpm", "speed RMS err [rpm]", "{:.1f}"), ("power_mean_kw", "power mean [kW]", "{:.0f}"),
           ("power_std_kw", "power std [kW]", "{:.0f}"), ("pitch_travel_deg", "pitch travel [deg]", "{:.0f}"),
           ("pitch_rate_rms_degs", "pitch-rate RMS [deg/s]", "{:.2f}"),
           ("del_twrbsmyt_knm", "TwrBsMyt DEL [MN m]", "{:.1f}"))


def _mean(rows, key):
    v = [r[key] for r in rows if key in r and r[key] is not None]
    return float(np.mean(v)) if v else float("nan")


def closed_loop_tables(rows, tmax) -> str:
    cl = [r for r in rows if r["stage"] == "closed_loop" and r["tmax"] == tmax]
    by = defaultdict(list)
    for r in cl:
        by[(r["wind"], r["label"])].append(r)
    winds = sorted({r["wind"] for r in cl})
    out = [f"Mean over the seeds {sorted({r['seed'] for r in cl})} ({tmax:g} s each, statistics after "
           f"{30:g} s); in brackets the ratio to ROSCO. Speed error: against the rated generator speed at 14 "
           "and 18 m/s, against the speed schedule of the wind at 8 m/s. Energy = power mean × time.", "",
           "| wind | controller | " + " | ".join(m[1] for m in METRICS) + " | controller step median / max [ms] |",
           "|---|---|" + "---:|" * (len(METRICS) + 1)]
    for u in winds:
        ref = by.get((u, "ROSCO"))
        for label in ORDER:
            rs = by.get((u, label))
            if not rs:
                continue
            cells = []
            for key, _, fmt in METRICS:
                v = _mean(rs, key)
                scale = 1e-3 if key == "del_twrbsmyt_knm" else 1.0
                text = fmt.format(v * scale)
                if ref is not None and label != "ROSCO":
                    text += f" ({v / _mean(ref, key):.2f})"
                cells.append(text)
            worst = max(r.get("controller_step_max_s", np.nan) for r in rs)
            step = f"{1e3 * _mean(rs, 'controller_step_median_s'):.3f} / {1e3 * worst:.1f}"
            if not np.isfinite(worst):
                step = "compiled into the loop"
            out.append(f"| {u:g} m/s | {label} | " + " | ".join(cells) + f" | {step} |")
    out += ["", "Per seed (ratios to ROSCO in the same wind: tower-base DEL / speed RMS error / pitch-rate RMS / "
            "energy):", "", "| wind | seed | " + " | ".join(ORDER[1:5]) + " |", "|---|---|" + "---|" * 4]
    for u in winds:
        for seed in sorted({r["seed"] for r in cl if r["wind"] == u}):
            ref = next((r for r in cl if r["wind"] == u and r["seed"] == seed and r["label"] == "ROSCO"), None)
            cells = []
            for label in ORDER[1:5]:
                r = next((r for r in cl if r["wind"] == u and r["seed"] == seed and r["label"] == label), None)
                if r is None or ref is None:
                    cells.append("—")
                    continue
                cells.append(" / ".join(f"{r[k] / ref[k]:.2f}" for k in ("del_twrbsmyt_knm", "speed_rms_rpm",
                                                                          "pitch_rate_rms_degs", "power_mean_kw")))
            out.append(f"| {u:g} | {seed} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def targets_table(rows, tmax) -> str:
    """The issue's closed-loop targets at 14 m/s, mean over the seeds."""
    cl = [r for r in rows if r["stage"] == "closed_loop" and r["tmax"] == tmax and r["wind"] == 14.0]
    get = {label: [r for r in cl if r["label"] == label] for label in ORDER}
    if not get["ROSCO"]:
        return ""
    ro = {k: _mean(get["ROSCO"], k) for k in ("pitch_rate_rms_degs", "del_twrbsmyt_knm", "speed_rms_rpm",
                                             "power_mean_kw")}
    nops = _mean(get["ROSCO, no peak shaving"], "power_mean_kw") if get["ROSCO, no peak shaving"] else float("nan")
    lines = ["| 14 m/s, mean of the seeds | pitch-rate RMS vs ROSCO (±10 %) | tower DEL vs ROSCO | speed RMS vs "
             "ROSCO | energy vs ROSCO (≥ -0.5 %) | energy vs ROSCO without peak shaving |", "|---|---|---|---|---|---|"]
    for label, del_t, spd_t in (("NMPC preview", -25, -15), ("NMPC + MHE", -10, 0), ("NMPC + EKF", -10, 0)):
        rs = get[label]
        if not rs:
            continue
        d = {k: 100 * (_mean(rs, k) / ro[k] - 1) for k in ro}
        e_nops = 100 * (_mean(rs, "power_mean_kw") / nops - 1)
        ok = lambda c: "met" if c else "**not met**"  # noqa: E731
        lines.append(f"| {label} (target DEL ≤ {del_t} %, speed ≤ {spd_t} %) | {d['pitch_rate_rms_degs']:+.1f} % "
                     f"({ok(abs(d['pitch_rate_rms_degs']) <= 10)}) | {d['del_twrbsmyt_knm']:+.1f} % "
                     f"({ok(d['del_twrbsmyt_knm'] <= del_t)}) | {d['speed_rms_rpm']:+.1f} % "
                     f"({ok(d['speed_rms_rpm'] <= spd_t)}) | {d['power_mean_kw']:+.2f} % "
                     f"({ok(d['power_mean_kw'] >= -0.5)}) | {e_nops:+.2f} % |")
    return "\n".join(lines)


def estimator_table(rows, tmax) -> str:
    est = [r for r in rows if r["stage"] == "closed_loop" and r["tmax"] == tmax and "est_wind_rms" in r]
    if not est:
        return ""
    lines = ["| wind | estimator (controller) | wind RMS err [m/s] | wind corr | RtVAvgxh RMS err [m/s] | TTDspFA RMS "
             "err [mm] (% of its std) | RotSpeed RMS err [rpm] | step median / max [ms] | failures |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|"]
    by = defaultdict(list)
    for r in est:
        by[(r["wind"], r["label"])].append(r)
    for (u, label), rs in sorted(by.items()):
        pct = 100 * _mean(rs, "est_ttdspfa_rms") / _mean(rs, "est_ttdspfa_std")
        corr = min(r["est_wind_corr"] for r in rs)
        lines.append(f"| {u:g} m/s | {label} | {_mean(rs, 'est_wind_rms'):.3f} | {corr:.4f} | "
                     f"{_mean(rs, 'est_rtvavg_rms'):.3f} | {1e3 * _mean(rs, 'est_ttdspfa_rms'):.1f} ({pct:.1f} %) | "
                     f"{_mean(rs, 'est_rotspeed_rms'):.4f} | {1e3 * _mean(rs, 'estimator_step_median_s'):.2f} / "
                     f"{1e3 * max(r['estimator_step_max_s'] for r in rs):.1f} | "
                     f"{sum(int(r.get('estimator_failures', 0)) for r in rs)} |")
    return "\n".join(lines)


def tradeoff(rows, tmax) -> str:
    tr = [r for r in rows if r["stage"] == "tradeoff" and r["tmax"] == tmax]
    if not tr:
        return ""
    ref = [r for r in rows if r["stage"] == "closed_loop" and r["tmax"] == tmax and r["label"] == "ROSCO"
           and r["wind"] == 14.0 and r["seed"] in {t["seed"] for t in tr}]
    lines = ["| controller | pitch-rate scale [deg/s] | pitch-rate RMS [deg/s] | tower DEL [MN m] | speed RMS err "
             "[rpm] | power std [kW] | power mean [kW] |", "|---|---:|---:|---:|---:|---:|---:|"]
    for r in ref:
        lines.append(f"| ROSCO | — | {r['pitch_rate_rms_degs']:.2f} | {r['del_twrbsmyt_knm'] / 1e3:.1f} | "
                     f"{r['speed_rms_rpm']:.1f} | {r['power_std_kw']:.0f} | {r['power_mean_kw']:.0f} |")
    for r in sorted(tr, key=lambda r: (r["label"], r["pitch_rate_scale_degs"])):
        lines.append(f"| {r['label']} | {r['pitch_rate_scale_degs']:g} | {r['pitch_rate_rms_degs']:.2f} | "
                     f"{r['del_twrbsmyt_knm'] / 1e3:.1f} | {r['speed_rms_rpm']:.1f} | {r['power_std_kw']:.0f} | "
                     f"{r['power_mean_kw']:.0f} |")
    _tradeoff_plot(tr, ref)
    return "\n".join(lines)


def _tradeoff_plot(tr, ref) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for label, marker in (("NMPC preview", "o-"), ("NMPC + MHE", "s-")):
        rs = sorted([r for r in tr if r["label"] == label], key=lambda r: r["pitch_rate_rms_degs"])
        x = [r["pitch_rate_rms_degs"] for r in rs]
        axes[0].plot(x, [r["del_twrbsmyt_knm"] / 1e3 for r in rs], marker, label=label)
        axes[1].plot(x, [r["speed_rms_rpm"] for r in rs], marker, label=label)
        for r in rs:
            xy = (r["pitch_rate_rms_degs"], r["del_twrbsmyt_knm"] / 1e3)
            axes[0].annotate(f"{r['pitch_rate_scale_degs']:g}", xy, fontsize=7, xytext=(3, 3),
                             textcoords="offset points")
    for r in ref:
        axes[0].plot(r["pitch_rate_rms_degs"], r["del_twrbsmyt_knm"] / 1e3, "k*", ms=12, label="ROSCO")
        axes[1].plot(r["pitch_rate_rms_degs"], r["speed_rms_rpm"], "k*", ms=12, label="ROSCO")
        for ax in axes:
            ax.axvspan(0.9 * r["pitch_rate_rms_degs"], 1.1 * r["pitch_rate_rms_degs"], color="0.9")
    axes[0].set_ylabel("tower-base fore-aft DEL (m = 4, 1 Hz) [MN m]")
    axes[1].set_ylabel("generator-speed RMS error [rpm]")
    for ax in axes:
        ax.set_xlabel("pitch-rate RMS [deg/s]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("NMPC tunings (pitch-rate scale, deg/s, annotated) at 14 m/s; grey: ROSCO's pitch activity ±10 %",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(FIG / "control_tradeoff.png", dpi=110)
    plt.close(fig)


def bars(rows, tmax) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    cl = [r for r in rows if r["stage"] == "closed_loop" and r["tmax"] == tmax]
    winds = sorted({r["wind"] for r in cl})
    labels = [lab for lab in ORDER[1:5] if any(r["label"] == lab for r in cl)]
    keys = (("del_twrbsmyt_knm", "tower DEL"), ("speed_rms_rpm", "speed RMS err"),
            ("pitch_rate_rms_degs", "pitch-rate RMS"), ("power_std_kw", "power std"), ("power_mean_kw", "energy"))
    fig, axes = plt.subplots(1, len(winds), figsize=(4.2 * len(winds), 4), sharey=True)
    axes = np.atleast_1d(axes)
    for ax, u in zip(axes, winds):
        ref = {k: _mean([r for r in cl if r["wind"] == u and r["label"] == "ROSCO"], k) for k, _ in keys}
        w = 0.8 / max(len(labels), 1)
        for i, lab in enumerate(labels):
            rs = [r for r in cl if r["wind"] == u and r["label"] == lab]
            vals = [_mean(rs, k) / ref[k] for k, _ in keys]
            ax.bar(np.arange(len(keys)) + i * w, vals, w, label=lab)
        ax.axhline(1.0, color="k", lw=0.8)
        ax.set_xticks(np.arange(len(keys)) + 0.4 - w / 2)
        ax.set_xticklabels([k[1] for k in keys], rotation=30, fontsize=8)
        ax.set_title(f"{u:g} m/s (ratio to ROSCO)", fontsize=9)
        ax.grid(axis="y", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(FIG / "control_closed_loop.png", dpi=110)
    plt.close(fig)


def ladder(rows) -> str:
    eps = [r for r in rows if r["stage"] == "ladder_eps"]
    nm = [r for r in rows if r["stage"] == "ladder_nmpc"]
    if not eps:
        return ""
    e = eps[-1]
    lines = [f"Closed loop with our baseline controller, Kaimal {e['wind']:g} m/s seed {e['seed']}, {e['tmax']:g} s; "
             f"ε against the richest rung (the plant's own DOFs and inflow); smallest rung within 2 %: "
             f"**{e['smallest']}**. Number in brackets: states of the prediction model (control form).", "",
             e["table"]]
    if nm:
        lines += ["", "The NMPC (ideal 5 s preview, default tuning) with each rung as its prediction model, against "
                  "the full plant, same wind:", "",
                  "| prediction model | states | speed RMS err [rpm] | tower DEL [MN m] | pitch-rate RMS [deg/s] | "
                  "power mean [kW] | step median / max [ms] |", "|---|---:|---:|---:|---:|---:|---:|"]
        for r in nm:
            lines.append(f"| {' + '.join(r['rung'])} | {r['states']} | {r['speed_rms_rpm']:.1f} | "
                         f"{r['del_twrbsmyt_knm'] / 1e3:.1f} | {r['pitch_rate_rms_degs']:.2f} | "
                         f"{r['power_mean_kw']:.0f} | {1e3 * r['controller_step_median_s']:.2f} / "
                         f"{1e3 * r['controller_step_max_s']:.1f} |")
    return "\n".join(lines)


def sizes(rows) -> str:
    sz = [r for r in rows if r["stage"] == "size"]
    if not sz:
        return ""
    lines = ["| prediction model | states | rhs SX instructions | build, cold cache [s] | step median [ms] (prep / "
             "QP feedback) | step max / p99 [ms] | first step [ms] | failures | load |",
             "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in sz:
        lines.append(f"| {r['label']} | {r['states']} | {r['rhs_instructions']} | {r['build_s']:.1f} | "
                     f"{1e3 * r['median_s']:.2f} ({1e3 * r['prep_median_s']:.2f} / "
                     f"{1e3 * r['feedback_median_s']:.2f}) | "
                     f"{1e3 * r['max_s']:.1f} / {1e3 * r['p99_s']:.1f} | {1e3 * r['first_s']:.0f} | "
                     f"{r['failures']} / {r['steps']} | {r['load']:.1f} |")
    return "\n".join(lines)


def report(rows, tmax) -> str:
    FIG.mkdir(exist_ok=True)
    parts = ["#### Closed loop: NMPC vs our baseline vs the ROSCO library", "", closed_loop_tables(rows, tmax), "",
             "![closed loop](figures/control_closed_loop.png)", "", "#### Targets at 14 m/s", "",
             targets_table(rows, tmax), "", "#### Trade-off across NMPC tunings (14 m/s)", "", tradeoff(rows, tmax),
             "", "![trade-off](figures/control_tradeoff.png)", "", "#### Estimators (20 Hz, sensor noise on)", "",
             estimator_table(rows, tmax), "", "#### The prediction model (fidelity ladder in closed loop)", "",
             ladder(rows), "", "![ladder](figures/control_prediction_ladder.png)", "",
             "#### NMPC step and build times by model size (RTI, hpipm, N = 40, dt = 0.1 s, compiled)", "",
             sizes(rows)]
    if any(r["stage"] == "closed_loop" for r in rows):
        bars(rows, tmax)
    return "\n".join(parts)
