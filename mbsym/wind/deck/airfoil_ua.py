"""Unsteady-aerodynamics (Beddoes-Leishman) constants of an AeroDyn 15 airfoil table.

An AirfoilInfo table with ``InclUAdata = True`` lists 36 constants before ``NumAlf``;
any of them may be missing, and the time constants (``T_f0`` ... ``filtCutOff``) may
read ``"Default"``.  AeroDyn then fills them in: fixed defaults for the time
constants and model coefficients, and values derived from the steady polar for the
angles, slopes and critical normal-force coefficients.  With ``InclUAdata = False``
it does the same for every constant.

:func:`ua_coefficients_from_polar` reproduces that step for the Beddoes-Leishman
models that work on the normal-force coefficient Cn (AeroDyn ``UA_Mod`` 2 and 3,
not the Cl-based HGM/Oye branch).  It is a re-implementation in numpy of the
behaviour of OpenFAST v5.0.0 ``AirfoilInfo.f90`` (``ReadAFfile``,
``CalculateUACoeffs``, ``ComputeUA360_AttachedFlow``,
``ComputeUA360_updateSeparationF``) and of the NWTC library routines it calls
(``kernelSmoothing``, ``InterpStp``, ``InterpExtrapStp``, ``fZeros``,
``EqualRealNos``); the facts and constants taken from there are marked
"OpenFAST v5" below.  It computes in double precision, like the default (CMake)
OpenFAST v5 build.

Units: angles in rad (the file gives ``alpha0``, ``alpha1``, ``alpha2``,
``alphaUpper``, ``alphaLower``, ``UACutout``, ``UACutout_delta`` in deg, and
AeroDyn converts them), ``C_nalpha``/``C_lalpha`` in 1/rad, time constants in
semi-chords [-], ``filtCutOff`` a reduced frequency [-] (default 0.5, although
the comment of many files says Hz).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields
from typing import Any, Mapping

import numpy as np

from ...exceptions import ParameterError
from ._record import _Record

__all__ = ["UACoefficients", "ua_coefficients_from_polar", "UA_KEYS"]

_DEG = math.pi / 180.0

#: The unsteady-aero keys of an AirfoilInfo table, in file order (OpenFAST v5 ReadAFfile).
UA_KEYS: tuple[str, ...] = (
    "alpha0", "alpha1", "alpha2", "alphaUpper", "alphaLower", "eta_e", "C_nalpha", "C_lalpha",
    "T_f0", "T_V0", "T_p", "T_VL", "b1", "b2", "b5", "A1", "A2", "A5", "S1", "S2", "S3", "S4",
    "Cn1", "Cn2", "St_sh", "Cd0", "Cm0", "k0", "k1", "k2", "k3", "k1_hat", "x_cp_bar",
    "UACutout", "UACutout_delta", "filtCutOff")

# Keys the file gives in deg; AeroDyn multiplies them by pi/180 (OpenFAST v5 ReadAFfile).
_ANGLE_KEYS = frozenset({"alpha0", "alpha1", "alpha2", "alphaUpper", "alphaLower", "UACutout",
                         "UACutout_delta"})

# Keys read with ParseVarWDefault: the word "Default" selects the default (OpenFAST v5
# ReadAFfile).  The other keys (ParseVar) accept numbers only.
_KEYWORD_DEFAULT_KEYS = frozenset({"T_f0", "T_V0", "T_p", "T_VL", "b1", "b2", "b5", "A1", "A2",
                                   "A5", "St_sh", "x_cp_bar", "UACutout", "UACutout_delta",
                                   "filtCutOff"})

# Fixed defaults for UA_Mod 2/3 (OpenFAST v5 CalculateUACoeffs), in UACoefficients units.
_FIXED_DEFAULTS: dict[str, float] = {
    "eta_e": 1.0, "k0": 0.0, "k1": 0.0, "k2": 0.0, "k3": 0.0, "k1_hat": 0.0,
    "S1": 0.0, "S2": 0.0, "S3": 0.0, "S4": 0.0,
    "T_f0": 3.0, "T_V0": 6.0, "T_p": 1.7, "T_VL": 11.0, "b1": 0.14, "b2": 0.53, "b5": 5.0,
    "A1": 0.3, "A2": 0.7, "A5": 1.0, "x_cp_bar": 0.2, "filtCutOff": 0.5,
    "St_sh": 0.19, "UACutout": 45.0 * _DEG, "UACutout_delta": 5.0 * _DEG,
}

# Constants of the polar analysis (OpenFAST v5 CalculateUACoeffs / ComputeUA360_*).
_ALPHA_RANGE = 20.0 * _DEG        # |alpha| window searched for the attached-flow region
_SLOPE_DROP = 0.90                # Cn slope below this fraction of its maximum ends the region
_F_CRITICAL = 0.7                 # separation point f at alpha1 / alpha2
_SMOOTH_RADIUS = 2.0 * _DEG       # triweight kernel radius for the Cn slope
_REVERSE_SLOPE = -2.0 * math.pi   # Cn slope of the reverse-flow line [1/rad]
_CYLINDER = {"alpha0": 0.0, "C_nalpha": 0.0, "C_lalpha": 0.0, "Cm0": 0.0, "alpha1": 10.0 * _DEG,
             "alpha2": -10.0 * _DEG, "Cn1": 0.0, "Cn2": 0.0, "alphaLower": -5.0 * _DEG,
             "alphaUpper": 5.0 * _DEG}


@dataclass(frozen=True)
class UACoefficients(_Record):
    """Beddoes-Leishman constants of one airfoil table, as AeroDyn uses them (immutable).

    Attributes
    ----------
    alpha0, alpha1, alpha2 : float
        Zero-lift AoA and the AoA above / below it where the separation point f is 0.7 [rad].
    eta_e : float
        Recovery factor [-].
    C_nalpha, C_lalpha : float
        Slopes of Cn and Cl in the attached-flow region [1/rad].
    T_f0, T_V0, T_p, T_VL : float
        Time constants of f, of the vortex-lift decay, of the leading-edge pressure and of
        the vortex advection [semi-chords, -].
    b1, b2, b5, A1, A2, A5 : float
        Indicial-function constants [-].
    S1, S2, S3, S4, k0, k1, k2, k3, k1_hat, x_cp_bar : float
        Curve-fit constants of UA_Mod 1 (unused by UA_Mod 2/3) [-].
    Cn1, Cn2 : float
        Critical Cn at leading-edge separation for positive / negative AoA [-].
    St_sh : float
        Strouhal shedding number [-].
    Cd0, Cm0 : float
        Drag coefficient subtracted in Cn (AeroDyn's default: the minimum Cd within
        |AoA| <= 20 deg) and Cm at ``alpha0`` [-].
    UACutout, UACutout_delta : float
        |AoA| above which UA is off, and the width of the blend below it [rad].
    filtCutOff : float
        Cut-off reduced frequency of the AoA low-pass filter [-].
    alphaUpper, alphaLower : float
        Ends of the fully attached region [rad]: the table angles AeroDyn snaps them to
        (OpenFAST v5 ComputeUA360_AttachedFlow), also when the file gives them.
    computed : frozenset of str
        Names whose value AeroDyn computed (missing line, ``"Default"``, or
        ``InclUAdata = False``) instead of reading it.
    """

    alpha0: float
    alpha1: float
    alpha2: float
    eta_e: float
    C_nalpha: float
    C_lalpha: float
    T_f0: float
    T_V0: float
    T_p: float
    T_VL: float
    b1: float
    b2: float
    b5: float
    A1: float
    A2: float
    A5: float
    S1: float
    S2: float
    S3: float
    S4: float
    Cn1: float
    Cn2: float
    St_sh: float
    Cd0: float
    Cm0: float
    k0: float
    k1: float
    k2: float
    k3: float
    k1_hat: float
    x_cp_bar: float
    UACutout: float
    UACutout_delta: float
    filtCutOff: float
    alphaUpper: float
    alphaLower: float
    computed: frozenset[str] = field(default_factory=frozenset)

    def __post_init__(self) -> None:
        for name in UA_KEYS:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)) \
                    or not math.isfinite(value):
                raise ParameterError(f"UACoefficients.{name} must be a finite number; got {value!r}.")
            object.__setattr__(self, name, float(value))
        computed = frozenset(self.computed)
        unknown = sorted(computed - set(UA_KEYS))
        if unknown:
            raise ParameterError(f"UACoefficients.computed names unknown constants {unknown}; "
                                 f"expected names among {list(UA_KEYS)}.")
        object.__setattr__(self, "computed", computed)

    @property
    def UACutout_blend(self) -> float:  # noqa: N802 (AeroDyn's name)
        """|AoA| [rad] below which UA is fully on: ``max(0, |UACutout| - |UACutout_delta|)``."""
        return max(0.0, abs(self.UACutout) - abs(self.UACutout_delta))

    def to_dict(self) -> dict[str, Any]:
        """Return a JSON-compatible dict (``computed`` as a sorted list)."""
        data = {f.name: getattr(self, f.name) for f in fields(self)}
        data["computed"] = sorted(self.computed)
        return data


# ----------------------------------------------------------------------------- helpers
def _equal_real(a: float, b: float, dtype: type = np.float64) -> bool:
    """NWTC ``EqualRealNos`` in ``dtype``: |a-b| <= max(|a+b|, 1) * 50 eps."""
    a_, b_ = dtype(a), dtype(b)
    tol = dtype(100.0) * np.finfo(dtype).eps / dtype(2.0)
    return bool(abs(a_ - b_) <= max(abs(a_ + b_), dtype(1.0)) * tol)


def _fsum_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares line ``y = slope x + intercept`` with exactly rounded sums (reproducible)."""
    n = len(x)
    x_mean, y_mean = math.fsum(x) / n, math.fsum(y) / n
    dx = x - x_mean
    slope = math.fsum(dx * (y - y_mean)) / math.fsum(dx * dx)
    return slope, y_mean - slope * x_mean


