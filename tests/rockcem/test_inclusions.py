"""Berryman P, Q and the self-consistent solver (rockcem.inclusions)."""

import numpy as np
import pytest
from scipy.optimize import root

from rockcem.bounds import hashin_shtrikman
from rockcem.inclusions import berryman_pq, self_consistent

KQ, GQ = 40.0, 39.0      # quartz, Carcione et al. 2022 Table 1
KC, GC = 35.0, 30.0      # cement, same table
KW = 2.2                 # water


def zeta(K, G):
    return G / 6.0 * (9.0 * K + 8.0 * G) / (K + 2.0 * G)


def beta_m(K, G):
    return G * (3.0 * K + G) / (3.0 * K + 4.0 * G)


# --- P and Q: limits tabulated by Berryman (1980) / Mavko et al. (2009) Table 4.8.1 -------------
@pytest.mark.parametrize("Ki,Gi", [(KW, 0.0), (0.0, 0.0), (KC, GC), (1e-3, 0.0)])
def test_pq_sphere_closed_form(Ki, Gi):
    P, Q = berryman_pq(KQ, GQ, Ki, Gi, 1.0)
    assert P == pytest.approx((KQ + 4 / 3 * GQ) / (Ki + 4 / 3 * GQ), rel=1e-14)
    assert Q == pytest.approx((GQ + zeta(KQ, GQ)) / (Gi + zeta(KQ, GQ)), rel=1e-14)


@pytest.mark.parametrize("Ki,Gi", [(KW, 0.0), (KC, GC), (5.0, 1.0)])
@pytest.mark.parametrize("eps", [1e-9, 1e-6, 1e-3, 0.05, 0.0999, 0.1001])
def test_pq_continuous_through_sphere(Ki, Gi, eps):
    """The spheroid formulas tend to the sphere ones from both sides (no 0/0 cancellation)."""
    P0, Q0 = berryman_pq(KQ, GQ, Ki, Gi, 1.0)
    for a in (1.0 - eps, 1.0 + eps):
        P, Q = berryman_pq(KQ, GQ, Ki, Gi, a)
        # P, Q are smooth in the aspect ratio: the change is O(eps).
        assert abs(P / P0 - 1) < 2.0 * eps + 1e-13
        assert abs(Q / Q0 - 1) < 2.0 * eps + 1e-13


def test_pq_penny_crack_limit():
    """Thin oblate cracks: P = Km/(Ki + pi a beta_m), Q of Mavko Table 4.8.1 (leading order in a)."""
    a = 1e-5
    for Ki, Gi in [(KW, 0.0), (0.0, 0.0)]:
        P, Q = berryman_pq(KQ, GQ, Ki, Gi, a)
        b = beta_m(KQ, GQ)
        P_ref = KQ / (Ki + np.pi * a * b)
        Q_ref = 0.2 * (1 + 8 * GQ / (4 * Gi + np.pi * a * (GQ + 2 * b))
                       + 2 * (Ki + 2 / 3 * (Gi + GQ)) / (Ki + 4 / 3 * Gi + np.pi * a * b))
        assert P == pytest.approx(P_ref, rel=1e-3)
        assert Q == pytest.approx(Q_ref, rel=1e-3)


def test_pq_needle_limit():
    """Prolate needles (aspect ratio -> infinity), Mavko et al. 2009 Table 4.8.1."""
    Ki, Gi = KC * 0.2, GC * 0.1
    P, Q = berryman_pq(KQ, GQ, Ki, Gi, 1e5)
    gam = GQ * (3 * KQ + GQ) / (3 * KQ + 7 * GQ)
    P_ref = (KQ + GQ + Gi / 3) / (Ki + GQ + Gi / 3)
    Q_ref = 0.2 * (4 * GQ / (GQ + Gi) + 2 * (GQ + gam) / (Gi + gam)
                   + (Ki + 4 / 3 * GQ) / (Ki + GQ + Gi / 3))
    assert P == pytest.approx(P_ref, rel=1e-3)
    assert Q == pytest.approx(Q_ref, rel=1e-3)


