"""A domain re-cut into blocks of the sizes a field asks for (``Domain.with_size``, ``--size``).

Any :class:`~blockmesh.domain.Domain` (a decomposed polygon, explicit blocks, a converted mesh,
a disc) is read as an outline: its boundary loops and the interfaces between its regions, cut
into chains at its corners (where the boundary turns, the patch changes, a curve starts or
regions meet). The size-driven decomposition (:func:`blockmesh.decompose.sized.sized_blocks`)
fills the outline with blocks of the sizes asked, and the new Domain keeps what the old one
said about its outline: every new boundary edge is in the patch of the boundary it lies on,
every block in the region it lies in, arcs stay arcs (each new edge along one is a piece of the
same circle, its nodes on the circle at every level), and for a domain made from a polygon,
every boundary edge still knows the polygon edge it lies on (:attr:`Domain.boundary_source`).

The size spec (:mod:`blockmesh.sizing.spec`) is resolved against the domain's patches and regions
first, and the memory guard predicts the cell count from the field (the integral of
``1 / (a h^2)``) before any block is made.

Examples
--------
>>> from blockmesh import Domain
>>> square = Domain.from_polygon([(0, 0), (1, 0), (1, 1), (0, 1)], patches={"bottom": [0]})
>>> fine = square.with_size({"default": 0.2, "near": [{"patch": "bottom", "size": 0.05,
...                                                     "growth": 1.3}]})
>>> fine.layout, fine.patch_names, fine.n_blocks > square.n_blocks
('sized', ('bottom', 'boundary'), True)
>>> bool(fine.size_report().worst_ratio <= 1.5)
True
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh._system.memory import available_memory, format_bytes, format_count
from blockmesh.curves.types import Arc, Curve, Polyline
from blockmesh.decompose.outline import CURVE_TURN_SAFE, ChainCurve, Outline, arc_pieces
from blockmesh.decompose.sized import SizedBlocks, sized_blocks
from blockmesh.errors import ArgumentError, DomainError, ResourceError, fmt_point
from blockmesh.geometry.polygons import COLLINEAR_SIN_TOL
from blockmesh.sizing.fields import SizeField, checked_sizes
from blockmesh.sizing.predict import EVALUATIONS, FLOOR, ideal_count, smallest_size
from blockmesh.sizing.spec import SizeSpec, as_size_spec

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["BYTES_PER_BLOCK", "DomainGeometry", "resized", "size_fits"]

#: Peak memory of the size-driven decomposition per block made (measured: triangulations, the
#: relaxation and the optimiser's work arrays: 3.8 kB measured at 100,000 blocks, with a margin).
BYTES_PER_BLOCK = 4608
#: Depth to which the curved blocks of a sized domain are checked (each of their curved edges
#: turns by about a third of :data:`~blockmesh.decompose.outline.CURVE_TURN`, at most 14.7
#: degrees, so the curve-aware refinement meets no new fold deeper down: the eleven curved
#: catalogue domains at 5 and 10 cells across refine to levels 4-5 with every cell strictly
#: convex; the full check would refine each to 7,776 cells).
CURVE_CHECK_LEVELS = 3
#: Points per curved edge when a patch's distance field or a region's polygon is drawn.
_CURVE_SAMPLES = 32
#: Points along the boundary (per the domain's width) where the field is checked first.
_OUTLINE_SAMPLES = 1024


@dataclass(frozen=True, eq=False)
class DomainGeometry:
    """The patches and regions of a domain as a size spec looks them up (``SizeGeometry``)."""

    domain: Domain

    @property
    def patch_names(self) -> tuple[str, ...]:
        """The domain's patches."""
        return self.domain.patch_names

    @property
    def region_names(self) -> tuple[str, ...]:
        """The domain's regions."""
        return self.domain.region_names

    def _edge_points(self, a: int, b: int) -> np.ndarray:
        """Points along block edge (a, b): its ends, and samples of its curve if it has one."""
        d = self.domain
        curve = d.curves.get((a, b))
        if curve is None and (b, a) in d.curves:
            return self._edge_points(b, a)[::-1]
        if curve is None:
            return d.vertices[[a, b]]
        return np.asarray(curve.point(np.linspace(0.0, 1.0, _CURVE_SAMPLES + 1)))

    def patch_segments(self, name: str) -> np.ndarray:
        """Straight pieces (S, 2, 2) along patch ``name``, curved edges sampled."""
        edges = self.domain.patches[name]
        pieces = []
        for a, b in edges.tolist():
            xy = self._edge_points(a, b)
            pieces.append(np.stack([xy[:-1], xy[1:]], axis=1))
        return np.concatenate(pieces) if pieces else np.zeros((0, 2, 2))

    def region_polygon(self, name: str) -> Any:
        """The union of the region's blocks, curved edges sampled."""
        import shapely

        polygons = []
        for block in self.domain.blocks[self.domain.regions[name]].tolist():
            ring = [self._edge_points(a, b)[:-1] for a, b in itertools.pairwise([*block, block[0]])]
            polygons.append(shapely.Polygon(np.vstack(ring)))
        return shapely.union_all(polygons)

    def polygon(self) -> Any:
        """The whole domain as a shapely polygon (curved edges sampled)."""
        import shapely

        return shapely.union_all([self.region_polygon(n) for n in self.region_names])


