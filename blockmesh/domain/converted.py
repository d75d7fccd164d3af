"""An existing triangle, quadrilateral or mixed mesh converted to a Domain of pentagonal blocks.

:func:`mesh_domain` reads the mesh (:func:`blockmesh.decompose.conversion.read_element_mesh`),
converts its elements (:func:`blockmesh.decompose.conversion.convert_elements`) and makes the
blocks a Domain, each error prefixed with the mesh's name.

Examples
--------
>>> import meshio, numpy as np
>>> from blockmesh import Domain
>>> points = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
>>> mesh_domain(Domain, meshio.Mesh(points, [("quad", [[0, 1, 2, 3]])])).layout
'conversion'
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from blockmesh.decompose.conversion import convert_elements, read_element_mesh
from blockmesh.errors import DomainError

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["mesh_domain"]


def mesh_domain(
    cls: type[Domain],
    source: Any,
    *,
    name: str | None = None,
    description: str = "",
) -> Domain:
    """The Domain of :meth:`blockmesh.Domain.from_mesh` (see there), as ``cls``."""
    mesh = read_element_mesh(source)
    label = str(source) if isinstance(source, str | Path) else "the mesh"
    default_name = Path(source).stem if isinstance(source, str | Path) else "mesh"
    try:
        spec = convert_elements(mesh)
        return cls.from_blocks(
            spec.vertices,
            spec.blocks,
            spec.patches,
            spec.regions,
            name=name or default_name,
            description=description,
            layout=spec.layout,
            block_source=spec.block_source,
        )
    except DomainError as error:
        raise type(error)(f"{label}: {error}") from None
