"""MATLAB .mat: read by scipy.io.loadmat as PolyMesher/VEM codes see it; fast read-back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from helpers_io import assert_same, tagged

import blockmesh.io as bio
from blockmesh.io.mat.format import matlab_name
from blockmesh.mesh import Mesh


@pytest.fixture(scope="module")
def mesh() -> Mesh:
    return tagged(2)


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
    np.testing.assert_array_equal(data["Parent"].ravel(), mesh.parent + 1)
    assert [str(s[0]) for s in data["PatchNames"].ravel()] == list(mesh.patch_names)
    assert [str(s[0]) for s in data["RegionNames"].ravel()] == list(mesh.region_names)
    assert_same(bio.read(path), mesh)


def test_mat_written_by_scipy_is_read(mesh: Mesh, tmp_path: Path) -> None:
    """A PolyMesher-style file (Node, Element) saved by another program: scipy reads Element."""
    import scipy.io

    element = np.empty((mesh.n_cells, 1), dtype=object)
    for k, row in enumerate(mesh.cells + 1.0):
        element[k, 0] = row.reshape(1, 5)
    scipy.io.savemat(tmp_path / "p.mat", {"Node": mesh.points, "Element": element})
    back = bio.read(tmp_path / "p.mat")
    np.testing.assert_array_equal(back.cells, mesh.cells)
    assert back.patch_names == ("boundary",)


def test_struct_field_names() -> None:
    assert matlab_name("outer wall") == "outer_wall" and matlab_name("2nd") == "p_2nd"
    assert len(matlab_name("x" * 100)) == 63


@pytest.mark.parametrize("compression", ["none", "zlib"])
def test_element_is_read_without_scipy(mesh: Mesh, tmp_path: Path, compression: str) -> None:
    """The Element cell array of blockmesh's files is read in chunks, not by scipy (30 s at
    level 8): the fast path must recognise both layouts."""
    import blockmesh.io.mat.format as mat

    path = bio.write(mesh, tmp_path / "m.mat", compression=compression)
    cells = mat._element_cells(path)
    assert cells is not None
    np.testing.assert_array_equal(cells, mesh.cells)
