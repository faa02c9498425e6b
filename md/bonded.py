r"""Bonded-contact cement: grains joined by cement bonds, and their static moduli.

Xu 2023 (Sects. 2.2–2.3, Figs. 1–6) validates the contact cement theory (CCT, contact bonding:
touching grains, :math:`h = 0`) and its contact-thickness extension (MCCT, distant bonding: a
gap :math:`h` bridged by cement) with grain packs whose cemented pairs carry a *bond*: a disc
of cement of radius :math:`a` between the two grains, with normal and shear springs, and
bending and twisting resistance. This module builds such samples from an :class:`md.Pack`,
linearises them (translations *and* rotations of every grain, 6 degrees of freedom) and
computes the static bulk and shear moduli by sparse solves under isotropic and shear strain.

The bond stiffness (normal, shear, bending, twisting) follows from the cement and grain
moduli and the bond geometry by the lumped layer-plus-half-space model of
:mod:`md.bond_stiffness`; its thickness :math:`\varepsilon = h/(2\bar R)` is half the axial
gap over the radius, as in :func:`rockcem.granular.contact_cement`.

The linearised sample: for a bond between grains :math:`i, j` with unit normal :math:`\hat n`
(from :math:`i` to :math:`j`) and branch vector :math:`\mathbf l = |\mathbf l|\hat n`, the
relative displacement of the two faces at the contact point (arms :math:`r_i^*, r_j^*` with
:math:`r_i^* + r_j^* = |\mathbf l|`) is
:math:`\boldsymbol\delta = \mathbf u_j - \mathbf u_i + r_j^*\,\hat n\times\boldsymbol\theta_j
+ r_i^*\,\hat n\times\boldsymbol\theta_i` and the relative rotation
:math:`\Delta\boldsymbol\theta = \boldsymbol\theta_j - \boldsymbol\theta_i`; the bond energy is
:math:`\tfrac12[k_n\delta_n^2 + k_s|\boldsymbol\delta_t|^2 + k_w\Delta\theta_n^2
+ k_b|\Delta\boldsymbol\theta_t|^2]`. A rigid motion of the whole pack costs nothing. Touching
grains (contact bonding) also keep their linearised Hertz–Mindlin contact
(:math:`2E_f a_H`, :math:`8 G_f a_H`, no rolling resistance) in parallel, as PFC's parallel
bond acts beside the linear contact (Xu 2023, Sect. 2.2). Pre-stress (geometric stiffness) is
left out, as in :mod:`md.acoustic`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import NamedTuple

import numpy as np

from .bond_stiffness import BondStiffness, bond_cement_volume, bond_stiffness
from .contact import GrainMaterial
from .observe import segment_fraction as _segment_fraction
from .state import Pack

__all__ = ["BondStiffness", "bond_stiffness", "bond_cement_volume", "BondedSystem",
           "bonded_system", "BondedModuli", "static_moduli", "bonded_moduli",
           "bonded_acoustic_system"]


@dataclass(frozen=True)
class BondedSystem:
    r"""Grains, bonds and contacts of a bonded sample, linearised (6 degrees of freedom per
    grain: displacement, then rotation).

    Attributes
    ----------
    positions : ndarray, shape (n, 3)
        Grain centres, m (x, y wrapped into the box).
    radii : ndarray, shape (n,)
        m (reduced to :math:`R/(1 + \varepsilon)` for distant bonding).
    box : Box
    pair_i, pair_j : ndarray of int64
        Grains of every bond (at contact bonding each with the pair's Hertz contact in
        parallel).
    branch : ndarray, shape (m, 3)
        Vector from ``i`` to ``j`` (minimum image), m.
    shift : ndarray, shape (m, 3)
        ``branch - (x_j - x_i)``: the periodic image shift, m.
    arm_i, arm_j : ndarray
        Distances from the centres to the contact point, m.
    kn, ks, kb, kw : ndarray
        Normal and shear stiffness (N/m), bending and twisting stiffness (N m/rad).
    boundary : ndarray of bool
        Grains of the two end slabs, whose motion is prescribed.
    core : (float, float)
        z range of the core where stress and strain are measured, m.
    bond_volume : ndarray
        Cement volume of every bond, m³ (:func:`bond_cement_volume`).
    metadata : dict
    """

    positions: np.ndarray
    radii: np.ndarray
    box: object
    pair_i: np.ndarray
    pair_j: np.ndarray
    branch: np.ndarray
    shift: np.ndarray
    arm_i: np.ndarray
    arm_j: np.ndarray
    kn: np.ndarray
    ks: np.ndarray
    kb: np.ndarray
    kw: np.ndarray
    boundary: np.ndarray
    core: tuple
    bond_volume: np.ndarray
    metadata: dict = field(default_factory=dict)

    @property
    def n_grains(self) -> int:
        return int(self.radii.size)

    @cached_property
    def frames(self):
        """Unit normal and two tangents of every link, each shape (m, 3)."""
        n = self.branch / np.linalg.norm(self.branch, axis=1)[:, None]
        helper = np.where(np.abs(n[:, [0]]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1, axis=1)[:, None]
        return n, t1, np.cross(n, t1)

    @cached_property
    def _b_matrices(self):
        """Per link the 6 x 12 map from (u_i, theta_i, u_j, theta_j) to the local measures
        (delta . e, for e = n, t1, t2; then dtheta . e)."""
        n, t1, t2 = self.frames
        m = n.shape[0]
        B = np.zeros((m, 6, 12))
        for row, e in enumerate((n, t1, t2)):
            exn = np.cross(e, n)                          # e . (n x theta) = theta . (e x n)
            B[:, row, 0:3] = -e
            B[:, row, 3:6] = self.arm_i[:, None] * exn
            B[:, row, 6:9] = e
            B[:, row, 9:12] = self.arm_j[:, None] * exn
            B[:, 3 + row, 3:6] = -e
            B[:, 3 + row, 9:12] = e
        return B

    @cached_property
    def _d(self):
        return np.stack([self.kn, self.ks, self.ks, self.kw, self.kb, self.kb], axis=1)

    @cached_property
    def _dofs(self):
        i, j = self.pair_i, self.pair_j
        return np.concatenate([6 * i[:, None] + np.arange(6), 6 * j[:, None] + np.arange(6)],
                              axis=1)

    def stiffness_matrix(self):
        """:math:`K` (6n x 6n, ``scipy.sparse`` CSR): N/m, N/rad, N m/m, N m/rad blocks."""
        import scipy.sparse as sp

        B = self._b_matrices
        Kb = np.einsum("mai,ma,maj->mij", B, self._d, B)
        dof = self._dofs
        rows = np.repeat(dof, 12, axis=1).ravel()
        cols = np.tile(dof, (1, 12)).ravel()
        size = 6 * self.n_grains
        return sp.csr_matrix((Kb.ravel(), (rows, cols)), shape=(size, size))

    def link_forces(self, q, strain):
        """Force on ``j`` of every link (global frame), N, for the degrees of freedom ``q``
        (shape (n, 6)) under the macroscopic ``strain`` (3 x 3) carried by the periodic
        image shifts."""
        n, t1, t2 = self.frames
        local = np.einsum("mai,mi->ma", self._b_matrices, q.reshape(-1)[self._dofs]) \
            + self._shift_measures(strain)
        f = self._d[:, :3] * local[:, :3]
        return -(f[:, [0]] * n + f[:, [1]] * t1 + f[:, [2]] * t2)

    def _shift_measures(self, strain):
        """The local measures (m, 6) that the macroscopic ``strain`` adds to the links crossing
        the periodic boundaries: :math:`(E\\,\\mathbf s)\\cdot\\mathbf e` (no rotation)."""
        shift = self.shift @ np.asarray(strain, dtype=float).T
        c = np.zeros((self.shift.shape[0], 6))
        for row, e in enumerate(self.frames):
            c[:, row] = np.einsum("mi,mi->m", e, shift)
        return c


def _pairs(pack: Pack, gap):
    from .neighbors import build_neighbors
    from .space import minimum_image

    x, r = pack.positions, pack.radii
    p = build_neighbors(x, r, pack.box, gap).pairs.astype(np.int64)
    raw = x[p[:, 1]] - x[p[:, 0]]
    d = minimum_image(raw, pack.box)
    dist = np.linalg.norm(d, axis=1)
    surface_gap = dist - r[p[:, 0]] - r[p[:, 1]]
    keep = surface_gap <= gap
    return p[keep], d[keep], (d - raw)[keep], dist[keep], surface_gap[keep]


def bonded_system(pack: Pack, radius_ratio, thickness_ratio=0.0, *, cement_bulk,
                  cement_shear, contact_gap=None, slab=1.0) -> BondedSystem:
    r"""Bond the touching grains of a (confined) pack with cement bonds.

    Every pair of grains whose surfaces are closer than ``contact_gap`` (default
    :math:`10^{-3}\bar R`) gets a bond of radius :math:`a = \alpha\bar R` and axial thickness
    :math:`h = 2\varepsilon\bar R` (:func:`bond_stiffness`, :math:`\bar R` the pair's harmonic
    mean radius). Contact bonding (:math:`\varepsilon = 0`): the overlapping pairs keep their
    linearised Hertz–Mindlin contact in parallel. Distant bonding (:math:`\varepsilon > 0`):
    every grain radius :math:`R` is reduced to :math:`R' = R/(1 + \varepsilon)` about its
    centre, so a touching pair is :math:`h = 2\varepsilon R'` apart and bare contacts vanish
    (Xu 2023, Fig. 3b); :math:`\alpha` and :math:`\varepsilon` refer to these grains.

    Parameters
    ----------
    pack : Pack
        A pack at mechanical equilibrium, e.g. isotropically compacted
        (:func:`md.compact` with ``isotropic=True``).
    radius_ratio : float
        :math:`a/R`, in (0, 1].
    thickness_ratio : float
        :math:`\varepsilon = h/(2R)`, in [0, 0.5).
    cement_bulk, cement_shear : float, keyword-only
        Cement moduli, Pa.
    contact_gap : float, optional
        Largest surface gap of a bonded pair, m.
    slab : float
        Thickness of the end slabs whose grains are moved affinely, in largest grain
        diameters (the core lies between them).

    Returns
    -------
    BondedSystem
    """
    if not isinstance(pack, Pack):
        raise ValueError(f"pack must be an md.Pack; got {type(pack).__name__}")
    alpha, eps = float(radius_ratio), float(thickness_ratio)
    if not 0.0 < alpha <= 1.0:
        raise ValueError(f"radius_ratio (a/R) must lie in (0, 1]; got {radius_ratio}")
    if not 0.0 <= eps < 0.5:
        raise ValueError(f"thickness_ratio (h/2R) must lie in [0, 0.5); got {thickness_ratio}")
    if not (np.isfinite(slab) and slab > 0):
        raise ValueError(f"slab must be > 0 largest grain diameters; got {slab}")
    mat: GrainMaterial = pack.material
    r0 = pack.radii
    gap = 1e-3 * float(r0.mean()) if contact_gap is None else float(contact_gap)
    if not gap >= 0:
        raise ValueError(f"contact_gap must be >= 0 m; got {contact_gap}")
    p, branch, shift, dist, surface_gap = _pairs(pack, gap)
    if p.shape[0] == 0:
        raise ValueError("the pack has no touching grains to bond")
    # Distant bonding: the grains shrink to R/(1 + eps) about their centres, so a touching pair
    # is 2 eps R' apart (R' the new radius) and a/R, h/(2R) refer to the grains that exist.
    radii = r0 / (1.0 + eps)
    ri, rj = radii[p[:, 0]], radii[p[:, 1]]
    R_bar = 2.0 * ri * rj / (ri + rj)
    K_grain = mat.bulk_modulus
    bs = bond_stiffness(R_bar, alpha, eps, K_grain, mat.shear_modulus, cement_bulk,
                        cement_shear)
    kn, ks, kb, kw = (np.array(v, dtype=float) for v in bs)
    arm_i = dist * ri / (ri + rj)
    arm_j = dist - arm_i
    if eps == 0.0:
        xi = -surface_gap
        touch = xi > 0
        a_H = np.sqrt(np.where(touch, ri * rj / (ri + rj) * np.maximum(xi, 0.0), 0.0))
        kn = kn + 2.0 * mat.E_f * a_H
        ks = ks + 8.0 * mat.G_f * a_H
    x = pack.positions.copy()
    x[:, 0] %= pack.box.lx
    x[:, 1] %= pack.box.ly
    d = 2.0 * r0.max()
    z_lo, z_hi = x[:, 2].min() + slab * d, x[:, 2].max() - slab * d
    if not z_hi > z_lo:
        raise ValueError("slab: the end slabs leave no core between them")
    boundary = (x[:, 2] < z_lo) | (x[:, 2] > z_hi)
    if not (np.any(x[:, 2] < z_lo) and np.any(x[:, 2] > z_hi)):
        raise ValueError(f"slab: both end slabs must hold grains; got slab = {slab}")
    volume_core = pack.box.lx * pack.box.ly * (z_hi - z_lo)
    from .protocols import porosity as pack_porosity

    shrunk = Pack(x, pack.velocities, pack.angular_velocities, radii, pack.box, mat,
                  pack.pairs, pack.history) if eps else pack
    phi_grains = pack_porosity(shrunk, bottom=z_lo, top=z_hi)
    bond_volume = bond_cement_volume(R_bar, alpha, eps)
    # The cement in the core, each bond weighted as in the stress average (_core_fraction).
    cement_volume = float(bond_volume @ _segment_fraction(x[p[:, 0], 2], branch[:, 2],
                                                          z_lo, z_hi))
    core_grains = ~boundary
    counts = np.bincount(p.ravel(), minlength=r0.size)
    meta = {"radius_ratio": alpha, "thickness_ratio": eps, "cement_bulk": float(cement_bulk),
            "cement_shear": float(cement_shear), "grain_bulk": K_grain,
            "grain_shear": mat.shear_modulus, "mean_radius": float(r0.mean()),
            "porosity_uncemented": phi_grains,
            "porosity": phi_grains - cement_volume / volume_core,
            "cement_fraction": cement_volume / volume_core,
            "coordination_number": float(counts[core_grains].mean()),
            "n_bonds": int(p.shape[0]), "volume_core": volume_core,
            "grain_volume_fraction": 1.0 - phi_grains, "grain_density": mat.density,
            "restitution": mat.restitution}
    return BondedSystem(x, radii, pack.box, p[:, 0], p[:, 1], branch, shift, arm_i, arm_j,
                        kn, ks, kb, kw, boundary, (float(z_lo), float(z_hi)), bond_volume,
                        meta)


class BondedModuli(NamedTuple):
    """Static moduli of a bonded sample, Pa: relaxed ``bulk`` and ``shear`` (mean of the xz and
    yz shears, measured by tractions on horizontal planes), ``shear_components`` (xz, yz, xy;
    the in-plane xy from the symmetrised in-plane stress, the less exact estimate), and the
    affine (unrelaxed, grains moved with the mean strain, no rotation) ``bulk_affine`` and
    ``shear_affine``."""

    bulk: float
    shear: float
    shear_components: tuple
    bulk_affine: float
    shear_affine: float


def _connected(system: BondedSystem):
    """Grains linked (directly or through others) to the prescribed end slabs."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    n = system.n_grains
    g = sp.coo_matrix((np.ones(system.pair_i.size), (system.pair_i, system.pair_j)),
                      shape=(n, n))
    _, label = connected_components(g, directed=False)
    return np.isin(label, np.unique(label[system.boundary]))


