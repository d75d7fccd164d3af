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

Only this module knows the file layout; :mod:`blockmesh.domain` validates the values. Reading is
bounded: the file must be a regular file (not a FIFO or a device) of at most
:data:`MAX_FILE_BYTES`, arrays and tables nest at most :data:`MAX_NESTING` deep, and integers
have at most :data:`MAX_DIGITS` digits; beyond that a located error says which limit was hit.

Examples
--------
>>> raw = parse_domain_text('polygon = [[0, 0], [1, 0], [0, 1]]', source="inline")
>>> raw["polygon"]
[[0, 0], [1, 0], [0, 1]]
"""

from __future__ import annotations

import json
import math
import os
import re
import stat
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh.curves.types import CURVE_KINDS, curve_from_fields
from blockmesh.decompose.polygon import MAX_CORNERS, MAX_FILE_CORNERS
from blockmesh.errors import DomainFormatError

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

#: Largest domain file read (bytes): ample for a million vertices.
MAX_FILE_BYTES = 64 * 2**20
#: Deepest nesting of arrays and inline tables (a domain file needs 4: holes of corners).
MAX_NESTING = 16
#: Most digits in an integer (a vertex id or an edge index has a handful).
MAX_DIGITS = 30

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


def read_text_bounded(path: str | Path, *, what: str = "domain file") -> str:
    """The text of a regular file of at most :data:`MAX_FILE_BYTES`, as UTF-8.

    FIFOs, devices, sockets and directories are refused before they are opened (reading one
    would block or never end); so are files larger than the cap.

    Examples
    --------
    >>> read_text_bounded("/dev/zero")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    blockmesh.errors.DomainFormatError: /dev/zero: not a regular file (a character device); ...
    """
    path = Path(path)
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise DomainFormatError(f"{path}: no such file") from None
    except OSError as error:
        raise DomainFormatError(f"{path}: cannot read the file ({error.strerror})") from None
    if not stat.S_ISREG(info.st_mode):
        raise DomainFormatError(
            f"{path}: not a regular file ({_file_kind(info.st_mode)}); a {what} must be an "
            "ordinary file"
        )
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as error:
        raise DomainFormatError(f"{path}: cannot read the file ({error.strerror})") from None
    if len(data) > MAX_FILE_BYTES:
        raise DomainFormatError(
            f"{path}: the file is larger than {MAX_FILE_BYTES // 2**20} MiB, the most a {what} "
            "may be"
        )
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise DomainFormatError(
            f"{path}: not UTF-8 text (byte {error.start}, line {line}); a {what} is a text file"
        ) from None


def _file_kind(mode: int) -> str:
    kinds = (
        (stat.S_ISDIR, "a directory"),
        (stat.S_ISFIFO, "a FIFO"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
    )
    return next((name for test, name in kinds if test(mode)), "not an ordinary file")


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


#: A top-level key at the start of a line (``polygon =``), for counting the corners it holds.
_KEY = re.compile(r"""[ \t]*("[^"\n]*"|'[^'\n]*'|[A-Za-z0-9_-]+)[ \t]*=""")
#: The keys whose numbers are polygon corners (two each), counted while scanning.
_CORNER_KEYS = frozenset({"polygon", "holes"})


