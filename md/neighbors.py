"""Neighbour lists for sphere packs: cell lists plus a Verlet skin.

A pair of spheres ``(i, j)`` is listed when its surface gap
:math:`g_{ij} = |\\mathbf d_{ij}| - (r_i + r_j)` is below the skin (strictly), with
:math:`\\mathbf d_{ij}` the minimum-image displacement (periodic in x and y, not in z). A list
built with skin :math:`s` holds every pair in contact (:math:`g < 0`) until some particle has
moved more than :math:`s/2` since the build, because a gap shrinks by at most the sum of the two
displacements; :func:`needs_rebuild` tests exactly that.

Layout: pairs are an int32 array of shape (M, 2), one row ``(i, j)`` per pair with ``i < j``,
rows sorted lexicographically. The search is a cell list (cells at least ``2 max(r) + skin``
wide) in numba kernels (:mod:`md._kernels_neighbors`); :func:`brute_force_pairs` is the plain
numpy twin the tests compare it with. Units are SI (m). Radii are assumed fixed between builds:
rebuild after changing them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from . import _kernels_neighbors as _k
from .space import Box, _check_box

__all__ = ["NeighborList", "brute_force_pairs", "build_neighbors", "needs_rebuild"]

# Cells per particle at most: a dilute gas in a tall box gets larger cells, not a huge empty grid.
_MAX_CELLS_PER_PARTICLE = 4
# Initial pair buffer per particle (a dense pack with a small skin has ~3-6 pairs per particle);
# an overflow costs one retry with the exact size.
_PAIRS_PER_PARTICLE = 8


@dataclass(frozen=True, eq=False)
class NeighborList:
    """A neighbour list and what is needed to decide when it is stale.

    Attributes
    ----------
    pairs : numpy.ndarray, int32, shape (M, 2)
        Rows ``(i, j)``, ``i < j``, in lexicographic order; read-only.
    reference_positions : numpy.ndarray, float64, shape (N, 3)
        Copy of the positions at build time, m; read-only.
    skin : float
        Gap threshold used at build time, m.
    box : Box
        Box at build time (its periods define the minimum image of the pairs).
    """

    pairs: np.ndarray
    reference_positions: np.ndarray
    skin: float
    box: Box

    @property
    def n_pairs(self) -> int:
        """Number of pairs M."""
        return self.pairs.shape[0]


def _as_positions(x) -> np.ndarray:
    arr = np.asarray(x, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError(f"x must have shape (N, 3), got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError("x must be finite (positions contain NaN or inf)")
    if arr.shape[0] >= 2**31 - 1:
        raise ValueError(f"x holds {arr.shape[0]} particles; int32 pair indices allow < 2**31 - 1")
    return np.ascontiguousarray(arr)


def _check_inputs(x, r, box, skin):
    """Validate and convert the common inputs; return ``x, r, box, skin``."""
    box = _check_box(box)
    x = _as_positions(x)
    r = np.ascontiguousarray(np.asarray(r, dtype=float))
    if r.shape != (x.shape[0],):
        raise ValueError(f"r must have shape (N,) = ({x.shape[0]},) to match x, got {r.shape}")
    if not np.all(np.isfinite(r)) or np.any(r <= 0.0):
        raise ValueError("r must be finite and > 0 m")
    try:
        skin = float(skin)
    except (TypeError, ValueError):
        raise ValueError(f"skin must be a real number, got {skin!r}") from None
    if not (math.isfinite(skin) and skin >= 0.0):
        raise ValueError(f"skin must be finite and >= 0 m, got {skin!r}")
    if r.size:
        largest = 4.0 * float(r.max())
        if box.lx <= largest or box.ly <= largest:
            raise ValueError(f"box periods lx = {box.lx:g} m and ly = {box.ly:g} m must exceed "
                             f"twice the largest diameter, {largest:g} m")
    return x, r, box, skin


def _cell_grid(box: Box, z_low: float, z_high: float, cutoff: float, n_particles: int):
    """Grid ``(nx, ny, nz), (sx, sy, sz)`` with cells >= ``cutoff``, at most ~4 cells/particle.

    The periodic sizes divide the periods exactly; z spans the particles, ``[z_low, z_high]``.
    """
    # A margin of 1e-9 keeps every cell >= cutoff despite rounding in the sizes and indices.
    cutoff *= 1.0 + 1e-9
    height = max(z_high - z_low, 0.0)
    max_cells = max(27, _MAX_CELLS_PER_PARTICLE * n_particles)
    # Start from the cell size that would give max_cells cells, if larger than the cutoff.
    volume = box.lx * box.ly * max(height, cutoff)
    cell = max(cutoff, (volume / max_cells) ** (1.0 / 3.0))
    while True:
        shape = tuple(max(1, int(length // cell)) for length in (box.lx, box.ly, height))
        if shape[0] * shape[1] * shape[2] <= max_cells:
            break
        cell *= 1.25
    size = (box.lx / shape[0], box.ly / shape[1], max(height / shape[2], cell))
    return shape, size


def build_neighbors(x, r, box: Box, skin, *, capacity=None) -> NeighborList:
    """Build the neighbour list of a sphere pack with a cell list.

    Parameters
    ----------
    x : array_like, shape (N, 3)
        Positions, m; finite, need not be wrapped into the box.
    r : array_like, shape (N,)
        Radii, m; finite, > 0.
    box : Box
        Periodic in x and y; its periods must exceed twice the largest diameter. The z walls
        play no part (the grid in z spans the particles).
    skin : float
        Gap threshold, m, >= 0: pairs with surface gap < ``skin`` are listed (``skin = 0``
        lists overlapping pairs only).
    capacity : int, optional, keyword-only
        Initial size of the pair buffer (default ``8 N``). Too small costs one rebuild with the
        exact size, never a lost pair.

    Returns
    -------
    NeighborList
        ``pairs`` int32 (M, 2), rows ``(i, j)``, ``i < j``, lexicographic; a copy of ``x``;
        ``skin``; ``box``.

    Raises
    ------
    ValueError
        Naming ``x``, ``r``, ``skin``, ``box`` or ``capacity``.
    TypeError
        If ``box`` is not a :class:`~md.space.Box`.

    Examples
    --------
    >>> box = Box(1e-2, 1e-2, 0.0, 1e-2)
    >>> x = [[0.0, 0.0, 0.0], [9.9e-3, 0.0, 0.0], [5e-3, 5e-3, 5e-3]]
    >>> build_neighbors(x, [1e-4, 1e-4, 1e-4], box, 1e-5).pairs.tolist()
    [[0, 1]]
    """
    x, r, box, skin = _check_inputs(x, r, box, skin)
    n = x.shape[0]
    if capacity is None:
        capacity = _PAIRS_PER_PARTICLE * n
    elif isinstance(capacity, bool) or not isinstance(capacity, (int, np.integer)) or capacity < 0:
        raise ValueError(f"capacity must be an integer >= 0, got {capacity!r}")
    capacity = int(capacity)
    if n:
        z_low, z_high = float(x[:, 2].min()), float(x[:, 2].max())
        cutoff = 2.0 * float(r.max()) + skin
    else:
        z_low = z_high = 0.0
        cutoff = 1.0
    shape, size = _cell_grid(box, z_low, z_high, cutoff, n)
    cell_of, cell_start, cell_order = _k.cell_list(x, box.lx, box.ly, z_low, shape, size)
    while True:
        pairs = np.empty((capacity, 2), dtype=np.int32)
        count = _k.neighbor_pairs(x, r, box.lx, box.ly, skin, shape, cell_of, cell_start,
                                  cell_order, pairs)
        if count <= capacity:
            break
        capacity = count  # overflow: the kernel counted every pair, retry with room for all
    pairs = pairs[:count].copy()
    pairs.flags.writeable = False
    reference = x.copy()
    reference.flags.writeable = False
    return NeighborList(pairs=pairs, reference_positions=reference, skin=skin, box=box)


def needs_rebuild(nl: NeighborList, x, box: Box) -> bool:
    """Whether a neighbour list may have missed a contact and must be rebuilt.

    True when any particle has moved more than ``nl.skin / 2`` (minimum image in x, y) since
    the build, when a position is not finite, or when the periods of ``box`` differ from those
    at build time. Displacements are assumed smaller than half a period.

    Parameters
    ----------
    nl : NeighborList
    x : array_like, shape (N, 3)
        Current positions, m (N as at build time).
    box : Box

    Returns
    -------
    bool

    Examples
    --------
    >>> box = Box(1e-2, 1e-2, 0.0, 1e-2)
    >>> nl = build_neighbors([[1e-3, 1e-3, 1e-3]], [1e-4], box, 2e-5)
    >>> needs_rebuild(nl, [[1e-3 + 0.9e-5, 1e-3, 1e-3]], box)
    False
    >>> needs_rebuild(nl, [[1e-3 + 1.1e-5, 1e-3, 1e-3]], box)
    True
    """
    if not isinstance(nl, NeighborList):
        raise TypeError(f"nl must be an md.neighbors.NeighborList, got {type(nl).__name__}")
    box = _check_box(box)
    x = np.ascontiguousarray(np.asarray(x, dtype=float))
    if x.shape != nl.reference_positions.shape:
        raise ValueError(f"x must have shape {nl.reference_positions.shape} as at build time, "
                         f"got {x.shape}")
    if box.lx != nl.box.lx or box.ly != nl.box.ly:
        return True
    return bool(_k.moved_beyond(x, nl.reference_positions, box.lx, box.ly, 0.5 * nl.skin))


def brute_force_pairs(x, r, box: Box, skin) -> np.ndarray:
    """All pairs with surface gap < ``skin`` by direct O(N²) comparison (plain numpy).

    The reference for :func:`build_neighbors`: same inputs, same checks, same arithmetic
    (``|d|^2 < (r_i + r_j + skin)^2`` with the minimum image of :func:`md.space.minimum_image`).

    Returns
    -------
    numpy.ndarray, int32, shape (M, 2)
        Rows ``(i, j)``, ``i < j``, in lexicographic order.
    """
    x, r, box, skin = _check_inputs(x, r, box, skin)
    rows = []
    for i in range(x.shape[0] - 1):
        d = x[i + 1:] - x[i]
        for axis, length in ((0, box.lx), (1, box.ly)):
            d[:, axis] -= length * np.floor(d[:, axis] / length + 0.5)
        cut = r[i] + r[i + 1:] + skin
        j = np.flatnonzero(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2] < cut * cut)
        rows.append(np.column_stack([np.full(j.size, i), i + 1 + j]))
    if not rows:
        return np.empty((0, 2), dtype=np.int32)
    return np.concatenate(rows).astype(np.int32)
