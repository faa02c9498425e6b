"""Physical constants and unit conversions used across the project.

Every conversion between the package's API units (GPa, g/cm³, km/s, MPa, °C, mm, m, Myr) and
anything else goes through a named constant defined here, so that no model hides a bare factor.
The values are quoted in ``tests/rockcem/test_constants.py``.
"""

from __future__ import annotations

import math

__all__ = [
    "GPA_PER_MPA",
    "SECONDS_PER_YEAR",
    "SECONDS_PER_MYR",
    "GAS_CONSTANT_CAL",
    "GAS_CONSTANT_J",
    "STANDARD_GRAVITY",
    "ZERO_CELSIUS_IN_KELVIN",
    "LN10",
    "STANDARD_ATMOSPHERE",
    "KM_PER_M",
]

#: Gigapascals per megapascal: pressures (MPa) meet moduli (GPa) in Hertz–Mindlin through this.
GPA_PER_MPA = 1.0e-3

#: Julian year in seconds (IAU): 365.25 d × 86 400 s.
SECONDS_PER_YEAR = 365.25 * 86400.0

#: One million years (Myr) in seconds.
SECONDS_PER_MYR = 1.0e6 * SECONDS_PER_YEAR

#: Gas constant in cal/(mol K), the value used by Pytte & Reynolds (1989) and Carcione et al.
#: (2022, App. A): R = 1.986 cal/(mol K). (CODATA: 8.314462618 J/(mol K) / 4.184 J/cal = 1.98720.)
GAS_CONSTANT_CAL = 1.986

#: Gas constant in J/(mol K) (CODATA 2018, exact).
GAS_CONSTANT_J = 8.314462618

#: Standard acceleration of gravity, m/s²: g_n = 9.80665 exactly (3rd CGPM 1901; CODATA, ISO
#: 80000-3). Carcione et al. (2022, Sect. 2) round it to 9.81, which puts every pressure along
#: depth 0.034 % higher; their figures are not read to that precision.
STANDARD_GRAVITY = 9.80665

#: 0 °C in kelvin.
ZERO_CELSIUS_IN_KELVIN = 273.15

#: Natural logarithm of 10 (Walderhaug kinetics are written in powers of ten).
LN10 = math.log(10.0)

#: One standard atmosphere, MPa (exact, 101 325 Pa): add it to a gauge pore pressure (the burial
#: path's, 0 at the sediment surface) for the absolute pressure of the pore-fluid equations.
STANDARD_ATMOSPHERE = 0.101325

#: Kilometres per metre: velocities in m/s (Batzle & Wang, CoolProp) to the package's km/s.
KM_PER_M = 1.0e-3
