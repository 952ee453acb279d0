"""The bottom-fixed SubDyn substructure on the platform DOFs (mbsym.wind.offshore.bottom_fixed).

References:
- OpenFAST v5.0.0 (ElastoDyn + SubDyn, the rosco 2.10.6 wheel's IEA 15 MW monopile deck in air: CompHydro =
  CompSeaSt = CompAero = CompServo = CompInflow = 0, initial TTDspFA 1 m and TTDspSS 0.5 m, 60 s;
  tests/data/openfast_subdyn_coupled/README.md): its base reactions ``ReactF*ss``/``ReactM*ss`` as functions of the
  recorded TP motion (no simulation needed), and, slow, the coupled decay itself;
- statics: a Guyan shape carries loads only at the TP and at the base, so the base reaction per unit TP
  displacement is ``−T K_BB`` (the TP's stiffness load carried to the base point); at rest the base carries the
  substructure's weight less the TP's share;
- the load's slope at rest by finite differences against ``−(K_BB − G)``.
"""

from __future__ import annotations

import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from mbsym.exceptions import UnsupportedFeatureError
from mbsym.wind.deck.subdyn import read_subdyn
from mbsym.wind.offshore.bottom_fixed import BottomFixedPlatform, _base_reaction, bottom_fixed_platform
from mbsym.wind.offshore.substructure import Substructure

DATA = Path(__file__).resolve().parents[2] / "data"
TP = (0.0, 0.0, 15.0)          # ElastoDyn's PtfmRefzt of the deck: SubDyn's TP reference point


def _platform(name: str = "monopile", water_depth: float = 0.0) -> BottomFixedPlatform:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sub = Substructure(read_subdyn(DATA / "openfast_subdyn" / f"{name}.dat"), reference_point=TP, gravity=9.81,
                           water_depth=water_depth)
        R, r0, R_m = _base_reaction(sub)
        return BottomFixedPlatform(sub.reduce(), R, r0, source=name, modal_reaction=R_m)


def _cross(v):
    x, y, z = v
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


@pytest.fixture(scope="module")
def platform():
    return _platform()


def test_base_reactions_of_recorded_motion_are_openfasts(platform):
    """SubDyn's ReactF*ss/ReactM*ss (about (0, 0, -WtrDpth), WtrDpth = 0 without HydroDyn as OpenFAST's glue code
    sets it) from the TP motion OpenFAST recorded: within 5e-4 of each channel's range (measured 2.0e-4 on FX,
    1.1e-4 on MY, 3e-8 on MZ; the recorded motion has 7 significant digits, SubDyn's yaw is ElastoDyn's to second
    order in roll and pitch)."""
    data = np.genfromtxt(DATA / "openfast_subdyn_coupled" / "mono_decay.csv", delimiter=",", names=True)
    u = np.column_stack([data["PtfmSurge"], data["PtfmSway"], data["PtfmHeave"],
                         *(np.radians(data[k]) for k in ("PtfmRoll", "PtfmPitch", "PtfmYaw"))])
    ours = np.array([np.array(platform.loads(ui, np.zeros(6))["react"]).ravel() for ui in u])
    for k, c in enumerate(("FX", "FY", "FZ", "MX", "MY", "MZ")):
        theirs = -data[f"minus_React{c}ss"]
        scale = max(np.ptp(theirs), 1e-3 * np.abs(theirs).max())
        assert np.abs(ours[:, k] - theirs).max() <= 5e-4 * scale, c
    assert np.ptp(data["minus_ReactMYss"]) > 1e8          # the TP moves: 0.1-0.5 GN m of base moment swing


def test_base_reaction_is_the_statics_of_a_guyan_shape(platform):
    """Per unit TP displacement the base point (here the origin) reacts ``−T K_BB`` (rel. 1e-6); at rest the base
    carries the weight the TP does not, R_z(0) = W + Y1_z(0), of which SubDyn's ReactFZss leaves out the reaction
    joint's own weight (its elements' forces only)."""
    move = np.eye(6)
    move[3:, :3] = _cross(np.array(TP))
    K = np.asarray(platform.reduced.stiffness)
    assert np.allclose(platform.reaction, -move @ K, rtol=0, atol=1e-6 * np.abs(K).max())
    weight = -np.asarray(platform.reduced.frame.gravity_load).reshape(-1, 6)[:, 2].sum()
    y1 = np.array(platform.loads(np.zeros(6), np.zeros(6))["load"]).ravel()
    assert y1[2] == pytest.approx(platform.reduced.gravity_load[2], rel=1e-12) and y1[2] < 0.0
    frame = platform.reduced.frame
    own = np.asarray(frame.gravity_load)[6 * frame.reaction_nodes[0] + 2]             # < 0: the joint's weight
    assert platform.reaction_static[2] == pytest.approx(weight + y1[2] + own, rel=1e-9) and own < 0
    assert weight == pytest.approx(9.81 * (platform.reduced.frame.steel_mass() + 1e5), rel=1e-9)   # + the CMass


