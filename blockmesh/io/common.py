"""What the format modules share: the :class:`Format` record, metadata and mesh rebuilding.

Examples
--------
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> pts = np.array([[0, 0], [2, 0], [2.5, 1], [2, 2], [0, 2.0]])
>>> mesh = Mesh.from_cells(pts, [[0, 1, 2, 3, 4]])
>>> decode_metadata(encode_metadata(mesh))["patch_names"]
['boundary']
"""

from __future__ import annotations

import json
import shutil
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh.curves.edges import CurvedEdges
from blockmesh.curves.types import curve_from_fields
from blockmesh.errors import BlockMeshError, BlockMeshWarning, ExportError
from blockmesh.geometry.polygons import MAX_COORDINATE
from blockmesh.geometry.topology import boundary_of_cells
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "CURVE_ARRAYS",
    "METADATA_VERSION",
    "Format",
    "check_mesh",
    "check_points",
    "curve_arrays",
    "curves_from_arrays",
    "decode_metadata",
    "encode_metadata",
    "interface_arrays",
    "line_arrays",
    "mesh_from_arrays",
    "name_lookup",
    "splice_after",
    "split_lines",
]

#: Version of the JSON metadata block (names, level) the formats carry.
METADATA_VERSION = 1


@dataclass(frozen=True)
class Format:
    """One file format of the registry :data:`blockmesh.io.FORMATS`.

    Attributes
    ----------
    name : str
        The registry key and the ``--format`` name.
    description : str
        One line for listings.
    extensions : tuple of str
        File name endings (lower case, with the dot) that select this format.
    writer : callable
        ``writer(mesh, path, **options) -> Path``, the path written; it writes atomically
        (:mod:`blockmesh._system.atomic`).
    reader : callable or None
        ``reader(path) -> Mesh``, or a PolygonMesh for a file of polygon cells.
    splits : tuple of str
        For a format without pentagons, the ways of splitting them it takes (names of
        :data:`blockmesh.io.SPLITS`), the first being the default; empty when the format keeps
        the pentagons.
    compressions : tuple of str
        Accepted ``compression`` values; the first is the default.
    directory : bool
        Whether the output is a directory (OpenFOAM) rather than a file.
    options : tuple of str
        Extra keyword options the writer takes (e.g. ``dz`` for OpenFOAM).
    """

    name: str
    description: str
    extensions: tuple[str, ...]
    writer: Callable[..., Path] = field(repr=False)
    reader: Callable[[Path], Mesh | PolygonMesh] | None = field(default=None, repr=False)
    splits: tuple[str, ...] = ()
    compressions: tuple[str, ...] = ("none",)
    directory: bool = False
    options: tuple[str, ...] = ()

    @classmethod
    def of(
        cls,
        writer: Callable[..., Path],
        reader: Callable[[Path], Mesh | PolygonMesh] | None,
        description: str,
        **fields: Any,
    ) -> Format:
        """The record of the format written by ``writer``, named after it.

        The name is the writer's less ``write_`` (``write_mat`` writes ``mat``) and the
        extension, unless ``fields`` give the ``extensions``, is that name (``.mat``); ``fields``
        are the other attributes.

        Examples
        --------
        >>> def write_demo(mesh, path): ...
        >>> Format.of(write_demo, None, "a demonstration", compressions=("none", "zlib"))
        Format(name='demo', description='a demonstration', extensions=('.demo',), splits=(), \
compressions=('none', 'zlib'), directory=False, options=())
        """
        name = writer.__name__.removeprefix("write_")
        fields.setdefault("extensions", (f".{name}",))
        return cls(name, description, writer=writer, reader=reader, **fields)

    @property
    def can_read(self) -> bool:
        """Whether :func:`blockmesh.io.read` can read this format."""
        return self.reader is not None

    @property
    def needs_split(self) -> bool:
        """Whether the format has no pentagons, so they are split (``splits``)."""
        return bool(self.splits)

    @property
    def default_split(self) -> str | None:
        """The split used when none is asked for (None for formats that keep pentagons)."""
        return self.splits[0] if self.splits else None

    @property
    def default_compression(self) -> str:
        """The compression used when none is asked for."""
        return self.compressions[0]

    def describe_options(self) -> str:
        """The options this format's writer takes, with their values, for messages.

        Examples
        --------
        >>> import blockmesh.io
        >>> blockmesh.io.FORMATS["msh"].describe_options()
        'split=tri5|tri3|quad5 (default tri5)'
        >>> blockmesh.io.FORMATS["npz"].describe_options()
        'compression=none|zlib (default none)'
        """
        parts = []
        if self.splits:
            parts.append(f"split={'|'.join(self.splits)} (default {self.default_split})")
        if len(self.compressions) > 1:
            parts.append(
                f"compression={'|'.join(self.compressions)} (default {self.default_compression})"
            )
        parts += [f"{name}=..." for name in self.options]
        return ", ".join(parts) or "no options"


