"""blockmesh: multi-block all-pentagonal finite element meshes of 2-D domains.

The pipeline: a :class:`Domain` (validated blocks, from a polygon, explicit blocks or a TOML file)
is refined into a :class:`Mesh` (:func:`refine`), which is integrated over or written to solver
formats.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("square-cut").mesh(2)
>>> mesh.n_cells
144
"""

from .domain import Domain
from .errors import (
    ArgumentError,
    ArgumentTypeError,
    BlockMeshError,
    BlockMeshWarning,
    DomainError,
    DomainFormatError,
    ExportError,
    ExpressionError,
    ResourceError,
    SolverError,
    TopologyError,
    UnknownNameError,
)
from .exact import exact_integral
from .expr import parse_expression
from .io import read, write
from .loading import load_domain, parse_polygon_string
from .mesh import Mesh, MeshQuality
from .quadrature import IntegrationResult, integrate, integrate_to_tolerance, quadrature_points
from .refinement import refine

__all__ = [
    "ArgumentError",
    "ArgumentTypeError",
    "BlockMeshError",
    "BlockMeshWarning",
    "Domain",
    "DomainError",
    "DomainFormatError",
    "ExportError",
    "ExpressionError",
    "IntegrationResult",
    "Mesh",
    "MeshQuality",
    "ResourceError",
    "SolverError",
    "TopologyError",
    "UnknownNameError",
    "exact_integral",
    "integrate",
    "integrate_to_tolerance",
    "load_domain",
    "parse_expression",
    "parse_polygon_string",
    "quadrature_points",
    "read",
    "refine",
    "write",
]
__version__ = "0.1.0"
