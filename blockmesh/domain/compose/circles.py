"""The circles of a composite domain, each followed at points every part on it shares.

Every circle (circular holes, discs, arcs, a Domain's arcs) is found once (:class:`Circles`),
with the points fixed on it: the ends of arcs, corners on it, and the points where straight edges
and other circles cross it (:func:`crossings`, computed once so that both share them bit for
bit). :func:`follow` turns a part's outline into the closed list of points every part on its
circles shares, with the curve each piece follows.

Two outlines may follow the same two points along different curves: two discs overlapping in a
lens whose arcs are each one chord, a straight edge that is a chord of a circle. Their pieces
then coincide, and the thin face between the true curves vanishes. :func:`split_shared_chords`
fixes a point in the middle of every such arc, so that the followed outlines keep the face.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely

from blockmesh.domain.compose.edges import straight_edges
from blockmesh.domain.parts import Outline, Part

__all__ = [
    "CIRCLE_PIECES",
    "GRADED_WIDTH",
    "NEAR_MISS_WIDTH",
    "SHARED_CHORD_PIECES",
    "SHARP_CROSSING",
    "Circle",
    "Circles",
    "FollowedRing",
    "circles_of",
    "crossings",
    "follow",
    "grade_near_misses",
    "split_crossed_chords",
    "split_shared_chords",
]

#: Chords a whole circle is followed with by default (two per 45 degrees; a part's circle may
#: ask for more with ``sides``); between the points fixed on a circle no chord turns more.
CIRCLE_PIECES = 16
#: Pieces an arc is cut into where two outlines follow it and another curve along one chord (times
#: ``finer`` of :meth:`Circle.sample`): its middle is enough to keep the face between them.
SHARED_CHORD_PIECES = 2
#: Relative distance under which two circles are the same circle (centres and radii).
_SAME_CIRCLE = 1e-9
#: Crossings of a circle sharper than this (radians) get its chords graded towards them. Measured
#: on random composites of a box, polygons, stars, holed polygons and discs: at 15 degrees the
#: blocks along blunter crossings stay convex without it (1 of 300 composites changes, +0.05 %
#: blocks), and every cusp refused before in 150 draws is meshed; at 40 degrees 16 of 300 change
#: (+9 % blocks) for nothing more.
SHARP_CROSSING = math.radians(15.0)
#: Narrowest wedge (times the arrangement's tolerance) where :meth:`Circle.grade_towards` puts a
#: point: nearer the crossing, the points on the two curves would come within a few tolerances.
GRADED_WIDTH = 30.0
#: Narrowest gap (times the arrangement's tolerance) that :meth:`Circle.grade_near` grades the
#: chords beside: its points stay the whole gap from the other outline. Measured in a 2 x 1.5
#: square, with a disc of radius 0.5 beside its edge, two discs side by side, a disc inside
#: another: gaps of 3e-5 are meshed (28,000-50,000 blocks), where without the grading gaps of
#: 3e-4 (1e-4 for the two discs side by side) were refused as too thin.
NEAR_MISS_WIDTH = 4.0
#: Smallest angle (radians) between fixed points :meth:`Circle.grade_towards` puts beside a
#: crossing: a curve touching the circle (an angle of 0) gets none (the thin checks judge it).
_MIN_GRADED_STEP = 1e-6


@dataclass
class Circle:
    """One circle of the domain, the points fixed on it, and the points it is followed at."""

    centre: np.ndarray
    radius: float
    exact: bool = False  # the centre and radius as a user gave them (not computed)
    pieces: int = 0  # chords for a whole circle with no fixed points (0: no whole circle)
    spans: list[tuple[tuple[float, float], float]] = field(default_factory=list)  # (start, sweep)
    anchors: set[tuple[float, float]] = field(default_factory=set)  # points fixed on it
    # Points wanted on it to grade the chords, each with the angle it wants kept free around it.
    graded: dict[tuple[float, float], float] = field(default_factory=dict)
    xy: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    angle: np.ndarray = field(default_factory=lambda: np.zeros(0))
    index: dict[tuple[float, float], int] = field(default_factory=dict)

    def angle_of(self, point: Any) -> float:
        """The angle of ``point`` seen from the centre (radians, -pi to pi)."""
        return math.atan2(point[1] - self.centre[1], point[0] - self.centre[0])

    def anchor(self, point: np.ndarray) -> None:
        """Fix ``point`` on the circle: it is followed there."""
        self.anchors.add((float(point[0]), float(point[1])))

    def covers(self, angle: float) -> bool:
        """Whether a point of the circle at ``angle`` lies on a whole circle or an arc of it."""
        if self.pieces:
            return True
        for start, sweep in self.spans:
            turn = (angle - self.angle_of(start)) * math.copysign(1.0, sweep) % (2 * math.pi)
            if turn <= abs(sweep):
                return True
        return False

    def grade(self, angle: float, clearance: float) -> None:
        """Want the circle followed at ``angle`` too, unless a point within ``clearance / 2`` is.

        Unlike a fixed point (:meth:`anchor`), a graded point only shapes the chords: it is left
        out where a fixed point or a finer graded point lies nearer (:meth:`followed_points`).
        """
        if self.covers(angle):
            point = self.centre + self.radius * np.array([math.cos(angle), math.sin(angle)])
            key = (float(point[0]), float(point[1]))
            self.graded[key] = min(clearance, self.graded.get(key, clearance))

    def grade_towards(self, point: np.ndarray, crossing: float, tol: float) -> None:
        """Grade the chords either side of ``point``, where a curve crosses the circle sharply.

        ``crossing`` is the angle (radians) between the circle and the curve crossing it there.
        The nearest points are an eighth of that angle away (seen from the centre), so the chord
        to them leaves the circle at a sixteenth of the crossing angle; the next ones 3, 7, 15,
        ... times as far, up to one chord of the circle's followed outline
        (:data:`CIRCLE_PIECES`). The thin wedge between the curve and the circle then has chords
        that bulge by at most a sixteenth of its width along them, and the blocks in it stay
        convex on their arcs. No point goes where the wedge is narrower than :data:`GRADED_WIDTH`
        times ``tol`` (the arrangement's tolerance): the thin checks judge what is thinner. Nothing
        is added for a crossing of :data:`SHARP_CROSSING` or more.
        """
        step = crossing / 8.0
        span = 2 * math.pi / max(self.pieces, CIRCLE_PIECES)
        if crossing >= SHARP_CROSSING or not _MIN_GRADED_STEP < step < span:
            return
        middle = self.angle_of(point)
        offset = step
        while offset < span:
            if self.radius * offset * math.sin(crossing) >= GRADED_WIDTH * tol:
                self.grade(middle - offset, offset)
                self.grade(middle + offset, offset)
            offset = 2.0 * offset + step

    def grade_near(self, angle: float, gap: float, tol: float) -> None:
        """Grade the chords either side of ``angle``, where an outline passes ``gap`` from the arc.

        A thin gap between the circle and an outline that does not cross it (a fibre nearly
        touching its cell's edge, two discs nearly touching) widens as ``gap + R a**2 / 2`` at an
        angle ``a`` from its narrowest place. The nearest points are where the chord across the
        narrowest place bulges by a sixteenth of the gap; the next ones 1.4 times as far (plus
        that first step), up to one chord of the circle's followed outline, so that every chord
        bulges by a small part of the gap beside it. Nothing is added where the followed chords
        bulge by less than half the gap already, nor for a gap under :data:`NEAR_MISS_WIDTH` times
        ``tol`` (the thin checks judge it).
        """
        span = 2 * math.pi / max(self.pieces, CIRCLE_PIECES)
        bulge = self.radius * (1.0 - math.cos(0.5 * span))
        if not NEAR_MISS_WIDTH * tol <= gap < 2.0 * bulge:
            return
        first = math.sqrt(gap / (8.0 * self.radius))
        offset = first
        while offset < span:
            spacing = 0.4 * offset + first
            self.grade(angle - offset, spacing)
            self.grade(angle + offset, spacing)
            offset += spacing

    def followed_points(self) -> list[tuple[float, float]]:
        """The fixed points, and the graded points that keep their clearance.

        Graded points are taken finest first, each only when half its clearance (an angle) is
        free of every point taken before it.
        """
        kept = sorted(self.anchors)
        taken = [self.angle_of(k) for k in kept]
        for key, clearance in sorted(self.graded.items(), key=lambda item: (item[1], item[0])):
            angle = self.angle_of(key)
            if all(abs(math.remainder(angle - a, 2 * math.pi)) >= 0.5 * clearance for a in taken):
                kept.append(key)
                taken.append(angle)
        return kept

    def sample(self, finer: int = 1) -> None:
        """The points the circle is followed at: its fixed points, and more between them.

        ``finer`` multiplies the number of chords (see :data:`FINER`).
        """
        wanted = max(self.pieces, CIRCLE_PIECES) * finer
        limit = 2 * math.pi / wanted
        keys = sorted(self.followed_points(), key=self.angle_of)
        if not keys:
            even = 2 * math.pi * np.arange(wanted) / wanted
            self.angle = even
            self.xy = self.centre + self.radius * np.c_[np.cos(even), np.sin(even)]
        else:
            first = [self.angle_of(k) for k in keys]
            angles: list[float] = []
            points: list[np.ndarray] = []
            for j, key in enumerate(keys):
                start = first[j]
                gap = (first[(j + 1) % len(keys)] - start) % (2 * math.pi)
                if gap == 0.0:
                    gap = 2 * math.pi
                count = max(1, math.ceil(gap / limit - 1e-9))
                inner = start + gap * np.arange(1, count) / count
                angles += [start, *inner.tolist()]
                points += [np.array(key)[None], self.centre + self.radius * np.c_[
                    np.cos(inner), np.sin(inner)]]  # fmt: skip
            self.angle = np.array(angles)
            self.xy = np.vstack(points)
        self.index = {(float(x), float(y)): k for k, (x, y) in enumerate(self.xy.tolist())}

    def chord(self, p: Any, q: Any) -> tuple[float, float]:
        """``(start angle, turn)`` of the arc from ``p`` to ``q``, neighbouring followed points.

        The arc is the one between them that no other followed point lies on; ``turn`` is
        signed (counter-clockwise > 0).
        """
        n = len(self.xy)
        i = self.index[(float(p[0]), float(p[1]))]
        j = self.index[(float(q[0]), float(q[1]))]
        if (j - i) % n == 1:
            return float(self.angle[i]), float((self.angle[j] - self.angle[i]) % (2 * math.pi))
        return float(self.angle[i]), -float((self.angle[i] - self.angle[j]) % (2 * math.pi))

    def inner(self, p: Any, q: Any, pieces: int) -> np.ndarray:
        """Points cutting the arc between neighbouring followed points ``p``, ``q`` evenly."""
        start, turn = self.chord(p, q)
        angles = start + turn * np.arange(1, pieces) / pieces
        return self.centre + self.radius * np.c_[np.cos(angles), np.sin(angles)]

    def between(self, p: np.ndarray, q: np.ndarray, sweep: float) -> np.ndarray:
        """The points followed strictly between fixed points ``p`` and ``q``, going ``sweep``."""
        n = len(self.xy)
        i = self.index[(float(p[0]), float(p[1]))]
        j = self.index[(float(q[0]), float(q[1]))]
        step = 1 if sweep > 0 else -1
        count = ((j - i) * step) % n
        return self.xy[[(i + step * m) % n for m in range(1, count)]]


class Circles:
    """The circles of all parts, each once (circles within a hair of each other are one)."""

    def __init__(self, size: float) -> None:
        self.items: list[Circle] = []
        self.tol = _SAME_CIRCLE * size

    def find(self, centre: Sequence[float], radius: float, exact: bool = False) -> int:
        """The circle's index; a circle given exactly replaces one computed (within a hair)."""
        c = np.asarray(centre, dtype=np.float64)
        for k, circle in enumerate(self.items):
            if (
                float(np.hypot(*(circle.centre - c))) <= self.tol
                and abs(circle.radius - radius) <= self.tol
            ):
                if exact and not circle.exact:
                    circle.centre, circle.radius, circle.exact = c, float(radius), True
                return k
        self.items.append(Circle(c, float(radius), exact))
        return len(self.items) - 1


@dataclass
class FollowedRing:
    """An outline followed as a closed list of points, with the patch and curve of each piece.

    Piece ``k`` runs from point ``k`` to point ``k + 1`` (cyclically); ``curve[k]`` is the index
    of the circle it is a chord of, or -1 for a straight piece.
    """

    xy: np.ndarray
    patch: list[str | None]
    curve: list[int]


def circles_of(parts: list[Part], size: float) -> Circles:
    """Every circle once, with the arcs' ends fixed on it."""
    circles = Circles(size)
    for part in parts:
        for polygon in part.polygons:
            for outline in polygon:
                if outline.circle is not None:
                    centre, radius, sides = outline.circle
                    circle = circles.items[circles.find(centre, radius, outline.circle_exact)]
                    circle.pieces = max(circle.pieces, 2 * sides)
                    continue
                n = len(outline.corners)
                for e, arc in enumerate(outline.arcs):
                    if arc is None:
                        continue
                    circle = circles.items[circles.find(arc.centre, arc.radius, arc.exact)]
                    p, q = outline.corners[e], outline.corners[(e + 1) % n]
                    circle.anchor(p)
                    circle.anchor(q)
                    circle.spans.append(((float(p[0]), float(p[1])), arc.sweep))
    return circles


def crossings(
    parts: list[Part], circles: Circles, tol: float
) -> dict[tuple[int, int, int, int], list[tuple[float, np.ndarray]]]:
    """Where straight edges and circles cross: points fixed on both, computed once.

    Returns, per straight edge (part, polygon, ring, edge), the points inside it where a circle
    crosses or touches it, with their fraction along the edge; the same points are fixed on the
    circles (so the two share them bit for bit). Corners lying on a circle are fixed on it.
    """
    starts, ends, keys = straight_edges(parts)
    splits: dict[tuple[int, int, int, int], list[tuple[float, np.ndarray]]] = {}
    corners = [
        outline.corners
        for part in parts
        for polygon in part.polygons
        for outline in polygon
        if len(outline.corners)
    ]
    all_corners = np.vstack(corners) if corners else np.zeros((0, 2))
    for circle in circles.items:
        c, radius = circle.centre, circle.radius
        if all_corners.size:
            on = np.abs(np.hypot(*(all_corners - c).T) - radius) <= tol
            for point in all_corners[on]:
                if circle.covers(circle.angle_of(point)):
                    circle.anchor(point)
        if not keys:
            continue
        d = ends - starts
        f = starts - c
        a = np.sum(d * d, axis=1)
        b = 2 * np.sum(f * d, axis=1)
        cc = np.sum(f * f, axis=1) - radius * radius
        disc = b * b - 4 * a * cc
        for k in np.flatnonzero(disc >= 0).tolist():
            root = math.sqrt(disc[k])
            length = math.sqrt(a[k])
            for t in sorted({(-b[k] - root) / (2 * a[k]), (-b[k] + root) / (2 * a[k])}):
                if not tol < t * length < length - tol:
                    continue
                point = starts[k] + t * d[k]
                if not circle.covers(circle.angle_of(point)):
                    continue
                circle.anchor(point)
                splits.setdefault(keys[k], []).append((t, point))
                radial = (point - c) / radius
                along = math.fabs(float(d[k] @ radial)) / length
                circle.grade_towards(point, math.asin(min(along, 1.0)), tol)
    for m, one in enumerate(circles.items):
        for two in circles.items[m + 1 :]:
            for point in _circle_crossings(one, two):
                if one.covers(one.angle_of(point)) and two.covers(two.angle_of(point)):
                    one.anchor(point)
                    two.anchor(point)
                    cosine = float((point - one.centre) @ (point - two.centre))
                    between = math.acos(max(-1.0, min(1.0, cosine / (one.radius * two.radius))))
                    crossing = min(between, math.pi - between)
                    one.grade_towards(point, crossing, tol)
                    two.grade_towards(point, crossing, tol)
    return splits


def grade_near_misses(parts: list[Part], circles: Circles, tol: float) -> None:
    """Grade every circle where a straight edge or another circle passes near it, uncrossed.

    See :meth:`Circle.grade_near`: an edge passing outside (its nearest point), an edge inside
    (its end nearest the arc), and two circles apart or one inside the other (along the line of
    their centres).
    """
    starts, ends, _ = straight_edges(parts)
    for circle in circles.items:
        if not len(starts):
            break
        c, radius = circle.centre, circle.radius
        d = ends - starts
        t = np.clip(np.sum((c - starts) * d, axis=1) / np.sum(d * d, axis=1), 0.0, 1.0)
        nearest = starts + t[:, None] * d
        outside = np.hypot(*(nearest - c).T) - radius
        start_far = np.hypot(*(starts - c).T) >= np.hypot(*(ends - c).T)
        far = np.where(start_far[:, None], starts, ends)
        inside = radius - np.hypot(*(far - c).T)
        for k in np.flatnonzero(outside > 0.0).tolist():
            circle.grade_near(circle.angle_of(nearest[k]), float(outside[k]), tol)
        for k in np.flatnonzero(inside > 0.0).tolist():
            circle.grade_near(circle.angle_of(far[k]), float(inside[k]), tol)
    for m, one in enumerate(circles.items):
        for two in circles.items[m + 1 :]:
            apart = float(np.hypot(*(two.centre - one.centre)))
            if apart == 0.0:
                continue
            towards = math.atan2(*(two.centre - one.centre)[::-1])
            gap = apart - one.radius - two.radius
            if gap > 0.0:  # side by side
                one.grade_near(towards, gap, tol)
                two.grade_near(towards + math.pi, gap, tol)
                continue
            small, big = sorted((one, two), key=lambda circle: circle.radius)
            gap = big.radius - small.radius - apart
            if gap > 0.0:  # one inside the other, nearest where the small one points away
                away = math.atan2(*(small.centre - big.centre)[::-1])
                big.grade_near(away, gap, tol)
                small.grade_near(away, gap, tol)


def _circle_crossings(one: Circle, two: Circle) -> list[np.ndarray]:
    d = float(np.hypot(*(two.centre - one.centre)))
    if d == 0.0 or d > one.radius + two.radius or d < abs(one.radius - two.radius):
        return []
    a = (one.radius**2 - two.radius**2 + d * d) / (2 * d)
    h = math.sqrt(max(one.radius**2 - a * a, 0.0))
    unit = (two.centre - one.centre) / d
    base = one.centre + a * unit
    normal = np.array([-unit[1], unit[0]])
    if h == 0.0:
        return [base]
    return [base + h * normal, base - h * normal]


def follow(
    outline: Outline,
    circles: Circles,
    splits: Mapping[tuple[int, int, int, int], list[tuple[float, np.ndarray]]],
    key: tuple[int, int, int] | None = None,
) -> FollowedRing:
    """An outline as the closed list of points every part on its circles shares."""
    if outline.circle is not None:
        centre, radius, _ = outline.circle
        k = circles.find(centre, radius)
        count = len(circles.items[k].xy)
        return FollowedRing(circles.items[k].xy.copy(), [outline.patches[0]] * count, [k] * count)
    points: list[np.ndarray] = []
    patch: list[str | None] = []
    curve: list[int] = []
    n = len(outline.corners)
    for e in range(n):
        p, q = outline.corners[e], outline.corners[(e + 1) % n]
        arc = outline.arcs[e]
        if arc is None:
            inner = sorted(splits.get((*key, e), []), key=lambda s: s[0]) if key else []
            run = [p[None], *(point[None] for _, point in inner)]
            k = -1
        else:
            k = circles.find(arc.centre, arc.radius)
            run = [p[None], circles.items[k].between(p, q, arc.sweep)]
        block = np.vstack(run)
        points.append(block)
        patch += [outline.patches[e]] * len(block)
        curve += [k] * len(block)
    return FollowedRing(np.vstack(points), patch, curve)


def split_shared_chords(
    rings: Sequence[FollowedRing], circles: Circles, pieces: int = SHARED_CHORD_PIECES
) -> int:
    """Fix a point mid-arc on every chord that two outlines follow along different curves.

    A piece of one outline may join the same two points as a piece of another along another
    curve: two circles crossing at points that are neighbours on both (a lens thinner than a
    chord's bulge), or a straight edge between two neighbouring points of a circle. Followed,
    both are one segment, so the thin face between the true curves (the lens, the circle's cap)
    is lost and nothing tells which curve the segment stands for. Each such circle gets its arc
    between the two points cut into ``pieces`` (the cuts fixed on it): followed again
    (:meth:`Circle.sample`, :func:`follow`), the pieces differ and the face between them is kept,
    however thin; whether it is a face of its own or part of a neighbouring region is then the
    fragmenting's business.

    Returns the number of points newly fixed (0: no chord is shared, the rings stand).

    Examples
    --------
    >>> import numpy as np
    >>> from blockmesh.domain.compose.circles import Circles
    >>> circles = Circles(1.0)
    >>> circle = circles.items[circles.find((0.0, 0.0), 1.0)]
    >>> for point in ([1.0, 0.0], [0.0, 1.0]):
    ...     circle.anchor(np.array(point))
    >>> circle.sample()  # a quarter circle: 4 chords between the fixed points
    >>> a, b = circle.xy[0], circle.xy[1]
    >>> chord = FollowedRing(np.array([a, b, [0.5, -1.0]]), [None] * 3, [0, -1, -1])
    >>> straight = FollowedRing(np.array([b, a, [0.5, 2.0]]), [None] * 3, [-1, -1, -1])
    >>> split_shared_chords([chord, straight], circles)
    1
    >>> split_shared_chords([chord], circles)
    0
    """
    if not rings:
        return 0
    start = np.vstack([ring.xy for ring in rings])
    stop = np.vstack([np.roll(ring.xy, -1, axis=0) for ring in rings])
    curve = np.concatenate([np.asarray(ring.curve, dtype=np.int64) for ring in rings])
    # Each piece by its two ends in a fixed order, so that both directions give one key.
    flip = (start[:, 0] > stop[:, 0]) | ((start[:, 0] == stop[:, 0]) & (start[:, 1] > stop[:, 1]))
    first = np.where(flip[:, None], stop, start)
    second = np.where(flip[:, None], start, stop)
    _, segment = np.unique(np.hstack([first, second]), axis=0, return_inverse=True)
    segment = segment.ravel()
    kinds, at = np.unique(np.c_[segment, curve], axis=0, return_index=True)
    curves_on = np.bincount(kinds[:, 0])
    shared = (curves_on[kinds[:, 0]] > 1) & (kinds[:, 1] >= 0)
    added = 0
    for k, piece in zip(kinds[shared, 1].tolist(), at[shared].tolist(), strict=True):
        circle = circles.items[k]
        before = len(circle.anchors)
        for point in circle.inner(first[piece], second[piece], pieces):
            circle.anchor(point)
        added += len(circle.anchors) - before
    return added


def split_crossed_chords(rings: Sequence[FollowedRing], circles: Circles) -> int:
    """Fix points on a circle around a corner that lies between one of its chords and its arc.

    A corner of one part may lie inside a circle but outside the outline that follows it, between
    a chord and the arc. Its straight edges then cross the chord where they do not cross the
    circle, and the fragmenting would compute each such crossing again, with its own rounding, in
    every shapely operation (and put the corner on the wrong side of the circle). Such a corner,
    ``d`` inside the circle, gets two points fixed on the circle either side of it, so close that
    their chord passes ``d / 2`` inside the arc: followed again, the corner lies inside. A crossing
    whose straight piece has no end inside the circle gets the circle's point at its angle fixed.

    Returns the number of points newly fixed (0: no straight piece crosses a chord).

    Examples
    --------
    >>> import numpy as np
    >>> circles = Circles(1.0)
    >>> circle = circles.items[circles.find((0.0, 0.0), 1.0)]
    >>> circle.pieces = 16  # a whole circle
    >>> for point in ([1.0, 0.0], [0.0, 1.0]):
    ...     circle.anchor(np.array(point))
    >>> circle.sample()
    >>> arc = FollowedRing(circle.xy, [None] * len(circle.xy), [0] * len(circle.xy))
    >>> tip = np.array([0.995, 0.07])  # inside the circle, outside its chord there
    >>> wedge = FollowedRing(np.array([tip, [0.5, 0.0], [0.5, 0.2]]), [None] * 3, [-1] * 3)
    >>> split_crossed_chords([arc, wedge], circles)  # either side of the tip: 1, 3 steps out
    4
    >>> circle.sample()
    >>> split_crossed_chords([FollowedRing(circle.xy, arc.patch, arc.curve), wedge], circles)
    0
    """
    if not rings:
        return 0
    start = np.vstack([ring.xy for ring in rings])
    stop = np.vstack([np.roll(ring.xy, -1, axis=0) for ring in rings])
    curve = np.concatenate([np.asarray(ring.curve, dtype=np.int64) for ring in rings])
    chord = np.flatnonzero(curve >= 0)
    straight = np.flatnonzero(curve < 0)
    if not chord.size or not straight.size:
        return 0
    lines = shapely.linestrings(np.stack([start, stop], axis=1))
    at, hit = shapely.STRtree(lines[chord]).query(lines[straight], predicate="crosses")
    added = 0
    for s, c in zip(straight[at].tolist(), chord[hit].tolist(), strict=True):
        circle = circles.items[int(curve[c])]
        before = len(circle.anchors) + len(circle.graded)
        _grade_around_corner(circle, start[s], stop[s], start[c], stop[c])
        added += len(circle.anchors) + len(circle.graded) - before
    return added


def _grade_around_corner(
    circle: Circle, p: np.ndarray, q: np.ndarray, a: np.ndarray, b: np.ndarray
) -> None:
    """Grade ``circle`` where a straight piece ``p``-``q`` crosses its chord ``a``-``b``.

    Around the piece's end beyond the chord, ``d`` inside the circle: the nearest two points so
    close that their chord passes within ``d / 8`` of the arc, the next ones 3, 7, 15, ... times
    as far out up to the chord's ends, so that the chords (and the blocks along them) grow away
    from the corner gradually. The circle's point at the crossing is fixed when that end is not
    inside the circle.
    """
    normal = np.array([a[1] - b[1], b[0] - a[0]])  # the chord turned a quarter
    corner = p if float((p - a) @ normal) * float((circle.centre - a) @ normal) < 0 else q
    depth = circle.radius - float(np.hypot(*(corner - circle.centre)))
    if depth <= 0.0:
        point = shapely.get_coordinates(
            shapely.intersection(shapely.linestrings([p, q]), shapely.linestrings([a, b]))
        )[0]
        angle = circle.angle_of(point)
        circle.anchor(circle.centre + circle.radius * np.array([math.cos(angle), math.sin(angle)]))
        return
    middle = circle.angle_of(corner)
    step = math.acos(1.0 - depth / (8.0 * circle.radius))
    ends = [math.remainder(circle.angle_of(end) - middle, 2 * math.pi) for end in (a, b)]
    for sign in (-1.0, 1.0):
        limit = max(sign * end for end in ends)  # the chord's end on this side of the corner
        offset = step
        while offset < limit:
            circle.grade(middle + sign * offset, offset)
            offset = 2.0 * offset + step
