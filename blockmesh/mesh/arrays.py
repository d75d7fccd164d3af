"""The stored arrays of a mesh frozen and checked: one home for both kinds of mesh.

A :class:`~blockmesh.mesh.Mesh` and a :class:`~blockmesh.mesh.polygons.PolygonMesh` keep their
arrays read-only and their names, level and curves checked alike: :func:`read_only` freezes an
array (copying it when it is the caller's), :func:`freeze_labels` checks the names, the level,
the name and the curves, :func:`check_label_lengths` the patch and interface entries against
their edges, :func:`check_finite` the points, and :func:`trusted` builds a mesh from arrays
consistent by construction without the constructor's full checks. ``kind`` names the class in
the messages (``"Mesh"``, ``"PolygonMesh"``). :func:`shared_values` gives the fields both kinds
have, which a conversion carries over; :func:`own_blocks` the labels of cells given bare.
"""

from __future__ import annotations

from dataclasses import MISSING, fields
from typing import Any, TypeVar

import numpy as np

from blockmesh.curves.edges import CurvedEdges
from blockmesh.errors import ArgumentError, ArgumentTypeError

__all__ = [
    "NO_EDGES",
    "NO_IDS",
    "SHARED_FIELDS",
    "check_finite",
    "check_label_lengths",
    "check_range",
    "freeze_labels",
    "frozen",
    "own_blocks",
    "read_only",
    "shared_values",
    "trusted",
]

#: The interfaces of a mesh that has none.
NO_EDGES = np.zeros((0, 2), dtype=np.int64)
NO_EDGES.setflags(write=False)
NO_IDS = np.zeros(0, dtype=np.int64)
NO_IDS.setflags(write=False)

T = TypeVar("T")

#: The fields a Mesh and a PolygonMesh both have, with the same meaning (all but the cells).
SHARED_FIELDS = (
    "points",
    "block_id",
    "parent",
    "boundary_edges",
    "boundary_patch",
    "patch_names",
    "region",
    "region_names",
    "level",
    "name",
    "curves",
    "interface_edges",
    "interface_patch",
    "interface_names",
)


def shared_values(mesh: Any) -> dict[str, Any]:
    """The :data:`SHARED_FIELDS` of ``mesh`` by name (what a conversion carries over as it is)."""
    return {name: getattr(mesh, name) for name in SHARED_FIELDS}


def own_blocks(m: int) -> dict[str, Any]:
    """The labels of ``m`` cells given bare: each its own block, no parent, one region ``domain``.

    Examples
    --------
    >>> labels = own_blocks(3)
    >>> labels["block_id"].tolist(), labels["parent"].tolist(), labels["region_names"]
    ([0, 1, 2], [-1, -1, -1], ('domain',))
    """
    return {
        "block_id": np.arange(m, dtype=np.int64),
        "parent": np.full(m, -1, dtype=np.int64),
        "region": np.zeros(m, dtype=np.int64),
        "region_names": ("domain",),
    }


def trusted(cls: type[T], values: dict[str, Any]) -> T:
    """An instance of the dataclass ``cls`` with ``values`` set, defaults elsewhere, unchecked.

    The caller freezes and checks what it needs (the ``_trusted`` constructors of the meshes).
    """
    mesh = object.__new__(cls)
    for f in fields(cls):  # type: ignore[arg-type]
        if f.name in values:
            value = values[f.name]
        elif f.default_factory is not MISSING:
            value = f.default_factory()
        else:
            value = f.default
        object.__setattr__(mesh, f.name, value)
    return mesh


def read_only(array: np.ndarray, original: Any) -> np.ndarray:
    """``array`` contiguous and read-only; copied first when it is (or views) ``original``."""
    array = np.ascontiguousarray(array)
    if array.flags.writeable:
        if array.base is not None or array is original:
            array = array.copy()
        array.setflags(write=False)
    return array