def _triweight_smooth(x: np.ndarray, f: np.ndarray, radius: float) -> np.ndarray:
    """Triweight-kernel smoothing of f(x) (NWTC ``kernelSmoothing``, kernel clipped at |u| = 1)."""
    u = np.clip((x[None, :] - x[:, None]) / radius, -1.0, 1.0)
    t = 1.0 - u * u
    k = (35.0 / 32.0) * t * t * t
    out = np.empty_like(f)
    for j in range(len(x)):
        total = math.fsum(k[j])
        out[j] = math.fsum(k[j] * f) / total if total > 0.0 else 0.0
    return out


def _zero_crossings(x: np.ndarray, f: np.ndarray, period: float | None = None) -> list[float]:
    """Linear-interpolated sign changes of f(x) (NWTC ``fZeros``; ``period``: wrap last->first)."""
    roots = []
    for j in range(1, len(f)):
        if (f[j - 1] < 0.0) != (f[j] < 0.0):
            roots.append(x[j] - f[j] * (x[j] - x[j - 1]) / (f[j] - f[j - 1]))
    if period is not None and (f[-1] < 0.0) != (f[0] < 0.0):
        roots.append(x[0] - f[0] * (x[0] - x[-1] + period) / (f[0] - f[-1]))
    return roots


def _interp_extrap(xval: float, xs: list[float], fs: list[float], ind: int) -> tuple[float, int]:
    """Linear inter/extrapolation with a remembered lower index (NWTC ``InterpExtrapStp``)."""
    n = len(xs)
    if xval <= xs[0]:
        ind = 0
    elif xval >= xs[-1]:
        ind = n - 2
    else:
        ind = max(min(ind, n - 2), 0)
        for _ in range(4 * n):
            if xval < xs[ind]:
                ind -= 1
            elif xval >= xs[ind + 1]:
                ind += 1
            else:
                break
            if not 0 <= ind <= n - 2:
                raise ParameterError("the attached-flow Cn line of the polar is degenerate "
                                     f"(break points {xs}); check the table near +/-180 deg.")
    value = (fs[ind + 1] - fs[ind]) * (xval - xs[ind]) / (xs[ind + 1] - xs[ind]) + fs[ind]
    return value, ind


