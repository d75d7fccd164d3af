"""Pentagonal conversion of an existing mesh: triangles, quadrilaterals or both, to a Domain.

Every element becomes strictly convex pentagons with two nodes on each of its edges at the
symmetric fractions 0.335645 / 0.664355 (:mod:`blockmesh.decompose.pieces`): a triangle 9, a
convex quadrilateral 12, a convex n-gon ``3 n``; elements sharing an edge share those nodes, so any
conforming mesh becomes a conforming pentagon mesh. A mesh whose elements are all strictly convex
pentagons already is one: its elements become the blocks as they are (a refined blockmesh mesh read
back, for example). A quadrilateral that is not strictly convex is split into two triangles along
the diagonal from its reflex corner.

Names come along: line elements in named groups (Gmsh physical curves, or the cell sets of other
formats) become patches, element groups become regions, and each block records the element it
came from (:attr:`blockmesh.domain.Domain.block_source`, the element's index among the input's
2-D elements in file order). The element corners stay where they are; the template nodes are
then moved to raise the worst angle (:mod:`blockmesh.decompose.optimise`).

The input is rejected, with the element or node named, when it has 3-D elements, points off one
plane, inverted elements (running the other way round from the rest; a mesh running clockwise
throughout is reversed, with a warning), degenerate elements, edges shared by three elements, or
hanging nodes (a node inside another element's edge: not conforming).

Examples
--------
>>> import meshio, numpy as np
>>> square = meshio.Mesh(
...     np.array([[0, 0], [1, 0], [1, 1], [0, 1], [2, 0], [2, 1]], dtype=float),
...     [("quad", np.array([[0, 1, 2, 3]])), ("triangle", np.array([[1, 4, 5], [1, 5, 2]]))],
... )
>>> spec = convert_elements(read_element_mesh(square))
>>> len(spec.blocks), spec.layout, sorted(set(spec.block_source.tolist()))
(30, 'conversion', [0, 1, 2])

:meth:`blockmesh.Domain.from_mesh` makes the Domain of it.
"""

from __future__ import annotations

import itertools
import os
import warnings
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from blockmesh import io as blockmesh_io
from blockmesh._moved import removed_names
from blockmesh._system.bounded import check_regular
from blockmesh.decompose.optimise import WorstAngle
from blockmesh.decompose.pieces import pentagons_from_pieces
from blockmesh.decompose.triangulate import constrained_delaunay
from blockmesh.errors import (
    BlockMeshError,
    BlockMeshWarning,
    DomainError,
    DomainFormatError,
    ResourceError,
)
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    MAX_COORDINATE,
    corner_sines,
    local_frame,
    signed_area,
)
from blockmesh.io.sandbox import read_with_meshio
from blockmesh.mesh.mesh import Mesh
from blockmesh.refinement.placement import Freedom

__all__ = ["BlockSpec", "convert_elements", "read_element_mesh"]

#: Names this module had, now elsewhere (release 0.1: ``convert_mesh``).
__getattr__ = removed_names(__name__)

_TWO_D = {"triangle": 3, "quad": 4, "triangle6": 3, "triangle7": 3, "quad8": 4, "quad9": 4}
_LINES = {"line": 2, "line3": 2}
_POINTS = {"vertex"}


class _Elements:
    """The planar element mesh the conversion works on (points, elements, groups)."""

    def __init__(self) -> None:
        self.points = np.zeros((0, 2))
        self.elements: list[np.ndarray] = []  # each (n,) vertex ids, in file order
        self.kind: list[str] = []
        self.lines: list[tuple[int, int, str]] = []  # (a, b, group)
        self.region_of: list[str | None] = []
        self.region_names: list[str] = []
        self.patch_names: list[str] = []


def read_element_mesh(source: Any) -> Any:
    """A meshio mesh (or a blockmesh :class:`~blockmesh.mesh.Mesh`) from a path or object.

    blockmesh's own files (``.npz``, ``.mat``, and the ``.vtu``/``.xdmf``/``.msh`` it writes) are
    read with :func:`blockmesh.read`, which keeps patch and region names; anything else with
    meshio, and a ``.msh`` that meshio cannot read with the gmsh API where it is installed, in a
    child process with memory and time limits (:mod:`blockmesh.io.sandbox`). Only regular files
    are read (a FIFO or a device is refused before it is opened).
    """
    import meshio

    if isinstance(source, meshio.Mesh | Mesh):
        return source
    path = Path(source)

    if not os.path.lexists(path):
        raise DomainFormatError(f"{path}: no such file")
    check_regular(path, error=DomainFormatError)
    try:
        return blockmesh_io.read(path)
    except ResourceError:
        raise
    except BlockMeshError:
        pass  # not a file blockmesh wrote
    try:
        return read_with_meshio(path)
    except BlockMeshError as error:
        raise DomainFormatError(f"{path}: cannot read it as a mesh ({error})") from None


