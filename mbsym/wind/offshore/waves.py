"""First-order incident waves as OpenFAST's SeaState makes them: the elevation's discrete Fourier transform.

SeaState (v5.0.0, ``Waves.f90``, ``UserWaves.f90``) describes a sea by the DFT ``C_k`` of the wave elevation
at the origin on ``N`` (``NStepWave``) samples ``Δt`` (``WaveDT``) apart, ``k = 0 … N/2`` at ``ω_k = k Δω``;
the elevation is the inverse transform, ``η(t_j) = (1/N) Σ C_k e^{iω_k t_j}`` over positive and negative
``k`` (numpy's ``irfft``), periodic in ``N Δt``. This module builds the same ``C_k``:

* **the grid**: ``N`` = the even number ≥ ``WaveTMax/WaveDT`` whose half is a product of the primes
  2 … 23 (SeaState's ``PSF``), ``Δω = 2π/(N Δt)`` (for an external series ``2π/WaveTMax``, as SeaState);
* **regular waves** (``WaveMod`` 1, ``1P#``): one component at ``k_p = round(N Δt / Tp)`` with amplitude
  ``Hs/2``, its phase drawn (1) or given (``1P#``);
* **irregular waves**: ``C_k = sqrt(N/2) W_k sqrt(π S(ω_k) / Δt)`` with ``S`` the one-sided JONSWAP /
  Pierson–Moskowitz (IEC 61400-3) or white-noise spectrum, zero outside ``[WvLowCOff, WvHiCOff]``, and
  ``W_k = sqrt(-2 ln U1) e^{2πi U2}`` (Box–Muller; ``sqrt 2`` for ``WaveNDAmp = False``) from uniform draws
  in SeaState's order (``k = 0, 2, 3, … N/2 − 1``; ``W_1 = W_(N/2) = 0``) — with ``WaveSeed(2) = RANLUX``
  from :class:`~.ranlux.RanLux`, so the realization is OpenFAST's; with an integer second seed SeaState
  uses the compiler's generator, which no other program reproduces: the spectrum is the same, the phases
  are numpy's (a :class:`~mbsym.exceptions.ModelWarning` says so);
* **an external elevation series** (``WaveMod`` 5, ``<WvKinFile>.Elev``): its DFT, mean and Nyquist removed,
  cut off as above;
* **wave components from a file** (``WaveMod`` 7, :mod:`.wave_components`): frequency, height, heading and phase
  of each;
* **directional spreading** (``WaveDirMod`` 1): a heading per component (:mod:`.spreading`);
* **constrained waves** (``ConstWaveMod`` 1, 2 with ``WaveMod`` 2): a given crest embedded in the JONSWAP sea
  (:mod:`.constrained`).

The elevation at another point ``(x, y)`` multiplies ``C_k`` by ``e^{-i κ_k (x cos β + y sin β)}`` (κ from
the finite-depth dispersion relation ``ω² = g κ tanh κh``, β the wave heading).
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import ModelWarning, OpenFASTFormatError, ParameterError, UnsupportedFeatureError
from .ranlux import RanLux

__all__ = ["IncidentWaves", "incident_waves", "jonswap", "wave_steps", "wave_number", "read_elevation_series",
           "grid_elevation", "index_weights"]

_PRIMES = (2, 3, 5, 7, 11, 13, 17, 19, 23)
#: SeaState's tolerance between WaveDT and an external series' time step [s] (UserWaves.f90).
ELEVATION_DT_TOLERANCE = 0.001


@dataclass(frozen=True, eq=False)
class IncidentWaves:
    """The first-order sea of a SeaState deck (module docstring).

    Attributes
    ----------
    time_step : float
        ``WaveDT`` [s].
    spectrum : (N/2 + 1,) complex ndarray
        ``C_k`` [m] (unnormalized DFT of the elevation at the origin).
    frequency_step : float
        ``Δω`` [rad/s].
    direction : float
        Wave heading β [rad] (propagation direction from the x axis, about z).
    water_depth, gravity : float
        [m], [m/s²] (for the dispersion relation).
    description : str
        What made it (for reports).
    directions : (N/2 + 1,) ndarray or None
        A heading per component [rad] for a spread sea (:mod:`.spreading`), None: ``direction`` for all.
    """

    time_step: float
    spectrum: np.ndarray
    frequency_step: float
    direction: float
    water_depth: float
    gravity: float
    description: str = ""
    directions: np.ndarray | None = None

    @property
    def n_steps(self) -> int:
        """``N``: samples per period."""
        return 2 * (len(self.spectrum) - 1)

    @property
    def period(self) -> float:
        """``N Δt`` [s]: the sea repeats after it."""
        return self.n_steps * self.time_step

    @property
    def frequencies(self) -> np.ndarray:
        """``ω_k`` [rad/s]."""
        return self.frequency_step * np.arange(len(self.spectrum))

    def times(self) -> np.ndarray:
        """``0, Δt, … N Δt`` [s] (the last sample repeats the first)."""
        return self.time_step * np.arange(self.n_steps + 1)

    def series(self, transform: np.ndarray) -> np.ndarray:
        """The periodic series ``(N + 1,)`` (last = first) of the DFT ``transform`` (``C_k`` times a transfer)."""
        x = np.fft.irfft(np.asarray(transform), n=self.n_steps)
        return np.append(x, x[0])

    def elevation(self, x: float = 0.0, y: float = 0.0) -> np.ndarray:
        """η [m] at ``(x, y)`` [m] on :meth:`times`."""
        if x == 0.0 and y == 0.0:
            return self.series(self.spectrum)
        kappa = np.array([wave_number(w, self.gravity, self.water_depth) for w in self.frequencies])
        beta = self.headings()
        shift = np.exp(-1j * kappa * (x * np.cos(beta) + y * np.sin(beta)))
        return self.series(self.spectrum * shift)

    def headings(self) -> np.ndarray:
        """Each component's heading [rad]."""
        if self.directions is None:
            return np.full(len(self.spectrum), self.direction)
        return np.asarray(self.directions, dtype=float)

    def significant_height(self) -> float:
        """``4 σ(η)`` [m] of the realization."""
        return 4.0 * float(np.std(self.elevation()[:-1]))


