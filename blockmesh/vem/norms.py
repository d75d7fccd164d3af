"""Error norms of a virtual element solution against an exact solution.

A virtual element function is not known inside a cell, only its projections are, so the errors are
measured on them, cell by cell, with the composite quadrature of :mod:`blockmesh.vem.rules`:

* ``l2``: ``‖u - Π⁰u_h‖`` over the domain,
* ``h1``: the broken H1 seminorm ``(Σ_E ‖∇u - ∇Π∇u_h‖²_E)^(1/2)``,
* ``energy``: the energy norm of ``u - Π u_h`` (``∫ κ|∇e|² + c e²`` for diffusion-reaction,
  ``∫ ε(e) : C ε(e)`` for elasticity).

On triangles these are the exact errors of the P1 finite element solution. The exact gradient is
used when given; otherwise it is computed from the exact solution by fourth-order central
differences with a step of 1e-3 times the cell's diameter (accurate to about 1e-9 relative on
smooth functions, and the stencil stays inside the cell, so a corner singularity is respected).
On a composite domain the exact solution may be given per region (a mapping region ->
expression, :func:`blockmesh.vem.fields.region_field`): each cell is measured against its own
region's piece, whose smooth continuation is also what the cell's sliver past a curved interface
sees.

Examples
--------
>>> norms = ErrorNorms(l2=0.5, h1=1.0, energy=1.0, l2_exact=2.0, h1_exact=4.0, energy_exact=4.0)
>>> norms.l2_relative, norms.h1_relative
(0.25, 0.25)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from blockmesh.geometry.polygons import polygon_diameter
from blockmesh.vem.fields import Field, RegionField
from blockmesh.vem.polygons import PolygonMesh
from blockmesh.vem.projections import Projections
from blockmesh.vem.rules import cell_chunks, cell_rule, points_per_cell

__all__ = ["ErrorNorms", "error_norms"]

#: Finite-difference step of the numerical gradient, relative to the cell diameter.
GRADIENT_STEP = 1e-3

#: ``energy(x, y, e, de, region)``: the energy density of an error at the points of some cells,
#: ``region`` (C,) the cells' regions.
EnergyDensity = Callable[[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray], np.ndarray]


@dataclass(frozen=True)
class ErrorNorms:
    """Absolute errors, and the norms of the exact solution (for relative errors).

    Attributes
    ----------
    l2, h1, energy : float
        ``‖u - Π⁰u_h‖_L2``, the broken seminorm ``|u - Π∇u_h|_H1``, and the energy norm.
    l2_exact, h1_exact, energy_exact : float
        ``‖u‖_L2``, ``|u|_H1`` and the energy norm of u.
    """

    l2: float
    h1: float
    energy: float
    l2_exact: float
    h1_exact: float
    energy_exact: float

    @property
    def l2_relative(self) -> float:
        """``l2 / l2_exact`` (inf when u = 0)."""
        return _ratio(self.l2, self.l2_exact)

    @property
    def h1_relative(self) -> float:
        """``h1 / h1_exact``."""
        return _ratio(self.h1, self.h1_exact)

    @property
    def energy_relative(self) -> float:
        """``energy / energy_exact``."""
        return _ratio(self.energy, self.energy_exact)

    def as_dict(self) -> dict[str, float]:
        """Plain dictionary (JSON-ready), absolute and relative errors."""
        return {
            "l2_error": self.l2,
            "h1_error": self.h1,
            "energy_error": self.energy,
            "l2_relative": self.l2_relative,
            "h1_relative": self.h1_relative,
            "energy_relative": self.energy_relative,
        }


def _ratio(a: float, b: float) -> float:
    return a / b if b > 0 else (0.0 if a == 0 else float("inf"))


def _numerical_gradient(
    field: Field | RegionField, x: np.ndarray, y: np.ndarray, step: np.ndarray, region: np.ndarray
):
    """∂f/∂x and ∂f/∂y by fourth-order central differences, step (C, 1) per cell."""

    def f(px: np.ndarray, py: np.ndarray) -> np.ndarray:
        return field.at(px, py, region)

    def derivative(dx: np.ndarray, dy: np.ndarray) -> np.ndarray:
        return (
            -f(x + 2 * dx, y + 2 * dy)
            + 8 * f(x + dx, y + dy)
            - 8 * f(x - dx, y - dy)
            + f(x - 2 * dx, y - 2 * dy)
        ) / (12 * step)

    zero = np.zeros_like(step)
    return derivative(step, zero), derivative(zero, step)


def error_norms(
    mesh: PolygonMesh,
    projections: Sequence[Projections],
    nodal: np.ndarray,
    exact: Sequence[Field | RegionField],
    gradient: Sequence[tuple[Field | RegionField, Field | RegionField]] | None,
    energy_density: EnergyDensity,
    order: int,
) -> ErrorNorms:
    """The norms of ``u - Π u_h`` for nodal values ``nodal`` (N, c) and an exact ``u`` (c fields).

    ``energy_density(x, y, e, de)`` gives the energy density of an error with values ``e``
    (C, Q, c) and gradients ``de`` (C, Q, c, 2) at the points ``x, y`` (C, Q) of cells of the
    regions ``region`` (C,).
    """
    sums = np.zeros(6)  # l2, h1, energy of the error; then of u
    cell_region = mesh.region
    for group, proj in zip(mesh.groups, projections, strict=True):
        per_cell = points_per_cell(group.size, order)
        group_region = cell_region[group.index]
        for part in cell_chunks(group.n_cells, per_cell):
            cells = group.cells[part]
            region = group_region[part]
            x, y, w = cell_rule(mesh.points, cells, order)
            local = nodal[cells]  # (C, n, c)
            grad_uh = np.einsum("cdn,cnk->ckd", proj.gradient[part], local)  # (C, c, 2)
            dx = x - proj.centre[part, 0:1]
            dy = y - proj.centre[part, 1:2]
            uh = (
                local.mean(axis=1)[:, None, :]
                + dx[..., None] * grad_uh[:, None, :, 0]
                + dy[..., None] * grad_uh[:, None, :, 1]
            )  # Π∇u_h at the points, (C, Q, c)
            u = np.stack([field.at(x, y, region) for field in exact], axis=-1)  # (C, Q, c)
            if gradient is None:
                step = GRADIENT_STEP * polygon_diameter(mesh.points[cells])[:, None]
                du = np.stack(
                    [np.stack(_numerical_gradient(f, x, y, step, region), -1) for f in exact],
                    axis=-2,
                )
            else:
                du = np.stack(
                    [
                        np.stack([gx.at(x, y, region), gy.at(x, y, region)], axis=-1)
                        for gx, gy in gradient
                    ],
                    axis=-2,
                )  # (C, Q, c, 2)
            e = u - uh
            de = du - grad_uh[:, None, :, :]
            sums += [
                np.sum(w * np.sum(e * e, axis=-1)),
                np.sum(w * np.sum(de * de, axis=(-2, -1))),
                np.sum(w * energy_density(x, y, e, de, region)),
                np.sum(w * np.sum(u * u, axis=-1)),
                np.sum(w * np.sum(du * du, axis=(-2, -1))),
                np.sum(w * energy_density(x, y, u, du, region)),
            ]
    roots = np.sqrt(np.maximum(sums, 0.0))
    return ErrorNorms(*(float(v) for v in roots))