def test_load_slope_at_rest_is_minus_the_stiffness(platform):
    """Central differences of Y1 about rest (h = 1e-6 m, rad) against ``−(K_BB − G)``: rel. 1e-6."""
    h, cols = 1e-6, []
    for j in range(6):
        e = np.zeros(6)
        e[j] = h
        up = np.array(platform.loads(e, np.zeros(6))["load"]).ravel()
        down = np.array(platform.loads(-e, np.zeros(6))["load"]).ravel()
        cols.append((up - down) / (2 * h))
    slope = np.column_stack(cols)
    assert np.allclose(slope, -platform.stiffness, rtol=0, atol=1e-6 * np.abs(platform.stiffness).max())
    ud = np.array([0.1, 0.0, 0.0, 0.0, 0.0, 0.0])             # no Guyan damping in the deck (GuyanDampMod 0)
    assert np.allclose(np.array(platform.loads(np.zeros(6), ud)["load"]).ravel(),
                       np.array(platform.loads(np.zeros(6), np.zeros(6))["load"]).ravel())


def test_channels_and_mass(platform):
    import casadi as ca

    loads = platform.loads(ca.DM.zeros(6), ca.DM.zeros(6))
    rows = platform.channel_rows(loads, ca.DM([0.0, 0.0, 0.0, 0.0, 0.01, 0.0]))
    names = [r[0] for r in rows]
    assert names[:6] == ["Intf1FXss", "Intf1FYss", "Intf1FZss", "Intf1MXss", "Intf1MYss", "Intf1MZss"]
    intf = np.array([float(r[2]) for r in rows[:6]])
    expected = -(np.array(loads["load"]).ravel() - np.asarray(platform.added_mass) @ [0, 0, 0, 0, 0.01, 0])
    assert np.allclose(intf, expected)
    assert np.allclose(platform.added_mass, platform.added_mass.T) and platform.state_names == ()
    assert not platform.floating and platform.for_prediction() is platform


def test_craig_bampton_modes_and_refusals():
    """With CB modes: their coordinates and rates become states, ``M_Bm M_mB`` leaves the TP's mass (the Schur
    complement of the coupled mass matrix, still positive definite), and at rest the modal equation is SubDyn's:
    q̈ = Φ_mᵀ F_g − M_mB ü (SubDyn starts the modes at 0)."""
    cb = _platform("monopile_cb")
    assert cb.state_names[:2] == ("SSqm01", "SSqm02") and len(cb.state_names) == 2 * cb.n_modes == 8
    coupling = np.asarray(cb.reduced.mass_coupling)
    assert np.allclose(cb.added_mass, np.asarray(cb.reduced.mass) - coupling @ coupling.T)
    assert np.all(np.linalg.eigvalsh(0.5 * (cb.added_mass + cb.added_mass.T)) > 0)
    out = cb.loads(np.zeros(6), np.zeros(6))
    assert np.allclose(np.array(out["xr_dot"]).ravel()[4:], cb.reduced.modal_gravity_load)
    assert np.allclose(np.array(out["xr_acc"])[4:], -coupling.T)
    from mbsym.linear.state_modes import StateMode
    from mbsym.wind.analysis.trim_linear import mode_label

    assert mode_label(StateMode(25.4, 0.01, 160.0, -1.6 + 160.0j, "SSqmd03")) == "substructure mode 3 (SSqmd03)"
    sim = SimpleNamespace(substructure_model=1, hydrodynamics_model=0, mooring_model=3, gravity=9.81, water_depth=30.0)
    deck = SimpleNamespace(simulation=sim, source_files={"fst": "x.fst", "subdyn": str(DATA / "openfast_subdyn" /
                                                                                       "monopile.dat")},
                           platform_reference=TP)
    with pytest.raises(UnsupportedFeatureError, match="CompMooring = 3 with CompSub = 1"):
        bottom_fixed_platform(deck)
    deck.simulation = SimpleNamespace(**{**vars(sim), "hydrodynamics_model": 1, "mooring_model": 0})
    with pytest.raises(UnsupportedFeatureError, match=r"CompHydro = 1 \(HydroDyn\) needs its input file"):
        bottom_fixed_platform(deck)
    deck.simulation = SimpleNamespace(**{**vars(sim), "substructure_model": 2, "hydrodynamics_model": 0})
    with pytest.raises(UnsupportedFeatureError, match="CompSub = 2"):
        bottom_fixed_platform(deck)
    deck.simulation = SimpleNamespace(**{**vars(sim), "substructure_model": 0})
    assert bottom_fixed_platform(deck) is None


