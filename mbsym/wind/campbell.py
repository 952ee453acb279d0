"""Campbell diagrams of :class:`~mbsym.wind.turbine.TurbineModel` s: fixed-frame modes vs rotor speed.

For each rotor speed Ω:

1. **Operating point** as ElastoDyn's linearization takes it (notes §7): the deck's initial
   conditions (tower-top and blade-tip deflections, yaw, platform …, *not* an equilibrium),
   the rotor spinning at Ω (generator azimuth speed Ω, or the prescribed azimuth inputs
   ``GeAz_d = Ω``, ``GeAz_dd = 0`` when GenDOF is off), all other speeds zero, and the
   accelerations of the nonlinear equations at that state, so that the linear model is the
   Jacobian of ``x' = f(x, u)`` as in ElastoDyn.
2. **Linear models** at ``n_azimuth`` equally spaced rotor azimuths over one revolution
   (:func:`mbsym.linearize`).
3. **Multi-blade coordinates** (:mod:`mbsym.wind.mbc`, with the ``dT/dt`` terms of a constant
   Ω), then the average of the fixed-frame state matrices over the azimuths (as OpenFAST's
   MBC3 does).
4. **Modes**: eigenvalues of the averaged matrix, ``f = |λ| / 2π`` [Hz] and
   ``ζ = -Re λ / |λ|``, each labelled by its dominant fixed-frame coordinate, weighted by
   the kinetic-energy diagonal ``diag(T1ᵀ M T1)`` so that metres and radians compare:
   blade collective ("1st flap collective"), the cyclic pair split into forward and
   backward whirl ("1st edge backward whirl") from the phase between its cosine and sine
   components, and the other DOFs in words ("1st tower fore-aft", "drivetrain torsion",
   "platform pitch" …). Labels are assigned one to one (an optimal assignment of modes to
   labels), so a label names the same physical mode at every speed.

The result is a :class:`CampbellDiagram` (``to_dict()`` gives the ``mbsym campbell --json``
object, ``plot()`` the diagram with the 1P, 3P, 6P lines).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from ..exceptions import ModelDefinitionError, ParameterError
from ..linear import linearize
from .mbc import N_BLADES, coleman_matrices, mbc_transform, whirl_components
from .parameters import TurbineParameters

__all__ = ["CampbellMode", "CampbellDiagram", "FixedFrameModes", "campbell", "fixed_frame_modes",
           "operating_point", "blade_groups", "DOF_LABELS"]

#: Words for the fixed-frame DOFs (coordinate name -> mode label).
DOF_LABELS = {
    "Sg": "platform surge", "Sw": "platform sway", "Hv": "platform heave", "R": "platform roll",
    "P": "platform pitch", "Y": "platform yaw", "TFA1": "1st tower fore-aft", "TSS1": "1st tower side-side",
    "TFA2": "2nd tower fore-aft", "TSS2": "2nd tower side-side", "Yaw": "nacelle yaw",
    "GeAz": "generator azimuth", "DrTr": "drivetrain torsion",
}
#: Weight of the continuity term (MAC with the labelled modes at the neighbouring speed) against
#: the participation (0..1): the dominant coordinate decides, continuity breaks near-ties such as
#: forward vs backward whirl of standing cyclic modes at low speed.
TRACKING_WEIGHT = 0.3
_BLADE_MODES = {"F1": "1st flap", "E1": "1st edge", "F2": "2nd flap"}
_BLADE_COORD = re.compile(r"B(\d+)(F1|E1|F2)")


@dataclass(frozen=True)
class CampbellMode:
    """One labelled mode across rotor speeds (NaN where it was not found)."""

    label: str
    freq_hz: np.ndarray
    damping_ratio: np.ndarray


@dataclass(frozen=True)
class FixedFrameModes:
    """Fixed-frame modes at one rotor speed.

    Attributes
    ----------
    rotor_speed : float
        [rad/s].
    labels : tuple of str
        Label of each mode (:data:`DOF_LABELS`, blade collective / forward / backward whirl).
    freq_hz, damping_ratio : ndarray
        Natural frequency ``|λ|/2π`` [Hz] and damping ratio ``-Re λ/|λ|`` (NaN for λ = 0).
    A : ndarray (2 n_q, 2 n_q)
        Azimuth-averaged state matrix in multi-blade coordinates.
    coordinates : tuple of str
        Its coordinates (blade triplets replaced by ``F1_coll``, ``F1_cos``, ``F1_sin`` …).
    participation : ndarray (n_modes, n_modes)
        Kinetic-energy share of each mode's own label (column k = label k) in each mode,
        normalized over all labels.
    vectors : ndarray (n_q, n_modes)
        Coordinate part of each mode's eigenvector in multi-blade coordinates, normalized
        to unit kinetic-energy norm ``Σ w_i |v_i|² = 1``, ``w = diag(T1ᵀ M T1)``.
    """

    rotor_speed: float
    labels: tuple[str, ...]
    freq_hz: np.ndarray
    damping_ratio: np.ndarray
    A: np.ndarray
    coordinates: tuple[str, ...]
    participation: np.ndarray
    vectors: np.ndarray


@dataclass(frozen=True)
class CampbellDiagram:
    """Frequencies and damping ratios of labelled fixed-frame modes vs rotor speed."""

    rpm: np.ndarray
    modes: tuple[CampbellMode, ...]

    def mode(self, label: str) -> CampbellMode:
        """The mode called ``label`` (e.g. ``"1st flap collective"``)."""
        for m in self.modes:
            if m.label == label:
                return m
        raise KeyError(f"no mode labelled {label!r}; labels are {[m.label for m in self.modes]}.")

    @property
    def labels(self) -> tuple[str, ...]:
        return tuple(m.label for m in self.modes)

    def to_dict(self) -> dict:
        """``{"rpm": [...], "modes": [{"label", "freq_hz", "damping_ratio"}, ...]}`` (NaN -> None)."""
        def clean(a):
            return [None if not np.isfinite(v) else float(v) for v in a]

        return {"rpm": [float(r) for r in self.rpm],
                "modes": [{"label": m.label, "freq_hz": clean(m.freq_hz), "damping_ratio": clean(m.damping_ratio)}
                          for m in self.modes]}

    def plot(self, path, *, excitations: Sequence[int] = (1, 3, 6), title: str | None = None) -> None:
        """Write the diagram (frequency vs rotor speed, with the nP excitation lines) to ``path``."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(8, 6))
        shown = [m for m in self.modes if np.nanmax(np.nan_to_num(m.freq_hz, nan=0.0)) > 0]
        fmax = max([np.nanmax(m.freq_hz) for m in shown], default=1.0)
        colors = plt.get_cmap("tab20").colors
        for i, m in enumerate(shown):
            ax.plot(self.rpm, m.freq_hz, "o-", ms=3, lw=1.2, color=colors[i % len(colors)], label=m.label)
        rpm = np.linspace(0.0, max(float(np.max(self.rpm)), 1e-9), 50)
        for n in excitations:
            ax.plot(rpm, n * rpm / 60.0, "--", color="0.6", lw=0.8)
            x = rpm[-1]
            if n * x / 60.0 <= 1.05 * fmax:
                ax.annotate(f"{n}P", (x, n * x / 60.0), fontsize=8, color="0.4")
        ax.set_xlabel("rotor speed [rpm]")
        ax.set_ylabel("frequency [Hz]")
        ax.set_ylim(0.0, 1.1 * fmax)
        ax.set_title(title or "Campbell diagram (fixed frame, multi-blade coordinates)")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2, loc="upper left")
        fig.tight_layout()
        fig.savefig(path, dpi=120)
        plt.close(fig)


