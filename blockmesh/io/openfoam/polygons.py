"""OpenFOAM cases of polygon meshes: one extruded layer of n-gon prisms, and reading them back.

A :class:`~blockmesh.mesh.polygons.PolygonMesh` is written as any mesh is
(:func:`~blockmesh.io.openfoam.writer.write_openfoam`): every cell a prism, its front and back
faces n-gons (hanging nodes included, so a coarse cell next to two finer ones has two side faces
there, each shared with one fine cell: the mesh is conforming, and ``checkMesh`` passes), its side
faces quadrilaterals. :func:`read_polygon_case` reads such a case back: the cells from the faces on
the bottom plane, the patches from the side faces, the regions from the cell zones and the
interfaces from the face zones.

The faces of the empty patch are parsed with a regular expression (they have different sizes,
so the fixed-width parser of :mod:`blockmesh.io.openfoam.reader` does not apply); that is about a
microsecond per face.

Examples
--------
>>> import pathlib, tempfile
>>> import blockmesh
>>> mesh = blockmesh.refine(blockmesh.load_domain("sp").mesh(1), cells=[0])
>>> case = pathlib.Path(tempfile.mkdtemp()) / "case"
>>> back = blockmesh.read(blockmesh.write(mesh, case, format="openfoam"))
>>> type(back).__name__, back.n_cells, sorted(set(back.cell_sizes().tolist()))
('PolygonMesh', 11, [5, 6])
"""

from __future__ import annotations

import os
import re
import zlib
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError
from blockmesh.geometry.topology import PolygonCells
from blockmesh.io.openfoam.files import (
    FaceSizeError,
    Inflated,
    find_polymesh,
    foam_file,
    list_size,
    read_boundary,
    read_face_zones,
    read_faces,
    read_list,
)
from blockmesh.io.openfoam.reader import (
    bottom_plane,
    case_regions,
    patch_arrays,
    read_points,
    zone_interfaces,
)
from blockmesh.io.openfoam.reader import read_openfoam as read_pentagon_case
from blockmesh.io.polygons import polygon_mesh_from_arrays
from blockmesh.io.text import parse_numbers
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["read_openfoam", "read_polygon_case"]

_FACE = re.compile(rb"(\d+)\s*\(([^()]*)\)")


def _face_text(poly: Path) -> tuple[bytes, str]:
    """The text of ``poly/faces`` (or ``faces.gz``, inflated), read within the read's bounds."""
    plain, packed = poly / "faces", poly / "faces.gz"
    if os.path.lexists(plain):
        path = plain
    elif os.path.lexists(packed):
        path = packed
    else:
        raise ExportError(f"{poly} has no faces file")
    where = str(path)
    guard = current_guard(where)
    try:
        with open_regular(path) as raw:
            if path is plain:
                guard.allocate(os.fstat(raw.fileno()).st_size, "the faces")
                return raw.read(), where
            stream = Inflated(raw, where)  # counted against what the files may expand to
            chunks = []
            while chunk := stream.read(1 << 22):
                guard.allocate(len(chunk), "the faces")
                chunks.append(chunk)
            guard.allocate(sum(len(c) for c in chunks), "the faces")  # joined below
            return b"".join(chunks), where
    except (OSError, EOFError, zlib.error) as error:
        raise ExportError(f"cannot read the faces of {poly}: {error}") from None


def _faces(poly: Path, start: int, count: int) -> tuple[np.ndarray, np.ndarray]:
    """Faces ``start .. start + count - 1`` as compressed rows (offsets, nodes)."""
    text, where = _face_text(poly)
    body = text[text.find(b"}") + 1 :]  # after the FoamFile header
    opening = re.search(rb"\d+\s*\(", body)
    if opening is None:
        raise ExportError(f"{where}: no list of faces")
    sizes: list[int] = []
    nodes: list[np.ndarray] = []
    for k, match in enumerate(_FACE.finditer(body, opening.end())):
        if k < start:
            continue
        if k >= start + count:
            break
        values = parse_numbers(match.group(2), np.int64, f"{where}: face {k}")
        if len(match.group(1)) > 18 or values.size != int(match.group(1)):
            raise ExportError(
                f"{where}: face {k} lists {values.size} nodes, not {match.group(1)[:20].decode()}"
            )
        sizes.append(values.size)
        nodes.append(values)
    if len(sizes) != count:
        raise ExportError(f"{where}: faces {start}..{start + count - 1} are not all in the file")
    offsets = np.concatenate([[0], np.cumsum(sizes, dtype=np.int64)])
    return offsets, np.concatenate(nodes) if nodes else np.empty(0, np.int64)


def _check_ids(ids: np.ndarray, n: int, what: str, where: str) -> None:
    """ExportError naming the first of ``ids`` outside ``0 .. n - 1``."""
    bad = (ids < 0) | (ids >= n)
    if np.any(bad):
        at = int(np.flatnonzero(bad.ravel())[0])
        raise ExportError(
            f"{where}: {what} {at} is {int(ids.ravel()[at])}, out of range (0..{n - 1})"
        )


