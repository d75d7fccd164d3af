"""OpenFOAM ``polyMesh``: the 2-D mesh extruded one layer into pentagonal prisms (ASCII).

Layout. Given a case directory ``CASE`` the mesh goes to ``CASE/constant/polyMesh`` and, only
where they are missing, minimal ``system/controlDict``, ``fvSchemes`` and ``fvSolution`` are
added so that ``checkMesh`` (and solvers) run in the case. Given a path ending in ``polyMesh``
only that directory is written. The ``polyMesh`` directory is replaced as a whole, atomically.

Mesh. Nodes ``0..N-1`` are the mesh's points at ``z = 0`` and ``N..2N-1`` the same at ``z = dz``
(default: the mean edge length). Cell ``k`` is the prism over pentagon ``k``. Faces, as OpenFOAM
requires: the internal faces first, in upper-triangular order (owner < neighbour, sorted by owner
then neighbour), then one patch per mesh patch (type ``wall`` if its name contains "wall", else
``patch``; faces sorted by owner), then the patch ``frontAndBack`` of type ``empty`` (the ``z = 0``
faces, then the ``z = dz`` ones). Every face's normal points out of its owner: a side face over
the cell edge ``a -> b`` (counter-clockwise in the owner) is ``(a, b, b+N, a+N)``; the back face of
cell ``(v0..v4)`` is ``(v4..v0)``. The regions are written as ``cellZones``. Patch and zone names
are made valid OpenFOAM words (other characters become ``_``).

Everything is built with whole-array operations and printed with :mod:`blockmesh.io._ascii`,
so 1.7 M cells take seconds. :func:`read_openfoam` rebuilds the pentagons from the ``z = 0``
faces of the ``empty`` patch, the boundary patches from the side faces, the regions from the
cell zones (block ids and the refinement parent are not kept by this format).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> from blockmesh.refinement import refine
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> mesh = refine(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), 1)
>>> case = pathlib.Path(tempfile.mkdtemp()) / "case"
>>> poly = write_openfoam(mesh, case)
>>> sorted(p.name for p in poly.iterdir())
['boundary', 'cellZones', 'faces', 'neighbour', 'owner', 'points']
>>> sorted(p.name for p in (case / "system").iterdir())
['controlDict', 'fvSchemes', 'fvSolution']
>>> back = read_openfoam(case)
>>> bool(np.array_equal(back.cells, mesh.cells)), back.patch_names
(True, ('boundary',))
"""

from __future__ import annotations

import contextlib
import gzip
import os
import re
import shutil
import warnings
from pathlib import Path
from typing import BinaryIO

import numpy as np

from ..atomic import atomic_dir, atomic_file, check_target
from ..errors import ExportError
from ..geometry import signed_area
from ..mesh import Mesh
from ..topology import boundary_slots, cell_neighbours
from ._ascii import float_bytes, write_rows
from ._common import Format, mesh_from_arrays

__all__ = [
    "FORMAT",
    "find_checkmesh",
    "foam_word",
    "polymesh_dir",
    "read_openfoam",
    "write_openfoam",
]

EMPTY_PATCH = "frontAndBack"

_BANNER = b"""/*--------------------------------*- C++ -*----------------------------------*\\
  =========                 |
  \\\\      /  F ield         | OpenFOAM: The Open Source CFD Toolbox
   \\\\    /   O peration     |
    \\\\  /    A nd           | Written by blockmesh (blockmesh.io.openfoam)
     \\\\/     M anipulation  |
\\*---------------------------------------------------------------------------*/
"""
_RULE = b"// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //\n\n"
_END = b"\n// ************************************************************************* //\n"


def foam_word(name: str) -> str:
    """``name`` made a valid OpenFOAM word (letters, digits and ``_ - . :`` only).

    Examples
    --------
    >>> foam_word("outer wall"), foam_word("2nd"), foam_word("inlet")
    ('outer_wall', 'p_2nd', 'inlet')
    """
    word = re.sub(r"[^A-Za-z0-9_.:-]", "_", name)
    if not word or not (word[0].isalpha() or word[0] == "_"):
        word = "p_" + word
    return word


