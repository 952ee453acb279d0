"""Small test models for control and estimation, built with :class:`mbsym.System`.

They serve the examples, the tests and the benchmarks of :mod:`mbsym.control`; any
model :func:`mbsym.as_dynamics` accepts works the same way.
"""

from __future__ import annotations

import casadi as ca

from ..dynamics import Dynamics, as_dynamics

__all__ = ["cart_double_pendulum"]


def cart_double_pendulum(*, cart_mass: float = 1.0, masses: tuple[float, float] = (0.3, 0.3),
                         lengths: tuple[float, float] = (0.5, 0.5), damping: float = 0.01) -> Dynamics:
    """A double pendulum on a cart, pushed by a horizontal force; links upright at zero angles.

    The cart slides along x (coordinate ``s`` [m]); link 1 turns about y at the cart
    (``a1`` [rad], 0 = upright), link 2 about y at the end of link 1 (``a2``,
    relative to link 1). Point masses at the link ends; viscous joint damping.

    Parameters
    ----------
    cart_mass : float, keyword-only
        [kg]
    masses : (float, float), keyword-only
        Point masses at the ends of the links [kg].
    lengths : (float, float), keyword-only
        Link lengths [m].
    damping : float, keyword-only
        Joint damping [N m s/rad].

    Returns
    -------
    Dynamics
        States ``s, a1, a2, s_d, a1_d, a2_d``; input ``F`` [N]; parameters ``mc,
        m1, m2, l1, l2, d`` (defaults as given); outputs ``cart`` [m], ``tip_x``,
        ``tip_z`` (position of the outer mass relative to the cart rail [m]),
        ``angle2`` (absolute angle of link 2 [rad]).

    Examples
    --------
    >>> dyn = cart_double_pendulum()
    >>> dyn.states
    ('s', 'a1', 'a2', 's_d', 'a1_d', 'a2_d')
    """
    import mbsym as mb      # the System API (no import cycle at module import time)

    sys = mb.System(gravity=[0.0, 0.0, -9.81])
    s, a1, a2 = sys.coordinates("s a1 a2")
    mc, m1, m2, l1, l2, d = sys.parameters(
        "mc m1 m2 l1 l2 d", values={"mc": cart_mass, "m1": masses[0], "m2": masses[1], "l1": lengths[0],
                                     "l2": lengths[1], "d": damping})
    force = sys.inputs("F")
    cart = mb.RigidBody("cart", mass=mc)
    link1 = mb.RigidBody("link1", mass=m1, com=[0, 0, l1])
    link2 = mb.RigidBody("link2", mass=m2, com=[0, 0, l2])
    sys.add_joint(mb.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=s))
    sys.add_joint(mb.Revolute(cart, link1, axis=[0, 1, 0], coordinate=a1))
    sys.add_joint(mb.Revolute(link1, link2, axis=[0, 1, 0], coordinate=a2, offset=[0, 0, l1]))
    sys.add_generalized_force(s, force)
    sys.add_damper(a1, d)
    sys.add_damper(a2, d)
    eom = sys.equations(name="cart_double_pendulum")
    dyn = as_dynamics(eom)
    x, u, p = ca.SX.sym("x", 6), ca.SX.sym("u", 1), ca.SX.sym("p", 6)
    L1, L2 = p[3], p[4]
    tip_x = x[0] + L1 * ca.sin(x[1]) + L2 * ca.sin(x[1] + x[2])
    tip_z = L1 * ca.cos(x[1]) + L2 * ca.cos(x[1] + x[2])
    y = ca.Function("cart_double_pendulum_outputs", [x, u, p], [ca.vertcat(x[0], tip_x, tip_z, x[1] + x[2])],
                    ["x", "u", "p"], ["y"])
    return Dynamics(dyn.rhs, states=dyn.states, inputs=dyn.inputs, parameters=dyn.parameters,
                    defaults=dict(dyn.defaults), outputs=y, output_names=["cart", "tip_x", "tip_z", "angle2"],
                    output_units=["m", "m", "m", "rad"], name="cart_double_pendulum", eom=eom)
