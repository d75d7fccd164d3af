"""Writing OpenFOAM cases and ``polyMesh`` folders (layout: :mod:`~blockmesh.io.openfoam.format`).

Examples
--------
>>> import pathlib, tempfile
>>> import numpy as np
>>> from blockmesh.mesh import Mesh
>>> sp = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0.0]])
>>> case = pathlib.Path(tempfile.mkdtemp()) / "case"
>>> poly = write_openfoam(Mesh.from_cells(sp, [[0, 1, 2, 3, 4]]), case)
>>> (poly / "owner").read_text().count("nCells:1")
1
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO

import numpy as np

from blockmesh._system.atomic import atomic_dir, atomic_file
from blockmesh._system.targets import export_errors
from blockmesh.errors import ExportError
from blockmesh.geometry.topology import PolygonCells, boundary_slots, cell_neighbours
from blockmesh.io.names import FOAM_WORD
from blockmesh.io.text import float_bytes, write_rows
from blockmesh.mesh.mesh import Mesh
from blockmesh.mesh.polygons import PolygonMesh

__all__ = ["EMPTY_PATCH", "polymesh_dir", "write_openfoam"]

EMPTY_PATCH = "frontAndBack"

_BANNER = b"""/*--------------------------------*- C++ -*----------------------------------*\\
  =========                 |
  \\\\      /  F ield         | OpenFOAM: The Open Source CFD Toolbox
   \\\\    /   O peration     |
    \\\\  /    A nd           | Written by blockmesh (blockmesh.io.openfoam.format)
     \\\\/     M anipulation  |
\\*---------------------------------------------------------------------------*/
"""
_RULE = b"// * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * * //\n\n"
_END = b"\n// ************************************************************************* //\n"


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
def _faces(mesh: Mesh | PolygonMesh) -> dict[str, np.ndarray]:
    """Quad side faces (internal, then per patch), owners, neighbours and patch sizes."""
    n, m = mesh.n_points, mesh.n_cells
    cells: np.ndarray | PolygonCells
    if isinstance(mesh, PolygonMesh):
        cells = mesh.polygon_cells()
        a, b, owner_of = mesh.nodes, cells.following(), cells.slot_cell()
    else:
        cells = mesh.cells
        a, b = cells.ravel(), np.roll(cells, -1, axis=1).ravel()
        owner_of = np.repeat(np.arange(m), 5)
    nb = cell_neighbours(cells, n).ravel()
    slot = np.arange(a.size)
    internal = (nb >= 0) & (slot < nb)
    own, nei = owner_of[slot[internal]], owner_of[nb[internal]]
    order = np.argsort(own * m + nei, kind="stable")  # by owner, then neighbour
    own, nei = own[order], nei[order]
    side_a, side_b = a[internal][order], b[internal][order]

    shaped = nb if isinstance(cells, PolygonCells) else nb.reshape(m, 5)
    b_slot = boundary_slots(cells, shaped, mesh.boundary_edges, n)
    b_order = np.argsort(mesh.boundary_patch * m + owner_of[b_slot], kind="stable")
    b_slot = b_slot[b_order]
    patch_sizes = np.bincount(mesh.boundary_patch, minlength=len(mesh.patch_names))
    all_a = np.concatenate([side_a, a[b_slot]])
    all_b = np.concatenate([side_b, b[b_slot]])
    return {
        "quads": np.stack([all_a, all_b, all_b + n, all_a + n], axis=1),
        "owner": np.concatenate([own, owner_of[b_slot]]),
        "neighbour": nei,
        "patch_sizes": patch_sizes,
        **_zone_faces(mesh, side_a, side_b),
    }


def _zone_faces(
    mesh: Mesh | PolygonMesh, side_a: np.ndarray, side_b: np.ndarray
) -> dict[str, np.ndarray]:
    """The internal face of every interface edge, and whether its normal runs backwards.

    An internal face over ``a -> b`` points out of its owner, the cell on the left of ``a -> b``;
    the interface's first side is the cell on the left of its edge, so the face is flipped
    (``flipMap``) where the two disagree.
    """
    edges = mesh.interface_edges
    if edges.shape[0] == 0:
        return {}
    n = mesh.n_points
    keys = np.minimum(side_a, side_b) * n + np.maximum(side_a, side_b)
    order = np.argsort(keys)
    wanted = np.minimum(edges[:, 0], edges[:, 1]) * n + np.maximum(edges[:, 0], edges[:, 1])
    at = order[np.minimum(np.searchsorted(keys[order], wanted), max(keys.size - 1, 0))]
    if keys.size == 0 or np.any(keys[at] != wanted):
        raise ExportError(
            "an interface edge of the mesh is not an internal face; the mesh is broken"
        )
    return {"zone_faces": at, "zone_flip": side_a[at] != edges[:, 0]}


def _mean_edge_length(mesh: Mesh | PolygonMesh, quads: np.ndarray) -> float:
    """Mean length of the mesh's edges: the side faces hold each edge once."""
    d = mesh.points[quads[:, 1]] - mesh.points[quads[:, 0]]
    return float(np.mean(np.hypot(d[:, 0], d[:, 1])))


