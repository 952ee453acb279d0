"""Flexible blades in the turbine template: DOF set, physics, outputs and initial conditions.

References
----------
- Uniform rotating cantilever, hub radius 0 (shared/guide/REFERENCE_NUMBERS.md, "Closed forms"):
  Southwell coefficients 1.193336 (1st flap), 6.478225 (2nd flap); edgewise: subtract 1 (spin
  softening); non-rotating frequency (βL)² sqrt(EI/(m L⁴)), βL = 1.875104, 4.694091. The blade's
  mode shapes are least-squares fits of the exact cantilever modes by ElastoDyn's polynomials
  (x², …, x⁶, summing to 1; max shape error 3e-6 for mode 1, 6e-4 for mode 2), on 100 of
  ElastoDyn's mid-point nodes. With one mode the model's ω² is exactly linear in Ω², its slope
  is the Rayleigh quotient of the centrifugal stiffness, so the differences are those of the
  fitted shape and the node sums: tolerance 1e-4 relative (1st mode), 2e-3 (2nd mode).
- ElastoDyn's tip components of the twisted NREL 5 MW shapes (docs/elastodyn_notes.md §1.6, §5:
  a unit F1 gives OoP 0.99103 / IP -0.12657, a unit E1 0.16750 / 0.98612 at zero pitch), +-5e-6.
- The engine's own kinematics of the deflected blade tip (independent of channels.py).
- ElastoDyn's state order (notes §7): ..., GeAz, DrTr, B1F1, B2F1, B3F1, B1E1, ..., B1F2, ...
- OpenFAST v5 blade_campbell linearization (shared/openfast/cases/blade_campbell): rotating-frame
  blade frequencies of the template's blades, 1e-4 relative (ElastoDyn's finite steps leave 1e-5).
"""

from __future__ import annotations

import dataclasses
import itertools
import warnings
from pathlib import Path

import numpy as np
import pytest

import mbsym as mb
from mbsym.wind import nrel5mw, read_openfast
from mbsym.wind.structure.elastodyn_bodies import blade_elastodyn_data
from mbsym.wind.structure.turbine import BLADE_FLAGS, MODELLED_DOFS, TurbineModel, blade_rotation, initial_blade_deflection

CASES = Path(__file__).resolve().parents[2].parent / "shared" / "openfast" / "cases"
BETA_L = (1.875104068711961, 4.694091132974174)


def _floating(t):
    """Platform data of the paper46 deck (the onshore tower on a spar), for the 22-DOF set."""
    return dataclasses.replace(t, platform_mass=7.5e6, platform_roll_inertia=4.2e9, platform_pitch_inertia=4.2e9,
                               platform_yaw_inertia=1.6e8, platform_cm=(0.0, 0.0, -90.0),
                               platform_reference=(0.0, 0.0, 20.0), tower_base_height=20.0)


def _inputs(eom, **values):
    return np.array([values.get(n, 0.0) for n in eom.inputs], dtype=float)


@pytest.fixture(scope="module")
def model22():
    return TurbineModel(_floating(nrel5mw()), dofs=list(MODELLED_DOFS))


# ---------------------------------------------------------------- DOF set and invariants
def test_22_dof_model_state_order(model22):
    blades = [f"B{k}{s}" for s in ("F1", "E1", "F2") for k in (1, 2, 3)]
    assert model22.eom.coordinates == ("Sg", "Sw", "Hv", "R", "P", "Y", "TFA1", "TSS1", "TFA2", "TSS2",
                                       "Yaw", "GeAz", "DrTr", *blades)
    assert model22.eom.n_q == 22


def test_22_dof_mass_matrix_spd_and_kinetic_energy_at_random_states(model22):
    """M symmetric (to the bit) and positive definite; T = ½ q̇ᵀ M q̇ (1e-10 relative)."""
    eom = model22.eom
    rng = np.random.default_rng(7)
    scale = np.array([2, 2, 1, 0.1, 0.1, 0.1, 1, 1, 0.2, 0.2, 0.3, 6.3, 0.05] + [3] * 3 + [1] * 3 + [0.5] * 3)
    for _ in range(5):
        q = scale * rng.uniform(-1, 1, eom.n_q)
        qd = scale * rng.uniform(-1, 1, eom.n_q)
        M = eom.mass_matrix(q)
        np.testing.assert_array_equal(M, M.T)
        np.linalg.cholesky(M)
        assert eom.kinetic_energy(q, qd) == pytest.approx(0.5 * qd @ M @ qd, rel=1e-10)


