"""Static moduli of the linearised acoustic stage: the long-wave limit of the pulse test by a
sparse solve on the same operator (García & Medina, Sect. III G; the cross-check of
:func:`md.pulse_test`), and the transversely isotropic stiffness of the sample
(:func:`static_stiffness`: C11, C13, C33, C44, C66 by five solves on one factorisation).

SI units. The sample is the :class:`md.AcousticSystem` cut into slabs along z; the bottom slab
is displaced (or, for the in-plane constants, the whole box strained through its periodic
images), the top slab held, and the free particles on the load path relax.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from .acoustic import AcousticSystem

__all__ = ["StaticModulus", "static_modulus", "static_moduli", "StaticStiffness",
           "static_stiffness", "SOLVERS", "LU_MAX_DOF", "LU_MAX_DOF_FILM", "FILM_DEGREE",
           "PA_PER_GPA"]

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


#: Static solvers: "lu" factorises K_ff once (fast and exact on film-like cement and small
#: samples), "cg" iterates with a block-Jacobi preconditioner (little memory), "auto" picks.
SOLVERS = ("auto", "lu", "cg")
#: Largest number of free degrees of freedom "auto" factorises ...
LU_MAX_DOF = 30_000
#: ... and, where the cement is film-like (its particles have on average at most
#: :data:`FILM_DEGREE` lattice bonds), the larger bound. The factor's cost depends on the
#: cement's shape more than on its size: a thin coating of 3e5 free dof (mean lattice degree
#: 2) factorises in 7 s, where block-Jacobi conjugate gradients need 10^4 iterations or more;
#: on well-connected cement the factor fills in (half-filled pores of 3e5, degree 6.5: 80 s
#: and 2.2 GB) and conjugate gradients converge in a few hundred to a thousand iterations.
#: On the shipped example's members (docs/studies/md_static_solver.md, the five loads of
#: :func:`static_stiffness`), the full sample (degree 10) of 4.9e4 free dof took 14.8 s with
#: SuperLU and 1.8 s with conjugate gradients, the 0.67-saturated coating (degree 6) of 1.1e5
#: 28.2 s with CHOLMOD's Cholesky factor and 4.4 s, while at 2.9e4 (degree 4.4) SuperLU was
#: the faster, 1.5 s against 1.8 s.
LU_MAX_DOF_FILM = 1_000_000
FILM_DEGREE = 4.0


def static_modulus(system: AcousticSystem, wave="p", *, rtol=1e-10, maxiter=None,
                   parallel=False, solver="auto") -> StaticModulus:
    """P-wave (or shear) modulus of the linearised sample by a sparse solve.

    The bottom slab is displaced by a small :math:`u_z` (``wave="p"``, uniaxial strain) or
    :math:`u_x` (``wave="s"``, simple shear), all of its particles alike, the top slab is held
    fixed, the periodic box keeps the lateral strain zero (with rotations,
    :attr:`md.AcousticSystem.rotations`, only the end slabs' translations are prescribed and
    every rotation is free); :math:`K_{ff} u_f = -K_{fp} u_p` is solved on the free particles
    bonded, directly or through others, to an end slab (rattlers and floating cement clusters
    drop out). The stress is the reaction on the fixed slab over the box area (the same through
    every horizontal section); the strain is the slope of a least-squares line through the
    centres of mass of the interior slabs (their load-path particles) in :math:`(z, u_z)` — the
    part of the sample the pulse test's detectors see.

    Parameters
    ----------
    system : md.AcousticSystem
    wave : {"p", "s"}
    rtol : float
        Tolerance of the conjugate gradients, in (0, 1): :math:`\\|b - K_{ff} u_f\\| \\le`
        ``rtol`` :math:`\\|b\\|`.
    maxiter : int, optional
        Iteration cap (``>= 1``; default 20 per free degree of freedom).
    parallel : bool
        Apply the operator with the multi-threaded gather kernels
        (:meth:`md.AcousticSystem.forces`; translations only, ``solver="cg"``).
    solver : {"auto", "lu", "cg"}
        ``"lu"``: conjugate gradients preconditioned by a sparse LU factor of :math:`K_{ff}`
        (:func:`_lu_preconditioner`), two to five iterations; ``"cg"``: preconditioned by
        :math:`K_{ff}`'s per-particle blocks (block Jacobi), thousands of iterations on thinly
        cemented samples but little memory; ``"auto"``: LU up to :data:`LU_MAX_DOF` free
        degrees of freedom, or :data:`LU_MAX_DOF_FILM` where the cement is film-like (a thin
        coating, whose factor stays small), else block Jacobi.

    Notes
    -----
    With rotations, :math:`K_{ff}` is singular: a cement particle bonded at two points turns
    about the line through them at no cost (its centre moves), and a few chains of them do the
    same together. The load is consistent (it does no work on these mechanisms), the stress is
    independent of them, but the centres of mass that give the strain are not. ``"lu"`` takes
    the solution with no component along them (each particle's own mechanisms pinned, a shift
    of 1e-10 of the unit-scaled diagonal for the collective ones); ``"cg"`` leaves whatever
    part its iterations picked up, which moves the modulus by 1e-5 to 3e-4 relative on thin
    coatings — far below the resolution error of the cement lattice, but not reproducible
    across solvers.
    """
    return static_moduli(system, (wave,), rtol=rtol, maxiter=maxiter, parallel=parallel,
                         solver=solver)[wave]


def static_moduli(system: AcousticSystem, waves=("p", "s"), *, rtol=1e-10, maxiter=None,
                  parallel=False, solver="auto") -> dict:
    """:func:`static_modulus` of each wave in ``waves``, sharing the set-up (and with
    ``solver="lu"`` the factorisation: :math:`K_{ff}` is the same for P and S). Returns a dict
    ``{wave: StaticModulus}``."""
    axes = [_wave_axis(w) for w in waves]
    with _StaticSetup(system, rtol=rtol, maxiter=maxiter, parallel=parallel,
                      solver=solver) as setup:
        out = {}
        for wave, ax in zip(waves, axes):
            u, iterations = setup.slab_load(ax)
            out[wave] = _measure(setup.system, u, wave, ax, setup.flag, setup.slab,
                                 setup.n_slabs, setup.connected, iterations)
    return out


class _StaticSetup:
    """What every static solve on one system shares: the end slabs, the load path, the pruned
    system, the free degrees of freedom and the factorised (or preconditioned) :math:`K_{ff}`.
    A context manager: inside it the solver's vector operations run on one BLAS thread (more
    only wait on each other: on a busy machine, with several solves at once, a dot product of
    10^4 numbers took 16 ms instead of 12 us)."""

    def __init__(self, system: AcousticSystem, *, rtol, maxiter, parallel, solver):
        if not 0.0 < rtol < 1.0:
            raise ValueError(f"rtol must lie in (0, 1); got {rtol}")
        if maxiter is not None and (isinstance(maxiter, bool) or int(maxiter) != maxiter
                                    or maxiter < 1):
            raise ValueError(f"maxiter must be an integer >= 1 or None; got {maxiter!r}")
        if solver not in SOLVERS:
            raise ValueError(f"solver must be one of {SOLVERS}; got {solver!r}")
        self.slab, self.n_slabs, self.flag = _prescribed(system)
        flag = self.flag
        n = system.n_particles
        self.amp = 1e-6 * system.slab_thickness
        dof = system.dof
        self.connected = connected = _load_path(system, flag)
        self.system = system = _bonds_among(system, connected | (flag != 0))
        diag = system.stiffness_diagonal()      # zero: no stiffness, not solved for
        free = np.zeros((n, dof), bool)         # the end slabs' translations are prescribed
        free[:, :3] = ((flag == 0) & connected)[:, None]
        free[:, 3:] = connected[:, None]        # rotations, where there are any, are all free
        free &= diag > 0
        self.free, self.free_idx = free, np.flatnonzero(free.ravel())
        if self.free_idx.size == 0:
            raise ValueError("no free particle between the end slabs is bonded to them")
        if solver == "auto":
            cap = LU_MAX_DOF_FILM if _lattice_degree(system) <= FILM_DEGREE else LU_MAX_DOF
            solver = "lu" if self.free_idx.size <= cap and not parallel else "cg"
        if solver == "lu" and parallel:
            raise ValueError("parallel applies to solver='cg' only")
        self.solver, self.parallel, self.rtol = solver, parallel, rtol
        self.maxiter = maxiter or 20 * self.free_idx.size

    def __enter__(self):
        from threadpoolctl import threadpool_limits

        self._limits = threadpool_limits(limits=1, user_api="blas")
        system, free, free_idx = self.system, self.free, self.free_idx
        if self.solver == "lu":
            K = system.stiffness_matrix().tocsr()[free_idx][:, free_idx]
            self.apply_, self.precondition = _lu_preconditioner(system, K, free, free_idx)
        else:
            self.apply_, self.precondition = _block_jacobi(system, free, free_idx,
                                                           self.parallel)
        return self

    def __exit__(self, *exc):
        self._limits.restore_original_limits()
        return False

    def solve(self, u_p, extra=None):
        """Displacements (n, dof) with the prescribed ones ``u_p`` (free entries ignored) and
        the free ones at equilibrium under the bond forces plus ``extra`` (forces, shape (n,
        dof), such as those of the periodic images' strain); and the iteration count."""
        u_p = np.array(u_p, dtype=float)
        u_p.ravel()[self.free_idx] = 0.0
        f = self.system.forces(u_p, parallel=self.parallel)
        if extra is not None:
            f = f + extra
        y, iterations = _pcg(self.apply_, self.precondition, f.ravel()[self.free_idx],
                             self.rtol, self.maxiter)
        u = u_p.ravel()
        u[self.free_idx] = y
        return u.reshape(u_p.shape), iterations

    def slab_load(self, ax):
        """The bottom slab displaced by :attr:`amp` along axis ``ax``, the top slab held."""
        u_p = np.zeros((self.system.n_particles, self.system.dof))
        u_p[self.flag == 2, ax] = self.amp
        return self.solve(u_p)


#: Pa in one GPa: the MD engine works in SI, the ``rockcem`` models in GPa.
PA_PER_GPA = 1.0e9


@dataclass(frozen=True)
class StaticStiffness:
    """Result of :func:`static_stiffness`: the transversely isotropic (axis z) stiffness of
    the linearised sample, Voigt notation, Pa.

    Attributes
    ----------
    c11, c12, c13, c33, c44, c66 : float
        Stiffness constants, Pa: ``c33`` and ``c44`` are :func:`static_moduli`'s P and S
        moduli (same solves); ``c13`` the lateral stress of the uniaxial z strain over that
        strain; ``c11``, ``c12`` the mean of the uniaxial x and y strains (the TI symmetry's
        two equal cases); ``c66`` the in-plane simple shear.
    c31 : float
        :math:`C_{31}` from the vertical stress of the lateral uniaxial strains (mean of x and
        y): equal to ``c13`` by the symmetry of the stiffness (Maxwell–Betti reciprocity) up to
        the noise of the in-plane stress of a band; their difference is a check, not used.
    density : float
        Bulk density (total mass over box area times height), kg/m³.
    bulk_reuss : float
        The bulk modulus of the sample under hydrostatic stress, Pa:
        :math:`1/K = \\sum_{i,j\\le3} S_{ij}`, :math:`S = C^{-1}` (the normal block with the
        measured ``c12``; :func:`rockcem.anisotropy.ti_bulk_modulus` with
        :math:`C_{66} = (C_{11} - C_{12})/2`); the modulus a confining or fluid pressure sees.
    bulk_voigt : float
        :math:`C_{iijj}/9 = (2C_{11} + C_{33} + 2C_{12} + 4C_{13})/9`, Pa: mean stress over
        volumetric strain under a hydrostatic *strain*; ``bulk_reuss <= bulk_voigt``, equal
        only for a sample without the anisotropy that couples shape to volume.
    epsilon, gamma, delta : float
        Thomsen's parameters (:func:`rockcem.anisotropy.thomsen`: eqs. 8a, 8b and 17 of
        [Thomsen1986]_).
    loads : dict
        Per load (``"z"``, ``"xz"``, ``"x"``, ``"y"``, ``"xy"``): the interior's mean strain
        and stress tensors (3 x 3, tension positive) and the solver's iteration count.
    """

    c11: float
    c12: float
    c13: float
    c33: float
    c44: float
    c66: float
    c31: float
    density: float
    bulk_reuss: float
    bulk_voigt: float
    epsilon: float
    gamma: float
    delta: float
    loads: dict = field(default_factory=dict, compare=False, repr=False)

    @property
    def bulk_isotropic(self) -> float:
        """:math:`C_{33} - \\tfrac43 C_{44}`, Pa: the bulk modulus an isotropic sample with this
        P and S modulus would have (what the isotropic reading of the pulse test reports)."""
        return self.c33 - 4.0 / 3.0 * self.c44


class _BandBonds:
    """Every bond of a (pruned) system with what the affine loads and the stress of the
    interior band need: the branch vector (centre to centre, minimum image in x and y), the
    image shift :math:`\\mathbf s = \\mathbf l - (\\mathbf x_j - \\mathbf x_i)` (a lattice vector
    of the periodic box, non-zero for a bond that crosses its side), the 3 x 3 constants and
    the weight of the bond in the band ``[z_lo, z_hi]`` (the fraction of its segment inside,
    :func:`md.observe.segment_fraction`)."""

    def __init__(self, system, z_lo, z_hi):
        from .observe import segment_fraction
        from .space import minimum_image

        i, j, n, k_n, k_t = system._bonds(system.bond_kn, system.bond_kt, system.lattice_kn,
                                          system.lattice_kt)
        x = system.positions
        raw = x[j] - x[i]
        self.branch = minimum_image(raw, system.box)
        self.shift = self.branch - raw
        self.i, self.j, self.normal = i, j, n
        self.k = (k_n - k_t)[:, None, None] * n[:, :, None] * n[:, None, :] \
            + k_t[:, None, None] * np.eye(3)
        self.arms = system._arms() if system.rotations else None
        self.weight = segment_fraction(x[i, 2], self.branch[:, 2], z_lo, z_hi)
        self.volume = system.box.lx * system.box.ly * (z_hi - z_lo)
        self.n, self.dof = system.n_particles, system.dof

    def opening(self, u, strain):
        """Relative displacement of the two faces of every bond (as in
        :mod:`md._kernels_rotation`) plus the jump :math:`E\\,\\mathbf s` the macroscopic
        displacement gradient ``strain`` gives the bonds across the box's sides, m."""
        u = u.reshape(self.n, self.dof)
        d = u[self.j, :3] - u[self.i, :3] + self.shift @ strain.T
        if self.arms is not None:
            a_i, a_j = self.arms
            d += np.cross(self.normal, a_i[:, None] * u[self.i, 3:] + a_j[:, None] * u[self.j, 3:])
        return d

    def jump_forces(self, strain):
        """Forces (and moments) on the particles, shape (n, dof), of the jumps alone."""
        return self._gather(np.einsum("mab,mb->ma", self.k, self.shift @ strain.T))

    def check(self, system, seed=0):
        """Raise unless these bonds give the operator's forces
        (:meth:`md.AcousticSystem.forces`) for a random displacement: the stress and the
        jumps then describe the same bonds as the solve."""
        u = np.random.default_rng(seed).standard_normal((self.n, self.dof))
        want = system.forces(u)
        got = self._gather(np.einsum("mab,mb->ma", self.k, self.opening(u, np.zeros((3, 3)))))
        scale = float(np.abs(want).max()) or 1.0
        if not np.abs(got - want).max() <= 1e-9 * scale:
            raise RuntimeError("the bond list of md.static does not reproduce "
                               "AcousticSystem.forces: the operator holds bonds it does not "
                               "know; update md.static._BandBonds")

    def _gather(self, F):
        """Forces (and moments) on the particles of the bond pulls ``F`` (on ``i``; ``-F`` on
        ``j``), shape (n, dof)."""
        f = np.zeros((self.n, self.dof))
        for a in range(3):
            f[:, a] = np.bincount(self.i, F[:, a], self.n) - np.bincount(self.j, F[:, a], self.n)
        if self.arms is not None:
            m = np.cross(self.normal, F)
            a_i, a_j = self.arms
            for a in range(3):
                f[:, 3 + a] = np.bincount(self.i, a_i * m[:, a], self.n) \
                    + np.bincount(self.j, a_j * m[:, a], self.n)
        return f

    def stress(self, u, strain):
        """Virial stress of the band, tension positive:
        :math:`\\sigma_{ab} = \\frac1V\\sum_b w_b\\, l_{b,a}\\, F_{b,b'}`, with :math:`\\mathbf F_b
        = k_b\\mathbf d_b` the pull of bond ``b`` on ``i`` (the force on ``j`` reversed) and row
        ``a`` the normal of the plane the traction acts on, Pa."""
        F = np.einsum("mab,mb->ma", self.k, self.opening(u, strain))
        return np.einsum("m,ma,mb->ab", self.weight, self.branch, F) / self.volume


def static_stiffness(system: AcousticSystem, *, rtol=1e-10, maxiter=None,
                     solver="auto") -> StaticStiffness:
    """The five constants of the transversely isotropic (axis z) sample by static solves on the
    operator of :func:`static_moduli`, sharing its set-up and factorisation.

    Five loads, each a solve of :math:`K_{ff} u_f = f_f` on the free particles of the load path
    (:func:`static_modulus`):

    * ``"z"``: the bottom slab displaced along z, the top held (:func:`static_moduli`'s P
      wave): :math:`C_{33}` as there (the reaction over the interior's strain), and
      :math:`C_{13} = \\tfrac12(\\sigma_{xx} + \\sigma_{yy})/\\varepsilon_{zz}` (the lateral strain
      of the interior is zero: the box is periodic in x and y);
    * ``"xz"``: the bottom slab displaced along x (the S wave): :math:`C_{44}` as there;
    * ``"x"``, ``"y"``: uniaxial strain :math:`\\varepsilon` along a periodic direction, a
      homogeneous (affine) strain of the box: the end slabs displaced by
      :math:`E\\mathbf x`, and every bond that crosses a side of the box opened by the jump
      :math:`E\\mathbf s` of its image (as :mod:`md.bonded`'s periodic images); the free
      particles relax. The interior's x and y strains are exactly the imposed ones (the
      fluctuations are periodic); its mean :math:`\\varepsilon_{zz}` (the least-squares slope
      of the slab centres of mass, as for ``"z"``) is small but not zero (the end slabs hold
      z), and is taken out with the ``"z"`` constants:
      :math:`C_{11} = (\\sigma_{xx} - C_{13}\\varepsilon_{zz})/\\varepsilon`,
      :math:`C_{12} = (\\sigma_{yy} - C_{13}\\varepsilon_{zz})/\\varepsilon`,
      :math:`C_{31} = (\\sigma_{zz} - C_{33}\\varepsilon_{zz})/\\varepsilon`; x and y are averaged;
    * ``"xy"``: simple shear :math:`u_x = \\gamma y` the same way:
      :math:`C_{66} = \\sigma_{yx}/\\gamma` (the traction on planes normal to y; simple shear,
      as ``"xz"``, so that without rotations, where the lattice resists rigid rotation, both
      are S-wave moduli).

    The in-plane stresses have no reaction to measure (x and y have no ends), so every stress
    of the affine loads and the lateral stress of ``"z"`` is the virial of the interior band
    (between the end slabs), each bond weighted by the fraction of its segment inside
    (Irving & Kirkwood's bond function). That is exactly the mean, over the planes normal to a
    direction, of the force crossing a plane per area: over the horizontal planes it equals
    the reaction of the end slab (every free particle is in equilibrium; tested), over the
    vertical planes it is the only traction there is. What it carries is the noise of the
    band: the forces crossing a vertical window of the band's height depend on the few layers
    of nearly horizontal bonds it holds.

    Parameters
    ----------
    system : md.AcousticSystem
    rtol, maxiter, solver
        As :func:`static_moduli` (the multi-threaded operator is not offered: the affine loads
        add forces of their own).

    Returns
    -------
    StaticStiffness
        With the bulk modulus under hydrostatic stress (:math:`1/K = \\sum_{i,j\\le3}S_{ij}`),
        the Voigt one and Thomsen's parameters (:mod:`rockcem.anisotropy`).
    """
    from rockcem.anisotropy import thomsen

    with _StaticSetup(system, rtol=rtol, maxiter=maxiter, parallel=False,
                      solver=solver) as setup:
        sys_ = setup.system
        z0 = sys_.extent[0]
        t = sys_.slab_thickness
        bonds = _BandBonds(sys_, z0 + t, z0 + (setup.n_slabs - 1) * t)
        bonds.check(sys_)
        args = (setup.flag, setup.slab, setup.n_slabs, setup.connected)
        loads = {}
        zero = np.zeros((3, 3))
        # The two slab loads of static_moduli: C33 and C44 from reaction and slab fit.
        u, it = setup.slab_load(2)
        p = _measure(sys_, u, "p", 2, *args, it)
        e = np.zeros((3, 3))
        e[2, 2] = p.strain
        loads["z"] = (e, bonds.stress(u, zero), it)
        u, it = setup.slab_load(0)
        s = _measure(sys_, u, "s", 0, *args, it)
        e = np.zeros((3, 3))
        e[0, 2] = e[2, 0] = 0.5 * s.strain
        loads["xz"] = (e, bonds.stress(u, zero), it)
        c33, c44 = p.modulus, s.modulus
        sig = loads["z"][1]
        c13 = 0.5 * (sig[0, 0] + sig[1, 1]) / p.strain
        # The affine loads through the periodic images.
        x = sys_.positions
        ends = setup.flag != 0
        for name, (a, b) in (("x", (0, 0)), ("y", (1, 1)), ("xy", (0, 1))):
            E = np.zeros((3, 3))
            E[a, b] = 1e-6
            u_p = np.zeros((sys_.n_particles, sys_.dof))
            u_p[ends, :3] = x[ends] @ E.T
            u, it = setup.solve(u_p, bonds.jump_forces(E))
            grad = E.copy()
            grad[:, 2] = _interior_slopes(sys_, u[:, :3] - x @ E.T, *args)
            loads[name] = (0.5 * (grad + grad.T), bonds.stress(u, E), it)
    c11, c12, c31 = [], [], []
    for name, a, o in (("x", 0, 1), ("y", 1, 0)):
        e, sig, _ = loads[name]
        c11.append((sig[a, a] - c13 * e[2, 2]) / e[a, a])
        c12.append((sig[o, o] - c13 * e[2, 2]) / e[a, a])
        c31.append((sig[2, 2] - c33 * e[2, 2]) / e[a, a])
    e, sig, _ = loads["xy"]
    c66 = sig[1, 0] / (2.0 * e[0, 1])
    c11, c12, c31 = (float(np.mean(v)) for v in (c11, c12, c31))
    gpa = {k: v / PA_PER_GPA for k, v in dict(c11=c11, c13=c13, c33=c33, c44=c44,
                                                   c66=c66).items()}
    th = thomsen(**gpa)
    # The bulk moduli of the measured normal block (its own C12, which the sample's in-plane
    # noise keeps from C11 - 2 C66 exactly): 1/K = 1.S.1 under hydrostatic stress, 1.C.1/9
    # under hydrostatic strain.
    normal = np.array([[c11, c12, c13], [c12, c11, c13], [c13, c13, c33]])
    ones = np.ones(3)
    bulk_reuss = 1.0 / float(ones @ np.linalg.solve(normal, ones))
    bulk_voigt = float(ones @ normal @ ones) / 9.0
    return StaticStiffness(float(c11), float(c12), float(c13), float(c33), float(c44),
                           float(c66), float(c31), p.density, bulk_reuss, float(bulk_voigt),
                           float(th.epsilon), float(th.gamma), float(th.delta), loads)


def _interior_slopes(system, u, flag, slab, n_slabs, connected):
    """Least-squares slopes against z of the interior slabs' centres of mass (load-path
    particles) of the three components of ``u`` (shape (n, 3)): the mean z derivatives of the
    interior's displacement, as :func:`static_modulus` takes its strain."""
    keep = connected & (flag == 0)
    m = system.masses * keep
    inner = np.arange(1, n_slabs - 1)
    mass = np.bincount(slab, weights=m, minlength=n_slabs)[inner]
    ok = mass > 0
    if ok.sum() < 2:
        raise ValueError("fewer than two interior slabs hold particles on the load path")
    zc = np.bincount(slab, weights=m * system.positions[:, 2], minlength=n_slabs)[inner]
    uc = np.stack([np.bincount(slab, weights=m * u[:, a], minlength=n_slabs)[inner]
                   for a in range(3)], axis=1)
    return np.polyfit(zc[ok] / mass[ok], uc[ok] / mass[ok][:, None], 1)[0]


def _lattice_degree(system) -> float:
    """Mean number of lattice (cement–cement) bonds of the cement particles that have any (0
    without them; pruned and floating cement does not count)."""
    bonds = np.count_nonzero(system.lattice_neighbors >= 0, axis=1)
    bonded = np.zeros(system.n_particles, bool)     # cement particles with a lattice bond
    bonded[system.n_grains:] = bonds > 0
    table = system.lattice_neighbors
    bonded[table[table >= 0]] = True
    count = np.count_nonzero(bonded[system.n_grains:])
    return 2.0 * bonds.sum() / count if count else 0.0


def _measure(system, u, wave, ax, flag, slab, n_slabs, connected, iterations):
    """Stress (reaction on the fixed slab) and interior strain of the solved displacements."""
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
                         iterations)


