"""The inflow of every AeroDyn node of the flexible blades: AeroDyn's annulus axes, the aerodynamic centres'
motion, and ElastoDyn's quasi-static pitch.

References:

* a hand computation of AeroDyn's axes with full rotation matrices (``BEM_Mod = 1``, AeroDyn.f90
  ``Calculate_MeshOrientation_NoSweepPitchTwist``: the section's orientation relative to the unpitched root,
  NWTC ``EulerExtract``, ``EulerConstruct([0, θy, 0])``), independent of :func:`annulus_axes`' closed form;
* OpenFAST v5.0.0's own node outputs (``B1N…VUndx/y``, ``B1N…STVx/y``) of the shared ``ff14_flex`` deck at 12
  instants, with OpenFAST's structural states (``Q_…``, ``QD_…``) at the same instants
  (``tests/data/openfast_node_inflow``, README there): mbsym's ``Vx``, ``Vy`` of those states must be OpenFAST's.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

from mbsym.wind.operation.blade_compose import annulus_axes

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "operation"))
from _op_data import INPUTS, need  # noqa: E402

DATA = Path(__file__).resolve().parents[2] / "data" / "openfast_node_inflow" / "ff14_flex_nodes.csv"
NODES = (7, 10, 12, 13, 14, 15, 16, 17, 18)


def _dcm(axis: int, angle: float) -> np.ndarray:
    """Direction-cosine matrix (rows: new axes in old coordinates) of a rotation by ``angle`` about ``axis``."""
    c, s = np.cos(angle), np.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][axis]
    m = np.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, s, -s, c
    return m


def _euler_extract_y(m: np.ndarray) -> float:
    """NWTC ``EulerExtract``'s θy of ``m = Z(θz) Y(θy) X(θx)``."""
    return float(np.arctan2(m[2, 0], np.hypot(m[0, 0], m[1, 0])))


@pytest.mark.parametrize("pitch_deg", [0.0, 4.0, 12.0, 25.0])
def test_annulus_axes_are_aerodyns(pitch_deg):
    """x and y of :func:`annulus_axes` equal AeroDyn's ``orientationAnnulus`` rows 1 and 2 built with full
    matrices from a bent, pitched section (both in ground axes). Tolerance 1e-12: the same geometry, exactly."""
    import casadi as ca

    rng = np.random.default_rng(3)
    beta = np.deg2rad(pitch_deg)
    for _ in range(20):
        # the unpitched root (DCM from ground): azimuth, cone, tilt at random
        root = _dcm(2, rng.uniform(-np.pi, np.pi)) @ _dcm(1, rng.uniform(-0.1, 0.1)) @ _dcm(0, rng.uniform(-1, 1))
        pitched = _dcm(2, -beta) @ root                        # j1 = cos β i1 − sin β i2 (AeroDyn's sign)
        bend = _dcm(0, rng.uniform(-0.05, 0.05)) @ _dcm(1, rng.uniform(-0.12, 0.12))   # out of / in plane
        section = _dcm(2, rng.uniform(-0.2, 0.2)) @ bend @ pitched          # with some twist
        rel = section @ root.T                                 # section relative to the unpitched root
        annulus = _dcm(1, _euler_extract_y(rel)) @ root        # EulerConstruct([0, θy, 0]) · root
        R = ca.DM(pitched.T)                                   # body -> ground (columns j1, j2, j3)
        tangent = ca.DM(section[2].reshape(3, 1))              # the section's span axis, ground
        x, y = annulus_axes(R, tangent, beta)
        np.testing.assert_allclose(np.asarray(x).ravel(), annulus[0], atol=1e-12)
        np.testing.assert_allclose(np.asarray(y).ravel(), annulus[1], atol=1e-12)


@pytest.mark.parametrize("pitch_deg", [0.0, 8.0, 20.0])
def test_annulus_axes_of_a_prebent_blade_are_aerodyns(pitch_deg):
    """With AeroDyn's curve angle (``BlCrvAng``, the IEA 15 MW's reaches −5.8°): the node's orientation is
    ``EulerConstruct(0, BlCrvAng, −BlTwist)`` (``Init_u``) carried by the bent, pitched section; AeroDyn's annulus
    is the unpitched root turned by that orientation's y Euler angle. Full matrices as above, against
    :func:`annulus_axes` with ``curve_angle``. Tolerance 2e-3: ``annulus_axes`` takes the section normal's component
    along ``i1`` as ``cos β``, exact for an unbent section and off by the bending slopes' squares (≤ 0.12 rad here)
    times ``sin(BlCrvAng)``; for an unbent section it must be exact (1e-12)."""
    import casadi as ca

    rng = np.random.default_rng(5)
    beta = np.deg2rad(pitch_deg)
    for bent in (False, True):
        for _ in range(20):
            root = _dcm(2, rng.uniform(-np.pi, np.pi)) @ _dcm(1, rng.uniform(-0.1, 0.1)) @ _dcm(0, rng.uniform(-1, 1))
            pitched = _dcm(2, -beta) @ root
            bend = (_dcm(0, rng.uniform(-0.05, 0.05)) @ _dcm(1, rng.uniform(-0.12, 0.12))) if bent else np.eye(3)
            section = bend @ pitched
            curve, twist = rng.uniform(-0.1, 0.02), rng.uniform(-0.2, 0.2)
            node = _dcm(2, -twist) @ _dcm(1, curve) @ section  # EulerConstruct(0, crv, −tw) · section (AeroDyn)
            annulus = _dcm(1, _euler_extract_y(node @ root.T)) @ root
            x, y = annulus_axes(ca.DM(pitched.T), ca.DM(section[2].reshape(3, 1)), beta, [curve])
            tol = 2e-3 if bent else 1e-12
            np.testing.assert_allclose(np.asarray(x).ravel(), annulus[0], atol=tol)
            np.testing.assert_allclose(np.asarray(y).ravel(), annulus[1], atol=1e-12)


