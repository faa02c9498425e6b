"""Private numba kernels of the neighbour search (cell list → pair list).

Conventions shared by every kernel here (the public wrappers in :mod:`md.neighbors` check them):

* ``x`` float64 (N, 3) C-contiguous positions, m; ``r`` float64 (N,) radii, m.
* x and y are periodic with periods ``lx``, ``ly``; positions need not be wrapped. z is not
  periodic; the grid in z starts at ``z0`` (the lowest particle) and particles beyond the last
  cell are put in it.
* The grid is ``shape = (nx, ny, nz)`` cells of size ``size = (sx, sy, sz)`` with every size at
  least the interaction cutoff, and the periodic sizes dividing the period exactly
  (``sx = lx / nx``). Cell ``(ix, iy, iz)`` has the flat index ``ix + nx * (iy + ny * iz)``, so
  cells adjacent in x are adjacent in memory.
* With fewer than 3 cells along a periodic direction the offsets -1, 0, +1 would visit one cell
  twice; the kernels then visit each of the 1 or 2 cells once.
* A pair ``(i, j)``, ``i < j`` (original indices), is a neighbour pair when its surface gap
  ``|d_ij| - (r_i + r_j)`` is below ``skin`` (strictly), ``d_ij`` the minimum-image displacement
  ``d - L * floor(d / L + 1/2)`` in x and y. The test is done on squares,
  ``|d|^2 < (r_i + r_j + skin)^2``, the same arithmetic as the brute-force twin.

Output layout: a pair array ``pairs`` (M, 2) int32, one row ``(i, j)`` per pair, ``i < j``, rows
in lexicographic order (by ``i``, then ``j``), independent of the cell layout. The caller
preallocates ``pairs``; the kernel writes the first ``min(M, capacity)`` rows and returns the
true count ``M``, so ``M > capacity`` is the overflow flag and tells the wrapper exactly how big a
buffer to retry with. No neighbour is ever dropped silently.

Memory access: the cell list is a counting sort (CSR: ``cell_start`` (n_cells + 1,) and
``cell_order`` (N,), particle indices grouped by cell, ascending within a cell). The pair kernel
first gathers positions and radii into cell-sorted copies, so the innermost loop over the
particles of one neighbour cell streams through contiguous memory; the outer loop runs over
particles in their original order (sequential reads, output already sorted by ``i``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["cell_list", "moved_beyond", "neighbor_pairs"]


@njit(cache=True)
def _periodic_cell(coord, length, cell_size, n_cells):
    """Cell index of ``coord`` along a periodic axis (any real coordinate)."""
    s = coord - length * np.floor(coord / length)
    k = int(s / cell_size)
    if k >= n_cells:  # s == length after rounding, or s / cell_size rounding up
        k = n_cells - 1
    elif k < 0:
        k = 0
    return k


@njit(cache=True)
def _bounded_cell(coord, origin, cell_size, n_cells):
    """Cell index along the bounded z axis, clamped to the grid."""
    f = np.floor((coord - origin) / cell_size)
    if f >= n_cells:  # compare as floats: no integer overflow for far-away particles
        return n_cells - 1
    if f < 0.0:
        return 0
    return int(f)


@njit(cache=True)
def cell_list(x, lx, ly, z0, shape, size):
    """Counting-sort particles into cells.

    Parameters
    ----------
    x : float64 (N, 3)
    lx, ly : float
        Periods, m.
    z0 : float
        Bottom of the grid in z, m.
    shape : (int, int, int)
        ``(nx, ny, nz)``, each >= 1.
    size : (float, float, float)
        Cell sizes, m.

    Returns
    -------
    cell_of : int64 (N,)
        Flat cell index of each particle.
    cell_start : int64 (nx * ny * nz + 1,)
        Particles of cell ``c`` are ``cell_order[cell_start[c]:cell_start[c + 1]]``.
    cell_order : int64 (N,)
        Particle indices grouped by cell, ascending within each cell.
    """
    n = x.shape[0]
    nx, ny, nz = shape
    sx, sy, sz = size
    n_cells = nx * ny * nz
    cell_of = np.empty(n, np.int64)
    cell_start = np.zeros(n_cells + 1, np.int64)
    for i in range(n):
        ix = _periodic_cell(x[i, 0], lx, sx, nx)
        iy = _periodic_cell(x[i, 1], ly, sy, ny)
        iz = _bounded_cell(x[i, 2], z0, sz, nz)
        c = ix + nx * (iy + ny * iz)
        cell_of[i] = c
        cell_start[c + 1] += 1
    for c in range(n_cells):
        cell_start[c + 1] += cell_start[c]
    fill = cell_start[:-1].copy()
    cell_order = np.empty(n, np.int64)
    for i in range(n):  # ascending i: stable, so each cell lists its particles in order
        c = cell_of[i]
        cell_order[fill[c]] = i
        fill[c] += 1
    return cell_of, cell_start, cell_order


@njit(cache=True)
def _sort_segment(pairs, start, stop):
    """Insertion sort of ``pairs[start:stop, 1]`` (short segments: one particle's partners)."""
    for a in range(start + 1, stop):
        value = pairs[a, 1]
        b = a - 1
        while b >= start and pairs[b, 1] > value:
            pairs[b + 1, 1] = pairs[b, 1]
            b -= 1
        pairs[b + 1, 1] = value


@njit(cache=True)
def neighbor_pairs(x, r, lx, ly, skin, shape, cell_of, cell_start, cell_order, pairs):
    """Neighbour pairs ``(i, j)``, ``i < j``, with surface gap ``< skin``, from a cell list.

    Parameters
    ----------
    x : float64 (N, 3)
    r : float64 (N,)
    lx, ly : float
        Periods, m.
    skin : float
        Gap threshold, m (>= 0).
    shape : (int, int, int)
        Grid of :func:`cell_list`, whose cell sizes must be >= ``2 max(r) + skin``.
    cell_of, cell_start, cell_order : int64 arrays
        Output of :func:`cell_list`.
    pairs : int32 (capacity, 2)
        Output buffer; its first ``min(M, capacity)`` rows are written.

    Returns
    -------
    int
        Number of pairs ``M``. If ``M > capacity`` the buffer overflowed: its content is
        incomplete (and unsorted) and the caller must retry with ``capacity >= M``.
    """
    n = x.shape[0]
    nx, ny, nz = shape
    capacity = pairs.shape[0]
    # Cell-sorted copies: the inner loop below reads them contiguously.
    xs = np.empty((n, 3))
    rs = np.empty(n)
    for k in range(n):
        i = cell_order[k]
        xs[k, 0] = x[i, 0]
        xs[k, 1] = x[i, 1]
        xs[k, 2] = x[i, 2]
        rs[k] = r[i]
    # Distinct neighbour cells along a periodic axis: offsets -1, 0, 1 with >= 3 cells,
    # otherwise every cell once.
    mx = min(nx, 3)
    my = min(ny, 3)
    count = 0
    for i in range(n):
        first = count
        xi0 = x[i, 0]
        xi1 = x[i, 1]
        xi2 = x[i, 2]
        ri = r[i]
        c = cell_of[i]
        ix = c % nx
        iy = (c // nx) % ny
        iz = c // (nx * ny)
        for jz in range(iz - 1, iz + 2):
            if jz < 0 or jz >= nz:
                continue
            for ky in range(my):
                jy = (iy + ky - 1) % ny if ny >= 3 else ky
                for kx in range(mx):
                    jx = (ix + kx - 1) % nx if nx >= 3 else kx
                    cj = jx + nx * (jy + ny * jz)
                    for k in range(cell_start[cj], cell_start[cj + 1]):
                        j = cell_order[k]
                        if j <= i:
                            continue
                        dx = xs[k, 0] - xi0
                        dx -= lx * np.floor(dx / lx + 0.5)
                        dy = xs[k, 1] - xi1
                        dy -= ly * np.floor(dy / ly + 0.5)
                        dz = xs[k, 2] - xi2
                        cut = ri + rs[k] + skin
                        if dx * dx + dy * dy + dz * dz < cut * cut:
                            if count < capacity:
                                pairs[count, 0] = i
                                pairs[count, 1] = j
                            count += 1
        if count <= capacity:
            _sort_segment(pairs, first, count)
    return count


@njit(cache=True)
def moved_beyond(x, x_ref, lx, ly, limit):
    """True when any particle moved more than ``limit`` (minimum image in x, y) or is not finite.

    Stops at the first such particle; no temporaries.
    """
    limit2 = limit * limit
    for i in range(x.shape[0]):
        dx = x[i, 0] - x_ref[i, 0]
        dx -= lx * np.floor(dx / lx + 0.5)
        dy = x[i, 1] - x_ref[i, 1]
        dy -= ly * np.floor(dy / ly + 0.5)
        dz = x[i, 2] - x_ref[i, 2]
        d2 = dx * dx + dy * dy + dz * dz
        if not d2 <= limit2:  # also catches NaN
            return True
    return False
