"""Shared fixtures: the catalogue, paper pentagons, small block layouts."""

from __future__ import annotations

import numpy as np
import pytest

import blockmesh
from blockmesh.catalogue import catalogue_names

CATALOGUE = catalogue_names()
SP = [(-1.0, -1.0), (1.0, -1.0), (2.0, 0.0), (0.0, 1.0), (-2.0, 0.0)]
USP = [(0.0, 0.0), (2.0, 0.0), (3.0, 1.0), (1.0, 3.0), (0.0, 2.0)]
#: Two pentagons sharing the edge (1, 2).
TWO_VERTICES = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)]
TWO_BLOCKS = [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)]


@pytest.fixture(scope="session")
def catalogue() -> dict[str, blockmesh.Domain]:
    return {name: blockmesh.load_domain(name) for name in CATALOGUE}


@pytest.fixture(params=CATALOGUE)
def catalogue_domain(request, catalogue) -> blockmesh.Domain:
    return catalogue[request.param]


@pytest.fixture
def sp_points() -> np.ndarray:
    return np.array(SP)
