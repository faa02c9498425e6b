r"""Pore fluids at the temperature and pressure of a depth: brine, oil and gas ([BatzleWang1992]_),
CO2 and methane (reference equations of state through CoolProp), and the mixing laws.

Units: temperature °C, pressure MPa (**absolute**: a gauge pore pressure that is 0 at the surface
should be given :data:`STANDARD_ATMOSPHERE` more; for water, brine and oil it changes nothing
that matters, 0.1 MPa), salinity as the NaCl mass fraction (0–1), gas gravity relative to air,
gas–oil ratio in litres of gas at 15.6 °C and 0.1 MPa per litre of oil, K in GPa, rho in g/cm³,
vp in km/s. Every fluid function returns :class:`FluidProperties` ``(K, rho, vp)``, arrays
broadcast over the inputs. The Batzle–Wang (B&W) equations give velocities in m/s; they are
converted here by :data:`KM_PER_M`.

Input outside the domain where a formula is defined (NaN, negative pressure, salinity outside
[0, 0.35), a gas colder than its pseudo-critical temperature…) raises ``ValueError`` naming the
argument. Input inside that domain but outside the range the correlations were fitted to is
computed all the same; :func:`validity_warnings` says where, in the style of
:mod:`rockcem.validity`.

The package, by concept: :mod:`~rockcem.pore_fluids.batzle_wang` (water, brine, oil, gas),
:mod:`~rockcem.pore_fluids.reference` (CO2 and methane through CoolProp, the ``fluids`` extra),
:mod:`~rockcem.pore_fluids.mixing` (Wood, Brie, patchy saturation) and
:mod:`~rockcem.pore_fluids.validity` (where a fluid leaves its source's range); every public
name is importable from ``rockcem.pore_fluids``. Where the public readings of Batzle & Wang
disagree, and how each was settled: :mod:`rockcem.pore_fluids.batzle_wang`.

References (:mod:`rockcem.references`): [BatzleWang1992]_, [KleisSanchez1990]_,
[SpanWagner1996]_, [SetzmannWagner1991]_, [Wood1955]_, [Brie1995]_, [Standing1947]_,
[Mavko2009]_ (partial and patchy saturation), [IAPWS1997]_ (vapour pressure of water).
"""

from ..constants import KM_PER_M, STANDARD_ATMOSPHERE
from ._common import FluidProperties
from .batzle_wang import brine, bubble_point_pressure, gas, max_gas_oil_ratio, oil, water
from .mixing import brie, patchy_saturation, wood
from .reference import co2, methane
from .validity import validity_warnings

__all__ = ["FluidProperties", "STANDARD_ATMOSPHERE", "KM_PER_M", "water", "brine", "oil",
           "max_gas_oil_ratio", "bubble_point_pressure", "gas", "co2", "methane", "wood", "brie",
           "patchy_saturation", "validity_warnings"]
