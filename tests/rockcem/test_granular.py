"""Granular contact models (rockcem.granular) against closed forms, bounds and published statements."""

import numpy as np
import pytest

from rockcem.bounds import hashin_shtrikman, hill
from rockcem.granular import (cement_radius, constant_cement, contact_cement, hertz_mindlin,
                              increasing_cement, patchy_cement, soft_sand, stiff_sand)
from rockcem.inclusions import self_consistent

# The example parameter set of the rockphypy documentation (contact models page).
K0, G0, PHIC, N, P = 36.6, 45.0, 0.4, 8.6, 20.0
KQ, GQ, KC, GC = 40.0, 39.0, 35.0, 30.0   # Carcione et al. 2022, Table 1


def nu(K, G):
    return (3 * K - 2 * G) / (2 * (3 * K + G))


def hm_reference(K, G, phic, n, p_mpa):
    """Mavko et al. 2009 eq. 5.4.x / Carcione et al. 2022 eqs. D.1-D.2, pressure in GPa."""
    p = p_mpa / 1000.0
    v = nu(K, G)
    Khm = (n**2 * (1 - phic) ** 2 * G**2 * p / (18 * np.pi**2 * (1 - v) ** 2)) ** (1 / 3)
    Ghm = (5 - 4 * v) / (5 * (2 - v)) * (3 * n**2 * (1 - phic) ** 2 * G**2 * p
                                         / (2 * np.pi**2 * (1 - v) ** 2)) ** (1 / 3)
    return Khm, Ghm


def test_hertz_mindlin_closed_form():
    m = hertz_mindlin(K0, G0, PHIC, N, P)
    Khm, Ghm = hm_reference(K0, G0, PHIC, N, P)
    assert float(m.K) == pytest.approx(Khm, rel=1e-13)
    assert float(m.G) == pytest.approx(Ghm, rel=1e-13)
    # eq. D.2 of Carcione et al. 2022: mu_u = 3 (5 - 4 nu) / (5 (2 - nu)) K_u.
    v = nu(K0, G0)
    assert float(m.G) == pytest.approx(3 * (5 - 4 * v) / (5 * (2 - v)) * float(m.K), rel=1e-13)


def test_hertz_mindlin_slip_and_prestress():
    v = nu(K0, G0)
    frictionless = hertz_mindlin(K0, G0, PHIC, N, P, f=0.0)
    # f = 0: G = (2 - nu) / (5 (2 - nu)) * cbrt(...) = 3/5 K (Walton's smooth limit).
    assert float(frictionless.G) == pytest.approx(0.6 * float(frictionless.K), rel=1e-13)
    assert v > 0
    a = hertz_mindlin(K0, G0, PHIC, N, 30.0, delta=70.0)
    b = hertz_mindlin(K0, G0, PHIC, N, 100.0)
    assert float(a.K) == pytest.approx(float(b.K), rel=1e-15)
    # Cube-root pressure scaling.
    c = hertz_mindlin(K0, G0, PHIC, N, 8 * P)
    assert float(c.K) == pytest.approx(2 * float(hertz_mindlin(K0, G0, PHIC, N, P).K), rel=1e-13)
    zero = hertz_mindlin(K0, G0, PHIC, N, 0.0)
    assert float(zero.K) == 0.0 and float(zero.G) == 0.0


def test_soft_and_stiff_sand_are_hs_bounds():
    """Soft sand is the HS lower and stiff sand the HS upper bound of (HM pack, mineral) mixed in
    proportions phi/phic and 1 - phi/phic (Mavko et al. 2009, Sect. 7.9)."""
    phi = np.linspace(0, PHIC, 9)
    hm = hertz_mindlin(K0, G0, PHIC, N, P)
    x = phi / PHIC
    b = hashin_shtrikman(np.stack(np.broadcast_arrays(hm.K, K0), -1) * np.ones((9, 1)),
                         np.stack(np.broadcast_arrays(hm.G, G0), -1) * np.ones((9, 1)),
                         np.stack([x, 1 - x], -1))
    soft = soft_sand(K0, G0, phi, PHIC, N, P)
    stiff = stiff_sand(K0, G0, phi, PHIC, N, P)
    np.testing.assert_allclose(soft.K, b.K_lower, rtol=1e-12)
    np.testing.assert_allclose(soft.G, b.G_lower, rtol=1e-12)
    np.testing.assert_allclose(stiff.K, b.K_upper, rtol=1e-12)
    np.testing.assert_allclose(stiff.G, b.G_upper, rtol=1e-12)
    # End points: mineral at phi = 0, Hertz–Mindlin at phic.
    assert soft.K[0] == pytest.approx(K0) and stiff.G[0] == pytest.approx(G0)
    assert soft.K[-1] == pytest.approx(float(hm.K)) and stiff.G[-1] == pytest.approx(float(hm.G))
    assert np.all(np.diff(soft.K) < 0) and np.all(np.diff(stiff.G) < 0)