def _unit_blocks(system, free):
    """Each particle's own block of :math:`K` on its free degrees of freedom (held ones: a unit
    diagonal), and the scale that makes the blocks' diagonals one (forces and moments differ by
    many orders of magnitude)."""
    dof = system.dof
    blocks = system.stiffness_blocks()
    held = ~free
    blocks[held[:, :, None] | held[:, None, :]] = 0.0
    blocks[:, np.arange(dof), np.arange(dof)] += held
    scale = 1.0 / np.sqrt(np.diagonal(blocks, axis1=1, axis2=2))
    return blocks * scale[:, :, None] * scale[:, None, :], scale


def _block_jacobi(system, free, free_idx, parallel):
    """Operator and block-Jacobi preconditioner of :func:`_pcg` for ``solver="cg"``, both
    written into buffers made once (no step allocates). Each particle's own block of K on its
    free degrees of freedom is inverted (a pseudo-inverse where a rotation has no stiffness):
    on a cemented 2 700-particle sample with rotations it takes 2.8 times fewer iterations than
    the diagonal."""
    from ._kernels_acoustic import block_jacobi

    n, dof = system.n_particles, system.dof
    unit, scale = _unit_blocks(system, free)
    inverse = np.linalg.pinv(unit, rcond=1e-10, hermitian=True) \
        * scale[:, :, None] * scale[:, None, :]
    full_u = np.zeros(n * dof)          # displacements: held entries stay zero
    full_r = np.zeros(n * dof)          # scratch of the preconditioner: held entries stay zero
    full_f = np.zeros(n * dof)
    full_z = np.zeros(n * dof)
    active = np.unique(free_idx // dof)
    zero_v = np.zeros(n * dof)

    def apply_(p, q):                   # q = K_ff p
        full_u[free_idx] = p
        system.forces(full_u, zero_v, parallel=parallel, out=full_f)
        np.take(full_f, free_idx, out=q, mode="clip")     # "raise" would buffer ``out``
        np.negative(q, out=q)

    def precondition(r, z):             # z = M^-1 r
        block_jacobi(inverse, active, free_idx, r, full_r, full_z, z)

    return apply_, precondition


def _pinned_matrix(system, K, free, free_idx, shift=1e-10):
    """The symmetric positive definite matrix that ``solver="lu"`` factorises,
    :math:`A = D^{-1/2} K_{ff} D^{-1/2} + N N^T + \\delta I` (CSC; :math:`D` the diagonal of
    :math:`K_{ff}`), and the scale :math:`D^{-1/2}` (a vector).

    :math:`N` holds each particle's own mechanisms — unit null vectors of its scaled block, such
    as a cement particle bonded at two points turning about the line through them — which are
    exact null vectors of the whole scaled matrix, so pinning them changes nothing on its range;
    the shift :math:`\\delta` (1e-10; 1e-8 to 1e-12 agree to 1e-8 in the modulus) covers the
    mechanisms several particles share."""
    import scipy.sparse as sp

    unit, _ = _unit_blocks(system, free)
    lam, vec = np.linalg.eigh(unit)
    part, k = np.nonzero((lam < 1e-10) & free.any(axis=1)[:, None])
    null = vec[part, :, k]                          # (m, dof), zero on held entries
    where = np.full(free.shape, -1)
    where.ravel()[free_idx] = np.arange(free_idx.size)
    rows = where[part]
    on = rows >= 0
    cols = np.broadcast_to(np.arange(part.size)[:, None], rows.shape)
    N = sp.csr_matrix((null[on], (rows[on], cols[on])), shape=(free_idx.size, part.size))
    sc = 1.0 / np.sqrt(K.diagonal())
    A = sp.diags(sc) @ K @ sp.diags(sc) + N @ N.T + shift * sp.identity(free_idx.size)
    return A.tocsc(), sc


def _factorise(A):
    """The solve :math:`b \\mapsto A^{-1} b` of a sparse LU factor of the symmetric positive
    definite ``A`` (CSC): SuperLU (Li 2005; :func:`scipy.sparse.linalg.splu`), minimum-degree
    ordering of :math:`A^T + A`, no pivoting. (A sparse Cholesky factor, CHOLMOD through
    ``cholespy``, or MKL PARDISO's, was measured in its place and not taken:
    docs/studies/md_static_solver.md.)"""
    import scipy.sparse.linalg as spla

    lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                   options={"SymmetricMode": True})
    return lu.solve


