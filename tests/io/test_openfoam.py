"""OpenFOAM polyMesh export: layout, face order and orientation, round trip, atomic commits,
and OpenFOAM itself: checkMesh, laplacianFoam and icoFoam run in the written case.

The OpenFOAM tools run when OpenFOAM is installed (Debian's ``openfoam`` package) and are
skipped otherwise.
"""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from helpers_io import find_checkmesh, foam_tool, listing, patch_atomic_os, snapshot, two_block

import blockmesh
import blockmesh.io as bio
import blockmesh.io.openfoam.writer as openfoam_writer
import blockmesh.io.text as text
from blockmesh.errors import ExportError, TopologyError
from blockmesh.io.openfoam.files import foam_file, read_boundary, read_faces, read_list
from blockmesh.mesh import Mesh


def numbers(path: Path, dtype: type) -> np.ndarray:
    """Every number in the list of an OpenFOAM file (counts of ``k(...)`` items included)."""
    with foam_file(path.parent, path.name) as (r, _):
        body = r.rest()
    inner = body[body.index(b"(") + 1 : body.rindex(b")")]
    return np.fromstring(inner.replace(b"(", b" ").replace(b")", b" "), dtype=dtype, sep=" ")


def listed(path: Path, cols: int, dtype: type) -> np.ndarray:
    with foam_file(path.parent, path.name) as (r, _):
        return read_list(r, cols, dtype)[1]


@pytest.fixture(scope="module")
def case(tmp_path_factory: pytest.TempPathFactory) -> tuple[Mesh, Path]:
    mesh = two_block(2)
    target = tmp_path_factory.mktemp("of") / "case"
    bio.write(mesh, target, format="openfoam", dz=0.25)
    return mesh, target


def test_case_layout(case: tuple[Mesh, Path]) -> None:
    _, target = case
    poly = target / "constant" / "polyMesh"
    assert listing(poly) == ["boundary", "cellZones", "faces", "neighbour", "owner", "points"]
    assert listing(target / "system") == ["controlDict", "fvSchemes", "fvSolution"]
    assert not [p for p in target.rglob(".*")]  # no temporaries left
    assert listing(target.parent) == ["case"]
    for name in ("points", "faces", "owner", "neighbour", "boundary"):
        head = (poly / name).read_text()[:800]
        assert (
            "FoamFile" in head and "format      ascii;" in head and f"object      {name};" in head
        )


def test_faces_order_and_orientation(case: tuple[Mesh, Path]) -> None:
    mesh, target = case
    poly = target / "constant" / "polyMesh"
    n, m = mesh.n_points, mesh.n_cells
    points = listed(poly / "points", 3, np.float64)
    np.testing.assert_array_equal(points[:n, :2], mesh.points)
    assert set(np.unique(points[:, 2])) == {0.0, 0.25}
    owner = listed(poly / "owner", 1, np.int64).ravel()
    neighbour = listed(poly / "neighbour", 1, np.int64).ravel()
    raw = numbers(poly / "faces", np.int64)
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
    # faces: quads then 2 m pentagons
    n_quads = expected_faces - 2 * m
    quads, pentagons = read_faces(poly, [(0, n_quads, 4), (n_quads, 2 * m, 5)])
    assert raw.size == quads.size + pentagons.size + expected_faces  # ids plus one count a face
    # every face normal points out of its owner: (face centre - cell centre) . normal > 0
    cell_centre = np.concatenate(
        [mesh.points[mesh.cells].mean(axis=1), np.full((m, 1), 0.125)], axis=1
    )
    for faces, first in ((quads, 0), (pentagons, n_quads)):
        nodes = points[faces]
        centre = nodes.mean(axis=1)
        normal = np.cross(nodes[:, 1] - nodes[:, 0], nodes[:, 2] - nodes[:, 1])
        face_ids = first + np.arange(faces.shape[0])
        outward = np.einsum("ij,ij->i", centre - cell_centre[owner[face_ids]], normal)
        assert np.all(outward > 0)
        if first == 0:
            internal = face_ids[face_ids < n_int]
            into = np.einsum(
                "ij,ij->i",
                cell_centre[neighbour[internal]] - cell_centre[owner[internal]],
                normal[: internal.size],
            )
            assert np.all(into > 0)


def test_boundary_file(case: tuple[Mesh, Path]) -> None:
    mesh, target = case
    patches = read_boundary(target / "constant" / "polyMesh")
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