def test_pq_disk_limit():
    """Flat solid disks (aspect ratio -> 0), Mavko et al. 2009 Table 4.8.1."""
    Ki, Gi = 20.0, 10.0
    P, Q = berryman_pq(KQ, GQ, Ki, Gi, 1e-7)
    assert P == pytest.approx((KQ + 4 / 3 * Gi) / (Ki + 4 / 3 * Gi), rel=1e-4)
    assert Q == pytest.approx((GQ + zeta(Ki, Gi)) / (Gi + zeta(Ki, Gi)), rel=1e-4)


# --- self-consistent solver ----------------------------------------------------------------------
def _scipy_sc(K, G, f, a):
    """Independent solution: scipy's hybrid Powell root finder on eq. 8, point by point."""
    def fun(x):
        k, g = np.exp(x)
        P, Q = berryman_pq(k, g, np.asarray(K), np.asarray(G), np.asarray(a))
        return [np.sum(f * (np.asarray(K) - k) * P) / k, np.sum(f * (np.asarray(G) - g) * Q) / g]
    hs = hashin_shtrikman(K, G, f)
    sol = root(fun, np.log([float(hs.K_upper), float(hs.G_upper)]), tol=1e-13)
    assert np.max(np.abs(fun(sol.x))) < 1e-12, sol.message
    return np.exp(sol.x)


@pytest.mark.parametrize("case", [
    ([KQ, KC, KW], [GQ, GC, 0.0], [0.6, 0.1, 0.3], [1, 1, 0.108]),
    ([KQ, KC, KW], [GQ, GC, 0.0], [0.6, 0.1, 0.3], [1, 1, 1.0]),
    ([9.0, 33.0, KW], [6.0, 28.0, 0.0], [0.3, 0.4, 0.3], [1, 1, 0.17]),
    ([KQ, KW], [GQ, 0.0], [0.9, 0.1], [1, 4.0]),
    ([KQ, 0.0], [GQ, 0.0], [0.9, 0.1], [1, 0.3]),
])
def test_sc_matches_scipy_root(case):
    K, G, f, a = case
    m = self_consistent(K, G, f, a)
    ref = _scipy_sc(*map(np.asarray, case))
    np.testing.assert_allclose([float(m.K), float(m.G)], ref, rtol=1e-9)


def test_sc_spheres_satisfy_hs_form():
    """For spheres, SC solves K = Lambda(G_sc), G = Gamma(zeta(K_sc, G_sc)) (Berryman 1980)."""
    K, G, f = np.array([KQ, KC, KW]), np.array([GQ, GC, 0.0]), np.array([0.5, 0.2, 0.3])
    m = self_consistent(K, G, f)
    k, g = float(m.K), float(m.G)
    lam = 1 / np.sum(f / (K + 4 / 3 * g)) - 4 / 3 * g
    z = zeta(k, g)
    gam = 1 / np.sum(f / (G + z)) - z
    assert k == pytest.approx(lam, rel=1e-11)
    assert g == pytest.approx(gam, rel=1e-11)


def test_sc_single_phase_and_bounds(rng):
    n = 200
    K = rng.uniform(1, 80, (n, 3))
    G = rng.uniform(0.5, 60, (n, 3))
    f = rng.dirichlet([1, 1, 1], n)
    a = rng.uniform(0.05, 5.0, (n, 3))
    m = self_consistent(K, G, f, a)
    hs = hashin_shtrikman(K, G, f)
    assert np.all(m.K >= hs.K_lower * (1 - 1e-9)) and np.all(m.K <= hs.K_upper * (1 + 1e-9))
    one = self_consistent(K, G, np.eye(3)[np.zeros(n, int)], a)
    np.testing.assert_allclose(one.K, K[:, 0], rtol=1e-12)
    np.testing.assert_allclose(one.G, G[:, 0], rtol=1e-12)


def test_sc_vectorised_equals_loop(rng):
    K = np.array([KQ, KC, KW])
    G = np.array([GQ, GC, 0.0])
    phi = rng.uniform(0.0, 0.4, 20)
    f = np.stack([1 - phi - 0.05, np.full(20, 0.05), phi], -1)
    vec = self_consistent(K, G, f, [1, 1, 0.1])
    for i in range(20):
        one = self_consistent(K, G, f[i], [1, 1, 0.1])
        assert float(one.K) == pytest.approx(vec.K[i], rel=1e-10)
        assert float(one.G) == pytest.approx(vec.G[i], rel=1e-10)


