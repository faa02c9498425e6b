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


@pytest.mark.parametrize("solver", ["cg", "lu"])
def test_pruned_static_solve_equals_a_regularised_direct_solve(compacted_pack, solver):
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
    pruned = static_modulus(system, "p", rtol=1e-13, solver=solver)
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


@pytest.mark.parametrize("rotations", [False, True])
def test_forces_into_a_buffer_equal_fresh_forces(cemented, rotations, rng):
    """``forces(u, out=buf)`` overwrites the buffer (stale values in it do not leak) with the
    forces of a fresh call; a buffer of the wrong size or type is refused."""
    pack, lat, cem = cemented
    system = acoustic_system(pack, lat, cem, HARD_CEMENT, rotations=rotations)
    u = rng.standard_normal((system.n_particles, system.dof)) * 1e-9
    buf = np.full(system.n_particles * system.dof, 7.0)
    got = system.forces(u, out=buf)
    np.testing.assert_array_equal(got, system.forces(u))
    assert np.shares_memory(got, buf)
    for bad in (np.zeros(buf.size - 1), np.zeros(buf.size, np.float32)):
        with pytest.raises(ValueError, match="out must be"):
            system.forces(u, out=bad)


def test_block_jacobi_kernel_equals_the_dense_block_product(rng):
    """The preconditioner kernel gives the free rows of the block-diagonal product, computed
    with numpy's einsum on the whole vector (held entries zero)."""
    from md._kernels_acoustic import block_jacobi

    n, dof = 50, 6
    inverse = rng.standard_normal((n, dof, dof))
    free = np.flatnonzero(rng.random(n * dof) < 0.7)
    r = rng.standard_normal(free.size)
    full = np.zeros(n * dof)
    full[free] = r
    want = np.einsum("pij,pj->pi", inverse, full.reshape(n, dof)).ravel()[free]
    z = np.empty(free.size)
    scratch = np.zeros(n * dof)
    block_jacobi(inverse, np.unique(free // dof), free, r, scratch, np.zeros(n * dof), z)
    np.testing.assert_allclose(z, want, rtol=1e-13, atol=1e-13)
    assert np.all(np.delete(scratch, free) == 0)         # held entries stay zero


@pytest.mark.parametrize("solver", ["cg", "lu"])
@pytest.mark.parametrize("wave", ["p", "s"])
def test_static_solve_equals_a_direct_solve_without_rotations(cemented, wave, solver):
    """Translations only (nothing pruned, a definite K_ff): the reaction of either solver's
    solution equals a direct sparse solve of the assembled operator's (spsolve: a factor
    without the LU solver's scaling, pinning and refinement)."""
    import scipy.sparse.linalg as spla

    from md.static import _load_path, _prescribed

    pack, lat, cem = cemented
    system = acoustic_system(pack, lat, cem, HARD_CEMENT, rotations=False)
    got = static_modulus(system, wave, rtol=1e-12, solver=solver)
    *_, flag = _prescribed(system)
    keep = _load_path(system, flag)
    n, ax = system.n_particles, {"p": 2, "s": 0}[wave]
    K = system.stiffness_matrix().tocsr()
    u = np.zeros((n, 3))
    u[flag == 2, ax] = 1e-6 * system.slab_thickness
    free_p = (flag == 0) & keep & (K.diagonal().reshape(n, 3) > 0).all(axis=1)
    free = np.flatnonzero(np.repeat(free_p, 3))
    known = np.setdiff1d(np.arange(3 * n), free)
    u.ravel()[free] = spla.spsolve(K[free][:, free].tocsc(), -K[free][:, known] @ u.ravel()[known])
    stress = -(K @ u.ravel()).reshape(n, 3)[flag == 1, ax].sum() / (system.box.lx * system.box.ly)
    assert got.stress == pytest.approx(stress, rel=1e-7)
    assert (got.iterations > 10) if solver == "cg" else (1 <= got.iterations <= 10), \
        got.iterations


@pytest.mark.parametrize("wave", ["p", "s"])
def test_lu_solve_is_the_minimum_norm_solution(compacted_pack, monkeypatch, wave):
    """With rotations K_ff is singular (cement particles bonded at two points turn about the
    line through them at no cost) and the strain depends on the part of the solution along
    these mechanisms. The LU solver (mechanisms pinned, a tiny shift) gives the solution with
    no part along them: the same modulus, to 1e-6, as the minimum-norm solution of the
    unit-scaled system by a dense pseudo-inverse, which the CG solver with block Jacobi need
    not give."""
    import md.static as static

    lat = cement_lattice(compacted_pack, 2.0)
    system = acoustic_system(compacted_pack, lat, grow_cement(lat, 0.02, "pore_body", seed=0),
                             HARD_CEMENT)

    def pseudo_inverse(apply_, precondition, b, rtol, maxiter):
        eye = np.eye(b.size)
        K = np.empty((b.size, b.size))
        for k in range(b.size):
            apply_(eye[k], K[:, k])
        d = 1.0 / np.sqrt(np.diag(K))
        A = d[:, None] * K * d[None, :]
        lam = np.linalg.eigvalsh(A)
        assert lam[0] > -1e-12 * lam[-1] and np.sum(lam < 1e-12 * lam[-1]) >= 1   # singular
        return d * (np.linalg.pinv(A, rcond=1e-12, hermitian=True) @ (d * b)), 1

    lu = static_modulus(system, wave, solver="lu", rtol=1e-12)
    monkeypatch.setattr(static, "_pcg", pseudo_inverse)
    exact = static_modulus(system, wave, solver="lu")
    assert lu.stress == pytest.approx(exact.stress, rel=1e-8)
    assert lu.modulus == pytest.approx(exact.modulus, rel=1e-6)
