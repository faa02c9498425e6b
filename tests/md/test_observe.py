"""Observables: static contact forces with the tangential spring, slab weights of the virial,
the Hertz overlap of a stress, and the blow-up limit that scales with it."""

import numpy as np
import pytest

from md._dynamics import MIN_OVERLAP, OVERLAP_FACTOR, check_overlaps, overlap_limit
from md.contact import QUARTZ, hertz_force, pair_force_reference
from md.observe import (contact_forces, contact_stress, expected_overlap, group_force,
                        segment_fraction)
from md.space import Box

R = 2e-4
M = 4 / 3 * np.pi * R**3 * QUARTZ.density


def test_static_force_is_the_kernel_force_at_rest():
    """contact_forces with a history equals the Hertz–Mindlin pair force (the plain-Python
    twin of the kernel) at zero relative velocity: below the Coulomb cap and above it."""
    rng = np.random.default_rng(3)
    box = Box(5e-3, 5e-3, 0.0, 5e-3)
    for scale in (1e-9, 1e-6):                    # spring holds / slides
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        xi = 5e-7
        x = np.array([[2e-3, 2e-3, 2e-3], [0.0, 0.0, 0.0]])
        x[1] = x[0] + (2 * R - xi) * n
        zeta = rng.normal(scale=scale, size=3)
        f, branch = contact_forces(x, np.array([R, R]), np.array([[0, 1]]), box, QUARTZ,
                                   zeta[None, :])
        # pair_force_reference advances zeta by v_t dt: with v = 0 it only projects it.
        ref, _, fn = pair_force_reference(xi, n, np.zeros(3), zeta, R / 2, M / 2, QUARTZ, 0.1,
                                          1e-8)
        np.testing.assert_allclose(f[0], ref, rtol=1e-9, atol=1e-12 * fn)
        np.testing.assert_allclose(branch[0], x[1] - x[0], rtol=1e-12)


def test_segment_fraction_of_simple_segments():
    za = np.array([0.0, 0.5, -1.0, 2.0, 0.5, 1.0])
    dz = np.array([2.0, 0.2, 0.5, -1.5, 0.0, 0.0])
    w = segment_fraction(za, dz, 0.0, 1.0)
    np.testing.assert_allclose(w, [0.5, 1.0, 0.0, 1 / 3, 1.0, 0.5])


def test_virial_of_a_column_equals_the_force_across_it():
    """A vertical column of grains, each contact carrying the same force F: sigma_zz of any
    slab inside is F / A, and the force on the top grain from the others is F."""
    xi, n = 1e-7, 6
    x = np.zeros((n, 3)) + 1e-3
    x[:, 2] = np.arange(n) * (2 * R - xi)
    r = np.full(n, R)
    pairs = np.array([[i, i + 1] for i in range(n - 1)])
    box = Box(2e-3, 3e-3, 0.0, 3e-3)
    F = float(hertz_force(xi, R / 2, QUARTZ.E_f))
    for window in ((0.0, x[-1, 2]), (0.3 * R, 3.7 * R), (1.1 * R, 1.2 * R)):
        s = contact_stress(x, r, pairs, box, QUARTZ, z_range=window)
        assert s[2, 2] == pytest.approx(F / (box.lx * box.ly), rel=1e-9)
    top = np.zeros(n, bool)
    top[-1] = True
    np.testing.assert_allclose(group_force(x, r, pairs, box, QUARTZ, top), [0, 0, F],
                               atol=1e-9 * F)


def test_expected_overlap_of_a_simple_cubic_lattice():
    """Simple cubic lattice (Z = 6, phi = 1 - pi/6), every contact at overlap xi: the mean
    stress is F / (4 R^2) (one contact per axis per cell of side 2R), and the estimate
    inverts it exactly."""
    xi = 3e-7
    F = float(hertz_force(xi, R / 2, QUARTZ.E_f))
    p = F / (4 * R**2)
    assert expected_overlap(p, R, 1 - np.pi / 6, 6.0, QUARTZ) == pytest.approx(xi, rel=1e-9)
    with pytest.raises(ValueError, match="stress"):
        expected_overlap(-1.0, R, 0.4, 6.0, QUARTZ)
    with pytest.raises(ValueError, match="stress"):         # was a silent NaN
        expected_overlap(np.nan, R, 0.4, 6.0, QUARTZ)


def test_overlap_limit_scales_with_the_stress_and_catches_a_blow_up():
    """A simple cubic block under a stress where the old fixed limit (5 % of R) is exceeded by
    sound Hertz overlaps (150 MPa: 6.3 % of R) passes; one contact pushed to ten times the
    lattice overlap is caught."""
    xi = 0.063 * R
    k = 4
    g = np.stack(np.meshgrid(*[np.arange(k)] * 3, indexing="ij"), -1).reshape(-1, 3)
    a = 2 * R - xi
    x = (g * a + R).astype(float)
    r = np.full(len(x), R)
    box = Box(k * a, k * a, 0.0, k * a)
    from md.neighbors import build_neighbors

    pairs = build_neighbors(x, r, box, 0.1 * R).pairs
    F = float(hertz_force(xi, R / 2, QUARTZ.E_f))
    assert F / (4 * R**2) > 100e6
    limit = overlap_limit(x, r, pairs, box, QUARTZ)
    assert limit > xi > MIN_OVERLAP * R
    assert limit <= OVERLAP_FACTOR * 1.5 * xi
    check_overlaps("compact", x, r, pairs, box, QUARTZ)
    y = x.copy()
    y[0, 2] += 9 * xi                             # grain 0 driven into its upper neighbour
    with pytest.raises(RuntimeError, match="compact: the integration blew up"):
        check_overlaps("compact", y, r, pairs, box, QUARTZ)


def test_porosity_counts_overlapping_grains_once():
    """Two grains overlapping by a fifth of a radius: the porosity of a slab holding both is
    that of their union, the spheres less the lens (two caps of Archimedes)."""
    import md
    from md.observe import porosity

    r = 1e-4
    d = 1.8 * r
    x = np.array([[3e-4, 3e-4, 3e-4], [3e-4, 3e-4, 3e-4 + d]])
    z = np.zeros_like(x)
    pack = md.Pack(x, z, z.copy(), np.full(2, r), Box(6e-4, 6e-4, 0.0, 1e-3), md.QUARTZ,
                   np.zeros((0, 2), np.int32), np.zeros((0, 3)))
    h = r - d / 2
    lens = 2 * np.pi * h * h * (3 * r - h) / 3
    union = 2 * 4 / 3 * np.pi * r**3 - lens
    assert porosity(pack, bottom=0.0, top=1e-3) == pytest.approx(
        1 - union / (6e-4 * 6e-4 * 1e-3), abs=1e-12)