def read_polygon_case(poly: Path) -> dict[str, Any]:
    """The arguments of :func:`~blockmesh.io.polygons.polygon_mesh_from_arrays` from ``poly``.

    ``poly`` is a ``polyMesh`` directory of one extruded layer whose front and back faces are
    polygons of any sizes.
    """
    where = str(poly)
    patches = read_boundary(poly)
    empty = [p for p in patches if p.get("type") == "empty"]
    if len(empty) != 1:
        raise ExportError(f"{where} needs one patch of type empty (the front and back faces)")
    with foam_file(poly, "owner") as (r, _):
        n_faces, owner = read_list(r, 1, np.int64)
    owner = owner.ravel()
    points = read_points(poly)
    n_points = points.shape[0]
    start, count = int(empty[0]["startFace"]), int(empty[0]["nFaces"])
    for p in patches:
        if int(p["startFace"]) + int(p["nFaces"]) > owner.size:
            raise ExportError(
                f"{where}: patch {p['name'][:60]!r} runs to face "
                f"{int(p['startFace']) + int(p['nFaces']) - 1:,}, beyond the {owner.size:,} "
                "faces of owner"
            )
    offsets, nodes = _faces(poly, start, count)
    _check_ids(nodes, n_points, "the empty patch's node", f"{where}/faces")
    face_owner = owner[start : start + count]
    _check_ids(face_owner, count, "the owner of empty-patch face", where)  # 2 faces per cell
    zmin, on_bottom = bottom_plane(points)
    faces = PolygonCells(offsets, nodes)
    slot_face = faces.slot_cell()
    low = np.bincount(slot_face, on_bottom[nodes], minlength=count) == faces.sizes()
    bottom = np.flatnonzero(low)
    cells_of = face_owner[bottom]
    n_cells = int(owner.max(initial=-1)) + 1
    if cells_of.size != n_cells or np.unique(cells_of).size != n_cells:
        raise ExportError(f"{where}: not every cell has exactly one face on the z = {zmin} plane")
    order = np.argsort(cells_of)
    chosen = bottom[order]
    sizes = faces.sizes()[chosen]
    cell_offsets = np.concatenate([[0], np.cumsum(sizes)])
    starts = np.repeat(offsets[chosen], sizes)
    within = np.arange(int(sizes.sum())) - np.repeat(cell_offsets[:-1], sizes)
    # the bottom face runs clockwise seen from +z: reversed within each cell
    reversed_within = np.repeat(sizes, sizes) - 1 - within
    cell_nodes = nodes[starts + reversed_within]
    used = np.zeros(n_points, dtype=bool)
    used[cell_nodes] = True
    new_id = np.cumsum(used) - 1
    sides = (
        (p["name"], _side_quads(poly, p, n_points)) for p in patches if p.get("type") != "empty"
    )
    boundary = patch_arrays(sides, on_bottom, new_id, where)
    regions = case_regions(poly, n_cells)
    interfaces = _interfaces(poly, on_bottom, new_id, where)
    del n_faces
    return {
        "points": points[used, :2],
        "offsets": cell_offsets,
        "nodes": new_id[cell_nodes],
        **regions,
        **boundary,
        **interfaces,
    }


def _side_quads(poly: Path, patch: dict[str, Any], n_points: int) -> np.ndarray:
    """The side faces (E, 4) of ``patch``; ExportError for faces that are not quads of points."""
    where = str(poly)
    first, size = int(patch["startFace"]), int(patch["nFaces"])
    quad_offsets, quad_nodes = _faces(poly, first, size) if size else (np.zeros(1, int), [])
    if size and np.any(np.diff(quad_offsets) != 4):
        raise ExportError(f"{where}: patch {patch['name']} has side faces that are not quads")
    quads = np.asarray(quad_nodes, dtype=np.int64).reshape(-1, 4)
    _check_ids(quads, n_points, f"patch {patch['name'][:60]!r}'s node", f"{where}/faces")
    return quads


def _interfaces(
    poly: Path, on_bottom: np.ndarray, new_id: np.ndarray, where: str
) -> dict[str, Any]:
    """The interfaces of a polygon case from its face zones (none without ``faceZones``)."""
    with foam_file(poly, "neighbour") as (r, _):
        n_internal = list_size(r)
    face_zones = read_face_zones(poly, n_internal)
    if face_zones is None or not n_internal:
        return {}
    internal = read_faces(poly, [(0, n_internal, 4)])[0]
    return zone_interfaces(face_zones, internal, on_bottom, new_id, where)


def read_openfoam(path: Path) -> Mesh | PolygonMesh:
    """Read a one-layer OpenFOAM case: a Mesh of pentagons, or a PolygonMesh of other polygons.

    The pentagon reader (:func:`blockmesh.io.openfoam.reader.read_openfoam`) is tried first; when
    the front and back faces are polygons of other sizes the case is read by
    :func:`read_polygon_case`.
    """
    try:
        return read_pentagon_case(path)
    except FaceSizeError:
        poly = find_polymesh(Path(path).absolute())
        return polygon_mesh_from_arrays(where=str(poly), **read_polygon_case(poly))
