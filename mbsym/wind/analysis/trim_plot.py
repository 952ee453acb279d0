"""The operating-point figure: rotor speed, pitch, power, thrust and tower-top deflection over wind speed."""

from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

__all__ = ["plot_operating_points", "plot_aero_campbell", "PLOT_CHANNELS"]

#: Panels: channel, axis label, factor: every channel in its OpenFAST unit, as in the table (docs/units.md).
PLOT_CHANNELS = (("RotSpeed", "RotSpeed [rpm]", 1.0), ("BldPitch1", "BldPitch1 [deg]", 1.0),
                 ("GenPwr", "GenPwr [kW]", 1.0), ("RtAeroFxh", "RtAeroFxh [N]", 1.0),
                 ("TTDspFA", "TTDspFA [m]", 1.0))


def plot_operating_points(points, path, *, reference: Mapping[str, Sequence[float]] | None = None,
                          reference_label: str = "OpenFAST", title: str | None = None) -> None:
    """Write the figure of :data:`PLOT_CHANNELS` (and a floating turbine's platform offsets) over wind speed
    to ``path`` (format from its suffix).

    Parameters
    ----------
    points : OperatingPoints
    path : str or Path
    reference : mapping, optional, keyword-only
        ``{"wind_speed": [...], <channel>: [...]}`` in the channels' OpenFAST units (RtAeroFxh in N),
        drawn as markers.
    reference_label : str, optional, keyword-only
    title : str, optional, keyword-only
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    units = points.units()
    channels = PLOT_CHANNELS + tuple((n, f"{n} [{units.get(n, '')}]", 1.0) for n in points.platform_channels()
                                     if not n.startswith("FAIRTEN"))
    fig, axes = plt.subplots(len(channels), 1, figsize=(7, 10 * len(channels) / len(PLOT_CHANNELS)), sharex=True)
    u = points.wind_speed
    for ax, (name, label, scale) in zip(axes, channels):
        ax.plot(u, points.channel(name) * scale, "-", lw=1.5, color="C0", label="mbsym trim")
        if reference is not None and name in reference:
            ax.plot(np.asarray(reference["wind_speed"], dtype=float), np.asarray(reference[name], dtype=float) * scale,
                    "o", ms=4, mfc="none", color="C3", label=reference_label)
        failed = [p.wind_speed for p in points if not p.success]
        if failed:
            ax.plot(failed, np.zeros(len(failed)), "x", color="k", label="failed")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8, loc="lower right")
    axes[-1].set_xlabel("hub-height wind speed [m/s]")
    axes[0].set_title(title or f"Operating points: {points.label}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_aero_campbell(diagram, path, *, title: str | None = None) -> None:
    """Frequency [Hz] and damping ratio [%] of the labelled modes over wind speed (:class:`~.trim_linear.AeroCampbell`)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax_f, ax_z) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for i, m in enumerate(diagram.modes):
        ax_f.plot(diagram.wind_speed, m.freq_hz, "o-", ms=3, color=f"C{i}", label=m.label)
        ax_z.plot(diagram.wind_speed, 100 * np.asarray(m.damping_ratio), "o-", ms=3, color=f"C{i}")
    ax_f.set_ylabel("frequency [Hz]")
    ax_z.set_ylabel("damping ratio [%]")
    ax_z.set_xlabel("hub-height wind speed [m/s]")
    for ax in (ax_f, ax_z):
        ax.grid(True, alpha=0.3)
    ax_f.legend(fontsize=8)
    ax_f.set_title(title or "Modes at the operating points, with aerodynamics and actuators", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
