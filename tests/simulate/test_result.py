"""SimulationResult, the model protocol (eom + hooks) and the cache of prepared Functions."""

import dataclasses
import gc
import weakref

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.simulate import METHODS, SimulationModel, simulate
from mbsym.simulate import base as sim_base

from ._reference import sdof_response
from .conftest import OSC, oscillator

#: Methods for any model (rk4-held needs dynamics with a held part: tests/simulate/test_held_rk4.py).
GENERIC = [m for m in METHODS if not METHODS[m].needs_held]

STAT_KEYS = {"method", "steps", "n_rhs", "n_jac", "integration_wall_s", "prepare_wall_s", "success", "message"}


@pytest.mark.parametrize("method", GENERIC)
def test_result_fields(osc, method):
    res = simulate(osc, 1.0, x0={"x": 0.2}, inputs={"F": 1.0}, method=method, t_out=np.linspace(0, 1, 11))
    assert res.x.shape == (11, 2) and res.u.shape == (11, 1) and res.y.shape == (11, 0)
    assert res.states == ("x", "x_d") and res.inputs == ("F",) and res.output_names == ()
    assert np.shares_memory(res.q, res.x) and np.shares_memory(res.qd, res.x)
    np.testing.assert_array_equal(res.q[:, 0], res.state("x"))
    np.testing.assert_array_equal(res.qd[:, 0], res.state("x_d"))
    assert res.x[0, 0] == 0.2 and res.x[0, 1] == 0.0          # dict x0: missing speed -> 0
    assert STAT_KEYS <= set(res.statistics) and res.statistics["method"] == method
    assert res.success and res.message
    assert res.statistics["steps"] > 0 and res.statistics["n_rhs"] > 0
    assert method in repr(res)


def test_result_is_immutable(osc):
    res = simulate(osc, 0.1)
    with pytest.raises(dataclasses.FrozenInstanceError):
        res.t = np.zeros(3)
    with pytest.raises(ValueError):
        res.x[0, 0] = 1.0
    with pytest.raises(KeyError, match=r"no state named 'y'; the states are \['x', 'x_d'\]"):
        res.state("y")


def test_to_dict(osc):
    res = simulate(osc, 0.1, inputs={"F": 2.0})
    d = res.to_dict()
    assert list(d) == ["t", "x", "x_d", "F"]
    np.testing.assert_array_equal(d["F"], np.full(res.t.size, 2.0))


class Wrapped:
    """A model object following the protocol: eom + all optional hooks (single-output form)."""

    output_names = ("spring_force_[N]", "F_[N]")

    def __init__(self, eom):
        self.eom = eom
        x, u, p = ca.SX.sym("x", eom.n_x), ca.SX.sym("u", eom.n_u), ca.SX.sym("p", eom.n_p)
        k = p[eom.parameters.index("k")]
        self._f = ca.Function("y", [x, u, p], [ca.vertcat(-k * x[0], u[0])])

    def default_state(self):
        return {"x": 0.05}

    def default_parameters(self):
        return {"k": 200.0}

    def default_inputs(self):
        return {"F": 1.5}

    def output_function(self):
        return self._f


def test_protocol_hooks(osc):
    model = Wrapped(osc)
    assert isinstance(model, SimulationModel)
    res = simulate(model, 2.0, method="rk4")
    x_ref, _ = sdof_response(res.t, OSC["m"], OSC["c"], 200.0, x0=0.05, a0=1.5)
    assert np.max(np.abs(res.state("x") - x_ref)) < 1e-6          # default state, parameter and input used
    assert res.output_names == Wrapped.output_names
    np.testing.assert_allclose(res.output("spring_force_[N]"), -200.0 * res.state("x"), rtol=1e-12)
    np.testing.assert_allclose(res.output("F_[N]"), 1.5)
    over = simulate(model, 0.1, x0={"x_d": 1.0}, p={"k": 50.0}, inputs={"F": 0.0})
    assert over.x[0].tolist() == [0.05, 1.0]                       # dict x0 keeps the default for 'x'
    np.testing.assert_allclose(over.output("spring_force_[N]"), -50.0 * over.state("x"), rtol=1e-12)
    np.testing.assert_allclose(over.u, 0.0)
    assert "spring_force_[N]" in over.to_dict()


def test_protocol_scalar_outputs_and_channels_object(osc):
    x, u, p = ca.SX.sym("x", 2), ca.SX.sym("u", 1), ca.SX.sym("p", 3)
    f = ca.Function("y", [x, u, p], [2 * x[0], x[1]], ["x", "u", "p"], ["two_x", "v"])

    class Scalars:
        eom = osc

        def output_function(self):
            return f

    class Channels:          # like mbsym.wind.structure.channels.Channels: .function and .names
        function = ca.Function("y", [x, u, p], [ca.vertcat(2 * x[0], x[1])])
        names = ("a", "b")

    class WithChannels:
        eom = osc

        def output_function(self):
            return Channels()

    r1 = simulate(Scalars(), 0.5, x0=[0.1, 0.0])
    r2 = simulate(WithChannels(), 0.5, x0=[0.1, 0.0])
    assert r1.output_names == ("two_x", "v") and r2.output_names == ("a", "b")
    np.testing.assert_allclose(r1.y, r2.y)
    np.testing.assert_allclose(r1.output("two_x"), 2 * r1.state("x"))


def test_protocol_errors(osc):
    class BadNames(Wrapped):
        output_names = ("only_one",)

    with pytest.raises(mb.DimensionError, match="1 names"):
        simulate(BadNames(osc), 0.1)

    class BadState:
        eom = osc

        def default_state(self):
            return [1.0, 2.0, 3.0]

    with pytest.raises(mb.DimensionError, match="x0 has 3 entries"):
        simulate(BadState(), 0.1)


