"""Ballistic settling of small grain packs: sequential deposition (the source's protocol) and
the faster release of all grains at once, at laptop-test sizes."""

import numpy as np
import pytest

from md.deposit import drop_speed
from md.observe import core_window
from md.protocols import coordination_number, porosity, settle
from md.state import load_pack, save_pack

OPTIONS = dict(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=1, kinetic_tolerance=1e-5)


@pytest.fixture(scope="module")
def pack():
    return settle(**OPTIONS, protocol="lattice")


@pytest.fixture(scope="module")
def sequential():
    return settle(**OPTIONS)


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
    """A random loose pack: the paper's settled sample has porosity 0.412. Coordination of a
    gravity-deposited frictional pack: 4-6. The porosity is that of the core window between
    the slabs a compaction would freeze, recorded with the pack."""
    phi = porosity(pack)
    assert 0.36 < phi < 0.47
    assert phi == pytest.approx(pack.metadata["porosity"], rel=1e-12)
    lo, hi = core_window(pack)
    assert [lo, hi] == pack.metadata["core_window_m"]
    z, r = pack.positions[:, 2], pack.radii
    assert lo > z.min() + 2 * r.max() and hi < z.max() - 2 * r.max()
    assert 3.0 <= coordination_number(pack) <= 6.5


def test_settle_is_reproducible_with_a_seed(sequential):
    again = settle(**OPTIONS)
    np.testing.assert_array_equal(again.positions, sequential.positions)
    np.testing.assert_array_equal(again.radii, sequential.radii)


def test_sequential_deposition_drops_waves_and_comes_to_rest(sequential):
    """Waves of at most a fifth of a monolayer (2 grains on a 3 x 3 floor), all grains in the
    box above the floor, at rest, with the core porosity recorded."""
    p = sequential
    md = p.metadata
    assert md["protocol"] == "sequential" and md["wave"] == 2
    assert md["waves"] == int(np.ceil(p.n_grains / 2))
    r, z = p.radii, p.positions[:, 2]
    assert np.min(z - r) > -0.01 * r.max()
    m = 4 / 3 * np.pi * r**3 * p.material.density
    assert 0.5 * np.sum(m[:, None] * p.velocities**2) / p.n_grains < 1e-5 * m.max() * 9.81 * 4e-4
    assert md["porosity"] == pytest.approx(porosity(p), rel=1e-12)
    assert 0.2 < md["porosity"] < 0.5


def test_drop_speed_against_the_integrated_fall():
    """drop_speed against scipy's integration of dv/dt = g - k v, dz/dt = v (no drag: the
    free fall sqrt(2 g h))."""
    from scipy.integrate import solve_ivp

    k, h = 50.0, 3e-3

    def hit(t, y):
        return y[1] - h
    hit.terminal = True
    sol = solve_ivp(lambda t, y: [9.81 - k * y[0], y[0]], (0, 1), [0.0, 0.0], events=hit,
                    rtol=1e-12, atol=1e-15)
    assert drop_speed(h, k) == pytest.approx(sol.y_events[0][0][0], rel=1e-8)
    assert drop_speed(h, 0.0) == pytest.approx(np.sqrt(2 * 9.81 * h), rel=1e-14)
    # A long fall through a viscous fluid ends at the terminal speed g / k.
    assert drop_speed(1.0, 500.0) == pytest.approx(9.81 / 500.0, rel=1e-14)
    with pytest.raises(ValueError, match="height"):
        drop_speed(-1.0, k)
    with pytest.raises(ValueError, match="drag"):          # was a negative speed
        drop_speed(1e-3, -k)


def test_settled_pack_round_trip(pack, tmp_path):
    back = load_pack(save_pack(pack, tmp_path / "settled.nc"))
    np.testing.assert_array_equal(back.positions, pack.positions)
    assert back.metadata == pack.metadata


@pytest.mark.parametrize("kwargs,match", [
    (dict(radius_range=(2e-4, 1e-4)), "radius_range"),
    (dict(size=(2, 8, 8)), "size"),
    (dict(size=(8, 8)), "size"),
    (dict(size=(3, 3, 4)), "size"),
    (dict(protocol="rain"), "protocol"),
    (dict(wave=0), "wave"),
    (dict(drop_height=0.0), "drop_height"),
    (dict(fall_stiffness_factor=0.0), "fall_stiffness_factor"),
    (dict(drag=-1.0), "drag"),
    (dict(kinetic_tolerance=0.0), "kinetic_tolerance"),
    (dict(max_time=-1.0), "max_time"),
])
def test_settle_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        settle(**kwargs)
