"""Private helpers of the MD protocols: neighbour-list refresh with tangential histories carried
over, the blow-up check scaled with the Hertz overlap expected at the current stress, and the
time step of the current state. SI units."""

from __future__ import annotations

import numpy as np

from .integrate import contact_time_step
from .neighbors import build_neighbors, needs_rebuild
from .observe import contact_forces, expected_overlap, pair_geometry

#: Largest overlap, as a multiple of the Hertz overlap of the mean contact force at the pack's
#: current mean stress (:func:`md.observe.expected_overlap`), before a run is declared blown
#: up. Contact forces in a static pack have an exponential tail: the largest of ~10^4 contacts
#: carries about 10 times the mean force, i.e. 10^(2/3) = 4.6 times the mean overlap; measured
#: 2–3 (tests/md/test_observe.py, benchmarks/md_settle_compact.py up to 100 MPa).
OVERLAP_FACTOR = 8.0
#: Overlap limit, as a fraction of the mean radius, at stresses where the scaled limit is
#: smaller (loose packs, impacts during settling: an impact at 1 m/s overlaps by 0.6 % of R).
MIN_OVERLAP = 0.05


def remap_history(old_pairs, old_hist, new_pairs, n):
    """Carry tangential histories over to a rebuilt neighbour list (pairs matched by (i, j))."""
    hist = np.zeros((new_pairs.shape[0], 3))
    if old_pairs.shape[0] == 0 or new_pairs.shape[0] == 0:
        return hist
    old_key = old_pairs[:, 0].astype(np.int64) * n + old_pairs[:, 1]
    new_key = new_pairs[:, 0].astype(np.int64) * n + new_pairs[:, 1]
    order = np.argsort(old_key)
    pos = np.searchsorted(old_key[order], new_key)
    pos = np.minimum(pos, old_key.size - 1)
    found = old_key[order][pos] == new_key
    hist[found] = old_hist[order][pos[found]]
    return hist


def overlap_limit(x, r, pairs, box, material, porosity=0.4):
    """Largest overlap (m) a sound run reaches in the current state: ``OVERLAP_FACTOR`` times
    the Hertz overlap of the mean contact force at the mean contact stress of the whole pack
    (virial of the normal forces), and at least ``MIN_OVERLAP`` of the mean radius."""
    force, branch = contact_forces(x, r, pairs, box, material)
    lz = float(np.ptp(x[:, 2])) + 2.0 * float(r.max())
    stress = max(float(np.einsum("ci,ci->", force, branch)) / (3.0 * box.lx * box.ly * lz), 0.0)
    n_contacts = int(np.count_nonzero(np.any(force != 0.0, axis=1)))
    coordination = max(2.0 * n_contacts / r.size, 1.0)
    r_mean = float(r.mean())
    xi = float(expected_overlap(stress, r_mean, porosity, coordination, material))
    return max(OVERLAP_FACTOR * xi, MIN_OVERLAP * r_mean)


def check_overlaps(stage, x, r, pairs, box, material):
    """Raise ``RuntimeError`` if an overlap exceeds :func:`overlap_limit` (a blown-up run)."""
    pairs = np.asarray(pairs).reshape(-1, 2)
    if pairs.shape[0] == 0:
        return
    worst = float(np.max(pair_geometry(x, r, pairs, box)[2]))
    limit = overlap_limit(x, r, pairs, box, material)
    if not worst <= limit:
        raise RuntimeError(f"{stage}: the integration blew up (an overlap of "
                           f"{worst / r.mean():.1%} of the mean radius, above the "
                           f"{limit / r.mean():.1%} that the pack's stress explains); the time "
                           "step or the stiffness is wrong")


def refresh_neighbors(stage, nl, hist, x, r, box, skin, material):
    """Rebuild the neighbour list when a grain has moved more than skin/2 (histories carried
    over) and check for blown-up overlaps; returns the list and histories to use next."""
    if not np.all(np.isfinite(x)):
        raise RuntimeError(f"{stage}: the integration blew up (non-finite positions)")
    if needs_rebuild(nl, x, box):
        new = build_neighbors(x, r, box, skin)
        hist = remap_history(nl.pairs, hist, new.pairs, r.size)
        nl = new
    check_overlaps(stage, x, r, nl.pairs, box, material)
    return nl, hist


def time_step(x, r, nl, box, material, *, mobile=None, z_floor=None, impact_speed=0.0):
    """:func:`md.integrate.contact_time_step` of the current state (the single rule of every
    protocol)."""
    return contact_time_step(x, r, nl.pairs, box, material, mobile=mobile, z_floor=z_floor,
                             impact_speed=impact_speed)