def _core_fraction(system: BondedSystem):
    """Fraction of each link's centre-to-centre segment that lies in the core slab: the
    weight of the link in the volume average of the Irving–Kirkwood stress over the core.
    For the tractions on the core's planes (zz, xz, yz) this is exact; the in-plane
    components (xx, yy, xy) of links that do not cross z carry the error of cutting the
    sample at a height (a flat link lying on a core plane counts one half)."""
    return _segment_fraction(system.positions[system.pair_i, 2], system.branch[:, 2],
                             *system.core)


class _StaticSolver:
    """Everything :func:`static_moduli` needs from one system, built once: the stiffness
    matrix, the load-bearing grains, the factorised free block, the stress weights of the
    links and the core grains of the strain fit."""

    def __init__(self, system: BondedSystem):
        from scipy.sparse.linalg import factorized

        self.system = system
        self.K = system.stiffness_matrix()
        live = _connected(system)
        free = live & ~system.boundary
        self.free_dof = (6 * np.flatnonzero(free)[:, None] + np.arange(6)).ravel()
        self.solve = factorized(self.K[self.free_dof][:, self.free_dof].tocsc())
        # Grains not linked to the end slabs (rattlers, floating clusters) carry no load: their
        # links and displacements stay out of the stress and the strain.
        self.weight = _core_fraction(system) * (live[system.pair_i] & live[system.pair_j])
        x = system.positions
        z_lo, z_hi = system.core
        self.inside = live & ~system.boundary & (x[:, 2] >= z_lo) & (x[:, 2] < z_hi)
        if not self.inside.any() or np.ptp(x[self.inside, 2]) <= 0.0:
            raise ValueError("the core holds no load-bearing grains at different heights; "
                             "make the sample taller or the end slabs thinner")

    def response(self, strain, relax):
        """Stress (virial of the core links, tension positive) and mean strain of the core
        for a macroscopic ``strain`` imposed on the end slabs and the periodic images."""
        system = self.system
        E = np.asarray(strain, dtype=float)
        x = system.positions
        q = np.zeros((system.n_grains, 6))
        q[:, :3] = x @ E.T                               # affine start, no rotation
        if relax:
            # Gradient of the energy at the affine state: K q + B^T D c (the shift terms).
            g_shift = np.zeros(q.size)
            np.add.at(g_shift, system._dofs.ravel(),
                      np.einsum("mai,ma,ma->mi", system._b_matrices, system._d,
                                system._shift_measures(E)).ravel())
            grad = self.K @ q.ravel() + g_shift
            q.reshape(-1)[self.free_dof] -= self.solve(grad[self.free_dof])
        f_j = system.link_forces(q, E)
        # stress[i, j] = -sum l_i f_j / V: row z (the tractions on horizontal planes) is exact
        # for a band cut by such planes; the in-plane rows carry the error of the cut.
        stress = -np.einsum("m,mi,mj->ij", self.weight, system.branch, f_j) / \
            system.metadata["volume_core"]
        # Mean displacement gradient of the core: the x and y derivatives are the imposed ones
        # (the fluctuations are periodic in x and y); the z derivatives are the least-squares
        # slope of the core grains' displacements (less their imposed x, y part) against z.
        inside = self.inside
        grad_u = E.copy()
        rest = q[inside, :3] - x[inside, :2] @ E[:, :2].T
        zc = x[inside, 2] - x[inside, 2].mean()
        grad_u[:, 2] = zc @ (rest - rest.mean(axis=0)) / (zc @ zc)
        return stress, 0.5 * (grad_u + grad_u.T)


