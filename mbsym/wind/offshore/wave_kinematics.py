"""The water's velocity at points below the still-water level in first-order waves, as SeaState gives it.

HydroDyn's Morison members see the waves through SeaState's kinematics grid (OpenFAST v5.0.0; read for the
facts in ``Waves.f90``, ``SeaState_Input.f90``, ``SeaSt_WaveField.f90`` and the NWTC ``GridInterp.f90``):

* **At the grid's nodes** the velocity is the inverse DFT of the elevation's ``C_k``
  (:class:`~.waves.IncidentWaves`) times, per component of heading β and wave number κ (finite depth ``h``),
  ``E = e^{−iκ(x cos β + y sin β)}``::

      u = cos β · ω C E · cosh κ(z + h) / sinh κh,   v = sin β · ω C E · cosh κ(z + h) / sinh κh,
      w = i ω C E · sinh κ(z + h) / sinh κh,

  with SeaState's deep-water forms (``e^{κz} ± e^{−κ(z + 2h)}``) where ``κh > 89.4``; zero at ω = 0.
* **The grid**: ``x`` and ``y`` as the elevation's (``X_HalfWidth``, ``NX``, …: :func:`~.waves.grid_elevation`),
  ``z`` on ``NZ`` nodes ``z_k = −(1 − cos((NZ − 1 − k) Δθ)) Z_Depth``, ``Δθ = π / (2 (NZ − 1))`` (from
  ``−Z_Depth`` to 0; ``Z_Depth`` default the water depth), read in the uniform variable
  ``θ(z) = π/2 − acos(1 + z/Z_Depth)``.
* **Between nodes** the NWTC ``GridInterp`` in each of ``x``, ``y``, ``θ`` (cubic Catmull–Rom inside, quadratic
  at the edges, linear on two nodes; a point off the grid clamped to its edge) and in time (periodic cubic,
  :func:`~.excitation.catmull_rom`), the tensor product of the four.

HydroDyn takes the kinematics of a node at its **undisplaced** position (``WaveDisp = 0``, ``WaveStMod = 0``)
and zero above the still-water level; :class:`WaveFlow` holds them on the wave time grid for the wet strip
nodes and end plates of :class:`~.morison.MorisonDrag`, and gives them as simulation input tables. The
acceleration (``iω`` times the velocity's transfer functions) and the dynamic pressure
(``ρ g C E cosh κ(z + h) / cosh κh``) are read off the same grid for the strip-theory members' wave inertia
(:func:`wave_acceleration_pressure`, :mod:`.strip_theory`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .excitation import catmull_rom
from .waves import IncidentWaves, _grid_weights, index_weights, wave_number

__all__ = ["WaveFlow", "wave_flow", "flow_input_names", "node_velocity", "node_acceleration_pressure",
           "wave_acceleration_pressure"]

#: κh above which SeaState switches to its deep-water forms of the depth functions.
_DEEP = 89.4


def flow_input_names(n: int) -> tuple[str, ...]:
    """The inputs of the water's velocity at ``n`` Morison points: ``MorisonU<k>xi``, ``…yi``, ``…zi`` [m/s]."""
    return tuple(f"MorisonU{k + 1}{c}i" for k in range(n) for c in "xyz")


