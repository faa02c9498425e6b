"""Quote the constants of rockcem.constants against their definitions.

Every value is written out here from where it is defined: the Julian year (IAU, 365.25 d of
86 400 s), the gas constant R = 1.986 cal/(mol K) of Pytte & Reynolds (1989) as used in
Carcione et al. 2022, App. A, standard gravity g_n = 9.80665 m/s2 (exact by definition, 3rd CGPM
1901; CODATA, ISO 80000-3), and the SI
prefixes (1 GPa = 1000 MPa).
"""

import math

import pytest

from rockcem import constants as c


def test_julian_year_and_myr():
    assert c.SECONDS_PER_YEAR == 365.25 * 24 * 60 * 60
    assert c.SECONDS_PER_YEAR == 31_557_600.0
    assert c.SECONDS_PER_MYR == pytest.approx(1e6 * 31_557_600.0, rel=1e-15)


def test_gas_constant_in_calories_is_the_one_of_pytte_reynolds_and_carcione2022():
    # Carcione et al. 2022, App. A (after Pytte & Reynolds 1989): R = 1.986 cal/(mol K).
    assert c.GAS_CONSTANT_CAL == 1.986
    # CODATA's R in thermochemical calories (4.184 J) is 1.98720; the printed 1.986 agrees to
    # three significant figures (0.06 %), and the paper's value is the one kept.
    assert c.GAS_CONSTANT_CAL == pytest.approx(c.GAS_CONSTANT_J / 4.184, rel=1e-3)
    assert c.GAS_CONSTANT_CAL != c.GAS_CONSTANT_J / 4.184  # the paper's rounded value is kept


def test_gas_constant_in_joules_is_avogadro_times_boltzmann():
    # SI 2019: N_A = 6.02214076e23 /mol and k_B = 1.380649e-23 J/K exactly; R = N_A k_B.
    assert c.GAS_CONSTANT_J == pytest.approx(6.02214076e23 * 1.380649e-23, rel=1e-10)
    assert c.GAS_CONSTANT_J == 8.314462618


def test_gravity_is_the_standard_acceleration_of_gravity():
    # g_n = 9.80665 m/s2 exactly (3rd CGPM 1901, CODATA, ISO 80000-3); Carcione et al. 2022 round
    # it to 9.81, 0.034 % more, which is not the standard value.
    assert c.STANDARD_GRAVITY == 9.80665
    assert c.STANDARD_GRAVITY != 9.81


def test_gpa_per_mpa():
    assert c.GPA_PER_MPA == 1e-3
    assert 1000.0 * c.GPA_PER_MPA == 1.0  # 1000 MPa is 1 GPa


def test_zero_celsius_and_ln10():
    assert c.ZERO_CELSIUS_IN_KELVIN == 273.15
    assert c.LN10 == math.log(10.0)
    assert math.exp(c.LN10) == pytest.approx(10.0, rel=1e-15)


def test_every_exported_constant_is_quoted_here():
    quoted = {"GPA_PER_MPA", "SECONDS_PER_YEAR", "SECONDS_PER_MYR", "GAS_CONSTANT_CAL",
              "GAS_CONSTANT_J", "STANDARD_GRAVITY", "ZERO_CELSIUS_IN_KELVIN", "LN10",
              "STANDARD_ATMOSPHERE", "KM_PER_M"}
    assert set(c.__all__) == quoted
    assert all(isinstance(getattr(c, name), float) for name in quoted)


def test_standard_atmosphere_and_km_per_m():
    # The standard atmosphere is defined as 101 325 Pa exactly (CGPM 1954); 1 km = 1000 m.
    assert c.STANDARD_ATMOSPHERE * 1e6 == pytest.approx(101_325.0, rel=1e-15)
    assert c.KM_PER_M * 1000.0 == 1.0
