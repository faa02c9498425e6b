"""Berryman P, Q and the self-consistent solver (rockcem.inclusions)."""

import numpy as np
import pytest
from scipy.optimize import root

from rockcem import inclusions
from rockcem.bounds import hashin_shtrikman
from rockcem.inclusions import berryman_pq, self_consistent

KQ, GQ = 40.0, 39.0      # quartz, Carcione et al. 2022 Table 1
KC, GC = 35.0, 30.0      # cement, same table
KW = 2.2                 # water


@pytest.fixture(params=["numpy", "numba"])
def engine(request, monkeypatch):
    """Run a solver test on both paths of self_consistent: the vectorised numpy iteration and
    the numba kernel (normally taken from inclusions._NUMBA_MIN_POINTS points on)."""
    if request.param == "numba":
        pytest.importorskip("numba")
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0 if request.param == "numba" else 2**62)
    return request.param


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
    """Thin oblate cracks: P = Km/(Ki + pi a beta_m), Q of Mavko Table 4.8.1 (leading order
    in a)."""
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
def test_sc_matches_scipy_root(case, engine):
    K, G, f, a = case
    m = self_consistent(K, G, f, a)
    ref = _scipy_sc(*map(np.asarray, case))
    np.testing.assert_allclose([float(m.K), float(m.G)], ref, rtol=1e-9)


def test_sc_spheres_satisfy_hs_form(engine):
    """For spheres, SC solves K = Lambda(G_sc), G = Gamma(zeta(K_sc, G_sc)) (Berryman 1980)."""
    K, G, f = np.array([KQ, KC, KW]), np.array([GQ, GC, 0.0]), np.array([0.5, 0.2, 0.3])
    m = self_consistent(K, G, f)
    k, g = float(m.K), float(m.G)
    lam = 1 / np.sum(f / (K + 4 / 3 * g)) - 4 / 3 * g
    z = zeta(k, g)
    gam = 1 / np.sum(f / (G + z)) - z
    assert k == pytest.approx(lam, rel=1e-11)
    assert g == pytest.approx(gam, rel=1e-11)


def test_sc_single_phase_and_bounds(rng, engine):
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


def test_sc_vectorised_equals_loop(rng, engine):
    K = np.array([KQ, KC, KW])
    G = np.array([GQ, GC, 0.0])
    phi = rng.uniform(0.0, 0.4, 20)
    f = np.stack([1 - phi - 0.05, np.full(20, 0.05), phi], -1)
    vec = self_consistent(K, G, f, [1, 1, 0.1])
    for i in range(20):
        one = self_consistent(K, G, f[i], [1, 1, 0.1])
        assert float(one.K) == pytest.approx(vec.K[i], rel=1e-10)
        assert float(one.G) == pytest.approx(vec.G[i], rel=1e-10)


def test_sc_dry_spheres_percolate_at_half(engine):
    """SC with spherical voids loses all stiffness at porosity 1/2 (Berryman 1980)."""
    below = self_consistent([KQ, 0.0], [GQ, 0.0], [[0.6, 0.4], [0.52, 0.48]])
    assert np.all(below.K > 0) and np.all(below.G > 0)
    assert np.all(np.diff(below.G) < 0)
    above = self_consistent([KQ, 0.0], [GQ, 0.0], [0.45, 0.55])
    assert float(above.K) == 0.0 and float(above.G) == 0.0


def test_sc_fluid_suspension_is_reuss(engine):
    """Beyond shear percolation a fluid-supported mixture has G = 0 and K = Reuss exactly."""
    m = self_consistent([KQ, KW], [GQ, 0.0], [0.4, 0.6])
    assert float(m.G) == 0.0
    assert float(m.K) == pytest.approx(1 / (0.4 / KQ + 0.6 / KW), rel=1e-14)


# --- stiff and extreme cases ---------------------------------------------------------------------
def test_sc_flat_cracks(engine):
    """Aspect ratio 1e-4: finite, between the bounds, and matching the independent solver."""
    f = [1 - 1e-5, 1e-5]
    m = self_consistent([KQ, KW], [GQ, 0.0], f, [1, 1e-4])
    ref = _scipy_sc(np.array([KQ, KW]), np.array([GQ, 0.0]), np.array(f), np.array([1, 1e-4]))
    np.testing.assert_allclose([float(m.K), float(m.G)], ref, rtol=1e-9)
    # Dense crack population: the shear stiffness collapses to exactly zero, K to Reuss.
    dense = self_consistent([KQ, KW], [GQ, 0.0], [0.99, 0.01], [1, 1e-4])
    assert float(dense.G) == 0.0
    assert float(dense.K) == pytest.approx(1 / (0.99 / KQ + 0.01 / KW), rel=1e-12)


