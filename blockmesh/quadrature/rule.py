"""What a quadrature rule is: nodes on the unit square of a sector, and a layout of sectors.

Every rule integrates a cell sector by sector. A **sector** has an apex ``c`` (a point inside the
cell) and an **edge** ``γ(s)``, ``0 <= s <= 1``; it is the image of the unit square under::

    x(r, s) = (1 - r) c + r γ(s),      Jacobian  r |det(γ(s) - c, γ'(s))|,

so ``∫∫_sector f = ∫_0^1 ∫_0^1 r f(x(r, s)) |det(γ(s) - c, γ'(s))| dr ds`` (the paper's map,
with the factor ``r`` of the collapsed coordinates). A rule of order ``n`` is a table of nodes
``(r_j, s_k)`` and weights ``w_jk`` for the integral ``∫_0^1 ∫_0^1 r g(r, s) dr ds`` — the factor
``r`` is inside the weights — and knows nothing of the geometry: the sector's map and Jacobian are
applied by the kernel (:mod:`blockmesh.quadrature.kernel`).

For a straight edge from corner ``a`` to corner ``b``, ``γ(s) = (1 - s) a + s b`` and the
determinant is the constant ``det(a - c, b - c)``, twice the triangle's area, so each point is a
fixed combination of the cell's corners and one matrix product places a whole chunk of points.
A curved edge (an arc or spline of a later domain format) plugs in its own ``γ`` and ``γ'``:
the same :class:`SectorNodes` then integrate it, with the determinant evaluated per point. Only
layouts whose sectors' edges are the cell's own edges (``Layout.edges_are_cell_edges``) can take
curved edges; the corner fan's triangles have diagonals for two of their sides.

The record of a rule is :class:`Rule`; the rules are registered in
:data:`blockmesh.quadrature.registry.RULES`.

Examples
--------
>>> from blockmesh.quadrature import RULES
>>> nodes = RULES["paper"].nodes(2)
>>> nodes.weights.shape, nodes.degree
((3, 2), 3)
>>> round(float(nodes.weights.sum()), 15)  # ∫∫ r dr ds
0.5
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Layout", "Rule", "RuleInfo", "SectorNodes"]


@dataclass(frozen=True, eq=False)
class SectorNodes:
    """A tensor rule on the unit square for ``∫_0^1 ∫_0^1 r g(r, s) dr ds``.

    Attributes
    ----------
    r : ndarray (Nr,)
        Radial nodes in (0, 1): the fraction of the way from the apex to the edge.
    one_minus_r : ndarray (Nr,)
        ``1 - r``, computed as accurately as ``r`` (the apex's share of each point).
    h : ndarray (Ns,)
        Nodes along the edge as offsets from its middle: ``s = 1/2 + h``, ``-1/2 < h < 1/2``.
        A straight edge's point is ``(a + b) / 2 + h (b - a)`` (the paper's form).
    weights : ndarray (Nr, Ns)
        ``w_jk``, the factor ``r`` included; the radial index is the outer one, as the points
        are laid out. The weights are a product ``u_j v_k`` of a radial and an along-edge rule.
    degree : int
        Largest total degree in ``x`` integrated exactly over a sector with a straight edge.
    """

    r: np.ndarray
    one_minus_r: np.ndarray
    h: np.ndarray
    weights: np.ndarray
    degree: int

    def __post_init__(self) -> None:
        for name in ("r", "one_minus_r", "h", "weights"):
            array = np.array(getattr(self, name), dtype=np.float64)
            array.setflags(write=False)
            object.__setattr__(self, name, array)
        if self.weights.shape != (self.r.size, self.h.size):
            raise ValueError(
                f"weights must have shape (len(r), len(h)) = ({self.r.size}, {self.h.size}), "
                f"not {self.weights.shape}"
            )

    @classmethod
    def from_gauss(
        cls, x: np.ndarray, t: np.ndarray, weights: np.ndarray, degree: int
    ) -> SectorNodes:
        """The nodes of radial points ``x`` and edge points ``t`` of rules on [-1, 1].

        ``r = (1 + x) / 2`` and ``h = t / 2``; ``weights`` are the ``w_jk`` (the factor ``r``
        and the Jacobians of both maps included).
        """
        return cls(r=(1 + x) / 2, one_minus_r=(1 - x) / 2, h=t / 2, weights=weights, degree=degree)

    @property
    def points_per_sector(self) -> int:
        """Evaluations of f per sector."""
        return int(self.weights.size)


@dataclass(frozen=True)
class Layout:
    """How a rule cuts a pentagon into sectors.

    Attributes
    ----------
    name : str
    sectors : tuple of (apex, k, i)
        Per sector: the apex (a corner index, or ``None`` for the cell's vertex mean) and the two
        corners of its edge; ``γ(s)`` runs from corner ``i`` (``s = 0``) to corner ``k``
        (``s = 1``), as the paper's program walks it.
    orient : callable, optional
        ``orient(x, y, ring) -> ring``: rotates each cell's corners before the sectors are taken
        (e.g. to put the best fan apex at corner 0). ``ring`` is (6, B) corner ids, corner 0
        repeated at the end; ``x``, ``y`` are the mesh's coordinates.
    edges_are_cell_edges : bool
        Whether every sector's edge is an edge of the cell (so a curved cell edge can be a
        sector's ``γ``).
    """

    name: str
    sectors: tuple[tuple[int | None, int, int], ...]
    orient: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray] | None = field(
        default=None, repr=False
    )
    edges_are_cell_edges: bool = True

    @property
    def sectors_per_cell(self) -> int:
        """Number of sectors (triangles, for straight cells) per cell."""
        return len(self.sectors)


@dataclass(frozen=True)
class Rule:
    """One composite rule of the registry :data:`blockmesh.quadrature.registry.RULES`.

    Attributes
    ----------
    name : str
        The registry key and the ``rule=`` name.
    description : str
        One line for listings.
    layout : Layout
        How a cell is cut into sectors.
    nodes : callable
        ``nodes(n) -> SectorNodes``, the rule of order ``n`` on the unit square (cached by the
        rule's module; the arrays are read-only).
    max_order : int
        Highest order the rule's Gauss tables reach.
    """

    name: str
    description: str
    layout: Layout
    nodes: Callable[[int], SectorNodes] = field(repr=False)
    max_order: int

    @property
    def sectors_per_cell(self) -> int:
        """Sectors (triangles) per cell."""
        return self.layout.sectors_per_cell

    def info(self, order: int) -> RuleInfo:
        """Points and exactness degree at ``order`` (a whole number, not checked here)."""
        nodes = self.nodes(order)
        return RuleInfo(
            self.name, order, nodes.points_per_sector, self.sectors_per_cell, nodes.degree
        )


@dataclass(frozen=True)
class RuleInfo:
    """What a rule of a given order costs and guarantees.

    Examples
    --------
    >>> from blockmesh.quadrature import rule_info
    >>> info = rule_info("fan", 5)
    >>> info.points_per_cell, info.degree
    (75, 9)
    """

    rule: str
    order: int
    points_per_triangle: int
    triangles_per_cell: int
    degree: int

    @property
    def points_per_cell(self) -> int:
        """Evaluations of f per cell."""
        return self.points_per_triangle * self.triangles_per_cell
