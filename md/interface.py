r"""The grain–cement interface of the acoustic stage: the springs that join a grain to the cement
cells touching it (García & Medina, Sect. III F, and the patch rule of this project).

Three rules, chosen by ``interface`` in :func:`md.acoustic_system`:

``"paper"`` (the source's prescription, Sect. III F)
    every cemented cell whose cube meets a grain is joined to it by eq. 4 with the mixed moduli
    :math:`E^* = [(1-\nu_g^2)/E_g + (1-\nu_c^2)/E_c]^{-1}`,
    :math:`G^* = [(2-\nu_g)/G_g + (2-\nu_c)/G_c]^{-1}` ([Johnson1985]_ eqs. 4.22 and 7.42) and a
    contact of diameter :math:`c_w`: :math:`k_n = 2E^*(c_w/2)`, :math:`k_s = 8G^*(c_w/2)`
    (:math:`k_n = \tfrac43 E^*(c_w/2)` with the source's secant reading of eq. 4,
    ``normal_stiffness="secant"`` of :func:`md.acoustic_system`).
    An interface of area :math:`A` holds :math:`\approx A/c_w^2` such springs in parallel, so
    its stiffness grows like :math:`E^* A / c_w \propto \Omega`: as the lattice is refined the
    grains under the cement become rigid, and cemented moduli do not converge in
    :math:`\Omega`.

``"patch"`` (converges with :math:`\Omega` wherever the cement's shape does)
    the cemented cells touching one grain are grouped into *patches* — sets connected through
    lattice bonds between cells that touch that same grain (:func:`interface_patches`). The
    grain under a patch is an elastic half-space loaded by a flat punch of the patch's outer
    radius :math:`a_p` (below): normal stiffness :math:`2a_pE_g/(1-\nu_g^2)` and
    tangential :math:`8G_ga_p/(2-\nu_g)` (the rigid circular punch on one half-space,
    [Johnson1985]_ Ch. 3 — the constants :mod:`md.bond_stiffness` uses for a welded bond). The
    patch stiffness is shared among its cells in proportion to their interface areas (a bed of
    uniform stiffness per area, whose uniform displacement has exactly the punch stiffness),
    and each cell's share is in series with the cement between the cell centre and the grain
    surface, a column of half a cell: :math:`M_cA_i/(c_w/2)` normal, :math:`G_cA_i/(c_w/2)`
    tangential. The cement itself is resolved by the lattice, so only the grain's moduli enter
    the punch.

``"facet"`` (default; the patch rule with patches kept apart by neighbour)
    as ``"patch"``, but two cells of a grain's interface are in one patch only if they also face
    the same neighbouring grain — the grain nearest the cell centre after the cell's own
    (:func:`bond_partners`; Voronoi facets of the grain surface toward its neighbours). Under
    ``"patch"`` the necks of one grain join into one patch once cement links them around the
    grain (contact cement past S_c ≈ 0.1 on a compacted pack), whose punch radius, taken along a
    mean normal that the necks' opposed normals nearly cancel, is capped at the grain radius: a
    grain with six necks of radius :math:`a` then has one punch of :math:`2RE^*` in place of
    six of :math:`2aE^*` and the pack *softens* as cement is added (compacted pack, full
    sample, Ω 7: hard contact cement Vp 3.13 km/s at S_c 0.1, 2.52 km/s at 0.2). Each neck is
    loaded by its own contact force, in its own direction, so it is its own punch; the facet
    rule keeps it so. For a single contact (two grains) the two rules are the same.
    A facet toward a grain it touches encloses their contact disc, whose punch the
    grain–grain bond carries already: its punch is the annulus outside the contact
    (``contact_radius`` of :func:`interface_stiffness`), so the disc and the cement around it
    load the grain as one punch of the facet's radius. (Counted twice, a fully cemented
    sample came out stiffer than the Voigt bound of its grains and cement.)

Which cells touch a grain, and the area each stands for. The paper joins a grain to the cells
whose cube meets its sphere; the patch rule also joins the pore cells one of whose 6 face
neighbours has its centre inside the grain (``faces`` of
:func:`md._kernels_acoustic.grain_cement_bonds`): where the sphere passes through the far
half of a solid cell, the pore cell beside it does not reach the sphere, and without these
bonds the interface has holes — rings of cement not joined to the grain, which split patches
and made the single-contact stiffness jump with :math:`\Omega`. For a plane of unit normal
:math:`\hat n` (grain centre to cell centre), a cell centred at distance :math:`s` on the pore
side is joined when :math:`0 < s < c_w\max(\|\hat n\|_\infty, \|\hat n\|_1/2)` (face
neighbour inside, or cube meeting the plane), so these cells number
:math:`\max(\|\hat n\|_\infty, \|\hat n\|_1/2)/c_w^2` per unit area and each stands for
:math:`A_i = c_w^2/\max(\|\hat n\|_\infty, \|\hat n\|_1/2)` of the grain surface (tested:
a fully coated sphere sums to :math:`4\pi R^2`).

Patch radius. Seen along its mean normal :math:`\hat m` (the area-weighted mean of the
cells' normals), a patch projects onto a disc or an annulus :math:`b < \rho < a` (cells at
:math:`\rho_i = R\,|\hat n_i \times \hat m|`, projected areas
:math:`w_i = A_i\,\hat n_i\cdot\hat m`). For a uniform annulus
:math:`\langle\rho^2\rangle_w = (a^2 + b^2)/2` and :math:`\sum w_i = \pi(a^2 - b^2)`, so
the outer radius is :math:`a_p = \sqrt{\langle\rho^2\rangle_w + \sum w_i/2\pi}`, exact for
any spherical cap or zone up to a hemisphere (capped at :math:`R`). The punch takes the outer
radius, not the radius of a disc of the patch's area: around a contact the lattice has no cell
where the gap between the grains is under a cell (:math:`\rho \lesssim \sqrt{Rc_w}`), while
the real cement fills that core, and the stiffness of a rigid annular punch is close to that of
the full disc.

Departure and limits. The bed lumps the half-space: it has the punch's stiffness for a uniform
displacement of the whole patch but none of the Boussinesq coupling between the cells of a
patch for non-uniform ones (a patch tilting or bending is too soft or too stiff by a factor of
order one), and two patches of one grain do not interact until they touch and merge, when
both take the punch of the merged patch's outer radius. Patches are therefore only as
resolution-independent as the cement's shape: rings around contacts (``"pendular"``) converge,
while a film thinner than a cell (``"coating"`` at :math:`S_c = 0.1` is 0.024 R thick) forms
spots that join into ever larger patches as :math:`\Omega` grows
(``benchmarks/md_omega_convergence.py``). The
single-contact check (``tests/md/test_interface.py``, ``benchmarks/md_single_contact.py``)
measures what this leaves against the cemented-contact integral equation of [Dvorkin1994]_
(:func:`rockcem.contact_integral.cemented_contact_stiffness`).
"""