def check_mesh(mesh: Any) -> Mesh | PolygonMesh:
    """``mesh`` itself if it is a non-empty Mesh or PolygonMesh, else ExportError."""
    if not isinstance(mesh, Mesh | PolygonMesh):
        raise ExportError(
            "write() takes a blockmesh Mesh or PolygonMesh (from blockmesh.refine), got "
            f"{type(mesh).__name__}"
        )
    if mesh.n_cells == 0:
        raise ExportError("the mesh has no cells; there is nothing to write")
    return mesh


def encode_metadata(mesh: Mesh | PolygonMesh, **extra: Any) -> str:
    """The names and level of a mesh (what the arrays cannot carry), plus ``extra``, as JSON.

    A mesh with curved edges also records how many (``curved_edges``): a reader of a format that
    does not keep the curves then says that refining the mesh further gives straight edges.
    """
    curved = {"curved_edges": len(mesh.curves)} if mesh.curves else {}
    return json.dumps(
        {
            "blockmesh_io": METADATA_VERSION,
            "name": mesh.name,
            "level": int(mesh.level),
            "patch_names": list(mesh.patch_names),
            "region_names": list(mesh.region_names),
            **({"interface_names": list(mesh.interface_names)} if mesh.interface_names else {}),
            **curved,
            **extra,
        },
        ensure_ascii=False,
        separators=(",", ":"),
    )


#: The arrays that carry a mesh's curves (:func:`curve_arrays`): the curved edges' nodes
#: (E, 2), their curve (E,), the curve's parameter at each end (E,) twice, and the curves
#: themselves (kind, ends and shape) as the UTF-8 bytes of a JSON list.
CURVE_ARRAYS = ("curve_edges", "curve_index", "curve_start", "curve_stop", "curve_shapes")


def curve_arrays(mesh: Mesh | PolygonMesh) -> dict[str, np.ndarray]:
    """The curves of ``mesh`` as arrays a file can hold (``{}`` when it has none).

    The keys are :data:`CURVE_ARRAYS`; :func:`curves_from_arrays` rebuilds the curves exactly
    (JSON writes every float so that it reads back bit for bit).

    Examples
    --------
    >>> import blockmesh
    >>> arrays = curve_arrays(blockmesh.load_domain("annulus").mesh(1))
    >>> arrays["curve_edges"].shape, arrays["curve_shapes"].dtype
    ((32, 2), dtype('uint8'))
    >>> len(curves_from_arrays(arrays, "annulus"))
    32
    """
    curves = mesh.curves
    if not curves:
        return {}
    shapes = [
        {"kind": c.kind, "start": list(c.start or ()), "end": list(c.end or ()), **c.to_fields()}
        for c in curves.curves
    ]
    text = json.dumps(shapes, separators=(",", ":"))
    return {
        "curve_edges": np.asarray(curves.edges, dtype=np.int64),
        "curve_index": np.asarray(curves.curve, dtype=np.int64),
        "curve_start": np.asarray(curves.start, dtype=np.float64),
        "curve_stop": np.asarray(curves.stop, dtype=np.float64),
        "curve_shapes": np.frombuffer(text.encode("utf-8"), dtype=np.uint8),
    }