# ---------------------------------------------------------------------------- the outline
@dataclass
class _Edge:
    a: int
    b: int
    left: int
    right: int
    patch: int  # -1 on an interface
    curve: Curve | None  # from a to b, bound
    source: tuple[int, int]
    interface: int = -1  # index into the domain's interface_names, or -1


def _curve_from(domain: Domain, a: int, b: int) -> Curve | None:
    """The curve of block edge (a, b), bound to run from a to b, or None."""
    curve = domain.curves.get((a, b))
    if curve is not None:
        return curve
    curve = domain.curves.get((b, a))
    if curve is None:
        return None
    p, q = domain.vertices[a], domain.vertices[b]
    if isinstance(curve, Arc):
        middle = curve.point(0.5)
        return Arc(through=(float(middle[0]), float(middle[1]))).with_ends(p, q)
    if isinstance(curve, Polyline):
        points = tuple((float(x), float(y)) for x, y in curve.points)[::-1]
        return Polyline(points=points).with_ends(p, q)
    return _Reversed(curve)  # type: ignore[return-value]


@dataclass(frozen=True, eq=False)
class _Reversed:
    """A curve run backwards (parameter ``1 - t``): what the outline needs of it."""

    curve: Curve

    def point(self, t: Any) -> np.ndarray:
        return np.asarray(self.curve.point(1.0 - np.asarray(t, dtype=np.float64)))

    def derivative(self, t: Any) -> np.ndarray:
        return -np.asarray(self.curve.derivative(1.0 - np.asarray(t, dtype=np.float64)))


def _outline_edges(domain: Domain) -> tuple[list[_Edge], np.ndarray]:
    """Boundary edges (the domain on their left) and interface edges (a region each side).

    Polyline edges come as straight edges between their points, which are returned too (they
    are numbered after the domain's vertices).
    """
    edges: list[_Edge] = []
    source = domain.boundary_source
    block_of_edge: dict[tuple[int, int], int] = {}
    for k, block in enumerate(domain.blocks.tolist()):
        for i in range(5):
            block_of_edge[(block[i], block[(i + 1) % 5])] = k
    for row, (a, b) in enumerate(domain.boundary_edges.tolist()):
        owner = block_of_edge[(a, b)]
        edges.append(
            _Edge(a, b, int(domain.region[owner]), -1, int(domain.boundary_patch[row]),
                  _curve_from(domain, a, b), (int(source[row, 0]), int(source[row, 1])))
        )  # fmt: skip
    # Named interfaces as the domain orients them (the first side's block on the left).
    named = {
        (int(a), int(b)): int(i)
        for (a, b), i in zip(domain.interface_edges.tolist(), domain.interface_patch.tolist(),
                             strict=True)
    }  # fmt: skip
    for (a, b), k in block_of_edge.items():
        other = block_of_edge.get((b, a))
        if other is None:
            continue
        interface = named.get((a, b), -1)
        if interface < 0 and ((b, a) in named or domain.region[k] == domain.region[other] or a > b):
            continue
        edges.append(
            _Edge(a, b, int(domain.region[k]), int(domain.region[other]), -1,
                  _curve_from(domain, a, b), (-1, -1), interface)
        )  # fmt: skip
    return _split_polylines(domain, edges)


def _split_polylines(domain: Domain, edges: list[_Edge]) -> tuple[list[_Edge], np.ndarray]:
    """Polyline edges become straight edges between their points (the points become corners)."""
    out = []
    extra: list[np.ndarray] = []
    n = domain.n_vertices
    for e in edges:
        if not isinstance(e.curve, Polyline):
            out.append(e)
            continue
        ids = [e.a]
        for point in e.curve.points:
            extra.append(np.asarray(point, dtype=np.float64))
            ids.append(n + len(extra) - 1)
        ids.append(e.b)
        for p, q in itertools.pairwise(ids):
            out.append(_Edge(p, q, e.left, e.right, e.patch, None, e.source, e.interface))
    return out, np.array(extra).reshape(-1, 2)


