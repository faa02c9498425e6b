"""Private numba kernels of the linearised acoustic stage (SI units).

Two kinds of bonds act between particles (grains and cement particles):

* *contact bonds* (grain–grain and grain–cement), each with its own unit normal ``nrm`` (from the
  first particle to the second), normal and tangential stiffnesses ``kn``, ``kt`` and dashpots
  ``gn``, ``gt``;
* *lattice bonds* (cement–cement), uniform springs of one of the 9 stencil directions ``dirn``
  (:data:`md.cement.LATTICE_OFFSETS`), with per-direction ``lat_kn``, ``lat_kt`` and normals,
  stored as a neighbour table: one int32 row of 9 particle indices (−1 for no bond) per cement
  particle, one column per half-stencil direction (36 B per node instead of 9 B per bond).

A bond with relative displacement :math:`\\mathbf d = \\mathbf u_j - \\mathbf u_i` pulls ``j`` back
by :math:`-[k_t\\mathbf d + (k_n - k_t)(\\mathbf d\\cdot\\hat n)\\hat n]` (and the dashpot term with
the relative velocity), and pushes ``i`` by the opposite force.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["lattice_table", "grain_cement_bonds", "interface_patches", "bond_force",
           "contact_forces",
           "lattice_forces", "gershgorin_rows", "leapfrog_run", "block_jacobi"]


@njit(cache=True)
def lattice_table(cells, where, nx, ny, nz, offsets, first, table):
    """Cement–cement bonds to the 18 nearest lattice neighbours as a neighbour table.

    ``cells`` are the flat indices of the cemented cells, ``where[flat]`` the index of a
    cemented cell among them (−1 otherwise). ``table[p, d]`` gets the particle index
    (``first + where``) of the neighbour of cement particle ``p`` at the half-stencil offset
    ``offsets[d]`` (so each bond is stored once), or −1 if that cell is empty or outside the
    lattice. Periodic in x and y, bounded in z. Returns the number of bonds.
    """
    n = 0
    for p in range(cells.shape[0]):
        c = cells[p]
        i = c % nx
        j = (c // nx) % ny
        k = c // (nx * ny)
        for d in range(offsets.shape[0]):
            table[p, d] = -1
            kk = k + offsets[d, 2]
            if kk < 0 or kk >= nz:
                continue
            ii = (i + offsets[d, 0]) % nx
            jj = (j + offsets[d, 1]) % ny
            q = where[ii + nx * (jj + ny * kk)]
            if q < 0:
                continue
            table[p, d] = first + q
            n += 1
    return n


@njit(cache=True)
def grain_cement_bonds(x, r, where, lx, ly, z0, cw, nx, ny, nz, faces, count_only, bi, bj, nrm):
    """Grain–cement bonds: every cemented cell whose cube intersects a grain's sphere, and with
    ``faces`` also every cemented cell one of whose 6 face neighbours has its centre inside the
    grain (the pore cells along the staircase boundary of the grain, whose cube may stop short
    of the sphere).

    ``bi`` gets the grain, ``bj`` the cement particle's index *among the cement particles*
    (``where[cell]``), ``nrm`` the unit vector from the grain centre to the cell centre (minimum
    image in x and y). Returns the number of bonds.
    """
    h = 0.5 * cw
    pad = 1 if faces else 0
    n = 0
    for g in range(x.shape[0]):
        rg = r[g]
        i0 = int(np.floor((x[g, 0] - rg) / cw)) - pad
        i1 = int(np.floor((x[g, 0] + rg) / cw)) + pad
        j0 = int(np.floor((x[g, 1] - rg) / cw)) - pad
        j1 = int(np.floor((x[g, 1] + rg) / cw)) + pad
        k0 = max(int(np.floor((x[g, 2] - rg - z0) / cw)) - pad, 0)
        k1 = min(int(np.floor((x[g, 2] + rg - z0) / cw)) + pad, nz - 1)
        for ii in range(i0, i1 + 1):
            i = ii % nx
            cx = (ii + 0.5) * cw
            for jj in range(j0, j1 + 1):
                j = jj % ny
                cy = (jj + 0.5) * cw
                for k in range(k0, k1 + 1):
                    q = where[i + nx * (j + ny * k)]
                    if q < 0:
                        continue
                    cz = z0 + (k + 0.5) * cw
                    dx = cx - x[g, 0]
                    dy = cy - x[g, 1]
                    dz = cz - x[g, 2]
                    qx = min(max(x[g, 0], cx - h), cx + h) - x[g, 0]
                    qy = min(max(x[g, 1], cy - h), cy + h) - x[g, 1]
                    qz = min(max(x[g, 2], cz - h), cz + h) - x[g, 2]
                    hit = qx * qx + qy * qy + qz * qz < rg * rg
                    if faces and not hit:
                        d2 = dx * dx + dy * dy + dz * dz + cw * cw
                        m = max(abs(dx), max(abs(dy), abs(dz)))
                        hit = d2 - 2.0 * cw * m < rg * rg     # the nearest face neighbour
                    if not hit:
                        continue
                    if not count_only:
                        norm = np.sqrt(dx * dx + dy * dy + dz * dz)
                        bi[n] = g
                        bj[n] = q
                        nrm[n, 0] = dx / norm
                        nrm[n, 1] = dy / norm
                        nrm[n, 2] = dz / norm
                    n += 1
    return n


@njit(cache=True)
def _root(parent, b):
    """Root of ``b`` in the union–find forest ``parent``, halving the path on the way."""
    while parent[b] != b:
        parent[b] = parent[parent[b]]
        b = parent[b]
    return b


@njit(cache=True)
def interface_patches(bond_group, start, table, first, label):
    """Connected patches of the grain–cement interface.

    Bonds are sorted by cement particle: those of cement particle ``p`` are
    ``start[p]:start[p + 1]``, ``bond_group[b]`` the group of bond ``b`` (its grain, or its
    grain and the neighbouring grain its cell faces). Two bonds belong to the same patch when
    they are of the *same group* and join two cement particles that share a lattice bond
    (``table``, rows by cement particle, entries ``first + q`` or −1), and patches are the
    transitive closure (union–find). ``label[b]`` gets a patch number in
    ``0 .. n_patches - 1`` (numbered by first bond). Returns ``n_patches``.
    """
    n = bond_group.shape[0]
    parent = np.arange(n)
    for p in range(table.shape[0]):
        for d in range(table.shape[1]):
            q = table[p, d]
            if q < 0:
                continue
            q -= first
            for b1 in range(start[p], start[p + 1]):
                for b2 in range(start[q], start[q + 1]):
                    if bond_group[b1] == bond_group[b2]:
                        r1 = _root(parent, b1)
                        r2 = _root(parent, b2)
                        if r1 != r2:
                            parent[max(r1, r2)] = min(r1, r2)
    n_patches = 0
    for b in range(n):
        r = _root(parent, b)
        if r == b:
            label[b] = n_patches
            n_patches += 1
        else:
            label[b] = label[r]
    return n_patches


@njit(cache=True, inline="always")
def _apply(f, sz, i, j, fx, fy, fz, nz_, want_sz, ax):
    """Force ``(fx, fy, fz)`` on ``i``, its opposite on ``j``; the stress share to ``sz``."""
    f[i, 0] += fx
    f[i, 1] += fy
    f[i, 2] += fz
    f[j, 0] -= fx
    f[j, 1] -= fy
    f[j, 2] -= fz
    if want_sz:
        c = -0.5 * (fx if ax == 0 else (fy if ax == 1 else fz)) * nz_
        sz[i] += c
        sz[j] += c


@njit(cache=True, inline="always")
def bond_force(u, v, i, j, nx_, ny_, nz_, kn, kt, gn, gt):
    """Force of one bond on its first particle ``i`` (its opposite acts on ``j``):
    :math:`k_t\\mathbf d + (k_n - k_t)(\\mathbf d\\cdot\\hat n)\\hat n` plus the dashpot
    term, :math:`\\mathbf d = \\mathbf u_j - \\mathbf u_i`; ``v`` may be ``u`` with zero
    dashpots (lattice springs)."""
    dx = u[j, 0] - u[i, 0]
    dy = u[j, 1] - u[i, 1]
    dz = u[j, 2] - u[i, 2]
    wx = v[j, 0] - v[i, 0]
    wy = v[j, 1] - v[i, 1]
    wz = v[j, 2] - v[i, 2]
    dn = (kn - kt) * (dx * nx_ + dy * ny_ + dz * nz_) \
        + (gn - gt) * (wx * nx_ + wy * ny_ + wz * nz_)
    return (kt * dx + gt * wx + dn * nx_, kt * dy + gt * wy + dn * ny_,
            kt * dz + gt * wz + dn * nz_)


@njit(cache=True, fastmath={"contract"})
def contact_forces(u, v, bi, bj, nrm, kn, kt, gn, gt, f, sz, want_sz, ax):
    """Add the forces of the contact bonds to ``f`` (elastic plus dashpot); with ``want_sz``
    add half of each bond's force component ``ax`` on its second particle times the z
    component of its normal (for ``ax = 2``: compression positive) to ``sz`` of both ends —
    each particle's share of the slab stress :math:`\\sigma_{az}`."""
    for b in range(bi.shape[0]):
        i = bi[b]
        j = bj[b]
        fx, fy, fz = bond_force(u, v, i, j, nrm[b, 0], nrm[b, 1], nrm[b, 2], kn[b], kt[b],
                                gn[b], gt[b])
        _apply(f, sz, i, j, fx, fy, fz, nrm[b, 2], want_sz, ax)


