r"""Observables of a grain pack from its contact forces: the static contact force of each pair,
the contact stress (virial) of a slab, the force on a set of grains, and the Hertz overlap
expected at a stress. SI units (m, N, Pa).
"""

from __future__ import annotations

import numpy as np

__all__ = ["pair_geometry", "contact_forces", "contact_stress", "group_force", "segment_fraction",
           "expected_overlap", "end_slabs", "core_window", "porosity", "coordination_number",
           "pack_stress"]


def pair_geometry(x, r, pairs, box):
    """Branch vectors ``d`` (M, 3) from ``i`` to ``j`` (minimum image in x and y), their lengths
    (M,) and the overlaps ``r_i + r_j - |d|`` (M,) of a pair list ``(i, j)``; SI units."""
    pairs = np.asarray(pairs).reshape(-1, 2)
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d[:, 0] -= box.lx * np.round(d[:, 0] / box.lx)
    d[:, 1] -= box.ly * np.round(d[:, 1] / box.ly)
    dist = np.linalg.norm(d, axis=1)
    return d, dist, r[pairs[:, 0]] + r[pairs[:, 1]] - dist


def contact_forces(x, r, pairs, box, material, history=None):
    r"""Static contact force of every pair of a pair list (García & Medina, eqs. 1–3 at rest).

    The elastic Hertz force :math:`\tfrac43 E_f\sqrt{R_f}\,\xi^{3/2}` along the branch vector
    and, with ``history``, the tangential Mindlin spring :math:`-\kappa_s\boldsymbol\zeta`
    (:math:`\kappa_s = 8 G_f\sqrt{R_f\xi}`, :math:`\boldsymbol\zeta` projected on the tangent
    plane) capped at :math:`\mu F_n` — the force the MD kernel applies
    (``md._kernels_contact.pair_force``) with the velocities set to zero.

    Parameters
    ----------
    x : ndarray, shape (N, 3)
        Positions, m.
    r : ndarray, shape (N,)
        Radii, m.
    pairs : ndarray, shape (M, 2), int
        Candidate contacts ``(i, j)``.
    box : md.space.Box
        Periodic in x and y (minimum image).
    material : md.contact.GrainMaterial
    history : ndarray, shape (M, 3), optional
        Tangential spring elongations of the pairs, m; without it the forces are normal only.

    Returns
    -------
    force : ndarray, shape (M, 3)
        Force on ``j`` (minus on ``i``), N; zero for pairs not in contact.
    branch : ndarray, shape (M, 3)
        Branch vector from ``i`` to ``j`` (minimum image), m.
    """
    pairs = np.asarray(pairs).reshape(-1, 2)
    d, dist, xi = pair_geometry(x, r, pairs, box)
    xi = np.maximum(xi, 0.0)
    ri, rj = r[pairs[:, 0]], r[pairs[:, 1]]
    R_f = ri * rj / (ri + rj)
    n = d / np.where(dist > 0, dist, 1.0)[:, None]
    fn = 4.0 / 3.0 * material.E_f * np.sqrt(R_f) * xi**1.5
    force = fn[:, None] * n
    if history is not None:
        zeta = np.asarray(history, dtype=float).reshape(-1, 3)
        zeta = zeta - np.sum(zeta * n, axis=1)[:, None] * n
        ft = -8.0 * material.G_f * np.sqrt(R_f * xi)[:, None] * zeta
        norm = np.linalg.norm(ft, axis=1)
        cap = material.friction * fn
        scale = np.where(norm > cap, cap / np.where(norm > 0, norm, 1.0), 1.0)
        force += ft * scale[:, None]
    return force, d


def segment_fraction(za, dz, z_lo, z_hi):
    """Fraction of the segments from heights ``za`` to ``za + dz`` inside ``[z_lo, z_hi]``;
    a horizontal segment counts 1 inside, 0 outside, one half on a bounding plane.

    This is the weight of a contact in the volume average of the Irving–Kirkwood stress over
    the slab: with it the virial of a slab equals the mean over its horizontal planes of the
    force crossing each plane per area, exactly."""
    za, dz = np.asarray(za, dtype=float), np.asarray(dz, dtype=float)
    zb = za + dz
    lo, hi = np.minimum(za, zb), np.maximum(za, zb)
    span = hi - lo
    inside = np.clip(np.minimum(hi, z_hi) - np.maximum(lo, z_lo), 0.0, None)
    tol = 1e-9 * max(float(np.abs(dz).max()) if dz.size else 0.0, abs(z_hi - z_lo))
    flat = span <= tol
    on_plane = (np.abs(lo - z_lo) <= tol) | (np.abs(lo - z_hi) <= tol)
    flat_weight = np.where(on_plane, 0.5, ((lo > z_lo) & (lo < z_hi)).astype(float))
    return np.where(flat, flat_weight, inside / np.where(flat, 1.0, span))


