"""Reading Gmsh ``.msh`` 4.1 ASCII files back into pentagon meshes (see :mod:`~.msh.format`).

The file is parsed section by section in chunks (:class:`blockmesh.io.text.TextReader`), never
held whole; the pentagons are rebuilt from their elements by :mod:`blockmesh.io.pentagons`.
Every count a header announces is checked against what is left of the file before it is looped
over or allocated, and every malformed header, tag or value is an :class:`ExportError` naming
the line (see :mod:`blockmesh._system.bounded`).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.io.msh.writer import write_msh
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> path = pathlib.Path(tempfile.mkdtemp()) / "a.msh"
>>> _ = write_msh(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), path)
>>> read_msh(path).cells.tolist()
[[0, 1, 2, 3, 4]]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError
from blockmesh.geometry.topology import PolygonCells, boundary_of_cells, edge_keys
from blockmesh.io.common import decode_metadata, mesh_from_arrays
from blockmesh.io.msh.writer import ELEMENT_NODES
from blockmesh.io.pentagons import join_lines, merge_elements, merge_polygons
from blockmesh.io.polygons import is_polygon_file, polygon_mesh_from_arrays
from blockmesh.io.text import TextReader
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["read_msh"]

_INT32 = np.iinfo(np.int32).max


@dataclass
class _Elements:
    """The element blocks of one dimension: tags, node tags, and each block's entity."""

    tags: list[np.ndarray] = field(default_factory=list)
    nodes: list[np.ndarray] = field(default_factory=list)
    runs: list[tuple[int, int]] = field(default_factory=list)  # (entity tag, elements)

    def join(self) -> None:
        """Each list made one array (after the section: the blocks are freed as joined)."""
        for name in ("tags", "nodes"):
            parts = getattr(self, name)
            if len(parts) > 1:
                setattr(self, name, [np.concatenate(parts)])
                parts.clear()

    def joined(self, width: int) -> tuple[np.ndarray, np.ndarray]:
        """Element tags (K,) and node tags (K, width)."""
        if not self.nodes:
            return np.empty(0, np.int64), np.empty((0, width), np.int64)
        self.join()
        return self.tags[0], self.nodes[0]

    def entity(self, index: np.ndarray) -> np.ndarray:
        """The entity tag of the elements ``index`` (positions in :meth:`joined`'s order)."""
        if not self.runs:
            return np.empty(0, np.int64)
        tags = np.array([t for t, _ in self.runs], dtype=np.int64)
        ends = np.cumsum([n for _, n in self.runs])
        return tags[np.searchsorted(ends, index, side="right")]


@dataclass
class _File:
    """What the sections of a .msh file hold, as parsed."""

    meta: dict[str, Any] = field(default_factory=dict)
    names: dict[tuple[int, int], str] = field(default_factory=dict)
    entities: dict[tuple[int, int], list[int]] = field(default_factory=dict)
    # node tags -> node indices (the tags themselves are not kept)
    to_index: Callable[[np.ndarray, str, str], np.ndarray] | None = None
    coords: np.ndarray | None = None
    lines: _Elements = field(default_factory=_Elements)
    surface: _Elements = field(default_factory=_Elements)
    # name -> (element tags, values); tags None: the values are the surface elements' own, in order
    views: dict[str, tuple[np.ndarray | None, np.ndarray]] = field(default_factory=dict)
    # the pentagon view is elements ``per * p .. per * p + per - 1`` for pentagon ``p`` (0: not)
    per: int = 0
    # the parent view holds one value per group of ``parent_per`` elements (0: one per element)
    parent_per: int = 0


