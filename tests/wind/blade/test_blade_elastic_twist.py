"""The elastic part of AeroDyn's local twist angle of a bent ElastoDyn blade (``blade_compose.elastic_twist``).

Reference: a hand computation with full rotation matrices of the chain OpenFAST runs (independent of the
closed form): ElastoDyn turns a blade section by one small rotation whose matrix is orthonormal (NWTC
``SmllRotTrans``: the rotation with quaternion vector part ``ω/2``, i.e. by the angle ``2 asin(|ω|/2)``
about ``ω``), with ``ω = (−s_y, s_x, 0)`` in the pitched blade axes; AeroDyn (``BEM_Mod = 1``) reads the
section's orientation relative to the unpitched root, decomposes it into z-y-x Euler angles (NWTC
``EulerExtract``: ``M = Z(θz) Y(θy) X(θx)``) and uses ``θ = −θz``. The closed form is AeroDyn's angle to
second order in the slopes; its relative error is ``ω₂²/2`` (the ``1 − ω₂²/2`` of ``EulerExtract``'s
``M11``), below 0.8 % for slopes up to 0.12 rad (about what OpenFAST's NREL 5 MW reaches at 60 m with
6 m of tip deflection): the tolerance below is 1 % of the value plus 1e-12 rad.
"""

import numpy as np
import pytest

from mbsym.wind.operation.blade_compose import elastic_twist


def _dcm_z(angle: float) -> np.ndarray:
    """Direction-cosine matrix (rows: new axes in old coordinates) of a rotation by ``angle`` about z."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, s, 0.0], [-s, c, 0.0], [0.0, 0.0, 1.0]])


def _dcm_small(omega: np.ndarray) -> np.ndarray:
    """ElastoDyn's small-rotation matrix: the rotation with quaternion ``(w, ω/2)``, ``w = √(1 − |ω/2|²)``."""
    v = 0.5 * np.asarray(omega, dtype=float)
    w = np.sqrt(1.0 - v @ v)
    skew = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    rotation = (w * w - v @ v) * np.eye(3) + 2.0 * np.outer(v, v) + 2.0 * w * skew     # active rotation
    return rotation.T                                                                  # as a DCM


def _aerodyn_theta(twist: float, structural_twist: float, pitch: float, slope_x: float, slope_y: float) -> float:
    """AeroDyn's θ of a section, through ElastoDyn's chain (ElastoDyn.f90 ``SetCoordSy``): the structural
    axes ``L`` are the pitched axes turned by the structural twist; the small rotation acts about
    ``(ThetaLxb, ThetaLyb)``, the rotation vector ``(ThetaIP, ThetaOoP) = (−s_y, s_x)`` in ``L``'s
    components; OpenFAST's mesh mapping gives AeroDyn's node that orientation times its reference offset
    (aerodynamic minus structural twist, about the span axis); θ is minus the z Euler angle relative to the
    unpitched root."""
    c, s = np.cos(structural_twist), np.sin(structural_twist)
    theta_ip, theta_oop = -slope_y, slope_x
    theta_lx, theta_ly = c * theta_ip - s * theta_oop, s * theta_ip + c * theta_oop
    structural = _dcm_z(-(pitch + structural_twist))          # j1 = cos β i1 − sin β i2, then the structural twist
    section = _dcm_small(np.array([theta_lx, theta_ly, 0.0])) @ structural
    node = _dcm_z(structural_twist - twist) @ section
    return float(-np.arctan2(-node[1, 0], node[0, 0]))


@pytest.mark.parametrize("pitch_deg", [0.0, 3.5, 8.6, 20.0])
def test_elastic_twist_is_aerodyn_euler_angle(pitch_deg):
    rng = np.random.default_rng(7)
    pitch = np.deg2rad(pitch_deg)
    for _ in range(50):
        sx, sy = rng.uniform(-0.12, 0.12), rng.uniform(-0.05, 0.05)
        twist, structural_twist = rng.uniform(-0.1, 0.25), rng.uniform(-0.1, 0.25)
        expected = _aerodyn_theta(twist, structural_twist, pitch, sx, sy) - twist - pitch
        got = float(elastic_twist(sx, sy, pitch))
        assert abs(got - expected) <= 0.01 * abs(expected) + 1e-12, (pitch_deg, sx, sy, got, expected)


def test_elastic_twist_signs():
    """A blade bent downwind (s_x > 0) and against the in-plane axis j2 (s_y < 0) feathers (θ grows), as
    OpenFAST's node output shows (B1N…Theta − twist − pitch ≈ +0.2° at 57 m of span with 4 m out of plane
    and −1.5 m in plane); pure flap feathers in proportion to sin 2β; no bending, no elastic twist."""
    assert elastic_twist(0.1, -0.04, 0.0) > 0.0
    assert elastic_twist(0.1, 0.0, np.deg2rad(8.0)) > 0.0
    assert elastic_twist(0.1, 0.0, 0.0) == 0.0
    assert elastic_twist(0.0, 0.0, 0.3) == 0.0


def test_operating_turbine_adds_the_elastic_twist_of_its_bent_blades():
    """Wiring: the blade-element model's θ at every node of a bent, pitched rotor is twist + pitch + the
    elastic twist of the slopes of ElastoDyn's shapes at that node (computed here with numpy from
    ``blade_point_shapes``), blade by blade. Same expression both ways: tolerance 1e-9 rad (round-off)."""
    import sys
    from pathlib import Path

    import mbsym as mb
    from mbsym.wind.structure.blade_points import blade_point_shapes

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
    from _op_data import INPUTS, need

    model = mb.wind.OperatingTurbine.from_openfast(need(INPUTS / "steady_14" / "steady_14.fst"), aero="blade",
                                                   dofs=["GenDOF", "FlapDOF1", "EdgeDOF"])
    model.dynamics()
    f, eom, rotor = model._parts["blade_aero"], model.structure.eom, model.rotor
    q = np.zeros(eom.n_q)
    deflection = {"F1": (3.0, 4.5, 6.0), "E1": (-1.0, 0.5, -0.3)}                 # per blade [m]
    for i, c in enumerate(eom.coordinates):
        if c[-2:] in deflection:
            q[i] = deflection[c[-2:]][int(c[1]) - 1]
    pitch = np.deg2rad(8.6)
    u_s = np.zeros(len(eom.inputs))
    u_s[eom.inputs.index("BlPitch")] = pitch
    out = f(q=q, qd=np.zeros(eom.n_q), u_s=u_s, p_s=np.zeros(eom.n_p), states=np.zeros(len(rotor.state_names)),
            wind=np.zeros(len(model.wind.inputs)), rho=1.225)
    theta = np.asarray(out["node_theta"]).ravel().reshape(rotor.n_blades, rotor.n_nodes)
    for k in range(rotor.n_blades):
        shapes = blade_point_shapes(model.structure, k, rotor.span)
        qk = np.array([q[eom.coordinates.index(c)] for c in shapes.coordinates])
        slope = np.einsum("enx,e->xn", shapes.slope, qk)                         # (2, nodes)
        expected = np.asarray(rotor.twist) + pitch + np.asarray(elastic_twist(slope[0], slope[1], pitch))
        np.testing.assert_allclose(theta[k], expected, rtol=0, atol=1e-9)
    assert np.rad2deg(theta[2, -3] - rotor.twist[-3] - pitch) > 0.05           # bent 6 m: feathered by > 0.05 deg