def static_moduli(system: BondedSystem, *, strain=1e-6) -> BondedModuli:
    r"""Static bulk and shear moduli of a bonded sample by sparse solves.

    The end-slab grains are moved with a macroscopic strain (their rotations held at 0), the
    periodic images in x and y carry the same strain, and the other grains (those linked to
    the end slabs) relax to equilibrium: one sparse direct solve
    of :math:`K_{ff}\,q_f = -g_f` per strain. Stress: the virial
    :math:`\sigma = -\frac1V\sum \mathbf l\otimes\mathbf f_j` over the load-bearing links,
    each weighted by the fraction of its segment inside the core (tension positive); strain:
    the imposed x and y derivatives of the displacement (exact: the fluctuations are periodic)
    and the least-squares z derivatives of the core grains' displacements. Rattlers and
    clusters not linked to the end slabs carry no load and are left out of both. Only the
    tractions on horizontal planes (:math:`\sigma_{zz}, \sigma_{zx}, \sigma_{zy}`) are exact for
    a band cut from the sample (the in-plane components depend on how many layers of nearly
    horizontal links the band holds), so the moduli use them: uniaxial strain along z gives
    :math:`C_{zzzz}`, isotropic strain then :math:`C_{zzxx} + C_{zzyy}`, and
    :math:`K = (C_{zzzz} + C_{zzxx} + C_{zzyy})/3` (:math:`(3\lambda + 2\mu)/3` for an
    isotropic sample); pure shears in xz and yz give :math:`G = \sigma_{za}/(2\varepsilon_{za})`,
    averaged. The in-plane xy shear is reported beside them.

    Parameters
    ----------
    system : BondedSystem
    strain : float
        Size of the imposed strain (the response is linear; it only scales), ``> 0``.

    Returns
    -------
    BondedModuli
    """
    if not (np.isfinite(strain) and strain > 0):
        raise ValueError(f"strain must be finite and > 0; got {strain}")
    solver = _StaticSolver(system)
    iso = strain * np.eye(3)
    shears = []
    for a, b in ((0, 2), (1, 2), (0, 1)):
        E = np.zeros((3, 3))
        E[a, b] = E[b, a] = 0.5 * strain
        shears.append((E, a, b))
    uni = np.zeros((3, 3))
    uni[2, 2] = strain
    out = {}
    for relax in (True, False):
        # Bulk from tractions on horizontal planes only: uniaxial strain gives M = C_zzzz,
        # isotropic strain then C_zzxx + C_zzyy, and K = (C_zzzz + C_zzxx + C_zzyy)/3 (for an
        # isotropic sample (lambda + 2 mu + 2 lambda)/3).
        s, e = solver.response(uni, relax)
        M = s[2, 2] / e[2, 2]
        s, e = solver.response(iso, relax)
        lateral = (s[2, 2] - M * e[2, 2]) / strain
        bulk = (M + lateral) / 3.0
        g = []
        for E, a, b in shears:
            s, e = solver.response(E, relax)
            # xz, yz: the traction on horizontal planes; xy: the symmetrised in-plane estimate.
            tau = s[b, a] if b == 2 else 0.5 * (s[a, b] + s[b, a])
            g.append(tau / (2.0 * e[a, b]))
        out[relax] = (float(bulk), tuple(float(v) for v in g))
    return BondedModuli(out[True][0], float(np.mean(out[True][1][:2])), out[True][1],
                        out[False][0], float(np.mean(out[False][1][:2])))


