"""Shape integrals (standard input data) of a straight beam from distributed properties.

Implements the paper's Appendices A, B, C and D3 (Branlard & Geisler, WES 7, 2022)
by quadrature on beam stations; see :class:`mbsym.beam.ShapeIntegrals` for the
definition and sign convention of each field.
"""

from __future__ import annotations

from typing import Literal, Sequence

import numpy as np
from numpy.typing import ArrayLike

from mbsym.beam.shapes import ShapeFunction
from mbsym.beam.sid import ShapeIntegrals, Taylor, _frequencies, damping_matrix, skew
from mbsym.beam.stiffening import unit_geometric_stiffness
from mbsym.exceptions import BeamDataError

__all__ = ["shape_integrals", "quadrature_weights", "check_stations"]

_ROOT_RTOL = 1e-6


def check_stations(z: ArrayLike, *, name: str = "z") -> np.ndarray:
    """Return stations as a float array after checking they are finite and increasing.

    Raises
    ------
    BeamDataError
        Fewer than 2 stations, NaN/Inf, or not strictly increasing (names the station).
    """
    zz = np.asarray(z, dtype=float).reshape(-1)
    if zz.size < 2:
        raise BeamDataError(f"`{name}` needs at least 2 stations; got {zz.size}.")
    bad = np.flatnonzero(~np.isfinite(zz))
    if bad.size:
        raise BeamDataError(f"`{name}` station {bad[0]} is {zz[bad[0]]}; stations must be finite numbers [m].")
    dec = np.flatnonzero(np.diff(zz) <= 0)
    if dec.size:
        k = dec[0] + 1
        raise BeamDataError(
            f"stations must increase strictly; station {k} ({name}={zz[k]:g} m) <= station {k - 1} "
            f"({name}={zz[k - 1]:g} m). Sort the stations or remove duplicates."
        )
    return zz


def _check_property(name: str, values: ArrayLike, n: int, *, positive: bool = True, unit: str = "") -> np.ndarray:
    v = np.asarray(values, dtype=float)
    if v.ndim == 0:
        v = np.full(n, float(v))
    v = v.reshape(-1) if v.ndim == 1 else v
    if v.shape != (n,):
        raise BeamDataError(f"`{name}` has shape {np.shape(values)}; expected a scalar or ({n},), one value per station.")
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        raise BeamDataError(f"`{name}` at station {bad[0]} is {v[bad[0]]}; values must be finite {unit}.")
    if positive:
        bad = np.flatnonzero(v <= 0)
        if bad.size:
            raise BeamDataError(
                f"`{name}` at station {bad[0]} is {v[bad[0]]:g} {unit}; it must be > 0. "
                "Check units and signs of the distributed properties."
            )
    return v


def quadrature_weights(z: ArrayLike, rule: Literal["trapezoid", "simpson"] = "trapezoid") -> np.ndarray:
    """Quadrature weights on (possibly non-uniform) stations.

    Parameters
    ----------
    z : array_like, shape (n,)
        Strictly increasing stations [m].
    rule : {"trapezoid", "simpson"}
        Composite trapezoid, or scipy's composite Simpson rule (non-uniform allowed).

    Returns
    -------
    numpy.ndarray, shape (n,)
        Weights ``w`` [m] such that ``int f dz ~ sum w f(z)``.

    Examples
    --------
    >>> quadrature_weights([0.0, 1.0, 2.0])
    array([0.5, 1. , 0.5])
    """
    zz = check_stations(z)
    if rule == "trapezoid":
        h = np.diff(zz)
        return np.concatenate([[0.0], h]) / 2 + np.concatenate([h, [0.0]]) / 2
    if rule == "simpson":
        from scipy.integrate import simpson      # imported on use: keeps `import mbsym` light

        return simpson(np.eye(zz.size), x=zz, axis=1)
    raise BeamDataError(f"unknown quadrature {rule!r}; expected 'trapezoid', 'simpson' or an array of weights.")


def _common_length(shapes: Sequence[ShapeFunction]) -> float:
    lengths = np.array([s.length for s in shapes])
    if np.any(np.abs(lengths - lengths[0]) > 1e-9 * lengths[0]):
        raise BeamDataError(f"all shapes must have the same length; got {lengths.tolist()} m.")
    return float(lengths[0])


def _as_shapes(shapes: ShapeFunction | Sequence[ShapeFunction]) -> list[ShapeFunction]:
    lst = [shapes] if isinstance(shapes, ShapeFunction) else list(shapes)
    if not lst:
        raise BeamDataError("`shapes` is empty; give at least one ShapeFunction.")
    for k, s in enumerate(lst):
        if not isinstance(s, ShapeFunction):
            raise BeamDataError(f"shapes[{k}] is a {type(s).__name__}; expected a ShapeFunction "
                                "(PolynomialShape, CallableShape, HermiteShape, BeamModes.shape(k)).")
    return lst