_GROUPS = ["TwFADOF1", "TwSSDOF1", "YawDOF", "GenDOF", "DrTrDOF", "PtfmPDOF"]


@pytest.mark.parametrize("dofs", [[b, g] for b, g in itertools.product(BLADE_FLAGS, _GROUPS)] + [list(BLADE_FLAGS)],
                         ids=lambda d: "+".join(d))
def test_blade_dof_combinations_rest_without_gravity(dofs):
    """Gravity off, zero displacements and speeds, rotor at rest: an equilibrium (accelerations 1e-12)."""
    model = TurbineModel(nrel5mw(), dofs=dofs)
    eom = model.eom
    u = _inputs(eom)                       # GeAz_d = 0 when the azimuth is prescribed
    xd = eom.rhs(np.zeros(eom.n_x), u, {"gravity": 0.0})
    np.testing.assert_allclose(xd, 0.0, atol=1e-12)


def test_rigid_blades_are_unchanged_by_the_flexible_option():
    """Without blade DOFs the blades stay rigid bodies with the flexible blades' mass (same M)."""
    t = nrel5mw()
    rigid = TurbineModel(t, dofs=["TwFADOF1", "GenDOF"]).eom
    flex = TurbineModel(t, dofs=["TwFADOF1", "GenDOF", "FlapDOF1"]).eom
    M_r, M_f = rigid.mass_matrix([0.0, 0.3]), flex.mass_matrix([0.0, 0.3, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(M_f[:2, :2], M_r, rtol=1e-12, atol=1e-12 * np.abs(M_r).max())


# ---------------------------------------------------------------- physics: uniform rotating beam
def _cantilever_fit(beta_l: float) -> np.ndarray:
    """ElastoDyn polynomial (x² … x⁶, coefficients summing to 1) closest to the exact cantilever mode."""
    x = np.linspace(0.0, 1.0, 2001)
    s = (np.cosh(beta_l) + np.cos(beta_l)) / (np.sinh(beta_l) + np.sin(beta_l))
    y = np.cosh(beta_l * x) - np.cos(beta_l * x) - s * (np.sinh(beta_l * x) - np.sin(beta_l * x))
    y = y / y[-1]
    X = np.vstack([x**k for k in range(2, 7)]).T
    c = np.linalg.lstsq(X[:, :4] - X[:, 4:], y - X[:, 4], rcond=None)[0]
    return np.append(c, 1.0 - c.sum())


def _uniform_rotor(L=50.0, m=20.0, EI=1.0e7, nodes=100):
    p = nrel5mw()
    c1, c2 = _cantilever_fit(BETA_L[0]), _cantilever_fit(BETA_L[1])
    blade = dataclasses.replace(p.blades[0], station_fraction=[0.0, 1.0], structural_twist=[0.0, 0.0],
                                mass_density=[m, m], flap_stiffness=[EI, EI], edge_stiffness=[EI, EI],
                                mass_factor=1.0, flap_stiffness_factor=1.0, edge_stiffness_factor=1.0,
                                flap_mode_shapes=[c1, c2], edge_mode_shapes=[c1], extra_columns={})
    return dataclasses.replace(p, blades=(blade,) * 3, n_blade_nodes=nodes, hub_radius=0.0, tip_radius=L,
                               precone=(0.0,) * 3, shaft_tilt=0.0, tip_mass=(0.0,) * 3), L, m, EI


def _omega2(eom, rotor_speed: float) -> float:
    lin = mb.linearize(eom, np.zeros(eom.n_q), np.zeros(eom.n_q), _inputs(eom, GeAz_d=rotor_speed),
                       {"gravity": 0.0})
    return lin.K[0, 0] / lin.M[0, 0]


@pytest.mark.parametrize("flag, mode, southwell, rtol", [
    ("FlapDOF1", 0, 1.193336, 1e-4),
    ("EdgeDOF", 0, 1.193336 - 1.0, 1e-4),
    ("FlapDOF2", 1, 6.478225, 2e-3),
])
def test_uniform_rotating_beam_southwell_coefficients(flag, mode, southwell, rtol):
    turbine, L, m, EI = _uniform_rotor()
    model = TurbineModel(turbine, dofs=[flag], prescribed_azimuth=True)
    eom = model.eom
    assert eom.coordinates[0] == f"B1{BLADE_FLAGS[flag]}"
    w0 = BETA_L[mode] ** 2 * np.sqrt(EI / (m * L**4))
    om = 0.6
    k0, k1 = _omega2(eom, 0.0), _omega2(eom, om)
    assert np.sqrt(k0) == pytest.approx(w0, rel=rtol)
    assert (k1 - k0) / om**2 == pytest.approx(southwell, rel=rtol)


def test_blade_campbell_rotating_frame_frequencies_in_the_template():
    """The template's three blades on a hub spinning through the prescribed azimuth: each blade's
    rotating-frame frequencies are OpenFAST's (blade_campbell.csv), 1e-4 relative."""
    deck = CASES / "blade_campbell" / "blade_campbell_rpm00.fst"
    if not deck.exists():
        pytest.skip("shared OpenFAST reference data not available")
    ref = np.loadtxt(deck.parent / "blade_campbell.csv", delimiter=",", skiprows=1)
    eom = TurbineModel(read_openfast(deck), prescribed_azimuth=True).eom
    for row in ref:
        u = _inputs(eom, GeAz=1.0, GeAz_d=row[0] * np.pi / 30)
        f, _ = mb.linearize(eom, np.zeros(eom.n_q), np.zeros(eom.n_q), u).frequencies()
        np.testing.assert_allclose(f.reshape(3, 3), np.repeat(row[1:4], 3).reshape(3, 3), rtol=1e-4)


def test_damping_from_the_deck_ratios():
    """Zero-rpm damping ratios of the blades are ElastoDyn's (blade_campbell.csv row 0, 1 %)."""
    deck = CASES / "blade_campbell" / "blade_campbell_rpm00.fst"
    if not deck.exists():
        pytest.skip("shared OpenFAST reference data not available")
    ref = np.loadtxt(deck.parent / "blade_campbell.csv", delimiter=",", skiprows=1)[0]
    eom = TurbineModel(read_openfast(deck)).eom
    _, z = mb.linearize(eom, np.zeros(eom.n_q)).frequencies()
    np.testing.assert_allclose(z.reshape(3, 3), np.repeat(ref[4:7], 3).reshape(3, 3), rtol=1e-2)


# ---------------------------------------------------------------- pitch
def test_pitch_input_equals_fixed_pitch():
    """Collective pitch as a prescribed input (value β) gives the model pitched at β in the deck:
    the same M and F (1e-9 relative) at a random state."""
    t = nrel5mw()
    beta = 0.25
    ic = dataclasses.replace(t.initial_conditions, blade_pitch=(beta,) * 3)
    dofs = ["TwFADOF1", "GenDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"]
    fixed = TurbineModel(dataclasses.replace(t, initial_conditions=ic), dofs=dofs).eom
    driven = TurbineModel(t, dofs=dofs, pitch_input=True)
    eom = driven.eom
    assert eom.prescribed == ("BlPitch",)
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-1, 1, eom.n_q), rng.uniform(-1, 1, eom.n_q)
    u = _inputs(eom, BlPitch=beta)
    np.testing.assert_allclose(eom.mass_matrix(q, u=u), fixed.mass_matrix(q), rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(eom.forcing(q, qd, u), fixed.forcing(q, qd, _inputs(fixed)), rtol=1e-9, atol=1e-6)
    F_rate = eom.forcing(q, qd, _inputs(eom, BlPitch=beta, BlPitch_d=0.5))
    assert not np.allclose(F_rate, eom.forcing(q, qd, u))      # a pitch rate loads the blades (Coriolis)
    assert driven.input_defaults()["BlPitch"](3.0) == 0.0       # the deck's pitch


def test_pitch_input_needs_one_deck_pitch():
    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, blade_pitch=(0.0, 0.1, 0.0))
    with pytest.raises(mb.ModelDefinitionError, match="collective pitch"):
        TurbineModel(dataclasses.replace(t, initial_conditions=ic), dofs=["FlapDOF1"], pitch_input=True)


# ---------------------------------------------------------------- outputs
def _channels(model, x, **u):
    ch = model.output_function()
    eom = model.eom
    y = np.array(ch.function(x, _inputs(eom, **u), eom.parameter_vector({}))).ravel()
    return dict(zip(ch.names, y)), dict(zip(ch.names, ch.units))


def test_tip_deflection_channels_match_elastodyn_tip_components():
    """Unit B1F1 and B2E1 at zero pitch: OoPDefl/IPDefl (= TipDxc/TipDyc) are ElastoDyn's twisted tip
    components (notes §1.6/§5); Q_B1F1 in m; other blades undeflected."""
    model = TurbineModel(nrel5mw(), dofs=["GenDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"])
    eom = model.eom
    x = np.zeros(eom.n_x)
    x[eom.coordinates.index("B1F1")] = 1.0
    x[eom.coordinates.index("B2E1")] = 1.0
    y, units = _channels(model, x)
    assert y["OoPDefl1"] == pytest.approx(0.99103, abs=5e-6) and y["IPDefl1"] == pytest.approx(-0.12657, abs=5e-6)
    assert y["OoPDefl2"] == pytest.approx(0.16750, abs=5e-6) and y["IPDefl2"] == pytest.approx(0.98612, abs=5e-6)
    assert y["TipDxc1"] == y["OoPDefl1"] and y["TipDyc2"] == y["IPDefl2"]
    assert y["OoPDefl3"] == y["IPDefl3"] == 0.0
    assert y["Q_B1F1"] == 1.0 and units["Q_B1F1"] == "m" and units["QD_B2E1"] == "m/s"
    assert units["OoPDefl1"] == "m" and units["BldPitch1"] == "deg"


def test_tip_deflection_channels_match_the_engine_kinematics():
    """With pitch 0.3 rad (input), precone and tilt, at a random blade deflection: OoPDefl/IPDefl equal
    the engine's deflected-tip displacement projected on the coned axes i1 = cos β j1 + sin β j2,
    i2 = -sin β j1 + cos β j2 (j = the blade body axes), 1e-12; TipDxb/TipDyb on j1, j2; TipDzc is
    ElastoDyn's -1/2 qᵀ AxRedBld(tip) q (notes §6) from blade_elastodyn_data, 1e-12 relative."""
    t = nrel5mw()
    beta = 0.3
    ic = dataclasses.replace(t.initial_conditions, blade_pitch=(beta,) * 3)
    model = TurbineModel(dataclasses.replace(t, initial_conditions=ic),
                         dofs=["TwFADOF1", "GenDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"])
    eom = model.eom
    rng = np.random.default_rng(11)
    q = rng.uniform(-2, 2, eom.n_q)
    y, _ = _channels(model, np.concatenate([q, np.zeros(eom.n_q)]))
    length = blade_elastodyn_data(t, 0).length
    p = eom.parameter_vector({})
    for k in (1, 2, 3):
        f = eom.point_kinematics(f"blade{k}", [0.0, 0.0, length])
        q0 = q.copy()
        q0[[eom.coordinates.index(f"B{k}{s}") for s in ("F1", "E1", "F2")]] = 0.0
        z = np.zeros(eom.n_q)
        u = np.zeros(eom.n_u)
        r, R = (np.array(v) for v in f(q, z, z, u, p)[:2])
        r0 = np.array(f(q0, z, z, u, p)[0])
        d = (r - r0).ravel()
        i1 = np.cos(beta) * R[:, 0] + np.sin(beta) * R[:, 1]
        i2 = -np.sin(beta) * R[:, 0] + np.cos(beta) * R[:, 1]
        assert y[f"OoPDefl{k}"] == pytest.approx(d @ i1, abs=1e-12)
        assert y[f"IPDefl{k}"] == pytest.approx(d @ i2, abs=1e-12)
        assert y[f"TipDxb{k}"] == pytest.approx(d @ R[:, 0], abs=1e-12)
        qb = q[[eom.coordinates.index(f"B{k}{s}") for s in ("F1", "F2", "E1")]]     # BLADE_DOFS order
        ax = blade_elastodyn_data(t, k - 1).tip_axial_reduction                      # notes §1.7, §6
        assert y[f"TipDzc{k}"] == pytest.approx(-0.5 * qb @ ax @ qb, rel=1e-12)
        assert y[f"BldPitch{k}"] == pytest.approx(np.rad2deg(beta), rel=1e-14)


def test_blade_data_computed_once_per_blade(monkeypatch):
    """TurbineModel computes ElastoDyn's blade data once per blade and the output channels reuse the
    bodies' shape integrals (no recomputation of blade or tower data in channels.py)."""
    import mbsym.wind.structure.turbine as turbine_module

    calls = []
    original = turbine_module.blade_elastodyn_data
    monkeypatch.setattr(turbine_module, "blade_elastodyn_data",
                        lambda t, k, **kw: calls.append(k) or original(t, k, **kw))
    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, blade_oop_tip_deflection=1.0)
    model = TurbineModel(dataclasses.replace(t, initial_conditions=ic),
                         dofs=["TwFADOF1", "GenDOF", "FlapDOF1", "EdgeDOF"])
    model.initial_state()
    model.output_function()
    rigid = TurbineModel(t, dofs=["TwFADOF1", "GenDOF"])
    assert sorted(calls) == [0, 0, 1, 1, 2, 2]          # 3 flexible + 3 rigid blades, once each
    assert model.blade_data(1) is model.blade_data(1)
    import mbsym.wind.structure.channels as channels_module
    assert not hasattr(channels_module, "blade_elastodyn_data") and not hasattr(channels_module, "tower_elastodyn_data")
    assert rigid.eom.n_q == 2


