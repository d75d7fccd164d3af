"""Closed-form reference solutions the solvers are measured against.

:func:`kirsch` is the classical plate-with-a-hole problem of elasticity (Kirsch 1898): an
infinite plate under uniaxial tension ``T`` along x with a traction-free circular hole of radius
``a`` at the origin. Its stress ``σ_xx`` reaches ``3 T`` at the top of the hole, ``(0, a)`` — the
stress concentration factor 3. On a finite domain (the catalogue's ``quarter-plate-hole`` and
``plate-hole``), prescribing the exact stress as traction on the outer sides makes the field
exact there too, so errors and the stress concentration can be checked against exact values.

Examples
--------
>>> from blockmesh.vem.reference import kirsch
>>> k = kirsch(radius=0.5, young=1.0, poisson=0.3)
>>> float(k.stress[0](0.0, 0.5))  # σ_xx at the top of the hole: 3 T
3.0
>>> round(float(k.stress[0](1e3, 0.0)), 4), round(float(k.stress[1](0.0, 1e3)), 4)  # far: T, 0
(1.0, 0.0)
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from blockmesh.checks import choice
from blockmesh.errors import ArgumentError

__all__ = ["KirschSolution", "kirsch"]

Function = Callable[[np.ndarray, np.ndarray], np.ndarray]


class KirschSolution(NamedTuple):
    """The Kirsch field as functions of ``(x, y)`` (numpy arrays in, arrays out)."""

    #: ``(u_x, u_y)``, the displacement (zero ``u_x`` on x = 0 and ``u_y`` on y = 0).
    displacement: tuple[Function, Function]
    #: ``(σ_xx, σ_yy, σ_xy)``, the stress.
    stress: tuple[Function, Function, Function]
    #: The stress concentration ``σ_xx(0, a) = 3 T``.
    peak: float


def kirsch(
    radius: float,
    young: float,
    poisson: float,
    plane: str = "stress",
    tension: float = 1.0,
) -> KirschSolution:
    """The exact field of an infinite plate with a circular hole under uniaxial tension along x.

    Parameters
    ----------
    radius : float
        The hole's radius ``a`` (> 0), centred at the origin.
    young, poisson : float
        Young's modulus (> 0) and Poisson's ratio (in (−1, 0.5)).
    plane : {"stress", "strain"}
        The plane model; it sets ``κ = (3 − ν)/(1 + ν)`` (stress) or ``3 − 4ν`` (strain) in the
        displacement. The stress does not depend on the material.
    tension : float
        The remote stress ``T``.

    Returns
    -------
    KirschSolution
        The displacement and stress functions and the peak stress ``3 T``.

    Notes
    -----
    With ``q = a²/r²`` and polar angle θ (Timoshenko & Goodier, §35, in Cartesian components),
    ``σ_xx = T(1 − q(3/2 cos 2θ + cos 4θ) + 3/2 q² cos 4θ)``,
    ``σ_yy = T(−q(1/2 cos 2θ − cos 4θ) − 3/2 q² cos 4θ)``,
    ``σ_xy = T(−q(1/2 sin 2θ + sin 4θ) + 3/2 q² sin 4θ)`` and, with ``μ = E / (2(1 + ν))``,
    ``u_x = T a/(8μ) (r/a (κ + 1) cos θ + 2a/r ((1 + κ) cos θ + cos 3θ) − 2a³/r³ cos 3θ)``,
    ``u_y = T a/(8μ) (r/a (κ − 3) sin θ + 2a/r ((1 − κ) sin θ + sin 3θ) − 2a³/r³ sin 3θ)``.
    """
    if not radius > 0 or not young > 0 or not -1 < poisson < 0.5:
        raise ArgumentError(
            f"kirsch needs radius > 0, young > 0 and poisson in (-1, 0.5); got radius {radius}, "
            f"young {young}, poisson {poisson}"
        )
    choice(plane, ("stress", "strain"), "plane")
    a, t = float(radius), float(tension)
    kappa = (3 - poisson) / (1 + poisson) if plane == "stress" else 3 - 4 * poisson
    scale = t * a * (1 + poisson) / (4 * young)  # T a / (8 μ)

    def polar(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        r = np.hypot(x, y)
        return r, np.arctan2(y, x), a * a / (r * r)

    def sxx(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        _, th, q = polar(x, y)
        return t * (1 - q * (1.5 * np.cos(2 * th) + np.cos(4 * th)) + 1.5 * q * q * np.cos(4 * th))

    def syy(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        _, th, q = polar(x, y)
        return t * (-q * (0.5 * np.cos(2 * th) - np.cos(4 * th)) - 1.5 * q * q * np.cos(4 * th))

    def sxy(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        _, th, q = polar(x, y)
        return t * (-q * (0.5 * np.sin(2 * th) + np.sin(4 * th)) + 1.5 * q * q * np.sin(4 * th))

    def ux(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        r, th, q = polar(x, y)
        near = (1 + kappa) * np.cos(th) + np.cos(3 * th)
        return scale * (
            r / a * (kappa + 1) * np.cos(th) + 2 * a / r * near - 2 * a * q / r * np.cos(3 * th)
        )

    def uy(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        r, th, q = polar(x, y)
        near = (1 - kappa) * np.sin(th) + np.sin(3 * th)
        return scale * (
            r / a * (kappa - 3) * np.sin(th) + 2 * a / r * near - 2 * a * q / r * np.sin(3 * th)
        )

    return KirschSolution((ux, uy), (sxx, syy, sxy), 3 * t)