def test_soft_sand_at_zero_pressure():
    m = soft_sand(K0, G0, [0.0, 0.2, 0.4], PHIC, N, 0.0)
    np.testing.assert_array_equal(m.K, [K0, 0.0, 0.0])


def test_soft_sand_formula_rockphypy():
    """The soft-sand equations as printed in the rockphypy documentation."""
    phi = 0.25
    Khm, Ghm = hm_reference(K0, G0, PHIC, N, P)
    K = 1 / ((phi / PHIC) / (Khm + 4 / 3 * Ghm) + (1 - phi / PHIC) / (K0 + 4 / 3 * Ghm)) - 4 / 3 * Ghm
    z = Ghm / 6 * (9 * Khm + 8 * Ghm) / (Khm + 2 * Ghm)
    G = 1 / ((phi / PHIC) / (Ghm + z) + (1 - phi / PHIC) / (G0 + z)) - z
    m = soft_sand(K0, G0, phi, PHIC, N, P)
    assert float(m.K) == pytest.approx(K, rel=1e-12)
    assert float(m.G) == pytest.approx(G, rel=1e-12)


# --- contact cement ------------------------------------------------------------------------------
def cct_reference(K0, G0, Kc, Gc, phi, phic, n, scheme):
    """Dvorkin & Nur (1996) as in the Rock Physics Handbook, written out from the docs of the
    rockphypy contact models (with the handbook coefficients)."""
    v, vc = nu(K0, G0), nu(Kc, Gc)
    if scheme == 1:
        alpha = 2 * ((phic - phi) / (3 * n * (1 - phic))) ** 0.25
    else:
        alpha = (2 * (phic - phi) / (3 * (1 - phic))) ** 0.5
    Ln = 2 * Gc / (np.pi * G0) * (1 - v) * (1 - vc) / (1 - 2 * vc)
    Lt = Gc / (np.pi * G0)
    An, Bn, Cn = -0.024153 * Ln**-1.3646, 0.20405 * Ln**-0.89008, 0.00024649 * Ln**-1.9864
    At = -1e-2 * (2.26 * v**2 + 2.07 * v + 2.3) * Lt ** (0.079 * v**2 + 0.1754 * v - 1.342)
    Bt = (0.0573 * v**2 + 0.0937 * v + 0.202) * Lt ** (0.0274 * v**2 + 0.0529 * v - 0.8765)
    Ct = 1e-4 * (9.654 * v**2 + 4.945 * v + 3.1) * Lt ** (0.01867 * v**2 + 0.4011 * v - 1.8186)
    Sn = An * alpha**2 + Bn * alpha + Cn
    St = At * alpha**2 + Bt * alpha + Ct
    Mc = Kc + 4 / 3 * Gc
    K = n * (1 - phic) * Mc * Sn / 6
    G = 3 / 5 * K + 3 / 20 * n * (1 - phic) * Gc * St
    return K, G


@pytest.mark.parametrize("scheme", [1, 2])
@pytest.mark.parametrize("phi", [0.39, 0.35, 0.3, 0.25])
def test_contact_cement_reference(scheme, phi):
    m = contact_cement(K0, G0, 36.6, 45.0, phi, PHIC, N, scheme)
    K, G = cct_reference(K0, G0, 36.6, 45.0, phi, PHIC, N, scheme)
    assert float(m.K) == pytest.approx(K, rel=1e-12)
    assert float(m.G) == pytest.approx(G, rel=1e-12)


@pytest.mark.parametrize("scheme", [1, 2])
def test_contact_cement_monotone_in_cement(scheme):
    phi = np.linspace(PHIC, 0.25, 30)
    m = contact_cement(KQ, GQ, KC, GC, phi, PHIC, N, scheme)
    assert np.all(np.diff(m.K) > 0) and np.all(np.diff(m.G) > 0)


def test_cement_radius_schemes():
    phi = np.array([0.4, 0.38, 0.3])
    a1 = cement_radius(phi, PHIC, N, 1)
    np.testing.assert_allclose(a1, 2 * ((PHIC - phi) / (3 * N * (1 - PHIC))) ** 0.25, rtol=1e-14)
    a2 = cement_radius(phi, PHIC, N, 2)
    np.testing.assert_allclose(a2, np.sqrt(2 * (PHIC - phi) / (3 * (1 - PHIC))), rtol=1e-14)
    # Scheme 2 does not depend on the coordination number (Han & Guo eq. 10; no 1/n of Xu A-6).
    np.testing.assert_array_equal(cement_radius(phi, PHIC, 4.0, 2), a2)


