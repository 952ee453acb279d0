"""Turbulent hub-height wind: a reproducible time series with the Kaimal spectrum.

Algorithm (a random-phase Fourier synthesis, as in Veers 1988 / TurbSim for one point):

1. time grid ``t_n = n dt``, ``n = 0 … N−1`` with ``N = round(duration/dt)`` rounded up
   to an even number; frequencies ``f_k = k / (N dt)``, ``k = 1 … N/2 − 1`` (the mean
   ``k = 0`` and the Nyquist bin carry nothing);
2. one-sided IEC Kaimal spectrum of the longitudinal component (IEC 61400-1 ed. 3,
   Annex B): ``S(f) = 4 σ² (L/U) / (1 + 6 f L/U)^(5/3)`` with ``σ = TI · U`` and the
   integral length scale ``L`` (IEC: ``L = 8.1 Λ1 = 340.2 m`` above 60 m hub height);
3. amplitudes ``a_k = sqrt(2 S(f_k) Δf)``, scaled by one common factor so that
   ``Σ a_k² / 2 = σ²`` exactly: the variance the grid cannot resolve (below ``1/duration``
   and above the Nyquist frequency, a few percent) is given back in proportion to the
   spectrum, so the series has exactly the requested standard deviation;
4. phases ``φ_k`` uniform in ``[0, 2π)`` from ``numpy.random.default_rng(seed)``
   (PCG64): the same ``seed`` gives the same series;
5. ``u(t_n) = U + Σ_k a_k cos(2π f_k t_n + φ_k)`` by one inverse real FFT.

Over ``[0, duration)`` the series therefore has mean ``U`` and standard deviation
``TI · U`` exactly (to rounding); it is periodic, and the table also holds the
point ``t = duration`` (equal to ``t = 0``) so it covers ``[0, duration]``.
"""

from __future__ import annotations

import math
from numbers import Integral

import numpy as np

from ...exceptions import WindInputError
from .signals import TabulatedWind, _number

__all__ = ["kaimal_spectrum", "kaimal_wind", "KaimalWind", "IEC_LENGTH_SCALE"]

#: IEC 61400-1 ed. 3 integral length scale of the longitudinal component for hub heights
#: of 60 m and above: L_u = 8.1 Λ1 with Λ1 = 42 m.
IEC_LENGTH_SCALE = 8.1 * 42.0


class KaimalWind(TabulatedWind):
    """A :class:`TabulatedWind` made by :func:`kaimal_wind`, with its parameters.

    Attributes
    ----------
    mean_speed : float
        U [m/s].
    turbulence_intensity : float
        σ/U [-].
    seed : int
        Seed of the phases.
    length_scale : float
        L [m].
    """

    def __init__(self, time, speed, *, mean_speed: float, turbulence_intensity: float, seed: int,
                 length_scale: float, source: str) -> None:
        super().__init__(time, speed, source=source)
        self.mean_speed, self.turbulence_intensity = mean_speed, turbulence_intensity
        self.seed, self.length_scale = seed, length_scale


def kaimal_spectrum(frequency, mean_speed: float, sigma: float, length_scale: float = IEC_LENGTH_SCALE):
    """One-sided Kaimal power spectral density S(f) [(m/s)²/Hz] at ``frequency`` [Hz].

    ``S(f) = 4 σ² (L/U) / (1 + 6 f L/U)^(5/3)``; its integral over ``f ≥ 0`` is ``σ²``.
    """
    ratio = length_scale / mean_speed
    f = np.asarray(frequency, dtype=float)
    return 4.0 * sigma**2 * ratio / (1.0 + 6.0 * f * ratio) ** (5.0 / 3.0)


def kaimal_wind(mean_speed: float, turbulence_intensity: float, seed: int, *, duration: float = 600.0,
                dt: float = 0.05, length_scale: float = IEC_LENGTH_SCALE) -> KaimalWind:
    """Turbulent hub-height wind speed with the Kaimal spectrum (see the module docstring).

    Parameters
    ----------
    mean_speed : float
        Mean wind speed U [m/s] (> 0).
    turbulence_intensity : float
        TI = σ/U as a fraction (0.14 for 14 %), in (0, 1).
    seed : int
        Seed of the random phases (>= 0); the same seed gives the same series.
    duration : float, optional
        Length of the series [s] (the table covers ``[0, duration]``).
    dt : float, optional
        Time step [s]; frequencies up to ``1/(2 dt)`` are resolved.
    length_scale : float, optional
        Integral length scale L [m]; IEC default 340.2 m.

    Returns
    -------
    KaimalWind
        The series (a :class:`TabulatedWind`); ``.source`` records the parameters.

    Examples
    --------
    >>> from mbsym.wind.inflow import kaimal_wind
    >>> w = kaimal_wind(12.0, 0.14, seed=1, duration=600.0)
    >>> round(float(w.speed[:-1].mean()), 9), round(float(w.speed[:-1].std() / 12.0), 9)
    (12.0, 0.14)
    """
    u = _number(mean_speed, "mean_speed", positive=True)
    ti = _number(turbulence_intensity, "turbulence_intensity", positive=True)
    if ti >= 1.0:
        raise WindInputError(f"turbulence_intensity must be a fraction in (0, 1) (0.14 for 14 %); got {ti:g}.")
    if isinstance(seed, bool) or not isinstance(seed, (Integral, np.integer)) or seed < 0:
        raise WindInputError(f"seed must be a non-negative integer; got {seed!r}.")
    duration = _number(duration, "duration", positive=True)
    dt = _number(dt, "dt", positive=True)
    length = _number(length_scale, "length_scale", positive=True)
    n = int(round(duration / dt))
    n += n % 2
    if n < 8:
        raise WindInputError(f"duration/dt must give at least 8 samples; got duration = {duration:g} s, "
                             f"dt = {dt:g} s.")
    sigma = ti * u
    k = np.arange(1, n // 2)
    df = 1.0 / (n * dt)
    amplitude = np.sqrt(2.0 * kaimal_spectrum(k * df, u, sigma, length) * df)
    amplitude *= sigma / math.sqrt(0.5 * float(np.sum(amplitude**2)))
    phase = np.random.default_rng(int(seed)).uniform(0.0, 2.0 * np.pi, size=k.size)
    spectrum = np.zeros(n // 2 + 1, dtype=complex)
    spectrum[1:n // 2] = 0.5 * n * amplitude * np.exp(1j * phase)
    series = u + np.fft.irfft(spectrum, n=n)
    time = dt * np.arange(n + 1)
    speed = np.append(series, series[0])
    source = (f"kaimal(U={u:g} m/s, TI={ti:g}, seed={int(seed)}, L={length:g} m, "
              f"duration={n * dt:g} s, dt={dt:g} s)")
    return KaimalWind(time, speed, mean_speed=u, turbulence_intensity=ti, seed=int(seed),
                      length_scale=length, source=source)
