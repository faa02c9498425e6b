"""Batzle & Wang (1992) at one state, hand-computed from the printed equations (issue 30, item 6).

The other tests of ``rockcem.pore_fluids`` compare with tables, figures and other equations of
state at 0.5-1.5 %, or by inequalities: a slip of one coefficient or one dropped term can hide
under those tolerances. Here every equation is transcribed again, independently of the module
(Table 1 typed by pressure column, eq. 10b's derivative taken numerically, the live-oil density
built from its bubble point), evaluated at one state, and compared at 1e-9. The hand-computed
numbers are written next to each equation (rounded; computed with this file's transcription,
which is all in plain ``math``).

State: 80 degC, 30 MPa; brine of salinity 0.1; a dead oil of 0.85 g/cm3; a live oil of
80 L/L of 0.7-gravity gas in it (bubble point 14.02 MPa); a gas of gravity 0.7.
"""

import math

import pytest

from rockcem import pore_fluids as pf

T, P = 80.0, 30.0
S = 0.1
RHO0, R_G, G_GAS = 0.85, 80.0, 0.7
R_GAS = 8.314462618                     # J/(mol K), CODATA (B&W print 8.3144)
RTOL = 1e-9

# Table 1 of Batzle & Wang (1992), m/s: one row per power of P (P^0 ... P^3), one entry per
# power of T (T^0 ... T^4) — typed here by column, the transpose of the printed table.
TABLE1_BY_P = [
    [1402.85, 4.871, -0.04783, 1.487e-4, -2.197e-7],
    [1.524, -0.0111, 2.747e-4, -6.503e-7, 7.987e-10],
    [3.437e-3, 1.739e-4, -2.135e-6, -1.455e-8, 5.230e-11],
    [-1.197e-5, -1.628e-6, 1.237e-8, 1.327e-10, -4.614e-13],
]


def water_density(t, p):
    """Eq. 27a, g/cm3."""
    return 1 + 1e-6 * (-80 * t - 3.3 * t**2 + 0.00175 * t**3 + 489 * p - 2 * t * p
                       + 0.016 * t**2 * p - 1.3e-5 * t**3 * p - 0.333 * p**2 - 0.002 * t * p**2)


def water_velocity(t, p):
    """Eq. 28 with Table 1, m/s."""
    return sum(TABLE1_BY_P[j][i] * t**i * p**j for i in range(5) for j in range(4))


def test_water_eqs_27a_28():
    rho = water_density(T, P)               # 0.985675
    v = water_velocity(T, P)                # 1614.53 m/s
    assert rho == pytest.approx(0.985675, abs=1e-6) and v == pytest.approx(1614.53, abs=0.01)
    w = pf.water(T, P)
    assert float(w.rho) == pytest.approx(rho, rel=RTOL)
    assert float(w.vp) == pytest.approx(v / 1000.0, rel=RTOL)
    assert float(w.K) == pytest.approx(rho * (v / 1000.0) ** 2, rel=RTOL)


def test_brine_eqs_27b_29():
    """Eq. 29 with -820 S^2 (the module's note 1: not the printed -1820)."""
    rho = water_density(T, P) + S * (0.668 + 0.44 * S + 1e-6 * (
        300 * P - 2400 * P * S + T * (80 + 3 * T - 3300 * S - 13 * P + 47 * P * S)))
    v = (water_velocity(T, P)
         + S * (1170 - 9.6 * T + 0.055 * T**2 - 8.5e-5 * T**3 + 2.6 * P - 0.0029 * T * P
                - 0.0476 * P**2)
         + S**1.5 * (780 - 10 * P + 0.16 * P**2) - 820 * S**2)
    assert rho == pytest.approx(1.054983, abs=1e-6)          # g/cm3
    assert v == pytest.approx(1699.93, abs=0.01)              # m/s
    b = pf.brine(T, P, S)
    assert float(b.rho) == pytest.approx(rho, rel=RTOL)
    assert float(b.vp) == pytest.approx(v / 1000.0, rel=RTOL)
    assert float(b.K) == pytest.approx(rho * (v / 1000.0) ** 2, rel=RTOL)


