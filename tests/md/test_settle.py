"""Ballistic settling of a small grain pack (the paper's protocol at a laptop-test size)."""

import numpy as np
import pytest

from md.protocols import coordination_number, porosity, settle
from md.state import load_pack, save_pack


@pytest.fixture(scope="module")
def pack():
    return settle(size=(3, 3, 4), fall_stiffness_factor=1e-3, seed=1, kinetic_tolerance=1e-5)


def test_settled_pack_is_at_rest_on_the_floor(pack):
    r, z = pack.radii, pack.positions[:, 2]
    m = 4 / 3 * np.pi * r**3 * pack.material.density
    ke = 0.5 * np.sum(m[:, None] * pack.velocities**2) / pack.n_grains
    # Rest: mean kinetic energy per grain below 1e-5 m g d (the run's criterion) ...
    assert ke < 1e-5 * m.max() * 9.81 * 4e-4
    # ... so no grain moves faster than a few per cent of sqrt(g d) = 6 cm/s.
    assert np.linalg.norm(pack.velocities, axis=1).max() < 0.05 * np.sqrt(9.81 * 4e-4)
    # On the floor, not through it: overlaps are a small fraction of a radius (Hertz at rest).
    assert np.min(z - r) > -0.01 * r.max()
    assert pack.stage == "settle" and pack.metadata["n_grains"] == pack.n_grains


def test_settled_pack_porosity_and_coordination(pack):
    """A random loose pack: the paper's settled sample has porosity 0.412; a small sample with
    a floor sits a little looser. Coordination of a gravity-deposited frictional pack: 4-6."""
    phi = porosity(pack)
    assert 0.36 < phi < 0.47
    assert phi == pytest.approx(pack.metadata["porosity"], rel=1e-12)
    assert 3.0 <= coordination_number(pack) <= 6.5


def test_settle_is_reproducible_with_a_seed(pack):
    again = settle(size=(3, 3, 4), fall_stiffness_factor=1e-3, seed=1, kinetic_tolerance=1e-5)
    np.testing.assert_array_equal(again.positions, pack.positions)
    np.testing.assert_array_equal(again.radii, pack.radii)


def test_settled_pack_round_trip(pack, tmp_path):
    back = load_pack(save_pack(pack, tmp_path / "settled.nc"))
    np.testing.assert_array_equal(back.positions, pack.positions)
    assert back.metadata == pack.metadata


@pytest.mark.parametrize("kwargs,match", [
    (dict(radius_range=(2e-4, 1e-4)), "radius_range"),
    (dict(size=(2, 8, 8)), "size"),
    (dict(size=(8, 8)), "size"),
    (dict(fall_stiffness_factor=0.0), "fall_stiffness_factor"),
    (dict(drag=-1.0), "drag"),
])
def test_settle_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        settle(**kwargs)
