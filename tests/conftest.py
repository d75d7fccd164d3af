"""Shared fixtures (the catalogue, paper pentagons, small block layouts) and test profiles.

Hypothesis runs under one of two profiles, registered here: ``default`` (a tenth of the
examples: the everyday ``python -m pytest``) and ``ci`` (the full counts, which CI runs with the
slow tests). Choose one with ``HYPOTHESIS_PROFILE=ci`` or ``--hypothesis-profile ci`` (the
option wins). A property that wants another count than the profile's asks for it in ``ci``
terms, ``@settings(max_examples=examples(600))``, and gets it scaled (:func:`helpers.examples`).

Tests marked ``slow`` are left out unless asked for (``-m slow``, or ``-m ""`` for everything):
``pyproject.toml`` passes ``-m "not slow"`` by default.
"""

from __future__ import annotations

import os

import numpy as np
import pytest
from helpers import CATALOGUE, CI_EXAMPLES, SP
from hypothesis import settings

import blockmesh

# No deadline in either profile: a loaded machine makes examples slow, and timing is not what the
# properties test.
settings.register_profile("default", max_examples=CI_EXAMPLES // 10, deadline=None)
settings.register_profile("ci", max_examples=CI_EXAMPLES, deadline=None)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "default"))


@pytest.fixture(scope="session")
def catalogue() -> dict[str, blockmesh.Domain]:
    return {name: blockmesh.load_domain(name) for name in CATALOGUE}


@pytest.fixture(params=CATALOGUE)
def catalogue_domain(request, catalogue) -> blockmesh.Domain:
    return catalogue[request.param]


@pytest.fixture
def sp_points() -> np.ndarray:
    return np.array(SP)


def pytest_report_header(config: pytest.Config) -> str:
    """Which hypothesis profile runs, and its examples per property."""
    name = getattr(settings, "get_current_profile_name", lambda: "?")()
    return (
        f"hypothesis profile {name!r}: {settings.default.max_examples} examples per property "
        f"(full counts: HYPOTHESIS_PROFILE=ci)"
    )
