"""burial: burial paths, quartz cementation, compaction and clay diagenesis.

Turns a time–temperature–pressure path into porosity, quartz-cement and illite fractions
(Carcione et al. 2022: eqs. 1–2, 7, App. A and B). Units: time Myr, depth m, temperature °C,
pressure MPa, grain size mm, fractions as fractions. The kinetics are integrated exactly over
each linear piece of the path, so results do not depend on the node spacing.
"""

from .clay import illite_fraction, smectite_fraction
from .compaction import (SandstonePorosity, athy_porosity, intergranular_volume,
                         sandstone_porosity)
from .horizons import HorizonPaths, horizon_paths, shifted_path
from .path import BurialPath, Pressures, linear_path, path_from_nodes, pressures
from .quartz import quartz_cement
from .state import sandstone_state, shale_state

__all__ = [
    "BurialPath",
    "Pressures",
    "linear_path",
    "path_from_nodes",
    "horizon_paths",
    "shifted_path",
    "HorizonPaths",
    "pressures",
    "quartz_cement",
    "smectite_fraction",
    "illite_fraction",
    "athy_porosity",
    "intergranular_volume",
    "sandstone_porosity",
    "SandstonePorosity",
    "sandstone_state",
    "shale_state",
]
