"""Decompose a convex polygon into strictly convex pentagons that meet edge to edge.

A convex n-gon becomes a conforming block mesh of strictly convex, counter-clockwise pentagons
(``docs/mathematics.md`` §4):

- ``n = 5``: the polygon itself (layout ``"pentagon"``);
- ``n = 3``: a 9-pentagon template in barycentric coordinates, mapped affinely
  (``"triangle-template"``);
- ``n = 4``: an 8-pentagon template of the unit square, mapped by the projective map that sends the
  square's corners to the quadrilateral's (``"quad-template"``); it keeps lines straight and
  convexity for every strictly convex quadrilateral;
- ``n >= 6``: the minimum number ``ceil((n - 2) / 3)`` of pentagons with corners among the polygon's
  vertices and edge midpoints, joined by non-crossing chords (``"chords"``), found by an exact
  dynamic programme that maximises the worst corner the chords create; or, when ``n`` is a multiple
  of 3 and it scores strictly better, a central hub with a spoke to every third vertex (``"star"``).

The *score* of a layout is the smallest ``min(theta, 180 - theta)`` over the corners it creates or
splits: corners at chord ends (split polygon vertices, used edge midpoints) and at the hub. Polygon
corners kept whole belong to the domain and do not count.

Examples
--------
>>> import numpy as np
>>> hexagon = np.array([[0.1, 0], [0.7, 0.2], [1, 0.5], [0.75, 0.85], [0.5, 1], [0, 0.25]])
>>> d = decompose_convex_polygon(hexagon)
>>> d.layout, d.blocks.shape, len(d.vertices)
('chords', (2, 5), 8)
>>> d.blocks.tolist()  # a chord joins the midpoints of edges 2 and 5 (new vertices 6 and 7)
[[0, 1, 2, 6, 7], [6, 3, 4, 5, 7]]
>>> [chain.tolist() for chain in d.edge_chains]
[[0, 1], [1, 2], [2, 6, 3], [3, 4], [4, 5], [5, 7, 0]]
"""

from __future__ import annotations

from functools import lru_cache, partial
from typing import NamedTuple

import numpy as np

from blockmesh.decompose.decomposition import Decomposition, in_local_frame
from blockmesh.decompose.templates import (
    SQUARE_FACES,
    TRIANGLE_FACES,
    TRIANGLE_WEIGHTS,
    square_weights,
)
from blockmesh.decompose.triangulate import DEFAULT_MIN_ANGLE
from blockmesh.decompose.triangulated import triangulated_decomposition
from blockmesh.errors import DomainError
from blockmesh.geometry.polygons import (
    COLLINEAR_SIN_TOL,
    interior_angles,
    is_strictly_convex,
    polygon_diameter,
)
from blockmesh.mesh.polygon_geometry import STRAIGHT_ULPS

__all__ = ["Decomposition", "check_corners_clear", "decompose_convex_polygon"]

#: Corners beyond which the exact chord programme (O(n^5)) is not used (see decompose_polygon).
CHORD_LIMIT = 16
#: Points closer than this times the polygon's diameter count as the same point (as in domain
#: validation); an edge that short breaks the input contract.
_SAME_POINT = 1e-11


