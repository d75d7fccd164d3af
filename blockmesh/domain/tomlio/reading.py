"""A domain file's checked table made a Domain: the constructor its keys ask for.

:func:`~blockmesh.domain.tomlio.layout.parse_domain_text` checks the keys and their types;
:func:`domain_from_table` hands the values to the constructor they belong to (parts to
:func:`~blockmesh.domain.compose.compose_parts`, a circle, a polygon, explicit blocks) and cuts
the result to the file's ``size``, each error prefixed with the file's name.

Examples
--------
>>> from blockmesh import Domain
>>> raw = parse_domain_text("polygon = [[0, 0], [2, 0], [3, 1], [1, 3], [0, 2]]", source="f")
>>> domain_from_table(Domain, raw, source="f").area
6.0
"""

from __future__ import annotations

import numbers
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from blockmesh.domain.compose import compose_parts
from blockmesh.domain.parts import part_from_table
from blockmesh.domain.tomlio.layout import parse_domain_text, read_domain_file
from blockmesh.errors import DomainError, DomainFormatError
from blockmesh.sizing.spec import as_size_spec

if TYPE_CHECKING:
    from blockmesh.domain.domain import Domain

__all__ = ["domain_from_file", "domain_from_table", "domain_from_text"]


def domain_from_file(cls: type[Domain], path: str | Path) -> Domain:
    """The Domain of the domain file ``path`` (:meth:`blockmesh.Domain.from_toml`)."""
    return domain_from_table(cls, read_domain_file(path), source=str(path))


def domain_from_text(cls: type[Domain], text: str, *, name: str = "domain") -> Domain:
    """The Domain of TOML text (:meth:`blockmesh.Domain.from_toml_text`)."""
    raw = parse_domain_text(text, source="<text>")
    raw.setdefault("name", name)
    return domain_from_table(cls, raw, source="<text>")


def domain_from_table(cls: type[Domain], raw: dict[str, Any], *, source: str) -> Domain:
    """The Domain of a domain file's table ``raw`` (checked), cut to its ``size`` if it has one."""
    size = raw.pop("size", None)
    domain = _geometry_from_table(cls, raw, source=source)
    if size is None:
        return domain
    try:
        return domain.with_size(as_size_spec(size, source=f"{source} [size]"))
    except DomainError as error:
        raise type(error)(f"{source}: {error}") from None


def _geometry_from_table(cls: type[Domain], raw: dict[str, Any], *, source: str) -> Domain:
    name = raw.get("name", "domain")
    description = raw.get("description", "")
    try:
        if "parts" in raw:
            parts = [part_from_table(table, k) for k, table in enumerate(raw["parts"])]
            return compose_parts(
                cls,
                parts,
                name=name,
                description=description,
                interfaces=raw.get("interfaces"),
            )
        if "circle" in raw:
            circle = raw["circle"]
            return cls.from_circle(
                circle["center"],
                circle["radius"],
                name=name,
                patch=circle.get("patch", "boundary"),
                description=description,
            )
        if "polygon" in raw:
            return cls.from_polygon(
                raw["polygon"],
                raw.get("holes"),
                name=name,
                patches=raw.get("patches"),
                description=description,
                arcs=raw.get("arcs"),
                circles=raw.get("circles"),
            )
        return cls.from_blocks(
            raw["vertices"],
            raw["blocks"],
            raw.get("patches"),
            raw.get("regions"),
            name=name,
            description=description,
            boundary_source=_source_table(raw.get("boundary_source")),
            block_source=_source_list(raw.get("block_source")),
            edges=raw.get("edges"),
            interfaces=raw.get("interfaces"),
            components=raw.get("components", 1),
            grading=raw.get("grading"),
        )
    except DomainError as error:
        raise type(error)(f"{source}: {error}") from None


def _whole(value: object) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _source_table(raw: Any) -> dict[tuple[int, int], tuple[int, int]] | None:
    """The ``boundary_source`` rows of a domain file, ``[a, b, ring, edge]`` each."""
    if raw is None:
        return None
    table = {}
    for k, row in enumerate(raw):
        if (
            not isinstance(row, list)
            or len(row) != 4
            or not all(_whole(v) and -1 <= int(v) < 2**62 for v in row)
        ):
            raise DomainFormatError(
                f"boundary_source row {k} is {row!r:.80}: each row is [a, b, ring, edge], whole "
                "numbers of at least -1"
            )
        table[(int(row[0]), int(row[1]))] = (int(row[2]), int(row[3]))
    return table


def _source_list(raw: Any) -> np.ndarray | None:
    """The ``block_source`` list of a domain file: one whole number per block."""
    if raw is None:
        return None
    bad = [k for k, v in enumerate(raw) if not _whole(v) or not -1 <= int(v) < 2**62]
    if bad:
        raise DomainFormatError(
            f"block_source entry {bad[0]} is {raw[bad[0]]!r}: one element number (or -1) per block"
        )
    return np.array(raw, dtype=np.int64)