def test_sc_stiffness_contrast_1e6(engine):
    K, G, f = np.array([40e6, 1.0]), np.array([39e6, 1.0]), np.array([0.5, 0.5])
    m = self_consistent(K, G, f)
    hs = hashin_shtrikman(K, G, f)
    assert np.isfinite(m.K) and np.isfinite(m.G)
    assert hs.K_lower <= m.K <= hs.K_upper
    assert hs.G_lower <= m.G <= hs.G_upper
    np.testing.assert_allclose([float(m.K), float(m.G)], _scipy_sc(K, G, f, np.ones(2)), rtol=1e-8)


def test_sc_reports_non_convergence(engine):
    with pytest.raises(RuntimeError, match="did not converge"):
        self_consistent([KQ, KC, KW], [GQ, GC, 0.0], [0.6, 0.1, 0.3], [1, 1, 0.1], max_iter=1)


def test_sc_full_output(engine):
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


# --- the two solver paths: numba kernel and numpy --------------------------------------------
def _sandstone_phases(n, K_pore):
    """Model 2's phases along the sandstone profile of benchmarks/_common.py (porosity
    0.36 -> 0.02, quartz cement 0.2 s^2): quartz and cement spheres, pores of aspect ratio 0.108
    (bulk modulus ``K_pore``), built as the benchmark builds them."""
    s = np.linspace(0.0, 1.0, n)
    phi = 0.36 - 0.34 * s
    beta_c = 0.2 * s**2 / (1.0 - phi)
    frac = np.stack([(1.0 - phi) * (1.0 - beta_c), (1.0 - phi) * beta_c, phi], -1)
    return np.array([KQ, KC, K_pore]), np.array([GQ, GC, 0.0]), frac, np.array([1.0, 1.0, 0.108])


@pytest.mark.parametrize("aspect", [1e-4, 0.108, 0.95, 1.0 + 1e-6, 4.0, 1e3])
def test_kernel_pq_equal_berryman_and_complex_step_derivatives(aspect, rng):
    """The kernel's P, Q (Berryman's F1..F9 as polynomials in A, B, R) equal the direct
    transcription ``_pq_spheroid``; its exact derivatives equal complex-step derivatives of that
    transcription (Squire & Trapp 1998: Im f(x + ih) / h, no cancellation)."""
    kernels = pytest.importorskip("rockcem._sc_kernels")
    th, f = inclusions._theta_f(np.array([aspect]))
    coef = inclusions._spheroid_coefficients(th, f)
    # Thin cracks: both forms cancel (P, Q to ~1e-12, their derivatives to ~1e-9).
    rtol_pq, rtol = (1e-11, 1e-8) if aspect < 1e-3 else (1e-13, 1e-11)
    for _ in range(10):
        K, G, Ki, Gi = rng.uniform(0.5, 60.0, 4)
        Gi *= rng.integers(0, 2)                             # half of them fluids (G_i = 0)
        P, PK, PG, Q, QK, QG = kernels.spheroid_pq(K, G, Ki, Gi, coef, 0)
        ref = inclusions._pq_spheroid(K, G, Ki, Gi, th[0], f[0])
        np.testing.assert_allclose([P, Q], ref, rtol=rtol_pq)
        h = 1e-30
        dK = [x.imag / (h * K) for x in inclusions._pq_spheroid(K + 1j * h * K, G, Ki, Gi, th[0],
                                                                 f[0])]
        dG = [x.imag / (h * G) for x in inclusions._pq_spheroid(K, G + 1j * h * G, Ki, Gi, th[0],
                                                                 f[0])]
        # Logarithmic sensitivities K dP/dK etc., compared on the scale of P and Q.
        np.testing.assert_allclose([K * PK, G * PG], [K * dK[0], G * dG[0]], rtol=rtol,
                                   atol=rtol * abs(P))
        np.testing.assert_allclose([K * QK, G * QG], [K * dK[1], G * dG[1]], rtol=rtol,
                                   atol=rtol * abs(Q))


