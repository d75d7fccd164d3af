"""Reading one-layer OpenFOAM ``polyMesh`` folders back into pentagon meshes (ASCII, or gzipped).

The files are parsed by :mod:`blockmesh.io.openfoam.files` (line by line in chunks); only what
the 2-D mesh needs is read: the points, and the faces and owners of the boundary patches (the
internal faces are skipped, unless face zones name interfaces). Here the back faces become the
pentagons, the side faces the boundary edges, the cell zones the regions. Layout:
:mod:`blockmesh.io.openfoam.format`. The file readers (:func:`foam_file`, :func:`read_list`,
:func:`read_boundary`, :func:`read_faces`) are re-exported here.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.io.openfoam.writer import write_openfoam
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> case = pathlib.Path(tempfile.mkdtemp()) / "case"
>>> _ = write_openfoam(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), case)
>>> [p["name"] for p in read_boundary(case / "constant" / "polyMesh")]
['boundary', 'frontAndBack']
>>> read_openfoam(case).cells.tolist()
[[0, 1, 2, 3, 4]]
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh.errors import ExportError
from blockmesh.geometry.polygons import signed_area
from blockmesh.io.common import check_points, mesh_from_arrays
from blockmesh.io.openfoam.files import (
    FaceSizeError,
    find_polymesh,
    foam_file,
    header_counts,
    list_size,
    read_boundary,
    read_face_zones,
    read_faces,
    read_list,
    read_zones,
)
from blockmesh.mesh.mesh import Mesh

__all__ = [
    "FaceSizeError",
    "bottom_plane",
    "case_regions",
    "foam_file",
    "patch_arrays",
    "read_boundary",
    "read_faces",
    "read_list",
    "read_openfoam",
    "read_points",
    "side_edges",
    "zone_interfaces",
]

_CHUNK = 1 << 18


def read_openfoam(path: Path) -> Mesh:
    """Read a one-layer extruded polyMesh (as :func:`write_openfoam` writes) back to pentagons.

    Raises :class:`FaceSizeError` when the front and back faces are not all pentagons;
    :func:`blockmesh.io.openfoam.polygons.read_openfoam` (what :func:`blockmesh.read` uses) then
    reads the case as a PolygonMesh.

    ``path`` is the case, its ``constant`` directory or the ``polyMesh`` directory. ASCII files
    (optionally gzipped) only. O(F) in the number of faces; the internal faces are skipped.
    """
    path = Path(path).absolute()
    poly = find_polymesh(path)
    arrays = _mesh_arrays(poly)  # the parsed files are freed before the Mesh is built
    return mesh_from_arrays(where=str(poly), **arrays)


def _mesh_arrays(poly: Path) -> dict[str, Any]:
    """The arguments of :func:`mesh_from_arrays` from the files of ``poly``."""
    where = str(poly)
    patches = read_boundary(poly)
    empty = [p for p in patches if p.get("type") == "empty"]
    if not empty:
        raise ExportError(f"{where} has no patch of type empty: not a one-layer 2-D mesh")
    spans = sorted(
        (int(p["startFace"]), int(p["nFaces"]), 5 if p.get("type") == "empty" else 4, k)
        for k, p in enumerate(patches)
        if int(p["nFaces"])
    )
    first_boundary = spans[0][0] if spans else 0

    with foam_file(poly, "owner") as (r, header):
        n_faces, owner = read_list(r, 1, np.int64, skip=first_boundary)
    owner = owner.ravel()
    note = header_counts(header)
    with foam_file(poly, "neighbour") as (r, _):
        n_internal = list_size(r)
    points = read_points(poly)
    n_points = points.shape[0]
    face_zones = read_face_zones(poly, n_internal)
    ranges = [(s, n, size) for s, n, size, _ in spans]
    if face_zones is not None and n_internal:
        ranges = [(0, n_internal, 4), *ranges]
    faces = read_faces(poly, ranges)
    internal = faces.pop(0) if face_zones is not None and n_internal else None
    face_of = {k: f for (_, _, _, k), f in zip(spans, faces, strict=True)}
    found = {"nPoints": n_points, "nFaces": n_faces, "nInternalFaces": n_internal}
    wrong = {k: (note[k], v) for k, v in found.items() if k in note and note[k] != v}
    if wrong or n_internal != first_boundary:
        said = ", ".join(f"{k} {a} in owner but {b} in the files" for k, (a, b) in wrong.items())
        said = said or "the patches do not start after the internal faces"
        raise ExportError(
            f"the files of {where} do not belong together ({said}); an interrupted copy? "
            "write the mesh again"
        )
    n_cells = note.get("nCells", int(owner.max(initial=-1)) + 1)

    zmin, on_bottom = bottom_plane(points)
    fronts, cell_of = [], []
    for start, _, _, k in spans:
        if patches[k].get("type") == "empty":
            fronts.append(face_of[k])
            cell_of.append(
                owner[start - first_boundary : start - first_boundary + face_of[k].shape[0]]
            )
    for _, _, _, k in spans:  # the front and back faces are freed with ``rows``
        if patches[k].get("type") == "empty":
            del face_of[k]
    if not fronts:
        raise ExportError(f"{where}: the patch of type empty has no faces: no cells to read")
    rows = fronts[0] if len(fronts) == 1 else np.concatenate(fronts)
    cells_of = cell_of[0] if len(cell_of) == 1 else np.concatenate(cell_of)
    del fronts, cell_of, faces
    if rows.size and (rows.max() >= n_points or rows.min() < 0):
        raise ExportError(
            f"{where}: faces name points outside the {n_points} of the points file "
            f"({rows.min()}..{rows.max()})"
        )
    if cells_of.size and cells_of.min() < 0:
        raise ExportError(
            f"{where}: the owner file names the cell {cells_of.min()} (cells are 0 or more)"
        )
    bottom = np.all(on_bottom[rows], axis=1)
    rows, cells_of = rows[bottom], cells_of[bottom]
    del owner, bottom
    if (
        cells_of.size != n_cells
        or np.unique(cells_of).size != n_cells
        or (n_cells and cells_of.max() >= n_cells)
    ):
        raise ExportError(f"{where}: not every cell has exactly one face on the z = {zmin} plane")
    cells = np.empty((n_cells, 5), dtype=np.int64)
    cells[cells_of] = rows[:, ::-1]  # the back face runs clockwise seen from +z
    del rows, cells_of
    xy = points[:, :2]
    for start in range(0, n_cells, _CHUNK):
        block = cells[start : start + _CHUNK]
        flip = signed_area(xy[block]) < 0
        block[flip] = block[flip][:, ::-1]

    used = np.zeros(points.shape[0], dtype=bool)
    used[cells] = True
    kept = int(np.count_nonzero(used))
    if used[:kept].all():  # the bottom points first, as blockmesh writes them: ids unchanged
        new_id = None
        points_2d = np.array(xy[:kept])
    else:
        new_id = np.cumsum(used) - 1
        points_2d = xy[used]
        for start in range(0, n_cells, _CHUNK):  # renumbered in place, a chunk at a time
            block = cells[start : start + _CHUNK]
            block[...] = new_id[block]
    del points, xy, used
    sides = (
        (p["name"], _checked_sides(face_of.get(k), n_points, f"{where}: patch {p['name'][:60]!r}"))
        for k, p in enumerate(patches)
        if p.get("type") != "empty"
    )
    boundary = patch_arrays(sides, on_bottom, new_id, where)
    interfaces: dict[str, Any] = {}
    if face_zones is not None and internal is not None:
        interfaces = zone_interfaces(face_zones, internal, on_bottom, new_id, where)
    return {
        "points": points_2d,
        "cells": cells,
        **case_regions(poly, n_cells),
        **boundary,
        **interfaces,
    }


def _checked_sides(quads: np.ndarray | None, n_points: int, what: str) -> np.ndarray:
    """``quads`` (E, 4), or none for None; ExportError naming ``what`` for a point not in 0..N-1."""
    if quads is None:
        return np.empty((0, 4), dtype=np.int64)
    if quads.size and (quads.max() >= n_points or quads.min() < 0):
        raise ExportError(f"{what} names points outside the points file")
    return quads


def read_points(poly: Path) -> np.ndarray:
    """The points (N, 3) of ``poly``, checked (:func:`~blockmesh.io.common.check_points`)."""
    with foam_file(poly, "points") as (r, _):
        _, points = read_list(r, 3, np.float64)
    check_points(points, str(poly / "points"))  # before the planes are found from them
    return points


def bottom_plane(points: np.ndarray) -> tuple[Any, np.ndarray]:
    """The lowest z of ``points`` (N, 3) and whether each point is on it (to 1e-9 of the span)."""
    zmin = points[:, 2].min(initial=0.0)
    tol = 1e-9 * max(1.0, float(np.ptp(points[:, 2])) if points.size else 1.0)
    return zmin, np.abs(points[:, 2] - zmin) <= tol


def case_regions(poly: Path, n_cells: int) -> dict[str, Any]:
    """The regions of a mesh (from the cell zones of ``poly``) and its name (the case's)."""
    zones = read_zones(poly, n_cells)
    region, region_names = zones if zones is not None else (None, None)
    case = poly.parent.parent if poly.parent.name == "constant" else poly
    return {"region": region, "region_names": region_names, "name": case.name}


def patch_arrays(
    sides: Iterable[tuple[str, np.ndarray]],
    on_bottom: np.ndarray,
    new_id: np.ndarray | None,
    where: str,
) -> dict[str, Any]:
    """The boundary of a mesh from each patch's name and side faces (quads (E, 4)).

    ``on_bottom`` tells whether each point is on the bottom plane, ``new_id`` the points' new
    ids (None: kept).
    """
    edges: list[np.ndarray] = []
    patch: list[np.ndarray] = []
    names: list[str] = []
    for name, quads in sides:
        edges.append(side_edges(quads, on_bottom, f"{where}: patch {name}"))
        patch.append(np.full(quads.shape[0], len(names)))
        names.append(name)
    boundary_edges = np.concatenate(edges) if edges else np.empty((0, 2), np.int64)
    return {
        "boundary_edges": boundary_edges if new_id is None else new_id[boundary_edges],
        "boundary_patch": np.concatenate(patch) if patch else np.empty(0, np.int64),
        "patch_names": names,
    }


def side_edges(quads: np.ndarray, on_bottom: np.ndarray, what: str) -> np.ndarray:
    """The bottom edge (E, 2) of every side face ``quads`` (E, 4) of a one-layer mesh.

    The edge runs as the face lists its two bottom points; ExportError naming ``what`` for a
    face without exactly one edge on the bottom plane.
    """
    low = on_bottom[quads]
    pair = low & np.roll(low, -1, axis=1)
    if np.any(pair.sum(axis=1) != 1):
        raise ExportError(f"{what} has faces that are not one-layer sides")
    i = np.argmax(pair, axis=1)
    rows = np.arange(quads.shape[0])
    return np.stack([quads[rows, i], quads[rows, (i + 1) % 4]], axis=1)


def zone_interfaces(
    face_zones: tuple[np.ndarray, np.ndarray, np.ndarray, list[str]],
    internal: np.ndarray,
    on_bottom: np.ndarray,
    new_id: np.ndarray | None,
    where: str,
) -> dict[str, Any]:
    """The interface arguments of a mesh from its face zones (:func:`read_face_zones`).

    ``internal`` are the internal faces (quads of the one layer), ``on_bottom`` whether each
    point is on the bottom plane, ``new_id`` the points' new ids (None: kept). Each zone face
    becomes the edge it stands on, directed so that the zone's first region (the face's flip
    map) is on its left.
    """
    labels, flip, zone, zone_names = face_zones
    inner = side_edges(internal[labels], on_bottom, f"{where}: a face zone")
    inner[flip] = inner[flip][:, ::-1]
    if new_id is not None:
        inner = new_id[inner]
    return {"interface_edges": inner, "interface_patch": zone, "interface_names": zone_names}
