"""Measurement sequences for open-loop controller comparisons (tests and benchmarks).

``openfast_measurements``: the controller inputs of an OpenFAST run (``shared/openfast/aero``, CSV with
OpenFAST units) interpolated linearly to the controller time step, converted to SI, in the order of
``BaselineController.measurement_names`` (GenSpeed, RotSpeed, BldPitch1, GenPwr, Wind1VelX).
``synthetic_sweep``: a plausible, reproducible sweep from region 2 through rated to region 3 and back;
``ipc_sweep``: the same with blade-root moments (1P and 2P) and a rotating azimuth.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

RPM = np.pi / 30.0


def read_openfast_csv(path: Path) -> dict[str, np.ndarray]:
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {name.split("_[")[0]: data[:, j] for j, name in enumerate(rows[0])}


def openfast_measurements(path: Path, dt: float, t_end: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(times, Y) with Y[k] = (GenSpeed [rad/s], RotSpeed [rad/s], BldPitch1 [rad], GenPwr [W], Wind1VelX [m/s])."""
    c = read_openfast_csv(path)
    t_end = c["Time"][-1] if t_end is None else t_end
    t = np.arange(0.0, t_end + 1e-9, dt)
    def at(name):
        return np.interp(t, c["Time"], c[name])
    y = np.column_stack([at("GenSpeed") * RPM, at("RotSpeed") * RPM, np.deg2rad(at("BldPitch1")),
                         at("GenPwr") * 1e3, at("Wind1VelX")])
    return t, y


def synthetic_sweep(dt: float, t_end: float = 160.0, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Wind 5 → 22 → 6 m/s with noise; rotor speed on a TSR-7.5 schedule capped at rated, power on a Cp curve."""
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, t_end + 1e-9, dt)
    wind = np.interp(t, [0.0, 0.45 * t_end, 0.55 * t_end, t_end], [5.0, 22.0, 22.0, 6.0])
    wind += 0.3 * np.sin(0.9 * t) + 0.05 * rng.standard_normal(t.size)
    rotor = np.clip(7.5 * wind / 63.0, 0.5, 1.26711) + 0.01 * np.sin(2.1 * t)
    power = np.minimum(0.5 * 1.225 * np.pi * 63.0**2 * 0.47 * wind**3 * 0.944, 5.0e6)
    y = np.column_stack([97.0 * rotor, rotor, np.zeros(t.size), power, wind])
    return t, y


def ipc_sweep(dt: float, t_end: float = 80.0, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """:func:`synthetic_sweep` plus blade-root moments and azimuth, for individual pitch control.

    Columns: the five of ``synthetic_sweep``, then ``RootMyc1..3`` [N m] and ``Azimuth`` [rad]. The azimuth
    integrates the rotor speed from 0.3 rad and is wrapped to [0, 2π) as OpenFAST sends it; blade k sits at
    ψ + (k − 1)·2π/3 and carries a mean flap moment 6 MN m (± 0.2 MN m slow variation), a 1P part of 1.5 MN m
    (phase −0.4 rad: a tilt and a yaw moment, as from shear and yaw misalignment), a 2P part of 0.4 MN m and
    noise (30 kN m): magnitudes of the NREL 5 MW near rated.
    """
    t, y = synthetic_sweep(dt, t_end)
    rng = np.random.default_rng(seed)
    psi = 0.3 + np.concatenate([[0.0], np.cumsum(y[:-1, 1]) * dt])
    moments = []
    for k in range(3):
        a = psi + 2.0 * np.pi * k / 3.0
        moments.append(6e6 + 2e5 * np.sin(0.9 * t) + 1.5e6 * np.cos(a - 0.4) + 4e5 * np.cos(2.0 * a + 0.5)
                       + 3e4 * rng.standard_normal(t.size))
    return t, np.column_stack([y] + moments + [np.mod(psi, 2.0 * np.pi)])