from __future__ import annotations

import numpy as np

__all__ = ["INTERFACES", "interface_area", "patch_radius", "interface_patches",
           "interface_stiffness", "bond_partners", "nearest_grain", "film_thickness",
           "film_bridges"]

#: Grain–cement interface rules of :func:`md.acoustic_system`, the default first.
INTERFACES = ("facet", "patch", "paper")


def bond_partners(bond_grain, cell_centres, positions, radii, box, k=8) -> np.ndarray:
    """The neighbouring grain each grain–cement bond's cell faces: the grain whose surface is
    nearest the cell centre, the bond's own grain excepted (periodic in x and y).

    Parameters
    ----------
    bond_grain : ndarray of int, shape (m,)
        Grain of each bond.
    cell_centres : ndarray, shape (m, 3)
        Centre of each bond's cement cell, m.
    positions : ndarray, shape (n, 3)
        Grain centres, m (x, y wrapped into the box).
    radii : ndarray, shape (n,)
        Grain radii, m.
    box : md.Box
        Periodic in x and y.
    k : int
        Nearest grain centres searched per cell (the nearest surface is among them unless the
        radii differ by more than the grain spacing).

    Returns
    -------
    ndarray of int64, shape (m,)
        Grain index, −1 where there is no other grain.
    """
    from scipy.spatial import cKDTree

    n = positions.shape[0]
    m = len(bond_grain)
    out = np.full(m, -1, np.int64)
    if n < 2 or m == 0:
        return out
    lo = min(float(positions[:, 2].min()), float(cell_centres[:, 2].min()))
    hi = max(float(positions[:, 2].max()), float(cell_centres[:, 2].max()))
    span = 3.0 * (hi - lo) + 1.0                       # z is not periodic: a box too tall to wrap
    shift = np.array([0.0, 0.0, lo - (hi - lo) - 0.5])

    def wrapped(x):
        y = np.asarray(x, dtype=float) - shift
        y[:, 0] %= box.lx
        y[:, 1] %= box.ly
        return y

    tree = cKDTree(wrapped(positions), boxsize=[box.lx, box.ly, span])
    kk = min(int(k), n)
    dist, idx = tree.query(wrapped(cell_centres), k=kk)
    dist, idx = dist.reshape(m, kk), idx.reshape(m, kk)
    gap = dist - radii[idx]
    gap[idx == np.asarray(bond_grain)[:, None]] = np.inf
    best = np.argmin(gap, axis=1)
    out[:] = idx[np.arange(m), best]
    out[~np.isfinite(gap[np.arange(m), best])] = -1
    return out


