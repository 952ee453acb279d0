"""Euler-Bernoulli cantilever modes by finite elements, and ElastoDyn polynomial fits.

Hermite cubic elements (deflection and slope per node), consistent mass matrix,
properties linearly interpolated from the stations and integrated by 4-point Gauss
quadrature on each element (exact for linearly varying mass and stiffness). Clamped
at ``z = 0``. Optional tip mass and rotational inertia, axial pre-load, and
centrifugal tension (with spin softening for in-plane bending).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from mbsym.beam.integrals import _check_property, check_stations
from mbsym.beam.shapes import HermiteShape, ShapeFunction, _hermite_basis
from mbsym.exceptions import BeamDataError

__all__ = ["BeamModes", "cantilever_modes", "fit_elastodyn_polynomial"]

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
_GAUSS_X, _GAUSS_W = (_GAUSS_X + 1) / 2, _GAUSS_W / 2  # on [0, 1]
#: Frequencies shown by ``repr(BeamModes)``.
_REPR_MODES = 6


@dataclass(frozen=True)
class BeamModes:
    """Mode shapes of a cantilever, normalised to unit tip deflection (as ElastoDyn).

    Attributes
    ----------
    frequencies_hz : ndarray (n_modes,)
        Natural frequencies [Hz], ascending.
    nodes : ndarray (n_nodes,)
        Finite-element nodes [m], ``nodes[0] = 0``.
    displacements, slopes : ndarray (n_modes, n_nodes)
        Nodal deflection [m] and slope [-] of each mode, tip deflection = 1.
    direction : str or ndarray
        Deflection direction in the body frame (``"x"`` or ``"y"``).
    """

    frequencies_hz: np.ndarray
    nodes: np.ndarray
    displacements: np.ndarray
    slopes: np.ndarray
    direction: str | np.ndarray

    @property
    def n_modes(self) -> int:
        """Number of modes."""
        return self.frequencies_hz.size

    def shape(self, k: int, *, name: str | None = None) -> HermiteShape:
        """Mode ``k`` (0-based) as a :class:`~mbsym.beam.shapes.HermiteShape`."""
        if not -self.n_modes <= k < self.n_modes:
            raise BeamDataError(f"mode index {k} out of range; {self.n_modes} modes were computed.")
        return HermiteShape(self.nodes, self.displacements[k], self.slopes[k], self.direction,
                            name=name or f"mode {k + 1} ({self.frequencies_hz[k]:.4g} Hz)")

    def shapes(self) -> list[HermiteShape]:
        """All modes as shape functions."""
        return [self.shape(k) for k in range(self.n_modes)]

    def __repr__(self) -> str:
        """One line: modes and their frequencies (the first :data:`_REPR_MODES`), nodes, direction; the arrays
        are attributes (their repr ran to a hundred lines)."""
        f = self.frequencies_hz
        shown = ", ".join(f"{v:.4g}" for v in f[:_REPR_MODES]) + (", ..." if f.size > _REPR_MODES else "")
        direction = repr(self.direction) if isinstance(self.direction, str) else \
            "[" + ", ".join(f"{v:.3g}" for v in np.ravel(self.direction)) + "]"
        return (f"BeamModes({self.n_modes} mode{'s' if self.n_modes != 1 else ''}: {shown} Hz; "
                f"{self.nodes.size} nodes over [{self.nodes[0]:g}, {self.nodes[-1]:g}] m; direction {direction})")


def _element_matrices(nodes, zs, m, ei, axial):
    """Stacked element stiffness, mass and geometric matrices, shape (n_el, 4, 4)."""
    h = np.diff(nodes)
    zg = nodes[:-1, None] + h[:, None] * _GAUSS_X[None, :]  # (n_el, 4)
    mg, eg = np.interp(zg, zs, m), np.interp(zg, zs, ei)
    ng = axial(zg)
    wg = h[:, None] * _GAUSS_W[None, :]
    b0 = np.stack([_hermite_basis(_GAUSS_X, hh, 0) for hh in h])  # (n_el, 4 dofs, 4 gauss)
    b1 = np.stack([_hermite_basis(_GAUSS_X, hh, 1) for hh in h])
    b2 = np.stack([_hermite_basis(_GAUSS_X, hh, 2) for hh in h])
    k = np.einsum("eg,eag,ebg->eab", wg * eg, b2, b2)
    mm = np.einsum("eg,eag,ebg->eab", wg * mg, b0, b0)
    kg = np.einsum("eg,eag,ebg->eab", wg * ng, b1, b1)
    return k, mm, kg


def _assemble(el: np.ndarray) -> np.ndarray:
    n_el = el.shape[0]
    out = np.zeros((2 * n_el + 2, 2 * n_el + 2))
    for e in range(n_el):
        out[2 * e:2 * e + 4, 2 * e:2 * e + 4] += el[e]
    return out[2:, 2:]  # clamped root: deflection and slope of node 0 removed


def cantilever_modes(
    z: ArrayLike,
    mass_per_length: ArrayLike,
    stiffness: ArrayLike,
    *,
    n_modes: int = 3,
    n_elements: int = 50,
    direction: str = "x",
    tip_mass: float = 0.0,
    tip_inertia: float = 0.0,
    axial_force: ArrayLike | None = None,
    rotor_speed: float = 0.0,
    hub_radius: float = 0.0,
    in_plane: bool = False,
) -> BeamModes:
    """Bending modes of a beam clamped at ``z = 0`` and free at ``z = L = z[-1]``.

    Parameters
    ----------
    z : array_like, shape (n,)
        Strictly increasing stations [m], ``z[0] = 0``.
    mass_per_length : array_like (n,) or float
        [kg/m], > 0.
    stiffness : array_like (n,) or float
        Bending stiffness resisting the deflection ``direction`` [N m^2], > 0.
    n_modes : int, keyword-only
        Number of modes returned.
    n_elements : int, keyword-only
        Number of equal-length elements (frequency error ~ (1/n_elements)^4).
    direction : {"x", "y"}, keyword-only
        Deflection direction of the returned shapes (body frame).
    tip_mass : float, keyword-only
        Point mass at the tip [kg].
    tip_inertia : float, keyword-only
        Rotational inertia of the tip mass about the axis normal to the bending plane [kg m^2].
    axial_force : array_like (n,), optional, keyword-only
        Axial pre-load at the stations, tension positive [N] (e.g. ``-g * M_out(z)``
        for a tower's self weight).
    rotor_speed : float, keyword-only
        Spin ``Omega`` [rad/s] about an axis perpendicular to the beam through
        ``z = -hub_radius``: adds the centrifugal tension
        ``Omega^2 [int_z^L m (r + z') dz' + M_tip (r + L)]``.
    hub_radius : float, keyword-only
        ``r`` [m].
    in_plane : bool, keyword-only
        The deflection lies in the rotation plane: add the spin softening
        ``-Omega^2 M`` (tip inertia excluded).

    Returns
    -------
    BeamModes

    Raises
    ------
    BeamDataError
        Bad beam data, or the pre-loaded beam is unstable (buckled).

    Examples
    --------
    >>> modes = cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=1, n_elements=20)
    >>> round(float(modes.frequencies_hz[0] * 2 * np.pi), 4)   # 1.875104^2
    3.516
    """
    from scipy.integrate import cumulative_trapezoid     # imported on use: keeps `import mbsym` light
    from scipy.linalg import eigh

    zs = check_stations(z)
    if abs(zs[0]) > 0:
        raise BeamDataError(f"the first station must be the clamped root z=0; got z[0]={zs[0]:g} m.")
    m = _check_property("mass_per_length", mass_per_length, zs.size, unit="kg/m")
    ei = _check_property("stiffness", stiffness, zs.size, unit="N m^2")
    n_el = int(n_elements)
    if n_el < 1 or not 1 <= int(n_modes) <= 2 * n_el:
        raise BeamDataError(f"need n_elements >= 1 and 1 <= n_modes <= 2*n_elements; got {n_elements}, {n_modes}.")
    for name, val in (("tip_mass", tip_mass), ("tip_inertia", tip_inertia)):
        if not (np.isfinite(val) and val >= 0):
            raise BeamDataError(f"{name} must be finite and >= 0; got {val}.")
    L = zs[-1]
    nodes = np.linspace(0.0, L, n_el + 1)
    n_pre = np.zeros(zs.size) if axial_force is None else _check_property(
        "axial_force", axial_force, zs.size, positive=False, unit="N")
    om2 = float(rotor_speed) ** 2
    zf = np.union1d(zs, np.linspace(0.0, L, 20 * n_el + 1))
    c = cumulative_trapezoid(np.interp(zf, zs, m) * (hub_radius + zf), zf, initial=0.0)
    n_cent = om2 * (c[-1] - c + tip_mass * (hub_radius + L))

    def axial(zq: np.ndarray) -> np.ndarray:
        return np.interp(zq, zs, n_pre) + np.interp(zq, zf, n_cent)

    k_el, m_el, g_el = _element_matrices(nodes, zs, m, ei, axial)
    kk, mm = _assemble(k_el) + _assemble(g_el), _assemble(m_el)
    mm[-2, -2] += tip_mass
    if in_plane:
        kk -= om2 * mm
    mm[-1, -1] += tip_inertia
    # Solve M v = mu K v for the largest mu = 1/omega^2: K (clamped) is better conditioned
    # than M when some nodes carry almost no mass; K not positive definite = buckled.
    n_dof = kk.shape[0]
    try:
        mu, vec = eigh(mm, kk, subset_by_index=[n_dof - int(n_modes), n_dof - 1])
    except np.linalg.LinAlgError:
        mu = np.zeros(1)
    if mu.min() <= 0:
        raise BeamDataError("the beam is unstable under the axial load (stiffness not positive definite); "
                            "reduce the compression or check its sign (tension positive).")
    lam, vec = 1.0 / mu[::-1], vec[:, ::-1]
    disp = np.vstack([np.zeros(vec.shape[1]), vec[0::2]]).T
    slope = np.vstack([np.zeros(vec.shape[1]), vec[1::2]]).T
    tipv = disp[:, -1].copy()
    small = np.abs(tipv) < 1e-8 * np.abs(disp).max(axis=1)
    tipv[small] = np.abs(disp[small]).max(axis=1)
    disp, slope = disp / tipv[:, None], slope / tipv[:, None]
    return BeamModes(np.sqrt(lam) / (2 * np.pi), nodes, disp, slope, direction)


def fit_elastodyn_polynomial(
    z: ArrayLike | ShapeFunction,
    values: ArrayLike | None = None,
    *,
    length: float | None = None,
    n_points: int = 101,
    weights: ArrayLike | None = None,
) -> np.ndarray:
    """Least-squares fit of ElastoDyn's ``sum_{k=2..6} c_k (z/L)^k`` with ``sum c_k = 1``.

    Parameters
    ----------
    z : array_like (n,) or ShapeFunction
        Stations [m], or a directional shape (e.g. ``BeamModes.shape(0)``), then
        sampled at ``n_points`` equally spaced stations along its direction.
    values : array_like (n,)
        Deflection at the stations, normalised to 1 at the tip (the constraint forces
        ``phi(L) = 1``). Not used with a shape.
    length : float, optional, keyword-only
        ``L`` [m]; default ``z[-1]`` (or the shape's length).
    n_points : int, keyword-only
        Sampling for a shape input.
    weights : array_like (n,), optional, keyword-only
        Least-squares weights.

    Returns
    -------
    numpy.ndarray, shape (5,)
        Coefficients of x^2 ... x^6, summing to 1 (to rounding).

    Examples
    --------
    >>> zz = np.linspace(0, 2, 11)
    >>> np.round(fit_elastodyn_polynomial(zz, (zz / 2) ** 3), 9) + 0.0
    array([0., 1., 0., 0., 0.])
    """
    if isinstance(z, ShapeFunction):
        shape = z
        d = getattr(shape, "direction", None)
        if d is None:
            raise BeamDataError("fit_elastodyn_polynomial needs a shape with a single direction.")
        length = shape.length if length is None else length
        zz = np.linspace(0.0, shape.length, int(n_points))
        v = d @ shape.evaluate(zz) / (d @ d)
    else:
        zz = check_stations(z)
        if values is None:
            raise BeamDataError("give the deflection `values` at the stations.")
        v = _check_property("values", values, zz.size, positive=False)
    L = float(zz[-1] if length is None else length)
    if not (np.isfinite(L) and L > 0):
        raise BeamDataError(f"length must be positive; got {L}.")
    w = np.ones(zz.size) if weights is None else _check_property("weights", weights, zz.size)
    a = (zz[:, None] / L) ** np.arange(2, 7)[None, :] * np.sqrt(w)[:, None]
    # c = c_p + N y with sum(c_p) = 1 and N spanning {sum = 0}; y by SVD least squares
    from scipy.linalg import null_space                   # imported on use: keeps `import mbsym` light

    c_p = np.full(5, 0.2)
    null = null_space(np.ones((1, 5)))
    y = np.linalg.lstsq(a @ null, v * np.sqrt(w) - a @ c_p, rcond=None)[0]
    return c_p + null @ y
