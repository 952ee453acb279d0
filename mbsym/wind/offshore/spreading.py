"""Directional spreading of SeaState's sea (``WaveDirMod = 1``): one heading per frequency component.

SeaState (v5.0.0, ``Waves.f90``: ``CalculateWaveNDir``, ``CalculateWaveSpreading``, ``CalculateWaveDirection``)
spreads the energy of a short-crested sea over ``WaveNDir`` headings of equal energy under the cos-2s
spreading function ``D(θ) = C |cos(π (θ − β)/R)|^(2s)`` over ``β ± R/2`` (``WaveDir`` β, ``WaveDirRange`` R,
``WaveDirSpread`` s; ``C`` normalizes it, exactly with the Γ function for s < 25, asymptotically above):
the headings are where the cumulative integral (a rectangle rule on max(15 WaveNDir, 1000) steps) reaches
``(i − ½)/WaveNDir``. ``WaveNDir`` is made odd and raised by 2 until it divides ``N/2`` (at most to 1.25 times
the deck's value). Each run of ``WaveNDir`` consecutive frequency components, from ω = 0, gets the headings
in the order of ``WaveNDir`` uniform draws (the smallest draw's heading first), and the last component one
more draw's smallest: the draws follow the amplitude and phase draws of the same generator.
"""

from __future__ import annotations

import math

import numpy as np

from ...exceptions import OpenFASTFormatError

__all__ = ["equal_energy_headings", "spread_headings", "direction_count"]


def direction_count(n_directions: int, half: int, where: str = "SeaState") -> int:
    """SeaState's ``WaveNDir`` for ``N/2 = half`` frequency components (odd, dividing ``half``)."""
    n = int(n_directions)
    if n <= 0:
        raise OpenFASTFormatError(f"{where}: WaveNDir must be at least 1; got {n}.")
    limit = math.ceil(1.25 * n)
    n += (n % 2 == 0)
    while half % n:
        n += 2
        if n > limit:
            raise OpenFASTFormatError(f"{where}: no odd WaveNDir up to {limit} divides the {half} wave frequencies "
                                      "(N/2); change WaveNDir or WaveTMax.")
    return n


def equal_energy_headings(direction: float, spread: float, span: float, count: int) -> np.ndarray:
    """The ``count`` headings [deg] of equal energy under cos-2s about ``direction`` over ``span`` [deg]."""
    steps = max(15 * count, 1000)
    dtheta = span / steps
    if spread < 25.0:
        const = math.sqrt(math.pi) * math.gamma(spread + 1.0) / (span * math.gamma(spread + 0.5))
    else:
        const = math.sqrt(math.pi * spread) * (1.0 + 0.125 / spread) / span
    thetas = np.arange(steps + 1) * dtheta + direction - span / 2
    density = const * np.abs(np.cos(math.pi * (thetas - direction) / span)) ** (2 * spread)
    integral = np.cumsum(density * dtheta)
    targets = (np.arange(1, count + 1) - 0.5) / count
    return np.interp(targets, integral, thetas)


def spread_headings(sea, half: int, uniforms) -> np.ndarray:
    """Per frequency component ``k = 0 … N/2`` its heading [rad] (module docstring); ``uniforms(n)`` draws ``n``."""
    count = direction_count(int(sea.n_directions), half, str(sea.path))
    headings = equal_energy_headings(math.degrees(float(sea.wave_direction)), float(sea.direction_spread),
                                     math.degrees(float(sea.direction_range)), count)
    out = np.empty(half + 1)
    k = 0
    for _ in range(half // count):
        for j in np.argsort(uniforms(count), kind="stable"):
            out[k] = headings[j]
            k += 1
    out[k] = headings[int(np.argmin(uniforms(count)))]
    return np.radians(out)