def test_sc_dry_spheres_percolate_at_half():
    """SC with spherical voids loses all stiffness at porosity 1/2 (Berryman 1980)."""
    below = self_consistent([KQ, 0.0], [GQ, 0.0], [[0.6, 0.4], [0.52, 0.48]])
    assert np.all(below.K > 0) and np.all(below.G > 0)
    assert np.all(np.diff(below.G) < 0)
    above = self_consistent([KQ, 0.0], [GQ, 0.0], [0.45, 0.55])
    assert float(above.K) == 0.0 and float(above.G) == 0.0


def test_sc_fluid_suspension_is_reuss():
    """Beyond shear percolation a fluid-supported mixture has G = 0 and K = Reuss exactly."""
    m = self_consistent([KQ, KW], [GQ, 0.0], [0.4, 0.6])
    assert float(m.G) == 0.0
    assert float(m.K) == pytest.approx(1 / (0.4 / KQ + 0.6 / KW), rel=1e-14)


# --- stiff and extreme cases ---------------------------------------------------------------------
def test_sc_flat_cracks():
    """Aspect ratio 1e-4: finite, between the bounds, and matching the independent solver."""
    f = [1 - 1e-5, 1e-5]
    m = self_consistent([KQ, KW], [GQ, 0.0], f, [1, 1e-4])
    ref = _scipy_sc(np.array([KQ, KW]), np.array([GQ, 0.0]), np.array(f), np.array([1, 1e-4]))
    np.testing.assert_allclose([float(m.K), float(m.G)], ref, rtol=1e-9)
    # Dense crack population: the shear stiffness collapses to exactly zero, K to Reuss.
    dense = self_consistent([KQ, KW], [GQ, 0.0], [0.99, 0.01], [1, 1e-4])
    assert float(dense.G) == 0.0
    assert float(dense.K) == pytest.approx(1 / (0.99 / KQ + 0.01 / KW), rel=1e-12)


def test_sc_stiffness_contrast_1e6():
    K, G, f = np.array([40e6, 1.0]), np.array([39e6, 1.0]), np.array([0.5, 0.5])
    m = self_consistent(K, G, f)
    hs = hashin_shtrikman(K, G, f)
    assert np.isfinite(m.K) and np.isfinite(m.G)
    assert hs.K_lower <= m.K <= hs.K_upper
    assert hs.G_lower <= m.G <= hs.G_upper
    np.testing.assert_allclose([float(m.K), float(m.G)], _scipy_sc(K, G, f, np.ones(2)), rtol=1e-8)


def test_sc_reports_non_convergence():
    with pytest.raises(RuntimeError, match="did not converge"):
        self_consistent([KQ, KC, KW], [GQ, GC, 0.0], [0.6, 0.1, 0.3], [1, 1, 0.1], max_iter=1)


def test_sc_full_output():
    m, info = self_consistent([KQ, KW], [GQ, 0.0], [[0.8, 0.2], [0.7, 0.3]], full_output=True)
    assert info.converged.all() and info.iterations.shape == (2,)
    assert np.all(info.residual < 1e-10)


@pytest.mark.parametrize("kwargs,match", [
    (dict(K=[KQ, -1.0], G=[GQ, 0.0], fractions=[0.5, 0.5]), "K"),
    (dict(K=[KQ, KW], G=[GQ, 0.0], fractions=[0.5, 0.6]), "fractions"),
    (dict(K=[KQ, KW], G=[GQ, 0.0], fractions=[0.5, 0.5], aspect_ratio=[1, 0.0]), "aspect_ratio"),
    (dict(K=[KQ, KW], G=[GQ, 0.0], fractions=[0.5, 0.5], tol=0.0), "tol"),
    (dict(K=[KQ, KW, 1.0], G=[GQ, 0.0], fractions=[0.5, 0.5]), "broadcast"),
])
def test_sc_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        self_consistent(**kwargs)


def test_pq_bad_matrix():
    with pytest.raises(ValueError, match="G_m"):
        berryman_pq(KQ, 0.0, KW, 0.0, 0.1)
