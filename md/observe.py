"""Observables of a grain pack: contact stress (virial), from the contact forces. SI units."""

from __future__ import annotations

import numpy as np

__all__ = ["contact_stress"]


def contact_stress(x, r, pairs, box, material, *, z_range=None):
    r"""Static contact stress tensor
    :math:`\sigma = \frac1V \sum_c \mathbf f_c \otimes \mathbf l_c`.

    Sum over the overlapping pairs of the elastic Hertz force on ``j`` (:math:`\mathbf f_c`,
    along the branch vector :math:`\mathbf l_c` from ``i`` to ``j``, minimum image in x and y) —
    compression positive. ``V`` is the box area times the height of ``z_range`` (default the
    span of grain centres), and only contacts whose midpoint lies in ``z_range`` count.

    Returns
    -------
    ndarray, shape (3, 3)
        Pa.
    """
    pairs = np.asarray(pairs)
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d[:, 0] -= box.lx * np.round(d[:, 0] / box.lx)
    d[:, 1] -= box.ly * np.round(d[:, 1] / box.ly)
    dist = np.linalg.norm(d, axis=1)
    ri, rj = r[pairs[:, 0]], r[pairs[:, 1]]
    xi = ri + rj - dist
    mid = x[pairs[:, 0], 2] + 0.5 * d[:, 2]
    z0, z1 = (float(x[:, 2].min()), float(x[:, 2].max())) if z_range is None else z_range
    keep = (xi > 0) & (mid >= z0) & (mid <= z1)
    R_f = ri[keep] * rj[keep] / (ri[keep] + rj[keep])
    fn = 4.0 / 3.0 * material.E_f * np.sqrt(R_f) * xi[keep] ** 1.5
    branch = d[keep]
    f = fn[:, None] * branch / dist[keep][:, None]
    volume = box.lx * box.ly * (z1 - z0)
    return np.einsum("ci,cj->ij", f, branch) / volume
