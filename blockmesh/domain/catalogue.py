"""The catalogue of ready-made domains: the ``domains/*.toml`` files shipped inside the package.

Examples
--------
>>> "square-cut" in catalogue_names()
True
>>> catalogue_path("sp").name
'sp.toml'
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

__all__ = ["catalogue_names", "catalogue_path"]


def _folder() -> Path:
    return Path(str(resources.files("blockmesh.domains")))


def catalogue_names() -> list[str]:
    """Names of the catalogue domains, sorted."""
    return sorted(p.stem for p in _folder().glob("*.toml"))


def catalogue_path(name: str) -> Path:
    """Path of the catalogue file ``name.toml`` (which must exist)."""
    path = _folder() / f"{name}.toml"
    if not path.is_file():
        raise KeyError(name)
    return path
