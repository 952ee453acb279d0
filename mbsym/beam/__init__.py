"""Numeric preprocessing of flexible beams (pure numpy/scipy, no CasADi).

From distributed beam properties and shape functions to the standard input data
(shape integrals, Taylor terms, geometric stiffness) consumed by the symbolic
engine; finite-element cantilever modes; rotating-beam (Southwell) utilities.

Convention: the beam lies along the body's local z axis from the root (z = 0,
body origin) to the tip (z = L) and bends in x and y. See :class:`ShapeIntegrals`
for every field, its units and the sign of the geometric stiffness.
"""

from mbsym.beam.fem import BeamModes, cantilever_modes, fit_elastodyn_polynomial
from mbsym.beam.integrals import quadrature_weights, shape_integrals
from mbsym.beam.loads import DistributedLoadIntegrals, distributed_load_integrals
from mbsym.beam.lumped import lumped_shape_integrals
from mbsym.beam.nodes import LumpedNodes, NodeMoments
from mbsym.beam.shapes import CallableShape, HermiteShape, PolynomialShape, ShapeFunction
from mbsym.beam.sid import ShapeIntegrals, Taylor, damping_matrix, skew
from mbsym.beam.stiffening import (
    axial_geometric_stiffness,
    rotating_stiffness,
    southwell_coefficients,
    spin_softening,
)

__all__ = [
    "ShapeIntegrals",
    "Taylor",
    "ShapeFunction",
    "PolynomialShape",
    "CallableShape",
    "HermiteShape",
    "BeamModes",
    "shape_integrals",
    "lumped_shape_integrals",
    "LumpedNodes",
    "NodeMoments",
    "distributed_load_integrals",
    "DistributedLoadIntegrals",
    "quadrature_weights",
    "damping_matrix",
    "cantilever_modes",
    "fit_elastodyn_polynomial",
    "axial_geometric_stiffness",
    "spin_softening",
    "rotating_stiffness",
    "southwell_coefficients",
    "skew",
]