def test_blade_frame_is_elastodyn_j_frame():
    """blade_rotation: blade 1 of a rotor at azimuth 0 points up (j3 = +z at q_GeAz = 3π/2), i2
    against the rotation; pitch turns j1 toward -i2 (notes §4)."""
    R = blade_rotation(0.0, 0.0, 0.2)
    np.testing.assert_allclose(R[:, 2], [0, -1, 0], atol=1e-15)             # j3 = g3 = -y at q_GeAz = 0
    np.testing.assert_allclose(R[:, 0], [np.cos(0.2), 0, -np.sin(0.2)], atol=1e-15)   # cos i1 - sin i2, i2 = z
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)


# ---------------------------------------------------------------- initial conditions
def _deck_with_tip(oop, ip, pitch):
    t = nrel5mw()
    ic = dataclasses.replace(t.initial_conditions, blade_oop_tip_deflection=oop, blade_ip_tip_deflection=ip,
                             blade_pitch=(pitch,) * 3)
    return dataclasses.replace(t, initial_conditions=ic)


def test_initial_tip_deflections_from_oopdefl_ipdefl():
    """ElastoDyn's rule (notes §5): F1 and E1 solve the coned-frame 2x2 system, F2 = 0; the outputs at
    t = 0 give back OoPDefl/IPDefl on every blade (1e-12)."""
    model = TurbineModel(_deck_with_tip(1.5, -0.4, 0.1), dofs=["GenDOF", "FlapDOF1", "EdgeDOF", "FlapDOF2"])
    x0 = model.initial_state()
    names = model.eom.coordinates
    y, _ = _channels(model, x0)
    for k in (1, 2, 3):
        assert y[f"OoPDefl{k}"] == pytest.approx(1.5, abs=1e-12)
        assert y[f"IPDefl{k}"] == pytest.approx(-0.4, abs=1e-12)
        assert x0[names.index(f"B{k}F2")] == 0.0
    assert np.all(x0[model.eom.n_q:][1:] == 0.0)           # blade rates zero


