"""SeaState's sea from a file of wave components (``WaveMod = 7``): frequencies, heights, headings and phases.

SeaState (OpenFAST v5.0.0; read for the facts in ``UserWaves.f90``: ``WaveComp_ReadFile``,
``UserWaveComponents_Init``, ``GetFileLength``) reads the file named by ``WvKinFile`` in one of two layouts:

* **OpenFAST's**: four columns, angular frequency [rad/s], wave **height** [m], heading [deg], phase [deg];
* **the .SEA layout** (the first line starts with ``source: SEAFileGenerator.exe``): frequency [Hz],
  **amplitude** [m], heading [rad], phase [rad]; a ``duration: <s>`` header line replaces ``WaveTMax``, and
  ``dconv: naut`` (nautical headings) is refused, by SeaState and here.

The header is every line before the first whose words are all numbers; text after the data starts is an error.
Every frequency must be a positive whole multiple of ``Δω = 2π/WaveTMax`` (within 0.1 % of ``Δω``; SeaState holds
``Δω`` in single precision, and so does this module) and appear once.
The DFT then has ``N/2`` = the product of the primes 2 … 23 at least ``max(round(ω_max/Δω) + 1, ⌈2π/(WaveDT Δω)⌉)``,
the time step becomes ``WaveTMax/N``, and component ``k = ω/Δω`` gets ``C_k = (N/2) A e^{iφ}`` (so that
``η(t) = Σ A cos(ω t + φ)`` at the origin) and its own heading; ``C_0 = C_{N/2} = 0`` and the components outside
``[WvLowCOff, WvHiCOff]`` are zeroed. The headings drive everything else as for a spread sea (elevation off the
origin, HydroDyn's excitation per component, the members' kinematics).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import OpenFASTFormatError, UnsupportedFeatureError

__all__ = ["WaveComponents", "read_wave_components", "component_spectrum"]

#: SeaState's tolerance on ω/Δω being a whole number (``WaveDOmega_RelTol``).
FREQUENCY_TOLERANCE = 1e-3
_SEA_SOURCE = "source: SEAFileGenerator.exe"
_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23)


@dataclass(frozen=True)
class WaveComponents:
    """The components of a ``WaveMod = 7`` file, SI units.

    Attributes
    ----------
    frequency, amplitude, heading, phase : ndarray (n,)
        ω [rad/s], amplitude [m], heading [rad] (propagation direction from the x axis), phase [rad].
    duration : float or None
        The ``.SEA`` file's ``duration`` [s] (replaces ``WaveTMax``), None for OpenFAST's layout.
    path : str
    """

    frequency: np.ndarray
    amplitude: np.ndarray
    heading: np.ndarray
    phase: np.ndarray
    duration: float | None
    path: str


def _number(word: str) -> float | None:
    try:
        return float(word.replace("d", "e").replace("D", "E"))
    except ValueError:
        return None


def read_wave_components(path) -> WaveComponents:
    """Read a ``WaveMod = 7`` wave-component file (either layout, module docstring).

    Raises
    ------
    OpenFASTFormatError
        Not four columns, text inside the data, no data, a number that is not one.
    UnsupportedFeatureError
        ``dconv: naut`` (nautical headings; SeaState refuses them too).
    """
    p = Path(path)
    if not p.is_file():
        raise OpenFASTFormatError(f"{p}: the wave-component file (WvKinFile, WaveMod = 7) does not exist.")
    lines = p.read_text(errors="replace").splitlines()
    sea_format = bool(lines) and lines[0].startswith(_SEA_SOURCE)
    rows, duration, header = [], None, True
    for number, line in enumerate(lines, start=1):
        words = line.split()
        if not words:
            continue
        values = [_number(w) for w in words]
        if any(v is None for v in values):
            if not header:
                raise OpenFASTFormatError(f"{p}, line {number}: text inside the data ({line.strip()!r}); SeaState "
                                          "reads the lines before the first all-number line as the header.")
            if sea_format and words[0] == "dconv:" and words[1:2] == ["naut"]:
                raise UnsupportedFeatureError(f"{p}, line {number}: 'dconv: naut' (nautical headings) is refused by "
                                              "SeaState; write the headings in the mathematical convention.")
            if sea_format and words[0] == "duration:" and len(words) > 1 and _number(words[1]) is not None:
                duration = float(_number(words[1]))
            continue
        header = False
        if len(values) != 4:
            raise OpenFASTFormatError(f"{p}, line {number}: {len(values)} columns; a wave-component file has 4 "
                                      "(frequency, height or amplitude, heading, phase).")
        rows.append(values)
    if not rows:
        raise OpenFASTFormatError(f"{p}: no wave components (lines of four numbers) found.")
    data = np.array(rows, dtype=float)
    if sea_format:                         # Hz, amplitude, rad, rad
        return WaveComponents(2 * math.pi * data[:, 0], data[:, 1], data[:, 2], data[:, 3], duration, str(p))
    return WaveComponents(data[:, 0], 0.5 * data[:, 1], np.radians(data[:, 2]), np.radians(data[:, 3]), None, str(p))


def _smooth_at_least(n: int) -> int:
    """The smallest product of the primes 2 … 23 that is ≥ ``n`` (SeaState's ``PSF``)."""
    n = max(int(n), 1)
    while True:
        m = n
        for p in _PRIMES:
            while m % p == 0:
                m //= p
        if m == 1:
            return n
        n += 1


def component_spectrum(components: WaveComponents, *, time_max: float, time_step: float,
                       band: tuple[float, float]) -> tuple[np.ndarray, np.ndarray, float, float]:
    """``(C_k, headings, Δω, WaveDT)`` of the sea the components make (module docstring).

    Parameters
    ----------
    components : WaveComponents
    time_max : float
        ``WaveTMax`` [s] (the file's ``duration`` wins when it gives one).
    time_step : float
        The deck's ``WaveDT`` [s] (sets the shortest DFT; the sea's own step is ``WaveTMax/N``).
    band : (float, float)
        ``(WvLowCOff, WvHiCOff)`` [rad/s].

    Raises
    ------
    OpenFASTFormatError
        A frequency ≤ 0, not a whole multiple of ``Δω``, or given twice (SeaState's checks).
    """
    tmax = float(components.duration or time_max)
    dw = float(np.float32(2 * math.pi / tmax))          # SeaState keeps Δω in single precision (WaveDOmega, SiKi)
    ratio = components.frequency / dw
    index = np.rint(ratio).astype(int)
    where = components.path
    bad = np.flatnonzero(components.frequency <= 0)
    if bad.size:
        raise OpenFASTFormatError(f"{where}: wave component {bad[0] + 1} has frequency "
                                  f"{components.frequency[bad[0]]:g} rad/s; frequencies must be positive.")
    off = np.flatnonzero(np.abs(ratio - index) > FREQUENCY_TOLERANCE)
    if off.size:
        raise OpenFASTFormatError(f"{where}: wave component {off[0] + 1} at {components.frequency[off[0]]:g} rad/s is "
                                  f"not a whole multiple of 2*pi/WaveTMax = {dw:g} rad/s (WaveTMax {tmax:g} s). "
                                  "Give frequencies on that grid or change WaveTMax.")
    seen = {}
    for k, j in enumerate(index):
        if j in seen:
            raise OpenFASTFormatError(f"{where}: wave components {seen[j] + 1} and {k + 1} share the frequency "
                                      f"{j * dw:g} rad/s; each frequency may appear once.")
        seen[j] = k
    # the shortest DFT for the deck's WaveDT, from the single-precision Δω as SeaState computes it (850 s at 0.25 s:
    # 3400.0001 -> 3401 -> N/2 = 3402, WaveDT 0.12493 s)
    half = _smooth_at_least(max(int(index.max()) + 1, math.ceil(2 * math.pi / (time_step * dw))))
    spectrum = np.zeros(half + 1, dtype=complex)
    headings = np.zeros(half + 1)
    spectrum[index] = half * components.amplitude * np.exp(1j * components.phase)
    headings[index] = components.heading
    spectrum[0] = spectrum[-1] = 0.0
    omega = dw * np.arange(half + 1)
    spectrum[(omega < band[0]) | (omega > band[1])] = 0.0
    return spectrum, headings, dw, tmax / (2 * half)
