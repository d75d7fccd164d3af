"""A literal transcription of the paper's ``nodaladdressesforpentagon`` (0-based), for tests.

Plain Python loops and a dictionary in place of the dense ``mdpt`` matrix; deliberately written
independently of :mod:`blockmesh.refinement.template` so that the two can be compared.
"""

from __future__ import annotations


def paper_cells(blocks: list[list[int]], levels: int) -> list[list[int]]:
    """Cells after ``levels`` refinements of ``blocks`` numbered by the paper's rule."""
    elm = [list(b) for b in blocks]
    next_id = 1 + max(max(b) for b in blocks)
    for _ in range(levels):
        mdpt: dict[frozenset[int], int] = {}
        new = []
        for v in elm:
            u = []
            for i in range(5):
                key = frozenset((v[i], v[(i + 1) % 5]))
                if key not in mdpt:
                    mdpt[key] = next_id
                    next_id += 1
                u.append(mdpt[key])
            w = list(range(next_id, next_id + 5))
            next_id += 5
            for k in range(5):
                new.append([v[k], u[k], w[k], w[k - 1], u[k - 1]])
            new.append(w)
        elm = new
    return elm
