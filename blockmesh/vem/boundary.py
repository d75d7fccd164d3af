"""Boundary conditions per patch: checked names, Dirichlet values at the nodes, Neumann loads.

A problem names patches of the mesh: Dirichlet patches get prescribed nodal values (a node shared
by two Dirichlet patches takes the value of the patch named first), Neumann patches a flux or
traction integrated against the basis functions along their edges (which are linear there), and
patches named by neither are natural boundaries with zero flux (insulated, or traction-free).

Examples
--------
>>> import blockmesh
>>> from blockmesh.vem.polygons import PolygonMesh
>>> mesh = PolygonMesh.from_mesh(blockmesh.load_domain("square").mesh(0))
>>> bc = boundary_conditions(mesh, {"left": "0"}, {"right": "1"}, components=1)
>>> [c.patch for c in bc.dirichlet], [c.patch for c in bc.neumann]
(['left'], ['right'])
>>> boundary_conditions(mesh, {"left": 0}, {"left": 1}, components=1)
Traceback (most recent call last):
...
blockmesh.errors.SolverError: patch 'left' is given both a Dirichlet and a Neumann condition; \
give each patch one condition
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from blockmesh.errors import ArgumentTypeError, SolverError
from blockmesh.vem.fields import (
    Field,
    RegionField,
    free_vector_field,
    scalar_field,
    vector_field,
)
from blockmesh.vem.polygons import PolygonMesh
from blockmesh.vem.rules import edge_rule

__all__ = ["BoundaryConditions", "PatchCondition", "ProblemData", "boundary_conditions"]


@dataclass(frozen=True)
class PatchCondition:
    """One patch's condition: its name, its edges and one field per component (None: free)."""

    patch: str
    edges: np.ndarray
    fields: tuple[Field | None, ...]


@dataclass(frozen=True)
class BoundaryConditions:
    """The checked Dirichlet and Neumann conditions of a problem."""

    dirichlet: tuple[PatchCondition, ...]
    neumann: tuple[PatchCondition, ...]
    components: int

    def fixed(self, mesh: PolygonMesh) -> tuple[np.ndarray, np.ndarray]:
        """Constrained degrees of freedom (sorted) and their values.

        Degree of freedom ``components * node + c`` is component c at a node.
        """
        dofs: list[np.ndarray] = []
        values: list[np.ndarray] = []
        for condition in self.dirichlet:
            nodes = np.unique(condition.edges)
            x, y = mesh.points[nodes, 0], mesh.points[nodes, 1]
            for c, field in enumerate(condition.fields):
                if field is not None:
                    dofs.append(self.components * nodes + c)
                    values.append(field(x, y))
        if not dofs:
            return np.empty(0, dtype=np.int64), np.empty(0)
        all_dofs = np.concatenate(dofs)
        all_values = np.concatenate(values)
        unique, first = np.unique(all_dofs, return_index=True)  # first: the patch named first
        return unique, all_values[first]

    def load(self, mesh: PolygonMesh, order: int) -> np.ndarray:
        """``∫_ΓN g φ_i ds`` for every degree of freedom (zero off the Neumann patches)."""
        out = np.zeros(self.components * mesh.n_points)
        for condition in self.neumann:
            edges = condition.edges
            x, y, w, s = edge_rule(mesh.points, edges, order)
            for c, field in enumerate(condition.fields):
                if field is None or field.is_zero:
                    continue
                g = field(x, y) * w
                ends = np.stack([np.sum(g * (1 - s), axis=1), np.sum(g * s, axis=1)], axis=1)
                np.add.at(out, self.components * edges + c, ends)
        return out


@dataclass(frozen=True)
class ProblemData:
    """The data a solution was computed from, kept for the error estimator.

    Attributes
    ----------
    load : tuple of Field or RegionField
        The source f (one field) or the body force (two); per region on a composite domain.
    conditions : BoundaryConditions
    recipe : str
        The stabilisation recipe; ``scale`` its factor.
    """

    load: tuple[Field | RegionField, ...]
    conditions: BoundaryConditions
    recipe: str
    scale: float


def boundary_conditions(
    mesh: PolygonMesh,
    dirichlet: Mapping[str, Any] | None,
    neumann: Mapping[str, Any] | None,
    *,
    components: int,
    dirichlet_name: str = "dirichlet",
    neumann_name: str = "neumann",
) -> BoundaryConditions:
    """Check the conditions against the mesh's patches and parse their data.

    Raises
    ------
    UnknownNameError
        For a patch the mesh does not have (the message lists the patches).
    SolverError
        For a patch given both conditions, or a condition on an interface.
    """
    given = {}
    for name, mapping in ((dirichlet_name, dirichlet), (neumann_name, neumann)):
        if mapping is None:
            mapping = {}
        if not isinstance(mapping, Mapping):
            raise ArgumentTypeError(
                f"{name} must map patch names to values, not {type(mapping).__name__}"
            )
        for patch in mapping:
            if not isinstance(patch, str):
                raise ArgumentTypeError(f"{name}: patch names are strings, got {patch!r}")
            if patch in mesh.interface_names and patch not in mesh.patch_names:
                raise SolverError(
                    f"{name} condition on {patch!r}: that is an interface (an internal patch "
                    "between two regions), not a boundary patch; across an interface u and the "
                    "flux are continuous by themselves. Give conditions on the boundary patches: "
                    f"{', '.join(mesh.patch_names)}"
                )
            mesh.patch_index(patch)
        given[name] = mapping
    both = [p for p in given[dirichlet_name] if p in given[neumann_name]]
    if both:
        raise SolverError(
            f"patch {both[0]!r} is given both a Dirichlet and a Neumann condition; give each "
            "patch one condition"
        )
    conditions = []
    for name, allow_free in ((dirichlet_name, True), (neumann_name, False)):
        items = []
        for patch, spec in given[name].items():
            what = f"{name} value on patch {patch!r}"
            fields: tuple[Field | None, ...]
            if components == 1:
                fields = (scalar_field(spec, what),)
            elif allow_free:
                fields = free_vector_field(spec, what)
            else:
                fields = vector_field(spec, what)
            items.append(PatchCondition(patch, mesh.patch_edges(patch), fields))
        conditions.append(tuple(items))
    return BoundaryConditions(conditions[0], conditions[1], components)