def nearest_grain(points, positions, radii, box, k=8) -> np.ndarray:
    """The grain whose surface is nearest each point (periodic in x and y): the owner of the
    film a partly filled cement cell holds (:func:`md.acoustic_system`).

    Parameters as :func:`bond_partners`, ``points`` of shape (m, 3), m. Returns the grain
    index of each point, int64.
    """
    m = np.asarray(points).shape[0]
    return bond_partners(np.full(m, -1), points, positions, radii, box, k)


def film_thickness(owner, volume, radii) -> np.ndarray:
    r"""Mean thickness of the cement film each grain carries: the cement volume of the cells it
    owns (:func:`nearest_grain`) over its surface, :math:`t_g = V_g / 4\pi R_g^2`, m
    (thin-film limit of the shell volume :math:`4\pi R^2 t (1 + t/R + t^2/3R^2)`).

    Parameters
    ----------
    owner : ndarray of int, shape (m,)
        Grain of each cement cell.
    volume : ndarray, shape (m,)
        Cement volume of each cell (fill times :math:`c_w^3`), m³.
    radii : ndarray, shape (n,)
        Grain radii, m.
    """
    r = np.asarray(radii, dtype=float)
    return np.bincount(np.asarray(owner, dtype=np.int64), np.asarray(volume, dtype=float),
                       r.size) / (4.0 * np.pi * r**2)


def pair_index(table, query, n) -> np.ndarray:
    """Row of each unordered grain pair of ``query`` in ``table`` (both int arrays of shape
    (m, 2), grain indices below ``n``; the order within a pair does not matter), −1 where
    ``table`` lacks it; of repeated rows of ``table``, the first."""
    table = np.sort(np.asarray(table, dtype=np.int64).reshape(-1, 2), axis=1)
    query = np.sort(np.asarray(query, dtype=np.int64).reshape(-1, 2), axis=1)
    out = np.full(query.shape[0], -1, np.int64)
    if table.shape[0] == 0 or query.shape[0] == 0:
        return out
    keys = table[:, 0] * n + table[:, 1]
    order = np.argsort(keys, kind="stable")
    keys = keys[order]
    want = query[:, 0] * n + query[:, 1]
    pos = np.minimum(np.searchsorted(keys, want), keys.size - 1)
    hit = (query[:, 0] >= 0) & (keys[pos] == want)
    out[hit] = order[pos[hit]]
    return out


