"""Writing Gmsh ``.msh`` 4.1 ASCII files (the layout: :mod:`blockmesh.io.msh.format`).

Examples
--------
>>> import tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> path = write_msh(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), Path(tempfile.mkdtemp()) / "a.msh")
>>> path.read_text().splitlines()[:3]
['$MeshFormat', '4.1 0 8', '$EndMeshFormat']
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO

import numpy as np

from blockmesh._system.atomic import atomic_file
from blockmesh.io.common import encode_metadata
from blockmesh.io.names import GMSH_NAME
from blockmesh.io.polygons import POLYGONS
from blockmesh.io.split import check_split, split_cells, split_edges
from blockmesh.io.text import write_rows
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["ELEMENT_NODES", "LAYOUT", "LINE", "QUADRANGLE", "TRIANGLE", "write_msh"]

#: Gmsh element type codes used here, and their numbers of nodes.
LINE, TRIANGLE, QUADRANGLE = 1, 2, 3
ELEMENT_NODES = {LINE: 2, TRIANGLE: 3, QUADRANGLE: 4, 15: 1}
#: Version of the blockmesh layout (2: the ``pentagon`` and ``parent`` views cover every element).
LAYOUT = 2


def _bbox(xy: np.ndarray, group: np.ndarray, n_groups: int) -> np.ndarray:
    """(n_groups, 4) min x, min y, max x, max y of the rows of ``xy`` (K, j, 2) per group."""
    lo, hi = xy.min(axis=1), xy.max(axis=1)
    box = np.zeros((n_groups, 4))
    box[:, :2], box[:, 2:] = np.inf, -np.inf
    order = np.argsort(group, kind="stable")
    starts = np.searchsorted(group[order], np.arange(n_groups))
    present = np.bincount(group, minlength=n_groups) > 0
    if order.size:
        s = np.minimum(starts, order.size - 1)
        mins = np.minimum.reduceat(lo[order], s, axis=0)
        maxs = np.maximum.reduceat(hi[order], s, axis=0)
        box[present, :2], box[present, 2:] = mins[present], maxs[present]
    box[~present] = 0.0
    return box


def _entity_line(tag: int, box: np.ndarray, physical: int) -> str:
    x0, y0, x1, y1 = (repr(float(v)) for v in box)
    return f"{tag} {x0} {y0} 0 {x1} {y1} 0 1 {physical} 0\n"


def write_msh(mesh: Mesh | PolygonMesh, path: Path, *, split: str = "tri5") -> Path:
    """Write ``mesh`` to ``path`` (atomically) as Gmsh 4.1 ASCII, split by ``split``.

    O(M log M) (the surface entities are sorted); the text is formatted with whole-array
    operations (:mod:`blockmesh.io.text`). A PolygonMesh is split by ``tri5`` (the fan around
    each cell's vertex mean, as many triangles as the cell has vertices) and its cell levels go
    in the element data ``cell_level``.
    """
    check_split(split)
    sc = split_cells(mesh, split)
    # The lines: boundary edges (a group per patch), then interface edges (a group each after).
    n_patches = len(mesh.patch_names)
    sb = split_edges(
        mesh,
        split,
        np.concatenate([mesh.boundary_edges, mesh.interface_edges]),
        np.concatenate([mesh.boundary_patch, mesh.interface_patch + n_patches]),
    )
    n_curves = n_patches + len(mesh.interface_names)
    per = np.bincount(sc.parent, minlength=mesh.n_cells)  # elements of each cell
    first_of = np.concatenate([[0], np.cumsum(per)])
    etype = TRIANGLE if sc.cells.shape[1] == 3 else QUADRANGLE

    n_regions = max(len(mesh.region_names), 1)
    pair = mesh.block_id * n_regions + mesh.region
    pairs, cell_entity = np.unique(pair, return_inverse=True)
    entity_block, entity_region = np.divmod(pairs, n_regions)
    if np.unique(entity_block).size == pairs.size and entity_block.min() >= 0:
        entity_tag = entity_block + 1  # the usual case: one surface per block
    else:
        entity_tag = np.arange(1, pairs.size + 1)

    cell_order = np.argsort(cell_entity, kind="stable")
    counts = per[cell_order]
    elem_index = np.repeat(first_of[cell_order] - np.cumsum(counts) + counts, counts) + np.arange(
        int(counts.sum())
    )
    elements = sc.cells[elem_index]
    element_entity = np.repeat(cell_entity[cell_order], counts)
    line_order = np.argsort(sb.patch, kind="stable")
    lines, line_patch = sb.edges[line_order], sb.patch[line_order]
    n_lines, n_elems = lines.shape[0], elements.shape[0]

    surf_box = _bbox(sc.points[sc.cells], cell_entity[sc.parent], pairs.size)
    curve_box = _bbox(sc.points[lines], line_patch, n_curves)
    extra = {"cells": POLYGONS} if isinstance(mesh, PolygonMesh) else {}
    meta = encode_metadata(
        mesh,
        **extra,
        layout=LAYOUT,
        split=split,
        n_points=mesh.n_points,
        entity_tag=entity_tag.tolist(),
        entity_block=entity_block.tolist(),
    )

    with atomic_file(path) as tmp, open(tmp, "wb") as f:
        w = f.write
        w(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        curves = GMSH_NAME.unique((*mesh.patch_names, *mesh.interface_names))
        names = [f'1 {k + 1} "{p}"\n' for k, p in enumerate(curves)]
        names += [f'2 {k + 1} "{r}"\n' for k, r in enumerate(GMSH_NAME.unique(mesh.region_names))]
        w(f"$PhysicalNames\n{len(names)}\n{''.join(names)}$EndPhysicalNames\n".encode())
        w(f"$Entities\n0 {n_curves} {pairs.size} 0\n".encode())
        for k in range(n_curves):
            w(_entity_line(k + 1, curve_box[k], k + 1).encode())
        for k in range(pairs.size):
            w(_entity_line(int(entity_tag[k]), surf_box[k], int(entity_region[k]) + 1).encode())
        w(b"$EndEntities\n")

        n_nodes = sc.points.shape[0]
        node_tags = np.arange(1, n_nodes + 1)
        w(f"$Nodes\n1 {n_nodes} 1 {n_nodes}\n2 {int(entity_tag[0])} 0 {n_nodes}\n".encode())
        write_rows(f, [node_tags, b"\n"])
        write_rows(f, [sc.points[:, 0], b" ", sc.points[:, 1], b" 0\n"])
        w(b"$EndNodes\n")

        line_blocks = np.flatnonzero(np.bincount(line_patch, minlength=n_curves))
        n_blocks = line_blocks.size + pairs.size
        total = n_lines + n_elems
        w(f"$Elements\n{n_blocks} {total} 1 {total}\n".encode())
        _write_blocks(f, 1, lines, line_patch, np.arange(n_curves) + 1, LINE, start_tag=1)
        _write_blocks(f, 2, elements, element_entity, entity_tag, etype, start_tag=n_lines + 1)
        w(b"$EndElements\n")

        pentagon = sc.parent[elem_index]
        tags = np.arange(1, total + 1)
        none = np.full(n_lines, -1, dtype=np.int64)
        views = [("pentagon", pentagon), ("parent", mesh.parent[pentagon])]
        if isinstance(mesh, PolygonMesh):
            views.append(("cell_level", mesh.cell_level[pentagon]))
        for view, values in views:
            w(f'$ElementData\n1\n"{view}"\n1\n0\n3\n0\n1\n{total}\n'.encode())
            write_rows(f, [tags, b" ", np.concatenate([none, values]), b"\n"])
            w(b"$EndElementData\n")
        w(f"$BlockMesh\n{meta}\n$EndBlockMesh\n".encode())
    return Path(path).absolute()


def _write_blocks(
    f: BinaryIO,
    dim: int,
    conn: np.ndarray,
    group: np.ndarray,
    group_tag: np.ndarray,
    etype: int,
    *,
    start_tag: int,
) -> None:
    """Element blocks: rows of ``conn`` (sorted by ``group``), one block per non-empty group."""
    counts = np.bincount(group, minlength=group_tag.size)
    offset = 0
    for g in np.flatnonzero(counts):
        n = int(counts[g])
        rows = conn[offset : offset + n] + 1
        f.write(f"{dim} {int(group_tag[g])} {etype} {n}\n".encode())
        tags = np.arange(start_tag + offset, start_tag + offset + n)
        write_rows(f, [tags, b" ", rows, b"\n"])
        offset += n


# ---------------------------------------------------------------------------------- reading