def decompose_convex_polygon(polygon: np.ndarray) -> Decomposition:
    """Split a strictly convex polygon into strictly convex pentagons, edge to edge.

    Parameters
    ----------
    polygon : ndarray, shape (n, 2)
        ``n >= 3`` vertices, counter-clockwise, strictly convex: no repeated points (every edge
        longer than ``1e-11`` times the diameter) and every corner turning left by more than
        :data:`~blockmesh.geometry.COLLINEAR_SIN_TOL` in sine.

    Returns
    -------
    Decomposition
        9 blocks for a triangle, 8 for a quadrilateral, the polygon itself for a pentagon and
        ``ceil((n - 2) / 3)`` blocks for ``6 <= n <= 16`` (the minimum the angle sum allows).
        Beyond 16 corners the chord programme's cost (and its long thin pieces) rule it out: the
        polygon goes through :func:`blockmesh.decompose.decompose_polygon` (layout
        ``"triangulation"``).

    Raises
    ------
    ValueError
        If ``polygon`` breaks the input contract above (a programming error: domain validation
        checks user input first).
    DomainError
        If the polygon is so thin that no layout has all its corners turning by more than
        ``COLLINEAR_SIN_TOL`` (only near the limit of the contract); or too thin for where it sits
        (:func:`check_corners_clear`): a block corner would lie within
        :data:`~blockmesh.mesh.polygon_geometry.STRAIGHT_ULPS` spacings of doubles of the chord of
        its two neighbours, and a mesh would read it as straight (a hanging node). A sliver 1e-5
        long and 5e-15 wide at ``x = 1`` (22 spacings) is refused: no block inside it can stand
        that far clear where it sits, whatever frame it is computed in. Block corners stand off
        their chords by a share of the polygon's own corners' distances to theirs (in the
        triangle template at least 0.0075 of the smallest altitude, its corners' smallest area
        share; measured on random polygons: 0.05 for triangles, 0.06 for quadrilaterals, 0.5 for
        the chord and star layouts), so a polygon whose corners all stand more than 3000
        spacings (at its largest coordinate) clear of their chords, and for ``n <= 4`` turn by
        more than ``1e-10`` in sine, is not refused.

    Notes
    -----
    For ``n >= 6`` the chord layout is an exact dynamic programme over intervals of the ``2n``
    boundary points (vertices and edge midpoints): ``O(n^5)`` candidate pentagons, pruned by the
    angle sum (a layout with ``k`` pieces uses exactly ``3k - n + 2`` edge midpoints) and
    evaluated with numpy. The candidate tables depend on ``n`` only and are cached; with them,
    ``n = 16`` takes a few milliseconds and ``n = 32`` well under a second. If the minimum
    number of pieces has no valid layout, one more piece is used.

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    >>> d = decompose_convex_polygon(square)
    >>> d.layout, len(d.blocks), round(d.min_angle, 1), round(d.max_angle, 1)
    ('quad-template', 8, 77.1, 128.6)
    >>> t = np.linspace(0, 2 * np.pi, 13)[:-1]
    >>> d = decompose_convex_polygon(np.column_stack([np.cos(t), np.sin(t)]))
    >>> d.layout, len(d.blocks), round(d.min_angle, 6)
    ('star', 4, 75.0)
    """
    p = _checked_polygon(polygon)
    n = len(p)
    if n > CHORD_LIMIT:
        # The chord programme is O(n^5): beyond its limit the quality triangulation takes over.
        d = in_local_frame([p], partial(triangulated_decomposition, min_angle=DEFAULT_MIN_ANGLE))
        check_corners_clear(d.vertices, d.blocks)
        return d
    if n == 3:
        layout = _template_layout(p, TRIANGLE_WEIGHTS, TRIANGLE_FACES, "triangle-template")
    elif n == 4:
        layout = _template_layout(p, square_weights(p), SQUARE_FACES, "quad-template")
    elif n == 5:
        chains = [np.array([i, (i + 1) % 5]) for i in range(5)]
        layout = _Layout("pentagon", p, np.arange(5)[None, :], chains, np.inf)
    else:
        layout = _best_layout(p)
    return _finished(layout)


class _Layout(NamedTuple):
    name: str
    vertices: np.ndarray
    blocks: np.ndarray
    edge_chains: list[np.ndarray]
    score: float


