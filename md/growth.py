"""Cement growth on the lattice of :mod:`md.cement`: the contact, coating and pore-body schemes
of García & Medina (Sects. III C–E) and the pendular contact cement of this project, as numba
kernels (:mod:`md._kernels_cement`), O(n log n) in the number of pore cells. Every scheme is
nested in the saturation, so one growth (:func:`cement_order`) serves a sweep
(:func:`cement_sweep`).
"""

from __future__ import annotations

import numpy as np

from .cement import CONTACT, SCHEMES, SURFACE, CementLattice

__all__ = ["grow_cement", "cement_order", "cement_sweep", "cement_fill", "film_fill",
           "FILM_MAX_THICKNESS", "FILM_MAX_SATURATION", "FILM_CAP", "coating_is_film"]


#: Uniforms drawn from the growth stream per call of the pore-body kernel (the result does not
#: depend on it: the kernel uses the stream in order and hands back what it did not use).
_PORE_BODY_CHUNK = 1 << 16

#: Smallest weight of a frontier cell in the pore-body scheme (cells at zero distance keep a
#: tiny chance of being picked, and the frontier's total weight stays > 0).
_WEIGHT_FLOOR = 1e-12

#: Children per node of the pore-body sum tree (8 float64: one cache line).
_TREE_FANOUT = 8


def _neighbour_map(lat: CementLattice) -> np.ndarray:
    """The 6 face neighbours of each pore cell as pore positions, shape (n, 6), int32.

    Columns +x, -x, +y, -y, +z, -z (periodic in x and y); -1 for a solid cell or beyond the
    bottom and top layers. One numba pass, O(n) (plus a scratch int32 array over the whole
    lattice).
    """
    from ._kernels_cement import face_neighbours

    nx, ny, nz = (int(s) for s in lat.shape)
    index = np.ascontiguousarray(lat.index, dtype=np.int32)
    where = np.empty(nx * ny * nz, dtype=np.int32)
    nbrs = np.empty((index.size, 6), dtype=np.int32)
    face_neighbours(index, nx, ny, nz, where, nbrs)
    return nbrs


def _distance_levels(distance) -> np.ndarray:
    """uint32 levels with the order of ``distance``: equal distances, equal levels.

    float32 distances (as :func:`cement_lattice` stores them) map bit for bit (O(n)); other
    dtypes by rank (``np.unique``, O(n log n)).
    """
    from ._kernels_cement import float32_levels

    levels = np.empty(distance.size, dtype=np.uint32)
    if distance.dtype == np.float32:
        bits = np.ascontiguousarray(distance + np.float32(0.0)).view(np.uint32)   # -0.0 -> +0.0
        float32_levels(bits, levels)
    else:
        levels[:] = np.unique(distance, return_inverse=True)[1].reshape(-1)
    return levels


def _order_keys(levels) -> np.ndarray:
    """uint64 keys ``level << 32 | cell``: their order is that of (distance, cell index)."""
    from ._kernels_cement import order_keys

    keys = np.empty(levels.size, dtype=np.uint64)
    order_keys(levels, keys)
    return keys


def _pore_body_streams(seed):
    """The three independent numpy Generators of the pore-body scheme: seeds, growth, restarts
    (``SeedSequence(seed).spawn(3)``)."""
    return tuple(np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(3))


def _grow_contact(lat: CementLattice, target: int) -> np.ndarray:
    from ._kernels_cement import contact_growth

    n = lat.index.size
    levels = _distance_levels(lat.distance)
    sorted_keys = np.sort(_order_keys(levels))
    nbrs = _neighbour_map(lat)
    kind = np.ascontiguousarray(lat.kind)
    cells = np.zeros(n, dtype=np.uint8)
    order = np.empty(target, dtype=np.int64)
    count = contact_growth(levels, kind, nbrs, sorted_keys, target, CONTACT, cells,
                           np.empty(n, dtype=np.uint64), order)
    if count != target:
        raise RuntimeError(f"contact growth stopped at {count} of {target} cells")
    return order