def grid_elevation(waves: IncidentWaves, sea, x: float, y: float) -> np.ndarray:
    """η [m] at ``(x, y)`` as SeaState outputs it (``WaveElevxi``/``WaveElevyi``), on ``waves.times()``.

    SeaState evaluates the sea on its surface grid (``X_HalfWidth``, ``NX``, ``Y_HalfWidth``, ``NY``: nodes
    ``n dX``, ``n = −NX+1 … NX−1``, ``dX = X_HalfWidth/(NX−1)``) and interpolates between nodes with the NWTC
    ``GridInterp`` (cubic where four nodes surround the point, quadratic or linear at the edges); a point off the
    grid is clamped to its edge (SeaState warns). At a node this is :meth:`IncidentWaves.elevation` there.
    """
    wx = _grid_weights(x, float(sea.x_half_width), int(sea.nx))
    wy = _grid_weights(y, float(sea.y_half_width), int(sea.ny))
    out = np.zeros(waves.n_steps + 1)
    for xi, a in wx:
        for yj, b in wy:
            if a * b != 0.0:
                out += a * b * waves.elevation(xi, yj)
    return out


def _grid_weights(p_in: float, half_width: float, n_half: int) -> list[tuple[float, float]]:
    """(node coordinate, weight) of the NWTC GridInterp along one non-periodic grid axis (``SetIndex``, ``GetN1D``)."""
    delta = half_width / (n_half - 1)
    return [((i - (n_half - 1)) * delta, w) for i, w in index_weights((p_in + half_width) / delta, 2 * n_half - 1)]


def index_weights(p: float, n: int) -> list[tuple[int, float]]:
    """(node index, weight) of the NWTC GridInterp at index coordinate ``p`` on ``n`` uniform nodes ``0 … n − 1``:
    cubic Catmull–Rom inside, quadratic at the first and last interval, linear on two nodes; ``p`` clamped."""
    p = min(max(p, 0.0), n - 1.0)
    if math.isclose(p, n - 1.0, rel_tol=0.0, abs_tol=1e-9):
        u, index = 1.0, [n - 3, n - 2, n - 1, n]
    else:
        u, index = p - math.floor(p), [math.floor(p) + k for k in (-1, 0, 1, 2)]
    if index[0] < 0:
        index[0] = 0
        support = 0 if index[3] > n - 1 else 1
        index[3] = min(index[3], n - 1)
    elif index[3] > n - 1:
        support, index[3] = 2, n - 1
    else:
        support = 3
    u2, u3 = u * u, u * u * u
    weights = {3: (-0.5 * u3 + u2 - 0.5 * u, 1.5 * u3 - 2.5 * u2 + 1.0, -1.5 * u3 + 2.0 * u2 + 0.5 * u, 0.5 * u3 - 0.5 * u2),
               1: (0.0, 0.5 * u2 - 1.5 * u + 1.0, -u2 + 2.0 * u, 0.5 * u2 - 0.5 * u),
               2: (0.5 * u2 - 0.5 * u, -u2 + 1.0, 0.5 * u2 + 0.5 * u, 0.0),
               0: (0.0, 1.0 - u, u, 0.0)}[support]
    return list(zip(index, weights))