@njit(cache=True, fastmath={"contract"})
def lattice_forces(u, table, first, lat_nrm, lat_kn, lat_kt, f, sz, want_sz, ax):
    """Add the forces of the lattice bonds (eq. 6, no dashpots) to ``f`` (and ``sz`` as in
    :func:`contact_forces`).

    ``table`` is the neighbour table of :func:`lattice_table`; row ``p`` is particle
    ``first + p``. One sweep in particle order: each particle's own force is summed in
    registers and written once, its neighbours' (mostly a few rows ahead, so in cache)
    are scattered. Only fused multiply–adds are allowed to reorder the arithmetic.
    """
    for p in range(table.shape[0]):
        i = first + p
        ux = u[i, 0]
        uy = u[i, 1]
        uz = u[i, 2]
        sx = 0.0
        sy = 0.0
        sz_i = 0.0
        ss = 0.0
        for d in range(table.shape[1]):
            j = table[p, d]
            if j < 0:
                continue
            nx_ = lat_nrm[d, 0]
            ny_ = lat_nrm[d, 1]
            nz_ = lat_nrm[d, 2]
            k_t = lat_kt[d]
            dx = u[j, 0] - ux
            dy = u[j, 1] - uy
            dz = u[j, 2] - uz
            dn = (lat_kn[d] - k_t) * (dx * nx_ + dy * ny_ + dz * nz_)
            fx = k_t * dx + dn * nx_
            fy = k_t * dy + dn * ny_
            fz = k_t * dz + dn * nz_
            sx += fx
            sy += fy
            sz_i += fz
            f[j, 0] -= fx
            f[j, 1] -= fy
            f[j, 2] -= fz
            if want_sz:
                c = -0.5 * (fx if ax == 0 else (fy if ax == 1 else fz)) * nz_
                ss += c
                sz[j] += c
        f[i, 0] += sx
        f[i, 1] += sy
        f[i, 2] += sz_i
        if want_sz:
            sz[i] += ss


