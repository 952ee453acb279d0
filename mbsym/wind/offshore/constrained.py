"""SeaState's constrained waves (``ConstWaveMod`` 1 and 2): an irregular sea with a given crest at a given time
and place.

For extreme-wave load cases SeaState (OpenFAST v5.0.0; read for the facts in ``Waves.f90``,
``ConstrainedNewWaves``, and ``SeaState_Input.f90``) embeds a NewWave-type crest in a JONSWAP realization
(``WaveMod = 2`` only; with any other wave model it leaves the sea alone). Working on the elevation's DFT
``C_k`` at the origin (:class:`~.waves.IncidentWaves`; ``η(t_j) = (1/N) Σ C_k e^{iω_k t_j}``), with the one-sided
spectrum ``S_k`` (zero outside the cut-offs), ``m_0 = Δω Σ S_k`` and ``m_2 = Δω Σ ω_k² S_k``:

1. the random sea's own elevation and slope at ``t = 0`` are taken out::

       Re C_k ← Re C_k − (Σ Re C / m_0) S_k Δω,     Im C_k ← Im C_k − (Σ ω Im C / m_2) ω_k S_k Δω;

2. a crest of elevation ``A`` is added, ``Re C_k ← Re C_k + A (N/2) S_k Δω / m_0`` (so ``η(0) = A`` and
   ``η'(0) = 0``): ``ConstWaveMod = 1`` takes ``A = CrestHmax/2``; ``ConstWaveMod = 2`` finds ``A`` such that the
   crest height over the lower of the troughs within ``⌈Tp/WaveDT⌉`` samples before and after it is ``CrestHmax``
   (SeaState's secant-Newton iteration from ``A = CrestHmax/2`` with a 1 mm step and 1 mm tolerance, at most 21
   passes — reproduced step by step, so the same ``A``);
3. the crest is moved to ``(CrestXi, CrestYi)`` at ``CrestTime``:
   ``C_k ← C_k e^{i(κ_k (x cos β_k + y sin β_k) − ω_k t)}`` for ``0 < k < N/2`` (κ from the finite-depth dispersion
   relation, ``β_k`` each component's heading, spread or not).

Everything downstream (the elevation at any point, HydroDyn's excitation, the members' kinematics) follows from the
modified ``C_k``, as in SeaState. SeaState refuses ``CrestHmax < WaveHs`` with a JONSWAP sea; so does mbsym.
"""

from __future__ import annotations

import math

import numpy as np

from ...exceptions import ParameterError

__all__ = ["constrain_crest", "CREST_TOLERANCE", "CREST_ITERATIONS"]

#: SeaState's crest-height tolerance and Newton step [m] and its iteration limit (``ConstrainedNewWaves``).
CREST_TOLERANCE = 1.0e-3
CREST_ITERATIONS = 20


def constrain_crest(spectrum: np.ndarray, density: np.ndarray, frequency_step: float, wave_numbers: np.ndarray,
                    headings: np.ndarray, *, mode: int, crest_height: float, crest_time: float,
                    crest_position: tuple[float, float], peak_period: float, time_step: float) -> np.ndarray:
    """The DFT ``C_k`` of a constrained sea (module docstring).

    Parameters
    ----------
    spectrum : (N/2 + 1,) complex ndarray
        The random sea's ``C_k`` [m].
    density : (N/2 + 1,) ndarray
        The one-sided spectrum ``S(ω_k)`` [m² s/rad], zero outside the cut-offs.
    frequency_step : float
        ``Δω`` [rad/s].
    wave_numbers, headings : (N/2 + 1,) ndarray
        κ_k [rad/m] and β_k [rad] of each component.
    mode : int
        ``ConstWaveMod``: 1 crest elevation ``CrestHmax/2``, 2 crest-to-trough height ``CrestHmax``.
    crest_height : float
        ``CrestHmax`` [m].
    crest_time : float
        ``CrestTime`` [s].
    crest_position : (float, float)
        ``(CrestXi, CrestYi)`` [m].
    peak_period, time_step : float
        ``WaveTp`` and ``WaveDT`` [s] (the trough search window of mode 2).

    Raises
    ------
    ParameterError
        A spectrum without energy (``m_0 = 0``), or ``mode`` not 1 or 2.
    """
    c = np.asarray(spectrum, dtype=complex)
    s = np.asarray(density, dtype=float)
    dw = float(frequency_step)
    n = 2 * (c.size - 1)
    omega = dw * np.arange(c.size)
    m0, m2 = dw * s.sum(), dw * float(np.sum(s * omega**2))
    if not (m0 > 0 and m2 > 0):
        raise ParameterError("constrained waves need a spectrum with energy inside the cut-offs (m0, m2 > 0); got "
                             f"m0 = {m0:g} m^2, m2 = {m2:g} m^2/s^2.")
    if mode not in (1, 2):
        raise ParameterError(f"ConstWaveMod must be 1 or 2 for a constrained crest; got {mode!r}.")
    real = c.real - c.real.sum() / m0 * s * dw
    imag = c.imag - float(np.sum(c.imag * omega)) / m2 * omega * s * dw
    unit = (n // 2) / m0 * dw * s
    crest = 0.5 * float(crest_height)
    if mode == 2:
        crest = _crest_for_height(real, imag, unit, float(crest_height), math.ceil(peak_period / time_step), n)
    c = (real + crest * unit) + 1j * imag
    x, y = crest_position
    beta = np.asarray(headings, dtype=float)
    phase = np.asarray(wave_numbers, dtype=float) * (x * np.cos(beta) + y * np.sin(beta)) - omega * float(crest_time)
    inner = slice(1, c.size - 1)                              # SeaState leaves ω = 0 and the Nyquist term alone
    c[inner] = c[inner] * np.exp(1j * phase[inner])
    return c


def _crest_for_height(real: np.ndarray, imag: np.ndarray, unit: np.ndarray, height: float, window: int,
                      n: int) -> float:
    """SeaState's iteration for the crest elevation whose height over the lower neighbouring trough is ``height``."""
    def crest_to_trough(crest: float) -> float:
        eta = np.fft.irfft((real + crest * unit) + 1j * imag, n=n)
        before = eta[max(n - window, 0):n]
        after = eta[1:min(window, n - 1) + 1]
        return crest - min(after.min(), before.min())

    crest, passes = 0.5 * height, 0
    error = height
    while error > CREST_TOLERANCE and passes <= CREST_ITERATIONS:
        passes += 1
        got = crest_to_trough(crest)
        error = abs(got - height)
        if error > CREST_TOLERANCE:
            nudged = crest_to_trough(crest + CREST_TOLERANCE) - got
            crest -= (got - height) * CREST_TOLERANCE / nudged
    return crest