def wave_steps(time_max: float, time_step: float) -> int:
    """SeaState's ``NStepWave``: even, ≥ ``time_max / time_step``, half a product of the primes 2 … 23."""
    n = math.ceil(time_max / time_step - 1e-9)
    half = max((n + n % 2) // 2, 1)
    while not _smooth(half):
        half += 1
    return 2 * half


def _smooth(n: int) -> bool:
    for p in _PRIMES:
        while n % p == 0:
            n //= p
    return n == 1


def jonswap(omega: np.ndarray, hs: float, tp: float, gamma: float) -> np.ndarray:
    """One-sided JONSWAP spectrum [m²/(rad/s)] (IEC 61400-3 form, as SeaState; γ = 1: Pierson–Moskowitz).

    Parameters
    ----------
    omega : array
        ω [rad/s]; 0 gives 0.
    hs, tp, gamma : float
        Significant height [m], peak period [s], peak shape [-].
    """
    omega = np.asarray(omega, dtype=float)
    out = np.zeros_like(omega)
    f = omega[omega > 0] / (2 * np.pi)
    fp4 = (1.0 / (tp * f)) ** 4
    sigma = np.where(f * tp <= 1.0, 0.07, 0.09)
    alpha = np.exp(-0.5 * ((f * tp - 1.0) / sigma) ** 2)
    out[omega > 0] = (1 - 0.287 * math.log(gamma)) * 0.3125 * hs ** 2 * fp4 / f * np.exp(-1.25 * fp4) \
        * gamma ** alpha / (2 * np.pi)
    return out


def wave_number(omega: float, gravity: float, depth: float) -> float:
    """κ [rad/m] of ``ω² = g κ tanh(κ h)`` (Newton from the deep-water value; 0 at ω = 0)."""
    if omega <= 0:
        return 0.0
    k = omega * omega / gravity
    if not math.isfinite(depth):
        return k
    for _ in range(50):
        th = math.tanh(k * depth)
        f = gravity * k * th - omega * omega
        df = gravity * th + gravity * k * depth * (1 - th * th)
        step = f / df
        k -= step
        if abs(step) < 1e-14 * k:
            break
    return k


def read_elevation_series(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """Times [s] and elevations [m] of a SeaState ``.Elev`` file (two columns; leading text lines skipped)."""
    path = Path(path)
    if not path.is_file():
        raise OpenFASTFormatError(f"wave-elevation file not found: tried '{path.absolute()}' (WvKinFile + '.Elev'). "
                                  "Check WvKinFile in the SeaState file.")
    rows, first = [], None
    for number, line in enumerate(path.read_text(encoding="latin-1").splitlines(), start=1):
        tokens = line.replace(",", " ").split()
        try:
            values = [float(t) for t in tokens]
        except ValueError:
            if rows:
                raise OpenFASTFormatError(f"{path}:{number}: expected two numbers (time, elevation); got {line!r}.")
            continue
        if len(values) != 2:
            raise OpenFASTFormatError(f"{path}:{number}: expected two columns (time s, elevation m); got {len(values)}.")
        first = number if first is None else first
        rows.append(values)
    if len(rows) < 2:
        raise OpenFASTFormatError(f"{path}: needs at least two rows of (time, elevation); found {len(rows)}.")
    data = np.array(rows)
    return data[:, 0], data[:, 1]


def incident_waves(sea, *, gravity: float, water_depth: float) -> IncidentWaves | None:
    """The :class:`IncidentWaves` of a SeaState reading (:func:`mbsym.wind.deck.read_seastate`), None in still water.

    Parameters
    ----------
    sea : SeaStateInput
    gravity, water_depth : float, keyword-only
        [m/s²], [m] (SeaState's ``WtrDpth`` + ``MSL2SWL``).

    Raises
    ------
    UnsupportedFeatureError
        Wave models 4 (user routine), 6 (external kinematics).
    ParameterError
        Constrained waves (``ConstWaveMod`` 1, 2 with ``WaveMod`` 2, :mod:`.constrained`) with ``CrestHmax < WaveHs``.
    OpenFASTFormatError
        An external series that does not cover ``WaveTMax`` or whose step is not ``WaveDT``.

    Examples
    --------
    >>> waves = incident_waves(read_seastate("SeaState.dat"), gravity=9.80665, water_depth=200.0)  # doctest: +SKIP
    >>> round(waves.significant_height(), 1)  # doctest: +SKIP
    4.0
    """
    mod = int(sea.wave_model)
    if mod == 0:
        return None
    where = f"{sea.path}"
    if mod in (4, 6):
        raise UnsupportedFeatureError(f"{where}: WaveMod = {mod} ({sea.wave_model_name}) is not modelled; use 1, 1P#, 2, "
                                      "3, 5 (an external elevation series) or 7 (wave components).")
    if sea.constrained_wave_model and mod != 2:
        warnings.warn(f"{where}: ConstWaveMod = {sea.constrained_wave_model} has no effect with WaveMod = {mod}: "
                      "SeaState constrains JONSWAP seas (WaveMod 2) only, and so does mbsym.", ModelWarning,
                      stacklevel=3)
    dt, tmax = float(sea.wave_time_step), float(sea.wave_time_max)
    if not (dt > 0 and tmax >= dt):
        raise OpenFASTFormatError(f"{where}: WaveDT = {dt} s and WaveTMax = {tmax} s must satisfy 0 < WaveDT <= WaveTMax.")
    n = wave_steps(tmax, dt)
    common = dict(direction=float(sea.wave_direction), water_depth=float(water_depth), gravity=float(gravity))
    if mod == 5:
        return _external(sea, n, dt, tmax, common)
    if mod == 7:
        return _components(sea, dt, tmax, common)
    dw = 2 * np.pi / (n * dt)
    omega = dw * np.arange(n // 2 + 1)
    uniforms = _generator(sea)
    draws = _draws(sea, n // 2, uniforms)
    if mod in (1, 10):
        s1 = np.zeros_like(omega)
        kp = int(np.rint(2 * np.pi / (dw * float(sea.peak_period))))
        if kp < n // 2 and (kp > 1 or kp == 0):
            draws[kp] *= math.sqrt(2.0) / abs(draws[kp])
            s1[kp] = 0.5 * (float(sea.wave_height) / 2) ** 2 / dw
        what = f"regular waves H {sea.wave_height} m, T {2 * np.pi / (kp * dw) if kp else 0:.4g} s"
    else:
        band = (omega >= float(sea.low_cutoff)) & (omega <= float(sea.high_cutoff))
        if mod == 2:
            s1 = jonswap(omega, float(sea.wave_height), float(sea.peak_period), float(sea.peak_shape))
        else:
            s1 = np.full_like(omega, float(sea.wave_height) ** 2 / (16 * (float(sea.high_cutoff) - float(sea.low_cutoff))))
        s1 = np.where(band, s1, 0.0)
        what = (f"{'JONSWAP' if mod == 2 else 'white-noise'} sea Hs {sea.wave_height} m"
                + (f", Tp {sea.peak_period} s, gamma {sea.peak_shape:.3g}" if mod == 2 else ""))
    spectrum = math.sqrt(n // 2) * draws * np.sqrt(2 * np.pi * 0.5 * s1 / dt)
    directions = None
    if mod in (2, 3) and sea.direction_model and int(sea.n_directions) > 1:
        from .spreading import spread_headings

        directions = spread_headings(sea, n // 2, uniforms)
        what += f", spread over {len(set(directions.round(9)))} headings (cos-2s, s = {sea.direction_spread:g})"
    if mod == 2 and sea.constrained_wave_model:
        spectrum, crest = _constrained(sea, spectrum, s1, dw, directions, common), sea.crest
        what += (f", constrained (ConstWaveMod {sea.constrained_wave_model}: CrestHmax {crest[0]:g} m at "
                 f"t = {crest[1]:g} s, x = {crest[2]:g} m, y = {crest[3]:g} m)")
    return IncidentWaves(dt, spectrum, dw, description=what, directions=directions, **common)


def _constrained(sea, spectrum: np.ndarray, s1: np.ndarray, dw: float, directions, common: dict) -> np.ndarray:
    """The JONSWAP sea's ``C_k`` with SeaState's constrained crest (:mod:`.constrained`)."""
    from .constrained import constrain_crest

    height, time, x, y = (float(v) for v in sea.crest)
    if height < float(sea.wave_height):
        raise ParameterError(f"{sea.path}: CrestHmax = {height:g} m must be at least WaveHs = {sea.wave_height:g} m "
                             "for constrained waves (SeaState refuses it too).")
    omega = dw * np.arange(spectrum.size)
    kappa = np.array([wave_number(w, common["gravity"], common["water_depth"]) if w > 0 else 0.0 for w in omega])
    headings = np.full(spectrum.size, common["direction"]) if directions is None else np.asarray(directions)
    return constrain_crest(spectrum, s1, dw, kappa, headings, mode=int(sea.constrained_wave_model),
                           crest_height=height, crest_time=time, crest_position=(x, y),
                           peak_period=float(sea.peak_period), time_step=float(sea.wave_time_step))


def _generator(sea):
    """``uniforms(n)``: ``n`` uniform numbers as one call of SeaState's generator (RANLUX, in single precision), or
    numpy's for an integer ``WaveSeed(2)`` (the compiler's generator is not reproducible: a warning says so)."""
    seed1, seed2 = sea.seeds
    if isinstance(seed2, str):
        rng = RanLux(abs(int(seed1)))
        return (lambda n: rng.call(n).astype(np.float32).astype(float))
    warnings.warn(f"{sea.path}: WaveSeed(2) = {seed2} asks SeaState for the compiler's random generator, which "
                  "no other program reproduces: mbsym draws the phases with numpy (same spectrum, another "
                  "realization). Set WaveSeed(2) = RANLUX to get OpenFAST's sea.", ModelWarning, stacklevel=4)
    gen = np.random.default_rng([abs(int(seed1)), abs(int(seed2))])
    return (lambda n: np.where((x := gen.random(n)) == 0.0, 0.5, x))


def _draws(sea, half: int, uniforms) -> np.ndarray:
    """SeaState's ``WGNC_k`` (Box–Muller), k = 0 … N/2 (``W_1 = W_(N/2) = 0``)."""
    phase = float(sea.wave_phase) if int(sea.wave_model) == 10 else None
    uniform = (lambda: float(uniforms(1)[0]))
    out = np.zeros(half + 1, dtype=complex)
    for k in [0, *range(2, half)]:
        u1 = 0.0
        while u1 == 0.0:
            u1 = uniform()
        u2 = uniform()
        c1 = math.sqrt(-2.0 * math.log(u1)) if sea.normal_amplitudes else math.sqrt(2.0)
        c2 = phase if phase is not None else 2 * np.pi * u2
        out[k] = c1 * complex(math.cos(c2), math.sin(c2))
    return out


def _components(sea, dt: float, tmax: float, common: dict) -> IncidentWaves:
    """The sea of a wave-component file (``WaveMod = 7``, :mod:`.wave_components`)."""
    from .wave_components import component_spectrum, read_wave_components

    components = read_wave_components(sea.components_file)
    high = min(float(sea.high_cutoff), math.pi / dt)        # SeaState caps WvHiCOff at pi/WaveDT (the deck's)
    spectrum, headings, dw, step = component_spectrum(components, time_max=tmax, time_step=dt,
                                                      band=(float(sea.low_cutoff), high))
    return IncidentWaves(step, spectrum, dw, description=f"{components.frequency.size} wave components from "
                         f"{Path(components.path).name}", directions=headings, **common)


def _external(sea, n: int, dt: float, tmax: float, common: dict) -> IncidentWaves:
    path = sea.elevation_file
    t, eta = read_elevation_series(path)
    span = float(t[-1] - t[0])
    file_dt = span / (len(t) - 1)
    if tmax > span + 1e-9:
        raise OpenFASTFormatError(f"{path}: the series spans {span:g} s; WaveTMax = {tmax:g} s in {sea.path} needs at "
                                  "least that much. Shorten WaveTMax or extend the series.")
    if abs(file_dt - dt) > ELEVATION_DT_TOLERANCE:
        raise OpenFASTFormatError(f"{path}: its time step {file_dt:g} s differs from WaveDT = {dt:g} s in {sea.path} "
                                  f"by more than {ELEVATION_DT_TOLERANCE} s (SeaState's check). Make them equal.")
    samples = np.zeros(n)
    m = min(len(eta), n)
    samples[:m] = eta[:m]
    spectrum = np.fft.rfft(samples)
    spectrum[0] = 0.0
    spectrum[-1] = 0.0
    dw = 2 * np.pi / tmax                                   # SeaState's WaveDOmega for WaveMod 5
    omega = dw * np.arange(len(spectrum))
    spectrum = np.where((omega >= float(sea.low_cutoff)) & (omega <= float(sea.high_cutoff)), spectrum, 0.0)
    return IncidentWaves(dt, spectrum, dw, description=f"elevation series {Path(path).name}", **common)
