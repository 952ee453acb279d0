"""Large blade and tower deflections: ElastoDyn's exact lumped-node kinematics (issue 10).

References
----------
- An independent numpy Newton–Euler replica made of point masses at ElastoDyn's nodes
  (tests/wind/_elastodyn_reference.py): blade and tower nodes at z e3 + Φq − ½ qᵀAx q e3 with
  their exact velocities and accelerations, tip masses, the tower top following the axial drop
  and turning with the slope rates (SmllRotTrans orientation), ElastoDyn's stiffness and damping.
  The template's accelerations must equal the replica's to 1e-9 relative (observed ≤ 1e-14):
  (b) a spinning rotor with a free generator and large blade deflections (tip OoP 3 m,
  IP −0.8 m, F1 + F2 + E1) with random blade rates; (b′) the tower with FA and SS (both modes)
  deflected by metres, random rates, and the nacelle's yaw inertia on a free yaw bearing.
- That the exact terms vanish at q = 0 (linearizations unchanged) is checked on bare bodies in
  tests/flexible/test_exact_lumped_body.py.
"""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

import numpy as np

from mbsym.wind import nrel5mw
from mbsym.wind.structure.turbine import TurbineModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _elastodyn_reference import reference_accelerations  # noqa: E402


def _turbine(**ic):
    t = nrel5mw()
    return dataclasses.replace(t, initial_conditions=dataclasses.replace(t.initial_conditions, **ic))


def _inputs(model):
    d = model.input_defaults()
    return np.array([d[n](0.0) if callable(d[n]) else d[n] for n in model.eom.inputs], dtype=float)


def _accelerations(model, x):
    eom = model.eom
    return np.array(eom.functions.rhs(x, _inputs(model), eom.parameter_vector({}))).ravel()[eom.n_q:]


def test_spinning_rotor_with_large_blade_deflection_matches_point_masses():
    t = _turbine(blade_oop_tip_deflection=3.0, blade_ip_tip_deflection=-0.8, rotor_speed=9 * np.pi / 30)
    model = TurbineModel(t, dofs=["GenDOF", "FlapDOF1", "FlapDOF2", "EdgeDOF"])
    eom = model.eom
    n = eom.n_q
    x = model.initial_state()
    assert x[eom.coordinates.index("B1F1")] > 2.5
    rng = np.random.default_rng(11)
    for rates in (np.zeros(n), rng.normal(scale=1.0, size=n)):
        x[n:] = rates
        x[n + eom.coordinates.index("GeAz")] = 9 * np.pi / 30
        q = x[:n].copy()
        q[eom.coordinates.index("B2F2")] = 0.4                  # the second flap mode deflected too
        x[:n] = q
        qdd = _accelerations(model, x)
        ref = reference_accelerations(t, eom.coordinates, x[:n], x[n:])
        np.testing.assert_allclose(qdd, ref, rtol=0, atol=1e-9 * np.abs(ref).max())


def test_deflected_tower_with_yaw_inertia_matches_point_masses():
    t = _turbine(tower_top_fa_displacement=2.0, tower_top_ss_displacement=-1.5, nacelle_yaw=0.3)
    model = TurbineModel(t, dofs=["TwFADOF1", "TwSSDOF1", "TwFADOF2", "TwSSDOF2", "YawDOF"])
    eom = model.eom
    n = eom.n_q
    assert eom.coordinates == ("TFA1", "TSS1", "TFA2", "TSS2", "Yaw")
    x = model.initial_state()
    x[:n] = [2.0, -1.5, 0.3, -0.2, 0.3]
    for rates in (np.zeros(n), np.random.default_rng(5).normal(scale=[0.8, 0.8, 0.2, 0.2, 0.3])):
        x[n:] = rates
        qdd = _accelerations(model, x)
        ref = reference_accelerations(t, eom.coordinates, x[:n], x[n:])
        np.testing.assert_allclose(qdd, ref, rtol=0, atol=1e-9 * np.abs(ref).max())
