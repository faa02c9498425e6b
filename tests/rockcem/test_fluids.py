"""Tests of rockcem.fluids: Gassmann, its inverse, and the generalized (multi-mineral) Gassmann.

Expected values are written out here from Gassmann (1951) in the forms of Mavko et al. 2009,
Sect. 6.3, from Carcione et al. 2022, eqs. 4-6 and 10-12 (Carcione et al. 2005), or are analytic
limits. Moduli from Carcione et al. 2022, Table 1 (quartz K = 40, illite K = 33, water K = 2.2).
"""

import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rockcem.fluids import gassmann, gassmann_dry, generalized_gassmann, generalized_gassmann_dry

K_QUARTZ, K_ILLITE, K_SMECTITE, K_WATER = 40.0, 33.0, 9.0, 2.2


def gassmann_mavko(K_dry, K0, K_fl, phi):
    """Mavko et al. 2009, Sect. 6.3 (Gassmann 1951), the form
    K_sat/(K0 - K_sat) = K_dry/(K0 - K_dry) + K_fl/(phi (K0 - K_fl)), solved for K_sat."""
    q = K_dry / (K0 - K_dry) + K_fl / (phi * (K0 - K_fl))
    return K0 * q / (1.0 + q)


def gassmann_biot(K_dry, K_s, K_f, phi):
    """Carcione et al. 2022, eqs. 4-6: K_G = K_m + alpha^2 M, M = [(alpha - phi)/K_s + phi/K_f]^-1."""
    alpha = 1.0 - K_dry / K_s
    return K_dry + alpha**2 / ((alpha - phi) / K_s + phi / K_f)


@pytest.mark.parametrize("K_dry, K_min, K_fl, phi", [
    (10.0, K_QUARTZ, K_WATER, 0.2), (2.0, K_QUARTZ, K_WATER, 0.35), (25.0, K_ILLITE, K_WATER, 0.05),
    (1.0, K_SMECTITE, 1.0, 0.4), (17.3, K_QUARTZ, 0.05, 0.2),
])
def test_gassmann_equals_mavko_form_and_biot_form(K_dry, K_min, K_fl, phi):
    got = gassmann(K_dry, K_min, K_fl, phi)
    np.testing.assert_allclose(got, gassmann_mavko(K_dry, K_min, K_fl, phi), rtol=1e-12)
    np.testing.assert_allclose(got, gassmann_biot(K_dry, K_min, K_fl, phi), rtol=1e-12)


def test_gassmann_limits():
    # phi -> 0: every frame saturates to the mineral (Mavko et al. 2009, Sect. 6.3).
    np.testing.assert_allclose(gassmann(10.0, K_QUARTZ, K_WATER, 0.0), K_QUARTZ, rtol=1e-14)
    np.testing.assert_allclose(gassmann(10.0, K_QUARTZ, K_WATER, 1e-12), K_QUARTZ, rtol=1e-9)
    # K_dry = K_min: no pore compliance, nothing to stiffen.
    phi = np.array([0.0, 0.1, 0.5, 1.0])
    np.testing.assert_allclose(gassmann(K_QUARTZ, K_QUARTZ, K_WATER, phi), K_QUARTZ, rtol=1e-14)
    # K_fluid = 0: an empty pore gives back the dry frame exactly.
    K_dry = np.array([0.0, 1.0, 10.0, 39.0])
    assert np.array_equal(gassmann(K_dry, K_QUARTZ, 0.0, 0.3), K_dry)
    # K_dry = 0 (suspension): Reuss average of mineral and fluid (Mavko et al. 2009, Sect. 6.3).
    np.testing.assert_allclose(gassmann(0.0, K_QUARTZ, K_WATER, 0.3),
                               1.0 / (0.7 / K_QUARTZ + 0.3 / K_WATER), rtol=1e-13)


def test_gassmann_monotone_in_fluid_modulus():
    K_fl = np.linspace(0.0, K_QUARTZ, 401)
    K_sat = gassmann(10.0, K_QUARTZ, K_fl, 0.2)
    assert np.all(np.diff(K_sat) > 0.0)
    assert K_sat[0] == 10.0 and K_sat[-1] == pytest.approx(K_QUARTZ, rel=1e-13)


dry_sat_cases = st.tuples(
    st.floats(5.0, 100.0),   # K_min
    st.floats(0.0, 0.999),   # K_dry / K_min
    st.floats(0.0, 0.5),     # K_fluid / K_min
    st.floats(0.02, 0.6),    # phi
)


