"""Writing a solution for ParaView: VTU (meshio) or XDMF + HDF5 (h5py), with its data.

The mesh writers of :mod:`blockmesh.io` write the mesh and its block/region/patch numbers but
take no solution fields, so the solution is written here, the same way (atomically: a temporary
file renamed into place). The files hold the cells (polygons; triangles and quadrilaterals under
their own VTK types) and

==================  ==========  ===================================================
array               where       what
==================  ==========  ===================================================
``u``               points      the nodal values (diffusion-reaction)
``gradient``        cells       ``∇Π∇u_h`` (x, y, 0)
``displacement``    points      (u_x, u_y, 0) (elasticity; ParaView's "Warp By Vector")
``stress``          cells       (σ_xx, σ_yy, σ_xy)
``von_mises``       cells       the von Mises stress
``error``           points      ``u_h - u`` at the nodes, when an exact solution is given
``region``          cells       index into the region names
``patch``           points      the patch of a boundary node (a corner: the first patch in
                                the mesh's order), -1 inside
``interface``       points      the interface of a node on one, -1 elsewhere (only when the
                                mesh has interfaces)
==================  ==========  ===================================================

The VTU also holds the names as field data, as the mesh files do: ``region:NAME``,
``patch:NAME`` and ``interface:NAME``, whose value is the index the arrays use.

Examples
--------
>>> import pathlib, tempfile
>>> import blockmesh, meshio
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("square").mesh(1)
>>> sol = solve_poisson(mesh, 1.0, dirichlet={"left": 0})
>>> path = write_solution(sol, pathlib.Path(tempfile.mkdtemp()) / "u.vtu")
>>> back = meshio.read(path)
>>> sorted(back.point_data), sorted(back.cell_data)
(['patch', 'u'], ['gradient', 'region'])
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.atomic import atomic_file, atomic_with_data, scratch_file
from blockmesh.errors import ExportError
from blockmesh.io.common import name_lookup
from blockmesh.io.vtu.format import insert_field_data
from blockmesh.vem.elasticity import ElasticitySolution
from blockmesh.vem.poisson import PoissonSolution
from blockmesh.vem.polygons import PolygonMesh

__all__ = ["SOLUTION_FORMATS", "solution_fields", "write_solution"]

#: Extensions a solution can be written to.
SOLUTION_FORMATS = (".vtu", ".xdmf")

_VTK_TYPES = {3: "triangle", 4: "quad"}
_XDMF_TYPES = {3: "Triangle", 4: "Quadrilateral"}

Solution = PoissonSolution | ElasticitySolution


def _padded(vectors: np.ndarray) -> np.ndarray:
    return np.column_stack([vectors, np.zeros(vectors.shape[0])])


def solution_fields(
    solution: Solution, extra_point_data: dict[str, np.ndarray] | None = None
) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
    """The point data and the cell data (in the mesh's cell order) of a solution."""
    if isinstance(solution, PoissonSolution):
        point = {"u": np.asarray(solution.values)}
        cell = {"gradient": _padded(solution.cell_gradient)}
    elif isinstance(solution, ElasticitySolution):
        point = {"displacement": _padded(solution.displacement)}
        cell = {"stress": np.asarray(solution.stress), "von_mises": solution.von_mises}
    else:
        raise ExportError(
            f"write_solution takes a PoissonSolution or ElasticitySolution, not "
            f"{type(solution).__name__}"
        )
    cell["region"] = np.asarray(solution.mesh.region, dtype=np.int64)
    point.update(_node_labels(solution.mesh))
    for name, values in (extra_point_data or {}).items():
        array = np.asarray(values, dtype=np.float64)
        if array.shape[0] != solution.mesh.n_points:
            raise ExportError(
                f"point data {name!r} has {array.shape[0]} values for {solution.mesh.n_points} "
                "nodes"
            )
        point[name] = array
    return point, cell


def _node_labels(mesh: PolygonMesh) -> dict[str, np.ndarray]:
    """``patch`` (and ``interface``) of every node, -1 where none applies."""
    out = {}
    patch = np.full(mesh.n_points, -1, dtype=np.int64)
    for k in range(len(mesh.patch_names) - 1, -1, -1):  # the first patch wins at a corner
        patch[mesh.boundary_edges[mesh.boundary_patch == k]] = k
    out["patch"] = patch
    if mesh.interface_names:
        interface = np.full(mesh.n_points, -1, dtype=np.int64)
        for k in range(len(mesh.interface_names) - 1, -1, -1):
            interface[mesh.interface_edges[mesh.interface_patch == k]] = k
        out["interface"] = interface
    return out


def _names(mesh: PolygonMesh) -> dict[str, np.ndarray]:
    """The name lookups ``KIND:NAME`` -> index of the regions, patches and interfaces."""
    out = {}
    for kind, names in (
        ("region", mesh.region_names),
        ("patch", mesh.patch_names),
        ("interface", mesh.interface_names),
    ):
        out.update({k: np.array([v], dtype=np.int64) for k, v in name_lookup(kind, names).items()})
    return out


def write_solution(
    solution: Solution,
    path: str | Path,
    *,
    extra_point_data: dict[str, np.ndarray] | None = None,
) -> Path:
    """Write the mesh and the solution to ``path`` (``.vtu``, or ``.xdmf`` with a ``.h5``).

    Returns the absolute path. Raises ExportError for another extension, or for XDMF on a mesh
    whose cells do not all have the same number of vertices.
    """
    path = Path(path).absolute()
    suffix = path.suffix.lower()
    point, cell = solution_fields(solution, extra_point_data)
    if suffix == ".vtu":
        return _write_vtu(solution.mesh, path, point, cell)
    if suffix in (".xdmf", ".xmf"):
        return _write_xdmf(solution.mesh, path, point, cell)
    raise ExportError(
        f"cannot write a solution to {path.name}: use a .vtu file (ParaView) or .xdmf (with a "
        ".h5 beside it)"
    )


def _write_vtu(
    mesh: PolygonMesh, path: Path, point: dict[str, Any], cell: dict[str, np.ndarray]
) -> Path:
    import meshio

    blocks = [(_VTK_TYPES.get(g.size, "polygon"), g.cells) for g in mesh.groups]
    cell_data = {name: [values[g.index] for g in mesh.groups] for name, values in cell.items()}
    out = meshio.Mesh(
        np.column_stack([mesh.points, np.zeros(mesh.n_points)]),
        blocks,
        point_data=point,
        cell_data=cell_data,
    )
    with atomic_file(path) as final, scratch_file(path) as raw:
        meshio.vtu.write(str(raw), out, binary=True, compression="zlib")
        insert_field_data(raw, final, _names(mesh))
    return path


def _write_xdmf(
    mesh: PolygonMesh, path: Path, point: dict[str, Any], cell: dict[str, np.ndarray]
) -> Path:
    import h5py

    if len(mesh.groups) != 1:
        sizes = ", ".join(str(g.size) for g in mesh.groups)
        raise ExportError(
            f"cannot write {path.name}: XDMF here takes cells of one size, this mesh has cells "
            f"of {sizes} vertices; write a .vtu file instead"
        )
    group = mesh.groups[0]
    order = np.argsort(group.index)  # cells in the mesh's order
    owned = _owned_by(path.name)
    with atomic_with_data(path, ".h5", owned=owned) as (tmp_xdmf, tmp_h5, h5):
        with h5py.File(tmp_h5, "w") as f:
            f.attrs[_OWNER] = path.name
            f.create_dataset("points", data=mesh.points)
            f.create_dataset("cells", data=group.cells[order])
            for name, values in point.items():
                f.create_dataset(f"point/{name}", data=values)
            for name, values in cell.items():
                f.create_dataset(f"cell/{name}", data=values)
        tree = _xdmf_tree(mesh, group.size, group.n_cells, h5.name, point, cell)
        with open(tmp_xdmf, "wb") as out:
            out.write(b'<?xml version="1.0" encoding="utf-8"?>\n')
            tree.write(out, encoding="utf-8", xml_declaration=False)
            out.write(b"\n")
    return path


#: HDF5 attribute naming the ``.xdmf`` file a data file belongs to (so old ones can be removed).
_OWNER = "blockmesh_solution_of"


def _owned_by(light: str) -> Callable[[Path], bool]:
    """Whether an ``.h5`` file is the data file of an earlier solution written to ``light``."""

    def owned(candidate: Path) -> bool:
        import h5py

        try:
            with h5py.File(candidate, "r") as f:
                return bool(f.attrs.get(_OWNER) == light)
        except Exception:  # not an HDF5 file, or a damaged one: not ours to remove
            return False

    return owned


def _item(parent: ET.Element, h5name: str, dataset: str, array: np.ndarray) -> None:
    item = ET.SubElement(
        parent,
        "DataItem",
        Dimensions=" ".join(str(s) for s in array.shape),
        NumberType="Float" if array.dtype.kind == "f" else "Int",
        Precision=str(array.dtype.itemsize),
        Format="HDF",
    )
    item.text = f"{h5name}:/{dataset}"


def _xdmf_tree(
    mesh: PolygonMesh,
    size: int,
    n_cells: int,
    h5name: str,
    point: dict[str, Any],
    cell: dict[str, np.ndarray],
) -> ET.ElementTree:
    root = ET.Element("Xdmf", Version="3.0")
    grid = ET.SubElement(ET.SubElement(root, "Domain"), "Grid", Name="solution")
    topology = ET.SubElement(
        grid,
        "Topology",
        TopologyType=_XDMF_TYPES.get(size, "Polygon"),
        NodesPerElement=str(size),
        NumberOfElements=str(n_cells),
    )
    _item(topology, h5name, "cells", np.empty((n_cells, size), dtype=np.int64))
    _item(ET.SubElement(grid, "Geometry", GeometryType="XY"), h5name, "points", mesh.points)
    for centre, fields in (("Node", point), ("Cell", cell)):
        for name, values in fields.items():
            array = np.asarray(values)
            kind = "Scalar" if array.ndim == 1 else "Vector" if array.shape[1] == 3 else "Matrix"
            attribute = ET.SubElement(
                grid, "Attribute", Name=name, AttributeType=kind, Center=centre
            )
            folder = "point" if centre == "Node" else "cell"
            _item(attribute, h5name, f"{folder}/{name}", array)
    ET.indent(root)
    return ET.ElementTree(root)