def blade_groups(coordinates: Sequence[str]) -> tuple[list[tuple[int, int, int]], tuple[str, ...]]:
    """Blade triplets ``(B1x, B2x, B3x)`` of a turbine's coordinates and the MBC coordinate names.

    Examples
    --------
    >>> blade_groups(["TFA1", "B1F1", "B2F1", "B3F1"])
    ([(1, 2, 3)], ('TFA1', 'F1_coll', 'F1_cos', 'F1_sin'))
    """
    by_type: dict[str, dict[int, int]] = {}
    for i, name in enumerate(coordinates):
        m = _BLADE_COORD.fullmatch(name)
        if m:
            by_type.setdefault(m.group(2), {})[int(m.group(1))] = i
    groups, names = [], list(coordinates)
    for kind, blades in by_type.items():
        if sorted(blades) != list(range(1, N_BLADES + 1)):
            raise ModelDefinitionError(f"multi-blade coordinates need blades 1..{N_BLADES} for each blade DOF; "
                                       f"{kind} has blades {sorted(blades)}.")
        g = tuple(blades[b] for b in range(1, N_BLADES + 1))
        groups.append(g)
        for i, suffix in zip(g, ("coll", "cos", "sin")):
            names[i] = f"{kind}_{suffix}"
    return groups, tuple(names)


