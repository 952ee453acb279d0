"""AeroDyn's continuous UA models ``UA_Mod`` 4 (HGM) and 6 (Øye) (mbsym.wind.aero.blade.ua_continuous).

Closed forms and invariants from UnsteadyAero.f90 / AirfoilInfo.f90 v5.0.0 (the model's equations, not a driver run):
the separation columns rebuild the polar's Cl where 0 < f_st < 1; the steady states are rest points; the
derivatives are first-order lags with AeroDyn's time constants (``b_k/T_u``, ``T_p T_u``, ``T_f0 T_u``).
Deck: the shared NREL 5 MW operating deck (/work/shared/openfast/aero, README).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from mbsym.exceptions import UnsupportedFeatureError
from mbsym.wind.aero.blade import BladeElementRotor
from mbsym.wind.aero.blade import ua_continuous as uc
from mbsym.wind.aero.blade import unsteady as ua

DECK = Path("/work/shared/openfast/aero/openfast_inputs")
FST = DECK / "steady_14" / "steady_14.fst"
AD = DECK / "deck" / "NRELOffshrBsline5MW_Onshore_AeroDyn15.dat"


@pytest.fixture(scope="module")
def rotor() -> BladeElementRotor:
    if not FST.exists():
        pytest.skip(f"shared OpenFAST decks not found at {FST}")
    return BladeElementRotor.from_openfast(FST, polar_method="linear")


def _nodes(rotor, mode):
    from mbsym.wind.deck.aerodyn import read_aerodyn

    aerodyn = dataclasses.replace(read_aerodyn(AD, n_blades=3), unsteady_model=mode)
    return ua.unsteady_nodes(aerodyn, rotor.bem, 1, dt=0.00625, speed_of_sound=340.0)


def test_modes_accepted_and_refused(rotor):
    from mbsym.wind.deck.aerodyn import read_aerodyn

    for mode, n_states in ((4, 4), (6, 1)):
        nodes = _nodes(rotor, mode)
        assert nodes.mode == mode and nodes.continuous
        # UA off on the cylinders (constant data) only: AeroDyn's UA_TurnOff_param for C_lalpha = 0
        assert all(rotor.bem.polars[j].ua is not None for j in nodes.node)
        assert len(ua.state_names([(0, int(j)) for j in nodes.node], mode)) == n_states * nodes.size
    aerodyn = read_aerodyn(AD, n_blades=3)
    for mode in (2, 5, 7):
        with pytest.raises(UnsupportedFeatureError, match="UA_Mod = ") as err:
            ua.unsteady_nodes(dataclasses.replace(aerodyn, unsteady_model=mode), rotor.bem, 3, dt=0.00625,
                              speed_of_sound=340.0)
        # the message says why: 5's vortex switch is updated per step, 7 is a discrete model
        assert "vortex switch" in str(err.value) and "discrete model" in str(err.value)


def test_separation_columns_rebuild_the_polar(rotor):
    """``f_st Cl_fa + (1 - f_st) Cl_fs = Cl`` at every table point (Kirchhoff inversion, AirfoilInfo.f90), to
    rounding, wherever ``f_st`` is not clipped to 0 or 1."""
    for j in _nodes(rotor, 6).node:
        p = rotor.bem.polars[int(j)]
        f, fs = uc.separation_columns(p.alpha, p.cl, p.ua)
        cl_fa = p.ua.C_lalpha * (p.alpha - p.ua.alpha0)
        inside = (f > 0.0) & (f < 1.0)
        assert np.all((f >= 0) & (f <= 1))
        assert np.max(np.abs(f * cl_fa + (1 - f) * fs - p.cl)[inside]) < 1e-12


@pytest.mark.parametrize("mode", [4, 6])
def test_rest_point_and_time_constants(rotor, mode):
    nodes = _nodes(rotor, 6)                      # the UA nodes (the same for either model)
    pol = rotor.polars
    k = nodes.size // 2
    j = int(nodes.node[k])
    sep = uc.separation_polars(pol)
    f = uc.node_function(mode, nodes.dt, nodes.has_cm, lambda x, _n: pol(x, [j]), lambda x, _n: sep(x, [j]))
    fs = uc.steady_node_function(mode, lambda x, _n: sep(x, [j]))
    c = ca.DM(uc.constants(nodes, pol)[:, k])
    prm = {key: float(c[i]) for i, key in enumerate(uc.PARAMETERS)}
    chord, u, alpha = float(c[len(uc.PARAMETERS)]), 40.0, math.radians(6.0)
    tu = chord / (2 * u)
    z = fs(alpha, u, 0.0, c)
    out = f(alpha, u, 0.0, z, c, alpha, u, 0.0)
    assert float(ca.norm_inf(out[4])) < 1e-12                                   # a rest point
    static = pol.numeric(np.array([alpha]), j)
    assert abs(float(out[0]) - static["cl"][0]) < 2e-3                          # ~ the static polar there
    assert abs(float(out[1]) - static["cd"][0]) < 1e-12
    step = math.radians(1.0)                                                    # the lags after a step in α
    zdot = np.asarray(f(alpha + step, u, 0.0, z, c, alpha + step, u, 0.0)[4]).ravel()
    f_new = float(sep.numeric(np.array([alpha + step]), j)["cl"][0])
    if mode == 6:
        assert zdot[0] == pytest.approx((f_new - float(z[0])) / (prm["T_f0"] * tu), rel=1e-12)
    else:
        assert zdot[0] == pytest.approx(prm["b1"] / tu * prm["A1"] * step, rel=1e-12)
        assert zdot[1] == pytest.approx(prm["b2"] / tu * prm["A2"] * step, rel=1e-12)
        a_e = (alpha + step) * (1 - prm["A1"] - prm["A2"]) + float(z[0]) + float(z[1])
        clp = prm["C_lalpha"] * (a_e - prm["alpha0"])
        assert zdot[2] == pytest.approx((clp - float(z[2])) / (prm["T_p"] * tu), rel=1e-12)
        assert zdot[3] == pytest.approx(0.0, abs=1e-12)                         # x4 follows x3, not α


def test_pitch_rate_term(rotor):
    """HGM's non-circulatory lift ``π T_u ω`` and moment ``-π/2 T_u ω`` (UnsteadyAero.f90 Eq. 16, 18)."""
    nodes = _nodes(rotor, 6)
    pol, k = rotor.polars, nodes.size // 2
    j = int(nodes.node[k])
    sep = uc.separation_polars(pol)
    f = uc.node_function(4, nodes.dt, nodes.has_cm, lambda x, _n: pol(x, [j]), lambda x, _n: sep(x, [j]))
    c = ca.DM(uc.constants(nodes, pol)[:, k])
    chord, u, alpha, w = float(c[len(uc.PARAMETERS)]), 40.0, math.radians(4.0), 0.2
    z = uc.steady_node_function(4, lambda x, _n: sep(x, [j]))(alpha, u, 0.0, c)
    a, b = f(alpha, u, 0.0, z, c, alpha, u, 0.0), f(alpha, u, w, z, c, alpha, u, w)
    tu = chord / (2 * u)
    # with ω the 3/4-chord angle moves too: α34 = atan2(U sin α + ω c/2, U cos α)
    a34 = math.atan2(u * math.sin(alpha) + w * chord / 2, u * math.cos(alpha))
    cl_move = float(f(a34, u, 0.0, z, c, a34, u, 0.0)[0]) - float(a[0])
    assert float(b[0]) - float(a[0]) == pytest.approx(math.pi * tu * w + cl_move, rel=1e-9)


