"""Tests of rockcem.frames: Krief's dry-frame law, single- and multi-mineral.

Expected values are written out from Carcione et al. 2022, eqs. 3 and 13-14 (Krief et al. 1990;
Carcione et al. 2005), with the two-phase Hashin–Shtrikman average of eqs. C.1-C.3 written out
independently; moduli from Carcione et al. 2022, Table 1.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rockcem.bounds import hashin_shtrikman_average
from rockcem.frames import krief, krief_factor, krief_multimineral

QUARTZ = (40.0, 39.0)
ILLITE = (33.0, 28.0)
SMECTITE = (9.0, 6.0)


def krief_written_out(phi, A=3.0):
    """Carcione et al. 2022, eq. 3 (Krief et al. 1990): (1 - phi)^(A/(1 - phi)), by math.pow."""
    return math.pow(1.0 - phi, A / (1.0 - phi))


def hs_average_two_phase(p1, p2, f1):
    """Carcione et al. 2022, eqs. C.1-C.3 for two well-ordered phases (p1 the stiffer)."""
    def hs(a, b, fa):
        (Ka, Ga), (Kb, Gb), fb = a, b, 1.0 - fa
        K = Ka + fb / (1.0 / (Kb - Ka) + fa / (Ka + 4.0 / 3.0 * Ga))
        G = Ga + fb / (1.0 / (Gb - Ga) + 2.0 * fa * (Ka + 2.0 * Ga) / (5.0 * Ga * (Ka + 4 / 3 * Ga)))
        return K, G
    up, lo = hs(p1, p2, f1), hs(p2, p1, 1.0 - f1)
    return 0.5 * (up[0] + lo[0]), 0.5 * (up[1] + lo[1])


@pytest.mark.parametrize("phi", [0.0, 1e-8, 0.05, 0.2, 0.36, 0.5, 0.9])
@pytest.mark.parametrize("A", [1.0, 3.0, 4.5])
def test_krief_factor_equals_eq3(phi, A):
    np.testing.assert_allclose(krief_factor(phi, A), krief_written_out(phi, A), rtol=1e-13)


def test_krief_known_value():
    # eq. 3 at phi = 0.2, A = 3: 0.8^3.75, by hand 0.43310...
    np.testing.assert_allclose(krief_factor(0.2), 0.8 ** 3.75, rtol=1e-14)
    m = krief(*QUARTZ, 0.2)
    np.testing.assert_allclose([m.K, m.G], [40.0 * 0.8 ** 3.75, 39.0 * 0.8 ** 3.75], rtol=1e-13)


def test_krief_limits():
    m = krief(*QUARTZ, 0.0)
    assert (float(m.K), float(m.G)) == QUARTZ  # phi = 0: the mineral, exactly
    m1 = krief(*QUARTZ, 1.0)
    assert float(m1.K) == 0.0 and float(m1.G) == 0.0
    near_one = krief(*QUARTZ, np.array([0.99, 0.999, 1.0 - 1e-9]))
    assert np.all(near_one.K <= 40.0 * 0.01 ** 300) and np.all(near_one.K >= 0.0)
    assert krief(9.0, 0.0, 0.3).G == 0.0  # a mineral with no shear stays so


def test_krief_monotone_decreasing_in_porosity_and_exponent():
    phi = np.linspace(0.0, 1.0, 2001)
    K = krief(40.0, 39.0, phi).K
    assert np.all(np.diff(K) <= 0.0)
    assert np.all(np.diff(K[K > 1e-300]) < 0.0)  # strictly, while representable
    f = krief_factor(0.25, np.array([0.5, 1.0, 2.0, 3.0, 5.0]))
    assert np.all(np.diff(f) < 0.0)


@settings(max_examples=50, deadline=None)
@given(st.floats(0.0, 0.999), st.floats(0.1, 10.0))
def test_krief_factor_bounded_and_matches_eq3(phi, A):
    f = float(krief_factor(phi, A))
    assert 0.0 <= f <= 1.0
    np.testing.assert_allclose(f, krief_written_out(phi, A), rtol=1e-11, atol=1e-300)


def test_floats_lists_and_arrays_agree():
    phi = [0.0, 0.1, 0.3]
    arr = krief(np.array([40.0, 33.0, 9.0]), np.array([39.0, 28.0, 6.0]), np.array(phi))
    for i, (K, G) in enumerate([QUARTZ, ILLITE, SMECTITE]):
        m = krief(K, G, phi[i])
        assert (float(m.K), float(m.G)) == (arr.K[i], arr.G[i])
    grid = krief(40.0, 39.0, np.array([[0.1], [0.2]]), A=np.array([2.0, 3.0]))
    assert grid.K.shape == (2, 2)
    assert grid.K[1, 0] == float(krief(40.0, 39.0, 0.2, A=2.0).K)


# --- multi-mineral, Carcione et al. 2022 eqs. 13-14 -------------------------------------------

@pytest.mark.parametrize("p1, p2", [(QUARTZ, ILLITE), (QUARTZ, SMECTITE), (ILLITE, SMECTITE)])
@pytest.mark.parametrize("f1", [0.2, 0.5, 0.8])
@pytest.mark.parametrize("phi", [0.0, 0.1, 0.3])
def test_multimineral_sums_to_krief_of_hs_average(p1, p2, f1, phi):
    m = krief_multimineral([p1[0], p2[0]], [p1[1], p2[1]], [f1, 1 - f1], phi)
    K_s, G_s = hs_average_two_phase(p1, p2, f1)
    # The property stated after eq. 13: sum_i K_mi = K_s (1-phi)^(A/(1-phi)), same for mu.
    fac = krief_written_out(phi)
    np.testing.assert_allclose([m.K.sum(), m.G.sum()], [K_s * fac, G_s * fac], rtol=1e-12)
    # eq. 13: each mineral's share is proportional to beta_i K_i (beta_i mu_i for shear).
    np.testing.assert_allclose(m.K[0] / m.K[1], f1 * p1[0] / ((1 - f1) * p2[0]), rtol=1e-12)
    np.testing.assert_allclose(m.G[0] / m.G[1], f1 * p1[1] / ((1 - f1) * p2[1]), rtol=1e-12)


def test_multimineral_at_zero_porosity_is_hs_average():
    m = krief_multimineral([40.0, 33.0], [39.0, 28.0], [0.6, 0.4], 0.0)
    np.testing.assert_allclose([m.K.sum(), m.G.sum()], hs_average_two_phase(QUARTZ, ILLITE, 0.6),
                               rtol=1e-12)


def test_multimineral_one_solid_is_krief():
    m = krief_multimineral([40.0], [39.0], [1.0], 0.25)
    ref = krief(40.0, 39.0, 0.25)
    np.testing.assert_allclose([m.K[0], m.G[0]], [ref.K, ref.G], rtol=1e-13)


@st.composite
def minerals(draw):
    n = draw(st.integers(1, 5))
    K = np.array(draw(st.lists(st.floats(1.0, 100.0), min_size=n, max_size=n)))
    shear = st.just(0.0) | st.floats(1e-6, 80.0)  # see test_bounds for near-underflow shear
    G = np.array(draw(st.lists(shear, min_size=n, max_size=n)))
    w = np.array(draw(st.lists(st.floats(0.01, 1.0), min_size=n, max_size=n)))
    return K, G, w / w.sum()


@settings(max_examples=50, deadline=None)
@given(minerals(), st.floats(0.0, 1.0), st.floats(0.5, 5.0))
def test_multimineral_sum_property_n_phases(mins, phi, A):
    K, G, beta = mins
    m = krief_multimineral(K, G, beta, phi, A=A)
    hs = hashin_shtrikman_average(K, G, beta)
    fac = float(krief_factor(phi, A))
    np.testing.assert_allclose(m.K.sum(), hs.K * fac, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(m.G.sum(), hs.G * fac, rtol=1e-12, atol=1e-13 * G.max())
    assert np.all(m.K >= 0.0) and np.all(m.G >= 0.0)


def test_multimineral_all_fluid_like_shear_is_zero_without_warning():
    m = krief_multimineral([9.0, 2.0], [0.0, 0.0], [0.5, 0.5], 0.2)
    assert np.all(m.G == 0.0)


def test_multimineral_broadcasts_over_depths():
    rng = np.random.default_rng(13)
    beta = rng.dirichlet([1.0, 1.0, 1.0], size=10)  # 10 depths x 3 minerals
    phi = np.linspace(0.0, 0.4, 10)
    K, G = np.array([40.0, 33.0, 9.0]), np.array([39.0, 28.0, 6.0])
    out = krief_multimineral(K, G, beta, phi)
    assert out.K.shape == (10, 3)
    for d in range(10):
        row = krief_multimineral(K, G, beta[d], float(phi[d]))
        np.testing.assert_allclose([out.K[d], out.G[d]], [row.K, row.G], rtol=1e-14)


def test_inputs_not_mutated():
    K, G, beta, phi = (np.array(v) for v in ([40.0, 9.0], [39.0, 6.0], [0.5, 0.5], [0.1, 0.2]))
    for a in (K, G, beta, phi):
        a.setflags(write=False)
    krief_multimineral(K, G, beta, phi)
    krief(K, G, phi)
    np.testing.assert_array_equal(beta, [0.5, 0.5])


BAD = [
    pytest.param(lambda: krief_factor(-0.1), "phi", id="phi-negative"),
    pytest.param(lambda: krief_factor(1.1), "phi", id="phi-above-1"),
    pytest.param(lambda: krief_factor(np.nan), "phi", id="phi-nan"),
    pytest.param(lambda: krief_factor(0.2, A=0.0), "A", id="A-zero"),
    pytest.param(lambda: krief_factor(0.2, A=-3.0), "A", id="A-negative"),
    pytest.param(lambda: krief(0.0, 39.0, 0.2), "K_min", id="K_min-zero"),
    pytest.param(lambda: krief(40.0, -1.0, 0.2), "G_min", id="G_min-negative"),
    pytest.param(lambda: krief(40.0 + 1j, 39.0, 0.2), "K_min", id="K_min-complex"),
    pytest.param(lambda: krief(np.array([40.0 + 0j]), 39.0, 0.2), "K_min", id="K_min-complex-arr"),
    pytest.param(lambda: krief([40.0, 9.0], [39.0, 6.0, 1.0], 0.2), "G_min", id="mismatched"),
    pytest.param(lambda: krief_multimineral([40.0, 9.0], [39.0, 6.0], [0.5, 0.4], 0.2),
                 "solid_fractions", id="fractions-sum"),
    pytest.param(lambda: krief_multimineral([40.0, 9.0], [39.0, 6.0], [1.5, -0.5], 0.2),
                 "solid_fractions", id="fractions-range"),
    pytest.param(lambda: krief_multimineral([40.0, -9.0], [39.0, 6.0], [0.5, 0.5], 0.2),
                 "K_solid", id="multi-negative-K"),
    pytest.param(lambda: krief_multimineral([40.0, 9.0], [39.0, 6.0], [0.5, 0.5], 1.2),
                 "phi", id="multi-phi"),
    pytest.param(lambda: krief_multimineral([40.0, 9.0], [39.0, 6.0, 1.0], [0.5, 0.5], 0.2),
                 "G_solid", id="multi-mismatched"),
]


@pytest.mark.parametrize("call, name", BAD)
def test_bad_input_raises_value_error_naming_argument(call, name, expect_value_error):
    expect_value_error(call, name)
