"""Writing and reading meshes: a registry of formats keyed by name and by file extension.

=========== ===================== =========================================================
name        extensions            what
=========== ===================== =========================================================
vtu         .vtu                  VTK XML (ParaView): polygons + boundary lines, streamed
vtk         .vtk                  legacy VTK 5.1 (older tools), through meshio: the same
xdmf        .xdmf .xmf (+ .h5)    XDMF 3 + HDF5 written with h5py (fastest for big meshes)
msh         .msh                  Gmsh 4.1 ASCII, pentagons split (``split``, default tri5)
mat         .mat                  MATLAB v5 for PolyMesher / VEM codes (1-based)
openfoam    a directory           OpenFOAM case or ``polyMesh``: one extruded layer
npz         .npz                  NumPy archive of every array (lossless)
=========== ===================== =========================================================

The format is taken from ``format=`` when given, else from the path: its extension, or
``openfoam`` for a path named ``polyMesh`` or an existing directory. Every writer is atomic (see
:mod:`blockmesh._system.atomic`): output goes to a temporary name in the target directory and is
committed by one rename, so a failure, Ctrl-C or kill never leaves a truncated file or a mixed
pair and never destroys an old output. Every problem the user can fix, a full disk or a
read-only folder included, raises :class:`~blockmesh.errors.ExportError`.

Adding a format: write one module with ``write_<name>(mesh, path, **options) -> Path``, a
reader and a :class:`Format` record ``FORMAT`` (:meth:`Format.of`), and add its name to
``_MODULES`` below; the extension lookup, the option checks, :func:`write`, :func:`read` and
the tests parametrised over :data:`FORMATS` pick it up.

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> import blockmesh.io
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 2)
>>> out = pathlib.Path(tempfile.mkdtemp())
>>> path = blockmesh.io.write(mesh, out / "sp.msh", split="quad5")
>>> blockmesh.io.read(path).n_cells
36
>>> list(blockmesh.io.FORMATS)
['vtu', 'vtk', 'xdmf', 'msh', 'mat', 'openfoam', 'npz']
"""

from __future__ import annotations

import functools
import importlib
import os
import stat
from pathlib import Path
from typing import TYPE_CHECKING, Any

from blockmesh._system.bounded import check_regular, file_kind, reading
from blockmesh._system.targets import as_path
from blockmesh.checks import whole_number
from blockmesh.errors import BlockMeshError, ExportError
from blockmesh.io.common import Format, check_mesh
from blockmesh.io.split import SPLITS, SplitBoundary, SplitCells, split_boundary, split_cells
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = [
    "FORMATS",
    "SPLITS",
    "Format",
    "SplitBoundary",
    "SplitCells",
    "check_options",
    "format_for_path",
    "read",
    "split_boundary",
    "split_cells",
    "write",
]

#: The format modules, in the order of the table above: each defines ``FORMAT``. They are
#: imported when a format is first needed (a command that writes nothing does not pay for them).
_MODULES = ("vtu", "vtk", "xdmf", "msh", "mat", "openfoam", "npz")

if TYPE_CHECKING:
    #: The formats, by name (the ``format=`` names), in the order of the table above.
    FORMATS: dict[str, Format]


@functools.cache
def _registry() -> tuple[dict[str, Format], dict[str, Format]]:
    """The formats by name and by extension, their modules imported on the first call."""
    modules = [importlib.import_module(f".{name}.format", __name__) for name in _MODULES]
    by_name = {m.FORMAT.name: m.FORMAT for m in modules}
    by_extension = {ext: fmt for fmt in by_name.values() for ext in fmt.extensions}
    return by_name, by_extension


def __getattr__(name: str) -> Any:
    """``FORMATS``, built on first use (PEP 562)."""
    if name == "FORMATS":
        return _registry()[0]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _supported() -> str:
    rows = []
    for fmt in _registry()[0].values():
        where = " ".join(fmt.extensions) if fmt.extensions else "a directory or .../polyMesh"
        rows.append(f"{where} ({fmt.name}: {fmt.description})")
    return "; ".join(rows)


