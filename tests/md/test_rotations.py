"""Grain and cement rotations in the linearised acoustic stage (md._kernels_rotation): rigid
motions cost nothing, the operator is the energy of the contact-point kinematics, and an
uncemented pack gets the shear stiffness of the 6-degree-of-freedom bonded model instead of the
translations-only Vp/Vs near 1."""

import dataclasses
import math

import numpy as np
import pytest

import md
from md.acoustic import acoustic_system, static_modulus
from md.cement import HARD_CEMENT, cement_lattice, grow_cement
from rockcem.granular import hertz_mindlin


@pytest.fixture(scope="module")
def cemented(compacted_pack):
    lat = cement_lattice(compacted_pack, 3.0)
    cem = grow_cement(lat, 0.1, "contact")
    return compacted_pack, lat, cem


def _interior(system):
    """The system without the bonds that cross the periodic boundary in x or y (a rigid
    rotation of the whole sample is not periodic)."""
    half = 0.5 * min(system.box.lx, system.box.ly)
    d = system.positions[system.bond_j] - system.positions[system.bond_i]
    keep = np.all(np.abs(d[:, :2]) < half, axis=1)
    table = system.lattice_neighbors.copy()
    own = np.arange(table.shape[0])[:, None] + system.n_grains
    far = np.abs(system.positions[np.maximum(table, 0)] - system.positions[own])[..., :2]
    table[(table >= 0) & np.any(far >= half, axis=-1)] = -1
    sub = {f: getattr(system, f)[keep] for f in ("bond_i", "bond_j", "bond_normal", "bond_kn",
                                                 "bond_kt", "bond_gn", "bond_gt")}
    if system.rotations:
        sub.update(arm_i=system.arm_i[keep], arm_j=system.arm_j[keep])
    return dataclasses.replace(system, lattice_neighbors=table, **sub), int(keep.sum())


@pytest.mark.parametrize("rotations", [True, False])
def test_rigid_rotation_of_a_cemented_sample_costs_nothing(cemented, rotations):
    """u = omega x (x - x0), theta = omega: zero force and moment on every particle with
    rotations; translations only (the source's eqs. 4-6), the same motion stretches the
    tangential springs."""
    pack, lat, cem = cemented
    system, n_bonds = _interior(acoustic_system(pack, lat, cem, HARD_CEMENT,
                                                rotations=rotations))
    assert n_bonds > 100 and system.n_lattice_bonds > 100
    omega = np.array([0.3, -0.5, 0.8]) * 1e-6
    arm = system.positions - system.positions.mean(axis=0)
    u = np.zeros((system.n_particles, system.dof))
    u[:, :3] = np.cross(omega, arm)
    if rotations:
        u[:, 3:] = omega
    f = system.forces(u)
    scale = np.max(np.abs(system.forces(np.pad(u[:, :3], ((0, 0), (0, system.dof - 3))))))
    if rotations:
        assert np.max(np.abs(f)) <= 1e-9 * scale
    else:
        assert np.max(np.abs(f)) > 1e-3 * scale


def test_operator_is_the_energy_of_the_contact_point_motion(cemented, rng):
    """1/2 u.K u equals the bond energies summed from the rigid-body motion of each particle's
    material point at the contact (u + theta x (x_c - x)), computed bond by bond in plain
    Python."""
    pack, lat, cem = cemented
    system = acoustic_system(pack, lat, cem, HARD_CEMENT)
    u = rng.normal(size=(system.n_particles, 6)) * np.r_[1e-9, 1e-9, 1e-9, 1e-5, 1e-5, 1e-5]
    i, j, n, kn, kt = system._bonds(system.bond_kn, system.bond_kt, system.lattice_kn,
                                    system.lattice_kt)
    arm_i, arm_j = system._arms()
    energy = 0.0
    for b in range(i.size):
        ci, cj = arm_i[b] * n[b], -arm_j[b] * n[b]          # contact point from each centre
        d = (u[j[b], :3] + np.cross(u[j[b], 3:], cj)) - (u[i[b], :3] + np.cross(u[i[b], 3:], ci))
        dn = d @ n[b]
        energy += 0.5 * (kt[b] * (d @ d) + (kn[b] - kt[b]) * dn**2)
    K = system.stiffness_matrix()
    assert 0.5 * u.ravel() @ (K @ u.ravel()) == pytest.approx(energy, rel=1e-10)
    assert -u.ravel() @ system.forces(u).ravel() == pytest.approx(2 * energy, rel=1e-10)


