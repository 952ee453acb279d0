"""Small test models for control and estimation, built with :class:`mbsym.System`.

They serve the examples, the tests and the benchmarks of :mod:`mbsym.control`; any
model :func:`mbsym.as_dynamics` accepts works the same way.
"""

from __future__ import annotations

import casadi as ca
import numpy as np

from ..dynamics import Dynamics, as_dynamics

__all__ = ["cart_double_pendulum", "rotor_tower", "hanging_chain"]


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
    from .. import bodies as _b, joints as _j, system as _s  # the System API, imported on use

    sys = _s.System(gravity=[0.0, 0.0, -9.81])
    s, a1, a2 = sys.coordinates("s a1 a2")
    mc, m1, m2, l1, l2, d = sys.parameters(
        "mc m1 m2 l1 l2 d", values={"mc": cart_mass, "m1": masses[0], "m2": masses[1], "l1": lengths[0],
                                     "l2": lengths[1], "d": damping})
    force = sys.inputs("F")
    cart = _b.RigidBody("cart", mass=mc)
    link1 = _b.RigidBody("link1", mass=m1, com=[0, 0, l1])
    link2 = _b.RigidBody("link2", mass=m2, com=[0, 0, l2])
    sys.add_joint(_j.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=s))
    sys.add_joint(_j.Revolute(cart, link1, axis=[0, 1, 0], coordinate=a1))
    sys.add_joint(_j.Revolute(link1, link2, axis=[0, 1, 0], coordinate=a2, offset=[0, 0, l1]))
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


def _power_coefficient(lam, pitch_deg):
    """A smooth Cp(λ, θ) surface of the form used in wind-turbine control studies (θ in degrees).

    ``1/λᵢ = 1/(λ + 0.08 θ) − 0.035/(θ³ + 1)``, ``Cp = 0.5176 (116/λᵢ − 0.4 θ − 5) e^{−21/λᵢ} + 0.0068 λ``
    (coefficients from Slootweg et al., IEEE Trans. Power Syst. 18(1), 2003). Peak ≈ 0.48 at λ ≈ 8.1, θ = 0.
    """
    inv = 1.0 / (lam + 0.08 * pitch_deg) - 0.035 / (pitch_deg ** 3 + 1.0)
    return 0.5176 * (116.0 * inv - 0.4 * pitch_deg - 5.0) * ca.exp(-21.0 * inv) + 0.0068 * lam


