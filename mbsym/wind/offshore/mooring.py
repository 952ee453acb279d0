"""A quasi-static catenary mooring system on the platform (MoorDyn or MAP++ decks).

Each line runs from a fixed anchor to a fairlead fixed on the platform at ``p`` (platform
axes, relative to the platform reference point). For platform DOFs
``q = (surge, sway, heave, roll, pitch, yaw)`` the fairlead is at ``r = q[0:3] + R p`` with
``R = Rz(yaw) Ry(pitch) Rx(roll)`` (the platform joint's rotation); the spans to the anchor
``a`` are ``l = |(a − r)_xy|`` and ``h = r_z − a_z``; the line's
:class:`~.catenary.CatenaryLine` gives the fairlead forces (H, V), and the line pulls the
platform by ``H (a − r)_xy / l − V e_z`` at the fairlead. :meth:`MooringSystem.load` sums the
forces and their moments about the reference point (inertial axes), and the fairlead
tensions ``√(H² + V²)`` (MoorDyn's ``FAIRTEN<n>``).

Two solvers of the catenary equations: ``"rootfinder"`` (CasADi's Newton ``rootfinder``,
converged to 1e-6 m; MX graphs) and ``"newton"`` (a fixed number of smooth Newton steps
written out in SX, usable inside any SX graph; by default as many as the lines need to converge to
1e-12 from MAP++'s starting point over a wide envelope of fairlead excursions, found once per system:
:func:`newton_steps`, 10 for the VolturnUS-S). Line dynamics (MoorDyn's lumped masses,
drag, seabed stiffness) are not modelled; with ``dynamics`` (one
:class:`~.line_dynamics.LineHydrodynamics` per line) :meth:`MooringSystem.line_loads` adds the
lines' drag and inertia on their quasi-static shape (:mod:`.line_dynamics`). See docs/offshore.md.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import DimensionError, ModelWarning, OptionError, UnsupportedFeatureError
from ..deck.moordyn_audit import moordyn_environment, moordyn_option_problems, moordyn_options
from ._casadi import _in, _symbolic, euler_zyx
from .catenary import CatenaryLine, wet_weight
from .line_dynamics import LineHydrodynamics, fairlead_terms
from .lumped_line import LumpedLine

__all__ = ["MooringSystem", "mooring_from_moordyn", "mooring_from_map", "LumpedStaticsError", "lumped_steps"]


#: The fairlead excursions over which :func:`newton_steps` checks convergence, as fractions of the fairlead's
#: height above its anchor: horizontal span ±25 %, height ±10 % (VolturnUS-S: ±46 m and ±19 m, 2.8 times its
#: mean surge at rated wind); points where the line would be near-taut (tension over 20 times the
#: undisplaced one) are left out.
NEWTON_ENVELOPE = (0.25, 0.10)
#: Relative accuracy of (H, V) that :func:`newton_steps` asks for over the envelope.
NEWTON_TOLERANCE = 1e-12


def _step(line: CatenaryLine) -> ca.Function:
    """One smooth Newton step ``(HV, lh) → HV`` on the span equations (SX; H kept positive)."""
    x, p = ca.SX.sym("HV", 2), ca.SX.sym("lh", 2)
    lm, hm = line.spans(x[0], x[1])
    r = ca.vertcat(lm - p[0], hm - p[1])
    dx = -ca.solve(ca.jacobian(r, x), r)
    tiny = 1e-6 * line.weight * line.length
    return ca.Function("catenary_step", [x, p], [ca.vertcat(ca.fmax(x[0] + dx[0], tiny), x[1] + dx[1])])


def _newton(line: CatenaryLine, l, h, steps: int):
    """(H, V) after ``steps`` Newton steps from MAP++'s initial guess (SX; smooth in l, h)."""
    step = _step(line)
    HV = ca.vertcat(*line.initial_guess(l, h))
    for _ in range(steps):
        HV = step(HV, ca.vertcat(l, h))
    return HV[0], HV[1]


