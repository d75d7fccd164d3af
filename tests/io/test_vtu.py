"""VTU: read back by meshio, by VTK's own XML reader and by ParaView; names shown as field data."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, expected_names, paraview_names, tagged, vtk_connectivity

import blockmesh.io as bio
import blockmesh.io.vtu.format as vtu
import blockmesh.io.vtu.stream as vtu_stream
from blockmesh.errors import ExportError
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


@pytest.mark.parametrize("compression", [None, "zlib", "lzma", "none"])
def test_vtu_through_meshio(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    import meshio

    path = bio.write(mesh, tmp_path / "m.vtu", compression=compression)
    header = path.read_bytes()[:300].decode()
    expected = {None: None, "zlib": "vtkZLib", "lzma": "vtkLZMA", "none": None}[compression]
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


@pytest.mark.parametrize("compression", ["zlib", "lzma", "none"])
@pytest.mark.parametrize("header", [None, "UInt32", "UInt64"])
def test_blockmesh_files_are_streamed(
    mesh: Mesh, tmp_path: Path, compression: str, header: str | None
) -> None:
    """The files blockmesh writes are read by the streaming reader (not meshio), to the same mesh,
    and so are those it wrote with meshio before issue 22 (block headers UInt32, or UInt64 for
    large meshes), whatever rows the base64 chunks split."""
    import meshio

    path = bio.write(mesh, tmp_path / "m.vtu", compression=compression)
    if header:  # meshio's writer with the field data added, as write_vtu did before
        raw = tmp_path / "raw.vtu"
        meshio.vtu.write(
            str(raw),
            vtu.meshio_mesh(mesh),
            compression=None if compression == "none" else compression,
            header_type=header,
        )
        vtu.insert_field_data(raw, path, vtu.field_data(mesh))
    parts = vtu_stream.read_stream(path)
    assert parts is not None
    np.testing.assert_array_equal(parts.points, mesh.points)
    np.testing.assert_array_equal(parts.cells, mesh.cells)
    np.testing.assert_array_equal(parts.edges, mesh.boundary_edges)
    np.testing.assert_array_equal(parts.cell_data["patch"][1], mesh.boundary_patch)
    assert np.all(parts.cell_data["block_id"][1] == -1)
    back = bio.read(path)
    assert_same(back, mesh)
    assert (back.level, back.name) == (mesh.level, mesh.name)


def test_small_chunks_give_the_same_arrays(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Arrays spanning many read chunks (and rows split across them) decode the same."""
    monkeypatch.setattr(vtu_stream, "_CHUNK", 64)
    for compression in ("zlib", "none"):
        path = bio.write(mesh, tmp_path / f"{compression}.vtu", compression=compression)
        parts = vtu_stream.read_stream(path)
        assert parts is not None
        np.testing.assert_array_equal(parts.points, mesh.points)
        np.testing.assert_array_equal(parts.cells, mesh.cells)
        np.testing.assert_array_equal(parts.cell_data["parent"][0], mesh.parent)


def test_other_files_fall_back_to_meshio(mesh: Mesh, tmp_path: Path) -> None:
    """Files blockmesh did not write (no metadata, ascii arrays) go to meshio; a damaged one of
    blockmesh's is an error naming the array."""
    import meshio

    plain = tmp_path / "plain.vtu"
    meshio.write(plain, meshio.Mesh(mesh.points, [("polygon", mesh.cells)]), binary=False)
    assert vtu_stream.read_stream(plain) is None
    np.testing.assert_array_equal(bio.read(plain).cells, mesh.cells)
    path = bio.write(mesh, tmp_path / "m.vtu")
    data = path.read_bytes()
    at = data.index(b'Name="connectivity"')
    at = data.index(b"\n", at) + 40
    path.write_bytes(data[:at] + b"*" + data[at + 1 :])  # not base64 any more
    with pytest.raises(ExportError, match=r"m.vtu: the DataArray 'connectivity' in <Cells>"):
        vtu_stream.read_stream(path)
    with pytest.raises(ExportError, match=r"m.vtu: the DataArray 'connectivity' in <Cells>"):
        bio.read(path)


def test_field_data_goes_in_after_the_grid_tag(mesh: Mesh, tmp_path: Path) -> None:
    """The field data block lands right after <UnstructuredGrid>, the rest of the file as it was;
    a file without that tag in its head is refused, naming it."""
    raw = tmp_path / "raw.vtu"
    raw.write_bytes(b"<VTKFile>\n<UnstructuredGrid>\n<Piece/>\n</UnstructuredGrid>\n</VTKFile>\n")
    out = tmp_path / "out.vtu"
    vtu.insert_field_data(raw, out, vtu.field_data(mesh))
    text = out.read_bytes()
    head, _, rest = text.partition(b"<UnstructuredGrid>\n<FieldData>")
    assert head == b"<VTKFile>\n"
    assert rest.split(b"</FieldData>\n", 1)[1] == b"\n<Piece/>\n</UnstructuredGrid>\n</VTKFile>\n"
    assert rest.count(b"<DataArray") == len(vtu.field_data(mesh))
    raw.write_bytes(b"<VTKFile>\n<PolyData/>\n</VTKFile>\n")
    with pytest.raises(ExportError, match=r"raw\.vtu: no <UnstructuredGrid>"):
        vtu.insert_field_data(raw, out, vtu.field_data(mesh))
