"""Shared fixtures: the catalogue, paper pentagons, small block layouts."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import CATALOGUE, SP

import blockmesh


@pytest.fixture(scope="session")
def catalogue() -> dict[str, blockmesh.Domain]:
    return {name: blockmesh.load_domain(name) for name in CATALOGUE}


@pytest.fixture(params=CATALOGUE)
def catalogue_domain(request, catalogue) -> blockmesh.Domain:
    return catalogue[request.param]


@pytest.fixture
def sp_points() -> np.ndarray:
    return np.array(SP)
