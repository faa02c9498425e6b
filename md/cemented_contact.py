r"""One cemented contact on the cement lattice, against the cemented-contact theory.

Two equal grains of radius :math:`R` on the z axis, their surfaces :math:`2\varepsilon R` apart
(:math:`\varepsilon = 0`: touching, no Hertz contact), joined by cement filling the gap within
radius :math:`a = \alpha R` of the axis — the cement body of Dvorkin et al.'s contact cement
theory ([Dvorkin1994]_; scheme 1 of :func:`rockcem.granular.contact_cement`). The lattice
(:func:`md.cement_lattice` at resolution :math:`\Omega`) is cut, the pore cells inside that body
are cemented, the operator of :func:`md.acoustic_system` is assembled, and the static stiffness
of the bond is solved directly: the lower grain held, the upper one moved along z (normal) or x
(tangential, no rotation), the cement relaxed, the reaction on the upper grain read.

The theory's stiffness of the same bond is :math:`k_n = \pi M_c R\,S(\alpha, \Lambda_n,
\varepsilon)` and :math:`k_t = \pi G_c R\,S(\alpha, \Lambda_\tau(1-\nu/2), \varepsilon)` with
:math:`S` the solution of the integral equation of
:func:`rockcem.contact_integral.cemented_contact_stiffness`,
:math:`\Lambda_n = M_c(1-\nu)/(\pi G)` and :math:`\Lambda_\tau = G_c/(\pi G)`. (Its rigid-grain
limit :math:`\Lambda \to 0` is the thin layer in uniaxial strain, :math:`\pi M_c R \ln(1 +
\alpha^2/2\varepsilon)`; its rigid-cement limit is the welded contact of two flat punches in
series, :math:`k_n = aE/(1-\nu^2)`, :math:`k_t = 4Ga/(2-\nu)`.) The normalisation: at
:math:`\Lambda \to 0`, :math:`S = \int_0^\alpha t\,dt/(\varepsilon + t^2/2)`, and the layer of
local thickness :math:`2R(\varepsilon + t^2/2)` and stiffness per area :math:`M_c/\text{thickness}`
integrates to :math:`\pi M_cR\,S`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .cement import HARD_CEMENT, CementMaterial
from .contact import QUARTZ, GrainMaterial

__all__ = ["ContactStiffness", "contact_system", "lattice_contact_stiffness",
           "theory_contact_stiffness"]


class ContactStiffness(NamedTuple):
    """Normal and tangential stiffness of a cemented contact, N/m."""

    normal: float
    tangential: float


def _check_contact(radius_ratio, radius, thickness_ratio):
    """``(alpha, eps, R)`` as floats, or a ValueError naming the input out of range."""
    alpha, eps, R = float(radius_ratio), float(thickness_ratio), float(radius)
    if not 0.0 < alpha <= 0.9:
        raise ValueError(f"radius_ratio must lie in (0, 0.9]; got {radius_ratio}")
    if not (np.isfinite(eps) and eps >= 0):
        raise ValueError(f"thickness_ratio must be >= 0; got {thickness_ratio}")
    if not (np.isfinite(R) and R > 0):
        raise ValueError(f"radius must be > 0 m; got {radius}")
    return alpha, eps, R


def _check_offset(lattice_offset):
    """``lattice_offset`` as a float array of 3, or a ValueError naming the valid range."""
    try:
        off = np.asarray(lattice_offset, dtype=float)
    except (TypeError, ValueError):
        off = np.full(1, np.nan)
    if off.shape != (3,) or not np.all((off >= 0.0) & (off < 1.0)):
        raise ValueError(f"lattice_offset must be three shifts in [0, 1) cells (x, y, z); got "
                         f"{lattice_offset!r}")
    return off


def _cemented_cells(alpha, resolution, eps, offset=(0.0, 0.0, 0.0)):
    """Centres (in units of R, contact plane at z = 0, axis x = y = 0) of the cells of a lattice
    of width 1/Omega (cell faces on the axis planes, shifted by ``offset`` cells along x, y and
    z) that lie in the cement body, their lattice indices and the lattice shape."""
    cw = 1.0 / resolution
    off = np.asarray(offset, dtype=float)
    half_xy = int(np.ceil(alpha / cw)) + 2
    h_max = eps + 1.0 - np.sqrt(1.0 - alpha**2)           # half the gap at the rim
    half_z = int(np.ceil(h_max / cw)) + 1 + int(np.any(off != 0.0))
    shape = (2 * half_xy, 2 * half_xy, 2 * half_z)
    k, j, i = np.meshgrid(*(np.arange(s) for s in shape[::-1]), indexing="ij")
    centre = np.stack([(i.ravel() - half_xy + 0.5 + off[0]) * cw,
                       (j.ravel() - half_xy + 0.5 + off[1]) * cw,
                       (k.ravel() - half_z + 0.5 + off[2]) * cw], axis=-1)
    rho2 = centre[:, 0] ** 2 + centre[:, 1] ** 2
    outside = np.all([np.sum((centre - [0.0, 0.0, s * (1.0 + eps)]) ** 2, axis=1) > 1.0
                      for s in (-1, 1)], axis=0)
    keep = (rho2 <= alpha**2) & outside & (np.abs(centre[:, 2]) < 1.0 + eps)
    return centre[keep], np.flatnonzero(keep), shape


def _grain_cement(centre, cw, eps):
    """Bonds (grain, cell, unit normal) of every cell that touches one of the two unit spheres
    at z = -(1 + eps) and z = 1 + eps: the closest point of its cube to the sphere's centre lies
    inside the sphere, or the centre of one of its 6 face neighbours does (the rule of
    :mod:`md.interface`, here by brute force)."""
    grain, cell, normal = [], [], []
    for g, zg in enumerate((-(1.0 + eps), 1.0 + eps)):
        centre_g = np.array([0.0, 0.0, zg])
        closest = np.clip(centre_g, centre - 0.5 * cw, centre + 0.5 * cw)
        inside = np.sum((closest - centre_g) ** 2, axis=1) < 1.0
        for step in np.vstack([np.eye(3), -np.eye(3)]) * cw:
            inside |= np.sum((centre + step - centre_g) ** 2, axis=1) < 1.0
        hit = np.flatnonzero(inside)
        d = centre[hit] - centre_g
        grain.append(np.full(hit.size, g))
        cell.append(hit)
        normal.append(d / np.linalg.norm(d, axis=1)[:, None])
    grain, cell, normal = np.concatenate(grain), np.concatenate(cell), np.concatenate(normal)
    order = np.argsort(cell, kind="stable")
    return grain[order], cell[order], normal[order]


def contact_system(radius_ratio, resolution, *, radius=1e-4, thickness_ratio=0.0,
                   material: GrainMaterial = QUARTZ, cement: CementMaterial = HARD_CEMENT,
                   interface="facet", rotations=False, lattice_offset=(0.0, 0.0, 0.0),
                   bond_column="half_cell", column_floor=0.1, rim_shift=0.0):
    r"""The linearised system of one cemented contact (module docstring): two grains (particles
    0 and 1, no Hertz contact between them) and the cement particles, on a lattice of width
    :math:`R/\Omega` whose cell faces lie on the contact plane and on two planes through the
    axis (by default; ``lattice_offset`` shifts them). Parameters as
    :func:`lattice_contact_stiffness`; returns an :class:`md.AcousticSystem` (no dashpots;
    with ``rotations`` the six degrees of freedom of :func:`md.acoustic_system`'s
    ``rotations=True``: bonds at their contact points, the
    rotating lattice's constants).

    ``bond_column`` (a study option, ``benchmarks/md_rotations_reference.py --twist``): the
    length of each grain–cement bond's cement column (``column`` of
    :func:`md.interface.interface_stiffness`). ``"half_cell"`` (default) :math:`c_w/2` for
    every bond; ``"volume"`` :math:`c_w^3/2A_i`, half a cell's volume spread over the bond's
    interface area :math:`A_i` (:func:`md.interface.interface_area`; :math:`c_w/2` times
    :math:`\max(\|\hat n\|_\infty, \|\hat n\|_1/2)`, the mean height of a cell centre
    above an inclined surface along its normal, for a staircase of columns along the
    dominant axis); ``"distance"`` the distance of the cell centre from the sphere,
    :math:`h = |\mathbf x_c - \mathbf x_g| - R`, at least ``column_floor`` :math:`c_w`
    (``column_floor`` in (0, 1]: a cell centre on the sphere would bond rigidly).
    ``rim_shift`` (a study option, cells, in [0, 1); default 0): the cells cemented are those
    whose centre lies within :math:`a + ` ``rim_shift`` :math:`c_w` of the axis (the
    continuum's neck keeps its radius a)."""
    from .acoustic import (_LATTICE_LENGTH2, AcousticSystem, _lattice_springs, _lattice_table,
                           grain_cement_arms)
    from .interface import interface_area, interface_stiffness
    from .space import Box

    alpha, eps, R = _check_contact(radius_ratio, radius, thickness_ratio)
    if not resolution >= 2.0:
        raise ValueError(f"resolution must be >= 2 cells per radius; got {resolution}")
    off = _check_offset(lattice_offset)
    if not 0.0 <= rim_shift < 1.0:
        raise ValueError(f"rim_shift must lie in [0, 1) cell widths; got {rim_shift}")
    centre, flat, shape = _cemented_cells(alpha + rim_shift / float(resolution),
                                          float(resolution), eps, off)
    if centre.shape[0] == 0:
        raise ValueError(f"no cell of width R/{resolution:g} lies in the cement (a/R = {alpha:g}, "
                         f"thickness {eps:g}): raise the resolution")
    cw = R / resolution
    n_c = centre.shape[0]
    where = np.full(int(np.prod(shape)), -1, np.int32)
    where[flat] = np.arange(n_c, dtype=np.int32)
    table, _ = _lattice_table(flat.astype(np.int64), where, shape, 2)
    grain, cell, normal = _grain_cement(centre, 1.0 / resolution, eps)
    grains = np.array([[0.0, 0.0, -(1.0 + eps)], [0.0, 0.0, 1.0 + eps]]) * R
    if bond_column == "half_cell":
        column = None
    elif bond_column == "volume":
        column = 0.5 * cw**3 / interface_area(normal, cw)
    elif bond_column == "distance":
        if not 0.0 < column_floor <= 1.0:
            raise ValueError(f"column_floor must lie in (0, 1] cell widths; got {column_floor}")
        h = np.linalg.norm(centre[cell] * R - grains[grain], axis=1) - R
        column = np.maximum(h, column_floor * cw)
    else:
        raise ValueError(f"bond_column must be 'half_cell', 'volume' or 'distance'; got "
                         f"{bond_column!r}")
    # Each grain's cells face the other grain: "facet" and "patch" are the same here.
    kn, kt = interface_stiffness(grain, cell, normal, np.full(2, R), table, 2, cw, material,
                                 cement, interface, 1 - grain, column=column)
    _, _, m_c, lat_kn, lat_kt = _lattice_springs(cement, cw, "waves", rotations)
    m_grain = material.density * 4.0 / 3.0 * np.pi * R**3
    zero = np.zeros(grain.size)
    side = shape[0] * cw
    rot = {}
    if rotations:       # a grain-cement bond acts at the cell centre (md.acoustic_system)
        arm_g, arm_c = grain_cement_arms(centre[cell] * R - grains[grain], normal)
        rot = {"arm_i": arm_g, "arm_j": arm_c,
               "lattice_arm": 0.5 * cw * np.sqrt(_LATTICE_LENGTH2),
               "inertia": np.concatenate([np.full(2, 0.4 * m_grain * R**2),
                                          np.full(n_c, m_c * cw**2 / 6.0)])}
    return AcousticSystem(
        np.concatenate([grains, centre * R]), np.concatenate([[m_grain, m_grain],
                                                              np.full(n_c, m_c)]), 2,
        Box(side, side, -2.0 * R, 2.0 * R), grain.astype(np.int32), (cell + 2).astype(np.int32),
        normal, kn, kt, zero, zero, table, lat_kn, lat_kt, R, (-2.0 * R, 2.0 * R),
        {"cell_width": cw, "n_cement": n_c, "interface": interface}, **rot)


def lattice_contact_stiffness(radius_ratio, resolution, *, radius=1e-4, thickness_ratio=0.0,
                              material: GrainMaterial = QUARTZ,
                              cement: CementMaterial = HARD_CEMENT,
                              interface="facet", rotations=False,
                              lattice_offset=(0.0, 0.0, 0.0)) -> ContactStiffness:
    r"""Static normal and tangential stiffness of one cemented contact on the lattice.

    Parameters
    ----------
    radius_ratio : float
        :math:`\alpha = a/R`, in (0, 0.9].
    resolution : float
        :math:`\Omega = R/c_w`, ``>= 2``; the gap at the rim, :math:`R\alpha^2`
        (touching grains), must hold cell centres, so small :math:`\alpha` needs
        :math:`\Omega \gtrsim 2/\alpha^2`.
    radius : float
        :math:`R`, m.
    thickness_ratio : float
        :math:`\varepsilon`, half the axial gap over :math:`R`, ``>= 0``.
    material : GrainMaterial
    cement : CementMaterial
    interface : {"facet", "patch", "paper"}
        Grain–cement rule (:mod:`md.interface`).
    rotations : bool
        Whether the cement particles rotate (:func:`md.acoustic_system`'s ``rotations``); the
        two grains are held in translation and rotation either way, the cement relaxes.
    lattice_offset : sequence of 3 floats
        Shift of the lattice against the contact, in cells along x, y and z, each in [0, 1);
        default none (cell faces on the contact plane and on the planes x = 0 and y = 0). In
        a pack every contact sits at its own offset from the lattice, so a mean over offsets
        is what a pack's contacts see on average (``benchmarks/md_rotations_reference.py``).

    Returns
    -------
    ContactStiffness
        N/m.

    Raises
    ------
    ValueError
        For inputs out of range, or when no cell (or no connected path of cells) lies in the
        cement at this resolution.
    """
    system = contact_system(radius_ratio, resolution, radius=radius,
                            thickness_ratio=thickness_ratio, material=material, cement=cement,
                            interface=interface, rotations=rotations,
                            lattice_offset=lattice_offset)
    return ContactStiffness(*_grain_reactions(system, (2, 0)))


def _grain_reactions(system, components, extra=None):
    """Reaction on grain 1 of :func:`contact_system`'s ``system`` along each of its degrees of
    freedom ``components`` (0-2 translations; 3-5 rotations about its centre, with rotations)
    when that one is moved by 1 (m or rad), grain 0 and grain 1's other degrees of freedom
    held and the cement relaxed: the diagonal of the bond's stiffness (N/m, N m/rad).
    ``extra`` (a sparse matrix of K's shape, optional) is added to the system's stiffness
    matrix (study springs, ``benchmarks/md_rotations_reference.py --twist``)."""
    from .static import _load_path, _lu_preconditioner, _pcg

    n, dof = system.n_particles, system.dof
    flag = np.zeros(n, np.int8)
    flag[0] = 1
    if not _load_path(system, flag)[1]:
        raise ValueError("the cement does not join the two grains at this resolution")
    flag[1] = 2
    free = np.repeat((_load_path(system, flag) & (flag == 0))[:, None], dof, axis=1)
    free_idx = np.flatnonzero(free)
    K = system.stiffness_matrix().tocsr()
    if extra is not None:
        if extra.shape != K.shape:
            raise ValueError(f"extra must have the stiffness matrix's shape {K.shape}; got "
                             f"{extra.shape}")
        K = (K + extra).tocsr()
    Kff = K[free_idx][:, free_idx]
    # K_ff is singular with rotations (a cell bonded at two points turns about the line through
    # them): the factor of md.static pins those mechanisms, which carry no load.
    apply_, precondition = _lu_preconditioner(system, Kff, free, free_idx)
    out = []
    for ax in components:
        u = np.zeros(n * dof)
        u[dof + ax] = 1.0
        u[free_idx], _ = _pcg(apply_, precondition, -(K[free_idx][:, [dof + ax]].toarray()
                                                        .ravel()), 1e-12, 200)
        out.append(float((K @ u)[dof + ax]))
    return out


def theory_contact_stiffness(radius_ratio, *, radius=1e-4, thickness_ratio=0.0,
                             material: GrainMaterial = QUARTZ,
                             cement: CementMaterial = HARD_CEMENT, limit=None,
                             panels=64) -> ContactStiffness:
    """Normal and tangential stiffness of the same contact from the cemented-contact theory.

    Parameters
    ----------
    radius_ratio, radius, thickness_ratio, material, cement
        As :func:`lattice_contact_stiffness`.
    limit : {None, "rigid_grains", "rigid_cement"}
        The integral equation (default) or one of its limits (module docstring); the
        rigid-grain limit needs ``thickness_ratio > 0``.
    panels : int
        Collocation panels of the integral equation.

    Returns
    -------
    ContactStiffness
        N/m.
    """
    from rockcem.contact_integral import cemented_contact_stiffness

    alpha, eps, R = _check_contact(radius_ratio, radius, thickness_ratio)
    G, nu = material.shear_modulus, material.poisson_ratio
    Mc, Gc = cement.p_modulus, cement.shear_modulus
    if limit == "rigid_cement":
        a = alpha * R
        return ContactStiffness(a * material.young_modulus / (1 - nu**2), 4 * G * a / (2 - nu))
    if limit == "rigid_grains":
        if not eps > 0:
            raise ValueError("the rigid-grain limit of a touching contact is infinite: "
                             "give thickness_ratio > 0")
        S = np.log1p(alpha**2 / (2 * eps))
        return ContactStiffness(np.pi * Mc * R * S, np.pi * Gc * R * S)
    if limit is not None:
        raise ValueError(f"limit must be None, 'rigid_grains' or 'rigid_cement'; got {limit!r}")
    lam_n = Mc * (1 - nu) / (np.pi * G)
    lam_t = Gc / (np.pi * G) * (1 - 0.5 * nu)
    S = cemented_contact_stiffness(alpha, [lam_n, lam_t], eps, panels=panels)
    return ContactStiffness(float(np.pi * Mc * R * S[0]), float(np.pi * Gc * R * S[1]))
