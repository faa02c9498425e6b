"""Static moduli of the linearised acoustic stage: the long-wave limit of the pulse test by a
sparse solve on the same operator (García & Medina, Sect. III G; the cross-check of
:func:`md.pulse_test`).

SI units. The sample is the :class:`md.AcousticSystem` cut into slabs along z; the bottom slab
is displaced, the top slab held, and the free particles on the load path relax.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .acoustic import AcousticSystem

__all__ = ["StaticModulus", "static_modulus"]

_AXIS = {"p": 2, "s": 0}


def _wave_axis(wave) -> int:
    if wave not in _AXIS:
        raise ValueError(f"wave must be 'p' or 's'; got {wave!r}")
    return _AXIS[wave]


@dataclass(frozen=True)
class StaticModulus:
    """Result of :func:`static_modulus`.

    Attributes
    ----------
    modulus : float
        P-wave (uniaxial-strain) modulus or shear modulus, Pa.
    density : float
        Bulk density of the sample (total mass over box area times height), kg/m³.
    velocity : float
        :math:`\\sqrt{M/\\rho}`, m/s.
    strain, stress : float
        Strain of the interior (:math:`\\partial u_z/\\partial z`, negative in compression, or
        :math:`\\partial u_x/\\partial z`) and the transmitted stress, Pa.
    iterations : int
        Conjugate-gradient iterations.
    """

    modulus: float
    density: float
    velocity: float
    strain: float
    stress: float
    iterations: int


def _prescribed(system: AcousticSystem):
    slab, n_slabs = system.slabs()
    if n_slabs < 4:
        raise ValueError(f"the sample holds {n_slabs} slab(s) of {system.slab_thickness:.3g} m "
                         "along z; the pulse test needs at least 4 (source, two detectors, "
                         "fixed end): use a taller sample or thinner slabs")
    flag = np.zeros(system.n_particles, np.int8)
    flag[slab == n_slabs - 1] = 1
    flag[slab == 0] = 2
    return slab, n_slabs, flag


def _load_path(system: AcousticSystem, flag):
    """Particles bonded (directly or through others) to the driven or the fixed slab; with
    rotations, less the dangling ones: a free particle held by a single bond carries no load at
    equilibrium (nothing else acts on it, so its bond force is zero), nor does a chain of them.
    They are pruned, leaf by leaf, before the solve, since with rotations such a particle is a
    mechanism (it turns about its contact point at no cost) that a Jacobi-preconditioned solve
    would move far. (Translations only, nothing is pruned: the results of the source's
    linearisation stay those of the committed studies.)"""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = system.n_particles
    li, lj, _ = system._lattice_list()
    i = np.concatenate([system.bond_i, li])
    j = np.concatenate([system.bond_j, lj])
    graph = sp.coo_matrix((np.ones(i.size, np.int8), (i, j)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    anchored = np.unique(label[flag != 0])
    keep = np.isin(label, anchored)
    while system.rotations:
        live = keep[i] & keep[j]
        degree = np.bincount(i[live], minlength=n) + np.bincount(j[live], minlength=n)
        leaf = keep & (flag == 0) & (degree <= 1)
        if not leaf.any():
            break
        keep &= ~leaf
    return keep


def _bonds_among(system: AcousticSystem, keep):
    """The system with only the bonds whose two particles are both in ``keep``."""
    import dataclasses

    own = keep[system.bond_i] & keep[system.bond_j]
    table = system.lattice_neighbors.copy()
    rows = keep[system.n_grains:][:, None] & keep[np.maximum(table, 0)]
    table[~rows] = -1
    sub = {f: getattr(system, f)[own] for f in ("bond_i", "bond_j", "bond_normal", "bond_kn",
                                                "bond_kt", "bond_gn", "bond_gt")}
    if system.rotations:
        sub.update(arm_i=system.arm_i[own], arm_j=system.arm_j[own])
    return dataclasses.replace(system, lattice_neighbors=table, **sub)


def static_modulus(system: AcousticSystem, wave="p", *, rtol=1e-10,
                   maxiter=None, parallel=False) -> StaticModulus:
    """P-wave (or shear) modulus of the linearised sample by a sparse solve.

    The bottom slab is displaced by a small :math:`u_z` (``wave="p"``, uniaxial strain) or
    :math:`u_x` (``wave="s"``, simple shear), all of its particles alike, the top slab is held
    fixed, the periodic box keeps the lateral strain zero (with rotations,
    :attr:`md.AcousticSystem.rotations`, only the end slabs' translations are prescribed and
    every rotation is free); :math:`K_{ff} u_f = -K_{fp} u_p` is
    solved by Jacobi-preconditioned conjugate gradients on the free particles bonded, directly or
    through others, to an end slab (rattlers and floating cement clusters drop out). The stress is
    the reaction on the fixed slab over the box area (the same through every horizontal section);
    the strain is the slope of a least-squares line through the centres of mass of the interior
    slabs (their load-path particles) in :math:`(z, u_z)` — the part of the sample the pulse test's
    detectors see. ``rtol`` is the CG tolerance, in (0, 1), ``maxiter`` its iteration cap
    (an integer >= 1; default 20 per free degree of freedom); ``parallel`` applies the operator
    with the multi-threaded gather kernels (:meth:`md.AcousticSystem.forces`).
    """
    import scipy.sparse.linalg as spla

    if not 0.0 < rtol < 1.0:
        raise ValueError(f"rtol must lie in (0, 1); got {rtol}")
    if maxiter is not None and (isinstance(maxiter, bool) or int(maxiter) != maxiter
                                or maxiter < 1):
        raise ValueError(f"maxiter must be an integer >= 1 or None; got {maxiter!r}")
    slab, n_slabs, flag = _prescribed(system)
    n = system.n_particles
    amp = 1e-6 * system.slab_thickness
    dof = system.dof
    u_p = np.zeros((n, dof))
    ax = _wave_axis(wave)
    u_p[flag == 2, ax] = amp
    connected = _load_path(system, flag)
    system = _bonds_among(system, connected | (flag != 0))
    diag = system.stiffness_diagonal()      # zero: no stiffness, not solved for
    free = np.zeros((n, dof), bool)         # the end slabs' translations are prescribed
    free[:, :3] = ((flag == 0) & connected)[:, None]
    free[:, 3:] = connected[:, None]        # rotations, where there are any, are all free
    free &= diag > 0
    free_idx = np.flatnonzero(free.ravel())
    if free_idx.size == 0:
        raise ValueError("no free particle between the end slabs is bonded to them")
    b = system.forces(u_p, parallel=parallel).ravel()[free_idx]

    def matvec(y):
        u = np.zeros(dof * n)
        u[free_idx] = y
        return -system.forces(u, parallel=parallel).ravel()[free_idx]

    op = spla.LinearOperator((free_idx.size,) * 2, matvec=matvec, dtype=float)
    # Block-Jacobi: each particle's own block of K on its free degrees of freedom, inverted
    # (a pseudo-inverse where a rotation has no stiffness). On a cemented 2 700-particle sample
    # with rotations it takes 2.8 times fewer iterations than the diagonal.
    blocks = system.stiffness_blocks()
    held = ~free
    blocks[held[:, :, None] | held[:, None, :]] = 0.0
    blocks[:, np.arange(dof), np.arange(dof)] += held
    # Scaled to a unit diagonal first (forces and moments differ by many orders of magnitude),
    # so that the cut-off of the pseudo-inverse is relative within each kind.
    scale = 1.0 / np.sqrt(np.diagonal(blocks, axis1=1, axis2=2))
    unit = blocks * scale[:, :, None] * scale[:, None, :]
    inverse = np.linalg.pinv(unit, rcond=1e-10, hermitian=True) \
        * scale[:, :, None] * scale[:, None, :]

    def precondition(y):
        r = np.zeros(dof * n)
        r[free_idx] = y
        return np.einsum("pij,pj->pi", inverse, r.reshape(n, dof)).ravel()[free_idx]

    pre = spla.LinearOperator((free_idx.size,) * 2, matvec=precondition, dtype=float)
    count = [0]

    def callback(_):
        count[0] += 1

    # The solver's vector operations are short: one BLAS thread. More only wait on each other,
    # and on a busy machine (several solves at once) a dot product of 10^4 numbers took 16 ms
    # instead of 12 us.
    from threadpoolctl import threadpool_limits

    with threadpool_limits(limits=1, user_api="blas"):
        y, info = spla.cg(op, b, rtol=rtol, atol=0.0, M=pre,
                          maxiter=maxiter or 20 * free_idx.size, callback=callback)
    if info != 0:
        raise RuntimeError(f"static solve did not converge in {count[0]} CG iterations")
    u = u_p.ravel().copy()
    u[free_idx] = y
    u = u.reshape(n, dof)
    f = system.forces(u)
    area = system.box.lx * system.box.ly
    stress = float(np.sum(f[flag == 1, ax])) / area       # push on the fixed top slab
    # Strain of the interior: slab centres of mass (load-path particles) between the end slabs.
    keep = connected & (flag == 0)
    m = system.masses * keep
    inner = np.arange(1, n_slabs - 1)
    mass = np.bincount(slab, weights=m, minlength=n_slabs)[inner]
    zc = np.bincount(slab, weights=m * system.positions[:, 2], minlength=n_slabs)[inner]
    uc = np.bincount(slab, weights=m * u[:, ax], minlength=n_slabs)[inner]
    ok = mass > 0
    if ok.sum() < 2:
        raise ValueError("fewer than two interior slabs hold particles on the load path")
    slope = float(np.polyfit(zc[ok] / mass[ok], uc[ok] / mass[ok], 1)[0])
    z0, z1 = system.extent
    density = float(system.masses.sum()) / (area * (z1 - z0))
    modulus = stress / -slope
    if not modulus > 0:
        raise RuntimeError(f"the sample has no {wave.upper()}-wave stiffness between the end slabs "
                           f"(no load-bearing path; stress {stress:.3g} Pa, interior strain "
                           f"{slope:.3g})")
    return StaticModulus(modulus, density, math.sqrt(modulus / density), slope, stress,
                         count[0])
