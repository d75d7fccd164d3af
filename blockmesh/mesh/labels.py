"""Patches, regions and interfaces of a mesh: looked up, assigned, summarised, relabelled.

One home for the bookkeeping a :class:`~blockmesh.mesh.Mesh` and a
:class:`~blockmesh.mesh.polygons.PolygonMesh` share: a patch's edges (:func:`patch_edges`), the
interfaces by name (:func:`interfaces_by_name`) and the two cells of every interface edge
(:func:`edge_cells`), the summary of the interfaces (:func:`interface_summary`), the patches of
named boundary edges (:func:`assign_patches`), and copies of a mesh with its patches, regions,
interfaces, points or name changed (:func:`with_patches` ...).

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(1)
>>> patch_edges(with_patches(mesh, [1] + [0] * 9, ["wall", "inlet"]), "inlet").tolist()
[[0, 5]]
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import fields
from types import MappingProxyType
from typing import Any, TypeVar

import numpy as np

from blockmesh.errors import ArgumentError, ArgumentTypeError, UnknownNameError
from blockmesh.geometry.topology import PolygonCells, edge_keys

__all__ = [
    "assign_patches",
    "copy_mesh",
    "edge_cells",
    "interface_cells",
    "interface_summary",
    "interfaces_by_name",
    "labels_text",
    "patch_edges",
    "patch_index",
    "with_interfaces",
    "with_patches",
    "with_points",
    "with_regions",
]

M = TypeVar("M")


# ------------------------------------------------------------------ lookups
def patch_index(mesh: Any, patch: str) -> int:
    """Index of ``patch`` in ``mesh.patch_names`` (UnknownNameError listing the patches)."""
    if patch not in mesh.patch_names:
        raise UnknownNameError(f"no patch {patch!r}; the patches are {', '.join(mesh.patch_names)}")
    return mesh.patch_names.index(patch)


def patch_edges(mesh: Any, patch: str) -> np.ndarray:
    """Boundary edges (E, 2) of the named patch."""
    return mesh.boundary_edges[mesh.boundary_patch == patch_index(mesh, patch)]


def interfaces_by_name(mesh: Any) -> Mapping[str, np.ndarray]:
    """Interface edges (E, 2) of each interface, by name (read-only view; empty if none)."""
    return MappingProxyType(
        {
            name: mesh.interface_edges[mesh.interface_patch == k]
            for k, name in enumerate(mesh.interface_names)
        }
    )


def interface_cells(mesh: Any, cells: np.ndarray | PolygonCells) -> np.ndarray:
    """The two cells of every interface edge of ``mesh`` (of cells ``cells``), cached."""
    if "interface_cells" not in mesh._cache:
        mesh._cache["interface_cells"] = edge_cells(cells, mesh.interface_edges, mesh.n_points)
    return mesh._cache["interface_cells"]


def interface_summary(mesh: Any) -> dict[str, dict[str, Any]]:
    """Each interface of ``mesh`` (a Mesh or PolygonMesh): its edges and the regions beside it.

    ``{name: {"edges": count, "between": [first side's regions, second side's]}}``, the regions
    of the cells on the left and on the right of its edges (one each on a composite domain).

    Examples
    --------
    >>> import blockmesh
    >>> mesh = blockmesh.load_domain("layered-plate").mesh(1)
    >>> interface_summary(mesh)["core|top"]
    {'edges': 24, 'between': ['core', 'top']}
    """
    out: dict[str, dict[str, Any]] = {}
    if not mesh.interface_names:
        return out
    cells = mesh.interface_cells()
    for k, name in enumerate(mesh.interface_names):
        mine = cells[mesh.interface_patch == k]
        sides = [
            sorted({mesh.region_names[r] for r in mesh.region[mine[:, j]].tolist()}) for j in (0, 1)
        ]
        out[name] = {"edges": int(mine.shape[0]), "between": [", ".join(s) for s in sides]}
    return out


def labels_text(mesh: Any) -> str:
    """The patches, regions and interfaces of ``mesh`` in a line (the end of its repr)."""
    interfaces = f"; interfaces {', '.join(mesh.interface_names)}" if mesh.interface_names else ""
    return (
        f"patches {', '.join(mesh.patch_names) or '-'}; regions "
        f"{', '.join(mesh.region_names) or '-'}{interfaces}"
    )


def edge_cells(cells: np.ndarray | PolygonCells, edges: np.ndarray, n_points: int) -> np.ndarray:
    """The cell on the left and the cell on the right of each edge, (E, 2); located errors.

    ``cells`` are an (M, k) array or the compressed rows of a polygon mesh.
    """
    out = np.empty((edges.shape[0], 2), dtype=np.int64)
    if edges.shape[0] == 0:
        out.setflags(write=False)
        return out
    owner: np.ndarray | None = None  # the cell of every slot (else slot // k)
    if isinstance(cells, PolygonCells):
        keys = cells.nodes * n_points + cells.following()
        owner, width = cells.slot_cell(), 0
    else:
        keys = (cells * n_points + np.roll(cells, -1, axis=1)).ravel()
        width = cells.shape[1]
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]
    for side, (a, b) in enumerate(((edges[:, 0], edges[:, 1]), (edges[:, 1], edges[:, 0]))):
        wanted = a * n_points + b
        at = np.minimum(np.searchsorted(ordered, wanted), ordered.size - 1)
        found = ordered[at] == wanted
        if not np.all(found):
            k = int(np.flatnonzero(~found)[0])
            raise ArgumentError(
                f"interface edge {k} ({int(edges[k, 0])}, {int(edges[k, 1])}) is not an edge "
                "between two cells; an interface runs between cells (boundary edges belong to "
                "patches)"
            )
        slots = order[at]
        out[:, side] = slots // width if owner is None else owner[slots]
    out.setflags(write=False)
    return out


def assign_patches(
    edges: np.ndarray, patches: Mapping[str, Any], n_points: int
) -> tuple[np.ndarray, tuple[str, ...]]:
    """The patch of every boundary edge, and the patch names, from edges named by patch.

    Boundary edges no patch names go to the patch ``boundary`` (appended); ArgumentError for an
    edge that is not on the boundary or in two patches.
    """
    if not isinstance(patches, Mapping):
        raise ArgumentTypeError("patches must map patch names to edge lists")
    keys = edge_keys(edges[:, 0], edges[:, 1], n_points)
    order = np.argsort(keys)
    sorted_keys = keys[order]
    patch = np.full(edges.shape[0], -1, dtype=np.int64)
    names = list(patches)
    for k, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise ArgumentTypeError(f"patch names must be non-empty strings, got {name!r}")
        pairs = np.asarray(patches[name], dtype=np.int64).reshape(-1, 2)
        wanted = edge_keys(pairs[:, 0], pairs[:, 1], n_points)
        at = np.minimum(np.searchsorted(sorted_keys, wanted), keys.size - 1)
        found = sorted_keys[at] == wanted
        if not np.all(found):
            a, b = pairs[int(np.flatnonzero(~found)[0])].tolist()
            raise ArgumentError(f"patch {name!r}: edge ({a}, {b}) is not a boundary edge")
        slots = order[at]
        if np.any(patch[slots] >= 0):
            a, b = edges[slots[np.flatnonzero(patch[slots] >= 0)[0]]].tolist()
            raise ArgumentError(f"patch {name!r}: edge ({a}, {b}) is already in another patch")
        patch[slots] = k
    if np.any(patch < 0):
        if "boundary" in names:
            raise ArgumentError(
                "some boundary edges are in no patch, and the patch for them, 'boundary', is "
                "already used: name every boundary edge or rename that patch"
            )
        patch[patch < 0] = len(names)
        names.append("boundary")
    return patch, tuple(names)


# ------------------------------------------------------------------- copies
def copy_mesh(mesh: M, changes: dict[str, Any]) -> M:
    """``mesh`` with some arrays replaced; the cheap checks run, the caches start empty."""
    values = {f.name: getattr(mesh, f.name) for f in fields(mesh) if f.name != "_cache"}  # type: ignore[arg-type]
    values.update(changes)
    return type(mesh)._trusted(**values)  # type: ignore[attr-defined]


def with_patches(mesh: M, boundary_patch: Any, patch_names: Any) -> M:
    """``mesh`` with its boundary edges put in other patches."""
    return copy_mesh(mesh, {"boundary_patch": boundary_patch, "patch_names": tuple(patch_names)})


def with_regions(mesh: M, region: Any, region_names: Any) -> M:
    """``mesh`` with its cells put in other regions (``region`` indexes the names)."""
    return copy_mesh(mesh, {"region": region, "region_names": tuple(region_names)})


def with_interfaces(mesh: M, interface_edges: Any, interface_patch: Any, interface_names: Any) -> M:
    """``mesh`` with other interfaces (internal patches); each edge is checked."""
    changed = copy_mesh(
        mesh,
        {
            "interface_edges": interface_edges,
            "interface_patch": interface_patch,
            "interface_names": tuple(interface_names),
        },
    )
    changed.interface_cells()  # type: ignore[attr-defined]
    return changed


def with_points(mesh: M, points: Any) -> M:
    """``mesh``'s cells on moved nodes; its cells are checked again (orientation, shape)."""
    moved = copy_mesh(mesh, {"points": points})
    moved._check_cells()  # type: ignore[attr-defined]
    return moved
