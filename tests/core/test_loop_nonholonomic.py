"""Velocity (non-holonomic) constraints: the Chaplygin sleigh against its closed-form motion.

A planar rigid sled (mass m = 2 kg, inertia I_c = 0.1 kg m^2 about its center of mass, which lies a = 0.3 m
ahead of a knife edge at the body origin) moves on x, y (prismatic) and th (revolute about z) with the
knife edge unable to slide sideways: ``-sin(th) x' + cos(th) y' = 0``. Closed form (Newton–Euler in the
body frame, forward speed u, yaw rate ω, I_P = I_c + m a²): u' = a ω², I_P ω' = -m a u ω, so energy
E = (m u² + I_P ω²)/2 is conserved and u(t) = U tanh(a m U t / I_P + atanh(u0/U)) with U = sqrt(2E/m); the
lateral contact force on the sled is N = m (u ω + a ω'). mbsym: ``add_velocity_constraint`` with x, th
independent speeds; CVODES at rtol 1e-11 over 3 s (θ stays below 1.2 rad, away from the chosen speeds'
singularity at π/2). Tolerances: 1e-7 (integration). Runtime ~1 s.
"""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

import mbsym as mb
from mbsym.exceptions import ConstraintError, ModelDefinitionError, UnsupportedFeatureError

M, IC, A = 2.0, 0.1, 0.3
IP = IC + M * A**2


def sleigh(closure: bool = False):
    s = mb.System()
    x, y, th = s.coordinates("x y th")
    cx, cy = mb.RigidBody("cx", 0.0), mb.RigidBody("cy", 0.0)
    sled = mb.RigidBody("sled", M, com=[A, 0, 0], inertia=np.diag([0.05, 0.05, IC]))
    s.add_joint(mb.Prismatic(s.ground, cx, axis=[1, 0, 0], coordinate=x))
    s.add_joint(mb.Prismatic(cx, cy, axis=[0, 1, 0], coordinate=y))
    s.add_joint(mb.Revolute(cy, sled, axis=[0, 0, 1], coordinate=th))
    s.add_velocity_constraint(-ca.sin(th) * s.speed(x) + ca.cos(th) * s.speed(y), name="edge")
    if closure:
        s.add_constraint(y - x)
    return s


def test_chaplygin_sleigh_closed_form():
    dyn = sleigh().equations(independent_speeds=["x", "th"])
    assert dyn.states == ("x", "y", "th", "x_d", "th_d")
    u0, w0 = 0.5, 0.8
    res = mb.simulate(dyn, 3.0, x0={"x_d": u0, "th_d": w0}, method="cvodes", rtol=1e-11, atol=1e-12, dt=0.01)
    th, xd, wd = res.state("th"), res.state("x_d"), res.state("th_d")
    yd = res.output("y_d")
    u = xd * np.cos(th) + yd * np.sin(th)
    assert np.max(np.abs(-np.sin(th) * xd + np.cos(th) * yd)) < 1e-12          # no side slip
    E = 0.5 * M * u0**2 + 0.5 * IP * w0**2
    U = np.sqrt(2 * E / M)
    u_ref = U * np.tanh(A * M * U * res.t / IP + np.arctanh(u0 / U))
    assert np.max(np.abs(u - u_ref)) < 1e-7
    assert np.max(np.abs(0.5 * M * u**2 + 0.5 * IP * wd**2 - E)) < 1e-7
    N_ref = M * (u * wd + A * (-M * A * u * wd / IP))
    assert np.max(np.abs(res.output("edge_lambda") - N_ref)) < 1e-7
    assert np.max(np.abs(th)) < 1.2


def test_velocity_constraint_errors():
    s = mb.System()
    x, th = s.coordinates("x th")
    with pytest.raises(ModelDefinitionError, match="no speed"):
        s.add_velocity_constraint(ca.sin(th))
    with pytest.raises(ModelDefinitionError, match="not linear"):
        s.add_velocity_constraint(s.speed(x) ** 2)
    assert s.constraints == ()
    with pytest.raises(ConstraintError, match="independent_speeds"):
        sleigh().equations(independent_speeds=["x"])
    with pytest.raises(ConstraintError, match="independent_speeds"):
        sleigh().equations()
    with pytest.raises(ConstraintError, match=r"do not determine the speeds of \['th'\]"):
        sleigh().equations(independent_speeds=["x", "y"])           # the edge says nothing about the yaw rate
    with pytest.raises(UnsupportedFeatureError, match="without holonomic closures"):
        sleigh(closure=True).equations(independent_speeds=["x", "th"])
    with pytest.raises(mb.exceptions.ArgumentTypeError, match="velocity constraints"):
        mb.linearize(sleigh().equations(independent_speeds=["x", "th"]))
