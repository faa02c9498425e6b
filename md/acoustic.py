"""The acoustic stage: the pack and its cement linearised about mechanical equilibrium, a sparse
linear system :math:`M\\ddot u + D\\dot u + K u = 0` (García & Medina, Sects. III F–G).

SI units. Particles are the grains (first ``n_grains``) and the cement particles (one per
cemented cell, mass :math:`m_c = \\rho_c c_w^3`, eq. 9). Three kinds of bonds:

* grain–grain contacts (eqs. 4–5): the Hertz contact linearised at its equilibrium overlap
  :math:`\\xi_0` with the contact area held fixed (no sliding), normal stiffness
  :math:`k_n = \\partial F_n/\\partial\\xi = 2E_f a` and Mindlin tangential stiffness
  :math:`k_s = 8 G_f a = 4 a G/(2-\\nu)`, :math:`a = \\sqrt{R_f\\xi_0}`; translations only, as in
  the paper's eqs. 4–5 (:math:`\\mathbf d = \\mathbf d_2 - \\mathbf d_1`), without the geometric
  stiffness of the pre-stress;
* cement–cement lattice springs to the 18 nearest lattice neighbours (eq. 6, constants from
  :func:`md.cement.lattice_constants`);
* grain–cement contacts: eq. 4 with the mixed moduli :math:`E^* = [(1-\\nu_g^2)/E_g +
  (1-\\nu_c^2)/E_c]^{-1}`, :math:`G^* = [(2-\\nu_g)/G_g + (2-\\nu_c)/G_c]^{-1}` and a contact of
  diameter :math:`c_w`: :math:`k_n = 2E^*(c_w/2)`, :math:`k_s = 8G^*(c_w/2)`, along the line from
  the grain centre to the cell centre.

Contacts carry dashpots :math:`\\gamma = 2\\zeta\\sqrt{k\\,m_{red}}` with the damping ratio
:math:`\\zeta = -\\ln e/\\sqrt{\\pi^2 + \\ln^2 e}` of a linear oscillator with restitution ``e``
(0.9 in the paper, normal and tangential); lattice springs are undamped.

:meth:`AcousticSystem.stiffness_matrix` (and damping, mass) assemble the operator as
``scipy.sparse`` matrices; the pulse test applies the same operator bond by bond in a numba
kernel (no matrix is stored), which the tests check against the assembled matrix.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .cement import (HARD_CEMENT, LATTICE_OFFSETS, CementLattice, CementMaterial,
                     lattice_constants)
from .space import Box
from .state import Pack

__all__ = ["AcousticSystem", "acoustic_system", "cement_block", "static_modulus",
           "pulse_test", "damping_ratio", "StaticModulus"]

_AXIS = {"p": 2, "s": 0}


def _wave_axis(wave) -> int:
    if wave not in _AXIS:
        raise ValueError(f"wave must be 'p' or 's'; got {wave!r}")
    return _AXIS[wave]

_LATTICE_NORMALS = LATTICE_OFFSETS / np.linalg.norm(LATTICE_OFFSETS, axis=1)[:, None]
_LATTICE_LENGTH2 = np.sum(LATTICE_OFFSETS**2, axis=1).astype(float)     # |x|^2 / c_w^2


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

    @property
    def n_particles(self) -> int:
        """Grains plus cement particles."""
        return int(self.masses.shape[0])

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
        return (self.bond_i, self.bond_j, self.bond_normal, self.bond_kn, self.bond_kt,
                self.bond_gn, self.bond_gt, self.lattice_neighbors, self.n_grains,
                _LATTICE_NORMALS, self.lattice_kn, self.lattice_kt)

    def forces(self, u, v=None) -> np.ndarray:
        """Bond forces :math:`-(K u + D v)` on every particle, shape (n, 3), N."""
        from ._kernels_acoustic import contact_forces, lattice_forces

        u = np.ascontiguousarray(u, dtype=float).reshape(self.n_particles, 3)
        v = np.zeros_like(u) if v is None else \
            np.ascontiguousarray(v, dtype=float).reshape(self.n_particles, 3)
        f = np.zeros_like(u)
        sz = np.zeros(0)
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

    def stiffness_diagonal(self) -> np.ndarray:
        """Diagonal of :math:`K`, shape (n, 3), N/m (zero for a particle without bonds)."""
        i, j, n, k_n, k_t = self._bonds(self.bond_kn, self.bond_kt, self.lattice_kn,
                                        self.lattice_kt)
        block_diag = (k_n - k_t)[:, None] * n**2 + k_t[:, None]
        return np.stack([np.bincount(i, block_diag[:, a], self.n_particles)
                         + np.bincount(j, block_diag[:, a], self.n_particles)
                         for a in range(3)], axis=-1)

    def _assemble(self, kn, kt, lattice_kn, lattice_kt):
        """Sparse matrix of bonds with contact constants ``kn, kt`` and per-direction lattice
        constants ``lattice_kn, lattice_kt``."""
        import scipy.sparse as sp

        i, j, n, k_n, k_t = self._bonds(kn, kt, lattice_kn, lattice_kt)
        blocks = (k_n - k_t)[:, None, None] * n[:, :, None] * n[:, None, :] \
            + k_t[:, None, None] * np.eye(3)
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

    def stiffness_matrix(self):
        """:math:`K` as a ``scipy.sparse`` CSR matrix (3 rows per particle: x, y, z), N/m."""
        return self._assemble(self.bond_kn, self.bond_kt, self.lattice_kn, self.lattice_kt)

    def damping_matrix(self):
        """:math:`D` as a ``scipy.sparse`` CSR matrix (dashpots of the contacts), N s/m."""
        return self._assemble(self.bond_gn, self.bond_gt, np.zeros(9), np.zeros(9))

    def mass_matrix(self):
        """:math:`M` as a sparse diagonal matrix, kg."""
        import scipy.sparse as sp

        return sp.diags(np.repeat(self.masses, 3)).tocsr()

    def max_frequency(self) -> float:
        """Gershgorin bound of the largest angular frequency :math:`\\omega_{max}` of
        :math:`M^{-1}K`, rad/s."""
        from ._kernels_acoustic import gershgorin_rows

        rows = gershgorin_rows(self.n_particles, self.bond_i, self.bond_j, self.bond_normal,
                               self.bond_kn, self.bond_kt, self.lattice_neighbors,
                               self.n_grains, _LATTICE_NORMALS, self.lattice_kn,
                               self.lattice_kt)
        return float(np.sqrt(np.max(rows / self.masses[:, None])))


def _lattice_springs(cement, cell_width, rule):
    """Lattice constants and the per-direction normal and tangential stiffness of eq. 6:
    ``(Cn, C, m_c, Cn + C/|x|^2, C/|x|^2)``."""
    Cn, C, m_c = lattice_constants(cement, cell_width, rule)
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


def _contact_bonds_grains(pack: Pack, m, zeta):
    """Grain–grain contacts of the pack (grain masses ``m``) linearised at their equilibrium
    overlap."""
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
    a = np.sqrt(R_f * xi)
    kn = 2.0 * mat.E_f * a
    kt = 8.0 * mat.G_f * a
    gn, gt = dashpots(kn, kt, m[p[:, 0]], m[p[:, 1]], zeta)
    return p[:, 0], p[:, 1], d / dist[:, None], kn, kt, gn, gt


def acoustic_system(pack: Pack, lattice: CementLattice | None = None, cemented=None,
                    cement: CementMaterial = HARD_CEMENT, *, rule="waves", restitution=None,
                    slab_thickness=None) -> AcousticSystem:
    """Linearise a (cemented) pack about its equilibrium for the pulse test.

    Parameters
    ----------
    pack : Pack
        The pack at mechanical equilibrium (after settling or compaction).
    lattice : CementLattice, optional
        The pack's cement lattice (:func:`md.cement.cement_lattice`); omit for no cement.
    cemented : ndarray of bool, optional
        Cemented pore cells of ``lattice`` (:func:`md.cement.grow_cement`).
    cement : CementMaterial
        Default :data:`md.cement.HARD_CEMENT`.
    rule : {"waves", "paper"}
        Lattice constants, see :func:`md.cement.lattice_constants`.
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
    mat = pack.material
    e = mat.restitution if restitution is None else restitution
    zeta = damping_ratio(e)
    r = pack.radii
    m_grain = mat.density * 4.0 / 3.0 * np.pi * r**3
    gi, gj, gnrm, gkn, gkt, ggn, ggt = _contact_bonds_grains(pack, m_grain, zeta)
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
            "lattice_rule": rule, "restitution": e, "mean_radius": float(r.mean())}
    if lattice is None or not np.any(cemented):
        return AcousticSystem(
            x, m_grain, n_g, pack.box, gi.astype(np.int32), gj.astype(np.int32), gnrm, gkn, gkt,
            ggn, ggt, np.zeros((0, 9), np.int32), np.zeros(9), np.zeros(9),
            thickness, extent, meta)
    cemented = np.asarray(cemented, dtype=bool)
    if cemented.shape != lattice.index.shape:
        raise ValueError(f"cemented must have the lattice's {lattice.index.size} pore cells; "
                         f"got shape {cemented.shape}")
    nx, ny, nz = lattice.shape
    if min(nx, ny) < 3:
        raise ValueError("the cement lattice needs at least 3 cells across x and y")
    cw = lattice.cell_width
    Cn, C, m_c, lat_kn, lat_kt = _lattice_springs(cement, cw, rule)
    cells = lattice.index[cemented].astype(np.int64)
    n_c = cells.size
    where = np.full(nx * ny * nz, -1, dtype=np.int32)
    where[cells] = np.arange(n_c, dtype=np.int32)
    table, n_lattice = _lattice_table(cells, where, lattice.shape, n_g)
    dummy_i = np.zeros(0, np.int32)
    args = (x, r, where, pack.box.lx, pack.box.ly, lattice.z0, cw, nx, ny, nz)
    n_gc = grain_cement_bonds(*args, True, dummy_i, dummy_i, np.zeros((0, 3)))
    ci, cj, cnrm = np.empty(n_gc, np.int32), np.empty(n_gc, np.int32), np.empty((n_gc, 3))
    grain_cement_bonds(*args, False, ci, cj, cnrm)
    # In cement-particle order: the sweep then reads the cement displacements in memory order
    # (the few grains stay in cache), several times faster than grain order on big lattices.
    order = np.argsort(cj, kind="stable")
    ci, cj, cnrm = ci[order], cj[order], cnrm[order]
    # Mixed contact moduli (Johnson, Contact Mechanics, eqs. 4.22 and 7.42 for a flat contact).
    nu_g, nu_c = mat.poisson_ratio, cement.poisson_ratio
    E_star = 1.0 / ((1 - nu_g**2) / mat.young_modulus + (1 - nu_c**2) / cement.young_modulus)
    G_star = 1.0 / ((2 - nu_g) / mat.shear_modulus + (2 - nu_c) / cement.shear_modulus)
    a = 0.5 * cw
    kn_gc = np.full(n_gc, 2.0 * E_star * a)
    kt_gc = np.full(n_gc, 8.0 * G_star * a)
    gn_gc, gt_gc = dashpots(kn_gc, kt_gc, m_grain[ci], m_c, zeta)
    centres = lattice.centres()[cemented]
    bond_i = np.concatenate([gi, ci]).astype(np.int32)
    bond_j = np.concatenate([gj, cj.astype(np.int64) + n_g]).astype(np.int32)
    meta.update(n_cement=int(n_c), n_grain_cement=int(n_gc), n_lattice_bonds=n_lattice,
                cell_width=cw, lattice_Cn=Cn, lattice_C=C)
    return AcousticSystem(
        np.concatenate([x, centres]), np.concatenate([m_grain, np.full(n_c, m_c)]), n_g,
        pack.box, bond_i, bond_j, np.concatenate([gnrm, cnrm]),
        np.concatenate([gkn, kn_gc]), np.concatenate([gkt, kt_gc]),
        np.concatenate([ggn, gn_gc]), np.concatenate([ggt, gt_gc]),
        table, lat_kn, lat_kt, thickness, extent, meta)


