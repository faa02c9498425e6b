"""Tests of rockcem.bounds: Voigt, Reuss, Hill and Hashin–Shtrikman for n phases.

Expected values are written out here from the published formulas (Carcione et al. 2022, App. C;
Hashin & Shtrikman 1963; Mavko et al. 2009, Sect. 4.1-4.2) or from analytic limits; the moduli
come from Carcione et al. 2022, Table 1 and Han & Guo.
"""

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rockcem.bounds import Bounds, hashin_shtrikman, hashin_shtrikman_average, hill, reuss, voigt
from rockcem.elastic import Moduli

# (K, G) in GPa. Carcione et al. 2022, Table 1; Han & Guo (quartz, epoxy).
QUARTZ = (40.0, 39.0)
SMECTITE = (9.0, 6.0)
ILLITE = (33.0, 28.0)
CEMENT = (35.0, 30.0)
WATER = (2.2, 0.0)
QUARTZ_HG = (38.0, 44.0)
EPOXY = (6.8, 2.0)


def hs_two_phase(stiff_or_soft_1, phase_2, f1):
    """Hashin–Shtrikman two-phase formulas, Carcione et al. 2022, eqs. C.1 (K) and C.2 (mu)
    (Hashin & Shtrikman 1963; Mavko et al. 2009, eq. 4.1.1-4.1.2): the upper bound when phase 1
    is the stiffer one, the lower bound when it is the softer one."""
    (K1, G1), (K2, G2) = stiff_or_soft_1, phase_2
    f2 = 1.0 - f1
    K = K1 + f2 / (1.0 / (K2 - K1) + f1 / (K1 + 4.0 / 3.0 * G1))
    G = G1 + f2 / (1.0 / (G2 - G1) + 2.0 * f1 * (K1 + 2.0 * G1) / (5.0 * G1 * (K1 + 4.0 / 3.0 * G1)))
    return K, G


WELL_ORDERED_PAIRS = [(QUARTZ, SMECTITE), (ILLITE, SMECTITE), (QUARTZ, CEMENT), (QUARTZ_HG, EPOXY)]


@pytest.mark.parametrize("stiff, soft", WELL_ORDERED_PAIRS)
@pytest.mark.parametrize("f_stiff", [0.05, 0.3, 0.7, 0.95])
def test_hs_two_phase_equals_carcione2022_eq_c1_c2(stiff, soft, f_stiff):
    b = hashin_shtrikman([stiff[0], soft[0]], [stiff[1], soft[1]], [f_stiff, 1.0 - f_stiff])
    K_up, G_up = hs_two_phase(stiff, soft, f_stiff)
    K_lo, G_lo = hs_two_phase(soft, stiff, 1.0 - f_stiff)
    np.testing.assert_allclose([b.K_upper, b.G_upper], [K_up, G_up], rtol=1e-12)
    np.testing.assert_allclose([b.K_lower, b.G_lower], [K_lo, G_lo], rtol=1e-12)
    avg = hashin_shtrikman_average([stiff[0], soft[0]], [stiff[1], soft[1]], [f_stiff, 1 - f_stiff])
    # Carcione et al. 2022, eq. C.3: the average is the mean of the bounds.
    np.testing.assert_allclose([avg.K, avg.G], [(K_up + K_lo) / 2, (G_up + G_lo) / 2], rtol=1e-12)


def test_hs_with_water_upper_is_eq_c1_c2_and_lower_is_reuss_and_zero():
    f_q = 0.75
    b = hashin_shtrikman([QUARTZ[0], WATER[0]], [QUARTZ[1], WATER[1]], [f_q, 1 - f_q])
    K_up, G_up = hs_two_phase(QUARTZ, WATER, f_q)  # 1/(G2 - G1) = -1/G1 is finite here
    np.testing.assert_allclose([b.K_upper, b.G_upper], [K_up, G_up], rtol=1e-12)
    # Lower bound with a fluid: the fluid's zero shear modulus makes K^- the Reuss average
    # (Mavko et al. 2009, Sect. 4.1) and G^- = 0.
    np.testing.assert_allclose(b.K_lower, 1.0 / (f_q / QUARTZ[0] + (1 - f_q) / WATER[0]), rtol=1e-12)
    assert b.G_lower == 0.0


