"""Round trips through every writer and a real reader; atomic writes; error messages.

The readers used are the peers' own where one exists: meshio for VTU, h5py + ElementTree for
XDMF, the gmsh Python API for .msh, scipy.io.loadmat for .mat, numpy for .npz (OpenFOAM, with
checkMesh, is in test_openfoam.py). Each also goes back through :func:`blockmesh.io.read`.
"""

from __future__ import annotations

import io as _io
import json
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import blockmesh.io as bio
from blockmesh import atomic as _safe
from blockmesh.errors import BlockMeshError, ExportError
from blockmesh.io import _ascii
from blockmesh.mesh import Mesh
from blockmesh.refinement import refine

TWO_POINTS = np.array([[0, 0], [2, 0], [2.5, 1], [2, 2], [0, 2], [4, 0], [4.5, 1], [4, 2]], float)
TWO_CELLS = [[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]]
SP = np.array([[-1, -1], [1, -1], [2, 0], [0, 1], [-2, 0]], dtype=float)


def tagged(level: int) -> Mesh:
    """The two-block mesh with three patches and two regions (names with a space and a word)."""
    base = refine(Mesh.from_cells(TWO_POINTS, TWO_CELLS), level)
    xy = base.points[base.boundary_edges]
    on_left = np.all(xy[:, :, 0] < 1e-12, axis=1)
    on_right = np.all(xy[:, :, 0] > 3.9, axis=1)
    patch = np.where(on_left, 1, np.where(on_right, 2, 0))
    return Mesh(
        points=base.points,
        cells=base.cells,
        block_id=base.block_id,
        parent=base.parent,
        boundary_edges=base.boundary_edges,
        boundary_patch=patch,
        patch_names=("outer wall", "inlet", "outlet"),
        region=base.block_id,
        region_names=("left", "right"),
        level=base.level,
        name="two-block",
    )


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


def edges_by_patch(m: Mesh) -> dict[str, set[tuple[int, int]]]:
    return {name: set(map(tuple, m.patch_edges(name).tolist())) for name in m.patch_names}


def assert_same(a: Mesh, b: Mesh, *, parent: bool = True, block: bool = True) -> None:
    np.testing.assert_array_equal(a.points, b.points)
    np.testing.assert_array_equal(a.cells, b.cells)
    np.testing.assert_array_equal(a.region, b.region)
    assert a.region_names == b.region_names
    assert a.patch_names == b.patch_names
    assert edges_by_patch(a) == edges_by_patch(b)
    if block:
        np.testing.assert_array_equal(a.block_id, b.block_id)
    if parent:
        np.testing.assert_array_equal(a.parent, b.parent)


def listing(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir())


# ----------------------------------------------------------------------------- registry
def test_registry_lists_every_format() -> None:
    assert set(bio.FORMATS) == {"vtu", "xdmf", "msh", "mat", "openfoam", "npz"}
    for name, fmt in bio.FORMATS.items():
        assert fmt.name == name and fmt.description and fmt.can_read
        assert fmt.default_compression in fmt.compressions
    assert bio.FORMATS["msh"].needs_split
    assert bio.FORMATS["openfoam"].directory and "dz" in bio.FORMATS["openfoam"].options


@pytest.mark.parametrize(
    ("path", "name"),
    [
        ("a.vtu", "vtu"),
        ("A.VTU", "vtu"),
        ("a.xdmf", "xdmf"),
        ("a.msh", "msh"),
        ("a.mat", "mat"),
        ("a.npz", "npz"),
        ("case/constant/polyMesh", "openfoam"),
    ],
)
def test_format_for_path(path: str, name: str) -> None:
    assert bio.format_for_path(path).name == name


def test_format_for_existing_directory_is_openfoam(tmp_path: Path) -> None:
    assert bio.format_for_path(tmp_path).name == "openfoam"
    assert bio.format_for_path("x.dat", "VTU").name == "vtu"
    assert bio.format_for_path("x.dat", ".msh").name == "msh"


def test_unknown_extension_lists_formats(mesh: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ExportError) as info:
        bio.write(mesh, tmp_path / "mesh.stl")
    msg = str(info.value)
    assert "'.stl'" in msg
    for ext in (".vtu", ".xdmf", ".msh", ".mat", ".npz", "polyMesh"):
        assert ext in msg
    assert "--format vtu|xdmf|msh|mat|openfoam|npz" in msg
    assert not any(tmp_path.iterdir())
    assert isinstance(info.value, BlockMeshError)