def cement_block(shape, cell_width, cement: CementMaterial = HARD_CEMENT, *, rule="waves",
                 slab_thickness=None) -> AcousticSystem:
    """A block of pure cement: every cell of an ``(nx, ny, nz)`` lattice holds a cement particle.

    Periodic in x and y, free ends in z. The homogeneous check of the lattice and of the pulse
    machinery: its P and S moduli are the cement's (:func:`md.cement.lattice_constants`).
    """
    nx, ny, nz = (int(s) for s in shape)
    if min(nx, ny) < 3 or nz < 2:
        raise ValueError(f"shape must have nx, ny >= 3 and nz >= 2 cells; got {shape}")
    Cn, C, m_c, lat_kn, lat_kt = _lattice_springs(cement, cell_width, rule)
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
         "lattice_rule": rule})


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
    """Particles bonded (directly or through others) to the driven or the fixed slab."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = system.n_particles
    li, lj, _ = system._lattice_list()
    i = np.concatenate([system.bond_i, li])
    j = np.concatenate([system.bond_j, lj])
    graph = sp.coo_matrix((np.ones(i.size, np.int8), (i, j)), shape=(n, n))
    _, label = connected_components(graph, directed=False)
    anchored = np.unique(label[flag != 0])
    return np.isin(label, anchored)


def static_modulus(system: AcousticSystem, wave="p", *, rtol=1e-10,
                   maxiter=None) -> StaticModulus:
    """P-wave (or shear) modulus of the linearised sample by a sparse solve.

    The bottom slab is displaced by a small :math:`u_z` (``wave="p"``, uniaxial strain) or
    :math:`u_x` (``wave="s"``, simple shear), all of its particles alike, the top slab is held
    fixed, the periodic box keeps the lateral strain zero; :math:`K_{ff} u_f = -K_{fp} u_p` is
    solved by Jacobi-preconditioned conjugate gradients on the free particles bonded, directly or
    through others, to an end slab (rattlers and floating cement clusters drop out). The stress is
    the reaction on the fixed slab over the box area (the same through every horizontal section);
    the strain is the slope of a least-squares line through the centres of mass of the interior
    slabs (their load-path particles) in :math:`(z, u_z)` — the part of the sample the pulse test's
    detectors see.
    """
    import scipy.sparse.linalg as spla

    slab, n_slabs, flag = _prescribed(system)
    n = system.n_particles
    amp = 1e-6 * system.slab_thickness
    u_p = np.zeros((n, 3))
    ax = _wave_axis(wave)
    u_p[flag == 2, ax] = amp
    diag = system.stiffness_diagonal()      # Jacobi preconditioner; zero: no bonds
    connected = _load_path(system, flag)
    free = ((flag == 0) & connected)[:, None] & (diag > 0)
    free_idx = np.flatnonzero(free.ravel())
    if free_idx.size == 0:
        raise ValueError("no free particle between the end slabs is bonded to them")
    b = system.forces(u_p).ravel()[free_idx]

    def matvec(y):
        u = np.zeros(3 * n)
        u[free_idx] = y
        return -system.forces(u).ravel()[free_idx]

    op = spla.LinearOperator((free_idx.size,) * 2, matvec=matvec, dtype=float)
    pre = spla.LinearOperator((free_idx.size,) * 2, matvec=lambda y: y / diag.ravel()[free_idx],
                              dtype=float)
    count = [0]

    def callback(_):
        count[0] += 1

    y, info = spla.cg(op, b, rtol=rtol, atol=0.0, M=pre,
                      maxiter=maxiter or 20 * free_idx.size, callback=callback)
    if info != 0:
        raise RuntimeError(f"static solve did not converge in {count[0]} CG iterations")
    u = u_p.ravel().copy()
    u[free_idx] = y
    u = u.reshape(n, 3)
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
                           "(no load-bearing path)")
    return StaticModulus(modulus, density, math.sqrt(modulus / density), slope, stress,
                         count[0])


def _first_peak(signal, floor=0.0):
    """Index of the maximum of the first run of samples at or above half the global maximum
    (−1 if that maximum is not above ``floor`` or the run has not ended)."""
    top = np.max(signal)
    if not top > max(floor, 0.0):
        return -1
    above = signal >= 0.5 * top
    start = int(np.argmax(above))
    run = above[start:]
    if run.all():
        if start > 0:
            return -1                                   # still rising at the end of the record
        stop = signal.size
    else:
        stop = start + int(np.argmin(run))
    return start + int(np.argmax(signal[start:stop]))


def pulse_test(system: AcousticSystem, wave="p", *, detectors=None, time_step_factor=0.5,
               pulse_duration=None, max_time=None, record_every=1, progress=False):
    """Acoustic pulse test (García & Medina, Sect. III G, eqs. 10–11).

    The sample is cut into slabs of ``system.slab_thickness`` along z. The bottom slab is
    displaced by a square wave — :math:`u_z = u_0` (``wave="p"``) or :math:`u_x = u_0`
    (``wave="s"``, the shear-wave variant) for :math:`0 \\le t < \\tau`, then back to 0 — the
    top slab is held fixed, and the linear system is integrated by the central-difference
    scheme. The signal of a slab (eq. 10) is the mean over its particles of the z (or x) force
    of their contacts, each bond's force on its second particle times the z component of its
    normal, halved between the two ends (compression positive): the particle's share of the
    slab's :math:`\\sigma_{zz}` (:math:`\\sigma_{xz}`). This unipolar signal peaks where the
    pulse is; the slab mean of the *net* force on the particles is the difference of the stresses
    on the slab's faces, a bipolar derivative of the pulse whose dispersive tail outgrows its
    first peak within a few slabs. The arrival time at a detector is the time of the maximum of
    the first pulse (the first run of the signal above half its maximum), so a reflection from
    the fixed end is not taken for it. With detectors at slabs :math:`s_1, s_2` a distance
    :math:`L` apart and arrival times :math:`T_1, T_2`, eq. 11 gives

    .. math:: V = \\frac{L}{T_2 - T_1} \\pm \\frac{L\\Delta T + (T_2-T_1)\\Delta L}{(T_2 - T_1)^2}

    with :math:`\\Delta L` the mean grain radius (the cell width for a pure cement block) and
    :math:`\\Delta T` the recording interval.

    The static modulus of the same operator (:func:`static_modulus`) is returned as a
    cross-check: :math:`\\sqrt{M/\\rho}` is the long-wave limit of the pulse velocity. They agree
    where the sample is homogeneous on the scale of the pulse (a cement block: 2 %); in grain
    packs the pulse, a few grains long, is dispersed and travels 5–30 % slower.

    Parameters
    ----------
    system : AcousticSystem
    wave : {"p", "s"}
    detectors : (int, int), optional
        Detector slabs, default ``(1, n_slabs - 3)`` (``(1, n_slabs - 2)`` for 4 or 5 slabs):
        two slabs are left before the fixed one, where the reflected pulse overlaps the incident
        one.
    time_step_factor : float
        Time step as a fraction of :math:`2/\\omega_{max}` (the stability limit of the scheme,
        :math:`\\omega_{max}` bounded by Gershgorin), in (0, 1]; default 0.5.
    pulse_duration : float, optional
        :math:`\\tau`, s; default twice the time a wave at the static velocity takes to cross
        one slab.
    max_time : float, optional
        Simulated time, s. By default the run lasts :math:`\\tau` plus 1.5 times the
        static-velocity travel time to the far detector and is extended (up to 20 times) until
        the far detector's first pulse has passed.
    record_every : int
        Record the slab signals every this many steps (:math:`\\Delta T`), ``>= 1``.
    progress : bool
        Show a progress bar (tqdm).

    Returns
    -------
    xarray.Dataset
        ``signal`` (time, slab), N; ``arrival_time`` (slab), s; ``n_particles`` (slab); scalars
        ``velocity`` and ``velocity_error`` (m/s, eq. 11), ``velocity_fit`` (m/s, least-squares
        slope of the arrival times of the detector slabs from :math:`s_1` to :math:`s_2`),
        ``velocity_static`` and ``modulus_static`` (the static cross-check), ``density``; the
        wave, time step, pulse duration and detector slabs in attributes.

    Raises
    ------
    ValueError
        For a sample of fewer than 4 slabs, detectors outside the interior slabs, or knobs out
        of range.
    RuntimeError
        When no first pulse is resolved at the detectors (e.g. no load path).
    """
    import xarray as xr
    from tqdm.auto import tqdm

    from ._kernels_acoustic import leapfrog_run

    if not 0.0 < time_step_factor <= 1.0:
        raise ValueError(f"time_step_factor must lie in (0, 1]; got {time_step_factor}")
    if int(record_every) != record_every or record_every < 1:
        raise ValueError(f"record_every must be an integer >= 1; got {record_every}")
    record_every = int(record_every)
    slab, n_slabs, flag = _prescribed(system)
    if detectors is None:                        # keep the far detector clear of the reflection
        s1, s2 = 1, (n_slabs - 3 if n_slabs >= 6 else n_slabs - 2)
    else:
        s1, s2 = (int(d) for d in detectors)
    if not 0 < s1 < s2 < n_slabs - 1:
        raise ValueError(f"detectors must be two slabs with 0 < s1 < s2 < {n_slabs - 1} "
                         f"(between the source and the fixed slab); got {detectors}")
    ax = _wave_axis(wave)
    static = static_modulus(system, wave)
    h = system.slab_thickness
    z0 = system.extent[0]
    centres = z0 + (np.arange(n_slabs) + 0.5) * h
    tau = 2.0 * h / static.velocity if pulse_duration is None else float(pulse_duration)
    if not tau > 0:
        raise ValueError(f"pulse_duration must be > 0 s; got {pulse_duration}")
    travel = (centres[s2] - centres[0]) / static.velocity
    t_run = tau + 1.5 * travel if max_time is None else float(max_time)
    t_cap = 20.0 * t_run if max_time is None else t_run
    omega = system.max_frequency()
    dt = time_step_factor * 2.0 / omega
    counts = np.bincount(slab, minlength=n_slabs)
    inv_m = 1.0 / system.masses
    n = system.n_particles
    u = np.zeros((n, 3))
    v = np.zeros((n, 3))
    amp = 1e-4 * system.slab_thickness
    u[flag == 2, ax] = amp
    args = (inv_m, flag, slab, n_slabs, *system._kernel_args())
    chunk = max(1, int(min(2000, math.ceil(t_run / dt))) // record_every) * record_every
    records = []
    t = 0.0
    bar = tqdm(total=t_run, disable=not progress, desc="pulse test", unit="s",
               bar_format="{l_bar}{bar}| {n:.3g}/{total:.3g} s simulated")
    while True:
        left = max(1, math.ceil((t_run - t) / dt / record_every)) * record_every
        steps = min(chunk, left)                 # the last chunk stops at t_run
        rec = np.empty((steps // record_every, n_slabs))
        leapfrog_run(u, v, *args, dt, t, steps, amp, tau, record_every, ax, rec)
        records.append(rec / np.maximum(counts, 1))
        t += steps * dt
        bar.update(min(steps * dt, max(t_run - bar.n, 0.0)))
        if t >= t_run:
            sig = np.concatenate(records)
            if _first_peak(sig[:, s2], 0.1 * sig[:, s1].max()) >= 0 or t >= t_cap:
                break
            t_run = min(t_run * 1.25, t_cap)
    bar.close()
    signal = np.concatenate(records)
    times = np.arange(signal.shape[0]) * dt * record_every
    arrival = np.full(n_slabs, np.nan)
    floor = 0.02 * signal[:, s1].max()
    for s in range(1, n_slabs - 1):
        k = _first_peak(signal[:, s], floor)
        if k >= 0:
            arrival[s] = times[k]
    if not (np.isfinite(arrival[s1]) and np.isfinite(arrival[s2]) and arrival[s2] > arrival[s1]):
        raise RuntimeError(f"no pulse arrival was resolved at detectors {s1} and {s2} within "
                           f"{t:.3g} s; raise max_time")
    L = centres[s2] - centres[s1]
    T = arrival[s2] - arrival[s1]
    dT = dt * record_every
    dL = float(system.metadata["mean_radius"] if system.n_grains else
               system.metadata["cell_width"])
    vel = L / T
    vel_err = (L * dT + T * dL) / T**2
    sel = np.arange(s1, s2 + 1)
    ok = np.isfinite(arrival[sel])
    vel_fit = float(1.0 / np.polyfit(centres[sel][ok], arrival[sel][ok], 1)[0]) \
        if ok.sum() >= 2 else np.nan
    name = wave.upper()
    return xr.Dataset(
        {
            "signal": (("time", "slab"), signal,
                       {"long_name": f"mean {'zx'[ax == 0]} contact force per particle of the "
                                     "slab (eq. 10)", "units": "N"}),
            "arrival_time": (("slab",), arrival, {"units": "s"}),
            "n_particles": (("slab",), counts),
            "velocity": ((), vel, {"units": "m s-1", "long_name": f"{name} velocity (eq. 11)"}),
            "velocity_error": ((), vel_err, {"units": "m s-1",
                                             "long_name": "error of velocity (eq. 11)"}),
            "velocity_fit": ((), vel_fit, {"units": "m s-1",
                                           "long_name": f"{name} velocity from all detectors"}),
            "velocity_static": ((), static.velocity, {"units": "m s-1"}),
            "modulus_static": ((), static.modulus, {"units": "Pa"}),
            "density": ((), static.density, {"units": "kg m-3"}),
        },
        coords={"time": ("time", times, {"units": "s"}),
                "slab": ("slab", np.arange(n_slabs)),
                "z": ("slab", centres, {"units": "m", "long_name": "slab centre"})},
        attrs={"wave": wave, "time_step_s": dt, "time_step_factor": time_step_factor,
               "pulse_duration_s": tau, "amplitude_m": amp, "detectors": [s1, s2],
               "distance_m": L, "delta_L_m": dL, "delta_T_s": dT,
               "references": "García & Medina, Sects. III F-G, eqs. 4-11"},
    )
