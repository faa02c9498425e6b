"""The faster paths of Model 2's self-consistent solves (rockcem._sc_kernels), against the
equations written out and against the other numerical path of the solver."""

import numpy as np
import pytest

from rockcem import inclusions
from rockcem.inclusions import self_consistent

KQ, GQ = 40.0, 39.0      # quartz, Carcione et al. 2022 Table 1
KC, GC = 35.0, 30.0      # cement, same table
KW = 2.2                 # water


@pytest.mark.parametrize("aspect", [1e-3, 0.108, 0.17, 0.95, 1.0 + 1e-6, 4.0, 1e3])
@pytest.mark.parametrize("K_pore", [0.0, KW, 30.0])
def test_fluid_spheroid_pq_against_berryman_and_complex_steps(aspect, K_pore, rng):
    """``spheroid_pq_fluid`` (Berryman's F1..F9 at A = -1, B = K_i/(3K), G_i = 0) equals the
    direct transcription of Berryman (1980) ``inclusions._pq_spheroid`` at G_i = 0, and its
    derivatives equal complex-step derivatives of that transcription (Squire & Trapp 1998)."""
    kernels = pytest.importorskip("rockcem._sc_kernels")
    th, f = inclusions._theta_f(np.array([aspect]))
    coef = inclusions._spheroid_coefficients(th, f)
    h = 1e-30
    for _ in range(20):
        K, G = rng.uniform(0.05, 60.0, 2)
        P, PK, PG, Q, QK, QG = kernels.spheroid_pq_fluid(K, G, K_pore, coef, 0)
        ref = inclusions._pq_spheroid(K, G, K_pore, 0.0, th[0], f[0])
        np.testing.assert_allclose([P, Q], ref, rtol=1e-12)
        dK = [x.imag / (h * K) for x in inclusions._pq_spheroid(K + 1j * h * K, G, K_pore, 0.0,
                                                                 th[0], f[0])]
        dG = [x.imag / (h * G) for x in inclusions._pq_spheroid(K, G + 1j * h * G, K_pore, 0.0,
                                                                 th[0], f[0])]
        np.testing.assert_allclose([K * PK, G * PG], [K * dK[0], G * dG[0]], rtol=1e-10,
                                   atol=1e-10 * abs(P))
        np.testing.assert_allclose([K * QK, G * QG], [K * dK[1], G * dG[1]], rtol=1e-10,
                                   atol=1e-10 * abs(Q))


def _profile(n, K_pore, aspect, phi0=0.36):
    """The sandstone profile of benchmarks/_common.py (porosity ``phi0`` -> 0.02, quartz
    cement 0.2 s^2) as Model 2's phases: quartz and cement spheres, pores of bulk modulus
    ``K_pore`` and aspect ratio ``aspect``."""
    s = np.linspace(0.0, 1.0, n)
    phi = phi0 - (phi0 - 0.02) * s
    beta_c = 0.2 * s**2 / (1.0 - phi)
    frac = np.stack([(1.0 - phi) * (1.0 - beta_c), (1.0 - phi) * beta_c, phi], -1)
    return (np.array([KQ, KC, K_pore]), np.array([GQ, GC, 0.0]), frac,
            np.array([1.0, 1.0, aspect]))


@pytest.mark.parametrize("K_pore", [0.0, KW])
def test_kernel_equals_numpy_path_at_tighter_tolerance(K_pore, monkeypatch):
    """Model 2's two solves along an ordered sandstone profile (dry pores cross the shear-
    percolation porosity) on the numba kernel at the default tol = 1e-12 agree with the numpy
    path (complex-step Jacobian, every point from its HS bound) at tol = 1e-14, run here: two
    different numerical paths. Shear collapse at the same points, exactly (Reuss, 0) there."""
    pytest.importorskip("numba")
    K, G, frac, a = _profile(6000, K_pore, 0.108)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0)
    fast = self_consistent(K, G, frac, a)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 2**62)
    ref = self_consistent(K, G, frac, a, tol=1e-14)
    np.testing.assert_array_equal(fast.G == 0.0, ref.G == 0.0)
    solid = ref.G > 1e-3
    np.testing.assert_allclose(fast.K[solid], ref.K[solid], rtol=1e-11)
    np.testing.assert_allclose(fast.G[solid], ref.G[solid], rtol=1e-11)
    # Next to the percolation threshold the moduli are ill-conditioned (G ~ 1e-4 GPa): there
    # compared in absolute terms, on the scale of the solids' moduli.
    np.testing.assert_allclose(fast.K, ref.K, rtol=0.0, atol=1e-11 * KQ)
    np.testing.assert_allclose(fast.G, ref.G, rtol=0.0, atol=1e-11 * KQ)
    if K_pore == 0.0:
        assert np.all(fast.K[fast.G == 0.0] == 0.0) and np.mean(fast.G == 0.0) > 0.1


