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


def test_lattice_matches_brute_force(rng):
    pack = make_pack(rng)
    lat = cement_lattice(pack, resolution=3.0, reach=1e-3)
    solid, touches, dist = brute_force(pack, lat)
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


@pytest.mark.parametrize("scheme", ["contact", "coating", "pore_body"])
def test_growth_reaches_the_saturation(lattice, scheme):
    for s in (0.0, 0.05, 0.2, 1.0):
        cem = grow_cement(lattice, s, scheme, seed=3)
        assert cem.sum() == round(s * lattice.index.size)


def test_coating_fills_by_distance_and_nests(lattice):
    a = grow_cement(lattice, 0.1, "coating")
    b = grow_cement(lattice, 0.3, "coating")
    assert np.all(b[a])                                    # nested
    assert lattice.distance[a].max() <= lattice.distance[~b].min()


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
