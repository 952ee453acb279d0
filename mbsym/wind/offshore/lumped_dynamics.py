"""MoorDyn's lumped-mass mooring lines in motion: node states, the right-hand side, RK2 steps, the initial relaxation.

A line from a fixed anchor (node 0) to a fairlead on the platform (node N) is cut into N segments of unstretched
length l = L/N (MoorDyn's ``NumSegs``); the N − 1 internal nodes carry the line's states, positions ``r_i`` and
velocities ``ṙ_i`` (inertial axes, z up, the free surface at z = 0). The conventions are MoorDyn v2's as OpenFAST
v5.0.0 runs it (``MoorDyn_Line.f90``, read to learn them; no code taken):

* segment j (nodes j − 1 → j), stretched length ℓ_j, unit vector e_j: elastic tension ``EA max(ℓ_j/l − 1, 0)``
  (a slack segment carries none) plus internal damping ``BA ℓ̇_j / l`` (also when slack); a negative ``BA``
  in the deck is a damping ratio ζ and gives ``BA = ζ l √(EA m)``;
* node i: mass ``m l_i`` and weight in water ``(m − ρ π d²/4) g l_i``, ``l_i`` its share of the line (l for an
  internal node, l/2 at the ends); added mass ``ρ (π d²/4) l_i [C_an (I − q qᵀ) + C_at q qᵀ]``, q the node's
  tangent (the chord between its neighbours, the end segment's direction at the ends); Morison drag on the
  water's velocity relative to the node (still water), across ``½ ρ C_dn d l_i |v_p| v_p`` and along
  ``½ ρ C_dt π d l_i |v_q| v_q``;
* the seabed at z = −depth pushes a node below it up by ``kBot δ d l_i`` and damps its vertical velocity by
  ``cBot ż d l_i`` (δ its penetration; no friction);
* the fairlead node moves with the platform; its net force (the last segment's pull, its weight, drag and seabed
  force) is what the line puts on the platform, and MoorDyn's ``FAIRTEN`` is its size. The node's mass and added
  mass ride with the platform (:meth:`DynamicMooring.fairlead_mass`).

Time integration is MoorDyn's: the midpoint rule (RK2) at the step ``dtM`` (shortened to fit a whole number of
steps into the caller's interval), the fairlead moving at constant velocity over the interval.

Before t = 0 MoorDyn relaxes the lines with the platform held still (``dtIC``, ``TmaxIC``, ``CdScaleIC``,
``threshIC``): from the elastic catenaries' shape (nodes at equal unstretched arc lengths), it integrates with the
drag scaled by ``CdScaleIC`` and checks the fairlead tensions every ``dtIC``/10 s; it stops when, for every line, the
newest tension agrees with each of the nine before it within ``threshIC`` (relative), or at ``TmaxIC``. The nodes
keep their velocities: a loose threshold leaves the lines swinging at t = 0 (:meth:`DynamicMooring.relax`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import casadi as ca
import numpy as np

from ...exceptions import ParameterError
from .catenary import CatenaryLine

__all__ = ["DynamicLine", "LineRelaxation", "DynamicMooring", "Relaxed", "DEFAULT_RELAXATION",
           "dynamic_mooring_from_moordyn", "fairlead_node_mass"]


@dataclass(frozen=True)
class DynamicLine:
    """One MoorDyn line between a fixed anchor and a fairlead on the platform.

    Parameters
    ----------
    anchor : array (3)
        Anchor position, inertial axes [m].
    fairlead : array (3)
        Fairlead position in platform axes, relative to the platform reference point [m].
    length : float
        Unstretched length L [m].
    segments : int
        ``NumSegs`` N (≥ 2).
    diameter, mass_per_length, axial_stiffness : float
        d [m], m [kg/m], EA [N].
    axial_damping : float
        BA [N s] (already converted from a damping ratio).
    drag_normal, drag_axial, added_mass_normal, added_mass_axial : float
        C_dn, C_dt, C_an, C_at [-].
    """

    anchor: np.ndarray
    fairlead: np.ndarray
    length: float
    segments: int
    diameter: float
    mass_per_length: float
    axial_stiffness: float
    axial_damping: float
    drag_normal: float
    drag_axial: float
    added_mass_normal: float
    added_mass_axial: float

    def __post_init__(self) -> None:
        for name in ("anchor", "fairlead"):
            arr = np.array(getattr(self, name), dtype=float).reshape(-1)
            if arr.shape != (3,) or not np.all(np.isfinite(arr)):
                raise ParameterError(f"DynamicLine.{name} must be 3 finite coordinates [m]; got {arr.tolist()}.")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        if not (isinstance(self.segments, (int, np.integer)) and self.segments >= 2):
            raise ParameterError(f"DynamicLine.segments must be an integer >= 2 (MoorDyn's NumSegs); got "
                                 f"{self.segments!r}.")
        for name in ("length", "diameter", "mass_per_length", "axial_stiffness"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ParameterError(f"DynamicLine.{name} must be a finite number > 0; got {getattr(self, name)}.")
        for name in ("axial_damping", "drag_normal", "drag_axial", "added_mass_normal", "added_mass_axial"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise ParameterError(f"DynamicLine.{name} must be a finite number >= 0; got {getattr(self, name)}.")

    @property
    def segment_length(self) -> float:
        """l = L/N [m]."""
        return self.length / self.segments

    @property
    def area(self) -> float:
        """π d²/4 [m²]."""
        return math.pi * self.diameter ** 2 / 4


@dataclass(frozen=True)
class LineRelaxation:
    """MoorDyn's initial relaxation (its options ``dtIC`` [s], ``TmaxIC`` [s], ``CdScaleIC`` [-], ``threshIC`` [-]).

    ``t_max`` 0 skips it: the lines start at rest on the catenaries' shape."""

    interval: float = 2.0
    t_max: float = 60.0
    drag_scale: float = 4.0
    threshold: float = 0.01

    def __post_init__(self) -> None:
        for name in ("interval", "drag_scale", "threshold"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ParameterError(f"LineRelaxation.{name} must be a finite number > 0; got {getattr(self, name)}.")
        if not (math.isfinite(self.t_max) and self.t_max >= 0):
            raise ParameterError(f"LineRelaxation.t_max must be a finite number >= 0; got {self.t_max}.")


#: MoorDyn v2's defaults (``MD_Init``).
DEFAULT_RELAXATION = LineRelaxation()
#: Tensions compared in the convergence check: the newest and the nine before it (MoorDyn keeps ten).
_HISTORY = 10


@dataclass(frozen=True)
class Relaxed:
    """The lines after the initial relaxation: ``state`` (positions, then velocities per line), how long it ran
    [s], whether it met the threshold, and the fairlead tensions of its last check [N]."""

    state: np.ndarray
    time: float
    converged: bool
    tensions: np.ndarray


@dataclass(frozen=True, eq=False)
class DynamicMooring:
    """MoorDyn's lines in motion, with its seabed, time step and initial relaxation (module docstring).

    Parameters
    ----------
    lines : tuple of DynamicLine
    water_density, gravity, depth : float
        ρ [kg/m³], g [m/s²], the water depth [m] (seabed at z = −depth).
    seabed_stiffness, seabed_damping : float
        ``kBot`` [Pa/m], ``cBot`` [Pa s/m].
    time_step : float
        ``dtM`` [s].
    relaxation : LineRelaxation
    catenaries : tuple of CatenaryLine
        The same lines as elastic catenaries (their shape starts the relaxation).
    """

    lines: tuple[DynamicLine, ...]
    water_density: float
    gravity: float
    depth: float
    seabed_stiffness: float
    seabed_damping: float
    time_step: float
    relaxation: LineRelaxation = DEFAULT_RELAXATION
    catenaries: tuple[CatenaryLine, ...] = field(default=())

    def __post_init__(self) -> None:
        if not self.lines or not all(isinstance(ln, DynamicLine) for ln in self.lines):
            raise ParameterError(f"DynamicMooring.lines must be one or more DynamicLine; got {self.lines!r}.")
        if self.catenaries and len(self.catenaries) != len(self.lines):
            raise ParameterError(f"DynamicMooring.catenaries must hold one CatenaryLine per line "
                                 f"({len(self.lines)}); got {len(self.catenaries)}.")
        for name in ("water_density", "gravity", "depth", "time_step"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ParameterError(f"DynamicMooring.{name} must be a finite number > 0; got {getattr(self, name)}.")
        for name in ("seabed_stiffness", "seabed_damping"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise ParameterError(f"DynamicMooring.{name} must be a finite number >= 0; got "
                                     f"{getattr(self, name)}.")

    # ---------------------------------------------------------------------------------------------- sizes
    @property
    def n_lines(self) -> int:
        return len(self.lines)

    @cached_property
    def offsets(self) -> np.ndarray:
        """Where each line's states start in the state vector (and the end), length n_lines + 1."""
        return np.concatenate([[0], np.cumsum([6 * (ln.segments - 1) for ln in self.lines])]).astype(int)

    @property
    def n_states(self) -> int:
        return int(self.offsets[-1])

    # ---------------------------------------------------------------------------------------- the physics
    def _line_terms(self, line: DynamicLine, x, rf, vf, drag_scale):
        """(ẋ, fairlead force (3), FAIRTEN) of one line; ``x`` its 6 (N − 1) states (SX)."""
        n = line.segments
        rho, g, d, l = self.water_density, self.gravity, line.diameter, line.segment_length
        pos = ca.reshape(x[:3 * (n - 1)], 3, n - 1)
        vel = ca.reshape(x[3 * (n - 1):], 3, n - 1)
        R = ca.horzcat(ca.DM(line.anchor), pos, rf)                      # 3 × (N + 1)
        V = ca.horzcat(ca.DM.zeros(3), vel, vf)
        dr, dv = R[:, 1:] - R[:, :-1], V[:, 1:] - V[:, :-1]
        stretched = ca.sqrt(ca.sum1(dr * dr))                            # 1 × N
        unit = dr / ca.repmat(stretched, 3, 1)
        rate = ca.sum1(dr * dv) / stretched
        pull = line.axial_stiffness * ca.fmax(stretched / l - 1, 0) + line.axial_damping * rate / l
        seg = unit * ca.repmat(pull, 3, 1)                                # segment j pulls node j−1 forward
        share = ca.DM([0.5] + [1.0] * (n - 1) + [0.5]).T * l             # l_i
        chord = ca.horzcat(R[:, 1] - R[:, 0], R[:, 2:] - R[:, :-2], R[:, n] - R[:, n - 1])
        q = chord / ca.repmat(ca.sqrt(ca.sum1(chord * chord)), 3, 1)
        rel = -V
        along = ca.repmat(ca.sum1(rel * q), 3, 1) * q
        across = rel - along
        drag = 0.5 * rho * d * drag_scale * ca.repmat(share, 3, 1) * (
            line.drag_normal * ca.repmat(ca.sqrt(ca.sum1(across * across)), 3, 1) * across
            + math.pi * line.drag_axial * ca.repmat(ca.sqrt(ca.sum1(along * along)), 3, 1) * along)
        wet = (line.mass_per_length - rho * line.area) * g
        below = R[2, :] < -self.depth
        bed = ca.if_else(below, (self.seabed_stiffness * (-self.depth - R[2, :]) - self.seabed_damping * V[2, :])
                         * d * share, 0)
        vertical = bed - wet * share
        force = drag + ca.vertcat(ca.DM.zeros(2, n + 1), vertical)
        net = force + ca.horzcat(seg, ca.DM.zeros(3, 1)) - ca.horzcat(ca.DM.zeros(3, 1), seg)
        inner, qi, mi = net[:, 1:n], q[:, 1:n], line.mass_per_length * l
        a_n = mi + rho * line.area * l * line.added_mass_normal
        a_t = mi + rho * line.area * l * line.added_mass_axial
        proj = ca.repmat(ca.sum1(inner * qi), 3, 1) * qi                 # M⁻¹ = (I − qqᵀ)/a_n + qqᵀ/a_t
        acc = (inner - proj) / a_n + proj / a_t
        end = net[:, n]
        return ca.vertcat(ca.vec(vel), ca.vec(acc)), end, ca.norm_2(end)

    @cached_property
    def rhs(self) -> ca.Function:
        """``(x, rf (3 × n), vf (3 × n), drag_scale) → (ẋ, fairlead forces (3 × n) [N], FAIRTEN (n) [N])``."""
        x = ca.SX.sym("x", self.n_states)
        rf, vf = ca.SX.sym("rf", 3, self.n_lines), ca.SX.sym("vf", 3, self.n_lines)
        scale = ca.SX.sym("drag_scale")
        xd, forces, tension = [], [], []
        for k, line in enumerate(self.lines):
            a, b = self.offsets[k], self.offsets[k + 1]
            dx, f, t = self._line_terms(line, x[a:b], rf[:, k], vf[:, k], scale)
            xd.append(dx), forces.append(f), tension.append(t)
        return ca.Function("moordyn_rhs", [x, rf, vf, scale], [ca.vertcat(*xd), ca.horzcat(*forces),
                                                                 ca.vertcat(*tension)],
                           ["x", "rf", "vf", "drag_scale"], ["xdot", "force", "tension"], {"cse": True})

    def step(self, n: int) -> ca.Function:
        """``(x, rf, vf, h, drag_scale) → (x after n RK2 steps of h, mean fairlead forces, mean FAIRTEN, last
        midpoint tensions)``: the fairlead starts at ``rf`` and moves at ``vf``; the means are over the forces at
        the ends of the n steps (what a zero-order hold over the interval should pass on)."""
        key = f"_step_{n}"
        cached = self.__dict__.get(key)
        if cached is not None:
            return cached
        x, rf, vf = ca.SX.sym("x", self.n_states), ca.SX.sym("rf", 3, self.n_lines), ca.SX.sym("vf", 3, self.n_lines)
        tau, h, scale = ca.SX.sym("tau"), ca.SX.sym("h"), ca.SX.sym("drag_scale")
        k0 = self.rhs(x, rf + tau * vf, vf, scale)[0]
        k1, _, t_mid = self.rhs(x + h / 2 * k0, rf + (tau + h / 2) * vf, vf, scale)
        x1 = x + h * k1
        _, f1, t1 = self.rhs(x1, rf + (tau + h) * vf, vf, scale)
        one = ca.Function("moordyn_rk2", [x, rf, vf, tau, h, scale], [x1, ca.vec(f1), t1, t_mid])
        many = one.mapaccum("moordyn_rk2_n", n)
        X, R, V, H, S = (ca.MX.sym(s, *shape) for s, shape in (("x", (self.n_states, 1)), ("rf", (3, self.n_lines)),
                                                                ("vf", (3, self.n_lines)), ("h", (1, 1)),
                                                                ("s", (1, 1))))
        taus = ca.DM(np.arange(n)).T * H
        xs, fs, ts, tm = many(X, ca.repmat(R, 1, n), ca.repmat(V, 1, n), taus, ca.repmat(H, 1, n),
                              ca.repmat(S, 1, n))
        out = ca.Function(f"moordyn_steps_{n}", [X, R, V, H, S],
                          [xs[:, -1], ca.reshape(ca.sum2(fs) / n, 3, self.n_lines), ca.sum2(ts) / n, tm[:, -1]],
                          ["x", "rf", "vf", "h", "drag_scale"], ["x_next", "force", "tension", "tension_mid"])
        object.__setattr__(self, key, out)
        return out

    def compiled_step(self, n: int, compile: bool = True):
        """:meth:`step` compiled to C (cached on disk; the virtual machine without a compiler)."""
        key = f"_compiled_{n}_{compile}"
        cached = self.__dict__.get(key)
        if cached is None:
            from ...codegen import compile_function

            cached = compile_function(self.step(n)).function if compile else self.step(n)
            object.__setattr__(self, key, cached)
        return cached

    def substeps(self, interval: float) -> tuple[int, float]:
        """MoorDyn's steps over ``interval`` [s]: ``n = ⌈interval / dtM⌉`` steps of ``interval / n``."""
        n = max(1, math.ceil(interval / self.time_step - 1e-9))
        return n, interval / n

    # ---------------------------------------------------------------------------- start: shape, relaxation
    def at_rest(self, fairleads: np.ndarray) -> np.ndarray:
        """The state with every node on its elastic catenary at rest (MoorDyn's starting shape), for the fairlead
        positions ``fairleads`` (3 × n, inertial axes) [m]."""
        x = np.zeros(self.n_states)
        for k, line in enumerate(self.lines):
            rf = np.asarray(fairleads, dtype=float)[:, k]
            cat = self.catenaries[k] if self.catenaries else None
            pos = _catenary_nodes(line, cat, rf)
            a = self.offsets[k]
            x[a:a + 3 * (line.segments - 1)] = pos[:, 1:-1].ravel(order="F")
        return x

    def relax(self, fairleads: np.ndarray, start: np.ndarray | None = None, *, compile: bool = True) -> Relaxed:
        """MoorDyn's initial relaxation with the fairleads held at ``fairleads`` (3 × n, inertial axes) [m].

        The lines start at rest on the catenaries to ``start`` (3 × n) [m], default the fairleads as the deck
        gives them (the platform undisplaced): OpenFAST v5.0.0 starts MoorDyn's shapes there whatever the
        platform's initial position, then holds the fairleads at ``fairleads`` (its log of the shared
        ``fl_steady_13``, surge 16.3 m: 2.92e8 N in the upwind line at the first check, reproduced to 6 digits)."""
        rel = self.relaxation
        if start is None:
            start = np.stack([ln.fairlead for ln in self.lines], axis=1)
        x = self.at_rest(start)
        rf = np.asarray(fairleads, dtype=float).reshape(3, self.n_lines)
        if rel.t_max <= 0:
            return Relaxed(x, 0.0, False, np.zeros(self.n_lines))
        check = rel.interval / 10
        n, h = self.substeps(check)
        f = self.compiled_step(n, compile)
        history = np.tile(np.arange(1.0, _HISTORY + 1)[:, None], (1, self.n_lines))   # MoorDyn's seed: fails
        still = np.zeros((3, self.n_lines))
        intervals = math.ceil(rel.t_max / check - 1e-9)
        tension = np.zeros(self.n_lines)
        for i in range(intervals):
            out = f(x, rf, still, h, rel.drag_scale)
            x = np.array(out[0], dtype=float).ravel()
            tension = np.array(out[3], dtype=float).ravel()
            history = np.vstack([tension[None, :], history[:-1]])
            if i + 1 >= _HISTORY and np.all(np.abs(history[0] / history[1:] - 1) <= rel.threshold):
                return Relaxed(x, (i + 1) * check, True, tension)
        return Relaxed(x, intervals * check, False, tension)


def fairlead_node_mass(mooring: DynamicMooring, q) -> ca.SX:
    """The fairlead nodes' mass and added mass on the platform DOFs ``q`` (surge … yaw) [kg, kg m, kg m²] (SX, 6 × 6).

    MoorDyn passes the platform the fairlead node's inertia, −M a, with its mass ``m l/2`` and added mass
    ``ρ (π d²/4) (l/2) [C_an (I − qqᵀ) + C_at qqᵀ]``; the node rides with the platform, so it joins the platform's
    mass matrix as ``Jᵀ M J`` (J = ∂r/∂q of the fairlead), the tangent q taken horizontal towards the anchor."""
    from ._casadi import euler_zyx

    R = euler_zyx(q[3:6])
    total = ca.SX.zeros(6, 6)
    for line in mooring.lines:
        r = q[0:3] + ca.mtimes(R, ca.DM(line.fairlead))
        e = np.zeros(3)
        e[:2] = line.anchor[:2] - line.fairlead[:2]
        e /= max(float(np.linalg.norm(e)), 1e-12)
        half = line.segment_length / 2
        vol = mooring.water_density * line.area * half
        M = line.mass_per_length * half * np.eye(3) + vol * (
            line.added_mass_normal * (np.eye(3) - np.outer(e, e)) + line.added_mass_axial * np.outer(e, e))
        J = ca.jacobian(r, q)
        total += ca.mtimes([J.T, ca.DM(M), J])
    return total


def _catenary_nodes(line: DynamicLine, catenary: CatenaryLine | None, rf: np.ndarray) -> np.ndarray:
    """Node positions (3 × (N + 1)) on the elastic catenary from the anchor to ``rf``, at equal unstretched arc
    lengths; a straight line where no catenary is known or it does not solve (MoorDyn's fallback)."""
    s = np.linspace(0.0, line.length, line.segments + 1)
    span = rf[:2] - line.anchor[:2]
    l, h = float(np.hypot(*span)), float(rf[2] - line.anchor[2])
    if catenary is not None and l > 0:
        try:
            H, V = catenary.solve(l, h)
            xs, zs = catenary.profile(H, V, s)
            e = span / l
            return np.vstack([line.anchor[0] + e[0] * xs, line.anchor[1] + e[1] * xs, line.anchor[2] + zs])
        except Exception:                         # noqa: BLE001 - MoorDyn falls back to a straight line too
            pass
    return line.anchor[:, None] + np.outer(rf - line.anchor, s / line.length)


def dynamic_mooring_from_moordyn(md, system, *, gravity: float, depth: float, coupling_dt: float) -> DynamicMooring:
    """MoorDyn's lines of a deck in motion, on the lines, anchors and fairleads of its quasi-static ``system``.

    Parameters
    ----------
    md : MoorDynInput
        The deck (:func:`~mbsym.wind.deck.moordyn.read_moordyn`), already checked by
        :func:`~.mooring.mooring_from_moordyn`, which built ``system`` (a :class:`~.mooring.MooringSystem`).
    gravity, depth : float
        g [m/s²] and the seabed's depth [m] MoorDyn uses (:func:`~mbsym.wind.deck.moordyn_audit.moordyn_environment`).
    coupling_dt : float
        The glue code's step [s] (OpenFAST's ``DT``): ``dtM``'s default.

    Raises
    ------
    UnsupportedFeatureError
        What the moving lines do not model: ``tScheme`` other than RK2, bending stiffness EI, internal damping
        given as a curve, naming file, line and key.
    """
    from ...exceptions import UnsupportedFeatureError
    from ..deck.moordyn_audit import moordyn_options

    opts = moordyn_options(md)
    scheme = opts.get("tScheme")
    if scheme is not None and scheme[2].upper() != "RK2":
        raise UnsupportedFeatureError(f"{md.path}, line {scheme[0]}: tScheme {scheme[2]!r}; the moving lines integrate "
                                      "with MoorDyn's default RK2. Remove the option or set it to RK2.")
    value = {name: float(opts[name][2].replace("d", "e").replace("D", "E")) for name in
             ("dtM", "kBot", "cBot", "dtIC", "TmaxIC", "CdScaleIC", "threshIC") if name in opts}
    lines = []
    for k, (ident, entry) in enumerate(sorted(md.lines.items())):
        kind = md.line_types[entry.line_type]
        for key, v in (("EI", kind.bending_stiffness), ("BA/-zeta", kind.axial_damping)):
            if not isinstance(v, (int, float)):
                raise UnsupportedFeatureError(f"{md.path}, line {kind.line}: line type {kind.name!r} gives {key} as "
                                              f"{v!r}; the moving lines take a number. Give one.")
        if kind.bending_stiffness != 0:
            raise UnsupportedFeatureError(f"{md.path}, line {kind.line}: line type {kind.name!r} has bending stiffness "
                                          f"EI = {kind.bending_stiffness:g}; the moving lines have none. Set EI to 0.")
        l, m, ea = entry.length / entry.n_segments, kind.mass_per_length, kind.axial_stiffness
        ba = -kind.axial_damping * l * math.sqrt(ea * m) if kind.axial_damping < 0 else kind.axial_damping
        lines.append(DynamicLine(system.anchors[k], system.fairleads[k], entry.length, int(entry.n_segments),
                                 kind.diameter, m, ea, ba, kind.drag_transverse, kind.drag_axial,
                                 kind.added_mass_transverse, kind.added_mass_axial))
    d = DEFAULT_RELAXATION
    relax = LineRelaxation(value.get("dtIC", d.interval), value.get("TmaxIC", d.t_max),
                           value.get("CdScaleIC", d.drag_scale),
                           value.get("threshIC", d.threshold))
    return DynamicMooring(tuple(lines), system.water_density, float(gravity), float(depth), value.get("kBot", 3.0e6),
                          value.get("cBot", 3.0e5), value.get("dtM", coupling_dt), relax, tuple(system.lines))

