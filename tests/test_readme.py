"""The README's examples, run verbatim in a fresh folder (issue 11; the machinery, shared with the
documentation pages, is in ``helpers_docs``)."""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers_docs import README, Example, examples, params, run_example


@pytest.mark.parametrize("example", params([README]))
def test_readme_example_runs(
    example: Example,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capfd: pytest.CaptureFixture[str],
) -> None:
    run_example(example, tmp_path, monkeypatch, capfd)


def test_readme_examples_are_found() -> None:
    """The quickstart's command and the Python example are collected (none silently lost)."""
    found = examples(README)
    text = README.read_text(encoding="utf-8")
    texts = [e.text for e in found]
    assert "blockmesh mesh square-cut --level 3 -o square-cut.vtu --plot square-cut.png" in texts
    assert sum(e.kind == "python" for e in found) == text.count("```python") >= 1
    assert sum(e.kind == "console" for e in found) == text.count("```console")