def _ints(text: bytes, r: TextReader, what: str, count: int = 1) -> list[int]:
    """The whole numbers of a header line (at least ``count`` of them)."""
    try:
        values = [int(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) < count:
        raise ExportError(f"{r.where}, line {r.line_number}: malformed {what} {text[:80]!r}")
    if any(abs(v) >= 2**62 for v in values):  # no tag or count is that large; int64 holds it
        raise ExportError(
            f"{r.where}, line {r.line_number}: {what} {text[:80]!r} holds a number beyond any "
            "tag or count"
        )
    return values


def _entities(body: list[bytes], r: TextReader, first: int) -> dict[tuple[int, int], list[int]]:
    """(dim, tag) -> physical tags, from the lines of an ASCII ``$Entities`` section.

    ``first`` is the line number of the section's first line (for errors).
    """
    try:
        counts = [int(v) for v in body[0].split()] if body else []
    except ValueError:
        counts = []
    if body and len(counts) != 4:
        raise ExportError(f"{r.where}, line {first}: malformed $Entities header {body[0]!r}")
    out: dict[tuple[int, int], list[int]] = {}
    row = 1
    try:
        for dim, count in enumerate(counts):
            for _ in range(count):
                vals = body[row].split()
                row += 1
                at = 4 if dim == 0 else 7
                n_phys = int(vals[at])
                out[(dim, int(vals[0]))] = [int(v) for v in vals[at + 1 : at + 1 + n_phys]]
    except (IndexError, ValueError):
        raise ExportError(f"{r.where}, line {first + row - 1}: malformed entity") from None
    return out


def _nodes(r: TextReader, f: _File) -> None:
    blocks, total, _, max_tag = _ints(r.line(), r, "$Nodes header", 4)[:4]
    r.check_count(blocks, "node blocks", 8)
    r.check_count(total, "nodes", 6)
    tags, coords = [], []
    for _ in range(blocks):
        _dim, _tag, parametric, n = _ints(r.line(), r, "node block header", 4)[:4]
        if parametric:
            raise ExportError(f"{r.where}: parametric nodes are not supported; save without them")
        tags.append(r.table(n, 1, np.int64, np.int32 if max_tag <= _INT32 else np.int64).ravel())
        coords.append(r.table(n, 3, np.float64, keep=2))
    node_tags = np.concatenate(tags) if len(tags) > 1 else tags[0] if tags else np.empty(0, int)
    del tags
    f.coords = (  # one block (as blockmesh writes): no copy
        np.concatenate(coords) if len(coords) > 1 else coords[0] if coords else np.empty((0, 2))
    )
    if node_tags.size != total:
        raise ExportError(f"{r.where}: $Nodes announces {total} nodes but holds {node_tags.size}")
    f.to_index = _node_index(node_tags, r.where)


def _elements(r: TextReader, f: _File) -> None:
    blocks, _, _, max_tag = _ints(r.line(), r, "$Elements header", 4)[:4]
    r.check_count(blocks, "element blocks", 8)
    small = (
        np.int32
        if max_tag <= _INT32 and f.coords is not None and f.coords.shape[0] <= _INT32
        else np.int64
    )
    for _ in range(blocks):
        dim, tag, etype, n = _ints(r.line(), r, "element block header", 4)[:4]
        if etype not in ELEMENT_NODES:
            raise ExportError(
                f"{r.where}, line {r.line_number}: element type {etype} is not supported (only "
                "points, lines, triangles and quadrangles of first order)"
            )
        group = {1: f.lines, 2: f.surface}.get(dim)
        if group is None:
            r.skip(n)
            continue
        tags, rows = r.tagged_table(n, 1 + ELEMENT_NODES[etype], np.int64, small)
        if group.nodes and group.nodes[0].shape[1] != rows.shape[1]:
            raise ExportError(
                f"{r.where}: the surface mixes triangles and quadrangles; blockmesh reads the "
                ".msh files it writes (one split for the whole mesh)"
            )
        group.tags.append(tags)
        group.nodes.append(rows)
        group.runs.append((tag, n))
    f.lines.join()
    f.surface.join()


def _element_data(r: TextReader, f: _File) -> None:
    n_str = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "string tags")
    strings = [r.line().strip().strip(b'"').decode(errors="replace") for _ in range(n_str)]
    n_real = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "real tags")
    for _ in range(n_real):
        r.line()
    n_int = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "integer tags")
    ints = [_ints(r.line(), r, "$ElementData header")[0] for _ in range(n_int)]
    if n_int < 3:
        raise ExportError(f"{r.where}, line {r.line_number}: $ElementData needs 3 integer tags")
    n_comp, count = ints[1], ints[2]
    if not 1 <= n_comp <= 9 or count < 0:
        raise ExportError(
            f"{r.where}, line {r.line_number}: $ElementData of {n_comp} components for {count} "
            "elements (blockmesh reads 1 component for 0 or more elements)"
        )
    try:
        tags, rows = r.tagged_table(
            count, 1 + n_comp, np.int64, np.int32 if count <= _INT32 else np.int64
        )
    except ExportError:
        raise ExportError(
            f"{r.where}: the element data {strings[:1]} holds non-integer values; blockmesh "
            "reads the .msh files it writes"
        ) from None
    if strings and n_comp >= 1:
        values = rows[:, 0]
        if f.surface.tags:  # checked against the elements now: the view's tags are freed
            surface = f.surface.tags[0]
            skip = tags.size - surface.size
            if skip >= 0 and np.array_equal(tags[skip:], surface):
                f.views[strings[0]] = (None, _compact_view(f, strings[0], values[skip:]))
                return
        f.views[strings[0]] = (tags, values)