def newton_steps(line: CatenaryLine, span: float, height: float, *, margin: int = 1, limit: int = 60) -> int:
    """The fixed number of Newton steps (from MAP++'s guess) that converges ``line`` over :data:`NEWTON_ENVELOPE`.

    Parameters
    ----------
    line : CatenaryLine
    span, height : float
        The undisplaced fairlead's horizontal distance from and height above the anchor [m].
    margin : int, keyword-only
        Steps added to the worst case found (each squares the error).
    limit : int, keyword-only
        More steps than this mean the line does not converge from MAP++'s guess: an error.

    Returns
    -------
    int
        The most steps any grid point (19 spans × 7 heights) needed to reach :data:`NEWTON_TOLERANCE`, plus ``margin``.
    """
    lh, guess, exact, keep = _envelope(line, span, height, limit)
    step = _step(line).map(lh.shape[1])
    hv, done = guess, np.zeros(lh.shape[1], dtype=int) - 1
    for n in range(limit + 1):
        ok = np.all(np.abs(hv - exact) <= NEWTON_TOLERANCE * np.abs(exact).max(axis=0), axis=0)
        done[(done < 0) & ok] = n
        if np.all(done[keep] >= 0):
            return int(done[keep].max()) + int(margin)
        hv = np.array(step(hv, lh), dtype=float)
    k = int(np.flatnonzero(keep & (done < 0))[0])
    raise UnsupportedFeatureError(f"the catenary line (L = {line.length} m) does not converge in {limit} Newton steps "
                                  f"at span {lh[0, k]:.1f} m, height {lh[1, k]:.1f} m; check its length, weight and "
                                  "stiffness in the mooring file.")


def _envelope(line: CatenaryLine, span: float, height: float, limit: int):
    """The fairlead spans of :data:`NEWTON_ENVELOPE` (2 × 134, the undisplaced point first), MAP++'s guess and the
    converged catenary forces there (2 × 134 each), and which points count (not near-taut)."""
    dl, dh = np.meshgrid(np.linspace(-1.0, 1.0, 19) * NEWTON_ENVELOPE[0] * height,
                         np.linspace(-1.0, 1.0, 7) * NEWTON_ENVELOPE[1] * height)
    lh = np.vstack([span + dl.ravel(), height + dh.ravel()])
    lh = np.hstack([[[span], [height]], lh])                       # the undisplaced point first
    step = _step(line).map(lh.shape[1])
    sym = ca.SX.sym("lh", 2)
    start = ca.Function("guess", [sym], [ca.vertcat(*line.initial_guess(sym[0], sym[1]))])
    guess = np.array(start.map(lh.shape[1])(lh), dtype=float)
    exact = guess
    for _ in range(limit):
        exact = np.array(step(exact, lh), dtype=float)
    size = np.hypot(*exact)
    return lh, guess, exact, np.all(np.isfinite(exact), axis=0) & (size <= 20 * size[0])


class LumpedStaticsError(UnsupportedFeatureError):
    """MoorDyn's lumped line at rest does not converge over the fairlead's envelope (too few segments for the
    line's geometry): :func:`lumped_steps`."""