def dead_oil_pressure(rho0, p):
    """Eq. 18: the oil of density rho0 (0.1 MPa, 15.6 degC) at pressure p, g/cm3."""
    return rho0 + (0.00277 * p - 1.71e-7 * p**3) * (rho0 - 1.15) ** 2 + 3.49e-4 * p


def eq19_denominator(t):
    return 0.972 + 3.81e-4 * (t + 17.78) ** 1.175


def eq20b(rho, t, p):
    """Eq. 20b, m/s."""
    return (2096 * math.sqrt(rho / (2.6 - rho)) - 3.7 * t + 4.64 * p
            + 0.0115 * (4.12 * math.sqrt(1.08 / rho - 1) - 1) * t * p)


def test_dead_oil_eqs_18_19_20b():
    rho = dead_oil_pressure(RHO0, P) / eq19_denominator(T)     # 0.822248 g/cm3
    v = eq20b(RHO0, T, P)                                      # 1335.52 m/s
    assert rho == pytest.approx(0.822248, abs=1e-6) and v == pytest.approx(1335.52, abs=0.01)
    o = pf.oil(T, P, reference_density=RHO0)
    assert float(o.rho) == pytest.approx(rho, rel=RTOL)
    assert float(o.vp) == pytest.approx(v / 1000.0, rel=RTOL)
    assert float(o.K) == pytest.approx(rho * (v / 1000.0) ** 2, rel=RTOL)
    # eq. 14 for API input: the same oil
    api = 141.5 / RHO0 - 131.5
    assert float(pf.oil(T, P, api=api).K) == pytest.approx(float(o.K), rel=RTOL)


def test_live_oil_eqs_21a_to_24():
    """Eq. 21a (bubble point), 23 (B0), 22 (pseudo-density, in eq. 20b), 24 (density at the
    bubble point), and above the bubble point the gas-free oil's compression from P_b to P
    (eq. 18's increment over eq. 19's denominator: the module's note 5)."""
    P_b = (R_G / (0.02123 * G_GAS)) ** (1 / 1.205) / math.exp(4.072 / RHO0 - 0.00377 * T)
    assert P_b == pytest.approx(14.0203, abs=1e-4)                        # MPa
    R_max = 0.02123 * G_GAS * (P * math.exp(4.072 / RHO0 - 0.00377 * T)) ** 1.205
    assert R_max == pytest.approx(200.068, abs=1e-3)                      # L/L
    B0 = 0.972 + 0.00038 * (2.4 * R_G * math.sqrt(G_GAS / RHO0) + T + 17.8) ** 1.175
    rho_pseudo = RHO0 / B0 / (1 + 0.001 * R_G)
    rho_G = (RHO0 + 0.0012 * G_GAS * R_G) / B0                            # eq. 24, at P_b
    rho = rho_G + (dead_oil_pressure(RHO0, P) - dead_oil_pressure(RHO0, P_b)) \
        / eq19_denominator(T)
    v = eq20b(rho_pseudo, T, P)
    assert B0 == pytest.approx(1.247722, abs=1e-6)
    assert rho_G == pytest.approx(0.735100, abs=1e-6)
    assert rho == pytest.approx(0.743807, abs=1e-6)                       # g/cm3
    assert v == pytest.approx(1097.83, abs=0.01)                          # m/s
    o = pf.oil(T, P, reference_density=RHO0, gas_oil_ratio=R_G, gas_gravity=G_GAS)
    assert float(o.rho) == pytest.approx(rho, rel=RTOL)
    assert float(o.vp) == pytest.approx(v / 1000.0, rel=RTOL)
    assert float(o.K) == pytest.approx(rho * (v / 1000.0) ** 2, rel=RTOL)
    assert float(pf.bubble_point_pressure(T, R_G, reference_density=RHO0, gas_gravity=G_GAS)) \
        == pytest.approx(P_b, rel=RTOL)
    assert float(pf.max_gas_oil_ratio(T, P, reference_density=RHO0, gas_gravity=G_GAS)) \
        == pytest.approx(R_max, rel=RTOL)


