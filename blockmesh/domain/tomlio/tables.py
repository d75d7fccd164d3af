"""The arrays of tables of a domain file read: ``[[arcs]]``, ``[[grading]]`` and ``[[edges]]``.

Each becomes a mapping the Domain's constructors take (unbound curves, grading ratios by edge);
the Domain checks the values against its blocks.

Examples
--------
>>> polygon_arcs([{"edge": 2, "through": [1, 2.4]}], "inline")[2].through
(1.0, 2.4)
>>> toml_type([1, 2])
'a list'
"""

from __future__ import annotations

from typing import Any

from blockmesh.curves.types import CURVE_KINDS, curve_from_fields
from blockmesh.errors import DomainFormatError

__all__ = ["curved_edges_table", "grading_table", "polygon_arcs", "toml_type"]


def polygon_arcs(tables: object, source: str) -> dict[Any, Any]:
    """``[[arcs]]`` tables as ``{edge: Arc}`` (unbound; the domain checks them)."""
    out: dict[Any, Any] = {}
    for k, table in enumerate(_tables(tables, "arcs", "one per curved polygon edge", source), 1):
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


def grading_table(tables: object, source: str) -> dict[tuple[int, int], Any]:
    """``[[grading]]`` tables as ``{(a, b): ratio}`` (the domain checks edges and ratios)."""
    out: dict[tuple[int, int], Any] = {}
    for k, table in enumerate(_tables(tables, "grading", "edge = [a, b], ratio = r", source), 1):
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
            if not _is_pair(pair):
                raise DomainFormatError(f"{where}: an edge is [a, b], two vertex ids, got {pair!r}")
            if (pair[0], pair[1]) in out:
                raise DomainFormatError(f"{where}: edge {pair} is graded twice")
            out[(pair[0], pair[1])] = table["ratio"]
    return out


def curved_edges_table(tables: object, source: str) -> dict[tuple[int, int], Any]:
    """``[[edges]]`` tables as ``{(a, b): curve}`` (unbound curves; the domain checks them)."""
    out: dict[tuple[int, int], Any] = {}
    for k, table in enumerate(_tables(tables, "edges", "one per curved edge", source), 1):
        kinds = [name for name in CURVE_KINDS if name in table]
        where = f"{source}: [[edges]] entry {k}"
        if len(kinds) != 1:
            raise DomainFormatError(
                f"{where} needs exactly one of {', '.join(CURVE_KINDS)} = [a, b] (the edge's two "
                f"vertex ids), got {', '.join(sorted(table)) or 'nothing'}"
            )
        kind = kinds[0]
        pair = table[kind]
        if not _is_pair(pair):
            raise DomainFormatError(f"{where}: {kind} must be [a, b], two vertex ids, got {pair!r}")
        key = (pair[0], pair[1])
        if key in out or key[::-1] in out:
            raise DomainFormatError(f"{where}: edge {list(key)} already has a curve")
        fields = {name: value for name, value in table.items() if name != kind}
        out[key] = curve_from_fields(kind, fields, f"{where} ({kind} = {list(key)})")
    return out


def _tables(tables: object, key: str, what: str, source: str) -> list[dict[str, Any]]:
    """``tables`` if it is a list of TOML tables (``[[key]]``); a located error otherwise."""
    if not isinstance(tables, list) or not all(isinstance(t, dict) for t in tables):
        raise DomainFormatError(
            f"{source}: '{key}' must be [[{key}]] tables ({what}), got {toml_type(tables)}"
        )
    return tables


def _is_pair(pair: object) -> bool:
    """Whether ``pair`` is ``[a, b]``, two whole numbers (vertex ids)."""
    return (
        isinstance(pair, list)
        and len(pair) == 2
        and all(isinstance(v, int) and not isinstance(v, bool) for v in pair)
    )


def toml_type(value: object) -> str:
    """How messages name the type of a TOML value: ``"a string"``, ``"a table"``, ..."""
    names = {str: "a string", int: "an integer", float: "a number", bool: "a boolean"}
    names.update({list: "a list", dict: "a table"})
    return names.get(type(value), type(value).__name__)