def lumped_steps(lumped: LumpedLine, span: float, height: float, *, limit: int = 30) -> int:
    """The Newton steps (from the catenary's forces) that converge ``lumped`` to :data:`NEWTON_TOLERANCE` over
    :data:`NEWTON_ENVELOPE` (4 for the VolturnUS-S's 50-segment lines; no margin: each step squares the error).

    Raises
    ------
    LumpedStaticsError
        A point of the envelope that does not converge in ``limit`` steps (measured: NumSegs 30 and more converge
        for the VolturnUS-S line, in 5 steps; 10 and 20 do not).
    """
    lh, _, smooth, keep = _envelope(lumped.catenary, span, height, 60)
    lh, smooth = lh[:, keep], smooth[:, keep]
    one = LumpedLine(lumped.catenary, lumped.segments, lumped.penetration, steps=1).function().map(lh.shape[1])
    iterates = [smooth]
    for _ in range(2 * limit):                   # the last as the converged forces: twice the steps allowed
        iterates.append(np.vstack([np.array(v, dtype=float) for v in one(lh[0], lh[1], *iterates[-1])]))
    exact = iterates[-1]
    for n, hv in enumerate(iterates[:limit + 1]):
        if np.all(np.abs(hv - exact) <= NEWTON_TOLERANCE * np.abs(exact).max(axis=0)):
            return max(n, 1)
    raise LumpedStaticsError(f"MoorDyn's {lumped.segments}-segment line (L = {lumped.catenary.length} m) at rest "
                             f"does not converge in {limit} Newton steps over the fairlead's envelope; use "
                             "mooring_statics='continuous' or check the line in the mooring file.")


