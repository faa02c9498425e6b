"""Private numba kernels of the voxel finite elements (:mod:`md.voxel`; SI units).

Every voxel is an 8-node trilinear hexahedron of side ``h``; its stiffness is
``h * (lam * KL + mu * KM)`` with ``KL`` and ``KM`` the unit cube's matrices (24 x 24, node
``a`` at the corner ``(a & 1, a >> 1 & 1, a >> 2 & 1)``, three displacement components per
node; :func:`md.voxel.element_matrices`). Nodes are numbered ``i + nx (j + ny k)`` on a grid
periodic in x and y; ``free`` maps a node to its row block (-1: held or absent).
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["element_nodes", "assemble_blocks", "affine_forces", "band_stress"]


@njit(cache=True)
def element_nodes(elements, nx, ny, out):
    """The 8 node numbers of each voxel ``elements`` (flat cell indices ``i + nx (j + ny k)``
    of a grid of ``nx * ny`` cells per layer), periodic in x and y, into ``out`` (m, 8)."""
    for e in range(elements.size):
        c = elements[e]
        i = c % nx
        j = (c // nx) % ny
        k = c // (nx * ny)
        for a in range(8):
            ii = (i + (a & 1)) % nx
            jj = (j + ((a >> 1) & 1)) % ny
            kk = k + ((a >> 2) & 1)
            out[e, a] = ii + nx * (jj + ny * kk)


@njit(cache=True)
def assemble_blocks(nodes, lam, mu, KL, KM, h, free, data, col):
    """Sum the 3 x 3 blocks of every element's stiffness into the node-block rows of the free
    nodes: ``data[r, s]`` is the block of row ``r`` towards its neighbour in slot ``s`` (the
    27 offsets (-1, 0, 1)^3, ``s = (dx+1) + 3 (dy+1) + 9 (dz+1)``) and ``col[r, s]`` that
    neighbour's row (-1: none, or held)."""
    for e in range(nodes.shape[0]):
        for a in range(8):
            ra = free[nodes[e, a]]
            if ra < 0:
                continue
            for b in range(8):
                cb = free[nodes[e, b]]
                if cb < 0:
                    continue
                s = (((b & 1) - (a & 1)) + 1) + 3 * ((((b >> 1) & 1) - ((a >> 1) & 1)) + 1) \
                    + 9 * ((((b >> 2) & 1) - ((a >> 2) & 1)) + 1)
                col[ra, s] = cb
                for p in range(3):
                    for q in range(3):
                        data[ra, s, p, q] += h * (lam[e] * KL[3 * a + p, 3 * b + q]
                                                  + mu[e] * KM[3 * a + p, 3 * b + q])


@njit(cache=True)
def affine_forces(nodes, lam, mu, KL, KM, h, H, free, out):
    """Right-hand side of the fluctuation solve: minus the nodal forces of the affine
    displacement ``u = H x`` of every element (``H`` the 3 x 3 displacement gradient, taken on
    the element's own corners so that a periodic jump is included), summed into ``out``
    (rows of the free nodes, 3 columns)."""
    ue = np.empty(24)
    for e in range(nodes.shape[0]):
        for a in range(8):
            xa = (a & 1) * h
            ya = ((a >> 1) & 1) * h
            za = ((a >> 2) & 1) * h
            for p in range(3):
                ue[3 * a + p] = H[p, 0] * xa + H[p, 1] * ya + H[p, 2] * za
        for a in range(8):
            ra = free[nodes[e, a]]
            if ra < 0:
                continue
            for p in range(3):
                f = 0.0
                for m in range(24):
                    f += (lam[e] * KL[3 * a + p, m] + mu[e] * KM[3 * a + p, m]) * ue[m]
                out[ra, p] -= h * f


@njit(cache=True)
def band_stress(nodes, lam, mu, h, H, w, out):
    """Sum over the elements ``nodes`` of their volume times their mean stress (the stress at
    the centre: the mean over a trilinear hexahedron of its strain), with the displacement
    ``H x + w`` (``w`` per node, shape (n_nodes, 3)), into ``out`` (3 x 3, tension
    positive)."""
    g = np.empty((3, 3))
    vol = h * h * h
    for e in range(nodes.shape[0]):
        for p in range(3):
            for q in range(3):
                g[p, q] = H[p, q]
        for a in range(8):
            n = nodes[e, a]
            # grad N_a at the centre: (2 o_j - 1) / (4 h) along each axis j.
            d0 = (2.0 * (a & 1) - 1.0) / (4.0 * h)
            d1 = (2.0 * ((a >> 1) & 1) - 1.0) / (4.0 * h)
            d2 = (2.0 * ((a >> 2) & 1) - 1.0) / (4.0 * h)
            for p in range(3):
                g[p, 0] += w[n, p] * d0
                g[p, 1] += w[n, p] * d1
                g[p, 2] += w[n, p] * d2
        tr = g[0, 0] + g[1, 1] + g[2, 2]
        for p in range(3):
            for q in range(3):
                eps = 0.5 * (g[p, q] + g[q, p])
                s = 2.0 * mu[e] * eps
                if p == q:
                    s += lam[e] * tr
                out[p, q] += vol * s
