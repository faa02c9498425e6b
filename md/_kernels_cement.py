"""Private numba kernels of the cement lattice (SI units): cell classification, the face-neighbour
map and the growth schemes of :func:`md.cement.grow_cement`."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["classify_cells", "face_neighbours", "float32_levels", "order_keys", "contact_growth",
           "tree_build", "tree_total", "tree_pick", "tree_picks", "pore_body_start",
           "pore_body_growth", "EMPTY", "FRONTIER", "CEMENTED"]


@njit(cache=True)
def classify_cells(x, r, lx, ly, z0, cw, nx, ny, nz, reach, touches, solid, dist, dist2):
    """Grain-centric pass over the cells near each grain.

    Cells are cubes of width ``cw``; cell (i, j, k) spans ``[i cw, (i+1) cw)`` in x (periodic,
    ``nx cw = lx``), likewise y, and ``z0 + [k cw, (k+1) cw)`` in z. For every grain and every
    cell within ``r + reach`` of its centre (minimum image in x, y):

    * ``solid[c] = 1`` if the cell centre lies inside the grain;
    * ``touches[c] += 1`` if the cube intersects the sphere (closest point of the cube to the
      centre inside the sphere);
    * ``dist[c] = min(dist[c], |centre - x| - r)``, the distance from the cell centre to the
      nearest grain surface, and ``dist2[c]`` the distance to the second-nearest grain surface
      (both capped at ``reach`` by the caller's initial values).
    """
    h = 0.5 * cw
    for g in range(x.shape[0]):
        rg = r[g]
        span = rg + reach
        i0 = int(np.floor((x[g, 0] - span) / cw))
        i1 = int(np.floor((x[g, 0] + span) / cw))
        j0 = int(np.floor((x[g, 1] - span) / cw))
        j1 = int(np.floor((x[g, 1] + span) / cw))
        k0 = max(int(np.floor((x[g, 2] - span - z0) / cw)), 0)
        k1 = min(int(np.floor((x[g, 2] + span - z0) / cw)), nz - 1)
        for ii in range(i0, i1 + 1):
            i = ii % nx
            cx = (ii + 0.5) * cw                     # unwrapped centre next to the grain
            dx = cx - x[g, 0]
            for jj in range(j0, j1 + 1):
                j = jj % ny
                cy = (jj + 0.5) * cw
                dy = cy - x[g, 1]
                for k in range(k0, k1 + 1):
                    cz = z0 + (k + 0.5) * cw
                    dz = cz - x[g, 2]
                    c = i + nx * (j + ny * k)
                    d = np.sqrt(dx * dx + dy * dy + dz * dz) - rg
                    if d < dist[c]:
                        dist2[c] = dist[c]
                        dist[c] = d
                    elif d < dist2[c]:
                        dist2[c] = d
                    if d < 0.0:
                        solid[c] = 1
                    # Closest point of the cube to the grain centre.
                    qx = min(max(x[g, 0], cx - h), cx + h) - x[g, 0]
                    qy = min(max(x[g, 1], cy - h), cy + h) - x[g, 1]
                    qz = min(max(x[g, 2], cz - h), cz + h) - x[g, 2]
                    if qx * qx + qy * qy + qz * qz < rg * rg:
                        touches[c] += 1


# ----------------------------------------------------------------------------- growth schemes
# Kernels of md.cement.grow_cement (García & Medina, Sects. III C–E). Cells are pore positions
# 0..n-1 (aligned with CementLattice.index); ``nbrs`` (n, 6) int32 holds the face neighbours of
# each (-1 where solid or outside the lattice in z).
#
# Ordering key of a cell: ``level << 32 | cell`` (uint64), ``level`` a uint32 with the order of
# the distance (equal distances, equal levels), so keys sort by (distance, cell index): every
# tie is broken by the cell index, deterministically.

_LOW32 = np.uint64(0xFFFFFFFF)
_SHIFT32 = np.uint64(32)

#: States of a pore cell during growth (uint8 array ``cells``).
EMPTY, FRONTIER, CEMENTED = 0, 1, 2


@njit(cache=True)
def face_neighbours(index, nx, ny, nz, where, nbrs):
    """Fill ``nbrs[p]`` with the pore positions of the 6 face neighbours of pore cell ``p``.

    ``index`` holds the flat lattice indices ``i + nx (j + ny k)`` of the pore cells; ``where``
    is scratch of ``nx ny nz`` entries (set here to flat index -> pore position, -1 for solid).
    Columns: +x, -x, +y, -y, +z, -z; periodic in x and y, -1 beyond the bottom and top layers.
    """
    for c in range(where.size):
        where[c] = -1
    for p in range(index.size):
        where[index[p]] = p
    nxy = nx * ny
    for p in range(index.size):
        c = np.int64(index[p])
        i = c % nx
        j = (c // nx) % ny
        k = c // nxy
        row = c - i                                     # flat index of (0, j, k)
        plane = c - (c % nxy)                           # flat index of (0, 0, k)
        ip = i + 1 if i + 1 < nx else 0
        im = i - 1 if i > 0 else nx - 1
        jp = j + 1 if j + 1 < ny else 0
        jm = j - 1 if j > 0 else ny - 1
        nbrs[p, 0] = where[row + ip]
        nbrs[p, 1] = where[row + im]
        nbrs[p, 2] = where[plane + i + nx * jp]
        nbrs[p, 3] = where[plane + i + nx * jm]
        nbrs[p, 4] = where[c + nxy] if k + 1 < nz else -1
        nbrs[p, 5] = where[c - nxy] if k > 0 else -1


@njit(cache=True)
def float32_levels(bits, levels):
    """Order-preserving map of float32 bit patterns (``bits``, uint32; no NaN, no -0.0) to
    uint32 ``levels``: flip the sign bit of non-negative numbers, all bits of negative ones."""
    for c in range(bits.size):
        b = bits[c]
        if b & np.uint32(0x80000000):
            levels[c] = ~b
        else:
            levels[c] = b | np.uint32(0x80000000)


@njit(cache=True)
def order_keys(levels, keys):
    """``keys[c] = levels[c] << 32 | c``: sorting the keys orders cells by (distance, index)."""
    for c in range(levels.size):
        keys[c] = (np.uint64(levels[c]) << _SHIFT32) | np.uint64(c)


@njit(cache=True)
def _cell_key(levels, c):
    return (np.uint64(levels[c]) << _SHIFT32) | np.uint64(c)


@njit(cache=True)
def _heap_push(heap, size, key):
    """Push ``key`` on the binary min-heap ``heap[:size]``; returns the new size."""
    i = size
    while i > 0:
        parent = (i - 1) >> 1
        if heap[parent] <= key:
            break
        heap[i] = heap[parent]
        i = parent
    heap[i] = key
    return size + 1


@njit(cache=True)
def _heap_pop(heap, size):
    """Pop the smallest key of ``heap[:size]`` (``size > 0``); returns (key, new size)."""
    top = heap[0]
    size -= 1
    last = heap[size]
    i = 0
    while True:
        child = 2 * i + 1
        if child >= size:
            break
        if child + 1 < size and heap[child + 1] < heap[child]:
            child += 1
        if heap[child] >= last:
            break
        heap[i] = heap[child]
        i = child
    heap[i] = last
    return top, size


@njit(cache=True)
def contact_growth(levels, kind, nbrs, sorted_keys, target, contact_kind, cells, heap, order):
    """Contact cement (García & Medina, Sect. III C) up to ``target`` cells.

    1. Contact cells (``kind == contact_kind``) by increasing key, until ``target`` or none left.
    2. Growth: the empty face neighbours of the cement on a binary min-heap of keys (each cell at
       most once, marked ``FRONTIER`` in ``cells``); the smallest is cemented and its empty
       neighbours pushed. When the heap is empty (pores not connected to the cement), the empty
       cell of smallest key (a monotone pointer into ``sorted_keys``) is cemented next.

    ``cells`` (uint8, n) starts ``EMPTY`` and ends ``CEMENTED`` where cemented (one state array
    rather than two flags: one cache line per neighbour look-up); ``heap`` (uint64, n) is
    scratch; ``order[i]`` (int64, >= target) gets the i-th cell cemented. Returns the number of
    cemented cells. O(n log n).
    """
    n = levels.size
    count = 0
    for r in range(n):
        if count >= target:
            break
        c = np.int64(sorted_keys[r] & _LOW32)
        if kind[c] == contact_kind:
            cells[c] = CEMENTED
            order[count] = c
            count += 1
    if count >= target:
        return count
    size = 0
    for c in range(n):
        if cells[c] == CEMENTED:
            for q in range(6):
                nb = nbrs[c, q]
                if nb >= 0 and cells[nb] == EMPTY:
                    cells[nb] = FRONTIER
                    size = _heap_push(heap, size, _cell_key(levels, nb))
    ptr = 0
    while count < target:
        if size == 0:                                   # disconnected pores: closest left
            while cells[np.int64(sorted_keys[ptr] & _LOW32)] == CEMENTED:
                ptr += 1
            c = np.int64(sorted_keys[ptr] & _LOW32)
        else:
            key, size = _heap_pop(heap, size)
            c = np.int64(key & _LOW32)
        cells[c] = CEMENTED
        order[count] = c
        count += 1
        for q in range(6):
            nb = nbrs[c, q]
            if nb >= 0 and cells[nb] == EMPTY:
                cells[nb] = FRONTIER
                size = _heap_push(heap, size, _cell_key(levels, nb))
    return count


# Sum tree of the pore-body frontier: a K-ary tree (``fanout`` K) stored level by level in one
# float64 array ``tree``; level 0 (``tree[:n]``, padded with zeros to a multiple of K) holds the
# weight of each cell, ``max(dist, floor)`` in the frontier and 0 outside (so the weight also
# flags the frontier); entry ``e`` of level ``l`` (from ``offsets[l]``) is the sum of entries
# ``e K .. e K + K - 1`` of level ``l - 1``; the top level is one group of K entries. K children
# share a cache line or two, so a pick or an update touches ``log_K n`` lines. Every update
# recomputes the sums on the leaf's path from the children, so a node whose leaves are all 0 is
# exactly 0 (no drift from incremental updates).

@njit(cache=True, inline="always")
def _group_sum(tree, start, fanout):
    """Sum of the ``fanout`` entries of ``tree`` from ``start`` (one group of children)."""
    s = 0.0
    for i in range(fanout):
        s += tree[start + i]
    return s


@njit(cache=True)
def _tree_set(tree, offsets, fanout, c, weight):
    """Set the weight of cell ``c`` and recompute the sums above it. O(K log_K n)."""
    tree[c] = weight
    e = c
    for lev in range(1, offsets.size):
        e //= fanout
        tree[offsets[lev] + e] = _group_sum(tree, offsets[lev - 1] + e * fanout, fanout)


@njit(cache=True)
def tree_build(tree, offsets, fanout):
    """All sums of the tree from the weights in level 0. O(n)."""
    for lev in range(1, offsets.size):
        for e in range((offsets[lev] - offsets[lev - 1]) // fanout):
            tree[offsets[lev] + e] = _group_sum(tree, offsets[lev - 1] + e * fanout, fanout)


@njit(cache=True)
def tree_total(tree, offsets, fanout):
    """Sum of all weights (the top group)."""
    return _group_sum(tree, offsets[offsets.size - 1], fanout)


@njit(cache=True)
def tree_pick(tree, offsets, fanout, u):
    """The cell where the running sum of the weights (in cell order) passes ``u * total``,
    ``0 <= u < 1``: cell ``c`` with probability ``weight[c] / total``.

    Within a group the descent only takes children of positive weight (if rounding leaves the
    remainder beyond the group's sum, it takes the last positive child), so it cannot return a
    cell outside the frontier. The total must be > 0. O(K log_K n).
    """
    x = u * tree_total(tree, offsets, fanout)
    e = 0
    for lev in range(offsets.size - 1, -1, -1):
        base = offsets[lev] + e * fanout
        chosen = -1
        last = -1
        for i in range(fanout):
            v = tree[base + i]
            if v > 0.0:
                if x < v:
                    chosen = i
                    break
                x -= v
                last = i
        if chosen < 0:                          # rounding: the last child of positive weight
            chosen = last
            x = tree[base + last]
        e = e * fanout + chosen
    return e


@njit(cache=True)
def tree_picks(tree, offsets, fanout, uniforms, out):
    """``out[i] = tree_pick(..., uniforms[i])`` (sampling with replacement; for tests)."""
    for i in range(uniforms.size):
        out[i] = tree_pick(tree, offsets, fanout, uniforms[i])


@njit(cache=True)
def pore_body_start(dist, nbrs, seeds, cells, tree, offsets, fanout, floor):
    """Cement the ``seeds``, put their empty face neighbours in the frontier (``cells``,
    weight ``max(dist, floor)`` in level 0 of ``tree``, which starts at 0) and build the sums.
    Returns the frontier size."""
    for s in range(seeds.size):
        cells[seeds[s]] = CEMENTED
    n_front = 0
    for s in range(seeds.size):
        for q in range(6):
            nb = nbrs[seeds[s], q]
            if nb >= 0 and cells[nb] == EMPTY:
                cells[nb] = FRONTIER
                tree[nb] = max(np.float64(dist[nb]), floor)
                n_front += 1
    tree_build(tree, offsets, fanout)
    return n_front


@njit(cache=True)
def pore_body_growth(dist, nbrs, cells, tree, offsets, fanout, floor, target, uniforms,
                     restart, state, order):
    """Pore-body growth (García & Medina, Sect. III E), resumable.

    While fewer than ``target`` cells are cemented: pick a frontier cell with probability
    proportional to ``max(dist, floor)`` (:func:`tree_pick`, one entry of ``uniforms`` per
    pick), cement it, remove it from the frontier and add its empty face neighbours. When the
    frontier is empty (pores not connected to the cement), cement the next empty cell of the
    random permutation ``restart`` (a uniform choice among the empty cells) instead.

    ``cells`` (uint8, n): ``EMPTY``, ``FRONTIER`` or ``CEMENTED``. ``state`` (int64, 4):
    cemented count, frontier size, pointer into ``restart``, uniforms used by this call.
    ``order[i]`` (int64, >= target) gets the i-th cell cemented (the seeds are the caller's).
    Returns 0 when ``target`` is reached, 1 when ``uniforms`` ran out, 2 when the frontier is
    empty and ``restart`` is empty (the caller supplies it and calls again with the unused
    uniforms).
    """
    count = state[0]
    n_front = state[1]
    ptr = state[2]
    k = 0
    status = 0
    while count < target:
        if n_front == 0:
            if restart.size == 0:
                status = 2
                break
            while cells[restart[ptr]] == CEMENTED:
                ptr += 1
            c = np.int64(restart[ptr])
        else:
            if k >= uniforms.size:
                status = 1
                break
            c = np.int64(tree_pick(tree, offsets, fanout, uniforms[k]))
            k += 1
            n_front -= 1
            _tree_set(tree, offsets, fanout, c, 0.0)
        cells[c] = CEMENTED
        order[count] = c
        count += 1
        for q in range(6):
            nb = nbrs[c, q]
            if nb >= 0 and cells[nb] == EMPTY:
                cells[nb] = FRONTIER
                n_front += 1
                _tree_set(tree, offsets, fanout, nb, max(np.float64(dist[nb]), floor))
    state[0] = count
    state[1] = n_front
    state[2] = ptr
    state[3] = k
    return status
