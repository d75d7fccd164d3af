"""Gradation: a size field made to grow by at most a given ratio per cell, even where it jumps.

A field that jumps (a small size inside a region, a large one outside) would ask for a tiny cell
beside a huge one. The graded field is the largest field below it whose growth is limited::

    h_g(x) = min over y of ( h(y) + s |x - y| ),    s = rate - 1,

so a cell of size h has neighbours (about h away) of size at most ``rate * h``. It is computed
on sample points (a triangulation that resolves the field) by one shortest-path pass: with a
source joined to every sample ``j`` at length ``h(y_j) / s``, ``h_g`` at sample ``i`` is ``s``
times its distance from the source along the triangulation's edges (so it does not leak across a
hole's gap any sooner than by going round). Between samples, ``h_g(x)`` is the smallest cone
``h_g(y_j) + s |x - y_j|`` over the nearest samples, and never more than ``h(x)`` itself. So
the growth is bounded exactly between samples joined by edges, and elsewhere to within ``s``
times the samples' spacing (a jump of the field between two samples is seen at the samples).

Examples
--------
>>> import numpy as np
>>> from blockmesh.sizing.fields import Constant, InRegion, Minimum
>>> import shapely
>>> jump = Minimum((Constant(1.0), InRegion(shapely.box(0, 0, 1, 1), 0.01)))
>>> x = np.linspace(0, 3, 31)
>>> samples = np.column_stack([x, np.full_like(x, 0.5)])
>>> edges = np.column_stack([np.arange(30), np.arange(1, 31)])
>>> graded = grade(jump, 1.5, samples, edges)
>>> graded(np.array([[1.0, 0.5], [1.5, 0.5], [3.0, 0.5]])).round(3).tolist()
[0.01, 0.26, 1.0]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from blockmesh.errors import ArgumentError
from blockmesh.sizing.fields import SizeField, checked_size, checked_sizes

__all__ = ["DEFAULT_GRADATION", "Graded", "checked_gradation", "grade"]

#: Default largest size ratio between neighbouring cells that the field itself may ask for.
DEFAULT_GRADATION = 1.3
#: Samples consulted to evaluate the graded field between samples.
_NEAREST = 6


def checked_gradation(rate: object) -> float:
    """A gradation rate: a finite number > 1.

    Examples
    --------
    >>> checked_gradation(1.2)
    1.2
    """
    value = checked_size(rate, "the gradation")
    if value <= 1.0:
        raise ArgumentError(
            f"the gradation must be > 1 (the largest size ratio between neighbouring cells), "
            f"got {rate!r}"
        )
    return value


@dataclass(frozen=True, eq=False)
class Graded(SizeField):
    """A field limited to grow by ``rate`` per cell, from its graded values at samples.

    ``asked`` is the field graded. Build it with :func:`grade`.
    """

    asked: SizeField
    rate: float
    samples: np.ndarray
    sample_sizes: np.ndarray
    label: str = "the graded size field"
    _tree: Any = field(init=False, repr=False)

    def __post_init__(self) -> None:
        from scipy.spatial import cKDTree

        object.__setattr__(self, "_tree", cKDTree(self.samples))

    def values(self, xy: np.ndarray) -> np.ndarray:
        """The smallest of the field and the cones of the nearest samples."""
        raw = self.asked.values(xy)
        if not len(xy):
            return raw
        k = min(_NEAREST, len(self.samples))
        dist, index = self._tree.query(xy, k=k)
        dist = dist.reshape(len(xy), k)
        index = index.reshape(len(xy), k)
        cones = self.sample_sizes[index] + (self.rate - 1.0) * dist
        return np.minimum(raw, cones.min(axis=1))

    def parts(self) -> tuple[SizeField, ...]:
        """The graded field's own parts are those of the field it grades."""
        return (*self.asked.parts(), self)

    def seeds(self) -> np.ndarray:
        """The field's seeds."""
        return self.asked.seeds()

    @property
    def smallest(self) -> float:
        """The field's bound."""
        return self.asked.smallest

    def _check(self, xy: np.ndarray, sizes: np.ndarray) -> None:  # noqa: ARG002
        return  # the graded values are never above the checked field's


def grade(
    field: SizeField,
    rate: float,
    samples: np.ndarray,
    edges: np.ndarray,
    caps: np.ndarray | None = None,
) -> SizeField:
    """``field`` limited to grow by ``rate`` per cell (see the module notes).

    Parameters
    ----------
    field : SizeField
        Finite and positive at every sample.
    rate : float
        Largest size ratio between neighbouring cells (> 1).
    samples : ndarray (N, 2)
        Points that resolve the field (the finer, the closer the graded field to the exact one).
    edges : ndarray (E, 2)
        Pairs of samples joined by a path inside the domain (a triangulation's edges).
    caps : ndarray (N,), optional
        Sizes no larger than which the graded field is at the samples, besides the field's own
        (what the geometry asks: the spacing of a boundary's points, a narrow gap), ``inf``
        where there is none.

    Returns
    -------
    SizeField

    Notes
    -----
    O(E log N) for the shortest paths; each evaluation O(log N) per point.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import dijkstra

    samples = np.asarray(samples, dtype=np.float64).reshape(-1, 2)
    edges = np.asarray(edges, dtype=np.int64).reshape(-1, 2)
    sizes = checked_sizes(field, samples)
    if caps is not None:
        sizes = np.minimum(sizes, caps)
    slope = rate - 1.0
    n = len(samples)
    lengths = np.hypot(*(samples[edges[:, 0]] - samples[edges[:, 1]]).T)
    source = np.full(n, n)
    rows = np.concatenate([edges[:, 0], edges[:, 1], source])
    cols = np.concatenate([edges[:, 1], edges[:, 0], np.arange(n)])
    weights = np.concatenate([lengths, lengths, sizes / slope])
    # A zero weight would read as "no edge": coincident samples are joined by a tiny length.
    weights = np.maximum(weights, 1e-300)
    graph = coo_matrix((weights, (rows, cols)), shape=(n + 1, n + 1)).tocsr()
    distance = dijkstra(graph, directed=True, indices=n)[:n]
    graded = np.minimum(sizes, slope * distance)
    return Graded(field, float(rate), samples, graded)