def _checked_polygon(polygon: np.ndarray) -> np.ndarray:
    p = np.array(polygon, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise ValueError(f"polygon must have shape (n, 2) with n >= 3, got {p.shape}")
    if not np.all(np.isfinite(p)):
        raise ValueError("polygon has non-finite coordinates")
    edges = np.hypot(*(np.roll(p, -1, axis=0) - p).T)
    if edges.min() <= _SAME_POINT * polygon_diameter(p):
        i = int(np.argmin(edges))
        raise ValueError(
            f"polygon has repeated points: edge {i} is {edges[i]:.3g} long, at most "
            f"{_SAME_POINT:g} times the polygon's diameter"
        )
    if not is_strictly_convex(p):
        raise ValueError(
            "polygon must be counter-clockwise and strictly convex "
            f"(every corner turning left by more than sine {COLLINEAR_SIN_TOL:g})"
        )
    return p


def check_corners_clear(
    vertices: np.ndarray, blocks: np.ndarray, what: str = "the polygon"
) -> None:
    """DomainError if a block corner is within round-off of the chord of its two neighbours.

    A mesh reads a vertex within :data:`~blockmesh.mesh.polygon_geometry.STRAIGHT_ULPS` spacings
    of doubles of the chord of its neighbours as straight, whatever its sine (a midpoint rounded
    to the spacing is that far off): such a block corner would be a hanging node. Corner sines
    are relative and do not see it; a sliver far from the origin for its width does (its blocks
    are a few spacings wide). The spacing is taken at the block's largest coordinate.

    Parameters
    ----------
    vertices : ndarray (V, 2)
    blocks : ndarray (B, 5)
        Counter-clockwise blocks over ``vertices``.
    what : str
        What the blocks decompose, for the message.

    Raises
    ------
    DomainError
        Naming the first such block and corner, its distance and the spacing where it lies.

    Examples
    --------
    >>> roof = np.array([[0, 0], [1, 0], [1, 1], [0.5, 1 + 1e-9], [0, 1]])
    >>> check_corners_clear(roof, np.array([[0, 1, 2, 3, 4]]))  # 1e-9 is 4.5e6 spacings at 1
    >>> check_corners_clear(roof + 1e7, np.array([[0, 1, 2, 3, 4]]))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainError: the polygon is too thin for where it sits ...(vertex 3)...
    """
    corners = np.asarray(vertices, dtype=np.float64)[blocks]
    inc = corners - np.roll(corners, 1, axis=1)
    out = np.roll(corners, -1, axis=1) - corners
    cross = inc[..., 0] * out[..., 1] - inc[..., 1] * out[..., 0]
    chord = np.hypot(inc[..., 0] + out[..., 0], inc[..., 1] + out[..., 1])
    off = np.divide(np.abs(cross), chord, out=np.zeros_like(cross), where=chord > 0)
    reach = np.abs(corners).max(axis=(1, 2))
    spacing = np.spacing(reach)
    close = off <= STRAIGHT_ULPS * spacing[:, None]
    if close.any():
        b, k = (int(i[0]) for i in np.nonzero(close))
        size = float(np.ptp(corners[b], axis=0).max())
        raise DomainError(
            f"{what} is too thin for where it sits to be decomposed in double precision: corner "
            f"{k} of block {b} (vertex {int(blocks[b, k])}) is {off[b, k]:.3g} from the chord of "
            f"its neighbours, within {STRAIGHT_ULPS} spacings of doubles there "
            f"({spacing[b]:.3g} at coordinates near {reach[b]:.3g}), so a mesh would read it as "
            f"straight (the block is {size:.3g} across); move the polygon near the origin (or "
            "use other units)"
        )


def _finished(layout: _Layout) -> Decomposition:
    corners = layout.vertices[layout.blocks]
    check_corners_clear(layout.vertices, layout.blocks)
    convex = is_strictly_convex(corners)
    if not np.all(convex):
        bad = int(np.flatnonzero(~convex)[0])
        raise DomainError(
            f"the polygon is too thin to split into strictly convex pentagons: block {bad} "
            f"(vertices {layout.blocks[bad].tolist()}) of the {layout.name} layout has a corner "
            f"turning by at most sine {COLLINEAR_SIN_TOL:g}"
        )
    angles = interior_angles(corners)
    arrays = [
        np.array(layout.vertices, dtype=np.float64),
        np.array(layout.blocks, dtype=np.int64),
        *(np.array(c, dtype=np.int64) for c in layout.edge_chains),
    ]
    for a in arrays:
        a.setflags(write=False)
    return Decomposition(
        vertices=arrays[0],
        blocks=arrays[1],
        edge_chains=tuple(arrays[2:]),
        layout=layout.name,
        min_angle=float(angles.min()),
        max_angle=float(angles.max()),
    )


# --- templates for triangles and quadrilaterals ------------------------------------------------


def _template_layout(
    polygon: np.ndarray, weights: np.ndarray, faces: np.ndarray, name: str
) -> _Layout:
    """Place a template's nodes by their weights on the polygon's corners; corners stay exact."""
    n = len(polygon)
    corner_of = np.flatnonzero(np.count_nonzero(weights, axis=1) == 1)
    inner = np.setdiff1d(np.arange(len(weights)), corner_of)
    ids = np.empty(len(weights), dtype=np.int64)
    ids[corner_of] = np.argmax(weights[corner_of], axis=1)
    ids[inner] = n + np.arange(len(inner))
    placed = weights[inner] @ polygon / weights[inner].sum(axis=1, keepdims=True)
    chains = []
    for i in range(n):
        j = (i + 1) % n
        on_edge = np.flatnonzero(np.delete(weights, [i, j], axis=1).sum(axis=1) == 0)
        along = weights[on_edge, j] / (weights[on_edge, i] + weights[on_edge, j])
        chains.append(ids[on_edge[np.argsort(along)]])
    return _Layout(name, np.vstack([polygon, placed]), ids[faces], chains, np.nan)


# --- layouts for n >= 6 -----------------------------------------------------------------------


def _min_angle(layout: _Layout) -> float:
    return float(interior_angles(layout.vertices[layout.blocks]).min())


def _best_layout(polygon: np.ndarray) -> _Layout:
    """The chord or star layout with the fewest pieces.

    Then the best score, then (on a tie) the larger smallest angle overall (regular 9-gon: both
    score 60 degrees; the star's smallest angle is 70, the chords' 60).
    """
    n = len(polygon)
    pieces = -(-(n - 2) // 3)
    chords = _chord_layout(polygon, pieces)
    star = _star_layout(polygon)
    if star is not None and (
        chords is None
        or star.score > chords.score + _SCORE_TOL
        or (
            star.score >= chords.score - _SCORE_TOL
            and _min_angle(star) > _min_angle(chords) + _SCORE_TOL
        )
    ):
        return star
    if chords is not None:
        return chords
    fallback = _chord_layout(polygon, pieces + 1)
    if fallback is None:
        raise DomainError(
            f"the {n}-gon is too thin to split into {pieces} or {pieces + 1} strictly convex "
            f"pentagons (every corner turning by more than sine {COLLINEAR_SIN_TOL:g})"
        )
    return fallback


def _star_layout(polygon: np.ndarray) -> _Layout | None:
    """Hub with spokes to every third vertex: ``n / 3`` sectors ``(hub, v_s .. v_s+3)``.

    Only ``n`` divisible by 3 gives the minimum number of pieces: with ``k`` sectors the angle
    sum needs ``n = 2k + a`` for ``a`` spokes ending at vertices, and ``k = ceil((n - 2) / 3)``
    then forces ``a = k = n / 3``. The hub is the vertex mean or the area centroid, and the
    spokes start at vertex 0, 1 or 2; the best score wins (the first on ties).
    """
    n = len(polygon)
    if n % 3:
        return None
    mean = polygon.mean(axis=0)
    local = polygon - mean
    rolled = np.roll(local, -1, axis=0)
    cross = local[:, 0] * rolled[:, 1] - rolled[:, 0] * local[:, 1]
    centroid = mean + ((local + rolled) * cross[:, None]).sum(axis=0) / (3.0 * cross.sum())
    best = None
    for hub in (mean, centroid):
        for first in range(3):
            spokes = np.arange(first, n, 3)
            rim = (spokes[:, None] + np.arange(4)) % n
            sectors = np.concatenate([np.full((len(spokes), 1), n), rim], axis=1)
            corners = np.vstack([polygon, hub])[sectors]
            if not np.all(is_strictly_convex(corners)):
                continue
            theta = interior_angles(corners)[:, [0, 1, 4]]
            score = float(np.minimum(theta, 180.0 - theta).min())
            if best is None or score > best.score:
                chains = [np.array([i, (i + 1) % n]) for i in range(n)]
                best = _Layout("star", np.vstack([polygon, hub]), sectors, chains, score)
    return best


def _chord_layout(polygon: np.ndarray, pieces: int) -> _Layout | None:
    """The best layout of ``pieces`` pentagons joined by chords, or None if there is none.

    Boundary points ``0..2n-1`` alternate vertex, edge midpoint. ``best[m, a, l]`` is the best
    score of the region cut off by the chord from point ``a + l`` back to point ``a`` (indices
    mod ``2n``), using exactly ``m`` edge midpoints strictly between; ``best[0, a, 1]`` and
    ``best[0, a, 2]`` (``a`` a vertex) stand for boundary sides. The pentagon next to the chord
    has corners ``a < c1 < c2 < c3 < a + l``; its other sides are boundary sides or chords whose
    regions are solved for shorter ``l``. The angle sum fixes the midpoints a region uses
    (``m = -(vertices inside) mod 3`` for the fewest pieces), so the budget
    ``3 * pieces - n + 2`` prunes most candidates before any geometry is looked at.
    """
    n = len(polygon)
    size = 2 * n
    budget = 3 * pieces - n + 2
    points = np.empty((size, 2))
    points[0::2] = polygon
    points[1::2] = (polygon + np.roll(polygon, -1, axis=0)) / 2
    corner = _corner_scores(points).ravel()
    best = np.full((budget + 1, size, size + 1), -np.inf)
    best[0, :, 1] = np.inf
    best[0, 0::2, 2] = np.inf
    choice = np.zeros(best.shape, dtype=np.int64)
    for length in range(4, size - 3):
        for parity in (0, 1):
            cands = _interval_candidates(length, parity, budget)
            starts = np.arange(parity, size, 2)
            scores = _piece_scores(starts, cands.chain, cands.sub_m, best, corner)
            for m in range(budget + 1):
                lo, hi = cands.bounds[m], cands.bounds[m + 1]
                if lo < hi:
                    pick = lo + np.argmax(scores[:, lo:hi], axis=1)
                    best[m, starts, length] = scores[np.arange(len(starts)), pick]
                    choice[m, starts, length] = pick
    root = _root_candidates(n, budget)
    chain, sub_m = (a[:, root.bounds[budget] : root.bounds[budget + 1]] for a in root[:2])
    scores = _piece_scores(np.zeros(1, dtype=np.int64), chain, sub_m, best, corner)[0]
    if not scores.size or scores.max() == -np.inf:
        return None
    top = int(np.argmax(scores))
    found = []
    stack = [(0, chain[:, top], sub_m[:, top])]
    while stack:
        start, offsets, side_m = stack.pop()
        found.append((start + offsets[:5]) % size)
        for j, d in enumerate(np.diff(offsets)):
            if d >= 4:  # a chord: visit the piece chosen next to it, on its far side
                s = (start + offsets[j]) % size
                cands = _interval_candidates(int(d), s % 2, budget)
                k = choice[side_m[j], s, d]
                stack.append((s, cands.chain[:, k], cands.sub_m[:, k]))
    return _assemble_chords(polygon, points, np.array(found), float(scores[top]))


def _assemble_chords(
    polygon: np.ndarray, points: np.ndarray, pieces: np.ndarray, score: float
) -> _Layout:
    n = len(polygon)
    used = np.unique(pieces[pieces % 2 == 1])
    ids = np.full(2 * n, -1, dtype=np.int64)
    ids[0::2] = np.arange(n)
    ids[used] = n + np.arange(len(used))
    chains = [ids[[2 * i, 2 * i + 1, (2 * i + 2) % (2 * n)]] for i in range(n)]
    chains = [c[c >= 0] for c in chains]
    return _Layout("chords", np.vstack([polygon, points[used]]), ids[pieces], chains, score)


def _corner_scores(points: np.ndarray) -> np.ndarray:
    """``out[i, j, k]``: the value of a piece's corner at point ``j`` between ``i`` and ``k``.

    ``-inf`` if the corner does not turn left by more than ``COLLINEAR_SIN_TOL`` in sine (computed
    exactly as :func:`~blockmesh.geometry.corner_sines` does) or is an edge midpoint that no
    chord ends at; ``+inf`` for a polygon corner kept whole; else ``min(theta, 180 - theta)``.
    """
    size = len(points)
    step = points[None, :, :] - points[:, None, :]  # step[i, j] = points[j] - points[i]
    inc, out = step[:, :, None, :], step[None, :, :, :]
    cross = inc[..., 0] * out[..., 1] - inc[..., 1] * out[..., 0]
    dot = inc[..., 0] * out[..., 0] + inc[..., 1] * out[..., 1]
    norms = np.hypot(inc[..., 0], inc[..., 1]) * np.hypot(out[..., 0], out[..., 1])
    sine = np.divide(cross, norms, out=np.zeros_like(cross), where=norms > 0)
    theta = 180.0 - np.degrees(np.arctan2(cross, dot))
    gap = (np.arange(size)[None, :] - np.arange(size)[:, None]) % size  # gap[i, j] = j - i
    even = np.arange(size) % 2 == 0
    side = (gap == 1) | ((gap == 2) & even[:, None])  # i -> j is a boundary side
    whole = side[:, :, None] & side[None, :, :] & even[None, :, None]
    midpoint_unused = side[:, :, None] & side[None, :, :] & ~even[None, :, None]
    value = np.where(whole, np.inf, np.minimum(theta, 180.0 - theta))
    return np.where((sine > COLLINEAR_SIN_TOL) & ~midpoint_unused, value, -np.inf)


#: The star replaces the chord layout only if its score (degrees) is higher by more than this,
#: so that round-off does not decide exact ties.
_SCORE_TOL = 1e-9
#: Candidate pieces scored at once (bounds the temporary arrays to a few MB).
_CHUNK = 1 << 16


class _Candidates(NamedTuple):
    chain: np.ndarray  # (S+1, C) corner offsets along the boundary; the last closes the piece
    sub_m: np.ndarray  # (S, C) midpoints used inside each side's region (0 for boundary sides)
    bounds: np.ndarray  # columns bounds[m]:bounds[m+1] use m midpoints in all


def _candidates(chain: np.ndarray, parity: int, budget: int) -> _Candidates:
    """Keep the corner chains (columns) whose sides can be boundary sides or chords in budget.

    A side over ``d`` points is a boundary side (``d = 1``, or ``d = 2`` from a vertex) or a chord
    (``d >= 4``) whose region needs ``-(vertices inside) mod 3`` midpoints, or 3 more (only when
    the budget allows one piece above the minimum). Midpoint corners count too; the total must
    stay within ``budget``. Columns come sorted by their total, stably.
    """
    d = chain[1:] - chain[:-1]
    odd = (parity + chain) % 2
    start_odd = odd[:-1]
    ok = np.all((d == 1) | ((d == 2) & (start_odd == 0)) | (d >= 4), axis=0)
    chord = d >= 4
    need = np.where(chord, (-((d - 1 + start_odd) // 2)) % 3, 0)
    base = need.sum(axis=0) + odd[1:-1].sum(axis=0)
    keep = np.flatnonzero(ok & (base <= budget))
    cols, subs, totals = [keep], [need[:, keep]], [base[keep]]
    for bump in range(len(d)):
        keep = np.flatnonzero(ok & chord[bump] & (base + 3 <= budget))
        sub = need[:, keep]
        sub[bump] += 3
        cols.append(keep)
        subs.append(sub)
        totals.append(base[keep] + 3)
    total = np.concatenate(totals)
    order = np.argsort(total, kind="stable")
    cands = _Candidates(
        chain[:, np.concatenate(cols)[order]],
        np.concatenate(subs, axis=1)[:, order],
        np.searchsorted(total[order], np.arange(budget + 2)),
    )
    for a in cands:
        a.setflags(write=False)
    return cands


def _triples(stop: int) -> np.ndarray:
    """All ``t1 < t2 < t3`` in ``1..stop-1`` as columns, shape ``(3, C(stop-1, 3))``."""
    t = np.arange(1, stop)
    i, j, k = np.meshgrid(t, t, t, indexing="ij", sparse=True)
    return np.stack(np.nonzero((i < j) & (j < k))) + 1


@lru_cache(maxsize=512)
def _interval_candidates(length: int, parity: int, budget: int) -> _Candidates:
    """Pieces ``(0, t1, t2, t3, length)`` next to a chord spanning ``length`` points."""
    t = _triples(length)
    row = np.ones((1, t.shape[1]), dtype=np.int64)
    return _candidates(np.vstack([0 * row, t, length * row]), parity, budget)


@lru_cache(maxsize=64)
def _root_candidates(n: int, budget: int) -> _Candidates:
    """Pieces ``(0, c1, .., c4)`` holding the boundary side that leaves vertex 0 (``c1 <= 2``)."""
    size = 2 * n
    chains = []
    for c1 in (1, 2):
        t = c1 + _triples(size - c1)
        row = np.ones((1, t.shape[1]), dtype=np.int64)
        chains.append(np.vstack([0 * row, c1 * row, t, size * row]))
    return _candidates(np.hstack(chains), 0, budget)


def _piece_scores(
    starts: np.ndarray, chain: np.ndarray, sub_m: np.ndarray, best: np.ndarray, corner: np.ndarray
) -> np.ndarray:
    """Score of every candidate piece at every start, shape ``(len(starts), chain.shape[1])``.

    The minimum over the piece's sides (``best`` looked up for each side's region) and its five
    corners (``corner``, the flattened table of :func:`_corner_scores`).
    """
    size = best.shape[1]
    fixed = (sub_m * (size * (size + 1)) + (chain[1:] - chain[:-1]))[:, None, :]
    out = np.empty((len(starts), chain.shape[1]))
    step = max(1, _CHUNK // max(1, chain.shape[1]))
    for lo in range(0, len(starts), step):
        at = (starts[None, lo : lo + step, None] + chain[:, None, :]) % size
        sides = best.ravel()[fixed + at[:-1] * (size + 1)]
        c = at[:5]
        turns = corner[(c[[4, 0, 1, 2, 3]] * size + c) * size + c[[1, 2, 3, 4, 0]]]
        np.minimum(sides.min(axis=0), turns.min(axis=0), out=out[lo : lo + step])
    return out