def test_cache_reuses_prepared_functions():
    eom = oscillator()
    first = simulate(eom, 1.0, x0=[0.1, 0.0])
    again = simulate(eom, 1.0, x0=[0.2, 0.0])
    assert not first.statistics["cache_hit"] and again.statistics["cache_hit"]
    np.testing.assert_allclose(again.x, 2 * first.x, rtol=1e-12, atol=1e-15)    # linear system
    other = simulate(eom, 1.0, x0=[0.1, 0.0], dt=0.005)
    assert not other.statistics["cache_hit"]
    c1 = simulate(eom, 1.0, x0=[0.1, 0.0], method="cvodes")
    c2 = simulate(eom, 1.0, x0=[0.1, 0.0], method="cvodes")
    assert not c1.statistics["cache_hit"] and c2.statistics["cache_hit"]


def test_cache_does_not_keep_models_alive():
    eom = oscillator()
    simulate(eom, 0.1)
    assert eom in sim_base._CACHE
    ref = weakref.ref(eom)
    del eom
    gc.collect()
    assert ref() is None


def test_adaptive_output_grid_follows_dt(osc):
    res = simulate(osc, 1.0, x0=[0.1, 0.0], method="cvodes", dt=0.1)
    np.testing.assert_allclose(res.t, np.linspace(0.0, 1.0, 11), atol=1e-12)
    assert res.statistics["dt"] is None        # no fixed step: dt only spaces the outputs


def test_step_shortened_to_end_at_tmax(osc):
    res = simulate(osc, 1.0, x0=[0.1, 0.0], dt=0.3)      # 4 steps of 0.25 s
    assert res.statistics["steps"] == 4 and res.statistics["dt"] == 0.25
    assert res.t[-1] == 1.0


def test_cache_drops_the_least_recently_used_entry(monkeypatch):
    """With room for 3 entries, re-using 'a' before inserting 'd' evicts 'b' (the LRU), not 'a' (the oldest)."""
    monkeypatch.setattr(sim_base, "CACHE_SIZE", 3)
    eom = oscillator()
    for key in "abc":
        sim_base.prepared(eom, key, lambda k=key: k)
    assert sim_base.prepared(eom, "a", lambda: "rebuilt") == ("a", True)
    sim_base.prepared(eom, "d", lambda: "d")
    assert list(sim_base._CACHE[eom]) == ["c", "a", "d"]
    assert sim_base.prepared(eom, "b", lambda: "rebuilt") == ("rebuilt", False)


def test_fixed_step_loop_keeps_its_step_function(monkeypatch):
    """Four step counts with room for 3 entries: the step Function, inserted first but used by every
    loop, is built once (dropping the oldest entry instead rebuilt it for the fourth loop)."""
    from mbsym.simulate.fixed import RK4

    builds = []
    original = RK4._build_step
    monkeypatch.setattr(RK4, "_build_step", lambda self: builds.append(1) or original(self))
    monkeypatch.setattr(sim_base, "CACHE_SIZE", 3)
    eom = oscillator()
    for n in (10, 20, 30, 40):
        simulate(eom, 1.0, x0=[0.1, 0.0], dt=1.0 / n)
    assert len(builds) == 1


@pytest.mark.parametrize("setting, value", [("rho_inf", 0.5), ("newton_stop", 1e-3), ("max_newton_iterations", 1)])
def test_cache_key_holds_method_settings(monkeypatch, setting, value):
    """A changed class setting of generalized-alpha builds a new step instead of hitting the cached one:
    rho_inf changes the result; a loose Newton stop (1e-3 > newton_tol 1e-6) or a single Newton iteration
    (first correction 0.028) makes the step fail. Restored, the first entry is hit again."""
    from mbsym.exceptions import IntegrationError
    from mbsym.simulate.second_order import GeneralizedAlpha

    eom = oscillator()
    kw = dict(x0=[0.1, 0.0], inputs={"F": 1.0}, method="generalized-alpha", dt=0.05)
    first = simulate(eom, 2.0, **kw)
    with monkeypatch.context() as m:
        m.setattr(GeneralizedAlpha, setting, value)
        if setting == "rho_inf":
            changed = simulate(eom, 2.0, **kw)
            assert not changed.statistics["cache_hit"] and np.max(np.abs(changed.x - first.x)) > 1e-6
        else:
            with pytest.raises(IntegrationError, match="Newton iteration did not converge"):
                simulate(eom, 2.0, **kw)
    again = simulate(eom, 2.0, **kw)
    assert again.statistics["cache_hit"]
    np.testing.assert_array_equal(again.x, first.x)


@pytest.mark.parametrize("method", GENERIC)
def test_success_and_message_come_from_the_integrator(osc, method):
    res = simulate(osc, 1.0, x0=[0.1, 0.0], method=method, t_out=[0.0, 0.5, 1.0])
    assert res.statistics["success"] is True and res.success
    assert ("steps of dt" in res.message) if METHODS[method].kind == "fixed-step" else ("t = 1 s" in res.message)


def test_outputs_on_grids_of_different_sizes(osc):
    """The mapped output Function is built per number of output times; each size gets its own."""
    model = Wrapped(osc)
    for n in (3, 7, 3, 12):
        res = simulate(model, 1.0, method="cvodes", t_out=np.linspace(0.0, 1.0, n))
        assert res.y.shape == (n, 2)
        np.testing.assert_allclose(res.output("spring_force_[N]"), -200.0 * res.state("x"), rtol=1e-12)
        np.testing.assert_allclose(res.output("F_[N]"), 1.5, rtol=0, atol=0)
