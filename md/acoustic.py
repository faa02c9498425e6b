"""The acoustic stage: the pack and its cement linearised about mechanical equilibrium, a sparse
linear system :math:`M\\ddot u + D\\dot u + K u = 0` (García & Medina, Sects. III F–G).

SI units. Particles are the grains (first ``n_grains``) and the cement particles (one per
cemented cell, mass :math:`m_c = \\rho_c c_w^3`, eq. 9). Three kinds of bonds:

* grain–grain contacts (eqs. 4–5): the Hertz contact linearised at its equilibrium overlap
  :math:`\\xi_0` with the contact area held fixed (no sliding), normal stiffness
  :math:`k_n = \\partial F_n/\\partial\\xi = 2E_f a` and Mindlin tangential stiffness
  :math:`k_s = 8 G_f a = 4 a G/(2-\\nu)`, :math:`a = \\sqrt{R_f\\xi_0}`; translations only, as in
  the paper's eqs. 4–5 (:math:`\\mathbf d = \\mathbf d_2 - \\mathbf d_1`), without the geometric
  stiffness of the pre-stress. ``normal_stiffness="secant"`` takes instead the source's literal
  eq. 4, whose :math:`\\kappa_n` is that of eq. 1, :math:`\\tfrac43 E_f a` (the secant
  :math:`F_n/\\xi`, two thirds of the tangent);
* cement–cement lattice springs to the 18 nearest lattice neighbours (eq. 6, constants from
  :func:`md.cement.lattice_constants`);
* grain–cement contacts: eq. 4 along the line from the grain centre to the cell centre, with
  the stiffness of the interface rule (:mod:`md.interface`): by default (``"facet"``) the grain
  under each cemented patch facing one neighbour is a flat punch on a half-space shared among
  the patch's cells, which converges as the lattice is refined; ``interface="paper"`` is the
  source's per-cell contact of diameter :math:`c_w` with mixed moduli, whose stiffness grows
  with :math:`\\Omega` (also two thirds of it in the normal direction with
  ``normal_stiffness="secant"``).

Contacts carry dashpots :math:`\\gamma = 2\\zeta\\sqrt{k\\,m_{red}}` with the damping ratio
:math:`\\zeta = -\\ln e/\\sqrt{\\pi^2 + \\ln^2 e}` of a linear oscillator with restitution ``e``
(0.9 in the paper, normal and tangential); lattice springs are undamped.

:meth:`AcousticSystem.stiffness_matrix` (and damping, mass) assemble the operator as
``scipy.sparse`` matrices; the pulse test (:mod:`md.pulse`) applies the same operator bond by
bond in a numba kernel (no matrix is stored), which the tests check against the assembled
matrix; :mod:`md.static` solves it for the static moduli.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from .cement import (HARD_CEMENT, LATTICE_OFFSETS, CementLattice, CementMaterial,
                     lattice_constants)
from .interface import (INTERFACES, bond_partners, film_bridges, film_thickness,
                        interface_stiffness, nearest_grain)
from .space import Box, minimum_image
from .state import Pack

__all__ = ["AcousticSystem", "acoustic_system", "cement_block", "static_modulus",
           "pulse_test", "damping_ratio", "StaticModulus", "dashpots", "NORMAL_STIFFNESS",
           "grain_cement_arms"]

#: Normal stiffness of the Hertzian bonds of eq. 4: the tangent (default) or the source's secant.
NORMAL_STIFFNESS = ("tangent", "secant")
#: k_n / (E_f a) of each choice: dF/dxi of F = (4/3) E_f sqrt(R) xi^(3/2), and F/xi (eq. 1).
_NORMAL_FACTOR = {"tangent": 2.0, "secant": 4.0 / 3.0}

_LATTICE_NORMALS = LATTICE_OFFSETS / np.linalg.norm(LATTICE_OFFSETS, axis=1)[:, None]
_LATTICE_LENGTH2 = np.sum(LATTICE_OFFSETS**2, axis=1).astype(float)     # |x|^2 / c_w^2


def _cross_matrices(n):
    """The matrices :math:`[\\hat n]_\\times` of the unit vectors ``n`` (shape (m, 3)):
    ``cross[b] @ t`` is ``n[b] x t``."""
    cross = np.zeros((n.shape[0], 3, 3))
    cross[:, 0, 1], cross[:, 0, 2] = -n[:, 2], n[:, 1]
    cross[:, 1, 0], cross[:, 1, 2] = n[:, 2], -n[:, 0]
    cross[:, 2, 0], cross[:, 2, 1] = -n[:, 1], n[:, 0]
    return cross


def damping_ratio(restitution) -> float:
    """Damping ratio :math:`\\zeta = -\\ln e / \\sqrt{\\pi^2 + \\ln^2 e}` of a linear spring–dashpot
    contact whose head-on impact has restitution ``e`` (half a period of the damped oscillator:
    :math:`e = \\exp(-\\pi\\zeta/\\sqrt{1-\\zeta^2})`)."""
    if not 0.0 < restitution <= 1.0:
        raise ValueError(f"restitution must lie in (0, 1]; got {restitution}")
    ln = math.log(restitution)
    return -ln / math.sqrt(math.pi**2 + ln**2)


def dashpots(kn, kt, m_i, m_j, zeta):
    """Normal and tangential dashpots :math:`2\\zeta\\sqrt{k\\,m_{ij}}` of springs ``kn``, ``kt``
    between masses ``m_i`` and ``m_j`` (reduced mass :math:`m_{ij}`), damping ratio ``zeta``
    (:func:`damping_ratio`), N s/m."""
    m_red = m_i * m_j / (m_i + m_j)
    return 2.0 * zeta * np.sqrt(kn * m_red), 2.0 * zeta * np.sqrt(kt * m_red)


@dataclass(frozen=True)
class AcousticSystem:
    """Particles and bonds of the linearised acoustic stage.

    Attributes
    ----------
    positions : ndarray, shape (n, 3)
        Equilibrium positions, m (grains first, then cement particles at their cell centres).
    masses : ndarray, shape (n,)
        kg.
    n_grains : int
    box : Box
        Periodic lengths in x and y.
    bond_i, bond_j : ndarray of int32
        Contact bonds (grain–grain, grain–cement) between particles ``i`` and ``j``.
    bond_normal : ndarray, shape (m, 3)
        Unit vectors from ``i`` to ``j``.
    bond_kn, bond_kt, bond_gn, bond_gt : ndarray
        Normal and tangential stiffnesses (N/m) and dashpots (N s/m).
    lattice_neighbors : ndarray of int32, shape (n - n_grains, 9)
        Cement–cement bonds as a neighbour table: row ``p`` belongs to particle
        ``n_grains + p``, column ``d`` holds the particle index of its neighbour at the
        half-stencil offset ``d`` (row of :data:`md.cement.LATTICE_OFFSETS`) or −1 (no bond);
        each bond is stored once. :attr:`lattice_i`, :attr:`lattice_j` and
        :attr:`lattice_dir` give the same bonds as a list.
    lattice_kn, lattice_kt : ndarray, shape (9,)
        Normal and tangential stiffness per direction: :math:`C_n + C/|x|^2` and :math:`C/|x|^2`.
    slab_thickness : float
        Thickness of the detector slabs along z, m.
    metadata : dict
    arm_i, arm_j : ndarray, optional
        With rotations: distances from the centres of ``bond_i`` and ``bond_j`` to the
        contact point of every contact bond, m (:mod:`md._kernels_rotation`); None without.
    lattice_arm : ndarray, shape (9,), optional
        With rotations: half the length of the lattice bonds of each stencil direction, m.
    inertia : ndarray, shape (n,), optional
        With rotations: moments of inertia, kg m² (:math:`\\tfrac25 mR^2` for a grain,
        :math:`\\tfrac16 m c_w^2` for a cement cube).
    """

    positions: np.ndarray
    masses: np.ndarray
    n_grains: int
    box: Box
    bond_i: np.ndarray
    bond_j: np.ndarray
    bond_normal: np.ndarray
    bond_kn: np.ndarray
    bond_kt: np.ndarray
    bond_gn: np.ndarray
    bond_gt: np.ndarray
    lattice_neighbors: np.ndarray
    lattice_kn: np.ndarray
    lattice_kt: np.ndarray
    slab_thickness: float
    extent: tuple = (0.0, 0.0)
    metadata: dict = field(default_factory=dict)
    arm_i: np.ndarray | None = None
    arm_j: np.ndarray | None = None
    lattice_arm: np.ndarray | None = None
    inertia: np.ndarray | None = None

    @property
    def n_particles(self) -> int:
        """Grains plus cement particles."""
        return int(self.masses.shape[0])

    @property
    def rotations(self) -> bool:
        """Whether the particles rotate (6 degrees of freedom each) or only translate (3)."""
        return self.arm_i is not None

    @property
    def dof(self) -> int:
        """Degrees of freedom per particle: 6 with rotations, else 3."""
        return 6 if self.rotations else 3

    @property
    def dof_masses(self) -> np.ndarray:
        """Mass (kg) of every translation and moment of inertia (kg m²) of every rotation,
        shape (n, dof)."""
        m = np.repeat(self.masses[:, None], 3, axis=1)
        if not self.rotations:
            return m
        return np.concatenate([m, np.repeat(self.inertia[:, None], 3, axis=1)], axis=1)

    def slabs(self):
        """Slab index of every particle and the number of slabs (the top slab takes the rest)."""
        z0, z1 = self.extent
        n_slabs = max(int((z1 - z0) // self.slab_thickness), 1)
        slab = np.floor((self.positions[:, 2] - z0) / self.slab_thickness).astype(np.int64)
        return np.clip(slab, 0, n_slabs - 1), n_slabs

    def _lattice_list(self):
        p, d = np.nonzero(self.lattice_neighbors >= 0)
        return ((p + self.n_grains).astype(np.int32), self.lattice_neighbors[p, d],
                d.astype(np.int8))

    @property
    def lattice_i(self) -> np.ndarray:
        """First particle of every lattice bond (int32), in table order."""
        return self._lattice_list()[0]

    @property
    def lattice_j(self) -> np.ndarray:
        """Second particle of every lattice bond (int32), in table order."""
        return self._lattice_list()[1]

    @property
    def lattice_dir(self) -> np.ndarray:
        """Stencil direction of every lattice bond (int8), in table order."""
        return self._lattice_list()[2]

    @property
    def n_lattice_bonds(self) -> int:
        """Number of cement–cement bonds."""
        return int(np.count_nonzero(self.lattice_neighbors >= 0))

    def _kernel_args(self):
        if self.rotations:
            return (self.bond_i, self.bond_j, self.bond_normal, self.bond_kn, self.bond_kt,
                    self.bond_gn, self.bond_gt, self.arm_i, self.arm_j, self.lattice_neighbors,
                    self.n_grains, _LATTICE_NORMALS, self.lattice_kn, self.lattice_kt,
                    self.lattice_arm)
        return (self.bond_i, self.bond_j, self.bond_normal, self.bond_kn, self.bond_kt,
                self.bond_gn, self.bond_gt, self.lattice_neighbors, self.n_grains,
                _LATTICE_NORMALS, self.lattice_kn, self.lattice_kt)

    @cached_property
    def gather_tables(self):
        """Per-particle tables of the multi-threaded kernels (:mod:`md._kernels_parallel`):
        contact bonds as CSR ``(start, bond, sign)`` and the 18-column lattice table."""
        from ._kernels_parallel import contact_lists, full_lattice_table

        full = np.empty((self.lattice_neighbors.shape[0], 18), np.int32)
        full_lattice_table(self.lattice_neighbors, self.n_grains, full)
        return (*contact_lists(self.n_particles, self.bond_i, self.bond_j), full)

    def gather_args(self):
        """Arguments of :func:`md._kernels_parallel.gather_forces` after ``u, v``."""
        start, bond, sign, full = self.gather_tables
        return (start, bond, sign, self.bond_i, self.bond_j, self.bond_normal, self.bond_kn,
                self.bond_kt, self.bond_gn, self.bond_gt, full, self.n_grains, _LATTICE_NORMALS,
                self.lattice_kn, self.lattice_kt)

    def forces(self, u, v=None, *, parallel=False, out=None) -> np.ndarray:
        """Bond forces :math:`-(K u + D v)` on every particle, shape (n, 3) — with rotations
        (n, 6): forces (N), then moments (N m) — for displacements ``u`` (and rotations);
        ``parallel`` uses the multi-threaded gather kernels (numba threads; translations
        only). ``out``, a C-contiguous float array of n × dof numbers, receives the forces
        (overwritten) and is returned as an (n, dof) view: an iterative solve then allocates
        nothing per step."""
        from ._kernels_acoustic import contact_forces, lattice_forces

        u = np.ascontiguousarray(u, dtype=float).reshape(self.n_particles, self.dof)
        v = np.zeros_like(u) if v is None else \
            np.ascontiguousarray(v, dtype=float).reshape(self.n_particles, self.dof)
        if out is None:
            f = np.zeros_like(u)
        else:
            if (out.dtype != np.float64 or out.size != u.size
                    or not out.flags.c_contiguous):
                raise ValueError(f"out must be a C-contiguous float64 array of {u.size} "
                                 f"numbers; got {out.dtype} of {out.size}")
            f = out.reshape(u.shape)
            f.fill(0.0)
        sz = np.zeros(0)
        if self.rotations:
            from ._kernels_rotation import contact_forces_rot, lattice_forces_rot

            if parallel:
                raise ValueError("the multi-threaded kernels move particles by translations "
                                 "only; use parallel=False for a system with rotations")
            contact_forces_rot(u, v, self.bond_i, self.bond_j, self.bond_normal, self.bond_kn,
                               self.bond_kt, self.bond_gn, self.bond_gt, self.arm_i,
                               self.arm_j, f, sz, False, 2)
            lattice_forces_rot(u, self.lattice_neighbors, self.n_grains, _LATTICE_NORMALS,
                               self.lattice_kn, self.lattice_kt, self.lattice_arm, f, sz,
                               False, 2)
            return f
        if parallel:
            from ._kernels_parallel import gather_forces

            gather_forces(u, v, *self.gather_args(), f, np.zeros(self.n_particles), False, 2)
            return f
        contact_forces(u, v, self.bond_i, self.bond_j, self.bond_normal, self.bond_kn,
                       self.bond_kt, self.bond_gn, self.bond_gt, f, sz, False, 2)
        lattice_forces(u, self.lattice_neighbors, self.n_grains, _LATTICE_NORMALS,
                       self.lattice_kn, self.lattice_kt, f, sz, False, 2)
        return f

    def _bonds(self, kn, kt, lattice_kn, lattice_kt):
        """All bonds as ``(i, j, normal, k_n, k_t)``: the contact bonds with constants ``kn, kt``,
        then the lattice bonds with per-direction constants ``lattice_kn, lattice_kt``."""
        li, lj, ld = self._lattice_list()
        ld = ld.astype(np.int64)
        return (np.concatenate([self.bond_i, li]).astype(np.int64),
                np.concatenate([self.bond_j, lj]).astype(np.int64),
                np.concatenate([self.bond_normal, _LATTICE_NORMALS[ld]]),
                np.concatenate([kn, lattice_kn[ld]]), np.concatenate([kt, lattice_kt[ld]]))

    def _arms(self):
        """Contact-point arms of all bonds in :meth:`_bonds` order (rotations only)."""
        ld = self._lattice_list()[2].astype(np.int64)
        return (np.concatenate([self.arm_i, self.lattice_arm[ld]]),
                np.concatenate([self.arm_j, self.lattice_arm[ld]]))

    def stiffness_diagonal(self) -> np.ndarray:
        """Diagonal of :math:`K`, shape (n, dof): N/m, then N m/rad with rotations (zero
        for a degree of freedom without stiffness)."""
        i, j, n, k_n, k_t = self._bonds(self.bond_kn, self.bond_kt, self.lattice_kn,
                                        self.lattice_kt)
        block_diag = (k_n - k_t)[:, None] * n**2 + k_t[:, None]
        diag = [np.bincount(i, block_diag[:, a], self.n_particles)
                + np.bincount(j, block_diag[:, a], self.n_particles) for a in range(3)]
        if self.rotations:          # [n]x^T k [n]x = k_t (I - n n^T), times the arm squared
            a_i, a_j = self._arms()
            rot = k_t[:, None] * (1.0 - n**2)
            diag += [np.bincount(i, a_i**2 * rot[:, a], self.n_particles)
                     + np.bincount(j, a_j**2 * rot[:, a], self.n_particles) for a in range(3)]
        return np.stack(diag, axis=-1)

    def stiffness_blocks(self) -> np.ndarray:
        """The diagonal blocks of :math:`K`, one per particle, shape (n, dof, dof): the
        stiffness of a particle's own degrees of freedom with every other particle held
        (the block-Jacobi preconditioner of :func:`md.static_modulus`)."""
        i, j, n, k_n, k_t = self._bonds(self.bond_kn, self.bond_kt, self.lattice_kn,
                                        self.lattice_kt)
        k = (k_n - k_t)[:, None, None] * n[:, :, None] * n[:, None, :] \
            + k_t[:, None, None] * np.eye(3)
        dof = self.dof
        out = np.zeros((self.n_particles, dof, dof))
        if not self.rotations:
            np.add.at(out, i, k)
            np.add.at(out, j, k)
            return out
        a_i, a_j = self._arms()
        cross = _cross_matrices(n)
        eye = np.broadcast_to(np.eye(3), cross.shape)
        for who, sign, arm in ((i, -1.0, a_i), (j, 1.0, a_j)):
            B = np.concatenate([sign * eye, arm[:, None, None] * cross], axis=2)   # (m, 3, 6)
            np.add.at(out, who, np.einsum("mai,mab,mbj->mij", B, k, B))
        return out

    def _assemble(self, kn, kt, lattice_kn, lattice_kt):
        """Sparse matrix of bonds with contact constants ``kn, kt`` and per-direction lattice
        constants ``lattice_kn, lattice_kt``."""
        import scipy.sparse as sp

        i, j, n, k_n, k_t = self._bonds(kn, kt, lattice_kn, lattice_kt)
        blocks = (k_n - k_t)[:, None, None] * n[:, :, None] * n[:, None, :] \
            + k_t[:, None, None] * np.eye(3)
        if self.rotations:
            return self._assemble_rotations(i, j, n, blocks)
        a = np.arange(3)
        rows_i = (3 * i[:, None, None] + a[None, :, None]).repeat(3, axis=2)
        cols_i = (3 * i[:, None, None] + a[None, None, :]).repeat(3, axis=1)
        rows_j = (3 * j[:, None, None] + a[None, :, None]).repeat(3, axis=2)
        cols_j = (3 * j[:, None, None] + a[None, None, :]).repeat(3, axis=1)
        rows = np.concatenate([rows_i, rows_j, rows_i, rows_j]).ravel()
        cols = np.concatenate([cols_i, cols_j, cols_j, cols_i]).ravel()
        vals = np.concatenate([blocks, blocks, -blocks, -blocks]).ravel()
        size = 3 * self.n_particles
        return sp.csr_matrix((vals, (rows, cols)), shape=(size, size))

    def _assemble_rotations(self, i, j, n, blocks):
        """Sparse 6n x 6n matrix :math:`\\sum_b B_b^T k_b B_b` of bonds whose 3 x 3 constants
        are ``blocks``, :math:`B_b` the map from ``(u_i, theta_i, u_j, theta_j)`` to the
        relative displacement of the faces (:mod:`md._kernels_rotation`)."""
        import scipy.sparse as sp

        a_i, a_j = self._arms()
        cross = _cross_matrices(n)
        eye = np.broadcast_to(np.eye(3), cross.shape)
        B = np.concatenate([-eye, a_i[:, None, None] * cross, eye,
                            a_j[:, None, None] * cross], axis=2)
        Kb = np.einsum("mai,mab,mbj->mij", B, blocks, B)
        dof = np.concatenate([6 * i[:, None] + np.arange(6), 6 * j[:, None] + np.arange(6)],
                             axis=1)
        size = 6 * self.n_particles
        return sp.csr_matrix((Kb.ravel(), (np.repeat(dof, 12, axis=1).ravel(),
                                           np.tile(dof, (1, 12)).ravel())),
                             shape=(size, size))

    def stiffness_matrix(self):
        """:math:`K` as a ``scipy.sparse`` CSR matrix (``dof`` rows per particle: x, y, z, and
        with rotations the rotations about x, y, z), N/m and N m/rad."""
        return self._assemble(self.bond_kn, self.bond_kt, self.lattice_kn, self.lattice_kt)

    def damping_matrix(self):
        """:math:`D` as a ``scipy.sparse`` CSR matrix (dashpots of the contacts), N s/m."""
        return self._assemble(self.bond_gn, self.bond_gt, np.zeros(9), np.zeros(9))

    def mass_matrix(self):
        """:math:`M` as a sparse diagonal matrix, kg (and kg m² with rotations)."""
        import scipy.sparse as sp

        return sp.diags(self.dof_masses.ravel()).tocsr()

    def max_frequency(self) -> float:
        """Gershgorin bound of the largest angular frequency :math:`\\omega_{max}` of
        :math:`M^{-1}K`, rad/s."""
        from ._kernels_acoustic import gershgorin_rows

        if self.rotations:
            from ._kernels_rotation import gershgorin_rows_rot

            rows = gershgorin_rows_rot(
                1.0 / np.sqrt(self.dof_masses), self.bond_i, self.bond_j, self.bond_normal,
                self.bond_kn, self.bond_kt, self.arm_i, self.arm_j, self.lattice_neighbors,
                self.n_grains, _LATTICE_NORMALS, self.lattice_kn, self.lattice_kt,
                self.lattice_arm)
            return float(np.sqrt(np.max(rows)))
        rows = gershgorin_rows(self.n_particles, self.bond_i, self.bond_j, self.bond_normal,
                               self.bond_kn, self.bond_kt, self.lattice_neighbors,
                               self.n_grains, _LATTICE_NORMALS, self.lattice_kn,
                               self.lattice_kt)
        return float(np.sqrt(np.max(rows / self.masses[:, None])))


def grain_cement_arms(offset, normal):
    r"""Lever arms of grain–cement bonds with rotations: the bond acts at the cell centre.

    A grain–cement bond is the grain under the cell in series with the column of cement from
    the grain's surface to the cell centre (:mod:`md.interface`); its tangential stiffness,
    :math:`G_cA_i/(c_w/2)` for the column, is the continuum's: the shear traction over the
    relative tangential displacement of the column's two ends. With rotations
    (:mod:`md._kernels_rotation`) the bond's relative displacement is
    :math:`\mathbf d = \mathbf u_c - \mathbf u_g + \hat n\times(a_g\boldsymbol\theta_g +
    a_c\boldsymbol\theta_c)`. Acting at the grain's surface (:math:`a_g = R`,
    :math:`a_c = h`, the cell centre's height :math:`h` above it) the cell's own rotation
    :math:`\boldsymbol\theta_c` moves the column's end by :math:`h\,\hat n\times
    \boldsymbol\theta_c`; in a uniform strain the cells of the rotating lattice turn with the
    macroscopic rotation (:func:`md.cement.lattice_constants`), so in a simple shear
    :math:`u_x = \gamma z` beside a grain (:math:`\theta_{c,y} = \gamma/2`) the column's
    ends move :math:`\gamma h - \gamma h/2` apart and the interface carries half the
    traction :math:`G_c\gamma` of the continuum — the thin cement of a contact (a few cells
    across the gap) then shears too easily, and more so the coarser the lattice (one cemented
    contact with hard cement, :math:`a/R = 0.5`, gap :math:`0.1R` at the axis, tangential
    stiffness at :math:`\Omega = 16`: 0.63 of the integral equation of Dvorkin et al. 1994
    against 0.92 without rotations, 0.90 with the rule below). Here the bond acts at the cell centre: :math:`a_g =
    (\mathbf x_c - \mathbf x_g)\cdot\hat n`, :math:`a_c = 0`, so it measures the cell centre
    against the grain's material point under it (the column's two ends), which the cell's own
    rotation does not move; a rigid motion still costs nothing (:math:`a_g + a_c` is the
    distance of the centres along :math:`\hat n`, the condition of
    :mod:`md._kernels_rotation`), and the bond's force and the moment it puts on the grain are
    those of the column.

    Parameters
    ----------
    offset : ndarray, shape (m, 3)
        Cell centre minus grain centre of each bond (minimum image), m.
    normal : ndarray, shape (m, 3)
        The bonds' unit normals (grain centre to cell centre).

    Returns
    -------
    arm_grain, arm_cell : ndarray, shape (m,)
        m: the distance along the normal, and zeros.
    """
    length = np.einsum("ij,ij->i", np.asarray(offset, dtype=float),
                       np.asarray(normal, dtype=float))
    return length, np.zeros_like(length)


def _lattice_springs(cement, cell_width, rule, rotations=False):
    """Lattice constants and the per-direction normal and tangential stiffness of eq. 6:
    ``(Cn, C, m_c, Cn + C/|x|^2, C/|x|^2)``."""
    Cn, C, m_c = lattice_constants(cement, cell_width, rule, rotations=rotations)
    kt = C / (_LATTICE_LENGTH2 * cell_width**2)
    return Cn, C, m_c, Cn + kt, kt


def _lattice_table(cells, where, shape, first):
    """Neighbour table of the cement–cement bonds among the particles of the cemented
    ``cells`` (``where[cell]`` is a cell's index among them, −1 for an empty cell; particle
    indices start at ``first``) and the number of bonds."""
    from ._kernels_acoustic import lattice_table

    nx, ny, nz = shape
    table = np.empty((cells.size, LATTICE_OFFSETS.shape[0]), np.int32)
    n = lattice_table(cells, where, nx, ny, nz, LATTICE_OFFSETS, first, table)
    return table, int(n)


def _contact_bonds_grains(pack: Pack, m, zeta, normal_factor=2.0):
    """Grain–grain contacts of the pack (grain masses ``m``) linearised at their equilibrium
    overlap, normal stiffness ``normal_factor`` E_f a."""
    from .neighbors import build_neighbors
    from .space import minimum_image

    x, r, mat = pack.positions, pack.radii, pack.material
    p = build_neighbors(x, r, pack.box, 0.0).pairs.astype(np.int64)
    d = minimum_image(x[p[:, 1]] - x[p[:, 0]], pack.box)
    dist = np.linalg.norm(d, axis=1)
    xi = r[p[:, 0]] + r[p[:, 1]] - dist
    keep = xi > 0
    p, d, dist, xi = p[keep], d[keep], dist[keep], xi[keep]
    ri, rj = r[p[:, 0]], r[p[:, 1]]
    R_f = ri * rj / (ri + rj)
    if pack.overlap_dissolved is None:
        a = np.sqrt(R_f * xi)           # Hertz contact radius
    else:
        # Grains truncated by pressure solution (md.reconstruct): the flat of the dissolved
        # overlap plus the Hertz radius of the elastic rest, a² = b² + R_f ξ_e (Digby 1981;
        # md.reconstruct.flattened_contact_radius). A contact of radius a has the incremental
        # stiffness of a flat punch of that radius whatever its profile — normal 2aE/(1-ν²)
        # and tangential 8Ga/(2-ν) per half-space (Johnson 1985, rigid punch; the constants
        # of md.bond_stiffness), 2 E_f a and 8 G_f a for the pair, Hertz's tangent and
        # Mindlin's no-slip stiffness at a = sqrt(R_f ξ).
        from .reconstruct import dissolved_of, flattened_contact_radius

        xi_p = np.minimum(dissolved_of(pack, p), xi)
        a = flattened_contact_radius(ri, rj, xi_p, xi - xi_p)
    kn = normal_factor * mat.E_f * a
    kt = 8.0 * mat.G_f * a
    gn, gt = dashpots(kn, kt, m[p[:, 0]], m[p[:, 1]], zeta)
    arm_i = (dist**2 + ri**2 - rj**2) / (2.0 * dist)   # the plane of the contact circle
    return p[:, 0], p[:, 1], d / dist[:, None], kn, kt, gn, gt, arm_i, dist - arm_i


def acoustic_system(pack: Pack, lattice: CementLattice | None = None, cemented=None,
                    cement: CementMaterial = HARD_CEMENT, *, rule="waves", interface="facet",
                    normal_stiffness="tangent", rotations=True, restitution=None,
                    slab_thickness=None) -> AcousticSystem:
    """Linearise a (cemented) pack about its equilibrium for the pulse test.

    Parameters
    ----------
    pack : Pack
        The pack at mechanical equilibrium (after settling or compaction).
    lattice : CementLattice, optional
        The pack's cement lattice (:func:`md.cement.cement_lattice`); omit for no cement.
    cemented : ndarray of bool or float, optional
        Cemented pore cells of ``lattice`` (:func:`md.cement.grow_cement`), or the fraction of
        each pore cell the cement fills, in [0, 1] (:func:`md.growth.cement_fill`). A full
        cell is the boolean path's cell exactly (all fills 0 or 1 take that path). A partly
        filled cell holding :math:`f` of a cell's cement is a *film cell* of its nearest grain
        (:func:`md.interface.nearest_grain`): mass and moment of inertia :math:`f` times a
        cell's, its bond to that grain alone, :math:`f` times a full cell's; its lattice bonds
        two half-bonds in series, :math:`2f_pf_q/(f_p+f_q)` times eq. 6's, and none to a film
        cell of another grain. Films meet only in *bridges*, grain–grain cement bonds over the
        disc where the gap between two grains is under the sum of their film thicknesses (the
        volume of a grain's partly filled cells over its surface,
        :func:`md.interface.film_thickness`; :func:`md.interface.film_bridges`), less the part
        full cells resolve; a film that
        joins nothing but its grain is folded into it (:func:`_lump_free_film`). So a coating
        thinner than a cell is the bridges it makes, whose size follows the film thickness, not
        spots of cells, and converges with the resolution.
    cement : CementMaterial
        Default :data:`md.cement.HARD_CEMENT`.
    rule : {"waves", "paper"}
        Lattice constants, see :func:`md.cement.lattice_constants`.
    interface : {"facet", "patch", "paper"}
        Grain–cement interface rule (:mod:`md.interface`): ``"facet"`` (default) converges
        with the resolution and never softens as cement is added; ``"patch"`` joins the necks
        of a grain into one punch once cement links them; ``"paper"`` is the source's per-cell
        rule (Sect. III F).
    normal_stiffness : {"tangent", "secant"}
        Normal stiffness of the Hertzian bonds (grain–grain, and grain–cement under
        ``interface="paper"``): ``"tangent"`` (default) the derivative of the Hertz force,
        :math:`2E_f a`, the stiffness of the linearised contact; ``"secant"`` the source's eq. 4
        read literally, whose :math:`\\kappa_n` is eq. 1's :math:`\\tfrac43 E_f a` (the force
        over the overlap, two thirds of the tangent), kept to reproduce the source. The
        tangential stiffness is Mindlin's in both.
    rotations : bool
        ``True`` (default): every particle also rotates (moment of inertia
        :math:`\\tfrac25 mR^2` for a grain, :math:`\\tfrac16 m_c c_w^2` for a cement cube); each
        bond acts at its contact point — the plane of the contact circle of two grains, the
        cell centre for a grain–cement bond (:func:`grain_cement_arms`), the midpoint of a
        lattice bond
        (:mod:`md._kernels_rotation`, lattice constants of
        :func:`md.cement.lattice_constants` with ``rotations=True``) — so a rigid motion of
        the sample costs nothing. ``False``: translations only, the source's eqs. 4–6, under
        which a rigid rotation stretches every tangential spring and the shear stiffness of a
        grain pack is far too high (dry Vp/Vs near 1).
    restitution : float, optional
        Restitution of the contact dashpots, default the pack material's (0.9).
    slab_thickness : float, optional
        Detector slab thickness, m; default two largest grain diameters (the paper's).

    Returns
    -------
    AcousticSystem
    """
    from ._kernels_acoustic import grain_cement_bonds

    if not isinstance(pack, Pack):
        raise ValueError(f"pack must be an md.Pack; got {type(pack).__name__}")
    if (lattice is None) != (cemented is None):
        raise ValueError("give both lattice and cemented, or neither")
    if interface not in INTERFACES:
        raise ValueError(f"interface must be one of {INTERFACES}; got {interface!r}")
    if normal_stiffness not in NORMAL_STIFFNESS:
        raise ValueError(f"normal_stiffness must be one of {NORMAL_STIFFNESS}; "
                         f"got {normal_stiffness!r}")
    normal_factor = _NORMAL_FACTOR[normal_stiffness]
    mat = pack.material
    e = mat.restitution if restitution is None else restitution
    zeta = damping_ratio(e)
    r = pack.radii
    m_grain = mat.density * 4.0 / 3.0 * np.pi * r**3
    gi, gj, gnrm, gkn, gkt, ggn, ggt, garm_i, garm_j = _contact_bonds_grains(pack, m_grain, zeta,
                                                                           normal_factor)
    x = pack.positions.copy()
    x[:, 0] %= pack.box.lx
    x[:, 1] %= pack.box.ly
    n_g = pack.n_grains
    thickness = 4.0 * float(r.max()) if slab_thickness is None else float(slab_thickness)
    if not thickness > 0:
        raise ValueError(f"slab_thickness must be > 0 m; got {slab_thickness}")
    extent = (float(np.min(x[:, 2] - r)), float(np.max(x[:, 2] + r)))
    meta = {"n_grain_contacts": int(gi.size), "n_cement": 0, "n_grain_cement": 0,
            "cement_vp": cement.vp, "cement_vs": cement.vs, "cement_density": cement.density,
            "lattice_rule": rule, "interface": interface, "normal_stiffness": normal_stiffness,
            "rotations": bool(rotations), "restitution": e,
            "mean_radius": float(r.mean())}
    inertia = 0.4 * m_grain * r**2
    fill = None
    if lattice is not None:
        cemented, fill = _cement_fill(cemented, lattice.index.size)
    if lattice is None or not np.any(cemented):
        rot = ({"arm_i": garm_i, "arm_j": garm_j, "lattice_arm": np.zeros(9),
                "inertia": inertia} if rotations else {})
        return AcousticSystem(
            x, m_grain, n_g, pack.box, gi.astype(np.int32), gj.astype(np.int32), gnrm, gkn, gkt,
            ggn, ggt, np.zeros((0, 9), np.int32), np.zeros(9), np.zeros(9),
            thickness, extent, meta, **rot)
    nx, ny, nz = lattice.shape
    if min(nx, ny) < 3:
        raise ValueError("the cement lattice needs at least 3 cells across x and y")
    cw = lattice.cell_width
    Cn, C, m_c, lat_kn, lat_kt = _lattice_springs(cement, cw, rule, rotations)
    cells = lattice.index[cemented].astype(np.int64)
    n_c = cells.size
    where = np.full(nx * ny * nz, -1, dtype=np.int32)
    where[cells] = np.arange(n_c, dtype=np.int32)
    table, n_lattice = _lattice_table(cells, where, lattice.shape, n_g)
    dummy_i = np.zeros(0, np.int32)
    args = (x, r, where, pack.box.lx, pack.box.ly, lattice.z0, cw, nx, ny, nz,
            interface != "paper")
    n_gc = grain_cement_bonds(*args, True, dummy_i, dummy_i, np.zeros((0, 3)))
    ci, cj, cnrm = np.empty(n_gc, np.int32), np.empty(n_gc, np.int32), np.empty((n_gc, 3))
    grain_cement_bonds(*args, False, ci, cj, cnrm)
    # In cement-particle order: the sweep then reads the cement displacements in memory order
    # (the few grains stay in cache), several times faster than grain order on big lattices.
    order = np.argsort(cj, kind="stable")
    ci, cj, cnrm = ci[order], cj[order], cnrm[order]
    centres = lattice.centres()[cemented]
    m_cell = np.full(n_c, m_c)
    extra = None
    if fill is not None:        # partly filled cells: the film of their nearest grain
        f = fill[cemented]
        owner = nearest_grain(centres, x, r, pack.box)
        film = f < 1.0
        keep = ~film[cj] | (ci == owner[cj])
        ci, cj, cnrm = ci[keep], cj[keep], cnrm[keep]
        n_gc = int(ci.size)
        table, extra = _film_lattice(table, f, owner, n_g, lat_kn, lat_kt, cw)
        n_lattice = int(np.count_nonzero(table >= 0))
        m_cell = m_c * f
    partner = (bond_partners(ci, centres[cj], x, r, pack.box) if interface == "facet"
               else None)
    kn_gc, kt_gc = interface_stiffness(ci, cj, cnrm, r, table if extra is None else extra[0],
                                       n_g, cw, mat, cement, interface, partner,
                                       paper_normal_factor=normal_factor,
                                       contact_pairs=np.stack([gi, gj], axis=1),
                                       contact_radius=gkn / (normal_factor * mat.E_f))
    if fill is not None:        # a cell holding f of its cement: f of its bond to the grain
        kn_gc, kt_gc = kn_gc * f[cj], kt_gc * f[cj]
    gn_gc, gt_gc = dashpots(kn_gc, kt_gc, m_grain[ci], m_cell[cj], zeta)
    bond_i = np.concatenate([gi, ci]).astype(np.int32)
    bond_j = np.concatenate([gj, cj.astype(np.int64) + n_g]).astype(np.int32)
    meta.update(n_cement=int(n_c), n_grain_cement=int(n_gc), n_lattice_bonds=n_lattice,
                cell_width=cw, lattice_Cn=Cn, lattice_C=C)
    rot = {}
    if rotations:       # a grain-cement bond acts at the cell centre (grain_cement_arms)
        arm_gc, arm_cg = grain_cement_arms(minimum_image(centres[cj] - x[ci], pack.box), cnrm)
        rot = {"arm_i": np.concatenate([garm_i, arm_gc]),
               "arm_j": np.concatenate([garm_j, arm_cg]),
               "lattice_arm": 0.5 * cw * np.sqrt(_LATTICE_LENGTH2),
               "inertia": np.concatenate([inertia, m_cell * cw**2 / 6.0])}
    parts = [(bond_i, bond_j, np.concatenate([gnrm, cnrm]), np.concatenate([gkn, kn_gc]),
              np.concatenate([gkt, kt_gc]), np.concatenate([ggn, gn_gc]),
              np.concatenate([ggt, gt_gc]),
              rot.get("arm_i"), rot.get("arm_j"))]
    if fill is not None:
        parts += _film_bonds(extra, f, owner, film, ci, cj, cnrm, partner, centres, gi, gj,
                             gkn, normal_factor, x, r, pack, cement, cw, (lat_kn, lat_kt),
                             m_grain, zeta, meta)
    merged = [np.concatenate(c) if c[0] is not None else None for c in zip(*parts)]
    positions = np.concatenate([x, centres])
    masses = np.concatenate([m_grain, m_cell])
    inertia_all = rot.get("inertia")
    if fill is not None:
        positions, masses, inertia_all, merged, table = _lump_free_film(
            positions, masses, inertia_all, merged, table, film, owner, n_g, pack.box, meta)
    if rotations:
        rot["arm_i"], rot["arm_j"], rot["inertia"] = merged[7], merged[8], inertia_all
    return AcousticSystem(
        positions, masses, n_g, pack.box, merged[0].astype(np.int32),
        merged[1].astype(np.int32), *merged[2:7], table, lat_kn, lat_kt, thickness, extent,
        meta, **rot)


def _lump_free_film(positions, masses, inertia, bonds, table, film, owner, n_g, box, meta):
    r"""Fold into its grain every film cell that joins nothing but that grain.

    A partly filled cell is bonded to its own grain and to film cells of the same grain only
    (:func:`_film_lattice`), so a film no full cell touches is an appendage of its grain: in a
    static solve it carries no force (it bears on one body only), in a wave it moves with the
    grain it is welded to. Its particles are removed and their mass added to the grain, their
    moment of inertia as that of a uniform shell at their distance :math:`\rho` from the
    grain's centre, :math:`\tfrac23 m\rho^2`, plus their own :math:`\tfrac16 m c_w^2`
    (exact for a rigid uniform film). Bonds of the removed particles are dropped and the
    others renumbered. Updates ``meta``; returns the new ``positions, masses, inertia, bonds,
    table``."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = masses.size
    n_c = n - n_g
    bi, bj = bonds[0].astype(np.int64), bonds[1].astype(np.int64)
    is_film = np.zeros(n, bool)
    is_film[n_g:] = film
    cement = np.arange(n) >= n_g
    ff = cement[bi] & cement[bj] & is_film[bi] & is_film[bj]
    graph = sp.coo_matrix((np.ones(int(ff.sum())), (bi[ff] - n_g, bj[ff] - n_g)),
                          shape=(n_c, n_c))
    _, label = connected_components(graph, directed=False)
    touches_bulk = cement[bi] & cement[bj] & (is_film[bi] != is_film[bj])
    anchored = np.zeros(label.max(initial=0) + 1, bool)
    ends = np.concatenate([bi[touches_bulk], bj[touches_bulk]])
    anchored[label[ends[is_film[ends]] - n_g]] = True
    free = np.zeros(n, bool)
    free[n_g:] = film & ~anchored[label]
    if not free.any():
        meta.update(n_film_lumped=0)
        return positions, masses, inertia, bonds, table
    idx = np.flatnonzero(free)
    g = owner[idx - n_g]
    masses = masses.copy()
    np.add.at(masses, g, masses[idx])
    if inertia is not None:
        inertia = inertia.copy()
        rho2 = np.sum(minimum_image(positions[idx] - positions[g], box) ** 2, axis=1)
        np.add.at(inertia, g, inertia[idx] + 2.0 / 3.0 * masses[idx] * rho2)
    keep = ~free
    new = np.cumsum(keep) - 1
    own = keep[bi] & keep[bj]
    bonds = [b[own] if b is not None else None for b in bonds]
    bonds[0] = new[bonds[0].astype(np.int64)]
    bonds[1] = new[bonds[1].astype(np.int64)]
    table = table[keep[n_g:]]
    table = np.where(table >= 0, new[np.maximum(table, 0)], -1).astype(np.int32)
    meta.update(n_film_lumped=int(idx.size), n_cement=int(n_c - idx.size))
    return (positions[keep], masses[keep], None if inertia is None else inertia[keep], bonds,
            table)


def _cement_fill(cemented, n):
    """``cemented`` of :func:`acoustic_system` as ``(cells, fill)``: the cemented pore cells
    (bool) and, where some cell is partly filled, the fill fractions (else None, so that cells
    full or empty take the boolean path unchanged)."""
    c = np.asarray(cemented)
    if c.shape != (n,):
        raise ValueError(f"cemented must have the lattice's {n} pore cells; got shape {c.shape}")
    if c.dtype == bool:
        return c, None
    if not (np.issubdtype(c.dtype, np.floating) or np.issubdtype(c.dtype, np.integer)):
        raise ValueError(f"cemented must be bool or fill fractions in [0, 1]; got dtype "
                         f"{c.dtype}")
    f = c.astype(float)
    if not np.all(np.isfinite(f) & (f >= 0.0) & (f <= 1.0)):
        bad = f[~(np.isfinite(f) & (f >= 0.0) & (f <= 1.0))][0]
        raise ValueError(f"cemented fill fractions must lie in [0, 1]; got {bad!r}")
    if np.all((f == 0.0) | (f == 1.0)):
        return f == 1.0, None
    return f > 0.0, f


def _film_lattice(table, f, owner, first, lat_kn, lat_kt, cw):
    r"""Split the lattice bonds of partly filled cells off the neighbour table.

    A bond between two cement particles holding fills :math:`f_p, f_q` is two half-bonds in
    series, each through its own cell's cement, scaled by that cell's fill:
    :math:`k = k_{lattice}\,2f_pf_q/(f_p + f_q)` (eq. 6 constants of
    :func:`md.cement.lattice_constants`; 1 at full cells). A film cell belongs to its nearest
    grain; two film cells of different grains are not bonded (the films meet only in a
    bridge, :func:`md.interface.film_bridges`). Returns the table of the bonds between full
    cells, and ``(table with every kept bond, p, q, direction, scale)`` of the others
    (``p``, ``q`` particle indices)."""
    film = f < 1.0
    rows, cols = np.nonzero(table >= 0)
    q = table[rows, cols] - first
    cut = film[rows] & film[q] & (owner[rows] != owner[q])
    full_table = table.copy()
    full_table[rows[cut], cols[cut]] = -1
    moved = ~cut & (film[rows] | film[q])
    bulk = table.copy()
    bulk[rows[cut | moved], cols[cut | moved]] = -1
    fp, fq = f[rows[moved]], f[q[moved]]
    scale = 2.0 * fp * fq / (fp + fq)
    return bulk, (full_table, rows[moved] + first, q[moved] + first,
                  cols[moved].astype(np.int64), scale)


def _film_bonds(extra, f, owner, film, ci, cj, cnrm, partner, positions_cells, gi, gj, gkn,
                normal_factor, x, r, pack, cement,
                cw, lattice_k, m_grain, zeta, meta):
    """The contact-bond blocks of a partly filled lattice: the scaled lattice bonds of film
    cells (:func:`_film_lattice`; no dashpots, acting at mid-bond with rotations) and the
    bridges the films make between grains (:func:`md.interface.film_bridges`), less the part
    of each bridge that full cells already resolve (those bonded to one grain of the pair and
    facing the other, :func:`md.interface.bond_partners`). Updates ``meta``."""
    from .interface import interface_area

    _, p, q, d, scale = extra
    mat = pack.material
    lat = (p, q, _LATTICE_NORMALS[d], lattice_k[0][d] * scale, lattice_k[1][d] * scale,
           np.zeros(p.size), np.zeros(p.size),
           0.5 * cw * np.sqrt(_LATTICE_LENGTH2[d]), 0.5 * cw * np.sqrt(_LATTICE_LENGTH2[d]))
    thickness = film_thickness(owner[film], f[film] * cw**3, r)    # the partly filled cells
    # the part of a pair's bridge whole cells already resolve: the full cells bonded to
    # either grain and facing the other, half of their interface area from each side
    full_bond = ~film[cj]
    if partner is None:
        partner = bond_partners(ci, positions_cells[cj], x, r, pack.box)
    faces = full_bond & (partner >= 0)
    covered = np.stack([ci[faces], partner[faces]], axis=1)
    covered_area = 0.5 * interface_area(cnrm[faces], cw)
    a_hertz = gkn / (normal_factor * mat.E_f)
    bi, bj, nrm, kn, kt, arm_i, arm_j = film_bridges(
        x, r, pack.box, thickness, mat, cement, np.stack([gi, gj], axis=1), a_hertz, covered,
        covered_area)
    gn, gt = dashpots(kn, kt, m_grain[bi], m_grain[bj], zeta)
    meta.update(n_film_cells=int(np.count_nonzero(film)), n_film_bridges=int(bi.size),
                cement_cells_volume=float(f.sum()), film_thickness_mean=float(
                    np.mean(thickness)))
    return [lat, (bi, bj, nrm, kn, kt, gn, gt, arm_i, arm_j)]


def cement_block(shape, cell_width, cement: CementMaterial = HARD_CEMENT, *, rule="waves",
                 rotations=True, slab_thickness=None) -> AcousticSystem:
    """A block of pure cement: every cell of an ``(nx, ny, nz)`` lattice holds a cement particle.

    Periodic in x and y, free ends in z. The homogeneous check of the lattice and of the pulse
    machinery: its P and S moduli are the cement's (:func:`md.cement.lattice_constants`).
    ``rotations`` as in :func:`acoustic_system`.
    """
    nx, ny, nz = (int(s) for s in shape)
    if min(nx, ny) < 3 or nz < 2:
        raise ValueError(f"shape must have nx, ny >= 3 and nz >= 2 cells; got {shape}")
    Cn, C, m_c, lat_kn, lat_kt = _lattice_springs(cement, cell_width, rule, rotations)
    cells = np.arange(nx * ny * nz, dtype=np.int64)
    table, _ = _lattice_table(cells, cells.astype(np.int32), (nx, ny, nz), 0)
    i, j, k = cells % nx, (cells // nx) % ny, cells // (nx * ny)
    pos = (np.stack([i, j, k], axis=-1) + 0.5) * cell_width
    e = np.zeros(0)
    cw = float(cell_width)
    return AcousticSystem(
        pos, np.full(cells.size, m_c), 0, Box(nx * cw, ny * cw, 0.0, nz * cw),
        np.zeros(0, np.int32), np.zeros(0, np.int32), np.zeros((0, 3)), e, e, e, e, table,
        lat_kn, lat_kt, 4.0 * cw if slab_thickness is None else float(slab_thickness),
        (0.0, nz * cw),
        {"n_cement": int(cells.size), "cell_width": cw, "lattice_Cn": Cn, "lattice_C": C,
         "lattice_rule": rule, "rotations": bool(rotations)},
        **({"arm_i": e, "arm_j": e, "lattice_arm": 0.5 * cw * np.sqrt(_LATTICE_LENGTH2),
            "inertia": np.full(cells.size, m_c * cw**2 / 6.0)} if rotations else {}))


# The solves on the operator live in their own modules; their public names stay importable
# from here.
from .pulse import pulse_test  # noqa: E402
from .static import StaticModulus, static_modulus  # noqa: E402
