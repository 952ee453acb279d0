"""Campbell diagrams of :class:`~mbsym.wind.structure.turbine.TurbineModel` s: fixed-frame modes vs rotor speed.

For each rotor speed Ω:

1. **Operating point** as OpenFAST's linearization of a deck with zero initial displacements
   (the ``*_lin0`` decks; :func:`operating_point`): tower, platform and drivetrain-torsion
   displacements zero, the blades at the deck's tip deflections (OoPDefl/IPDefl), the deck's
   NacYaw and BlPitch, the rotor spinning at Ω (generator azimuth speed Ω, or the prescribed
   azimuth inputs ``GeAz_d = Ω``, ``GeAz_dd = 0`` when GenDOF is off), all other speeds
   zero. Not an equilibrium: the linear model is the Jacobian of ``x' = f(x, u)`` there, as
   in ElastoDyn (docs/elastodyn_notes.md §7).
2. **Linear models** at ``n_azimuth`` equally spaced rotor azimuths over one revolution, in one
   batch (:func:`mbsym.linear.linearize_azimuths`), by default with ElastoDyn's central
   differences (``method="elastodyn-fd"``, as ``mbsym linearize``) so that the frequencies are
   OpenFAST's including its finite-step error (notes §8.3: 0.8 % on a floating platform's
   pitch); ``method="exact"`` for automatic differentiation.
3. **Multi-blade coordinates** (:mod:`mbsym.wind.structure.mbc`, blade-1 azimuth = ElastoDyn's
   ``Azimuth`` output ``q_GeAz + q_DrTr + AzimB1Up + π/2``, with the ``dT/dt`` terms of a
   constant Ω), then the average of the fixed-frame state matrices over the azimuths
   (:meth:`mbsym.linear.AzimuthSweep.average`, as OpenFAST's MBC3 does).
4. **Modes**: eigenvalues of the averaged matrix, ``f = |λ| / 2π`` [Hz] and
   ``ζ = -Re λ / |λ|``, each labelled by the fixed-frame coordinate that carries most of
   its kinetic energy. With ``M̄`` the azimuth average of ``T1ᵀ M T1`` (the mass matrix in
   multi-blade coordinates, coupling included) and the mode shape ``v`` normalised to
   ``vᴴ M̄ v = 1``, coordinate ``i`` carries ``|Re(conj(v_i) (M̄ v)_i)|``; a cyclic pair is
   split into forward and backward whirl by the unitary change of basis
   :func:`~mbsym.wind.structure.mbc.whirl_coordinates` applied to ``v`` and ``M̄ v``. Labels: blade
   collective ("1st flap collective"), whirl ("1st edge backward whirl") and the other DOFs
   in words ("1st tower fore-aft", "drivetrain torsion", "platform pitch" …), assigned one
   to one (an optimal assignment of modes to labels), so a label names the same physical
   mode at every speed.

Why the blades keep the deck's deflections and nothing else does: the decks' tower-top and
platform initial displacements (TTDspFA = 1 m, PtfmPitch = 2° …) are free-decay starting
points, not operating states, and OpenFAST's own linearizations of those turbines are run from
decks with zero displacements (``*_lin0``; ``mbsym linearize`` does the same). Around such a
deflected point the nonlinear platform pitch moves the floating platform's frequencies by
~2 % (paper46: 0.1022 / 0.7959 Hz deflected, 0.0998 / 0.7998 Hz undeflected, the latter
OpenFAST's lin0). A blade tip deflection, on the contrary, is the rotor's operating state
(e.g. the mean flap deflection under thrust) that a Campbell diagram is asked about; decks
without one (blade_campbell) are unaffected.

The result is a :class:`CampbellDiagram` (``to_dict()`` gives the ``mbsym campbell --json``
object, ``plot()`` the diagram with the 1P, 3P, 6P lines).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.optimize import linear_sum_assignment

from ...exceptions import ModelDefinitionError, ParameterError
from ...linear import METHODS
from ...linear import OperatingPoint, linearize_azimuths
from ..structure.mbc import N_BLADES, blade_dof, blade_indices, coleman_matrices, mbc_coordinate_names, whirl_coordinates
from ..deck.parameters import TurbineParameters

__all__ = ["CampbellMode", "CampbellDiagram", "FixedFrameModes", "campbell", "fixed_frame_modes",
           "operating_point", "campbell_model", "DOF_LABELS", "UNDEFLECTED"]

#: Words for the fixed-frame DOFs (coordinate name -> mode label).
DOF_LABELS = {
    "Sg": "platform surge", "Sw": "platform sway", "Hv": "platform heave", "R": "platform roll",
    "P": "platform pitch", "Y": "platform yaw", "TFA1": "1st tower fore-aft", "TSS1": "1st tower side-side",
    "TFA2": "2nd tower fore-aft", "TSS2": "2nd tower side-side", "Yaw": "nacelle yaw",
    "GeAz": "generator azimuth", "DrTr": "drivetrain torsion",
}
#: Displacement coordinates set to zero at the operating point (module docstring).
UNDEFLECTED = ("Sg", "Sw", "Hv", "R", "P", "Y", "TFA1", "TSS1", "TFA2", "TSS2", "DrTr")
#: Weight of the continuity term (MAC with the labelled modes at the neighbouring speed) against
#: the participation (0..1): the dominant coordinate decides, continuity breaks near-ties such as
#: forward vs backward whirl of standing cyclic modes at low speed.
TRACKING_WEIGHT = 0.3
_BLADE_MODES = {"F1": "1st flap", "E1": "1st edge", "F2": "2nd flap"}


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
        Natural frequency ``|λ|/2π`` [Hz] and damping ratio ``-Re λ/|λ|``.
    A : ndarray (2 n_q, 2 n_q)
        Azimuth-averaged state matrix in multi-blade coordinates.
    coordinates : tuple of str
        Its coordinates (blade triplets replaced by ``F1_coll``, ``F1_cos``, ``F1_sin`` …).
    participation : ndarray (n_modes, n_modes)
        Kinetic-energy share of each mode's own label (column k = label k) in each mode,
        normalized over all labels.
    vectors : ndarray (n_q, n_modes)
        Coordinate part of each mode's eigenvector in multi-blade coordinates, normalized
        to ``vᴴ M̄ v = 1``.
    M : ndarray (n_q, n_q)
        ``M̄``: the azimuth average of ``T1ᵀ M T1``, the kinetic-energy matrix in
        multi-blade coordinates [kg, kg m, kg m²].
    """

    rotor_speed: float
    labels: tuple[str, ...]
    freq_hz: np.ndarray
    damping_ratio: np.ndarray
    A: np.ndarray
    coordinates: tuple[str, ...]
    participation: np.ndarray
    vectors: np.ndarray
    M: np.ndarray


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
        colors = plt.get_cmap("tab10").colors
        families = list(dict.fromkeys(mode_family(m.label)[0] for m in shown))
        for m in shown:
            family, style = mode_family(m.label)
            ax.plot(self.rpm, m.freq_hz, marker=_MARKERS[style], linestyle=style, ms=3, lw=1.3,
                    color=colors[families.index(family) % len(colors)], label=m.label)
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