@dataclass(frozen=True, eq=False)
class MooringSystem:
    """Catenary lines between anchors (inertial) and fairleads (platform axes) [m].

    ``dynamics``: one :class:`~.line_dynamics.LineHydrodynamics` per line (mass, Morison coefficients,
    segments) for :meth:`line_loads`, or None (quasi-static lines only); ``water_density`` [kg/m³] for
    their drag and added mass. ``lumped``: one :class:`~.lumped_line.LumpedLine` per line (MoorDyn's
    segments at rest give the fairlead forces; the continuous catenary starts them and keeps the shape of the
    drag and inertia), or None (continuous catenaries).
    """

    lines: tuple[CatenaryLine, ...]
    anchors: np.ndarray
    fairleads: np.ndarray
    dynamics: tuple[LineHydrodynamics, ...] | None = None
    water_density: float = 1025.0
    lumped: tuple[LumpedLine, ...] | None = None

    def __post_init__(self) -> None:
        n = len(self.lines)
        if self.dynamics is not None and (len(self.dynamics) != n
                                          or not all(isinstance(d, LineHydrodynamics) for d in self.dynamics)):
            raise DimensionError(f"MooringSystem.dynamics must hold one LineHydrodynamics per line ({n}); got "
                                 f"{self.dynamics!r}.")
        if self.lumped is not None and (len(self.lumped) != n or not all(
                isinstance(ln, LumpedLine) and ln.catenary == line for ln, line in zip(self.lumped, self.lines))):
            raise DimensionError(f"MooringSystem.lumped must hold one LumpedLine per line ({n}), each of the same "
                                 f"CatenaryLine as `lines`; got {self.lumped!r}.")
        for name in ("anchors", "fairleads"):
            arr = np.array(getattr(self, name), dtype=float).reshape(-1, 3)
            if arr.shape[0] != n:
                raise DimensionError(f"MooringSystem.{name} has {arr.shape[0]} rows; expected {n} (one per line).")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)

    def _expressions(self, x, method: str, steps: int):
        R = euler_zyx(x[3:6])
        force, moment, tension, fair_h = ca.DM.zeros(3), ca.DM.zeros(3), [], []
        solvers = [ln.function() for ln in self.lines] if method == "rootfinder" else None
        for k, line in enumerate(self.lines):
            arm = ca.mtimes(R, ca.DM(self.fairleads[k]))
            r = x[0:3] + arm
            d = ca.DM(self.anchors[k][:2]) - r[0:2]
            l, h = ca.sqrt(ca.sumsqr(d)), r[2] - self.anchors[k][2]
            H, V = solvers[k](ca.vertcat(l, h)) if solvers else _newton(line, l, h, steps)
            H, V = self._at_rest(k, l, h, H, V)
            f = ca.vertcat(H * d / l, -V)
            force += f
            moment += ca.cross(arm, f)
            tension.append(ca.sqrt(H ** 2 + V ** 2))
            fair_h.append(ca.vertcat(H, V))
        return ca.vertcat(force, moment), ca.vertcat(*tension), ca.horzcat(*fair_h)

    def _at_rest(self, k: int, l, h, H, V):
        """The fairlead forces of line ``k``: the continuous catenary's (H, V), or its lumped line's from them."""
        if self.lumped is None:
            return H, V
        return self.lumped[k].function()(l, h, H, V)

    def newton_steps(self) -> int:
        """The fixed Newton steps of this system's catenaries (:func:`newton_steps` over every line; computed once)."""
        cached = self.__dict__.get("_newton_steps")
        if cached is None:
            cached = max(newton_steps(line, float(np.hypot(*(self.anchors[k][:2] - self.fairleads[k][:2]))),
                                      float(self.fairleads[k][2] - self.anchors[k][2]))
                         for k, line in enumerate(self.lines))
            object.__setattr__(self, "_newton_steps", cached)
        return cached

    def _steps(self, steps: int | None) -> int:
        return self.newton_steps() if steps is None else int(steps)

    def with_dynamics(self, dynamics, water_density: float) -> "MooringSystem":
        """The same lines with drag and inertia (:meth:`line_loads`), or quasi-static again with None."""
        return MooringSystem(self.lines, self.anchors, self.fairleads,
                             None if dynamics is None else tuple(dynamics), float(water_density), self.lumped)

    def line_loads(self, q, qd, *, steps: int | None = None):
        """Static load, the lines' drag and their mass on the platform DOFs (SX expressions).

        Parameters
        ----------
        q, qd : casadi.SX
            Platform DOFs (surge … yaw) [m, rad] and their rates [m/s, rad/s].

        Returns
        -------
        static : SX (6)
            As :meth:`load` [N, N m].
        drag : SX (6)
            The lines' drag as a load at the reference point, inertial axes [N, N m] (0 without ``dynamics``).
        mass : SX (6 × 6)
            The lines' mass and added mass on ``q`` [kg, kg m, kg m²]: ``Σ J_rᵀ M_r J_r`` with ``J_r = ∂r/∂q``
            the fairlead's Jacobian (:mod:`.line_dynamics`; 0 without ``dynamics``).
        tension : SX (n)
            Fairlead tensions [N], as :meth:`tensions`.
        """
        R = euler_zyx(q[3:6])
        steps = self._steps(steps)
        static, drag, mass, tension = ca.SX.zeros(6), ca.SX.zeros(6), ca.SX.zeros(6, 6), []
        for k, line in enumerate(self.lines):
            arm = ca.mtimes(R, ca.DM(self.fairleads[k]))
            r = q[0:3] + arm
            d = ca.DM(self.anchors[k][:2]) - r[0:2]
            l, h = ca.sqrt(ca.sumsqr(d)), r[2] - self.anchors[k][2]
            H0, V0 = _newton(line, l, h, steps)
            H, V = self._at_rest(k, l, h, H0, V0)
            f = ca.vertcat(H * d / l, -V)
            static += ca.vertcat(f, ca.cross(arm, f))
            tension.append(ca.sqrt(H ** 2 + V ** 2))
            if self.dynamics is None:
                continue
            terms = fairlead_terms(line, self.dynamics[k], self.water_density, self.anchors[k])
            rd = ca.jtimes(r, q, qd)
            fd, mr, _, _ = terms(r, ca.vertcat(H0, V0), rd)   # drag and inertia on the continuous shape
            drag += ca.vertcat(fd, ca.cross(arm, fd))
            J = ca.jacobian(r, q)
            mass += ca.mtimes([J.T, mr, J])
        return static, drag, mass, ca.vertcat(*tension)

    def function(self, *, method: str = "newton", steps: int | None = None) -> ca.Function:
        """``q → (load [N, N m] (6), tensions [N] (n), HV (2 × n))`` as one CasADi Function (``steps``: Newton
        steps, default :meth:`newton_steps`)."""
        if method not in ("newton", "rootfinder"):
            raise OptionError(f"method must be 'newton' or 'rootfinder'; got {method!r}.")
        q = (ca.SX if method == "newton" else ca.MX).sym("q", 6)
        load, tension, hv = self._expressions(q, method, self._steps(steps) if method == "newton" else 0)
        return ca.Function("mooring", [q], [load, tension, hv], ["q"], ["load", "tension", "HV"])

    def load(self, q, *, method: str = "newton", steps: int | None = None):
        """Mooring force and moment about the reference point, inertial axes [N, N m].

        ``q`` as numbers (numpy back) or a CasADi SX/MX vector (an expression back; with
        ``method="rootfinder"`` only MX).
        """
        x = _in(q, 6, "q")
        if _symbolic(q) and method == "newton":
            return self._expressions(x, "newton", self._steps(steps))[0]
        out = self.function(method=method, steps=steps)(x)[0]
        return out if _symbolic(q) else np.array(out, dtype=float).ravel()

    def tensions(self, q, *, method: str = "newton", steps: int | None = None) -> np.ndarray:
        """Fairlead tensions √(H² + V²) [N] of every line at platform position ``q`` (numbers)."""
        return np.array(self.function(method=method, steps=steps)(_in(q, 6, "q"))[1], dtype=float).ravel()

    def stiffness(self, q=np.zeros(6), *, method: str = "newton", steps: int | None = None) -> np.ndarray:
        """The 6×6 mooring stiffness −∂load/∂q about ``q`` [N/m, N/rad, N m/m, N m/rad] (exact derivatives)."""
        f = self.function(method=method, steps=steps)
        sym = (ca.SX if method == "newton" else ca.MX).sym("q", 6)
        jac = ca.Function("mooring_jac", [sym], [-ca.jacobian(f(sym)[0], sym)])
        return np.array(jac(_in(q, 6, "q")), dtype=float)