@pytest.mark.parametrize("K, G", [QUARTZ, SMECTITE, WATER, (0.0, 0.0), EPOXY])
def test_one_phase_collapses_all_bounds(K, G):
    for fn in (voigt, reuss, hill, hashin_shtrikman_average):
        m = fn([K], [G], [1.0])
        assert (float(m.K), float(m.G)) == pytest.approx((K, G), rel=1e-14, abs=1e-300)
    b = hashin_shtrikman([K], [G], [1.0])
    np.testing.assert_allclose([b.K_lower, b.K_upper], [K, K], rtol=1e-14)
    np.testing.assert_allclose([b.G_lower, b.G_upper], [G, G], rtol=1e-14)


def test_identical_phases_collapse():
    b = hashin_shtrikman([33.0] * 4, [28.0] * 4, [0.1, 0.2, 0.3, 0.4])
    np.testing.assert_allclose(np.array(b), [33.0, 28.0, 33.0, 28.0], rtol=1e-13)


def test_voigt_reuss_hill_written_out():
    K, G, f = np.array([40.0, 33.0, 9.0]), np.array([39.0, 28.0, 6.0]), np.array([0.5, 0.3, 0.2])
    v, r, h = voigt(K, G, f), reuss(K, G, f), hill(K, G, f)
    # Mavko et al. 2009, Sect. 4.2: M_V = sum f_i M_i, 1/M_R = sum f_i / M_i.
    K_V, G_V = 0.5 * 40 + 0.3 * 33 + 0.2 * 9, 0.5 * 39 + 0.3 * 28 + 0.2 * 6
    K_R, G_R = 1 / (0.5 / 40 + 0.3 / 33 + 0.2 / 9), 1 / (0.5 / 39 + 0.3 / 28 + 0.2 / 6)
    np.testing.assert_allclose([v.K, v.G, r.K, r.G], [K_V, G_V, K_R, G_R], rtol=1e-13)
    # Carcione et al. 2022, eq. 19: Hill is the mean of Voigt and Reuss.
    np.testing.assert_allclose([h.K, h.G], [(K_V + K_R) / 2, (G_V + G_R) / 2], rtol=1e-13)


def test_fluid_phase_reuss_shear_is_zero_and_voigt_finite():
    r = reuss([40.0, 2.2], [39.0, 0.0], [0.9, 0.1])
    assert r.G == 0.0
    np.testing.assert_allclose(r.K, 1 / (0.9 / 40 + 0.1 / 2.2), rtol=1e-13)
    np.testing.assert_allclose(voigt([40.0, 2.2], [39.0, 0.0], [0.9, 0.1]).G, 0.9 * 39, rtol=1e-13)


@pytest.mark.parametrize("fn", [voigt, reuss, hill, hashin_shtrikman_average])
def test_zero_fraction_phase_is_ignored_even_with_zero_moduli(fn):
    ref = fn([40.0, 9.0], [39.0, 6.0], [0.6, 0.4])
    got = fn([40.0, 0.0, 9.0, 2.2], [39.0, 0.0, 6.0, 0.0], [0.6, 0.0, 0.4, 0.0])
    np.testing.assert_allclose([got.K, got.G], [ref.K, ref.G], rtol=1e-14)


def test_zero_fraction_phase_ignored_by_hs_bounds():
    ref = hashin_shtrikman([40.0, 9.0], [39.0, 6.0], [0.6, 0.4])
    got = hashin_shtrikman([40.0, 0.0, 9.0, 100.0], [39.0, 0.0, 6.0, 90.0], [0.6, 0.0, 0.4, 0.0])
    np.testing.assert_allclose(np.array(got), np.array(ref), rtol=1e-14)


