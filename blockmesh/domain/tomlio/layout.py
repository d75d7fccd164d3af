"""The layout of a domain file: which keys it may have, their types, and which go together.

:func:`parse_domain_text` checks the keys and their types, not the geometry (the Domain's
constructors check that): a polygon or explicit blocks or a circle or parts, never two of them,
and each key with what it belongs to.

Examples
--------
>>> raw = parse_domain_text('polygon = [[0, 0], [1, 0], [0, 1]]', source="inline")
>>> raw["polygon"]
[[0, 0], [1, 0], [0, 1]]
"""

from __future__ import annotations

import tomllib
from pathlib import Path
from types import UnionType
from typing import Any

from blockmesh.checks import key_list, unknown_keys
from blockmesh.domain.tomlio.bounds import check_limits, read_text_bounded
from blockmesh.domain.tomlio.tables import (
    curved_edges_table,
    grading_table,
    polygon_arcs,
    toml_type,
)
from blockmesh.errors import DomainFormatError

__all__ = ["ALLOWED_KEYS", "parse_domain_text", "read_domain_file"]

#: Top-level keys of a domain file and what each holds.
ALLOWED_KEYS = {
    "name": "the domain's name (a string)",
    "description": "one line saying what the domain is (a string)",
    "polygon": "corners of a polygon (convex or not), [[x, y], ...]",
    "holes": "holes of the polygon, each a list of corners, [[[x, y], ...], ...]",
    "vertices": "block corner coordinates, [[x, y], ...]",
    "blocks": "pentagons as 5 vertex ids each, [[a, b, c, d, e], ...]",
    "patches": "a table: patch name = list of edges",
    "regions": "a table: region name = list of block ids",
    "boundary_source": "the polygon edge each boundary edge lies on, [[a, b, ring, edge], ...]",
    "block_source": "the mesh element each block came from, [e0, e1, ...]",
    "edges": "curved block edges: [[edges]] tables, each arc|spline|polyline = [a, b] with "
    "through|center|points",
    "arcs": 'curved polygon edges: [[arcs]] tables, each edge = i or "hole K:E" with '
    "through|center",
    "circles": 'circular holes of a polygon: [{center = [x, y], radius = r, patch = "name"}]',
    "circle": 'a whole disc instead of a polygon: {center = [x, y], radius = r, patch = "name"}',
    "components": "with blocks: how many separate pieces they form (default 1)",
    "parts": "a composite domain: [[parts]] tables, each region = name with polygon, holes, "
    "arcs, circles and patches; a later part is cut out of the earlier ones",
    "interfaces": 'with parts, a table "A|B" = name (renames the interface between regions A '
    "and B); with blocks, a table name = list of edges [a, b] between two blocks",
    "grading": "graded block edges (explicit blocks): [[grading]] tables, each edge = [a, b] "
    "(or edges = [[a, b], ...]) and ratio = last piece / first piece",
    "size": "the cell size: a number, an expression in x, y, or a [size] table (default, "
    "regions, [[size.near]], expression, gradation); the blocks are cut to it",
}

#: The type a top-level key must have, and how a message names it.
_KEY_TYPES: dict[str, tuple[type | UnionType, str]] = {
    "name": (str, "a string"),
    "description": (str, "a string"),
    **{
        key: (list, f"a list ({ALLOWED_KEYS[key]})")
        for key in ("polygon", "holes", "vertices", "blocks", "boundary_source", "block_source")
    },
    "size": (dict | str | int | float, "a number, an expression or a [size] table"),
}

#: The keys that belong to explicit blocks, and what a domain given as a polygon is told instead.
_BLOCKS_ONLY = {
    **{
        key: f"{key!r} belongs to explicit blocks (blockmesh writes it with them)"
        for key in ("boundary_source", "block_source", "components")
    },
    "regions": "'regions' needs explicit blocks; a polygon is decomposed automatically",
    "interfaces": "'interfaces' belong to [[parts]] (renaming the interfaces between regions) or "
    "to explicit blocks (listing their edges), not to one polygon",
    "edges": "'edges' needs explicit blocks (vertices and blocks), not a polygon",
    "grading": "'grading' grades edges of explicit blocks (vertices and blocks), not a polygon's",
}


def read_domain_file(path: str | Path) -> dict[str, Any]:
    """Read and check the layout of a domain file (types of the top-level keys).

    Raises DomainFormatError for unreadable or special files, files over the size cap,
    malformed TOML (with line and column), nesting or numbers beyond the limits, and misplaced
    or mistyped keys.
    """
    path = Path(path)
    text = read_text_bounded(path)
    raw = parse_domain_text(text, source=str(path))
    raw.setdefault("name", path.stem)
    return raw