def bonded_moduli(pack: Pack, radius_ratios, thickness_ratios=(0.0,), *, cement_bulk,
                  cement_shear, cement_density=None, contact_gap=None, slab=1.0,
                  progress=False):
    r"""Static moduli of a pack bonded over a grid of bond radii and thicknesses.

    Parameters
    ----------
    pack : Pack
    radius_ratios, thickness_ratios : sequence of float
        :math:`a/R` and :math:`\varepsilon = h/(2R)` (see :func:`bonded_system`).
    cement_bulk, cement_shear : float, keyword-only
        Pa.
    cement_density : float, optional
        kg/m³, for the density and the velocities; default the grain density (quartz cement
        on quartz grains).
    contact_gap, slab
        As in :func:`bonded_system`.
    progress : bool
        Progress bar.

    Returns
    -------
    xarray.Dataset
        Over ``radius_ratio`` and ``thickness_ratio``: ``K``, ``G``, ``K_affine``,
        ``G_affine`` (GPa), ``G_xz``, ``G_yz``, ``G_xy`` (GPa), ``porosity``,
        ``cement_fraction``, ``density`` (g/cm³: grains and bond cement of the core, dry) and the
        static velocities ``vp`` = :math:`\sqrt{(K + \tfrac43 G)/\rho}`, ``vs`` =
        :math:`\sqrt{G/\rho}` (km/s); ``porosity_uncemented`` over ``thickness_ratio`` (the
        grains shrink with it) and the scalar ``coordination_number``;
        grain and cement moduli ``grain_K``, ``grain_G``, ``cement_K``, ``cement_G`` (GPa, as
        :func:`md.calibrate.calibrate` reads them) and the mean grain radius (m) in attrs.
    """
    import xarray as xr
    from tqdm.auto import tqdm

    a_list = [float(v) for v in np.atleast_1d(radius_ratios)]
    h_list = [float(v) for v in np.atleast_1d(thickness_ratios)]
    shape = (len(a_list), len(h_list))
    names = ("K", "G", "K_affine", "G_affine", "G_xz", "G_yz", "G_xy", "porosity",
             "cement_fraction", "density", "vp", "vs")
    phi_unc = np.full(len(h_list), np.nan)
    rho_c = pack.material.density if cement_density is None else float(cement_density)
    if not (np.isfinite(rho_c) and rho_c > 0):
        raise ValueError(f"cement_density must be > 0 kg/m3; got {cement_density}")
    data = {k: np.full(shape, np.nan) for k in names}
    meta = {}
    with tqdm(total=shape[0] * shape[1], disable=not progress, desc="bonded moduli") as bar:
        for ia, a in enumerate(a_list):
            for ih, h in enumerate(h_list):
                system = bonded_system(pack, a, h, cement_bulk=cement_bulk,
                                       cement_shear=cement_shear, contact_gap=contact_gap,
                                       slab=slab)
                m = static_moduli(system)
                meta = system.metadata
                values = (m.bulk, m.shear, m.bulk_affine, m.shear_affine,
                          *m.shear_components)
                for k, v in zip(names[:7], values):
                    data[k][ia, ih] = v / 1e9
                data["porosity"][ia, ih] = meta["porosity"]
                phi_unc[ih] = meta["porosity_uncemented"]
                data["cement_fraction"][ia, ih] = meta["cement_fraction"]
                rho = (meta["grain_volume_fraction"] * meta["grain_density"]
                       + meta["cement_fraction"] * rho_c) / 1e3              # g/cm3
                data["density"][ia, ih] = rho
                data["vp"][ia, ih] = np.sqrt((m.bulk + 4.0 * m.shear / 3.0) / 1e9 / rho)
                data["vs"][ia, ih] = np.sqrt(m.shear / 1e9 / rho)
                bar.update(1)
    units = {"K": "GPa", "G": "GPa", "K_affine": "GPa", "G_affine": "GPa", "G_xz": "GPa",
             "G_yz": "GPa", "G_xy": "GPa", "porosity": "1", "cement_fraction": "1",
             "density": "g cm-3", "vp": "km s-1", "vs": "km s-1"}
    long = {"K": "static bulk modulus (relaxed)", "G": "static shear modulus (relaxed, mean)",
            "K_affine": "bulk modulus, affine (unrelaxed)",
            "G_affine": "shear modulus, affine (unrelaxed)", "G_xz": "shear modulus xz",
            "G_yz": "shear modulus yz", "G_xy": "shear modulus xy",
            "porosity": "porosity (grains and bond cement)",
            "cement_fraction": "bond cement volume fraction",
            "density": "dry bulk density", "vp": "static P velocity",
            "vs": "static S velocity"}
    dims = ("radius_ratio", "thickness_ratio")
    ds = xr.Dataset(
        {k: (dims, v, {"units": units[k], "long_name": long[k]}) for k, v in data.items()},
        coords={"radius_ratio": ("radius_ratio", a_list, {"long_name": "bond radius a/R"}),
                "thickness_ratio": ("thickness_ratio", h_list,
                                    {"long_name": "contact thickness epsilon = h/(2R)"})})
    ds["porosity_uncemented"] = ("thickness_ratio", phi_unc, {
        "units": "1", "long_name": "porosity of the grains alone (shrunk by 1/(1 + eps))"})
    ds["coordination_number"] = ((), meta["coordination_number"], {"units": "1"})
    ds.attrs.update(grain_K=meta["grain_bulk"] / 1e9, grain_G=meta["grain_shear"] / 1e9,
                    cement_K=float(cement_bulk) / 1e9, cement_G=float(cement_shear) / 1e9,
                    grain_rho=meta["grain_density"] / 1e3, cement_rho=rho_c / 1e3,
                    mean_radius_m=meta["mean_radius"], n_grains=int(pack.n_grains),
                    references="Xu 2023, Sects. 2.2-2.3, Figs. 4-6; md.bonded docstring")
    return ds