def rotor_tower(*, tower_mass: float = 3.5e5, tower_frequency: float = 0.32, tower_damping: float = 0.01,
                rotor_inertia: float = 4.4e7, radius: float = 63.0, gear_ratio: float = 97.0,
                pitch_time: float = 0.3, aero_time: float = 0.5) -> Dynamics:
    """A reduced turbine-like model with 6 states: tower fore-aft mode, rotor, aero-torque lag, pitch actuator.

    The structure is built with :class:`mbsym.System` (a tower-top mass on a spring
    along x, the rotor turning about x on it); a first-order lag of a quasi-steady
    aerodynamic torque (Cp surface of :func:`_power_coefficient`), a thrust
    ``½ ρ A Ct v²`` with ``Ct = 0.8 Cp/0.48 + 0.1`` (a crude but smooth surrogate) on
    the relative wind ``v − ẋ``, and a first-order pitch actuator are composed onto it.
    Sizes like a 5 MW turbine (NREL 5 MW rotor radius, gear ratio, inertia, first
    tower frequency). Not a validated turbine: a control benchmark model.

    Returns
    -------
    Dynamics
        States ``tower, azimuth, tower_d, rotor_speed`` [m, rad, m/s, rad/s],
        ``pitch`` [rad], ``aero_torque`` [N m]; inputs ``pitch_cmd`` [rad],
        ``gen_torque`` [N m, high-speed shaft], ``wind`` [m/s]; outputs ``gen_speed``
        [rpm], ``power`` [W], ``tower``, ``tower_d``, ``pitch``, ``thrust`` [N].
    """
    from .. import bodies as _b, joints as _j, system as _s

    sys = _s.System(gravity=[0.0, 0.0, 0.0])
    xt, psi = sys.coordinates("tower azimuth")
    m, J = sys.parameters("tower_mass rotor_inertia", values={"tower_mass": tower_mass, "rotor_inertia": rotor_inertia})
    thrust, shaft = sys.inputs("thrust shaft_torque")
    nacelle = _b.RigidBody("nacelle", mass=m)
    rotor = _b.RigidBody("rotor", mass=0.0, inertia=(J, 0.0, 0.0))
    sys.add_joint(_j.Prismatic(sys.ground, nacelle, axis=[1, 0, 0], coordinate=xt))
    sys.add_joint(_j.Revolute(nacelle, rotor, axis=[1, 0, 0], coordinate=psi))
    k = tower_mass * (2 * np.pi * tower_frequency) ** 2
    sys.add_spring(xt, k)
    sys.add_damper(xt, 2 * tower_damping * np.sqrt(k * tower_mass))
    sys.add_generalized_force(xt, thrust)
    sys.add_generalized_force(psi, shaft)
    eom = sys.equations(name="rotor_tower_structure")

    x = ca.SX.sym("x", 6)
    u = ca.SX.sym("u", 3)
    p = ca.SX.sym("p", 2)
    rho, area = 1.225, np.pi * radius ** 2
    v_rel = u[2] - x[2]
    omega = x[3]
    lam = omega * radius / v_rel
    pitch_deg = x[4] * 180.0 / np.pi
    cp = _power_coefficient(lam, pitch_deg)
    aero_qs = 0.5 * rho * area * cp * v_rel ** 3 / omega
    force = 0.5 * rho * area * (0.8 * cp / 0.48 + 0.1) * v_rel ** 2
    xs = ca.vertcat(x[0], x[1], x[2], x[3])
    xs_dot = eom.functions.rhs(xs, ca.vertcat(force, x[5] - gear_ratio * u[1]), p)
    rhs = ca.vertcat(xs_dot, (u[0] - x[4]) / pitch_time, (aero_qs - x[5]) / aero_time)
    gen_speed = omega * gear_ratio * 60.0 / (2 * np.pi)
    y = ca.vertcat(gen_speed, u[1] * omega * gear_ratio, x[0], x[2], x[4], force)
    f = ca.Function("rotor_tower_rhs", [x, u, p], [rhs], ["x", "u", "p"], ["xd"])
    h = ca.Function("rotor_tower_outputs", [x, u, p], [y], ["x", "u", "p"], ["y"])
    return Dynamics(f, states=["tower", "azimuth", "tower_d", "rotor_speed", "pitch", "aero_torque"],
                    inputs=["pitch_cmd", "gen_torque", "wind"], parameters=list(eom.parameters),
                    defaults=dict(eom.defaults), outputs=h,
                    output_names=["gen_speed", "power", "tower_out", "tower_d_out", "pitch_out", "thrust"],
                    output_units=["rpm", "W", "m", "m/s", "rad", "N"], name="rotor_tower", eom=None)


def hanging_chain(n_links: int = 6, *, cart_mass: float = 1.0, link_mass: float = 0.1, link_length: float = 0.2,
                  damping: float = 0.005) -> Dynamics:
    """A cart carrying a hanging chain of ``n_links`` pendulum links (2 n_links + 2 states), pushed by ``F``.

    States ``s, a1..an`` (relative joint angles, 0 hanging down) and their speeds;
    input ``F`` [N]; outputs ``cart`` [m] and ``tip_x`` [m] (horizontal position of the last mass).
    """
    from .. import bodies as _b, joints as _j, system as _s

    sys = _s.System(gravity=[0.0, 0.0, -9.81])
    names = ["s"] + [f"a{i + 1}" for i in range(n_links)]
    coords = sys.coordinates(" ".join(names))
    force = sys.inputs("F")
    cart = _b.RigidBody("cart", mass=cart_mass)
    sys.add_joint(_j.Prismatic(sys.ground, cart, axis=[1, 0, 0], coordinate=coords[0]))
    parent, offset = cart, [0.0, 0.0, 0.0]
    for i in range(n_links):
        link = _b.RigidBody(f"link{i + 1}", mass=link_mass, com=[0, 0, -link_length])
        sys.add_joint(_j.Revolute(parent, link, axis=[0, 1, 0], coordinate=coords[i + 1], offset=offset))
        sys.add_damper(coords[i + 1], damping)
        parent, offset = link, [0.0, 0.0, -link_length]
    sys.add_generalized_force(coords[0], force)
    eom = sys.equations(name=f"chain{n_links}")
    dyn = as_dynamics(eom)
    x, u, p = ca.SX.sym("x", eom.n_x), ca.SX.sym("u", 1), ca.SX.sym("p", eom.n_p)
    angle = 0
    tip = x[0]
    for i in range(n_links):
        angle = angle + x[i + 1]
        tip = tip + link_length * ca.sin(angle)
    h = ca.Function("chain_outputs", [x, u, p], [ca.vertcat(x[0], tip)], ["x", "u", "p"], ["y"])
    return Dynamics(dyn.rhs, states=dyn.states, inputs=dyn.inputs, parameters=dyn.parameters,
                    defaults=dict(dyn.defaults), outputs=h, output_names=["cart", "tip_x"], name=eom.name, eom=eom)
