"""What a :class:`~blockmesh.mesh.Mesh` and a :class:`~blockmesh.mesh.PolygonMesh` do alike.

:class:`MeshBase` is the base class of both: the checks on construction, the node count, the
curved area, the patches and interfaces by name, and the relabelled copies, each a method here
once (the work itself is done in :mod:`~blockmesh.mesh.labels`). The fields stay with each
class: a PolygonMesh stores its cells in other arrays, between the same fields in the same order.

Examples
--------
>>> import blockmesh
>>> mesh = blockmesh.load_domain("sp").mesh(1)
>>> isinstance(mesh, MeshBase), mesh.with_name("copy").name
(True, 'copy')
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any, Self

import numpy as np

from blockmesh.mesh import labels

__all__ = ["MeshBase"]


class MeshBase:
    """The methods a Mesh and a PolygonMesh share (a base class; it holds no fields)."""

    if TYPE_CHECKING:
        points: np.ndarray

        def _freeze(self) -> None: ...
        def _check_arrays(self) -> None: ...
        def _check_cells(self) -> None: ...
        def curved_cell_areas(self) -> np.ndarray:
            """Area of every cell bounded by its curved edges, shape (M,)."""

    def __post_init__(self) -> None:
        self._freeze()
        self._check_arrays()
        self._check_cells()

    @property
    def n_points(self) -> int:
        """Number of nodes N."""
        return int(self.points.shape[0])

    @property
    def curved_area(self) -> float:
        """Total area of the mesh bounded by its curved edges (its :attr:`area` without curves).

        Examples
        --------
        >>> import blockmesh
        >>> disc = blockmesh.load_domain("disc")
        >>> mesh = disc.mesh(2)
        >>> round(mesh.curved_area, 12), mesh.area < mesh.curved_area
        (3.14159265359, True)
        """
        return float(np.sum(self.curved_cell_areas()))

    # ------------------------------------------------------------ boundaries
    def patch_edges(self, patch: str) -> np.ndarray:
        """Boundary edges (E, 2) of the named patch.

        Examples
        --------
        >>> import blockmesh
        >>> blockmesh.load_domain("sp").mesh(2).patch_edges("boundary").shape
        (20, 2)
        """
        return labels.patch_edges(self, patch)

    @property
    def interfaces(self) -> Mapping[str, np.ndarray]:
        """Interface edges (E, 2) of each interface, by name (read-only view; empty if none).

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("layered-plate").mesh(1)
        >>> {name: len(edges) for name, edges in mesh.interfaces.items()}
        {'bottom|core': 24, 'core|top': 24}
        """
        return labels.interfaces_by_name(self)

    # ------------------------------------------------------------ copies
    def _copy(self, **changes: Any) -> Self:
        """A copy with some arrays replaced; the cheap checks run, the caches start empty."""
        return labels.copy_mesh(self, changes)

    def with_patches(self, boundary_patch: Any, patch_names: Any) -> Self:
        """The same mesh with its boundary edges put in other patches.

        Parameters
        ----------
        boundary_patch : array_like (Eb,) int
            Index into ``patch_names`` of every boundary edge, in the order of ``boundary_edges``.
        patch_names : sequence of str

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("sp").mesh(1)
        >>> first = (np.arange(10) < 2).astype(int)
        >>> mesh.with_patches(first, ["wall", "inlet"]).patch_edges("inlet").tolist()
        [[0, 5], [5, 1]]
        """
        return labels.with_patches(self, boundary_patch, patch_names)

    def with_regions(self, region: Any, region_names: Any) -> Self:
        """The same mesh with its cells put in other regions (``region`` indexes the names).

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("sp").mesh(1)
        >>> mesh.with_regions(np.arange(6) % 2, ["even", "odd"]).region_names
        ('even', 'odd')
        """
        return labels.with_regions(self, region, region_names)

    def with_interfaces(
        self, interface_edges: Any, interface_patch: Any, interface_names: Any
    ) -> Self:
        """The same mesh with other interfaces (internal patches); each edge is checked.

        Parameters
        ----------
        interface_edges : array_like (Ei, 2) int
            Edges each shared by two cells, the first side's cell on the left.
        interface_patch : array_like (Ei,) int
            Index into ``interface_names`` of every interface edge.
        interface_names : sequence of str

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("joined-2").mesh(0)
        >>> mesh.with_interfaces([[1, 2]], [0], ["glue"]).interfaces["glue"].tolist()
        [[1, 2]]
        """
        return labels.with_interfaces(self, interface_edges, interface_patch, interface_names)

    def with_points(self, points: Any) -> Self:
        """The same cells on moved nodes (e.g. after smoothing); orientation is checked again.

        A PolygonMesh's cells are checked to be star-shaped again too.

        Examples
        --------
        >>> import blockmesh
        >>> mesh = blockmesh.load_domain("sp").mesh(1)
        >>> round(mesh.with_points(2 * mesh.points).area, 12)
        20.0
        """
        return labels.with_points(self, points)

    def with_name(self, name: str) -> Self:
        """The same mesh under another name."""
        return self._copy(name=name)
