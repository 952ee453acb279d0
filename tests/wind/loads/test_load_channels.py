"""Load channels from locked joints (mbsym.wind.structure.load_cuts): root forces, shaft forces, yaw-bearing loads.

References
----------
- OpenFAST v5.0.0 ElastoDyn's own channels (``data/ed_loads_*.csv``, made by ``ed_loads_reference.py``: the NREL 5 MW
  with all 16 onshore DOFs, deflected, spinning at 12 rpm, pitched 8°, yawed 6°, a 20 t yaw-bearing mass; yaw DOF
  free and fixed): mbsym's channels evaluated at OpenFAST's states (``Q_*``, ``QD_*``) must equal OpenFAST's
  ``RootF*c/b``, ``RootM*c/b``, ``LSShftF*``, ``YawBrF*p``, ``YawBrM*p``, ``TwrBsM*t``. The states are stored to 12
  digits and the accelerations of the two codes agree to ~1e-5 relative (test_openfast_large_motion.py), so the
  tolerance is 1e-5 of the largest magnitude of each channel (observed ≤ 4e-7).
- OpenFAST v5.0.0 with quasi-steady AeroDyn 15 (``data/ad_loads_ss14.csv``, made by ``ad_loads_reference.py``: the
  shared ``ss14_shear_flex`` deck, DBEMT off and no ServoDyn so that OpenFAST's states determine the loads): the
  blade-element model's channels at OpenFAST's states within 2 % of each channel's magnitude (two BEM codes),
  ``RootMzc`` within 3 kN m (it needs AeroDyn's aerodynamic-centre offsets as lever arms).
- Closed forms: a rotor at rest under gravity (root forces = blade weight, shaft force = rotor weight, yaw-bearing
  force and moment = the weight of nacelle and rotor and its moment about the tower top).
- Newton's law on the parts between cuts at random moving states with random applied loads (two independent
  locked reactions and the point kinematics): shaft force = Σ root forces + the hub's weight and inertia force +
  the thrust input; yaw-bearing force = shaft force + the nacelle's weight and inertia force.
- The blade-element operating turbine: with rigid blades on a fixed tower the rotor's centre of mass does not
  accelerate, so the shaft force is the aerodynamic force of the BEM nodes (``RtAeroF*h``) plus the rotor weight.
The identities are exact: tolerance 1e-9 relative (round-off of sums of 10^5–10^6 N terms).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np
import pytest

from mbsym.exceptions import ModelDefinitionError
from mbsym.wind import nrel5mw
from mbsym.wind.structure.elastodyn_nodes import rotor_mass_properties
from mbsym.wind.structure.load_cuts import reaction_rows
from mbsym.wind.structure.turbine import TurbineModel

sys.path.insert(0, str(Path(__file__).resolve().parent))
import ed_loads_reference as ref  # noqa: E402

ALL_CUTS = dict(pitch_input=True, tower_base_reactions=True, blade_root_reactions=True, blade_root_forces=True,
                shaft_reactions=True, yaw_bearing_reactions=True)


def _inputs(model, **values) -> np.ndarray:
    d = {**model.input_defaults(), **values}
    return np.array([d[n](0.0) if callable(d[n]) else d[n] for n in model.eom.inputs], dtype=float)


def _channels(model, q, qd, u, pitch) -> dict[str, float]:
    """Load channels [kN, kN m] at (q, qd, u) with the model's accelerations."""
    eom = model.eom
    p = eom.parameter_vector({})
    qdd = np.asarray(eom.functions.rhs(np.r_[q, qd], u, p)).ravel()[eom.n_q:]
    lam = np.asarray(eom.functions.reactions(q, qd, qdd, u, p)).ravel()
    return {n: float(v) for n, _, v in reaction_rows(eom.locked, lam, pitch)}, qdd