def test_gzipped_files_are_read(case: tuple[Mesh, Path], tmp_path: Path) -> None:
    import gzip
    import shutil

    mesh, target = case
    copy = tmp_path / "c"
    shutil.copytree(target, copy)
    for f in (copy / "constant" / "polyMesh").iterdir():
        f.with_name(f.name + ".gz").write_bytes(gzip.compress(f.read_bytes()))
        f.unlink()
    np.testing.assert_array_equal(bio.read(copy).cells, mesh.cells)


def test_default_dz_is_mean_edge_length(tmp_path: Path) -> None:
    mesh = two_block(1)
    bio.write(mesh, tmp_path / "c", format="openfoam")
    z = listed(tmp_path / "c" / "constant" / "polyMesh" / "points", 3, np.float64)[:, 2]
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

    monkeypatch.setattr(openfoam_writer, "write_rows", boom)
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

    monkeypatch.setattr(text, "_as_matrix", boom)
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


# ----------------------------------------------------------------- atomic: old or new
@pytest.mark.parametrize("swap", ["exchange", "two renames"])
def test_failure_at_the_swap_keeps_the_old_mesh(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, swap: str
) -> None:
    import os

    import blockmesh._system.atomic as atomic

    bio.write(two_block(0), tmp_path / "c", format="openfoam")
    before = snapshot(tmp_path)
    if swap == "two renames":  # a file system that cannot swap: old aside, new in
        monkeypatch.setattr(atomic, "_exchange", lambda a, b: False)
    calls: list[object] = []

    def flaky(src: object, dst: object) -> None:
        calls.append(dst)
        if len(calls) == (1 if swap == "exchange" else 2):
            raise OSError(5, "rename failed")
        os.rename(src, dst)

    patch_atomic_os(monkeypatch, rename=flaky)
    if swap == "exchange":
        monkeypatch.setattr(atomic, "_exchange", lambda a, b: flaky(a, b))
    with pytest.raises(ExportError, match="Input/output error"):
        bio.write(two_block(2), tmp_path / "c", format="openfoam")
    monkeypatch.undo()
    assert snapshot(tmp_path) == before
    assert not [p for p in tmp_path.rglob(".*")]


KILLED = """
import os, sys
sys.path.insert(0, {tests!r})
import blockmesh.io as bio
from blockmesh._system import atomic
from helpers_io import two_block
if {two_renames}:
    atomic._exchange = lambda a, b: False
real, calls = os.rename, []
def rename(src, dst):
    calls.append(dst)
    if len(calls) == {at_call}:
        os._exit(137)  # killed here: no clean-up runs
    real(src, dst)
class Os:
    def __getattr__(self, name):
        return rename if name == "rename" else getattr(os, name)
atomic.os = Os()
bio.write(two_block(2), {path!r}, format="openfoam")
os._exit(0)
"""


@pytest.mark.parametrize(("two_renames", "at_call"), [(True, 1), (True, 2), (True, 3), (False, 1)])
def test_killed_while_swapping(tmp_path: Path, two_renames: bool, at_call: int) -> None:
    """Killed between the renames: the case holds the old mesh or the new one (after the next
    write at the latest, which puts the moved-aside old mesh back and removes the leftovers)."""
    case = tmp_path / "c"
    bio.write(two_block(0), case, format="openfoam")
    script = KILLED.format(
        tests=str(Path(__file__).parents[1]),
        two_renames=two_renames,
        at_call=at_call,
        path=str(case),
    )
    run = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script)], capture_output=True, timeout=300
    )
    assert run.returncode in (0, 137), run.stderr.decode()
    poly = case / "constant" / "polyMesh"
    if poly.exists():
        assert bio.read(case).n_cells in (2, two_block(2).n_cells)
    else:  # killed between "old aside" and "new in": the reader says what happened
        with pytest.raises(ExportError, match="an interrupted write left .polyMesh"):
            bio.read(case)
    bio.write(two_block(1), case, format="openfoam")  # the next write repairs and cleans
    assert not [p for p in case.rglob(".*")]
    assert bio.read(case).n_cells == two_block(1).n_cells


def test_files_from_two_meshes_are_refused(tmp_path: Path) -> None:
    bio.write(two_block(1), tmp_path / "a", format="openfoam")
    bio.write(two_block(2), tmp_path / "b", format="openfoam")
    mixed = tmp_path / "b" / "constant" / "polyMesh"
    (tmp_path / "a" / "constant" / "polyMesh" / "points").replace(mixed / "points")
    with pytest.raises(ExportError, match="do not belong together .*nPoints"):
        bio.read(tmp_path / "b")


# ------------------------------------------------------------------------ OpenFOAM itself
CHECKMESH = find_checkmesh()
LAPLACIAN = foam_tool("laplacianFoam")
ICO = foam_tool("icoFoam")


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