def _same_circle(one: Curve | None, two: Curve | None) -> bool:
    if not (isinstance(one, Arc) and isinstance(two, Arc)):
        return False
    c1, c2 = np.array(one.centre_point), np.array(two.centre_point)
    r = max(one.radius, two.radius)
    return bool(np.hypot(*(c1 - c2)) <= 1e-9 * r and abs(one.radius - two.radius) <= 1e-9 * r)


def _outline(
    domain: Domain,
) -> tuple[Outline, np.ndarray, list[tuple[int, int]], np.ndarray]:
    """The domain's outline: chains between corners; each chain's patch and polygon edge.

    Returns ``(outline, chain_patch, chain_source, chain_interface)``: the patch index of each
    chain (-1 for an interface), its ``(ring, edge)`` source (``(-1, -1)`` when not known) and
    its named interface (an index into ``domain.interface_names``, -1 for none).
    """
    edges, extra = _outline_edges(domain)
    points = np.vstack([domain.vertices, extra])
    outgoing: dict[int, list[int]] = {}
    incoming: dict[int, list[int]] = {}
    for k, e in enumerate(edges):
        outgoing.setdefault(e.a, []).append(k)
        incoming.setdefault(e.b, []).append(k)

    def joins(first: _Edge, second: _Edge) -> bool:
        """Whether the two edges, meeting at a vertex of nothing else, are one chain."""
        same = (first.left, first.right, first.patch, first.source, first.interface) == (
            second.left, second.right, second.patch, second.source, second.interface)  # fmt: skip
        if not same:
            return False
        if first.curve is None and second.curve is None:
            u = points[first.b] - points[first.a]
            v = points[second.b] - points[second.a]
            cross = u[0] * v[1] - u[1] * v[0]
            return bool(abs(cross) <= COLLINEAR_SIN_TOL * np.hypot(*u) * np.hypot(*v)) and bool(
                u @ v > 0
            )
        return _same_circle(first.curve, second.curve)

    # A vertex continues a chain when one edge comes in, one goes out, and they join.
    through: dict[int, tuple[int, int]] = {}
    for v, ins in incoming.items():
        outs = outgoing.get(v, [])
        if len(ins) == 1 and len(outs) == 1 and joins(edges[ins[0]], edges[outs[0]]):
            through[v] = (ins[0], outs[0])
    follow = {ins: outs for ins, outs in through.values()}
    starts = [k for k, e in enumerate(edges) if e.a not in through]
    runs: list[list[int]] = []
    seen: set[int] = set()
    for k in starts:
        run = [k]
        while run[-1] in follow:
            run.append(follow[run[-1]])
        runs.append(run)
        seen.update(run)
    # Loops with no corner at all (a whole circle): cut them at their first edge.
    for k in range(len(edges)):
        if k in seen:
            continue
        run = [k]
        while follow.get(run[-1], k) != k:
            run.append(follow[run[-1]])
        runs.append(run)
        seen.update(run)
    # Arcs join while they turn by less than half a circle (an arc is fixed by its ends and a
    # point); longer runs are cut in equal parts.
    cut: list[list[int]] = []
    for run in runs:
        curve = edges[run[0]].curve
        if isinstance(curve, Arc) and len(run) > 1:
            sweep = sum(abs(edges[k].curve.sweep) for k in run)  # type: ignore[union-attr]
            parts = max(1, math.ceil(sweep / (0.9 * math.pi)))
            size = math.ceil(len(run) / parts)
            cut += [run[i : i + size] for i in range(0, len(run), size)]
        else:
            cut.append(run)
    corner_ids = sorted({edges[run[0]].a for run in cut} | {edges[run[-1]].b for run in cut})
    index = {v: i for i, v in enumerate(corner_ids)}
    chains, left, right, patch, sources, interface = [], [], [], [], [], []
    curves: list[ChainCurve | None] = []
    for run in cut:
        first, last = edges[run[0]], edges[run[-1]]
        chains.append((index[first.a], index[last.b]))
        left.append(first.left)
        right.append(first.right)
        patch.append(first.patch)
        sources.append(first.source)
        interface.append(first.interface)
        if first.curve is None:
            curves.append(None)
        elif len(run) == 1:
            curves.append(ChainCurve(first.curve))
        else:
            middle = edges[run[len(run) // 2]].curve.point(0.5 if len(run) % 2 else 0.0)  # type: ignore[union-attr]
            arc = Arc(through=(float(middle[0]), float(middle[1]))).with_ends(
                points[first.a], points[last.b]
            )
            curves.append(ChainCurve(arc))
    outline = Outline(
        corners=points[corner_ids],
        chains=np.array(chains, dtype=np.int64).reshape(-1, 2),
        curves=tuple(curves),
        left=np.array(left, dtype=np.int64),
        right=np.array(right, dtype=np.int64),
    )
    return outline, np.array(patch, dtype=np.int64), sources, np.array(interface, np.int64)


# ---------------------------------------------------------------------------- the guard
def size_fits(field: SizeField, geometry: DomainGeometry, max_memory: int | None = None) -> float:
    """The predicted ideal cell count; ResourceError when the blocks would not fit in memory.

    The count is the integral of ``1 / (a h^2)`` over the domain
    (:func:`~blockmesh.sizing.ideal_count`, in at most
    :data:`~blockmesh.sizing.predict.EVALUATIONS` evaluations of the field whatever the sizes
    asked); the decomposition makes about 1.5 times that many blocks, each needing about
    :data:`BYTES_PER_BLOCK` while it is made. A field scaled by ``s`` asks ``1 / s^2`` times the
    cells, so the error names the largest size that fits: every size asked times
    ``sqrt(count / cells that fit)``. A field that falls towards 0 somewhere (its smallest size,
    searched from the smallest sampled, below :data:`~blockmesh.sizing.predict.FLOOR` of the
    domain's width) is an ArgumentError naming the place.

    A count the budget did not finish is a lower bound: above what fits, it is refused ("at
    least"); below, it is counted on with a budget of a few evaluations per cell that fits (the
    mesh about to be made costs far more) and refused as soon as it passes what fits.
    """
    limit = available_memory() if max_memory is None else int(max_memory)
    fits = limit / (BYTES_PER_BLOCK * 1.5)
    polygon = geometry.polygon()
    _check_outline(field, polygon)
    count = ideal_count(field, polygon)
    least = count.finest_size
    if count.finest is not None:
        low_x, low_y, high_x, high_y = polygon.bounds
        where, least = smallest_size(field, polygon, count.finest)
        if least < FLOOR * max(high_x - low_x, high_y - low_y):
            raise ArgumentError(
                f"{field.label} gets ever smaller near {fmt_point(where)} (down to {least:.3g}, "
                f"less than {FLOOR:g} of the domain's width): a size must stay above some number "
                "> 0 everywhere in the domain, or the mesh would need endlessly many cells"
            )
    if not count.complete and count.cells <= fits:
        count = ideal_count(field, polygon, limit=fits, budget=max(EVALUATIONS, int(4 * fits)))
    if count.cells <= fits:
        return count.cells
    cells = count.cells
    scale = math.sqrt(cells / fits)
    smallest = field.smallest if field.smallest > 0 else min(count.finest_size, least)
    if count.complete:
        more, hint = (
            "",
            (
                f"the largest size that fits is about {smallest * scale:.3g} (every size asked "
                f"{scale:.3g} times larger)"
            ),
        )
    else:
        more, hint = (
            "at least ",
            (
                f"the largest size that fits is at most {smallest * scale:.3g} (every size asked "
                f"{scale:.3g} times larger or more)"
            ),
        )
    if field.smallest <= 0:
        hint += f"; the smallest size asked is about {smallest:.3g}"
    source = "the limit given" if max_memory is not None else "the memory available now"
    raise ResourceError(
        f"the size field asks for {more}{format_count(int(cells))} cells (the integral of "
        f"1 / (0.6572 h^2) over {geometry.domain.name!r}); making their blocks needs about "
        f"{format_bytes(int(cells * 1.5 * BYTES_PER_BLOCK))}, more than {source} "
        f"({format_bytes(limit)}): {hint}"
    )


def _check_outline(field: SizeField, polygon: Any) -> None:
    """The field checked along the domain's boundary and at its own seeds inside the domain.

    The count samples box centres, which never fall on the boundary: a field that is 0 (or not
    finite) on the boundary, such as ``0.1*y`` on a domain whose edge is ``y = 0``, is found
    here, at the point, before any counting.
    """
    import shapely

    low_x, low_y, high_x, high_y = polygon.bounds
    spacing = max(high_x - low_x, high_y - low_y) / _OUTLINE_SAMPLES
    boundary = shapely.segmentize(polygon.boundary, spacing) if spacing > 0 else polygon.boundary
    points = [shapely.get_coordinates(boundary)]
    seeds = np.asarray(field.seeds(), dtype=np.float64).reshape(-1, 2)
    if len(seeds):
        points.append(seeds[shapely.intersects_xy(polygon, seeds[:, 0], seeds[:, 1])])
    checked_sizes(field, np.vstack(points))


# ---------------------------------------------------------------------------- the domain
def resized(
    domain: Domain,
    size: Any,
    *,
    gradation: float | None = None,
    max_memory: int | None = None,
    source: str = "size",
) -> Domain:
    """``domain`` re-cut into blocks of the sizes ``size`` asks for (see the module notes).

    Parameters
    ----------
    domain : Domain
    size : number, expression, function, size table, SizeField or SizeSpec
        As :func:`blockmesh.sizing.as_size_spec` takes them.
    gradation : float, optional
        Largest size ratio between neighbouring cells the field may ask (default: the spec's,
        1.3).
    max_memory : int, optional
        Refuse fields whose blocks are predicted to need more bytes than this.
    source : str
        How messages name the size spec.

    Returns
    -------
    Domain
        Its ``size_field`` is the field asked; ``layout`` is ``"sized"``.
    """
    spec: SizeSpec = as_size_spec(size, source=source)
    geometry = DomainGeometry(domain)
    field = spec.field(geometry)
    size_fits(field, geometry, max_memory)
    outline, chain_patch, chain_source, chain_interface = _outline(domain)
    rate = spec.gradation if gradation is None else gradation
    chains = (chain_patch, chain_source, chain_interface)
    # Curves sampled every CURVE_TURN; if a block along one folds, again every CURVE_TURN_SAFE.
    try:
        sized = _sized_domain(domain, outline, sized_blocks(outline, field, gradation=rate), chains)
    except DomainError:
        if all(curve is None for curve in outline.curves):
            raise
        outline = replace(outline, curve_turn=CURVE_TURN_SAFE)
        sized = _sized_domain(domain, outline, sized_blocks(outline, field, gradation=rate), chains)
    object.__setattr__(sized, "size_field", field)
    object.__setattr__(sized, "size_gradation", rate)
    return sized


def _sized_domain(
    domain: Domain,
    outline: Outline,
    made: SizedBlocks,
    chains: tuple[np.ndarray, list[tuple[int, int]], np.ndarray],
) -> Domain:
    """The Domain of the blocks ``made``, with the patches, interfaces, regions and curves.

    ``chains`` is ``(chain_patch, chain_source, chain_interface)`` as :func:`_outline` gives
    them. Raises DomainError when the blocks fail the Domain's own checks (a block that folds
    along its curve when refined).
    """
    chain_patch, chain_source, chain_interface = chains
    patches: dict[str, list[tuple[int, int]]] = {name: [] for name in domain.patch_names}
    boundary_source: dict[tuple[int, int], tuple[int, int]] = {}
    curved: dict[tuple[int, int], Curve] = {}
    interfaces: dict[str, list[tuple[int, int]]] = {n: [] for n in domain.interface_names}
    for c, (ids, params) in enumerate(zip(made.chain_nodes, made.chain_params, strict=True)):
        pairs = list(zip(ids[:-1].tolist(), ids[1:].tolist(), strict=True))
        if chain_interface[c] >= 0:
            interfaces[domain.interface_names[chain_interface[c]]] += pairs
        if chain_patch[c] >= 0:
            patches[domain.patch_names[chain_patch[c]]] += pairs
            if chain_source[c][0] >= 0:
                for pair in pairs:
                    boundary_source[pair] = chain_source[c]
        for pair, arc in zip(pairs, arc_pieces(outline, c, params), strict=False):
            curved[pair] = arc
    regions = {
        name: np.flatnonzero(made.region == k).tolist()
        for k, name in enumerate(domain.region_names)
    }
    try:
        return type(domain)._from_parsed(
            made.vertices,
            made.blocks,
            {k: v for k, v in patches.items() if v},
            {k: v for k, v in regions.items() if v},
            boundary_source=boundary_source or None,
            edges=curved or None,
            curve_levels=CURVE_CHECK_LEVELS,
            interfaces={k: v for k, v in interfaces.items() if v} or None,
            components=domain.components,
            name=domain.name,
            description=domain.description,
            layout="sized",
        )
    except DomainError as error:
        raise DomainError(
            f"the blocks made for the sizes asked of {domain.name!r} fail their own check "
            f"({error}); ask larger sizes near the curved or thin parts"
        ) from None
