"""md: a compact numba molecular-dynamics engine for grain packs (García & Medina 2007).

SI units inside (m, kg, s, Pa). Built so far: Hertz–Mindlin contacts with restitution-calibrated
damping and Coulomb friction (:mod:`md.contact`), the periodic box and cell-list neighbour search
(:mod:`md.space`, :mod:`md.neighbors`), velocity-Verlet integration with the time step from the
shortest contact (:mod:`md.integrate`), ballistic settling (:func:`md.settle`) and packs saved to
netCDF between stages (:mod:`md.state`). Compaction, cementation and the acoustic pulse test
are being built.
"""

from .contact import QUARTZ, GrainMaterial
from .neighbors import build_neighbors, needs_rebuild
from .protocols import compact, coordination_number, porosity, prepare_pack, settle
from .space import Box
from .state import Pack, load_pack, save_pack

__all__ = ["QUARTZ", "GrainMaterial", "Box", "Pack", "build_neighbors", "needs_rebuild", "settle",
           "compact", "prepare_pack", "porosity", "coordination_number", "save_pack", "load_pack"]