@pytest.mark.parametrize("case", list(ref.CASES))
def test_load_channels_equal_elastodyn_at_its_states(case):
    if not (ref.BASE / ref.ED).is_file():
        pytest.skip(f"shared OpenFAST base deck not found at {ref.BASE}")
    from mbsym.wind import read_openfast

    with tempfile.TemporaryDirectory() as tmp:
        turbine = read_openfast(ref.write_deck(Path(tmp), case))
    model = TurbineModel(turbine, **ALL_CUTS)
    data = ref.read_reference(case)
    coords = model.eom.coordinates
    sign = np.array([-1.0 if c.startswith("TSS") else 1.0 for c in coords])      # ElastoDyn's Q_TSS = -ours
    u = _inputs(model)
    ours = []
    for i in range(data["Time"].size):
        q = sign * np.array([data[f"Q_{c}"][i] for c in coords])
        qd = sign * np.array([data[f"QD_{c}"][i] for c in coords])
        ours.append(_channels(model, q, qd, u, [np.deg2rad(data["BldPitch1"][i])] * 3)[0])
    checked = 0
    for name in ref.LOAD_CHANNELS:
        key = "LSShftFxa" if name == "RotThrust" else name          # ElastoDyn's RotThrust is LSShftFxa
        got = np.array([row[key] for row in ours])
        want = data[name]
        scale = max(np.abs(want).max(), 1.0)                           # kN or kN m
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-5 * scale, err_msg=name)
        checked += 1
    assert checked == len(ref.LOAD_CHANNELS) == 42
    if case == "ed_loads_fixed_yaw":                                    # the bearing carries a yaw moment
        assert np.abs(data["YawBrMzp"]).max() > 10.0


@pytest.fixture(scope="module")
def gravity_model():
    return TurbineModel(nrel5mw(), ("GenDOF",), **ALL_CUTS)


def test_rotor_at_rest_carries_its_weight(gravity_model):
    """Static closed forms: every cut carries the weight outboard of it, and its moment about the cut point."""
    model = gravity_model
    eom = model.eom
    u, p = _inputs(model, BlPitch=0.0), eom.parameter_vector({})
    z = np.zeros(eom.n_q)
    lam = np.asarray(eom.functions.reactions(z, z, z, u, p)).ravel()
    y = {n: 1e3 * float(v) for n, _, v in reaction_rows(eom.locked, lam, [0.0] * 3)}
    defaults = dict(eom.defaults)
    g = np.array([0.0, 0.0, -defaults["gravity"]])

    def kin(body, point=(0.0, 0.0, 0.0)):
        r, R = (np.asarray(v) for v in eom.point_kinematics(body, point)(z, z, z, u, p)[:2])
        return r.ravel(), R

    weights = []                                   # (mass, centre of mass) of every part outboard of the bearing
    for k in range(3):
        data = model.blade_data(k)
        m = np.append(data.element_mass, data.tip_mass)
        zc = float(m @ np.append(data.span, data.length)) / m.sum()
        r, R = kin(f"blade{k + 1}", (0.0, 0.0, zc))
        force = m.sum() * g                        # static: the blade's force on the hub is its weight
        np.testing.assert_allclose([y[f"RootF{a}c{k + 1}"] for a in "xyz"], R.T @ force, rtol=1e-9, atol=1e-6)
        weights.append((m.sum(), r))
    rotor = defaults["hub_mass"] + sum(w[0] for w in weights)
    assert rotor == pytest.approx(defaults["hub_mass"] + sum(rotor_mass_properties(model.turbine).blade_mass))
    _, R_shaft = kin("shaft")
    np.testing.assert_allclose([y[n] for n in ("LSShftFxa", "LSShftFys", "LSShftFzs")], R_shaft.T @ (rotor * g),
                               rtol=1e-9)
    t = model.turbine
    weights.append((defaults["hub_mass"], kin("hub", (t.hub_cm, 0.0, 0.0))[0]))
    weights.append((defaults["nacelle_mass"], kin("nacelle", t.nacelle_cm)[0]))
    top, R_top = kin("yaw_bearing")
    force = sum(m for m, _ in weights) * g
    moment = sum(np.cross(r - top, m * g) for m, r in weights)
    np.testing.assert_allclose([y[f"YawBrF{a}p"] for a in "xyz"], R_top.T @ force, rtol=1e-9)
    np.testing.assert_allclose([y[f"YawBrM{a}p"] for a in "xyz"], R_top.T @ moment, rtol=1e-9,
                               atol=1e-9 * np.abs(moment).max())
    assert y["YawBrMyp"] < 0.0                     # the overhanging rotor tips the nacelle upwind (ElastoDyn's sign)


@pytest.fixture(scope="module")
def moving_model():
    dofs = ("TwFADOF1", "TwSSDOF1", "YawDOF", "GenDOF", "DrTrDOF", "FlapDOF1", "EdgeDOF")
    return TurbineModel(nrel5mw(), dofs, blade_loads=True, **ALL_CUTS)