def _lu_preconditioner(system, K, free, free_idx, shift=1e-10):
    """Operator and preconditioner of :func:`_pcg` for ``solver="lu"``: the sparse factor
    (:func:`_factorise`) of the pinned, scaled and shifted
    :math:`A = D^{-1/2} K_{ff} D^{-1/2} + N N^T + \\delta I` (:func:`_pinned_matrix`). The
    preconditioned iterations then refine the factor's solution on the unmodified
    :math:`K_{ff}`, in two to five steps."""
    A, sc = _pinned_matrix(system, K, free, free_idx, shift)
    solve = _factorise(A)

    def apply_(p, q):
        q[:] = K @ p

    def precondition(r, z):
        z[:] = sc * solve(sc * r)

    return apply_, precondition


def _pcg(apply_, precondition, b, rtol, maxiter):
    """Preconditioned conjugate gradients (Hestenes & Stiefel 1952; Saad 2003, Alg. 9.1) for
    :math:`K_{ff} y = b` from :math:`y = 0`, with ``apply_(p, q)`` writing :math:`K_{ff} p`
    into ``q`` and ``precondition(r, z)`` writing :math:`M^{-1} r` into ``z``; stops when
    :math:`\\|b - K_{ff} y\\| \\le` ``rtol`` :math:`\\|b\\|` (the criterion of
    :func:`scipy.sparse.linalg.cg`). Returns ``y`` and the iteration count.

    Written out rather than taken from scipy so that no step allocates: every vector lives in a
    buffer made once. A solve of a few thousand iterations otherwise allocates tens of arrays of
    100 kB–1 MB per iteration, and where the C library returns such blocks to the kernel at once
    (``MALLOC_TRIM_THRESHOLD_`` set, as a dask.distributed nanny does for its workers) every one
    of them page-faults afresh: the same member ran 3–4 times slower in a dask worker.
    """
    y = np.zeros(b.size)
    r = b.copy()
    z = np.empty_like(b)
    q = np.empty_like(b)
    t = np.empty_like(b)
    tol = rtol * float(np.sqrt(b @ b))
    precondition(r, z)
    p = z.copy()
    rz = float(r @ z)
    for it in range(maxiter + 1):
        if float(np.sqrt(r @ r)) <= tol:
            return y, it
        if it == maxiter:
            break
        apply_(p, q)
        alpha = rz / float(p @ q)
        np.multiply(p, alpha, out=t)
        y += t
        np.multiply(q, alpha, out=t)
        r -= t
        precondition(r, z)
        rz_new = float(r @ z)
        p *= rz_new / rz
        p += z
        rz = rz_new
    raise RuntimeError(f"static solve did not converge in {maxiter} CG iterations")