@st.composite
def phase_sets(draw):
    n = draw(st.integers(1, 5))
    moduli = st.floats(0.01, 100.0)
    K = np.array(draw(st.lists(moduli, min_size=n, max_size=n)))
    # Shear moduli: exactly 0 (fluid-like) or >= 1e-6 GPa; subnormal values are tested separately.
    shear = st.one_of(st.just(0.0), st.floats(1e-6, 80.0))
    G = np.array(draw(st.lists(shear, min_size=n, max_size=n)))
    kind = draw(st.sampled_from(["solids", "fluid", "vacuum"]))
    if kind == "fluid":
        K[0], G[0] = draw(st.floats(0.01, 5.0)), 0.0
    elif kind == "vacuum":
        K[0], G[0] = 0.0, 0.0
    # Weights 0 or >= 1e-6 (fractions near the float underflow are tested separately).
    weight = st.one_of(st.just(0.0), st.floats(1e-6, 1.0))
    w = np.array(draw(st.lists(weight, min_size=n, max_size=n)))
    if w.sum() < 1e-3:
        w[-1] = 1.0
    return K, G, w / w.sum()


@settings(max_examples=50, deadline=None)
@given(phase_sets())
def test_reuss_le_hs_lower_le_hs_upper_le_voigt(phases):
    K, G, f = phases
    v, r, b = voigt(K, G, f), reuss(K, G, f), hashin_shtrikman(K, G, f)
    tol = 1e-13 * max(K.max(), G.max())  # round-off at the scale of the stiffest phase
    for lo, mid_lo, mid_hi, hi in [(r.K, b.K_lower, b.K_upper, v.K), (r.G, b.G_lower, b.G_upper, v.G)]:
        assert lo <= mid_lo + tol
        assert mid_lo <= mid_hi + tol
        assert mid_hi <= hi + tol
        assert np.isfinite([lo, mid_lo, mid_hi, hi]).all()
    h = hill(K, G, f)
    np.testing.assert_allclose([h.K, h.G], [(v.K + r.K) / 2, (v.G + r.G) / 2], rtol=1e-14)
    if np.any((G == 0.0) & (f > 0.0)):  # any fluid/vacuum present: lower shear bound is 0
        assert b.G_lower == 0.0 and r.G == 0.0
        np.testing.assert_allclose(b.K_lower, r.K, rtol=1e-12)


@settings(max_examples=50, deadline=None)
@given(phase_sets(), st.permutations(range(5)))
def test_bounds_do_not_depend_on_phase_order(phases, perm):
    K, G, f = phases
    p = [i for i in perm if i < K.size]
    a, b = hashin_shtrikman(K, G, f), hashin_shtrikman(K[p], G[p], f[p])
    np.testing.assert_allclose(np.array(a), np.array(b), rtol=1e-12, atol=1e-13 * K.max())


def test_broadcasting_depths_by_phases_equals_loop():
    rng = np.random.default_rng(20220101)
    K = np.array([40.0, 33.0, 2.2])
    G = np.array([39.0, 28.0, 0.0])
    f = rng.dirichlet([2.0, 1.0, 1.0], size=10)  # 10 depths x 3 phases
    f[3] = [1.0, 0.0, 0.0]
    for fn in (voigt, reuss, hill, hashin_shtrikman, hashin_shtrikman_average):
        out = np.array(fn(K, G, f))
        assert out.shape[1:] == (10,)
        loop = np.array([np.array(fn(K, G, row)) for row in f]).T
        np.testing.assert_allclose(out, loop, rtol=1e-14)
    # K and G may vary per depth too, and leading axes stack (2 x 10 x 3).
    K2 = np.broadcast_to(K, (2, 10, 3)) * np.array([1.0, 1.1])[:, None, None]
    b = hashin_shtrikman(K2, G, f)
    assert b.K_upper.shape == (2, 10)
    np.testing.assert_allclose(b.K_upper[0], hashin_shtrikman(K, G, f).K_upper, rtol=1e-14)