def _read_with_gmsh(path: Path) -> Any:
    """A meshio mesh of a .msh file read through the gmsh API, or None without gmsh."""
    try:
        import gmsh
    except ImportError:
        return None
    import meshio

    initialised = gmsh.isInitialized()
    if not initialised:
        gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        tags, coords, _ = gmsh.model.mesh.getNodes()
        index = {int(t): k for k, t in enumerate(tags)}
        points = np.asarray(coords).reshape(-1, 3)
        cells: list[tuple[str, np.ndarray]] = []
        sets: dict[str, dict[int, np.ndarray]] = {}
        for dim, entity in gmsh.model.getEntities():
            if dim not in (1, 2):
                continue
            names = [
                gmsh.model.getPhysicalName(dim, p)
                for p in gmsh.model.getPhysicalGroupsForEntity(dim, entity)
            ]
            types, _, nodes = gmsh.model.mesh.getElements(dim, entity)
            for kind, node_tags in zip(types, nodes, strict=True):
                name, _, _, corners = gmsh.model.mesh.getElementProperties(kind)[:4]
                meshio_type = {1: "line", 2: "triangle", 3: "quad"}.get(int(kind))
                if meshio_type is None:
                    raise DomainFormatError(
                        f"{path}: element type {name!r} is not a line, triangle or quadrilateral"
                    )
                size = len(node_tags) // max(int(corners), 1) if corners else 0
                ids = np.array([index[int(t)] for t in node_tags]).reshape(size, -1)[:, :corners]
                block = len(cells)
                cells.append((meshio_type, ids))
                for group in names or []:
                    sets.setdefault(group, {})[block] = np.arange(len(ids))
        cell_sets = {
            name: [members.get(b, np.zeros(0, np.int64)) for b in range(len(cells))]
            for name, members in sets.items()
        }
        return meshio.Mesh(points, cells, cell_sets=cell_sets)
    except Exception as error:
        raise DomainFormatError(f"{path}: gmsh cannot read it either ({error})") from None
    finally:
        if not initialised:
            gmsh.finalize()


class BlockSpec(NamedTuple):
    """A converted mesh as the arguments of :meth:`blockmesh.Domain.from_blocks`."""

    vertices: np.ndarray
    blocks: np.ndarray
    patches: dict[str, Any]
    regions: dict[str, Any]
    layout: str
    block_source: np.ndarray


def convert_elements(mesh: Any) -> BlockSpec:
    """The pentagonal blocks of a mesh read by :func:`read_element_mesh` (see the module notes).

    Layout ``"mesh"`` when the elements are the blocks (all strictly convex pentagons, or a
    blockmesh Mesh read back, its patches and regions kept), ``"conversion"`` when they went
    through the templates.
    """
    if isinstance(mesh, Mesh):
        return _from_pentagon_mesh(mesh)
    elements = _elements_of(mesh)
    _check_elements(elements)
    return _convert(elements)


def _from_pentagon_mesh(mesh: Mesh) -> BlockSpec:
    """A blockmesh Mesh read back: its cells are the blocks, its patches and regions kept."""
    patches = {
        patch: mesh.boundary_edges[mesh.boundary_patch == k].tolist()
        for k, patch in enumerate(mesh.patch_names)
    }
    regions = {
        region: np.flatnonzero(mesh.region == k).tolist()
        for k, region in enumerate(mesh.region_names)
    }
    return BlockSpec(
        mesh.points,
        mesh.cells,
        {k: v for k, v in patches.items() if v},
        {k: v for k, v in regions.items() if v},
        "mesh",
        np.arange(mesh.n_cells),
    )


