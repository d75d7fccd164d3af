"""Reading one-layer OpenFOAM ``polyMesh`` folders back into pentagon meshes (ASCII, or gzipped).

The files are parsed line by line in chunks (:class:`blockmesh.io.text.TextReader`); only what
the 2-D mesh needs is parsed: the points, and the faces and owners of the boundary patches (the
internal faces are skipped). Layout: :mod:`blockmesh.io.openfoam.format`.

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

import contextlib
import gzip
import os
import re
import zlib
from collections.abc import Iterator
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError
from blockmesh.geometry.polygons import signed_area
from blockmesh.io.common import check_points, mesh_from_arrays
from blockmesh.io.text import TextReader, parse_numbers
from blockmesh.mesh.mesh import Mesh

__all__ = [
    "FaceSizeError",
    "foam_file",
    "read_boundary",
    "read_faces",
    "read_list",
    "read_openfoam",
    "side_edges",
    "zone_interfaces",
]


class FaceSizeError(ExportError):
    """Faces of a range that are not all of the size asked for (e.g. polygons, not pentagons)."""


_INT32 = np.iinfo(np.int32).max
_CHUNK = 1 << 18
#: Most lines, and most bytes of a line, of a ``FoamFile`` header.
_HEADER_LINES, _HEADER_LINE = 200, 4096
#: Most digits of a count (a face or point count of int64).
_DIGITS = 18


class _Inflated:
    """A gzip stream whose output is counted against the read's expansion allowance."""

    def __init__(self, packed: BinaryIO, where: str) -> None:
        self.stream = gzip.GzipFile(fileobj=packed, mode="rb")
        self.where = where

    def read(self, size: int = -1, /) -> bytes:
        data = self.stream.read(size if size >= 0 else 1 << 22)
        current_guard(self.where).expanded(len(data), "the gzip stream")
        return data


@contextlib.contextmanager
def foam_file(poly: Path, name: str) -> Iterator[tuple[TextReader, dict[str, str]]]:
    """A reader positioned after the ``FoamFile`` header of ``poly/name`` (or ``name.gz``).

    Also yields the header's entries. Raises :class:`ExportError` for a missing file, one that
    is not a regular file (a FIFO would block), a missing header or a binary file. A gzipped file
    is inflated a chunk at a time, within what the files read may expand to.
    """
    plain, packed = poly / name, poly / f"{name}.gz"
    if os.path.lexists(plain):
        raw, where = open_regular(plain), str(plain)
    elif os.path.lexists(packed):
        raw, where = open_regular(packed), str(packed)
    else:
        raise ExportError(f"{poly} has no {name} file; is it an OpenFOAM polyMesh directory?")
    with raw:
        handle: Any = raw
        size = None
        if where.endswith(".gz"):
            guard = current_guard(where)
            handle = _Inflated(raw, where)
            size = guard.expansion_allowed - guard.expanded_bytes
        r = TextReader(handle, where, size=size)
        try:
            header = _header(r)
        except (OSError, EOFError, zlib.error) as exc:
            raise ExportError(f"cannot read {where}: {exc}") from None
        try:
            yield r, header
        except (OSError, EOFError, zlib.error) as exc:  # a damaged gzip stream
            raise ExportError(f"cannot read {where}: {exc}") from None


def _header(r: TextReader) -> dict[str, str]:
    """The entries of the ``FoamFile { ... }`` header; the reader is left after it."""
    while True:
        line = r.line()
        if line.strip().startswith(b"FoamFile"):
            break
        if r.at_end or r.line_number > 1000:
            raise ExportError(f"{r.where} has no FoamFile header")
    lines: list[bytes] = []
    while not lines or b"}" not in lines[-1]:
        line = r.line()
        if (r.at_end and not line) or len(lines) > _HEADER_LINES:
            raise ExportError(
                f"{r.where}: the FoamFile header does not end (no }} within {_HEADER_LINES} lines)"
            )
        lines.append(line[:_HEADER_LINE])
    text = b"\n".join(lines) + b"\n"
    header = {}
    for entry in text.split(b"}")[0].strip().lstrip(b"{").decode(errors="replace").split(";"):
        parts = entry.split(None, 1)
        if len(parts) == 2:
            header[parts[0]] = parts[1].strip().strip('"')
    if header.get("format", "ascii") != "ascii":
        raise ExportError(
            f"{r.where} is in binary format; blockmesh reads ASCII polyMesh files "
            "(run foamFormatConvert with writeFormat ascii)"
        )
    return header


def _significant(r: TextReader) -> bytes:
    """The next line that is not blank and not a ``//`` comment."""
    while True:
        text = r.line().strip()
        if text and not text.startswith(b"//"):
            return text
        if r.at_end:
            raise ExportError(f"{r.where}: the file ends at line {r.line_number} before a list")


