"""Private numba kernels of the cement lattice (SI units)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["classify_cells"]


@njit(cache=True)
def classify_cells(x, r, lx, ly, z0, cw, nx, ny, nz, reach, touches, solid, dist):
    """Grain-centric pass over the cells near each grain.

    Cells are cubes of width ``cw``; cell (i, j, k) spans ``[i cw, (i+1) cw)`` in x (periodic,
    ``nx cw = lx``), likewise y, and ``z0 + [k cw, (k+1) cw)`` in z. For every grain and every
    cell within ``r + reach`` of its centre (minimum image in x, y):

    * ``solid[c] = 1`` if the cell centre lies inside the grain;
    * ``touches[c] += 1`` if the cube intersects the sphere (closest point of the cube to the
      centre inside the sphere);
    * ``dist[c] = min(dist[c], |centre - x| - r)``, the distance from the cell centre to the
      nearest grain surface (capped at ``reach`` by the caller's initial value).
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
                        dist[c] = d
                    if d < 0.0:
                        solid[c] = 1
                    # Closest point of the cube to the grain centre.
                    qx = min(max(x[g, 0], cx - h), cx + h) - x[g, 0]
                    qy = min(max(x[g, 1], cy - h), cy + h) - x[g, 1]
                    qz = min(max(x[g, 2], cz - h), cz + h) - x[g, 2]
                    if qx * qx + qy * qy + qz * qz < rg * rg:
                        touches[c] += 1