def operating_point(model, azimuth: float, rotor_speed: float, p: dict | None = None) -> dict:
    """ElastoDyn-style linearization point of a TurbineModel (module docstring, step 1).

    Parameters
    ----------
    model : TurbineModel
    azimuth : float
        Rotor azimuth of blade 1 from vertical, increasing with the rotation [rad]
        (``q_GeAz + q_DrTr + π/2``).
    rotor_speed : float
        [rad/s].
    p : dict, optional
        Parameter values by name (the model's defaults fill the gaps).

    Returns
    -------
    dict
        ``q``, ``qd``, ``qdd``, ``u`` (arrays in the model's orders) and ``p``.

    Raises
    ------
    ModelDefinitionError
        The rotor can spin neither through GenDOF nor through the prescribed azimuth.
    """
    eom = model.eom
    n = eom.n_q
    x0 = model.initial_state()
    q, qd = x0[:n].copy(), np.zeros(n)
    geaz = float(np.mod(azimuth - np.pi / 2, 2 * np.pi))
    defaults = model.input_defaults()
    u = {k: (v(0.0) if callable(v) else float(v)) for k, v in defaults.items()}
    if "GeAz" in eom.coordinates:
        i = eom.coordinates.index("GeAz")
        q[i], qd[i] = geaz, rotor_speed
    elif "GeAz" in eom.inputs:
        u.update(GeAz=geaz, GeAz_d=rotor_speed, GeAz_dd=0.0)
    elif rotor_speed != 0.0 or any(_BLADE_COORD.fullmatch(c) for c in eom.coordinates):
        raise ModelDefinitionError(
            "the rotor of this model cannot turn (GenDOF off and a fixed azimuth); build it with "
            "TurbineModel(..., prescribed_azimuth=True) or enable GenDOF.")
    uu = np.array([u[name] for name in eom.inputs], dtype=float)
    p = dict(p or {})
    qdd = eom.accelerations(q, qd, uu, p)
    return {"q": q, "qd": qd, "qdd": np.asarray(qdd, dtype=float).reshape(-1), "u": uu, "p": p}


