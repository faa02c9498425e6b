"""Private numba kernels of the time integration (velocity Verlet, SI units)."""

from __future__ import annotations

import numpy as np
from numba import njit

from ._kernels_contact import accumulate_forces, branch_vector, pair_damping, pair_force

__all__ = ["verlet_run", "kick_drift", "kick", "elastic_energy", "floor_forces"]


@njit(cache=True)
def floor_forces(x, v, w, r, m, z_floor, wall_hist, E_f, G_f, beta_c, v_ref, mu, dt, force,
                 torque):
    """Add the Hertz–Mindlin forces of a rigid flat floor at ``z_floor`` (same material, sphere on
    a half-space: R_f = r, m_f = m). ``wall_hist`` (N, 3) holds the tangential histories."""
    for j in range(x.shape[0]):
        xi = r[j] - (x[j, 2] - z_floor)
        if xi <= 0.0:
            wall_hist[j, 0] = 0.0
            wall_hist[j, 1] = 0.0
            wall_hist[j, 2] = 0.0
            continue
        # n points from the floor into the grain; contact point at -r n from the centre.
        vrx = v[j, 0] - r[j] * w[j, 1]
        vry = v[j, 1] + r[j] * w[j, 0]
        vrz = v[j, 2]
        fx, fy, fz, zx, zy, zz, fn = pair_force(xi, 0.0, 0.0, 1.0, vrx, vry, vrz, wall_hist[j, 0],
                                                wall_hist[j, 1], wall_hist[j, 2], r[j], m[j],
                                                E_f, G_f, beta_c, v_ref, mu, dt)
        wall_hist[j, 0] = zx
        wall_hist[j, 1] = zy
        wall_hist[j, 2] = zz
        force[j, 0] += fx
        force[j, 1] += fy
        force[j, 2] += fz
        # Torque (-r n) x f_t with n = z: -r (n x f_t) = -r (-f_ty, f_tx, 0).
        torque[j, 0] += r[j] * fy
        torque[j, 1] -= r[j] * fx


@njit(cache=True)
def elastic_energy(x, r, pairs, box_l, E_f):
    """Hertz energy 8/15 E_f sqrt(R_f) xi^(5/2) summed over the contacts of a pair list."""
    total = 0.0
    for p in range(pairs.shape[0]):
        i = pairs[p, 0]
        j = pairs[p, 1]
        dx, dy, dz = branch_vector(x, i, j, box_l[0], box_l[1])
        xi = r[i] + r[j] - np.sqrt(dx * dx + dy * dy + dz * dz)
        if xi > 0.0:
            R_f = r[i] * r[j] / (r[i] + r[j])
            total += 8.0 / 15.0 * E_f * np.sqrt(R_f) * xi ** 2.5
    return total


@njit(cache=True, inline="always")
def kick_drift(x, v, w, m, inertia, force, torque, dt, gravity_z, fixed, has_fixed):
    """First half of a velocity-Verlet step: half kick by ``force``, ``torque`` and gravity,
    then the drift; grains with ``fixed[i]`` (where ``has_fixed``) only drift."""
    for i in range(x.shape[0]):
        if has_fixed and fixed[i]:
            for a in range(3):
                x[i, a] += dt * v[i, a]
            continue
        for a in range(3):
            v[i, a] += 0.5 * dt * force[i, a] / m[i]
            w[i, a] += 0.5 * dt * torque[i, a] / inertia[i]
            x[i, a] += dt * v[i, a]
        v[i, 2] += 0.5 * dt * gravity_z


@njit(cache=True, inline="always")
def kick(v, w, m, inertia, force, torque, dt, gravity_z, drag, fixed, has_fixed):
    """Second half of a velocity-Verlet step: the drag ``-drag m v`` added to ``force``, then
    the half kick; grains with ``fixed[i]`` (where ``has_fixed``) keep their velocities."""
    for i in range(v.shape[0]):
        if has_fixed and fixed[i]:
            continue
        for a in range(3):
            force[i, a] -= drag * m[i] * v[i, a]
            v[i, a] += 0.5 * dt * force[i, a] / m[i]
            w[i, a] += 0.5 * dt * torque[i, a] / inertia[i]
        v[i, 2] += 0.5 * dt * gravity_z


@njit(cache=True)
def verlet_run(x, v, w, r, m, pairs, hist, box_l, E_f, G_f, beta_c, v_ref, mu, dt, n_steps,
               gravity_z, record_every, energy, z_floor=-np.inf, wall_hist=np.zeros((0, 3)),
               drag=0.0, fixed=np.zeros(0, dtype=np.bool_)):
    """Advance ``n_steps`` of velocity Verlet in place (translation and rotation of spheres).

    Forces are evaluated with the half-step velocities (the usual choice for dissipative
    contacts). Every ``record_every`` steps the total energy (kinetic + rotational + Hertz +
    gravitational) is written to ``energy[k]``. Returns the number of records written. With a
    finite ``z_floor`` a rigid floor acts (``wall_hist`` (N, 3)); ``drag`` (1/s) adds the viscous
    force ``-drag m v`` of the settling fluid. Grains with ``fixed[i]`` keep their velocities
    (prescribed motion, e.g. the frozen end slabs of a compaction).
    """
    use_floor = np.isfinite(z_floor)
    has_fixed = fixed.shape[0] == x.shape[0]
    n = x.shape[0]
    force = np.zeros((n, 3))
    torque = np.zeros((n, 3))
    inertia = np.empty(n)
    for i in range(n):
        inertia[i] = 0.4 * m[i] * r[i] * r[i]
    damping = pair_damping(r, m, pairs, E_f, beta_c, v_ref)     # the list is fixed in this call
    accumulate_forces(x, v, w, r, pairs, hist, box_l, E_f, G_f, damping, mu, dt, force, torque)
    if use_floor:
        floor_forces(x, v, w, r, m, z_floor, wall_hist, E_f, G_f, beta_c, v_ref, mu, dt, force,
                     torque)
    k = 0
    for step in range(n_steps):
        if record_every > 0 and step % record_every == 0 and k < energy.shape[0]:
            e = elastic_energy(x, r, pairs, box_l, E_f)
            for i in range(n):
                e += 0.5 * m[i] * (v[i, 0] ** 2 + v[i, 1] ** 2 + v[i, 2] ** 2)
                e += 0.5 * inertia[i] * (w[i, 0] ** 2 + w[i, 1] ** 2 + w[i, 2] ** 2)
                e -= m[i] * gravity_z * x[i, 2]
            energy[k] = e
            k += 1
        kick_drift(x, v, w, m, inertia, force, torque, dt, gravity_z, fixed, has_fixed)
        accumulate_forces(x, v, w, r, pairs, hist, box_l, E_f, G_f, damping, mu, dt, force,
                          torque)
        if use_floor:
            floor_forces(x, v, w, r, m, z_floor, wall_hist, E_f, G_f, beta_c, v_ref, mu, dt,
                         force, torque)
        kick(v, w, m, inertia, force, torque, dt, gravity_z, drag, fixed, has_fixed)
    return k
