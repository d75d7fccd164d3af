"""Patches and regions resolved: every boundary edge in one named patch, every block in one region.

Examples
--------
>>> resolve_regions(3, {"left": [0]})
(('left', 'domain'), array([0, 1, 1]))
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Iterable, Mapping

import numpy as np

from blockmesh.domain.validate.problems import raise_problems
from blockmesh.errors import DomainError, DomainFormatError

__all__ = [
    "DEFAULT_PATCH",
    "DEFAULT_REGION",
    "as_mapping",
    "check_name",
    "edge_pair",
    "resolve_patches",
    "resolve_regions",
]

#: Patch of every boundary edge no patch names.
DEFAULT_PATCH = "boundary"
#: Region of every block no region names.
DEFAULT_REGION = "domain"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]*$")


def check_name(name: object, what: str) -> str:
    """``name`` if it is a valid patch or region name (letters, digits, ``_-.``), else an error."""
    if not isinstance(name, str) or not _NAME.match(name):
        raise DomainFormatError(
            f"{what} name {name!r} is not valid: use letters, digits, '_', '-' or '.', starting "
            "with a letter or '_'"
        )
    return name


def as_mapping(raw: object, what: str, of: str) -> dict[str, object]:
    """``raw`` (a mapping, or None for none) as a dict; a located error for anything else."""
    if raw is None:
        return {}
    if not isinstance(raw, Mapping):
        raise DomainFormatError(f"{what} must map {of}, got {type(raw).__name__} {raw!r:.60}")
    return dict(raw)


def resolve_patches(
    boundary: np.ndarray, raw: Mapping[str, object] | None, blocks: np.ndarray
) -> tuple[tuple[str, ...], np.ndarray]:
    """Assign every boundary edge to one patch.

    Parameters
    ----------
    boundary : ndarray (Eb, 2)
        The boundary edges, oriented with the domain on their left.
    raw : mapping of name to a list of [a, b] vertex pairs, or None
    blocks : ndarray (B, 5)
        The blocks (to name the owners of an edge that is not on the boundary).

    Returns
    -------
    names : tuple of str
        Patch names in the order given, then ``"boundary"`` for unnamed edges (if any).
    patch : ndarray (Eb,)
        Index into ``names`` for each boundary edge.
    """
    raw = as_mapping(raw, "patches", "patch names to lists of edges [a, b]")
    index = {(int(a), int(b)): k for k, (a, b) in enumerate(boundary)}
    index.update({(b, a): k for (a, b), k in list(index.items())})
    patch = np.full(boundary.shape[0], -1, dtype=np.int64)
    names: list[str] = []
    problems = []
    for name, edges in raw.items():
        check_name(name, "patch")
        if isinstance(edges, str | bytes) or not isinstance(edges, Iterable):
            raise DomainFormatError(
                f"patch {name!r} must be a list of edges [a, b] (vertex pairs), got {edges!r}"
            )
        names.append(name)
        k_name = len(names) - 1
        for edge in edges:
            key = edge_pair(edge, f"patch {name!r}")
            k = index.get(key)
            if k is None:
                owners = _edge_owners(blocks, *key)
                if owners:
                    problems.append(
                        f"patch {name!r} names edge {key}, which is not on the boundary: it is "
                        f"shared by blocks {owners[0]} and {owners[1]}"
                    )
                else:
                    problems.append(
                        f"patch {name!r} names edge {key}, which is not an edge of any block"
                    )
                continue
            if patch[k] == k_name:
                problems.append(f"patch {name!r} lists edge {key} twice")
            elif patch[k] >= 0:
                problems.append(
                    f"edge {key} is in patches {names[patch[k]]!r} and {name!r}; a boundary edge "
                    "belongs to one patch"
                )
            patch[k] = k_name
    raise_problems(DomainError, problems)
    _name_the_rest(patch, names, DEFAULT_PATCH)
    used = np.unique(patch)
    empty = [n for k, n in enumerate(names) if k not in used]
    raise_problems(
        DomainError, [f"patch {n!r} has no edges; give it edges or remove it" for n in empty]
    )
    return tuple(names), patch


def edge_pair(edge: object, owner: str) -> tuple[int, int]:
    """``edge`` as a pair of vertex ids ``(a, b)``; DomainFormatError naming ``owner`` otherwise.

    Examples
    --------
    >>> edge_pair([3, 4], "patch 'inlet'")
    (3, 4)
    """
    pair = list(edge) if isinstance(edge, Iterable) and not isinstance(edge, str) else None
    if (
        pair is None
        or len(pair) != 2
        or not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in pair)
    ):
        raise DomainFormatError(f"{owner} has {edge!r}; each edge is a pair of vertex ids [a, b]")
    return int(pair[0]), int(pair[1])


def _edge_owners(blocks: np.ndarray, a: int, b: int) -> list[int]:
    """The blocks having the edge ``(a, b)`` either way round. O(B)."""
    ahead = np.roll(blocks, -1, axis=1)
    hit = ((blocks == a) & (ahead == b)) | ((blocks == b) & (ahead == a))
    return np.flatnonzero(np.any(hit, axis=1)).tolist()


def resolve_regions(
    n_blocks: int, raw: Mapping[str, object] | None
) -> tuple[tuple[str, ...], np.ndarray]:
    """Assign every block to one region; unnamed blocks form the region ``"domain"``.

    Examples
    --------
    >>> resolve_regions(3, {"left": [0]})
    (('left', 'domain'), array([0, 1, 1]))
    """
    region = np.full(n_blocks, -1, dtype=np.int64)
    names: list[str] = []
    problems = []
    for name, ids in as_mapping(raw, "regions", "region names to lists of block ids").items():
        check_name(name, "region")
        if isinstance(ids, str | bytes) or not isinstance(ids, Iterable):
            raise DomainFormatError(f"region {name!r} must be a list of block ids, got {ids!r}")
        names.append(name)
        for b in ids:
            if not isinstance(b, numbers.Integral) or isinstance(b, bool):
                raise DomainFormatError(f"region {name!r} has block id {b!r}, not a whole number")
            if not 0 <= int(b) < n_blocks:
                problems.append(
                    f"region {name!r} names block {b}, but the blocks are numbered "
                    f"0..{n_blocks - 1}"
                )
            elif region[b] >= 0 and region[b] != len(names) - 1:
                problems.append(
                    f"block {b} is in regions {names[region[b]]!r} and {name!r}; a block belongs "
                    "to one region"
                )
            else:
                region[b] = len(names) - 1
    raise_problems(DomainError, problems)
    _name_the_rest(region, names, DEFAULT_REGION)
    return tuple(names), region


def _name_the_rest(index: np.ndarray, names: list[str], default: str) -> None:
    """Give every entry of ``index`` still unnamed (-1) the name ``default`` (added if new)."""
    if np.any(index < 0):
        if default in names:
            index[index < 0] = names.index(default)
        else:
            names.append(default)
            index[index < 0] = len(names) - 1
