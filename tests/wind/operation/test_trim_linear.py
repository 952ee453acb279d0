"""Linear models about trimmed operating points and the Campbell diagram with aerodynamics.

References:
- A and B (exact AD of the composed graph) against central finite differences of the nonlinear right-hand
  side (:meth:`mbsym.Dynamics.rhs_value`), steps 1e-6 of each variable's scale; agreement 1e-5 of the
  largest entry of each row (truncation O(h²) and rounding O(ε/h));
- the aerodynamic damping: the fore-aft tower mode's damping ratio at a trimmed point is larger with air
  than without (air density 1e-9 kg/m³, same state), more than threefold the structural value (0.36 % here;
  with air 2.4 % at 4 m/s, 5.6 % at 11 m/s), and grows with the thrust slope from 4 to 8 m/s in region 2
  (∂T/∂U ∝ U at a constant tip-speed ratio);
- the Campbell diagram labels the two tower modes at their frequency with the rotor: 0.32–0.33 Hz
  (OpenFAST's first tower modes of the NREL 5 MW, 0.32 Hz, NREL/TP-500-38060 Table 9-1: 0.3240 and
  0.3120 Hz), within 3 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mbsym.exceptions import DimensionError, ModelDefinitionError
from mbsym.wind.operation import SteadyControl
from mbsym.wind.analysis.operating_points import operating_points
from mbsym.wind.analysis.trim_linear import linearize_dynamics, linearize_point


@pytest.fixture(scope="module")
def points(operating):
    return operating_points(operating, [4.0, 8.0, 16.0], SteadyControl.nrel5mw())


def _scales(dyn, x, u):
    xs = np.maximum(np.abs(x), 1e-2)
    us = np.maximum(np.abs(u), 1e-2)
    return xs, us


def test_linear_model_matches_finite_differences(points):
    dyn = points.trimmer.dyn
    for point in points:
        lin = linearize_point(points.trimmer, point, keep_azimuth=True)
        x, u, p = point.state, point.inputs, dict(point.parameters)
        xs, us = _scales(dyn, x, u)
        A_fd = np.zeros((dyn.n_x, dyn.n_x))
        B_fd = np.zeros((dyn.n_x, dyn.n_u))
        for j in range(dyn.n_x):
            h = 1e-6 * xs[j]
            e = np.zeros(dyn.n_x)
            e[j] = h
            A_fd[:, j] = (dyn.rhs_value(x + e, u, p) - dyn.rhs_value(x - e, u, p)) / (2 * h)
        for j in range(dyn.n_u):
            h = 1e-6 * us[j]
            e = np.zeros(dyn.n_u)
            e[j] = h
            B_fd[:, j] = (dyn.rhs_value(x, u + e, p) - dyn.rhs_value(x, u - e, p)) / (2 * h)
        for M, M_fd in ((lin.A, A_fd), (lin.B, B_fd)):
            row = np.maximum(np.max(np.abs(M), axis=1, keepdims=True), 1e-12)
            assert np.max(np.abs(M - M_fd) / row) < 1e-5, point.wind_speed
        ss = lin.to_statespace()
        assert ss.input_labels == ["Wind1VelX", "BlPitchCom", "GenTqCom"]
        assert "TTDspFA" in ss.output_labels and ss.nstates == dyn.n_x
        assert lin.operating_point["wind_speed"] == point.wind_speed


def _fore_aft_damping(A, eom_coordinates, states):
    """Damping ratio of the oscillatory eigenvalue whose eigenvector is largest in TFA1."""
    lam, V = np.linalg.eig(A)
    i = states.index("TFA1")
    osc = [k for k in range(lam.size) if lam[k].imag > 1e-6 and abs(lam[k]) < 2 * math.pi * 1.0]
    k = max(osc, key=lambda k: abs(V[i, k]) / np.linalg.norm(V[:len(eom_coordinates), k]))
    return -lam[k].real / abs(lam[k]), abs(lam[k]) / (2 * math.pi)


def test_aerodynamic_damping_of_the_tower_fore_aft_mode(points):
    dyn = points.trimmer.dyn
    coords = points.trimmer.model.structure.eom.coordinates
    zeta = {}
    for point in points:
        p = dict(point.parameters)
        with_air = linearize_dynamics(dyn, point.state, point.inputs, p)["A"]
        without = linearize_dynamics(dyn, point.state, point.inputs, {**p, "air_density": 1e-9})["A"]
        z_air, f_air = _fore_aft_damping(with_air, coords, dyn.states)
        z_dry, _ = _fore_aft_damping(without, coords, dyn.states)
        assert z_air > 3 * z_dry > 0, (point.wind_speed, z_air, z_dry)
        assert 0.31 < f_air < 0.34
        zeta[point.wind_speed] = z_air
    assert zeta[8.0] > zeta[4.0]


def test_campbell_with_aerodynamics(points):
    cd = points.campbell()
    fa, ss = cd.mode("1st tower fore-aft"), cd.mode("1st tower side-side")
    assert np.all(np.abs(fa.freq_hz / 0.324 - 1) < 0.03) and np.all(np.abs(ss.freq_hz / 0.312 - 1) < 0.04)
    assert np.all(fa.damping_ratio > 5 * ss.damping_ratio)          # side-side sees no thrust damping
    d = cd.to_dict()
    assert d["wind_speed"] == [4.0, 8.0, 16.0] and len(d["modes"]) == 2


def test_linearize_rejects_bad_input(points):
    with pytest.raises(DimensionError, match="unknown output"):
        linearize_point(points.trimmer, points[0], outputs=["NoSuchChannel"])
    failed = points[0].__class__(**{**points[0].__dict__, "success": False, "message": "test"})
    with pytest.raises(ModelDefinitionError, match="failed operating point"):
        linearize_point(points.trimmer, failed)