def _sum_tree(n: int, fanout: int):
    """Zeroed storage of the pore-body sum tree over ``n`` cells: the flat float64 array and
    the offset of each level (level 0, the cell weights, at 0; the top level is one group of
    ``fanout`` entries). See :mod:`md._kernels_cement`."""
    offsets = []
    total = 0
    m = max(int(n), 1)
    while True:
        padded = -(-m // fanout) * fanout
        offsets.append(total)
        total += padded
        if m <= fanout:
            break
        m = padded // fanout
    return np.zeros(total), np.array(offsets, dtype=np.int64)


def _grow_pore_body(lat: CementLattice, target: int, seed: int) -> np.ndarray:
    from ._kernels_cement import pore_body_growth, pore_body_start

    n = lat.index.size
    seeds_rng, growth_rng, restart_rng = _pore_body_streams(seed)
    surface = np.flatnonzero(lat.kind == SURFACE)
    n_seeds = max(1, min(target, surface.size // 50 + 1))
    seeds = seeds_rng.permutation(surface if surface.size else n)[:n_seeds]
    dist = np.ascontiguousarray(lat.distance)
    nbrs = _neighbour_map(lat)
    cells = np.zeros(n, dtype=np.uint8)
    tree, offsets = _sum_tree(n, _TREE_FANOUT)
    n_front = pore_body_start(dist, nbrs, seeds, cells, tree, offsets, _TREE_FANOUT,
                              _WEIGHT_FLOOR)
    state = np.array([n_seeds, n_front, 0, 0], dtype=np.int64)
    order = np.empty(target, dtype=np.int64)
    order[:n_seeds] = seeds
    restart = np.zeros(0, dtype=np.int64)
    uniforms = np.zeros(0)
    while True:
        status = pore_body_growth(dist, nbrs, cells, tree, offsets, _TREE_FANOUT,
                                  _WEIGHT_FLOOR, target, uniforms, restart, state, order)
        if status == 0:
            break
        if status == 2:                        # frontier empty: the restart permutation, once
            restart = restart_rng.permutation(n)
            uniforms = uniforms[state[3]:]
        else:
            uniforms = growth_rng.random(min(_PORE_BODY_CHUNK, max(target - int(state[0]), 1)))
    if state[0] != target:
        raise RuntimeError(f"pore-body growth stopped at {state[0]} of {target} cells")
    return order


def _distance_order(distance, target: int) -> np.ndarray:
    """The ``target`` cells of smallest (distance, cell index), in that order."""
    keys = _order_keys(_distance_levels(distance))
    if target < keys.size:
        keys = np.partition(keys, target - 1)[:target]
    keys.sort()
    return (keys & np.uint64(0xFFFFFFFF)).astype(np.int64)


def cement_order(lat: CementLattice, saturation, scheme="contact", *, seed=0) -> np.ndarray:
    """The pore cells in the order a scheme cements them, up to saturation :math:`S_c`.

    Every scheme of :func:`grow_cement` is nested in :math:`S_c`, so one growth serves a
    whole saturation sweep: ``grow_cement(lat, s, scheme, seed=seed)`` cements exactly
    ``order[:round(s * n)]`` for every ``s`` up to ``saturation`` (tested), where ``order`` is
    returned here. Parameters as :func:`grow_cement`.

    Returns
    -------
    ndarray of int64
        Pore positions (into ``lat.index``), ``round(S_c n)`` of them.
    """
    _check_growth(lat, saturation, scheme, seed)
    n = lat.index.size
    target = int(round(saturation * n))
    if target == 0:
        return np.zeros(0, dtype=np.int64)
    if scheme in ("coating", "pendular"):
        return _distance_order(lat.distance if scheme == "coating" else lat.distance2, target)
    if scheme == "contact":
        return _grow_contact(lat, target)
    return _grow_pore_body(lat, target, int(seed))


def cement_sweep(lat: CementLattice, saturations, scheme="contact", *, seed=0) -> np.ndarray:
    """Cemented cells at each of ``saturations`` from one growth (:func:`cement_order`).

    Returns
    -------
    ndarray of bool, shape (len(saturations), n)
        Row ``k`` equals ``grow_cement(lat, saturations[k], scheme, seed=seed)``.
    """
    sat = np.atleast_1d(np.asarray(saturations, dtype=float))
    if sat.ndim != 1 or sat.size == 0:
        raise ValueError(f"saturations must be a non-empty 1-d sequence; got {saturations!r}")
    order = cement_order(lat, float(sat.max()), scheme, seed=seed)
    n = lat.index.size
    out = np.zeros((sat.size, n), dtype=bool)
    for k, s in enumerate(sat):
        _check_growth(lat, s, scheme, seed)
        out[k, order[:int(round(s * n))]] = True
    return out


def _check_growth(lat, saturation, scheme, seed):
    if not 0.0 <= saturation <= 1.0:
        raise ValueError(f"saturation must lie in [0, 1]; got {saturation}")
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {SCHEMES}; got {scheme!r}")
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be an integer >= 0; got {seed!r}")
    if int(round(saturation * lat.index.size)) == 0:
        return
    if scheme == "pendular" and lat.distance2 is None:
        raise ValueError("the pendular scheme needs lat.distance2 (md.cement_lattice "
                         "computes it)")
    name = "distance2" if scheme == "pendular" else "distance"
    if not np.all(np.isfinite(getattr(lat, name))):
        raise ValueError(f"lat.{name} must be finite (distances to the grain surfaces, m)")


def grow_cement(lat: CementLattice, saturation, scheme="contact", *, seed=0) -> np.ndarray:
    """Cement the pore cells of a lattice up to a saturation :math:`S_c` (fraction of pore cells).

    Schemes (García & Medina, Sects. III C–E):

    * ``"contact"`` (Sect. III C): the contact cells first (closest to the grains first), then
      growth into the empty face neighbours of the cement, always the one closest to a grain
      surface next; when none is left (pores not connected to the cement), the empty cell
      closest to a grain seeds the growth again;
    * ``"coating"`` (Sect. III D): cells by increasing distance to the grain surface (an even
      coat);
    * ``"pendular"`` (this project's contact cement that converges with :math:`\\Omega`): cells
      by increasing distance to the *second*-nearest grain surface (``lat.distance2``; ties by
      cell index), so the cement fills the set :math:`\\{d_2 < \\delta\\}` — pendular rings
      around every contact (and the narrowest throats), the cement body of Dvorkin et al.'s
      scheme 1 — whose shape is a fixed region of space, not of cells. The source's
      ``"contact"`` scheme fills the contact cells (those meeting two grains: a neck of height
      about :math:`c_w`) and then grows the face neighbours *closest to a grain*, which at fine
      resolution is a film of one cell spreading over the grain surfaces: on a 4 × 4 × 12 pack
      at :math:`S_c = 0.1` its mean distance to the grains falls from 0.038 R to 0.024 R and
      the grain surface it covers rises from 23 % to 38 % between :math:`\\Omega` 4 and 12
      (``benchmarks/md_omega_convergence.py``), so its moduli do not converge in
      :math:`\\Omega`;
    * ``"pore_body"`` (Sect. III E): ``max(1, min(N, n_surface // 50 + 1))`` random surface
      cells as seeds (``N = round(S_c n)``; any cells if there are no surface cells), then
      growth into empty face neighbours of the cement chosen at random with probability
      proportional to their distance to the grains, ``max(d, 1e-12 m)`` (cement grows into pore
      bodies); when none is left, a random empty cell seeds the growth again.

    Ties in distance are broken by the cell's position in ``lat.index`` (smaller first), so the
    contact, coating and pendular schemes are deterministic. All are nested: for a fixed ``seed``,
    the cells cemented at :math:`S_{c1} < S_{c2}` are a subset of those at :math:`S_{c2}`
    (pore body too, since the seeds are a prefix of one random permutation and the growth
    uses one random stream in order).

    Cost: O(n log n) for n pore cells; the contact scheme keeps a binary heap of the empty
    face neighbours of the cement, keyed on (distance, cell index); the pore-body scheme a sum
    tree over all cells (weight ``max(d, 1e-12)`` in the frontier, 0 elsewhere), O(log n) per
    pick (numba kernels in :mod:`md._kernels_cement`).

    Randomness (pore body only): ``numpy.random.SeedSequence(seed).spawn(3)`` gives three
    independent ``numpy.random.Generator`` streams: the seeds (the first of a random
    permutation of the surface cells), the growth (one uniform per pick, drawn in chunks and
    used in order) and the restarts (a random permutation of all cells, drawn only if the
    frontier empties; the next empty cell in it is a uniform choice among the empty cells).
    The result depends on ``seed`` only (not on the chunk size). This stream differs from the
    one of versions before the numba kernels (``rng.choice`` on one Generator), so pore-body
    cells for a given seed differ from those versions; the distribution is the same.

    Parameters
    ----------
    lat : CementLattice
        Its ``distance`` must be finite.
    saturation : float
        :math:`S_c`, in [0, 1].
    scheme : {"contact", "coating", "pore_body", "pendular"}
    seed : int, keyword-only
        Random seed of the pore-body scheme, ``>= 0``.

    Returns
    -------
    ndarray of bool
        Cemented pore cells (aligned with ``lat.index``); ``round(S_c n)`` of them.
    """
    order = cement_order(lat, saturation, scheme, seed=seed)
    cemented = np.zeros(lat.index.size, dtype=bool)
    cemented[order] = True
    return cemented


#: Thickest film (in mean grain radii) :func:`cement_fill` lays as a film; a thicker coating is
#: whole cells. Film and cells agree there once the cells resolve it (3 x 3 x 6 pack at 10 MPa,
#: S_c 0.5, t = 0.10 R, rotations: static M 20.9 GPa as a film from Omega 8, 20.9 as whole
#: cells at Omega 12, which give 18.9 at Omega 6).
FILM_MAX_THICKNESS = 0.1
#: Largest cement saturation (cement over the window's porosity) :func:`cement_fill` lays as a
#: film. Past it the cement fills the pore throats between neighbours, which a film (bridges
#: where two grains' films meet, the rest riding on its grain) does not represent: on a pack
#: reconstructed to burial's intergranular volume (3 x 3 x 8, IGV 0.30, rotations, static M)
#: the film gives 25.2 GPa at S_c 0.37 where whole cells converge to 31.3-32.0 (Omega 6-9), and
#: 30.1 against 43.0-44.6 at S_c 0.67; at S_c 0.185 the film's 21.1 lies below whole cells'
#: 22.5 (Omega 6) and 25.2 (Omega 9), which have not converged.
FILM_MAX_SATURATION = 0.25
#: Largest fill of a film cell (below 1: a full cell is a cell of the lattice, not film).
FILM_CAP = 1.0 - 2.0**-20


def film_fill(distance, cell_width, volume, *, count=None, cap=1.0) -> np.ndarray:
    """Fill fractions of a film of uniform thickness on the grains holding ``volume`` cells.

    Each pore cell is a slab of the distance-to-the-grains coordinate, one cell wide, from
    :math:`s_i = \\max(d_i - c_w/2, 0)` (:math:`d_i` the distance of its centre to the
    nearest grain surface; the cells of the first layer, whose cube reaches into the grain,
    start at the surface). A film reaching :math:`\\tau` (in cells) fills

    .. math:: f_i(\\tau) = \\min\\left(\\max\\left(\\tau - s_i/c_w, 0\\right), 1\\right),

    and :math:`\\tau` is solved (bisection to machine precision; :math:`\\sum f_i` is continuous
    and non-decreasing in :math:`\\tau`) so that the counted cells hold ``volume`` cells of
    cement. (This project's sub-cell coating: the source's coating, Sect. III D of García &
    Medina, fills whole cells by increasing distance, which a film thinner than a cell turns
    into spots; here every surface cell holds its share of the film, and a cell is full once
    the film passes it, :math:`\\tau \\ge s_i/c_w + 1`: in the source's order, so
    a thick coating is the source's, with a graded front. While :math:`\\tau < 1` no cell is
    full: the first layer holds the whole film, as a film.)

    Parameters
    ----------
    distance : array_like, shape (n,)
        :math:`d_i`, m, ``>= 0`` (``CementLattice.distance``).
    cell_width : float
        :math:`c_w`, m.
    volume : float
        Cement to place, in cells (:math:`c_w^3`), ``>= 0``.
    count : ndarray of bool, shape (n,), optional
        The cells whose fill counts toward ``volume`` (default all); the others get the same
        film.
    cap : float
        Largest fill, in (0, 1] (:data:`FILM_CAP` keeps every cell a film cell of
        :func:`md.acoustic_system`: the film then spreads over further layers).

    Returns
    -------
    ndarray, shape (n,)
        Fills in [0, ``cap``]; all ``cap`` where ``volume`` exceeds what the counted cells
        hold.
    """
    d = np.asarray(distance, dtype=float)
    cw = float(cell_width)
    if not (np.isfinite(cw) and cw > 0):
        raise ValueError(f"cell_width must be > 0 m; got {cell_width!r}")
    if not (np.isfinite(volume) and volume >= 0):
        raise ValueError(f"volume must be a finite number of cells >= 0; got {volume!r}")
    if not np.all(np.isfinite(d) & (d >= 0)):
        raise ValueError("distance must be finite and >= 0 m")
    if not 0.0 < cap <= 1.0:
        raise ValueError(f"cap must lie in (0, 1]; got {cap!r}")
    start = np.maximum(d - 0.5 * cw, 0.0) / cw                 # in cells
    width = np.ones(d.size)
    sel = slice(None) if count is None else np.asarray(count, dtype=bool)
    counted, counted_width = start[sel], width[sel]
    if volume <= 0 or counted.size == 0:
        return np.zeros(d.size)
    if volume >= cap * counted.size:
        return np.full(d.size, float(cap))

    def held(tau):
        return float(np.sum(np.clip((tau - counted) / counted_width, 0.0, cap)))

    lo, hi = 0.0, float(np.max(counted + counted_width))
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if held(mid) < volume:
            lo = mid
        else:
            hi = mid
    # held() is linear between breakpoints: one secant step on the bracket lands on the volume.
    v_lo, v_hi = held(lo), held(hi)
    tau = lo if v_hi == v_lo else lo + (volume - v_lo) * (hi - lo) / (v_hi - v_lo)
    return np.clip((tau - start) / width, 0.0, cap)


def coating_is_film(pack, fraction, *, window=None) -> bool:
    """Whether :func:`cement_fill` lays a coating of cement ``fraction`` (volume per bulk volume
    of the ``window``, default the pack's core window) as a film: at most
    :data:`FILM_MAX_THICKNESS` mean radii thick (its volume over the surface of the grains
    whose centres lie in the window) and at most :data:`FILM_MAX_SATURATION` of the window's
    porosity (:func:`md.observe.porosity`). Both depend on the volume only, never on the
    lattice, so every resolution of one member shares the representation."""
    from .observe import core_window, porosity

    lo, hi = core_window(pack) if window is None else (float(window[0]), float(window[1]))
    grains = (pack.positions[:, 2] >= lo) & (pack.positions[:, 2] < hi)
    surface = 4.0 * np.pi * float(np.sum(pack.radii[grains] ** 2))
    volume = fraction * pack.box.lx * pack.box.ly * (hi - lo)
    if not surface > 0 or volume / surface > FILM_MAX_THICKNESS * float(pack.radii.mean()):
        return False
    phi = porosity(pack, bottom=lo, top=hi)
    return phi > 0 and fraction <= FILM_MAX_SATURATION * phi


def cement_fill(pack, lat: CementLattice, fraction, scheme="coating", *, seed=0, window=None,
                film=True):
    """Fill fractions of the pore cells holding the cement ``fraction`` of the core window.

    The volume rule of :func:`md.along_depth.cement_cells` without its rounding to whole
    cells: the cells whose centres lie in the window (default :func:`md.observe.core_window`
    of the pack) hold exactly ``fraction`` of the window's volume,
    :math:`\\sum_{i \\in W} f_i c_w^3 = S\\,l_x l_y (z_1 - z_0)`.

    * ``"coating"`` (with ``film``, the default) while the film is at most
      :data:`FILM_MAX_THICKNESS` mean radii thick (its volume over the surface of the grains
      whose centres lie in the window) and at most :data:`FILM_MAX_SATURATION` of the window's
      porosity (:func:`coating_is_film`): a film of uniform thickness (:func:`film_fill`, no
      cell full, :data:`FILM_CAP`), every surface cell
      holding its share, so that a film thinner than a cell is a film (cells partly filled,
      :func:`md.acoustic_system` scales their mass and springs and bridges the grains the film
      joins), not spots of whole cells;
    * the other schemes: the growth order of :func:`md.growth.cement_order` over the whole
      lattice, whole cells up to the last level it reaches (cells of equal distance, or one
      cell for ``"contact"`` and ``"pore_body"``), the rest of the volume spread evenly over
      that level's cells in the window (and the same fill on its cells outside).

    Parameters
    ----------
    pack : md.Pack
    lat : CementLattice
        The pack's lattice (:func:`md.cement_lattice`).
    fraction : float
        Cement volume per bulk volume of the window, in [0, 1].
    scheme : {"contact", "coating", "pore_body", "pendular"}
    seed : int
        Random seed of the pore-body scheme.
    window : (float, float), optional
        ``(bottom, top)``, m.
    film : bool
        ``False``: the coating too by whole cells in its growth order (the source's coating,
        the last level partly filled), as is a coating thicker than
        :data:`FILM_MAX_THICKNESS`. The choice depends on the volume only, never on
        :math:`\\Omega`, so the members of one resolution sequence share a representation.

    Returns
    -------
    fill : ndarray, shape (n,)
        Per pore cell of ``lat``, in [0, 1].
    overflow : bool
        Whether the window's pores were too few (then all of them are full).
    """
    from .observe import core_window

    if not (np.isfinite(fraction) and 0.0 <= fraction <= 1.0):
        raise ValueError(f"fraction must lie in [0, 1]; got {fraction!r}")
    if scheme not in SCHEMES:
        raise ValueError(f"scheme must be one of {SCHEMES}; got {scheme!r}")
    lo, hi = core_window(pack) if window is None else (float(window[0]), float(window[1]))
    if not hi > lo:
        raise ValueError(f"window must be (bottom, top) with top > bottom; got {window!r}")
    z = lat.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    cw = lat.cell_width
    want = fraction * pack.box.lx * pack.box.ly * (hi - lo) / cw**3     # cells
    n_in = int(np.count_nonzero(inside))
    fill = np.zeros(lat.index.size)
    if want <= 0:
        return fill, False
    overflow = want > n_in
    if scheme == "coating" and film and not overflow and coating_is_film(pack, fraction,
                                                                        window=(lo, hi)):
        return film_fill(lat.distance, cw, want, count=inside, cap=FILM_CAP), False
    order = cement_order(lat, 1.0, scheme, seed=seed)
    if overflow:
        fill[order] = 1.0
        return fill, True
    if scheme in ("coating", "pendular"):
        levels = _distance_levels(lat.distance2 if scheme == "pendular" else lat.distance)[order]
        new = np.flatnonzero(np.diff(levels) != 0) + 1
    else:
        new = np.arange(1, order.size)
    starts = np.concatenate([[0], new])                 # first position of every level
    cum = np.concatenate([[0], np.cumsum(inside[order])])
    before = cum[starts]                                # window cells before each level
    k = int(np.searchsorted(before, want, side="left")) - 1     # the level the cut falls in
    begin = starts[k]
    end = starts[k + 1] if k + 1 < starts.size else order.size
    fill[order[:begin]] = 1.0
    level = order[begin:end]
    n_level = int(np.count_nonzero(inside[level]))
    fill[level] = (want - before[k]) / n_level
    return fill, False