def _grouping(values: np.ndarray) -> int | None:
    """``per`` if ``values`` is ``0 0 .. 0 1 1 .. 1 ..`` (each id ``per`` times), else None.

    Checked a chunk at a time (no temporaries of the view's size).
    """
    k = values.size
    m = int(values[-1]) + 1 if k else 0
    if m <= 0 or k % m:
        return None
    per = k // m
    step = per << 16  # elements per chunk: temporaries of a few megabytes
    for start in range(0, k, step):
        chunk = values[start : start + step]
        if not np.array_equal(chunk, np.arange(start, start + chunk.size) // per):
            return None
    return per


def _compact_view(f: _File, name: str, values: np.ndarray) -> np.ndarray:
    """A view matched to the surface elements, kept small when its layout allows.

    The ``pentagon`` view of the files blockmesh writes numbers the elements ``per`` at a time
    (``f.per``): it is kept as a broadcast ``(M, per)`` view of ``0..M-1``, and the ``parent``
    view, then constant on each group, as one value per pentagon.
    """
    if name == "pentagon":
        per = _grouping(values)
        if per is not None:
            f.per = per
            m = values.size // per
            return np.broadcast_to(np.arange(m)[:, None], (m, per))
    elif name == "parent" and f.per and values.size % f.per == 0:
        grouped = values.reshape(-1, f.per)
        if all(np.array_equal(grouped[:, j], grouped[:, 0]) for j in range(1, f.per)):
            f.parent_per = f.per
            return np.array(grouped[:, 0])
    return values


def _parse(path: Path) -> _File:
    where = str(path)
    f = _File()
    with open_regular(path) as handle:
        r = TextReader(handle, where)
        head = r.line().strip()
        if head != b"$MeshFormat":
            raise ExportError(
                f"{where} is not a Gmsh .msh file (it does not start with $MeshFormat)"
            )
        fmt = r.line().split()
        if len(fmt) < 2 or not fmt[0].startswith(b"4"):
            raise ExportError(f"{where} is not a Gmsh 4.x .msh file (saved as MSH 4.1 ASCII?)")
        if fmt[1] != b"0":
            raise ExportError(
                f"{where} is a binary .msh; blockmesh reads ASCII 4.1 (save it as ASCII)"
            )
        r.lines_until(b"$EndMeshFormat")
        while True:
            text = r.line()
            if not text.strip():
                if r.at_end:
                    break
                continue
            section = text.strip()
            if not section.startswith(b"$"):
                raise ExportError(
                    f"{where}, line {r.line_number}: expected a $Section, got {section[:40]!r}"
                )
            end = b"$End" + section[1:]
            if section == b"$Nodes":
                _nodes(r, f)
            elif section == b"$Elements":
                _elements(r, f)
            elif section == b"$ElementData":
                _element_data(r, f)
            else:
                first = r.line_number + 1
                body = r.lines_until(end)
                if section == b"$PhysicalNames":
                    f.names = _physical_names(body, r, first)
                elif section == b"$Entities":
                    f.entities = _entities(body, r, first)
                elif section == b"$BlockMesh" and body:
                    f.meta = decode_metadata(body[0].strip(), where)
                continue
            r.lines_until(end)
    if f.coords is None or not f.surface.nodes:
        raise ExportError(f"{where} has no $Nodes or no surface elements in $Elements")
    return f


def _physical_names(body: list[bytes], r: TextReader, first: int) -> dict[tuple[int, int], str]:
    """(dim, tag) -> name, from the lines of a ``$PhysicalNames`` section."""
    names: dict[tuple[int, int], str] = {}
    for k, line in enumerate(body[1:], start=first + 1):
        parts = line.decode(errors="replace").split(maxsplit=2)
        if not parts:
            continue
        try:
            if len(parts) != 3:
                raise ValueError
            dim, tag = int(parts[0]), int(parts[1])
        except ValueError:
            raise ExportError(
                f"{r.where}, line {k}: malformed physical name {line[:80]!r} (expected "
                '"DIMENSION TAG NAME", the first two whole numbers)'
            ) from None
        names[(dim, tag)] = parts[2].strip().strip('"')
    return names


def _values_for(
    tags: np.ndarray, view: tuple[np.ndarray | None, np.ndarray], what: str, where: str
) -> np.ndarray:
    """The view's value for each element tag in ``tags``.

    O(K) when the view lists the elements in file order, as blockmesh writes it, else O(K log K).
    """
    vtags, values = view
    if vtags is None:  # already matched to the elements while parsing
        return values
    skip = vtags.size - tags.size
    if skip >= 0 and np.array_equal(vtags[skip:], tags):
        return values[skip:]
    order = np.argsort(vtags, kind="stable")
    pos = np.minimum(np.searchsorted(vtags[order], tags), max(vtags.size - 1, 0))
    if vtags.size == 0 or np.any(vtags[order][pos] != tags):
        raise ExportError(f'{where}: some elements have no "{what}" value')
    return values[order][pos]


def read_msh(path: Path) -> Mesh | PolygonMesh:
    """Read a Gmsh 4.1 ASCII file written by :func:`~blockmesh.io.msh.writer.write_msh`.

    Needs the ``"pentagon"`` element data (files of blockmesh 0.1 name it ``"parent"``); other
    files holding it (e.g. re-saved by Gmsh as ASCII 4.1) are read too. O(K) for the files
    blockmesh writes, O(K log K) otherwise (K elements).
    """
    path = Path(path)
    where = str(path)
    parsed = _parse(path)
    if is_polygon_file(parsed.meta):
        return polygon_mesh_from_arrays(where=where, **_polygon_arrays(parsed, where))
    arrays = _mesh_arrays(parsed, where)  # the parsed file is freed before the Mesh
    del parsed
    return mesh_from_arrays(where=where, **arrays)


def _polygon_arrays(f: _File, where: str) -> dict[str, Any]:
    """The arguments of :func:`polygon_mesh_from_arrays` from a parsed file of a PolygonMesh."""
    meta = f.meta
    assert f.coords is not None and f.to_index is not None
    tags, nodes = f.surface.joined(3)
    if "pentagon" not in f.views:
        raise ExportError(f'{where} has no "pentagon" element data naming each cell')
    cell = np.reshape(_values_for(tags, f.views.pop("pentagon"), "pentagon", where), -1)
    views = {
        name: np.reshape(_values_for(tags, f.views.pop(name), name, where), -1)
        for name in ("parent", "cell_level")
        if name in f.views
    }
    order = None
    if tags.size > 1 and np.any(tags[1:] <= tags[:-1]):
        order = np.argsort(tags, kind="stable")
        nodes, cell = nodes[order], cell[order]
    conn = f.to_index(nodes, "elements", where)
    n_points = meta.get("n_points")
    if not (isinstance(n_points, int) and 0 < n_points <= f.coords.shape[0]):
        raise ExportError(f"{where}: the blockmesh metadata lacks the number of mesh nodes")
    offsets, cell_nodes, first = merge_polygons(
        conn, cell, f.coords, where=where, corner_nodes=n_points
    )
    _, line_nodes = f.lines.joined(2)
    lines = f.to_index(line_nodes, "boundary lines", where)
    line_entity = f.lines.entity(np.arange(lines.shape[0]))
    region_of_tag, region_names = _groups(f, 2, meta.get("region_names"))
    patch_of_tag, patch_names = _groups(f, 1, _line_names(meta))
    element = first if order is None else order[first]
    entity_of_cell = f.surface.entity(element)
    columns: dict[str, Any] = {name: values[element] for name, values in views.items()}
    patch = _lookup(f, line_entity, 1, patch_of_tag, where)
    cells = PolygonCells(offsets, cell_nodes)
    return {
        "points": np.array(f.coords[:n_points]),
        "offsets": offsets,
        "nodes": cell_nodes,
        "block_id": _block_ids(meta, entity_of_cell, where),
        "region": _lookup(f, entity_of_cell, 2, region_of_tag, where),
        "region_names": region_names,
        **_lines_and_interfaces(lines, patch, patch_names, cells, meta),
        "level": meta.get("level", 0),
        "name": meta.get("name", ""),
        **columns,
    }


def _mesh_arrays(f: _File, where: str) -> dict[str, Any]:
    """The arguments of :func:`mesh_from_arrays` from a parsed file."""
    meta = f.meta
    assert f.coords is not None and f.to_index is not None
    tags, nodes = f.surface.joined(3)
    if "pentagon" in f.views:
        pentagon = _values_for(tags, f.views.pop("pentagon"), "pentagon", where)
        parent_view = f.views.pop("parent", None)
    elif "parent" in f.views and meta.get("layout") is None:  # blockmesh 0.1
        pentagon, parent_view = _values_for(tags, f.views.pop("parent"), "parent", where), None
    else:
        raise ExportError(
            f'{where} has no "pentagon" element data, so its elements cannot be merged back into '
            "pentagons; blockmesh reads the .msh files it writes (blockmesh.io.write(...))"
        )
    # the per-element parent, a view of the file's values (their tags are freed here)
    parent_values = None if parent_view is None else _values_for(tags, parent_view, "parent", where)
    del parent_view
    order = None
    if tags.size > 1 and np.any(tags[1:] <= tags[:-1]):  # saved by another tool: tag order
        order = np.argsort(tags, kind="stable")
        nodes, pentagon = nodes[order], np.reshape(pentagon, -1)[order]
    f.surface.tags.clear()  # the element tags are no longer needed
    del tags
    to_index = f.to_index
    conn = to_index(nodes, "elements", where)
    f.surface.nodes.clear()
    del nodes
    n_points = meta.get("n_points")
    corner_nodes = (
        n_points
        if isinstance(n_points, int)
        and not isinstance(n_points, bool)
        and 0 < n_points <= f.coords.shape[0]
        else None
    )
    split = meta.get("split")
    merged = merge_elements(
        conn,
        pentagon,
        f.coords,
        where=where,
        split=split if isinstance(split, str) else None,
        corner_nodes=corner_nodes,
    )
    del conn, pentagon
    _, line_nodes = f.lines.joined(2)
    lines, first = join_lines(
        to_index(line_nodes, "boundary lines", where), merged.is_corner, where
    )
    line_entity = f.lines.entity(first)
    if merged.point_index is None:
        points = np.array(f.coords[:corner_nodes])
    else:
        assert merged.renumber is not None
        points = f.coords[merged.point_index]
        lines = merged.renumber[lines]
    f.coords = None  # freed before the Mesh is built

    region_of_tag, region_names = _groups(f, 2, meta.get("region_names"))
    patch_of_tag, patch_names = _groups(f, 1, _line_names(meta))
    # each pentagon's first element, as a position in the file
    element = merged.first_element if order is None else order[merged.first_element]
    entity_of_cell = f.surface.entity(element)
    region = _lookup(f, entity_of_cell, 2, region_of_tag, where)
    patch = _lookup(f, line_entity, 1, patch_of_tag, where)
    block_id = _block_ids(meta, entity_of_cell, where)
    parent = None
    if parent_values is not None:
        parent = parent_values[element // f.parent_per if f.parent_per else element]
    return {
        "points": points,
        "cells": merged.cells,
        "block_id": block_id,
        "parent": parent,
        "region": region,
        "region_names": region_names,
        **_lines_and_interfaces(lines, patch, patch_names, merged.cells, meta),
        "level": meta.get("level", 0),
        "name": meta.get("name", ""),
        "dropped_curves": meta.get("curved_edges", 0),
    }


def _line_names(meta: dict[str, Any]) -> Any:
    """The names of the physical lines blockmesh wrote: the patches, then the interfaces."""
    known = meta.get("patch_names")
    inner = meta.get("interface_names")
    if isinstance(known, list) and isinstance(inner, list):
        return known + inner
    return known


def _lines_and_interfaces(
    lines: np.ndarray,
    group: np.ndarray,
    names: list[str],
    cells: np.ndarray | PolygonCells,
    meta: dict[str, Any],
) -> dict[str, Any]:
    """Boundary edges and patches, and interface edges and interfaces, from the line groups.

    The files blockmesh writes list the interfaces after the patches (``$BlockMesh`` names
    both); in other files a physical line whose edges are all inside the mesh (each shared by
    two cells) is an interface.
    """
    inner_names = meta.get("interface_names")
    if isinstance(inner_names, list) and isinstance(meta.get("patch_names"), list):
        n_patches = len(meta["patch_names"])
        inner = group >= n_patches
        return {
            "boundary_edges": lines[~inner],
            "boundary_patch": group[~inner],
            "patch_names": names[:n_patches],
            "interface_edges": lines[inner],
            "interface_patch": group[inner] - n_patches,
            "interface_names": names[n_patches:],
        }
    ids = cells.nodes if isinstance(cells, PolygonCells) else cells
    n = int(max(ids.max(initial=-1), lines.max(initial=-1))) + 1
    outer = boundary_of_cells(cells, n)
    on_boundary = np.isin(
        edge_keys(lines[:, 0], lines[:, 1], n), edge_keys(outer[:, 0], outer[:, 1], n)
    )
    groups = np.arange(len(names))
    interior = np.array(
        [bool(np.any(group == g)) and not np.any(on_boundary[group == g]) for g in groups],
        dtype=bool,
    ).reshape(-1)
    if not interior.any():
        return {"boundary_edges": lines, "boundary_patch": group, "patch_names": names}
    renumber = np.empty(len(names), dtype=np.int64)
    renumber[~interior] = np.arange(int(np.count_nonzero(~interior)))
    renumber[interior] = np.arange(int(np.count_nonzero(interior)))
    inner = interior[group]
    return {
        "boundary_edges": lines[~inner],
        "boundary_patch": renumber[group[~inner]],
        "patch_names": [name for name, i in zip(names, interior, strict=True) if not i],
        "interface_edges": lines[inner],
        "interface_patch": renumber[group[inner]],
        "interface_names": [name for name, i in zip(names, interior, strict=True) if i],
    }


def _groups(f: _File, dim: int, names: Any) -> tuple[dict[int, int], list[str]]:
    """Physical tag -> index, and the names; the real names from ``$BlockMesh`` when given."""
    if isinstance(names, list) and all(isinstance(n, str) for n in names):
        return {k + 1: k for k in range(len(names))}, names
    tags = sorted({ts[0] for (d, _), ts in f.entities.items() if d == dim and ts})
    return {t: k for k, t in enumerate(tags)}, [f.names.get((dim, t), f"group_{t}") for t in tags]


def _lookup(f: _File, ent: np.ndarray, dim: int, table: dict[int, int], where: str) -> np.ndarray:
    """Per entity tag in ``ent``, the index its physical group maps to (vectorised)."""
    tags, inverse = np.unique(ent, return_inverse=True)
    values = []
    for t in tags.tolist():  # one per entity, not per element
        groups = f.entities.get((dim, t))
        phys = groups[0] if groups else None
        if phys not in table:
            raise ExportError(f"{where}: entity {dim}:{t} belongs to no physical group")
        values.append(table[phys])
    return np.array(values, dtype=np.int64)[inverse] if ent.size else ent.astype(np.int64)


def _block_ids(meta: dict[str, Any], entity_of_cell: np.ndarray, where: str) -> np.ndarray:
    if "entity_tag" not in meta or "entity_block" not in meta:
        return entity_of_cell - 1
    known = _int_list(meta["entity_tag"], "entity_tag", where)
    blocks_of = _int_list(meta["entity_block"], "entity_block", where)
    if known.size != blocks_of.size:
        raise ExportError(
            f"{where}: the $BlockMesh data lists {known.size} entity tags but {blocks_of.size} "
            "entity blocks"
        )
    by_tag = np.argsort(known)
    pos = np.minimum(np.searchsorted(known[by_tag], entity_of_cell), max(known.size - 1, 0))
    if known.size == 0 or np.any(known[by_tag][pos] != entity_of_cell):
        raise ExportError(f"{where}: a surface entity is missing from the $BlockMesh data")
    return blocks_of[by_tag][pos]


def _int_list(value: Any, key: str, where: str) -> np.ndarray:
    """``value`` (from the ``$BlockMesh`` JSON) as int64; ExportError unless whole numbers."""
    if not isinstance(value, list) or not all(
        isinstance(v, int) and not isinstance(v, bool) and abs(v) < 2**62 for v in value
    ):
        raise ExportError(f"{where}: the $BlockMesh data {key!r} is not a list of whole numbers")
    return np.array(value, dtype=np.int64)


def _node_index(node_tags: np.ndarray, where: str) -> Callable[[np.ndarray, str, str], np.ndarray]:
    """A function mapping node tags to node indices (tag - 1 when the tags are 1..N in order).

    The tags it is given are the parsed file's own arrays: tag - 1 is computed in place (no copy
    of the elements), so they hold indices afterwards.
    """
    n = node_tags.size
    consecutive = n == 0 or (
        node_tags[0] == 1 and node_tags[-1] == n and bool(np.all(np.diff(node_tags) == 1))
    )
    index_of = None
    order = sorted_tags = None
    if not consecutive:
        low, high = int(node_tags.min()), int(node_tags.max())
        if low < 1:
            raise ExportError(f"{where}: $Nodes holds the node tag {low}; tags are 1 or more")
        if high <= 4 * n + 1024:  # dense: a table of tag -> index
            current_guard().allocate(8 * (high + 1), "the node tag table")
            index_of = np.full(high + 1, -1, dtype=np.int64)
            index_of[node_tags] = np.arange(n)
        else:  # sparse: sorted tags, looked up by bisection (no table of the largest tag)
            order = np.argsort(node_tags, kind="stable")
            sorted_tags = node_tags[order]

    def to_index(tags: np.ndarray, what: str, where: str) -> np.ndarray:
        if tags.size == 0:
            return np.empty(tags.shape, dtype=np.int64)
        low, high = int(tags.min()), int(tags.max())
        missing = ExportError(f"{where}: some {what} use node tags that are not in $Nodes")
        if sorted_tags is not None and order is not None:
            pos = np.minimum(np.searchsorted(sorted_tags, tags), n - 1)
            if np.any(sorted_tags[pos] != tags):
                raise missing
            return order[pos]
        if index_of is None:
            if low < 1 or high > n:
                raise missing
            return np.subtract(tags, 1, out=tags)
        if low < 0 or high >= index_of.size or np.any(index_of[tags] < 0):
            raise missing
        return index_of[tags]

    return to_index