def curves_from_arrays(arrays: Mapping[str, Any], where: str) -> CurvedEdges | None:
    """The curves stored by :func:`curve_arrays` in ``arrays`` (None when they are not there).

    Raises :class:`ExportError` naming ``where`` for arrays that are there but broken.
    """
    if not all(key in arrays for key in CURVE_ARRAYS):
        return None
    try:
        shapes = json.loads(bytes(np.asarray(arrays["curve_shapes"], dtype=np.uint8)))
        curves = []
        for k, shape in enumerate(shapes):
            fields = dict(shape)
            kind, start, end = fields.pop("kind"), fields.pop("start"), fields.pop("end")
            curve = curve_from_fields(kind, fields, f"{where}: curve {k}")
            curves.append(curve.with_ends(start, end, f"curve {k}"))
        edges = np.asarray(arrays["curve_edges"]).reshape(-1, 2)
        return CurvedEdges(
            edges=_index_array(edges, edges.size, "curve_edges", where).reshape(-1, 2),
            curve=_index_array(arrays["curve_index"], edges.shape[0], "curve_index", where),
            start=np.asarray(arrays["curve_start"], dtype=np.float64).reshape(-1),
            stop=np.asarray(arrays["curve_stop"], dtype=np.float64).reshape(-1),
            curves=tuple(curves),
        )
    except ExportError:
        raise
    except (BlockMeshError, ValueError, TypeError, KeyError, AttributeError) as error:
        raise ExportError(f"{where}: the curved edges it stores are damaged ({error})") from None


def _warn_dropped_curves(count: int, where: str) -> None:
    warnings.warn(
        f"{where} was written from a mesh with {count:,} curved edges, which this format does "
        "not keep: its nodes are on the curves, but refining it further puts the new nodes on "
        "straight edges (write .npz, .xdmf or .vtu to keep the curves)",
        BlockMeshWarning,
        stacklevel=4,
    )


def decode_metadata(
    text: str | bytes | np.ndarray | None, where: str = "the file"
) -> dict[str, Any]:
    """The dictionary of :func:`encode_metadata` (``{}`` for ``None``); ExportError if broken."""
    if text is None:
        return {}
    if isinstance(text, bytes | bytearray | np.ndarray):
        try:
            text = bytes(text).decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ExportError(f"the blockmesh metadata in {where} is not UTF-8: {exc}") from None
    try:
        meta = json.loads(text)
    except ValueError as exc:
        raise ExportError(f"the blockmesh metadata in {where} is not valid JSON: {exc}") from None
    if not isinstance(meta, dict):
        raise ExportError(f"the blockmesh metadata in {where} is not a JSON object")
    return meta


def name_lookup(kind: str, names: tuple[str, ...] | list[str]) -> dict[str, int]:
    """``{"KIND:NAME": index}`` for each name: the lookup tables shown in ParaView.

    VTK and XDMF files carry the patch and region names this way, as one-value integer arrays of
    field data named ``patch:NAME`` and ``region:NAME`` whose value is the index used by the
    ``patch`` and ``region`` cell arrays (ParaView lists them in its Information panel).

    Examples
    --------
    >>> name_lookup("patch", ["outer wall", "inlet"])
    {'patch:outer wall': 0, 'patch:inlet': 1}
    """
    return {f"{kind}:{name}": k for k, name in enumerate(names)}