@pytest.mark.parametrize("eps", [1e-12, 1e-6, 1e-3, 0.01, 0.05, 1.0, 1e3])
def test_cement_radius_with_thickness_solves_han_guo_eq6(eps):
    """Han & Guo eq. 6: 3n/16 a^4 + 3 n eps / 4 a^2 = (phic - phi)/(1 - phic)."""
    phi = 0.33
    a = float(cement_radius(phi, PHIC, N, 1, eps))
    lhs = 3 * N / 16 * a**4 + 3 * N * eps / 4 * a**2
    assert lhs == pytest.approx((PHIC - phi) / (1 - PHIC), rel=1e-12)


def test_cement_radius_thickness_limit_is_cct():
    phi = np.linspace(0.2, 0.4, 11)
    np.testing.assert_array_equal(cement_radius(phi, PHIC, N, 1, 0.0), cement_radius(phi, PHIC, N, 1))
    small = cement_radius(phi, PHIC, N, 1, 1e-14)
    np.testing.assert_allclose(small, cement_radius(phi, PHIC, N, 1), rtol=1e-6)


def test_contact_cement_thickness_zero_is_exactly_cct():
    phi = np.linspace(0.25, 0.4, 7)
    a = contact_cement(KQ, GQ, KC, GC, phi, PHIC, N, 1, 0.0)
    b = contact_cement(KQ, GQ, KC, GC, phi, PHIC, N, 1)
    np.testing.assert_array_equal(a.K, b.K)
    np.testing.assert_array_equal(a.G, b.G)


def test_contact_cement_thickness_softens_scheme1():
    """Han & Guo: velocities decrease with contact thickness (Fig. 4)."""
    eps = np.array([0.0, 0.01, 0.03, 0.05])
    m = contact_cement(38.0, 44.0, 2.24, 1.57, 0.3, PHIC, N, 1, eps)
    assert np.all(np.diff(m.K) < 0) and np.all(np.diff(m.G) < 0)


@pytest.mark.parametrize("kwargs,match", [
    (dict(phi=0.45), "phi"),
    (dict(phi=-0.1), "phi"),
    (dict(phic=1.0), "phic"),
    (dict(n=0.0), "n"),
    (dict(scheme=3), "scheme"),
    (dict(thickness=-0.01), "thickness"),
    (dict(Gc=-1.0), "Gc"),
    (dict(Gc=1e-5), "Lambda"),
])
def test_contact_cement_bad_input(kwargs, match):
    args = dict(K0=KQ, G0=GQ, Kc=KC, Gc=GC, phi=0.3, phic=PHIC, n=N)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        contact_cement(**args)


# --- constant, increasing and patchy cement -------------------------------------------------------
def test_constant_and_increasing_cement_are_hs_bounds():
    phib = 0.3
    phi = np.linspace(0, phib, 7)
    b = contact_cement(KQ, GQ, KC, GC, phib, PHIC, N)
    x = phi / phib
    Ks = np.stack(np.broadcast_arrays(b.K, KQ), -1) * np.ones((7, 1))
    Gs = np.stack(np.broadcast_arrays(b.G, GQ), -1) * np.ones((7, 1))
    hs = hashin_shtrikman(Ks, Gs, np.stack([x, 1 - x], -1))
    cc = constant_cement(KQ, GQ, KC, GC, phi, PHIC, N, phib)
    ic = increasing_cement(KQ, GQ, KC, GC, phi, PHIC, N, phib)
    np.testing.assert_allclose(cc.K, hs.K_lower, rtol=1e-12)
    np.testing.assert_allclose(cc.G, hs.G_lower, rtol=1e-12)
    np.testing.assert_allclose(ic.K, hs.K_upper, rtol=1e-12)
    np.testing.assert_allclose(ic.G, hs.G_upper, rtol=1e-12)
    assert cc.K[-1] == pytest.approx(float(b.K)) and ic.G[0] == pytest.approx(GQ)
    with pytest.raises(ValueError, match="phib"):
        constant_cement(KQ, GQ, KC, GC, 0.35, PHIC, N, phib)


def patchy_reference(phi, phip, p, delta, limit=0.05, phic=0.36, n=9.0):
    """Model 4 of Carcione et al. 2022 assembled step by step from independent pieces."""
    bonded = min(phip, limit)
    alpha_phi = phic - bonded                      # eq. 16 with phi_p-bar in place of phic - phi
    Ka, Ga = cct_reference(KQ, GQ, KC, GC, alpha_phi, phic, n, 1)
    Ku, Gu = hm_reference(KQ, GQ, phic, n, p + delta)
    f = phip / phic
    b = hashin_shtrikman([Ka, Ku], [Ga, Gu], [f, 1 - f]).upper
    s = self_consistent([KQ, KC], [GQ, GC], [1 - phic, phic])
    x = phi / phic
    return hill([float(s.K), float(b.K)], [float(s.G), float(b.G)], [1 - x, x])


