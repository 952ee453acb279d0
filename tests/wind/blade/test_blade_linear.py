"""Linear models of the blade-element turbine about its periodic operating point, in multi-blade coordinates.

References (independent of the code under test):
- central finite differences of the nonlinear right-hand side (Dynamics.rhs) for the azimuth-wise A and B;
- the closed-form fixed-frame model of an isotropic rotor (per-blade lags on a spinning hub): constant in
  multi-blade coordinates, collective unchanged, cyclic pair coupled by the rotor speed;
- physics of the NREL 5 MW at 14 m/s: aerodynamic damping of the first tower fore-aft mode well above its
  structural 1 % (the rotor-effective model of the same deck, trim_linear, gives the same order), the blade
  flap modes heavily damped by the air (> 10 %, Hansen 2007 "Aeroelastic instability problems for wind
  turbines": flapwise aerodynamic damping is tens of percent);
- the rotor-effective model's linear model at the same wind speed for the static rotor-speed response to
  collective pitch.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
from _op_data import INPUTS, need  # noqa: E402

from mbsym.wind.structure.mbc import derivative_pairs, mbc_names, mbc_system, rotating_triplets  # noqa: E402

DOFS = ["GenDOF", "TwFADOF1", "TwSSDOF1", "FlapDOF1", "EdgeDOF"]


@pytest.fixture(scope="module")
def case():
    import mbsym as mb
    from mbsym.wind.analysis.blade_linear import blade_linear_model
    from mbsym.wind.analysis.blade_periodic import periodic_point
    from mbsym.wind.operation import trim

    fst = need(INPUTS / "steady_14" / "steady_14.fst")
    rotor = mb.wind.OperatingTurbine.from_openfast(fst, aero="rotor", dofs=["GenDOF", "TwFADOF1", "TwSSDOF1"])
    start = trim(rotor, 14.0)
    model = mb.wind.OperatingTurbine.from_openfast(fst, aero="blade", dofs=DOFS, pitch="individual")
    point = periodic_point(model, 14.0, start=start)
    lin = blade_linear_model(model, point, keep_azimuth=True)
    return {"rotor": rotor, "start": start, "model": model, "point": point, "lin": lin}


def test_periodic_point_converges(case):
    """The state one revolution later equals the state (relative 1e-4, the default tolerance), at the trim's speed
    within 1 % (held torque and pitch of the rotor-effective trim; the two aerodynamic models differ by ~1 %)."""
    point = case["point"]
    assert point.converged and point.residual_norm <= 1e-4
    assert point.rotor_speed == pytest.approx(case["start"].x()["GeAz_d"], rel=0.01)
    assert np.allclose(np.diff(np.unwrap(point.blade_azimuths)), 2 * np.pi / 12, rtol=0.02)


def test_azimuth_jacobians_match_central_differences(case):
    """A, B at one sample against central differences of the rhs: steps 1e-6 of each variable's scale, agreement
    1e-5 of the column's largest entry (truncation O(h²) and rounding O(ε/h) are both far below)."""
    from mbsym.wind.analysis.blade_periodic import azimuth_jacobians

    model, point = case["model"], case["point"]
    dyn = model.dynamics()
    x, u = point.states[3], point.inputs
    p = dict(point.parameters)
    jac = azimuth_jacobians(dyn, x[None, :], u, dyn.parameter_vector(p))
    cols = [dyn.states.index(n) for n in ("TFA1", "B2F1", "B3E1", "GeAz", "GeAz_d", "B1F1_d", "BlPitch2", "GenTq",
                                          "B1N10_vind_x", "B3N17_vind1_y")]
    for j in cols:
        h = 1e-6 * max(abs(x[j]), 1e-2)
        e = np.zeros(dyn.n_x)
        e[j] = h
        fd = (dyn.rhs_value(x + e, u, p) - dyn.rhs_value(x - e, u, p)) / (2 * h)
        assert np.max(np.abs(jac["A"][0][:, j] - fd)) <= 1e-5 * np.max(np.abs(fd)), dyn.states[j]
    for name in ("Wind1VelX", "HLinShr", "BlPitchCom1", "GenTqCom"):
        j = dyn.inputs.index(name)
        h = 1e-6 * max(abs(u[j]), 1e-2)
        e = np.zeros(dyn.n_u)
        e[j] = h
        fd = (dyn.rhs_value(x, u + e, p) - dyn.rhs_value(x, u - e, p)) / (2 * h)
        assert np.max(np.abs(jac["B"][0][:, j] - fd)) <= 1e-5 * np.max(np.abs(fd)), name