@dataclass(frozen=True, eq=False)
class WaveFlow:
    """The water's velocity at fixed points on the waves' time grid.

    Attributes
    ----------
    waves : IncidentWaves
    velocity : ndarray (N + 1, n, 3)
        [m/s], inertial axes, on ``waves.times()`` (the last sample repeats the first).
    """

    waves: IncidentWaves
    velocity: np.ndarray

    @property
    def n_points(self) -> int:
        return int(self.velocity.shape[1])

    def at(self, t) -> np.ndarray:
        """``(len(t), 3 n)`` velocities at times ``t`` [s], as HydroDyn reads them (periodic cubic in time)."""
        flat = self.velocity.reshape(self.velocity.shape[0], -1)
        return catmull_rom(flat, self.waves.time_step, np.atleast_1d(np.asarray(t, dtype=float)))

    def tables(self, t: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
        """Input tables ``name → (t, values)`` (:func:`flow_input_names`) on the times ``t`` [s]."""
        values = self.at(t)
        return {name: (t, values[:, j]) for j, name in enumerate(flow_input_names(self.n_points))}


def node_velocity(waves: IncidentWaves, x: float, y: float, z: float) -> np.ndarray:
    """``(N + 1, 3)`` velocity [m/s] at a point ``z ≤ 0`` on ``waves.times()``, exact (no grid)."""
    omega = waves.frequencies
    beta = waves.headings()
    h = waves.water_depth
    kappa = np.array([wave_number(w, waves.gravity, h) if w > 0 else 0.0 for w in omega])
    ch, sh = _depth_functions(kappa, z, h)
    c = waves.spectrum * np.exp(-1j * kappa * (x * np.cos(beta) + y * np.sin(beta))) * omega
    return np.column_stack([waves.series(np.cos(beta) * c * ch), waves.series(np.sin(beta) * c * ch),
                            waves.series(1j * c * sh)])


def node_acceleration_pressure(waves: IncidentWaves, x: float, y: float, z: float, water_density: float) -> np.ndarray:
    """``(N + 1, 4)`` acceleration [m/s²] and dynamic pressure [Pa] at a point ``z ≤ 0`` on ``waves.times()``, exact
    (no grid): SeaState's ``iω`` times the velocity, and ``ρ g C E cosh κ(z + h) / cosh κh`` (its deep-water form
    ``e^{κz} + e^{−κ(z + 2h)}`` beyond κh = 89.4)."""
    omega = waves.frequencies
    beta = waves.headings()
    h = waves.water_depth
    kappa = np.array([wave_number(w, waves.gravity, h) if w > 0 else 0.0 for w in omega])
    ch, sh = _depth_functions(kappa, z, h)
    e = waves.spectrum * np.exp(-1j * kappa * (x * np.cos(beta) + y * np.sin(beta)))
    c = 1j * omega * omega * e
    return np.column_stack([waves.series(np.cos(beta) * c * ch), waves.series(np.sin(beta) * c * ch),
                            waves.series(1j * c * sh),
                            waves.series(water_density * waves.gravity * e * _pressure_depth(kappa, z, h))])


def _pressure_depth(kappa: np.ndarray, z: float, h: float) -> np.ndarray:
    """``cosh κ(z+h) / cosh κh`` (SeaState's ``COSHNumOvrCOSHDen``; 1 at κ = 0)."""
    out = np.ones_like(kappa)
    for i, k in enumerate(kappa):
        if k <= 0.0:
            continue
        out[i] = math.exp(k * z) + math.exp(-k * (z + 2 * h)) if k * h > _DEEP else \
            math.cosh(k * (z + h)) / math.cosh(k * h)
    return out


def _depth_functions(kappa: np.ndarray, z: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """``cosh κ(z+h) / sinh κh`` and ``sinh κ(z+h) / sinh κh`` (SeaState's deep-water forms beyond κh = 89.4;
    0 and 1 at κ = 0, where ω = 0 zeroes the velocity)."""
    ch, sh = np.zeros_like(kappa), np.ones_like(kappa)
    for i, k in enumerate(kappa):
        if k <= 0.0:
            continue
        if k * h > _DEEP:
            ch[i], sh[i] = math.exp(k * z) + math.exp(-k * (z + 2 * h)), math.exp(k * z) - math.exp(-k * (z + 2 * h))
        else:
            ch[i], sh[i] = math.cosh(k * (z + h)) / math.sinh(k * h), math.sinh(k * (z + h)) / math.sinh(k * h)
    return ch, sh


def wave_flow(waves: IncidentWaves, sea, points: np.ndarray) -> WaveFlow:
    """:class:`WaveFlow` at ``points`` (n, 3) [m, undisplaced, inertial; z relative to the still-water level] read
    off SeaState's kinematics grid (module docstring); points above the water get zero."""
    return WaveFlow(waves, _on_grid(waves, sea, points, lambda x, y, z: node_velocity(waves, x, y, z), 3))


def wave_acceleration_pressure(waves: IncidentWaves, sea, points: np.ndarray,
                               water_density: float) -> tuple[np.ndarray, np.ndarray]:
    """The waves' acceleration ``(N + 1, n, 3)`` [m/s²] and dynamic pressure ``(N + 1, n)`` [Pa] at ``points``
    (as :func:`wave_flow`) on ``waves.times()``, read off SeaState's grid."""
    out = _on_grid(waves, sea, points,
                   lambda x, y, z: node_acceleration_pressure(waves, x, y, z, water_density), 4)
    return out[:, :, :3], out[:, :, 3]


def _on_grid(waves: IncidentWaves, sea, points: np.ndarray, at, width: int) -> np.ndarray:
    """``(N + 1, n, width)``: ``at(x, y, z)`` on SeaState's grid nodes around each point, interpolated as GridInterp
    does; zero above the water."""
    depth = _grid_depth(sea, waves.water_depth)
    nz = int(sea.nz)
    cache: dict[tuple[float, float, float], np.ndarray] = {}
    out = np.zeros((waves.n_steps + 1, len(points), width))
    for j, (x, y, z) in enumerate(np.asarray(points, dtype=float)):
        if z > 0.0:
            continue
        for (xi, a), (yi, b), (zi, c) in _stencil(sea, depth, nz, x, y, z):
            key = (xi, yi, zi)
            if key not in cache:
                cache[key] = at(xi, yi, zi)
            out[:, j] += a * b * c * cache[key]
    return out


def _grid_depth(sea, water_depth: float) -> float:
    value = getattr(sea, "domain_depth", None)
    if value is None or (isinstance(value, str) and value.lower() == "default"):
        return float(water_depth)
    return float(value)


def _stencil(sea, depth: float, nz: int, x: float, y: float, z: float):
    """``((x, w), (y, w), (z, w))`` of the grid nodes around a point with their GridInterp weights."""
    wx = [(p, w) for p, w in _grid_weights(x, float(sea.x_half_width), int(sea.nx)) if w != 0.0]
    wy = [(p, w) for p, w in _grid_weights(y, float(sea.y_half_width), int(sea.ny)) if w != 0.0]
    dtheta = math.pi / (2 * (nz - 1))
    theta = math.pi / 2 - math.acos(min(max(1.0 + z / depth, -1.0), 1.0))
    wz = [(-(1.0 - math.cos((nz - 1 - k) * dtheta)) * depth, w) for k, w in index_weights(theta / dtheta, nz)
          if w != 0.0]
    return [(a, b, c) for a in wx for b in wy for c in wz]