def mooring_from_moordyn(md, *, water_density: float, gravity: float, water_depth: float | None = None,
                         line_dynamics: bool = True, line_segments: int | None = 10,
                         line_statics: str = "continuous") -> MooringSystem:
    """The quasi-static system of a MoorDyn deck (every line between a fixed and a vessel point).

    ``water_density``, ``gravity``, ``water_depth`` are what OpenFAST hands MoorDyn (SeaState's ``WtrDens``
    and ``WtrDpth``, the .fst's ``Gravity``); the file's ``rhoW``/``g``/``WtrDpth`` options override them, as
    in MoorDyn (:func:`~mbsym.wind.deck.moordyn_audit.moordyn_environment`). With a depth (given or in the
    file) every anchor must lie on the seabed. Every option, line-type column and point column is modelled,
    accepted or refused as :mod:`mbsym.wind.deck.moordyn_audit` lists. The seabed is frictionless
    (MoorDyn's default; friction is refused). Free points, bodies, rods and lines
    between free points are refused (:class:`~mbsym.exceptions.UnsupportedFeatureError`).
    With ``line_dynamics`` (default) the lines carry MoorDyn's mass, added mass and drag on their
    quasi-static shape (:meth:`MooringSystem.line_loads`), summed over ``line_segments`` segments of
    each line (None: the deck's ``NumSegs``). The default 10 is a quadrature of a known shape, not
    MoorDyn's discretization of the line's own dynamics: on ``fl_decay_a`` it differs from 50 segments
    by 0.1 % of the surge decay at half the cost (docs/offshore.md §6).
    ``line_statics``: ``"continuous"`` (default) gives the fairlead forces of the elastic catenaries, the
    limit of MoorDyn's lines as their segments shrink; ``"lumped"`` those of MoorDyn's ``NumSegs`` lumped
    masses at rest on its seabed springs ``kBot`` (:class:`~.lumped_line.LumpedLine`), what OpenFAST computes
    for the deck as written: with few segments the stiffness ripples as nodes lift off the seabed
    (docs/offshore.md §7).

    Raises
    ------
    OptionError
        ``line_segments`` not a positive integer or None, or given other than the default with
        ``line_dynamics=False`` (where it would do nothing); ``line_statics`` not one of the two.
    UnsupportedFeatureError
        What :func:`~mbsym.wind.deck.moordyn_audit.moordyn_option_problems` refuses (water kinematics,
        seabed friction, a bathymetry file, anchors off the seabed, visco-elastic EA, VIV, vessel points
        with mass, volume or drag), naming file, line and key.
    LumpedStaticsError
        With ``line_statics="lumped"``: a line whose segments at rest do not converge (:func:`lumped_steps`).

    Warns
    -----
    ModelWarning
        What is left of MoorDyn's line dynamics: the line's own motion (waves along the line; with
        ``line_dynamics=False`` also its drag and inertia), internal damping, the seabed's
        stiffness ``kbot`` and damping ``cbot``; and, when the deck has them, bending stiffness EI,
        MoorDyn's integration options (accepted: no effect on quasi-static lines) and unknown options
        (ignored, as MoorDyn does).
    """
    if not isinstance(line_dynamics, bool):
        raise OptionError(f"line_dynamics must be True or False; got {line_dynamics!r}.")
    if line_segments is not None and not (isinstance(line_segments, int) and line_segments >= 1):
        raise OptionError(f"line_segments must be a positive integer or None (the deck's NumSegs); got "
                          f"{line_segments!r}.")
    if line_statics not in ("continuous", "lumped"):
        raise OptionError(f"line_statics must be 'continuous' or 'lumped'; got {line_statics!r}.")
    if not line_dynamics and line_segments != 10:
        raise OptionError(f"line_segments={line_segments!r} has no effect with line_dynamics=False (it sets the "
                          "segments of the lines' drag and inertia): drop it, or keep line_dynamics=True.")
    if md.other_sections:
        raise UnsupportedFeatureError(f"{md.path}: sections {sorted(md.other_sections)} (rods, bodies, …) are not "
                                      "modelled by the quasi-static mooring.")
    env = moordyn_environment(md, water_density=water_density, gravity=gravity, water_depth=water_depth)
    refused, notes = moordyn_option_problems(md, env)
    if refused:
        raise UnsupportedFeatureError(refused[0] if len(refused) == 1 else
                                      f"{len(refused)} MoorDyn inputs are not modelled:\n  - " + "\n  - ".join(refused))
    rho, g = env.water_density, env.gravity
    opts = moordyn_options(md)
    kbot = float(opts["kBot"][2]) if "kBot" in opts else 3.0e6       # MoorDyn's default seabed stiffness [Pa/m]
    lines, anchors, fairs, dynamics, lumped = [], [], [], [], []
    for ident, entry in sorted(md.lines.items()):
        kinds = {md.points[entry.end_a].kind, md.points[entry.end_b].kind}
        if not ({"fixed"} <= kinds and kinds & {"vessel", "coupled"}):
            raise UnsupportedFeatureError(f"{md.path}, line {entry.line}: mooring line {ident} joins {sorted(kinds)} "
                                          "points; only lines from a fixed anchor to a vessel fairlead are modelled.")
        kind = md.line_types[entry.line_type]
        lines.append(CatenaryLine(entry.length, wet_weight(kind.mass_per_length, kind.diameter, rho, g),
                                  kind.axial_stiffness))
        anchor = md.anchor(ident)
        if anchor.position[2] == "seabed":          # MoorDyn: z on its seabed (the depth option, else the glue code's)
            if env.water_depth is None:
                raise UnsupportedFeatureError(f"{md.path}, line {anchor.line}: anchor {anchor.id} is on the 'seabed', "
                                              "but no depth is known: give water_depth (the .fst's WtrDpth) or a "
                                              "WtrDpth option.")
            anchors.append(anchor.position[:2] + (-env.water_depth,))
        else:
            anchors.append(anchor.position)
        fairs.append(md.fairlead(ident).position)
        dynamics.append(LineHydrodynamics.from_moordyn(kind, entry.n_segments if line_segments is None
                                                       else line_segments))
        if line_statics == "lumped":
            at_rest = LumpedLine(lines[-1], int(entry.n_segments), lines[-1].weight / (kbot * kind.diameter))
            fair = np.array(fairs[-1], dtype=float)
            steps = lumped_steps(at_rest, float(np.hypot(*(np.array(anchors[-1][:2], dtype=float) - fair[:2]))),
                                 float(fair[2] - anchors[-1][2]))
            lumped.append(dataclasses.replace(at_rest, steps=steps))
    more = "".join(f"; {note}" for note in notes)
    if line_statics == "lumped":
        statics, seabed = ("at rest the lines are MoorDyn's NumSegs lumped masses on its seabed springs kBot "
                           "(line_statics='lumped'); ", "the seabed's damping")
    else:
        statics, seabed = "", "the seabed's stiffness and damping"
    if line_dynamics:
        segments = "NumSegs" if line_segments is None else f"{line_segments} segments per line, not NumSegs"
        warnings.warn(f"{md.path}: {statics}MoorDyn's line dynamics are modelled on the quasi-static shape (line "
                      f"mass, added mass and drag of nodes that follow the catenary, {segments}); the line's own "
                      f"motion (waves along it), internal damping and {seabed} are not{more} "
                      "(mooring_lines='dynamic' moves MoorDyn's lines: docs/offshore.md §3c)", ModelWarning,
                      stacklevel=2)
    else:
        warnings.warn(f"{md.path}: {statics}MoorDyn's line dynamics (line mass and added mass, drag, internal "
                      f"damping, {seabed}) are not modelled; the lines are quasi-static{more} "
                      "(mooring_lines='dynamic' moves MoorDyn's lines: docs/offshore.md §3c)", ModelWarning,
                      stacklevel=2)
    return MooringSystem(tuple(lines), np.array(anchors), np.array(fairs),
                         tuple(dynamics) if line_dynamics else None, float(rho),
                         tuple(lumped) if line_statics == "lumped" else None)


