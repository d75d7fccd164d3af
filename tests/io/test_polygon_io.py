"""Polygon meshes (hanging nodes, cells of 5 to 11 vertices) through every writer and real readers.

Every format writes a PolygonMesh and :func:`blockmesh.read` gives it back (every array the
format holds equal); meshio, the gmsh API, VTK's own XML reader, OpenFOAM's checkMesh and Octave
read the files (each test skips, saying why, where the tool is absent).
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from helpers_io import find_checkmesh, run_pvpython, target

import blockmesh
import blockmesh.io as bio
from blockmesh.errors import ExportError
from blockmesh.mesh.polygons import PolygonMesh
from blockmesh.refinement.local import refine_locally

#: What each format keeps besides points, cells, regions and patches.
KEEPS = {
    "vtu": ("block_id", "parent", "cell_level"),
    "vtk": ("block_id", "parent", "cell_level"),
    "xdmf": ("block_id", "parent", "cell_level"),
    "msh": ("block_id", "parent", "cell_level"),
    "mat": ("block_id", "parent", "cell_level"),
    "npz": ("block_id", "parent", "cell_level"),
    "openfoam": (),
}


@pytest.fixture(scope="module")
def polygons() -> PolygonMesh:
    """The L-shape refined three times towards its re-entrant corner, with named patches."""
    base = blockmesh.load_domain("l-shape").mesh(1)
    mesh = refine_locally(base, lambda m: np.hypot(*(m.vertex_means() - 1).T) < 0.35, rounds=3)
    assert mesh.hanging_nodes().size > 0 and int(mesh.cell_sizes().max()) > 6
    return mesh


def _boundary(mesh) -> set[tuple[int, int, str]]:
    return {
        (int(a), int(b), mesh.patch_names[int(k)])
        for (a, b), k in zip(mesh.boundary_edges, mesh.boundary_patch, strict=True)
    }


def test_every_format_is_covered():
    assert set(KEEPS) == set(bio.FORMATS)


@pytest.mark.parametrize("name", list(KEEPS))
def test_round_trip_through_every_writer(tmp_path: Path, polygons: PolygonMesh, name: str):
    path = bio.write(polygons, target(bio.FORMATS[name], tmp_path), format=name)
    back = blockmesh.read(path)
    assert isinstance(back, PolygonMesh)
    np.testing.assert_array_equal(back.points, polygons.points)
    np.testing.assert_array_equal(back.offsets, polygons.offsets)
    np.testing.assert_array_equal(back.nodes, polygons.nodes)
    np.testing.assert_array_equal(back.region, polygons.region)
    assert back.region_names == polygons.region_names
    assert back.patch_names == polygons.patch_names
    assert _boundary(back) == _boundary(polygons)
    for key in KEEPS[name]:
        np.testing.assert_array_equal(getattr(back, key), getattr(polygons, key), err_msg=key)
    if KEEPS[name]:
        assert back.level == polygons.level and back.name == polygons.name
    back.check_geometry()


def test_a_mesh_of_pentagons_stays_a_mesh(tmp_path: Path):
    mesh = blockmesh.load_domain("sp").mesh(2)
    for name, fmt in bio.FORMATS.items():
        (tmp_path / name).mkdir()
        back = blockmesh.read(bio.write(mesh, target(fmt, tmp_path / name), format=name))
        assert isinstance(back, blockmesh.Mesh), name


def test_msh_takes_the_fan_split_only(tmp_path: Path, polygons: PolygonMesh):
    with pytest.raises(ExportError, match="split by tri5"):
        bio.write(polygons, tmp_path / "m.msh", split="quad5")


def test_meshio_reads_the_polygons(tmp_path: Path, polygons: PolygonMesh):
    meshio = pytest.importorskip("meshio")
    vtu = meshio.read(bio.write(polygons, tmp_path / "m.vtu"))
    sizes = [c.data.shape[1] for c in vtu.cells if c.type == "polygon" for _ in c.data]
    assert sorted(sizes) == sorted(polygons.cell_sizes().tolist())
    assert vtu.points.shape[0] == polygons.n_points
    msh = meshio.read(bio.write(polygons, tmp_path / "m.msh"))
    triangles = sum(len(c.data) for c in msh.cells if c.type == "triangle")
    assert triangles == int(polygons.cell_sizes().sum())  # the fan: n triangles per n-gon


def test_gmsh_opens_the_fan_split(tmp_path: Path, polygons: PolygonMesh):
    gmsh = pytest.importorskip("gmsh")
    path = bio.write(polygons, tmp_path / "m.msh")
    gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        types, tags, _ = gmsh.model.mesh.getElements(dim=2)
        assert list(types) == [2]
        assert sum(len(t) for t in tags) == int(polygons.cell_sizes().sum())
        nodes = gmsh.model.mesh.getNodes()[0]
        assert len(nodes) == polygons.n_points + polygons.n_cells  # the fans' centres
        names = {gmsh.model.getPhysicalName(d, t) for d, t in gmsh.model.getPhysicalGroups()}
        assert set(polygons.patch_names) | set(polygons.region_names) <= names
    finally:
        gmsh.finalize()


def test_vtk_reads_the_polygons(tmp_path: Path, polygons: PolygonMesh):
    pytest.importorskip("vtk")
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(bio.write(polygons, tmp_path / "m.vtu")))
    reader.Update()
    grid = reader.GetOutput()
    m, eb = polygons.n_cells, polygons.boundary_edges.shape[0]
    assert grid.GetNumberOfCells() == m + eb
    sizes = sorted(grid.GetCell(k).GetNumberOfPoints() for k in range(grid.GetNumberOfCells()))
    assert sizes == sorted(polygons.cell_sizes().tolist() + [2] * eb)


def test_vtk_reads_the_xdmf_mixed_topology(tmp_path: Path, polygons: PolygonMesh):
    xdmf = pytest.importorskip("vtkmodules.vtkIOXdmf2", reason="the vtk package is absent")
    x = xdmf.vtkXdmfReader()
    x.SetFileName(str(bio.write(polygons, tmp_path / "m.xdmf")))
    x.Update()
    grid = x.GetOutputDataObject(0)
    m = polygons.n_cells
    assert grid.GetNumberOfCells() == m + polygons.boundary_edges.shape[0]
    rows = [[grid.GetCell(k).GetPointId(j) for j in range(grid.GetCell(k).GetNumberOfPoints())]
            for k in range(m)]  # fmt: skip
    assert rows == polygons.cell_lists()


@pytest.mark.parametrize("name", ["m.vtu", "./m.xdmf"])
def test_paraview_reads_the_polygons(tmp_path: Path, polygons: PolygonMesh, name: str):
    bio.write(polygons, tmp_path / name)
    script = (
        "from paraview.simple import OpenDataFile\n"
        f"r = OpenDataFile({name!r}); r.UpdatePipeline()\n"
        "print('cells', r.GetDataInformation().GetNumberOfCells())\n"
    )
    run = run_pvpython(script, tmp_path)
    expected = polygons.n_cells + polygons.boundary_edges.shape[0]
    assert f"cells {expected}" in run.stdout, run.stdout + run.stderr


CHECKMESH = find_checkmesh()


@pytest.mark.skipif(CHECKMESH is None, reason="OpenFOAM checkMesh is not installed")
def test_checkmesh_takes_the_polygon_prisms(tmp_path: Path, polygons: PolygonMesh):
    assert CHECKMESH is not None
    exe, env = CHECKMESH
    bio.write(polygons, tmp_path / "case", format="openfoam")
    run = subprocess.run(
        [exe], cwd=tmp_path / "case", env=env, capture_output=True, text=True, timeout=300
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0, out
    assert "Mesh OK." in out, out
    assert re.search(rf"^\s*cells:\s+{polygons.n_cells}$", out, re.M), out
    assert "Upper triangular ordering OK." in out and "***" not in out, out


OCTAVE = shutil.which("octave-cli") or shutil.which("octave")


@pytest.mark.skipif(OCTAVE is None, reason="Octave is not installed (apt-get install octave)")
def test_octave_reads_the_cell_array(tmp_path: Path, polygons: PolygonMesh):
    assert OCTAVE is not None
    bio.write(polygons, tmp_path / "m.mat")
    script = (
        "d = load('m.mat'); "
        "n = cellfun(@numel, d.Element); "
        "printf('cells %d\\n', numel(d.Element)); "
        "printf('sizes %s\\n', mat2str(n(:)')); "
        "printf('nodes %d\\n', rows(d.Node)); "
        "printf('first %s\\n', mat2str(d.Element{1})); "
        "printf('kind %s\\n', d.Kind);"
    )
    run = subprocess.run(
        [OCTAVE, "--no-gui", "--quiet", "--eval", script],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=300,
    )
    out = run.stdout + run.stderr
    assert run.returncode == 0, out
    assert f"cells {polygons.n_cells}" in out
    sizes = re.search(r"sizes \[([\d ]+)\]", out)
    assert sizes is not None, out
    assert [int(v) for v in sizes[1].split()] == polygons.cell_sizes().tolist()
    assert f"nodes {polygons.n_points}" in out
    first = re.search(r"first \[([\d ]+)\]", out)
    assert first is not None and [int(v) - 1 for v in first[1].split()] == polygons.cell(0).tolist()
    assert "kind polygons" in out
