"""XDMF + HDF5: layout (h5py, ElementTree), VTK's and ParaView's readers, the atomic pair."""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from helpers import slow_except
from helpers_io import (
    assert_same,
    expected_names,
    listing,
    paraview_names,
    patch_atomic_os,
    run_pvpython,
    snapshot,
    sp_mesh,
    tagged,
    vtk_connectivity,
)

import blockmesh.io as bio
from blockmesh.errors import ExportError
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


def h5_of(path: Path) -> Path:
    """The .h5 file the .xdmf file names."""
    root = ET.parse(path).getroot()
    item = root.find(".//Geometry/DataItem")
    assert item is not None and item.text is not None
    return path.parent / item.text.strip().partition(":")[0]


@pytest.mark.parametrize("compression", [None, "zlib"])
def test_xdmf_through_h5py(mesh: Mesh, tmp_path: Path, compression: str | None) -> None:
    import h5py

    path = bio.write(mesh, tmp_path / "m.xdmf", compression=compression)
    h5 = h5_of(path)
    assert listing(tmp_path) == sorted([h5.name, "m.xdmf"])
    assert h5.name.startswith("m.") and h5.suffix == ".h5" and len(h5.name) == len("m.01234567.h5")
    root = ET.parse(path).getroot()
    assert root.tag == "Xdmf" and root.get("Version") == "3.0"
    grids = root.findall("Domain/Grid")
    assert len(grids) == 1 and grids[0].get("GridType") == "Uniform"  # one grid, as meshio wants
    grid = grids[0]
    top = grid.find("Topology")
    assert top is not None
    m, eb = mesh.n_cells, mesh.boundary_edges.shape[0]
    assert (top.get("TopologyType"), top.get("NumberOfElements")) == ("Mixed", str(m + eb))
    assert grid.find("Geometry").get("GeometryType") == "XY"
    centres = {a.get("Name"): a.get("Center") for a in grid.iter("Attribute")}
    assert {k: v for k, v in centres.items() if v == "Cell"} == dict.fromkeys(
        ("block_id", "region", "parent", "patch"), "Cell"
    )
    lookups = {
        a.get("Name"): int(a.find("DataItem").text)
        for a in grid.iter("Attribute")
        if a.get("Center") == "Grid"
    }
    assert lookups == expected_names(mesh)
    with h5py.File(h5, "r") as f:
        np.testing.assert_array_equal(f["mesh/points"][()], mesh.points)
        top = f["mesh/topology"][()]
        np.testing.assert_array_equal(top[: 7 * m].reshape(m, 7)[:, 2:], mesh.cells)
        assert set(top[: 7 * m].reshape(m, 7)[:, 0]) == {3}  # XDMF polygon
        np.testing.assert_array_equal(top[7 * m :].reshape(eb, 4)[:, 2:], mesh.boundary_edges)
        np.testing.assert_array_equal(f["mesh/patch"][m:], mesh.boundary_patch)
        np.testing.assert_array_equal(f["mesh/region"][:m], mesh.region)
        assert np.all(f["mesh/region"][m:] == -1) and np.all(f["mesh/patch"][:m] == -1)
        meta = json.loads(f.attrs["blockmesh"])
        assert meta["patch_names"] == list(mesh.patch_names) and meta["light"] == "m.xdmf"
        assert f["mesh/topology"].compression == ("gzip" if compression == "zlib" else None)
    assert_same(bio.read(path), mesh)


def test_vtk_xdmf_reader(mesh: Mesh, tmp_path: Path) -> None:
    """VTK's XDMF (2) reader reads the mixed grid as one unstructured grid."""
    xdmf = pytest.importorskip("vtkmodules.vtkIOXdmf2", reason="the vtk package is absent")
    from vtkmodules.util.numpy_support import vtk_to_numpy

    x = xdmf.vtkXdmfReader()
    x.SetFileName(str(bio.write(mesh, tmp_path / "m.xdmf")))
    x.Update()
    grid = x.GetOutputDataObject(0)
    m = mesh.n_cells
    assert {grid.GetCellType(i) for i in range(m)} == {7}  # polygon
    rows = vtk_connectivity(grid)
    assert rows[:m] == mesh.cells.tolist() and rows[m:] == mesh.boundary_edges.tolist()
    np.testing.assert_array_equal(
        vtk_to_numpy(grid.GetCellData().GetArray("region"))[:m], mesh.region
    )
    patch = vtk_to_numpy(grid.GetCellData().GetArray("patch"))
    np.testing.assert_array_equal(patch[m:], mesh.boundary_patch)
    fields = grid.GetFieldData()
    names = {fields.GetArrayName(i) for i in range(fields.GetNumberOfArrays())}
    assert names == set(expected_names(mesh))