def mooring_from_map(mp, *, water_density: float, gravity: float, water_depth: float) -> MooringSystem:
    """The quasi-static system of a MAP++ deck (with its ``repeat`` copies, seabed friction ``CB``).

    Connect nodes (line junctions) are refused. MAP++ is quasi-static: no line drag or inertia
    (its ``Ca``, ``Cdn``, ``Cdt`` columns are for its unused lumped-mass option).
    """
    lines, anchors, fairs = [], [], []
    angles = (0.0,) + mp.repeat_angles
    for ident, entry in sorted(mp.lines.items()):
        kinds = (mp.nodes[entry.anchor].kind, mp.nodes[entry.fairlead].kind)
        if kinds != ("fix", "vessel"):
            raise UnsupportedFeatureError(f"{mp.path}, line {entry.line}: line {ident} runs {kinds[0]} → {kinds[1]}; "
                                          "only fix → vessel lines are modelled.")
        kind = mp.line_types[entry.line_type]
        line = CatenaryLine(entry.length, wet_weight(kind.mass_per_length, kind.diameter, water_density, gravity),
                            kind.axial_stiffness, kind.seabed_friction)
        a, f = mp.repeated_positions(entry.anchor, water_depth), mp.repeated_positions(entry.fairlead, water_depth)
        for k in range(len(angles)):
            lines.append(line)
            anchors.append(a[k])
            fairs.append(f[k])
    return MooringSystem(tuple(lines), np.array(anchors), np.array(fairs))