def _check_limits(text: str, source: str) -> None:
    """Nesting depth, integer size and polygon corners, checked before the TOML parser runs.

    A small scanner that skips strings and comments: ``[`` and ``{`` in values open a level (a
    ``[table]`` header at the start of a line is not a value); digits runs outside strings are
    numbers. The numbers of ``polygon`` and ``holes`` are counted as they are met, per table (a
    composite domain's ``[[parts]]`` each have their own polygon): more than twice
    :data:`~blockmesh.decompose.polygon.MAX_CORNERS` in one table, or twice
    :data:`~blockmesh.decompose.polygon.MAX_FILE_CORNERS` in the file, is refused at once,
    before the parser or the geometry sees them.
    """
    depth = 0
    line, column = 1, 0
    i, n = 0, len(text)
    at_line_start = True
    key = ""
    corner_numbers = file_numbers = 0  # of the polygon being read, of the whole file
    while i < n:
        c = text[i]
        if c == "\n":
            line, column, at_line_start = line + 1, 0, True
            i += 1
            continue
        column += 1
        if c in " \t\r":
            i += 1
            continue
        if c == "#":
            stop = text.find("\n", i)
            i = n if stop < 0 else stop
            continue
        if c in "\"'":
            quote = text[i : i + 3] if text[i : i + 3] in ('"""', "'''") else c
            j = i + len(quote)
            while j < n:
                if quote[0] == '"' and text[j] == "\\":
                    j += 2
                    continue
                if text.startswith(quote, j):
                    break
                j += 1
            skipped = text[i : j + len(quote)]
            line += skipped.count("\n")
            i = j + len(quote)
            at_line_start = False
            continue
        if at_line_start and depth == 0 and c not in "[{":
            found = _KEY.match(text, i)
            if found is not None:
                key = found[1].strip("\"'")
        if c in "[{" and not (at_line_start and c == "[" and depth == 0):
            depth += 1
            if depth > MAX_NESTING:
                raise DomainFormatError(
                    f"{source}: arrays or tables nest more than {MAX_NESTING} deep at line "
                    f"{line}, column {column}; a domain file needs at most 4 levels"
                )
        elif c in "]}" and depth > 0:
            depth -= 1
        elif c.isdigit():
            match = _NUMBER.match(text, i)
            token = match.group(0) if match else c
            digits = sum(ch.isdigit() for ch in token.split("e")[0].split("E")[0])
            if digits > MAX_DIGITS and not any(ch in token for ch in ".eE"):
                raise DomainFormatError(
                    f"{source}: the integer at line {line}, column {column} has {digits} digits; "
                    f"numbers in a domain file have at most {MAX_DIGITS}"
                )
            if key in _CORNER_KEYS and depth:
                corner_numbers += 1
                file_numbers += 1
                if corner_numbers > 2 * MAX_CORNERS or file_numbers > 2 * MAX_FILE_CORNERS:
                    most, what = (
                        (MAX_CORNERS, "the polygon and its holes")
                        if corner_numbers > 2 * MAX_CORNERS
                        else (MAX_FILE_CORNERS, "the polygons of the file")
                    )
                    raise DomainFormatError(
                        f"{source}: {what} have more than {most:,} corners (counted up to line "
                        f"{line}); a polygon of at most {MAX_CORNERS:,} is decomposed in seconds, "
                        f"a file holds at most {MAX_FILE_CORNERS:,} (simplify the outline, or "
                        "split the domain into parts)"
                    )
            i += len(token)
            column += len(token) - 1
            at_line_start = False
            continue
        if c == "[" and at_line_start and depth == 0:  # a table header: a part of its own
            corner_numbers, key = 0, ""
            stop = text.find("\n", i)
            i = n if stop < 0 else stop
            continue
        at_line_start = False
        i += 1


_NUMBER = re.compile(r"[0-9][0-9_]*(?:\.[0-9_]*)?(?:[eE][+-]?[0-9_]+)?")


