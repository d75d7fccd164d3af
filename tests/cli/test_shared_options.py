"""Options several commands share: defined once, the same on every command, renamed ones noted."""

from __future__ import annotations

import argparse
import json
import re
from pathlib import Path

import pytest

from blockmesh.cli import build_parser, main
from blockmesh.commands import SUMMARIES, Group, load, options

COMMANDS = Path(options.__file__).parent

#: The shared options and the attribute each stores.
SHARED = {
    "--level": "level",
    "--smooth": "smooth",
    "--placement": "quality_rule",
    "--max-memory": "max_memory",
    "--plot": "plot",
    "--json": "json",
}


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _option(parser: argparse.ArgumentParser, name: str) -> argparse.Action | None:
    return next((a for a in parser._actions if name in a.option_strings), None)


def test_the_shared_options_are_spelled_only_in_the_options_module() -> None:
    """No command module defines a shared option itself (one definition, one meaning)."""
    for path in sorted(COMMANDS.rglob("*.py")):
        if path.name == "options.py":
            continue
        text = path.read_text(encoding="utf-8")
        for name in SHARED:
            defined = re.search(rf'(add_argument|Option)\(\s*"{name}"', text)
            assert defined is None, f"{path.name} defines {name} itself: use commands/options.py"


@pytest.mark.parametrize("name", list(SUMMARIES))
def test_a_command_parser_has_exactly_its_declared_options(name: str) -> None:
    """``register`` adds the module's ``OPTIONS`` (groups included), in order, and nothing else."""
    module = load(name)
    declared: list[tuple[str | None, tuple[str, ...]]] = []
    for item in module.OPTIONS:
        if isinstance(item, Group):
            declared += [(item.title, option.flags) for option in item.options]
        else:
            declared.append((None, item.flags))
    parser = _subparsers()[name]
    groups = {id(a): g.title for g in parser._action_groups[2:] for a in g._group_actions}
    added = [
        (groups.get(id(a)), tuple(a.option_strings) or (a.dest,))
        for a in parser._actions
        if not isinstance(a, argparse._HelpAction)
    ]
    assert added == declared


def test_a_shared_option_is_the_same_option_on_every_command() -> None:
    """Same option strings, destination, type and choices wherever a command takes it."""
    seen: dict[str, dict[str, object]] = {}
    for command, parser in _subparsers().items():
        for name, dest in SHARED.items():
            action = _option(parser, name)
            if action is None:
                continue
            shape = {
                "strings": tuple(action.option_strings),
                "dest": action.dest,
                "type": action.type,
                "choices": action.choices,
                "nargs": action.nargs,
            }
            assert action.dest == dest, (command, name)
            assert seen.setdefault(name, shape) == shape, (command, name)
    assert set(seen) == set(SHARED), "every shared option is used by some command"


def test_every_command_that_reports_takes_json() -> None:
    for command, parser in _subparsers().items():
        if command != "show":  # show draws a picture and prints nothing else
            assert _option(parser, "--json") is not None, command


@pytest.mark.parametrize(
    ("earlier", "current", "argv"),
    [
        (
            "--quality-rule",
            "--placement",
            ["mesh", "square", "-l", "1", "--quality-rule", "angles"],
        ),
        ("--exact", "--exact-integral", ["integrate", "sp", "-f", "x*y", "-l", "1", "--exact"]),
        (
            "--exact",
            "--exact-solution",
            ["solve", "square", "-l", "1", "--dirichlet", "*=x", "--exact", "x"],
        ),
    ],
)
def test_an_earlier_spelling_works_and_names_the_current_one(
    earlier: str, current: str, argv: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    assert main([*argv, "--json"]) == 0
    first = capsys.readouterr()
    notes = [line for line in first.err.splitlines() if "note:" in line]
    assert len(notes) == 1 and earlier in notes[0] and current in notes[0]
    renamed = [current if word == earlier else word for word in argv]
    assert main([*renamed, "--json"]) == 0
    second = capsys.readouterr()
    assert "note:" not in second.err
    assert _same_report(first.out, second.out)


def _same_report(first: str, second: str) -> bool:
    """The two JSON reports agree apart from timings."""
    a, b = json.loads(first), json.loads(second)
    timing = re.compile(r"seconds|time|bytes|memory|residual")
    return {k: v for k, v in a.items() if not timing.search(k)} == {
        k: v for k, v in b.items() if not timing.search(k)
    }


def test_tables_json_gives_every_entry_the_text_gives(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["tables", "--table", "1,7", "--levels", "1,2", "--pentagon", "SP", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["entries"] == sum(len(t["orders"]) * len(t["levels"]) for t in report["tables"])
    assert [t["table"] for t in report["tables"]] == [1, 7]
    for table in report["tables"]:
        values, errors = table["values"], table["errors"]
        assert len(values) == len(table["orders"]) == len(errors)
        assert all(len(row) == len(table["levels"]) for row in values)
    assert main(["tables", "--table", "1", "--levels", "1", "--pentagon", "SP"]) == 0
    text = capsys.readouterr().out
    values_block = text.split("|value - reference|")[0]
    printed = [
        float(line.split()[1])
        for line in values_block.splitlines()
        if re.match(r"\s+\d+\s+\S", line)
    ]
    json_column = [row[0] for row in report["tables"][0]["values"]]
    assert printed == pytest.approx(json_column, rel=1e-15)
