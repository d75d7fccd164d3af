"""The quality of a mesh's cells: angles, aspect ratios and areas in one record.

:class:`MeshQuality` is what :meth:`Mesh.quality <blockmesh.mesh.Mesh.quality>` and
:meth:`PolygonMesh.quality <blockmesh.mesh.polygons.PolygonMesh.quality>` return.

Examples
--------
>>> q = MeshQuality.of(min_angle=60.0, max_angle=120.0, max_aspect_ratio=1.5, min_area=1.0,
...                    max_area=4.0, not_strictly_convex=0)
>>> q.area_ratio
0.25
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

__all__ = ["MeshQuality"]

#: What a :class:`MeshQuality` is made of: its fields but the area ratio, which it finds.
_MEASURED = (
    "min_angle",
    "max_angle",
    "max_aspect_ratio",
    "min_area",
    "max_area",
    "not_strictly_convex",
)


@dataclass(frozen=True)
class MeshQuality:
    """Shape measures of a mesh's cells (angles in degrees).

    ``max_aspect_ratio`` is the largest diameter**2 / area over the cells (a regular pentagon has
    1.52); ``area_ratio`` is the smallest cell area over the largest.
    """

    min_angle: float
    max_angle: float
    max_aspect_ratio: float
    min_area: float
    max_area: float
    area_ratio: float
    not_strictly_convex: int

    @classmethod
    def of(
        cls,
        *,
        min_angle: float,
        max_angle: float,
        max_aspect_ratio: float,
        min_area: float,
        max_area: float,
        not_strictly_convex: int,
    ) -> MeshQuality:
        """The quality of measured cells, their ``area_ratio`` found (0 when none has area)."""
        ratio = min_area / max_area if max_area > 0 else 0.0
        return cls(
            min_angle, max_angle, max_aspect_ratio, min_area, max_area, ratio, not_strictly_convex
        )

    @classmethod
    def from_measures(cls, measures: Mapping[str, Any]) -> MeshQuality:
        """The quality of measured cells from a mapping holding the arguments of :meth:`of`."""
        return cls.of(**{name: measures[name] for name in _MEASURED})

    def as_dict(self) -> dict[str, float | int]:
        """Plain dictionary (JSON-ready)."""
        return {
            "min_angle": self.min_angle,
            "max_angle": self.max_angle,
            "max_aspect_ratio": self.max_aspect_ratio,
            "min_area": self.min_area,
            "max_area": self.max_area,
            "area_ratio": self.area_ratio,
            "not_strictly_convex": self.not_strictly_convex,
        }