def test_kernel_equals_its_python_twin(tmp_path):
    """The compiled kernel and the same source run as plain Python (NUMBA_DISABLE_JIT=1), on a
    short ordered profile (continuation starts, shear collapse, a fluid-only point) and random
    points."""
    pytest.importorskip("numba")
    import os
    import subprocess
    import sys

    code = f"""
import numpy as np
from rockcem import inclusions
inclusions._NUMBA_MIN_POINTS = 0
rng = np.random.default_rng(7)
K, G, f = np.zeros((2, 16, 3)), np.zeros((2, 16, 3)), np.zeros((2, 16, 3))
phi = np.linspace(0.36, 0.2, 16)
K[0], G[0] = [{KQ}, {KC}, 0.0], [{GQ}, {GC}, 0.0]
f[0] = np.stack([0.9 * (1 - phi), 0.1 * (1 - phi), phi], -1)
f[0, 5] = [0.0, 0.0, 1.0]
K[1], G[1] = rng.uniform(1, 60, (16, 3)), rng.uniform(0, 40, (16, 3))
f[1] = rng.dirichlet([2, 2, 1], 16)
m, info = inclusions.self_consistent(K, G, f, [1.0, 1.0, 0.108], full_output=True)
np.save({str(tmp_path / "out.npy")!r}, np.stack([m.K, m.G, info.iterations]))
"""
    for jit in ("0", "1"):
        env = {**os.environ, "NUMBA_DISABLE_JIT": jit}
        subprocess.run([sys.executable, "-c", code], check=True, env=env)
        out = np.load(tmp_path / "out.npy")
        if jit == "0":
            compiled = out
    assert np.all(compiled[1, 0, :4] == 0.0) and np.all(compiled[1, 0, 8:] > 0.0)
    np.testing.assert_allclose(out[:2], compiled[:2], rtol=1e-12, atol=0.0)


def test_sc_numba_and_numpy_paths_agree(rng, monkeypatch):
    """Random composites (fluids, oblate and prolate spheroids, mixed per point) on both paths."""
    pytest.importorskip("numba")
    n = 500
    K = rng.uniform(1.0, 80.0, (n, 3))
    G = rng.uniform(0.5, 60.0, (n, 3)) * (rng.uniform(size=(n, 3)) > 0.2)
    f = rng.dirichlet([1, 1, 1], n)
    a = rng.choice([0.01, 0.108, 1.0, 3.0], (n, 3))
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0)
    fast = self_consistent(K, G, f, a)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 2**62)
    ref = self_consistent(K, G, f, a)
    np.testing.assert_array_equal(fast.G == 0.0, ref.G == 0.0)
    np.testing.assert_allclose(fast.K, ref.K, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(fast.G, ref.G, rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("K_pore", [KW, 0.0])
def test_sc_profile_with_continuation_matches_scipy(K_pore, rng, monkeypatch):
    """A dense, ordered depth profile on the numba path (continuation starts; dry pores cross
    the shear-percolation porosity): equal to scipy's root finder point by point, to the numpy
    path (every point from its HS bound), and to itself with the points shuffled."""
    pytest.importorskip("numba")
    K, G, frac, a = _sandstone_phases(20_000, K_pore)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0)
    m, info = self_consistent(K, G, frac, a, full_output=True)
    # Continuation: one or two Newton iterations at the solid points (5-8 from the HS bound;
    # shear collapse takes ~13).
    assert np.mean(info.iterations[m.G > 0.0]) < 2.0
    perm = rng.permutation(frac.shape[0])
    shuffled = self_consistent(K, G, frac[perm], a)
    np.testing.assert_allclose(shuffled.K, m.K[perm], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(shuffled.G, m.G[perm], rtol=1e-10, atol=1e-12)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 2**62)
    ref = self_consistent(K, G, frac, a)
    np.testing.assert_allclose(m.K, ref.K, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(m.G, ref.G, rtol=1e-10, atol=1e-12)
    solid = np.flatnonzero(m.G > 0.1)
    for i in solid[np.linspace(0, solid.size - 1, 6).round().astype(int)]:
        np.testing.assert_allclose([m.K[i], m.G[i]], _scipy_sc(K, G, frac[i], a), rtol=1e-10)
    if K_pore == 0.0:
        # Beyond percolation: exactly G = 0 and K = Reuss = 0 (vacuum pores).
        assert np.all(m.K[m.G == 0.0] == 0.0) and 0.1 < np.mean(m.G == 0.0) < 0.3


def test_sc_no_spurious_shear_collapse(engine):
    """Dry pores of aspect ratio 0.108 at porosity 0.258, below the percolation porosity
    (~0.291): the rock is solid (G = 3.2 GPa, as scipy's root finder finds). Point 60082 of the
    200 000-point benchmark profile, where the Broyden solver (40492ae and after) wrongly reported
    shear collapse (G = 0)."""
    K, G, frac, a = _sandstone_phases(200_000, 0.0)
    f = frac[60082]
    m = self_consistent(K, G, f, a)
    np.testing.assert_allclose([float(m.K), float(m.G)], _scipy_sc(K, G, f, a), rtol=1e-10)