def _wheel_monopile(tmp_path: Path, water: bool = False, modes: int = 0) -> Path:
    """The wheel's monopile deck copied and edited as the reference run (README; ``water``: HydroDyn and SeaState
    on, brought to OpenFAST v5's format), or skip."""
    import re
    import shutil
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "control"))
    import _rosco

    fst = _rosco.rosco_test_case("IEA-15-240-RWT", "IEA-15-240-RWT-Monopile/IEA-15-240-RWT-Monopile.fst")
    if fst is None:
        pytest.skip("the ROSCO 2.10.6 wheel is not cached and could not be fetched with pip")
    root = tmp_path / "IEA-15-240-RWT"
    shutil.copytree(fst.parents[1], root)
    case = root / "IEA-15-240-RWT-Monopile"

    def edit(path: Path, values: dict) -> None:
        text = path.read_text()
        for key, value in values.items():
            text, n = re.subn(rf"^(\s*)(\S+)(\s+{key}\s)", lambda m: f"{m.group(1)}{value}{m.group(3)}", text, count=1,
                              flags=re.M)
            assert n == 1, key
        path.write_text(text)

    switches = {"TMax": 20, "CompInflow": 0, "CompAero": 0, "CompServo": 0}
    edit(case / "IEA-15-240-RWT-Monopile.fst", switches if water else {**switches, "CompSeaSt": 0, "CompHydro": 0})
    edit(case / "IEA-15-240-RWT-Monopile_ElastoDyn.dat", {"TTDspFA": 1.0, "TTDspSS": 0.5, "RotSpeed": 0.0})
    if modes:
        edit(case / "IEA-15-240-RWT-Monopile_SubDyn.dat", {"Nmodes": modes, "JDampings": 1.0})
    if water:                                  # the lines OpenFAST v5 (and mbsym) need that the wheel's files lack
        sys.path.insert(0, str(DATA / "openfast_subdyn_water"))
        import make_reference

        make_reference.upgrade_to_v5(case)
    return case / "IEA-15-240-RWT-Monopile.fst"


def _decay(fst: Path, csv: str, t_end: float, cases, water: bool = False) -> None:
    """Simulate the structure of ``fst`` on its substructure (CVODES) and check ε = mean|Δ|/range per
    ``(ours, theirs, sign, tolerance)`` against the stored OpenFAST series ``csv``."""
    from mbsym import simulate
    from mbsym.wind import read_openfast
    from mbsym.wind.offshore.floating import floating_structure

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = floating_structure(read_openfast(fst))
    data = np.genfromtxt(DATA / "openfast_subdyn_coupled" / csv, delimiter=",", names=True)
    res = simulate(model.dynamics(), t_end, t_out=data["Time"], method="cvodes", rtol=1e-8, atol=1e-10,
                   **({"inputs": model.sea_tables(t_end)} if water else {}))
    names = list(res.output_names)
    for ours, theirs, sign, tol in cases:
        y, ref = np.asarray(res.y)[:, names.index(ours)], sign * data[theirs]
        eps = np.mean(np.abs(y - ref)) / np.ptp(ref)
        assert eps <= tol, (ours, eps)
    return model


@pytest.mark.slow
def test_coupled_decay_against_openfast(tmp_path):
    """The deck's ElastoDyn DOFs on SubDyn's Guyan substructure, released from TTDspFA 1 m, TTDspSS 0.5 m: over
    0-20 s the TP surge, sway, roll, pitch and the base moments within ε = mean|Δ|/range ≤ 0.3 % of OpenFAST's
    (measured over 60 s: 0.01-0.08 %; heave, yaw and their reactions, 0.2 mm and 2e-4 deg, are left out: an
    axial 16 Hz Guyan mode that OpenFAST's ABM4 at 5 ms damps numerically)."""
    cases = [(c, c, 1.0, 3e-3) for c in ("PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch")]
    _decay(_wheel_monopile(tmp_path), "mono_decay.csv", 20.0,
           cases + [("ReactMYss", "minus_ReactMYss", -1.0, 3e-3), ("ReactMXss", "minus_ReactMXss", -1.0, 3e-3)])

@pytest.mark.slow
def test_coupled_decay_in_waves_against_openfast(tmp_path):
    """The same release with HydroDyn's monopile in the deck's JONSWAP sea (its added mass in the mass matrix, its
    buoyancy and fill on the nodes, the waves' loads as inputs; mbsym.wind.offshore.substructure_water): over 0-20 s
    the TP surge, sway, roll, pitch, the base moments and the elevation within ε ≤ 0.4 % of OpenFAST's (measured
    over 60 s: 0.05-0.12 %)."""
    cases = [(c, c, 1.0, 4e-3) for c in ("PtfmSurge", "PtfmSway", "PtfmRoll", "PtfmPitch", "Wave1Elev")]
    _decay(_wheel_monopile(tmp_path, water=True), "mono_wdecay.csv", 20.0,
           cases + [("ReactMYss", "minus_ReactMYss", -1.0, 4e-3), ("ReactMXss", "minus_ReactMXss", -1.0, 4e-3)],
           water=True)

