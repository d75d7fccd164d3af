"""Gmsh ``.msh`` 4.1 (ASCII), with every pentagon split into triangles or quadrilaterals.

The format has no pentagons, so they are split (see :mod:`blockmesh.io.split`): ``tri5`` (the
default), ``tri3`` or ``quad5``. The file (written by :mod:`blockmesh.io.msh.writer`, read by
:mod:`blockmesh.io.msh.reader`) has these sections:

``$PhysicalNames``
    one physical group per patch (dimension 1, tag = patch index + 1), then per interface of a
    composite domain (dimension 1, tags after the patches) and per region (dimension 2, tag =
    region index + 1), named after them (a double quote or line break, which Gmsh names cannot
    hold, becomes ``_``; the real names are in ``$BlockMesh``).
``$Entities``
    one curve per patch and per interface (tag = its physical tag) and one surface per (block,
    region) pair of the
    cells (tag = block id + 1 whenever each block lies in one region, as blocks do), each carrying
    its physical group.
``$Nodes``, ``$Elements``
    the mesh's nodes (tags 1..N) then the split's new ones; the boundary lines, then the
    interface lines (halved for ``quad5``, so the line mesh conforms), then the split elements,
    block by block.
``$ElementData`` ``"pentagon"`` and ``"parent"``
    for every element: the 0-based index of the pentagon (the mesh cell) it comes from, and that
    pentagon's parent one refinement level up (``Mesh.parent``); -1 on the boundary lines. Gmsh
    shows them as post-processing views; meshio reads them as cell data.
``$BlockMesh``
    a JSON line (names, level, mesh name, split, the number of the mesh's own nodes and the block
    id of each surface entity). Gmsh and meshio skip sections they do not know.

:func:`read_msh` rebuilds the pentagons from their elements and drops the split's extra nodes;
the mesh read back equals the one written.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_msh(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.msh", split="quad5")
>>> back = read_msh(path)
>>> bool(np.array_equal(back.cells, mesh.cells)), bool(np.array_equal(back.parent, mesh.parent))
(True, True)
"""

from __future__ import annotations

from blockmesh.io.common import Format
from blockmesh.io.msh.reader import read_msh
from blockmesh.io.msh.writer import write_msh
from blockmesh.io.split import SPLITS

__all__ = ["FORMAT", "read_msh", "write_msh"]

FORMAT = Format.of(
    write_msh,
    read_msh,
    "Gmsh 4.1 ASCII; pentagons split (split=tri5|tri3|quad5), pentagon ids kept",
    splits=tuple(SPLITS),
)