@pytest.fixture(scope="module")
def flex_model():
    from mbsym.wind.operation.deck import operating_deck

    deck = operating_deck(need(INPUTS / "ff14_flex" / "ff14_flex.fst"))
    model = deck.model(aero="blade")
    return model, model.dynamics()


def _reference():
    table = np.genfromtxt(DATA, delimiter=",", names=True)
    return table


def _state(model, d, row, *, pitch_rate: float = 0.0) -> np.ndarray:
    """The model's state with OpenFAST's structural states (``Q_TSS*`` = −ours, ElastoDyn's internal sign)."""
    values = {}
    for c in model.structure.eom.coordinates:
        sign = -1.0 if c.startswith("TSS") else 1.0
        values[c] = sign * row[f"Q_{c}"]
        values[f"{c}_d"] = sign * row[f"QD_{c}"]
    values["BlPitch"] = np.deg2rad(row["BldPitch1"])
    values["BlPitch_d"] = pitch_rate
    return np.array([values.get(n, 0.0) for n in d.states])


def _inflow(model, d, x, t):
    f = model._parts["blade_inflow"]
    u = np.array([t if n == "WindTime" else d.defaults.get(n, 0.0) for n in d.inputs], dtype=float)
    p = np.array([d.defaults[n] for n in d.parameters], dtype=float)
    out = dict(zip(f.name_out(), f(x, u, p)))
    return np.asarray(out["node_vx"]).ravel(), np.asarray(out["node_vy"]).ravel()


def test_node_inflow_is_openfasts(flex_model):
    """``Vx = VUndx − STVx`` and ``Vy = VUndy − STVy`` (AeroDyn's annulus axes; no tower influence, so the
    disturbed wind is the undisturbed) of blade 1's nodes at 18-60 m of span, 12 instants of ff14_flex, from
    OpenFAST's own structural states. Tolerance 0.06 m/s: over the whole 170 s record the largest difference
    is 0.043 m/s (rms ≤ 0.011 m/s), left by the interpolation of ElastoDyn's shapes to the AeroDyn nodes;
    with the rotor plane's axes through each deflected node and the nodes on the pitch axis (before) the
    differences were up to 0.46 m/s (Vx) and 0.74 m/s (Vy), Vx biased by +0.09 m/s at 57 m."""
    model, d = flex_model
    table = _reference()
    worst = 0.0
    for row in table:
        vx, vy = _inflow(model, d, _state(model, d, row), row["Time"])
        for n in NODES:
            ref_x = row[f"N{n}VUndx"] - row[f"N{n}STVx"]
            ref_y = row[f"N{n}VUndy"] - row[f"N{n}STVy"]
            worst = max(worst, abs(vx[n - 1] - ref_x), abs(vy[n - 1] - ref_y))
            assert abs(vx[n - 1] - ref_x) <= 0.06, (row["Time"], n, vx[n - 1], ref_x)
            assert abs(vy[n - 1] - ref_y) <= 0.06, (row["Time"], n, vy[n - 1], ref_y)
    assert worst > 0.0


def test_pitch_rate_stays_out_of_the_structure(flex_model):
    """ElastoDyn without PitchDOF: the pitch actuator's rate moves no node and loads no DOF. With the blades
    bent (OpenFAST's state), a pitch rate of 0.1 rad/s changes neither ``Vx``/``Vy`` nor the structure's
    accelerations (1e-9 relative: the same graph values); β̇ itself still integrates to β."""
    model, d = flex_model
    row = _reference()[5]
    x0, x1 = _state(model, d, row), _state(model, d, row, pitch_rate=0.1)
    assert np.allclose(_inflow(model, d, x0, row["Time"]), _inflow(model, d, x1, row["Time"]), rtol=0, atol=1e-9)
    u = np.array([row["Time"] if n == "WindTime" else d.defaults.get(n, 0.0) for n in d.inputs], dtype=float)
    p = np.array([d.defaults[n] for n in d.parameters], dtype=float)
    n_q = model.structure.eom.n_q
    xd0, xd1 = (np.asarray(d.rhs(x, u, p)).ravel() for x in (x0, x1))
    np.testing.assert_allclose(xd1[n_q:2 * n_q], xd0[n_q:2 * n_q], rtol=1e-9, atol=1e-9)
    assert xd1[d.states.index("BlPitch")] == pytest.approx(0.1)
