"""Private multi-threaded numba kernels of the linearised acoustic stage (SI units).

The serial kernels of :mod:`md._kernels_acoustic` scatter each bond's force to both of its
particles, which threads cannot share without races. Here every particle *gathers* the forces
of its own bonds (``prange`` over particles, each writing only its own row): the lattice bonds
through a full 18-column neighbour table (the 9 stored half-stencil directions and their
reverses), the contact bonds through a per-particle list (CSR: ``start``, ``bond``, ``sign``).
Each bond is evaluated twice, once per end, so a thread does twice the arithmetic of the serial
sweep; the gain comes from the cores. The forces are the same as the serial kernels' up to
round-off (tested).
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from ._kernels_acoustic import bond_force, record_slabs

__all__ = ["full_lattice_table", "contact_lists", "gather_forces", "leapfrog_run_parallel"]


@njit(cache=True)
def full_lattice_table(table, first, full):
    """``full[p, d]`` = ``table[p, d]`` for the 9 half-stencil directions and
    ``full[q, 9 + d]`` = ``first + p`` for each stored bond ``p -> q`` of direction ``d``
    (−1 elsewhere)."""
    for p in range(full.shape[0]):
        for d in range(18):
            full[p, d] = -1
    for p in range(table.shape[0]):
        for d in range(table.shape[1]):
            j = table[p, d]
            full[p, d] = j
            if j >= 0:
                full[j - first, 9 + d] = first + p


def contact_lists(n_particles, bi, bj):
    """Per-particle contact bonds as CSR: ``start`` (n + 1), ``bond`` and ``sign`` (+1 where the
    particle is the bond's first, −1 where it is the second)."""
    ends = np.concatenate([bi, bj]).astype(np.int64)
    bonds = np.concatenate([np.arange(bi.size), np.arange(bj.size)]).astype(np.int64)
    sign = np.concatenate([np.ones(bi.size), -np.ones(bj.size)])
    order = np.argsort(ends, kind="stable")
    start = np.searchsorted(ends[order], np.arange(n_particles + 1)).astype(np.int64)
    return start, bonds[order], sign[order]


@njit(cache=True, parallel=True, fastmath={"contract"})
def gather_forces(u, v, start, cbond, csign, bi, bj, nrm, kn, kt, gn, gt, full, first, lat_nrm,
                  lat_kn, lat_kt, f, sz, want_sz, ax):
    """Forces :math:`-(Ku + Dv)` into ``f`` (overwritten) and, with ``want_sz``, each
    particle's stress share into ``sz`` (overwritten), as the serial ``contact_forces`` plus
    ``lattice_forces``."""
    n = u.shape[0]
    for i in prange(n):
        fx = 0.0
        fy = 0.0
        fz = 0.0
        s = 0.0
        for k in range(start[i], start[i + 1]):
            b = cbond[k]
            gx, gy, gz = bond_force(u, v, bi[b], bj[b], nrm[b, 0], nrm[b, 1], nrm[b, 2], kn[b],
                                    kt[b], gn[b], gt[b])
            nz_ = nrm[b, 2]
            sg = csign[k]
            fx += sg * gx
            fy += sg * gy
            fz += sg * gz
            if want_sz:
                s += -0.5 * (gx if ax == 0 else (gy if ax == 1 else gz)) * nz_
        p = i - first
        if p >= 0:
            for d in range(18):
                j = full[p, d]
                if j < 0:
                    continue
                dd = d % 9
                nz_ = lat_nrm[dd, 2]
                gx, gy, gz = bond_force(u, u, i, j, lat_nrm[dd, 0], lat_nrm[dd, 1], nz_,
                                        lat_kn[dd], lat_kt[dd], 0.0, 0.0)
                fx += gx
                fy += gy
                fz += gz
                if want_sz:
                    # the serial sweep adds -0.5 F_ax n_z to both ends, F the force on the
                    # bond's first particle: g here, -g where i is the second (reverse column)
                    sgn = 1.0 if d < 9 else -1.0
                    s += -0.5 * sgn * (gx if ax == 0 else (gy if ax == 1 else gz)) * nz_
        f[i, 0] = fx
        f[i, 1] = fy
        f[i, 2] = fz
        if want_sz:
            sz[i] = s


@njit(cache=True, parallel=True)
def _update(u, v, f, inv_m, flag, dt, drive, ax):
    for p in prange(u.shape[0]):
        fl = flag[p]
        if fl == 0:
            for a in range(3):
                v[p, a] += dt * f[p, a] * inv_m[p]
                u[p, a] += dt * v[p, a]
        elif fl == 2:
            for a in range(3):
                v[p, a] = 0.0
                u[p, a] = 0.0
            u[p, ax] = drive


@njit(cache=True)
def leapfrog_run_parallel(u, v, inv_m, flag, slab, n_slabs, start, cbond, csign, bi, bj, nrm,
                          kn, kt, gn, gt, full, first, lat_nrm, lat_kn, lat_kt, dt, t0, n_steps,
                          amplitude, duration, every, ax, record):
    """The multi-threaded twin of :func:`md._kernels_acoustic.leapfrog_run` (same arguments
    with the gather tables in place of the neighbour table)."""
    n = u.shape[0]
    f = np.empty((n, 3))
    sz = np.zeros(n)
    for step in range(n_steps):
        want = step % every == 0
        gather_forces(u, v, start, cbond, csign, bi, bj, nrm, kn, kt, gn, gt, full, first,
                      lat_nrm, lat_kn, lat_kt, f, sz, want, ax)
        if want:
            record_slabs(record, step // every, slab, sz)
        t_next = t0 + (step + 1) * dt
        drive = amplitude if t_next < duration else 0.0
        _update(u, v, f, inv_m, flag, dt, drive, ax)