#: Line style of each kind of mode in :meth:`CampbellDiagram.plot` (and its marker).
WHIRL_STYLES = {"collective": "-", "forward whirl": "--", "backward whirl": ":"}
_MARKERS = {"-": "o", "--": "^", ":": "v"}


def mode_family(label: str) -> tuple[str, str]:
    """``(family, line style)`` of a mode label: blade modes share their family's colour, with a
    solid line for collective, dashed for forward and dotted for backward whirl; every other
    mode is a family of its own (solid).

    Examples
    --------
    >>> mode_family("1st edge backward whirl"), mode_family("1st tower fore-aft")
    (('1st edge', ':'), ('1st tower fore-aft', '-'))
    """
    for kind, style in WHIRL_STYLES.items():
        if label.endswith(" " + kind):
            return label[: -len(kind) - 1], style
    return label, "-"


def campbell_model(turbine: TurbineParameters, dofs: Sequence[str] | None = None):
    """The TurbineModel :func:`campbell` builds for a deck: zero tower and platform displacements.

    The deck's TTDspFA, TTDspSS, platform displacements and TeetDefl are set to zero (module
    docstring; disabled DOFs keep these values as constants), the blade tip deflections,
    NacYaw, BlPitch and Azimuth are kept, and the rotor turns through the prescribed azimuth
    when GenDOF is off.

    Parameters
    ----------
    turbine : TurbineParameters
    dofs : sequence of str, optional
        ElastoDyn flags (default: the deck's).

    Returns
    -------
    TurbineModel

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> campbell_model(nrel5mw(), ["TwFADOF1"]).eom.prescribed
    ('GeAz',)
    """
    from ..structure.turbine import TurbineModel

    ic = turbine.initial_conditions
    zero = dict(tower_top_fa_displacement=0.0, tower_top_ss_displacement=0.0, platform_surge=0.0,
                platform_sway=0.0, platform_heave=0.0, platform_roll=0.0, platform_pitch=0.0, platform_yaw=0.0,
                teeter_angle=0.0)
    flat = dataclasses.replace(turbine, initial_conditions=dataclasses.replace(ic, **zero))
    return TurbineModel(flat, dofs=dofs, prescribed_azimuth=True)


