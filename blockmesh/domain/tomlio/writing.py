"""A domain written as a domain file: the explicit-block form, exact, read back to the same domain.

Examples
--------
>>> from blockmesh import Domain
>>> square = Domain.from_polygon([(0, 0), (1, 0), (1, 1), (0, 1)])
>>> Domain.from_toml_text(dumps_domain(square)).vertices.tolist() == square.vertices.tolist()
True
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from blockmesh._system.atomic import as_path, atomic_file

__all__ = ["dumps_domain", "write_domain"]


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


def write_domain(domain, path: str | Path) -> Path:
    """Write :func:`dumps_domain` of ``domain`` to ``path`` atomically (temporary file, rename)."""
    path = as_path(path)
    with atomic_file(path) as temporary:
        temporary.write_text(dumps_domain(domain), encoding="utf-8")
    return path


def _toml_value(value: Any) -> str:
    """A point ``[x, y]`` or a list of points, with exact floats."""
    if value and isinstance(value[0], list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return f"[{', '.join(_float(c) for c in value)}]"