def fixed_frame_modes(model, rotor_speed: float, *, n_azimuth: int = 12, p: dict | None = None,
                      reference: "FixedFrameModes | None" = None) -> FixedFrameModes:
    """Labelled fixed-frame modes of a TurbineModel at one rotor speed (module docstring).

    Parameters
    ----------
    model : TurbineModel
    rotor_speed : float
        [rad/s].
    n_azimuth : int, keyword-only
        Number of equally spaced azimuths over one revolution for the MBC average (default 12).
    p : dict, optional, keyword-only
        Parameter values by name (e.g. ``{"gravity": 0.0}``); the model's defaults fill the gaps.
    reference : FixedFrameModes, optional, keyword-only
        Labelled modes at a nearby speed of the same model: each label's score adds the
        modal assurance criterion (kinetic-energy weighted) with that label's mode there,
        so that labels follow the modes where the dominant coordinate alone is ambiguous
        (standing cyclic modes at low speed, Ω = 0), with weight :data:`TRACKING_WEIGHT`.

    Returns
    -------
    FixedFrameModes
        Oscillatory modes only (rigid-body and overdamped modes have no label), sorted by
        frequency.
    """
    if not isinstance(n_azimuth, (int, np.integer)) or n_azimuth < 1:
        raise ParameterError(f"n_azimuth must be a positive integer; got {n_azimuth!r}.")
    eom = model.eom
    groups, names = blade_groups(eom.coordinates)
    if groups and model.turbine.number_of_blades != N_BLADES:
        raise ModelDefinitionError(f"multi-blade coordinates need a {N_BLADES}-bladed rotor; the deck has "
                                   f"{model.turbine.number_of_blades} blades.")
    n = eom.n_q
    A_sum, w_sum = np.zeros((2 * n, 2 * n)), np.zeros(n)
    for j in range(int(n_azimuth)):
        psi = 2 * np.pi * j / int(n_azimuth)
        op = operating_point(model, psi, rotor_speed, p)
        lin = linearize(eom, op["q"], op["qd"], op["u"], op["p"], qdd0=op["qdd"])
        A_sum += mbc_transform(lin.A, groups, psi, rotor_speed)
        T1 = coleman_matrices(n, groups, psi).T1
        w_sum += np.diag(T1.T @ lin.M @ T1)
    A, w = A_sum / n_azimuth, w_sum / n_azimuth
    labels, scores_of = _label_space(eom.coordinates, groups, w)
    lam, V = np.linalg.eig(A)
    wn = np.abs(lam)
    keep = np.flatnonzero((lam.imag > 1e-6 * wn) & (wn > 2 * np.pi * 1e-5))       # oscillatory, one per pair
    vecs = V[:n, keep]
    vecs = vecs / np.sqrt(np.maximum(np.einsum("i,ik->k", w, np.abs(vecs) ** 2), 1e-300))
    S = np.array([scores_of(vecs[:, k]) for k in range(keep.size)]).reshape(keep.size, len(labels))
    P = S.copy()
    if reference is not None and keep.size:
        for c, lab in enumerate(labels):
            if lab in reference.labels:
                ref = reference.vectors[:, reference.labels.index(lab)]
                S[:, c] += TRACKING_WEIGHT * np.abs(np.einsum("i,i,ik->k", w, ref.conj(), vecs)) ** 2
    rows, cols = linear_sum_assignment(S, maximize=True)
    lam_k = lam[keep[rows]]
    freq = np.abs(lam_k) / (2 * np.pi)
    order = np.lexsort((cols, np.round(freq, 6)))      # by frequency; ties in label order
    rows, cols, lam_k, freq = rows[order], cols[order], lam_k[order], freq[order]
    return FixedFrameModes(float(rotor_speed), tuple(labels[c] for c in cols), freq, -lam_k.real / np.abs(lam_k),
                           A, names, P[rows][:, cols] if rows.size else np.zeros((0, 0)), vecs[:, rows])


def _label_space(coordinates, groups, w):
    """Labels (one per fixed-frame coordinate but the rotor azimuth) and the eigenvector scores.

    The generator azimuth is the rotor's rigid-body rotation: no oscillatory mode is named
    after it (its motion in a mode, e.g. the rotor turning against the blades' collective
    edge bending, is not scored).
    """
    in_group = {i for g in groups for i in g}
    singles = [i for i in range(len(coordinates)) if i not in in_group and coordinates[i] != "GeAz"]
    labels = [DOF_LABELS.get(coordinates[i], coordinates[i]) for i in singles]
    for g in groups:
        kind = _BLADE_MODES[_BLADE_COORD.fullmatch(coordinates[g[0]]).group(2)]
        labels += [f"{kind} collective", f"{kind} forward whirl", f"{kind} backward whirl"]

    def scores(v: np.ndarray) -> np.ndarray:
        out = [w[i] * abs(v[i]) ** 2 for i in singles]
        for g in groups:
            fwd, bwd = whirl_components(v[g[1]], v[g[2]])
            wc = 0.5 * (w[g[1]] + w[g[2]])
            out += [w[g[0]] * abs(v[g[0]]) ** 2, wc * fwd, wc * bwd]
        out = np.asarray(out, dtype=float)
        total = out.sum()
        return out / total if total > 0 else out

    return labels, scores