@pytest.mark.parametrize("mode", [4, 6])
def test_rest_states_read_the_section_rate(mode):
    """``HGM_Steady`` sets the states from the first step's inputs with ``u%omega`` (UnsteadyAero.f90 v5.0.0:
    ``Get_HGM_constants`` -> ``alpha_34``): x1 = A1 α34, x2 = A2 α34, x3 = C_lα (α34 − α0), x4 = f_st(α34) with
    ``α34 = atan2(U sin α + ω c/2, U cos α)``. ``steady_states(..., ua_omega=)`` passes the rate on; without it
    the states are those at ω = 0."""
    from mbsym.wind.deck.aerodyn import read_aerodyn

    if not AD.exists():
        pytest.skip(f"shared OpenFAST decks not found at {AD}")
    aerodyn = dataclasses.replace(read_aerodyn(AD, n_blades=3), unsteady_model=mode)
    rot = BladeElementRotor.from_aerodyn(aerodyn, hub_radius=1.5, precone=-0.04363, n_blades=3, ua_dt=0.00625,
                                         speed_of_sound=340.0, polar_method="linear", dynamic_wake=False)
    n = rot.n_blades * rot.n_nodes
    r = np.tile(np.asarray(rot.bem.local_radius, float), 3)
    vx, vy, theta = np.full(n, 10.0), r * 1.2, np.tile(np.asarray(rot.bem.twist, float), 3) + 0.05
    w = np.linspace(-0.2, 0.3, n)
    z0, zw = rot.steady_states(vx, vy, r, theta), rot.steady_states(vx, vy, r, theta, ua_omega=w)
    out = rot.evaluate(vx, vy, r, theta, np.zeros(n), ca.DM(z0), rho=1.2)
    alpha, vrel = (np.asarray(ca.evalf(out[k])).ravel() for k in ("alpha", "vrel"))
    ua_nodes, names = rot.unsteady, uc.state_suffixes(mode)
    sep = uc.separation_polars(rot.polars)
    zw = zw.reshape(ua_nodes.size, len(names))
    z0 = z0.reshape(ua_nodes.size, len(names))
    for k, i in enumerate(np.asarray(ua_nodes.index, int)):
        chord, prm = float(ua_nodes.chord[k]), {q: float(ua_nodes.params[q][k]) for q in uc.PARAMETERS}
        for z, rate in ((z0, 0.0), (zw, w[i])):
            a34 = math.atan2(vrel[i] * math.sin(alpha[i]) + rate * chord / 2, vrel[i] * math.cos(alpha[i]))
            want = {"x1": prm["A1"] * a34, "x2": prm["A2"] * a34, "x3": prm["C_lalpha"] * (a34 - prm["alpha0"]),
                    "x4": float(ca.evalf(sep(ca.SX(a34), [int(ua_nodes.node[k])])["cl"]))}
            assert z[k] == pytest.approx([want[q] for q in names], rel=1e-10, abs=1e-12)