def frozen(values: Any, dtype: Any, what: str, tail: tuple[int, ...] = ()) -> np.ndarray:
    """``values`` as a contiguous read-only array of ``dtype`` and shape ``(n, *tail)``."""
    integer = np.issubdtype(np.dtype(dtype), np.integer)
    if integer and isinstance(values, np.ndarray) and values.dtype.kind == "f":
        raise ArgumentTypeError(f"Mesh {what} must be integers, got {values.dtype}")
    try:
        array = np.ascontiguousarray(values, dtype=dtype)
    except (TypeError, ValueError) as error:
        raise ArgumentTypeError(
            f"Mesh {what} cannot be read as {np.dtype(dtype)}: {error}"
        ) from None
    if array.ndim != 1 + len(tail) or array.shape[1:] != tail:
        shape = "(n" + "".join(f", {t}" for t in tail) + ")"
        raise ArgumentError(f"Mesh {what} must have shape {shape}, got {array.shape}")
    return read_only(array, values)


def check_range(values: np.ndarray, low: int, high: int, what: str, upper: str) -> None:
    """ArgumentError naming the first entry of ``values`` outside ``low..high - 1``."""
    if values.size == 0:
        return
    if int(values.min()) >= low and int(values.max()) < high:
        return
    flat = values.reshape(values.shape[0], -1)
    row = int(np.flatnonzero(np.any((flat < low) | (flat >= high), axis=1))[0])
    shown = flat[row].tolist()
    raise ArgumentError(
        f"{what} {row} is {shown[0] if len(shown) == 1 else shown}, but {upper} "
        f"(valid: {low}..{high - 1})"
    )


def freeze_labels(mesh: Any, kind: str) -> None:
    """Check and set the names (tuples), the level (an int), the name and the curves of ``mesh``.

    Patch, region and interface names must be different strings, no interface may have a patch's
    name; ``kind`` names the class in the messages.
    """
    set_ = object.__setattr__
    for name in ("patch_names", "region_names", "interface_names"):
        names = getattr(mesh, name)
        if isinstance(names, str) or not all(isinstance(n, str) for n in names):
            raise ArgumentTypeError(f"{kind} {name} must be a sequence of strings, got {names!r}")
        if len(set(names)) != len(names):
            raise ArgumentError(f"{kind} {name} must be different names, got {names!r}")
        set_(mesh, name, tuple(names))
    clash = sorted(set(mesh.interface_names) & set(mesh.patch_names))
    if clash:
        raise ArgumentError(
            f"{kind} interface {clash[0]!r} has the name of a boundary patch; an interface is "
            "an internal patch and needs a name of its own"
        )
    if isinstance(mesh.level, bool) or not isinstance(mesh.level, int | np.integer):
        raise ArgumentTypeError(f"{kind} level must be a whole number, got {mesh.level!r}")
    set_(mesh, "level", int(mesh.level))
    if not isinstance(mesh.name, str):
        raise ArgumentTypeError(f"{kind} name must be a string, got {mesh.name!r}")
    if mesh.curves is not None and not isinstance(mesh.curves, CurvedEdges):
        raise ArgumentTypeError(
            f"{kind} curves must be a blockmesh.curves.CurvedEdges or None, got {mesh.curves!r}"
        )


def check_label_lengths(mesh: Any, kind: str, per_cell: tuple[str, ...]) -> None:
    """ArgumentError unless the arrays ``per_cell`` and the patch entries have the right lengths.

    Every array named in ``per_cell`` needs an entry per cell, ``boundary_patch`` one per boundary
    edge, ``interface_patch`` one per interface edge.
    """
    m = mesh.n_cells
    for name in per_cell:
        length = getattr(mesh, name).shape[0]
        if length != m:
            raise ArgumentError(f"{kind} {name} has {length} entries for {m} cells")
    eb = int(mesh.boundary_edges.shape[0])
    if mesh.boundary_patch.shape[0] != eb:
        raise ArgumentError(
            f"{kind} boundary_patch has {mesh.boundary_patch.shape[0]} entries for {eb} "
            "boundary edges"
        )
    ei = int(mesh.interface_edges.shape[0])
    if mesh.interface_patch.shape[0] != ei:
        raise ArgumentError(
            f"{kind} interface_patch has {mesh.interface_patch.shape[0]} entries for {ei} "
            "interface edges"
        )


def check_finite(points: np.ndarray, error: type[Exception] = ArgumentError) -> None:
    """``error`` naming the first point with a coordinate that is not finite."""
    if not np.all(np.isfinite(points)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(points), axis=1))[0])
        raise error(f"point {bad} {points[bad].tolist()} is not finite")