@njit(cache=True)
def block_jacobi(inverse, active, free_idx, r, full_r, full_z, z):
    """``z = M^-1 r`` on the free degrees of freedom ``free_idx`` (indices into the particle-major
    n × dof vector) for the block-diagonal ``inverse`` (n, dof, dof); ``full_r`` and ``full_z``
    (n × dof) are scratch, and the held entries of ``full_r`` must be zero (they stay so);
    ``active`` lists the particles with a free degree of freedom."""
    dof = inverse.shape[1]
    for k in range(free_idx.size):
        full_r[free_idx[k]] = r[k]
    for p in active:                    # whole blocks (held rows too: cheaper than dividing
        base = p * dof                  # each free index by dof), then the free rows kept
        for a in range(dof):
            acc = 0.0
            for b in range(dof):
                acc += inverse[p, a, b] * full_r[base + b]
            full_z[base + a] = acc
    for k in range(free_idx.size):
        z[k] = full_z[free_idx[k]]


@njit(cache=True)
def _add_block_rows(rows, i, j, nx_, ny_, nz_, k_n, k_t):
    n = (nx_, ny_, nz_)
    for a in range(3):
        s = 0.0
        for c in range(3):
            s += abs((k_n - k_t) * n[a] * n[c] + (k_t if a == c else 0.0))
        rows[i, a] += 2.0 * s
        rows[j, a] += 2.0 * s


