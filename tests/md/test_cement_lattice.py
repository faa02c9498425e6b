"""The cement lattice: cell classes and distances against a brute-force evaluation."""

import numpy as np
import pytest

from md.cement import BODY, CONTACT, SURFACE, cement_lattice, grow_cement
from md.contact import QUARTZ
from md.space import Box
from md.state import Pack


def make_pack(rng, n=12, L=1.6e-3):
    x = np.column_stack([rng.uniform(0, L, n), rng.uniform(0, L, n), rng.uniform(0.2e-3, 1e-3, n)])
    r = rng.uniform(0.18e-3, 0.2e-3, n)
    z = np.zeros((n, 3))
    return Pack(x, z.copy(), z.copy(), r, Box(L, L, 0.0, 1.5e-3), QUARTZ,
                np.zeros((0, 2), np.int32), np.zeros((0, 3)))


def brute_force(pack, lat):
    """Every cell against every grain image, directly from the definitions."""
    nx, ny, nz = lat.shape
    cw = lat.cell_width
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    c = np.stack([(i.ravel() + 0.5) * cw, (j.ravel() + 0.5) * cw,
                  lat.z0 + (k.ravel() + 0.5) * cw], -1)
    L = np.array([pack.box.lx, pack.box.ly])
    touches = np.zeros(len(c), int)
    dist = np.full(len(c), np.inf)
    solid = np.zeros(len(c), bool)
    for xg, rg in zip(pack.positions, pack.radii):
        d = c - xg
        d[:, :2] -= L * np.round(d[:, :2] / L)
        centre_dist = np.linalg.norm(d, axis=1) - rg
        dist = np.minimum(dist, centre_dist)
        solid |= centre_dist < 0
        q = np.clip(np.zeros(3), d - cw / 2, d + cw / 2)        # closest cube point - grain
        touches += (np.sum(q * q, axis=1) < rg * rg)
    return solid, touches, dist


def second_distance(pack, lat, reach):
    """Distance to the second-nearest grain surface, every periodic image a grain of its own,
    capped at ``reach``."""
    nx, ny, nz = lat.shape
    cw = lat.cell_width
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    c = np.stack([(i.ravel() + 0.5) * cw, (j.ravel() + 0.5) * cw,
                  lat.z0 + (k.ravel() + 0.5) * cw], -1)
    d = [np.linalg.norm(c - xg - [sx * pack.box.lx, sy * pack.box.ly, 0.0], axis=1) - rg
         for xg, rg in zip(pack.positions, pack.radii) for sx in (-1, 0, 1) for sy in (-1, 0, 1)]
    return np.minimum(np.sort(np.array(d), axis=0)[1], reach)


def test_lattice_matches_brute_force(rng):
    pack = make_pack(rng)
    lat = cement_lattice(pack, resolution=3.0, reach=1e-3)
    solid, touches, dist = brute_force(pack, lat)
    np.testing.assert_allclose(lat.distance2, second_distance(pack, lat, 1e-3)[~solid],
                               rtol=1e-6)
    np.testing.assert_array_equal(lat.index, np.flatnonzero(~solid))
    np.testing.assert_array_equal(lat.kind, np.minimum(touches[~solid], 2))
    np.testing.assert_allclose(lat.distance, np.minimum(dist[~solid], 1e-3), rtol=1e-6)
    assert lat.index.dtype == np.int32 and lat.kind.dtype == np.int8
    assert lat.distance.dtype == np.float32 and np.all(lat.distance > 0)
    assert {CONTACT, SURFACE, BODY} >= set(np.unique(lat.kind).tolist())


def test_two_touching_grains_have_contact_cells():
    # Lattice of width cw = 1.6 mm / 48; the contact plane is put on a row of cell centres
    # (11.5 cells above the bottom of the lattice), so the neck ring has pore-cell centres.
    cw = 1.6e-3 / 48
    d = 2 * (11.5 * cw - 2e-4)
    x = np.array([[0.8e-3, 0.8e-3, 0.5e-3], [0.8e-3, 0.8e-3, 0.5e-3 + d]])
    z = np.zeros((2, 3))
    pack = Pack(x, z.copy(), z.copy(), np.array([2e-4, 2e-4]), Box(1.6e-3, 1.6e-3, 0, 1.5e-3),
                QUARTZ, np.zeros((0, 2), np.int32), np.zeros((0, 3)))
    lat = cement_lattice(pack, resolution=6.0)
    centres = lat.centres()
    contact = centres[lat.kind == CONTACT]
    assert contact.size > 0
    # Contact cells ring the neck between the grains, around the contact point.
    mid = x.mean(axis=0)
    assert np.max(np.linalg.norm(contact - mid, axis=1)) < 0.2e-3    # within a grain radius