def test_initial_deflection_edge_off_warns_and_fits_flap_alone():
    """FlapDOF1 without EdgeDOF: ElastoDyn would freeze a nonzero edge mode; we fit F1 by least squares
    and say so. Without a flap DOF the edge mode is fitted by least squares."""
    ut = blade_elastodyn_data(nrel5mw(), 0).tip_displacement
    with pytest.warns(UserWarning, match="freeze the disabled edge mode"):
        v = initial_blade_deflection(ut, 0.0, [1.0, 0.0], {"FlapDOF1": True})
    a = ut[0]
    assert v["FlapDOF1"] == pytest.approx(a[0] / (a @ a), rel=1e-12) and v["EdgeDOF"] == 0.0
    e = initial_blade_deflection(ut, 0.0, [0.0, 2.0], {"EdgeDOF": True})
    assert e["EdgeDOF"] == pytest.approx(2.0 * ut[2, 1] / (ut[2] @ ut[2]), rel=1e-12)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        both = initial_blade_deflection(ut, 0.2, [1.0, 0.5], {"FlapDOF2": True, "EdgeDOF": True})
    assert both["FlapDOF1"] == 0.0 and both["FlapDOF2"] != 0.0


def test_unknown_blade_request_errors():
    with pytest.raises(mb.ModelDefinitionError, match=r"\['PitchDOF'\] are not modelled by this template yet"):
        TurbineModel(nrel5mw(), dofs=["PitchDOF"])
