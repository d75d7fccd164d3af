"""Composite quadrature over all-pentagon meshes: the paper's rule and cheaper ones.

Every rule cuts each (convex) cell into sectors ``(c, γ)`` — an apex and an edge — and
integrates over each one in collapsed coordinates::

    ∫∫_sector f = ∫_0^1 ∫_0^1 r f((1 - r) c + r γ(s)) |det(γ(s) - c, γ'(s))| dr ds,

with a tensor Gauss rule in ``(r, s)``; for a straight edge the determinant is twice the
triangle's area. The rules (``order = n``, :mod:`.registry`):

======  ==================================  =============================  ==========  ======
rule    triangles per cell                  points in (r, s) per triangle  per cell    degree
======  ==================================  =============================  ==========  ======
paper   5, apex at the cell's vertex mean   (n+1) Gauss-Legendre x n GL    5 n (n+1)   2n - 1
jacobi  5, apex at the cell's vertex mean   n Gauss-Jacobi(0, 1) x n GL    5 n^2       2n - 1
fan     3, fanned from the cell's corner 0  n Gauss-Jacobi(0, 1) x n GL    3 n^2       2n - 1
======  ==================================  =============================  ==========  ======

``"paper"`` is the rule of the seed's FIFTH program and reproduces Tables 1-11
(:mod:`blockmesh.tables`; the convention is in ``docs/mathematics.md`` §6). Here each point is
formed as a fixed linear combination of the cell's 5 corners (one matrix product per chunk of
cells), which equals the program's ``xs`` up to round-off. Gauss rules are accurate to the last
bit (:mod:`blockmesh.numerics.gauss`).

The package, one job per module: :mod:`.rule` (the record of a rule: nodes on the unit square
and a layout of sectors), :mod:`.layouts`, one module per rule (:mod:`.paper`, :mod:`.jacobi`,
:mod:`.fan`), :mod:`.registry`, :mod:`.kernel` (points in chunks, cell sums),
:mod:`.estimate` (error estimates of a fixed rule), :mod:`.targets` (what to integrate over, the
work budget), :mod:`.fixed` (:func:`integrate`, :func:`integrate_cells`,
:func:`integrate_with_estimate`, :func:`quadrature_points`) and :mod:`.adaptive`
(:func:`integrate_to_tolerance`).

Examples
--------
>>> from blockmesh.mesh import Mesh
>>> sp = Mesh.from_cells([(-1, -1), (1, -1), (2, 0), (0, 1), (-2, 0)], [[0, 1, 2, 3, 4]])
>>> round(integrate(sp, "(x^4 + y^3) / (1 + x^2)", order=10, level=2), 13)
1.9240305426326
>>> integrate_cells(sp, "x", order=1, level=1).shape
(6,)
"""

from blockmesh.quadrature.adaptive import integrate_to_tolerance
from blockmesh.quadrature.fixed import (
    DEFAULT_WARN_RTOL,
    integrate,
    integrate_cells,
    integrate_with_estimate,
    quadrature_points,
)
from blockmesh.quadrature.kernel import DEFAULT_CHUNK
from blockmesh.quadrature.registry import RULES, get_rule, rule_info
from blockmesh.quadrature.result import IntegrationResult
from blockmesh.quadrature.rule import Layout, Rule, RuleInfo, SectorNodes
from blockmesh.quadrature.targets import DEFAULT_MAX_POINTS

__all__ = [
    "DEFAULT_CHUNK",
    "DEFAULT_MAX_POINTS",
    "DEFAULT_WARN_RTOL",
    "RULES",
    "IntegrationResult",
    "Layout",
    "Rule",
    "RuleInfo",
    "SectorNodes",
    "get_rule",
    "integrate",
    "integrate_cells",
    "integrate_to_tolerance",
    "integrate_with_estimate",
    "quadrature_points",
    "rule_info",
]
