"""VTU: read back by meshio, by VTK's own XML reader and by ParaView; names shown as field data."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, expected_names, paraview_names, tagged, vtk_connectivity

import blockmesh.io as bio
from blockmesh.io import vtu
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


@pytest.mark.parametrize("compression", [None, "zlib", "lzma", "none"])
def test_vtu_through_meshio(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    import meshio

    path = bio.write(mesh, tmp_path / "m.vtu", compression=compression)
    header = path.read_bytes()[:300].decode()
    expected = {None: "vtkZLib", "zlib": "vtkZLib", "lzma": "vtkLZMA", "none": None}[compression]
    assert (expected in header) if expected else ("compressor" not in header)
    vm = meshio.read(path)
    kinds = [c.type for c in vm.cells]
    assert kinds == ["polygon", "line"]
    np.testing.assert_array_equal(vm.cells[0].data, mesh.cells)
    np.testing.assert_array_equal(vm.cells[1].data, mesh.boundary_edges)
    np.testing.assert_array_equal(vm.points[:, :2], mesh.points)
    np.testing.assert_array_equal(vm.cell_data["block_id"][0], mesh.block_id)
    np.testing.assert_array_equal(vm.cell_data["region"][0], mesh.region)
    np.testing.assert_array_equal(vm.cell_data["patch"][1], mesh.boundary_patch)
    assert np.all(vm.cell_data["patch"][0] == -1) and np.all(vm.cell_data["block_id"][1] == -1)
    meta = json.loads(bytes(vm.field_data["blockmesh"].astype(np.uint8)).decode())
    assert meta["patch_names"] == list(mesh.patch_names)
    assert meta["region_names"] == list(mesh.region_names)
    for k, name in enumerate(mesh.patch_names):  # the lookups ParaView shows
        assert vm.field_data[f"patch:{name}"].tolist() == [k]
    for k, name in enumerate(mesh.region_names):
        assert vm.field_data[f"region:{name}"].tolist() == [k]
    assert_same(bio.read(path), mesh)
    assert bio.read(path).level == mesh.level and bio.read(path).name == mesh.name


def test_vtu_from_meshio_without_metadata(mesh: Mesh, tmp_path: Path) -> None:
    import meshio

    path = tmp_path / "plain.vtu"
    meshio.write(path, meshio.Mesh(mesh.points, [("polygon", mesh.cells)]))
    back = bio.read(path)
    np.testing.assert_array_equal(back.cells, mesh.cells)
    assert back.patch_names == ("boundary",)
    assert back.boundary_edges.shape == mesh.boundary_edges.shape


def test_names_come_from_the_lookups_without_json(mesh: Mesh, tmp_path: Path) -> None:
    """A file whose JSON was dropped (by a converter) still has its names, from the lookups."""
    import meshio

    vm = meshio.read(bio.write(mesh, tmp_path / "m.vtu"))
    del vm.field_data["blockmesh"]
    back = vtu.mesh_from_meshio(vm, {}, "converted.vtu")
    assert (back.patch_names, back.region_names) == (mesh.patch_names, mesh.region_names)
    assert_same(back, mesh)


def test_vtk_xml_reader(mesh: Mesh, tmp_path: Path) -> None:
    """ParaView's reader (VTK's XML reader), when the vtk package is present."""
    xml = pytest.importorskip("vtkmodules.vtkIOXML", reason="the vtk package is not installed")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    r = xml.vtkXMLUnstructuredGridReader()
    r.SetFileName(str(bio.write(mesh, tmp_path / "m.vtu")))
    r.Update()
    grid = r.GetOutput()
    assert grid.GetNumberOfCells() == mesh.n_cells + mesh.boundary_edges.shape[0]
    rows = vtk_connectivity(grid)
    assert rows[: mesh.n_cells] == mesh.cells.tolist()
    assert rows[mesh.n_cells :] == mesh.boundary_edges.tolist()
    fields = grid.GetFieldData()
    meta = bytes(vtk_to_numpy(fields.GetArray("blockmesh"))).decode()
    assert json.loads(meta)["region_names"] == list(mesh.region_names)
    names = {fields.GetArrayName(i) for i in range(fields.GetNumberOfArrays())}
    assert {"patch:outer wall", "patch:inlet", "region:left", "region:right"} <= names
    assert vtk_to_numpy(fields.GetArray("patch:outlet")).tolist() == [2]


def test_paraview_shows_the_names(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.vtu")
    cells, names = paraview_names(path)
    assert cells == mesh.n_cells + mesh.boundary_edges.shape[0]
    assert names == expected_names(mesh)