def contact_stress(x, r, pairs, box, material, *, z_range=None, history=None):
    r"""Static contact stress tensor of a horizontal slab,
    :math:`\sigma_{ab} = \frac1V \sum_c w_c\, f_{c,a}\, l_{c,b}` (compression positive).

    :math:`\mathbf f_c` is the static force on ``j`` (:func:`contact_forces`: Hertz normal force
    and, with ``history``, the tangential spring), :math:`\mathbf l_c` the branch vector from
    ``i`` to ``j`` (minimum image in x and y), :math:`w_c` the fraction of the branch inside
    ``z_range`` (:func:`segment_fraction`) and ``V`` the box area times the slab height. With
    these weights :math:`\sigma_{zz}` is the mean over the slab's horizontal planes of the
    vertical force crossing a plane per area; for a pack at rest without body forces it equals
    the force on either frozen end slab per area (tested to 1 %).

    Parameters
    ----------
    x, r, pairs, box, material, history
        As in :func:`contact_forces`.
    z_range : (float, float), optional
        Bottom and top of the slab, m; default the span of the grain centres.

    Returns
    -------
    ndarray, shape (3, 3)
        Pa. ``sigma[2, 2]`` is the vertical stress :math:`\sigma_{zz}`,
        ``np.trace(sigma) / 3`` the mean stress.
    """
    pairs = np.asarray(pairs).reshape(-1, 2)
    z0, z1 = (float(x[:, 2].min()), float(x[:, 2].max())) if z_range is None \
        else map(float, z_range)
    if not z1 > z0:
        raise ValueError(f"z_range must have top > bottom; got ({z0}, {z1})")
    force, branch = contact_forces(x, r, pairs, box, material, history)
    weight = segment_fraction(x[pairs[:, 0], 2], branch[:, 2], z0, z1)
    volume = box.lx * box.ly * (z1 - z0)
    return np.einsum("c,ci,cj->ij", weight, force, branch) / volume


def group_force(x, r, pairs, box, material, group, history=None):
    """Total contact force on the grains of ``group`` from the grains outside it, N, shape (3,).

    Parameters
    ----------
    x, r, pairs, box, material, history
        As in :func:`contact_forces`.
    group : ndarray, shape (N,), bool
        The grains (e.g. a frozen end slab).
    """
    pairs = np.asarray(pairs).reshape(-1, 2)
    force, _ = contact_forces(x, r, pairs, box, material, history)
    gi, gj = group[pairs[:, 0]], group[pairs[:, 1]]
    return force[gj & ~gi].sum(axis=0) - force[gi & ~gj].sum(axis=0)


def expected_overlap(stress, radius, porosity, coordination, material):
    r"""Hertz overlap of the mean contact force of a pack under the mean stress ``stress``.

    For identical spheres the virial gives the mean normal force
    :math:`\bar F = 4\pi R^2 p / (Z (1-\phi))` (from :math:`p = \frac{1}{3V}\sum_c F_c\,2R`,
    Z contacts per grain) and Hertz (García & Medina, eq. 1; :math:`R_f = R/2`) the overlap
    :math:`\xi = (3\bar F / (4 E_f\sqrt{R/2}))^{2/3}`.

    Parameters
    ----------
    stress : float or ndarray
        Mean stress, Pa, ``>= 0``.
    radius : float
        Grain radius, m.
    porosity : float
        In (0, 1).
    coordination : float
        Contacts per grain, ``> 0``.
    material : md.contact.GrainMaterial

    Returns
    -------
    float or ndarray
        Overlap, m.
    """
    stress = np.asarray(stress, dtype=float)
    if not np.all(stress >= 0):
        raise ValueError("stress must be >= 0 Pa (and not NaN)")
    if not 0 < porosity < 1 or not coordination > 0 or not radius > 0:
        raise ValueError("need radius > 0, porosity in (0, 1) and coordination > 0")
    force = 4.0 * np.pi * radius**2 * stress / (coordination * (1.0 - porosity))
    return (3.0 * force / (4.0 * material.E_f * np.sqrt(0.5 * radius))) ** (2.0 / 3.0)