def format_for_path(path: str | os.PathLike[str], format: str | None = None) -> Format:
    """The :class:`Format` for ``path``: ``format`` if given, else from the path.

    ``format`` may be a registry name or an extension (``"vtu"``, ``".vtu"``). Without it, the
    extension decides (case-insensitive); a path named ``polyMesh`` or an existing directory is
    OpenFOAM.

    Raises
    ------
    ExportError
        For an unknown format name or extension, listing the supported ones.

    Examples
    --------
    >>> format_for_path("mesh.VTU").name, format_for_path("case/constant/polyMesh").name
    ('vtu', 'openfoam')
    >>> format_for_path("mesh.stl")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot tell the format of 'mesh.stl' from its extension '.stl'...
    """
    formats, by_extension = _registry()
    names = "|".join(formats)
    if format is not None:
        key = str(format).lower()
        if key in formats:
            return formats[key]
        ext = key if key.startswith(".") else "." + key
        if ext in by_extension:
            return by_extension[ext]
        raise ExportError(
            f"unknown format {format!r}; format= takes {names}. Supported: {_supported()}"
        )
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in by_extension:
        return by_extension[suffix]
    if p.name == "polyMesh" or p.is_dir():
        return formats["openfoam"]
    what = f"its extension {suffix!r}" if suffix else "it (no extension)"
    raise ExportError(
        f"cannot tell the format of {str(path)!r} from {what}. Supported: {_supported()}. "
        f"Or give format= ({names})"
    )


def check_options(
    fmt: Format, *, split: str | None = None, compression: str | None = None, **options: Any
) -> dict[str, Any]:
    """The keyword options for ``fmt``'s writer, with the defaults filled in.

    Every option a format does not take is an error naming the options it does take (see
    :meth:`Format.describe_options`). ``compression="none"`` is accepted by every format.

    Examples
    --------
    >>> check_options(format_for_path("mesh.msh"))
    {'split': 'tri5'}
    >>> check_options(format_for_path("mesh.msh"), split="tri3", compression="lzma")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: msh takes no compression (got compression=...); its options: ...
    """
    kwargs: dict[str, Any] = {}
    accepted = f"its options: {fmt.describe_options()}"
    if fmt.splits:
        chosen = fmt.default_split if split is None else split
        if chosen not in fmt.splits:
            choices = "; ".join(f"{k}: {SPLITS[k]}" for k in fmt.splits)
            raise ExportError(
                f"split {split!r} is not available for {fmt.name}; choose one of "
                f"{', '.join(fmt.splits)} ({choices})"
            )
        kwargs["split"] = chosen
    elif split is not None:
        splitting = ", ".join(f.name for f in _registry()[0].values() if f.splits)
        raise ExportError(
            f"split={split!r} applies to {splitting} only; {fmt.name} keeps the pentagons "
            f"({accepted})"
        )
    if len(fmt.compressions) > 1:
        chosen = fmt.default_compression if compression is None else compression
        if chosen not in fmt.compressions:
            raise ExportError(
                f"compression {compression!r} is not available for {fmt.name}; choose one of "
                f"{', '.join(fmt.compressions)}"
            )
        kwargs["compression"] = chosen
    elif compression not in (None, "none"):
        raise ExportError(
            f"{fmt.name} takes no compression (got compression={compression!r}); {accepted}"
        )
    unknown = sorted(set(options) - set(fmt.options))
    if unknown:
        raise ExportError(
            f"option {', '.join(unknown)} is not known to the {fmt.name} writer ({accepted})"
        )
    kwargs.update(options)
    return kwargs


