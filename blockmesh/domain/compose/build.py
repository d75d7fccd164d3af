"""The Domain on the decomposed faces: arcs on the circles, regions, patches, interfaces.

Block vertices on a chord of a circle move onto the circle, and every block edge along it becomes
an arc around the circle's centre (stored once per edge, so both regions share its nodes bit for
bit); the blocks get their regions, the boundary edges the parts' patches, and the edges between
regions their interfaces (``"A|B"``, or the names :func:`interface_renames` checked).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np
import shapely

from blockmesh.curves.types import Arc, Curve
from blockmesh.domain.compose.arrangement import Arrangement, _listed
from blockmesh.domain.compose.circles import Circles
from blockmesh.domain.compose.fragments import SourcePieces
from blockmesh.domain.interfaces import check_interface_name, default_interface_name
from blockmesh.domain.parts import Part
from blockmesh.domain.validate.points import coincident_pairs
from blockmesh.domain.validate.tolerances import NEAR_TOL
from blockmesh.errors import DomainError, DomainFormatError, fmt_point
from blockmesh.geometry.polygons import interior_angles, signed_area
from blockmesh.geometry.topology import graph_components

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["BlocksFailError", "build_domain", "interface_renames"]

#: How far around a folded block (in its diameters) the width of its sliver is measured.
_WIDTH_WINDOW = 3.0


class BlocksFailError(Exception):
    """The blocks made for the faces fail the Domain's checks (``error`` says how).

    ``vertices`` and ``blocks`` are the failed blocks (arcs' nodes on their circles),
    ``block_face`` the face of each.
    """

    def __init__(
        self, error: DomainError, vertices: np.ndarray, blocks: np.ndarray, block_face: np.ndarray
    ) -> None:
        super().__init__(str(error))
        self.error = error
        self.vertices = vertices
        self.blocks = blocks
        self.block_face = block_face

    def located(
        self, parts: list[Part], arrangement: Arrangement, pieces: SourcePieces
    ) -> DomainError:
        """The error, naming the region, the place and the parts where a block folds.

        A block folds where a face is too thin for its curved sides: a sliver left of an earlier
        part where a later part's circle cuts it at a sharp angle, its blocks' nodes moved onto
        the circles by more than the sliver is wide (or two of them onto one point). Without a
        folded block (a curved edge bulging too far), :attr:`error` as it is.
        """
        corners = self.vertices[self.blocks]
        doubled = np.zeros(len(self.vertices), dtype=bool)  # nodes moved onto one point
        doubled[np.array(coincident_pairs(self.vertices), dtype=np.int64).ravel()] = True
        folded = np.flatnonzero(
            (interior_angles(corners).max(axis=1) >= 180.0)
            | (signed_area(corners) <= 0.0)
            | doubled[self.blocks].any(axis=1)
        )
        if not folded.size:
            return self.error
        b = int(folded[0])
        face = int(self.block_face[b])
        where = corners[b].mean(axis=0)
        outline = shapely.Polygon(
            arrangement.points[arrangement.faces[face][0]],
            [arrangement.points[ring] for ring in arrangement.faces[face][1:]],
        )
        diameter = float(np.ptp(corners[b], axis=0).max())
        wide = _width_near(outline, where, _WIDTH_WINDOW * diameter)
        near = pieces.near(where, wide + diameter)
        return DomainError(
            f"{parts[int(arrangement.face_region[face])].label} is too thin near "
            f"{fmt_point(where)} (a sliver about {wide:.3g} wide there, between the outlines of "
            f"{_listed(near)}) for blocks that stay convex along its curved sides: "
            "there a later part's circle cuts it at a sharp angle or nearly touches its outline; "
            "let the later part cover the sliver (overlap the parts by more there) or keep the "
            "parts clearly apart"
        )


def _width_near(face: Any, where: np.ndarray, reach: float) -> float:
    """The width of ``face`` near ``where``: its widest disc within ``reach`` of the point."""
    window = shapely.intersection(face, shapely.Point(*where).buffer(reach))
    pieces = list(shapely.get_parts(window)) or [face]
    piece = min(pieces, key=lambda g: shapely.distance(g, shapely.Point(*where)))
    return 2 * float(shapely.length(shapely.maximum_inscribed_circle(piece)))


def interface_renames(
    interfaces: Mapping[str, str] | None, parts: list[Part]
) -> dict[tuple[str, str], str]:
    """User names of interfaces by region pair (either order), checked."""
    if not interfaces:
        return {}
    if not isinstance(interfaces, Mapping):
        raise DomainFormatError(
            'interfaces must map "A|B" (two regions) to a name, e.g. {"matrix|fibre": "bond"}, '
            f"got {type(interfaces).__name__}"
        )
    regions = {p.region for p in parts}
    out: dict[tuple[str, str], str] = {}
    for pair, new in interfaces.items():
        if not isinstance(pair, str) or pair.count("|") != 1:
            raise DomainFormatError(
                f'interface {pair!r}: name an interface by its two regions, "A|B"'
            )
        a, b = (s.strip() for s in pair.split("|"))
        for region in (a, b):
            if region not in regions:
                raise DomainError(
                    f"interface {pair!r} names the region {region!r}, but the regions are "
                    f"{', '.join(p.region for p in parts)}"
                )
        check_interface_name(new, ())
        out[(a, b)] = out[(b, a)] = new
    return out


def build_domain(
    cls: type[Domain],
    parts: list[Part],
    arrangement: Arrangement,
    result: Any,
    circles: Circles,
    pieces: SourcePieces,
    renames: dict[tuple[str, str], str],
    name: str,
    description: str,
) -> Domain:
    """Regions, patches, interfaces and arcs on the decomposed faces: the Domain."""
    vertices = np.array(result.vertices)
    chains: dict[tuple[int, int], np.ndarray] = {}  # arrangement edge (a < b) -> chain a..b
    for face, face_chains in zip(arrangement.faces, result.ring_chains, strict=True):
        for ring, ring_chains in zip(face, face_chains, strict=True):
            for a, b, chain in zip(
                ring.tolist(), np.roll(ring, -1).tolist(), ring_chains, strict=True
            ):
                chains.setdefault((min(a, b), max(a, b)), chain if a < b else chain[::-1])
    edges: dict[tuple[int, int], Curve] = {}
    points = arrangement.points
    for (a, b), chain in chains.items():
        k = pieces.curve(points[a], points[b])
        if k < 0:
            continue
        circle = circles.items[k]
        p, q = points[a], points[b]
        start, turn = circle.chord(p, q)
        d = q - p
        inner = chain[1:-1]
        fraction = (vertices[inner] - p) @ d / float(d @ d)
        angles = start + fraction * turn
        vertices[inner] = circle.centre + circle.radius * np.c_[np.cos(angles), np.sin(angles)]
        centre = (float(circle.centre[0]), float(circle.centre[1]))
        for u, v in zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True):
            edges[(u, v)] = Arc(center=centre)
    region_names = [p.region for p in parts]
    regions: dict[str, list[int]] = {n: [] for n in region_names}
    face_of_block = result.block_face
    block_region = arrangement.face_region[face_of_block]
    for b, r in enumerate(block_region.tolist()):
        regions[region_names[r]].append(b)
    patches: dict[str, list[tuple[int, int]]] = {}
    interfaces: dict[str, list[tuple[int, int]]] = {}
    boundary_keys = [e for e, f in arrangement.edge_faces.items() if len(f) == 1]
    middles = np.array([(points[a] + points[b]) / 2 for a, b in boundary_keys]).reshape(-1, 2)
    tol = NEAR_TOL * float(np.hypot(*np.ptp(points, axis=0)))
    named = pieces.patches_at(middles, tol) if boundary_keys else []
    for (a, b), patch in zip(boundary_keys, named, strict=True):
        if patch is not None:
            chain = chains[(a, b)]
            patches.setdefault(patch, []).extend(
                zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True)
            )
    pairs = []
    for (a, b), faces in arrangement.edge_faces.items():
        if len(faces) != 2:
            continue
        r1, r2 = sorted(int(arrangement.face_region[f]) for f in faces)
        if r1 == r2:
            continue
        pairs.append((r1, r2, a, b))
    for r1, r2, a, b in sorted(pairs):
        first, second = region_names[r1], region_names[r2]
        label = renames.get((first, second), default_interface_name(first, second))
        chain = chains[(a, b)]
        interfaces.setdefault(label, []).extend(
            zip(chain[:-1].tolist(), chain[1:].tolist(), strict=True)
        )
    for label in interfaces:
        if label in patches:
            raise DomainError(
                f"interface {label!r} has the name of a boundary patch; an interface is an "
                "internal patch (between two regions), so give one of them another name"
            )
    joined = np.array(
        [faces for faces in arrangement.edge_faces.values() if len(faces) == 2], dtype=np.int64
    ).reshape(-1, 2)
    components, _ = graph_components(len(arrangement.faces), joined[:, 0], joined[:, 1])
    try:
        return cls._from_parsed(
            vertices,
            np.array(result.blocks),
            patches,
            regions,
            made_for="the composite domain",
            name=name,
            description=description,
            layout="composite",
            edges=edges,
            interfaces=interfaces,
            components=components,
        )
    except DomainError as error:
        raise BlocksFailError(error, vertices, np.array(result.blocks), face_of_block) from None
