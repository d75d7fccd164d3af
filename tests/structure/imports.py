"""The package's imports as data: every import of a blockmesh module, where and how it is made."""

from __future__ import annotations

import ast
from dataclasses import dataclass
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "blockmesh"


@dataclass(frozen=True)
class Import:
    """One imported blockmesh module (or name of one) in one module."""

    source: str  # the importing module
    target: str  # the imported module
    names: tuple[str, ...]  # the names taken from it (empty for ``import x``)
    line: int
    deferred: bool  # inside a function (made when the function runs)
    typing_only: bool  # under ``if TYPE_CHECKING:``


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    return {module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


def _walk(node: ast.AST, deferred: bool, typing_only: bool):
    for child in ast.iter_child_nodes(node):
        if isinstance(child, ast.Import | ast.ImportFrom):
            yield child, deferred, typing_only
        elif isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda):
            yield from _walk(child, True, typing_only)
        elif isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
            for part in child.body:
                yield from _walk(ast.Module(body=[part], type_ignores=[]), deferred, True)
            for part in child.orelse:
                yield from _walk(ast.Module(body=[part], type_ignores=[]), deferred, typing_only)
        else:
            yield from _walk(child, deferred, typing_only)


def imports() -> list[Import]:
    """Every import of a blockmesh module made by a module of the package."""
    known = modules()
    found = []
    for source, path in known.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        package = source if path.name == "__init__.py" else source.rpartition(".")[0]
        for node, deferred, typing_only in _walk(tree, False, False):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    if alias.name.split(".")[0] == "blockmesh":
                        found.append(
                            Import(source, alias.name, (), node.lineno, deferred, typing_only)
                        )
                continue
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if target.split(".")[0] != "blockmesh":
                continue
            plain = []
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in known:
                    found.append(Import(source, sub, (), node.lineno, deferred, typing_only))
                else:
                    plain.append(alias.name)
            if plain:
                found.append(
                    Import(source, target, tuple(plain), node.lineno, deferred, typing_only)
                )
    return found
