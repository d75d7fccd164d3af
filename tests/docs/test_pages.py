"""The examples of every documentation page (``docs/**/*.md``), run verbatim in a fresh folder.

The machinery, shared with the README's test, is in ``helpers_docs``: every console, Python and
shell block and every ``blockmesh ...`` command quoted in the text runs as a reader would type it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from helpers_docs import (
    DOCS,
    NEEDS,
    README,
    SETUP,
    SKIP,
    SLOW,
    Example,
    doc_pages,
    examples,
    params,
    run_example,
)

PAGES = doc_pages()


@pytest.mark.parametrize("example", params(PAGES))
def test_page_example_runs(
    example: Example,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capfd: pytest.CaptureFixture[str],
) -> None:
    run_example(example, tmp_path, monkeypatch, capfd)


def test_every_kind_of_example_is_found() -> None:
    """The extraction itself: the pages' examples are all collected (none silently lost)."""
    found = [e for path in PAGES for e in examples(path)]
    assert {e.kind for e in found} == {"console", "command", "python", "sh"}
    for path in PAGES:
        text = path.read_text(encoding="utf-8")
        mine = examples(path)
        assert sum(e.kind == "console" for e in mine) == text.count("```console"), path
        assert sum(e.kind == "python" for e in mine) == text.count("```python"), path
    texts = [e.text for e in found]
    assert "blockmesh show l-shape" in texts
    assert "blockmesh mesh star --level 3 --placement angles" in texts
    every = texts + [e.text for e in examples(README)]
    for key in [*SKIP, *SETUP, *SLOW, *NEEDS]:
        assert any(key in t for t in every), f"{key!r} matches no example any more"


def test_the_pages_are_the_site() -> None:
    """The pages searched are the site's own: the index and the task pages, no built page."""
    names = {path.relative_to(DOCS).as_posix() for path in PAGES}
    tasks = {
        "index.md",
        "getting-started.md",
        "domains.md",
        "composite.md",
        "curves.md",
        "decomposition.md",
        "refinement.md",
        "export.md",
        "integration.md",
        "solving.md",
        "scaling.md",
        "reliability.md",
        "mathematics.md",
        "benchmarks/index.md",
    }
    assert tasks <= names
    assert not any(name.startswith(("_build/", "generated/", "auto_gallery/")) for name in names)