def film_bridges(positions, radii, box, thickness, material, cement, hertz_pairs=None,
                 hertz_radius=None, covered_pairs=None, covered_area=None):
    r"""Bonds of the cement bridges that two grains' films make where they meet.

    Two grains of radii :math:`R_i, R_j` whose surfaces are :math:`h_0` apart on the line of
    centres (:math:`h_0 < 0` where they overlap), each coated by a film of thickness
    :math:`t_i, t_j`, are joined by cement wherever the gap between them is under
    :math:`T = t_i + t_j`. With the sphere profile of :mod:`md.bond_stiffness` (gap
    :math:`h + 2(\bar R - \sqrt{\bar R^2 - \rho^2})` at distance :math:`\rho` from the axis,
    :math:`\bar R = 2R_iR_j/(R_i + R_j)`), the bridge is the disc

    .. math:: a_b^2 = \bar R^2 - \left(\bar R - \frac{T - h_0}{2}\right)^2
              \quad (h_0 \ge 0), \qquad
              a_b^2 = a_H^2 + \bar R^2 - \left(\bar R - \frac T2\right)^2 \quad (h_0 < 0),

    the second around a Hertzian contact of radius :math:`a_H` (flattened: the film adds the
    annulus a touching pair would bridge). For equal touching grains coated by a film of
    thickness :math:`t` (:math:`T = 2t`), :math:`a_b^2/R^2 = 2t/R - t^2/R^2`: to first order
    the contact-cement radius of the uniform-coating scheme of Dvorkin & Nur (1996, eq. 6,
    :math:`\alpha = [2S\phi_0/3(1-\phi_0)]^{1/2}` with :math:`t/R = S\phi_0/3(1-\phi_0)`).
    Its stiffness is the cement bond of
    :func:`md.bond_stiffness.bond_stiffness` (thin cement layer of that profile in series with
    both grains as half-spaces; the welded contact of radius :math:`a_b` for rigid cement,
    Dvorkin et al. 1994's layer for rigid grains) at the disc radius and axial gap
    :math:`\max(h_0, 0)`; for an overlapping pair the Hertzian bond is already in the system,
    and the bridge adds ``bond(a_b) - bond(a_H)`` (both at zero gap, never below zero), so the
    pair's stiffness is continuous as the film vanishes.

    Parameters
    ----------
    positions : ndarray, shape (n, 3)
        Grain centres, m.
    radii : ndarray, shape (n,)
        m.
    box : md.Box
    thickness : ndarray, shape (n,)
        Film thickness of each grain (:func:`film_thickness`), m, ``>= 0``.
    material : md.GrainMaterial
    cement : md.CementMaterial
    hertz_pairs : ndarray of int, shape (p, 2), optional
        Grain pairs with a Hertzian bond, and ``hertz_radius`` their contact radii (m).
    covered_pairs : ndarray of int, shape (q, 2), optional
        Pairs whose bridge full cells of the lattice resolve in part, and ``covered_area``
        (shape (q,), m²; a pair may repeat, its areas add) the area they resolve.
        The bridge keeps the part of its disc (the annulus outside a Hertzian contact) the
        cells do not cover: its stiffness is scaled by
        :math:`\max(0, 1 - A_{cells}/\pi(a_b^2 - a_H^2))`, so that the bridge hands over to
        the lattice cell by cell as a coating thickens past a cell.

    Returns
    -------
    i, j : ndarray of int64
        Grains of each bridge.
    normal : ndarray, shape (b, 3)
        Unit vectors from ``i`` to ``j``.
    kn, kt : ndarray, shape (b,)
        N/m.
    arm_i, arm_j : ndarray, shape (b,)
        Distances from the centres to the bridge's plane (the radical plane), m.
    """
    from .bond_stiffness import bond_stiffness
    from .neighbors import build_neighbors
    from .space import minimum_image

    x = np.asarray(positions, dtype=float)
    r = np.asarray(radii, dtype=float)
    t = np.asarray(thickness, dtype=float)
    empty = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros(0),
             np.zeros(0), np.zeros(0), np.zeros(0))
    if t.shape != r.shape or not np.all(np.isfinite(t) & (t >= 0)):
        raise ValueError("thickness must be finite, >= 0 m, one per grain")
    if x.shape[0] < 2 or not np.any(t > 0):
        return empty
    skin = 2.0 * float(t.max())
    p = build_neighbors(x, r, box, skin).pairs.astype(np.int64)
    p = np.sort(p, axis=1)
    d = minimum_image(x[p[:, 1]] - x[p[:, 0]], box)
    dist = np.linalg.norm(d, axis=1)
    ri, rj = r[p[:, 0]], r[p[:, 1]]
    h0 = dist - ri - rj
    T = t[p[:, 0]] + t[p[:, 1]]
    n = x.shape[0]
    a_h = np.zeros(p.shape[0])
    if hertz_pairs is not None and len(hertz_pairs):
        at = pair_index(hertz_pairs, p, n)
        found = at >= 0
        a_h[found] = np.asarray(hertz_radius, dtype=float)[at[found]]
    covered = np.zeros(p.shape[0])
    if covered_pairs is not None and len(covered_pairs):
        at = pair_index(p, covered_pairs, n)
        hit = at >= 0
        np.add.at(covered, at[hit], np.asarray(covered_area, dtype=float)[hit])
    keep = (T > h0) & (T > 0)
    p, d, dist, h0, T, a_h, ri, rj, covered = (
        v[keep] for v in (p, d, dist, h0, T, a_h, ri, rj, covered))
    if p.shape[0] == 0:
        return empty
    Rb = 2.0 * ri * rj / (ri + rj)
    touching = h0 < 0
    half = np.where(touching, 0.5 * T, 0.5 * (T - h0))
    half = np.minimum(half, Rb)
    a_b = np.sqrt(np.where(touching, a_h**2, 0.0) + Rb**2 - (Rb - half) ** 2)
    a_b = np.minimum(a_b, Rb)
    gap = np.maximum(h0, 0.0)
    Kc = cement.p_modulus - 4.0 / 3.0 * cement.shear_modulus
    moduli = (material.bulk_modulus, material.shear_modulus, Kc, cement.shear_modulus)
    bond = bond_stiffness(Rb, a_b / Rb, gap / (2.0 * Rb), *moduli)
    kn, kt = bond.normal, bond.shear
    h = touching & (a_h > 0)
    if np.any(h):
        hertz = bond_stiffness(Rb[h], np.minimum(a_h[h] / Rb[h], 1.0), 0.0, *moduli)
        kn[h] = np.maximum(kn[h] - hertz.normal, 0.0)
        kt[h] = np.maximum(kt[h] - hertz.shear, 0.0)
    share = np.clip(1.0 - covered / (np.pi * (a_b**2 - np.where(touching, a_h**2, 0.0))),
                    0.0, 1.0)
    kn, kt = kn * share, kt * share
    live = share > 0
    arm_i = (dist**2 + ri**2 - rj**2) / (2.0 * dist)
    return (p[live, 0], p[live, 1], (d / dist[:, None])[live], kn[live], kt[live], arm_i[live],
            (dist - arm_i)[live])