def _write_list(f: BinaryIO, count: int, parts: list, *, empty: bool = False) -> None:
    f.write(f"{count}\n(\n".encode())
    if count and not empty:
        write_rows(f, parts)
    f.write(b")\n")


def _cell_blocks(mesh: Mesh | PolygonMesh) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """The cells as blocks of one size: ``(size, cells (M_n, n), cell ids)`` each."""
    if isinstance(mesh, PolygonMesh):
        return [(g.size, g.cells, g.index) for g in mesh.groups]
    return [(5, mesh.cells, np.arange(mesh.n_cells))]


def _write_polymesh(
    mesh: Mesh | PolygonMesh, poly: Path, faces: dict[str, np.ndarray], dz: float
) -> None:
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
        for size, rows, _ in _cell_blocks(mesh):
            write_rows(f, [f"{size}(".encode(), rows[:, ::-1], b")\n"])
        for size, rows, _ in _cell_blocks(mesh):
            write_rows(f, [f"{size}(".encode(), rows + n, b")\n"])
        f.write(b")\n" + _END)

    with open(poly / "owner", "wb") as f:
        f.write(_header("labelList", "owner", note=note))
        f.write(f"{n_faces}\n(\n".encode())
        write_rows(f, [owner, b"\n"])
        for _ in range(2):
            for _, _, cell_ids in _cell_blocks(mesh):
                write_rows(f, [cell_ids, b"\n"])
        f.write(b")\n" + _END)

    with open(poly / "neighbour", "wb") as f:
        f.write(_header("labelList", "neighbour", note=note))
        _write_list(f, n_internal, [neighbour, b"\n"])
        f.write(_END)

    names = FOAM_WORD.unique(mesh.patch_names, {EMPTY_PATCH})
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

    zones = FOAM_WORD.unique(mesh.region_names)
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
    if mesh.interface_names:
        _write_face_zones(mesh, poly, faces)


def _write_face_zones(mesh: Mesh | PolygonMesh, poly: Path, faces: dict[str, np.ndarray]) -> None:
    """``faceZones``: one zone per interface, its internal faces and their flip map."""
    zones = FOAM_WORD.unique(mesh.interface_names, set(FOAM_WORD.unique(mesh.region_names)))
    with open(poly / "faceZones", "wb") as f:
        f.write(_header("regIOobject", "faceZones"))
        f.write(f"{len(zones)}\n(\n".encode())
        for k, name in enumerate(zones):
            mine = mesh.interface_patch == k
            labels = faces["zone_faces"][mine]
            flips = faces["zone_flip"][mine].astype(np.int64)
            order = np.argsort(labels, kind="stable")
            f.write(f"{name}\n{{\n    type faceZone;\nfaceLabels      List<label> ".encode())
            _write_list(f, labels.size, [labels[order], b"\n"])
            f.write(b";\nflipMap         List<bool> ")
            _write_list(f, labels.size, [flips[order], b"\n"])
            f.write(b";\n}\n")
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
runTimeModifiable true;
""",
    "fvSchemes": """// Written by blockmesh for a 2-D case (one layer, frontAndBack empty). The
// pentagons' faces are not orthogonal: "corrected" schemes and a non-orthogonal
// corrector keep that accurate.