@pytest.mark.slow
def test_coupled_decay_with_craig_bampton_modes_against_openfast(tmp_path):
    """The release in air with 5 CB modes as states (their inertia coupled through the TP's acceleration): over
    0-10 s the TP motion and the base reactions within ε ≤ 0.2 % of OpenFAST's at DT 1 ms (measured over 30 s:
    0.00-0.04 %, the heave's axial mode included)."""
    cases = [(c, c, 1.0, 2e-3) for c in ("PtfmSurge", "PtfmSway", "PtfmHeave", "PtfmPitch")]
    model = _decay(_wheel_monopile(tmp_path, modes=5), "mono_cb.csv", 10.0,
                   cases + [("ReactMYss", "minus_ReactMYss", -1.0, 2e-3), ("ReactFZss", "minus_ReactFZss", -1.0, 2e-3)])
    assert model.platform.n_modes == 5

@pytest.mark.slow
def test_coupled_decay_with_modes_in_waves_against_openfast(tmp_path):
    """5 CB modes and HydroDyn's monopile in the deck's sea: the water's added mass couples the modes to the TP
    (``N q̈ = g − P ü``, ``Y1 −= Q q̈``): over 0-10 s within ε ≤ 0.2 % (heave and the vertical reaction 1 %) of
    OpenFAST's at DT 1 ms (measured over 30 s: 0.05-0.08 %, heave 0.36 %)."""
    cases = [(c, c, 1.0, 2e-3) for c in ("PtfmSurge", "PtfmPitch", "PtfmRoll")]
    cases.append(("PtfmHeave", "PtfmHeave", 1.0, 1e-2))
    model = _decay(_wheel_monopile(tmp_path, water=True, modes=5), "mono_wcb.csv", 10.0,
                   cases + [("ReactMYss", "minus_ReactMYss", -1.0, 2e-3), ("ReactFZss", "minus_ReactFZss", -1.0, 1e-2)],
                   water=True)
    assert model.platform.n_modes == 5 and model.platform.sea_inputs[-1] == "CBWave05"


def test_modes_with_the_waters_added_mass_keep_the_coupled_mass_matrix():
    """CB modes with HydroDyn's added mass: the TP's mass the turbine sees is the Schur complement of the coupled
    mass matrix [[M_BB + Φ_TPᵀ A Φ_TP, Q], [P, N]] (rel. 1e-9, positive definite), and the water adds mass to it."""
    from mbsym.wind.deck.hydrodyn import read_hydrodyn
    from mbsym.wind.deck.seastate import read_seastate
    from mbsym.wind.offshore.bottom_fixed import _water_terms
    from mbsym.wind.offshore.substructure_water import substructure_hydrodynamics

    water_data = DATA / "openfast_subdyn_water"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sub = Substructure(read_subdyn(DATA / "openfast_subdyn" / "monopile_cb.dat"), reference_point=TP,
                           gravity=9.81, water_depth=30.0)
        water = substructure_hydrodynamics(read_hydrodyn(water_data / "monopile_HydroDyn.dat"),
                                           read_seastate(water_data / "still_SeaState.dat"), sub,
                                           water_density=1025.0, gravity=9.81, water_depth=30.0)
    reduced = sub.reduce()
    R, r0, R_m = _base_reaction(sub, water.static_loads)
    platform = BottomFixedPlatform(reduced, R, r0, water=water, substructure=sub,
                                   water_terms=_water_terms(sub, reduced, water), modal_reaction=R_m)
    phi, modes, A = np.asarray(reduced.tp_shapes), np.asarray(reduced.modal_shapes), np.asarray(water.added_mass)
    coupling = np.asarray(reduced.mass_coupling)
    n = reduced.n_modes
    full = np.block([[np.asarray(reduced.mass) + phi.T @ A @ phi, coupling + phi.T @ A @ modes],
                     [coupling.T + modes.T @ A @ phi, np.eye(n) + modes.T @ A @ modes]])
    schur = full[:6, :6] - full[:6, 6:] @ np.linalg.solve(full[6:, 6:], full[6:, :6])
    assert np.allclose(platform.added_mass, 0.5 * (schur + schur.T), rtol=1e-9, atol=1e-9 * np.abs(schur).max())
    assert np.all(np.linalg.eigvalsh(platform.added_mass) > 0)
    dry = _platform("monopile_cb")
    # the water adds to the TP's surge mass (2.50e5 against 1.84e5 kg; with a Guyan reduction 8.9e5 against 2.7e5 kg:
    # with the modes most of the water's inertia moves with them)
    assert platform.added_mass[0, 0] > 1.2 * dry.added_mass[0, 0]
