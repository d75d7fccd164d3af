"""Domain files: read a TOML document into checked raw fields, write a domain back without loss.

A domain file holds either a convex polygon (decomposed automatically) or explicit blocks, like
OpenFOAM's blockMeshDict::

    name = "house"
    description = "A pentagon"
    polygon = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]
    [patches]
    floor = [0]            # polygon edge i runs from polygon[i] to polygon[i+1]

    # or
    vertices = [[0, 0], [2, 0], [2, 1], [1, 2], [0, 1]]
    blocks = [[0, 1, 2, 3, 4]]
    [patches]
    floor = [[0, 1]]       # boundary edges as vertex pairs
    [regions]
    solid = [0]            # block ids

    [[edges]]              # curved block edges (explicit blocks only), one table each
    arc = [3, 4]           # from vertex 3 to vertex 4, through a point or around a centre
    through = [0.5, 2.2]   # or: center = [x, y]
    [[edges]]
    spline = [4, 0]        # or polyline = [a, b]: through the interior points, in order
    points = [[0.1, 0.6], [-0.1, 0.3]]

Only this module knows the file layout; :mod:`blockmesh.domain` validates the values.

Examples
--------
>>> raw = parse_domain_text('polygon = [[0, 0], [1, 0], [0, 1]]', source="inline")
>>> raw["polygon"]
[[0, 0], [1, 0], [0, 1]]
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path
from typing import Any

from .errors import DomainFormatError

__all__ = ["ALLOWED_KEYS", "dumps_domain", "parse_domain_text", "read_domain_file"]

#: Top-level keys of a domain file and what each holds.
ALLOWED_KEYS = {
    "name": "the domain's name (a string)",
    "description": "one line saying what the domain is (a string)",
    "polygon": "corners of a convex polygon, [[x, y], ...]",
    "vertices": "block corner coordinates, [[x, y], ...]",
    "blocks": "pentagons as 5 vertex ids each, [[a, b, c, d, e], ...]",
    "patches": "a table: patch name = list of edges",
    "regions": "a table: region name = list of block ids",
    "edges": "curved block edges: [[edges]] tables, each arc|spline|polyline = [a, b] with "
    "through|center|points",
}


def read_domain_file(path: str | Path) -> dict[str, Any]:
    """Read and check the layout of a domain file (types of the top-level keys).

    Raises DomainFormatError for unreadable files, malformed TOML (with line and column) and
    misplaced or mistyped keys.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise DomainFormatError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as error:
        raise DomainFormatError(f"{path}: cannot read the file ({error})") from None
    raw = parse_domain_text(text, source=str(path))
    raw.setdefault("name", path.stem)
    return raw


def parse_domain_text(text: str, *, source: str) -> dict[str, Any]:
    """Parse domain TOML text; checks keys and their types, not the geometry."""
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise DomainFormatError(f"{source}: malformed TOML: {error}") from None
    unknown = sorted(set(raw) - set(ALLOWED_KEYS))
    if unknown:
        allowed = "; ".join(f"{k} ({v})" for k, v in ALLOWED_KEYS.items())
        raise DomainFormatError(
            f"{source}: unknown key{'s' if len(unknown) > 1 else ''} "
            f"{', '.join(map(repr, unknown))}; the keys are: {allowed}"
        )
    for key in ("name", "description"):
        if key in raw and not isinstance(raw[key], str):
            raise DomainFormatError(
                f"{source}: key {key!r} must be a string, got {_toml_type(raw[key])}"
            )
    for key in ("polygon", "vertices", "blocks"):
        if key in raw and not isinstance(raw[key], list):
            raise DomainFormatError(
                f"{source}: key {key!r} must be a list ({ALLOWED_KEYS[key]}), got "
                f"{_toml_type(raw[key])}"
            )
    for key in ("patches", "regions"):
        if key in raw and not isinstance(raw[key], dict):
            raise DomainFormatError(
                f"{source}: key {key!r} must be a table, a [{key}] section with one "
                f"'name = [...]' line each, got {_toml_type(raw[key])}"
            )
        for name, value in raw.get(key, {}).items():
            if not isinstance(value, list):
                what = "patch" if key == "patches" else "region"
                raise DomainFormatError(
                    f"{source}: {what} {name!r} must be a list, got {_toml_type(value)}"
                )
    has_polygon = "polygon" in raw
    has_blocks = "vertices" in raw or "blocks" in raw
    if has_polygon and has_blocks:
        raise DomainFormatError(
            f"{source}: give either 'polygon' or 'vertices' and 'blocks', not both"
        )
    if not has_polygon and not has_blocks:
        raise DomainFormatError(
            f"{source}: no geometry: give 'polygon' (a convex polygon) or 'vertices' and 'blocks'"
        )
    if has_blocks and ("vertices" not in raw or "blocks" not in raw):
        missing = "vertices" if "vertices" not in raw else "blocks"
        raise DomainFormatError(f"{source}: key {missing!r} is missing (blocks need both)")
    if has_polygon and "edges" in raw:
        raise DomainFormatError(
            f"{source}: 'edges' needs explicit blocks (vertices and blocks), not a polygon"
        )
    if has_polygon and "regions" in raw:
        raise DomainFormatError(
            f"{source}: 'regions' needs explicit blocks; a polygon is decomposed automatically"
        )
    if "edges" in raw:
        raw["edges"] = _curved_edges(raw["edges"], source)
    return raw