def interface_area(normals, cell_width) -> np.ndarray:
    """Grain-surface area a cemented cell joined to a grain stands for (patch rule),
    :math:`c_w^2/\\max(\\|\\hat n\\|_\\infty, \\|\\hat n\\|_1/2)`.

    Parameters
    ----------
    normals : array_like, shape (m, 3)
        Unit vectors from the grain centre to the cell centre.
    cell_width : float
        :math:`c_w`, m.

    Returns
    -------
    ndarray, shape (m,)
        m².
    """
    n = np.asarray(normals, dtype=float)
    a = np.abs(n)
    return float(cell_width) ** 2 / np.maximum(a.max(axis=-1), 0.5 * a.sum(axis=-1))


def patch_radius(normals, area, label, radius) -> np.ndarray:
    """Outer radius of each patch, seen along its mean normal (module docstring).

    Parameters
    ----------
    normals : ndarray, shape (m, 3)
        Unit vectors from the grain centre to the cells.
    area : ndarray, shape (m,)
        Interface area of each cell (:func:`interface_area`), m².
    label : ndarray of int, shape (m,)
        Patch of each cell, ``0 .. n_patches - 1``.
    radius : ndarray, shape (n_patches,)
        Radius of each patch's grain, m.

    Returns
    -------
    ndarray, shape (n_patches,)
        m, at most ``radius``.
    """
    n_p = int(radius.shape[0])
    axis = np.stack([np.bincount(label, area * normals[:, k], n_p) for k in range(3)], axis=-1)
    norm = np.linalg.norm(axis, axis=1)
    axis = axis / np.where(norm > 0, norm, 1.0)[:, None]
    cos = np.sum(normals * axis[label], axis=1)
    w = area * np.maximum(cos, 0.0)                     # projected area of each cell
    R = radius[label]
    projected = np.bincount(label, w, n_p)
    rho2 = np.bincount(label, w * R**2 * (1.0 - cos**2), n_p) / np.where(projected > 0,
                                                                         projected, 1.0)
    a2 = rho2 + projected / (2.0 * np.pi)
    return np.where(projected > 0, np.minimum(np.sqrt(a2), radius), radius)


