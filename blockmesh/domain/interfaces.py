"""Interfaces of a domain: named internal patches where two regions meet.

An interface is a set of block edges each shared by two blocks, named like a patch; a composite
domain (:mod:`blockmesh.domain.compose`) names the edges between regions ``A`` and ``B``
``"A|B"`` (the two regions in the order of the domain's region names) unless the user names them.
:func:`resolve_interfaces` checks what a user gives (``{name: [(a, b), ...]}``) and orients every
edge so that its first side is on its left: the block of the earlier region (the lower block
where both are in one region).

Examples
--------
>>> import numpy as np
>>> blocks = np.array([[0, 1, 2, 3, 4], [1, 5, 6, 7, 2]])
>>> region = np.array([1, 0])
>>> names, edges, patch = resolve_interfaces(blocks, region, {"glue": [(1, 2)]}, ("boundary",))
>>> names, edges.tolist(), patch.tolist()  # block 1 (region 0) runs along it from 2 to 1
(('glue',), [[2, 1]], [0])
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping

import numpy as np

from blockmesh.domain.validate.names import as_mapping, edge_pair
from blockmesh.domain.validate.problems import raise_problems
from blockmesh.errors import DomainError, DomainFormatError

__all__ = [
    "INTERFACE_NAME",
    "check_interface_name",
    "default_interface_name",
    "resolve_interfaces",
]

#: A valid interface name: a patch-like name, or two region names joined by ``|``.
INTERFACE_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*(\|[A-Za-z_][A-Za-z0-9_.\-]*)?$")


def default_interface_name(first: str, second: str) -> str:
    """The name of the interface between two regions, in their order: ``"first|second"``.

    Examples
    --------
    >>> default_interface_name("matrix", "fibre")
    'matrix|fibre'
    """
    return f"{first}|{second}"


def check_interface_name(name: object, patch_names: Iterable[str]) -> str:
    """``name`` if it is a valid interface name that no boundary patch has; else a located error."""
    if not isinstance(name, str) or not INTERFACE_NAME.match(name):
        raise DomainFormatError(
            f"interface name {name!r} is not valid: use letters, digits, '_', '-' or '.', "
            "starting with a letter or '_' (or two such names joined by '|', as in "
            "'matrix|fibre')"
        )
    if name in set(patch_names):
        raise DomainError(
            f"interface {name!r} has the name of a boundary patch; an interface is an internal "
            "patch (between two regions), so give it a name of its own"
        )
    return name


def resolve_interfaces(
    blocks: np.ndarray,
    region: np.ndarray,
    raw: Mapping[str, object] | None,
    patch_names: Iterable[str],
) -> tuple[tuple[str, ...], np.ndarray, np.ndarray]:
    """Check named interfaces and orient their edges.

    Parameters
    ----------
    blocks : ndarray (B, 5)
    region : ndarray (B,)
        Region index of every block (the earlier region's block is an edge's first side).
    raw : mapping of name to a list of (a, b) vertex pairs, or None
        Each pair an edge shared by two blocks, either way round.
    patch_names : iterable of str
        The boundary patches (an interface may not share a name with one).

    Returns
    -------
    names : tuple of str
    edges : ndarray (Ei, 2) int64
        Each oriented with its first side's block on the left.
    patch : ndarray (Ei,) int64
        Index into ``names`` of each edge.
    """
    given = as_mapping(raw, "interfaces", "interface names to lists of edges [a, b]")
    n = int(blocks.max(initial=-1)) + 1
    ahead = np.roll(blocks, -1, axis=1)
    keys = (blocks * n + ahead).ravel()
    order = np.argsort(keys, kind="stable")
    ordered = keys[order]

    def owner(a: int, b: int) -> int:
        if not (0 <= a < n and 0 <= b < n):
            return -1
        at = int(np.searchsorted(ordered, a * n + b))
        return int(order[at]) // 5 if at < ordered.size and ordered[at] == a * n + b else -1

    names: list[str] = []
    rows: list[tuple[int, int]] = []
    patch: list[int] = []
    seen: dict[tuple[int, int], str] = {}
    problems = []
    for name, edges in given.items():
        check_interface_name(name, patch_names)
        if isinstance(edges, str | bytes) or not isinstance(edges, Iterable):
            raise DomainFormatError(
                f"interface {name!r} must be a list of edges [a, b] (vertex pairs), got {edges!r}"
            )
        names.append(name)
        for edge in edges:
            a, b = edge_pair(edge, f"interface {name!r}")
            forward, backward = owner(a, b), owner(b, a)
            if forward < 0 or backward < 0:
                where = "on the boundary" if max(forward, backward) >= 0 else "no block edge"
                problems.append(
                    f"interface {name!r} names edge ({a}, {b}), which is {where}; an interface "
                    "runs between two blocks (boundary edges belong to patches)"
                )
                continue
            key = (min(a, b), max(a, b))
            if key in seen:
                problems.append(
                    f"edge ({a}, {b}) is in interfaces {seen[key]!r} and {name!r}; an edge "
                    "belongs to one interface"
                    if seen[key] != name
                    else f"interface {name!r} lists edge ({a}, {b}) twice"
                )
                continue
            seen[key] = name
            first = (int(region[forward]), forward) <= (int(region[backward]), backward)
            rows.append((a, b) if first else (b, a))
            patch.append(len(names) - 1)
    raise_problems(DomainError, problems)
    empty = [name for k, name in enumerate(names) if k not in set(patch)]
    raise_problems(
        DomainError, [f"interface {e!r} has no edges; give it edges or remove it" for e in empty]
    )
    return (
        tuple(names),
        np.array(rows, dtype=np.int64).reshape(-1, 2),
        np.array(patch, dtype=np.int64),
    )
