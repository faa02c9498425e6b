"""Private numba kernels of the linearised acoustic stage with rotations (SI units).

Every particle carries six degrees of freedom, ``u[p, 0:3]`` its displacement and
``u[p, 3:6]`` its (small) rotation. A bond between ``i`` and ``j`` with unit normal
:math:`\\hat n` (from ``i`` to ``j``) acts at its contact point, at the distance
:math:`a_i` from the centre of ``i`` and :math:`a_j` from that of ``j``
(:math:`a_i + a_j = |\\mathbf x_j - \\mathbf x_i|`). The relative displacement of the two
faces there is

.. math:: \\mathbf d = \\mathbf u_j - \\mathbf u_i
          + \\hat n\\times(a_i\\boldsymbol\\theta_i + a_j\\boldsymbol\\theta_j),

which vanishes for a rigid motion :math:`\\mathbf u = \\boldsymbol\\omega\\times\\mathbf x`,
:math:`\\boldsymbol\\theta = \\boldsymbol\\omega` (the grain's material point at the contact
moves by :math:`\\mathbf u_i + \\boldsymbol\\theta_i\\times a_i\\hat n`). The bond pulls ``i``
by :math:`\\mathbf F = k_t\\mathbf d + (k_n - k_t)(\\mathbf d\\cdot\\hat n)\\hat n` (plus the
dashpot term with the relative velocity of the faces) and ``j`` by :math:`-\\mathbf F`; the
moments about the centres are :math:`a_i\\,\\hat n\\times\\mathbf F` on ``i`` and
:math:`a_j\\,\\hat n\\times\\mathbf F` on ``j`` (the lever arms :math:`\\pm a\\hat n`), so that
force and moment are :math:`-\\partial U/\\partial(\\mathbf u, \\boldsymbol\\theta)` of the bond
energy :math:`U = \\tfrac12[k_t|\\mathbf d|^2 + (k_n - k_t)(\\mathbf d\\cdot\\hat n)^2]`.

Lattice bonds (cement–cement, :mod:`md._kernels_acoustic`'s neighbour table) act at the
midpoint of the bond: :math:`a_i = a_j = |\\mathbf x_{12}|/2` per stencil direction.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ._kernels_acoustic import record_slabs

__all__ = ["contact_forces_rot", "lattice_forces_rot", "gershgorin_rows_rot",
           "leapfrog_run_rot"]


@njit(cache=True, inline="always")
def _face_force(u, v, i, j, nx_, ny_, nz_, kn, kt, gn, gt, ai, aj):
    """Force of one bond on ``i`` at its contact point (its opposite acts on ``j``)."""
    sx = ai * u[i, 3] + aj * u[j, 3]
    sy = ai * u[i, 4] + aj * u[j, 4]
    sz = ai * u[i, 5] + aj * u[j, 5]
    dx = u[j, 0] - u[i, 0] + ny_ * sz - nz_ * sy
    dy = u[j, 1] - u[i, 1] + nz_ * sx - nx_ * sz
    dz = u[j, 2] - u[i, 2] + nx_ * sy - ny_ * sx
    rx = ai * v[i, 3] + aj * v[j, 3]
    ry = ai * v[i, 4] + aj * v[j, 4]
    rz = ai * v[i, 5] + aj * v[j, 5]
    wx = v[j, 0] - v[i, 0] + ny_ * rz - nz_ * ry
    wy = v[j, 1] - v[i, 1] + nz_ * rx - nx_ * rz
    wz = v[j, 2] - v[i, 2] + nx_ * ry - ny_ * rx
    dn = (kn - kt) * (dx * nx_ + dy * ny_ + dz * nz_) \
        + (gn - gt) * (wx * nx_ + wy * ny_ + wz * nz_)
    return (kt * dx + gt * wx + dn * nx_, kt * dy + gt * wy + dn * ny_,
            kt * dz + gt * wz + dn * nz_)


@njit(cache=True, inline="always")
def _apply_rot(f, sz, i, j, fx, fy, fz, nx_, ny_, nz_, ai, aj, want_sz, ax):
    """Force ``F`` on ``i``, ``-F`` on ``j``, the moments ``a n x F`` on both; the stress
    share of :func:`md._kernels_acoustic.contact_forces` to ``sz``."""
    mx = ny_ * fz - nz_ * fy
    my = nz_ * fx - nx_ * fz
    mz = nx_ * fy - ny_ * fx
    f[i, 0] += fx
    f[i, 1] += fy
    f[i, 2] += fz
    f[j, 0] -= fx
    f[j, 1] -= fy
    f[j, 2] -= fz
    f[i, 3] += ai * mx
    f[i, 4] += ai * my
    f[i, 5] += ai * mz
    f[j, 3] += aj * mx
    f[j, 4] += aj * my
    f[j, 5] += aj * mz
    if want_sz:
        c = -0.5 * (fx if ax == 0 else (fy if ax == 1 else fz)) * nz_
        sz[i] += c
        sz[j] += c


@njit(cache=True, fastmath={"contract"})
def contact_forces_rot(u, v, bi, bj, nrm, kn, kt, gn, gt, arm_i, arm_j, f, sz, want_sz, ax):
    """Add the forces and moments of the contact bonds to ``f`` (shape (n, 6)); ``sz`` as in
    :func:`md._kernels_acoustic.contact_forces`."""
    for b in range(bi.shape[0]):
        i = bi[b]
        j = bj[b]
        nx_ = nrm[b, 0]
        ny_ = nrm[b, 1]
        nz_ = nrm[b, 2]
        fx, fy, fz = _face_force(u, v, i, j, nx_, ny_, nz_, kn[b], kt[b], gn[b], gt[b],
                                 arm_i[b], arm_j[b])
        _apply_rot(f, sz, i, j, fx, fy, fz, nx_, ny_, nz_, arm_i[b], arm_j[b], want_sz, ax)


@njit(cache=True, fastmath={"contract"})
def lattice_forces_rot(u, table, first, lat_nrm, lat_kn, lat_kt, lat_arm, f, sz, want_sz, ax):
    """Add the forces and moments of the lattice bonds (undamped, acting at the bond
    midpoints, arm ``lat_arm[d]`` per direction) to ``f`` (shape (n, 6))."""
    for p in range(table.shape[0]):
        i = first + p
        for d in range(table.shape[1]):
            j = table[p, d]
            if j < 0:
                continue
            a = lat_arm[d]
            nx_ = lat_nrm[d, 0]
            ny_ = lat_nrm[d, 1]
            nz_ = lat_nrm[d, 2]
            fx, fy, fz = _face_force(u, u, i, j, nx_, ny_, nz_, lat_kn[d], lat_kt[d], 0.0, 0.0,
                                     a, a)
            _apply_rot(f, sz, i, j, fx, fy, fz, nx_, ny_, nz_, a, a, want_sz, ax)


@njit(cache=True)
def _bond_rows(rows, w, i, j, nx_, ny_, nz_, k_n, k_t, ai, aj):
    """Add the absolute row sums of one bond's 12 x 12 stiffness block, scaled on both sides
    by ``w`` (:math:`1/\\sqrt{m}` per degree of freedom), to ``rows``."""
    n = np.array((nx_, ny_, nz_))
    k = np.empty((3, 3))
    cross = np.zeros((3, 3))                 # [n]x: cross @ t = n x t
    cross[0, 1] = -nz_
    cross[0, 2] = ny_
    cross[1, 0] = nz_
    cross[1, 2] = -nx_
    cross[2, 0] = -ny_
    cross[2, 1] = nx_
    for a in range(3):
        for c in range(3):
            k[a, c] = (k_n - k_t) * n[a] * n[c] + (k_t if a == c else 0.0)
    B = np.zeros((3, 12))                    # d = B (u_i, theta_i, u_j, theta_j)
    for a in range(3):
        B[a, a] = -1.0
        B[a, 6 + a] = 1.0
        for c in range(3):
            B[a, 3 + c] = ai * cross[a, c]
            B[a, 9 + c] = aj * cross[a, c]
    K = B.T @ k @ B
    wb = np.empty(12)
    for a in range(6):
        wb[a] = w[i, a]
        wb[6 + a] = w[j, a]
    for r in range(12):
        s = 0.0
        for c in range(12):
            s += abs(K[r, c]) * wb[c]
        if r < 6:
            rows[i, r] += s * wb[r]
        else:
            rows[j, r - 6] += s * wb[r]


@njit(cache=True)
def gershgorin_rows_rot(w, bi, bj, nrm, kn, kt, arm_i, arm_j, table, first, lat_nrm,
                        lat_kn, lat_kt, lat_arm):
    """Row sums of :math:`|M^{-1/2} K M^{-1/2}|` per particle and degree of freedom (shape
    (n, 6); ``w`` is :math:`1/\\sqrt{m}` of every degree of freedom, mass or moment of
    inertia): their largest is the Gershgorin bound of :math:`\\omega_{max}^2` (the scaling
    keeps the bound independent of the units of translations and rotations)."""
    rows = np.zeros((w.shape[0], 6))
    for b in range(bi.shape[0]):
        _bond_rows(rows, w, bi[b], bj[b], nrm[b, 0], nrm[b, 1], nrm[b, 2], kn[b], kt[b],
                   arm_i[b], arm_j[b])
    for p in range(table.shape[0]):
        for d in range(table.shape[1]):
            j = table[p, d]
            if j >= 0:
                _bond_rows(rows, w, first + p, j, lat_nrm[d, 0], lat_nrm[d, 1], lat_nrm[d, 2],
                           lat_kn[d], lat_kt[d], lat_arm[d], lat_arm[d])
    return rows


@njit(cache=True)
def leapfrog_run_rot(u, v, inv_m, flag, slab, n_slabs, bi, bj, nrm, kn, kt, gn, gt, arm_i,
                     arm_j, table, first, lat_nrm, lat_kn, lat_kt, lat_arm, dt, t0, n_steps,
                     amplitude, duration, every, ax, record):
    """:func:`md._kernels_acoustic.leapfrog_run` with rotations: ``u``, ``v`` and ``inv_m``
    (inverse mass, then inverse moment of inertia) have shape (n, 6). ``flag`` prescribes the
    translations of the fixed (1) and driven (2) particles; every rotation is free."""
    n = u.shape[0]
    f = np.empty((n, 6))
    sz = np.empty(n)
    for step in range(n_steps):
        f[:] = 0.0
        want = step % every == 0
        if want:
            sz[:] = 0.0
        contact_forces_rot(u, v, bi, bj, nrm, kn, kt, gn, gt, arm_i, arm_j, f, sz, want, ax)
        lattice_forces_rot(u, table, first, lat_nrm, lat_kn, lat_kt, lat_arm, f, sz, want, ax)
        if want:
            record_slabs(record, step // every, slab, sz)
        t_next = t0 + (step + 1) * dt
        drive = amplitude if t_next < duration else 0.0
        for p in range(n):
            fl = flag[p]
            for a in range(3, 6):
                v[p, a] += dt * f[p, a] * inv_m[p, a]
                u[p, a] += dt * v[p, a]
            if fl == 0:
                for a in range(3):
                    v[p, a] += dt * f[p, a] * inv_m[p, a]
                    u[p, a] += dt * v[p, a]
            elif fl == 2:
                for a in range(3):
                    v[p, a] = 0.0
                    u[p, a] = 0.0
                u[p, ax] = drive
    return u, v
