"""The project's front door: the version in one place, the README's size, the changelog and the
pre-commit configuration."""

from __future__ import annotations

import importlib.metadata
import tomllib
from pathlib import Path

import pytest

import blockmesh
from blockmesh.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_the_version_is_written_once() -> None:
    """pyproject.toml reads the version from blockmesh.__version__ (and states none itself)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert "version" not in project["project"]
    assert "version" in project["project"]["dynamic"]
    assert project["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "blockmesh.__version__"}
    try:
        installed = importlib.metadata.version("blockmesh")
    except importlib.metadata.PackageNotFoundError:  # pragma: no cover - not installed
        pytest.skip("blockmesh is not installed (pip install -e .)")
    assert installed == blockmesh.__version__


def test_the_command_prints_the_version(capsys) -> None:
    with pytest.raises(SystemExit) as done:
        main(["--version"])
    assert done.value.code == 0
    assert capsys.readouterr().out.strip() == f"blockmesh {blockmesh.__version__}"


def test_the_readme_is_a_front_page() -> None:
    """At most 15 KB, with the quickstart CI checks and a link into the site."""
    readme = ROOT / "README.md"
    assert readme.stat().st_size <= 15 * 1024
    text = readme.read_text(encoding="utf-8")
    assert "\n## Quickstart\n" in text
    assert "](docs/getting-started.md)" in text


def test_the_changelog_starts_with_unreleased() -> None:
    text = (ROOT / "CHANGELOG.md").read_text(encoding="utf-8")
    versions = [line for line in text.splitlines() if line.startswith("## ")]
    assert versions[0] == "## Unreleased"
    assert any(line.startswith(f"## {blockmesh.__version__}") for line in versions)


def test_pre_commit_runs_the_checks_ci_runs() -> None:
    config = (ROOT / ".pre-commit-config.yaml").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    for check in ("ruff check", "ruff format --check", "mypy"):
        assert check in ci
        assert f"entry: {check}" in config