_INLINE = re.compile(rb"^(\d+)\s*\((.*)\)\s*;?$")
_UNIFORM = re.compile(rb"^(\d+)\s*\{(.*)\}\s*;?$")


def read_list(
    r: TextReader, cols: int, dtype: type, *, skip: int = 0, out_dtype: type | None = None
) -> tuple[int, np.ndarray]:
    """The count and the rows from ``skip`` on of the next list ``N ( items )`` (one item a line).

    Items ``(x y z)`` and ``4(a b c d)`` are read as plain numbers (the parentheses are blanks).
    Short lists written on one line (``3(0 1 2)``) and uniform lists (``3{7}``) are read too.
    """
    text = _significant(r)
    for pattern in (_INLINE, _UNIFORM):
        match = pattern.match(text)
        if match:
            count = _count(match[1], r)
            if pattern is _UNIFORM:
                current_guard(r.where).allocate(8 * cols * count, f"a uniform list of {count:,}")
            inner = match[2].replace(b"(", b" ").replace(b")", b" ")
            values = parse_numbers(inner, dtype, f"{r.where}, line {r.line_number}")
            if pattern is _UNIFORM:
                values = np.repeat(values, count)
            if values.size != count * cols:
                raise ExportError(f"{r.where}, line {r.line_number}: malformed list {text[:60]!r}")
            return count, values.reshape(count, cols)[skip:].astype(out_dtype or dtype)
    if not text.isdigit():
        raise ExportError(
            f"{r.where}, line {r.line_number}: expected a list size, got {text[:60]!r}"
        )
    count = _count(text, r)
    if _significant(r) != b"(":
        raise ExportError(f"{r.where}, line {r.line_number}: expected ( after the list size")
    r.skip(skip)
    rows = r.table(count - skip, cols, dtype, out_dtype, blank=b"()")
    if not _significant(r).startswith(b")"):
        raise ExportError(f"{r.where}, line {r.line_number}: the list of {count} does not end")
    return count, rows


def _count(digits: bytes, r: TextReader) -> int:
    """A list size (whole number of at most :data:`_DIGITS` digits)."""
    if len(digits) > _DIGITS:
        raise ExportError(
            f"{r.where}, line {r.line_number}: a list size of {len(digits)} digits (damaged?)"
        )
    return int(digits)


def _list_size(r: TextReader) -> int:
    text = _significant(r)
    match = re.match(rb"^(\d+)", text)
    if match is None:
        raise ExportError(
            f"{r.where}, line {r.line_number}: expected a list size, got {text[:60]!r}"
        )
    return _count(match[1], r)


#: A comment (an unclosed one runs to the end: one pass, linear time).
_COMMENT = re.compile(r"//[^\n]*|/\*.*?(?:\*/|\Z)", flags=re.S)


def _tokens(text: str) -> list[str]:
    text = _COMMENT.sub(" ", text)
    return re.findall(r'"[^"]*"|[{}();]|[^\s{}();]+', text)


def read_boundary(poly: Path) -> list[dict[str, str]]:
    """The patches of ``poly/boundary``: one dictionary of entries (and ``name``) each."""
    with foam_file(poly, "boundary") as (r, _):
        body = r.rest()
        where = r.where
    toks = _tokens(body.decode(errors="replace"))
    try:
        k = toks.index("(") + 1
        patches = []
        while k < len(toks) and toks[k] != ")":
            name, k = toks[k], k + 2  # skip name and "{"
            entry: dict[str, str] = {"name": name}
            while toks[k] != "}":
                key, k = toks[k], k + 1
                value = []
                depth = 0
                while depth or toks[k] != ";":
                    depth += toks[k] == "("
                    depth -= toks[k] == ")"
                    value.append(toks[k])
                    k += 1
                entry[key] = " ".join(value)
                k += 1
            patches.append(entry)
            k += 1
    except (ValueError, IndexError):
        raise ExportError(f"{where}: malformed patch list") from None
    for p in patches:
        for key in ("nFaces", "startFace"):
            entry_value = p.get(key, "")
            if not entry_value.isdigit() or len(entry_value) > _DIGITS:
                raise ExportError(
                    f"{where}: patch {p['name'][:60]!r} has {key} {entry_value[:30]!r}, not a "
                    "whole number"
                )
    return patches


