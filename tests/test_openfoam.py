"""OpenFOAM polyMesh export: layout, face order and orientation, round trip, and checkMesh.

checkMesh runs when OpenFOAM is installed (Debian's ``openfoam`` package) and is skipped
otherwise.
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

import blockmesh
import blockmesh.io as bio
from blockmesh.errors import ExportError, TopologyError
from blockmesh.io import _ascii, openfoam
from blockmesh.mesh import Mesh
from blockmesh.refinement import refine

TWO_POINTS = np.array([[0, 0], [2, 0], [2.5, 1], [2, 2], [0, 2], [4, 0], [4.5, 1], [4, 2]], float)
TWO_CELLS = [[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]]


def two_block(level: int) -> Mesh:
    """The two-block example with patches ``outer wall``, ``inlet`` and two regions."""
    base = refine(Mesh.from_cells(TWO_POINTS, TWO_CELLS), level)
    xy = base.points[base.boundary_edges]
    inlet = np.all(xy[:, :, 0] < 1e-12, axis=1)
    return Mesh(
        points=base.points,
        cells=base.cells,
        block_id=base.block_id,
        parent=base.parent,
        boundary_edges=base.boundary_edges,
        boundary_patch=inlet.astype(np.int64),
        patch_names=("outer wall", "inlet"),
        region=base.block_id,
        region_names=("left", "right"),
        level=base.level,
        name="two-block",
    )


def read_list(path: Path, dtype: type) -> np.ndarray:
    text = path.read_bytes()
    _, body = openfoam._split_header(text, str(path))
    _, inner = openfoam._list(body, str(path))
    return np.fromstring(inner.replace(b"(", b" ").replace(b")", b" "), dtype=dtype, sep=" ")


@pytest.fixture(scope="module")
def case(tmp_path_factory: pytest.TempPathFactory) -> tuple[Mesh, Path]:
    mesh = two_block(2)
    target = tmp_path_factory.mktemp("of") / "case"
    bio.write(mesh, target, format="openfoam", dz=0.25)
    return mesh, target


def test_case_layout(case: tuple[Mesh, Path]) -> None:
    _, target = case
    poly = target / "constant" / "polyMesh"
    assert sorted(p.name for p in poly.iterdir()) == [
        "boundary",
        "cellZones",
        "faces",
        "neighbour",
        "owner",
        "points",
    ]
    assert sorted(p.name for p in (target / "system").iterdir()) == [
        "controlDict",
        "fvSchemes",
        "fvSolution",
    ]
    assert not [p for p in target.rglob(".*")]  # no temporaries left
    for name in ("points", "faces", "owner", "neighbour", "boundary"):
        head = (poly / name).read_text()[:800]
        assert (
            "FoamFile" in head and "format      ascii;" in head and f"object      {name};" in head
        )


def test_faces_order_and_orientation(case: tuple[Mesh, Path]) -> None:
    mesh, target = case
    poly = target / "constant" / "polyMesh"
    n, m = mesh.n_points, mesh.n_cells
    points = read_list(poly / "points", float).reshape(-1, 3)
    np.testing.assert_array_equal(points[:n, :2], mesh.points)
    assert set(np.unique(points[:, 2])) == {0.0, 0.25}
    owner = read_list(poly / "owner", int)
    neighbour = read_list(poly / "neighbour", int)
    raw = read_list(poly / "faces", int)
    note = re.search(r'note\s+"([^"]*)"', (poly / "owner").read_text()[:1000])
    assert note is not None
    expected_faces = owner.size
    assert note.group(1).split() == [
        f"nPoints:{2 * n}",
        f"nCells:{m}",
        f"nFaces:{expected_faces}",
        f"nInternalFaces:{neighbour.size}",
    ]
    n_int = neighbour.size
    assert n_int == mesh.n_edges - mesh.boundary_edges.shape[0]
    assert np.all(owner[:n_int] < neighbour)
    order = np.lexsort((neighbour, owner[:n_int]))
    np.testing.assert_array_equal(order, np.arange(n_int))  # upper-triangular order
    # faces: quads then 2 m pentagons; decode the "k(a b ..)" stream
    ids, offsets = openfoam._read_faces(poly)
    sizes = np.diff(offsets)
    assert sizes.size == expected_faces
    assert np.all(sizes[: expected_faces - 2 * m] == 4) and np.all(sizes[-2 * m :] == 5)
    assert raw.size == ids.size + sizes.size
    # every face normal points out of its owner: (face centre - cell centre) . normal > 0
    cell_centre = np.concatenate(
        [mesh.points[mesh.cells].mean(axis=1), np.full((m, 1), 0.125)], axis=1
    )
    for k in (4, 5):
        faces = np.flatnonzero(sizes == k)
        nodes = points[ids[offsets[faces][:, None] + np.arange(k)]]
        centre = nodes.mean(axis=1)
        normal = np.cross(nodes[:, 1] - nodes[:, 0], nodes[:, 2] - nodes[:, 1])
        outward = np.einsum("ij,ij->i", centre - cell_centre[owner[faces]], normal)
        assert np.all(outward > 0)
        if k == 4:
            internal = faces[faces < n_int]
            into = np.einsum(
                "ij,ij->i",
                cell_centre[neighbour[internal]] - cell_centre[owner[internal]],
                normal[: internal.size],
            )
            assert np.all(into > 0)


def test_boundary_file(case: tuple[Mesh, Path]) -> None:
    mesh, target = case
    patches = openfoam._read_boundary(target / "constant" / "polyMesh")
    assert [p["name"] for p in patches] == ["outer_wall", "inlet", "frontAndBack"]
    assert [p["type"] for p in patches] == ["wall", "patch", "empty"]
    sizes = [int(p["nFaces"]) for p in patches]
    assert sizes[:2] == np.bincount(mesh.boundary_patch).tolist()
    assert sizes[2] == 2 * mesh.n_cells
    starts = [int(p["startFace"]) for p in patches]
    assert starts[1] == starts[0] + sizes[0] and starts[2] == starts[1] + sizes[1]


def test_round_trip(case: tuple[Mesh, Path]) -> None:
    mesh, target = case
    for path in (target, target / "constant", target / "constant" / "polyMesh"):
        back = bio.read(path, format="openfoam")
        np.testing.assert_array_equal(back.points, mesh.points)
        np.testing.assert_array_equal(back.cells, mesh.cells)
        np.testing.assert_array_equal(back.region, mesh.region)
        assert back.region_names == mesh.region_names
        assert back.patch_names == ("outer_wall", "inlet")
        for k in range(2):
            got = set(map(tuple, back.boundary_edges[back.boundary_patch == k].tolist()))
            want = set(map(tuple, mesh.boundary_edges[mesh.boundary_patch == k].tolist()))
            assert got == want
    assert bio.read(target).name == "case"  # an existing directory is OpenFOAM


def test_default_dz_is_mean_edge_length(tmp_path: Path) -> None:
    mesh = two_block(1)
    bio.write(mesh, tmp_path / "c", format="openfoam")
    z = read_list(tmp_path / "c" / "constant" / "polyMesh" / "points", float).reshape(-1, 3)[:, 2]
    e = mesh.edges()
    mean = np.mean(np.linalg.norm(mesh.points[e[:, 1]] - mesh.points[e[:, 0]], axis=1))
    assert z.max() == pytest.approx(mean, rel=1e-12)


@pytest.mark.parametrize("dz", [0, -1.0, float("nan"), "thick"])
def test_bad_dz(tmp_path: Path, dz: object) -> None:
    with pytest.raises(ExportError, match="dz must be a positive number"):
        bio.write(two_block(0), tmp_path / "c", format="openfoam", dz=dz)
    assert list(tmp_path.iterdir()) == []


def test_existing_system_files_are_kept(tmp_path: Path) -> None:
    (tmp_path / "c" / "system").mkdir(parents=True)
    mine = tmp_path / "c" / "system" / "controlDict"
    mine.write_text("// my own\n")
    bio.write(two_block(0), tmp_path / "c", format="openfoam")
    assert mine.read_text() == "// my own\n"
    assert (tmp_path / "c" / "system" / "fvSchemes").exists()


def test_bare_polymesh_target(tmp_path: Path) -> None:
    poly = tmp_path / "constant" / "polyMesh"
    assert bio.write(two_block(0), poly) == poly
    assert not (tmp_path / "system").exists()
    assert bio.read(poly).n_cells == 2


def test_failed_write_keeps_old_polymesh(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    bio.write(two_block(0), tmp_path / "c", format="openfoam")
    poly = tmp_path / "c" / "constant" / "polyMesh"
    before = {p.name: p.read_bytes() for p in poly.iterdir()}

    def boom(*args: object, **kw: object) -> None:
        raise KeyboardInterrupt("simulated Ctrl-C")

    monkeypatch.setattr(openfoam, "write_rows", boom)
    with pytest.raises(KeyboardInterrupt):
        bio.write(two_block(2), tmp_path / "c", format="openfoam")
    monkeypatch.undo()
    assert {p.name: p.read_bytes() for p in poly.iterdir()} == before
    assert sorted(p.name for p in (tmp_path / "c" / "constant").iterdir()) == ["polyMesh"]
    assert bio.read(tmp_path / "c").n_cells == 2


def test_failed_first_write_removes_created_dirs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def boom(*args: object, **kw: object) -> None:
        raise RuntimeError("simulated")

    monkeypatch.setattr(_ascii, "_as_matrix", boom)
    with pytest.raises(RuntimeError):
        bio.write(two_block(0), tmp_path / "new", format="openfoam")
    assert list(tmp_path.iterdir()) == []


def test_inconsistent_boundary_is_refused() -> None:
    mesh = two_block(0)
    with pytest.raises(TopologyError, match="boundary edges are listed"):
        Mesh(
            points=mesh.points,
            cells=mesh.cells,
            block_id=mesh.block_id,
            parent=mesh.parent,
            boundary_edges=mesh.boundary_edges[1:],
            boundary_patch=mesh.boundary_patch[1:],
            patch_names=mesh.patch_names,
            region=mesh.region,
            region_names=mesh.region_names,
        )


# ------------------------------------------------------------------------------ checkMesh
CHECKMESH = openfoam.find_checkmesh()


@pytest.mark.skipif(CHECKMESH is None, reason="OpenFOAM checkMesh is not installed")
@pytest.mark.parametrize(
    ("domain", "level"), [("two-block", 0), ("two-block", 1), ("square-cut", 3), ("hexagon", 4)]
)
def test_checkmesh_says_ok(tmp_path: Path, domain: str, level: int) -> None:
    assert CHECKMESH is not None
    exe, env = CHECKMESH
    mesh = two_block(level) if domain == "two-block" else blockmesh.load_domain(domain).mesh(level)
    bio.write(mesh, tmp_path / "case", format="openfoam")
    run = subprocess.run(
        [exe], cwd=tmp_path / "case", env=env, capture_output=True, text=True, timeout=300
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0, out
    assert "Mesh OK." in out, out
    assert re.search(rf"^\s*cells:\s+{mesh.n_cells}$", out, re.M), out
    assert "Upper triangular ordering OK." in out
    assert "Boundary openness" in out and "***" not in out, out