def _evaluate_shapes(shapes: list[ShapeFunction], z: np.ndarray, L: float, check_root: bool) -> list[np.ndarray]:
    out = []
    for d in range(3):
        arr = np.stack([s.evaluate(z, d) for s in shapes])  # (n_e, 3, n)
        bad = np.argwhere(~np.isfinite(arr))
        if bad.size:
            j = bad[0][0]
            raise BeamDataError(f"shape {j} ({shapes[j].name!r}) derivative {d} is not finite at z={z[bad[0][2]]:g} m.")
        out.append(arr)
    scale = np.abs(out[0]).max(axis=(1, 2))
    for j, s in enumerate(shapes):
        if scale[j] == 0:
            raise BeamDataError(f"shape {j} ({s.name!r}) is zero at every station; it moves no mass.")
    if check_root:
        root = [s.evaluate([0.0], d)[:, 0] for s in shapes for d in (0, 1)]
        for j, s in enumerate(shapes):
            v0, s0 = np.abs(root[2 * j]).max(), np.abs(root[2 * j + 1]).max() * L
            if max(v0, s0) > _ROOT_RTOL * scale[j]:
                raise BeamDataError(
                    f"shape {j} ({s.name!r}) does not satisfy the clamped root condition: |Phi(0)|={v0:.3g}, "
                    f"L |Phi'(0)|={s0:.3g} (max |Phi|={scale[j]:.3g}). The body origin must be a clamped "
                    "root; fix the shape or pass check_root=False if this is intended."
                )
    return out


def _inertial_terms(dm: np.ndarray, pos: np.ndarray, phi: np.ndarray) -> dict:
    """Mass shape integrals (A3-A7, A11-A13) from point masses.

    dm (p,), pos (p, 3) undeflected positions, phi (n_e, p, 3) shape values.
    """
    sp, sf = skew(pos), skew(phi)  # (p,3,3), (n_e,p,3,3)
    ssp = np.einsum("p,pab,jpbc->jac", dm, sp, sf)  # int s~ Phi~_j
    sps = np.einsum("p,jpab,pbc->jac", dm, sf, sp)  # int Phi~_j s~
    ff = np.einsum("p,kpab,jpbc->kjac", dm, sf, sf)  # [k, j] = int Phi~_k Phi~_j
    return {
        "mass": dm.sum(),
        "mxt": Taylor(-np.einsum("p,pab->ab", dm, sp), -np.einsum("p,jpab->jab", dm, sf)),
        "mtt": Taylor(-np.einsum("p,pab,pbc->ac", dm, sp, sp), -(ssp + sps)),
        "ct": np.einsum("p,jpa->ja", dm, phi),
        "cr0": np.einsum("p,pab,jpb->ja", dm, sp, phi),  # int s x Phi_j
        "cr1": np.einsum("p,kpab,jpb->kja", dm, sf, phi),
        "me": np.einsum("p,ipa,jpa->ij", dm, phi, phi),
        "gr": Taylor(-2.0 * ssp, -2.0 * ff),
        "ge": -2.0 * np.einsum("p,ipa,jpab->jib", dm, phi, sf),
        "oe": Taylor(sps, np.swapaxes(ff, 0, 1)),
        "mtt2": -ff,
    }


def _bending_stiffness(w, ddphi, eix, eiy, twist) -> np.ndarray:
    """K_e,ij = int Phi_i''^T E Phi_j'' with E = R(theta) diag(EI_x, EI_y) R(theta)^T."""
    c, s = np.cos(twist), np.sin(twist)
    exx, eyy, exy = eix * c**2 + eiy * s**2, eix * s**2 + eiy * c**2, (eix - eiy) * c * s
    ax, ay = ddphi[:, 0, :], ddphi[:, 1, :]
    return (np.einsum("k,ik,jk->ij", w * exx, ax, ax) + np.einsum("k,ik,jk->ij", w * eyy, ay, ay)
            + np.einsum("k,ik,jk->ij", w * exy, ax, ay) + np.einsum("k,ik,jk->ij", w * exy, ay, ax))