@settings(max_examples=50, deadline=None)
@given(dry_sat_cases)
def test_dry_sat_dry_round_trip(case):
    K_min, u, v, phi = case
    K_dry = u * K_min
    K_sat = gassmann(K_dry, K_min, v * K_min, phi)
    assume(K_sat > 0.0)  # K_dry = K_fluid = 0: gassmann_dry documents K_sat in (0, K_min]
    assert K_dry <= K_sat <= K_min * (1 + 1e-14)
    np.testing.assert_allclose(gassmann_dry(K_sat, K_min, v * K_min, phi), K_dry,
                               rtol=1e-10, atol=1e-10 * K_min)


def test_gassmann_dry_of_reuss_suspension_is_zero():
    K_reuss = 1.0 / (0.7 / K_QUARTZ + 0.3 / K_WATER)
    np.testing.assert_allclose(gassmann_dry(K_reuss, K_QUARTZ, K_WATER, 0.3), 0.0, atol=1e-12)


def test_floats_lists_and_arrays_agree_and_broadcast():
    phi = np.array([0.05, 0.2, 0.35])
    arr = gassmann(np.array([[20.0], [5.0]]), K_QUARTZ, K_WATER, phi)  # (2, 1) x (3,) -> (2, 3)
    assert arr.shape == (2, 3)
    for i, K_dry in enumerate([20.0, 5.0]):
        for j, p in enumerate(phi.tolist()):
            assert float(gassmann(K_dry, K_QUARTZ, K_WATER, p)) == arr[i, j]
            assert float(gassmann_dry(arr[i, j], K_QUARTZ, K_WATER, p)) == \
                gassmann_dry(arr, K_QUARTZ, K_WATER, phi)[i, j]
    np.testing.assert_array_equal(gassmann([20.0, 5.0], 40, 2.2, [0.2, 0.3]),
                                  gassmann(np.array([20.0, 5.0]), 40.0, 2.2, np.array([0.2, 0.3])))


def test_inputs_not_mutated():
    K_dry, phi = np.array([10.0, 5.0]), np.array([0.2, 0.3])
    K_dry.setflags(write=False)
    phi.setflags(write=False)
    K_sat = gassmann(K_dry, K_QUARTZ, K_WATER, phi)
    K_sat.setflags(write=False)
    gassmann_dry(K_sat, K_QUARTZ, K_WATER, phi)
    np.testing.assert_array_equal(K_dry, [10.0, 5.0])


# --- generalized Gassmann, Carcione et al. 2022 eqs. 10-12 (Carcione et al. 2005) -----------------

def carcione_eq10(K_mi, K_i, beta, K_f, phi):
    """Eqs. 10-12 of Carcione et al. 2022 written out, with the exponent 2 of Carcione et al. 2005:
    K_G = sum K_mi + (sum alpha_i)^2 M, M = (sum phi'_i/K_i + phi/K_f)^-1,
    phi'_i = alpha_i - beta_i phi, alpha_i = beta_i - K_mi/K_i."""
    alpha = [b - km / k for km, k, b in zip(K_mi, K_i, beta)]
    inv_M = sum((a - b * phi) / k for a, b, k in zip(alpha, beta, K_i)) + phi / K_f
    return sum(K_mi) + sum(alpha) ** 2 / inv_M


@pytest.mark.parametrize("K_mi, K_i, beta, K_f, phi", [
    ([8.0, 3.0], [K_QUARTZ, K_ILLITE], [0.7, 0.3], K_WATER, 0.2),
    ([1.5, 0.4], [K_QUARTZ, K_SMECTITE], [0.4, 0.6], K_WATER, 0.3),
    ([5.0, 2.0, 0.5], [K_QUARTZ, K_ILLITE, K_SMECTITE], [0.5, 0.3, 0.2], 1.0, 0.15),
])
def test_generalized_gassmann_equals_carcione2022_eqs_10_12(K_mi, K_i, beta, K_f, phi):
    got = generalized_gassmann(K_mi, K_i, beta, K_f, phi)
    np.testing.assert_allclose(got, carcione_eq10(K_mi, K_i, beta, K_f, phi), rtol=1e-12)


@pytest.mark.parametrize("K_dry, K_fl, phi", [(10.0, K_WATER, 0.2), (0.5, 0.0, 0.4), (30.0, 5.0, 0.0)])
def test_generalized_gassmann_one_solid_and_identical_solids_equal_gassmann(K_dry, K_fl, phi):
    ref = gassmann(K_dry, K_QUARTZ, K_fl, phi)
    np.testing.assert_allclose(generalized_gassmann([K_dry], [K_QUARTZ], [1.0], K_fl, phi), ref,
                               rtol=1e-13)
    beta = np.array([0.2, 0.5, 0.3])
    same = generalized_gassmann(beta * K_dry, [K_QUARTZ] * 3, beta, K_fl, phi)
    np.testing.assert_allclose(same, ref, rtol=1e-13)