def line_arrays(mesh: Mesh | PolygonMesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The line cells of a mesh's file: boundary edges, then interface edges.

    Returns ``(edges (Eb + Ei, 2), patch, interface)``: ``patch`` is the boundary edge's patch
    and -1 on the interface lines, ``interface`` the interface edge's interface and -1 on the
    boundary lines (the ``patch`` and ``interface`` cell data of VTU, VTK and XDMF files).

    Examples
    --------
    >>> import blockmesh
    >>> mesh = blockmesh.load_domain("layered-plate").mesh(0)
    >>> edges, patch, interface = line_arrays(mesh)
    >>> edges.shape[0] == mesh.boundary_edges.shape[0] + mesh.interface_edges.shape[0]
    True
    >>> sorted(set(interface.tolist()))
    [-1, 0, 1]
    """
    eb, ei = mesh.boundary_edges.shape[0], mesh.interface_edges.shape[0]
    edges = np.concatenate([mesh.boundary_edges, mesh.interface_edges])
    patch = np.concatenate([mesh.boundary_patch, np.full(ei, -1, np.int64)])
    interface = np.concatenate([np.full(eb, -1, np.int64), mesh.interface_patch])
    return edges, patch, interface


def splice_after(
    src: Path, dst: Path, marker: bytes, block: bytes, *, head: int, missing: str
) -> None:
    """Copy ``src`` to ``dst`` with ``block`` right after ``marker``, found in its first bytes.

    For the files meshio writes, which have no place for blockmesh's field data: the first
    ``head`` bytes of ``src`` must hold ``marker`` (else ExportError with the message
    ``missing``); the rest is copied as it is, in chunks. O(size of ``src``); memory O(``head``).

    Examples
    --------
    >>> import pathlib, tempfile
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "a").write_bytes(b"<Grid><Piece/></Grid>")
    >>> splice_after(folder / "a", folder / "b", b"<Grid>", b"<Data/>", head=64, missing="no grid")
    >>> (folder / "b").read_bytes()
    b'<Grid><Data/><Piece/></Grid>'
    """
    with open(src, "rb") as fin, open(dst, "wb") as fout:
        start = fin.read(head)
        at = start.find(marker)
        if at < 0:
            raise ExportError(missing)
        at += len(marker)
        fout.write(start[:at] + block + start[at:])
        shutil.copyfileobj(fin, fout, 1 << 22)


def split_lines(
    edges: np.ndarray | None, patch: np.ndarray | None, interface: np.ndarray | None
) -> dict[str, Any]:
    """The arguments of :func:`mesh_from_arrays` from a file's line cells and their data.

    Lines whose ``interface`` is >= 0 are interface edges; the others boundary edges (all of
    them when the file has no ``interface`` data, as files written before interfaces).
    """
    if edges is None or interface is None:
        return {"boundary_edges": edges, "boundary_patch": patch}
    inner = np.asarray(interface).reshape(-1) >= 0
    edges = np.asarray(edges).reshape(-1, 2)
    return {
        "boundary_edges": edges[~inner],
        "boundary_patch": None if patch is None else np.asarray(patch).reshape(-1)[~inner],
        "interface_edges": edges[inner],
        "interface_patch": np.asarray(interface).reshape(-1)[inner],
    }


def _index_array(values: Any, n: int, what: str, where: str) -> np.ndarray:
    arr = np.asarray(values).reshape(-1)
    if arr.shape[0] != n:
        raise ExportError(f"{where}: {what} has {arr.shape[0]} entries, expected {n}")
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr)):
        raise ExportError(f"{where}: {what} holds non-finite values")
    if arr.dtype.kind not in "iuf":
        raise ExportError(f"{where}: {what} holds {arr.dtype} values, not integers")
    return arr.astype(np.int64, copy=False)


def _names(value: Any, what: str, where: str) -> tuple[str, ...] | None:
    """Names read from a file as a tuple of str (None stays None); ExportError otherwise."""
    if value is None:
        return None
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if not isinstance(value, list | tuple) or not all(isinstance(v, str) for v in value):
        raise ExportError(f"{where}: the {what} are not a list of strings")
    return tuple(value)


def check_points(points: np.ndarray, where: str) -> None:
    """ExportError naming ``where`` and the first point not finite or beyond MAX_COORDINATE."""
    fine = np.all(np.abs(points) <= MAX_COORDINATE, axis=1)  # NaN fails too
    if not np.all(fine):
        bad = int(np.flatnonzero(~fine)[0])
        raise ExportError(
            f"{where}: point {bad} has the coordinates {points[bad].tolist()}: not finite numbers "
            f"of at most {MAX_COORDINATE:g} in magnitude"
        )


def _level(value: Any, cells: int, where: str, *, polygons: bool = False) -> int:
    """A stored level, checked: a whole number a mesh of ``cells`` cells can have.

    A uniformly refined mesh of level L has at least ``6**L`` cells; a polygon mesh
    (``polygons``) at least ``L`` (each round of local refinement splits a cell into 3 or more).
    """
    if isinstance(value, np.ndarray) and value.size == 1:
        value = value.reshape(-1)[0].item()
    if isinstance(value, float) and value.is_integer() and abs(value) < 2**62:
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ExportError(f"{where}: the stored level {value!r:.40} is not a whole number")
    level = int(value)
    most = cells if polygons else 0
    while not polygons and 6 ** (most + 1) <= cells:
        most += 1
    if not 0 <= level <= most:
        shown = str(level) if len(str(level)) <= 20 else f"of {len(str(abs(level)))} digits"
        rule = "at least L cells" if polygons else "at least 6^L cells"
        raise ExportError(
            f"{where}: the stored level {shown} is impossible for {cells:,} cells (a mesh of level "
            f"L has {rule}: at most level {most} here)"
        )
    return level


def _read_only(arr: np.ndarray) -> np.ndarray:
    """``arr`` made read-only: the Mesh takes it over without copying.

    Copied when it is a view of a larger buffer (which it would otherwise keep alive).
    """
    base = arr.base
    if not arr.flags.c_contiguous or (base is not None and getattr(base, "nbytes", 0) > arr.nbytes):
        arr = np.array(arr, order="C")
    arr.setflags(write=False)
    return arr


def mesh_from_arrays(
    points: np.ndarray,
    cells: np.ndarray,
    *,
    where: str,
    block_id: np.ndarray | None = None,
    parent: np.ndarray | None = None,
    region: np.ndarray | None = None,
    region_names: tuple[str, ...] | list[str] | None = None,
    boundary_edges: np.ndarray | None = None,
    boundary_patch: np.ndarray | None = None,
    patch_names: tuple[str, ...] | list[str] | None = None,
    interface_edges: np.ndarray | None = None,
    interface_patch: np.ndarray | None = None,
    interface_names: tuple[str, ...] | list[str] | None = None,
    level: Any = 0,
    name: str = "",
    curves: CurvedEdges | None = None,
    dropped_curves: int = 0,
) -> Mesh:
    """A :class:`Mesh` from arrays read from a file, with defaults for what the file lacks.

    Missing block ids become 0 for every cell; a missing parent -1; a missing region the single
    region ``"domain"``; missing boundary edges are found from the cells and put in one patch
    ``"boundary"``; missing interfaces are none. Shapes, index ranges and the mesh itself
    (orientation, boundary, every interface edge between two cells) are checked;
    ``where`` names the file in the :class:`ExportError` raised when they are wrong. The arrays
    are taken over (made read-only), not copied. ``curves`` are the mesh's curved edges (from
    :func:`curves_from_arrays`); without them, ``dropped_curves`` (the count the file's metadata
    records) > 0 warns (:class:`BlockMeshWarning`) that refining the mesh gives straight edges.
    ``level`` must be a whole number a mesh of these cells can have: ``6**level <= M`` (a block
    mesh refined ``level`` times has ``6**level`` times its cells); names must be strings;
    coordinates finite.
    """
    region_names = _names(region_names, "region names", where)
    patch_names = _names(patch_names, "patch names", where)
    points = np.asarray(points)
    if points.ndim != 2 or points.shape[1] < 2 or points.dtype.kind not in "iuf":
        raise ExportError(f"{where}: the points have shape {points.shape}, expected (N, 2)")
    points = np.ascontiguousarray(points[:, :2], dtype=np.float64)
    cells = np.asarray(cells)
    if cells.ndim != 2 or cells.shape[1] != 5:
        raise ExportError(
            f"{where}: the cells have shape {cells.shape}; blockmesh reads pentagons only (M, 5)"
        )
    cells = _index_array(cells, cells.size, "cells", where).reshape(-1, 5)
    n, m = points.shape[0], cells.shape[0]
    if cells.size and (cells.min() < 0 or cells.max() >= n):
        raise ExportError(
            f"{where}: cell node ids run from {cells.min()} to {cells.max()}, "
            f"but there are {n} points"
        )
    block_id = (
        np.zeros(m, np.int64) if block_id is None else _index_array(block_id, m, "block_id", where)
    )
    parent = (
        np.full(m, -1, np.int64) if parent is None else _index_array(parent, m, "parent", where)
    )
    if region is None:
        region = np.zeros(m, dtype=np.int64)
        region_names = region_names or ("domain",)
    region = _index_array(region, m, "region", where)
    region_names = _names_of(region, region_names, "region", where)
    if boundary_edges is None:
        boundary_edges = boundary_of_cells(cells, n)
        boundary_patch = np.zeros(boundary_edges.shape[0], dtype=np.int64)
        patch_names = patch_names or ("boundary",)
    boundary_edges = np.asarray(boundary_edges).reshape(-1, 2)
    eb = boundary_edges.shape[0]
    boundary_edges = _index_array(boundary_edges, 2 * eb, "boundary edges", where).reshape(-1, 2)
    if boundary_patch is None:
        boundary_patch = np.zeros(eb, dtype=np.int64)
    boundary_patch = _index_array(boundary_patch, eb, "boundary_patch", where)
    if patch_names is None:
        patch_names = tuple(f"patch_{k}" for k in range(int(boundary_patch.max(initial=-1)) + 1))
    if boundary_patch.size and (
        boundary_patch.min() < 0 or boundary_patch.max() >= len(patch_names)
    ):
        raise ExportError(
            f"{where}: patch indices run from {boundary_patch.min()} to {boundary_patch.max()}, "
            f"but there are {len(patch_names)} patch names"
        )
    if boundary_edges.size and (boundary_edges.min() < 0 or boundary_edges.max() >= n):
        raise ExportError(f"{where}: boundary edge node ids are out of range (0..{n - 1})")
    level = _level(level, m, where)
    check_points(points, where)
    interfaces = interface_arrays(interface_edges, interface_patch, interface_names, n, where)
    try:
        mesh = Mesh(
            points=_read_only(points),
            cells=_read_only(cells),
            block_id=_read_only(block_id),
            parent=_read_only(parent),
            boundary_edges=_read_only(boundary_edges),
            boundary_patch=_read_only(boundary_patch),
            patch_names=tuple(str(p) for p in patch_names),
            region=_read_only(region),
            region_names=tuple(str(r) for r in region_names),
            level=int(level),
            name=str(name),
            **interfaces,
            curves=curves,
        )
    except (BlockMeshError, TypeError, ValueError) as error:
        raise ExportError(f"{where} does not hold a valid mesh: {error}") from None
    if curves is None and int(dropped_curves or 0) > 0:
        _warn_dropped_curves(int(dropped_curves), where)
    return mesh


def interface_arrays(
    edges: np.ndarray | None,
    patch: np.ndarray | None,
    names: tuple[str, ...] | list[str] | None,
    n: int,
    where: str,
) -> dict[str, Any]:
    """The interface arguments of a Mesh or PolygonMesh, checked (none when the file has none).

    ``names`` default to ``interface_0``, ``interface_1``, ...; an ExportError naming ``where``
    for indices or node ids out of range.
    """
    if edges is None or np.size(edges) == 0:
        return {}
    edges = np.asarray(edges).reshape(-1, 2)
    ei = edges.shape[0]
    edges = _index_array(edges, 2 * ei, "interface edges", where).reshape(-1, 2)
    patch = np.zeros(ei, np.int64) if patch is None else _index_array(patch, ei, "interface", where)
    names = _names_of(patch, _names(names, "interface names", where), "interface", where)
    if edges.min() < 0 or edges.max() >= n:
        raise ExportError(f"{where}: interface edge node ids are out of range (0..{n - 1})")
    return {
        "interface_edges": _read_only(edges),
        "interface_patch": _read_only(patch),
        "interface_names": tuple(str(k) for k in names),
    }


def _names_of(index: np.ndarray, names: Any, kind: str, where: str) -> Any:
    """``names`` (``KIND_0``, ``KIND_1``, ... when None), checked to cover every index."""
    if names is None:
        names = tuple(f"{kind}_{k}" for k in range(int(index.max(initial=-1)) + 1))
    if index.size and (index.min() < 0 or index.max() >= len(names)):
        raise ExportError(
            f"{where}: {kind} indices run from {index.min()} to {index.max()}, "
            f"but there are {len(names)} {kind} names"
        )
    return names
