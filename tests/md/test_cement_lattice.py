"""The cement lattice: cell classes and distances against a brute-force evaluation."""

import numpy as np
import pytest

from md.cement import BODY, CONTACT, SURFACE, cement_lattice
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
