"""XDMF 3 + HDF5 (``.xdmf`` naming a sibling ``.h5``): the fast path for big meshes (ParaView).

meshio cannot write polygons to XDMF, so the heavy data goes straight to HDF5 with h5py and the
light XML is written with :mod:`xml.etree`. The XDMF file holds one uniform grid, like the VTU:
a ``Mixed`` topology of the pentagons (``Polygon`` of 5 nodes) followed by the boundary edges
and then the interface edges of a composite domain (``Polyline`` of 2), ``Geometry XY``, the cell
attributes ``block_id``, ``region``, ``parent``, ``patch`` and, with interfaces, ``interface``
(-1 where they do not apply), the name lookups ``patch:NAME``, ``region:NAME`` and
``interface:NAME`` as grid attributes (ParaView shows them as field data: the index each name
has), and an ``Information`` element ``blockmesh`` with the JSON metadata. The ``.h5`` file holds

===================== ============== =========================================================
``/mesh/points``      (N, 2) f8      node coordinates
``/mesh/topology``    (7M + 4Eb,) i8 per pentagon ``3 5 v0 .. v4``, per boundary or interface
                                     edge ``2 2 a b`` (XDMF's mixed layout)
``/mesh/block_id``    (M + Eb,) i8   cell data, -1 where it does not apply; likewise
                                     ``/mesh/region``, ``/mesh/parent``, ``/mesh/patch`` and
                                     (with interfaces) ``/mesh/interface`` (Eb counts the
                                     interface lines too)
===================== ============== =========================================================

and the root attribute ``blockmesh`` (the same JSON). A mesh with curved edges also has the group
``/curves`` with the arrays of :data:`~blockmesh.io.common.CURVE_ARRAYS` (``/curves/curve_edges``
...), which ParaView ignores and :func:`read_xdmf` reads back, so that refining the mesh read
follows its curves. The cells, in h5py:
``f["mesh/topology"][: 7 * M].reshape(M, 7)[:, 2:]``.

Files, atomically. The ``.h5`` of ``mesh.xdmf`` is ``mesh.<8 hex digits>.h5``, a new name at
every write; it is renamed in first and the ``.xdmf`` last, so a reader sees the old pair or the
new one, never a mix; the ``.h5`` of the previous write is then removed
(:func:`blockmesh._system.atomic.atomic_with_data`). Both files carry the same write id, and
:func:`read_xdmf` refuses a pair whose ids differ.

ParaView. Open the ``.xdmf`` with a path that names its folder (``./mesh.xdmf``, or any path
from File > Open): ParaView's XDMF 3 reader mislocates the ``.h5`` of a bare relative file name
(``OpenDataFile("mesh.xdmf")`` aborts).

meshio cannot read this file (nor any XDMF of polygons: its XDMF reader has no polygon cells);
read it with :func:`blockmesh.read`, or write a ``.vtu`` for meshio.

Compression: ``"none"`` (default, fastest) or ``"zlib"`` (HDF5 gzip level 4, chunked datasets).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> path = write_xdmf(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.xdmf")
>>> [p.suffix for p in sorted(path.parent.iterdir())]
['.h5', '.xdmf']
>>> back = read_xdmf(path)
>>> bool(np.array_equal(back.points, mesh.points)), back.n_cells
(True, 36)
"""

from __future__ import annotations

from blockmesh.io.common import Format
from blockmesh.io.xdmf.reader import read_xdmf
from blockmesh.io.xdmf.writer import write_xdmf

__all__ = ["FORMAT", "read_xdmf", "write_xdmf"]


FORMAT = Format.of(
    write_xdmf,
    read_xdmf,
    "XDMF 3 + HDF5 pair (ParaView), polygons written directly with h5py: fastest",
    extensions=(".xdmf", ".xmf"),
    compressions=("none", "zlib"),
)
