"""Builders and harnesses shared by the tests (import them: ``from helpers import ...``)."""

from __future__ import annotations

import pytest

from blockmesh.catalogue import catalogue_names, catalogue_path
from blockmesh.cli import main

#: The catalogue domains with curved edges (their refined cells approach the curves, so the
#: straight-edged invariants, area preserved and nodes on the block edges, do not apply to them).
CURVED_CATALOGUE = [n for n in catalogue_names() if "[[edges]]" in catalogue_path(n).read_text()]
#: Every straight-edged catalogue domain name.
CATALOGUE = [n for n in catalogue_names() if n not in CURVED_CATALOGUE]
#: The paper's symmetric and unsymmetrical pentagons.
SP = [(-1.0, -1.0), (1.0, -1.0), (2.0, 0.0), (0.0, 1.0), (-2.0, 0.0)]
USP = [(0.0, 0.0), (2.0, 0.0), (3.0, 1.0), (1.0, 3.0), (0.0, 2.0)]
#: Two pentagons sharing the edge (1, 2).
TWO_VERTICES = [(0, 0), (2, 0), (2.5, 1), (2, 2), (0, 2), (4, 0), (4.5, 1), (4, 2)]
TWO_BLOCKS = [(0, 1, 2, 3, 4), (1, 5, 6, 7, 2)]


def run_cli(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    """Run ``blockmesh ARGV...`` through :func:`blockmesh.cli.main`: (exit code, stdout, stderr)."""
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err
