"""rockcem: rock physics of burial history.

Petro-elastic models (bounds, fluid substitution, frames, inclusions, granular contact models and
the four models of Carcione et al. 2022) that take arrays of rock state and return moduli,
density and velocities. Units: GPa, g/cm³, km/s, MPa, fractions.

Importing ``rockcem`` never imports numba (only the optional ``md`` engine uses it). The
sub-packages not imported here (:mod:`rockcem.pore_fluids`, :mod:`rockcem.scene`,
:mod:`rockcem.plots`, :mod:`rockcem.wells`, …) are attributes all the same, imported on first
use (``import rockcem; rockcem.pore_fluids.brine(...)``), so ``import rockcem`` stays as quick
as the models need.
"""

from __future__ import annotations

import importlib
from importlib.metadata import PackageNotFoundError, version

from . import bounds, constants, elastic, fluids, frames, granular, inclusions, materials, models
from .elastic import Moduli, Velocities, poisson_ratio, velocities
from .materials import Fluid, Mineral, fluid, mineral
from .validity import RockcemValidityWarning

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
    "RockcemValidityWarning",
]

#: Public sub-modules imported on first attribute access (PEP 562), not by ``import rockcem``.
_LAZY = ("anisotropy", "calibrate", "contact_integral", "plots", "pore_fluids", "references",
         "reflectivity", "scene", "synthetics", "variables", "wells")


def __getattr__(name):
    """``rockcem.<sub-module>`` for the sub-modules of :data:`_LAZY`, imported on first use."""
    if name in _LAZY:
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_LAZY))