def _curved_edges(tables: object, source: str) -> dict[tuple[int, int], Any]:
    """``[[edges]]`` tables as ``{(a, b): curve}`` (unbound curves; the domain checks them)."""
    from .curves import CURVE_KINDS, curve_from_fields

    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise DomainFormatError(
            f"{source}: 'edges' must be [[edges]] tables (one per curved edge), got "
            f"{_toml_type(tables)}"
        )
    out: dict[tuple[int, int], Any] = {}
    for k, table in enumerate(tables, start=1):
        kinds = [name for name in CURVE_KINDS if name in table]
        where = f"{source}: [[edges]] entry {k}"
        if len(kinds) != 1:
            raise DomainFormatError(
                f"{where} needs exactly one of {', '.join(CURVE_KINDS)} = [a, b] (the edge's two "
                f"vertex ids), got {', '.join(sorted(table)) or 'nothing'}"
            )
        kind = kinds[0]
        pair = table[kind]
        if (
            not isinstance(pair, list)
            or len(pair) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
        ):
            raise DomainFormatError(f"{where}: {kind} must be [a, b], two vertex ids, got {pair!r}")
        key = (pair[0], pair[1])
        if key in out or key[::-1] in out:
            raise DomainFormatError(f"{where}: edge {list(key)} already has a curve")
        fields = {name: value for name, value in table.items() if name != kind}
        out[key] = curve_from_fields(kind, fields, f"{where} ({kind} = {list(key)})")
    return out


def _toml_type(value: object) -> str:
    names = {str: "a string", int: "an integer", float: "a number", bool: "a boolean"}
    names.update({list: "a list", dict: "a table"})
    return names.get(type(value), type(value).__name__)


def _float(x: float) -> str:
    if not math.isfinite(x):
        raise ValueError("non-finite coordinates cannot be written")
    text = repr(float(x))
    return text if any(c in text for c in ".en") else text + ".0"


def _key(name: str) -> str:
    return json.dumps(name)


def dumps_domain(domain) -> str:
    """A domain as TOML text in the explicit-block form; reading it back gives the same domain.

    Coordinates are written with Python's shortest round-trip ``repr``, so they survive exactly.
    """
    lines = [f"name = {json.dumps(domain.name)}"]
    if domain.description:
        lines.append(f"description = {json.dumps(domain.description)}")
    lines.append("vertices = [")
    lines += [f"  [{_float(x)}, {_float(y)}]," for x, y in domain.vertices]
    lines.append("]")
    lines.append("blocks = [")
    lines += [f"  [{', '.join(str(int(v)) for v in block)}]," for block in domain.blocks]
    lines.append("]")
    lines.append("")
    lines.append("[patches]")
    for name, edges in domain.patches.items():
        pairs = ", ".join(f"[{int(a)}, {int(b)}]" for a, b in edges)
        lines.append(f"{_key(name)} = [{pairs}]")
    lines.append("")
    lines.append("[regions]")
    for name, ids in domain.regions.items():
        lines.append(f"{_key(name)} = [{', '.join(str(int(b)) for b in ids)}]")
    for (a, b), curve in domain.curves.items():
        lines += ["", "[[edges]]", f"{curve.kind} = [{int(a)}, {int(b)}]"]
        for name, value in curve.to_fields().items():
            lines.append(f"{name} = {_toml_value(value)}")
    return "\n".join(lines) + "\n"


def _toml_value(value: Any) -> str:
    """A point ``[x, y]`` or a list of points, with exact floats."""
    if value and isinstance(value[0], list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return f"[{', '.join(_float(c) for c in value)}]"