def operating_point(model, rotor_speed: float, *, azimuth: float = 0.0, p: dict | None = None) -> OperatingPoint:
    """OpenFAST-style linearization point of a TurbineModel (module docstring, step 1).

    Parameters
    ----------
    model : TurbineModel
    rotor_speed : float
        [rad/s].
    azimuth : float, keyword-only
        Azimuth of blade 1, ElastoDyn's ``Azimuth`` (``q_GeAz + AzimB1Up + π/2``) [rad].
    p : dict, optional, keyword-only
        Parameter values by name (the model's defaults fill the gaps).

    Returns
    -------
    OperatingPoint
        ``q`` with the :data:`UNDEFLECTED` coordinates zero and the others at the model's
        initial state, the rotor azimuth and speed set, ``qdd`` the accelerations there.

    Raises
    ------
    ModelDefinitionError
        The rotor can spin neither through GenDOF nor through the prescribed azimuth.

    Examples
    --------
    >>> from mbsym.wind import nrel5mw
    >>> from mbsym.wind.structure.turbine import TurbineModel
    >>> op = operating_point(TurbineModel(nrel5mw(), ["TwFADOF1", "GenDOF"]), 1.0)
    >>> op.q.round(4).tolist(), op.qd.tolist()          # q_GeAz = 3π/2 with blade 1 up
    ([0.0, 4.7124], [0.0, 1.0])
    """
    eom, t = model.eom, model.turbine
    n = eom.n_q
    q, qd = model.initial_state()[:n].copy(), np.zeros(n)
    for i, name in enumerate(eom.coordinates):
        if name in UNDEFLECTED:
            q[i] = 0.0
    geaz = float(np.mod(azimuth - t.azimuth_blade1_up - np.pi / 2, 2 * np.pi))
    defaults = model.input_defaults()
    u = {k: (v(0.0) if callable(v) else float(v)) for k, v in defaults.items()}
    if "GeAz" in eom.coordinates:
        i = eom.coordinates.index("GeAz")
        q[i], qd[i] = geaz, rotor_speed
    elif "GeAz" in eom.inputs:
        u.update(GeAz=geaz, GeAz_d=rotor_speed, GeAz_dd=0.0)
    else:
        raise ModelDefinitionError(
            "the rotor of this model cannot turn (GenDOF off and a fixed azimuth); build it with "
            "TurbineModel(..., prescribed_azimuth=True) or campbell_model(turbine), or enable GenDOF.")
    uu = np.array([u[name] for name in eom.inputs], dtype=float)
    pp = eom.parameter_vector(dict(p or {}))
    pd = dict(zip(eom.parameters, pp.tolist()))
    qdd = np.asarray(eom.accelerations(q, qd, uu, pd), dtype=float).reshape(-1)
    return OperatingPoint(q, qd, qdd, uu, pd, eom.coordinates, eom.inputs, held=("GeAz",),
                          message=f"ElastoDyn linearization point, rotor at {rotor_speed:.6g} rad/s")


