"""Parsing a Gmsh ``.msh`` 4.1 ASCII file section by section into its raw arrays.

The file is read in chunks (:class:`blockmesh.io.text.TextReader`), never held whole; every
count a header announces is checked against what is left of the file before it is looped over
or allocated, and every malformed header, tag or value is an :class:`ExportError` naming the
line (see :mod:`blockmesh._system.bounded`). :func:`parse_msh` returns an :class:`MshFile`:
the nodes, the element blocks, the physical names and entities, the element data views and the
blockmesh metadata, which :mod:`blockmesh.io.msh.reader` turns into a mesh.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.bounded import current_guard, open_regular
from blockmesh.errors import ExportError
from blockmesh.io.common import decode_metadata
from blockmesh.io.msh.writer import ELEMENT_NODES
from blockmesh.io.text import TextReader

__all__ = ["MshFile", "parse_msh"]

_INT32 = np.iinfo(np.int32).max


@dataclass
class _Elements:
    """The element blocks of one dimension: tags, node tags, and each block's entity."""

    tags: list[np.ndarray] = field(default_factory=list)
    nodes: list[np.ndarray] = field(default_factory=list)
    runs: list[tuple[int, int]] = field(default_factory=list)  # (entity tag, elements)

    def join(self) -> None:
        """Each list made one array (after the section: the blocks are freed as joined)."""
        for name in ("tags", "nodes"):
            parts = getattr(self, name)
            if len(parts) > 1:
                setattr(self, name, [np.concatenate(parts)])
                parts.clear()

    def joined(self, width: int) -> tuple[np.ndarray, np.ndarray]:
        """Element tags (K,) and node tags (K, width)."""
        if not self.nodes:
            return np.empty(0, np.int64), np.empty((0, width), np.int64)
        self.join()
        return self.tags[0], self.nodes[0]

    def entity(self, index: np.ndarray) -> np.ndarray:
        """The entity tag of the elements ``index`` (positions in :meth:`joined`'s order)."""
        if not self.runs:
            return np.empty(0, np.int64)
        tags = np.array([t for t, _ in self.runs], dtype=np.int64)
        ends = np.cumsum([n for _, n in self.runs])
        return tags[np.searchsorted(ends, index, side="right")]


@dataclass
class MshFile:
    """What the sections of a .msh file hold, as parsed."""

    meta: dict[str, Any] = field(default_factory=dict)
    names: dict[tuple[int, int], str] = field(default_factory=dict)
    entities: dict[tuple[int, int], list[int]] = field(default_factory=dict)
    # node tags -> node indices (the tags themselves are not kept)
    to_index: Callable[[np.ndarray, str, str], np.ndarray] | None = None
    coords: np.ndarray | None = None
    lines: _Elements = field(default_factory=_Elements)
    surface: _Elements = field(default_factory=_Elements)
    # name -> (element tags, values); tags None: the values are the surface elements' own, in order
    views: dict[str, tuple[np.ndarray | None, np.ndarray]] = field(default_factory=dict)
    # the pentagon view is elements ``per * p .. per * p + per - 1`` for pentagon ``p`` (0: not)
    per: int = 0
    # the parent view holds one value per group of ``parent_per`` elements (0: one per element)
    parent_per: int = 0


def _ints(text: bytes, r: TextReader, what: str, count: int = 1) -> list[int]:
    """The whole numbers of a header line (at least ``count`` of them)."""
    try:
        values = [int(v) for v in text.split()]
    except ValueError:
        values = []
    if len(values) < count:
        raise ExportError(f"{r.where}, line {r.line_number}: malformed {what} {text[:80]!r}")
    if any(abs(v) >= 2**62 for v in values):  # no tag or count is that large; int64 holds it
        raise ExportError(
            f"{r.where}, line {r.line_number}: {what} {text[:80]!r} holds a number beyond any "
            "tag or count"
        )
    return values


def _entities(body: list[bytes], r: TextReader, first: int) -> dict[tuple[int, int], list[int]]:
    """(dim, tag) -> physical tags, from the lines of an ASCII ``$Entities`` section.

    ``first`` is the line number of the section's first line (for errors).
    """
    try:
        counts = [int(v) for v in body[0].split()] if body else []
    except ValueError:
        counts = []
    if body and len(counts) != 4:
        raise ExportError(f"{r.where}, line {first}: malformed $Entities header {body[0]!r}")
    out: dict[tuple[int, int], list[int]] = {}
    row = 1
    try:
        for dim, count in enumerate(counts):
            for _ in range(count):
                vals = body[row].split()
                row += 1
                at = 4 if dim == 0 else 7
                n_phys = int(vals[at])
                out[(dim, int(vals[0]))] = [int(v) for v in vals[at + 1 : at + 1 + n_phys]]
    except (IndexError, ValueError):
        raise ExportError(f"{r.where}, line {first + row - 1}: malformed entity") from None
    return out