def interface_patches(bond_grain, bond_cell, table, first, bond_partner=None) -> np.ndarray:
    """Patch label of every grain–cement bond (see the module docstring).

    Parameters
    ----------
    bond_grain, bond_cell : ndarray of int, shape (m,)
        Grain and cement particle (index among the cement particles) of each bond, sorted by
        ``bond_cell``.
    bond_partner : ndarray of int, shape (m,), optional
        The neighbouring grain each bond's cell faces (:func:`bond_partners`); given, patches
        are split by it too (the ``"facet"`` rule).
    table : ndarray of int32, shape (n_cement, 9)
        Lattice neighbour table (:class:`md.AcousticSystem`), entries ``first + q`` or −1.
    first : int
        Particle index of the first cement particle.

    Returns
    -------
    ndarray of int64, shape (m,)
        Patch numbers ``0 .. n_patches - 1``.
    """
    from ._kernels_acoustic import interface_patches as kernel

    cell = np.asarray(bond_cell, dtype=np.int64)
    if cell.size and np.any(np.diff(cell) < 0):
        raise ValueError("bond_cell must be sorted (bonds grouped by cement particle)")
    start = np.searchsorted(cell, np.arange(table.shape[0] + 1)).astype(np.int64)
    group = np.asarray(bond_grain, dtype=np.int64)
    if bond_partner is not None:
        partner = np.asarray(bond_partner, dtype=np.int64)
        group = group * (int(partner.max(initial=0)) + 2) + (partner + 1)
    label = np.empty(cell.size, np.int64)
    kernel(group, start, table, int(first), label)
    return label


#: Smallest facet punch around a contact, as a fraction of the facet's outer radius (keeps the
#: cells of a facet no wider than its contact, an artefact of a coarse lattice, joined).
MIN_ANNULUS = 0.05


def _facet_contact_radius(label, n_patches, patch_grain, bond_partner, pairs, radius, n_grains):
    """Radius of the contact between each facet's grain and the grain it faces (0 if none)."""
    partner = np.full(n_patches, -1, np.int64)
    partner[label] = np.asarray(bond_partner, dtype=np.int64)
    at = pair_index(pairs, np.stack([np.asarray(patch_grain, np.int64), partner], axis=1),
                    n_grains)
    hit = (partner >= 0) & (at >= 0)
    return np.where(hit, np.asarray(radius, dtype=float)[np.maximum(at, 0)], 0.0)


