"""The closed-loop figure: loop margins and closed-loop poles over wind speed (a ``ClosedLoopSweep``)."""

from __future__ import annotations

import numpy as np

from .closed_loop import LOOPS

__all__ = ["plot_closed_loop", "plot_loop_bode", "POLE_PLOT_MAX_HZ"]

#: Closed-loop poles above this frequency [Hz] (actuators, controller memories) are left out of the pole panels.
POLE_PLOT_MAX_HZ = 2.0


def plot_closed_loop(sweep, path, *, title: str | None = None) -> None:
    """Write gain and phase margins of both loops and the closed-loop poles below :data:`POLE_PLOT_MAX_HZ`
    (frequency and damping ratio, coloured by their label) over wind speed to ``path`` (format from its suffix).

    Inactive loops and infinite margins are not drawn (the legend says which loops were inactive where).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = sweep.to_dict()
    u = np.asarray(data["wind_speed"], dtype=float)
    fig, axes = plt.subplots(4, 1, figsize=(7, 11), sharex=True)
    for color, loop in (("C0", "pitch"), ("C3", "torque")):
        for ax, key, unit in ((axes[0], "gain_margin_db", "dB"), (axes[1], "phase_margin_deg", "deg")):
            v = np.array([np.nan if x is None else x for x in data[f"{loop}_{key}"]], dtype=float)
            ax.plot(u, v, "o-", ms=3, color=color, label=f"{loop} loop (at {LOOPS[loop]})")
    axes[0].set_ylabel("gain margin [dB]")
    axes[1].set_ylabel("phase margin [deg]")
    labels: dict[str, int] = {}
    for k, poles in enumerate(data["closed_loop_poles"]):
        for p in poles:
            if p["freq_hz"] > POLE_PLOT_MAX_HZ:
                continue
            new = p["label"] not in labels
            i = labels.setdefault(p["label"], len(labels))
            kw = {"color": f"C{i % 10}", "marker": "os^vD"[(i // 10) % 5], "ms": 4, "ls": "none"}
            axes[2].plot(u[k], p["freq_hz"], **kw)
            axes[3].plot(u[k], 100 * p["damping_ratio"], **kw, label=p["label"] if new else None)
    axes[2].set_ylabel("closed-loop pole [Hz]")
    axes[3].set_ylabel("damping ratio [%]")
    axes[3].set_yscale("symlog", linthresh=1.0)
    axes[3].set_xlabel("hub-height wind speed [m/s]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[3].legend(fontsize=6, ncol=2, loc="lower right")
    unstable = [f"{v:g}" for v, s in zip(u, data["stable"]) if s is False]
    note = f"; UNSTABLE at {', '.join(unstable)} m/s" if unstable else ""
    axes[0].set_title((title or f"Closed loop with the baseline controller (dt = {data['sample_time']:g} s)") + note,
                      fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)



def plot_loop_bode(cl, path, *, title: str | None = None) -> None:
    """Write the Bode plot of the pitch and torque loops of ``cl`` (a ``ClosedLoopLinear``) to ``path``.

    The phase is wrapped into (−360°, 0°] (:meth:`mbsym.linear.FrequencyResponse.wrapped_phase_deg`: every
    crossing of the negative real axis is a crossing of the −180° line; the continuous phase of a sampled
    loop reaches −810° at the Nyquist frequency), with a break where it wraps; 0 dB and −180° are drawn, the
    crossovers of the margins marked. An inactive loop (zero) is not drawn.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (mag, ph) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for color, loop in (("C0", "pitch"), ("C3", "torque")):
        m = cl.margins[loop]
        if not m.active:
            continue
        r = cl.frequency_response(loop)
        phase = r.wrapped_phase_deg()
        wraps = np.flatnonzero(np.abs(np.diff(phase)) > 180.0)
        f, phase = np.insert(r.freq_hz, wraps + 1, np.nan), np.insert(phase, wraps + 1, np.nan)
        db = np.insert(r.magnitude_db, wraps + 1, np.nan)
        label = (f"{loop} loop (at {LOOPS[loop]}): GM {m.gain_margin_db:.3g} dB, PM {m.phase_margin_deg:.3g} deg")
        mag.semilogx(f, db, color=color, label=label)
        ph.semilogx(f, phase, color=color)
        for ax, crossover in ((mag, m.gain_crossover_hz), (ph, m.phase_crossover_hz)):
            if np.isfinite(crossover):
                ax.axvline(crossover, color=color, ls=":", lw=0.8)
    mag.axhline(0.0, color="k", lw=0.6)
    ph.axhline(-180.0, color="k", lw=0.6)
    ph.set_ylim(-360.0, 0.0)
    ph.set_yticks(np.arange(-360.0, 1.0, 90.0))
    mag.set_ylabel("|L| [dB]")
    ph.set_ylabel("phase of L [deg], wrapped to (-360, 0]")
    ph.set_xlabel("frequency [Hz]")
    for ax in (mag, ph):
        ax.grid(True, which="both", alpha=0.3)
    mag.legend(fontsize=8)
    mag.set_title(title or f"Loop transfer functions at {cl.wind_speed:g} m/s (region {cl.region}), baseline "
                           f"controller, dt = {cl.dt:g} s", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