def _first(mask: np.ndarray) -> int:
    """0-based index of the first True, or -1 (Fortran minloc of an ascending array)."""
    hits = np.flatnonzero(mask)
    return int(hits[0]) if hits.size else -1


def _last(mask: np.ndarray) -> int:
    """0-based index of the last True, or -1 (Fortran maxloc of an ascending array)."""
    hits = np.flatnonzero(mask)
    return int(hits[-1]) if hits.size else -1


# ----------------------------------------------------------------------------- public
def ua_coefficients_from_polar(alpha: np.ndarray, cl: np.ndarray, cd: np.ndarray,
                               cm: np.ndarray | None, given: Mapping[str, float | None],
                               has_cm: bool) -> UACoefficients:
    """The UA constants AeroDyn (UA_Mod 2/3) uses for one airfoil table.

    Every key of :data:`UA_KEYS` that ``given`` lacks or maps to None gets AeroDyn's value:
    a fixed default, or one derived from the polar (``Cd0``, ``alpha0``, ``C_nalpha``,
    ``C_lalpha``, ``Cm0``, ``alphaUpper``, ``alphaLower``, ``alpha1``, ``alpha2``, ``Cn1``,
    ``Cn2``), with AeroDyn's special values for a cylinder-like polar (constant Cd, or
    Cl < 0.01, within |AoA| <= 20 deg).  ``alphaUpper``/``alphaLower`` are then snapped
    to table angles, also when given.

    Parameters
    ----------
    alpha : array_like, shape (n,)
        Angle of attack [rad], strictly increasing, n >= 3 (a non-constant table).
    cl, cd : array_like, shape (n,)
        Lift and drag coefficients [-].
    cm : array_like, shape (n,), or None
        Pitching-moment coefficient [-]; used only if ``has_cm``.
    given : mapping of str to float or None
        Values read from the file, in the units of :class:`UACoefficients` (angles in rad,
        already converted from the file's deg); None = compute.
    has_cm : bool
        Whether the table has a Cm column (AeroDyn ``InCol_Cm > 0``); if not, ``Cm0`` = 0.

    Returns
    -------
    UACoefficients
        ``computed`` names the keys that were not given.

    Raises
    ------
    ParameterError
        If the arrays are malformed, ``given`` names an unknown key or a non-finite value,
        or no table angle lies within |AoA| <= 20 deg (AeroDyn would index out of bounds).
    """
    alpha, cl, cd, cm = _check_polar(alpha, cl, cd, cm, has_cm)
    values: dict[str, float | None] = {k: None for k in UA_KEYS}
    for key, value in given.items():
        if key not in values:
            raise ParameterError(f"given names the unknown UA constant {key!r}; expected names "
                                 f"among {list(UA_KEYS)}.")
        if value is not None:
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)) \
                    or not math.isfinite(value):
                raise ParameterError(f"given[{key!r}] must be a finite number or None; got "
                                     f"{value!r}.")
            values[key] = float(value)
    computed = frozenset(k for k, v in values.items() if v is None)
    for key, default in _FIXED_DEFAULTS.items():
        if values[key] is None:
            values[key] = default
    _polar_derived(alpha, cl, cd, cm if has_cm else None, values, computed)
    return UACoefficients(**values, computed=computed)  # type: ignore[arg-type]