def read_faces(poly: Path, ranges: list[tuple[int, int, int]]) -> list[np.ndarray]:
    """The faces ``start`` to ``start + count - 1`` of ``poly/faces``, each of ``size`` nodes.

    ``ranges`` are ``(start, count, size)``, in increasing order of ``start``; returns one
    ``(count, size)`` array of node ids each. Faces before and between are skipped, not parsed.
    Raises :class:`ExportError` when a face in a range has another size.
    """
    out = []
    with foam_file(poly, "faces") as (r, header):
        if header.get("class") == "faceCompactList":
            raise ExportError(f"{r.where}: faceCompactList files are not supported (faceList)")
        count = _list_size(r)
        if _significant(r) != b"(":
            raise ExportError(f"{r.where}: expected ( after the number of faces")
        at = 0
        for start, n, size in ranges:
            if start < at or start + n > count:
                raise ExportError(f"{r.where}: faces {start}..{start + n - 1} are not in the file")
            r.skip(start - at)
            try:
                rows = r.table(
                    n, 1 + size, np.int64, np.int32 if count <= _INT32 else np.int64, blank=b"()"
                )
            except ExportError:
                raise FaceSizeError(
                    f"{r.where}: faces {start}..{start + n - 1} are not all of {size} nodes"
                ) from None
            if np.any(rows[:, 0] != size):
                raise FaceSizeError(
                    f"{r.where}: faces {start}..{start + n - 1} are not all of {size} nodes"
                )
            out.append(rows[:, 1:])
            at = start + n
    return out


def _note(header: dict[str, str]) -> dict[str, int]:
    """The counts in a ``note "nPoints:.. nCells:.. nFaces:.. nInternalFaces:.."``."""
    return {k: int(v) for k, v in re.findall(r"(n\w+):\s*(\d+)", header.get("note", ""))}


def _zones(poly: Path, file: str) -> list[tuple[str, dict[str, np.ndarray]]] | None:
    """The zones of ``poly/file`` (``cellZones``, ``faceZones``): each name and its lists.

    The lists are the ``NAME List<label|bool> ...`` entries of each zone (``cellLabels``,
    ``faceLabels``, ``flipMap``), read whether written one value a line, inline or uniform.
    None when there is no such file.
    """
    if not ((poly / file).exists() or (poly / f"{file}.gz").exists()):
        return None
    out: list[tuple[str, dict[str, np.ndarray]]] = []
    with foam_file(poly, file) as (r, _):
        n_zones = _list_size(r)
        if _significant(r) != b"(":
            raise ExportError(f"{r.where}: expected ( after the number of zones")
        for _ in range(n_zones):
            name = _significant(r).decode(errors="replace")
            if _significant(r) != b"{":
                raise ExportError(f"{r.where}, line {r.line_number}: expected {{ after zone {name}")
            found: dict[str, np.ndarray] = {}
            while True:
                line = _significant(r)
                if line.startswith(b"}"):
                    break
                match = re.match(rb"(\w+)\s+List<(?:label|bool)>\s*(.*)$", line)
                if match is not None:
                    found[match[1].decode()] = _zone_list(r, match[2].strip())
            out.append((name, found))
    return out


def _zone_list(r: TextReader, rest: bytes) -> np.ndarray:
    """The values of a zone's list whose first line (after ``List<...>``) is ``rest``."""
    where = f"{r.where}, line {r.line_number}"
    for pattern in (_INLINE, _UNIFORM):
        inner = pattern.match(rest)
        if inner:
            values = parse_numbers(inner[2], np.int64, where)
            if pattern is _INLINE:
                return values
            count = int(inner[1]) if len(inner[1]) <= _DIGITS else -1
            if count < 0 or values.size != 1:
                raise ExportError(
                    f"{where}: a uniform list {rest[:60]!r} is not COUNT{{VALUE}} with a count of "
                    f"at most {_DIGITS} digits"
                )
            current_guard(r.where).allocate(8 * count, f"a uniform list of {count:,}")
            return np.repeat(values, count)
    count = _count(rest, r) if rest.isdigit() else _list_size(r)
    if _significant(r) != b"(":
        raise ExportError(f"{where}: expected (")
    values = r.table(count, 1, np.int64).ravel()
    _significant(r)  # the closing ")" (or ");")
    return values


def _read_zones(poly: Path, n_cells: int) -> tuple[np.ndarray, list[str]] | None:
    zones = _zones(poly, "cellZones")
    if zones is None:
        return None
    where = str(poly / "cellZones")
    region = np.full(n_cells, -1, dtype=np.int64)
    names: list[str] = []
    for name, lists in zones:
        labels = lists.get("cellLabels")
        if labels is None:
            raise ExportError(f"{where}: zone {name} has no cellLabels")
        if labels.size and (labels.min() < 0 or labels.max() >= n_cells):
            raise ExportError(f"{where}: zone {name} names cells outside 0..{n_cells - 1}")
        region[labels] = len(names)
        names.append(name)
    if np.any(region < 0):
        region[region < 0] = len(names)
        names.append("unzoned")
    return region, names