def test_paraview_shows_the_names(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.xdmf")
    cells, names = paraview_names(path)
    assert cells == mesh.n_cells + mesh.boundary_edges.shape[0]
    assert names == expected_names(mesh)


@pytest.mark.parametrize("how", slow_except(["./m.xdmf", "absolute"], "./m.xdmf"))
def test_paraview_opens_it_as_the_readme_says(mesh: Mesh, tmp_path: Path, how: str) -> None:
    """ParaView's XDMF 3 reader with a path that names the folder (the export page's advice)."""
    bio.write(mesh, tmp_path / "m.xdmf")
    name = str(tmp_path / "m.xdmf") if how == "absolute" else how
    script = (
        "from paraview.simple import OpenDataFile\n"
        f"r = OpenDataFile({name!r}); r.UpdatePipeline()\n"
        "print('CELLS', r.GetDataInformation().GetNumberOfCells())\n"
    )
    run = run_pvpython(script, tmp_path)
    assert run.returncode == 0, run.stdout + run.stderr
    assert f"CELLS {mesh.n_cells + mesh.boundary_edges.shape[0]}" in run.stdout


def test_meshio_cannot_read_polygons_from_xdmf(mesh: Mesh, tmp_path: Path) -> None:
    """meshio's XDMF reader knows no polygon cells (Mixed type 3): it fails, but no longer
    exits the interpreter ("Only supports one grid"), since the file is one grid."""
    import meshio

    path = bio.write(mesh, tmp_path / "m.xdmf")
    with pytest.raises(KeyError):
        meshio.read(path)


def test_old_layout_is_still_read(mesh: Mesh, tmp_path: Path) -> None:
    """Files of blockmesh 0.1: a collection of a Polygon grid and a Polyline grid, m.h5."""
    import h5py

    meta = json.dumps(
        {
            "patch_names": list(mesh.patch_names),
            "region_names": list(mesh.region_names),
            "level": 2,
            "name": "two-block",
        }
    )
    with h5py.File(tmp_path / "m.h5", "w") as f:
        f.attrs["blockmesh"] = meta
        for key, value in (
            ("mesh/points", mesh.points),
            ("mesh/cells", mesh.cells),
            ("mesh/block_id", mesh.block_id),
            ("mesh/region", mesh.region),
            ("mesh/parent", mesh.parent),
            ("boundary/edges", mesh.boundary_edges),
            ("boundary/patch", mesh.boundary_patch),
        ):
            f[key] = value
    n, m, eb = mesh.n_points, mesh.n_cells, mesh.boundary_edges.shape[0]

    def item(dataset: str, dims: str, kind: str = "Int") -> str:
        return (
            f'<DataItem Dimensions="{dims}" NumberType="{kind}" Precision="8" Format="HDF">'
            f"m.h5:{dataset}</DataItem>"
        )

    def grid(name: str, topology: str, nodes: int, count: int, conn: str) -> str:
        return (
            f'<Grid Name="{name}"><Topology TopologyType="{topology}" NodesPerElement="{nodes}" '
            f'NumberOfElements="{count}">{item(conn, f"{count} {nodes}")}</Topology>'
            f'<Geometry GeometryType="XY">{item("/mesh/points", f"{n} 2", "Float")}</Geometry>'
        )

    attrs = "".join(
        f'<Attribute Name="{a}" Center="Cell">{item("/mesh/" + a, str(m))}</Attribute>'
        for a in ("block_id", "region", "parent")
    )
    (tmp_path / "m.xdmf").write_text(
        f'<Xdmf Version="3.0"><Domain><Information Name="blockmesh" Value=\'{meta}\'/>'
        '<Grid Name="two-block" GridType="Collection" CollectionType="Spatial">'
        + grid("cells", "Polygon", 5, m, "/mesh/cells")
        + f"{attrs}</Grid>"
        + grid("boundary", "Polyline", 2, eb, "/boundary/edges")
        + f'<Attribute Name="patch" Center="Cell">{item("/boundary/patch", str(eb))}</Attribute>'
        + "</Grid></Grid></Domain></Xdmf>"
    )
    assert_same(bio.read(tmp_path / "m.xdmf"), mesh)
    bio.write(sp_mesh(1), tmp_path / "m.xdmf")  # rewriting replaces the old pair whole
    assert "m.h5" not in listing(tmp_path) and len(listing(tmp_path)) == 2
    assert bio.read(tmp_path / "m.xdmf").n_cells == 6


# --------------------------------------------------------------------- the atomic pair
def test_a_pair_from_two_writes_is_refused(mesh: Mesh, tmp_path: Path) -> None:
    (tmp_path / "a").mkdir()
    old = bio.write(sp_mesh(1), tmp_path / "a" / "m.xdmf")
    new = bio.write(mesh, tmp_path / "m.xdmf")
    h5_of(old).replace(h5_of(new))  # someone copies the old data file over the new one
    with pytest.raises(
        ExportError, match="do not belong together: they come from different writes"
    ):
        bio.read(new)


def test_missing_data_file_is_named(mesh: Mesh, tmp_path: Path) -> None:
    path = bio.write(mesh, tmp_path / "m.xdmf")
    h5_of(path).unlink()
    pattern = r"refers to the HDF5 file 'm\.[0-9a-f]{8}\.h5', which is not a regular file in"
    with pytest.raises(ExportError, match=pattern):
        bio.read(path)


@pytest.mark.parametrize("at_call", [1, 2])
def test_failure_between_the_renames_leaves_the_old_pair(
    mesh: Mesh, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, at_call: int
) -> None:
    """The data file is renamed in first, the light file last: the old pair stays whole."""
    import os

    bio.write(sp_mesh(1), tmp_path / "m.xdmf")
    before = snapshot(tmp_path)
    calls: list[object] = []

    def flaky(src: object, dst: object) -> None:
        calls.append(dst)
        if len(calls) == at_call:
            raise OSError(5, "rename failed")
        os.replace(src, dst)

    patch_atomic_os(monkeypatch, replace=flaky)
    with pytest.raises(ExportError, match="rename failed|Input/output error"):
        bio.write(mesh, tmp_path / "m.xdmf")
    monkeypatch.undo()
    assert snapshot(tmp_path) == before
    assert bio.read(tmp_path / "m.xdmf").n_cells == 6


KILLED = """
import os, sys
sys.path.insert(0, {tests!r})
import blockmesh.io as bio
from blockmesh._system import atomic
from helpers_io import tagged
real, calls = os.replace, []
def replace(src, dst):
    calls.append(dst)
    if len(calls) == {at_call}:
        os._exit(137)  # killed: nothing after this runs, no clean-up
    real(src, dst)
class Os:
    def __getattr__(self, name):
        return replace if name == "replace" else getattr(os, name)
atomic.os = Os()
bio.write(tagged(2), {path!r})
os._exit(0)
"""


@pytest.mark.parametrize("at_call", slow_except([1, 2, 3], 2))
def test_killed_between_the_renames(mesh: Mesh, tmp_path: Path, at_call: int) -> None:
    """A process killed at the first or second rename (or after): old or new pair, never a mix;
    the next write removes what the killed one left."""
    path = tmp_path / "m.xdmf"
    bio.write(sp_mesh(1), path)
    script = KILLED.format(tests=str(Path(__file__).parents[1]), at_call=at_call, path=str(path))
    run = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(script)], capture_output=True, timeout=300
    )
    assert run.returncode in (0, 137), run.stderr.decode()
    back = bio.read(path)
    assert back.n_cells == (6 if at_call <= 2 else mesh.n_cells)  # the commit is the 2nd rename
    if run.returncode == 137:
        assert len(listing(tmp_path)) > 2  # leftovers of the killed write
    bio.write(sp_mesh(2), path)
    assert len(listing(tmp_path)) == 2 and not [p for p in tmp_path.glob(".*")]
    assert bio.read(path).n_cells == 36
