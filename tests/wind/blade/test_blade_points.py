"""Points along the blades (mbsym.wind.structure.blade_points) and the structure's blade-load inputs.

References: the virtual-power identity of Kane's method (the generalized forces of the blade-load inputs,
computed by the structure's own equations, do the same power as the distributed loads on the moving
points: exact, 1e-9 relative for round-off), ElastoDyn's shapes at its own nodes (interpolation exact
there), and a static closed form for the root-moment reactions.
"""

import casadi as ca
import numpy as np
import pytest

from mbsym.wind import nrel5mw
from mbsym.wind.structure.blade_points import blade_point_kinematics, blade_point_loads, blade_point_shapes
from mbsym.wind.structure.turbine import BLADE_LOAD_INPUTS, TurbineModel

DOFS = ("FlapDOF1", "FlapDOF2", "EdgeDOF", "GenDOF", "TwFADOF1", "TwSSDOF1")


@pytest.fixture(scope="module")
def model():
    return TurbineModel(nrel5mw(), DOFS, pitch_input=True, blade_loads=True, tower_base_reactions=True,
                        blade_root_reactions=True)


def test_shapes_at_elastodyn_nodes_are_elastodyn_shapes(model):
    data = model.blade_data(1)
    shapes = blade_point_shapes(model, 1, data.span)
    np.testing.assert_allclose(shapes.displacement, data.displacement, rtol=0, atol=1e-14)
    np.testing.assert_allclose(shapes.axial_reduction, data.axial_reduction, rtol=0, atol=1e-14)
    tip = blade_point_shapes(model, 1, [data.length])
    np.testing.assert_allclose(tip.displacement[:, 0], data.tip_displacement, atol=1e-14)
    assert shapes.coordinates == ("B2F1", "B2F2", "B2E1")


def test_points_off_the_blade_are_refused(model):
    from mbsym.exceptions import ParameterError

    with pytest.raises(ParameterError, match="BldFlexL"):
        blade_point_shapes(model, 0, [0.0, 70.0])


def test_blade_load_inputs_do_the_power_of_the_distributed_loads(model):
    """q̇ᵀ (F(q, q̇, u) − F(q, q̇, 0)) = Σ_j w_j (f_j · v_j + m_j · ω) for random states and loads."""
    eom = model.eom
    rng = np.random.default_rng(3)
    q = ca.SX.sym("q", eom.n_q)
    qd = ca.SX.sym("qd", eom.n_q)
    p = ca.DM(eom.parameter_vector()) if hasattr(eom, "parameter_vector") else None
    defaults = dict(eom.defaults)
    pv = ca.DM([defaults[n] for n in eom.parameters])
    u_base = {n: 0.0 for n in eom.inputs}
    u_base.update(BlPitch=0.1)          # pitch held: a prescribed rate would do power of its own
    spans = np.linspace(0.0, 61.5, 9)
    weights = np.full(spans.size, 61.5 / 8)
    weights[[0, -1]] /= 2
    power = 0.0
    inputs = dict(u_base)
    sym_u = ca.vertcat(*[u_base[n] for n in eom.inputs])
    forces = []
    for k in range(3):
        frame_f = eom.point_kinematics(f"blade{k + 1}")
        out = dict(zip(frame_f.name_out(), frame_f(q, qd, ca.DM.zeros(eom.n_q), sym_u, pv)))
        shapes = blade_point_shapes(model, k, spans)
        idx = [eom.coordinates.index(c) for c in shapes.coordinates]
        kin = blade_point_kinematics(shapes, out, q[idx], qd[idx])
        f = ca.DM(rng.normal(scale=1e3, size=(3, spans.size)))
        m = ca.DM(rng.normal(scale=1e2, size=(3, spans.size)))
        loads = blade_point_loads(kin, out["R"], f, m, weights)
        power += ca.sum2(ca.sum1(kin["v"] * f) * ca.DM(weights).T) + ca.dot(out["w"], m @ ca.DM(weights))
        for c, value in zip(BLADE_LOAD_INPUTS, ca.vertsplit(ca.vertcat(loads["F"], loads["M"]))):
            inputs[f"B{k + 1}Aero{c}"] = value
        for c, value in zip(shapes.coordinates, loads["Q"]):
            inputs[f"{c}AeroQ"] = value
    u_loaded = ca.vertcat(*[inputs[n] for n in eom.inputs])
    F = eom.functions.forcing
    gen = ca.dot(qd, F(q, qd, u_loaded, pv) - F(q, qd, sym_u, pv))
    check = ca.Function("check", [q, qd], [gen, power])
    for _ in range(3):
        qv, qdv = rng.normal(scale=0.3, size=eom.n_q), rng.normal(scale=0.5, size=eom.n_q)
        a, b = (float(v) for v in check(qv, qdv))
        assert a == pytest.approx(b, rel=1e-9, abs=1e-6)


def test_root_reactions_hold_the_blade_weight(model):
    """Rotor at rest: the root reactions of every blade balance its weight moment about the root.

    Closed form: a blade of node masses m_j at z_j along its axis i3 (pitch 0: body axes = i1, i2, i3)
    carries the moment M = Σ m_j z_j i3 × (−g e_z) about its root; the locked root rotations must supply
    λ = −M·(i1, i2, i3) (static, exact to round-off: 1e-9 relative).
    """
    t = nrel5mw()
    m = TurbineModel(t, ("GenDOF",), pitch_input=True, blade_loads=True, blade_root_reactions=True,
                     tower_base_reactions=True)
    eom = m.eom
    defaults = dict(eom.defaults)
    pv = [defaults[n] for n in eom.parameters]
    u = [0.0] * len(eom.inputs)
    zeros = np.zeros(eom.n_q)
    lam = np.asarray(eom.functions.reactions(zeros, zeros, zeros, u, pv)).ravel()
    g = defaults["gravity"]
    for k in range(3):
        data = m.blade_data(k)
        mass = np.append(data.element_mass, data.tip_mass)
        z = np.append(data.span, data.length)
        R = np.asarray(eom.point_kinematics(f"blade{k + 1}")(zeros, zeros, zeros, u, pv)[1])
        moment = float(mass @ z) * np.cross(R[:, 2], [0.0, 0.0, -g])
        np.testing.assert_allclose(lam[2 + 3 * k:5 + 3 * k], -R.T @ moment, rtol=1e-9, atol=1e-6 * abs(moment).max())