def campbell(turbine, rpm: Sequence[float], *, dofs: Sequence[str] | None = None,
             n_azimuth: int = 12, p: dict | None = None) -> CampbellDiagram:
    """Campbell diagram of a turbine: labelled fixed-frame modes at each rotor speed.

    Parameters
    ----------
    turbine : TurbineParameters or TurbineModel
        A deck (:func:`mbsym.wind.read_openfast`): the model is built with its DOFs (or
        ``dofs``) and, when GenDOF is off, a prescribed azimuth; or a ready model.
    rpm : sequence of float
        Rotor speeds [rpm], each >= 0.
    dofs : sequence of str, optional, keyword-only
        ElastoDyn flags (with a TurbineParameters only); default the deck's.
    n_azimuth : int, keyword-only
        Azimuths per revolution for the MBC average (default 12).
    p : dict, optional, keyword-only
        Model parameter values by name (e.g. ``{"gravity": 0.0}``).

    Returns
    -------
    CampbellDiagram
        Modes sorted by their frequency at the first speed.

    Raises
    ------
    ParameterError
        Empty, negative or non-finite speeds.

    Examples
    --------
    Three blades with their 1st flap mode on a hub turning at a fixed speed (no gravity):
    the whirling modes sit 1P above and below the collective one.

    >>> from mbsym.wind import nrel5mw
    >>> cd = campbell(nrel5mw(), [0.0, 12.0], dofs=["FlapDOF1"], n_azimuth=3, p={"gravity": 0.0})
    >>> cd.labels
    ('1st flap collective', '1st flap forward whirl', '1st flap backward whirl')
    >>> [[round(float(f), 3) for f in m.freq_hz] for m in cd.modes]
    [[0.673, 0.723], [0.673, 0.923], [0.673, 0.523]]
    """
    from .turbine import TurbineModel

    speeds = np.asarray(rpm, dtype=float).reshape(-1)
    if speeds.size == 0 or not np.all(np.isfinite(speeds)) or np.any(speeds < 0):
        raise ParameterError(f"rotor speeds must be a non-empty list of finite values >= 0 [rpm]; got {list(rpm)}.")
    if isinstance(turbine, TurbineParameters):
        model = TurbineModel(turbine, dofs=dofs, prescribed_azimuth=True)
    elif isinstance(turbine, TurbineModel):
        if dofs is not None:
            raise TypeError("dofs= applies to TurbineParameters only; the model's DOFs are fixed.")
        model = turbine
    else:
        raise TypeError(f"turbine must be TurbineParameters or TurbineModel; got {type(turbine).__name__}.")
    # label from the highest speed down: whirl directions are clearest where the rotor spins fastest
    by_speed: dict[float, FixedFrameModes] = {}
    ref = None
    for s in sorted(set(speeds.tolist()), reverse=True):
        ref = by_speed[s] = fixed_frame_modes(model, s * np.pi / 30.0, n_azimuth=n_azimuth, p=p, reference=ref)
    per_speed = [by_speed[s] for s in speeds.tolist()]
    labels: list[str] = []
    for m in per_speed:
        labels += [lab for lab in m.labels if lab not in labels]
    freq = np.full((len(labels), speeds.size), np.nan)
    zeta = np.full_like(freq, np.nan)
    for k, m in enumerate(per_speed):
        for lab, f, z in zip(m.labels, m.freq_hz, m.damping_ratio):
            freq[labels.index(lab), k], zeta[labels.index(lab), k] = f, z
    first = np.array([row[np.isfinite(row)][0] if np.any(np.isfinite(row)) else np.inf for row in freq])
    order = np.lexsort((np.arange(len(labels)), np.round(first, 6)))
    modes = tuple(CampbellMode(labels[i], freq[i], zeta[i]) for i in order)
    return CampbellDiagram(speeds, modes)