def _nodes(r: TextReader, f: MshFile) -> None:
    blocks, total, _, max_tag = _ints(r.line(), r, "$Nodes header", 4)[:4]
    r.check_count(blocks, "node blocks", 8)
    r.check_count(total, "nodes", 6)
    tags, coords = [], []
    for _ in range(blocks):
        _dim, _tag, parametric, n = _ints(r.line(), r, "node block header", 4)[:4]
        if parametric:
            raise ExportError(f"{r.where}: parametric nodes are not supported; save without them")
        tags.append(r.table(n, 1, np.int64, np.int32 if max_tag <= _INT32 else np.int64).ravel())
        coords.append(r.table(n, 3, np.float64, keep=2))
    node_tags = np.concatenate(tags) if len(tags) > 1 else tags[0] if tags else np.empty(0, int)
    del tags
    f.coords = (  # one block (as blockmesh writes): no copy
        np.concatenate(coords) if len(coords) > 1 else coords[0] if coords else np.empty((0, 2))
    )
    if node_tags.size != total:
        raise ExportError(f"{r.where}: $Nodes announces {total} nodes but holds {node_tags.size}")
    f.to_index = _node_index(node_tags, r.where)


def _elements(r: TextReader, f: MshFile) -> None:
    blocks, _, _, max_tag = _ints(r.line(), r, "$Elements header", 4)[:4]
    r.check_count(blocks, "element blocks", 8)
    small = (
        np.int32
        if max_tag <= _INT32 and f.coords is not None and f.coords.shape[0] <= _INT32
        else np.int64
    )
    for _ in range(blocks):
        dim, tag, etype, n = _ints(r.line(), r, "element block header", 4)[:4]
        if etype not in ELEMENT_NODES:
            raise ExportError(
                f"{r.where}, line {r.line_number}: element type {etype} is not supported (only "
                "points, lines, triangles and quadrangles of first order)"
            )
        group = {1: f.lines, 2: f.surface}.get(dim)
        if group is None:
            r.skip(n)
            continue
        tags, rows = r.tagged_table(n, 1 + ELEMENT_NODES[etype], np.int64, small)
        if group.nodes and group.nodes[0].shape[1] != rows.shape[1]:
            raise ExportError(
                f"{r.where}: the surface mixes triangles and quadrangles; blockmesh reads the "
                ".msh files it writes (one split for the whole mesh)"
            )
        group.tags.append(tags)
        group.nodes.append(rows)
        group.runs.append((tag, n))
    f.lines.join()
    f.surface.join()


def _element_data(r: TextReader, f: MshFile) -> None:
    n_str = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "string tags")
    strings = [r.line().strip().strip(b'"').decode(errors="replace") for _ in range(n_str)]
    n_real = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "real tags")
    for _ in range(n_real):
        r.line()
    n_int = r.check_count(_ints(r.line(), r, "$ElementData header")[0], "integer tags")
    ints = [_ints(r.line(), r, "$ElementData header")[0] for _ in range(n_int)]
    if n_int < 3:
        raise ExportError(f"{r.where}, line {r.line_number}: $ElementData needs 3 integer tags")
    n_comp, count = ints[1], ints[2]
    if not 1 <= n_comp <= 9 or count < 0:
        raise ExportError(
            f"{r.where}, line {r.line_number}: $ElementData of {n_comp} components for {count} "
            "elements (blockmesh reads 1 component for 0 or more elements)"
        )
    try:
        tags, rows = r.tagged_table(
            count, 1 + n_comp, np.int64, np.int32 if count <= _INT32 else np.int64
        )
    except ExportError:
        raise ExportError(
            f"{r.where}: the element data {strings[:1]} holds non-integer values; blockmesh "
            "reads the .msh files it writes"
        ) from None
    if strings and n_comp >= 1:
        values = rows[:, 0]
        if f.surface.tags:  # checked against the elements now: the view's tags are freed
            surface = f.surface.tags[0]
            skip = tags.size - surface.size
            if skip >= 0 and np.array_equal(tags[skip:], surface):
                f.views[strings[0]] = (None, _compact_view(f, strings[0], values[skip:]))
                return
        f.views[strings[0]] = (tags, values)


