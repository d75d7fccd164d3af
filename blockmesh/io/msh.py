"""Gmsh ``.msh`` 4.1 (ASCII), with every pentagon split into triangles or quadrilaterals.

The format has no pentagons, so a ``split`` is required (see :mod:`blockmesh.io.split`):
``tri5``, ``tri3`` or ``quad5``. The file is written directly (no meshio), in these sections:

``$PhysicalNames``
    one physical group per patch (dimension 1, tag = patch index + 1) and per region
    (dimension 2, tag = region index + 1), named after them.
``$Entities``
    one curve per patch (tag = patch index + 1) and one surface per (block, region) pair of the
    cells (tag = block id + 1 whenever each block lies in one region, as blocks do), each carrying
    its physical group.
``$Nodes``, ``$Elements``
    the mesh's nodes (tags 1..N) then the split's new ones; the boundary lines (halved for
    ``quad5``, so the line mesh conforms), then the split elements, block by block.
``$ElementData`` ``"parent"``
    for every triangle/quadrilateral, the 0-based index of the pentagon it comes from. Gmsh
    loads it as a post-processing view named "parent".
``$BlockMesh``
    a JSON line (names, level, mesh name, split, the number of the mesh's own nodes and the block
    id of each surface entity). Gmsh ignores sections it does not know.

:func:`read_msh` rebuilds the pentagons: the elements of each parent are merged (the outline of
their union, counter-clockwise, from the first node of the parent's first element, which is the
pentagon's corner 0 in the files written here); nodes that are not pentagon corners (midpoints,
centres) are dropped, and boundary lines are joined back across them.

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
>>> bool(np.array_equal(back.cells, mesh.cells)), bool(np.array_equal(back.points, mesh.points))
(True, True)
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path
from typing import BinaryIO

import numpy as np

from ..atomic import atomic_file
from ..errors import ExportError
from ..mesh import Mesh
from ..topology import edge_keys
from ._ascii import write_rows
from ._common import Format, decode_metadata, encode_metadata, mesh_from_arrays
from .split import check_split, split_boundary, split_cells

__all__ = ["FORMAT", "read_msh", "write_msh"]

_LINE, _TRI, _QUAD, _POINT = 1, 2, 3, 15
_NODES_PER_TYPE = {_LINE: 2, _TRI: 3, _QUAD: 4, _POINT: 1}


def _check_name(name: str, what: str) -> str:
    if '"' in name or "\n" in name:
        raise ExportError(
            f"the {what} name {name!r} holds a double quote or a newline, which Gmsh physical "
            "names cannot; rename it"
        )
    return name


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


def write_msh(mesh: Mesh, path: Path, *, split: str) -> Path:
    """Write ``mesh`` to ``path`` (atomically) as Gmsh 4.1 ASCII, split by ``split``.

    O(M log M) (the surface entities are sorted); the text is formatted with whole-array
    operations (:mod:`blockmesh.io._ascii`).
    """
    check_split(split)
    for p in mesh.patch_names:
        _check_name(p, "patch")
    for r in mesh.region_names:
        _check_name(r, "region")
    sc = split_cells(mesh, split)
    sb = split_boundary(mesh, split)
    per_cell = sc.cells.shape[0] // max(mesh.n_cells, 1)
    etype = _TRI if sc.cells.shape[1] == 3 else _QUAD

    n_regions = max(len(mesh.region_names), 1)
    pair = mesh.block_id * n_regions + mesh.region
    pairs, cell_entity = np.unique(pair, return_inverse=True)
    entity_block, entity_region = np.divmod(pairs, n_regions)
    if np.unique(entity_block).size == pairs.size and entity_block.min() >= 0:
        entity_tag = entity_block + 1  # the usual case: one surface per block
    else:
        entity_tag = np.arange(1, pairs.size + 1)
    n_patches = len(mesh.patch_names)

    cell_order = np.argsort(cell_entity, kind="stable")
    elem_index = (cell_order[:, None] * per_cell + np.arange(per_cell)).ravel()
    elements = sc.cells[elem_index]
    element_entity = np.repeat(cell_entity[cell_order], per_cell)
    line_order = np.argsort(sb.patch, kind="stable")
    lines, line_patch = sb.edges[line_order], sb.patch[line_order]
    n_lines, n_elems = lines.shape[0], elements.shape[0]

    surf_box = _bbox(sc.points[mesh.cells], cell_entity, pairs.size)
    curve_box = _bbox(sc.points[lines], line_patch, n_patches)
    meta = json.loads(encode_metadata(mesh))
    meta.update(
        split=split,
        n_points=mesh.n_points,
        entity_tag=entity_tag.tolist(),
        entity_block=entity_block.tolist(),
    )

    with atomic_file(path) as tmp, open(tmp, "wb") as f:
        w = f.write
        w(b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
        names = [f'1 {k + 1} "{p}"\n' for k, p in enumerate(mesh.patch_names)]
        names += [f'2 {k + 1} "{r}"\n' for k, r in enumerate(mesh.region_names)]
        w(f"$PhysicalNames\n{len(names)}\n{''.join(names)}$EndPhysicalNames\n".encode())
        w(f"$Entities\n0 {n_patches} {pairs.size} 0\n".encode())
        for k in range(n_patches):
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

        line_blocks = np.flatnonzero(np.bincount(line_patch, minlength=n_patches))
        n_blocks = line_blocks.size + pairs.size
        total = n_lines + n_elems
        w(f"$Elements\n{n_blocks} {total} 1 {total}\n".encode())
        _write_blocks(f, 1, lines, line_patch, np.arange(n_patches) + 1, _LINE, start_tag=1)
        _write_blocks(f, 2, elements, element_entity, entity_tag, etype, start_tag=n_lines + 1)
        w(b"$EndElements\n")

        parent = sc.parent[elem_index]
        w(f'$ElementData\n1\n"parent"\n1\n0\n3\n0\n1\n{n_elems}\n'.encode())
        write_rows(f, [np.arange(n_lines + 1, total + 1), b" ", parent, b"\n"])
        w(b"$EndElementData\n")
        w(f"$BlockMesh\n{json.dumps(meta, ensure_ascii=False)}\n$EndBlockMesh\n".encode())
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
def _sections(data: bytes, where: str) -> dict[str, list[bytes]]:
    """Body of every ``$Name ... $EndName`` section, by name (in file order)."""
    out: dict[str, list[bytes]] = {}
    pos = 0
    while True:
        start = data.find(b"$", pos)
        if start < 0:
            return out
        eol = data.find(b"\n", start)
        name = data[start + 1 : eol if eol >= 0 else len(data)].strip().decode("ascii", "replace")
        end_tag = f"$End{name}".encode()
        end = data.find(end_tag, eol)
        if eol < 0 or end < 0:
            raise ExportError(f"{where}: section ${name} has no {end_tag.decode()}")
        out.setdefault(name, []).append(data[eol + 1 : end])
        pos = end + len(end_tag)


def _numbers(body: bytes, dtype: type, where: str) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return np.fromstring(body, dtype=dtype, sep=" ")
        except (DeprecationWarning, ValueError) as exc:
            raise ExportError(f"{where}: malformed numbers in the file ({exc})") from None


def _entities(body: bytes) -> dict[tuple[int, int], list[int]]:
    """(dim, tag) -> physical tags, from an ASCII ``$Entities`` body."""
    lines = body.decode().split("\n")
    counts = [int(c) for c in lines[0].split()]
    out: dict[tuple[int, int], list[int]] = {}
    row = 1
    for dim, count in enumerate(counts):
        for _ in range(count):
            vals = lines[row].split()
            row += 1
            at = 4 if dim == 0 else 7
            n_phys = int(vals[at])
            out[(dim, int(vals[0]))] = [int(v) for v in vals[at + 1 : at + 1 + n_phys]]
    return out


def _numbers_any(body: bytes, where: str) -> np.ndarray:
    """Integers when the text holds only integers (exact and fast), else floats."""
    try:
        return _numbers(body, np.int64, where)
    except ExportError:
        return _numbers(body, np.float64, where)


def _read_nodes(body: bytes, where: str) -> tuple[np.ndarray, np.ndarray]:
    """Node tags and (n, 3) coordinates; tags and coordinates are parsed apart (ints are fast)."""
    newline = np.flatnonzero(np.frombuffer(body, dtype=np.uint8) == 10)
    line = 0

    def take(k: int) -> bytes:  # the next k lines
        nonlocal line
        start = newline[line - 1] + 1 if line else 0
        line += k
        return body[start : newline[line - 1] + 1] if k else b""

    n_blocks = int(take(1).split()[0])
    tags, coords = [], []
    for _ in range(n_blocks):
        _dim, _tag, parametric, n = (int(v) for v in take(1).split())
        if parametric:
            raise ExportError(f"{where}: parametric nodes are not supported; save without them")
        tags.append(_numbers(take(n), np.int64, where))
        coords.append(_numbers(take(n), np.float64, where).reshape(n, 3))
    return np.concatenate(tags), np.concatenate(coords)


def _read_elements(body: bytes, where: str) -> list[tuple[int, int, int, np.ndarray]]:
    """(dim, entity tag, type, rows (n, 1 + nodes)) per element block."""
    vals = _numbers(body, np.int64, where)
    pos, blocks = 4, []
    for _ in range(int(vals[0])):
        dim, tag, etype, n = (int(v) for v in vals[pos : pos + 4])
        pos += 4
        if etype not in _NODES_PER_TYPE:
            raise ExportError(
                f"{where}: element type {etype} is not supported (only lines, triangles and "
                "quadrangles of first order)"
            )
        width = 1 + _NODES_PER_TYPE[etype]
        blocks.append((dim, tag, etype, vals[pos : pos + n * width].reshape(n, width)))
        pos += n * width
    return blocks


def _element_data(
    views: list[bytes], name: str, where: str
) -> tuple[np.ndarray, np.ndarray] | None:
    """Element tags and values of the ``$ElementData`` view called ``name``, if any."""
    for body in views:
        lines = body.split(b"\n", 64)
        n_str = int(lines[0])
        strings = [s.strip().strip(b'"').decode() for s in lines[1 : 1 + n_str]]
        if not strings or strings[0] != name:
            continue
        row = 1 + n_str
        n_real = int(lines[row])
        row += 1 + n_real
        n_int = int(lines[row])
        ints = [int(v) for v in lines[row + 1 : row + 1 + n_int]]
        n_comp = ints[1] if n_int > 1 else 1
        rest = b"\n".join(lines[row + 1 + n_int :])
        vals = _numbers_any(rest, where).reshape(-1, 1 + n_comp)
        return vals[:, 0].astype(np.int64), vals[:, 1]
    return None


def _outlines(
    edges: np.ndarray, owner: np.ndarray, start: np.ndarray, n_nodes: int, where: str
) -> np.ndarray:
    """For each owner 0..P-1, its outline from ``start[p]``: (P, L) node ids, -1 padded.

    ``edges`` (E, 2) are the directed edges of CCW elements, ``owner`` their parent; edges met
    in both directions within a parent are interior and dropped. O(E log E).
    """
    key = edge_keys(edges[:, 0], edges[:, 1], n_nodes)
    order = np.argsort(key)  # an edge is in at most two elements: equal keys are neighbours
    k_sorted, o_sorted = key[order], owner[order]
    same = (k_sorted[1:] == k_sorted[:-1]) & (o_sorted[1:] == o_sorted[:-1])
    twin = np.zeros(order.size, dtype=bool)
    twin[order[1:][same]] = True
    twin[order[:-1][same]] = True
    out_edges, out_owner = edges[~twin], owner[~twin]
    n_parents = start.size
    length = np.bincount(out_owner, minlength=n_parents)
    src_key = out_owner * n_nodes + out_edges[:, 0]
    by_src = np.argsort(src_key)
    src_sorted = src_key[by_src]
    if np.any(src_sorted[1:] == src_sorted[:-1]):
        raise ExportError(f"{where}: the elements of some parent do not form one simple polygon")
    longest = int(length.max(initial=0))
    ring = np.full((n_parents, longest), -1, dtype=np.int64)
    current = start.copy()
    parents = np.arange(n_parents)
    for step in range(longest):
        active = step < length
        ring[active, step] = current[active]
        look = parents[active] * n_nodes + current[active]
        pos = np.minimum(np.searchsorted(src_sorted, look), max(src_sorted.size - 1, 0))
        if src_sorted.size == 0 or np.any(src_sorted[pos] != look):
            raise ExportError(f"{where}: the elements of some parent do not form a closed outline")
        current[active] = out_edges[by_src[pos], 1]
    if np.any(current != start):
        raise ExportError(f"{where}: the elements of some parent do not form one closed outline")
    return ring


def _corners(ring: np.ndarray, points: np.ndarray, is_node: np.ndarray | None) -> np.ndarray:
    """Keep the pentagon corners of each outline: mesh nodes (when known) or turning vertices."""
    valid = ring >= 0
    if is_node is not None:
        keep = valid & is_node[np.where(valid, ring, 0)]
    else:
        xy = points[np.where(valid, ring, 0)]
        length = valid.sum(axis=1)
        idx = np.arange(ring.shape[1])
        prev = (idx - 1) % np.maximum(length, 1)[:, None]
        nxt = (idx + 1) % np.maximum(length, 1)[:, None]
        rows = np.arange(ring.shape[0])[:, None]
        a, b = xy - xy[rows, prev], xy[rows, nxt] - xy
        cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
        scale = np.hypot(*np.moveaxis(a, -1, 0)) * np.hypot(*np.moveaxis(b, -1, 0))
        keep = valid & (np.abs(cross) > 1e-9 * scale)
    counts = keep.sum(axis=1)
    if np.any(counts != 5):
        bad = int(np.flatnonzero(counts != 5)[0])
        raise ExportError(
            f"the elements of parent {bad} merge into a polygon of {counts[bad]} corners, "
            "not a pentagon"
        )
    return ring[keep].reshape(-1, 5)


def _join_lines(
    lines: np.ndarray, is_corner: np.ndarray, where: str
) -> tuple[np.ndarray, np.ndarray]:
    """Boundary lines joined across nodes that are not corners (quad5's midpoints).

    Also the index of the first line of each joined one.
    """
    if lines.size == 0 or np.all(is_corner[lines]):
        return lines, np.arange(lines.shape[0])
    first = np.flatnonzero(is_corner[lines[:, 0]])
    starts = lines[first]
    inner = lines[~is_corner[lines[:, 0]]]
    order = np.argsort(inner[:, 0])
    src = inner[order, 0]
    end = starts[:, 1].copy()
    for _ in range(inner.shape[0] + 1):
        todo = ~is_corner[end]
        if not todo.any():
            return np.stack([starts[:, 0], end], axis=1), first
        pos = np.minimum(np.searchsorted(src, end[todo]), src.size - 1)
        if np.any(src[pos] != end[todo]):
            raise ExportError(f"{where}: a boundary line ends at a node that no line continues")
        end[todo] = inner[order[pos], 1]
    raise ExportError(f"{where}: boundary lines form a loop without pentagon corners")


def read_msh(path: Path) -> Mesh:
    """Read a Gmsh 4.1 ASCII file written by :func:`write_msh` back into a pentagon mesh.

    Needs the ``"parent"`` element data; other files holding it (e.g. re-saved by Gmsh as ASCII
    4.1) are read too. O(K log K) in the number of elements.
    """
    path = Path(path)
    where = str(path)
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise ExportError(f"cannot read {where}: {exc}") from None
    sec = _sections(data, where)
    fmt = (sec.get("MeshFormat") or [b""])[0].split()
    if len(fmt) < 2 or not fmt[0].startswith(b"4"):
        raise ExportError(f"{where} is not a Gmsh 4.x .msh file (saved as MSH 4.1 ASCII?)")
    if fmt[1] != b"0":
        raise ExportError(f"{where} is a binary .msh; blockmesh reads ASCII 4.1 (save it as ASCII)")
    meta = decode_metadata(sec["BlockMesh"][0].strip() if "BlockMesh" in sec else None, where)
    phys_names: dict[tuple[int, int], str] = {}
    for body in sec.get("PhysicalNames", []):
        for line in body.decode().strip().split("\n")[1:]:
            dim, tag, name = line.split(maxsplit=2)
            phys_names[(int(dim), int(tag))] = name.strip().strip('"')
    entities = _entities(sec["Entities"][0]) if "Entities" in sec else {}
    if "Nodes" not in sec or "Elements" not in sec:
        raise ExportError(f"{where} has no $Nodes or no $Elements section")
    node_tags, coords = _read_nodes(sec["Nodes"][0], where)
    index_of = np.full(int(node_tags.max(initial=0)) + 1, -1, dtype=np.int64)
    index_of[node_tags] = np.arange(node_tags.size)
    blocks = _read_elements(sec["Elements"][0], where)
    parent_data = _element_data(sec.get("ElementData", []), "parent", where)
    if parent_data is None:
        raise ExportError(
            f'{where} has no "parent" element data, so its elements cannot be merged back into '
            "pentagons; blockmesh reads the .msh files it writes "
            "(blockmesh.io.write(..., split=...))"
        )

    # surface elements: directed edges with their parent; first node, tag and entity of each
    edges, owner, e_tag, e_parent, e_first, e_entity = [], [], [], [], [], []
    line_rows, line_entity = [], []
    ptags, pvals = parent_data
    psort = np.argsort(ptags)
    ptags, pvals = ptags[psort], pvals[psort].astype(np.int64)
    for dim, tag, _etype, rows in blocks:
        if rows.size and (rows[:, 1:].max() >= index_of.size or np.any(index_of[rows[:, 1:]] < 0)):
            raise ExportError(f"{where}: some elements use node tags that are not in $Nodes")
        conn = index_of[rows[:, 1:]]
        if dim == 1:
            line_rows.append(conn)
            line_entity.append(np.full(conn.shape[0], tag))
        elif dim == 2:
            pos = np.minimum(np.searchsorted(ptags, rows[:, 0]), max(ptags.size - 1, 0))
            if ptags.size == 0 or np.any(ptags[pos] != rows[:, 0]):
                raise ExportError(f'{where}: some surface elements have no "parent" value')
            par = pvals[pos]
            edges.append(np.stack([conn, np.roll(conn, -1, axis=1)], axis=2).reshape(-1, 2))
            owner.append(np.repeat(par, conn.shape[1]))
            e_tag.append(rows[:, 0])
            e_parent.append(par)
            e_first.append(conn[:, 0])
            e_entity.append(np.full(conn.shape[0], tag))
    if not edges:
        raise ExportError(f"{where} has no surface elements")
    parent_ids, elem_p = np.unique(np.concatenate(e_parent), return_inverse=True)
    owner_all = np.searchsorted(parent_ids, np.concatenate(owner))
    order = np.lexsort((np.concatenate(e_tag), elem_p))
    head = order[np.r_[True, elem_p[order][1:] != elem_p[order][:-1]]]
    start = np.concatenate(e_first)[head]
    entity_of_parent = np.concatenate(e_entity)[head]

    n_nodes = node_tags.size
    ring = _outlines(np.concatenate(edges), owner_all, start, n_nodes, where)
    n_points = meta.get("n_points")
    is_node = None
    if isinstance(n_points, int) and 0 < n_points <= n_nodes:
        is_node = np.zeros(n_nodes, dtype=bool)
        is_node[:n_points] = True
    cells = _corners(ring, coords, is_node)

    used = np.zeros(n_nodes, dtype=bool)
    used[cells] = True
    lines = np.concatenate(line_rows) if line_rows else np.empty((0, 2), np.int64)
    lent = np.concatenate(line_entity) if line_entity else np.empty(0, np.int64)
    lines, first_line = _join_lines(lines, used, where)
    lent = lent[first_line]
    new_id = np.cumsum(used) - 1
    points = coords[used]
    cells, lines = new_id[cells], new_id[lines]

    # regions and blocks from the surface entities, patches from the curve entities
    def groups(dim: int) -> tuple[dict[int, int], list[str]]:
        tags = sorted({t for (d, _), ts in entities.items() if d == dim for t in ts[:1]})
        return {t: k for k, t in enumerate(tags)}, [
            phys_names.get((dim, t), f"group_{t}") for t in tags
        ]

    region_of_tag, region_names = groups(2)
    patch_of_tag, patch_names = groups(1)
    if "region_names" in meta:
        region_names = meta["region_names"]
        region_of_tag = {k + 1: k for k in range(len(region_names))}
    if "patch_names" in meta:
        patch_names = meta["patch_names"]
        patch_of_tag = {k + 1: k for k in range(len(patch_names))}

    def lookup(ent: np.ndarray, dim: int, table: dict[int, int]) -> np.ndarray:
        """Per entity tag in ``ent``, the index its physical group maps to (vectorised)."""
        tags, inverse = np.unique(ent, return_inverse=True)
        values = []
        for t in tags.tolist():  # one per entity, not per element
            phys = (entities.get((dim, t)) or [None])[0]
            if phys not in table:
                raise ExportError(f"{where}: entity {dim}:{t} belongs to no physical group")
            values.append(table[phys])
        return np.array(values, dtype=np.int64)[inverse] if ent.size else ent.astype(np.int64)

    region = lookup(entity_of_parent, 2, region_of_tag)
    patch = lookup(lent, 1, patch_of_tag)
    if "entity_tag" in meta and "entity_block" in meta:
        known = np.asarray(meta["entity_tag"], dtype=np.int64)
        blocks_of = np.asarray(meta["entity_block"], dtype=np.int64)
        by_tag = np.argsort(known)
        pos = np.minimum(np.searchsorted(known[by_tag], entity_of_parent), known.size - 1)
        if known.size == 0 or np.any(known[by_tag][pos] != entity_of_parent):
            raise ExportError(f"{where}: a surface entity is missing from the $BlockMesh data")
        block_id = blocks_of[by_tag][pos]
    else:
        block_id = entity_of_parent - 1
    return mesh_from_arrays(
        points,
        cells,
        where=where,
        block_id=block_id,
        region=region,
        region_names=region_names,
        boundary_edges=lines,
        boundary_patch=patch,
        patch_names=patch_names,
        level=meta.get("level", 0),
        name=meta.get("name", ""),
    )


FORMAT = Format(
    name="msh",
    description="Gmsh 4.1 ASCII; pentagons split (--split tri5|tri3|quad5), parent ids kept",
    extensions=(".msh",),
    writer=write_msh,
    reader=read_msh,
    needs_split=True,
)