def fixed_frame_modes(model, rotor_speed: float, *, n_azimuth: int = 12, p: dict | None = None,
                      method: str = "elastodyn-fd", reference: "FixedFrameModes | None" = None) -> FixedFrameModes:
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
    method : {"elastodyn-fd", "exact", "fd"}, keyword-only
        How A is computed (:func:`mbsym.linearize`): ElastoDyn's central differences
        (default, as OpenFAST and ``mbsym linearize``) or exact derivatives.
    reference : FixedFrameModes, optional, keyword-only
        Labelled modes at a nearby speed of the same model: each label's score adds the
        modal assurance criterion (``M̄``-weighted) with that label's mode there,
        so that labels follow the modes where the dominant coordinate alone is ambiguous
        (standing cyclic modes at low speed, Ω = 0), with weight :data:`TRACKING_WEIGHT`.

    Returns
    -------
    FixedFrameModes
        Oscillatory modes only (rigid-body and overdamped modes have no label), sorted by
        frequency.

    Raises
    ------
    ParameterError
        ``n_azimuth`` not a positive integer, or an unknown ``method``.
    ModelDefinitionError
        Blade DOFs on a rotor that is not 3-bladed, or a rotor that cannot turn.
    """
    if not isinstance(n_azimuth, (int, np.integer)) or n_azimuth < 1:
        raise ParameterError(f"n_azimuth must be a positive integer; got {n_azimuth!r}.")
    if method not in METHODS:
        raise ParameterError(f"unknown linearization method {method!r}; choose one of {list(METHODS)}.")
    eom = model.eom
    groups = blade_indices(eom.coordinates)
    if groups and model.turbine.number_of_blades != N_BLADES:
        raise ModelDefinitionError(f"multi-blade coordinates need a {N_BLADES}-bladed rotor; the deck has "
                                   f"{model.turbine.number_of_blades} blades.")
    names = mbc_coordinate_names(eom.coordinates)
    op = operating_point(model, rotor_speed, p=p)
    sweep = linearize_azimuths(model, op, int(n_azimuth), method=method, qdd0="rhs")
    A = sweep.average().A
    n = eom.n_q
    Mbar = np.zeros((n, n))
    for M, psi in zip(sweep.batch.M, sweep.blade_azimuths):
        T1 = coleman_matrices(n, groups, psi).T1
        Mbar += T1.T @ M @ T1
    Mbar = 0.5 * (Mbar + Mbar.T) / len(sweep.blade_azimuths)
    return _label_modes(A, Mbar, eom.coordinates, names, groups, float(rotor_speed), reference)


def _label_modes(A, Mbar, coordinates, names, groups, rotor_speed, reference) -> FixedFrameModes:
    """Oscillatory eigenpairs of A, normalised by M̄, assigned to labels (module docstring, step 4)."""
    n = len(coordinates)
    labels, scores_of = _label_space(coordinates, groups, Mbar)
    lam, V = np.linalg.eig(A)
    wn = np.abs(lam)
    keep = np.flatnonzero((lam.imag > 1e-6 * wn) & (wn > 2 * np.pi * 1e-5))       # oscillatory, one per pair
    vecs = V[:n, keep]
    norm = np.einsum("ik,ij,jk->k", vecs.conj(), Mbar, vecs).real
    vecs = vecs / np.sqrt(np.maximum(norm, 1e-300))
    S = np.array([scores_of(vecs[:, k]) for k in range(keep.size)]).reshape(keep.size, len(labels))
    P = S.copy()
    if reference is not None and keep.size:
        for c, lab in enumerate(labels):
            if lab in reference.labels:
                ref = reference.vectors[:, reference.labels.index(lab)]
                S[:, c] += TRACKING_WEIGHT * np.abs(ref.conj() @ Mbar @ vecs) ** 2
    rows, cols = linear_sum_assignment(S, maximize=True)
    lam_k = lam[keep[rows]]
    freq = np.abs(lam_k) / (2 * np.pi)
    order = np.lexsort((cols, np.round(freq, 6)))      # by frequency; ties in label order
    rows, cols, lam_k, freq = rows[order], cols[order], lam_k[order], freq[order]
    return FixedFrameModes(rotor_speed, tuple(labels[c] for c in cols), freq, -lam_k.real / np.abs(lam_k),
                           A, names, P[rows][:, cols] if rows.size else np.zeros((0, 0)), vecs[:, rows], Mbar)


def _label_space(coordinates, groups, Mbar):
    """Labels (one per fixed-frame coordinate but the rotor azimuth) and the eigenvector scores.

    The score of coordinate i is its share ``|Re(conj(v_i) (M̄ v)_i)|`` of the kinetic
    energy; cyclic pairs are split into forward and backward whirl in the same way. The
    generator azimuth is the rotor's rigid-body rotation: no oscillatory mode is named
    after it (its motion in a mode, e.g. the rotor turning against the blades' collective
    edge bending, is not scored).
    """
    in_group = {i for g in groups for i in g}
    singles = [i for i in range(len(coordinates)) if i not in in_group and coordinates[i] != "GeAz"]
    labels = [DOF_LABELS.get(coordinates[i], coordinates[i]) for i in singles]
    for g in groups:
        kind = _BLADE_MODES[blade_dof(coordinates[g[0]])[1]]
        labels += [f"{kind} collective", f"{kind} forward whirl", f"{kind} backward whirl"]

    def scores(v: np.ndarray) -> np.ndarray:
        g = Mbar @ v
        share = np.abs((v.conj() * g).real)
        out = [share[i] for i in singles]
        for grp in groups:
            (vf, vb), (gf, gb) = whirl_coordinates(v[grp[1]], v[grp[2]]), whirl_coordinates(g[grp[1]], g[grp[2]])
            out += [share[grp[0]], abs((vf.conjugate() * gf).real), abs((vb.conjugate() * gb).real)]
        out = np.asarray(out, dtype=float)
        total = out.sum()
        return out / total if total > 0 else out

    return labels, scores


def campbell(turbine, rpm: Sequence[float], *, dofs: Sequence[str] | None = None, n_azimuth: int = 12,
             p: dict | None = None, method: str = "elastodyn-fd") -> CampbellDiagram:
    """Campbell diagram of a turbine: labelled fixed-frame modes at each rotor speed.

    Parameters
    ----------
    turbine : TurbineParameters or TurbineModel
        A deck (:func:`mbsym.wind.read_openfast`): the model is :func:`campbell_model` of it
        (its DOFs or ``dofs``, zero tower and platform displacements, a prescribed azimuth
        when GenDOF is off); or a ready model (its enabled tower, platform and drivetrain
        coordinates are still linearized at zero, :func:`operating_point`).
    rpm : sequence of float
        Rotor speeds [rpm], each >= 0.
    dofs : sequence of str, optional, keyword-only
        ElastoDyn flags (with a TurbineParameters only); default the deck's.
    n_azimuth : int, keyword-only
        Azimuths per revolution for the MBC average (default 12).
    p : dict, optional, keyword-only
        Model parameter values by name (e.g. ``{"gravity": 0.0}``).
    method : {"elastodyn-fd", "exact", "fd"}, keyword-only
        Linearization method (:func:`fixed_frame_modes`); default ElastoDyn's central
        differences, as ``mbsym linearize`` and OpenFAST.

    Returns
    -------
    CampbellDiagram
        Modes sorted by their frequency at the first speed.

    Raises
    ------
    ParameterError
        Empty, negative or non-finite speeds, or an unknown method.

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
    from ..structure.turbine import TurbineModel

    speeds = np.asarray(rpm, dtype=float).reshape(-1)
    if speeds.size == 0 or not np.all(np.isfinite(speeds)) or np.any(speeds < 0):
        raise ParameterError(f"rotor speeds must be a non-empty list of finite values >= 0 [rpm]; got {list(rpm)}.")
    if isinstance(turbine, TurbineParameters):
        model = campbell_model(turbine, dofs)
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
        ref = by_speed[s] = fixed_frame_modes(model, s * np.pi / 30.0, n_azimuth=n_azimuth, p=p, method=method,
                                              reference=ref)
    return _collect(speeds, [by_speed[s] for s in speeds.tolist()])


def _collect(speeds: np.ndarray, per_speed: list[FixedFrameModes]) -> CampbellDiagram:
    """One CampbellMode per label over the speeds, sorted by the frequency at the first speed."""
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
    return CampbellDiagram(speeds, tuple(CampbellMode(labels[i], freq[i], zeta[i]) for i in order))
