"""Private numba kernels of the contact laws (SI units). Public wrappers are in md/contact.py."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["pair_force", "pair_force_damped", "damping_constant", "pair_damping",
           "accumulate_forces", "branch_vector"]


@njit(cache=True)
def branch_vector(x, i, j, lx, ly):
    """Vector from grain i to grain j, minimum image in x and y (periodic lengths lx, ly)."""
    dx = x[j, 0] - x[i, 0]
    dy = x[j, 1] - x[i, 1]
    dx -= lx * np.rint(dx / lx)
    dy -= ly * np.rint(dy / ly)
    return dx, dy, x[j, 2] - x[i, 2]


@njit(cache=True, inline="always")
def damping_constant(R_f, m_f, E_f, beta_c, v_ref):
    """Prefactor ``c`` of the normal damping force :math:`c\\sqrt{\\xi}\\,\\dot\\xi` of a pair:
    :math:`c = \\beta m_f^{2/5} v_{ref}^{-1/5} k^{3/5}` with :math:`k = \\tfrac43 E_f\\sqrt{R_f}`
    (restitution :math:`e(\\beta)` at the impact speed ``v_ref``; :mod:`md.contact`). It depends
    on the pair only, so a fixed pair list computes it once (:func:`pair_damping`)."""
    k_hertz = 4.0 / 3.0 * E_f * np.sqrt(R_f)
    return beta_c * m_f ** 0.4 * v_ref ** -0.2 * k_hertz ** 0.6


@njit(cache=True)
def pair_force(xi_n, nx, ny, nz, vrx, vry, vrz, zx, zy, zz, R_f, m_f, E_f, G_f, beta_c, v_ref,
               mu, dt):
    """Hertz–Mindlin force on particle j from particle i, and the updated tangential history.

    ``n = (nx, ny, nz)`` is the unit vector from i to j, ``xi_n > 0`` the overlap, ``vr`` the
    relative velocity of the contact point (j minus i), ``z`` the tangential spring elongation
    (history). Returns ``(fx, fy, fz, zx, zy, zz, fn)`` with ``f`` the force on j (minus on i) and
    ``fn >= 0`` the normal force magnitude. :func:`pair_force_damped` with the pair's
    :func:`damping_constant`.
    """
    return pair_force_damped(xi_n, nx, ny, nz, vrx, vry, vrz, zx, zy, zz, R_f,
                             damping_constant(R_f, m_f, E_f, beta_c, v_ref), E_f, G_f, mu, dt)


@njit(cache=True)
def pair_force_damped(xi_n, nx, ny, nz, vrx, vry, vrz, zx, zy, zz, R_f, c, E_f, G_f, mu, dt):
    """:func:`pair_force` given the pair's damping prefactor ``c`` (:func:`damping_constant`)."""
    root = np.sqrt(xi_n * R_f)
    kappa_n = 4.0 / 3.0 * E_f * root                       # F_el = kappa_n * xi
    v_n = vrx * nx + vry * ny + vrz * nz                   # > 0: separating
    xi_dot = -v_n
    fn = kappa_n * xi_n + c * np.sqrt(xi_n) * xi_dot
    if fn < 0.0:
        fn = 0.0                                           # no cohesion
    # Tangential: Mindlin spring 8 G_f a (a = sqrt(R_f xi)), history rotated into the tangent plane.
    vtx = vrx - v_n * nx
    vty = vry - v_n * ny
    vtz = vrz - v_n * nz
    zn = zx * nx + zy * ny + zz * nz
    zx = zx - zn * nx + vtx * dt
    zy = zy - zn * ny + vty * dt
    zz = zz - zn * nz + vtz * dt
    kappa_s = 8.0 * G_f * root
    gamma_s = c * np.sqrt(xi_n) * (2.0 / 3.0)              # shear damping, same time scale
    ftx = -kappa_s * zx - gamma_s * vtx
    fty = -kappa_s * zy - gamma_s * vty
    ftz = -kappa_s * zz - gamma_s * vtz
    ft = np.sqrt(ftx * ftx + fty * fty + ftz * ftz)
    cap = mu * fn
    if ft > cap:
        # Coulomb: slide; the force is capped at mu |F_n| and the spring rescaled to match.
        if ft > 0.0:
            s = cap / ft
            ftx *= s
            fty *= s
            ftz *= s
        if kappa_s > 0.0:
            zx = -(ftx + gamma_s * vtx) / kappa_s
            zy = -(fty + gamma_s * vty) / kappa_s
            zz = -(ftz + gamma_s * vtz) / kappa_s
    return (fn * nx + ftx, fn * ny + fty, fn * nz + ftz, zx, zy, zz, fn)


