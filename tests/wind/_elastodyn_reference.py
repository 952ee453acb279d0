"""An independent numpy Newton–Euler replica of ElastoDyn's kinematic chain (test reference only).

Written from docs/elastodyn_notes.md §1.8, §3.5, §4 and issue 10, without mbsym's symbolic
engine: every mass is a point mass (tower and blade nodes at ElastoDyn's exact positions
``z e3 + Phi q - 1/2 q^T Ax q e3``, yaw bearing, nacelle, hub) or a rigid body with its rotary
inertia (platform, nacelle about its yaw axis, hub and generator about the shaft). Kinematics
are propagated frame by frame with explicit velocities and accelerations:

- platform: ``R = Rz(Y) Ry(P) Rx(R)``, ``w = Ydot z + Pdot y' + Rdot x''`` and its exact derivative;
- tower top: orientation ``SmllRotTrans`` (rotation by atan|theta| about theta), angular velocity
  the slope rates ``R_platform Psi qdot`` (ElastoDyn's convention, not the orientation's rate);
- points: ``a = a_O + alpha x r + w x (w x r) + 2 w x v_rel + a_rel``.

Each acceleration is kept affine in the unknown accelerations qdd (a 3 x (n + 1) array: the
columns multiply ``[qdd; 1]``), so that its qdd part is the partial velocity. Kane's equations
``sum_i [v_i . (F - m a) + w_i . (T - I alpha - w x I w)] = 0`` plus the elastic forces
``-K q - D qdot`` then give ``M qdd = F``, solved with numpy.

Only what the tests need: platform (6 DOFs), tower FA/SS (1st and 2nd modes), yaw, generator
(no drivetrain torsion; with GenDOF off the rotor spins at RotSpeed), rigid or flexible blades
(F1, F2, E1); three blades, no teeter, no pitch input.
"""

from __future__ import annotations

import numpy as np

from mbsym.wind.structure.elastodyn_bodies import BLADE_DOFS, TOWER_DOFS, blade_elastodyn_data, tower_elastodyn_data

TOWER_NAMES = {"TwFADOF1": "TFA1", "TwFADOF2": "TFA2", "TwSSDOF1": "TSS1", "TwSSDOF2": "TSS2"}
BLADE_SUFFIX = {"FlapDOF1": "F1", "FlapDOF2": "F2", "EdgeDOF": "E1"}


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _small_rotation(theta):
    """ElastoDyn's SmllRotTrans as a child->parent rotation: angle atan|theta| about theta."""
    n = np.linalg.norm(theta)
    if n == 0:
        return np.eye(3)
    k = theta / n
    a = np.arctan(n)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def _cross(w, A):
    """w x A for a 3-vector w and an affine 3 x (n+1) array A (column by column)."""
    return np.cross(w, A.T).T


def _const(v, n):
    out = np.zeros((3, n + 1))
    out[:, -1] = v
    return out


class Frame:
    """Origin position/velocity/acceleration (affine), orientation, angular velocity/acceleration (affine)."""

    def __init__(self, r, v, a, R, w, alpha):
        self.r, self.v, self.a, self.R, self.w, self.alpha = r, v, a, R, w, alpha

    def point(self, local, rel_vel=None, rel_acc=None):
        """(r, v, a) of a point at ``local`` (frame axes) moving with rel_vel, rel_acc (frame axes)."""
        rho = self.R @ local
        v = self.v + np.cross(self.w, rho)
        a = self.a - _cross(rho, self.alpha) + _const(np.cross(self.w, np.cross(self.w, rho)), self.a.shape[1] - 1)
        if rel_vel is not None:
            vr = self.R @ rel_vel
            v = v + vr
            a = a + _const(2 * np.cross(self.w, vr), self.a.shape[1] - 1) + self.R @ rel_acc
        return self.r + rho, v, a

    def child(self, local, R_rel, w_rel=None, alpha_rel=None):
        """A frame fixed at ``local`` turned by R_rel, spinning with w_rel / alpha_rel (this frame's axes)."""
        r, v, a = self.point(local)
        R = self.R @ R_rel
        if w_rel is None:
            return Frame(r, v, a, R, self.w, self.alpha)
        wr = self.R @ w_rel
        alpha = self.alpha + _const(np.cross(self.w, wr), self.a.shape[1] - 1) + self.R @ alpha_rel
        return Frame(r, v, a, R, self.w + wr, alpha)