def _grouping(values: np.ndarray) -> int | None:
    """``per`` if ``values`` is ``0 0 .. 0 1 1 .. 1 ..`` (each id ``per`` times), else None.

    Checked a chunk at a time (no temporaries of the view's size).
    """
    k = values.size
    m = int(values[-1]) + 1 if k else 0
    if m <= 0 or k % m:
        return None
    per = k // m
    step = per << 16  # elements per chunk: temporaries of a few megabytes
    for start in range(0, k, step):
        chunk = values[start : start + step]
        if not np.array_equal(chunk, np.arange(start, start + chunk.size) // per):
            return None
    return per


def _compact_view(f: MshFile, name: str, values: np.ndarray) -> np.ndarray:
    """A view matched to the surface elements, kept small when its layout allows.

    The ``pentagon`` view of the files blockmesh writes numbers the elements ``per`` at a time
    (``f.per``): it is kept as a broadcast ``(M, per)`` view of ``0..M-1``, and the ``parent``
    view, then constant on each group, as one value per pentagon.
    """
    if name == "pentagon":
        per = _grouping(values)
        if per is not None:
            f.per = per
            m = values.size // per
            return np.broadcast_to(np.arange(m)[:, None], (m, per))
    elif name == "parent" and f.per and values.size % f.per == 0:
        grouped = values.reshape(-1, f.per)
        if all(np.array_equal(grouped[:, j], grouped[:, 0]) for j in range(1, f.per)):
            f.parent_per = f.per
            return np.array(grouped[:, 0])
    return values


def parse_msh(path: Path) -> MshFile:
    """The sections of the .msh file ``path``, parsed; ExportError naming the line otherwise."""
    where = str(path)
    f = MshFile()
    with open_regular(path) as handle:
        r = TextReader(handle, where)
        head = r.line().strip()
        if head != b"$MeshFormat":
            raise ExportError(
                f"{where} is not a Gmsh .msh file (it does not start with $MeshFormat)"
            )
        fmt = r.line().split()
        if len(fmt) < 2 or not fmt[0].startswith(b"4"):
            raise ExportError(f"{where} is not a Gmsh 4.x .msh file (saved as MSH 4.1 ASCII?)")
        if fmt[1] != b"0":
            raise ExportError(
                f"{where} is a binary .msh; blockmesh reads ASCII 4.1 (save it as ASCII)"
            )
        r.lines_until(b"$EndMeshFormat")
        while True:
            text = r.line()
            if not text.strip():
                if r.at_end:
                    break
                continue
            section = text.strip()
            if not section.startswith(b"$"):
                raise ExportError(
                    f"{where}, line {r.line_number}: expected a $Section, got {section[:40]!r}"
                )
            end = b"$End" + section[1:]
            if section == b"$Nodes":
                _nodes(r, f)
            elif section == b"$Elements":
                _elements(r, f)
            elif section == b"$ElementData":
                _element_data(r, f)
            else:
                first = r.line_number + 1
                body = r.lines_until(end)
                if section == b"$PhysicalNames":
                    f.names = _physical_names(body, r, first)
                elif section == b"$Entities":
                    f.entities = _entities(body, r, first)
                elif section == b"$BlockMesh" and body:
                    f.meta = decode_metadata(body[0].strip(), where)
                continue
            r.lines_until(end)
    if f.coords is None or not f.surface.nodes:
        raise ExportError(f"{where} has no $Nodes or no surface elements in $Elements")
    return f


def _physical_names(body: list[bytes], r: TextReader, first: int) -> dict[tuple[int, int], str]:
    """(dim, tag) -> name, from the lines of a ``$PhysicalNames`` section."""
    names: dict[tuple[int, int], str] = {}
    for k, line in enumerate(body[1:], start=first + 1):
        parts = line.decode(errors="replace").split(maxsplit=2)
        if not parts:
            continue
        try:
            if len(parts) != 3:
                raise ValueError
            dim, tag = int(parts[0]), int(parts[1])
        except ValueError:
            raise ExportError(
                f"{r.where}, line {k}: malformed physical name {line[:80]!r} (expected "
                '"DIMENSION TAG NAME", the first two whole numbers)'
            ) from None
        names[(dim, tag)] = parts[2].strip().strip('"')
    return names


def _node_index(node_tags: np.ndarray, where: str) -> Callable[[np.ndarray, str, str], np.ndarray]:
    """A function mapping node tags to node indices (tag - 1 when the tags are 1..N in order).

    The tags it is given are the parsed file's own arrays: tag - 1 is computed in place (no copy
    of the elements), so they hold indices afterwards.
    """
    n = node_tags.size
    consecutive = n == 0 or (
        node_tags[0] == 1 and node_tags[-1] == n and bool(np.all(np.diff(node_tags) == 1))
    )
    index_of = None
    order = sorted_tags = None
    if not consecutive:
        low, high = int(node_tags.min()), int(node_tags.max())
        if low < 1:
            raise ExportError(f"{where}: $Nodes holds the node tag {low}; tags are 1 or more")
        if high <= 4 * n + 1024:  # dense: a table of tag -> index
            current_guard().allocate(8 * (high + 1), "the node tag table")
            index_of = np.full(high + 1, -1, dtype=np.int64)
            index_of[node_tags] = np.arange(n)
        else:  # sparse: sorted tags, looked up by bisection (no table of the largest tag)
            order = np.argsort(node_tags, kind="stable")
            sorted_tags = node_tags[order]

    def to_index(tags: np.ndarray, what: str, where: str) -> np.ndarray:
        if tags.size == 0:
            return np.empty(tags.shape, dtype=np.int64)
        low, high = int(tags.min()), int(tags.max())
        missing = ExportError(f"{where}: some {what} use node tags that are not in $Nodes")
        if sorted_tags is not None and order is not None:
            pos = np.minimum(np.searchsorted(sorted_tags, tags), n - 1)
            if np.any(sorted_tags[pos] != tags):
                raise missing
            return order[pos]
        if index_of is None:
            if low < 1 or high > n:
                raise missing
            return np.subtract(tags, 1, out=tags)
        if low < 0 or high >= index_of.size or np.any(index_of[tags] < 0):
            raise missing
        return index_of[tags]

    return to_index
