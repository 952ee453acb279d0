"""Bad beam data raises BeamDataError (a ValueError) naming what is wrong and how to fix it."""

from __future__ import annotations

import numpy as np
import pytest

from mbsym.beam import (
    CallableShape,
    PolynomialShape,
    ShapeIntegrals,
    Taylor,
    cantilever_modes,
    damping_matrix,
    fit_elastodyn_polynomial,
    shape_integrals,
)
from mbsym.exceptions import BeamDataError, DimensionError

L = 10.0
Z = np.linspace(0.0, L, 6)
SHAPE = PolynomialShape([1.0], L)


def good(**kw):
    args = dict(z=Z, mass_per_length=np.full(6, 2.0), stiffness_x=np.full(6, 1e4), stiffness_y=np.full(6, 1e4),
                shapes=SHAPE)
    args.update(kw)
    return shape_integrals(**args)


def test_good_data_builds():
    assert good().n_e == 1


def test_beam_data_error_is_a_value_error():
    assert issubclass(BeamDataError, ValueError)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"z": [0, 2, 4, 4, 8, 10]}, r"stations must increase strictly; station 3 \(z=4 m\) <= station 2 \(z=4 m\)"),
        ({"z": [0, 2, 6, 4, 8, 10]}, r"station 3 \(z=4 m\) <= station 2 \(z=6 m\). Sort the stations"),
        ({"z": [0, 2, np.nan, 6, 8, 10]}, r"station 2 is nan; stations must be finite"),
        ({"mass_per_length": np.ones(5)}, r"`mass_per_length` has shape \(5,\); expected a scalar or \(6,\)"),
        ({"mass_per_length": [1, 1, np.nan, 1, 1, 1]}, r"`mass_per_length` at station 2 is nan"),
        ({"mass_per_length": [1, 1, 0, 1, 1, 1]}, r"`mass_per_length` at station 2 is 0 kg/m; it must be > 0"),
        ({"stiffness_x": [1, -5, 1, 1, 1, 1]}, r"`stiffness_x` at station 1 is -5 N m\^2; it must be > 0"),
        ({"stiffness_y": [1, 1, 1, 1, 1, np.inf]}, r"`stiffness_y` at station 5 is inf"),
        ({"twist": [0, 0, np.nan, 0, 0, 0]}, r"`twist` at station 2 is nan"),
        ({"z": np.linspace(1, 10, 6)}, r"must span \[0, L\] = \[0, 10\] m; got \[1, 10\] m"),
        ({"z": np.linspace(0, 12, 6)}, r"stations span \[0, 12\] m but the shapes have length L=10 m"),
        ({"shapes": [SHAPE, PolynomialShape([1.0], 11.0)]}, r"same length"),
        ({"shapes": []}, r"`shapes` is empty"),
        ({"shapes": ["x"]}, r"shapes\[0\] is a str; expected a ShapeFunction"),
        ({"shapes": CallableShape(lambda z: 1 + z, L)}, r"shape 0 \('callable'\) does not satisfy the clamped root"),
        ({"shapes": CallableShape(lambda z: 0 * z, L)}, r"shape 0 \('callable'\) is zero at every station"),
        ({"shapes": CallableShape(lambda z: np.where(z > 5, np.nan, z**2), L)}, r"derivative 0 is not finite at z=6 m"),
        ({"quadrature": "gauss"}, r"unknown quadrature 'gauss'"),
        ({"quadrature": np.ones(5)}, r"`quadrature weights` has shape \(5,\)"),
        ({"quadrature": [1, 1, -1, 1, 1, 1]}, r"`quadrature weights` at station 2 is -1"),
        ({"quadrature": np.ones(6), "n_points": 100}, r"n_points cannot be combined"),
        ({"n_points": 1}, r"n_points must be >= 2"),
        ({"damping": "rayleigh"}, r"unknown damping method 'rayleigh'"),
        ({"damping_ratios": [0.01, 0.02]}, r"damping_ratios has 2 entries; expected 1"),
        ({"damping_ratios": [-0.01]}, r"damping_ratios must be finite and >= 0"),
        ({"tip_mass": -1.0}, r"tip_mass must be finite and >= 0"),
        ({"tip_inertia": [[1, 2, 0], [0, 1, 0], [0, 0, 1]]}, r"tip_inertia must be a finite symmetric"),
    ],
)
def test_bad_beam_data(kwargs, match):
    with pytest.raises(BeamDataError, match=match):
        good(**kwargs)


def test_root_check_can_be_disabled():
    """A shape that does not vanish at the root is accepted with check_root=False (documented)."""
    sid = good(shapes=CallableShape(lambda z: 1 + z / L, L), check_root=False)
    assert sid.me[0, 0] > 0


def test_unknown_keyword_is_a_type_error():
    with pytest.raises(TypeError):
        good(tipmass=3.0)


