"""The benchmark pages: ``benchmarks/_page.py`` writes each script's tables to a docs page."""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT / "benchmarks"


@pytest.fixture(scope="module")
def page_module():
    spec = importlib.util.spec_from_file_location("_page", BENCHMARKS / "_page.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _args(page_module, *argv: str) -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    page_module.add_arguments(parser)
    return parser.parse_args(list(argv))


def test_a_table_is_a_markdown_table(page_module, capsys) -> None:
    table = page_module.Table("Speed", ["domain", "time"])
    table.row("sp", "1.5 ms")
    table.row("a|b", 2)
    table.note("Best of 3.")
    assert table.markdown().splitlines() == [
        "## Speed",
        "",
        "| domain | time |",
        "| --- | --- |",
        "| sp | 1.5 ms |",
        "| a\\|b | 2 |",
        "",
        "Best of 3.",
    ]
    printed = capsys.readouterr().out
    assert "Speed" in printed and "sp  1.5 ms" in printed  # shown on the terminal as measured
    with pytest.raises(ValueError, match="3 cells for 2 columns"):
        table.row(1, 2, 3)


def test_the_page_says_when_where_and_how(page_module, tmp_path, monkeypatch) -> None:
    monkeypatch.setattr(sys, "argv", [str(BENCHMARKS / "bench_x.py"), "--repeat", "2"])
    page = page_module.Page("x", "A benchmark", "What it measures.")
    page.table("Results", ["n", "time"]).row(1, "2 s")
    page.text("A closing remark.")
    path = page.write(_args(page_module, "--page-dir", str(tmp_path)))
    assert path == tmp_path / "x.md"
    text = path.read_text(encoding="utf-8")
    lines = text.splitlines()
    assert lines[0] == "# A benchmark"
    assert "Written by `python benchmarks/bench_x.py --repeat 2` on " in text
    assert " UTC; blockmesh " in text and "*Machine: " in text and " cores, " in text
    assert " at the end.*" in text  # how busy the machine was
    assert text.index("What it measures.") < text.index("## Results") < text.index("A closing")
    assert "| 1 | 2 s |" in lines
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.md"]  # no temporary left


def test_no_page_writes_nothing(page_module, tmp_path) -> None:
    page = page_module.Page("x", "A benchmark")
    assert page.write(_args(page_module, "--page-dir", str(tmp_path), "--no-page")) is None
    assert list(tmp_path.iterdir()) == []


def test_a_failed_write_keeps_the_old_page(page_module, tmp_path, monkeypatch) -> None:
    (tmp_path / "x.md").write_text("the last measurement\n")

    def broken(source, target):
        raise OSError("disk full")

    monkeypatch.setattr(os, "replace", broken)
    page = page_module.Page("x", "A benchmark")
    with pytest.raises(OSError, match="disk full"):
        page.write(_args(page_module, "--page-dir", str(tmp_path)))
    assert (tmp_path / "x.md").read_text() == "the last measurement\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.md"]


@pytest.mark.parametrize("script", sorted(BENCHMARKS.glob("bench_*.py")), ids=lambda p: p.stem)
def test_every_benchmark_writes_its_page(script: Path) -> None:
    """Each script takes the page options and writes its page (a re-measurement regenerates it)."""
    source = script.read_text(encoding="utf-8")
    assert "from _page import Page, add_arguments" in source
    assert "add_arguments(parser)" in source
    assert ".write(args)" in source


def test_the_index_links_every_page() -> None:
    """Every benchmark page is linked from docs/benchmarks/index.md."""
    folder = ROOT / "docs" / "benchmarks"
    index = (folder / "index.md").read_text(encoding="utf-8")
    for page in folder.glob("*.md"):
        if page.name != "index.md":
            assert f"]({page.name})" in index or ":glob:" in index, page.name