def test_newton_between_the_cuts_at_random_states(moving_model):
    """Shaft force = Σ root forces + hub (m g − m a) + thrust; bearing force = shaft force + nacelle (m g − m a)."""
    model = moving_model
    eom = model.eom
    t = model.turbine
    rng = np.random.default_rng(19)
    p = eom.parameter_vector({})
    defaults = dict(eom.defaults)
    g = np.array([0.0, 0.0, -defaults["gravity"]])
    for _ in range(3):
        q, qd = rng.normal(scale=0.3, size=eom.n_q), rng.normal(scale=0.5, size=eom.n_q)
        values = {n: rng.normal(scale=2e5) for n in eom.inputs if "Aero" in n or n in ("RotThrust", "RotTorq")}
        values.update(GenTq=4e4, BlPitch=0.2, BlPitch_d=0.1, BlPitch_dd=-0.3)
        u = _inputs(model, **values)
        y, qdd = _channels(model, q, qd, u, [0.2] * 3)
        y = {n: 1e3 * v for n, v in y.items()}

        def kin(body, point=(0.0, 0.0, 0.0)):
            out = eom.point_kinematics(body, point)(q, qd, qdd, u, p)
            return np.asarray(out[1]), np.asarray(out[4]).ravel()             # R, acceleration

        R_shaft, _ = kin("shaft")
        shaft = R_shaft @ [y["LSShftFxa"], y["LSShftFys"], y["LSShftFzs"]]
        roots = sum(kin(f"pitch{k}")[0] @ np.array([y[f"RootF{a}b{k}"] for a in "xy"] + [y[f"RootFzc{k}"]])
                    for k in (1, 2, 3))
        _, a_hub = kin("hub", (t.hub_cm, 0.0, 0.0))
        expected = roots + defaults["hub_mass"] * (g - a_hub) + values["RotThrust"] * R_shaft[:, 0]
        np.testing.assert_allclose(shaft, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        R_top, _ = kin("yaw_bearing")
        _, a_nac = kin("nacelle", t.nacelle_cm)
        bearing = R_top @ [y[f"YawBrF{a}p"] for a in "xyz"]
        expected = shaft + defaults["nacelle_mass"] * (g - a_nac)
        np.testing.assert_allclose(bearing, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())


def test_cuts_leave_the_equations_unchanged(moving_model):
    """Locked joints add reactions, not dynamics: the same accelerations as the model without cuts."""
    plain = TurbineModel(nrel5mw(), [f for f, on in moving_model.dofs.items() if on], pitch_input=True,
                         blade_loads=True)
    rng = np.random.default_rng(7)
    x = rng.normal(scale=0.3, size=plain.eom.n_x)
    values = {n: rng.normal(scale=2e5) for n in plain.eom.inputs if "Aero" in n}
    a = plain.eom.functions.rhs(x, _inputs(plain, **values), plain.eom.parameter_vector({}))
    b = moving_model.eom.functions.rhs(x, _inputs(moving_model, **values), moving_model.eom.parameter_vector({}))
    np.testing.assert_allclose(np.asarray(b), np.asarray(a), rtol=1e-10, atol=1e-10)


def test_root_forces_need_the_pitch_input():
    with pytest.raises(ModelDefinitionError, match="blade_root_forces=True needs pitch_input=True"):
        TurbineModel(nrel5mw(), ("GenDOF",), blade_root_forces=True)


def test_operating_turbine_refuses_a_non_boolean_switch():
    from mbsym.wind.operation import OperatingTurbine

    with pytest.raises(TypeError, match="load_channels must be True or False"):
        OperatingTurbine(nrel5mw(), load_channels="yes")


def test_blade_rung_shaft_force_is_the_aerodynamic_force_plus_the_rotor_weight():
    """Blade-element rotor (ss14 deck: 14 m/s, shear 0.2), rigid blades, GenDOF only: the rotor's centre of mass is on
    the fixed shaft axis, so LSShftF = R_shaftᵀ (R_hub RtAeroF·h + m_rotor g) and YawBrF adds the nacelle weight."""
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
    from _op_data import INPUTS, need

    import casadi as ca

    from mbsym.wind.operation.blade_channels import aerodyn_hub_axes
    from mbsym.wind.operation.deck import operating_deck

    model = operating_deck(need(INPUTS / "ss14_shear_flex" / "ss14_shear_flex.fst")).model(
        aero="blade", dofs=["GenDOF"], load_channels=True)
    d = model.dynamics()
    x, u = np.asarray(d.x0, dtype=float), np.asarray(d.u0, dtype=float)
    x[d.states.index("GeAz")] = 0.7                       # blades off the symmetric positions
    p = np.array([d.defaults[n] for n in d.parameters])
    y = dict(zip(d.output_names, np.asarray(d.outputs(x, u, p)).ravel()))
    eom = model.structure.eom
    qs, zs = x[:eom.n_q], np.zeros(eom.n_q)
    us = np.zeros(len(eom.inputs))
    R_hub = np.asarray(eom.point_kinematics("hub")(qs, zs, zs, us, eom.parameter_vector({}))[1])
    R_shaft = np.asarray(eom.point_kinematics("shaft")(qs, zs, zs, us, eom.parameter_vector({}))[1])
    defaults = dict(eom.defaults)
    g = np.array([0.0, 0.0, -defaults["gravity"]])
    rotor = defaults["hub_mass"] + sum(rotor_mass_properties(model.turbine).blade_mass)
    aero = np.asarray(aerodyn_hub_axes(ca.DM(R_hub))) @ [y["RtAeroFxh"], y["RtAeroFyh"], y["RtAeroFzh"]]
    assert np.linalg.norm(aero) > 3e5                     # the wind loads the rotor (N)
    shaft = R_shaft.T @ (aero + rotor * g) / 1e3
    np.testing.assert_allclose([y["LSShftFxa"], y["LSShftFys"], y["LSShftFzs"]], shaft, rtol=1e-9,
                               atol=1e-9 * np.abs(shaft).max())
    bearing = (aero + (rotor + defaults["nacelle_mass"]) * g) / 1e3      # rigid tower, no yaw: tower-top = ground axes
    np.testing.assert_allclose([y[f"YawBrF{a}p"] for a in "xyz"], bearing, rtol=1e-9, atol=1e-9 * np.abs(bearing).max())
    assert {f"RootF{a}c{k}" for a in "xyz" for k in (1, 2, 3)} <= set(y)


def test_rotor_rung_bearing_force_balances_the_shaft_force_and_the_nacelle():
    """Rotor-effective rung (built-in NREL 5 MW, TwFA1, TwSS1, GenDOF) at random moving states: YawBrF = LSShftF +
    nacelle (m g − m a) exactly, and LSShftFxa equals the Newton–Euler axial force of the model without the shaft
    joints (thrust + m_rotor (g − a_apex)·c₁) up to the acceleration of the rotor's centre of mass relative to the
    apex (coning puts it ~1 m along the shaft; with the tower top turning at these speeds m_rotor ω² d < 1e-3 of
    the thrust). With the joints, ``RotThrust`` is ``LSShftFxa`` (ElastoDyn's alias)."""
    from mbsym.wind.operation import OperatingTurbine

    model = OperatingTurbine.nrel5mw(load_channels=True)
    d = model.dynamics()
    plain = OperatingTurbine.nrel5mw().dynamics()
    assert plain.states == d.states and plain.inputs == d.inputs and plain.parameters == d.parameters
    eom = model.structure.eom
    n = eom.n_q
    p = np.array([d.defaults[name] for name in d.parameters])
    ps = eom.parameter_vector({})
    defaults = dict(eom.defaults)
    g = np.array([0.0, 0.0, -defaults["gravity"]])
    rng = np.random.default_rng(5)
    for _ in range(3):
        x = np.asarray(d.x0, dtype=float).copy()
        x[:n] += rng.normal(scale=0.3, size=n)
        x[n:2 * n] += rng.normal(scale=0.5, size=n)
        u = np.array([14.0, 0.15, 3e4])
        y = dict(zip(d.output_names, 1e3 * np.asarray(d.outputs(x, u, p)).ravel()))
        y_plain = dict(zip(plain.output_names, 1e3 * np.asarray(plain.outputs(x, u, p)).ravel()))
        np.testing.assert_allclose(np.asarray(d.rhs(x, u, p)), np.asarray(plain.rhs(x, u, p)), rtol=1e-12, atol=1e-12)
        qdd = np.asarray(d.rhs(x, u, p)).ravel()[n:2 * n]
        us = np.zeros(len(eom.inputs))

        def kin(body, point=(0.0, 0.0, 0.0)):
            out = eom.point_kinematics(body, point)(x[:n], x[n:2 * n], qdd, us, ps)
            return np.asarray(out[1]), np.asarray(out[4]).ravel()

        R_shaft, _ = kin("shaft")
        R_top, _ = kin("yaw_bearing")
        _, a_nac = kin("nacelle", model.turbine.nacelle_cm)
        expected = R_shaft @ [y["LSShftFxa"], y["LSShftFys"], y["LSShftFzs"]] + defaults["nacelle_mass"] * (g - a_nac)
        np.testing.assert_allclose(R_top @ [y[f"YawBrF{a}p"] for a in "xyz"], expected, rtol=1e-9,
                                   atol=1e-9 * np.abs(expected).max())
        assert y["RotThrust"] == pytest.approx(y["LSShftFxa"], rel=1e-12)
        assert y["LSShftFxa"] == pytest.approx(y_plain["RotThrust"], rel=1e-3)


@pytest.fixture(scope="module")
def aerodyn_case():
    """The blade-element model of ``ad_loads_reference``'s deck and OpenFAST's rows (quasi-steady AeroDyn)."""
    import ad_loads_reference as ad

    if not (ad.INPUTS / ad.CASE).is_dir():
        pytest.skip(f"shared OpenFAST aero cases not found at {ad.INPUTS}")
    from mbsym.wind.operation.deck import operating_deck

    with tempfile.TemporaryDirectory() as tmp:
        deck = operating_deck(ad.write_deck(Path(tmp)))
        model = deck.model(aero="blade", load_channels=True)
        d = model.dynamics()
    data = ref.read_reference(ad.NAME)
    eom = model.structure.eom
    n = eom.n_q
    p = np.array([d.defaults[k] for k in d.parameters])
    rows = []
    for i in range(1, data["Time"].size):            # t = 0: AeroDyn's inputs are not yet those of the state
        x = np.asarray(d.x0, dtype=float).copy()
        for j, c in enumerate(eom.coordinates):
            s = -1.0 if c.startswith("TSS") else 1.0
            x[j], x[n + j] = s * data[f"Q_{c}"][i], s * data[f"QD_{c}"][i]
        x[d.states.index("BlPitch")] = np.deg2rad(data["BldPitch1"][i])
        x[d.states.index("BlPitch_d")] = x[d.states.index("GenTq")] = 0.0      # no ServoDyn: fixed pitch, no torque
        u = np.asarray(d.u0, dtype=float).copy()                                # the deck's steady sheared wind
        u[d.inputs.index("BlPitchCom")], u[d.inputs.index("GenTqCom")] = x[d.states.index("BlPitch")], 0.0
        rows.append(dict(zip(d.output_names, np.asarray(d.outputs(x, u, p)).ravel())))
    return ad, rows, {k: v[1:] for k, v in data.items()}


def test_blade_rung_load_channels_equal_openfast_with_aerodyn_at_its_states(aerodyn_case):
    """OpenFAST v5 + quasi-steady AeroDyn 15 (``data/ad_loads_ss14.csv``, sheared 14 m/s, flexible blades and tower,
    12 rows over 3 s) against the blade-element model at OpenFAST's states: every root force and moment, shaft force,
    yaw-bearing and tower-base load within 2 % of the channel's largest magnitude. The aerodynamic loads are not the
    same code (our BEM solves with a fixed number of Newton steps on C² polars at AeroDyn's nodes); the shared
    ss14 runs give the scale: RootMyc1 means within 0.3 %, 1P amplitudes within 0.8 % (benchmarks/README.md).
    Observed here: ≤ 0.8 % (root and shaft forces), ≤ 0.9 % (YawBrMzp)."""
    ad, rows, data = aerodyn_case
    checked = 0
    for name in ad.LOAD_CHANNELS:
        if name.startswith("RootMzc"):
            continue                                # its own tolerance below
        got = np.array([r[name] for r in rows])
        want = data[name]
        np.testing.assert_allclose(got, want, rtol=0, atol=0.02 * np.abs(want).max(), err_msg=name)
        checked += 1
    assert checked == len(ad.LOAD_CHANNELS) - 3


def test_blade_rung_root_pitching_moment_equals_openfast_with_aerodyn(aerodyn_case):
    """RootMzc is a small difference of large terms: the airfoils' pitching moment (UseBlCm True − False in OpenFAST:
    −89 … −102 kN m) and the lever arms of the aerodynamic forces on the deflected blade and at the aerodynamic
    centres (AeroDyn's BlSwpAC, up to 0.6 m from the pitch axis: without them ours was 46–66 kN m off, growing with
    the flap force). Tolerance 3 kN m (3 % of the pitching part); observed ≤ 1.2 kN m."""
    _, rows, data = aerodyn_case
    for k in (1, 2, 3):
        got = np.array([r[f"RootMzc{k}"] for r in rows])
        np.testing.assert_allclose(got, data[f"RootMzc{k}"], rtol=0, atol=3.0, err_msg=f"RootMzc{k}")
