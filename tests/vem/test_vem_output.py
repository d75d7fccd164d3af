"""Solution files: VTU of mixed polygon meshes read back by meshio, XDMF limits, bad paths."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

from blockmesh.errors import ExportError
from blockmesh.vem import PolygonMesh, solve_poisson, write_solution

POINTS = [(0, 0), (1, 0), (2, 0), (0, 1), (1, 1), (2, 1), (0, 2), (1, 2), (2, 2), (1.5, 1.6)]
CELLS = [[0, 1, 4], [0, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 9], [4, 9, 8, 7]]


def _solution():
    mesh = PolygonMesh.from_cells(POINTS, CELLS)
    return solve_poisson(mesh, 1.0, dirichlet={"boundary": "x + y"})


def test_mixed_mesh_vtu_round_trip(tmp_path):
    sol = _solution()
    path = write_solution(sol, tmp_path / "mixed.vtu", extra_point_data={"twice": 2 * sol.values})
    back = meshio.read(path)
    assert sorted(block.type for block in back.cells) == ["quad", "triangle"]
    assert np.array_equal(back.point_data["u"], sol.values)
    assert np.array_equal(back.point_data["twice"], 2 * sol.values)
    gradients = np.concatenate(back.cell_data["gradient"])[:, :2]
    order = np.concatenate([g.index for g in sol.mesh.groups])
    assert np.array_equal(gradients, sol.cell_gradient[order])


def test_xdmf_needs_one_cell_size_and_paths_are_checked(tmp_path):
    sol = _solution()
    with pytest.raises(ExportError, match="XDMF here takes cells of one size"):
        write_solution(sol, tmp_path / "mixed.xdmf")
    with pytest.raises(ExportError, match="use a .vtu file"):
        write_solution(sol, tmp_path / "mixed.msh")
    with pytest.raises(ExportError, match="does not exist"):
        write_solution(sol, tmp_path / "missing" / "u.vtu")
    with pytest.raises(ExportError, match="point data 'bad' has 3 values"):
        write_solution(sol, tmp_path / "u.vtu", extra_point_data={"bad": np.zeros(3)})
    assert not list(tmp_path.iterdir())  # nothing half-written