def _find_polymesh(path: Path) -> Path:
    candidates = [path / "constant" / "polyMesh", path / "polyMesh", path]
    poly = next(
        (c for c in candidates if (c / "boundary").exists() or (c / "boundary.gz").exists()), None
    )
    if poly is not None:
        return poly
    leftovers = sorted(
        p.name
        for c in (path / "constant", path)
        if c.is_dir()
        for p in c.iterdir()
        if p.name.startswith(".polyMesh.") or p.name.startswith(".constant.")
    )
    hint = (
        f"; an interrupted write left {', '.join(leftovers)}: write the mesh again (blockmesh "
        "then puts back or removes them)"
        if leftovers
        else ""
    )
    raise ExportError(
        f"{path} holds no OpenFOAM polyMesh (looked for constant/polyMesh/boundary){hint}"
    )


def read_openfoam(path: Path) -> Mesh:
    """Read a one-layer extruded polyMesh (as :func:`write_openfoam` writes) back to pentagons.

    Raises :class:`FaceSizeError` when the front and back faces are not all pentagons;
    :func:`blockmesh.io.openfoam.polygons.read_openfoam` (what :func:`blockmesh.read` uses) then
    reads the case as a PolygonMesh.

    ``path`` is the case, its ``constant`` directory or the ``polyMesh`` directory. ASCII files
    (optionally gzipped) only. O(F) in the number of faces; the internal faces are skipped.
    """
    path = Path(path).absolute()
    poly = _find_polymesh(path)
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
    note = _note(header)
    with foam_file(poly, "neighbour") as (r, _):
        n_internal = _list_size(r)
    with foam_file(poly, "points") as (r, _):
        n_points, points = read_list(r, 3, np.float64)
    check_points(points, str(poly / "points"))  # before the planes are found from them
    face_zones = _read_face_zones(poly, n_internal)
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

    zmin = points[:, 2].min(initial=0.0)
    tol = 1e-9 * max(1.0, float(np.ptp(points[:, 2])) if points.size else 1.0)
    on_bottom = np.abs(points[:, 2] - zmin) <= tol
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
    edges: list[np.ndarray] = []
    patch: list[np.ndarray] = []
    names: list[str] = []
    for k, p in enumerate(patches):
        if p.get("type") == "empty":
            continue
        quad = face_of.get(k, np.empty((0, 4), dtype=np.int64))
        if quad.size and (quad.max() >= n_points or quad.min() < 0):
            raise ExportError(
                f"{where}: patch {p['name'][:60]!r} names points outside the points file"
            )
        edges.append(side_edges(quad, on_bottom, f"{where}: patch {p['name']}"))
        patch.append(np.full(quad.shape[0], len(names)))
        names.append(p["name"])
    boundary_edges = np.concatenate(edges) if edges else np.empty((0, 2), np.int64)
    if new_id is not None:
        boundary_edges = new_id[boundary_edges]
    interfaces: dict[str, Any] = {}
    if face_zones is not None and internal is not None:
        interfaces = zone_interfaces(face_zones, internal, on_bottom, new_id, where)
    zones = _read_zones(poly, n_cells)
    region, region_names = zones if zones is not None else (None, None)
    case = poly.parent.parent if poly.parent.name == "constant" else poly
    return {
        "points": points_2d,
        "cells": cells,
        "region": region,
        "region_names": region_names,
        "boundary_edges": boundary_edges,
        "boundary_patch": np.concatenate(patch) if patch else np.empty(0, np.int64),
        "patch_names": names,
        **interfaces,
        "name": case.name,
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
    """The interface arguments of a mesh from its face zones (:func:`_read_face_zones`).

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


def _read_face_zones(
    poly: Path, n_internal: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[str]] | None:
    """The internal faces of every face zone: labels, flips, zone index, zone names (or None)."""
    zones = _zones(poly, "faceZones")
    if not zones:
        return None
    where = str(poly / "faceZones")
    labels, flips, names = [], [], []
    for name, lists in zones:
        face = lists.get("faceLabels")
        if face is None:
            raise ExportError(f"{where}: face zone {name} has no faceLabels")
        if face.size and (face.min() < 0 or face.max() >= n_internal):
            raise ExportError(
                f"{where}: face zone {name} names faces outside the internal faces "
                f"0..{n_internal - 1} (blockmesh reads zones of internal faces: interfaces)"
            )
        flip = lists.get("flipMap", np.zeros(face.size, dtype=np.int64))
        if flip.size != face.size:
            raise ExportError(f"{where}: face zone {name}'s flipMap has another length")
        labels.append(face)
        flips.append(flip != 0)
        names.append(name)
    zone = np.repeat(np.arange(len(names)), [f.size for f in labels])
    return np.concatenate(labels), np.concatenate(flips), zone, names