@pytest.mark.parametrize("kwargs,match", [(dict(resolution=0.5), "resolution"),
                                          (dict(reach=0.0), "reach")])
def test_bad_input(rng, kwargs, match):
    with pytest.raises(ValueError, match=match):
        cement_lattice(make_pack(rng), **kwargs)


@pytest.fixture(scope="module")
def lattice():
    rng = np.random.default_rng(5)
    return cement_lattice(make_pack(rng, n=14), resolution=3.0)


@pytest.mark.parametrize("scheme", ["contact", "coating", "pore_body", "pendular"])
def test_growth_reaches_the_saturation(lattice, scheme):
    for s in (0.0, 0.05, 0.2, 1.0):
        cem = grow_cement(lattice, s, scheme, seed=3)
        assert cem.sum() == round(s * lattice.index.size)


def test_coating_fills_by_distance_and_nests(lattice):
    a = grow_cement(lattice, 0.1, "coating")
    b = grow_cement(lattice, 0.3, "coating")
    assert np.all(b[a])                                    # nested
    assert lattice.distance[a].max() <= lattice.distance[~b].min()


def test_pendular_fills_by_second_distance_and_nests(lattice):
    """Pendular cement: the cells nearest to a second grain first (ties by index), nested."""
    a = grow_cement(lattice, 0.05, "pendular")
    b = grow_cement(lattice, 0.2, "pendular")
    assert np.all(b[a])
    assert lattice.distance2[a].max() <= lattice.distance2[~b].min()
    n = round(0.2 * lattice.index.size)
    order = np.lexsort((np.arange(lattice.index.size), lattice.distance2))[:n]
    assert np.array_equal(np.flatnonzero(b), np.sort(order))
    # it sits between grains: its cells are nearer a second grain than the coating's
    coat = grow_cement(lattice, 0.2, "coating")
    assert np.median(lattice.distance2[b]) < np.median(lattice.distance2[coat])


def test_pendular_needs_the_second_distance():
    with pytest.raises(ValueError, match="distance2"):
        grow_cement(synthetic_lattice(4), 0.1, "pendular")


def test_contact_cement_starts_at_the_contacts(lattice):
    n_contact = int(np.sum(lattice.kind == CONTACT))
    s = 0.5 * n_contact / lattice.index.size
    cem = grow_cement(lattice, s, "contact")
    assert np.all(lattice.kind[cem] == CONTACT)
    more = grow_cement(lattice, min(1.0, 3 * n_contact / lattice.index.size), "contact")
    assert np.all(more[lattice.kind == CONTACT])


def test_pore_body_cement_sits_farther_from_grains_and_is_seeded(lattice):
    a = grow_cement(lattice, 0.2, "pore_body", seed=1)
    b = grow_cement(lattice, 0.2, "pore_body", seed=1)
    np.testing.assert_array_equal(a, b)
    coat = grow_cement(lattice, 0.2, "coating")
    contact = grow_cement(lattice, 0.2, "contact")
    d = lattice.distance
    # Pore-body cement lies farther from the grains than the average pore cell; contact and
    # coating cement lie closer (the paper's three microstructures).
    assert d[a].mean() > d.mean() > d[contact].mean() >= d[coat].mean()


@pytest.mark.parametrize("kwargs,match", [(dict(saturation=1.5), "saturation"),
                                          (dict(saturation=0.1, scheme="random"), "scheme")])
def test_growth_bad_input(lattice, kwargs, match):
    with pytest.raises(ValueError, match=match):
        grow_cement(lattice, **kwargs)


# ----------------------------------------------------------------------------- growth kernels
# Plain-Python twins of the numba growth kernels of md._kernels_cement, compared on small
# lattices cell for cell (García & Medina, Sects. III C–E).

