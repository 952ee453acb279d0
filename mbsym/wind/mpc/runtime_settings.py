"""What an exported NMPC reads from its input file at run time: cost scales, limits and the preview source.

The exported library (:mod:`.discon_nmpc`) generates its OCP once: the prediction model, the horizon, the sample
times, the estimator and its noise levels are compiled in (they size its memory and its generated code). Its cost
scales and its limits are not: they are inputs of the generated Functions (:mod:`.sample`), read from the input
file at the first call, so a user retunes the controller by editing a text file, with no compiler:

- **cost scales** (:class:`~.nmpc.NMPCTuning`, same names and units; :data:`SCALE_KEYS`) of the terms the exported
  OCP has. Each residual row of the Gauss–Newton cost is multiplied by ``s_exported / s`` (the root weight
  ``1/s``): the run-time value gives exactly the cost an export with that scale gives (tested). ``inf`` removes
  a term; a term the export did not have (its scale ``inf`` then) cannot be added at run time: export again.
  ``TerminalFactor`` multiplies the terminal rows' weights (their roots by ``sqrt(f / f_exported)``). The QP's
  scaling (:func:`~.sample_rti.qp_scaling`) stays the exported one: it only conditions the QP.
- **limits** of the NMPC's pitch and torque demands and their rates (:data:`LIMIT_KEYS`), narrowed at run time
  within the exported ones (the prediction model's actuators hold the exported limits; to widen them, export
  again). They bound the OCP, the plan's first rates and the ramps between NMPC samples.
- **the preview source** (with a lidar preview compiled in): ``lidar``, or ``none`` (the estimated wind held over
  the horizon, as without preview), and the lidar's focal distance and advection filter.

Keys whose values are compiled in (horizon, sample times, estimator, power reference, the lidar's beams and
moving-average window) are written too and checked: another value is an error naming the export option to change.
An unknown, repeated or out-of-range key is an error at the first call (``aviFAIL = -1``, the host stops), never
ignored. :meth:`RuntimeLayout.settings` is the same check in Python (:class:`~.sample.SampledLoop`).

The settings vector (:attr:`RuntimeSettings.vector`, an input of ``qp_data``, ``finish`` and ``startup``): the cost
scales of :attr:`RuntimeLayout.scales`, then the limits in :data:`LIMIT_KEYS` order.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

import casadi as ca
import numpy as np

from ...exceptions import ControlDefinitionError

__all__ = ["SCALE_KEYS", "LIMIT_KEYS", "RuntimeLayout", "RuntimeSettings", "runtime_layout", "weighted_problem",
           "symbolic_bounds"]

#: NMPCTuning field -> (input-file key, unit).
SCALE_KEYS = {"speed_scale": ("SpeedScale", "rpm"), "power_scale": ("PowerScale", "kW"),
              "pitch_scale": ("PitchScale", "deg"), "torque_scale": ("TorqueScale", "kN m"),
              "tower_velocity_scale": ("TowerVelocityScale", "m/s"), "tower_moment_scale": ("TowerMomentScale", "kN m"),
              "tower_deflection_scale": ("TowerDeflectionScale", "m"),
              "platform_pitch_rate_scale": ("PlatformPitchRateScale", "rad/s"),
              "pitch_rate_scale": ("PitchRateScale", "rad/s"), "torque_rate_scale": ("TorqueRateScale", "N m/s"),
              "pitch_acceleration_scale": ("PitchAccelerationScale", "rad/s^2"),
              "terminal_factor": ("TerminalFactor", "-")}
#: The limits' input-file keys and units, in the settings vector's order.
LIMIT_KEYS = (("PitchMin", "rad"), ("PitchMax", "rad"), ("TorqueMin", "N m"), ("TorqueMax", "N m"),
              ("PitchRateMin", "rad/s"), ("PitchRateMax", "rad/s"), ("TorqueRateMin", "N m/s"),
              ("TorqueRateMax", "N m/s"))
#: The OCP's state and control names the limits bound.
_LIMITED = (("x", "BlPitch"), ("x", "GenTq"), ("u", "BlPitchRate"), ("u", "GenTqRate"))
PREVIEW_SOURCES = ("lidar", "none")


@dataclass(frozen=True)
class RuntimeSettings:
    """One set of run-time settings: the settings ``vector`` (module docstring) and the preview (None: the
    estimated wind held over the horizon)."""

    vector: np.ndarray
    preview: object = None

    @property
    def limits(self) -> tuple:
        """Pitch [rad] and torque [N m] demand limits ``((lo, hi), (lo, hi))``."""
        v = self.vector[-8:]
        return (float(v[0]), float(v[1])), (float(v[2]), float(v[3]))

    @property
    def rate_bounds(self) -> tuple:
        """Pitch-rate [rad/s] and torque-rate [N m/s] bounds."""
        v = self.vector[-4:]
        return (float(v[0]), float(v[1])), (float(v[2]), float(v[3]))


@dataclass(frozen=True)
class RuntimeLayout:
    """The run-time settings of one exported NMPC (:func:`runtime_layout`).

    Attributes
    ----------
    scales : tuple of str
        NMPCTuning fields settable at run time (the OCP's terms, then ``terminal_factor`` if it has terminal rows).
    exported : ndarray
        The settings vector at export.
    stage_rows, terminal_rows : tuple of int
        For each stage (terminal) residual row, the index in :attr:`scales` of its scale.
    ranges : tuple of (float, float, bool, bool)
        Per vector entry: allowed (min, max, min open, max open).
    fixed : tuple of (str, str, str)
        Compiled-in keys: (key, value as written, how to change it).
    preview : PreviewSettings or None
        The compiled preview.
    """

    scales: tuple
    exported: np.ndarray
    stage_rows: tuple
    terminal_rows: tuple
    ranges: tuple
    fixed: tuple
    preview: object = None

    @property
    def keys(self) -> tuple:
        """The settings vector's input-file keys."""
        return tuple(SCALE_KEYS[s][0] for s in self.scales) + tuple(k for k, _ in LIMIT_KEYS)

    def factors(self, s: ca.MX) -> tuple[ca.MX, ca.MX]:
        """Factors of the stage and terminal residual rows for the settings vector ``s`` (module docstring)."""
        e = self.exported
        stage = [e[j] / s[j] for j in self.stage_rows]
        term = [e[j] / s[j] for j in self.terminal_rows]
        if self.terminal_rows:
            tf = self.scales.index("terminal_factor")
            term = [v * ca.sqrt(s[tf] / e[tf]) for v in term]
        return (ca.vertcat(*stage) if stage else ca.MX(0, 1)), (ca.vertcat(*term) if term else ca.MX(0, 1))

    def settings(self, changes: Mapping[str, object] | None = None) -> RuntimeSettings:
        """The settings with ``changes`` (input-file key -> value) applied and checked as the library checks them.

        Raises
        ------
        ControlDefinitionError
            An unknown key, a value out of its range, a compiled-in key with another value, crossed limits.
        """
        if changes is not None and not isinstance(changes, Mapping):
            raise TypeError(f"run-time settings are a dict of input-file key -> value; got {type(changes).__name__}.")
        v = self.exported.copy()
        use, lidar = self.preview is not None, {}
        keys = self.keys
        fixed = {k: (val, how) for k, val, how in self.fixed}
        for key, value in (changes or {}).items():
            if key in fixed:
                if str(value) != fixed[key][0] and not _same_number(value, fixed[key][0]):
                    raise ControlDefinitionError(f"{key} is {value!r}; this library is compiled for {fixed[key][0]} "
                                                 f"({fixed[key][1]}).")
            elif key == "PreviewSource":
                use = self._source(value)
            elif key in ("LidarDistance", "LidarAdvectionTime") and self.preview is not None:
                x = _number(key, value)
                if not (math.isfinite(x) and x > 0):
                    raise ControlDefinitionError(f"{key} is {value!r}; expected a finite number > 0.")
                lidar["distance" if key == "LidarDistance" else "advection_time"] = x
            elif key in keys:
                i = keys.index(key)
                v[i] = _number(key, value)
                lo, hi, open_lo, open_hi = self.ranges[i]
                if not _inside(v[i], lo, hi, open_lo, open_hi):
                    raise ControlDefinitionError(f"{key} is {value!r}; expected {_range_text(*self.ranges[i])}.")
            else:
                raise ControlDefinitionError(f"unknown run-time setting {key!r}; this NMPC reads {list(keys)}, "
                                             "PreviewSource, LidarDistance, LidarAdvectionTime and the compiled-in "
                                             f"{[k for k, _, _ in self.fixed]}.")
        lim = v[len(self.scales):]
        for a, b in ((0, 1), (2, 3)):
            if not lim[a] < lim[b]:
                raise ControlDefinitionError(f"{LIMIT_KEYS[a][0]} {lim[a]:g} must be below {LIMIT_KEYS[b][0]} "
                                             f"{lim[b]:g}.")
        return RuntimeSettings(v, dataclasses.replace(self.preview, **lidar) if use else None)

    def _source(self, value) -> bool:
        """Whether ``PreviewSource`` ``value`` uses the lidar."""
        if value not in PREVIEW_SOURCES or (value == "lidar" and self.preview is None):
            raise ControlDefinitionError(f"PreviewSource is {value!r}; this library reads "
                                         f"{'lidar or none' if self.preview is not None else 'none'}"
                                         f"{'' if self.preview is not None else ' (export with --preview lidar)'}.")
        return value == "lidar"


def _number(key: str, value) -> float:
    try:
        return float(value)
    except (TypeError, ValueError):
        raise ControlDefinitionError(f"{key} is {value!r}; expected a number.") from None


def _same_number(value, written: str) -> bool:
    try:
        a, b = float(value), float(written)
    except (TypeError, ValueError):
        return False
    return abs(a - b) <= 1e-9 * max(1.0, abs(b))


def _inside(x: float, lo: float, hi: float, open_lo: bool, open_hi: bool) -> bool:
    if math.isnan(x):
        return False
    return (x > lo if open_lo else x >= lo) and (x < hi if open_hi else x <= hi)


def _interval(lo: float, hi: float, open_lo: bool, open_hi: bool) -> str:
    return f"{'(' if open_lo else '['}{lo:.9g}, {hi:.9g}{')' if open_hi else ']'}"


def _range_text(lo: float, hi: float, open_lo: bool, open_hi: bool) -> str:
    return f"a value in {_interval(lo, hi, open_lo, open_hi)}"


def runtime_layout(nmpc, estimator, preview=None) -> RuntimeLayout:
    """The run-time settings of ``nmpc`` (a :class:`~.nmpc.TurbineNMPC`) exported with ``estimator`` and
    ``preview`` (module docstring).

    Raises
    ------
    ControlDefinitionError
        An OCP whose residual rows or limits are not those :class:`~.nmpc.TurbineNMPC` builds.
    """
    t = nmpc.tuning
    stage, term = nmpc.residual_scales
    scales = tuple(dict.fromkeys(stage + term)) + (("terminal_factor",) if term else ())
    values = [float(getattr(t, s)) for s in scales]
    P = nmpc.nmpc.transcription.problem
    _check_rows(P, stage, term, t)
    limits = _exported_limits(P)
    ranges = [(0.0, math.inf, True, False) for _ in scales]
    if term:
        ranges[-1] = (0.0, math.inf, True, True)
    for i, (lo, hi) in enumerate(limits):
        if i < 2:                                        # pitch, torque: within the exported range
            ranges += [(lo, hi, False, False)] * 2
        else:                                            # rates: lower in [lo, 0), upper in (0, hi]
            ranges += [(lo, 0.0, False, True), (0.0, hi, True, False)]
    fixed = [("Horizon", str(int(t.horizon)), "export with another NMPCTuning.horizon"),
             ("NMPCSampleTime", repr(float(t.dt)), "export with another NMPCTuning.dt"),
             ("Estimator", estimator.kind, "export with --estimator"),
             ("EstimatorSampleTime", repr(float(estimator.dt)), "export with another estimator sample time"),
             ("PowerReference", t.power_reference, "export with another NMPCTuning.power_reference")]
    if preview is not None:
        fixed += [("LidarBeams", str(int(preview.n_beams)), "export for the lidar's beams"),
                  ("LidarWindow", repr(float(preview.window)), "export with another PreviewSettings.window")]
    return RuntimeLayout(scales=scales, exported=np.array(values + [v for b in limits for v in b], dtype=float),
                         stage_rows=tuple(scales.index(s) for s in stage),
                         terminal_rows=tuple(scales.index(s) for s in term), ranges=tuple(ranges),
                         fixed=tuple(fixed), preview=preview)


def _check_rows(P, stage: tuple, term: tuple, tuning) -> None:
    n_r, n_rN = P.path.size1_out(2), P.terminal.size1_out(1)
    if (n_r, n_rN) != (len(stage), len(term)):
        raise ControlDefinitionError(f"the OCP has {n_r} stage and {n_rN} terminal residual rows; the NMPC's cost "
                                     f"names {len(stage)} and {len(term)} (an OCP changed after TurbineNMPC built it "
                                     "cannot have run-time cost scales).")
    for s in stage + term:
        if not math.isfinite(getattr(tuning, s)):
            raise ControlDefinitionError(f"NMPCTuning.{s} is inf but the OCP has its term.")


def _exported_limits(P) -> list[tuple[float, float]]:
    names = P.names
    out = []
    for kind, name in _LIMITED:
        if name not in names.get(kind, ()):
            raise ControlDefinitionError(f"the exported NMPC bounds {name}; its OCP has no {kind} named so "
                                         f"({names.get(kind)}).")
        i = names[kind].index(name)
        lo, hi = (P.lbx, P.ubx) if kind == "x" else (P.lbu, P.ubu)
        if not (math.isfinite(lo[i]) and math.isfinite(hi[i])):
            raise ControlDefinitionError(f"the exported NMPC needs finite bounds on {name}; got [{lo[i]}, {hi[i]}].")
        out.append((float(lo[i]), float(hi[i])))
    return out


def weighted_problem(P, layout: RuntimeLayout):
    """``P`` with residual rows scaled by factors appended to its stage parameters: ``d' = [d; a; b]``, the stage
    residual ``a ∘ r``, the terminal ``b ∘ r_N`` (:meth:`RuntimeLayout.factors` gives ``a``, ``b``)."""
    n_d, n_r, n_rN = P.n_d, len(layout.stage_rows), len(layout.terminal_rows)

    def sym(fn):
        return ca.SX if fn.is_a("SXFunction") else ca.MX

    S = sym(P.path)
    x, u, d, p = S.sym("x", P.n_x), S.sym("u", P.n_u), S.sym("d", n_d + n_r + n_rN), S.sym("p", P.n_p)
    f, c, r, l_ = P.path(x, u, d[:n_d], p)
    path = ca.Function("ocp_stage", [x, u, d, p], [f, c, r * d[n_d:n_d + n_r], l_], ["x", "u", "d", "p"],
                       ["f", "c", "r", "l"])
    S = sym(P.terminal)
    x, d, p = S.sym("x", P.n_x), S.sym("d", n_d + n_r + n_rN), S.sym("p", P.n_p)
    cN, rN, lN = P.terminal(x, d[:n_d], p)
    terminal = ca.Function("ocp_terminal", [x, d, p], [cN, rN * d[n_d + n_r:], lN], ["x", "d", "p"], ["c", "r", "l"])
    jac = P.dynamics_jacobian
    if jac is not None:
        x, u, d, p = (ca.MX.sym(s, n) for s, n in (("x", P.n_x), ("u", P.n_u), ("d", n_d + n_r + n_rN),
                                                    ("p", P.n_p)))
        jac = ca.Function(jac.name(), [x, u, d, p], jac(x, u, d[:n_d], p), ["x", "u", "d", "p"], ["f", "J"])
    names = dict(P.names, d=list(P.names.get("d", [])) + [f"factor:{i}" for i in range(n_r + n_rN)])
    return dataclasses.replace(P, path=path, terminal=terminal, dynamics_jacobian=jac, names=names)


def symbolic_bounds(P, layout: RuntimeLayout, s: ca.MX) -> list[ca.MX]:
    """``(lbw, ubw, lbg, ubg)`` of ``P`` with the limits of the settings vector ``s`` (module docstring)."""
    lim = s[len(layout.scales):]
    lo = {"x": [ca.MX(v) for v in P.lbx], "u": [ca.MX(v) for v in P.lbu]}
    hi = {"x": [ca.MX(v) for v in P.ubx], "u": [ca.MX(v) for v in P.ubu]}
    for k, (kind, name) in enumerate(_LIMITED):
        i = P.names[kind].index(name)
        lo[kind][i], hi[kind][i] = lim[2 * k], lim[2 * k + 1]

    def w(side):
        stage = ca.vertcat(*side["x"], *side["u"])
        return ca.vertcat(ca.repmat(stage, P.N, 1), *side["x"])

    _, _, lbg, ubg = P.bounds()
    return [w(lo), w(hi), ca.MX(ca.DM(lbg)), ca.MX(ca.DM(ubg))]


#: The run-time settings in the exported library's C (:mod:`.discon_nmpc`): the settings vector ``settings`` (read
#: by the generated Functions; ``LIMITS`` and ``RATE_LIM`` its limits), the preview's switch and parameters, and the
#: input-file hooks ``input_begin``, ``input_key``, ``input_end`` the wrapper's ``read_input`` calls.
SETTINGS_C = r"""
/* ---- run-time settings (mbsym.wind.mpc.runtime_settings: the same checks in Python) ---- */
#define NSET {n_set}
#define NSCALE {n_scale}
#define NFIXED {n_fixed}
#define SET_LIDAR {lidar}
static const double SETTINGS0[NSET] = {{{exported}}};
static const char *SET_KEY[NSET] = {{{keys}}};
static const double SET_MIN[NSET] = {{{mins}}};
static const double SET_MAX[NSET] = {{{maxs}}};
static const int SET_OPEN[NSET] = {{{opens}}};          /* 1: the minimum excluded, 2: the maximum, 3: both */
static const char *FIXED_KEY[NFIXED] = {{{fixed_keys}}};
static const char *FIXED_VALUE[NFIXED] = {{{fixed_values}}};
static const char *FIXED_HOW[NFIXED] = {{{fixed_how}}};
static double settings[NSET];
static int pv_use;
static double pv_dist, pv_tadv;
#define LIMITS (settings + NSCALE)
#define RATE_LIM (settings + NSCALE + 4)

static int parse_number(const char *text, double *v)
{{
    char *end;
    *v = strtod(text, &end);
    return end != text && *end == '\0';
}}

static void input_begin(void)
{{
    memcpy(settings, SETTINGS0, sizeof settings);
    pv_use = SET_LIDAR; pv_dist = {distance!r}; pv_tadv = {advection!r};
}}

static int input_key(const char *file, const char *value, const char *key, char *err, size_t n_err)
{{
    int i, o;
    double v, c;
    for (i = 0; i < NFIXED; ++i) {{
        if (strcmp(key, FIXED_KEY[i]) != 0) continue;
        if (strcmp(value, FIXED_VALUE[i]) == 0 || (parse_number(value, &v) && parse_number(FIXED_VALUE[i], &c)
                                                   && fabs(v - c) <= 1e-9 * fmax(1.0, fabs(c)))) return 1;
        snprintf(err, n_err, "%s: %s is '%s'; this library is compiled for %s (%s)", file, key, value, FIXED_VALUE[i],
                 FIXED_HOW[i]);
        return -1;
    }}
    for (i = 0; i < NSET; ++i) {{
        if (strcmp(key, SET_KEY[i]) != 0) continue;
        o = SET_OPEN[i];
        if (!parse_number(value, &v) || isnan(v) || ((o & 1) ? v <= SET_MIN[i] : v < SET_MIN[i])
            || ((o & 2) ? v >= SET_MAX[i] : v > SET_MAX[i])) {{
            snprintf(err, n_err, "%s: %s is '%s'; expected a value in %c%.9g, %.9g%c", file, key, value,
                     (o & 1) ? '(' : '[', SET_MIN[i], SET_MAX[i], (o & 2) ? ')' : ']');
            return -1;
        }}
        settings[i] = v;
        return 1;
    }}
    if (strcmp(key, "PreviewSource") == 0) {{
        if (strcmp(value, "none") == 0) {{ pv_use = 0; return 1; }}
        if (SET_LIDAR && strcmp(value, "lidar") == 0) {{ pv_use = 1; return 1; }}
        snprintf(err, n_err, "%s: PreviewSource is '%s'; this library reads %s", file, value,
                 SET_LIDAR ? "lidar or none" : "none (export with --preview lidar)");
        return -1;
    }}
    if (SET_LIDAR && (strcmp(key, "LidarDistance") == 0 || strcmp(key, "LidarAdvectionTime") == 0)) {{
        if (!parse_number(value, &v) || !isfinite(v) || v <= 0.0) {{
            snprintf(err, n_err, "%s: %s is '%s'; expected a finite number > 0", file, key, value);
            return -1;
        }}
        if (key[5] == 'D') pv_dist = v; else pv_tadv = v;
        return 1;
    }}
    snprintf(err, n_err, "%s: unknown key '%s'; this library reads the keys of the input file mbsym export-discon "
             "writes beside it (docs/discon_export.md)", file, key);
    return -1;
}}

static int input_end(const char *file, char *err, size_t n_err)
{{
    if (!(LIMITS[0] < LIMITS[1] && LIMITS[2] < LIMITS[3])) {{
        snprintf(err, n_err, "%s: PitchMin %g must be below PitchMax %g and TorqueMin %g below TorqueMax %g", file,
                 LIMITS[0], LIMITS[1], LIMITS[2], LIMITS[3]);
        return -1;
    }}
    return 0;
}}
"""


def _c_strings(values) -> str:
    return ", ".join('"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"' for v in values)


def _c_float(v: float) -> str:
    return "INFINITY" if v == math.inf else ("-INFINITY" if v == -math.inf else repr(float(v)))


def settings_c(layout: RuntimeLayout) -> str:
    """:data:`SETTINGS_C` for ``layout``."""
    pv = layout.preview
    return SETTINGS_C.format(
        n_set=layout.exported.size, n_scale=len(layout.scales), n_fixed=len(layout.fixed),
        lidar=int(pv is not None), exported=", ".join(_c_float(v) for v in layout.exported),
        keys=_c_strings(layout.keys), mins=", ".join(_c_float(r[0]) for r in layout.ranges),
        maxs=", ".join(_c_float(r[1]) for r in layout.ranges),
        opens=", ".join(str(int(r[2]) + 2 * int(r[3])) for r in layout.ranges),
        fixed_keys=_c_strings(k for k, _, _ in layout.fixed), fixed_values=_c_strings(v for _, v, _ in layout.fixed),
        fixed_how=_c_strings(h for _, _, h in layout.fixed), distance=float(pv.distance) if pv else 0.0,
        advection=float(pv.advection_time) if pv else 0.0)


def input_lines(layout: RuntimeLayout) -> list[str]:
    """The input file's run-time and compiled-in keys (``value  Key  ! comment``)."""
    def line(value, key, comment):
        return f"{value:<24} {key:<22} ! {comment}"

    out = ["! run-time settings (read at the first call; docs/discon_export.md, \"The NMPC's input file\"):",
           "! cost scales (NMPCTuning, same names; the deviation that costs one unit; inf: no term):"]
    for i, s in enumerate(layout.scales):
        key, unit = SCALE_KEYS[s]
        what = "terminal weights of " + ", ".join(sorted({layout.scales[j] for j in layout.terminal_rows})) + \
            ", in stage weights" if s == "terminal_factor" else f"NMPCTuning.{s}"
        out.append(line(_text(layout.exported[i]), key, f"{what} [{unit}]"))
    off = [SCALE_KEYS[s][0] for s in SCALE_KEYS if s not in layout.scales]
    if off:
        out.append(f"! not in the exported cost (export with a finite scale to add them): {', '.join(off)}")
    out.append("! limits of the NMPC's demands and rates, within the exported ones (narrow them here):")
    n = len(layout.scales)
    for i, (key, unit) in enumerate(LIMIT_KEYS):
        out.append(line(_text(layout.exported[n + i]), key, f"[{unit}] in {_interval(*layout.ranges[n + i])}"))
    pv = layout.preview
    if pv is not None:
        out += [line("lidar", "PreviewSource", "lidar or none (the estimated wind held over the horizon)"),
                line(_text(pv.distance), "LidarDistance", "mean focal distance upstream of the rotor [m]"),
                line(_text(pv.advection_time), "LidarAdvectionTime", "advection-speed filter time constant [s]")]
    else:
        out.append(line("none", "PreviewSource", "no preview compiled in (export with --preview lidar)"))
    out.append("! compiled in (checked; another value is an error: export again):")
    out += [line(v, k, how) for k, v, how in layout.fixed]
    return out


def _text(v: float) -> str:
    return "inf" if v == math.inf else repr(float(v))