@njit(cache=True)
def pair_damping(r, m, pairs, E_f, beta_c, v_ref):
    """:func:`damping_constant` of every pair of a pair list (radii ``r``, masses ``m``)."""
    c = np.empty(pairs.shape[0])
    for p in range(pairs.shape[0]):
        i = pairs[p, 0]
        j = pairs[p, 1]
        R_f = r[i] * r[j] / (r[i] + r[j])
        m_f = m[i] * m[j] / (m[i] + m[j])
        c[p] = damping_constant(R_f, m_f, E_f, beta_c, v_ref)
    return c


@njit(cache=True)
def accumulate_forces(x, v, w, r, pairs, hist, box_l, E_f, G_f, damping, mu, dt, force,
                      torque):
    """Forces and torques of all contacts of a pair list (periodic in x and y).

    ``pairs`` (M, 2) int32, ``hist`` (M, 3) tangential histories (updated in place; zeroed for
    pairs not in contact), ``damping`` (M,) the pairs' damping prefactors
    (:func:`pair_damping`, computed once per list: the three powers per contact and step were
    half the cost of this loop). ``force``, ``torque`` (N, 3) are overwritten.
    """
    force[:, :] = 0.0
    torque[:, :] = 0.0
    lx = box_l[0]
    ly = box_l[1]
    for p in range(pairs.shape[0]):
        i = pairs[p, 0]
        j = pairs[p, 1]
        dx, dy, dz = branch_vector(x, i, j, lx, ly)
        d = np.sqrt(dx * dx + dy * dy + dz * dz)
        xi_n = r[i] + r[j] - d
        if xi_n <= 0.0:
            hist[p, 0] = 0.0
            hist[p, 1] = 0.0
            hist[p, 2] = 0.0
            continue
        nx = dx / d
        ny = dy / d
        nz = dz / d
        # Contact-point velocity of j relative to i: v_j - v_i - (r_i w_i + r_j w_j) x n.
        ax = r[i] * w[i, 0] + r[j] * w[j, 0]
        ay = r[i] * w[i, 1] + r[j] * w[j, 1]
        az = r[i] * w[i, 2] + r[j] * w[j, 2]
        vrx = v[j, 0] - v[i, 0] - (ay * nz - az * ny)
        vry = v[j, 1] - v[i, 1] - (az * nx - ax * nz)
        vrz = v[j, 2] - v[i, 2] - (ax * ny - ay * nx)
        R_f = r[i] * r[j] / (r[i] + r[j])
        fx, fy, fz, zx, zy, zz, fn = pair_force_damped(xi_n, nx, ny, nz, vrx, vry, vrz,
                                                       hist[p, 0], hist[p, 1], hist[p, 2], R_f,
                                                       damping[p], E_f, G_f, mu, dt)
        hist[p, 0] = zx
        hist[p, 1] = zy
        hist[p, 2] = zz
        force[j, 0] += fx
        force[j, 1] += fy
        force[j, 2] += fz
        force[i, 0] -= fx
        force[i, 1] -= fy
        force[i, 2] -= fz
        # Torque of the tangential part about each centre: (-r n) x f on j, (r n) x (-f) on i.
        ftx = fx - fn * nx
        fty = fy - fn * ny
        ftz = fz - fn * nz
        cx = ny * ftz - nz * fty
        cy = nz * ftx - nx * ftz
        cz = nx * fty - ny * ftx
        torque[j, 0] -= r[j] * cx
        torque[j, 1] -= r[j] * cy
        torque[j, 2] -= r[j] * cz
        torque[i, 0] -= r[i] * cx
        torque[i, 1] -= r[i] * cy
        torque[i, 2] -= r[i] * cz