@settings(max_examples=50, deadline=None)
@given(
    st.lists(st.floats(5.0, 80.0), min_size=1, max_size=4),  # K_i
    st.lists(st.floats(0.05, 1.0), min_size=4, max_size=4),  # weights -> beta
    st.floats(0.0, 0.95),                                     # K_m / Reuss(K_i)
    st.floats(0.5, 4.0),                                      # K_fluid (< every K_i)
    st.floats(0.02, 0.6),                                     # phi
)
def test_generalized_inverse_round_trip(K_i, w, u, K_f, phi):
    K_i = np.array(K_i)
    beta = np.array(w[: K_i.size]) / np.sum(w[: K_i.size])
    K_m = u / np.sum(beta / K_i)
    weights = beta * K_i / np.sum(beta * K_i)   # eq. 13 partition K_mi = w_i K_m
    K_sat = generalized_gassmann(weights * K_m, K_i, beta, K_f, phi)
    np.testing.assert_allclose(K_sat, carcione_eq10(weights * K_m, K_i, beta, K_f, phi), rtol=1e-12)
    np.testing.assert_allclose(generalized_gassmann_dry(K_sat, K_i, beta, K_f, phi), K_m,
                               rtol=1e-9, atol=1e-10 * K_i.max())


def test_generalized_inverse_one_solid_equals_gassmann_dry():
    K_sat = np.array([9.5, 15.0, 30.0])  # Reuss suspension value here is 9.02
    np.testing.assert_allclose(generalized_gassmann_dry(K_sat, [K_QUARTZ], [1.0], K_WATER, 0.2),
                               gassmann_dry(K_sat, K_QUARTZ, K_WATER, 0.2), rtol=1e-12)