def test_mbc_of_an_isotropic_rotor_is_constant():
    """Per-blade lags x_b' = -a x_b + u_b with y_b = x_b, and a fixed-frame state driven by the blades' cosine sum:
    in multi-blade coordinates the model does not depend on the azimuth, the collective keeps -a, the cyclic pair
    is [[-a, -Ω], [Ω, -a]] and the fixed state sees the cosine coordinate with gain 3/2 (Σ cos² ψ_b = 3/2)."""
    a, om = 0.7, 1.3
    names = ["T", "L1", "L2", "L3"]
    tx = rotating_triplets(names)
    expected_A = np.array([[-1.0, 0.0, 1.5, 0.0], [0, -a, 0, 0], [0, 0, -a, -om], [0, 0, om, -a]])
    for psi in (0.0, 0.4, 2.0, 5.1):
        A = np.diag([-1.0, -a, -a, -a])
        A[0, 1:] = np.cos(psi + 2 * np.pi * np.arange(3) / 3)
        B = np.vstack([np.zeros((1, 3)), np.eye(3)])
        C = np.hstack([np.zeros((3, 1)), np.eye(3)])
        Ab, Bb, Cb, Db = mbc_system(A, B, C, np.zeros((3, 3)), psi, om, states=tx, inputs=[(0, 1, 2)],
                                    outputs=[(0, 1, 2)])
        np.testing.assert_allclose(Ab, expected_A, atol=1e-12)
        np.testing.assert_allclose(Bb, B, atol=1e-12)
        np.testing.assert_allclose(Cb, C, atol=1e-12)
    assert mbc_names(names, tx) == ("T", "L_coll", "L_cos", "L_sin")
    states = ["B1F1", "B2F1", "B3F1", "B1F1_d", "B2F1_d", "B3F1_d", "BlPitch1", "BlPitch2", "BlPitch3"]
    assert derivative_pairs(states, rotating_triplets(states)) == [(0, 1)]


def test_linear_model_names_and_units(case):
    lin = case["lin"]
    ss = lin.to_statespace()
    assert ss.input_labels == ["BlPitchCom_coll", "BlPitchCom_cos", "BlPitchCom_sin", "GenTqCom", "Wind1VelX",
                               "HLinShr", "VLinShr"]
    assert ss.output_labels[:4] == ["RootMyc_coll", "RootMyc_cos", "RootMyc_sin", "RotSpeed"]
    assert "F1_cos_d" in ss.state_labels and "N5_vind_x_sin" in ss.state_labels
    y = dict(zip(lin.outputs, lin.operating_point["y"]))
    # SI: RotSpeed in rad/s (the mean rotor speed), the collective root moment in N m (OpenFAST's ~6.3 MN m at 14 m/s
    # without shear is 6337 kN m with shear: same order)
    assert y["RotSpeed"] == pytest.approx(case["point"].rotor_speed, rel=1e-3)
    assert 2e6 < y["RootMyc_coll"] < 2e7


def test_aerodynamic_damping_of_tower_and_flap(case):
    """Tower fore-aft damping with air well above the structural 1 % and within a factor 1.5 of the rotor-effective
    model's (trim_linear) at the same wind speed (different aerodynamic models: BEM per node with the tower's motion at
    every node vs the rotor's thrust slope on the surfaces); collective flap damping > 10 %."""
    from mbsym.wind.analysis.blade_linear import labelled_modes
    from mbsym.wind.analysis.trim_linear import _labelled_modes, linearize_point
    from mbsym.wind.analysis.campbell_diagram import DOF_LABELS
    from mbsym.wind.operation.trim import Trimmer

    labels, f, z = labelled_modes(case["lin"])
    zeta = dict(zip(labels, z))
    assert zeta["1st tower fore-aft"] > 0.03
    assert zeta["1st flap collective"] > 0.10
    rotor = case["rotor"]
    trimmer = Trimmer(rotor)
    ref = linearize_point(trimmer, trimmer.solve(14.0), outputs=())
    names, _, zr = _labelled_modes(ref, rotor.structure.eom.coordinates, DOF_LABELS)
    z_ref = dict(zip(names, zr))["1st tower fore-aft"]
    assert z_ref / 1.5 < zeta["1st tower fore-aft"] < 1.5 * z_ref


def test_rotor_speed_response_to_collective_pitch(case):
    """Static RotSpeed / collective pitch (torque held) against the rotor-effective linear model: same sign (more
    pitch, less torque, lower speed) and within 20 % (different aerodynamic models)."""
    from mbsym.wind.analysis.blade_linear import blade_linear_model
    from mbsym.wind.analysis.trim_linear import linearize_point
    from mbsym.wind.operation.trim import Trimmer

    lin = blade_linear_model(case["model"], case["point"], inputs=["BlPitchCom1", "BlPitchCom2", "BlPitchCom3"],
                             outputs=["RotSpeed"])
    ss = lin.to_statespace()
    g_blade = float(np.real(ss.dcgain()[0, 0]))
    trimmer = Trimmer(case["rotor"])
    ref = linearize_point(trimmer, trimmer.solve(14.0), outputs=("RotSpeed",))
    keep = [i for i, s in enumerate(ref.states) if s != "GeAz"]
    A, B = ref.A[np.ix_(keep, keep)], ref.B[keep][:, [ref.inputs.index("BlPitchCom")]]
    C = ref.Cy[:, keep] * (math.pi / 30 if ref.output_units[0] == "rpm" else 1.0)     # rad/s (SI since issue 22)
    g_ref = float(-(C @ np.linalg.solve(A, B))[0, 0])
    assert g_blade < 0 and g_ref < 0
    assert g_blade == pytest.approx(g_ref, rel=0.2)