class Reference:
    """Newton–Euler replica of a TurbineModel's DOF set at one state; ``accelerations()`` solves for qdd."""

    def __init__(self, turbine, coordinates, q, qd):
        self.t, self.names = turbine, list(coordinates)
        self.n = len(self.names)
        self.q, self.qd = dict(zip(self.names, q)), dict(zip(self.names, qd))
        self.M = np.zeros((self.n, self.n))
        self.F = np.zeros(self.n)
        self.g = np.array([0.0, 0.0, -turbine.simulation.gravity])

    # ------------------------------------------------------------ helpers
    def _unit(self, name, vec):
        """Affine column block: ``vec`` times qdd of ``name`` (zero if the DOF is off)."""
        out = np.zeros((3, self.n + 1))
        if name in self.names:
            out[:, self.names.index(name)] = vec
        return out

    def _val(self, name, default=0.0):
        return self.q.get(name, default), self.qd.get(name, 0.0)

    def mass(self, m, a):
        J, c = a[:, :-1], a[:, -1]
        self.M += m * J.T @ J
        self.F += J.T @ (m * (self.g - c))

    def inertia(self, I_world, w, alpha):
        J, c = alpha[:, :-1], alpha[:, -1]
        self.M += J.T @ I_world @ J
        self.F += J.T @ (-I_world @ c - np.cross(w, I_world @ w))

    def elastic(self, names, K, D):
        idx = [self.names.index(n) for n in names]
        q = np.array([self.q[n] for n in names])
        qd = np.array([self.qd[n] for n in names])
        self.F[idx] += -K @ q - D @ qd

    # ------------------------------------------------------------ chain
    def accelerations(self):
        t, ic = self.t, self.t.initial_conditions
        n = self.n
        platform = self._platform()
        ref = np.asarray(t.platform_reference, dtype=float)
        if any(k in self.names for k in ("Sg", "Sw", "Hv", "R", "P", "Y")):
            r, v, a = platform.point(np.asarray(t.platform_cm) - ref)
            self.mass(t.platform_mass, a)
            I = np.diag([t.platform_roll_inertia, t.platform_pitch_inertia, t.platform_yaw_inertia])
            self.inertia(platform.R @ I @ platform.R.T, platform.w, platform.alpha)
        top = self._tower(platform, ref)
        self.mass(t.yaw_bearing_mass, top.a)
        yaw, yawd = self._val("Yaw", ic.nacelle_yaw)
        nac = top.child(np.zeros(3), _rz(yaw), np.array([0, 0, yawd]), self._unit("Yaw", [0, 0, 1.0])
                        + _const(np.zeros(3), n))
        cm = np.asarray(t.nacelle_cm, dtype=float)
        _, _, a = nac.point(cm)
        self.mass(t.nacelle_mass, a)
        i_zz = t.nacelle_yaw_inertia - t.nacelle_mass * (cm[0] ** 2 + cm[1] ** 2)
        e3 = nac.R[:, 2]
        self.inertia(i_zz * np.outer(e3, e3), nac.w, nac.alpha)
        tilt = t.shaft_tilt
        c1 = np.array([np.cos(tilt), 0.0, np.sin(tilt)])
        shaft = nac.child(np.array([0.0, 0.0, t.twr2shft]) + t.overhang * c1, _ry(-tilt))
        # a disabled GenDOF keeps spinning at RotSpeed from ElastoDyn's initial azimuth (notes §4, §5)
        psi0 = np.mod(ic.azimuth - t.azimuth_blade1_up - np.pi / 2, 2 * np.pi)
        psi, psid = (self._val("GeAz") if "GeAz" in self.names else (psi0, ic.rotor_speed))
        ex = np.array([1.0, 0.0, 0.0])
        gear = abs(t.gearbox_ratio)
        gen = shaft.child(np.zeros(3), _rx(gear * psi), gear * psid * ex, gear * self._unit("GeAz", ex))
        axis = shaft.R[:, 0]
        self.inertia(t.generator_inertia * np.outer(axis, axis), gen.w, gen.alpha)
        hub = shaft.child(np.zeros(3), _rx(psi), psid * ex, self._unit("GeAz", ex))
        _, _, a = hub.point(np.array([t.hub_cm, 0.0, 0.0]))
        self.mass(t.hub_mass, a)
        self.inertia(t.hub_inertia * np.outer(axis, axis), hub.w, hub.alpha)
        for k in range(t.number_of_blades):
            self._blade(hub, k)
        return np.linalg.solve(self.M, self.F)

    def _platform(self):
        t, ic = self.t, self.t.initial_conditions
        init = dict(Sg=ic.platform_surge, Sw=ic.platform_sway, Hv=ic.platform_heave, R=ic.platform_roll,
                    P=ic.platform_pitch, Y=ic.platform_yaw)
        val = {k: self._val(k, v) for k, v in init.items()}
        (R, Rd), (P, Pd), (Y, Yd) = val["R"], val["P"], val["Y"]
        z = np.array([0.0, 0.0, 1.0])
        y1 = _rz(Y) @ np.array([0.0, 1.0, 0.0])
        x2 = _rz(Y) @ _ry(P) @ np.array([1.0, 0.0, 0.0])
        w = Yd * z + Pd * y1 + Rd * x2
        y1_dot = np.cross(Yd * z, y1)
        x2_dot = np.cross(Yd * z + Pd * y1, x2)
        alpha = (self._unit("Y", z) + self._unit("P", y1) + self._unit("R", x2)
                 + _const(Pd * y1_dot + Rd * x2_dot, self.n))
        r = np.array([val["Sg"][0], val["Sw"][0], val["Hv"][0]]) + np.asarray(t.platform_reference, dtype=float)
        v = np.array([val["Sg"][1], val["Sw"][1], val["Hv"][1]])
        a = self._unit("Sg", [1, 0, 0]) + self._unit("Sw", [0, 1, 0]) + self._unit("Hv", [0, 0, 1])
        return Frame(r, v, a, _rz(Y) @ _ry(P) @ _rx(R), w, alpha)

    def _tower(self, platform, ref):
        t = self.t
        base = platform.child(np.array([0.0, 0.0, t.tower_base_height - ref[2]]), np.eye(3))
        data = tower_elastodyn_data(t)
        flags = [f for f in TOWER_DOFS if TOWER_NAMES[f] in self.names]
        if not flags:
            for m, h in zip(data.element_mass, data.height):
                self.mass(m, base.point(np.array([0.0, 0.0, h]))[2])
            return base.child(np.array([0.0, 0.0, data.length]), np.eye(3))
        idx = [TOWER_DOFS.index(f) for f in flags]
        names = [TOWER_NAMES[f] for f in flags]
        q = np.array([self.q[c] for c in names])
        qd = np.array([self.qd[c] for c in names])
        phi, ax = data.displacement[idx], data.axial_reduction[np.ix_(idx, idx)]
        for J, (m, h) in enumerate(zip(data.element_mass, data.height)):
            self.mass(m, self._flex_point(base, h, phi[:, J], ax[:, :, J], names, q, qd)[2])
        tip_phi, tip_ax = data.tip_displacement[idx], data.tip_axial_reduction[np.ix_(idx, idx)]
        r, v, a = self._flex_point(base, data.length, tip_phi, tip_ax, names, q, qd)
        psi = np.stack([-data.tip_slope[idx, 1], data.tip_slope[idx, 0], np.zeros(len(idx))])   # (3, k)
        R_top = base.R @ _small_rotation(psi @ q)
        w_rel = base.R @ (psi @ qd)
        alpha = base.alpha + _const(np.cross(base.w, w_rel), self.n)
        for j, c in enumerate(names):
            alpha = alpha + self._unit(c, base.R @ psi[:, j])
        return Frame(r, v, a, R_top, base.w + w_rel, alpha)

    def _flex_point(self, frame, z, phi, ax, names, q, qd):
        """A node at ``z`` along the frame's z axis moving with shapes ``phi`` (k, 2) and ``ax`` (k, k)."""
        local = np.array([phi[:, 0] @ q, phi[:, 1] @ q, z - 0.5 * q @ ax @ q])
        S = np.vstack([phi[:, 0], phi[:, 1], -(ax @ q)])                                  # (3, k)
        rel_acc = _const(np.array([0.0, 0.0, -qd @ ax @ qd]), self.n)
        for j, c in enumerate(names):
            rel_acc = rel_acc + self._unit(c, S[:, j])
        return frame.point(local, S @ qd, rel_acc)

    def _blade(self, hub, k):
        t = self.t
        gamma, cone, pitch = 2 * np.pi * k / t.number_of_blades, t.precone[k], t.initial_conditions.blade_pitch[k]
        g1, g2, g3 = np.array([1.0, 0, 0]), np.array([0, 0, 1.0]), np.array([0, -1.0, 0])
        g2p, g3p = np.cos(gamma) * g2 + np.sin(gamma) * g3, -np.sin(gamma) * g2 + np.cos(gamma) * g3
        i1, i2, i3 = np.cos(cone) * g1 - np.sin(cone) * g3p, g2p, np.sin(cone) * g1 + np.cos(cone) * g3p
        j1, j2 = np.cos(pitch) * i1 - np.sin(pitch) * i2, np.sin(pitch) * i1 + np.cos(pitch) * i2
        root = hub.child(t.hub_radius * i3, np.column_stack([j1, j2, i3]))
        data = blade_elastodyn_data(t, k)
        flags = [f for f in BLADE_DOFS if f"B{k + 1}{BLADE_SUFFIX[f]}" in self.names]
        masses = list(data.element_mass) + [data.tip_mass]
        spans = list(data.span) + [data.length]
        if not flags:
            for m, z in zip(masses, spans):
                self.mass(m, root.point(np.array([0.0, 0.0, z]))[2])
            return
        idx = [BLADE_DOFS.index(f) for f in flags]
        names = [f"B{k + 1}{BLADE_SUFFIX[f]}" for f in flags]
        q = np.array([self.q[c] for c in names])
        qd = np.array([self.qd[c] for c in names])
        phis = list(np.moveaxis(data.displacement[idx], 1, 0)) + [data.tip_displacement[idx]]
        axs = list(np.moveaxis(data.axial_reduction[np.ix_(idx, idx)], 2, 0)) + \
            [data.tip_axial_reduction[np.ix_(idx, idx)]]
        for m, z, phi, ax in zip(masses, spans, phis, axs):
            self.mass(m, self._flex_point(root, z, phi, ax, names, q, qd)[2])
        K, D = data.stiffness[np.ix_(idx, idx)], data.damping[np.ix_(idx, idx)]
        self.elastic(names, K, D)


def reference_accelerations(turbine, coordinates, q, qd) -> np.ndarray:
    """qdd of the Newton–Euler replica (tower and blade stiffness/damping included) at (q, qd)."""
    ref = Reference(turbine, coordinates, q, qd)
    flags = [f for f in TOWER_DOFS if TOWER_NAMES[f] in ref.names]
    if flags:
        data, idx = tower_elastodyn_data(turbine), [TOWER_DOFS.index(f) for f in flags]
        ref.elastic([TOWER_NAMES[f] for f in flags], data.stiffness[np.ix_(idx, idx)], data.damping[np.ix_(idx, idx)])
    return ref.accelerations()
