"""The size-driven decomposition's optimiser: sizes first, then the worst angles with sizes capped.

:class:`~blockmesh.decompose.optimise.WorstAngle` with the sizes asked trades angles for size: a
block beyond 1.35 times its size scores as a bad corner does, so nodes move to shrink it at the
cost of angles elsewhere (down to about 26 degrees at 1.5 times). That pass brings the blocks
within the size guarantee, but it leaves worst angles a few degrees below those the templates
had. :class:`SizedAngles` runs it, then runs the optimiser again on angles alone, with each
block's diameter capped at :data:`SIZE_CAP` times its size (or where it already is, if larger):
the worst angles rise again and no block grows past the cap, so the guarantee still holds
without more blocks. The second pass works only where angles are low (the nodes of the blocks
scoring below 44 degrees and of the blocks around them), so it costs a fraction of the first.

Examples
--------
>>> import numpy as np
>>> from blockmesh.decompose.templates import ring_hub_faces, ring_hub_nodes
>>> from blockmesh.decompose.optimise import worst_score
>>> quad = np.array([[0, 0], [3, 0], [3, 1], [0, 1]], dtype=float)
>>> nodes, faces = ring_hub_nodes(quad[None])[0], ring_hub_faces(4)
>>> fixed = np.arange(len(nodes)) < 12
>>> sizes = np.full(len(faces), 1.2)
>>> moved = SizedAngles(sizes=sizes).place(nodes, faces, Freedom(fixed, np.zeros_like(nodes)))
>>> bool(worst_score(moved, faces) > worst_score(nodes, faces) + 5)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from blockmesh.decompose.optimise import WorstAngle, _block_scores
from blockmesh.refinement.placement import Freedom, Placement
from blockmesh.sizing.measure import cell_diameters

__all__ = ["SIZE_CAP", "SizedAngles"]

#: The second pass keeps every block's diameter at most this times its size (or as it was):
#: below the guarantee's 1.5 (and the repairs' 1.4925), with room for the centroid's move.
SIZE_CAP = 1.46
#: The second pass works on nodes whose worst corner scores below this (degrees).
_ANGLE_TARGET = 50.0
#: ... among the nodes of the blocks scoring below this (degrees) and of the blocks around
#: them: the worst angles are raised where they are, at a tenth of the time of every node below
#: the target (10^5 blocks: 3,700 to 12,700 nodes against 110,000).
_FOCUS_BELOW = 44.0


@dataclass(frozen=True)
class SizedAngles(Placement):
    """:class:`WorstAngle` with sizes, then again on angles alone with each diameter capped.

    Attributes
    ----------
    target, sweeps : float, int
        The first pass's (see :class:`WorstAngle`); the second pass aims at 50 degrees.
    sizes : ndarray (B,) or None
        The diameter asked of each block (without it, only the first pass runs).
    """

    target: float = 38.0
    sweeps: int = 5
    sizes: np.ndarray | None = None
    name: ClassVar[str] = "sized-angles"
    nested: ClassVar[bool] = False

    def place(self, points: np.ndarray, cells: np.ndarray, freedom: Freedom) -> np.ndarray:
        """Positions from the two passes (see the module notes)."""
        first = WorstAngle(self.target, self.sweeps, self.sizes).place(points, cells, freedom)
        if self.sizes is None:
            return first
        limits = np.maximum(SIZE_CAP * np.asarray(self.sizes), cell_diameters(first, cells))
        cells = np.asarray(cells)
        # Only where angles are low: the nodes of the blocks scoring below _FOCUS_BELOW and of
        # the blocks around those nodes (room to move); every other node is held.
        focus = np.zeros(len(first), dtype=bool)
        focus[cells[_block_scores(first, cells) < _FOCUS_BELOW].ravel()] = True
        focus[cells[np.any(focus[cells], axis=1)].ravel()] = True
        held = Freedom(np.asarray(freedom.fixed) | ~focus, freedom.slide)
        second = WorstAngle(max(_ANGLE_TARGET, self.target), self.sweeps, limits=limits)
        return second.place(first, cells, held)
