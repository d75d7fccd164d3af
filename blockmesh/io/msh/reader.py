"""Reading Gmsh ``.msh`` 4.1 ASCII files back into pentagon meshes (see :mod:`~.msh.format`).

The file is parsed section by section by :mod:`blockmesh.io.msh.sections` (in chunks, every
count checked); here its element blocks, physical groups and element data become the mesh's
arrays: the pentagons are rebuilt from their elements by :mod:`blockmesh.io.pentagons`, the
boundary lines grouped into patches and interfaces, the blocks and regions looked up. Anything
missing or inconsistent is an :class:`ExportError` naming the file.

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

from pathlib import Path
from typing import Any

import numpy as np

from blockmesh.errors import ExportError
from blockmesh.geometry.topology import PolygonCells, boundary_of_cells, edge_keys
from blockmesh.io.common import mesh_from_arrays
from blockmesh.io.msh.sections import MshFile, parse_msh
from blockmesh.io.pentagons import join_lines, merge_elements, merge_polygons
from blockmesh.io.polygons import is_polygon_file, polygon_mesh_from_arrays
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["read_msh"]


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
    parsed = parse_msh(path)
    if is_polygon_file(parsed.meta):
        return polygon_mesh_from_arrays(where=where, **_polygon_arrays(parsed, where))
    arrays = _mesh_arrays(parsed, where)  # the parsed file is freed before the Mesh
    del parsed
    return mesh_from_arrays(where=where, **arrays)


def _polygon_arrays(f: MshFile, where: str) -> dict[str, Any]:
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


def _mesh_arrays(f: MshFile, where: str) -> dict[str, Any]:
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


def _groups(f: MshFile, dim: int, names: Any) -> tuple[dict[int, int], list[str]]:
    """Physical tag -> index, and the names; the real names from ``$BlockMesh`` when given."""
    if isinstance(names, list) and all(isinstance(n, str) for n in names):
        return {k + 1: k for k in range(len(names))}, names
    tags = sorted({ts[0] for (d, _), ts in f.entities.items() if d == dim and ts})
    return {t: k for k, t in enumerate(tags)}, [f.names.get((dim, t), f"group_{t}") for t in tags]


def _lookup(f: MshFile, ent: np.ndarray, dim: int, table: dict[int, int], where: str) -> np.ndarray:
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
