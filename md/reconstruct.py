r"""Compaction past Hertzian contact by process-based reconstruction, and the geometry of
overlapping (truncated) grains.

Elastic spheres stop compacting at a porosity of 0.36–0.38; a buried sandstone goes on by
pressure solution at the grain contacts. Process-based reconstruction models that as Bryant,
King & Mellor (1993) and Øren & Bakke (2002, Sect. 2.2) do: the grain centres are moved
together along the vertical, :math:`z' = z_b + (z - z_b)(1 - \lambda)` (the compaction factor
:math:`\lambda` of Øren & Bakke), and the volume where grains then overlap is removed as
pressure-solution volume — the grains become spheres truncated by the planes of their contact
circles, and the solid is the *union* of the spheres. :func:`reconstruct` finds the
:math:`\lambda` that gives a target intergranular volume; :func:`union_porosity` measures the
porosity of overlapping grains (union volume, not the sum of the spheres).

Each contact's overlap :math:`\xi` is then split into the dissolved part :math:`\xi_p`
(geometry: the flattened contact) and the elastic part :math:`\xi_e = \xi - \xi_p` that carries
the stress; :attr:`md.Pack.overlap_dissolved` stores :math:`\xi_p` per pair. The contact radius
of a flattened, loaded contact is Digby's (1981): :math:`a^2 = b^2 + R_f \xi_e`, :math:`b` the
radius of the flat (:func:`contact_circle_radius` at overlap :math:`\xi_p`) and
:math:`\sqrt{R_f\xi_e}` the Hertz radius of the elastic part (:func:`flattened_contact_radius`).

References
----------
Bryant, S., King, P. R. & Mellor, D. W. (1993). Network model evaluation of permeability and
spatial correlation in a real random sphere packing. Transport in Porous Media 11, 53–70.
Øren, P.-E. & Bakke, S. (2002). Process based reconstruction of sandstones and prediction of
transport properties. Transport in Porous Media 46, 311–343.
Digby, P. J. (1981). The effective elastic moduli of porous granular rocks. J. Appl. Mech. 48,
803–808; in Mavko, Mukerji & Dvorkin, The Rock Physics Handbook, 2nd ed. (2009), Sect. 5.4.
Weisstein, E. W. Sphere–Sphere Intersection. MathWorld (eqs. 8 and 16).
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["lens_volume", "contact_circle_radius", "flattened_contact_radius",
           "union_solid_volume", "union_porosity", "reconstruct", "attach_cement",
           "carried_cells"]


def _check_pair(r1, r2, d):
    r1, r2, d = (np.asarray(v, dtype=float) for v in (r1, r2, d))
    if not (np.all(r1 > 0) and np.all(r2 > 0)):
        raise ValueError("r1, r2 must be > 0 m")
    if not np.all(d > 0):
        raise ValueError("d (centre distance) must be > 0 m")
    return r1, r2, d


def lens_volume(r1, r2, d):
    r"""Volume common to two spheres of radii ``r1``, ``r2`` with centres ``d`` apart, m³.

    Weisstein, "Sphere–Sphere Intersection" (MathWorld), eq. 16:

    .. math:: V = \frac{\pi (r_1 + r_2 - d)^2 (d^2 + 2dr_2 - 3r_2^2 + 2dr_1 + 6r_1r_2
              - 3r_1^2)}{12 d}

    valid for :math:`|r_1 - r_2| \le d \le r_1 + r_2`; 0 for ``d >= r1 + r2`` and the smaller
    sphere's volume for ``d <= |r1 - r2|`` (one inside the other).

    Parameters
    ----------
    r1, r2 : array_like
        Radii, m, ``> 0``.
    d : array_like
        Centre distance, m, ``> 0``.
    """
    r1, r2, d = _check_pair(r1, r2, d)
    v = np.pi * (r1 + r2 - d) ** 2 * (d * d + 2 * d * r2 - 3 * r2 * r2 + 2 * d * r1
                                       + 6 * r1 * r2 - 3 * r1 * r1) / (12.0 * d)
    inside = 4.0 / 3.0 * np.pi * np.minimum(r1, r2) ** 3
    return np.where(d >= r1 + r2, 0.0, np.where(d <= np.abs(r1 - r2), inside, v))


def contact_circle_radius(r1, r2, d):
    r"""Radius of the circle where two spheres intersect (the flat face of two grains truncated
    by pressure solution), m; 0 where they do not overlap.

    Weisstein, "Sphere–Sphere Intersection" (MathWorld), eq. 8:
    :math:`a = \frac{1}{2d}\sqrt{4d^2r_1^2 - (d^2 - r_2^2 + r_1^2)^2}`; for a small overlap
    :math:`\xi = r_1 + r_2 - d`, :math:`a^2 \to 2R_f\xi` (:math:`R_f = r_1r_2/(r_1+r_2)`), twice
    the Hertz contact area of the same overlap.
    """
    r1, r2, d = _check_pair(r1, r2, d)
    arm = (d * d + r1 * r1 - r2 * r2) / (2.0 * d)
    a2 = np.where(d < r1 + r2, r1 * r1 - arm * arm, 0.0)
    return np.sqrt(np.maximum(a2, 0.0))


def flattened_contact_radius(r1, r2, overlap_dissolved, overlap_elastic):
    r"""Contact radius of two grains flattened by pressure solution and loaded elastically, m.

    Digby (1981): a contact that is flat over a circle of radius :math:`b` and then loaded
    normally has the contact radius :math:`a` with :math:`a^2 = b^2 + (Rd)^2`, :math:`Rd` the
    radius the load alone would give (Rock Physics Handbook, 2nd ed., Sect. 5.4: "b/R =
    sqrt(d² + (a/R)²)" in its notation, bonded radius a, contact radius b). Here :math:`b` is
    the intersection circle of the spheres at the dissolved overlap (:func:`contact_circle_radius`
    at :math:`d = r_1 + r_2 - \xi_p`) and the elastic part is Hertz's,
    :math:`(Rd)^2 = R_f\xi_e` (García & Medina eq. 1's contact radius):

    .. math:: a = \sqrt{b(\xi_p)^2 + R_f\,\xi_e}

    With :math:`\xi_p = 0` this is the Hertz radius :math:`\sqrt{R_f\xi}`.

    Parameters
    ----------
    r1, r2 : array_like
        Radii, m, ``> 0``.
    overlap_dissolved, overlap_elastic : array_like
        :math:`\xi_p` in ``[0, r1 + r2)`` and :math:`\xi_e \ge 0`, m.
    """
    r1, r2 = (np.asarray(v, dtype=float) for v in (r1, r2))
    xp, xe = (np.asarray(v, dtype=float) for v in (overlap_dissolved, overlap_elastic))
    if not np.all((xp >= 0) & (xp < r1 + r2)):
        raise ValueError("overlap_dissolved must lie in [0, r1 + r2) m")
    if not np.all(xe >= 0):
        raise ValueError("overlap_elastic must be >= 0 m")
    b = contact_circle_radius(r1, r2, r1 + r2 - xp)
    return np.sqrt(b * b + r1 * r2 / (r1 + r2) * xe)


def _overlapping_pairs(x, r, box):
    """Pairs (i < j) of overlapping spheres, their branch vectors (minimum image in x, y) and
    distances."""
    from .neighbors import build_neighbors

    p = build_neighbors(x, r, box, 0.0).pairs.astype(np.int64).reshape(-1, 2)
    d = x[p[:, 1]] - x[p[:, 0]]
    d[:, 0] -= box.lx * np.round(d[:, 0] / box.lx)
    d[:, 1] -= box.ly * np.round(d[:, 1] / box.ly)
    dist = np.linalg.norm(d, axis=1)
    reach = r[p[:, 0]] + r[p[:, 1]]
    keep = dist < reach * (1.0 - 1e-12)         # touching to rounding: no overlap
    return p[keep], d[keep], dist[keep]


def _sphere_in_slab(z, r, z0, z1):
    """Volume of each sphere between the planes z0 < z1 (spherical caps counted exactly)."""
    def below(h):
        s = np.clip(h - (z - r), 0.0, 2.0 * r)
        return np.pi * s * s * (3.0 * r - s) / 3.0
    return below(z1) - below(z0)


def union_solid_volume(x, r, box, bottom, top, *, samples=12):
    r"""Volume of the union of spheres (periodic in x and y) between heights ``bottom`` and
    ``top``, m³.

    Inclusion–exclusion by lenses: :math:`V = \sum_i V_i - E`, :math:`V_i` each sphere's volume
    in the slab (caps exact) and :math:`E = \int (k - 1)_+\,dV` the excess of the points
    covered by :math:`k \ge 2` spheres. A point covered by :math:`k` spheres lies in
    :math:`\binom{k}{2}` lenses, so :math:`E = \sum_{\rm pairs}\int_{\rm lens} 2/k\,dV`: a lens
    that lies inside the slab and meets no third sphere contributes its closed-form volume
    (:func:`lens_volume`); the others (cut by a slab plane, or with a third sphere in them) its
    volume times the mean of :math:`2/k` (times the slab indicator) over a regular grid of
    ``samples`` points a side (``samples**3`` in all) in the lens's bounding cylinder.

    Parameters
    ----------
    x : ndarray, shape (N, 3)
        Centres, m.
    r : ndarray, shape (N,)
        Radii, m, ``> 0``.
    box : md.space.Box
    bottom, top : float
        The slab, m, ``top > bottom``.
    samples : int
        Grid points per axis of a lens that needs sampling, ``>= 4``.
    """
    x, r = np.asarray(x, dtype=float), np.asarray(r, dtype=float)
    z0, z1 = float(bottom), float(top)
    if not z1 > z0:
        raise ValueError(f"bottom, top: the slab is empty ({z0} to {z1} m)")
    if not int(samples) >= 4:
        raise ValueError(f"samples must be >= 4; got {samples}")
    solid = float(np.sum(_sphere_in_slab(x[:, 2], r, z0, z1)))
    p, d, dist = _overlapping_pairs(x, r, box)
    if p.size == 0:
        return solid
    ri, rj = r[p[:, 0]], r[p[:, 1]]
    lens = lens_volume(ri, rj, dist)
    # z-extent of each lens: within both spheres' z-ranges.
    zi = x[p[:, 0], 2]
    zj = zi + d[:, 2]
    lo = np.maximum(zi - ri, zj - rj)
    hi = np.minimum(zi + ri, zj + rj)
    outside = (hi <= z0) | (lo >= z1)
    inside = (lo >= z0) & (hi <= z1)
    # Third spheres: l overlapping both i and j.
    n = r.size
    neighbours = [set() for _ in range(n)]
    for a, b in p:
        neighbours[a].add(b)
        neighbours[b].add(a)
    third = [sorted(neighbours[a] & neighbours[b]) for a, b in p]
    simple = inside & np.array([not t for t in third])
    excess = float(np.sum(lens[simple]))
    s = int(samples)
    u = (np.arange(s) + 0.5) / s
    for c in np.flatnonzero(~simple & ~outside):
        a, b = p[c]
        n_hat = d[c] / dist[c]
        arm = (dist[c] ** 2 + ri[c] ** 2 - rj[c] ** 2) / (2 * dist[c])
        t_lo, t_hi = max(dist[c] - rj[c], -ri[c]), min(ri[c], dist[c] + rj[c])
        rad = float(contact_circle_radius(ri[c], rj[c], dist[c])) if \
            abs(ri[c] - rj[c]) < dist[c] else min(ri[c], rj[c])
        rad = max(rad, 1e-300)
        if arm < t_lo or arm > t_hi:        # the lens is wider than its circle (large overlap)
            rad = min(ri[c], rj[c])
        e1 = np.cross(n_hat, [1.0, 0.0, 0.0] if abs(n_hat[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(n_hat, e1)
        t = t_lo + (t_hi - t_lo) * u
        v1 = rad * (2 * u - 1)
        T, V1, V2 = np.meshgrid(t, v1, v1, indexing="ij")
        pts = x[a] + T.reshape(-1, 1) * n_hat + V1.reshape(-1, 1) * e1 + V2.reshape(-1, 1) * e2
        rel_i = pts - x[a]
        rel_j = rel_i - d[c]
        in_lens = (np.einsum("ij,ij->i", rel_i, rel_i) < ri[c] ** 2) & \
            (np.einsum("ij,ij->i", rel_j, rel_j) < rj[c] ** 2)
        if not in_lens.any():
            continue
        q = pts[in_lens]
        k = np.full(q.shape[0], 2.0)
        for l in third[c]:
            dl = q - x[l]
            dl[:, 0] -= box.lx * np.round(dl[:, 0] / box.lx)
            dl[:, 1] -= box.ly * np.round(dl[:, 1] / box.ly)
            k += np.einsum("ij,ij->i", dl, dl) < r[l] ** 2
        in_slab = (q[:, 2] >= z0) & (q[:, 2] <= z1)
        excess += float(lens[c] * np.mean(np.where(in_slab, 2.0 / k, 0.0)))
    return solid - excess


def union_porosity(pack, *, bottom=None, top=None, samples=12) -> float:
    """Porosity of a pack of possibly overlapping grains between ``bottom`` and ``top`` (m;
    default its core window, :func:`md.observe.core_window`): one minus the union volume of
    the grains (:func:`union_solid_volume`) over the slab's volume."""
    from .observe import core_window

    if bottom is None or top is None:
        lo, hi = core_window(pack)
        bottom = lo if bottom is None else bottom
        top = hi if top is None else top
    solid = union_solid_volume(pack.positions, pack.radii, pack.box, bottom, top,
                               samples=samples)
    return float(1.0 - solid / (pack.box.lx * pack.box.ly * (float(top) - float(bottom))))


def _scaled(pack, lam):
    """The pack with its centres moved together vertically by the factor ``1 - lam`` about
    the lowest centre (Øren & Bakke 2002, Sect. 2.2: :math:`z' = z(1-\\lambda)`), the box and
    core window with it."""
    from .observe import core_window
    from .space import Box

    zb = float(pack.positions[:, 2].min())
    f = 1.0 - lam
    x = pack.positions.copy()
    x[:, 2] = zb + (x[:, 2] - zb) * f
    lo, hi = core_window(pack)
    box = Box(pack.box.lx, pack.box.ly, zb + (pack.box.lz_min - zb) * f,
              zb + (pack.box.lz_max - zb) * f)
    meta = {**pack.metadata, "core_window_m": [zb + (lo - zb) * f, zb + (hi - zb) * f]}
    return dataclasses.replace(pack, positions=x, box=box, metadata=meta,
                               velocities=np.zeros_like(pack.velocities),
                               angular_velocities=np.zeros_like(pack.angular_velocities))


def _pair_keys(p, n):
    p = np.sort(np.asarray(p, dtype=np.int64).reshape(-1, 2), axis=1)
    return p[:, 0] * n + p[:, 1]


def dissolved_of(pack, pairs):
    """The dissolved overlap :math:`\\xi_p` (m) a pack records for each of ``pairs`` (0 for a
    pair it does not record, and for every pair of a pack without
    :attr:`md.Pack.overlap_dissolved`)."""
    pairs = np.asarray(pairs).reshape(-1, 2)
    out = np.zeros(pairs.shape[0])
    if pack.overlap_dissolved is None or len(pack.pairs) == 0 or pairs.size == 0:
        return out
    n = pack.n_grains
    known = _pair_keys(pack.pairs, n)
    order = np.argsort(known)
    known = known[order]
    want = _pair_keys(pairs, n)
    pos = np.clip(np.searchsorted(known, want), 0, known.size - 1)
    hit = known[pos] == want
    out[hit] = np.asarray(pack.overlap_dissolved)[order][pos[hit]]
    return out


def reconstruct(pack, intergranular_volume, *, tolerance=1e-4, max_factor=0.6, samples=12):
    r"""Compact a pack past Hertzian contact to a target porosity by process-based
    reconstruction (Bryant, King & Mellor 1993; Øren & Bakke 2002, Sect. 2.2).

    The grain centres are moved together along the vertical,
    :math:`z' = z_b + (z - z_b)(1 - \lambda)` about the lowest centre :math:`z_b` (the box and
    the core window with them), and the overlap this makes is removed as pressure-solution
    volume: the solid is the union of the spheres (:func:`union_porosity`). :math:`\lambda` is
    found by bisection so that the core window's porosity is ``intergranular_volume`` (the
    uncemented pack's porosity; burial's IGV). Each overlapping pair's overlap is split into
    the elastic part it had before (the Hertz overlap that carries the stress, kept) and the
    dissolved rest :math:`\xi_p`, recorded in the returned pack's
    :attr:`~md.Pack.overlap_dissolved` (aligned with its ``pairs``, the overlapping pairs);
    :func:`flattened_contact_radius` gives their contact radius.

    The returned pack is a sample to measure (porosity, cement lattice, linearised
    stiffness), not a state to run MD on: its overlaps are mostly not Hertzian, and
    :func:`md.compact` would read them as enormous elastic forces. A deeper depth starts again
    from the Hertzian pack (:func:`md.along_depth.carry_down`).

    A pack already at or below the target porosity is returned with :math:`\lambda = 0`
    (reconstruction only compacts; ``metadata["reconstruct_reached"]`` is then False unless
    it is within ``tolerance``).

    Parameters
    ----------
    pack : md.Pack
        A pack at equilibrium (its overlaps elastic, or with ``overlap_dissolved`` already).
    intergranular_volume : float
        Target porosity of the core window, in (0, 1).
    tolerance : float
        Porosity tolerance of the bisection, in (0, 0.01].
    max_factor : float
        Largest :math:`\lambda`, in (0, 0.9).
    samples : int
        See :func:`union_solid_volume`.

    Returns
    -------
    md.Pack
        ``stage="reconstruct"``; ``metadata`` adds ``compaction_factor`` (:math:`\lambda`),
        ``porosity`` (reached), ``porosity_target`` and ``reconstruct_reached``.
    """
    from .state import Pack

    if not isinstance(pack, Pack):
        raise ValueError(f"pack must be an md.Pack; got {type(pack).__name__}")
    target = float(intergranular_volume)
    if not 0 < target < 1:
        raise ValueError(f"intergranular_volume must lie in (0, 1); got {target}")
    if not 0 < tolerance <= 0.01:
        raise ValueError(f"tolerance must lie in (0, 0.01]; got {tolerance}")
    if not 0 < max_factor < 0.9:
        raise ValueError(f"max_factor must lie in (0, 0.9); got {max_factor}")

    def phi(lam):
        return union_porosity(_scaled(pack, lam), samples=samples)

    lo, hi = 0.0, float(max_factor)
    phi_lo = phi(lo)
    if phi_lo <= target + tolerance:
        lam, reached = 0.0, abs(phi_lo - target) <= tolerance
    else:
        if phi(hi) > target:
            raise ValueError(f"intergranular_volume {target:g} is below what a vertical "
                             f"compaction by max_factor = {max_factor:g} reaches")
        while hi - lo > 1e-7:
            mid = 0.5 * (lo + hi)
            v = phi(mid)
            if abs(v - target) <= 0.25 * tolerance:
                lo = hi = mid
                break
            if v > target:
                lo = mid
            else:
                hi = mid
        lam, reached = 0.5 * (lo + hi), True
    # Elastic part of each overlap before the compaction (all of it where none is recorded).
    p0, _, dist0 = _overlapping_pairs(pack.positions, pack.radii, pack.box)
    r = pack.radii
    xi0 = r[p0[:, 0]] + r[p0[:, 1]] - dist0
    elastic0 = np.maximum(xi0 - dissolved_of(pack, p0), 0.0)
    out = _scaled(pack, lam)
    p1, _, dist1 = _overlapping_pairs(out.positions, r, out.box)
    xi1 = r[p1[:, 0]] + r[p1[:, 1]] - dist1
    n = pack.n_grains
    k0, k1 = _pair_keys(p0, n), _pair_keys(p1, n)
    order = np.argsort(k0)
    pos = np.clip(np.searchsorted(k0[order], k1), 0, max(k0.size - 1, 0))
    elastic = np.zeros(k1.size)
    if k0.size:
        hit = k0[order][pos] == k1
        elastic[hit] = elastic0[order][pos[hit]]
    elastic = np.minimum(elastic, xi1)
    dissolved = xi1 - elastic
    # Tangential histories of the pairs carried over (zero for a new contact).
    hist = np.zeros((k1.size, 3))
    if len(pack.pairs):
        kh = _pair_keys(pack.pairs, n)
        oh = np.argsort(kh)
        ph = np.clip(np.searchsorted(kh[oh], k1), 0, kh.size - 1)
        hh = kh[oh][ph] == k1
        hist[hh] = np.asarray(pack.history)[oh][ph[hh]]
    phi_end = union_porosity(out, samples=samples)
    meta = {**out.metadata, "compaction_factor": float(lam), "porosity": phi_end,
            "porosity_target": target, "reconstruct_reached": bool(reached)}
    return dataclasses.replace(out, pairs=np.ascontiguousarray(p1, dtype=np.int32),
                               history=hist, overlap_dissolved=dissolved,
                               stage="reconstruct", metadata=meta)


def attach_cement(pack, lattice, cells):
    """Cemented cells of a lattice attached to the grains: for each cemented cell the grain
    whose surface is nearest its centre and the centre's offset from that grain's centre
    (minimum image in x and y), so that the cement can be carried with the grains
    (:func:`carried_cells`). Returns ``(grain, offset)``, shapes (n,) and (n, 3)."""
    cells = np.asarray(cells, dtype=bool)
    if cells.shape != lattice.index.shape:
        raise ValueError("cells must have one entry per pore cell of lattice")
    c = lattice.centres()[cells]
    if c.shape[0] == 0:
        return np.zeros(0, np.int64), np.zeros((0, 3))
    x, r, box = pack.positions, pack.radii, pack.box
    best = np.full(c.shape[0], np.inf)
    grain = np.zeros(c.shape[0], np.int64)
    offset = np.zeros_like(c)
    for chunk in range(0, x.shape[0], 64):      # all grains, in chunks (small packs)
        xs = x[chunk:chunk + 64]
        d = c[:, None, :] - xs[None, :, :]
        d[..., 0] -= box.lx * np.round(d[..., 0] / box.lx)
        d[..., 1] -= box.ly * np.round(d[..., 1] / box.ly)
        gap = np.linalg.norm(d, axis=2) - r[None, chunk:chunk + 64]
        k = np.argmin(gap, axis=1)
        g = gap[np.arange(c.shape[0]), k]
        better = g < best
        best[better] = g[better]
        grain[better] = chunk + k[better]
        offset[better] = d[np.arange(c.shape[0]), k][better]
    return grain, offset


def carried_cells(pack, lattice, grain, offset):
    """The pore cells of ``lattice`` (a lattice of ``pack``) that hold cement carried with the
    grains: each attached cement point (:func:`attach_cement`) moved with its grain to
    ``pack``'s positions; a point now inside a grain (dissolved by the compaction) or off the
    lattice is lost, and points that fall in one cell make one cemented cell. Returns a bool
    array, one entry per pore cell."""
    cells = np.zeros(lattice.index.size, dtype=bool)
    grain = np.asarray(grain, dtype=np.int64)
    if grain.size == 0:
        return cells
    if grain.min() < 0 or grain.max() >= pack.n_grains:
        raise ValueError(f"grain must index the pack's {pack.n_grains} grains")
    pts = pack.positions[grain] + np.asarray(offset, dtype=float)
    nx, ny, nz = lattice.shape
    cw = lattice.cell_width
    i = np.floor(np.mod(pts[:, 0], pack.box.lx) / cw).astype(np.int64) % nx
    j = np.floor(np.mod(pts[:, 1], pack.box.ly) / cw).astype(np.int64) % ny
    k = np.floor((pts[:, 2] - lattice.z0) / cw).astype(np.int64)
    ok = (k >= 0) & (k < nz)
    flat = i[ok] + nx * (j[ok] + ny * k[ok])
    pos = np.clip(np.searchsorted(lattice.index, flat), 0, lattice.index.size - 1)
    hit = lattice.index[pos] == flat             # a pore cell (index is sorted)
    cells[pos[hit]] = True
    return cells