def _elements_of(mesh: Any) -> _Elements:
    """Planar points, 2-D elements in file order, named line groups and element groups."""
    out = _Elements()
    for cells in mesh.cells:
        known = cells.type in _TWO_D or cells.type in _LINES or cells.type in _POINTS
        if not known and not cells.type.startswith("polygon"):
            raise DomainError(
                f"the mesh has {len(cells.data)} {cells.type} elements: blockmesh converts 2-D "
                "meshes of triangles, quadrilaterals and polygons only (no 3-D elements)"
            )
    points = np.asarray(mesh.points, dtype=np.float64)
    if points.ndim != 2 or points.shape[1] not in (2, 3) or points.shape[0] == 0:
        raise DomainFormatError(f"the mesh's points must be (n, 2) or (n, 3), got {points.shape}")
    fine = np.all(np.abs(points) <= MAX_COORDINATE, axis=1)  # NaN fails too
    if not fine.all():
        bad = int(np.flatnonzero(~fine)[0])
        raise DomainFormatError(
            f"point {bad} of the mesh is {points[bad].tolist()}: coordinates must be finite "
            f"numbers of at most {MAX_COORDINATE:g} in magnitude"
        )
    if points.shape[1] == 3:
        z = points[:, 2]
        extent = float(np.ptp(points[:, :2], axis=0).max()) or 1.0
        if float(np.ptp(z)) > 1e-9 * extent:
            worst = int(np.argmax(np.abs(z - np.median(z))))
            raise DomainError(
                f"the mesh is not planar: point {worst} has z = {z[worst]:.6g} while the others "
                f"lie near z = {float(np.median(z)):.6g}; blockmesh converts 2-D meshes in the "
                "x-y plane"
            )
    out.points = points[:, :2].copy()
    groups = _cell_groups(mesh)
    for block, cells in enumerate(mesh.cells):
        kind, data = cells.type, np.asarray(cells.data)
        if kind in _POINTS:
            continue
        if kind in _LINES:
            for k, row in enumerate(data[:, :2].tolist()):
                for group in groups.get((block, k), ()):
                    out.lines.append((int(row[0]), int(row[1]), group))
            continue
        if kind == "polygon" or kind.startswith("polygon"):
            corners = data.shape[1]
        elif kind in _TWO_D:
            corners = _TWO_D[kind]
            if data.shape[1] > corners:
                warnings.warn(
                    f"{len(data)} {kind} elements are higher order; only their corners are "
                    "used (their curved edges become straight)",
                    BlockMeshWarning,
                    stacklevel=4,
                )
        for k, row in enumerate(data[:, :corners]):
            out.elements.append(np.asarray(row, dtype=np.int64))
            out.kind.append(kind)
            names = groups.get((block, k), ())
            out.region_of.append(names[0] if names else None)
    if not out.elements:
        raise DomainError("the mesh has no triangles, quadrilaterals or polygons")
    return out


def _cell_groups(mesh: Any) -> dict[tuple[int, int], tuple[str, ...]]:
    """Named groups of each cell: meshio's cell sets, else Gmsh physical tags and names."""
    groups: dict[tuple[int, int], list[str]] = {}
    sets = {k: v for k, v in (getattr(mesh, "cell_sets", None) or {}).items()}
    sets = {k: v for k, v in sets.items() if not k.startswith("gmsh:")}
    if sets:
        for name, per_block in sets.items():
            for block, members in enumerate(per_block):
                for k in np.asarray(members, dtype=np.int64).tolist():
                    groups.setdefault((block, k), []).append(str(name))
        return {key: tuple(v) for key, v in groups.items()}
    physical = (getattr(mesh, "cell_data", None) or {}).get("gmsh:physical")
    if physical is None:
        return {}
    names = {
        (int(tag_dim[1]), int(tag_dim[0])): str(name)
        for name, tag_dim in (getattr(mesh, "field_data", None) or {}).items()
        if len(tag_dim) >= 2
    }
    for block, (cells, tags) in enumerate(zip(mesh.cells, physical, strict=True)):
        dim = 1 if cells.type in _LINES else 2
        for k, tag in enumerate(np.asarray(tags).tolist()):
            group = names.get((dim, int(tag)))
            if group is not None:
                groups.setdefault((block, k), []).append(group)
    return {key: tuple(v) for key, v in groups.items()}