def foam_dict(cls: str, name: str, body: str) -> str:
    return (
        f"FoamFile {{ version 2.0; format ascii; class {cls}; object {name}; }}\n"
        + textwrap.dedent(body)
    )


def internal_field(path: Path) -> np.ndarray:
    """The values of a ``nonuniform List<scalar>`` internalField an OpenFOAM solver wrote."""
    body = path.read_text()
    start = body.index("internalField")
    count = re.search(r"List<scalar>\s*(\d+)\s*\(", body[start:])
    assert count is not None, body[start : start + 200]
    at = start + count.end()
    return np.array(body[at : body.index(")", at)].split(), dtype=float)


@pytest.mark.skipif(LAPLACIAN is None, reason="OpenFOAM laplacianFoam is not installed")
def test_laplacian_foam_runs_to_the_end(tmp_path: Path) -> None:
    """The written system files let laplacianFoam run; T stays within its boundary values."""
    assert LAPLACIAN is not None
    exe, env = LAPLACIAN
    mesh = blockmesh.load_domain("l-shape").mesh(3)
    case = tmp_path / "case"
    bio.write(mesh, case, format="openfoam")
    (case / "0").mkdir()
    (case / "0" / "T").write_text(
        foam_dict(
            "volScalarField",
            "T",
            """
            dimensions [0 0 0 1 0 0 0];
            internalField uniform 0;
            boundaryField
            {
                inlet { type fixedValue; value uniform 1; }
                outlet { type fixedValue; value uniform 0; }
                boundary { type zeroGradient; }
                frontAndBack { type empty; }
            }
            """,
        )
    )
    for name in ("transportProperties", "physicalProperties"):  # older and newer OpenFOAM
        (case / "constant" / name).write_text(
            foam_dict("dictionary", name, "DT DT [0 2 -1 0 0 0 0] 1;\n")
        )
    run = subprocess.run([exe], cwd=case, env=env, capture_output=True, text=True, timeout=600)
    out = run.stdout + run.stderr
    assert run.returncode == 0, out[-3000:]
    assert re.search(r"^End\s*$", out, re.M), out[-3000:]
    t = internal_field(case / "1" / "T")
    assert t.size == mesh.n_cells
    assert t.min() > -1e-9 and t.max() < 1 + 1e-9  # the maximum principle
    assert t.max() - t.min() > 0.5  # heat flows from inlet to outlet


@pytest.mark.skipif(ICO is None, reason="OpenFOAM icoFoam is not installed")
def test_ico_foam_runs_to_the_end(tmp_path: Path) -> None:
    """A transient flow solver (PISO: p and U solvers, div(phi,U), laplacian(nu,U)) runs too."""
    assert ICO is not None
    exe, env = ICO
    case = tmp_path / "case"
    bio.write(blockmesh.load_domain("square-cut").mesh(2), case, format="openfoam")
    patches = [p["name"] for p in read_boundary(case / "constant" / "polyMesh")]
    walls = "\n".join(f"{p} {{ type noSlip; }}" for p in patches if p != "frontAndBack")
    pressure = "\n".join(f"{p} {{ type zeroGradient; }}" for p in patches if p != "frontAndBack")
    (case / "0").mkdir()
    (case / "0" / "U").write_text(
        foam_dict(
            "volVectorField",
            "U",
            "dimensions [0 1 -1 0 0 0 0];\ninternalField uniform (1 0 0);\n"
            f"boundaryField {{\n{walls}\nfrontAndBack {{ type empty; }}\n}}\n",
        )
    )
    (case / "0" / "p").write_text(
        foam_dict(
            "volScalarField",
            "p",
            "dimensions [0 2 -2 0 0 0 0];\ninternalField uniform 0;\n"
            f"boundaryField {{\n{pressure}\nfrontAndBack {{ type empty; }}\n}}\n",
        )
    )
    for name in ("transportProperties", "physicalProperties"):
        (case / "constant" / name).write_text(
            foam_dict("dictionary", name, "transportModel Newtonian;\nnu [0 2 -1 0 0 0 0] 0.1;\n")
        )
    control = case / "system" / "controlDict"
    control.write_text(
        re.sub(
            r"deltaT\s+1;",
            "deltaT 0.001;",
            re.sub(r"endTime\s+1;", "endTime 0.005;", control.read_text()),
        )
    )
    run = subprocess.run([exe], cwd=case, env=env, capture_output=True, text=True, timeout=600)
    out = run.stdout + run.stderr
    assert run.returncode == 0, out[-3000:]
    assert re.search(r"^End\s*$", out, re.M), out[-3000:]
    assert "Solving for p" in out and "Solving for Ux" in out