def test_uncemented_pack_shear_matches_the_bonded_model(compacted_pack):
    """Uncemented pack compacted to 10 MPa. Translations only, a shear turns every grain
    contact's tangential spring as a rigid rotation would: Vp/Vs near 1. With rotations the
    shear modulus is md.bonded's xz shear (6 degrees of freedom per grain, periodic strain
    instead of end slabs; vanishing bonds beside the same Hertz-Mindlin contacts) to the
    spread that the end slabs give this 96-grain sample: slabs of 1, 1.5 and 2 diameters give
    G 0.755, 0.895 and 0.865 GPa against md.bonded's 0.777 (on a 171-grain pack at 30 MPa,
    1.280 against 1.244 GPa), so within 15 %; and the
    dry Vp/Vs (1.7-1.9, of dry sands) lies above the Hertz-Mindlin no-slip value: effective
    medium theory assumes affine grain motion, which overestimates the shear stiffness most
    (non-affine relaxation, md.bonded's shear_affine against shear)."""
    trans = acoustic_system(compacted_pack, rotations=False)
    rot = acoustic_system(compacted_pack)
    m_t, g_t = (static_modulus(trans, w).modulus for w in "ps")
    m_r, g_r = (static_modulus(rot, w).modulus for w in "ps")
    assert math.sqrt(m_t / g_t) < 1.1
    bonded = md.bonded_static_moduli(md.bonded_system(compacted_pack, 1e-3, cement_bulk=1e6,
                                                      cement_shear=1e6))
    assert g_r == pytest.approx(bonded.shear_components[0], rel=0.15)
    assert g_r < bonded.shear_affine
    nu = md.QUARTZ.poisson_ratio
    K0 = 2 * md.QUARTZ.shear_modulus * (1 + nu) / (3 * (1 - 2 * nu)) / 1e9
    hm = hertz_mindlin(K0, md.QUARTZ.shear_modulus / 1e9, 0.38, 6.0, 10.0, f=1.0)
    no_slip = math.sqrt((hm.K + 4 / 3 * hm.G) / hm.G)
    assert no_slip < math.sqrt(m_r / g_r) < 2.0


def test_pruned_static_solve_equals_a_regularised_direct_solve(compacted_pack):
    """Pore-body cement at Omega 2 leaves cement particles hanging by one bond (to a grain or to
    another cement particle). The static solve prunes them before its conjugate gradients; a
    direct sparse solve of the whole operator, made definite by adding 1e-10 of each diagonal
    entry (the pack also has soft, nearly free rotations), gives the same reaction on the fixed
    slab."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from md.static import _load_path, _prescribed

    lat = cement_lattice(compacted_pack, 2.0)
    system = acoustic_system(compacted_pack, lat, grow_cement(lat, 0.02, "pore_body", seed=0),
                             HARD_CEMENT)
    slab, n_slabs, flag = _prescribed(system)
    assert (~_load_path(system, flag)).sum() >= 1           # something to prune
    pruned = static_modulus(system, "p", rtol=1e-13)
    n = system.n_particles
    K0 = system.stiffness_matrix().tocsr()
    K = (K0 + sp.diags(1e-10 * K0.diagonal())).tocsr()
    u = np.zeros((n, 6))
    u[flag == 2, 2] = 1e-6 * system.slab_thickness
    fixed = np.zeros((n, 6), bool)
    fixed[flag != 0, :3] = True
    fixed |= (K0.diagonal() == 0).reshape(n, 6)
    free, known = np.flatnonzero(~fixed.ravel()), np.flatnonzero(fixed.ravel())
    u.ravel()[free] = spla.spsolve(K[free][:, free].tocsc(),
                                   -K[free][:, known] @ u.ravel()[known])
    f = -(K0 @ u.ravel()).reshape(n, 6)
    stress = f[flag == 1, 2].sum() / (system.box.lx * system.box.ly)
    assert pruned.stress == pytest.approx(stress, rel=1e-6)


@pytest.mark.parametrize("rotations", [False, True])
def test_stiffness_blocks_are_the_diagonal_blocks_of_k(cemented, rotations):
    """The block-Jacobi preconditioner's blocks equal the particle blocks of the assembled
    stiffness matrix."""
    pack, lat, cem = cemented
    system = acoustic_system(pack, lat, cem, HARD_CEMENT, rotations=rotations)
    K = system.stiffness_matrix().tocsr()
    d = system.dof
    blocks = system.stiffness_blocks()
    for p in range(0, system.n_particles, 7):
        ref = K[d * p:d * p + d, d * p:d * p + d].toarray()
        np.testing.assert_allclose(blocks[p], ref, rtol=1e-12, atol=1e-12 * abs(ref).max())