def test_unknown_format_name(mesh: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ExportError, match=r"unknown format 'stl'.*--format vtu\|xdmf"):
        bio.write(mesh, tmp_path / "x", format="stl")


def test_missing_directory_is_named(mesh: Mesh, tmp_path: Path) -> None:
    missing = tmp_path / "no" / "such"
    with pytest.raises(ExportError, match=f"the directory {missing} does not exist"):
        bio.write(mesh, missing / "mesh.vtu")
    with pytest.raises(ExportError, match="does not exist"):
        bio.write(mesh, missing / "case", format="openfoam")


def test_options_are_checked(mesh: Mesh, tmp_path: Path) -> None:
    with pytest.raises(ExportError, match=r"--split tri5\|tri3\|quad5"):
        bio.write(mesh, tmp_path / "m.msh")
    with pytest.raises(ExportError, match="split 'tri4' is not available.*tri5, tri3, quad5"):
        bio.write(mesh, tmp_path / "m.msh", split="tri4")
    with pytest.raises(ExportError, match="applies to msh only"):
        bio.write(mesh, tmp_path / "m.vtu", split="tri5")
    with pytest.raises(
        ExportError, match="compression 'lzma' is not available for xdmf.*none, zlib"
    ):
        bio.write(mesh, tmp_path / "m.xdmf", compression="lzma")
    with pytest.raises(ExportError, match="option dz is not known to the vtu writer"):
        bio.write(mesh, tmp_path / "m.vtu", dz=1.0)
    with pytest.raises(ExportError, match="takes a blockmesh Mesh"):
        bio.write("not a mesh", tmp_path / "m.vtu")
    with pytest.raises(ExportError, match="it is a directory"):
        bio.write(mesh, tmp_path, format="vtu")
    assert listing(tmp_path) == []


def test_read_errors(tmp_path: Path) -> None:
    with pytest.raises(ExportError, match="does not exist"):
        bio.read(tmp_path / "none.vtu")
    bad = tmp_path / "bad.msh"
    bad.write_text("$MeshFormat\n4.1 1 8\n$EndMeshFormat\n")
    with pytest.raises(ExportError, match="binary"):
        bio.read(bad)


# ---------------------------------------------------------------------------------- VTU
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


