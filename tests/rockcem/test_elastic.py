"""Tests of rockcem.elastic: Poisson ratio, velocities and the P-wave modulus.

Expected values come from published tables (Carcione et al. 2022, Table 1; Garcia & Medina,
Tables I-II) and from the isotropic relations written out here (Mavko et al. 2009, Sect. 2.2;
Carcione et al. 2022, eqs. 22-25).
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rockcem.elastic import Moduli, Velocities, p_wave_modulus, poisson_ratio, velocities


def test_velocities_quartz_carcione2022_table1():
    # Quartz K = 40, mu = 39 GPa, rho = 2.65 g/cm3; eqs. 22-25: vp = sqrt((K + 4/3 mu)/rho).
    v = velocities(40.0, 39.0, 2.65)
    assert isinstance(v, Velocities)
    np.testing.assert_allclose(v.vp, math.sqrt((40.0 + 52.0) / 2.65), rtol=1e-14)
    np.testing.assert_allclose(v.vs, math.sqrt(39.0 / 2.65), rtol=1e-14)


def test_velocities_water_has_no_shear_wave():
    v = velocities(2.2, 0.0, 1.04)  # water, Carcione et al. 2022, Table 1
    assert v.vs == 0.0
    np.testing.assert_allclose(v.vp, math.sqrt(2.2 / 1.04), rtol=1e-14)


@pytest.mark.parametrize("vp, vs, rho", [(3.0, 1.8, 2.65), (1.5, 0.9, 2.65)])
def test_velocities_back_from_garcia_medina_table2_moduli(vp, vs, rho):
    # Garcia & Medina, Table II (hard and soft cement): G = rho vs^2, K = rho (vp^2 - 4/3 vs^2).
    K, G = rho * (vp**2 - 4.0 / 3.0 * vs**2), rho * vs**2
    v = velocities(K, G, rho)
    np.testing.assert_allclose([v.vp, v.vs], [vp, vs], rtol=1e-14)
    # nu from velocities (Mavko et al. 2009, Sect. 2.2): (vp^2 - 2 vs^2) / (2 (vp^2 - vs^2)).
    nu = (vp**2 - 2 * vs**2) / (2 * (vp**2 - vs**2))
    np.testing.assert_allclose(poisson_ratio(K, G), nu, rtol=1e-13)
    np.testing.assert_allclose(p_wave_modulus(K, G), rho * vp**2, rtol=1e-14)


def test_poisson_ratio_garcia_medina_table1_quartz():
    # Garcia & Medina, Table I: quartz G = 44 GPa, nu = 0.08; K from K = 2G(1+nu)/(3(1-2nu)).
    K = 2 * 44.0 * 1.08 / (3 * (1 - 0.16))
    np.testing.assert_allclose(poisson_ratio(K, 44.0), 0.08, rtol=1e-13)


def test_poisson_ratio_limits():
    assert poisson_ratio(2.2, 0.0) == 0.5            # fluid
    np.testing.assert_allclose(poisson_ratio(2.0, 3.0), 0.0, atol=1e-16)  # 3K = 2G
    # Young's modulus route: E = 9KG/(3K+G), nu = E/(2G) - 1 (Mavko et al. 2009, Sect. 2.2).
    K, G = 40.0, 39.0
    np.testing.assert_allclose(poisson_ratio(K, G), 9 * K * G / (3 * K + G) / (2 * G) - 1, rtol=1e-13)
    tiny = poisson_ratio(1.0, 1e6)                  # G >> K approaches -1 from above
    assert -1.0 < tiny < -0.99


@settings(max_examples=50, deadline=None)
@given(st.floats(0.01, 200.0), st.floats(0.0, 200.0), st.floats(0.1, 10.0))
def test_isotropic_relations_hold(K, G, rho):
    v = velocities(K, G, rho)
    np.testing.assert_allclose(rho * v.vp**2, K + 4.0 / 3.0 * G, rtol=1e-13)
    np.testing.assert_allclose(rho * v.vs**2, G, rtol=1e-13, atol=1e-300)
    np.testing.assert_allclose(p_wave_modulus(K, G), rho * v.vp**2, rtol=1e-13)
    nu = float(poisson_ratio(K, G))
    assert -1.0 < nu <= 0.5
    # Inverting nu with G recovers K (G > 0): K = 2G(1+nu)/(3(1-2nu)).
    if G > 1e-3 and nu < 0.49:
        np.testing.assert_allclose(2 * G * (1 + nu) / (3 * (1 - 2 * nu)), K, rtol=1e-9)


def test_broadcasting_and_floats_equal_arrays():
    K = np.array([[40.0], [33.0]])
    G = np.array([39.0, 28.0, 0.0])
    v = velocities(K, G, 2.65)
    assert v.vp.shape == (2, 3)
    for i, k in enumerate([40.0, 33.0]):
        for j, g in enumerate([39.0, 28.0, 0.0]):
            w = velocities(k, g, 2.65)
            assert (float(w.vp), float(w.vs)) == (v.vp[i, j], v.vs[i, j])
            assert float(poisson_ratio(k, g)) == poisson_ratio(K, G)[i, j]
    np.testing.assert_array_equal(p_wave_modulus([40, 33], [39, 28]),
                                  p_wave_modulus(np.array([40.0, 33.0]), np.array([39.0, 28.0])))


def test_moduli_namedtuple():
    m = Moduli(1.0, 2.0)
    assert m.K == 1.0 and m.G == 2.0 and tuple(m) == (1.0, 2.0)


def test_inputs_not_mutated():
    K, G, rho = np.array([40.0, 2.2]), np.array([39.0, 0.0]), np.array([2.65, 1.04])
    for a in (K, G, rho):
        a.setflags(write=False)
    velocities(K, G, rho)
    poisson_ratio(K, G)
    p_wave_modulus(K, G)
    np.testing.assert_array_equal(G, [39.0, 0.0])


BAD = [
    pytest.param(lambda: velocities(-1.0, 1.0, 2.0), "K", id="vel-negative-K"),
    pytest.param(lambda: velocities(1.0, -1.0, 2.0), "G", id="vel-negative-G"),
    pytest.param(lambda: velocities(1.0, 1.0, 0.0), "density", id="vel-zero-density"),
    pytest.param(lambda: velocities(1.0, np.nan, 2.0), "G", id="vel-nan"),
    pytest.param(lambda: velocities(1.0 + 2j, 1.0, 2.0), "K", id="vel-complex"),
    pytest.param(lambda: velocities(np.array([1.0 + 0j]), 1.0, 2.0), "K", id="vel-complex-arr"),
    pytest.param(lambda: velocities([1.0, 2.0], [1.0, 2.0, 3.0], 2.0), "G", id="vel-mismatched"),
    pytest.param(lambda: poisson_ratio(0.0, 1.0), "K", id="nu-zero-K"),
    pytest.param(lambda: poisson_ratio(1.0, -1.0), "G", id="nu-negative-G"),
    pytest.param(lambda: poisson_ratio([1.0, 2.0], [1.0, 2.0, 3.0]), "G", id="nu-mismatched"),
    pytest.param(lambda: p_wave_modulus(np.nan, 1.0), "K", id="M-nan"),
    pytest.param(lambda: p_wave_modulus(1.0, 1.0 + 1j), "G", id="M-complex"),
    pytest.param(lambda: p_wave_modulus(-1.0, 1.0), "K", id="M-negative-K"),
    pytest.param(lambda: p_wave_modulus([1.0, 2.0], [1.0, 2.0, 3.0]), "G", id="M-mismatched"),
]


@pytest.mark.parametrize("call, name", BAD)
def test_bad_input_raises_value_error_naming_argument(call, name, expect_value_error):
    expect_value_error(call, name)