def bonded_acoustic_system(system: BondedSystem, *, cement_density=None, restitution=None,
                           slab_thickness=None):
    """The bonded sample as an :class:`md.AcousticSystem` for :func:`md.pulse_test`.

    Each link becomes a contact bond of the acoustic operator with its normal and shear
    stiffness (:math:`k_n`, :math:`k_s`), linear dashpots from the restitution
    (:func:`md.acoustic.damping_ratio`), and the cement of each bond split between its two
    grains' masses. The acoustic operator has translations only (García & Medina's eqs. 4–5):
    grain rotations, and with them the bending and twisting stiffness, are left out, so its
    waves see the sample with rotations locked; compare with :func:`static_moduli`, which
    lets the grains rotate.

    Parameters
    ----------
    system : BondedSystem
    cement_density : float, optional
        kg/m³; default the grain density.
    restitution : float, optional
        Restitution of the dashpots, default the grain material's (0.9).
    slab_thickness : float, optional
        Detector slab thickness, m; default two largest grain diameters.

    Returns
    -------
    AcousticSystem
    """
    from .acoustic import AcousticSystem, damping_ratio, dashpots

    rho_g = system.metadata["grain_density"]
    rho_c = rho_g if cement_density is None else float(cement_density)
    if not (np.isfinite(rho_c) and rho_c > 0):
        raise ValueError(f"cement_density must be > 0 kg/m3; got {cement_density}")
    e = system.metadata["restitution"] if restitution is None else float(restitution)
    zeta = damping_ratio(e)
    r = system.radii
    i, j = system.pair_i, system.pair_j
    half = 0.5 * rho_c * system.bond_volume
    m = rho_g * 4.0 / 3.0 * np.pi * r**3 + np.bincount(i, half, r.size) \
        + np.bincount(j, half, r.size)
    gn, gt = dashpots(system.kn, system.ks, m[i], m[j], zeta)
    thickness = 4.0 * float(r.max()) if slab_thickness is None else float(slab_thickness)
    if not thickness > 0:
        raise ValueError(f"slab_thickness must be > 0 m; got {slab_thickness}")
    z = system.positions[:, 2]
    extent = (float(np.min(z - r)), float(np.max(z + r)))
    meta = {"n_grain_contacts": int(i.size), "n_cement": 0, "n_grain_cement": 0,
            "restitution": e, "mean_radius": float(r.mean()), "bonded": 1,
            "radius_ratio": system.metadata["radius_ratio"],
            "thickness_ratio": system.metadata["thickness_ratio"]}
    return AcousticSystem(
        system.positions.copy(), m, system.n_grains, system.box, i.astype(np.int32),
        j.astype(np.int32), system.frames[0], system.kn.copy(), system.ks.copy(), gn, gt,
        np.zeros((0, 9), np.int32), np.zeros(9), np.zeros(9), thickness, extent, meta)
