"""Edge grading of explicit blocks: geometric spacing at every level, shared edges agreeing,
cells strictly convex, a located error where a grading folds a cell."""

from __future__ import annotations

import numpy as np
import pytest

import blockmesh
from blockmesh.refinement.grading import geometric_fractions


def graded_channel(n: int = 4, ratio: float = 0.1):
    """A channel 8 x 2 of pentagons (a row of roofs, a row of inverted roofs between them),
    the edges across the upper row graded ``ratio`` (last piece over first) towards the top
    wall: cells ten times thinner at the wall than at the middle."""
    length, h1, h2, width = 8.0, 0.8, 1.2, 2.0
    dx = length / n
    xs = np.arange(n + 1) * dx
    xm = xs[:-1] + dx / 2
    vertices: list[tuple[float, float]] = []

    def vid(p):
        vertices.append(p)
        return len(vertices) - 1

    bottom = [vid((x, 0.0)) for x in xs]
    low = [vid((x, h1)) for x in xs]
    peak = [vid((x, h2)) for x in xm]
    top = [vid((x, width)) for x in xm]
    corner_l, corner_r = vid((0.0, width)), vid((length, width))
    bulge_l, bulge_r = vid((-0.15, 1.4)), vid((length + 0.15, 1.4))
    blocks = [(bottom[k], bottom[k + 1], low[k + 1], peak[k], low[k]) for k in range(n)]
    blocks += [(peak[k], low[k + 1], peak[k + 1], top[k + 1], top[k]) for k in range(n - 1)]
    blocks.append((low[0], peak[0], top[0], corner_l, bulge_l))
    blocks.append((peak[n - 1], low[n], bulge_r, corner_r, top[n - 1]))
    grading = {(peak[k], top[k]): ratio for k in range(n)}
    patches = {"top": [(corner_r, top[n - 1])] + [(top[k + 1], top[k]) for k in range(n - 1)]
               + [(top[0], corner_l)]}  # fmt: skip
    return blockmesh.Domain.from_blocks(vertices, blocks, patches, grading=grading, name="channel")


@pytest.mark.parametrize("level", [0, 1, 2, 3, 4])
def test_graded_channel_is_geometric_at_every_level(level):
    domain = graded_channel()
    mesh = domain.mesh(level)
    mesh.check_geometry()  # every cell strictly convex and counter-clockwise
    pieces = 2**level
    for (a, b), ratio in domain.grading.items():
        start, stop = domain.vertices[a], domain.vertices[b]
        direction = (stop - start) / np.hypot(*(stop - start))
        offset = mesh.points - start
        along = offset @ direction
        across = offset @ np.array([-direction[1], direction[0]])
        on = np.flatnonzero((np.abs(across) < 1e-12) & (along > -1e-12) & (along < 1 + 1e-12))
        positions = np.sort(along[on]) / np.hypot(*(stop - start))
        assert positions.size == pieces + 1
        expected = geometric_fractions(ratio, pieces)
        assert np.max(np.abs(positions - expected)) < 1e-12
        steps = np.diff(positions)
        if pieces > 1:
            q = ratio ** (1 / (pieces - 1))
            assert np.allclose(steps[1:] / steps[:-1], q, rtol=1e-12, atol=0)


def test_grading_is_shared_and_round_trips(tmp_path):
    domain = graded_channel()
    mesh = domain.mesh(3)
    # Conforming: the shared graded edges have one chain of nodes (no duplicate points).
    rounded = np.unique(mesh.points.round(12), axis=0)
    assert len(rounded) == mesh.n_points
    text = domain.to_toml()
    assert "[[grading]]" in text
    again = blockmesh.Domain.from_toml_text(text)
    assert dict(again.grading) == dict(domain.grading)
    assert np.array_equal(again.mesh(3).points, mesh.points)


def test_inverse_ratio_is_the_same_grading():
    d = graded_channel()
    (a, b), r = next(iter(d.grading.items()))
    flipped = {**{k: v for k, v in d.grading.items() if k != (a, b)}, (b, a): 1 / r}
    e = blockmesh.Domain.from_blocks(d.vertices, d.blocks, grading=flipped)
    assert np.allclose(e.mesh(2).points, d.mesh(2).points, atol=1e-13)


def test_bad_gradings_are_located():
    d = graded_channel()
    with pytest.raises(blockmesh.DomainError, match=r"graded edge \(0, 9\) is not a block edge"):
        blockmesh.Domain.from_blocks(d.vertices, d.blocks, grading={(0, 9): 2.0})
    with pytest.raises(blockmesh.DomainError, match=r"ratio .* must be a finite number"):
        blockmesh.Domain.from_blocks(d.vertices, d.blocks, grading={(0, 1): 0.0})
    with pytest.raises(blockmesh.DomainError, match="graded twice"):
        blockmesh.Domain.from_blocks(d.vertices, d.blocks, grading={(0, 1): 2.0, (1, 0): 2.0})
    # A strong grading on one side of the bottom blocks only folds their cells.
    folding = {(0, 5): 1e-4}
    strong = blockmesh.Domain.from_blocks(d.vertices, d.blocks, grading=folding)
    with pytest.raises(
        blockmesh.DomainError, match=r"the grading folds cell \d+ of block 0 at level"
    ):
        strong.mesh(4)


def test_grading_in_a_domain_file(tmp_path):
    text = (
        "vertices = [[0, 0], [2, 0], [2.4, 1], [2, 2], [0, 2]]\nblocks = [[0, 1, 2, 3, 4]]\n"
        "[[grading]]\nedges = [[4, 0], [1, 2]]\nratio = 3\n"
    )
    d = blockmesh.Domain.from_toml_text(text)
    assert dict(d.grading) == {(4, 0): 3.0, (1, 2): 3.0}
    d.mesh(3).check_geometry()
    with pytest.raises(blockmesh.DomainFormatError, match=r"\[\[grading\]\] entry 1 takes edge"):
        blockmesh.Domain.from_toml_text(text.replace("ratio = 3", "factor = 3"))