# --------------------------------------------------------------------------------- XDMF
@pytest.mark.parametrize("compression", [None, "zlib"])
def test_xdmf_through_h5py(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    import h5py

    path = bio.write(mesh, tmp_path / "m.xdmf", compression=compression)
    assert listing(tmp_path) == ["m.h5", "m.xdmf"]
    root = ET.parse(path).getroot()
    assert root.tag == "Xdmf" and root.get("Version") == "3.0"
    grids = {g.get("Name"): g for g in root.iter("Grid") if g.get("GridType") == "Uniform"}
    top = grids["cells"].find("Topology")
    assert top is not None
    assert (top.get("TopologyType"), top.get("NodesPerElement")) == ("Polygon", "5")
    assert top.get("NumberOfElements") == str(mesh.n_cells)
    assert grids["cells"].find("Geometry").get("GeometryType") == "XY"
    centres = {a.get("Name"): a.get("Center") for a in grids["cells"].iter("Attribute")}
    assert centres == {"block_id": "Cell", "region": "Cell", "parent": "Cell"}
    assert grids["boundary"].find("Topology").get("TopologyType") == "Polyline"
    with h5py.File(tmp_path / "m.h5", "r") as f:
        np.testing.assert_array_equal(f["mesh/points"][()], mesh.points)
        np.testing.assert_array_equal(f["mesh/cells"][()], mesh.cells)
        np.testing.assert_array_equal(f["boundary/edges"][()], mesh.boundary_edges)
        np.testing.assert_array_equal(f["boundary/patch"][()], mesh.boundary_patch)
        assert json.loads(f.attrs["blockmesh"])["patch_names"] == list(mesh.patch_names)
        assert f["mesh/cells"].compression == ("gzip" if compression == "zlib" else None)
    assert_same(bio.read(path), mesh)


def test_vtk_reads_vtu_and_xdmf(mesh: Mesh, tmp_path: Path) -> None:
    """ParaView's readers (VTK's XML reader and XDMF reader), when the vtk package is present."""
    xdmf_reader = pytest.importorskip("vtkmodules.vtkIOXdmf2").vtkXdmfReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonCore import vtkIdList
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader

    def connectivity(grid: object) -> list[list[int]]:
        ids = vtkIdList()
        rows = []
        for c in range(grid.GetNumberOfCells()):
            grid.GetCellPoints(c, ids)
            rows.append([ids.GetId(k) for k in range(ids.GetNumberOfIds())])
        return rows

    r = vtkXMLUnstructuredGridReader()
    r.SetFileName(str(bio.write(mesh, tmp_path / "m.vtu")))
    r.Update()
    grid = r.GetOutput()
    assert grid.GetNumberOfCells() == mesh.n_cells + mesh.boundary_edges.shape[0]
    rows = connectivity(grid)
    assert rows[: mesh.n_cells] == mesh.cells.tolist()
    assert rows[mesh.n_cells :] == mesh.boundary_edges.tolist()
    meta = bytes(vtk_to_numpy(grid.GetFieldData().GetArray("blockmesh"))).decode()
    assert json.loads(meta)["region_names"] == list(mesh.region_names)

    x = xdmf_reader()
    x.SetFileName(str(bio.write(mesh, tmp_path / "m.xdmf")))
    x.Update()
    blocks = x.GetOutputDataObject(0)
    cells, lines = blocks.GetBlock(0), blocks.GetBlock(1)
    assert {cells.GetCellType(i) for i in range(cells.GetNumberOfCells())} == {7}  # polygon
    assert connectivity(cells) == mesh.cells.tolist()
    np.testing.assert_array_equal(vtk_to_numpy(cells.GetCellData().GetArray("region")), mesh.region)
    assert connectivity(lines) == mesh.boundary_edges.tolist()
    patch = vtk_to_numpy(lines.GetCellData().GetArray("patch"))
    np.testing.assert_array_equal(patch, mesh.boundary_patch)


# ---------------------------------------------------------------------------------- MSH
def gmsh_summary(path: Path) -> dict:
    gmsh = pytest.importorskip("gmsh")
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(str(path))
        groups = {}
        for dim, tag in gmsh.model.getPhysicalGroups():
            count = 0
            for ent in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
                count += sum(len(t) for t in gmsh.model.mesh.getElements(dim, ent)[1])
            groups[(dim, gmsh.model.getPhysicalName(dim, tag))] = count
        types, elem_tags, _ = gmsh.model.mesh.getElements(2)
        views = gmsh.view.getTags()
        names = [gmsh.option.getString(f"View[{gmsh.view.getIndex(v)}].Name") for v in views]
        _, data_tags, data, _, _ = gmsh.view.getModelData(views[names.index("parent")], 0)
        parent = dict(zip(np.asarray(data_tags).tolist(), np.ravel(data).tolist(), strict=True))
        return {
            "groups": groups,
            "types": list(types),
            "elements": [len(t) for t in elem_tags],
            "element_tags": np.concatenate(elem_tags),
            "nodes": len(gmsh.model.mesh.getNodes()[0]),
            "parent": parent,
        }
    finally:
        gmsh.finalize()


@pytest.mark.parametrize(
    ("split", "gmsh_type", "per_cell", "new_nodes", "lines_per_edge"),
    [("tri5", 2, 5, "cells", 1), ("tri3", 2, 3, "none", 1), ("quad5", 3, 5, "edges+cells", 2)],
)
def test_msh_through_gmsh(
    mesh: Mesh,
    tmp_path: Path,
    split: str,
    gmsh_type: int,
    per_cell: int,
    new_nodes: str,
    lines_per_edge: int,
) -> None:
    path = bio.write(mesh, tmp_path / "m.msh", split=split)
    info = gmsh_summary(path)
    m = mesh.n_cells
    extra = {"cells": m, "none": 0, "edges+cells": mesh.n_edges + m}[new_nodes]
    assert info["nodes"] == mesh.n_points + extra
    assert info["types"] == [gmsh_type] and info["elements"] == [per_cell * m]
    for k, name in enumerate(mesh.patch_names):
        edges = int(np.count_nonzero(mesh.boundary_patch == k))
        assert info["groups"][(1, name)] == lines_per_edge * edges
    for k, name in enumerate(mesh.region_names):
        assert info["groups"][(2, name)] == per_cell * int(np.count_nonzero(mesh.region == k))
    # the "parent" view: every element's pentagon, each pentagon with per_cell children
    parent = np.array([info["parent"][t] for t in info["element_tags"].tolist()], dtype=int)
    np.testing.assert_array_equal(np.bincount(parent, minlength=m), np.full(m, per_cell))
    assert_same(bio.read(path), mesh, parent=False)


def test_msh_blocks_spanning_regions(mesh: Mesh, tmp_path: Path) -> None:
    """A block whose cells lie in two regions gets one surface entity per (block, region)."""
    mixed = Mesh(
        points=mesh.points,
        cells=mesh.cells,
        block_id=mesh.block_id,
        parent=mesh.parent,
        boundary_edges=mesh.boundary_edges,
        boundary_patch=mesh.boundary_patch,
        patch_names=mesh.patch_names,
        region=np.arange(mesh.n_cells) % 2,
        region_names=("even", "odd"),
    )
    path = bio.write(mixed, tmp_path / "m.msh", split="tri3")
    info = gmsh_summary(path)
    assert info["groups"][(2, "even")] == 3 * ((mesh.n_cells + 1) // 2)
    assert_same(bio.read(path), mixed, parent=False)


def test_msh_children_tile_their_parent(mesh: Mesh) -> None:
    from blockmesh.geometry import signed_area

    for split in bio.SPLITS:
        s = bio.split_cells(mesh, split)
        area = signed_area(s.points[s.cells])
        assert np.all(area > 0), split
        np.testing.assert_allclose(
            np.bincount(s.parent, weights=area), mesh.cell_areas(), rtol=1e-12
        )


def test_quad5_is_conforming(mesh: Mesh) -> None:
    s = bio.split_cells(mesh, "quad5")
    n = s.points.shape[0]
    a, b = s.cells, np.roll(s.cells, -1, axis=1)
    _, counts = np.unique(np.minimum(a, b) * n + np.maximum(a, b), return_counts=True)
    lines = bio.split_boundary(mesh, "quad5").edges
    assert np.count_nonzero(counts == 1) == lines.shape[0]  # only the boundary halves are free
    assert set(np.unique(counts)) == {1, 2}
    assert np.unique(s.points, axis=0).shape[0] == n  # no duplicate nodes


# ---------------------------------------------------------------------------------- MAT
@pytest.mark.parametrize("compression", [None, "zlib"])
def test_mat_through_scipy(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    import scipy.io

    path = bio.write(mesh, tmp_path / "m.mat", compression=compression)
    data = scipy.io.loadmat(path)
    np.testing.assert_array_equal(data["Node"], mesh.points)
    element = data["Element"]
    assert element.shape == (mesh.n_cells, 1) and element.dtype == object
    assert element[0, 0].shape == (1, 5)
    np.testing.assert_array_equal(np.vstack(element.ravel()), mesh.cells + 1)
    assert data["BoundaryEdges"].dtype.names == ("outer_wall", "inlet", "outlet")
    for k, field in enumerate(data["BoundaryEdges"].dtype.names):
        edges = data["BoundaryEdges"][0, 0][field]
        np.testing.assert_array_equal(edges, mesh.boundary_edges[mesh.boundary_patch == k] + 1)
        nodes = data["BoundaryNodes"][0, 0][field].ravel()
        np.testing.assert_array_equal(nodes, np.unique(edges))
    np.testing.assert_array_equal(data["BlockId"].ravel(), mesh.block_id + 1)
    np.testing.assert_array_equal(data["Region"].ravel(), mesh.region + 1)
    assert [str(s[0]) for s in data["PatchNames"].ravel()] == list(mesh.patch_names)
    assert [str(s[0]) for s in data["RegionNames"].ravel()] == list(mesh.region_names)
    assert_same(bio.read(path), mesh)


# ---------------------------------------------------------------------------------- NPZ
@pytest.mark.parametrize("compression", [None, "zlib"])
def test_npz_is_lossless(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    path = bio.write(mesh, tmp_path / "m.npz", compression=compression)
    with np.load(path, allow_pickle=False) as data:
        for key in ("points", "cells", "block_id", "parent", "boundary_edges", "region"):
            np.testing.assert_array_equal(data[key], getattr(mesh, key))
            assert data[key].dtype == getattr(mesh, key).dtype
        assert tuple(data["patch_names"].tolist()) == mesh.patch_names
    back = bio.read(path)
    assert_same(back, mesh)
    np.testing.assert_array_equal(back.boundary_edges, mesh.boundary_edges)
    assert (back.level, back.name) == (mesh.level, mesh.name)


# -------------------------------------------------------------------- every format at once
@pytest.mark.parametrize("level", [0, 1, 3])
@pytest.mark.parametrize(
    ("name", "kwargs"),
    [
        ("m.vtu", {}),
        ("m.xdmf", {}),
        ("m.msh", {"split": "quad5"}),
        ("m.mat", {}),
        ("m.npz", {}),
        ("case", {"format": "openfoam"}),
    ],
)
def test_round_trip_levels(tmp_path: Path, level: int, name: str, kwargs: dict) -> None:
    m = refine(Mesh.from_cells(SP, [[0, 1, 2, 3, 4]]), level)
    path = bio.write(m, tmp_path / name, **kwargs)
    back = bio.read(path)
    lossy = name in ("case", "m.msh")
    assert_same(back, m, parent=not lossy, block=name != "case")


# ------------------------------------------------------------------------------- atomic
def _writers() -> list[tuple[str, dict, str, str]]:
    """(file name, write kwargs, object to break, attribute) per format."""
    return [
        ("m.vtu", {}, "blockmesh.io.vtu", "_insert_field_data"),
        ("m.xdmf", {}, "blockmesh.io.xdmf", "_xdmf_tree"),
        ("m.msh", {"split": "tri5"}, "blockmesh.io.msh", "_write_blocks"),
        ("m.mat", {}, "scipy.io", "savemat"),
        ("m.npz", {}, "numpy", "savez"),
    ]


@pytest.mark.parametrize("error", [RuntimeError, KeyboardInterrupt])
@pytest.mark.parametrize(("name", "kwargs", "module", "attr"), _writers())
def test_failed_write_keeps_old_file(
    mesh: Mesh,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    name: str,
    kwargs: dict,
    module: str,
    attr: str,
    error: type[BaseException],
) -> None:
    import importlib

    old = bio.write(refine(Mesh.from_cells(SP, [[0, 1, 2, 3, 4]]), 1), tmp_path / name, **kwargs)
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}

    def boom(*args: object, **kw: object) -> None:
        raise error("simulated failure mid-write")

    monkeypatch.setattr(importlib.import_module(module), attr, boom)
    with pytest.raises(error, match="simulated"):
        bio.write(mesh, tmp_path / name, **kwargs)
    after = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    assert after == before  # old file(s) intact, no temporary left
    monkeypatch.undo()
    assert bio.read(old).n_cells == 6


def test_failed_first_write_leaves_nothing(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def boom(*args: object, **kw: object) -> None:
        raise OSError("disk full")

    monkeypatch.setattr(_ascii, "_as_matrix", boom)
    with pytest.raises(OSError, match="disk full"):
        bio.write(mesh, tmp_path / "m.msh", split="tri3")
    assert listing(tmp_path) == []


def test_pair_rename_failure_restores_old_pair(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    bio.write(refine(Mesh.from_cells(SP, [[0, 1, 2, 3, 4]]), 1), tmp_path / "m.xdmf")
    before = {p.name: p.read_bytes() for p in tmp_path.iterdir()}
    real = os.replace
    calls = []

    def flaky(src: object, dst: object) -> None:
        calls.append(dst)
        if len(calls) == 2:  # the second target: the first is already renamed in
            raise OSError("rename failed")
        real(src, dst)

    monkeypatch.setattr(_safe.os, "replace", flaky)
    with pytest.raises(OSError, match="rename failed"):
        bio.write(mesh, tmp_path / "m.xdmf")
    monkeypatch.undo()
    assert {p.name: p.read_bytes() for p in tmp_path.iterdir()} == before
    assert bio.read(tmp_path / "m.xdmf").n_cells == 6


def test_new_files_get_normal_permissions(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.npz")
    umask = _safe._umask()
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask


# ------------------------------------------------------------------------- ASCII helpers
@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(-(2**62), 2**62), min_size=1, max_size=40))
def test_int_bytes_matches_str(values: list[int]) -> None:
    rows = _ascii.int_bytes(np.array(values, dtype=np.int64))
    assert [bytes(r[r != 0]).decode() for r in rows] == [str(v) for v in values]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=40))
def test_float_bytes_round_trips_exactly(values: list[float]) -> None:
    x = np.array(values, dtype=np.float64)
    texts = [bytes(r[r != 0]).decode() for r in _ascii.float_bytes(x)]
    back = np.array([float(t) for t in texts])
    np.testing.assert_array_equal(back.view(np.int64), (x + 0.0).view(np.int64))
    assert all(len(t) <= 24 and " " not in t for t in texts)


def test_write_rows_layout() -> None:
    buf = _io.BytesIO()
    _ascii.write_rows(buf, [b"4(", np.array([[1, 22, 333, 0]]), b") ", np.array([0.5]), b"\n"])
    assert buf.getvalue() == b"4(1 22 333 0) 5e-1\n"
