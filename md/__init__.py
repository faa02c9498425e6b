"""md: a compact numba molecular-dynamics engine for grain packs (García & Medina 2007).

SI units inside (m, kg, s, Pa). Hertz–Mindlin contacts with restitution-calibrated damping and
Coulomb friction (:mod:`md.contact`), the periodic box and cell-list neighbour search
(:mod:`md.space`, :mod:`md.neighbors`), velocity-Verlet integration with the time step from the
stiffest linearised contacts of the current state (:mod:`md.integrate`), sequential ballistic
deposition (:func:`md.settle`), compaction to a stress (:func:`md.compact`), porosity and stress
of a pack's core window (:mod:`md.observe`), packs saved to netCDF between stages
(:mod:`md.state`), the cement lattice with contact, coating, pore-body and pendular growth
(:mod:`md.cement`), the linearised acoustic stage (:mod:`md.acoustic`; grain–cement interface
rules in :mod:`md.interface`) with the pulse test (:mod:`md.pulse`) and static moduli
(:mod:`md.static`; or by voxel finite elements on the lattice's cells, :mod:`md.voxel`), one
cemented contact against the cemented-contact theory
(:mod:`md.cemented_contact`), and bonded-contact cement with static bulk and shear moduli
(:mod:`md.bonded`); :mod:`md.calibrate` fits the effective-medium models of :mod:`rockcem` to
MD results (the one md module that uses rockcem).
"""

from .acoustic import AcousticSystem, acoustic_system, cement_block, pulse_test, static_modulus
from .static import static_moduli
from . import calibrate
from .bonded import (BondedModuli, BondedSystem, bond_stiffness, bonded_acoustic_system,
                     bonded_moduli, bonded_system)
from .bonded import static_moduli as bonded_static_moduli
from .cement import (HARD_CEMENT, SOFT_CEMENT, CementLattice, CementMaterial, cement_lattice,
                     cement_sweep, grow_cement)
from .contact import QUARTZ, GrainMaterial
from .neighbors import build_neighbors, needs_rebuild
from .protocols import compact, coordination_number, porosity, prepare_pack, settle
from .space import Box
from .calibrate import write_calibration
from .state import Pack, load_pack, save_pack
from .voxel import VoxelPhase, voxel_stiffness

__all__ = ["QUARTZ", "GrainMaterial", "Box", "Pack", "build_neighbors", "needs_rebuild", "settle",
           "compact", "prepare_pack", "porosity", "coordination_number", "save_pack", "load_pack",
           "CementLattice", "CementMaterial", "HARD_CEMENT", "SOFT_CEMENT", "cement_lattice",
           "grow_cement", "cement_sweep", "AcousticSystem", "acoustic_system", "cement_block",
           "pulse_test", "static_modulus", "static_moduli", "BondedSystem", "BondedModuli",
           "bond_stiffness", "bonded_system", "bonded_static_moduli", "bonded_moduli",
           "bonded_acoustic_system",
           "calibrate", "write_calibration", "VoxelPhase", "voxel_stiffness"]