def parse_domain_text(text: str, *, source: str) -> dict[str, Any]:
    """Parse domain TOML text; checks keys and their types, not the geometry."""
    check_limits(text, source)
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise DomainFormatError(f"{source}: malformed TOML: {error}") from None
    except (ValueError, RecursionError, MemoryError) as error:
        raise DomainFormatError(f"{source}: the TOML reader gave up: {error}") from None
    unknown = unknown_keys(raw, ALLOWED_KEYS)
    if unknown:
        raise DomainFormatError(
            f"{source}: unknown {unknown}; the keys are: {key_list(ALLOWED_KEYS)}"
        )
    for key, (kind, wanted) in _KEY_TYPES.items():
        if key in raw and not isinstance(raw[key], kind):
            raise DomainFormatError(
                f"{source}: key {key!r} must be {wanted}, got {toml_type(raw[key])}"
            )
    for key in ("patches", "regions"):
        if key in raw and not isinstance(raw[key], dict):
            raise DomainFormatError(
                f"{source}: key {key!r} must be a table, a [{key}] section with one "
                f"'name = [...]' line each, got {toml_type(raw[key])}"
            )
        for name, value in raw.get(key, {}).items():
            if not isinstance(value, list):
                what = "patch" if key == "patches" else "region"
                raise DomainFormatError(
                    f"{source}: {what} {name!r} must be a list, got {toml_type(value)}"
                )
    if "circle" in raw:
        return _disc(raw, source)
    if "parts" in raw:
        return _parts(raw, source)
    has_polygon = "polygon" in raw
    has_blocks = "vertices" in raw or "blocks" in raw
    for key in ("arcs", "circles"):
        if key in raw and not has_polygon:
            raise DomainFormatError(
                f"{source}: '{key}' belong to a 'polygon'; with explicit blocks, curve their "
                "edges with [[edges]]"
            )
    if has_polygon and has_blocks:
        raise DomainFormatError(
            f"{source}: give either 'polygon' or 'vertices' and 'blocks', not both"
        )
    if not has_polygon and not has_blocks:
        raise DomainFormatError(
            f"{source}: no geometry: give 'polygon' (any simple polygon, with 'holes' if it has "
            "any) or 'vertices' and 'blocks'"
        )
    if has_blocks and ("vertices" not in raw or "blocks" not in raw):
        missing = "vertices" if "vertices" not in raw else "blocks"
        raise DomainFormatError(f"{source}: key {missing!r} is missing (blocks need both)")
    # From here on the domain is either a polygon or explicit blocks.
    if has_polygon:
        for key, message in _BLOCKS_ONLY.items():
            if key in raw:
                raise DomainFormatError(f"{source}: {message}")
    elif "holes" in raw:
        raise DomainFormatError(
            f"{source}: 'holes' belong to a 'polygon'; with explicit blocks, leave the holes' "
            "area without blocks"
        )
    if "interfaces" in raw:
        _check_table(raw["interfaces"], "interfaces", source, list, "a list of edges [a, b]")
    if "grading" in raw:
        raw["grading"] = grading_table(raw["grading"], source)
    if "edges" in raw:
        raw["edges"] = curved_edges_table(raw["edges"], source)
    if "arcs" in raw:
        raw["arcs"] = polygon_arcs(raw["arcs"], source)
    if "circles" in raw and not isinstance(raw["circles"], list):
        raise DomainFormatError(
            f"{source}: 'circles' must be a list of tables, got {toml_type(raw['circles'])}"
        )
    return raw


def _parts(raw: dict[str, Any], source: str) -> dict[str, Any]:
    """A ``[[parts]]`` domain: a list of tables, and optionally ``[interfaces]`` renames."""
    others = sorted(set(raw) - {"name", "description", "parts", "interfaces", "size"})
    if others:
        raise DomainFormatError(
            f"{source}: with [[parts]], the geometry is in the parts; leave out "
            f"{', '.join(map(repr, others))} (each part takes region, polygon, holes, arcs, "
            "circles and patches)"
        )
    parts = raw["parts"]
    if not isinstance(parts, list) or not parts or not all(isinstance(t, dict) for t in parts):
        raise DomainFormatError(
            f"{source}: 'parts' must be [[parts]] tables, one per part (region = ..., polygon = "
            f"... or circles = ...), got {toml_type(parts)}"
        )
    if "interfaces" in raw:
        _check_table(raw["interfaces"], "interfaces", source, str, 'a name, "A|B" = "name"')
    return raw


def _check_table(table: object, key: str, source: str, kind: type, what: str) -> None:
    """``table`` a TOML table whose every value is a ``kind``; a located error otherwise."""
    if not isinstance(table, dict):
        raise DomainFormatError(
            f"{source}: {key!r} must be a table ([{key}] with one line each), got "
            f"{toml_type(table)}"
        )
    for name, value in table.items():
        if not isinstance(value, kind):
            raise DomainFormatError(
                f"{source}: {key} {name!r} must be {what}, got {toml_type(value)}"
            )


def _disc(raw: dict[str, Any], source: str) -> dict[str, Any]:
    """A ``circle = {...}`` domain: the table checked, no other geometry."""
    others = sorted(set(raw) - {"name", "description", "circle", "size"})
    if others:
        raise DomainFormatError(
            f"{source}: a 'circle' is the whole domain; leave out {', '.join(map(repr, others))} "
            "(its boundary patch is circle.patch)"
        )
    circle = raw["circle"]
    if not isinstance(circle, dict):
        raise DomainFormatError(
            f"{source}: 'circle' must be a table {{center = [x, y], radius = r}}, got "
            f"{toml_type(circle)}"
        )
    unknown = sorted(set(circle) - {"center", "radius", "patch"})
    if unknown or "center" not in circle or "radius" not in circle:
        raise DomainFormatError(
            f"{source}: 'circle' takes center = [x, y], radius = r and optionally patch, got "
            f"{', '.join(sorted(circle)) or 'nothing'}"
        )
    return raw
