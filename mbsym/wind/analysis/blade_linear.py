"""Linear models of a blade-element turbine about its periodic operating point, in multi-blade coordinates.

As OpenFAST's linearization with MBC3 (Bir 2008): at ``N`` equally spaced azimuths of one
revolution of the periodic state (:func:`~.blade_periodic.periodic_point`) the model
``ẋ = f(x, u, p)``, ``y = h(x, u, p)`` is differentiated exactly
(:func:`~.blade_periodic.azimuth_jacobians`); each linear model is written in multi-blade
coordinates (:func:`mbsym.wind.structure.mbc.mbc_system`) with blade 1's azimuth at that
sample, and the matrices are averaged over the azimuths. Every per-blade triplet is
transformed — blade DOFs and their speeds (``F1_coll``, ``F1_cos``, ``F1_sin``, ``F1_coll_d`` …),
per-blade pitch actuators (``BlPitch_coll`` …), the dynamic-wake states of the same node on the
three blades (``N5_vind_x_coll`` …), the inputs ``BlPitchCom1..3`` (``BlPitchCom_coll``: the
collective pitch; ``_cos``, ``_sin``: the cyclic pitch) and outputs such as ``RootMyc1..3``
(``RootMyc_coll``; ``RootMyc_cos`` is the tilt and ``RootMyc_sin`` the yaw combination: with the
azimuth measured from blade 1 up, ``RootMyc_b = coll + cos cos ψ_b + sin sin ψ_b``).

Units are SI throughout: states as the model's (m, rad, m/s, rad/s, N m), inputs (m/s, rad,
N m, the shears dimensionless), outputs converted from OpenFAST's units (rpm -> rad/s,
kN m -> N m, deg -> rad, kW -> W). The rotor azimuth ``GeAz`` is left out by default (its
column averages out and its row is the rotor speed), as OpenFAST users do after MBC.

:func:`blade_aero_campbell` gives the Campbell diagram with aerodynamic damping over wind
speed, labelled as :func:`mbsym.wind.analysis.campbell` labels the structure's modes (tower,
drivetrain, blade collective / forward / backward whirl): on the structural block of the
averaged ``A`` (structure + aerodynamic derivatives with frozen wake) by kinetic energy with
the azimuth-averaged mass matrix in multi-blade coordinates, then matched to the nearest
eigenvalue of the whole ``A`` (dynamic wake, actuators), which is the one reported.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from ...exceptions import ParameterError
from ...linear import LinearModel
from ..structure.mbc import (blade_indices, coleman_matrices, derivative_pairs, mbc_names, mbc_state_matrices,
                             mbc_system, rotating_triplets)
from .blade_periodic import PeriodicPoint, azimuth_jacobians, periodic_point
from .trim_linear import to_si

__all__ = ["blade_linear_model", "blade_statespace", "mbc_average", "blade_aero_campbell", "DEFAULT_OUTPUTS",
           "default_inputs", "SI_FACTORS"]

#: Default outputs (OpenFAST channel names; in SI in the linear model).
DEFAULT_OUTPUTS = ("RootMyc1", "RootMyc2", "RootMyc3", "RotSpeed", "GenSpeed", "TTDspFA", "TTDspSS", "TwrBsMyt")
#: OpenFAST unit -> factor to SI.
SI_FACTORS = {"rpm": math.pi / 30.0, "deg": math.pi / 180.0, "deg/s": math.pi / 180.0, "kN": 1e3, "kN-m": 1e3,
              "kW": 1e3, "deg/s^2": math.pi / 180.0}


def default_inputs(model) -> tuple[str, ...]:
    """Pitch commands (per blade or collective), ``GenTqCom``, ``Wind1VelX``, ``HLinShr``, ``VLinShr``."""
    return tuple(model.command_names) + tuple(n for n in ("Wind1VelX", "HLinShr", "VLinShr")
                                              if n in model.dynamics().inputs)


def mbc_average(jac: Mapping[str, np.ndarray], states: Sequence[str], inputs: Sequence[str],
                outputs: Sequence[str], blade_azimuths, rotor_speed: float, *, keep_azimuth: bool = False,
                azimuth_state: str = "GeAz") -> dict:
    """Average of azimuth-wise linear models in multi-blade coordinates (module docstring).

    Parameters
    ----------
    jac : mapping
        ``A`` (n_s, n_x, n_x), ``B`` (n_s, n_x, n_u), ``C`` (n_s, n_y, n_x), ``D`` (n_s, n_y, n_u),
        optionally ``x`` (n_s, n_x) the states.
    states, inputs, outputs : sequence of str
        Names (per-blade triplets found by :func:`~mbsym.wind.structure.mbc.rotating_triplets`).
    blade_azimuths : array (n_s,)
        Blade-1 azimuth of each sample [rad].
    rotor_speed : float
        [rad/s].
    keep_azimuth : bool, keyword-only
        Keep the state ``azimuth_state`` (default: left out).

    Returns
    -------
    dict
        ``A``, ``B``, ``C``, ``D`` averaged; ``states``, ``inputs``, ``outputs`` (renamed);
        ``x`` (mean state in multi-blade coordinates, when given); ``T_at(psi) -> (T, dT/dt)``
        of the states (all states).
    """
    tx, tu, ty = rotating_triplets(states), rotating_triplets(inputs), rotating_triplets(outputs)
    pairs = derivative_pairs(states, tx)
    psi = np.asarray(blade_azimuths, dtype=float).reshape(-1)
    om = float(rotor_speed)
    acc = None
    xs = []
    for k, ps in enumerate(psi):
        mats = mbc_system(jac["A"][k], jac["B"][k], jac["C"][k], jac["D"][k], ps, om, states=tx, derivatives=pairs,
                          inputs=tu, outputs=ty)
        acc = list(mats) if acc is None else [a + m for a, m in zip(acc, mats)]
        if "x" in jac:
            T, _ = mbc_state_matrices(len(states), tx, ps, om, derivatives=pairs)
            xs.append(np.linalg.solve(T, jac["x"][k]))
    A, B, C, D = (a / psi.size for a in acc)
    names_x = mbc_names(states, tx)
    keep = [i for i, n in enumerate(states) if keep_azimuth or n != azimuth_state]
    out = {"A": A[np.ix_(keep, keep)], "B": B[keep], "C": C[:, keep], "D": D,
           "states": tuple(names_x[i] for i in keep), "inputs": mbc_names(inputs, tu),
           "outputs": mbc_names(outputs, ty), "keep": keep,
           "T_at": lambda ps: mbc_state_matrices(len(states), tx, ps, om, derivatives=pairs)}
    if xs:
        out["x"] = np.mean(xs, axis=0)[keep]
    return out


def blade_linear_model(model, point: PeriodicPoint, *, inputs: Sequence[str] | None = None,
                       outputs: Sequence[str] | None = None, keep_azimuth: bool = False,
                       inflow: str = "dynamic") -> LinearModel:
    """The azimuth-averaged linear model in multi-blade coordinates about a periodic point (module docstring).

    Parameters
    ----------
    model : OperatingTurbine
        The blade-element turbine ``point`` belongs to.
    point : PeriodicPoint
        From :func:`~.blade_periodic.periodic_point`.
    inputs : sequence of str, optional, keyword-only
        Model inputs to keep (default :func:`default_inputs`).
    outputs : sequence of str, optional, keyword-only
        OpenFAST channels (default :data:`DEFAULT_OUTPUTS`, those the model has).
    keep_azimuth : bool, keyword-only
        Keep the rotor azimuth state ``GeAz`` (default: left out).
    inflow : {"dynamic", "frozen", "quasi-steady"}, keyword-only
        The wake states of every node kept (default; OpenFAST's ``DBEMT_Mod = 3``), removed with
        the induced velocities held at the periodic point (frozen wake, ``DBEMT_Mod = -1``), or in
        equilibrium with each node's inflow (quasi-steady, ``DBEMT_Mod = 0``), applied at every
        azimuth in the rotating frame before the multi-blade transformation
        (:mod:`.inflow_choice`).

    Returns
    -------
    LinearModel
        ``A``, ``B``, ``Cy``, ``Dy`` in SI with renamed states, inputs and outputs; ``M`` is the
        azimuth-averaged structural mass matrix in multi-blade coordinates (azimuth left out
        unless kept); ``operating_point`` holds the mean state ``x`` (multi-blade coordinates),
        ``u``, mean outputs ``y`` (SI), ``wind``, ``rotor_speed``, ``residual_norm``,
        ``blade_azimuths``, ``inflow``. ``.to_statespace()`` gives the named ``control.StateSpace``.

    Raises
    ------
    ParameterError
        Unknown input or output names, or a point of another model.
    OptionError, ArgumentTypeError
        A bad ``inflow``.
    """
    from .inflow_choice import check_inflow

    check_inflow(inflow)
    dyn = model.dynamics()
    if tuple(point.state_names) != tuple(dyn.states):
        raise ParameterError("the periodic point belongs to another model (its states differ); compute it with "
                             "periodic_point(model, ...).")
    ins = tuple(inputs) if inputs is not None else default_inputs(model)
    outs = tuple(outputs) if outputs is not None else tuple(n for n in DEFAULT_OUTPUTS if n in dyn.output_names)
    unknown = [n for n in ins if n not in dyn.inputs]
    if unknown:
        raise ParameterError(f"unknown inputs {unknown}; the model has {list(dyn.inputs)}.")
    pv = dyn.parameter_vector(dict(point.parameters))
    jac = azimuth_jacobians(dyn, point.states, point.inputs, pv, outputs=outs)
    cols = [dyn.inputs.index(n) for n in ins]
    units = [dyn.output_units[dyn.output_names.index(n)] for n in outs]
    f = np.array([SI_FACTORS.get(u, 1.0) for u in units])
    sel = {"A": jac["A"], "B": jac["B"][:, :, cols], "C": jac["C"] * f[None, :, None],
           "D": jac["D"][:, :, cols] * f[None, :, None], "x": point.states}
    sel, states, held = _apply_inflow(sel, dyn.states, inflow)
    avg = mbc_average(sel, states, ins, outs, point.blade_azimuths, point.rotor_speed, keep_azimuth=keep_azimuth)
    M, coords = _mass_in_mbc(model, point, keep_azimuth)
    op = {"x": avg["x"], "u": np.asarray(point.inputs)[cols], "y": np.mean(jac["y"], axis=0) * f,
          "wind": dict(point.wind), "commands": dict(point.commands), "rotor_speed": point.rotor_speed,
          "residual_norm": point.residual_norm, "blade_azimuths": np.asarray(point.blade_azimuths).copy(),
          "p": dict(point.parameters), "inflow": inflow}
    if held:
        op["removed_states"] = held
    state_units = [u for s, u in zip(dyn.states, dyn.state_units) if s in states]
    units_x = {avg["states"][j]: state_units[i] for j, i in enumerate(avg["keep"])}
    empty = np.zeros((0, 0))
    return LinearModel(M, empty, empty, np.zeros((0, len(ins))), avg["A"], avg["B"], coords, avg["states"],
                       avg["inputs"], op, outputs=avg["outputs"], Cy=avg["C"], Dy=avg["D"],
                       output_units=tuple(to_si(u)[1] for u in units), method="exact", units=units_x,
                       input_units=tuple(dyn.input_units[dyn.inputs.index(n)] for n in ins))   # MBC renames in place


def _apply_inflow(sel: dict, states: Sequence[str], inflow: str) -> tuple[dict, tuple[str, ...], dict]:
    """The azimuth-wise matrices with the inflow choice applied (:func:`~.inflow_choice.reduce_inflow` at every
    sample, rotating frame), the remaining state names and the mean values of the removed states."""
    from .inflow_choice import reduce_inflow

    if inflow == "dynamic":
        return sel, tuple(states), {}
    out: dict = {"A": [], "B": [], "C": [], "D": []}
    keep: list[int] = []
    for k in range(sel["A"].shape[0]):
        mats = reduce_inflow(sel["A"][k], sel["B"][k], sel["C"][k], sel["D"][k], states, inflow)
        for name, m in zip("ABCD", mats[:4]):
            out[name].append(m)
        keep = mats[4]
    reduced = {name: np.asarray(v) for name, v in out.items()}
    reduced["x"] = np.asarray(sel["x"])[:, keep]
    dropped = [i for i in range(len(states)) if i not in set(keep)]
    held = {states[i]: float(np.mean(np.asarray(sel["x"])[:, i])) for i in dropped}
    return reduced, tuple(states[i] for i in keep), held


def blade_statespace(model, point: PeriodicPoint, *, inputs: Sequence[str] | None = None,
                     outputs: Sequence[str] | None = None, keep_azimuth: bool = False, name: str | None = None):
    """:func:`blade_linear_model` as a named ``control.StateSpace`` (python-control).

    The operating point is the attribute ``operating_point`` (dict, see :func:`blade_linear_model`).
    """
    lin = blade_linear_model(model, point, inputs=inputs, outputs=outputs, keep_azimuth=keep_azimuth)
    return lin.to_statespace(name=name)


def _mass_in_mbc(model, point: PeriodicPoint, keep_azimuth: bool) -> tuple[np.ndarray, tuple[str, ...]]:
    """Azimuth average of ``T1ᵀ M T1`` [kg, kg m, kg m²] and the coordinate names in multi-blade coordinates."""
    eom = model.structure.eom
    dyn = model.dynamics()
    n = eom.n_q
    groups = blade_indices(eom.coordinates)
    p_all = dict(point.parameters)
    p_s = np.array([p_all[k] for k in eom.parameters])
    mass = eom.functions.mass_matrix
    Mbar = np.zeros((n, n))
    for x, psi in zip(point.states, point.blade_azimuths):
        xs = dict(zip(dyn.states, x))
        u_s = np.array([xs.get(name, 0.0) for name in eom.inputs])
        M = np.asarray(mass(x[:n], u_s, p_s) if mass.n_in() == 3 else mass(x[:n], p_s), dtype=float)
        T1 = coleman_matrices(n, groups, psi).T1
        Mbar += T1.T @ M @ T1
    Mbar = 0.5 * (Mbar + Mbar.T) / len(point.blade_azimuths)
    keep = [i for i, c in enumerate(eom.coordinates) if keep_azimuth or c != "GeAz"]
    names = mbc_names(eom.coordinates, groups)
    return Mbar[np.ix_(keep, keep)], tuple(names[i] for i in keep)


# ---------------------------------------------------------------------- Campbell diagram
def blade_aero_campbell(model, starts, *, wind: Mapping[str, float] | None = None, n_azimuth: int = 12,
                        tol: float = 1e-4, max_revolutions: int = 12, p: Mapping[str, float] | None = None,
                        progress=None):
    """Frequencies and damping ratios of the labelled modes over wind speed, with blade-element aerodynamics.

    Parameters
    ----------
    model : OperatingTurbine
        Blade-element turbine (GenDOF on).
    starts : OperatingPoints or sequence of TrimPoint
        Trims of the rotor-effective model of the same deck
        (:func:`~.operating_points.operating_points`): each gives the wind speed, the held pitch and
        torque and the starting rotor speed of one periodic point.
    wind : dict, optional, keyword-only
        Other uniform-wind inputs at every point (e.g. ``{"VShrExp": 0.2}``).
    n_azimuth, tol, max_revolutions, p : optional, keyword-only
        As :func:`~.blade_periodic.periodic_point`.
    progress : callable, optional, keyword-only
        Called with each :class:`~.blade_periodic.PeriodicPoint`.

    Returns
    -------
    AeroCampbell
        The chart style of :func:`~.trim_linear.aero_campbell` (``plot(path)``); ``rpm`` is the
        mean rotor speed of each periodic point [rpm].
    """
    from .campbell_diagram import CampbellMode
    from .trim_linear import AeroCampbell

    points = [s for s in starts if s.success]
    per: list[tuple[list, np.ndarray, np.ndarray]] = []
    speeds, rpm = [], []
    for start in points:
        w = {"Wind1VelX": float(start.wind_speed), **dict(wind or {})}
        point = periodic_point(model, w, start=start, n_azimuth=n_azimuth, tol=tol, max_revolutions=max_revolutions,
                               p=p)
        if progress is not None:
            progress(point)
        lin = blade_linear_model(model, point, outputs=(), keep_azimuth=True)
        per.append(labelled_modes(lin))
        speeds.append(start.wind_speed)
        rpm.append(point.rotor_speed * 30 / math.pi)
    labels: list[str] = []
    for lab, _, _ in per:
        labels += [x for x in lab if x not in labels]
    freq = np.full((len(labels), len(per)), np.nan)
    zeta = np.full_like(freq, np.nan)
    for k, (lab, f, z) in enumerate(per):
        for name, fk, zk in zip(lab, f, z):
            freq[labels.index(name), k], zeta[labels.index(name), k] = fk, zk
    order = np.argsort([np.nanmin(r) if np.any(np.isfinite(r)) else np.inf for r in freq], kind="stable")
    modes = tuple(CampbellMode(labels[i], freq[i], zeta[i]) for i in order)
    return AeroCampbell(np.asarray(speeds, dtype=float), np.asarray(rpm), modes)


def labelled_modes(lin: LinearModel) -> tuple[list[str], np.ndarray, np.ndarray]:
    """``(labels, freq_hz, damping_ratio)`` of the structural modes of a :func:`blade_linear_model` (module docstring).

    ``lin`` must keep the azimuth (``keep_azimuth=True``): the structural block is ``[q; q̇]`` of
    every coordinate, the rotor's rotation included (the collective edge mode turns the rotor
    against the generator).
    """
    from scipy.optimize import linear_sum_assignment

    from .campbell_diagram import _label_modes

    if "GeAz" not in lin.coordinates:
        raise ParameterError("labelled_modes needs the rotor azimuth in the model: blade_linear_model(..., "
                             "keep_azimuth=True).")
    coords = tuple(_blade_name(c) for c in lin.coordinates)
    n = len(coords)
    groups = blade_indices(coords)
    A = lin.A
    modes = _label_modes(A[:2 * n, :2 * n], lin.M, coords, coords, groups, 0.0, None)
    zeta = modes.damping_ratio
    lam_s = 2 * np.pi * modes.freq_hz * (-zeta + 1j * np.sqrt(np.maximum(1 - zeta**2, 0.0)))
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag > 0]
    if lam.size and lam_s.size:
        cost = np.abs(lam_s[:, None] - lam[None, :]) / np.maximum(np.abs(lam_s[:, None]), 1e-12)
        r, c = linear_sum_assignment(cost)
        lam_s = lam_s.copy()
        lam_s[r] = lam[c]
    return list(modes.labels), np.abs(lam_s) / (2 * np.pi), -lam_s.real / np.abs(lam_s)


def _blade_name(name: str) -> str:
    """``F1_coll`` -> ``B1F1``, ``_cos`` -> blade 2, ``_sin`` -> blade 3 (the triplet's positions), for the labels."""
    stem, _, part = name.rpartition("_")
    k = {"coll": 1, "cos": 2, "sin": 3}.get(part)
    return f"B{k}{stem}" if k and stem in ("F1", "E1", "F2") else name