def test_live_oil_at_its_bubble_point_is_eq_24():
    """At P = P_b eq. 24 alone is the density: no compression is added (the former 0 -> P
    increment added the compression from 0 to P_b a second time, about 1 % here)."""
    P_b = (R_G / (0.02123 * G_GAS)) ** (1 / 1.205) / math.exp(4.072 / RHO0 - 0.00377 * T)
    B0 = 0.972 + 0.00038 * (2.4 * R_G * math.sqrt(G_GAS / RHO0) + T + 17.8) ** 1.175
    o = pf.oil(T, P_b, reference_density=RHO0, gas_oil_ratio=R_G, gas_gravity=G_GAS)
    assert float(o.rho) == pytest.approx((RHO0 + 0.0012 * G_GAS * R_G) / B0, rel=RTOL)


def z_factor(pr, tr):
    """Eq. 10b."""
    return ((0.03 + 0.00527 * (3.5 - tr) ** 3) * pr + (0.642 * tr - 0.007 * tr**4 - 0.52)
            + 0.109 * (3.85 - tr) ** 2
            * math.exp(-(0.45 + 8 * (0.56 - 1 / tr) ** 2) * pr**1.2 / tr))


def test_gas_eqs_9_to_11():
    """Eqs. 9a-b (pseudo-reduced state), 10a-b (density, Z), 11a-b (adiabatic modulus); the
    derivative of Z, which the paper does not print, by a central difference here."""
    Ta = T + 273.15
    Pr = P / (4.892 - 0.4048 * G_GAS)
    Tr = Ta / (94.72 + 170.75 * G_GAS)
    Z = z_factor(Pr, Tr)
    h = 1e-5
    dZ = (z_factor(Pr + h, Tr) - z_factor(Pr - h, Tr)) / (2 * h)
    gamma0 = 0.85 + 5.6 / (Pr + 2) + 27.1 / (Pr + 3.5) ** 2 - 8.7 * math.exp(-0.65 * (Pr + 1))
    rho = 28.8 * G_GAS * P / (Z * R_GAS * Ta)                 # g/cm3 (MPa g/mol / (J/mol))
    K = P * gamma0 / (1 - Pr / Z * dZ) / 1000.0               # GPa
    assert (Pr, Tr) == (pytest.approx(6.509513, abs=1e-6), pytest.approx(1.648347, abs=1e-6))
    assert Z == pytest.approx(0.935688, abs=1e-6)
    assert rho == pytest.approx(0.220134, abs=1e-6)
    assert K == pytest.approx(0.075259, abs=1e-6)
    g = pf.gas(T, P, G_GAS)
    assert float(g.rho) == pytest.approx(rho, rel=RTOL)
    assert float(g.K) == pytest.approx(K, rel=1e-8)           # the difference quotient's error
    assert float(g.vp) == pytest.approx(math.sqrt(K / rho), rel=1e-8)


def test_wood_and_brie_at_one_state():
    """Wood (1955) and Brie et al. (1995) with a brine and a gas at the state above, water
    saturation 0.3 (so that S_w and 1 - S_w are told apart)."""
    b, g = pf.brine(T, P, S), pf.gas(T, P, G_GAS)
    Kb, Kg, rb, rg = float(b.K), float(g.K), float(b.rho), float(g.rho)
    Sw = 0.3
    w = pf.wood([Sw, 1 - Sw], [Kb, Kg], [rb, rg])
    assert float(w.K) == pytest.approx(1 / (Sw / Kb + (1 - Sw) / Kg), rel=1e-12)
    assert float(w.rho) == pytest.approx(Sw * rb + (1 - Sw) * rg, rel=1e-12)
    for e in (1.0, 3.0, 5.0):
        m = pf.brie(Sw, Kb, Kg, rb, rg, exponent=e)
        assert float(m.K) == pytest.approx((Kb - Kg) * Sw**e + Kg, rel=1e-12)
        assert float(m.rho) == pytest.approx(Sw * rb + (1 - Sw) * rg, rel=1e-12)
        assert float(m.vp) == pytest.approx(math.sqrt(float(m.K) / float(m.rho)), rel=1e-12)