def interface_stiffness(bond_grain, bond_cell, bond_normal, radii, table, first, cell_width,
                        material, cement, interface="patch", bond_partner=None,
                        paper_normal_factor=2.0, contact_pairs=None, contact_radius=None,
                        column=None):
    """Normal and tangential stiffness of the grain–cement bonds.

    Parameters
    ----------
    bond_grain, bond_cell : ndarray of int, shape (m,)
        Grain and cement particle (among the cement particles) of each bond, sorted by cell.
    bond_normal : ndarray, shape (m, 3)
        Unit vectors from the grain centre to the cell centre.
    radii : ndarray, shape (n_grains,)
        Grain radii, m.
    table : ndarray of int32, shape (n_cement, 9)
        Lattice neighbour table; ``first`` the index of the first cement particle.
    cell_width : float
        :math:`c_w`, m.
    material : md.GrainMaterial
    cement : md.CementMaterial
    interface : {"patch", "paper", "facet"}
        The rule (module docstring).
    bond_partner : ndarray of int, shape (m,), optional
        The neighbouring grain each bond's cell faces (:func:`bond_partners`); needed by
        ``"facet"``.
    paper_normal_factor : float
        ``"paper"`` only: :math:`k_n = f E^* (c_w/2)` with this :math:`f`, 2 for the tangent of
        the Hertz force (default), 4/3 for the secant of the source's eq. 1
        (``normal_stiffness`` of :func:`md.acoustic_system`).
    contact_pairs : ndarray of int, shape (p, 2), optional
        ``"facet"`` only: grain pairs in contact (the grain–grain bonds of the system), and
        ``contact_radius`` (shape (p,), m) the radius of each contact. A facet of grain
        :math:`i` facing a grain :math:`j` it touches encloses their contact disc, whose punch
        on :math:`i`'s half-space the contact bond already carries: the facet's punch is then
        the annulus outside it, :math:`2E_g^*(a_p - a_c)` and :math:`8G_g(a_p - a_c)/(2-\\nu_g)`
        (the stiffness of a rigid flat punch is linear in its radius, so the disc and the
        annulus moving together are the punch of radius :math:`a_p`; Johnson 1985, Sect. 3.8;
        the rule :func:`film_bridges` applies to a bridge around a Hertzian contact), at least
        :data:`MIN_ANNULUS` :math:`a_p`. Without it the two punches are counted in parallel on
        the same surface, and a fully cemented sample is stiffer than the Hashin–Shtrikman
        upper bound of its grains and cement.
    column : ndarray, shape (m,), optional
        ``"patch"`` and ``"facet"`` only: the length of each bond's cement column, m,
        ``> 0``; default :math:`c_w/2` for every bond (the column of half a cell). The
        cement's part of the bond is :math:`M_cA_i/L` and :math:`G_cA_i/L` with this
        :math:`L` (a layer of thickness L bonded over the area :math:`A_i`).

    Returns
    -------
    kn, kt : ndarray, shape (m,)
        N/m.
    """
    if interface not in INTERFACES:
        raise ValueError(f"interface must be one of {INTERFACES}; got {interface!r}")
    nu_g, nu_c = material.poisson_ratio, cement.poisson_ratio
    m = len(bond_grain)
    cw = float(cell_width)
    if interface == "paper":
        E_star = 1.0 / ((1 - nu_g**2) / material.young_modulus
                        + (1 - nu_c**2) / cement.young_modulus)
        G_star = 1.0 / ((2 - nu_g) / material.shear_modulus + (2 - nu_c) / cement.shear_modulus)
        return (np.full(m, paper_normal_factor * E_star * 0.5 * cw),
                np.full(m, 8.0 * G_star * 0.5 * cw))
    if interface == "facet" and bond_partner is None:
        raise ValueError("interface 'facet' needs bond_partner (md.interface.bond_partners)")
    area = interface_area(bond_normal, cw)
    label = interface_patches(bond_grain, bond_cell, table, first,
                              bond_partner if interface == "facet" else None)
    n_patches = int(label.max()) + 1 if m else 0
    patch_area = np.bincount(label, area, n_patches)
    patch_grain = np.zeros(n_patches, np.int64)
    patch_grain[label] = bond_grain
    a_p = patch_radius(np.asarray(bond_normal, dtype=float), area, label,
                       np.asarray(radii, dtype=float)[patch_grain])
    if interface == "facet" and contact_pairs is not None and len(contact_pairs):
        a_c = _facet_contact_radius(label, n_patches, patch_grain, bond_partner,
                                    contact_pairs, contact_radius, len(radii))
        a_p = np.maximum(a_p - a_c, MIN_ANNULUS * a_p)
    share = area / patch_area[label]
    k_grain_n = 2.0 * a_p[label] * material.young_modulus / (1.0 - nu_g**2) * share
    k_grain_t = 8.0 * material.shear_modulus * a_p[label] / (2.0 - nu_g) * share
    if column is None:
        length = np.full(m, 0.5 * cw)
    else:
        length = np.asarray(column, dtype=float)
        if length.shape != (m,) or not np.all(np.isfinite(length) & (length > 0)):
            raise ValueError(f"column must be {m} finite lengths > 0 m, one per bond")
    k_cement_n = cement.p_modulus * area / length
    k_cement_t = cement.shear_modulus * area / length
    return (1.0 / (1.0 / k_grain_n + 1.0 / k_cement_n),
            1.0 / (1.0 / k_grain_t + 1.0 / k_cement_t))