def _check_polar(alpha: Any, cl: Any, cd: Any, cm: Any, has_cm: bool
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    arrays = []
    for name, value in (("alpha", alpha), ("cl", cl), ("cd", cd),
                        ("cm", cm if has_cm else np.zeros(np.shape(alpha)))):
        arr = np.asarray(value, dtype=float)
        if arr.ndim != 1 or not np.all(np.isfinite(arr)):
            raise ParameterError(f"{name} must be a 1-D array of finite numbers; got shape "
                                 f"{arr.shape}.")
        arrays.append(arr)
    if any(a.shape != arrays[0].shape for a in arrays):
        raise ParameterError("alpha, cl, cd (and cm) must have the same length; got "
                             f"{[a.size for a in arrays]}.")
    if arrays[0].size < 3 or np.any(np.diff(arrays[0]) <= 0):
        raise ParameterError("alpha must hold at least 3 strictly increasing angles [rad] (AeroDyn "
                             "computes UA constants only for non-constant tables).")
    return arrays[0], arrays[1], arrays[2], arrays[3]


def _polar_derived(alpha: np.ndarray, cl: np.ndarray, cd: np.ndarray, cm: np.ndarray | None,
                   v: dict[str, Any], computed: frozenset[str]) -> None:
    """Fill the polar-derived constants of ``v`` (OpenFAST v5 CalculateUACoeffs, UA_Mod 2/3)."""
    near = np.abs(alpha) <= _ALPHA_RANGE
    if not near.any():
        raise ParameterError("the polar has no angle of attack within +/-20 deg; AeroDyn cannot "
                             "derive the UA constants from it. Refine the table.")
    candidates = np.flatnonzero(near)
    i_cdmin = int(candidates[np.argmin(cd[candidates])])  # first minimum, as Fortran minloc
    if cd[near].max() == cd[near].min() or cl[near].max() < 0.01:  # cylinder-like polar
        if "Cd0" in computed:
            v["Cd0"] = float(cd[i_cdmin])
        for key, value in _CYLINDER.items():
            if key in computed:
                v[key] = value
        i_lower, i_upper = _attached_bounds(alpha, v["alphaLower"], v["alphaUpper"])
        v["alphaLower"], v["alphaUpper"] = float(alpha[i_lower]), float(alpha[i_upper])
        return
    if "Cd0" in computed:
        v["Cd0"] = float(cd[i_cdmin])
    cn = _normal_coefficient(alpha, cl, cd, v["Cd0"])
    mid = 0.5 * (alpha[1:] + alpha[:-1])
    slope = _triweight_smooth(mid, np.diff(cn) / np.diff(alpha), _SMOOTH_RADIUS)
    m = mid.size
    i_hi_lim = min(_last(mid < _ALPHA_RANGE) + 1, m - 1)
    i_lo_lim = max(_first(mid > -_ALPHA_RANGE) - 1, 0)
    if i_hi_lim - i_lo_lim < 3:
        i_hi_lim = min(i_lo_lim + 2, m - 1)
    if i_hi_lim - i_lo_lim < 3:
        i_lo_lim = max(i_hi_lim - 2, 0)
    _attached_region(alpha, mid, slope, i_cdmin, i_lo_lim, i_hi_lim, v, computed)
    if computed & {"C_nalpha", "C_lalpha", "alpha0"}:
        _lift_slopes(alpha, cn, cl, i_lo_lim, i_hi_lim, v, computed)
    if "Cm0" in computed:
        v["Cm0"] = float(np.interp(v["alpha0"], alpha, cm)) if cm is not None else 0.0
    i_lower, i_upper = _attached_bounds(alpha, v["alphaLower"], v["alphaUpper"])
    v["alphaLower"], v["alphaUpper"] = float(alpha[i_lower]), float(alpha[i_upper])
    f_st = _separation_function(alpha, cn, i_lower, i_upper)
    if "alpha1" in computed:
        guess = max(_first((alpha >= v["alphaUpper"]) & (f_st <= _F_CRITICAL)), 0)
        roots = _zero_crossings(alpha[i_upper:], _F_CRITICAL - f_st[i_upper:])
        v["alpha1"] = _pick_root(roots, float(alpha[guess]))
    if "alpha2" in computed:
        # AeroDyn reads alpha(0) if no angle qualifies (out of bounds); the first angle here.
        guess = max(_last((alpha <= v["alphaLower"]) & (f_st <= _F_CRITICAL)), 0)
        roots = _zero_crossings(alpha[:i_lower + 1], _F_CRITICAL - f_st[:i_lower + 1])
        v["alpha2"] = _pick_root(roots, float(alpha[guess]))
    if "Cn1" in computed:
        v["Cn1"] = float(np.interp(v["alpha1"], alpha, cn))
    if "Cn2" in computed:
        v["Cn2"] = float(np.interp(v["alpha2"], alpha, cn))


def _normal_coefficient(alpha: np.ndarray, cl: np.ndarray, cd: np.ndarray, cd0: float
                        ) -> np.ndarray:
    """Cn = Cl cos(alpha) + (Cd - Cd0) sin(alpha) (OpenFAST v5 Calculate_Cn)."""
    cos = np.array([math.cos(a) for a in alpha])  # libm, not numpy's SIMD: reproducible
    sin = np.array([math.sin(a) for a in alpha])
    return cl * cos + (cd - cd0) * sin


def _attached_region(alpha: np.ndarray, mid: np.ndarray, slope: np.ndarray, i_cdmin: int,
                     i_lo_lim: int, i_hi_lim: int, v: dict[str, Any], computed: frozenset[str]
                     ) -> None:
    """alphaUpper/alphaLower: where the smoothed Cn slope falls below 90 % of its maximum."""
    m = mid.size
    alpha_at_cdmin = float(alpha[i_cdmin])
    slope_at_cdmin = float(np.interp(alpha_at_cdmin, mid, slope))
    i_high2 = i_hi_lim
    if "alphaUpper" in computed:
        i_high = i_hi_lim if i_hi_lim >= i_cdmin else m - 1
        best, i_high2 = slope_at_cdmin, i_cdmin  # i_cdmin if the scan is empty
        for row in range(i_cdmin, i_high + 1):
            i_high2 = row
            if slope[row] > best:
                best = slope[row]
            elif slope[row] < _SLOPE_DROP * best:
                break
        if i_high2 == i_cdmin:
            v["alphaUpper"] = alpha_at_cdmin
        else:
            i_high2 = min(max(0, i_high2 - 1), m - 1)
            v["alphaUpper"] = float(mid[i_high2])
    if "alphaLower" in computed:
        best = slope_at_cdmin
        i_high = max(0, min(i_high2, i_cdmin, m - 1))
        i_low = i_lo_lim if i_high >= i_lo_lim else 0
        i_low2 = i_high
        for row in range(i_high, i_low - 1, -1):
            i_low2 = row
            if slope[row] > best:
                best = slope[row]
            elif slope[row] < _SLOPE_DROP * best:
                break
        if i_low2 == i_cdmin:
            v["alphaLower"] = alpha_at_cdmin
        else:
            i_low2 = min(max(0, i_low2 + 1), m - 1)
            v["alphaLower"] = float(mid[i_low2])


def _lift_slopes(alpha: np.ndarray, cn: np.ndarray, cl: np.ndarray, i_lo_lim: int, i_hi_lim: int,
                 v: dict[str, Any], computed: frozenset[str]) -> None:
    """C_nalpha, C_lalpha, alpha0: line fits over the inner 60 % of [alphaLower, alphaUpper]."""
    margin = 0.2 * (v["alphaUpper"] - v["alphaLower"])
    lo = i_lo_lim
    while lo < i_hi_lim - 1 and alpha[lo] < v["alphaLower"] + margin:
        lo += 1
    hi = i_hi_lim
    while hi > lo + 1 and alpha[hi] > v["alphaUpper"] - margin:
        hi -= 1
    if hi - lo + 1 < 2:  # AeroDyn's fallback (Calculate_C_alpha)
        cn_alpha = cl_alpha = float(np.finfo(float).eps)
        alpha0 = 0.0
    else:
        cn_alpha, cn_0 = _fsum_fit(alpha[lo:hi + 1], cn[lo:hi + 1])
        cl_alpha, _ = _fsum_fit(alpha[lo:hi + 1], cl[lo:hi + 1])
        alpha0 = -cn_0 / cn_alpha if not _equal_real(cn_alpha, 0.0) else 0.0
    for key, value in (("C_nalpha", cn_alpha), ("C_lalpha", cl_alpha), ("alpha0", alpha0)):
        if key in computed:
            v[key] = float(value)


def _attached_bounds(alpha: np.ndarray, alpha_lower: float, alpha_upper: float
                     ) -> tuple[int, int]:
    """Table indices bounding the attached region (OpenFAST v5 Compute_iLoweriUpper), 0-based."""
    n = alpha.size
    i_lower = max(0, min(n - 2, _first(alpha >= alpha_lower)))
    i_upper = max(1, min(n - 1, _last(alpha <= alpha_upper)))
    return i_lower, i_upper


def _pick_root(roots: list[float], guess: float) -> float:
    """One root: the only one, the one nearest ``guess``, or ``guess`` if none."""
    if not roots:
        return guess
    return float(roots[int(np.argmin(np.abs(np.asarray(roots) - guess)))])


def _separation_function(alpha: np.ndarray, cn: np.ndarray, i_lower: int, i_upper: int
                         ) -> np.ndarray:
    """Static separation point f(alpha) from Cn (OpenFAST v5 ComputeUA360_*), in [0, 1]."""
    n = alpha.size
    attached, a_break_lower, a_break_upper = _attached_cn(alpha, cn, i_lower, i_upper)
    # Offset keeping numerator and denominator of the Cn ratio of one sign near 0 deg.
    base = cn[i_lower] + 0.05 if cn[i_lower] > -0.05 else 0.0
    scale = 0.1 / _DEG
    offset = base * (np.tanh(scale * (alpha + math.pi / 2))
                     - np.tanh(scale * (alpha - math.pi / 2))) / 2.0
    f = np.empty(n)
    for row in range(n):
        if _equal_real(attached[row], offset[row]):
            ratio = 1.0
        else:
            ratio = (cn[row] - offset[row]) / (attached[row] - offset[row])
        f[row] = min(max((2.0 * math.sqrt(max(0.25, ratio)) - 1.0) ** 2, 0.0), 1.0)
    f[i_lower:i_upper + 1] = 1.0
    # Make f decrease monotonically from a single peak near +/-180 deg: work on the table
    # rotated to start after alphaBreakLower, with the angles unwrapped.
    shift = _last(alpha <= a_break_lower) + 1
    angle, fs = np.roll(alpha, -shift), np.roll(f, -shift)
    for row in range(1, n):
        if angle[row] < angle[row - 1]:
            angle[row] += 2.0 * math.pi
    beyond = angle > a_break_upper
    if beyond.any():
        i_peak = int(np.flatnonzero(beyond)[np.argmax(fs[beyond])])
        i_break = _first(angle >= a_break_upper)
        for row in range(i_peak - 1, i_break, -1):
            if _equal_real(fs[row], 0.0):
                fs[row - 1] = 0.0
            if fs[row - 1] > fs[row]:
                fs[row] = 0.5 * (fs[row + 1] + fs[row - 1])
        for row in range(i_peak + 1, n - 1):
            if _equal_real(fs[row], 0.0):
                fs[row + 1] = 0.0
            if fs[row + 1] > fs[row]:
                fs[row] = 0.5 * (fs[row + 1] + fs[row - 1])
    return np.roll(fs, shift)


def _attached_cn(alpha: np.ndarray, cn: np.ndarray, i_lower: int, i_upper: int
                 ) -> tuple[np.ndarray, float, float]:
    """Fully attached Cn: the table inside the region, lines to the reverse-flow zero outside.

    Returns the attached Cn per table angle, alphaBreakLower and alphaBreakUpper [rad]
    (OpenFAST v5 ComputeUA360_AttachedFlow).
    """
    n = alpha.size
    slope_up = (cn[i_upper - 1] - cn[i_upper]) / (alpha[i_upper - 1] - alpha[i_upper])
    zero_up = alpha[i_upper] if _equal_real(slope_up, 0.0) else alpha[i_upper] - cn[i_upper] / slope_up
    slope_lo = (cn[i_lower] - cn[i_lower + 1]) / (alpha[i_lower] - alpha[i_lower + 1])
    zero_lo = alpha[i_lower] if _equal_real(slope_lo, 0.0) else alpha[i_lower] - cn[i_lower] / slope_lo
    roots = np.asarray(_zero_crossings(alpha, cn, period=2.0 * math.pi))
    zero_reverse = float(alpha[0])  # AeroDyn's value when Cn has no zero beyond 45 deg
    far = np.abs(roots) >= 45.0 * _DEG if roots.size else np.zeros(0, bool)
    if far.any():
        zero_reverse = float(roots[np.flatnonzero(far)[np.argmax(np.abs(roots[far]))]])
        if zero_reverse < -math.pi / 2:
            zero_reverse += 2.0 * math.pi
    s = _REVERSE_SLOPE
    a_bu = (s * zero_reverse - slope_up * zero_up) / (s - slope_up)
    cn_bu = slope_up * (a_bu - zero_up)
    a_bl = (s * (zero_reverse - 2.0 * math.pi) - slope_lo * zero_lo) / (s - slope_lo)
    cn_bl = slope_lo * (a_bl - zero_lo)
    attached = cn.astype(float).copy()
    ind = 0  # one remembered index for both sides, as AeroDyn
    xs, fs = [zero_reverse - 2.0 * math.pi, a_bl, float(alpha[i_lower])], [0.0, cn_bl, float(cn[i_lower])]
    for row in range(0, i_lower):
        attached[row], ind = _interp_extrap(float(alpha[row]), xs, fs, ind)
    xs, fs = [float(alpha[i_upper]), a_bu, zero_reverse], [float(cn[i_upper]), cn_bu, 0.0]
    for row in range(i_upper + 1, n):
        attached[row], ind = _interp_extrap(float(alpha[row]), xs, fs, ind)
    return attached, float(a_bl), float(a_bu)