def test_inputs_not_mutated_and_read_only_accepted():
    K, G, f = np.array([40.0, 0.0, 2.2]), np.array([39.0, 0.0, 0.0]), np.array([0.7, 0.0, 0.3])
    copies = [a.copy() for a in (K, G, f)]
    for a in (K, G, f):
        a.setflags(write=False)
    for fn in (voigt, reuss, hill, hashin_shtrikman, hashin_shtrikman_average):
        fn(K, G, f)
    for a, c in zip((K, G, f), copies):
        np.testing.assert_array_equal(a, c)


def test_lists_tuples_and_arrays_give_same_values():
    a = hashin_shtrikman([40.0, 9.0], (39.0, 6.0), [0.3, 0.7])
    b = hashin_shtrikman(np.array([40.0, 9.0]), np.array([39.0, 6.0]), np.array([0.3, 0.7]))
    c = hashin_shtrikman([40, 9], [39, 6], [0.3, 0.7])  # integers
    np.testing.assert_array_equal(np.array(a), np.array(b))
    np.testing.assert_array_equal(np.array(a), np.array(c))


def test_bounds_namedtuple_properties():
    b = Bounds(1.0, 2.0, 3.0, 5.0)
    assert b.lower == Moduli(1.0, 2.0) and b.upper == Moduli(3.0, 5.0)
    assert b.average == Moduli(2.0, 3.5)


FUNCS = [voigt, reuss, hill, hashin_shtrikman, hashin_shtrikman_average]
BAD = [
    pytest.param(([-1.0, 9.0], [39.0, 6.0], [0.5, 0.5]), "K", id="negative-K"),
    pytest.param(([40.0, 9.0], [39.0, -6.0], [0.5, 0.5]), "G", id="negative-G"),
    pytest.param(([40.0, 9.0], [39.0, 6.0], [0.5, 0.4]), "fractions", id="sum-not-1"),
    pytest.param(([40.0, 9.0], [39.0, 6.0], [1.5, -0.5]), "fractions", id="fraction-outside-0-1"),
    pytest.param(([40.0, 9.0, 2.2], [39.0, 6.0], [0.5, 0.5]), "K", id="mismatched-shapes"),
    pytest.param(([40.0, np.nan], [39.0, 6.0], [0.5, 0.5]), "K", id="nan-K"),
    pytest.param(([40.0, 9.0], [39.0, 6.0], [np.nan, 0.5]), "fractions", id="nan-fractions"),
    pytest.param(([40.0, np.inf], [39.0, 6.0], [0.5, 0.5]), "K", id="infinite-K"),
    pytest.param(([40.0 + 1j, 9.0], [39.0, 6.0], [0.5, 0.5]), "K", id="complex-list"),
    pytest.param((40.0, 39.0, 1.0), "fractions", id="no-phase-axis"),
    pytest.param((np.array([40.0, 9.0], dtype=complex), [39.0, 6.0], [0.5, 0.5]), "K",
                 id="complex-array"),
]


@pytest.mark.parametrize("fn", FUNCS, ids=lambda f: f.__name__)
@pytest.mark.parametrize("args, name", BAD)
def test_bad_input_raises_value_error_naming_argument(fn, args, name):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a clean ValueError, with no warning on the way
        with pytest.raises(ValueError, match=rf"\b{name}\b"):
            fn(*args)


def test_hs_bounds_never_negative_for_trace_of_solid_in_water():
    b = hashin_shtrikman([2.2, 35.0], [0.0, 30.0], [1.0, 1e-20])  # water + a trace of cement
    assert min(b) >= 0.0


@pytest.mark.parametrize("fn", [reuss, hashin_shtrikman], ids=lambda f: f.__name__)
@pytest.mark.parametrize("G, f", [([5e-324, 39.0], [0.5, 0.5]), ([0.0, 4.0], [1.0, 2.2e-308])],
                         ids=["subnormal-G", "tiny-fraction"])
def test_underflowing_values_give_no_warning(fn, G, f):
    # f / (G + s) or 1 / sum(...) underflowing to ~1e-309 must not overflow with a warning.
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        out = fn([1.0, 40.0], G, f)
    assert out[1] == pytest.approx(0.0, abs=1e-300)  # reuss G, or the HS lower G