@pytest.mark.parametrize("phi,phip", [(0.36, 0.0), (0.3, 0.02), (0.2, 0.08), (0.05, 0.25)])
def test_patchy_cement_assembly(phi, phip):
    m = patchy_cement(KQ, GQ, KC, GC, phi, 0.36, 9.0, 25.0, phip, delta=100.0)
    ref = patchy_reference(phi, phip, 25.0, 100.0)
    assert float(m.K) == pytest.approx(float(ref.K), rel=1e-10)
    assert float(m.G) == pytest.approx(float(ref.G), rel=1e-10)


def test_patchy_cement_zero_cement_not_below_uncemented():
    """At zero cement the model is the Hill mix of Hertz–Mindlin and the SC mineral; adding cement
    at fixed porosity only stiffens it."""
    phi = 0.3
    zero = patchy_cement(KQ, GQ, KC, GC, phi, 0.36, 9.0, 20.0, 0.0, delta=40.0)
    hm = hertz_mindlin(KQ, GQ, 0.36, 9.0, 60.0)
    s = self_consistent([KQ, KC], [GQ, GC], [0.64, 0.36])
    ref = hill([float(s.K), float(hm.K)], [float(s.G), float(hm.G)], [1 - phi / 0.36, phi / 0.36])
    assert float(zero.K) == pytest.approx(float(ref.K), rel=1e-12)
    more = patchy_cement(KQ, GQ, KC, GC, phi, 0.36, 9.0, 20.0, np.linspace(0, 0.06, 13), delta=40.0)
    assert np.all(np.diff(more.K) >= 0) and np.all(np.diff(more.G) >= 0)
    assert np.all(more.K >= float(zero.K))


# --- property tests ------------------------------------------------------------------------------
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=60, deadline=None)
@given(Kg=st.floats(10, 80), Gg=st.floats(5, 60), Kc=st.floats(5, 80), Gc=st.floats(3, 60),
       phic=st.floats(0.3, 0.45), n=st.floats(5, 14), scheme=st.sampled_from([1, 2]),
       eps=st.sampled_from([0.0, 0.02]))
def test_contact_cement_monotone_property(Kg, Gg, Kc, Gc, phic, n, scheme, eps):
    """More cement (lower porosity at fixed critical porosity) never softens the rock."""
    phi = np.linspace(phic, phic - 0.08, 9)
    m = contact_cement(Kg, Gg, Kc, Gc, phi, phic, n, scheme, eps)
    assert np.all(np.isfinite(m.K)) and np.all(np.diff(m.K) > 0) and np.all(np.diff(m.G) > 0)


@settings(max_examples=40, deadline=None)
@given(phi=st.floats(0.0, 0.36), p=st.floats(0.0, 80.0), delta=st.floats(0.0, 150.0),
       scheme=st.sampled_from([1, 2]))
def test_patchy_cement_monotone_in_cement_property(phi, p, delta, scheme):
    phip = np.linspace(0.0, 0.36, 10)
    m = patchy_cement(KQ, GQ, KC, GC, phi, 0.36, 9.0, p, phip, scheme=scheme, delta=delta)
    assert np.all(np.diff(m.K) >= -1e-12) and np.all(np.diff(m.G) >= -1e-12)
    # The zero-porosity end member is the SC mix of grain and cement in proportions
    # (1 - phic, phic) (Carcione et al. 2022, Sect. 4.4): never stiffer than its HS upper bound.
    hs = hashin_shtrikman([KQ, KC], [GQ, GC], [0.64, 0.36])
    assert np.all(m.K <= hs.K_upper * (1 + 1e-12)) and np.all(m.G >= 0)


@pytest.mark.parametrize("scheme,eps", [(1, 0.0), (1, 0.03), (2, 0.0), (2, 0.05)])
def test_cement_porosity_inverts_cement_radius(scheme, eps):
    """cement_radius(cement_porosity(alpha)) = alpha (eq. 7 of Han & Guo / eq. 18 of Carcione
    2022); scheme 1 at eps = 0 is the closed form phic - 3 n (1 - phic) (alpha/2)^4."""
    from rockcem.granular import cement_porosity, cement_radius

    alpha = np.linspace(0.05, 0.5, 10)
    phi = cement_porosity(alpha, 0.4, 6.0, scheme, eps)
    np.testing.assert_allclose(cement_radius(phi, 0.4, 6.0, scheme, eps), alpha, rtol=1e-12)
    if scheme == 1 and eps == 0.0:
        np.testing.assert_allclose(phi, 0.4 - 3 * 6.0 * 0.6 * (alpha / 2) ** 4, rtol=1e-14)


def test_cement_porosity_beyond_the_pore_space_raises(expect_value_error):
    from rockcem.granular import cement_porosity

    expect_value_error(lambda: cement_porosity(0.9, 0.4, 12.0), "alpha")
