"""Measures and integrals over the true curved cells of a mesh (``exact_geometry=True``).

A cell with curved edges is split from a centre ``c`` into straight triangles (its straight edges)
and curved sectors (its curved edges). A sector is the image of the unit square under the paper's
map with the curve in place of the straight edge (``docs/mathematics.md`` §6),

    x(r, s) = (1 - r) c + r γ(s),   dx dy = r det(γ(s) - c, γ'(s)) dr ds,

so the rule in ``r`` is the paper's and the rule in ``s`` runs along the curve. The determinant is
signed: the sectors then add up to the cell by Green's theorem whatever the centre, even where a
concave curve hides part of the cell from it. Areas have closed forms: the straight cell's area
plus, for every curved edge, the signed area between the curve and its chord
(:meth:`blockmesh.curves.Curve.segment_area`).

Examples
--------
>>> import math
>>> import blockmesh
>>> from blockmesh.curves import Arc
>>> corners = [(1, 0), (math.cos(1.2), math.sin(1.2)), (0, 0.4), (0, 0), (0.5, -0.1)]
>>> d = blockmesh.Domain.from_blocks(corners, [(0, 1, 2, 3, 4)], edges={(0, 1): Arc(center=(0, 0))})
>>> mesh = d.block_mesh()
>>> bool(cell_areas(mesh).sum() > mesh.area)
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .curved_refinement import curved_slots
from .curves import CurvedEdges

if TYPE_CHECKING:
    from .mesh import Mesh

__all__ = ["area_corrections", "cell_areas"]


def area_corrections(cells: np.ndarray, n_points: int, curves: CurvedEdges | None) -> np.ndarray:
    """For every cell, the signed area between its curved edges and their chords, shape (M,).

    Positive where a curve bulges out of its cell. Cells without curved edges get 0.
    """
    cells = np.asarray(cells, dtype=np.int64)
    out = np.zeros(cells.shape[0])
    if curves is None or len(curves) == 0:
        return out
    row, forward = curved_slots(cells, n_points, curves)
    cell, _ = np.nonzero(row >= 0)
    rows, ahead = row[row >= 0], forward[row >= 0]
    first = np.where(ahead, curves.start[rows], curves.stop[rows])
    last = np.where(ahead, curves.stop[rows], curves.start[rows])
    for k, curve in enumerate(curves.curves):
        mine = curves.curve[rows] == k
        if np.any(mine):
            np.add.at(out, cell[mine], curve.segment_area(first[mine], last[mine]))
    return out


def cell_areas(mesh: Mesh) -> np.ndarray:
    """Area of every cell bounded by its curved edges (the straight area where it has none)."""
    return mesh.cell_areas() + area_corrections(mesh.cells, mesh.n_points, mesh.curves)