def parse_domain_text(text: str, *, source: str) -> dict[str, Any]:
    """Parse domain TOML text; checks keys and their types, not the geometry."""
    _check_limits(text, source)
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        raise DomainFormatError(f"{source}: malformed TOML: {error}") from None
    except (ValueError, RecursionError, MemoryError) as error:
        raise DomainFormatError(f"{source}: the TOML reader gave up: {error}") from None
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
    for key in ("polygon", "holes", "vertices", "blocks", "boundary_source", "block_source"):
        if key in raw and not isinstance(raw[key], list):
            raise DomainFormatError(
                f"{source}: key {key!r} must be a list ({ALLOWED_KEYS[key]}), got "
                f"{_toml_type(raw[key])}"
            )
    if "size" in raw and not isinstance(raw["size"], dict | str | int | float):
        raise DomainFormatError(
            f"{source}: key 'size' must be a number, an expression or a [size] table, got "
            f"{_toml_type(raw['size'])}"
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
    if "holes" in raw and not has_polygon:
        raise DomainFormatError(
            f"{source}: 'holes' belong to a 'polygon'; with explicit blocks, leave the holes' "
            "area without blocks"
        )
    for key in ("boundary_source", "block_source", "components"):
        if key in raw and not has_blocks:
            raise DomainFormatError(
                f"{source}: {key!r} belongs to explicit blocks (blockmesh writes it with them)"
            )
    if has_polygon and "regions" in raw:
        raise DomainFormatError(
            f"{source}: 'regions' needs explicit blocks; a polygon is decomposed automatically"
        )
    if "interfaces" in raw and not has_blocks:
        raise DomainFormatError(
            f"{source}: 'interfaces' belong to [[parts]] (renaming the interfaces between "
            "regions) or to explicit blocks (listing their edges), not to one polygon"
        )
    if "interfaces" in raw:
        _check_table(raw["interfaces"], "interfaces", source, list, "a list of edges [a, b]")
    if has_polygon and "edges" in raw:
        raise DomainFormatError(
            f"{source}: 'edges' needs explicit blocks (vertices and blocks), not a polygon"
        )
    if "grading" in raw and not has_blocks:
        raise DomainFormatError(
            f"{source}: 'grading' grades edges of explicit blocks (vertices and blocks), not a "
            "polygon's"
        )
    if "grading" in raw:
        raw["grading"] = _grading(raw["grading"], source)
    if "edges" in raw:
        raw["edges"] = _curved_edges(raw["edges"], source)
    if "arcs" in raw:
        raw["arcs"] = _polygon_arcs(raw["arcs"], source)
    if "circles" in raw and not isinstance(raw["circles"], list):
        raise DomainFormatError(
            f"{source}: 'circles' must be a list of tables, got {_toml_type(raw['circles'])}"
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
            f"... or circles = ...), got {_toml_type(parts)}"
        )
    if "interfaces" in raw:
        _check_table(raw["interfaces"], "interfaces", source, str, 'a name, "A|B" = "name"')
    return raw


def _check_table(table: object, key: str, source: str, kind: type, what: str) -> None:
    """``table`` a TOML table whose every value is a ``kind``; a located error otherwise."""
    if not isinstance(table, dict):
        raise DomainFormatError(
            f"{source}: {key!r} must be a table ([{key}] with one line each), got "
            f"{_toml_type(table)}"
        )
    for name, value in table.items():
        if not isinstance(value, kind):
            raise DomainFormatError(
                f"{source}: {key} {name!r} must be {what}, got {_toml_type(value)}"
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
            f"{_toml_type(circle)}"
        )
    unknown = sorted(set(circle) - {"center", "radius", "patch"})
    if unknown or "center" not in circle or "radius" not in circle:
        raise DomainFormatError(
            f"{source}: 'circle' takes center = [x, y], radius = r and optionally patch, got "
            f"{', '.join(sorted(circle)) or 'nothing'}"
        )
    return raw


def _polygon_arcs(tables: object, source: str) -> dict[Any, Any]:
    """``[[arcs]]`` tables as ``{edge: Arc}`` (unbound; the domain checks them)."""
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise DomainFormatError(
            f"{source}: 'arcs' must be [[arcs]] tables (one per curved polygon edge), got "
            f"{_toml_type(tables)}"
        )
    out: dict[Any, Any] = {}
    for k, table in enumerate(tables, start=1):
        where = f"{source}: [[arcs]] entry {k}"
        if "edge" not in table:
            raise DomainFormatError(f'{where} needs edge = i (outer edge i) or edge = "hole K:E"')
        edge = table["edge"]
        if not (isinstance(edge, int | str) and not isinstance(edge, bool)):
            raise DomainFormatError(f'{where}: edge must be i or "hole K:E", got {edge!r}')
        if edge in out:
            raise DomainFormatError(f"{where}: edge {edge!r} already has an arc")
        fields = {name: value for name, value in table.items() if name != "edge"}
        out[edge] = curve_from_fields("arc", fields, f"{where} (edge = {edge!r})")
    return out


def _grading(tables: object, source: str) -> dict[tuple[int, int], Any]:
    """``[[grading]]`` tables as ``{(a, b): ratio}`` (the domain checks edges and ratios)."""
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise DomainFormatError(
            f"{source}: 'grading' must be [[grading]] tables (edge = [a, b], ratio = r), got "
            f"{_toml_type(tables)}"
        )
    out: dict[tuple[int, int], Any] = {}
    for k, table in enumerate(tables, start=1):
        where = f"{source}: [[grading]] entry {k}"
        unknown = sorted(set(table) - {"edge", "edges", "ratio"})
        if unknown or "ratio" not in table or ("edge" in table) == ("edges" in table):
            raise DomainFormatError(
                f"{where} takes edge = [a, b] (or edges = [[a, b], ...]) and ratio = r, got "
                f"{', '.join(sorted(table)) or 'nothing'}"
            )
        pairs = [table["edge"]] if "edge" in table else table["edges"]
        if not isinstance(pairs, list):
            raise DomainFormatError(f"{where}: edges must be a list of [a, b]")
        for pair in pairs:
            if (
                not isinstance(pair, list)
                or len(pair) != 2
                or not all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
            ):
                raise DomainFormatError(f"{where}: an edge is [a, b], two vertex ids, got {pair!r}")
            if (pair[0], pair[1]) in out:
                raise DomainFormatError(f"{where}: edge {pair} is graded twice")
            out[(pair[0], pair[1])] = table["ratio"]
    return out


def _curved_edges(tables: object, source: str) -> dict[tuple[int, int], Any]:
    """``[[edges]]`` tables as ``{(a, b): curve}`` (unbound curves; the domain checks them)."""
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
    known = np.flatnonzero(domain.boundary_source[:, 0] >= 0)
    if known.size:
        lines.append("boundary_source = [  # [a, b, ring, edge]: boundary edge (a, b) on that edge")
        lines += [
            f"  [{int(a)}, {int(b)}, {int(r)}, {int(e)}],"
            for (a, b), (r, e) in zip(
                domain.boundary_edges[known], domain.boundary_source[known], strict=True
            )
        ]
        lines.append("]")
    if np.any(domain.block_source >= 0):
        lines.append(f"block_source = [{', '.join(str(int(k)) for k in domain.block_source)}]")
    if domain.components > 1:
        lines.append(f"components = {int(domain.components)}")
    lines.append("")
    lines.append("[patches]")
    for name, edges in domain.patches.items():
        pairs = ", ".join(f"[{int(a)}, {int(b)}]" for a, b in edges)
        lines.append(f"{_key(name)} = [{pairs}]")
    lines.append("")
    lines.append("[regions]")
    for name, ids in domain.regions.items():
        lines.append(f"{_key(name)} = [{', '.join(str(int(b)) for b in ids)}]")
    if domain.interface_names:
        lines.append("")
        lines.append("[interfaces]")
        for name, edges in domain.interfaces.items():
            pairs = ", ".join(f"[{int(a)}, {int(b)}]" for a, b in edges)
            lines.append(f"{_key(name)} = [{pairs}]")
    for (a, b), ratio in getattr(domain, "grading", {}).items():
        lines += ["", "[[grading]]", f"edge = [{int(a)}, {int(b)}]", f"ratio = {_float(ratio)}"]
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
