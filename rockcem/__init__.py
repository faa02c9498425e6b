"""rockcem: rock physics of burial history.

Petro-elastic models (bounds, fluid substitution, frames, inclusions, granular contact models and
the four models of Carcione et al. 2022) that take arrays of rock state and return moduli,
density and velocities. Units: GPa, g/cm³, km/s, MPa, fractions.

Importing ``rockcem`` never imports numba (only the optional ``md`` engine uses it).
"""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

from . import bounds, constants, elastic, fluids, frames, granular, inclusions, materials, models
from .elastic import Moduli, Velocities, poisson_ratio, velocities
from .materials import Fluid, Mineral, fluid, mineral

try:
    __version__ = version("rockcem")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"

__all__ = [
    "__version__",
    "bounds",
    "constants",
    "elastic",
    "fluids",
    "frames",
    "granular",
    "inclusions",
    "materials",
    "models",
    "Moduli",
    "Velocities",
    "poisson_ratio",
    "velocities",
    "Mineral",
    "Fluid",
    "mineral",
    "fluid",
]