def _unique_words(names: tuple[str, ...], taken: set[str]) -> list[str]:
    out: list[str] = []
    for name in names:
        base = candidate = foam_word(name)
        k = 1
        while candidate in out or candidate in taken:
            k += 1
            candidate = f"{base}_{k}"
        out.append(candidate)
    return out


def _header(cls: str, obj: str, location: str = "constant/polyMesh", note: str = "") -> bytes:
    note_line = f'    note        "{note}";\n' if note else ""
    return (
        _BANNER
        + (
            "FoamFile\n{\n    version     2.0;\n    format      ascii;\n"
            f"    class       {cls};\n{note_line}"
            f'    location    "{location}";\n    object      {obj};\n}}\n'
        ).encode()
        + _RULE
    )


def polymesh_dir(path: Path) -> tuple[Path, Path | None]:
    """Where the ``polyMesh`` goes for ``path``, and the case directory (None if not a case).

    Examples
    --------
    >>> polymesh_dir(Path("/runs/cavity"))
    (PosixPath('/runs/cavity/constant/polyMesh'), PosixPath('/runs/cavity'))
    >>> polymesh_dir(Path("/runs/cavity/constant/polyMesh"))[1] is None
    True
    """
    path = Path(path).absolute()
    if path.name == "polyMesh":
        return path, None
    return path / "constant" / "polyMesh", path