def test_generalized_inverse_fluid_as_stiff_as_solid_is_a_clear_error():
    # With K_fluid = K_min every frame saturates to K_min: the inverse is undefined.
    with pytest.raises(ValueError):
        gassmann_dry(5.0, 5.0, 5.0, 0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        with pytest.raises(ValueError):
            generalized_gassmann_dry(5.0, [5.0], [1.0], 5.0, 0.5)


def test_generalized_one_solid_of_two_is_that_solid_alone():
    """With all the solid in one mineral (fractions [1, 0]) the other mineral does not count:
    Gassmann's equation with that mineral (each of the issue-24 minerals alone: 15-18 GPa)."""
    for k, K_min in enumerate([36.6, 76.8]):
        beta = [1.0 - k, float(k)]
        frame = [10.0 * (1 - k), 10.0 * k]
        got = generalized_gassmann(frame, [36.6, 76.8], beta, 2.25, 0.2)
        np.testing.assert_allclose(got, gassmann(10.0, K_min, 2.25, 0.2), rtol=1e-13)
        assert 15.0 < float(got) < 18.0


def test_generalized_broadcasts_over_depths():
    rng = np.random.default_rng(2005)
    beta = rng.dirichlet([1.0, 1.0], size=10)
    K_mi = beta * np.array([8.0, 3.0])
    phi = np.linspace(0.05, 0.4, 10)
    out = generalized_gassmann(K_mi, [K_QUARTZ, K_ILLITE], beta, K_WATER, phi)
    loop = [carcione_eq10(K_mi[d], [K_QUARTZ, K_ILLITE], beta[d], K_WATER, phi[d]) for d in range(10)]
    np.testing.assert_allclose(out, loop, rtol=1e-12)


# --- bad input --------------------------------------------------------------------------------

G2 = ([8.0, 3.0], [40.0, 33.0], [0.7, 0.3], 2.2, 0.2)   # a valid generalized_gassmann call


def _gg(**kw):
    names = ["K_frame", "K_solid", "solid_fractions", "K_fluid", "phi"]
    args = dict(zip(names, G2)) | kw
    return lambda: generalized_gassmann(*args.values())


BAD = [
    pytest.param(lambda: gassmann(10.0, 40.0, 2.2, -0.1), "phi", id="phi-negative"),
    pytest.param(lambda: gassmann(10.0, 40.0, 2.2, 1.5), "phi", id="phi-above-1"),
    pytest.param(lambda: gassmann(-1.0, 40.0, 2.2, 0.2), "K_dry", id="K_dry-negative"),
    pytest.param(lambda: gassmann(10.0, -40.0, 2.2, 0.2), "K_min", id="K_min-negative"),
    pytest.param(lambda: gassmann(10.0, 0.0, 2.2, 0.2), "K_min", id="K_min-zero"),
    pytest.param(lambda: gassmann(10.0, 40.0, -2.2, 0.2), "K_fluid", id="K_fluid-negative"),
    pytest.param(lambda: gassmann(10.0, 40.0, 2.2, np.nan), "phi", id="phi-nan"),
    pytest.param(lambda: gassmann(10.0, 40.0, 2.2 + 1j, 0.2), "K_fluid", id="K_fluid-complex"),
    pytest.param(lambda: gassmann(np.array([10.0 + 0j]), 40.0, 2.2, 0.2), "K_dry",
                 id="K_dry-complex-array"),
    pytest.param(lambda: gassmann([10.0, 5.0], 40.0, 2.2, [0.1, 0.2, 0.3]), "K_dry",
                 id="mismatched-shapes"),
    pytest.param(lambda: gassmann(41.0, 40.0, 2.2, 0.2), "K_dry", id="K_dry-above-K_min"),
    pytest.param(lambda: gassmann_dry(20.0, 40.0, 2.2, 0.0), "phi", id="dry-phi-zero"),
    pytest.param(lambda: gassmann_dry(5.0, 40.0, 2.2, 0.3), "K_sat", id="dry-below-reuss"),
    pytest.param(lambda: gassmann_dry(41.0, 40.0, 2.2, 0.3), "K_sat", id="dry-above-K_min"),
    pytest.param(lambda: gassmann_dry(-1.0, 40.0, 2.2, 0.3), "K_sat", id="dry-K_sat-negative"),
    pytest.param(_gg(solid_fractions=[0.7, 0.4]), "solid_fractions", id="gen-sum-not-1"),
    pytest.param(_gg(solid_fractions=[1.2, -0.2]), "solid_fractions", id="gen-fraction-range"),
    pytest.param(_gg(K_frame=[8.0, 3.0, 1.0]), "K_frame", id="gen-mismatched-K_frame"),
    pytest.param(_gg(K_frame=[-8.0, 3.0]), "K_frame", id="gen-negative-K_frame"),
    pytest.param(_gg(K_solid=[0.0, 33.0]), "K_solid", id="gen-zero-K_solid"),
    pytest.param(_gg(phi=1.0), "phi", id="gen-phi-1"),
    pytest.param(_gg(phi=[0.1, 0.2, 0.3], K_frame=[[8.0, 3.0]] * 2), "phi",
                 id="gen-phi-mismatched-depths"),
    pytest.param(_gg(phi=[0.1, 0.2], K_fluid=[2.2, 2.2, 2.2]), "phi",
                 id="gen-K_fluid-phi-mismatched"),
    pytest.param(lambda: generalized_gassmann_dry(10.0, [40.0, 33.0], [0.7, 0.3], 0.0, 0.2),
                 "K_fluid", id="gen-dry-K_fluid-zero"),
    pytest.param(lambda: generalized_gassmann_dry(10.0, [40.0, 33.0], [0.7, 0.3], 2.2, 0.0),
                 "phi", id="gen-dry-phi-zero"),
    pytest.param(lambda: generalized_gassmann_dry(3.0, [40.0, 33.0], [0.7, 0.3], 2.2, 0.3),
                 "K_sat", id="gen-dry-below-reuss"),
    # Issue 24: one fraction against two solids was stretched to [1, 1] after the sum-to-one
    # check (42.8 GPa); a scalar frame modulus was counted once per solid.
    pytest.param(lambda: generalized_gassmann(10.0, [36.6, 76.8], [1.0], 2.25, 0.2),
                 "solid_fractions", id="gen-one-fraction-two-solids"),
    pytest.param(lambda: generalized_gassmann([10.0, 0.0], [36.6, 76.8], [1.0], 2.25, 0.2),
                 "solid_fractions", id="gen-one-fraction-two-frames"),
    pytest.param(lambda: generalized_gassmann(10.0, [36.6, 76.8], [1.0, 0.0], 2.25, 0.2),
                 "K_frame", id="gen-scalar-frame-two-solids"),
    pytest.param(lambda: generalized_gassmann_dry(15.0, [36.6, 76.8], [1.0], 2.25, 0.2),
                 "solid_fractions", id="gen-dry-one-fraction-two-solids"),
    pytest.param(lambda: generalized_gassmann_dry([15.0] * 3, [36.6, 76.8], [0.5, 0.5], 2.25,
                                                  [0.2, 0.3]), "K_sat", id="gen-dry-shapes"),
    pytest.param(lambda: generalized_gassmann(*G2[:3], 2.2, "0.2"), "phi", id="gen-phi-text"),
]


@pytest.mark.parametrize("call, name", BAD)
def test_bad_input_raises_value_error_naming_argument(call, name, expect_value_error):
    expect_value_error(call, name)
