"""Simulation box: periodic in x and y, bounded by walls in z.

Units are SI (m). The box spans ``[0, lx) x [0, ly)`` laterally, with periodic images every
``lx`` and ``ly``; vertically it lies between the walls at ``lz_min`` and ``lz_max`` and has no
images. Displacements follow the minimum-image convention in x and y only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Box", "minimum_image", "wrap"]


@dataclass(frozen=True)
class Box:
    """A box periodic in x and y and bounded by walls in z.

    Parameters
    ----------
    lx, ly : float
        Periods in x and y, m; finite and > 0.
    lz_min, lz_max : float
        Heights of the lower and upper walls, m; finite, ``lz_max > lz_min``.

    Raises
    ------
    ValueError
        Naming the field that is not finite or not positive (``lz_max`` when the height
        ``lz_max - lz_min`` is not positive).

    Examples
    --------
    >>> Box(1e-2, 1e-2, 0.0, 2e-2).lz
    0.02
    """

    lx: float
    ly: float
    lz_min: float
    lz_max: float

    def __post_init__(self):
        for name in ("lx", "ly", "lz_min", "lz_max"):
            value = getattr(self, name)
            try:
                value = float(value)
            except (TypeError, ValueError):
                raise ValueError(f"{name} must be a real number, got {value!r}") from None
            if not math.isfinite(value):
                raise ValueError(f"{name} must be finite, got {value!r}")
            object.__setattr__(self, name, value)
        for name in ("lx", "ly"):
            if getattr(self, name) <= 0.0:
                raise ValueError(f"{name} must be > 0 m, got {getattr(self, name)!r}")
        if self.lz_max <= self.lz_min:
            raise ValueError(f"lz_max must be > lz_min (box height > 0 m), got lz_min="
                             f"{self.lz_min!r}, lz_max={self.lz_max!r}")

    @property
    def lz(self) -> float:
        """Height between the walls, m."""
        return self.lz_max - self.lz_min

    @property
    def volume(self) -> float:
        """Volume between the walls, m³."""
        return self.lx * self.ly * self.lz


def _check_box(box) -> Box:
    if not isinstance(box, Box):
        raise TypeError(f"box must be an md.space.Box, got {type(box).__name__}")
    return box


def _as_vectors(name: str, value) -> np.ndarray:
    arr = np.asarray(value, dtype=float)
    if arr.ndim == 0 or arr.shape[-1] != 3:
        raise ValueError(f"{name} must have shape (..., 3), got {arr.shape}")
    return arr


def minimum_image(d, box: Box) -> np.ndarray:
    """Minimum-image displacement vectors (x and y wrapped, z untouched).

    Parameters
    ----------
    d : array_like, shape (..., 3)
        Displacements, m (typically (N, 3)).
    box : Box

    Returns
    -------
    numpy.ndarray, shape (..., 3), float64
        A new array with each x component in ``[-lx/2, lx/2)`` (up to rounding) and each y
        component in ``[-ly/2, ly/2)``: ``d - L * floor(d / L + 1/2)``. The neighbour kernels use
        the same formula, so brute force and kernel agree on ties.

    Examples
    --------
    >>> box = Box(1.0, 2.0, 0.0, 1.0)
    >>> minimum_image([[0.9, -1.5, 3.0]], box)
    array([[-0.1,  0.5,  3. ]])
    """
    box = _check_box(box)
    out = np.array(_as_vectors("d", d), dtype=float, copy=True)
    for axis, length in ((0, box.lx), (1, box.ly)):
        out[..., axis] -= length * np.floor(out[..., axis] / length + 0.5)
    return out


def wrap(x, box: Box) -> np.ndarray:
    """Positions folded into the periodic cell ``[0, lx) x [0, ly)``; z is untouched.

    Parameters
    ----------
    x : array_like, shape (..., 3)
        Positions, m.
    box : Box

    Returns
    -------
    numpy.ndarray, shape (..., 3), float64
        A new array; x and y components strictly inside ``[0, L)`` (a value that rounds to
        ``L``, e.g. ``-1e-300 mod L``, is mapped to 0).

    Examples
    --------
    >>> wrap([[1.25, -0.5, 7.0]], Box(1.0, 2.0, 0.0, 1.0))
    array([[0.25, 1.5 , 7.  ]])
    """
    box = _check_box(box)
    out = np.array(_as_vectors("x", x), dtype=float, copy=True)
    for axis, length in ((0, box.lx), (1, box.ly)):
        folded = np.mod(out[..., axis], length)
        folded[folded >= length] = 0.0
        out[..., axis] = folded
    return out