def _tip_inertia(tip_inertia) -> np.ndarray:
    if tip_inertia is None:
        return np.zeros((3, 3))
    j = np.asarray(tip_inertia, dtype=float)
    j = np.diag(j) if j.shape == (3,) else j
    if j.shape != (3, 3) or not np.all(np.isfinite(j)) or np.abs(j - j.T).max() > 1e-9 * max(np.abs(j).max(), 1):
        raise BeamDataError(f"tip_inertia must be a finite symmetric 3x3 matrix or 3 principal values [kg m^2]; got {j.tolist()}.")
    if np.linalg.eigvalsh(j).min() < 0:
        raise BeamDataError("tip_inertia must be positive semi-definite.")
    return j


def shape_integrals(
    z: ArrayLike,
    mass_per_length: ArrayLike,
    stiffness_x: ArrayLike,
    stiffness_y: ArrayLike,
    shapes: ShapeFunction | Sequence[ShapeFunction],
    *,
    twist: ArrayLike | None = None,
    damping_ratios: ArrayLike | None = None,
    damping: Literal["stiffness-proportional", "modal"] = "stiffness-proportional",
    tip_mass: float = 0.0,
    tip_inertia: ArrayLike | None = None,
    quadrature: Literal["trapezoid", "simpson"] | ArrayLike = "trapezoid",
    n_points: int | None = None,
    check_root: bool = True,
) -> ShapeIntegrals:
    """Standard input data of a straight beam along local z from distributed properties.

    Parameters
    ----------
    z : array_like, shape (n,)
        Strictly increasing stations [m] (root at 0). With a named rule they must
        span ``[0, L]``, ``L`` being the shapes' length.
    mass_per_length : array_like (n,) or float
        ``m(z)`` [kg/m], > 0.
    stiffness_x, stiffness_y : array_like (n,) or float
        Bending stiffness resisting deflection along x (paper ``EI_y``) and along y
        (``EI_x``) [N m^2], > 0. With ``twist`` they are the principal stiffnesses.
    shapes : ShapeFunction or sequence of them
        The ``n_e`` shape functions, clamped at the root, all of length ``L``.
    twist : array_like (n,) or float, optional, keyword-only
        Structural twist ``theta(z)`` [rad]: the principal axis of ``stiffness_x`` is
        body x rotated by ``theta`` about +z; ``E = R diag(EI_x, EI_y) R^T``.
    damping_ratios : array_like (n_e,), optional, keyword-only
        Damping ratio per shape as a fraction (0.01 = 1 %). Default: no damping.
    damping : {"stiffness-proportional", "modal"}, keyword-only
        See :func:`mbsym.beam.damping_matrix` (ElastoDyn's rule is the default); the
        frequency of shape j is ``sqrt(K_e,jj / M_e,jj) / 2 pi`` of this body (tip mass
        included, no geometric stiffness).
    tip_mass : float, keyword-only
        Point mass at ``z = L`` [kg], treated as part of the body (rigid terms, ``M_e``,
        and the axial force in ``kg_t`` / ``kg_omega``).
    tip_inertia : array_like (3, 3) or (3,), optional, keyword-only
        Rotational inertia of the tip point about itself, body axes [kg m^2]. Adds to
        ``mtt.order0``, to ``cr.order0`` (``J Psi``) and to ``me`` (``Psi^T J Psi``),
        ``Psi`` = ``end_rotation``; its q_e-dependent and gyroscopic terms are neglected.
    quadrature : {"trapezoid", "simpson"} or array_like (n,), keyword-only
        Rule on the stations, or explicit weights [m] (e.g. ElastoDyn's element lengths
        with stations at element mid-points; then ``M_out`` at station k is
        ``dm_k / 2 + sum_{l > k} dm_l`` as in ElastoDyn). With a named rule the outboard
        mass and first moment are cumulative trapezoid integrals of the linearly
        interpolated properties.
    n_points : int, optional, keyword-only
        Refine: add ``n_points`` equally spaced stations over ``[0, L]`` (properties and
        twist linearly interpolated). Only with a named rule.
    check_root : bool, keyword-only
        Require ``Phi(0) = Phi'(0) = 0`` (relative tolerance 1e-6 of max |Phi|), raising
        :class:`BeamDataError` otherwise. Default True.

    Returns
    -------
    ShapeIntegrals

    Raises
    ------
    BeamDataError
        Non-increasing stations, mismatched lengths, non-positive or non-finite
        properties, shapes not clamped at the root, bad weights or options.

    Examples
    --------
    >>> from mbsym.beam import PolynomialShape
    >>> sid = shape_integrals([0.0, 10.0], 1.0, 1.0, 1.0, PolynomialShape([1.0], 10.0),
    ...                       quadrature="simpson", n_points=201)
    >>> round(float(sid.me[0, 0]), 6)   # int (z/L)^4 dz = L/5
    2.0
    """
    if damping not in ("stiffness-proportional", "modal"):
        raise BeamDataError(f"unknown damping method {damping!r}; expected 'stiffness-proportional' or 'modal'.")
    shapes = _as_shapes(shapes)
    L = _common_length(shapes)
    zz = check_stations(z)
    n = zz.size
    m = _check_property("mass_per_length", mass_per_length, n, unit="kg/m")
    eix = _check_property("stiffness_x", stiffness_x, n, unit="N m^2")
    eiy = _check_property("stiffness_y", stiffness_y, n, unit="N m^2")
    th = np.zeros(n) if twist is None else _check_property("twist", twist, n, positive=False, unit="rad")
    tip_mass = float(tip_mass)
    if not (np.isfinite(tip_mass) and tip_mass >= 0):
        raise BeamDataError(f"tip_mass must be finite and >= 0; got {tip_mass} kg.")
    if zz[0] < -1e-9 * L or zz[-1] > L * (1 + 1e-9):
        raise BeamDataError(f"stations span [{zz[0]:g}, {zz[-1]:g}] m but the shapes have length L={L:g} m; "
                            "stations must lie within [0, L].")

    if isinstance(quadrature, str):
        if abs(zz[0]) > 1e-9 * L or abs(zz[-1] - L) > 1e-9 * L:
            raise BeamDataError(
                f"with quadrature={quadrature!r} the stations must span [0, L] = [0, {L:g}] m; got "
                f"[{zz[0]:g}, {zz[-1]:g}] m. Add root and tip stations or pass explicit weights."
            )
        if n_points is not None:
            if int(n_points) < 2:
                raise BeamDataError(f"n_points must be >= 2; got {n_points}.")
            zf = np.union1d(zz, np.linspace(0.0, L, int(n_points)))
            zf = zf[np.concatenate([[True], np.diff(zf) > 1e-12 * L])]
            m, eix, eiy, th = (np.interp(zf, zz, v) for v in (m, eix, eiy, th))
            zz = zf
        from scipy.integrate import cumulative_trapezoid      # imported on use (import time of mbsym)

        w = quadrature_weights(zz, quadrature)
        m_out = (lambda c: c[-1] - c)(cumulative_trapezoid(m, zz, initial=0.0))
        s_out = (lambda c: c[-1] - c)(cumulative_trapezoid(m * zz, zz, initial=0.0))
        dm = m * w
    else:
        if n_points is not None:
            raise BeamDataError("n_points cannot be combined with explicit quadrature weights.")
        w = _check_property("quadrature weights", quadrature, n, unit="m")
        dm = m * w
        m_out = np.cumsum(dm[::-1])[::-1] - dm / 2
        s_out = np.cumsum((dm * zz)[::-1])[::-1] - dm * zz / 2
    m_out, s_out = m_out + tip_mass, s_out + tip_mass * L

    phi, dphi, ddphi = _evaluate_shapes(shapes, zz, L, check_root)
    tip = [np.stack([s.evaluate([L], d)[:, 0] for s in shapes], axis=1) for d in (0, 1)]  # (3, n_e)
    psi = np.vstack([-tip[1][1], tip[1][0], np.zeros(len(shapes))])

    pos = np.zeros((zz.size, 3))
    pos[:, 2] = zz
    pts_phi = np.transpose(phi, (0, 2, 1))
    if tip_mass > 0:
        dm = np.append(dm, tip_mass)
        pos = np.vstack([pos, [0.0, 0.0, L]])
        pts_phi = np.concatenate([pts_phi, tip[0].T[:, None, :]], axis=1)
    t = _inertial_terms(dm, pos, pts_phi)
    jt = _tip_inertia(tip_inertia)
    ke = _bending_stiffness(w, ddphi, eix, eiy, th)
    me = t["me"] + psi.T @ jt @ psi
    de = np.zeros_like(ke) if damping_ratios is None else damping_matrix(ke, me, damping_ratios, method=damping)
    kg = unit_geometric_stiffness(w, dphi, m_out, s_out)
    return ShapeIntegrals(
        mass=t["mass"], n_e=len(shapes), mxt=t["mxt"],
        mtt=Taylor(t["mtt"].order0 + jt, t["mtt"].order1), ct=t["ct"],
        cr=Taylor(t["cr0"] + (jt @ psi).T, t["cr1"]), me=me, gr=t["gr"], ge=t["ge"], oe=t["oe"],
        ke=ke, de=de, **kg, end_position=np.array([0.0, 0.0, L]), end_displacement=tip[0],
        end_rotation=psi, frequencies_hz=_frequencies(ke, me), mtt2=t["mtt2"],
    )
