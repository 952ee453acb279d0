"""RANLUX, the random-number generator SeaState draws its wave phases and amplitudes from.

Lüscher's subtract-with-borrow generator with decimation (M. Lüscher, Comput. Phys. Commun. 79 (1994)
100-110), in F. James's formulation (Comput. Phys. Commun. 79 (1994) 111-114): 24 seeds ``s`` on the
grid ``2^-24``, lags 24 and 10, ``x_n = s_(n-10) - s_(n-24) - c`` (+1 and carry ``c = 2^-24`` when
negative), and after every 24 numbers ``p - 24`` numbers are thrown away (``p = 223`` at luxury
level 3). James's start: 24 integers from the linear congruential generator
``j <- 40014 j mod 2147483563`` (Schrage's form), each reduced ``mod 2^24``.

OpenFAST facts used here (NWTC library, ``NWTC_RandomNumber.f90`` and ``ranlux/RANLUX.f90``, v5.0.0):
SeaState with ``WaveSeed(2) = "RANLUX"`` starts the generator at luxury level 3 from
``|WaveSeed(1)|``, asks for one number per call, and its F90 generator adds the small-number
refinement ``2^-24 s_j`` (``x < 2^-12``) with ``j`` the lag-10 index *before* the number's step.
NWTC's own unit test gives the first two numbers for seed 1: 0.94589489698410034, 0.47347849607467651
(``tests/test_NWTC_RandomNumber.F90``); mbsym's tests check them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RanLux"]

_N = 24
_LAG = 10
#: Numbers skipped after every 24 (James's table for luxury levels 0-4).
_SKIP = (0, 24, 73, 199, 365)
_TWO_M24 = 2.0 ** -24
_TWO_M12 = 2.0 ** -12


class RanLux:
    """RANLUX uniform numbers in (0, 1), as OpenFAST's SeaState draws them.

    Parameters
    ----------
    seed : int
        The start seed (OpenFAST passes ``|WaveSeed(1)|``); 0 is James's default 314159265.
    luxury : int, optional
        Luxury level 0-4 (OpenFAST: 3).

    Examples
    --------
    >>> rng = RanLux(1)
    >>> [round(rng.uniform(), 12) for _ in range(2)]
    [0.945894896984, 0.473478496075]
    """

    def __init__(self, seed: int, luxury: int = 3) -> None:
        if not 0 <= int(luxury) < len(_SKIP):
            raise ValueError(f"luxury must be 0-4; got {luxury}.")
        seed = abs(int(seed)) or 314159265
        if seed > 2 ** 31 - 1:
            raise ValueError(f"seed must fit a 32-bit integer (|seed| <= 2147483647); got {seed}.")
        self.skip = _SKIP[int(luxury)]
        state = []
        j = seed
        for _ in range(_N):
            k = j // 53668
            j = 40014 * (j - k * 53668) - k * 12211
            if j < 0:
                j += 2147483563
            state.append((j % (1 << 24)) * _TWO_M24)
        self.seeds = state                  # Fortran's Seeds(1..24) at indices 0..23
        self.i24, self.j24 = _N - 1, _LAG - 1   # Fortran's I24 = 24, J24 = 10
        self.carry = _TWO_M24 if state[-1] == 0.0 else 0.0
        self.in24 = 0

    def _step(self) -> float:
        s, i, j = self.seeds, self.i24, self.j24
        x = s[j] - s[i] - self.carry
        if x < 0.0:
            x += 1.0
            self.carry = _TWO_M24
        else:
            self.carry = 0.0
        s[i] = x
        self.i24 = i - 1 if i > 0 else _N - 1
        self.j24 = j - 1 if j > 0 else _N - 1
        return x

    def call(self, n: int) -> np.ndarray:
        """``n`` numbers in (0, 1) from one call of OpenFAST's ``RanLux`` with an array of ``n`` (its F90 form
        takes the small-number refinement ``2^-24 s_j`` once per call, before the first step)."""
        refine = _TWO_M24 * self.seeds[self.j24]
        out = np.empty(int(n))
        for k in range(int(n)):
            x = self._step()
            self.in24 += 1
            if self.in24 == _N:
                self.in24 = 0
                for _ in range(self.skip):
                    self._step()
            if x < _TWO_M12:
                x += refine
            out[k] = x if x != 0.0 else _TWO_M24 * _TWO_M24
        return out

    def uniform(self) -> float:
        """The next number in (0, 1) (one call with one element)."""
        return float(self.call(1)[0])

    def uniforms(self, n: int) -> np.ndarray:
        """``n`` numbers, one :meth:`uniform` call each."""
        return np.array([self.uniform() for _ in range(int(n))])