@pytest.mark.parametrize("aspect", [0.108, 0.17, 1.0])
def test_collapse_ahead_equals_the_full_iteration(aspect):
    """Dry pores past the shear-percolation porosity: the kernel stops once the damped Newton
    iteration is in its asymptotic collapse (G a tenth per step) and counts the steps it skips.
    From the HS bound (no continuation) it gives the numpy path's full iteration exactly: the
    same collapsed points, (K, G) = (Reuss, 0) = (0, 0) there, the same number of iterations."""
    kernels = pytest.importorskip("rockcem._sc_kernels")
    K, G, frac, a = _profile(3000, 0.0, aspect, phi0=0.62)
    ref, info = self_consistent(K, G, frac, a, engine="numpy", full_output=True)
    assert 0.05 < np.mean(ref.G == 0.0) < 0.95
    n = frac.shape[0]
    out = (np.empty(n), np.empty(n), np.empty(n, dtype=np.int64), np.empty(n),
           np.empty(n, dtype=np.bool_))
    th, f = inclusions._theta_f(np.array([aspect]))
    kind = np.broadcast_to(np.array([-1, -1, -1 if aspect == 1.0 else 0]), frac.shape)
    kernels.solve_points(np.broadcast_to(K, frac.shape), np.broadcast_to(G, frac.shape), frac,
                         kind, inclusions._spheroid_coefficients(th, f), 1e-12, 200, False, *out)
    k, g, iterations, _, done = out
    assert np.all(done)
    collapsed = ref.G == 0.0
    np.testing.assert_array_equal(g == 0.0, collapsed)
    assert np.all(k[collapsed] == 0.0)
    np.testing.assert_array_equal(iterations[collapsed], info.iterations[collapsed])
    np.testing.assert_allclose(k[~collapsed], ref.K[~collapsed], rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(g[~collapsed], ref.G[~collapsed], rtol=1e-10, atol=1e-12)


def test_model2_density_checks_kept():
    """Model 2 computes its bulk density from checked fractions without bulk_density's checks
    of them; the densities are still refused by name (as bulk_density's own messages)."""
    from rockcem.materials import Fluid, Mineral
    from rockcem.models import self_consistent_model

    quartz = Mineral(KQ, GQ, 2.65, name="quartz")
    water = Fluid(KW, 1.0)
    kw = dict(aspect_ratio=0.108)
    with pytest.raises(ValueError, match=r"^mineral_density must lie in \(0, 25\]"):
        self_consistent_model([Mineral(KQ, GQ, 2650.0)], [1.0], 0.2, water, **kw)
    with pytest.raises(ValueError, match=r"^fluid_density must lie in \[0, 25\]"):
        self_consistent_model([quartz], [1.0], 0.2, Fluid(KW, 1000.0), **kw)
    with pytest.raises(ValueError, match=r"porosity \(2,\), fluid_density \(3,\)"):
        self_consistent_model([quartz], [1.0], [0.1, 0.2], Fluid(KW, [1.0, 1.0, 1.0]), **kw)
    # Eq. 24 by hand: (1 - phi) rho_s + phi rho_f.
    r = self_consistent_model([quartz], [1.0], [0.1, 0.2], Fluid(KW, [1.0, 1.1]), **kw)
    np.testing.assert_allclose(r.density, [0.9 * 2.65 + 0.1 * 1.0, 0.8 * 2.65 + 0.2 * 1.1],
                               rtol=1e-15)


def test_kernel_bounds_follow_the_phases_present(monkeypatch):
    """The kernel keeps the bounds' phase constants from one point to the next while the
    moduli and the phases present are the same: a row with the stiffest phase after rows
    without it (its HS upper bound, else one from the soft phase's shear modulus, below the
    solution), and dry rows after rows without pores (Reuss K = 0 at the collapse), each
    give their own solution (the numpy path at tol = 1e-14)."""
    pytest.importorskip("numba")
    K = np.array([KQ, 20.0, 0.0])
    G = np.array([GQ, 0.5, 0.0])
    frac = np.array([[0.0, 1.0, 0.0], [0.0, 0.3, 0.7], [0.0, 0.9, 0.1], [0.7, 0.2, 0.1]] * 50)
    a = np.array([1.0, 1.0, 0.108])
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0)
    fast = self_consistent(K, G, frac, a)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 2**62)
    ref = self_consistent(K, G, frac, a, tol=1e-14)
    assert np.all(ref.G[1::4] == 0.0) and np.all(ref.K[1::4] == 0.0)
    assert np.all(ref.G[3::4] > 10.0)
    np.testing.assert_allclose(fast.K, ref.K, rtol=1e-11, atol=0.0)
    np.testing.assert_allclose(fast.G, ref.G, rtol=1e-11, atol=0.0)
