"""Composite domains: several parts (materials) meshed together, conforming across interfaces.

A composite domain is a list of parts (:mod:`blockmesh.domain.parts`), each a region with its
geometry. They are put together the way gmsh's boolean *fragment* does it:

**a later part is cut out of the earlier ones.** A fibre listed after the matrix it lies in makes
the matrix a part with a hole and the fibre its own region; parts may also touch along edges or
overlap anywhere, and where two overlap the later one wins. Nobody cuts holes by hand.

The steps (``docs/composite.md``):

1. every circle (circular holes, discs, arcs, a Domain's arcs) is followed at points shared by
   every part on it, with the points where other parts cross it computed exactly, and more
   finely where two outlines would otherwise follow one chord along different curves (a thin
   lens between two circles, a circle's cap cut by a straight edge), so that no face between
   them is lost however thin; the points where straight edges cross, and corners lying on
   another part's edge, are fixed on the edges too (:mod:`~blockmesh.domain.compose.edges`);
2. the parts are fragmented (shapely: region ``i`` is part ``i`` minus the later parts), their
   boundaries noded, and the faces of the arrangement found (:func:`shapely.polygonize`); each
   face is a connected piece of one region, its rings point ids of the arrangement;
3. the input is checked, each problem a located :class:`~blockmesh.errors.DomainError` naming the
   parts: a part the later ones cover entirely, parts that touch at a point only, slivers and
   gaps thinner than :data:`~blockmesh.domain.validate.NEAR_TOL` times the domain's size;
4. all faces are decomposed at once (:func:`blockmesh.decompose.fragments.decompose_faces`): the
   blocks of neighbouring regions meet edge to edge along every interface;
5. block vertices on a chord of a circle move onto the circle, and every block edge along it
   becomes an arc around the circle's centre: stored once per edge, so a fibre keeps a true
   circle on both sides and both regions share its nodes bit for bit at every level (blocks
   that fold there are made again with the circles followed more finely, :data:`FINER`; a
   sliver too thin for them even then is a located error naming its region and the parts);
6. the Domain gets its regions, boundary patches (the parts' patches where their edges are on
   the boundary, ``"boundary"`` elsewhere) and interfaces (``"A|B"`` between regions ``A`` and
   ``B``, in the order of the parts, unless renamed).

Step 1 is :mod:`~blockmesh.domain.compose.circles`, step 2
:mod:`~blockmesh.domain.compose.fragments`, step 3 :mod:`~blockmesh.domain.compose.arrangement`,
steps 5 and 6 :mod:`~blockmesh.domain.compose.build`; :func:`compose_parts` runs them in turn.

Examples
--------
>>> import shapely
>>> from blockmesh import Domain
>>> d = Domain.compose({"a": shapely.box(0, 0, 1, 1), "b": shapely.box(1, 0, 2, 1)})
>>> d.region_names, d.interface_names, round(d.area, 12)
(('a', 'b'), ('a|b',), 2.0)
>>> fibre = Domain.compose({"matrix": shapely.box(0, 0, 2, 2),
...                         "fibre": Domain.from_circle((1, 1), 0.5)})
>>> fibre.interface_names, round(fibre.area, 12)
(('matrix|fibre',), 4.0)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.decompose.fragments import decompose_faces
from blockmesh.domain.compose.arrangement import Arrangement
from blockmesh.domain.compose.build import BlocksFailError, build_domain, interface_renames
from blockmesh.domain.compose.circles import (
    CIRCLE_PIECES,
    SHARED_CHORD_PIECES,
    Circles,
    circles_of,
    crossings,
    follow,
    grade_near_misses,
    split_crossed_chords,
    split_shared_chords,
)
from blockmesh.domain.compose.edges import edge_crossings, merge_splits, on_edge_tol
from blockmesh.domain.compose.fragments import (
    SourcePieces,
    fragments,
    part_shape,
    report_filled_holes,
)
from blockmesh.domain.parts import Part, part_from_value
from blockmesh.domain.validate.tolerances import NEAR_TOL
from blockmesh.errors import ArgumentTypeError, DomainError

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["CIRCLE_PIECES", "MIN_ANGLE", "compose_mapping", "compose_parts"]
#: How many times finer circles are followed when the blocks along them do not stay convex with
#: their arcs (a chord's bulge larger than the blocks beside it, as where two circles cross at a
#: sharp angle): each try doubles the chords of every circle.
FINER = (1, 2, 4, 8)
#: Smallest angle (degrees) the triangulation of the faces aims at: above the single polygon's
#: default, as the faces' chords of circles make corners where many triangles would meet
#: (measured on a disc in a square: 22 degrees gives blocks of 22.5, 30 gives 43.7, 18 % more).
MIN_ANGLE = 30.0
#: Most rounds of following the outlines and splitting chords (two or three are the rule: a
#: corner between a chord and its circle takes one more round per halving of the chords near it).
_FOLLOW_ROUNDS = 24


def compose_parts(
    cls: type[Domain],
    parts: Sequence[Part],
    *,
    name: str = "composite",
    description: str = "",
    interfaces: Mapping[str, str] | None = None,
) -> Domain:
    """The composite Domain of ``parts`` (see the module docstring).

    The front door is :meth:`blockmesh.Domain.compose` (and the domain files' ``[[parts]]``).

    ``interfaces`` renames interfaces: ``{"matrix|fibre": "bond"}`` (either order of the two
    regions).
    """
    parts = list(parts)
    if not parts:
        raise DomainError("a composite domain needs at least one part")
    check_region_names(parts)
    renames = interface_renames(interfaces, parts)
    size = extent(parts)
    for attempt, finer in enumerate(FINER):
        circles, pieces, arrangement = arrange(parts, size, finer, report=attempt == 0)
        result = decompose_faces(arrangement.points, arrangement.faces, min_angle=MIN_ANGLE)
        try:
            return build_domain(
                cls, parts, arrangement, result, circles, pieces, renames, name, description
            )
        except BlocksFailError as failed:
            # Blocks that fold with their arcs: follow the circles more finely and try again.
            if not circles.items or finer == FINER[-1]:
                raise failed.located(parts, arrangement, pieces) from None
    raise AssertionError("unreachable")  # pragma: no cover


def compose_mapping(
    cls: type[Domain], parts: Mapping[str, Any], patches: Any = None, **options: Any
) -> Domain:
    """The Domain of :meth:`blockmesh.Domain.compose` (see there), as ``cls``.

    ``options`` (``name``, ``description``, ``interfaces``) go to :func:`compose_parts`.
    """
    if not isinstance(parts, Mapping):
        raise ArgumentTypeError(
            f"compose takes a mapping of region name to part, got {type(parts).__name__}"
        )
    patches = patches or {}
    unknown = sorted(set(patches) - set(parts))
    if unknown:
        raise DomainError(
            f"patches name the region {unknown[0]!r}, but the parts are "
            f"{', '.join(map(str, parts))}"
        )
    listed = [
        part_from_value(cls, region, value, k, patches.get(region))
        for k, (region, value) in enumerate(parts.items())
    ]
    return compose_parts(cls, listed, **options)


def arrange(
    parts: list[Part], size: float, finer: int = 1, *, report: bool = False
) -> tuple[Circles, SourcePieces, Arrangement]:
    """Steps 1 to 3: the circles followed, the parts fragmented, the arrangement checked.

    ``size`` is the parts' :func:`extent`, ``finer`` how many times finer the circles are
    followed (:data:`FINER`); with ``report``, a hole that a later part fills is reported (a
    warning). Returns the circles, the pieces of the outlines and the checked arrangement.
    """
    tol = NEAR_TOL * size
    circles = circles_of(parts, size)
    splits = crossings(parts, circles, tol)
    merge_splits(splits, edge_crossings(parts, tol, on_edge_tol(parts, size)))
    grade_near_misses(parts, circles, tol)
    for _ in range(_FOLLOW_ROUNDS):
        for circle in circles.items:
            circle.sample(finer)
        rings = [
            [[follow(o, circles, splits, (i, j, r)) for r, o in enumerate(polygon)]
             for j, polygon in enumerate(part.polygons)]
            for i, part in enumerate(parts)
        ]  # fmt: skip
        # Chords two outlines share along different curves get their arcs' middles fixed, and
        # chords that straight edges cross get the circle graded around the corner beyond them;
        # the outlines are followed again until nothing more is split (a few rounds; what is
        # left after the last, the arrangement's checks judge).
        followed = [ring for part in rings for polygon in part for ring in polygon]
        shared = split_shared_chords(followed, circles, SHARED_CHORD_PIECES * finer)
        if not shared and not split_crossed_chords(followed, circles):
            break
    shapes = [part_shape(part, ring) for part, ring in zip(parts, rings, strict=True)]
    regions = fragments(parts, shapes)
    pieces = SourcePieces(parts, rings)
    if report:
        report_filled_holes(parts, rings, regions, tol)
    return circles, pieces, Arrangement.of(parts, regions, pieces, tol)


def check_region_names(parts: list[Part]) -> None:
    """Each region named by one part; a located error for a region given twice."""
    seen: dict[str, Part] = {}
    for part in parts:
        if part.region in seen:
            raise DomainError(
                f"the region {part.region!r} is given twice, by {seen[part.region].label} and "
                f"{part.label}; a region is one part (give its pieces together: one part with "
                "several circles, or a MultiPolygon)"
            )
        seen[part.region] = part


def extent(parts: list[Part]) -> float:
    """The diagonal of the box around every part (1 for a point): the domain's size."""
    points = []
    for part in parts:
        for polygon in part.polygons:
            for outline in polygon:
                if outline.circle is not None:
                    (cx, cy), r, _ = outline.circle
                    points.append(np.array([[cx - r, cy - r], [cx + r, cy + r]]))
                else:
                    points.append(outline.corners)
    xy = np.vstack(points)
    return float(np.hypot(*np.ptp(xy, axis=0))) or 1.0
