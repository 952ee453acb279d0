"""First-order wave excitation on the platform, the way HydroDyn computes it (``ExctnMod = 1``).

HydroDyn (v5.0.0, ``WAMIT.f90``) multiplies the elevation's DFT ``C_k`` (:class:`~.waves.IncidentWaves`) by the
WAMIT ``.3`` transfer function ``X(ω_k, β)`` [N/m, N m/m] and transforms back: the excitation is a time
series fixed before the run, periodic with the sea, ``F(t_j) = (1/N) Σ X(ω_k, β) C_k e^{iω_k t_j}``. So the
same elevation gives the same force. HydroDyn's readings of ``X``:

* in frequency, linear between the ``.3`` frequencies, the lowest frequency's value below it (HydroDyn's
  zero-frequency limit) and the highest's above it (its infinite-frequency row is 0 at ``HUGE``);
* in heading, linear between the ``.3`` headings, the wave heading β (minus ``PtfmRefY``) wrapped into their
  range by whole turns;
* in time, between the ``WaveDT`` samples, the periodic Catmull–Rom cubic of the NWTC ``GridInterp``
  (SeaState's ``Wave1Elev`` too), which :meth:`WaveExcitation.at` reproduces.

The platform is taken at its undisplaced position (``ExctnDisp = 0``) with a constant reference yaw
(``PtfmYMod = 0``); the loads act at the WAMIT reference point in inertial axes, as the other platform
loads (:mod:`.operating`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...exceptions import UnsupportedFeatureError
from .waves import IncidentWaves, grid_elevation

__all__ = ["WaveExcitation", "wave_excitation", "excitation_transfer", "EXCITATION_CHANNELS", "catmull_rom"]

#: HydroDyn's first-order excitation channels (body 1) and their units.
EXCITATION_CHANNELS = {"B1WvsFxi": "N", "B1WvsFyi": "N", "B1WvsFzi": "N", "B1WvsMxi": "N-m", "B1WvsMyi": "N-m",
                       "B1WvsMzi": "N-m"}


def catmull_rom(series: np.ndarray, step: float, t: np.ndarray) -> np.ndarray:
    """The periodic Catmull–Rom cubic of ``series`` (samples ``step`` apart, last = first) at times ``t`` [s].

    ``series`` may have trailing dimensions (one column per signal).
    """
    s = np.asarray(series)[:-1]
    n = len(s)
    p = np.asarray(t, dtype=float) / step
    i = np.floor(p).astype(int)
    u = p - i
    if s.ndim > 1:
        u = u[..., None]
    u2, u3 = u * u, u * u * u
    weights = (-0.5 * u3 + u2 - 0.5 * u, 1.5 * u3 - 2.5 * u2 + 1.0, -1.5 * u3 + 2.0 * u2 + 0.5 * u, 0.5 * u3 - 0.5 * u2)
    return sum(w * s[(i + j) % n] for w, j in zip(weights, (-1, 0, 1, 2)))


def excitation_transfer(wamit, omega: np.ndarray, heading) -> np.ndarray:
    """``X(ω, β)`` (len(ω) × 6, complex) [N/m, N m/m] read as HydroDyn reads the ``.3`` data (module docstring).

    Parameters
    ----------
    wamit : WamitHydrodynamics
        With its excitation (``read_wamit(..., excitation=True)``).
    omega : array
        Frequencies [rad/s].
    heading : float or array
        Wave heading relative to the platform [rad]: one, or one per frequency (a spread sea).
    """
    if wamit.excitation is None:
        raise UnsupportedFeatureError("the WAMIT data have no excitation (.3 file); waves need it. Provide the .3 file.")
    w = np.asarray(omega, dtype=float)
    beta = np.broadcast_to(np.asarray(heading, dtype=float), w.shape)
    out = np.zeros((len(w), 6), dtype=complex)
    for value in np.unique(beta):
        at = beta == value
        out[at] = _transfer_at(wamit, w[at], float(value))
    return out


def _transfer_at(wamit, w: np.ndarray, heading: float) -> np.ndarray:
    """``X`` at frequencies ``w`` for one heading [rad]."""
    freq = np.asarray(wamit.excitation_frequencies, dtype=float)
    heads = np.degrees(np.asarray(wamit.headings, dtype=float))
    order = np.argsort(heads)
    heads, data = heads[order], wamit.excitation[:, order, :6]
    beta = math.degrees(heading)
    beta -= 360.0 * math.floor((beta - heads[0]) / 360.0)            # into [first, first + 360)
    if beta > heads[-1] + 1e-9:
        if len(heads) > 1 or not math.isclose(beta - 360.0, heads[0], abs_tol=1e-9):
            raise UnsupportedFeatureError(f"the .3 file covers wave headings {heads[0]:g}..{heads[-1]:g} deg; the "
                                          f"waves come from {math.degrees(heading):g} deg. Use a heading inside that "
                                          "range or rerun WAMIT with more headings.")
        beta = heads[0]
    if len(heads) == 1:
        at_heading = data[:, 0, :]
    else:
        j = min(max(int(np.searchsorted(heads, beta, side="right")) - 1, 0), len(heads) - 2)
        f = (beta - heads[j]) / (heads[j + 1] - heads[j])
        at_heading = (1 - f) * data[:, j, :] + f * data[:, j + 1, :]
    return np.stack([np.interp(w, freq, at_heading[:, m].real) + 1j * np.interp(w, freq, at_heading[:, m].imag)
                     for m in range(at_heading.shape[1])], axis=1)


@dataclass(frozen=True, eq=False)
class WaveExcitation:
    """The sea at the platform: the first-order excitation and the elevation at the output point.

    Attributes
    ----------
    waves : IncidentWaves
    forces : (N + 1, 6) ndarray
        Excitation [N, N m] at the WAMIT reference point, inertial axes, on ``waves.times()``.
    elevation : (N + 1,) ndarray
        η [m] at the elevation output point (``WaveElevxi(1)``, ``WaveElevyi(1)``; ``Wave1Elev``).
    """

    waves: IncidentWaves
    forces: np.ndarray
    elevation: np.ndarray

    def at(self, t) -> np.ndarray:
        """``[F (6), η]`` at times ``t`` [s] (rows), as HydroDyn and SeaState interpolate them."""
        table = np.column_stack([self.forces, self.elevation])
        return catmull_rom(table, self.waves.time_step, np.atleast_1d(np.asarray(t, dtype=float)))

    def tables(self, t_end: float, max_step: float = 0.025) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Input tables ``name → (t, values)`` over ``[0, t_end]`` [s], the cubic sampled at most ``max_step`` apart.

        Sampled finely enough that linear interpolation between samples (how :func:`mbsym.simulate` reads
        tables) stays within ~1e-4 of the cubic for waves longer than 2 s.
        """
        dt = self.waves.time_step
        per = max(1, math.ceil(dt / max_step - 1e-9))
        n = math.ceil(float(t_end) / (dt / per) - 1e-9) + 1
        t = (dt / per) * np.arange(n)
        values = self.at(t)
        names = (*EXCITATION_CHANNELS, "Wave1Elev")
        return {name: (t, values[:, k]) for k, name in enumerate(names)}


def wave_excitation(wamit, waves: IncidentWaves, *, reference_yaw: float = 0.0,
                    elevation_point: tuple[float, float] = (0.0, 0.0), sea=None) -> WaveExcitation:
    """The :class:`WaveExcitation` of ``waves`` on a platform with the WAMIT data ``wamit``.

    Parameters
    ----------
    wamit : WamitHydrodynamics
    waves : IncidentWaves
    reference_yaw : float, keyword-only
        HydroDyn's ``PtfmRefY`` [rad] (the heading seen by the platform is β − PtfmRefY).
    elevation_point : (float, float), keyword-only
        Where ``Wave1Elev`` is taken [m].
    sea : SeaStateInput, optional, keyword-only
        Its surface grid, to read ``Wave1Elev`` off it as SeaState does (:func:`~.waves.grid_elevation`); without
        it the exact elevation at the point.
    """
    transfer = excitation_transfer(wamit, waves.frequencies, waves.headings() - reference_yaw)
    forces = np.column_stack([waves.series(transfer[:, m] * waves.spectrum) for m in range(6)])
    elevation = waves.elevation(*elevation_point) if sea is None else grid_elevation(waves, sea, *elevation_point)
    return WaveExcitation(waves, forces, elevation)
