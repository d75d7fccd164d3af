"""Writing and reading meshes: a registry of formats keyed by name and by file extension.

=========== ===================== =========================================================
name        extensions            what
=========== ===================== =========================================================
vtu         .vtu                  VTK (ParaView) via meshio: polygons + boundary lines
xdmf        .xdmf .xmf (+ .h5)    XDMF 3 + HDF5 written with h5py (fastest for big meshes)
msh         .msh                  Gmsh 4.1 ASCII, pentagons split (``split`` required)
mat         .mat                  MATLAB v5 for PolyMesher / VEM codes (1-based)
openfoam    a directory           OpenFOAM case or ``polyMesh``: one extruded layer
npz         .npz                  NumPy archive of every array (lossless)
=========== ===================== =========================================================

The format is taken from ``format=`` when given, else from the path: its extension, or
``openfoam`` for a path named ``polyMesh`` or an existing directory. Every writer is atomic (see
:mod:`blockmesh.atomic`): output goes to a temporary name in the target directory and is
renamed into place, so a failure or Ctrl-C never leaves a truncated file or destroys an old one.
Every problem the user can fix raises :class:`~blockmesh.errors.ExportError`.

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
>>> path = blockmesh.io.write(mesh, out / "sp.msh", split="tri5")
>>> blockmesh.io.read(path).n_cells
36
>>> sorted(blockmesh.io.FORMATS)
['mat', 'msh', 'npz', 'openfoam', 'vtu', 'xdmf']
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from ..errors import ExportError
from ..mesh import Mesh
from . import mat, msh, npz, openfoam, vtu, xdmf
from ._common import Format, check_mesh
from .split import SPLITS, SplitBoundary, SplitCells, split_boundary, split_cells

__all__ = [
    "FORMATS",
    "SPLITS",
    "Format",
    "SplitBoundary",
    "SplitCells",
    "format_for_path",
    "read",
    "split_boundary",
    "split_cells",
    "write",
]

#: The formats, by name (the ``--format`` names), in the order of the table above.
FORMATS: dict[str, Format] = {m.FORMAT.name: m.FORMAT for m in (vtu, xdmf, msh, mat, openfoam, npz)}

_BY_EXTENSION: dict[str, Format] = {ext: fmt for fmt in FORMATS.values() for ext in fmt.extensions}


def _supported() -> str:
    rows = []
    for fmt in FORMATS.values():
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
    if format is not None:
        key = str(format).lower()
        if key in FORMATS:
            return FORMATS[key]
        ext = key if key.startswith(".") else "." + key
        if ext in _BY_EXTENSION:
            return _BY_EXTENSION[ext]
        raise ExportError(
            f"unknown format {format!r}; choose --format {'|'.join(FORMATS)}. "
            f"Supported: {_supported()}"
        )
    p = Path(path)
    suffix = p.suffix.lower()
    if suffix in _BY_EXTENSION:
        return _BY_EXTENSION[suffix]
    if p.name == "polyMesh" or p.is_dir():
        return FORMATS["openfoam"]
    what = f"its extension {suffix!r}" if suffix else "it (no extension)"
    raise ExportError(
        f"cannot tell the format of {str(path)!r} from {what}. Supported: {_supported()}. "
        f"Or pass format= (--format {'|'.join(FORMATS)})"
    )


def _check_option(
    value: str | None, choices: tuple[str, ...] | dict, what: str, fmt: Format
) -> None:
    if value not in choices:
        raise ExportError(
            f"{what} {value!r} is not available for {fmt.name}; choose one of {', '.join(choices)}"
        )


def write(
    mesh: Mesh,
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
    mesh : Mesh
    path : str or PathLike
        The target file, or for OpenFOAM a case directory or ``.../polyMesh``.
    format : str, optional
        A name of :data:`FORMATS`; default from the path (see :func:`format_for_path`).
    split : {"tri5", "tri3", "quad5"}, optional
        How to split the pentagons; required by ``msh`` and refused by the other formats.
    compression : str, optional
        ``"none"``, ``"zlib"`` or ``"lzma"`` as the format allows (``Format.compressions``);
        default the format's own: ``zlib`` for VTU, ``none`` for the others.
    **options
        Format-specific options (``Format.options``), e.g. ``dz=0.1`` for OpenFOAM.

    Raises
    ------
    ExportError
        Unknown format or extension, missing or unneeded ``split``, an unsupported compression or
        option, a missing parent directory, or a mesh the format cannot hold.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> import numpy as np
    >>> from blockmesh.mesh import Mesh
    >>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
    >>> mesh = Mesh.from_cells(sp, [[0, 1, 2, 3, 4]])
    >>> write(mesh, pathlib.Path(tempfile.mkdtemp()) / "sp.msh")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: Gmsh .msh has no pentagons: ... --split tri5|tri3|quad5 ...
    """
    fmt = format_for_path(path, format)
    mesh = check_mesh(mesh)
    kwargs: dict[str, Any] = {}
    if fmt.needs_split:
        if split is None:
            choices = "; ".join(f"{k}: {v}" for k, v in SPLITS.items())
            raise ExportError(
                "Gmsh .msh has no pentagons: choose how to split them with "
                f"--split tri5|tri3|quad5 ({choices})"
            )
        _check_option(split, SPLITS, "split", fmt)
        kwargs["split"] = split
    elif split is not None:
        raise ExportError(
            f"split={split!r} applies to msh only; {fmt.name} keeps the pentagons (drop --split)"
        )
    if compression is not None and compression not in fmt.compressions:
        _check_option(compression, fmt.compressions, "compression", fmt)
    if len(fmt.compressions) > 1:
        kwargs["compression"] = compression or fmt.default_compression
    unknown = sorted(set(options) - set(fmt.options))
    if unknown:
        accepted = ", ".join(fmt.options) or "none"
        raise ExportError(
            f"option {', '.join(unknown)} is not known to the {fmt.name} writer "
            f"(its options: {accepted})"
        )
    kwargs.update(options)
    return fmt.writer(mesh, Path(path), **kwargs)


def read(path: str | os.PathLike[str], *, format: str | None = None) -> Mesh:
    """Read a mesh written by :func:`write` (format from ``format`` or the path).

    Raises
    ------
    ExportError
        Unknown format, a missing path, or a file that does not hold a pentagon mesh.

    Examples
    --------
    >>> read("/no/such/mesh.vtu")
    Traceback (most recent call last):
    ...
    blockmesh.errors.ExportError: cannot read /no/such/mesh.vtu: it does not exist
    """
    fmt = format_for_path(path, format)
    p = Path(path)
    if not p.exists():
        raise ExportError(f"cannot read {p}: it does not exist")
    if fmt.reader is None:
        raise ExportError(f"blockmesh cannot read {fmt.name} files")
    return fmt.reader(p)