def end_slabs(z, r, slab):
    """The frozen end slabs of a pack (García & Medina, Sect. III A): grains whose centres lie
    within ``slab`` largest diameters of the lowest and of the highest centre.

    Parameters
    ----------
    z : ndarray, shape (N,)
        Heights of the grain centres, m.
    r : ndarray, shape (N,)
        Radii, m.
    slab : float
        Thickness in largest diameters, ``> 0``.

    Returns
    -------
    ndarray, shape (N,), bool
    """
    if not slab > 0:
        raise ValueError(f"slab must be > 0 largest diameters; got {slab}")
    d = 2.0 * float(r.max())
    return (z < z.min() + slab * d) | (z > z.max() - slab * d)


def slab_core(z, r, fixed):
    """The core window between frozen end slabs, ``(bottom, top)`` in m: from the highest
    centre of the lower slab plus the largest radius to the lowest centre of the upper slab
    minus the largest radius, so that no slab grain reaches into it."""
    centre = 0.5 * (z.min() + z.max())
    low, high = fixed & (z < centre), fixed & (z > centre)
    if not low.any() or not high.any():
        raise ValueError("slab: both end slabs must hold grains")
    bottom = float(z[low].max() + r.max())
    top = float(z[high].min() - r.max())
    if not top > bottom:
        raise ValueError("slab: the end slabs leave no core between them (the pack is too "
                         "low for slabs this thick)")
    return bottom, top


def core_window(pack, slab=1.0):
    """Core window ``(bottom, top)`` (m) in which a pack's porosity and stress are measured.

    A pack that records its window (``metadata["core_window_m"]``: compacted packs, the window
    between their frozen slabs; settled packs, the window between the slabs a compaction would
    freeze) gives that one; otherwise the window between end slabs ``slab`` largest diameters
    thick (:func:`end_slabs`, :func:`slab_core`)."""
    if "core_window_m" in pack.metadata:
        bottom, top = pack.metadata["core_window_m"]
        return float(bottom), float(top)
    z, r = pack.positions[:, 2], pack.radii
    return slab_core(z, r, end_slabs(z, r, slab))


def porosity(pack, *, bottom=None, top=None) -> float:
    """Porosity of a pack in the slab from ``bottom`` to ``top`` (m), by default its core
    window (:func:`core_window`): one minus the volume of the *union* of its grains in the slab
    over the slab's volume (:func:`md.reconstruct.union_solid_volume`: spherical caps of grains
    cut by the slab's planes counted exactly, the lenses where grains overlap counted once —
    a pack compacted by :func:`md.reconstruct.reconstruct` overlaps by a tenth of a radius and
    more; the Hertz overlaps of elastic grains (ξ/R up to 0.06 at 60 MPa) raise it by up to
    4e-4 over the sum of the spheres)."""
    from .reconstruct import union_solid_volume

    if bottom is None or top is None:
        lo, hi = core_window(pack)
        bottom = lo if bottom is None else bottom
        top = hi if top is None else top
    z0, z1 = float(bottom), float(top)
    if not z1 > z0:
        raise ValueError(f"bottom, top: the slab for the porosity is empty ({z0} to {z1} m)")
    solid = union_solid_volume(pack.positions, pack.radii, pack.box, z0, z1)
    return float(1.0 - solid / (pack.box.lx * pack.box.ly * (z1 - z0)))


def coordination_number(pack, *, tolerance=0.0, exclude_rattlers=False) -> float:
    """Mean number of contacts per grain (overlap > ``tolerance`` m); grain–floor contacts are
    not counted. With ``exclude_rattlers`` grains with fewer than two contacts are left out."""
    from .neighbors import build_neighbors

    nl = build_neighbors(pack.positions, pack.radii, pack.box, 0.0)
    p = nl.pairs
    xi = pair_geometry(pack.positions, pack.radii, p, pack.box)[2]
    p = p[xi > tolerance]
    counts = np.bincount(p.ravel(), minlength=pack.n_grains)
    if exclude_rattlers:
        counts = counts[counts >= 2]
    return float(counts.mean()) if counts.size else 0.0


def pack_stress(pack):
    """Contact stress tensor (Pa, shape (3, 3)) of a pack in its core window
    (:func:`core_window`), normal and tangential forces (:func:`contact_stress` with the pack's
    tangential histories)."""
    return contact_stress(pack.positions, pack.radii, pack.pairs, pack.box, pack.material,
                          z_range=core_window(pack), history=pack.history)
