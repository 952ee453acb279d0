"""Models shared by the simulation tests, each built once per session; the SIGINT disposition of the tests that
send signals."""

import signal
import sys
import threading

import casadi as ca
import pytest

import mbsym as mb

#: Oscillator parameters [kg, N/m, N s/m]: omega_n = 5 rad/s, damping ratio 0.02.
OSC = {"m": 2.0, "k": 50.0, "c": 0.4}


def oscillator(stiffness: float = OSC["k"]):
    """Mass-spring-damper on a prismatic joint, force input F [N] (README quick-start style)."""
    sys = mb.System(gravity=[0.0, 0.0, 0.0])
    x = sys.coordinates("x")
    m, k, c = sys.parameters("m k c", values={"m": OSC["m"], "k": stiffness, "c": OSC["c"]})
    F = sys.inputs("F")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", m), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, k)
    sys.add_damper(x, c)
    sys.add_generalized_force(x, F)
    return sys.equations(name="oscillator")


def two_force_oscillator():
    """The oscillator with two force inputs F and G [N] on the same coordinate."""
    sys = mb.System(gravity=[0.0, 0.0, 0.0])
    x = sys.coordinates("x")
    m, k, c = sys.parameters("m k c", values=OSC)
    F, G = sys.inputs("F G")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", m), axis=[1, 0, 0], coordinate=x))
    sys.add_spring(x, k)
    sys.add_damper(x, c)
    sys.add_generalized_force(x, F + G)
    return sys.equations(name="two_force_oscillator")


def pendulum():
    """Undamped simple pendulum: point mass m [kg] at distance l [m], angle th [rad]."""
    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    th = sys.coordinates("th")
    m, l = sys.parameters("m l", values={"m": 1.0, "l": 1.0})
    sys.add_joint(mb.Revolute(sys.ground, mb.RigidBody("bob", m, com=[0, 0, -l]), axis=[0, 1, 0], coordinate=th))
    return sys.equations(name="pendulum")


def cubic_blowup():
    """x'' = x^3 (unit mass): from x = 1 at rest it reaches infinity at t* = sqrt(2) K(1/2) = 1.8541 s."""
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", 1.0), axis=[1, 0, 0], coordinate=x))
    sys.add_generalized_force(x, x**3)
    return sys.equations(name="blowup")


def sqrt_spring():
    """A spring force -sqrt(x): not defined (NaN) once x < 0, which the free swing reaches."""
    sys = mb.System()
    x = sys.coordinates("x")
    sys.add_joint(mb.Prismatic(sys.ground, mb.RigidBody("mass", 1.0), axis=[1, 0, 0], coordinate=x))
    sys.add_generalized_force(x, -ca.sqrt(x))
    return sys.equations(name="sqrt_spring")


@pytest.fixture(scope="session")
def osc():
    return oscillator()


@pytest.fixture(scope="session")
def pend():
    return pendulum()


def _set_sigint(action):
    """Set SIGINT to ``action`` for one test and give back the previous action, or skip where it cannot be."""
    if sys.platform == "win32":
        pytest.skip("Windows cannot deliver SIGINT to the own process (os.kill ends it instead)")
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set in the main thread")
    return signal.signal(signal.SIGINT, action)


@pytest.fixture
def sigint_delivered():
    """SIGINT raises KeyboardInterrupt during the test (Python's default handler), whatever the test process
    inherited: started in the background by a non-interactive shell (``bash .ci/run &``, ``nohup``), it inherits
    SIGINT as ignored. Child processes started meanwhile get the default action (handled signals are reset by
    exec), so a Python child turns SIGINT into KeyboardInterrupt too. The previous handler is restored after."""
    previous = _set_sigint(signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


@pytest.fixture
def sigint_ignored():
    """SIGINT ignored during the test, as inherited by a process started in the background by a script; child
    processes started meanwhile inherit it (ignored signals stay ignored across exec). Restored after."""
    previous = _set_sigint(signal.SIG_IGN)
    yield
    signal.signal(signal.SIGINT, previous)
