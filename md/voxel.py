"""Voxel finite elements: the static, transversely isotropic stiffness of a digital sample.

The digital-rock standard (Garboczi 1998, NIST IR 6269, its elastic finite-element programs;
Arns et al. 2002, Geophysics 67, 1396): every voxel of the sample is an 8-node trilinear
hexahedron (the isoparametric brick of Hughes 2000, *The Finite Element Method*, Ch. 3) of one
isotropic material, and the displacement that minimises the elastic energy under a macroscopic
strain is found by preconditioned conjugate gradients. Here the voxels are the cells of the MD
cement lattice (:func:`md.cement.cement_lattice`): a cell whose centre is inside a grain is
grain material, a cemented cell is cement, the rest is dry pore (:func:`pack_phases`), so the
grains and the cement are one continuous solid with its own Poisson coupling, where the MD
acoustic stage holds rigid grains on beds of springs and a lattice of pair springs
(docs/studies/md_full_cement.md).

The sample is periodic in x and y (the pack's box) and not along z. It is loaded as
:func:`md.static.static_stiffness` loads the MD sample, with one change in what is measured
(:func:`voxel_stiffness`): both end slabs follow the macroscopic displacement gradient, the
voxels between relax, and the stress and the strain are the means over one band, between two
node planes half a slab inside the end slabs — the stress the volume mean over the band's
voxels, the strain the difference of the mean displacements of its two bounding planes. Both
are then the means over the same volume, exact for a laminate (Backus's average), where a
least-squares slope through the interior is not.

Limits (docs/studies/md_voxel_fe.md): a cell is one material, so two grains are welded
wherever their voxels touch — over a disc of radius about :math:`\\sqrt{2hR}` around each
contact, not the contact's own. Where the pores are full of cement that does not matter (the
full sample converges to 0.1 % per step of :math:`\\Omega`, at the Hashin–Shtrikman bound), but
where the load runs through uncemented grain contacts (a coating, a bare pack) the constants are
far too stiff and converge slowly (7 % per step at :math:`\\Omega` 6 on a coating at
:math:`S_c` 0.37).

SI units (Pa, kg/m³, m).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .static import PA_PER_GPA, StaticStiffness

__all__ = ["VoxelPhase", "VoxelStiffness", "element_matrices", "voxel_stiffness",
           "pack_phases", "sample_stiffness", "SOLVERS", "EMPTY"]

#: Phase index of an empty (dry pore) voxel in the grids of :func:`voxel_stiffness`.
EMPTY = -1
#: Preconditioners of the conjugate gradients: smoothed-aggregation algebraic multigrid
#: (pyamg) or the inverse 3 x 3 diagonal blocks of the stiffness (block Jacobi).
SOLVERS = ("amg", "jacobi")

# The five loads (displacement gradients, one entry 1) of the transversely isotropic sample.
_LOADS = {"z": (2, 2), "xz": (0, 2), "x": (0, 0), "y": (1, 1), "xy": (0, 1)}
_STRAIN = 1e-6


@dataclass(frozen=True)
class VoxelPhase:
    """One isotropic material of a voxel sample (SI units).

    Parameters
    ----------
    bulk_modulus, shear_modulus : float
        Pa, ``> 0`` (so the Poisson ratio lies in (-1, 0.5)).
    density : float
        kg/m³, ``> 0``.
    """

    bulk_modulus: float
    shear_modulus: float
    density: float

    def __post_init__(self):
        bad = [(n, v) for n, v in zip(("bulk_modulus", "shear_modulus", "density"),
                                      (self.bulk_modulus, self.shear_modulus, self.density))
               if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.number))
               or not (math.isfinite(v) and v > 0)]
        if bad:
            raise ValueError(f"voxel phase {bad[0][0]} must be a finite number > 0 (Pa, or "
                             f"kg/m3 for density); got {bad[0][1]!r}")

    @property
    def lame_lambda(self) -> float:
        """:math:`\\lambda = K - \\tfrac23 G`, Pa."""
        return self.bulk_modulus - 2.0 * self.shear_modulus / 3.0

    @classmethod
    def of_grain(cls, material) -> VoxelPhase:
        """The phase of a :class:`md.contact.GrainMaterial` (its :math:`G`, :math:`\\nu`,
        density): :math:`K = 2G(1+\\nu)/(3(1-2\\nu))`."""
        G, nu = material.shear_modulus, material.poisson_ratio
        return cls(2.0 * G * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu)), G, material.density)

    @classmethod
    def of_cement(cls, cement) -> VoxelPhase:
        """The phase of a :class:`md.cement.CementMaterial`: :math:`G = \\rho V_s^2`,
        :math:`K = \\rho(V_p^2 - \\tfrac43 V_s^2)`."""
        return cls(cement.p_modulus - 4.0 / 3.0 * cement.shear_modulus, cement.shear_modulus,
                   cement.density)


@dataclass(frozen=True)
class VoxelStiffness(StaticStiffness):
    """:class:`md.static.StaticStiffness` of a voxel sample (same fields, Pa and kg/m³), with
    ``metadata``: ``n_voxels`` (solid voxels), ``n_elements`` (those on the load path),
    ``dropped_clusters`` and ``dropped_voxels`` (solid voxels not joined through faces to both
    end slabs), ``free_dof``, ``solver``, ``rtol``, ``iterations`` (per load), ``setup_s`` and
    ``solve_s`` (wall times), ``band`` (the node planes of the measured band)."""

    metadata: dict = field(default_factory=dict, compare=False, repr=False)


def element_matrices():
    """Stiffness matrices of the unit cube's 8-node trilinear hexahedron for :math:`\\lambda = 1,
    \\mu = 0` and for :math:`\\lambda = 0, \\mu = 1`.

    :math:`K_e = \\int_{V_e} B^T D B\\,dV` (the element stiffness of the displacement method,
    Hughes 2000, Chs. 2-3; Garboczi 1998's elastic programs minimise the same energy) with
    the isotropic :math:`D = \\lambda\\,\\mathbf 1\\mathbf 1^T + \\mu\\,
    \\mathrm{diag}(2, 2, 2, 1, 1, 1)` (engineering shear strains), integrated by 2 x 2 x 2
    Gauss–Legendre quadrature (points :math:`\\tfrac12 \\pm \\tfrac{1}{2\\sqrt3}`, weights
    :math:`\\tfrac18`), exact here since the integrand is of degree 2 in each coordinate. For a
    cube of side :math:`h`, :math:`K_e = h(\\lambda K_\\lambda + \\mu K_\\mu)`.

    Returns
    -------
    (ndarray, ndarray)
        :math:`K_\\lambda` and :math:`K_\\mu`, shape (24, 24); node :math:`a` at the corner
        ``(a & 1, a >> 1 & 1, a >> 2 & 1)``, its x, y, z components at rows ``3a``..``3a+2``.
    """
    corners = np.array([(a & 1, (a >> 1) & 1, (a >> 2) & 1) for a in range(8)], float)
    g = np.array([0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0)])
    D_lam = np.zeros((6, 6))
    D_lam[:3, :3] = 1.0
    D_mu = np.diag([2.0, 2.0, 2.0, 1.0, 1.0, 1.0])
    KL, KM = np.zeros((24, 24)), np.zeros((24, 24))
    for x in g:
        for y in g:
            for z in g:
                s = np.array([x, y, z])
                # N_a = prod_j (o_aj s_j + (1 - o_aj)(1 - s_j)); dN_a/ds_j.
                f = np.where(corners == 1, s, 1.0 - s)
                df = 2.0 * corners - 1.0
                grad = np.stack([df[:, j] * np.prod(np.delete(f, j, axis=1), axis=1)
                                 for j in range(3)], axis=1)
                B = np.zeros((6, 24))
                for a in range(8):
                    gx, gy, gz = grad[a]
                    c = 3 * a
                    B[0, c], B[1, c + 1], B[2, c + 2] = gx, gy, gz
                    B[3, c + 1], B[3, c + 2] = gz, gy          # gamma_yz
                    B[4, c], B[4, c + 2] = gz, gx              # gamma_xz
                    B[5, c], B[5, c + 1] = gy, gx              # gamma_xy
                KL += 0.125 * B.T @ D_lam @ B
                KM += 0.125 * B.T @ D_mu @ B
    return KL, KM


def _check_phases(phase, materials):
    phase = np.asarray(phase)
    if phase.ndim != 3 or min(phase.shape) < 1:
        raise ValueError(f"phase must be a 3-d grid (nx, ny, nz) of phase indices; got shape "
                         f"{phase.shape}")
    if not np.issubdtype(phase.dtype, np.integer):
        raise ValueError("phase must hold integer phase indices (-1: empty)")
    materials = tuple(materials)
    if not materials:
        raise ValueError("materials must hold at least one VoxelPhase")
    for m in materials:
        if not isinstance(m, VoxelPhase):
            raise ValueError(f"materials must be VoxelPhase instances; got {type(m).__name__}")
    lo, hi = int(phase.min()), int(phase.max())
    if lo < EMPTY or hi >= len(materials):
        raise ValueError(f"phase indices must lie in [-1, {len(materials) - 1}] (-1 empty, "
                         f"else an index into materials); got {lo} to {hi}")
    if hi < 0:
        raise ValueError("the voxel sample is empty: no voxel holds a solid phase")
    return phase, materials


def _face_clusters(solid, nx, ny, nz):
    """Label of every solid voxel's cluster, voxels joined through shared faces (periodic in x
    and y); returns the labels of the flat solid voxels (x fastest)."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    flat = solid.ravel(order="F")
    cells = np.flatnonzero(flat)
    where = np.full(flat.size, -1, np.int64)
    where[cells] = np.arange(cells.size)
    i, j, k = cells % nx, (cells // nx) % ny, cells // (nx * ny)
    rows, cols = [], []
    for di, dj, dk in ((1, 0, 0), (0, 1, 0), (0, 0, 1)):
        kk = k + dk
        ok = kk < nz
        nb = ((i + di) % nx + nx * ((j + dj) % ny + ny * np.minimum(kk, nz - 1)))[ok]
        other = where[nb]
        rows.append(np.arange(cells.size)[ok][other >= 0])
        cols.append(other[other >= 0])
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = sp.coo_matrix((np.ones(r.size, np.int8), (r, c)), shape=(cells.size,) * 2)
    return cells, connected_components(graph, directed=False)[1]


def _matrix(nodes, lam, mu, h, free, n_free):
    """The stiffness of the free nodes as a block-sparse (3 x 3) matrix."""
    import scipy.sparse as sp

    from ._kernels_voxel import assemble_blocks

    KL, KM = element_matrices()
    data = np.zeros((n_free, 27, 3, 3))
    col = np.full((n_free, 27), -1, np.int64)
    assemble_blocks(nodes, lam, mu, KL, KM, h, free, data, col)
    keep = col >= 0
    indptr = np.concatenate([[0], np.cumsum(keep.sum(axis=1))])
    A = sp.bsr_matrix((data[keep], col[keep], indptr), shape=(3 * n_free, 3 * n_free))
    del data
    A.sum_duplicates()          # a grid two cells wide meets one neighbour twice
    return A, KL, KM


def _preconditioner(A, solver, coords):
    """``M`` for :func:`scipy.sparse.linalg.cg` approximating :math:`A^{-1}`."""
    import scipy.sparse.linalg as spla

    if solver == "amg":
        import pyamg

        n = coords.shape[0]
        B = np.zeros((3 * n, 6))            # rigid-body modes: the near null space
        for a in range(3):
            B[a::3, a] = 1.0
        x, y, z = (coords[:, a] - coords[:, a].mean() for a in range(3))
        B[0::3, 3], B[1::3, 3] = -y, x
        B[1::3, 4], B[2::3, 4] = -z, y
        B[0::3, 5], B[2::3, 5] = z, -x
        scale = np.abs(B[:, 3:]).max() or 1.0
        B[:, 3:] /= scale
        ml = pyamg.smoothed_aggregation_solver(A, B=B, symmetry="symmetric",
                                               strength="symmetric", max_coarse=500)
        return ml.aspreconditioner(cycle="V")
    # Block Jacobi: the inverse of each node's own 3 x 3 block.
    d = np.zeros((A.shape[0] // 3, 3, 3))
    Abs = A.tobsr(blocksize=(3, 3))
    rows = np.repeat(np.arange(Abs.shape[0] // 3), np.diff(Abs.indptr))
    diag = rows == Abs.indices
    d[rows[diag]] = Abs.data[diag]
    inv = np.linalg.inv(d)
    return spla.LinearOperator(A.shape, matvec=lambda r: np.einsum(
        "nab,nb->na", inv, r.reshape(-1, 3)).ravel(), dtype=float)


def voxel_stiffness(phase, materials, cell_width, *, slab_thickness, margin=0.5, rtol=1e-8,
                    solver="amg", maxiter=None) -> VoxelStiffness:
    """The five constants of a voxel sample, transversely isotropic about z, by static finite
    elements.

    Each voxel is an 8-node trilinear hexahedron (:func:`element_matrices`; Garboczi 1998,
    NIST IR 6269; Arns et al. 2002). The sample is periodic in x and y; the displacement is
    :math:`\\mathbf u = H\\mathbf x + \\mathbf w` with :math:`\\mathbf w` periodic (as in
    Garboczi 1998: the macroscopic strain enters through the jumps at the periodic sides) and
    :math:`\\mathbf w = 0` on the nodes of the end slabs (the voxels of the bottom and top
    ``slab_thickness``), which so follow the affine displacement :math:`H\\mathbf x` as the end
    slabs of :func:`md.static.static_stiffness` do. Five loads :math:`H` (one entry
    ``1e-6``): ``"z"`` (:math:`H_{zz}`), ``"xz"`` (simple shear :math:`u_x = \\gamma z`),
    ``"x"``, ``"y"`` (uniaxial strain in the plane) and ``"xy"`` (:math:`u_x = \\gamma y`).

    Measured over the band between the node planes ``margin`` slabs inside the end slabs:
    the mean stress :math:`\\bar\\sigma = \\frac1V\\sum_e V_e\\sigma_e` over its voxels (void
    counts as zero stress; the mean over a trilinear brick of its stress is its value at the
    centre) and the mean strain, whose in-plane part is :math:`H`'s (the fluctuations are
    periodic) and whose z derivatives are the differences of the mean displacements of the
    band's two bounding planes (each node weighted by its solid voxels) over its height. Then,
    as in :func:`md.static.static_stiffness`: :math:`C_{33} = \\bar\\sigma_{zz}/\\bar
    \\varepsilon_{zz}`, :math:`C_{13} = \\tfrac12(\\bar\\sigma_{xx} + \\bar\\sigma_{yy})/
    \\bar\\varepsilon_{zz}` (load ``"z"``), :math:`C_{44} = \\bar\\sigma_{xz}/2\\bar
    \\varepsilon_{xz}`, :math:`C_{11} = (\\bar\\sigma_{xx} - C_{13}\\bar\\varepsilon_{zz})/
    \\varepsilon`, :math:`C_{12}`, :math:`C_{31}` likewise (x and y averaged) and
    :math:`C_{66} = \\bar\\sigma_{xy}/2\\bar\\varepsilon_{xy}`.

    Solid voxels not joined through shared faces to both end slabs (floating clusters, and
    voxels hanging by an edge or a corner, which would be mechanisms) are dropped, and so are
    the nodes no remaining voxel touches; both are counted in ``metadata``.

    Parameters
    ----------
    phase : array_like of int, shape (nx, ny, nz)
        Phase of each voxel: an index into ``materials``, or :data:`EMPTY` (-1) for pore.
    materials : sequence of VoxelPhase
    cell_width : float
        Voxel side, m, ``> 0``.
    slab_thickness : float
        Thickness of each end slab, m (rounded to whole voxels, at least one).
    margin : float
        Distance of the measured band from each end slab, slabs, in [0, 1]; 0: the whole
        interior (the apparent stiffness under affine displacement of its faces).
    rtol : float
        Relative residual of the conjugate gradients, in (0, 1).
    solver : {"amg", "jacobi"}
        Preconditioner: smoothed-aggregation algebraic multigrid (pyamg, Vaněk, Mandel &
        Brezina 1996; rigid-body modes as near null space) or block Jacobi.
    maxiter : int, optional
        Iteration cap per load (default 10 000).

    Returns
    -------
    VoxelStiffness
        The fields of :class:`md.static.StaticStiffness` (Pa; density the solid voxels' mass
        over the grid's volume, kg/m³) and ``metadata``.
    """
    import scipy.sparse.linalg as spla

    from rockcem.anisotropy import thomsen, ti_bulk_modulus

    from ._kernels_voxel import affine_forces, band_stress, element_nodes

    phase, materials = _check_phases(phase, materials)
    if not (np.isfinite(cell_width) and cell_width > 0):
        raise ValueError(f"cell_width must be a finite length > 0 m; got {cell_width!r}")
    if not (np.isfinite(slab_thickness) and slab_thickness > 0):
        raise ValueError(f"slab_thickness must be a finite length > 0 m; got "
                         f"{slab_thickness!r}")
    if not 0.0 <= margin <= 1.0:
        raise ValueError(f"margin must lie in [0, 1] slabs; got {margin!r}")
    if not 0.0 < rtol < 1.0:
        raise ValueError(f"rtol must lie in (0, 1); got {rtol!r}")
    if solver not in SOLVERS:
        raise ValueError(f"solver must be one of {SOLVERS}; got {solver!r}")
    maxiter = 10_000 if maxiter is None else int(maxiter)
    if maxiter < 1:
        raise ValueError(f"maxiter must be >= 1; got {maxiter}")
    t0 = time.perf_counter()
    h = float(cell_width)
    nx, ny, nz = phase.shape
    ns = max(int(round(slab_thickness / h)), 1)
    off = int(round(margin * ns))
    kb, kt = ns + off, nz - ns - off        # node planes bounding the measured band
    if kt - kb < 1:
        raise ValueError(f"the sample is {nz} voxels tall: too short for two end slabs of "
                         f"{ns} voxels and a measured band between them (margin {margin:g} "
                         "slabs); use a taller sample or thinner slabs")
    solid = phase >= 0
    cells, label = _face_clusters(solid, nx, ny, nz)
    k_cell = cells // (nx * ny)
    bottom = np.unique(label[k_cell < ns])
    top = np.unique(label[k_cell >= nz - ns])
    anchored = np.intersect1d(bottom, top)
    keep = np.isin(label, anchored)
    if not keep.any():
        raise ValueError("no solid path joins the two end slabs of the voxel sample (through "
                         "shared faces): it has no stiffness along z")
    dropped_clusters = int(np.unique(label[~keep]).size)
    elements = cells[keep]
    ph = phase.ravel(order="F")[elements]
    lam_of = np.array([m.lame_lambda for m in materials])
    mu_of = np.array([m.shear_modulus for m in materials])
    lam, mu = lam_of[ph], mu_of[ph]
    nodes = np.empty((elements.size, 8), np.int64)
    element_nodes(elements, nx, ny, nodes)
    n_nodes = nx * ny * (nz + 1)
    weight = np.bincount(nodes.ravel(), minlength=n_nodes)
    k_el = elements // (nx * ny)
    in_slab = (k_el < ns) | (k_el >= nz - ns)
    held = np.zeros(n_nodes, bool)
    held[nodes[in_slab].ravel()] = True
    free_nodes = np.flatnonzero((weight > 0) & ~held)
    free = np.full(n_nodes, -1, np.int64)
    free[free_nodes] = np.arange(free_nodes.size)
    A, KL, KM = _matrix(nodes, lam, mu, h, free, free_nodes.size)
    node_k = np.arange(n_nodes) // (nx * ny)
    coords = np.stack([np.arange(n_nodes) % nx, (np.arange(n_nodes) // nx) % ny, node_k],
                      axis=1)[free_nodes] * h
    M = _preconditioner(A, solver, coords)
    t_setup = time.perf_counter() - t0
    band = (k_el >= kb) & (k_el < kt)
    band_nodes = nodes[band]
    volume = nx * ny * (kt - kb) * h**3
    planes = [np.flatnonzero((node_k == k) & (weight > 0)) for k in (kb, kt)]
    loads, iterations = {}, {}
    for name, (a, b) in _LOADS.items():
        H = np.zeros((3, 3))
        H[a, b] = _STRAIN
        rhs = np.zeros((free_nodes.size, 3))
        affine_forces(nodes, lam, mu, KL, KM, h, H, free, rhs)
        count = [0]

        def step(_, count=count):
            count[0] += 1

        x, info = spla.cg(A, rhs.ravel(), rtol=rtol, atol=0.0, M=M, maxiter=maxiter,
                          callback=step)
        if info != 0:
            raise RuntimeError(f"voxel solve (load {name!r}) did not reach rtol {rtol:g} in "
                               f"{maxiter} CG iterations")
        w = np.zeros((n_nodes, 3))
        w[free_nodes] = x.reshape(-1, 3)
        sig = np.zeros((3, 3))
        band_stress(band_nodes, lam[band], mu[band], h, H, w, sig)
        sig /= volume
        mean = [np.average(w[p], axis=0, weights=weight[p]) for p in planes]
        grad = H.copy()
        grad[:, 2] += (mean[1] - mean[0]) / ((kt - kb) * h)
        loads[name] = (0.5 * (grad + grad.T), sig, count[0])
        iterations[name] = count[0]
    e, sig, _ = loads["z"]
    c33 = sig[2, 2] / e[2, 2]
    c13 = 0.5 * (sig[0, 0] + sig[1, 1]) / e[2, 2]
    e, sig, _ = loads["xz"]
    c44 = sig[0, 2] / (2.0 * e[0, 2])
    # The in-plane loads x (axis 0) and y (axis 1), averaged; their small interior strain
    # e_zz is taken out with the "z" constants.
    strain = np.stack([loads["x"][0], loads["y"][0]])
    stress = np.stack([loads["x"][1], loads["y"][1]])
    axis, both = np.array([0, 1]), np.array([0, 1])
    eps, ezz = strain[both, axis, axis], strain[:, 2, 2]
    c11 = float(np.mean((stress[both, axis, axis] - c13 * ezz) / eps))
    c12 = float(np.mean((stress[both, 1 - axis, 1 - axis] - c13 * ezz) / eps))
    c31 = float(np.mean((stress[:, 2, 2] - c33 * ezz) / eps))
    e, sig, _ = loads["xy"]
    c66 = sig[0, 1] / (2.0 * e[0, 1])
    if not (c33 > 0 and c44 > 0 and c66 > 0 and c11 > 0):
        raise RuntimeError(f"the voxel sample has no positive stiffness (C33 {c33:.3g}, C44 "
                           f"{c44:.3g}, C11 {c11:.3g}, C66 {c66:.3g} Pa)")
    gpa = [v / PA_PER_GPA for v in (c11, c13, c33, c44, c66)]
    th = thomsen(*gpa)
    # Bulk moduli of the measured normal block with its own C12 (C66 := (C11 - C12)/2 in the
    # closed form): under hydrostatic stress, and C_iijj/9 under hydrostatic strain.
    bulk_reuss = float(ti_bulk_modulus(gpa[0], gpa[1], gpa[2], 0.5 * (gpa[0] - c12 / PA_PER_GPA))) \
        * PA_PER_GPA
    bulk_voigt = (2.0 * c11 + c33 + 2.0 * c12 + 4.0 * c13) / 9.0
    rho_of = np.array([m.density for m in materials])
    density = float(rho_of[phase[solid]].sum()) / (nx * ny * nz)
    meta = {"n_voxels": int(cells.size), "n_elements": int(elements.size),
            "dropped_clusters": dropped_clusters, "dropped_voxels": int((~keep).sum()),
            "free_dof": int(3 * free_nodes.size), "solver": solver, "rtol": float(rtol),
            "iterations": iterations, "setup_s": t_setup,
            "solve_s": time.perf_counter() - t0 - t_setup, "band": (kb, kt),
            "slab_voxels": ns}
    return VoxelStiffness(float(c11), float(c12), float(c13), float(c33), float(c44),
                          float(c66), float(c31), density, bulk_reuss, bulk_voigt,
                          float(th.epsilon), float(th.gamma), float(th.delta), loads, meta)


def pack_phases(pack, lattice, cemented=None):
    """The voxel grid of a cemented pack: the cells of its cement lattice, grain (0) where the
    cell's centre is inside a grain, cement (1) where the cell is cemented, else
    :data:`EMPTY`.

    Parameters
    ----------
    pack : md.Pack
    lattice : md.CementLattice
        The pack's lattice (:func:`md.cement.cement_lattice`).
    cemented : array_like of bool, optional
        One per pore cell of ``lattice`` (the ``cells`` of :func:`md.along_depth.cement_cells`
        or :func:`md.growth.cement_fill` when its fills are whole cells); fills strictly between
        0 and 1 (films thinner than a cell) are refused: a voxel is one material.

    Returns
    -------
    ndarray of int8, shape ``lattice.shape``
    """
    nx, ny, nz = lattice.shape
    flat = np.zeros(nx * ny * nz, np.int8)
    flat[lattice.index] = EMPTY
    if cemented is not None:
        c = np.asarray(cemented)
        if c.shape != lattice.index.shape:
            raise ValueError(f"cemented must hold one entry per pore cell of the lattice "
                             f"({lattice.index.size}); got shape {c.shape}")
        if c.dtype != bool:
            c = c.astype(float)
            if np.any((c != 0) & (c != 1)):
                raise ValueError("cemented holds fills strictly between 0 and 1 (a film "
                                 "thinner than a cell): voxel elements take whole cells only")
            c = c == 1
        flat[lattice.index[c]] = 1
    return flat.reshape((nx, ny, nz), order="F")


def sample_stiffness(pack, lattice, cemented, cement, *, grain=None, slab_thickness=None,
                     **options) -> VoxelStiffness:
    """:func:`voxel_stiffness` of a pack cemented on its lattice (:func:`pack_phases`).

    Parameters
    ----------
    pack : md.Pack
    lattice : md.CementLattice
    cemented : array_like of bool or None
    cement : md.CementMaterial
    grain : md.GrainMaterial, optional
        Default the pack's material.
    slab_thickness : float, optional
        m; default two largest grain diameters, as :func:`md.acoustic.acoustic_system`.
    **options
        ``margin``, ``rtol``, ``solver``, ``maxiter`` of :func:`voxel_stiffness`.
    """
    grain = pack.material if grain is None else grain
    t = 4.0 * float(pack.radii.max()) if slab_thickness is None else slab_thickness
    return voxel_stiffness(pack_phases(pack, lattice, cemented),
                           (VoxelPhase.of_grain(grain), VoxelPhase.of_cement(cement)),
                           lattice.cell_width, slab_thickness=t, **options)
