"""Legacy VTK: read back by meshio, VTK's legacy reader and ParaView, names included."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, expected_names, paraview_names, tagged, vtk_connectivity

import blockmesh.io as bio
import blockmesh.io.vtk.format as legacy_vtk
import blockmesh.io.vtk.stream as vtk_stream
from blockmesh.errors import ExportError
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


def test_vtk_through_meshio(mesh: Mesh, tmp_path: Path) -> None:
    import meshio

    path = bio.write(mesh, tmp_path / "m.vtk")
    assert path.read_bytes().startswith(b"# vtk DataFile Version 5.1\n")
    vm = meshio.read(path)
    assert [c.type for c in vm.cells] == ["polygon", "line"]
    np.testing.assert_array_equal(vm.cells[0].data, mesh.cells)
    np.testing.assert_array_equal(vm.cells[1].data, mesh.boundary_edges)
    np.testing.assert_array_equal(vm.points[:, :2], mesh.points)
    for name in ("block_id", "region", "parent"):
        np.testing.assert_array_equal(vm.cell_data[name][0], getattr(mesh, name))
        assert np.all(vm.cell_data[name][1] == -1)
    np.testing.assert_array_equal(vm.cell_data["patch"][1], mesh.boundary_patch)
    back = bio.read(path)
    assert_same(back, mesh)
    assert (back.name, back.level) == (mesh.name, mesh.level)


def test_vtk_legacy_reader(mesh: Mesh, tmp_path: Path) -> None:
    legacy = pytest.importorskip("vtkmodules.vtkIOLegacy", reason="the vtk package is absent")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    r = legacy.vtkUnstructuredGridReader()
    r.SetFileName(str(bio.write(mesh, tmp_path / "m.vtk")))
    r.Update()
    grid = r.GetOutput()
    rows = vtk_connectivity(grid)
    assert rows[: mesh.n_cells] == mesh.cells.tolist()
    assert rows[mesh.n_cells :] == mesh.boundary_edges.tolist()
    assert {grid.GetCellType(i) for i in range(mesh.n_cells)} == {7}  # VTK_POLYGON
    np.testing.assert_array_equal(
        vtk_to_numpy(grid.GetCellData().GetArray("region"))[: mesh.n_cells], mesh.region
    )
    fields = grid.GetFieldData()
    names = {
        fields.GetArrayName(i): int(fields.GetArray(i).GetTuple1(0))
        for i in range(fields.GetNumberOfArrays())
        if fields.GetArrayName(i) != "blockmesh"
    }
    assert names == expected_names(mesh)  # "outer wall": VTK decodes the %20


def test_names_are_encoded_without_spaces() -> None:
    for name in ("outer wall", "100%", 'a"b', "ünïcode", "tab\there"):
        word = legacy_vtk.encode_name(name)
        assert all(33 <= ord(c) <= 126 for c in word) and '"' not in word
        assert legacy_vtk.decode_name(word) == name


def test_paraview_shows_the_names(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.vtk")
    cells, names = paraview_names(path)
    assert cells == mesh.n_cells + mesh.boundary_edges.shape[0]
    assert names == expected_names(mesh)


def test_blockmesh_files_are_read_directly(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The files blockmesh writes are read without meshio, to the same mesh, also when the
    points, offsets and types span many chunks."""
    monkeypatch.setattr(vtk_stream, "_ROWS", 7)
    path = bio.write(mesh, tmp_path / "m.vtk")
    parts = vtk_stream.read_stream(path)
    assert parts is not None
    np.testing.assert_array_equal(parts["points"], mesh.points)
    np.testing.assert_array_equal(parts["cells"], mesh.cells)
    np.testing.assert_array_equal(parts["edges"], mesh.boundary_edges)
    np.testing.assert_array_equal(parts["cell_data"]["parent"][0], mesh.parent)
    np.testing.assert_array_equal(parts["cell_data"]["patch"][1], mesh.boundary_patch)
    back = bio.read(path)
    assert_same(back, mesh)
    assert (back.name, back.level) == (mesh.name, mesh.level)


def test_other_files_fall_back_to_meshio(mesh: Mesh, tmp_path: Path) -> None:
    """Files of another layout (ascii, from meshio) go to meshio; a damaged one of blockmesh's
    is an error naming the section."""
    import meshio

    plain = tmp_path / "plain.vtk"
    meshio.write(plain, meshio.Mesh(mesh.points, [("polygon", mesh.cells)]), binary=False)
    assert vtk_stream.read_stream(plain) is None
    np.testing.assert_array_equal(bio.read(plain).cells, mesh.cells)
    path = bio.write(mesh, tmp_path / "m.vtk")
    data = path.read_bytes()
    cut = data.index(b"CELL_TYPES")
    path.write_bytes(data[: cut - 16] + data[cut:])  # the connectivity cut short
    with pytest.raises(ExportError, match="m.vtk: CONNECTIVITY: an array of another length"):
        vtk_stream.read_stream(path)
    with pytest.raises(ExportError, match="m.vtk"):
        bio.read(path)
