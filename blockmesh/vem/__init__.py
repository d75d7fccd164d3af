"""Lowest-order conforming virtual elements on polygon meshes: diffusion-reaction and elasticity.

The virtual element method (VEM) works on any polygons, so it runs on blockmesh's pentagons as
they are (no splitting), on triangles (where it is the P1 finite element method) and on mixed
meshes. One degree of freedom per node (per component); the element matrices of all cells with
the same vertex count are computed at once.

===============================  =====================================================
:func:`solve_poisson`            ``-∇·(κ∇u) + c u = f``, Dirichlet and Neumann patches
:func:`solve_elasticity`         plane stress / plane strain, displacement and traction patches
:class:`PolygonMesh`             the solver's mesh: any polygons, with patches
:func:`write_solution`           VTU (point data, cell data) or XDMF + HDF5
:func:`.reference.kirsch`        the exact plate-with-a-hole field (stress concentration 3)
===============================  =====================================================

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem import solve_poisson
>>> mesh = blockmesh.load_domain("square").mesh(1)
>>> sol = solve_poisson(mesh, "0", dirichlet={"left": "1 + x + y", "right": "1 + x + y"},
...                     neumann={"bottom": -1, "top": 1})
>>> bool(abs(sol.values - (1 + mesh.points.sum(axis=1))).max() < 1e-12)  # linear: exact
True
"""

from blockmesh.vem.assembly import SOLVERS, SolveInfo
from blockmesh.vem.elasticity import ElasticitySolution, elasticity_matrix, solve_elasticity
from blockmesh.vem.norms import ErrorNorms
from blockmesh.vem.output import write_solution
from blockmesh.vem.poisson import PoissonSolution, solve_poisson
from blockmesh.vem.polygons import CellGroup, PolygonMesh
from blockmesh.vem.stabilization import STABILIZATIONS

__all__ = [
    "SOLVERS",
    "STABILIZATIONS",
    "CellGroup",
    "ElasticitySolution",
    "ErrorNorms",
    "PoissonSolution",
    "PolygonMesh",
    "SolveInfo",
    "elasticity_matrix",
    "solve_elasticity",
    "solve_poisson",
    "write_solution",
]