def _check_elements(e: _Elements) -> None:
    """Orientation, degenerate elements, manifold edges and hanging nodes, named."""
    n_points = e.points.shape[0]
    for k, element in enumerate(e.elements):
        if element.min() < 0 or element.max() >= n_points or len(set(element.tolist())) < 3:
            raise DomainError(
                f"element {k} ({e.kind[k]} {element.tolist()}) refers to missing or repeated nodes"
            )
    frame = local_frame(e.points)
    local = frame.to_local(e.points)
    areas = np.array([float(signed_area(local[el])) for el in e.elements])
    extent = np.array([float(np.ptp(local[el], axis=0).max()) for el in e.elements])
    flat = np.flatnonzero(np.abs(areas) <= 1e-12 * extent**2)
    if flat.size:
        k = int(flat[0])
        raise DomainError(
            f"element {k} ({e.kind[k]} {e.elements[k].tolist()}) has zero area: its corners lie "
            "on one line"
        )
    negative = areas < 0
    if negative.all():
        warnings.warn(
            "the mesh's elements all run clockwise; they were reversed to counter-clockwise",
            BlockMeshWarning,
            stacklevel=4,
        )
        e.elements = [el[::-1].copy() for el in e.elements]
    elif negative.any():
        bad = np.flatnonzero(negative)
        shown = ", ".join(f"{int(k)} ({e.kind[k]})" for k in bad[:5])
        raise DomainError(
            f"{bad.size} element{'s are' if bad.size > 1 else ' is'} inverted (running clockwise "
            f"while the others run counter-clockwise): {shown}; fix the mesh's orientation"
        )
    _check_conforming(e, local)


def _check_conforming(e: _Elements, local: np.ndarray) -> None:
    import shapely

    starts = np.concatenate([el for el in e.elements])
    stops = np.concatenate([np.roll(el, -1) for el in e.elements])
    owner = np.repeat(np.arange(len(e.elements)), [len(el) for el in e.elements])
    n = local.shape[0]
    lo, hi = np.minimum(starts, stops), np.maximum(starts, stops)
    keys = lo * n + hi
    unique, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
    if counts.max() > 2:
        a, b = divmod(int(unique[np.argmax(counts)]), n)
        users = sorted(set(owner[keys == unique[np.argmax(counts)]].tolist()))
        raise DomainError(
            f"edge ({a}, {b}) belongs to {counts.max()} elements ({', '.join(map(str, users))}); "
            "an edge may be shared by two elements at most"
        )
    free = counts[inverse] == 1
    seg_a, seg_b, seg_owner = starts[free], stops[free], owner[free]
    segments = shapely.linestrings(np.stack([local[seg_a], local[seg_b]], axis=1))
    tol = 1e-11
    used = np.unique(starts)
    nodes = shapely.points(local[used])
    node_index, segment = shapely.STRtree(segments).query(nodes, predicate="dwithin", distance=tol)
    v = used[node_index]
    inside = (v != seg_a[segment]) & (v != seg_b[segment])
    if inside.any():
        k = int(np.flatnonzero(inside)[0])
        node, s = int(v[k]), int(segment[k])
        raise DomainError(
            f"node {node} {tuple(float(c) for c in e.points[node])} lies on edge "
            f"({int(seg_a[s])}, {int(seg_b[s])}) of element {int(seg_owner[s])} without being one "
            "of its corners (a hanging node): the mesh is not conforming"
        )


def _convert(e: _Elements) -> BlockSpec:
    """Pieces to pentagons (or the pentagons as blocks), patches, regions, sources."""
    used = np.unique(np.concatenate(e.elements))
    renumber = np.full(e.points.shape[0], -1, dtype=np.int64)
    renumber[used] = np.arange(used.size)
    points = e.points[used]
    local = local_frame(points).to_local(points)
    pieces: list[np.ndarray] = []
    source: list[int] = []
    for k, element in enumerate(e.elements):
        corners = renumber[element]
        for piece in _convex_parts(local, corners):
            pieces.append(piece)
            source.append(k)
    lines = [
        (int(renumber[a]), int(renumber[b]), g)
        for a, b, g in e.lines
        if renumber[a] >= 0 and renumber[b] >= 0
    ]
    if all(len(p) == 5 for p in pieces) and len(pieces) == len(e.elements):
        blocks = np.array(pieces, dtype=np.int64)
        return BlockSpec(
            points, blocks, _patches_direct(lines, blocks), _element_sets(e), "mesh",
            np.array(source),
        )  # fmt: skip
    groups: dict[int, list[int]] = {}
    for i, piece in enumerate(pieces):
        groups.setdefault(len(piece), []).append(i)
    order = [i for n in sorted(groups) for i in groups[n]]
    result = pentagons_from_pieces(
        points, [np.array([pieces[i] for i in groups[n]]) for n in sorted(groups)]
    )
    block_piece = np.array(order, dtype=np.int64)[result.piece]
    block_source = np.array(source, dtype=np.int64)[block_piece]
    block_regions = {
        region: np.flatnonzero(np.isin(block_source, ids)).tolist()
        for region, ids in _element_sets(e).items()
    }
    patches = _patches_templated(lines, result, pieces)
    nodes = _improved(result, pieces, points)
    return BlockSpec(nodes, result.blocks, patches, block_regions, "conversion", block_source)