ddtSchemes
{
    default         Euler;          // steadyState for steady solvers (simpleFoam)
}

gradSchemes
{
    default         Gauss linear;
}

divSchemes
{
    default         Gauss linear;
    div(phi,U)      Gauss linearUpwind grad(U);
    div(phi,k)      Gauss upwind;
    div(phi,epsilon) Gauss upwind;
    div(phi,omega)  Gauss upwind;
    div(phi,nuTilda) Gauss upwind;
    div(phi,T)      Gauss linearUpwind grad(T);
    div((nuEff*dev2(T(grad(U))))) Gauss linear;
}

laplacianSchemes
{
    default         Gauss linear corrected;
}

interpolationSchemes
{
    default         linear;
}

snGradSchemes
{
    default         corrected;
}

wallDist
{
    method          meshWave;
}
""",
    "fvSolution": """solvers
{
    "(T|Phi|p|p_rgh|pcorr)(Final)?"
    {
        solver          PCG;
        preconditioner  DIC;
        tolerance       1e-08;
        relTol          0;
    }

    "(U|k|epsilon|omega|nuTilda|h|e)(Final)?"
    {
        solver          PBiCGStab;
        preconditioner  DILU;
        tolerance       1e-08;
        relTol          0;
    }
}

SIMPLE
{
    nNonOrthogonalCorrectors 1;
    consistent      yes;
    pRefCell        0;
    pRefValue       0;
}

PISO
{
    nCorrectors     2;
    nNonOrthogonalCorrectors 1;
    pRefCell        0;
    pRefValue       0;
}

PIMPLE
{
    nOuterCorrectors 1;
    nCorrectors     2;
    nNonOrthogonalCorrectors 1;
    pRefCell        0;
    pRefValue       0;
}

potentialFlow
{
    nNonOrthogonalCorrectors 3;
}

relaxationFactors
{
    equations
    {
        U               0.9;
        ".*"            0.9;
    }
}
""",
}


def _write_system(case: Path) -> None:
    """The ``system`` files missing from ``case`` (each written atomically; others kept)."""
    system = case / "system"
    with export_errors(system):
        system.mkdir(exist_ok=True)
    for name, text in _SYSTEM.items():
        target = system / name
        if target.exists():
            continue
        with atomic_file(target) as tmp:
            tmp.write_bytes(_header("dictionary", name, location="system") + text.encode() + _END)


def write_openfoam(mesh: Mesh | PolygonMesh, path: Path, *, dz: float | None = None) -> Path:
    """Write ``mesh`` as an OpenFOAM case (or bare ``polyMesh``); returns the ``polyMesh`` path.

    Parameters
    ----------
    mesh : Mesh or PolygonMesh
        A PolygonMesh's cells become n-gon prisms (see :mod:`blockmesh.io.openfoam.polygons`).
    path : Path
        A case directory (created if its parent exists), or a path ending in ``polyMesh``.
    dz : float, optional
        Thickness of the extruded layer (> 0); default the mean edge length of the mesh.

    O(M log M); about a second per million cells plus disk time. A new case (or ``constant``
    folder) is built whole and renamed in; an existing ``polyMesh`` is swapped in one step.
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
    if case is not None and case.exists() and not case.is_dir():
        raise ExportError(f"cannot write the OpenFOAM case {case}: a file of that name exists")
    if case is not None and not case.exists():
        with atomic_dir(case) as tmp:  # a new case: built whole, renamed in
            (tmp / "constant" / "polyMesh").mkdir(parents=True)
            _write_polymesh(mesh, tmp / "constant" / "polyMesh", faces, dz)
            _write_system(tmp)
        return poly
    if case is not None:  # the system files it lacks first: a failure leaves the old mesh
        _write_system(case)
    constant = poly.parent
    if not constant.exists() and constant.name == "constant" and constant.parent.is_dir():
        with atomic_dir(constant) as tmp:
            (tmp / "polyMesh").mkdir()
            _write_polymesh(mesh, tmp / "polyMesh", faces, dz)
    else:
        with atomic_dir(poly) as tmp:
            _write_polymesh(mesh, tmp, faces, dz)
    return poly
