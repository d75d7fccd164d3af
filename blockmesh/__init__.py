"""blockmesh: multi-block all-pentagonal finite element meshes of 2-D domains.

The pipeline: a :class:`Domain` (validated blocks, from a polygon, explicit blocks or a TOML file)
is refined into a :class:`Mesh` (:func:`refine`), which is integrated over or written to solver
formats.

The public names are imported on first use (PEP 562 module ``__getattr__``), so that
``import blockmesh`` and ``blockmesh --version`` stay fast; ``from blockmesh import refine`` and
``blockmesh.refine`` work as usual.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("square-cut").mesh(2)
>>> mesh.n_cells
144
"""

import importlib as _importlib
import typing as _typing

from blockmesh import _moved

_moved.install()

__version__ = "0.1.0"

#: Public name -> the module that defines it.
_EXPORTS = {
    "Domain": "domain.domain",
    "ArgumentError": "errors",
    "ArgumentTypeError": "errors",
    "BlockMeshError": "errors",
    "BlockMeshWarning": "errors",
    "DomainError": "errors",
    "DomainFormatError": "errors",
    "ExportError": "errors",
    "ExpressionError": "errors",
    "ResourceError": "errors",
    "SolverError": "errors",
    "TopologyError": "errors",
    "UnknownNameError": "errors",
    "exact_integral": "quadrature.exact",
    "parse_expression": "numerics.expr",
    "read": "io",
    "write": "io",
    "load_domain": "domain.loading",
    "parse_polygon_string": "domain.loading",
    "Mesh": "mesh.mesh",
    "MeshQuality": "mesh.quality",
    "PolygonMesh": "mesh.polygons",
    "IntegrationResult": "quadrature",
    "integrate": "quadrature",
    "integrate_to_tolerance": "quadrature",
    "quadrature_points": "quadrature",
    "refine": "refinement.pipeline",
}

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
    "PolygonMesh",
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


#: What ``dir(blockmesh)`` lists besides :data:`__all__`: the module's own dunder basics.
_DUNDERS = ("__all__", "__doc__", "__file__", "__name__", "__path__", "__version__")


def __getattr__(name: str) -> _typing.Any:
    """Import a public name's module on first use and cache the name here."""
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'blockmesh' has no attribute {name!r}")
    value = getattr(_importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    """The public names (:data:`__all__`) and the dunder basics, not the helpers or submodules.

    Examples
    --------
    >>> import blockmesh
    >>> "refine" in dir(blockmesh), "importlib" in dir(blockmesh)
    (True, False)
    """
    return sorted({*__all__, *_DUNDERS})


if _typing.TYPE_CHECKING:  # for type checkers and IDEs: the names as if imported eagerly
    from blockmesh.domain.domain import Domain
    from blockmesh.domain.loading import load_domain, parse_polygon_string
    from blockmesh.errors import (
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
    from blockmesh.io import read, write
    from blockmesh.mesh.mesh import Mesh
    from blockmesh.mesh.polygons import PolygonMesh
    from blockmesh.mesh.quality import MeshQuality
    from blockmesh.numerics.expr import parse_expression
    from blockmesh.quadrature import (
        IntegrationResult,
        integrate,
        integrate_to_tolerance,
        quadrature_points,
    )
    from blockmesh.quadrature.exact import exact_integral
    from blockmesh.refinement.pipeline import refine