def _improved(result: Any, pieces: list[np.ndarray], points: np.ndarray) -> np.ndarray:
    """The template nodes moved to raise the worst angle.

    Element corners stay; the side nodes on the boundary slide along their edge.
    """
    frame = local_frame(result.nodes)
    local = frame.to_local(result.nodes)
    fixed = np.zeros(len(local), dtype=bool)
    fixed[: points.shape[0]] = True
    slide = np.zeros_like(local)
    for a, b in _boundary_edge_set(pieces):
        chain = result.side_chain(a, b)
        d = local[b] - local[a]
        slide[chain[1:3]] = d / np.hypot(*d)
    moved = frame.to_global(WorstAngle().place(local, result.blocks, Freedom(fixed, slide)))
    moved[: points.shape[0]] = points
    return moved


def _convex_parts(local: np.ndarray, corners: np.ndarray) -> list[np.ndarray]:
    """The element itself if strictly convex, else triangles from its reflex corner(s)."""
    if np.all(corner_sines(local[corners]) > COLLINEAR_SIN_TOL):
        return [corners]
    import shapely

    polygon = shapely.Polygon(local[corners])
    parts = shapely.get_parts(constrained_delaunay(polygon))
    ids = {tuple(p): k for p, k in zip(local[corners].tolist(), corners.tolist(), strict=True)}
    out = []
    for tri in parts:
        xy = shapely.get_coordinates(tri)[:3]
        t = np.array([ids[tuple(p)] for p in xy.tolist()], dtype=np.int64)
        if signed_area(local[t]) < 0:
            t = t[::-1]
        out.append(t)
    return out


def _element_sets(e: _Elements) -> dict[str, list[int]]:
    sets: dict[str, list[int]] = {}
    for k, region in enumerate(e.region_of):
        if region is not None:
            sets.setdefault(region, []).append(k)
    return sets


def _boundary_edge_set(blocks: list[np.ndarray] | np.ndarray) -> set[tuple[int, int]]:
    edges: dict[tuple[int, int], int] = {}
    for block in blocks:
        for a, b in zip(list(block), list(np.roll(block, -1)), strict=True):
            key = (min(int(a), int(b)), max(int(a), int(b)))
            edges[key] = edges.get(key, 0) + 1
    return {key for key, count in edges.items() if count == 1}


def _patches_direct(
    lines: list[tuple[int, int, str]], blocks: np.ndarray
) -> dict[str, list[tuple[int, int]]]:
    boundary = _boundary_edge_set(blocks)
    patches: dict[str, list[tuple[int, int]]] = {}
    inside: dict[str, int] = {}
    for a, b, group in lines:
        if (min(a, b), max(a, b)) in boundary:
            patches.setdefault(group, []).append((a, b))
        else:
            inside[group] = inside.get(group, 0) + 1
    _warn_inside(inside)
    return patches


def _patches_templated(
    lines: list[tuple[int, int, str]], result: Any, pieces: list[np.ndarray]
) -> dict[str, list[tuple[int, int]]]:
    boundary = _boundary_edge_set(pieces)
    patches: dict[str, list[tuple[int, int]]] = {}
    inside: dict[str, int] = {}
    for a, b, group in lines:
        if (min(a, b), max(a, b)) not in boundary:
            inside[group] = inside.get(group, 0) + 1
            continue
        chain = result.side_chain(a, b).tolist()
        patches.setdefault(group, []).extend(itertools.pairwise(chain))
    _warn_inside(inside)
    return patches


def _warn_inside(inside: dict[str, int]) -> None:
    for group, count in inside.items():
        warnings.warn(
            f"group {group!r} has {count} line element{'s' if count > 1 else ''} inside the "
            "domain; a patch lies on the boundary, so they were left out",
            BlockMeshWarning,
            stacklevel=5,
        )
