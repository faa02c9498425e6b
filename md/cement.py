"""The cement lattice of a grain pack (García & Medina, Sect. III B): cubic cells of width
:math:`c_w = R/\\Omega` classified as contact, surface or body cells of the pore space.

SI units. Only pore cells are stored (compactly: int32 indices, int8 classes, float32 distances),
since they are the only ones cement can fill. :func:`grow_cement` fills them by the contact,
coating and pore-body schemes of Sects. III C–E (numba kernels in :mod:`md._kernels_cement`,
O(n log n) in the number of pore cells; :mod:`md.growth`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .state import Pack

__all__ = ["CementLattice", "cement_lattice", "grow_cement", "cement_order", "cement_sweep",
           "cement_fill",
           "SCHEMES", "CONTACT", "SURFACE", "BODY",
           "CementMaterial", "HARD_CEMENT", "SOFT_CEMENT", "lattice_constants",
           "LATTICE_OFFSETS"]

#: Growth schemes of :func:`grow_cement`: the source's three and the pendular contact cement.
SCHEMES = ("contact", "coating", "pore_body", "pendular")

#: Cell classes: touching two or more grains, one grain, or none.
CONTACT, SURFACE, BODY = 2, 1, 0


#: The 9 lattice-neighbour offsets of one half of the 18-neighbour stencil (6 faces, 12 edges of
#: a cube; the other half are their negatives), in cells.
LATTICE_OFFSETS = np.array([(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1),
                            (1, 0, -1), (0, 1, 1), (0, 1, -1)], dtype=np.int64)


@dataclass(frozen=True)
class CementMaterial:
    """An isotropic cement of the MD engine (SI units; García & Medina, Table II).

    Parameters
    ----------
    vp, vs : float
        P and S velocities, m/s, with :math:`-1 < \\nu \\le 1/4` (``4/3 vs**2 < vp**2 <=
        3 vs**2``): the range the 18-neighbour lattice of eq. 6 can represent with non-negative
        spring constants (see :func:`lattice_constants`).
    density : float
        kg/m³, ``> 0``.
    """

    vp: float
    vs: float
    density: float

    def __post_init__(self):
        for name in ("vp", "vs", "density"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float, np.floating)) and np.isfinite(value)
                    and value > 0):
                raise ValueError(f"cement {name} must be a finite number > 0; got {value!r}")
        if not 4.0 / 3.0 * self.vs**2 < self.vp**2 <= 3.0 * self.vs**2 * (1 + 1e-12):
            raise ValueError(
                f"cement vp/vs = {self.vp / self.vs:.4g} is outside (sqrt(4/3), sqrt(3)] "
                "(Poisson ratio -1 to 0.25), the range the 18-neighbour cement lattice represents")

    @property
    def shear_modulus(self) -> float:
        """:math:`G_c = \\rho_c V_{sc}^2`, Pa."""
        return self.density * self.vs**2

    @property
    def p_modulus(self) -> float:
        """:math:`M_c = \\rho_c V_{pc}^2`, Pa."""
        return self.density * self.vp**2

    @property
    def poisson_ratio(self) -> float:
        """:math:`\\nu_c = (V_p^2 - 2V_s^2) / (2(V_p^2 - V_s^2))`."""
        return (self.vp**2 - 2 * self.vs**2) / (2 * (self.vp**2 - self.vs**2))

    @property
    def young_modulus(self) -> float:
        """:math:`E_c = 2 G_c (1 + \\nu_c)`, Pa."""
        return 2.0 * self.shear_modulus * (1.0 + self.poisson_ratio)


#: Hard (quartz-like) and soft (clay-like) cement of García & Medina, Table II.
HARD_CEMENT = CementMaterial(3000.0, 1800.0, 2650.0)
SOFT_CEMENT = CementMaterial(1500.0, 900.0, 2650.0)


def lattice_constants(cement: CementMaterial, cell_width, rule="waves", *, rotations=False):
    """Spring constants :math:`C_n`, :math:`C` and particle mass :math:`m_c` of the cement lattice.

    A cement particle interacts with its 18 nearest lattice neighbours by (García & Medina,
    eq. 6; O'Brien & Bean 2004)

    .. math:: \\mathbf f = C_n (\\mathbf u_{12}\\cdot\\hat{\\mathbf n})\\hat{\\mathbf n}
              + \\frac{C}{|\\mathbf x_{12}|^2}\\mathbf u_{12},

    the same :math:`C_n` and :math:`C` for face (:math:`|x| = c_w`) and edge
    (:math:`|x| = \\sqrt2 c_w`) neighbours. Summing the strain energy of the 9 bonds per node
    over the cell volume :math:`c_w^3` for a displacement field :math:`u_z(z)` (a P wave, or
    uniaxial strain) and :math:`u_x(z)` (an S wave, or simple shear) gives the wave moduli of
    this lattice:

    .. math:: \\rho_c V_p^2 = \\frac{3C_n}{c_w} + \\frac{3C}{c_w^3}, \\qquad
              \\rho_c V_s^2 = \\frac{C_n}{c_w} + \\frac{3C}{c_w^3}.

    These have the form of the paper's eq. 8 with 3 in place of its 2. (The bending term of
    eq. 6 resists rigid rotation, so the lattice's pure-shear modulus, :math:`C_n/c_w +
    3C/2c_w^3`, differs from its S-wave modulus; waves and simple shear carry rotation, and
    those are what the pulse test measures.)

    ``rule="waves"`` (default) solves these for the cement's velocities:
    :math:`C_n = \\tfrac12\\rho_c(V_p^2 - V_s^2)c_w` (the paper's eq. 9) and
    :math:`C = \\tfrac16\\rho_c(3V_s^2 - V_p^2)c_w^3`, non-negative for a Poisson ratio up to
    1/4. Static sparse solves and pulse tests on a cement block check both velocities
    (``tests/md/test_acoustic.py``).

    ``rule="paper"`` uses eq. 9 as derived from eq. 8: the same :math:`C_n` and
    :math:`C = \\tfrac14\\rho_c(3V_s^2 - V_p^2)c_w^3`. (The printed eq. 9,
    :math:`\\tfrac14\\rho_c(3V_p^2 - V_s^2)c_w^3`, contradicts eq. 8, from which subtracting the
    two lines gives :math:`C_n` and the :math:`V_s` line then gives :math:`C`.) On this lattice
    these constants make the cement 1 % fast in P and 3 % in S (Table II cements); kept to
    reproduce the paper.

    With ``rotations=True`` every cement particle also rotates and the tangential term of
    eq. 6 acts on the relative displacement of the bond's midpoint
    (:mod:`md._kernels_rotation`), so a rigid rotation costs nothing. A uniform strain then
    leaves every particle at the macroscopic rotation (the moments cancel on the
    centrosymmetric stencil), and simple shear and S waves see the pure-shear modulus:

    .. math:: \\rho_c V_p^2 = \\frac{3C_n}{c_w} + \\frac{3C}{c_w^3}, \\qquad
              \\rho_c V_s^2 = \\frac{C_n}{c_w} + \\frac{3C}{2c_w^3},

    whence ``rule="waves"`` gives :math:`C_n = \\rho_c(V_p^2 - 2V_s^2)c_w = \\lambda_c c_w`
    and :math:`C = \\tfrac23\\rho_c(3V_s^2 - V_p^2)c_w^3 = \\tfrac23(\\mu_c - \\lambda_c)c_w^3`,
    both non-negative for a Poisson ratio in [0, 1/4]. ``rule="paper"`` (the source's lattice,
    translations only) refuses rotations.

    In both rules :math:`m_c = \\rho_c c_w^3` (eq. 9).

    Parameters
    ----------
    cement : CementMaterial
    cell_width : float
        :math:`c_w`, m, ``> 0``.
    rule : {"waves", "paper"}
    rotations : bool
        Constants of the lattice whose particles rotate (see above); default False.

    Returns
    -------
    (float, float, float)
        :math:`C_n` (N/m), :math:`C` (N m), :math:`m_c` (kg).

    Examples
    --------
    >>> Cn, C, m = lattice_constants(HARD_CEMENT, 1e-5)
    >>> vp2 = (3 * Cn / 1e-5 + 3 * C / 1e-15) / 2650.0
    >>> vs2 = (Cn / 1e-5 + 3 * C / 1e-15) / 2650.0
    >>> round(vp2**0.5, 6), round(vs2**0.5, 6)
    (3000.0, 1800.0)
    """
    if not (np.isfinite(cell_width) and cell_width > 0):
        raise ValueError(f"cell_width must be > 0 m; got {cell_width!r}")
    rho, vp2, vs2 = cement.density, cement.vp**2, cement.vs**2
    Cn = 0.5 * rho * (vp2 - vs2) * cell_width
    if rule == "waves" and rotations:
        if not vs2 <= vp2 / 2.0 <= 1.5 * vs2:
            raise ValueError(f"the rotating cement lattice holds Poisson ratios in [0, 1/4] "
                             f"only; got {cement.poisson_ratio:.3g} (vp {cement.vp:g}, "
                             f"vs {cement.vs:g} m/s)")
        Cn = rho * (vp2 - 2.0 * vs2) * cell_width
        C = 2.0 * rho * (3.0 * vs2 - vp2) * cell_width**3 / 3.0
    elif rule == "waves":
        C = rho * (3.0 * vs2 - vp2) * cell_width**3 / 6.0
    elif rule == "paper" and rotations:
        raise ValueError("rule='paper' is the source's lattice of translations only (eqs. 6-9); "
                         "use rotations=False with it, or rule='waves'")
    elif rule == "paper":
        C = 0.25 * rho * (3.0 * vs2 - vp2) * cell_width**3
    else:
        raise ValueError(f"rule must be 'waves' or 'paper'; got {rule!r}")
    return float(Cn), float(C), float(rho * cell_width**3)


@dataclass(frozen=True)
class CementLattice:
    """Pore cells of a pack on a cubic lattice.

    Attributes
    ----------
    cell_width : float
        :math:`c_w`, m.
    shape : (int, int, int)
        Lattice cells along x, y, z (x fastest in the flat index ``i + nx (j + ny k)``).
    z0 : float
        Bottom of the lattice, m.
    index : ndarray of int32
        Flat indices of the pore cells (cell centre outside every grain).
    kind : ndarray of int8
        :data:`CONTACT`, :data:`SURFACE` or :data:`BODY` per pore cell.
    distance : ndarray of float32
        Distance from the cell centre to the nearest grain surface, m (capped at the search reach).
    distance2 : ndarray of float32, optional
        Distance from the cell centre to the second-nearest grain surface, m (capped likewise);
        needed by the ``"pendular"`` growth scheme.
    """

    cell_width: float
    shape: tuple
    z0: float
    index: np.ndarray
    kind: np.ndarray
    distance: np.ndarray
    distance2: np.ndarray | None = None

    def centres(self) -> np.ndarray:
        """Centres of the pore cells, shape (n, 3), m."""
        nx, ny, _ = self.shape
        i = self.index % nx
        j = (self.index // nx) % ny
        k = self.index // (nx * ny)
        return np.stack([(i + 0.5) * self.cell_width, (j + 0.5) * self.cell_width,
                         self.z0 + (k + 0.5) * self.cell_width], axis=-1)


def cement_lattice(pack: Pack, resolution=4.0, *, reach=None) -> CementLattice:
    """Cut the pack into cubic cells of width :math:`c_w = \\bar R/\\Omega` and classify the pores.

    Parameters
    ----------
    pack : Pack
    resolution : float
        :math:`\\Omega`, cells per mean grain radius, ``>= 1`` (the paper uses about 10; the
        default 4 keeps a laptop run quick).
    reach : float, optional
        How far from grain surfaces distances are computed, m (default one mean radius); farther
        cells get this value.

    Returns
    -------
    CementLattice
        The lattice spans the box laterally (the cell width is adjusted so that whole cells fill
        the periodic lengths) and the pack vertically.
    """
    from ._kernels_cement import classify_cells

    if not resolution >= 1.0:
        raise ValueError(f"resolution must be >= 1 cell per grain radius; got {resolution}")
    r = pack.radii
    x = pack.positions.copy()
    x[:, 0] %= pack.box.lx
    x[:, 1] %= pack.box.ly
    r_mean = float(r.mean())
    nx = max(int(round(pack.box.lx / (r_mean / resolution))), 1)
    cw = pack.box.lx / nx
    ny = max(int(round(pack.box.ly / cw)), 1)
    if abs(ny * cw - pack.box.ly) > 1e-9 * pack.box.ly:
        raise ValueError("the box's lx and ly must be commensurate with one cell width "
                         f"(lx/ly = {pack.box.lx / pack.box.ly:g})")
    z0 = float(np.min(x[:, 2] - r))
    nz = int(np.ceil((float(np.max(x[:, 2] + r)) - z0) / cw))
    reach = r_mean if reach is None else float(reach)
    if not reach > 0:
        raise ValueError("reach must be > 0")
    n_cells = nx * ny * nz
    if n_cells > 2**31 - 1:
        raise ValueError("too many cells for int32 indices: lower the resolution")
    touches = np.zeros(n_cells, dtype=np.int8)
    solid = np.zeros(n_cells, dtype=np.int8)
    dist = np.full(n_cells, reach)
    dist2 = np.full(n_cells, reach)
    classify_cells(x, r, pack.box.lx, pack.box.ly, z0, cw, nx, ny, nz, reach, touches, solid,
                   dist, dist2)
    pore = np.flatnonzero(solid == 0).astype(np.int32)
    kind = np.minimum(touches[pore], 2).astype(np.int8)
    return CementLattice(cw, (nx, ny, nz), z0, pore, kind, dist[pore].astype(np.float32),
                         dist2[pore].astype(np.float32))


# The growth schemes live in md.growth; their public names stay importable from here.
from .growth import cement_fill, cement_order, cement_sweep, grow_cement  # noqa: E402