def write(
    mesh: Mesh | PolygonMesh,
    path: str | os.PathLike[str],
    *,
    format: str | None = None,
    split: str | None = None,
    compression: str | None = None,
    **options: Any,
) -> Path:
    """Write ``mesh`` to ``path``; returns the path written (the ``polyMesh`` for OpenFOAM).

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
        A PolygonMesh (cells of any vertex count, e.g. from local refinement) is written as the
        format holds polygons (see :mod:`blockmesh.io.polygons`) and read back as one.
    path : str or PathLike
        The target file, or for OpenFOAM a case directory or ``.../polyMesh``.
    format : str, optional
        A name of :data:`FORMATS`; default from the path (see :func:`format_for_path`).
    split : {"tri5", "tri3", "quad5"}, optional
        How to split the pentagons, for the formats without pentagons (``msh``: default
        ``tri5``); refused by the other formats.
    compression : str, optional
        ``"none"``, ``"zlib"`` or ``"lzma"`` as the format allows (``Format.compressions``);
        default ``none`` (the fastest) for every format.
    **options
        Format-specific options (``Format.options``), e.g. ``dz=0.1`` for OpenFOAM.

    Raises
    ------
    ExportError
        Unknown format or extension, an option the format does not take, a missing parent
        directory, an operating-system failure (full disk, read-only or forbidden folder), a
        mesh that fails its final check (:meth:`Mesh.check_geometry`: every cell strictly convex
        and counter-clockwise) or one the format cannot hold. The old output, if any, is then
        left as it was.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> from blockmesh.mesh import Mesh
    >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    >>> mesh = Mesh.from_cells(sp, [[0, 1, 2, 3, 4]])
    >>> write(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.mat", dz=1.0)
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: option dz is not known to the mat writer (its options: ...
    """
    fmt = format_for_path(as_path(path), format)
    mesh = check_mesh(mesh)
    kwargs = check_options(fmt, split=split, compression=compression, **options)
    try:
        mesh.check_geometry()  # the final guard: never write a broken mesh
    except BlockMeshError as error:
        raise ExportError(f"cannot write {path}: {error}") from error
    return fmt.writer(mesh, Path(path), **kwargs)


def read(
    path: str | os.PathLike[str], *, format: str | None = None, max_memory: int | None = None
) -> Mesh | PolygonMesh:
    """Read a mesh written by :func:`write` (format from ``format`` or the path).

    A file of polygon cells (a PolygonMesh written, or cells that are not all pentagons) is
    read as a :class:`~blockmesh.mesh.polygons.PolygonMesh`, anything else as a Mesh.

    Files are read within bounds (:mod:`blockmesh._system.bounded`): only regular files are
    opened (an OpenFOAM case is a folder of them), every size a file declares is checked against
    the file and against ``max_memory`` (bytes; default: the memory available now) before
    anything is allocated, and compressed data never expands past what it declares.

    Raises
    ------
    ExportError
        Unknown format, a missing path, a FIFO, device or socket, or a file that does not hold a
        pentagon mesh (or, for the formats of several files, files that do not belong
        together), naming the file, the part of it and the value.
    ResourceError
        When reading would need more memory than ``max_memory``.

    Examples
    --------
    >>> read("/no/such/mesh.vtu")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot read /no/such/mesh.vtu: it does not exist
    """
    p = as_path(path)
    fmt = format_for_path(p, format)
    if max_memory is not None:
        max_memory = whole_number(max_memory, "max_memory", minimum=1)
    try:
        mode = os.stat(p).st_mode
    except FileNotFoundError:
        raise ExportError(f"cannot read {p}: it does not exist") from None
    except OSError as error:
        raise ExportError(f"cannot read {p}: {error.strerror or error}") from None
    if fmt.directory:
        if not stat.S_ISDIR(mode):
            raise ExportError(
                f"cannot read {p}: it is {file_kind(mode)}; an OpenFOAM mesh is a folder (the "
                "case, its constant folder or its polyMesh)"
            )
    else:
        check_regular(p)
    if fmt.reader is None:
        raise ExportError(f"blockmesh cannot read {fmt.name} files")
    with reading(p, max_memory=max_memory):
        return fmt.reader(p)