def reference_neighbours(lat):
    """The 6 face neighbours of each pore cell, straight from the definition."""
    nx, ny, nz = lat.shape
    where = {int(c): p for p, c in enumerate(lat.index)}
    out = np.full((lat.index.size, 6), -1, dtype=np.int64)
    for p, c in enumerate(lat.index.tolist()):
        i, j, k = c % nx, (c // nx) % ny, c // (nx * ny)
        for q, (di, dj, dk) in enumerate(((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0),
                                          (0, 0, 1), (0, 0, -1))):
            if 0 <= k + dk < nz:
                flat = (i + di) % nx + nx * ((j + dj) % ny + ny * (k + dk))
                out[p, q] = where.get(flat, -1)
    return out


def contact_reference(lat, saturation):
    """Contact cement with heapq and lazy deletion (the pure-Python version before the numba
    kernel): contact cells by (distance, index), then the empty face neighbour of the cement
    closest to a grain; the closest empty cell when no neighbour is left."""
    import heapq

    n = lat.index.size
    target = int(round(saturation * n))
    cemented = np.zeros(n, dtype=bool)
    if target == 0:
        return cemented
    dist = lat.distance.astype(float)
    nbrs = reference_neighbours(lat)
    contact = np.flatnonzero(lat.kind == CONTACT)
    first = contact[np.lexsort((contact, dist[contact]))][:target]
    cemented[first] = True
    count = first.size
    heap = [(dist[c], int(c)) for c in np.unique(nbrs[first].ravel()) if c >= 0
            and not cemented[c]]
    heapq.heapify(heap)
    while count < target:
        if not heap:
            rest = np.flatnonzero(~cemented)
            best = rest[np.argmin(dist[rest])]
            heap = [(dist[best], int(best))]
        _, c = heapq.heappop(heap)
        if cemented[c]:
            continue
        cemented[c] = True
        count += 1
        for nb in nbrs[c]:
            if nb >= 0 and not cemented[nb]:
                heapq.heappush(heap, (dist[nb], int(nb)))
    return cemented


def coating_reference(lat, saturation):
    n = lat.index.size
    cemented = np.zeros(n, dtype=bool)
    cemented[np.lexsort((np.arange(n), lat.distance.astype(float)))[:round(saturation * n)]] = True
    return cemented


def pore_body_twin(lat, saturation, seed):
    """Pore-body cement with a Python set as the frontier and a cumulative sum for each pick,
    on the same three random streams as md.cement (seeds, growth uniforms, restarts)."""
    n = lat.index.size
    target = int(round(saturation * n))
    cemented = np.zeros(n, dtype=bool)
    if target == 0:
        return cemented
    seeds_rng, growth_rng, restart_rng = (np.random.default_rng(s) for s in
                                          np.random.SeedSequence(seed).spawn(3))
    dist = lat.distance.astype(float)
    nbrs = reference_neighbours(lat)
    surface = np.flatnonzero(lat.kind == SURFACE)
    n_seeds = max(1, min(target, surface.size // 50 + 1))
    seeds = seeds_rng.permutation(surface if surface.size else n)[:n_seeds]
    cemented[seeds] = True
    count = n_seeds
    frontier = {int(c) for c in nbrs[seeds].ravel() if c >= 0 and not cemented[c]}
    uniforms = iter(growth_rng.random(target))
    restart, ptr = None, 0
    while count < target:
        if not frontier:
            if restart is None:
                restart = restart_rng.permutation(n)
            while cemented[restart[ptr]]:
                ptr += 1
            c = int(restart[ptr])
        else:
            cand = np.array(sorted(frontier))
            cum = np.cumsum(np.maximum(dist[cand], 1e-12))
            pick = np.searchsorted(cum, next(uniforms) * cum[-1], side="right")
            c = int(cand[min(pick, cand.size - 1)])
            frontier.discard(c)
        cemented[c] = True
        count += 1
        frontier.update(int(nb) for nb in nbrs[c] if nb >= 0 and not cemented[nb])
    return cemented


def synthetic_lattice(seed, shape=(9, 7, 10), solid_fraction=0.5, dtype=np.float32):
    """A random pore space cut in two by a solid layer (k = 4) and with isolated pockets, so
    that growth must restart in pores the cement does not reach; distances on a coarse grid
    (many ties)."""
    from md.cement import CementLattice

    rng = np.random.default_rng(seed)
    nx, ny, nz = shape
    solid = rng.random(nx * ny * nz) < solid_fraction
    solid[4 * nx * ny:5 * nx * ny] = True
    index = np.flatnonzero(~solid).astype(np.int32)
    kind = rng.choice(np.array([BODY, SURFACE, CONTACT], np.int8), size=index.size,
                      p=[0.6, 0.3, 0.1])
    kind[index >= 5 * nx * ny] = np.where(kind[index >= 5 * nx * ny] == CONTACT, SURFACE,
                                          kind[index >= 5 * nx * ny])  # no contacts on top
    distance = (rng.integers(0, 6, index.size) * 1e-5).astype(dtype)
    return CementLattice(1e-5, shape, 0.0, index, kind, distance)


def lattices_for_growth():
    out = [cement_lattice(make_pack(np.random.default_rng(s), n=n), resolution=res)
           for s, n, res in ((1, 12, 2.0), (2, 14, 2.5), (3, 10, 2.0))]
    out += [synthetic_lattice(4), synthetic_lattice(5, dtype=np.float64),
            synthetic_lattice(6, shape=(1, 5, 12), solid_fraction=0.2)]
    return out


@pytest.fixture(scope="module")
def growth_lattices():
    return lattices_for_growth()


def test_neighbour_map_matches_the_definition(growth_lattices):
    from md.growth import _neighbour_map

    for lat in growth_lattices:
        nbrs = _neighbour_map(lat)
        assert nbrs.dtype == np.int32 and nbrs.shape == (lat.index.size, 6)
        np.testing.assert_array_equal(nbrs, reference_neighbours(lat))


def test_distance_levels_keep_the_order_and_the_ties(rng):
    from md.growth import _distance_levels

    values = np.array([-3.5, -1e-30, -0.0, 0.0, 1e-30, 2.0, np.inf, -np.inf], np.float32)
    d = rng.choice(values, 200).astype(np.float32)
    for dist in (d, d.astype(np.float64)):
        levels = _distance_levels(dist)
        assert levels.dtype == np.uint32
        order = np.argsort(dist, kind="stable")
        np.testing.assert_array_equal(np.argsort(levels, kind="stable"), order)
        ties = dist[order][1:] == dist[order][:-1]
        np.testing.assert_array_equal(levels[order][1:] == levels[order][:-1], ties)


SATURATIONS = (0.004, 0.03, 0.1, 0.35, 0.8, 1.0)


def test_contact_cement_equals_the_heap_reference(growth_lattices):
    for lat in growth_lattices:
        n_contact = int(np.sum(lat.kind == CONTACT))
        for s in SATURATIONS + (n_contact / lat.index.size,):
            np.testing.assert_array_equal(grow_cement(lat, s, "contact"),
                                          contact_reference(lat, s), err_msg=f"S_c {s}")


def test_coating_cement_equals_the_sorted_reference(growth_lattices):
    for lat in growth_lattices:
        for s in SATURATIONS:
            np.testing.assert_array_equal(grow_cement(lat, s, "coating"),
                                          coating_reference(lat, s), err_msg=f"S_c {s}")


def test_pore_body_cement_equals_the_python_twin(growth_lattices, monkeypatch):
    import md.growth

    for lat in growth_lattices:
        for s, seed in ((0.002, 0), (0.3, 1), (1.0, 2)):
            expected = pore_body_twin(lat, s, seed)
            np.testing.assert_array_equal(grow_cement(lat, s, "pore_body", seed=seed),
                                          expected, err_msg=f"S_c {s}")
    # Chunks of uniforms handed to the kernel: the result does not depend on their size.
    lat = growth_lattices[3]
    expected = grow_cement(lat, 0.9, "pore_body", seed=7)
    monkeypatch.setattr(md.growth, "_PORE_BODY_CHUNK", 3)
    np.testing.assert_array_equal(grow_cement(lat, 0.9, "pore_body", seed=7), expected)


@pytest.mark.parametrize("scheme", ["contact", "coating", "pore_body"])
def test_growth_is_nested_in_saturation(growth_lattices, scheme):
    for lat in growth_lattices:
        previous = np.zeros(lat.index.size, dtype=bool)
        for s in (0.0, 0.001, 0.01, 0.05, 0.2, 0.5, 0.9, 1.0):
            cem = grow_cement(lat, s, scheme, seed=11)
            assert cem.sum() == round(s * lat.index.size)
            assert np.all(cem[previous])
            previous = cem


def test_pore_body_cement_depends_on_the_seed(lattice):
    a = grow_cement(lattice, 0.3, "pore_body", seed=1)
    b = grow_cement(lattice, 0.3, "pore_body", seed=2)
    assert a.sum() == b.sum() and np.any(a != b)


@pytest.mark.parametrize("fanout", [2, 3, 8])
def test_sum_tree_picks_follow_the_weights(rng, fanout):
    from scipy.stats import chisquare

    from md._kernels_cement import _tree_set, tree_build, tree_pick, tree_picks
    from md.growth import _sum_tree

    n = 70
    weights = rng.integers(1, 20, n).astype(float)
    weights[rng.random(n) < 0.3] = 0.0                      # not in the frontier
    tree, offsets = _sum_tree(n, fanout)
    # Built by single updates (in random order), the sums equal a build from the leaves.
    for c in rng.permutation(n):
        _tree_set(tree, offsets, fanout, c, weights[c])
    rebuilt = tree.copy()
    tree_build(rebuilt, offsets, fanout)
    np.testing.assert_array_equal(tree, rebuilt)
    # With integer weights the arithmetic is exact: a pick is where the running sum passes u W.
    cum = np.cumsum(weights)
    for u in np.append(rng.random(500), [0.0, np.nextafter(1.0, 0.0)]):
        expected = min(np.searchsorted(cum, u * cum[-1], side="right"), n - 1)
        assert tree_pick(tree, offsets, fanout, u) == expected
    # Frequencies of 2e5 picks against the weights (chi-square, fixed seed).
    out = np.empty(200_000, dtype=np.int64)
    tree_picks(tree, offsets, fanout, rng.random(out.size), out)
    counts = np.bincount(out, minlength=n)
    assert np.all(counts[weights == 0] == 0)
    live = weights > 0
    expected = out.size * weights[live] / weights.sum()
    assert chisquare(counts[live], expected).pvalue > 1e-3


def test_sum_tree_never_picks_outside_the_frontier(rng):
    from md._kernels_cement import _tree_set, tree_pick
    from md.growth import _sum_tree

    # Weights spanning 30 orders of magnitude and many removals: rounding must not lead the
    # descent to a cell of zero weight.
    n = 5000
    tree, offsets = _sum_tree(n, 8)
    weights = 10.0 ** rng.uniform(-12, 18, n)
    for c in range(n):
        _tree_set(tree, offsets, 8, c, weights[c])
    for c in rng.permutation(n)[: n - 40]:
        _tree_set(tree, offsets, 8, c, 0.0)
    live = set(np.flatnonzero(tree[:n] > 0).tolist())
    assert len(live) == 40
    for u in np.append(rng.random(2000), [np.nextafter(1.0, 0.0)]):
        assert tree_pick(tree, offsets, 8, u) in live


@pytest.mark.parametrize("kwargs,name", [(dict(seed=-1), "seed"), (dict(seed=1.5), "seed"),
                                         (dict(seed=True), "seed")])
def test_growth_bad_seed(lattice, expect_value_error, kwargs, name):
    expect_value_error(lambda: grow_cement(lattice, 0.1, "pore_body", **kwargs), name)


def test_growth_rejects_non_finite_distances(expect_value_error):
    lat = synthetic_lattice(8)
    lat.distance[3] = np.nan
    expect_value_error(lambda: grow_cement(lat, 0.1, "contact"), "distance")


@pytest.mark.parametrize("scheme", ["contact", "coating", "pore_body"])
def test_float32_distances_grow_the_same_cement_as_float64(rng, scheme):
    """The lattice stores the distance to the grains as float32 (half the memory). Growing
    cement from the exact float64 distances (brute force) cements the same cells but for
    rounding ties (none on this pack; at most 0.5 % of the cemented cells may differ)."""
    import dataclasses

    pack = make_pack(rng, n=14)
    lat = cement_lattice(pack, resolution=4.0, reach=1e-3)
    solid, _, dist = brute_force(pack, lat)
    exact = dataclasses.replace(lat, distance=np.minimum(dist[~solid], 1e-3))
    for sc in (0.05, 0.2, 0.5):
        a = grow_cement(lat, sc, scheme, seed=4)
        b = grow_cement(exact, sc, scheme, seed=4)
        assert np.count_nonzero(a != b) <= 0.005 * 2 * a.sum()


@pytest.mark.parametrize("scheme", ["contact", "coating", "pore_body", "pendular"])
def test_one_growth_serves_a_saturation_sweep(lattice, scheme):
    """cement_sweep (one growth, prefixes of its order) = grow_cement at every saturation."""
    from md.cement import cement_order, cement_sweep

    sats = [0.0, 0.003, 0.05, 0.2, 0.5]
    sweep = cement_sweep(lattice, sats, scheme, seed=4)
    for row, s in zip(sweep, sats):
        assert np.array_equal(row, grow_cement(lattice, s, scheme, seed=4))
    order = cement_order(lattice, 0.5, scheme, seed=4)
    assert np.unique(order).size == order.size == round(0.5 * lattice.index.size)
