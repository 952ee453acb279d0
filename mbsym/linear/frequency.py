"""Frequency responses for Bode plots: a resolved, continuous phase, and the same wrapped into one band.

A Bode phase is only defined up to multiples of 360°. :func:`frequency_response` makes it a function of
frequency that a reader can trust:

1. **resolved**: the response is evaluated on the given grid, then wherever two neighbouring points differ
   in phase by more than ``max_phase_step_deg`` (a lightly damped pole or zero between them: its 180° swing
   happens within a relative band ~2ζ, which a grid of 100 points per decade misses for ζ below ~1 %), the
   geometric midpoint is added, until every step is below the bound. Only then is the unwrapped phase the
   phase the response actually goes through (unwrapping a coarse grid can add or lose 360° at such a mode);
2. **continuous** (:attr:`FrequencyResponse.phase_deg`): the running sum of those small steps
   (``numpy.unwrap``), **anchored** by a multiple of 360° so that the phase at the lowest frequency lies in
   (−180°, 180°]. An integrator then reads −90°, a lag 1/(1 + s/ω) goes 0° → −90°, a type-1 loop with two
   lags −90° → −270°. A high-order sampled loop keeps losing phase up to the Nyquist frequency: the NREL 5 MW
   pitch loop at 16 m/s ends at −810° (13 poles, 12 zeros of which 3 lie outside the unit circle; the sum of
   the pole and zero angles gives the same), true but unreadable on a plot;
3. **wrapped** (:meth:`FrequencyResponse.wrapped_phase_deg`): the continuous phase folded into one 360° band,
   (−360°, 0°] by default, the band of a Bode plot: every crossing of the negative real axis (each a
   gain-margin candidate) is a crossing of the −180° line, and the low-frequency phase of a type-0 or type-1
   loop (0°, −90°) is unchanged.

A step that cannot be resolved (a zero on the frequency axis itself: the phase truly jumps by 180°) stops
the refinement at a relative spacing of 1e-9 and is kept as the jump ``numpy.unwrap`` gives.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..exceptions import DimensionError

__all__ = ["FrequencyResponse", "frequency_response", "anchored_phase_deg"]

#: Largest number of frequencies the refinement may reach.
MAX_POINTS = 50_000


@dataclass(frozen=True)
class FrequencyResponse:
    """A frequency response ready for a Bode plot (module docstring).

    Attributes
    ----------
    freq_hz : ndarray
        Frequencies [Hz], increasing (the grid asked for, refined where the phase moves fast).
    response : ndarray of complex
        The response at ``freq_hz``.
    magnitude_db : ndarray
        ``20 log10 |response|`` [dB].
    phase_deg : ndarray
        Continuous phase [deg], the first value in (−180, 180].
    """

    freq_hz: np.ndarray
    response: np.ndarray
    magnitude_db: np.ndarray
    phase_deg: np.ndarray

    def wrapped_phase_deg(self, low: float = -360.0) -> np.ndarray:
        """:attr:`phase_deg` folded into (``low``, ``low`` + 360] [deg] (module docstring, step 3).

        Examples
        --------
        >>> import numpy as np
        >>> r = FrequencyResponse(np.array([1.0, 2.0]), np.ones(2), np.zeros(2), np.array([-90.0, -810.0]))
        >>> r.wrapped_phase_deg()
        array([-90., -90.])
        """
        return low + 360.0 - np.mod(low + 360.0 - self.phase_deg, 360.0)


def anchored_phase_deg(response) -> np.ndarray:
    """The unwrapped phase of ``response`` [deg], shifted by a multiple of 360° into (−180, 180] at its first
    sample (module docstring, steps 2 and 3; no refinement: the samples must be dense enough).

    Examples
    --------
    >>> import numpy as np
    >>> w = np.array([0.1, 1.0, 10.0])
    >>> np.round(anchored_phase_deg(1 / (1j * w * (1 + 1j * w) ** 2)), 1)      # -90 - 2 atan(w)
    array([-101.4, -180. , -258.6])
    """
    h = np.asarray(response, dtype=complex).reshape(-1)
    if h.size == 0:
        return np.zeros(0)
    phase = np.degrees(np.unwrap(np.angle(h)))
    return phase - 360.0 * np.ceil((phase[0] - 180.0) / 360.0)


def frequency_response(evaluate: Callable[[np.ndarray], np.ndarray], freq_hz, *,
                       max_phase_step_deg: float = 10.0) -> FrequencyResponse:
    """The response ``evaluate(f)`` on the grid ``freq_hz`` [Hz], refined until the phase is resolved, with a
    continuous phase anchored in (−180°, 180°] (module docstring).

    Parameters
    ----------
    evaluate : callable
        ``evaluate(f)`` returns the complex response at the frequencies ``f`` [Hz] (an array).
    freq_hz : array_like
        At least two positive, increasing frequencies [Hz].
    max_phase_step_deg : float, optional, keyword-only
        Largest phase change between neighbouring points [deg] (default 10; in (0, 90]).

    Raises
    ------
    DimensionError
        Fewer than two frequencies, or not positive, finite and increasing; a bad ``max_phase_step_deg``.

    Examples
    --------
    >>> import numpy as np
    >>> r = frequency_response(lambda f: 1 / (2j * np.pi * f), [0.01, 1.0, 100.0])     # an integrator
    >>> np.round(r.phase_deg, 6)
    array([-90., -90., -90.])
    """
    f = np.asarray(freq_hz, dtype=float).reshape(-1)
    if f.size < 2 or not np.all(np.isfinite(f)) or f[0] <= 0 or np.any(np.diff(f) <= 0):
        raise DimensionError(f"freq_hz must hold at least two positive, finite, increasing frequencies [Hz]; got "
                             f"{f.size} value(s) from {f[:1]} to {f[-1:]}.")
    if not 0.0 < max_phase_step_deg <= 90.0:
        raise DimensionError(f"max_phase_step_deg must be in (0, 90] deg; got {max_phase_step_deg!r}.")
    h = np.asarray(evaluate(f), dtype=complex).reshape(-1)
    step = np.radians(max_phase_step_deg)
    while f.size < MAX_POINTS:
        jump = np.abs(np.angle(h[1:] / h[:-1])) > step
        jump &= f[1:] / f[:-1] - 1.0 > 1e-9                  # a true discontinuity: stop refining there
        if not np.any(jump):
            break
        i = np.flatnonzero(jump)[: MAX_POINTS - f.size]
        mid = np.sqrt(f[i] * f[i + 1])
        hm = np.asarray(evaluate(mid), dtype=complex).reshape(-1)
        f, h = np.insert(f, i + 1, mid), np.insert(h, i + 1, hm)
    with np.errstate(divide="ignore"):
        magnitude_db = 20.0 * np.log10(np.abs(h))
    return FrequencyResponse(f, h, magnitude_db, anchored_phase_deg(h))
