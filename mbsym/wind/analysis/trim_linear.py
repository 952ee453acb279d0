"""Linear models about trimmed operating points, and the Campbell diagram with aerodynamics.

:func:`linearize_point` differentiates the composed model (CasADi AD of the same graph the trim
solved) at a :class:`~.trim.TrimPoint`: ``δẋ = A δx + B δu``, ``δy = C δx + D δu`` with the
inputs ``Wind1VelX`` [m/s], ``BlPitchCom`` [rad], ``GenTqCom`` [N m] and every state of the
model, so the aerodynamic damping (thrust and torque depend on the relative wind, which the
tower velocity changes), the aerodynamic stiffness of the rotor speed and the pitch and
torque paths are in ``A`` and ``B``. The result is a :class:`mbsym.linear.LinearModel`
(``to_statespace()`` gives a named ``control.StateSpace``); its ``M`` is the structure's mass
matrix at the point (for kinetic-energy mode labels), ``C``, ``K``, ``Q`` are left empty
because the composed model is first order (actuator and inflow states).

:func:`aero_campbell` gives frequencies and damping ratios of the labelled structural modes at
every operating point. Each mode is labelled on the structural block ``A_ss`` of ``A`` (the
structure with the aerodynamic derivatives of the frozen inflow) by the coordinate that
carries most of its kinetic energy (:data:`~mbsym.wind.analysis.campbell_diagram.DOF_LABELS`)
and then matched to the nearest eigenvalue of the whole ``A`` (actuators and dynamic inflow
included), which is the one reported. A rotor described by performance surfaces loads the hub
only, so models with blade DOFs are refused here (their Campbell diagram without
aerodynamics is :func:`mbsym.wind.analysis.campbell`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Sequence

import casadi as ca
import numpy as np
from scipy.optimize import linear_sum_assignment

from ...exceptions import DimensionError, ModelDefinitionError
from ...linear import LinearModel
from ..operation.units import INPUT_UNITS as OPERATION_INPUT_UNITS
from ..structure.mbc import rotating_triplets

__all__ = ["linearize_dynamics", "linearize_point", "aero_campbell", "AeroCampbell", "SI_UNITS", "to_si",
           "whirl_labels", "numbered_labels",
           "INPUT_UNITS", "STATE_LABELS", "mode_label"]


def linearize_dynamics(dyn, x, u, p=None, *, outputs: Sequence[str] | None = None) -> dict:
    """Exact Jacobians of an :class:`mbsym.Dynamics` at ``(x, u, p)``.

    Parameters
    ----------
    dyn : Dynamics
    x, u : array or dict by name
    p : dict, optional
    outputs : sequence of str, optional, keyword-only
        Output channels (names of ``dyn.output_names``) for ``C``, ``D``.

    Returns
    -------
    dict
        ``A`` (n_x, n_x), ``B`` (n_x, n_u), ``C`` (n_y, n_x), ``D`` (n_y, n_u), ``xd``, ``y``,
        ``outputs`` (names), ``units``.

    Raises
    ------
    DimensionError
        Unknown output names.
    """
    xv, uv, pv = dyn.state_vector(x), dyn.input_vector(u), dyn.parameter_vector(p)
    names = tuple(outputs or ())
    unknown = [n for n in names if n not in dyn.output_names]
    if unknown:
        raise DimensionError(f"unknown output channels {unknown}; the model has {list(dyn.output_names)}.")
    f = _jacobian_function(dyn, names)
    A, B, C, D, xd, y = (np.asarray(v, dtype=float) for v in f(xv, uv, pv))
    units = tuple(dyn.output_units[dyn.output_names.index(n)] for n in names)
    return {"A": A, "B": B, "C": C.reshape(len(names), dyn.n_x), "D": D.reshape(len(names), dyn.n_u),
            "xd": xd.reshape(-1), "y": y.reshape(-1), "outputs": names, "units": units}


def _jacobian_function(dyn, names: tuple[str, ...]) -> ca.Function:
    """``(x, u, p) -> (A, B, C, D, xd, y)``, built once per Dynamics and output selection (kept on the object)."""
    cache = dyn.__dict__.setdefault("_mbsym_linearized", {})
    if names not in cache:
        sym = ca.SX if dyn.rhs.is_a("SXFunction") else ca.MX
        x, u, p = (sym.sym(s, n) for s, n in (("x", dyn.n_x), ("u", dyn.n_u), ("p", dyn.n_p)))
        xd = dyn.rhs(x, u, p)
        if names and dyn.outputs is not None:
            idx = [dyn.output_names.index(n) for n in names]
            y = dyn.outputs(x, u, p)[idx]
        else:
            y = sym(0, 1)
        cache[names] = ca.Function("linearized", [x, u, p], [ca.jacobian(xd, x), ca.jacobian(xd, u),
                                                              ca.jacobian(y, x), ca.jacobian(y, u), xd, y])
    return cache[names]


def linearize_point(trimmer, point, *, outputs: Sequence[str] | None = None,
                    keep_azimuth: bool = False, inflow: str = "dynamic") -> LinearModel:
    """The linear model about a trimmed point (module docstring), in SI units.

    Outputs are converted from their channel units to SI (:data:`SI_UNITS`: rpm → rad/s,
    deg → rad, kW → W, kN-m → N m …), so a quantity has one unit on inputs, states and outputs
    (``BlPitchCom``, ``BlPitch`` and ``BldPitch1`` in rad); ``output_units`` and
    ``input_units`` say which, and the repr shows them.

    Parameters
    ----------
    trimmer : Trimmer
        The trim problem the point came from (its model and parameters).
    point : TrimPoint
    outputs : sequence of str, optional, keyword-only
        Output channels; default ``RotSpeed``, ``GenSpeed``, ``BldPitch1``, ``GenPwr``,
        ``RtAeroFxh``, ``TTDspFA``, ``TwrBsMyt``, ``YawBrTAxp`` (those the model has).
    keep_azimuth : bool, optional, keyword-only
        Keep the free generator azimuth ``GeAz`` as a state. By default it is left out (as
        OpenFAST users do after MBC): it only integrates the rotor speed, and its zero
        eigenvalue with a zero at the origin makes ``dcgain`` 0 in python-control. With blade
        DOFs the model depends on the azimuth: by default it is then averaged over
        :data:`N_AZIMUTH` azimuths in multi-blade coordinates (``F1_coll``, ``F1_cos``, ``F1_sin`` …,
        as OpenFAST's MBC3), and ``keep_azimuth=True`` gives the model at the trim's azimuth in
        the blades' own coordinates.
    inflow : {"dynamic", "frozen", "quasi-steady"}, optional, keyword-only
        The rotor-averaged DBEMT states kept (default), removed with the induction held at the
        trim (as OpenFAST's frozen-wake linearization), or in equilibrium with the inflow
        (:mod:`.inflow_choice`).

    Returns
    -------
    LinearModel
        Inputs: the model's, without the waves' velocity at Morison members (``MorisonU…``: their drag is
        quadratic, so it has no first-order effect about a still-water trim).
        ``operating_point`` holds ``x``, ``u``, ``p``, ``xd`` (the trim residual, the azimuth
        row the rotor speed), ``y``, the wind speed, the regime and ``inflow``.

    Raises
    ------
    OptionError, ArgumentTypeError, UnsupportedFeatureError
        A bad ``inflow`` (:func:`~.inflow_choice.with_inflow`).
    """
    from .inflow_choice import check_inflow, with_inflow

    check_inflow(inflow)
    if not point.success:
        raise ModelDefinitionError(f"cannot linearize a failed operating point ({point.message}).")
    dyn, model = trimmer.dyn, trimmer.model
    default = ("RotSpeed", "GenSpeed", "BldPitch1", "GenPwr", "RtAeroFxh", "TTDspFA", "TwrBsMyt", "YawBrTAxp")
    names = tuple(outputs) if outputs is not None else tuple(n for n in default if n in dyn.output_names)
    if not keep_azimuth and "GeAz" in dyn.states and rotating_triplets(model.structure.eom.coordinates):
        return with_inflow(_azimuth_average(trimmer, point, names, keep_azimuth), inflow)
    lin = linearize_dynamics(dyn, point.state, point.inputs, dict(point.parameters), outputs=names)
    # the waves' velocity at Morison members: quadratic drag, no first-order effect about a still-water trim
    keep = [i for i, n in enumerate(dyn.inputs) if not n.startswith("MorisonU")]
    inputs, input_units = tuple(dyn.inputs[i] for i in keep), tuple(dyn.input_units[i] for i in keep)
    lin = {**lin, "B": np.asarray(lin["B"])[:, keep], "D": np.asarray(lin["D"])[:, keep]}
    eom = model.structure.eom
    M = structural_mass_matrix(trimmer, point)
    units = dict(zip(dyn.states, dyn.state_units))
    op = {"x": point.state.copy(), "u": np.asarray(point.inputs)[keep].copy(), "p": dict(point.parameters),
          "xd": lin["xd"],
          "y": lin["y"], "wind_speed": point.wind_speed, "regime": point.regime,
          "q": point.state[:eom.n_q].copy(), "qd": point.state[eom.n_q:2 * eom.n_q].copy()}
    empty = np.zeros((0, 0))
    factors, si_units = zip(*(to_si(u) for u in lin["units"])) if names else ((), ())
    scale = np.asarray(factors, dtype=float).reshape(-1, 1)
    op["y"] = op["y"] * scale.reshape(-1)
    result = LinearModel(M, empty, empty, np.zeros((0, len(keep))), lin["A"], lin["B"], eom.coordinates, dyn.states,
                         inputs, op, outputs=names, Cy=lin["C"] * scale, Dy=lin["D"] * scale,
                         output_units=tuple(si_units), method="exact", units=units, input_units=input_units)
    if not keep_azimuth and "GeAz" in result.states:
        result = result.without_states(["GeAz"])
    return with_inflow(result, inflow)


#: Units of the operating turbine's inputs (:mod:`mbsym.wind.operation.units`).
INPUT_UNITS = OPERATION_INPUT_UNITS
#: Channel unit -> (factor to SI, SI unit) for the outputs of linear models.
SI_UNITS = {"rpm": (math.pi / 30.0, "rad/s"), "deg": (math.pi / 180.0, "rad"), "deg/s": (math.pi / 180.0, "rad/s"),
            "deg/s^2": (math.pi / 180.0, "rad/s^2"), "kW": (1e3, "W"), "kN": (1e3, "N"), "kN-m": (1e3, "N m"),
            "kN m": (1e3, "N m"), "N-m": (1.0, "N m"), "%": (0.01, "-")}


def to_si(unit: str) -> tuple[float, str]:
    """(factor, SI unit) of a channel unit (:data:`SI_UNITS`; others are SI already: factor 1).

    Examples
    --------
    >>> to_si("rpm")[1], to_si("m/s")
    ('rad/s', (1.0, 'm/s'))
    """
    return SI_UNITS.get(unit, (1.0, unit))


#: Azimuths of one revolution at which a model with blade DOFs is linearized and averaged (OpenFAST's MBC3 users
#: take 12 to 36; the blade-element rung's default is 12 too).
N_AZIMUTH = 12


def _azimuth_average(trimmer, point, names: tuple[str, ...], keep_azimuth: bool) -> LinearModel:
    """The linear model of a trimmed rotor-effective turbine with blade DOFs: exact Jacobians at
    :data:`N_AZIMUTH` rotor azimuths of the trimmed state (the other states held), each written in multi-blade
    coordinates and averaged (:func:`~.blade_linear.mbc_average`), as OpenFAST's MBC3; the azimuth left out
    unless kept. The mass matrix is the azimuth average of ``T1ᵀ M T1``."""
    from ..structure.mbc import blade_indices, coleman_matrices, mbc_names
    from .blade_linear import mbc_average

    dyn, model = trimmer.dyn, trimmer.model
    eom = model.structure.eom
    keep = [i for i, n in enumerate(dyn.inputs) if not n.startswith("MorisonU")]
    i_az = dyn.states.index("GeAz")
    states, jac, masses = [], {k: [] for k in ("A", "B", "C", "D")}, []
    ys = []
    for k in range(N_AZIMUTH):
        x = point.state.copy()
        x[i_az] = point.state[i_az] + 2.0 * math.pi * k / N_AZIMUTH
        lin = linearize_dynamics(dyn, x, point.inputs, dict(point.parameters), outputs=names)
        for key in jac:
            jac[key].append(np.asarray(lin[key]))
        states.append(x)
        ys.append(lin["y"])
        masses.append(structural_mass_matrix(trimmer, point, state=x))
    factors, si_units = zip(*(to_si(u) for u in lin["units"])) if names else ((), ())
    scale = np.asarray(factors, dtype=float).reshape(-1, 1)
    sel = {"A": np.array(jac["A"]), "B": np.array(jac["B"])[:, :, keep], "C": np.array(jac["C"]) * scale[None],
           "D": np.array(jac["D"])[:, :, keep] * scale[None], "x": np.array(states)}
    frame = model.structure.rotating_frame()
    X = np.array(states)[:, :eom.n_q]
    blade_az = frame.azimuths(X[:, eom.coordinates.index("GeAz")], X)
    xs = point.x()
    speed = xs.get("GeAz_d", 0.0) + xs.get("DrTr_d", 0.0)
    inputs = tuple(dyn.inputs[i] for i in keep)
    avg = mbc_average(sel, dyn.states, inputs, names, blade_az, speed, keep_azimuth=keep_azimuth)
    groups = blade_indices(eom.coordinates)
    Mbar = sum(coleman_matrices(eom.n_q, groups, psi).T1.T @ M @ coleman_matrices(eom.n_q, groups, psi).T1
               for M, psi in zip(masses, blade_az)) / N_AZIMUTH
    on = [i for i, c in enumerate(eom.coordinates) if keep_azimuth or c != "GeAz"]
    coords = mbc_names(eom.coordinates, groups)
    units = dict(zip(dyn.states, dyn.state_units))
    op = {"x": avg["x"], "u": np.asarray(point.inputs)[keep].copy(), "p": dict(point.parameters),
          "y": np.mean(ys, axis=0) * scale.reshape(-1), "wind_speed": point.wind_speed, "regime": point.regime,
          "blade_azimuths": blade_az, "rotor_speed": speed}
    empty = np.zeros((0, 0))
    return LinearModel(0.5 * (Mbar + Mbar.T)[np.ix_(on, on)], empty, empty, np.zeros((0, len(keep))), avg["A"],
                       avg["B"], tuple(coords[i] for i in on), avg["states"], avg["inputs"], op,
                       outputs=avg["outputs"], Cy=avg["C"], Dy=avg["D"], output_units=tuple(si_units),
                       method="exact", units={avg["states"][j]: units[dyn.states[i]] for j, i in
                                              enumerate(avg["keep"])},
                       input_units=tuple(dyn.input_units[i] for i in keep))


def structural_mass_matrix(trimmer, point, *, state=None) -> np.ndarray:
    """The structure's mass matrix [kg, kg m, kg m²] at the point (pitch from the actuator state), or at
    ``state`` (the model's state vector) with the point's loads."""
    eom = trimmer.model.structure.eom
    x = point.x() if state is None else dict(zip(point.state_names, np.asarray(state).tolist()))
    values = {"BlPitch": x["BlPitch"], "BlPitch_d": x["BlPitch_d"], "BlPitch_dd": 0.0, "GenTq": x["GenTq"],
              "RotThrust": point["RtAeroFxh"], "RotTorq": point["RtAeroMxh"],
              "GeAz": x.get("GeAz", 0.0), "GeAz_d": point.parameters.get("rotor_speed", 0.0), "GeAz_dd": 0.0}
    u_struct = np.array([values.get(n, 0.0) for n in eom.inputs])
    p_struct = np.array([point.parameters[n] for n in eom.parameters])
    mass = eom.functions.mass_matrix
    q = (point.state if state is None else np.asarray(state))[:eom.n_q]
    M = mass(q, u_struct, p_struct) if mass.n_in() == 3 else mass(q, p_struct)
    return np.asarray(M, dtype=float)


@dataclass(frozen=True)
class AeroCampbell:
    """Labelled structural modes with aerodynamics over the operating points.

    Attributes
    ----------
    wind_speed, rpm : ndarray
        [m/s], rotor speed [rpm] of each point.
    modes : tuple of CampbellMode
        ``freq_hz`` [Hz] and ``damping_ratio`` [-] per point (NaN where not found).
    """

    wind_speed: np.ndarray
    rpm: np.ndarray
    modes: tuple

    def mode(self, label: str):
        for m in self.modes:
            if m.label == label:
                return m
        raise KeyError(f"no mode labelled {label!r}; labels are {[m.label for m in self.modes]}.")

    def plot(self, path, *, title: str | None = None) -> None:
        """Write frequency and damping over wind speed to ``path`` (:func:`~.trim_plot.plot_aero_campbell`)."""
        from .trim_plot import plot_aero_campbell

        plot_aero_campbell(self, path, title=title)

    def to_dict(self) -> dict:
        """``{"wind_speed", "rpm", "modes": [{"label", "freq_hz", "damping_ratio"}, ...]}`` (NaN -> None)."""
        def clean(a):
            return [None if not np.isfinite(v) else float(v) for v in a]

        return {"wind_speed": clean(self.wind_speed), "rpm": clean(self.rpm),
                "modes": [{"label": m.label, "freq_hz": clean(m.freq_hz), "damping_ratio": clean(m.damping_ratio)}
                          for m in self.modes]}


def aero_campbell(points) -> AeroCampbell:
    """Frequencies and damping ratios of the structural modes at each operating point (module docstring).

    Parameters
    ----------
    points : OperatingPoints

    Raises
    ------
    ModelDefinitionError
        Blade DOFs (the rotor aerodynamics load the hub only).
    """
    from .campbell_diagram import DOF_LABELS, CampbellMode

    trimmer = points.trimmer
    eom = trimmer.model.structure.eom
    blades = [c for c in eom.coordinates if c.startswith("B") and c[1:2].isdigit()]
    if blades:
        raise ModelDefinitionError(f"the Campbell diagram with aerodynamics needs rigid blades; the model has blade "
                                   f"DOFs {blades} (the rotor's performance surfaces load the hub only). Use "
                                   "mbsym.wind.analysis.campbell for the structure alone.")
    labels = [DOF_LABELS.get(c, c) for c in eom.coordinates if c != "GeAz"]
    ok = [p for p in points if p.success]
    freq = np.full((len(labels), len(ok)), np.nan)
    zeta = np.full_like(freq, np.nan)
    for k, point in enumerate(ok):
        lin = linearize_point(trimmer, point, outputs=(), keep_azimuth=True)
        for lab, f, z in zip(*_labelled_modes(lin, eom.coordinates, DOF_LABELS)):
            freq[labels.index(lab), k], zeta[labels.index(lab), k] = f, z
    modes = tuple(CampbellMode(lab, freq[i], zeta[i]) for i, lab in enumerate(labels))
    return AeroCampbell(np.array([p.wind_speed for p in ok]), np.array([p["RotSpeed"] for p in ok]), modes)


def _labelled_modes(lin: LinearModel, coordinates, dof_labels):
    """(labels, freq_hz, damping) of the oscillatory structural modes of one linear model (with or without the
    free azimuth: the structural block is taken by state name)."""
    coordinates = [c for c in coordinates if c in lin.states and f"{c}_d" in lin.states]
    n = len(coordinates)
    block = [lin.states.index(c) for c in coordinates] + [lin.states.index(f"{c}_d") for c in coordinates]
    A = lin.A
    lam_s, V = np.linalg.eig(A[np.ix_(block, block)])
    wn = np.abs(lam_s)
    keep = np.flatnonzero((lam_s.imag > 1e-6 * wn) & (wn > 2 * math.pi * 1e-5))
    if keep.size == 0:
        return [], [], []
    rows = [list(lin.coordinates).index(c) for c in coordinates]
    M = lin.M[np.ix_(rows, rows)]
    vecs = V[:n, keep]
    share = np.abs((vecs.conj() * (M @ vecs)).real)
    candidates = [i for i, c in enumerate(coordinates) if c != "GeAz"]
    S = share[candidates, :].T
    S = S / np.maximum(S.sum(axis=1, keepdims=True), 1e-300)
    rows, cols = linear_sum_assignment(S, maximize=True)
    lam_full = np.linalg.eigvals(A)
    lam_full = lam_full[lam_full.imag > 0]
    targets = lam_s[keep[rows]]
    if lam_full.size:
        cost = np.abs(targets[:, None] - lam_full[None, :]) / np.maximum(np.abs(targets[:, None]), 1e-12)
        r2, c2 = linear_sum_assignment(cost)
        matched = targets.copy()
        matched[r2] = lam_full[c2]
    else:
        matched = targets
    names = [dof_labels.get(coordinates[candidates[c]], coordinates[candidates[c]]) for c in cols]
    return names, np.abs(matched) / (2 * math.pi), -matched.real / np.abs(matched)


#: Words for the non-structural states of the operating turbine (state group -> mode label).
STATE_LABELS = {"GeAz": "rotor speed", "GeAz_d": "rotor speed", "BlPitch": "pitch actuator",
                "GenTq": "generator-torque actuator", "DBEMT_w": "dynamic inflow (DBEMT_w)",
                "DBEMT_v": "dynamic inflow (DBEMT_v)", "RotThrustLag": "inflow lag (thrust)",
                "RotTorqLag": "inflow lag (torque)"}


def mode_label(mode) -> str:
    """Words for a mode of an operating turbine's linear model (a :class:`mbsym.linear.state_modes.StateMode`).

    Structural state groups by :data:`~.campbell_diagram.DOF_LABELS` ("1st tower fore-aft"),
    blade DOFs as "blade 1 1st flap" or in multi-blade coordinates as "1st flap collective", "1st edge cyclic
    (cos)", actuators, inflow and rotor speed by :data:`STATE_LABELS`,
    HydroDyn's radiation and excitation states as "radiation memory (Rdtn7)", SubDyn's Craig–Bampton coordinates
    as "substructure mode 2 (SSqm02)",
    any other state (a controller's) as "controller state <name>" when its name is qualified
    (``baseline.first``), else by its name; a rigid-body mode as "rigid body (<group>)".

    Examples
    --------
    >>> from mbsym.linear.state_modes import StateMode
    >>> mode_label(StateMode(7.96, 0.7, 5.7, -35 + 35.7j, "BlPitch"))
    'pitch actuator'
    >>> mode_label(StateMode(0.07, 0.54, 0.4, -0.24 + 0.37j, "Rdtn26"))
    'radiation memory (Rdtn26)'
    >>> mode_label(StateMode(0.6, 0.02, 3.8, -0.08 + 3.8j, "F1_coll"))
    '1st flap collective'
    >>> mode_label(StateMode(25.4, 0.01, 160.0, -1.6 + 160.0j, "SSqm01"))
    'substructure mode 1 (SSqm01)'
    """
    from ..structure.dofs import blade_dof
    from .campbell_diagram import DOF_LABELS

    name = mode.dominant_dof
    if getattr(mode, "rigid_body", False):
        return f"rigid body ({name})"
    words = {"F1": "1st flap", "E1": "1st edge", "F2": "2nd flap"}
    blade = blade_dof(name)
    if blade:
        return f"blade {blade[0]} " + words.get(blade[1], blade[1])
    stem, _, part = name.rpartition("_")
    if stem in words and part in ("coll", "cos", "sin"):             # multi-blade coordinates
        return f"{words[stem]} " + {"coll": "collective", "cos": "cyclic (cos)", "sin": "cyclic (sin)"}[part]
    if name in STATE_LABELS:
        return STATE_LABELS[name]
    for prefix, words in (("Rdtn", "radiation memory"), ("Exctn", "wave-excitation state")):
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            return f"{words} ({name})"
    for prefix in ("SSqmd", "SSqm"):                                  # SubDyn's Craig-Bampton coordinates
        if name.startswith(prefix) and name[len(prefix):].isdigit():
            return f"substructure mode {int(name[len(prefix):])} ({name})"
    if name in DOF_LABELS:
        return DOF_LABELS[name]
    return f"controller state {name}" if "." in name else name


def whirl_labels(labels: Sequence[str], freqs_hz: Sequence[float]) -> list[str]:
    """``labels`` with each pair of cyclic modes of one blade mode told apart by their whirl.

    In multi-blade coordinates a blade mode of rotating-frame frequency ``ω`` appears in the fixed frame as a
    backward-whirling mode near ``ω − Ω`` and a forward-whirling one near ``ω + Ω`` (Bir 2008); the dominant
    coordinate (cos or sin) of each is a matter of phase, so both were often labelled "(cos)". Where exactly two
    modes carry a family's cyclic label ("1st flap cyclic (cos)", "... (sin)"), the lower frequency becomes
    "1st flap cyclic (backward whirl)" and the higher "(forward whirl)"; other labels are returned unchanged.

    Examples
    --------
    >>> whirl_labels(["1st flap cyclic (cos)", "1st flap collective", "1st flap cyclic (cos)"], [0.92, 0.7, 0.52])
    ['1st flap cyclic (forward whirl)', '1st flap collective', '1st flap cyclic (backward whirl)']
    """
    out = list(labels)
    families: dict[str, list[int]] = {}
    for i, label in enumerate(out):
        for part in (" cyclic (cos)", " cyclic (sin)"):
            if label.endswith(part):
                families.setdefault(label[:-len(part)], []).append(i)
    for family, idx in families.items():
        if len(idx) == 2 and freqs_hz[idx[0]] != freqs_hz[idx[1]]:
            low, high = sorted(idx, key=lambda i: freqs_hz[i])
            out[low], out[high] = f"{family} cyclic (backward whirl)", f"{family} cyclic (forward whirl)"
    return out


def numbered_labels(labels: Sequence[str], freqs_hz: Sequence[float]) -> list[str]:
    """``labels`` made distinct: where several modes share a label (one dominant state for two modes, e.g. a
    monopile's first and second tower-substructure modes both led by ``TFA1``, or the two poles of a controller's
    second-order filter), the lowest frequency keeps it and the others get " (2)", " (3)", … by frequency.

    Examples
    --------
    >>> numbered_labels(["1st tower fore-aft", "pitch actuator", "1st tower fore-aft"], [1.16, 7.96, 0.175])
    ['1st tower fore-aft (2)', 'pitch actuator', '1st tower fore-aft']
    """
    out = list(labels)
    groups: dict[str, list[int]] = {}
    for i, label in enumerate(out):
        groups.setdefault(label, []).append(i)
    for label, idx in groups.items():
        for k, i in enumerate(sorted(idx, key=lambda j: freqs_hz[j])[1:], start=2):
            out[i] = f"{label} ({k})"
    return out