# ----------------------------------------------------------------------------------- writing
def _faces(mesh: Mesh) -> dict[str, np.ndarray]:
    """Quad side faces (internal, then per patch), owners, neighbours and patch sizes."""
    cells, n, m = mesh.cells, mesh.n_points, mesh.n_cells
    nb = cell_neighbours(cells, n).ravel()
    a = cells.ravel()
    b = np.roll(cells, -1, axis=1).ravel()
    slot = np.arange(5 * m)
    internal = (nb >= 0) & (slot < nb)
    own, nei = slot[internal] // 5, nb[internal] // 5
    order = np.argsort(own * m + nei, kind="stable")  # by owner, then neighbour
    own, nei = own[order], nei[order]
    side_a, side_b = a[internal][order], b[internal][order]

    b_slot = boundary_slots(cells, nb.reshape(m, 5), mesh.boundary_edges, n)
    b_order = np.argsort(mesh.boundary_patch * m + b_slot // 5, kind="stable")
    b_slot = b_slot[b_order]
    patch_sizes = np.bincount(mesh.boundary_patch, minlength=len(mesh.patch_names))
    all_a = np.concatenate([side_a, a[b_slot]])
    all_b = np.concatenate([side_b, b[b_slot]])
    return {
        "quads": np.stack([all_a, all_b, all_b + n, all_a + n], axis=1),
        "owner": np.concatenate([own, b_slot // 5]),
        "neighbour": nei,
        "patch_sizes": patch_sizes,
    }


def _mean_edge_length(mesh: Mesh, quads: np.ndarray) -> float:
    """Mean length of the mesh's edges: the side faces hold each edge once."""
    d = mesh.points[quads[:, 1]] - mesh.points[quads[:, 0]]
    return float(np.mean(np.hypot(d[:, 0], d[:, 1])))


def _write_list(f: BinaryIO, count: int, parts: list, *, empty: bool = False) -> None:
    f.write(f"{count}\n(\n".encode())
    if count and not empty:
        write_rows(f, parts)
    f.write(b")\n")


def _write_polymesh(mesh: Mesh, poly: Path, faces: dict[str, np.ndarray], dz: float) -> None:
    n, m = mesh.n_points, mesh.n_cells
    quads, owner, neighbour = faces["quads"], faces["owner"], faces["neighbour"]
    n_quads = quads.shape[0]
    n_faces = n_quads + 2 * m
    n_internal = neighbour.size
    note = f"nPoints:{2 * n}  nCells:{m}  nFaces:{n_faces}  nInternalFaces:{n_internal}"

    fx, fy = float_bytes(mesh.points[:, 0]), float_bytes(mesh.points[:, 1])
    with open(poly / "points", "wb") as f:
        f.write(_header("vectorField", "points"))
        f.write(f"{2 * n}\n(\n".encode())
        for z in (b"0", repr(float(dz)).encode()):
            write_rows(f, [b"(", fx, b" ", fy, b" " + z + b")\n"])
        f.write(b")\n" + _END)
    del fx, fy

    with open(poly / "faces", "wb") as f:
        f.write(_header("faceList", "faces"))
        f.write(f"{n_faces}\n(\n".encode())
        write_rows(f, [b"4(", quads, b")\n"])
        write_rows(f, [b"5(", mesh.cells[:, ::-1], b")\n"])
        write_rows(f, [b"5(", mesh.cells + n, b")\n"])
        f.write(b")\n" + _END)

    cell_ids = np.arange(m)
    with open(poly / "owner", "wb") as f:
        f.write(_header("labelList", "owner", note=note))
        f.write(f"{n_faces}\n(\n".encode())
        write_rows(f, [owner, b"\n"])
        write_rows(f, [cell_ids, b"\n"])
        write_rows(f, [cell_ids, b"\n"])
        f.write(b")\n" + _END)

    with open(poly / "neighbour", "wb") as f:
        f.write(_header("labelList", "neighbour", note=note))
        _write_list(f, n_internal, [neighbour, b"\n"])
        f.write(_END)

    names = _unique_words(mesh.patch_names, {EMPTY_PATCH})
    entries, start = [], n_internal
    for name, size in zip(names, faces["patch_sizes"].tolist(), strict=True):
        kind = "wall" if "wall" in name.lower() else "patch"
        groups = "\n        inGroups        List<word> 1(wall);" if kind == "wall" else ""
        entries.append(
            f"    {name}\n    {{\n        type            {kind};{groups}\n"
            f"        nFaces          {size};\n        startFace       {start};\n    }}\n"
        )
        start += size
    entries.append(
        f"    {EMPTY_PATCH}\n    {{\n        type            empty;\n"
        f"        inGroups        List<word> 1(empty);\n"
        f"        nFaces          {2 * m};\n        startFace       {start};\n    }}\n"
    )
    with open(poly / "boundary", "wb") as f:
        f.write(_header("polyBoundaryMesh", "boundary"))
        f.write(f"{len(entries)}\n(\n{''.join(entries)})\n".encode() + _END)

    zones = _unique_words(mesh.region_names, set())
    with open(poly / "cellZones", "wb") as f:
        f.write(_header("regIOobject", "cellZones"))
        f.write(f"{len(zones)}\n(\n".encode())
        order = np.argsort(mesh.region, kind="stable")
        counts = np.bincount(mesh.region, minlength=len(zones))
        offset = 0
        for name, count in zip(zones, counts.tolist(), strict=True):
            f.write(f"{name}\n{{\n    type cellZone;\ncellLabels      List<label> ".encode())
            _write_list(f, count, [order[offset : offset + count], b"\n"])
            f.write(b";\n}\n")
            offset += count
        f.write(b")\n" + _END)


_SYSTEM = {
    "controlDict": """startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         1;
deltaT          1;
writeControl    timeStep;
writeInterval   1;
purgeWrite      0;
writeFormat     ascii;
writePrecision  17;
writeCompression off;
timeFormat      general;
timePrecision   6;
runTimeModifiable false;
""",
    "fvSchemes": """ddtSchemes      { default steadyState; }
gradSchemes     { default Gauss linear; }
divSchemes      { default none; }
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes   { default corrected; }
""",
    "fvSolution": """solvers
{
}

SIMPLE
{
    nNonOrthogonalCorrectors 0;
}
""",
}


def _write_system(case: Path) -> None:
    system = case / "system"
    system.mkdir(exist_ok=True)
    for name, body in _SYSTEM.items():
        target = system / name
        if target.exists():
            continue
        with atomic_file(target) as tmp:
            tmp.write_bytes(_header("dictionary", name, location="system") + body.encode() + _END)


def write_openfoam(mesh: Mesh, path: Path, *, dz: float | None = None) -> Path:
    """Write ``mesh`` as an OpenFOAM case (or bare ``polyMesh``); returns the ``polyMesh`` path.

    Parameters
    ----------
    mesh : Mesh
    path : Path
        A case directory (created if its parent exists), or a path ending in ``polyMesh``.
    dz : float, optional
        Thickness of the extruded layer (> 0); default the mean edge length of the mesh.

    O(M log M); about a second per million cells plus disk time.
    """
    faces = _faces(mesh)
    if dz is None:
        dz = _mean_edge_length(mesh, faces["quads"])
    try:
        dz = float(dz)
    except (TypeError, ValueError):
        raise ExportError(f"dz must be a positive number, got {dz!r}") from None
    if not np.isfinite(dz) or dz <= 0:
        raise ExportError(f"dz must be a positive number, got {dz!r}")
    poly, case = polymesh_dir(path)
    missing: list[Path] = []
    if case is not None:
        if not case.exists():
            check_target(case, directory=True)
            missing.append(case)
        elif not case.is_dir():
            raise ExportError(f"cannot write the OpenFOAM case {case}: a file of that name exists")
        if not poly.parent.exists():
            missing.append(poly.parent)
    elif not poly.parent.exists():
        if poly.parent.name == "constant" and poly.parent.parent.is_dir():
            missing.append(poly.parent)
        else:
            check_target(poly, directory=True)  # names the missing directory
    created: list[Path] = []
    for directory in missing:
        directory.mkdir()
        created.append(directory)
    try:
        with atomic_dir(poly) as tmp:
            _write_polymesh(mesh, tmp, faces, dz)
        if case is not None:
            _write_system(case)
    except BaseException:
        for directory in reversed(created):
            with contextlib.suppress(OSError):
                directory.rmdir()
        raise
    return poly


# ----------------------------------------------------------------------------------- reading
def _open_foam(poly: Path, name: str) -> bytes:
    plain, packed = poly / name, poly / f"{name}.gz"
    if plain.exists():
        return plain.read_bytes()
    if packed.exists():
        with gzip.open(packed, "rb") as f:
            return f.read()
    raise ExportError(f"{poly} has no {name} file; is it an OpenFOAM polyMesh directory?")


def _split_header(data: bytes, where: str) -> tuple[dict[str, str], bytes]:
    """The FoamFile header entries and the bytes after the header."""
    at = data.find(b"FoamFile")
    if at < 0:
        raise ExportError(f"{where} has no FoamFile header")
    open_, close = data.find(b"{", at), data.find(b"}", at)
    header = {}
    for entry in data[open_ + 1 : close].decode(errors="replace").split(";"):
        parts = entry.split(None, 1)
        if len(parts) == 2:
            header[parts[0]] = parts[1].strip().strip('"')
    if header.get("format", "ascii") != "ascii":
        raise ExportError(
            f"{where} is in binary format; blockmesh reads ASCII polyMesh files "
            "(run foamFormatConvert with writeFormat ascii)"
        )
    return header, data[close + 1 :]


def _list(body: bytes, where: str) -> tuple[int, bytes]:
    """The count and the inner bytes of the first top-level list ``N ( ... )`` of ``body``."""
    body = re.sub(rb"//[^\n]*", b"", body[: 1 << 12]) + body[1 << 12 :]
    match = re.search(rb"(\d+)\s*([({])", body)
    if match is None:
        raise ExportError(f"{where}: no list found")
    count = int(match.group(1))
    if match.group(2) == b"{":  # uniform list N{value}
        end = body.find(b"}", match.end())
        return count, b" ".join([body[match.end() : end]] * count)
    end = body.rfind(b")")
    return count, body[match.end() : end]


def _numbers(text: bytes, dtype: type, where: str) -> np.ndarray:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        try:
            return np.fromstring(text, dtype=dtype, sep=" ")
        except (DeprecationWarning, ValueError) as exc:
            raise ExportError(f"{where}: malformed numbers ({exc})") from None


def _read_faces(poly: Path) -> tuple[np.ndarray, np.ndarray]:
    """Face node ids (flat) and offsets (F + 1)."""
    where = str(poly / "faces")
    header, body = _split_header(_open_foam(poly, "faces"), where)
    if header.get("class") == "faceCompactList":
        _, inner = _list(body, where)
        offsets = _numbers(inner, np.int64, where)
        rest = body[body.find(inner) + len(inner) + 1 :]
        _, inner = _list(rest, where)
        return _numbers(inner, np.int64, where), offsets
    count, inner = _list(body, where)
    # "k(a b c)" -> "k.5 a b c ": the counts are the only non-integers
    vals = _numbers(inner.replace(b"(", b".5 ").replace(b")", b" "), np.float64, where)
    is_count = vals != np.floor(vals)
    sizes = vals[is_count].astype(np.int64)
    ids = vals[~is_count].astype(np.int64)
    if sizes.size != count or sizes.sum() != ids.size:
        raise ExportError(f"{where}: expected {count} faces, could not parse them")
    return ids, np.concatenate([[0], np.cumsum(sizes)])


def _tokens(text: str) -> list[str]:
    text = re.sub(r"//[^\n]*|/\*.*?\*/", " ", text, flags=re.S)
    return re.findall(r'"[^"]*"|[{}();]|[^\s{}();]+', text)


def _read_boundary(poly: Path) -> list[dict[str, str]]:
    where = str(poly / "boundary")
    _, body = _split_header(_open_foam(poly, "boundary"), where)
    toks = _tokens(body.decode(errors="replace"))
    try:
        start = toks.index("(") + 1
    except ValueError:
        raise ExportError(f"{where}: no patch list") from None
    patches, k = [], start
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
    return patches


def _read_zones(poly: Path, n_cells: int) -> tuple[np.ndarray, list[str]] | None:
    plain = poly / "cellZones"
    if not (plain.exists() or (poly / "cellZones.gz").exists()):
        return None
    where = str(plain)
    _, body = _split_header(_open_foam(poly, "cellZones"), where)
    region = np.full(n_cells, -1, dtype=np.int64)
    names: list[str] = []
    for match in re.finditer(rb"(\S+)\s*\{[^{}]*?cellLabels\s+List<label>\s+(\d+)\s*([({])", body):
        count = int(match.group(2))
        if match.group(3) == b"{":
            end = body.find(b"}", match.end())
            labels = np.full(count, int(body[match.end() : end]))
        else:
            end = body.find(b")", match.end())
            labels = _numbers(body[match.end() : end], np.int64, where)
        region[labels] = len(names)
        names.append(match.group(1).decode())
    if np.any(region < 0):
        region[region < 0] = len(names)
        names.append("unzoned")
    return region, names


def read_openfoam(path: Path) -> Mesh:
    """Read a one-layer extruded polyMesh (as :func:`write_openfoam` writes) back to pentagons.

    ``path`` is the case, its ``constant`` directory or the ``polyMesh`` directory. ASCII files
    (optionally gzipped) only.
    """
    path = Path(path).absolute()
    candidates = [path / "constant" / "polyMesh", path / "polyMesh", path]
    poly = next(
        (c for c in candidates if (c / "boundary").exists() or (c / "boundary.gz").exists()), None
    )
    if poly is None:
        raise ExportError(
            f"{path} holds no OpenFOAM polyMesh (looked for constant/polyMesh/boundary)"
        )
    where = str(poly)
    _, body = _split_header(_open_foam(poly, "points"), str(poly / "points"))
    _, inner = _list(body, str(poly / "points"))
    points = _numbers(inner.replace(b"(", b" ").replace(b")", b" "), np.float64, where).reshape(
        -1, 3
    )
    ids, offsets = _read_faces(poly)
    _, body = _split_header(_open_foam(poly, "owner"), str(poly / "owner"))
    owner = _numbers(_list(body, str(poly / "owner"))[1], np.int64, where)
    patches = _read_boundary(poly)
    sizes = np.diff(offsets)
    zmin = points[:, 2].min(initial=0.0)
    tol = 1e-9 * max(1.0, float(np.ptp(points[:, 2])) if points.size else 1.0)
    on_bottom = np.abs(points[:, 2] - zmin) <= tol

    empty = [p for p in patches if p.get("type") == "empty"]
    if not empty:
        raise ExportError(f"{where} has no patch of type empty: not a one-layer 2-D mesh")
    fronts = np.concatenate(
        [np.arange(int(p["startFace"]), int(p["startFace"]) + int(p["nFaces"])) for p in empty]
    )
    if np.any(sizes[fronts] != 5):
        raise ExportError(f"{where}: the empty patch has faces that are not pentagons")
    rows = ids[offsets[fronts][:, None] + np.arange(5)]
    bottom = np.all(on_bottom[rows], axis=1)
    rows, cell_of = rows[bottom], owner[fronts][bottom]
    n_cells = int(owner.max(initial=-1)) + 1
    if cell_of.size != n_cells or np.unique(cell_of).size != n_cells:
        raise ExportError(f"{where}: not every cell has exactly one face on the z = {zmin} plane")
    cells = np.empty((n_cells, 5), dtype=np.int64)
    cells[cell_of] = rows[:, ::-1]  # the back face runs clockwise seen from +z
    flip = signed_area(points[cells][:, :, :2]) < 0
    cells[flip] = cells[flip][:, ::-1]

    used = np.zeros(points.shape[0], dtype=bool)
    used[cells] = True
    new_id = np.cumsum(used) - 1
    edges, patch, names = [], [], []
    for p in patches:
        if p.get("type") == "empty":
            continue
        faces = np.arange(int(p["startFace"]), int(p["startFace"]) + int(p["nFaces"]))
        if np.any(sizes[faces] != 4):
            raise ExportError(f"{where}: patch {p['name']} has faces that are not quadrilaterals")
        quad = ids[offsets[faces][:, None] + np.arange(4)]
        low = on_bottom[quad]
        pair = low & np.roll(low, -1, axis=1)
        if np.any(pair.sum(axis=1) != 1):
            raise ExportError(f"{where}: patch {p['name']} has faces that are not one-layer sides")
        i = np.argmax(pair, axis=1)
        rows_ = np.arange(quad.shape[0])
        edges.append(np.stack([quad[rows_, i], quad[rows_, (i + 1) % 4]], axis=1))
        patch.append(np.full(quad.shape[0], len(names)))
        names.append(p["name"])
    zones = _read_zones(poly, n_cells)
    region, region_names = zones if zones is not None else (None, None)
    case = poly.parent.parent if poly.parent.name == "constant" else poly
    return mesh_from_arrays(
        points[used, :2],
        new_id[cells],
        where=where,
        region=region,
        region_names=region_names,
        boundary_edges=new_id[np.concatenate(edges)] if edges else np.empty((0, 2), np.int64),
        boundary_patch=np.concatenate(patch) if patch else np.empty(0, np.int64),
        patch_names=names,
        name=case.name,
    )


def find_checkmesh() -> tuple[str, dict[str, str]] | None:
    """OpenFOAM's ``checkMesh`` executable and the environment it needs, or None if absent.

    Distribution packages (Debian's ``openfoam``) put ``checkMesh`` on the PATH but need
    ``WM_PROJECT_DIR`` to find ``etc/controlDict``; it is set here when the shell has not.
    """
    exe = shutil.which("checkMesh")
    if exe is None:
        found = sorted(Path("/usr/lib/openfoam").glob("*/bin/checkMesh"))
        exe = str(found[-1]) if found else None
    if exe is None:
        return None
    env = dict(os.environ)
    if not env.get("WM_PROJECT_DIR"):
        roots = [Path("/usr/share/openfoam"), *sorted(Path("/usr/lib/openfoam").glob("*"))]
        root = next((r for r in roots if (r / "etc" / "controlDict").exists()), None)
        if root is not None:
            env["WM_PROJECT_DIR"] = str(root)
    return exe, env


FORMAT = Format(
    name="openfoam",
    description="OpenFOAM case / polyMesh directory: one extruded layer of pentagonal prisms",
    extensions=(),
    writer=write_openfoam,
    reader=read_openfoam,
    directory=True,
    options=("dz",),
)