@pytest.mark.parametrize(
    "make, match",
    [
        (lambda: PolynomialShape([0.5, 0.4], L), r"sum to 0.9; expected 1 within 0.0015 .* normalize=True"),
        (lambda: PolynomialShape([0.5, np.nan], L), r"finite numbers"),
        (lambda: PolynomialShape([1.0, -1.0], L, normalize=True), r"cannot normalize"),
        (lambda: PolynomialShape([1.0], -2.0), r"length must be positive"),
        (lambda: PolynomialShape([1.0], L, "z"), r"direction must be 'x', 'y' or a vector"),
        (lambda: PolynomialShape([1.0], L, [0, 0, 1]), r"transverse"),
        (lambda: CallableShape("not callable", L), r"`function` must be callable"),
        (lambda: CallableShape(lambda z: np.vstack([z, z, z]), L, None).evaluate([1.0]), r"z-component must be 0"),
        (lambda: CallableShape(lambda z: z, L).evaluate([1.0], 3), r"derivative must be 0, 1 or 2"),
    ],
)
def test_bad_shapes(make, match):
    with pytest.raises(BeamDataError, match=match):
        make()


def test_elastodyn_sum_tolerance_boundary():
    """ElastoDyn's rule: |sum - 1| <= 0.0015 accepted, beyond rejected."""
    PolynomialShape([0.5, 0.5014], L)
    with pytest.raises(BeamDataError, match="sum to 1.0016"):
        PolynomialShape([0.5, 0.5016], L)


def test_fem_errors():
    with pytest.raises(BeamDataError, match=r"first station must be the clamped root z=0"):
        cantilever_modes([1.0, 2.0], 1.0, 1.0)
    with pytest.raises(BeamDataError, match=r"unstable under the axial load"):
        cantilever_modes([0.0, 1.0], 1.0, 1.0, axial_force=[-10.0, -10.0])  # Euler load pi^2/4 = 2.47
    with pytest.raises(BeamDataError, match=r"n_modes <= 2\*n_elements"):
        cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=5, n_elements=2)
    with pytest.raises(BeamDataError, match=r"`stiffness` at station 0 is -1"):
        cantilever_modes([0.0, 1.0], 1.0, [-1.0, 1.0])
    with pytest.raises(BeamDataError, match=r"mode index 3 out of range"):
        cantilever_modes([0.0, 1.0], 1.0, 1.0, n_modes=3).shape(3)
    with pytest.raises(BeamDataError, match=r"give the deflection `values`"):
        fit_elastodyn_polynomial([0.0, 1.0])


def test_sid_container_errors():
    sid = good()
    with pytest.raises(DimensionError, match=r"me: shape \(2, 2\), expected \(1, 1\)"):
        ShapeIntegrals(**{**sid.__dict__, "me": np.eye(2)})
    with pytest.raises(BeamDataError, match=r"me must be symmetric"):
        ShapeIntegrals(**{**sid.__dict__, "n_e": 2, **_resized(sid, 2), "me": np.array([[1.0, 0.5], [0.0, 1.0]])})
    with pytest.raises(BeamDataError, match=r"NaN or Inf"):
        ShapeIntegrals(**{**sid.__dict__, "ke": np.array([[np.nan]])})
    with pytest.raises(DimensionError, match=r"Taylor.order1 has shape \(1, 2, 2\); expected \(n_e, \*\(3, 3\)\)"):
        Taylor(np.eye(3), np.ones((1, 2, 2)))
    with pytest.raises(DimensionError, match=r"q_e has 2 entries; expected 1"):
        sid.mxt.evaluate([0.1, 0.2])
    with pytest.raises(BeamDataError, match=r"exactly one of `ratios` or `matrix`"):
        sid.with_damping()
    with pytest.raises(BeamDataError, match=r"positive diagonal"):
        damping_matrix([[0.0]], [[1.0]], [0.01])
    # a failed call leaves the original unchanged and read-only
    assert sid.n_e == 1 and not sid.me.flags.writeable


def _resized(sid, n):
    """Zero-filled fields of a consistent SID with n shapes (to reach the symmetry check)."""
    z = np.zeros
    return {"mxt": Taylor(sid.mxt.order0, z((n, 3, 3))), "mtt": Taylor(sid.mtt.order0, z((n, 3, 3))),
            "ct": z((n, 3)), "cr": Taylor(z((n, 3)), z((n, n, 3))), "gr": Taylor(z((n, 3, 3)), z((n, n, 3, 3))),
            "ge": z((n, n, 3)), "oe": Taylor(z((n, 3, 3)), z((n, n, 3, 3))), "ke": np.eye(n), "de": z((n, n)),
            "kg_t": z((3, n, n)), "kg_r": z((3, n, n)), "kg_omega": z((3, 3, n, n)), "kg_tip": z((3, n, n)),
            "end_displacement": z((3, n)), "end_rotation": z((3, n)), "frequencies_hz": z(n), "mtt2": None}