@njit(cache=True)
def gershgorin_rows(n_particles, bi, bj, nrm, kn, kt, table, first, lat_nrm, lat_kn, lat_kt):
    """Row sums of :math:`|K|` per particle and axis (diagonal block plus off-diagonal blocks),
    the Gershgorin bound of the stiffness matrix."""
    rows = np.zeros((n_particles, 3))
    for b in range(bi.shape[0]):
        _add_block_rows(rows, bi[b], bj[b], nrm[b, 0], nrm[b, 1], nrm[b, 2], kn[b], kt[b])
    for p in range(table.shape[0]):
        for d in range(table.shape[1]):
            j = table[p, d]
            if j >= 0:
                _add_block_rows(rows, first + p, j, lat_nrm[d, 0], lat_nrm[d, 1],
                                lat_nrm[d, 2], lat_kn[d], lat_kt[d])
    return rows


@njit(cache=True, inline="always")
def record_slabs(record, row, slab, sz):
    """Row ``row`` of the slab signals: the particles' ``sz`` summed per slab."""
    record[row, :] = 0.0
    for p in range(slab.size):
        record[row, slab[p]] += sz[p]


@njit(cache=True)
def leapfrog_run(u, v, inv_m, flag, slab, n_slabs, bi, bj, nrm, kn, kt, gn, gt, table, first,
                 lat_nrm, lat_kn, lat_kt, dt, t0, n_steps, amplitude, duration, every, ax, record):
    """Advance the linear system ``n_steps`` by the explicit central-difference (leapfrog) scheme.

    ``u`` are displacements at time ``t0``, ``v`` velocities at ``t0 - dt/2``; the dashpots use
    the lagged velocity. ``flag``: 0 free, 1 fixed, 2 driven (displacement ``amplitude`` along
    axis ``ax`` for ``0 <= t < duration``, else 0). Every ``every`` steps,
    ``record[step // every, s]`` gets the sum over the particles of slab ``s`` of their contact
    forces along ``ax`` (``sz`` of :func:`contact_forces`) at time ``t0 + step dt``.
    """
    n = u.shape[0]
    f = np.empty((n, 3))
    sz = np.empty(n)
    for step in range(n_steps):
        f[:] = 0.0
        want = step % every == 0
        if want:
            sz[:] = 0.0
        contact_forces(u, v, bi, bj, nrm, kn, kt, gn, gt, f, sz, want, ax)
        lattice_forces(u, table, first, lat_nrm, lat_kn, lat_kt, f, sz, want, ax)
        if want:
            record_slabs(record, step // every, slab, sz)
        t_next = t0 + (step + 1) * dt
        drive = amplitude if t_next < duration else 0.0
        for p in range(n):
            fl = flag[p]
            if fl == 0:
                for a in range(3):
                    v[p, a] += dt * f[p, a] * inv_m[p]
                    u[p, a] += dt * v[p, a]
            elif fl == 2:
                v[p, 0] = 0.0
                v[p, 1] = 0.0
                v[p, 2] = 0.0
                u[p, 0] = 0.0
                u[p, 1] = 0.0
                u[p, 2] = 0.0
                u[p, ax] = drive
