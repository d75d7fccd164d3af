"""Domain files: read a TOML document into checked raw fields, write a domain back without loss.

A domain file holds either a polygon, with holes or not (decomposed automatically), or explicit
blocks, like OpenFOAM's blockMeshDict::

    name = "plate"
    description = "A plate with a hole"
    polygon = [[0, 0], [4, 0], [4, 2], [0, 2]]
    holes = [[[1.5, 0.5], [2.5, 0.5], [2.5, 1.5], [1.5, 1.5]]]
    [patches]
    inlet = [3]            # polygon edge i runs from polygon[i] to polygon[i+1]
    cylinder = ["hole 0"]  # every edge of hole 0; "hole 0:2" is its edge 2

    # or
    vertices = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]
    blocks = [[0, 1, 2, 3, 4]]
    [patches]
    floor = [[0, 1]]       # boundary edges as vertex pairs
    [regions]
    solid = [0]            # block ids

    [[grading]]            # graded block edges (explicit blocks), like blockMesh's edgeGrading
    edge = [0, 4]          # refined, pieces spaced geometrically from vertex 0 to vertex 4,
    ratio = 10             # the last 10 times the first

    [[edges]]              # curved block edges (explicit blocks), one table each
    arc = [3, 4]           # from vertex 3 to vertex 4, through a point or around a centre
    through = [0.5, 2.2]   # or: center = [x, y]
    [[edges]]
    spline = [4, 0]        # or polyline = [a, b]: through the interior points, in order
    points = [[0.1, 0.6], [-0.1, 0.3]]

    # curves of a polygon: [[arcs]] on its edges, circular holes, or a whole circle
    [[arcs]]
    edge = 2               # or "hole K:E"
    through = [1, 2.4]
    circles = [{center = [1, 1], radius = 0.3, patch = "cylinder"}]
    circle = {center = [0, 0], radius = 1, patch = "rim"}   # alone: a disc

    # or several parts (materials), a later part cut out of the earlier ones
    [[parts]]
    region = "matrix"
    polygon = [[0, 0], [2, 0], [2, 2], [0, 2]]
    patches = {left = [3], right = [1]}
    [[parts]]
    region = "fibre"
    circles = [{center = [1, 1], radius = 0.4}]   # without a polygon: the part's discs
    [interfaces]
    "matrix|fibre" = "bond"   # optional: the interface's name (default "matrix|fibre")

Only this package knows the file layout; :mod:`blockmesh.domain` validates the values. Reading
is bounded (:mod:`~blockmesh.domain.tomlio.bounds`): the file must be a regular file (not a FIFO
or a device) of at most :data:`MAX_FILE_BYTES`, arrays and tables nest at most
:data:`MAX_NESTING` deep, and integers have at most :data:`MAX_DIGITS` digits; beyond that a
located error says which limit was hit. The keys and their types are checked in
:mod:`~blockmesh.domain.tomlio.layout`, the arrays of tables (``[[arcs]]``, ``[[grading]]``,
``[[edges]]``) read in :mod:`~blockmesh.domain.tomlio.tables`, and a domain written back in
:mod:`~blockmesh.domain.tomlio.writing`.

Examples
--------
>>> raw = parse_domain_text('polygon = [[0, 0], [1, 0], [0, 1]]', source="inline")
>>> raw["polygon"]
[[0, 0], [1, 0], [0, 1]]
"""

from __future__ import annotations

from blockmesh.domain.tomlio.bounds import (
    MAX_DIGITS,
    MAX_FILE_BYTES,
    MAX_NESTING,
    read_text_bounded,
)
from blockmesh.domain.tomlio.layout import ALLOWED_KEYS, parse_domain_text, read_domain_file
from blockmesh.domain.tomlio.writing import dumps_domain

__all__ = [
    "ALLOWED_KEYS",
    "MAX_DIGITS",
    "MAX_FILE_BYTES",
    "MAX_NESTING",
    "dumps_domain",
    "parse_domain_text",
    "read_domain_file",
    "read_text_bounded",
]
