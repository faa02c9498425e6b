"""Voxel finite elements (md.voxel) against closed forms: the element's energy, a homogeneous
block, Backus's laminate, the Hashin-Shtrikman bounds, and bad input."""

import numpy as np
import pytest

from md.voxel import EMPTY, VoxelPhase, element_matrices, pack_phases, voxel_stiffness

A = VoxelPhase(40e9, 30e9, 2650.0)     # lambda 20, mu 30 GPa
B = VoxelPhase(10e9, 4e9, 1000.0)      # lambda 7.33, mu 4 GPa


@pytest.mark.parametrize("lam, mu", [(1.0, 0.0), (0.0, 1.0), (2.0, 3.0)])
def test_element_energy_of_a_bilinear_field(lam, mu):
    """u_x = x y on the unit cube (representable by the trilinear brick): strain
    eps_xx = y, eps_xy = x/2, energy (lam/2) y^2 + mu (y^2 + x^2/2) integrated = lam/6 + mu/2
    (hand-computed); the element's energy is u.K.u/2."""
    KL, KM = element_matrices()
    u = np.zeros(24)
    for a in range(8):
        u[3 * a] = (a & 1) * ((a >> 1) & 1)
    K = lam * KL + mu * KM
    assert 0.5 * u @ K @ u == pytest.approx(lam / 6.0 + mu / 2.0, rel=1e-13)
    # Rigid motions cost nothing: translations and an infinitesimal rotation.
    x = np.array([[(a & 1), (a >> 1) & 1, (a >> 2) & 1] for a in range(8)], float)
    rot = np.zeros((8, 3))
    rot[:, 0], rot[:, 1] = -x[:, 1], x[:, 0]
    for v in (np.tile([1.0, 0, 0], 8), rot.ravel()):
        assert np.abs(K @ v).max() < 1e-13


@pytest.mark.parametrize("shape, h", [((3, 4, 12), 1e-5), ((5, 5, 9), 3e-6)])
def test_homogeneous_block_is_exact(shape, h):
    """One isotropic material: C11 = C33 = lambda + 2 mu, C12 = C13 = C31 = lambda,
    C44 = C66 = mu, at any grid."""
    r = voxel_stiffness(np.zeros(shape, int), [A], h, slab_thickness=2 * h)
    lam, mu = A.lame_lambda, A.shear_modulus
    want = dict(c11=lam + 2 * mu, c33=lam + 2 * mu, c12=lam, c13=lam, c31=lam, c44=mu, c66=mu)
    for k, v in want.items():
        assert getattr(r, k) == pytest.approx(v, rel=1e-10), k
    assert r.bulk_reuss == pytest.approx(A.bulk_modulus, rel=1e-10)
    assert r.density == pytest.approx(A.density, rel=1e-14)
    assert abs(r.epsilon) < 1e-10 and abs(r.gamma) < 1e-10 and abs(r.delta) < 1e-9


def _backus(phases, fractions):
    """Backus (1962) average of isotropic layers, eqs. 13 (Mavko et al. 2009, Sect. 4.13)."""
    f = np.asarray(fractions)
    lam = np.array([p.lame_lambda for p in phases])
    mu = np.array([p.shear_modulus for p in phases])
    M = lam + 2 * mu
    c33 = 1.0 / np.sum(f / M)
    c44 = 1.0 / np.sum(f / mu)
    c66 = np.sum(f * mu)
    c13 = np.sum(f * lam / M) * c33
    c11 = np.sum(f * 4 * mu * (lam + mu) / M) + np.sum(f * lam / M) ** 2 * c33
    return dict(c11=c11, c33=c33, c13=c13, c31=c13, c44=c44, c66=c66, c12=c11 - 2 * c66)


@pytest.mark.parametrize("solver", ["amg", "jacobi"])
def test_laminate_is_backus(solver):
    """Layers along z (3 voxels of A, 4 of B, twice through the measured band): the voxel
    elements are exact, so the five constants are Backus's average (nx = 2: a neighbour met
    twice through the periodic side)."""
    nz, h = 20, 1e-5
    phase = np.zeros((2, 3, nz), int)
    kb = 2 + 1                            # slab 2 voxels, margin half a slab
    for k in range(nz):
        phase[:, :, k] = 0 if (k - kb) % 7 < 3 else 1
    r = voxel_stiffness(phase, [A, B], h, slab_thickness=2 * h, solver=solver, rtol=1e-12)
    assert r.metadata["band"] == (kb, nz - kb)
    for k, v in _backus([A, B], [3 / 7, 4 / 7]).items():
        assert getattr(r, k) == pytest.approx(v, rel=1e-8), k
    assert r.c31 == pytest.approx(r.c13, rel=1e-8)


def _random_sample(seed=0, shape=(6, 6, 10), refine=2):
    """Random phases (0 or 1) on a grid of ``shape``, each cell split into ``refine``^3
    voxels."""
    p = np.random.default_rng(seed).integers(0, 2, shape)
    return p.repeat(refine, 0).repeat(refine, 1).repeat(refine, 2)


def test_random_two_phase_inside_hashin_shtrikman():
    """A random two-phase medium, each random cell 2 x 2 x 2 voxels: its moduli within the
    Hashin-Shtrikman bounds of its volume fractions (rockcem.bounds), C31 close to C13
    (Maxwell-Betti). (At one voxel per random cell the trilinear elements are too stiff for the
    checkerboard's corners: C11 38.2 GPa against the bound's 37.3 on an 8 x 8 x 16 sample, 34.6
    when refined twice, 33.8 three times.)"""
    from rockcem.bounds import hashin_shtrikman

    phase = _random_sample()
    r = voxel_stiffness(phase, [A, B], 1e-5, slab_thickness=4e-5, rtol=1e-10)
    fB = float(np.mean(phase))
    hs = hashin_shtrikman([A.bulk_modulus / 1e9, B.bulk_modulus / 1e9],
                          [A.shear_modulus / 1e9, B.shear_modulus / 1e9], [1 - fB, fB])
    Kl, Ku = float(hs.lower.K), float(hs.upper.K)
    Gl, Gu = float(hs.lower.G), float(hs.upper.G)
    gpa = {k: getattr(r, k) / 1e9 for k in ("c11", "c33", "c44", "c66", "bulk_reuss",
                                           "c13", "c31")}
    assert Kl < gpa["bulk_reuss"] < Ku
    for k in ("c11", "c33"):
        assert Kl + 4 / 3 * Gl < gpa[k] < Ku + 4 / 3 * Gu, k
    for k in ("c44", "c66"):
        assert Gl < gpa[k] < Gu, k
    assert gpa["c31"] == pytest.approx(gpa["c13"], rel=0.01)


def test_refining_lowers_the_kinematic_stiffness():
    """Rayleigh-Ritz: with margin 0 the measured strain is the imposed one and the band's
    mean stress times it is twice its energy, which a finer (nested) trilinear space can only
    lower; the elements converge from above."""
    base = _random_sample(2, (5, 5, 8), 1)
    c33 = [voxel_stiffness(base.repeat(f, 0).repeat(f, 1).repeat(f, 2), [A, B], 1e-5 / f,
                           slab_thickness=2e-5, margin=0.0, rtol=1e-11).c33 for f in (1, 2)]
    assert c33[1] < c33[0]


def test_solver_tolerance_does_not_move_the_moduli():
    phase = _random_sample(1)
    a = voxel_stiffness(phase, [A, B], 1e-5, slab_thickness=2e-5, rtol=1e-6)
    b = voxel_stiffness(phase, [A, B], 1e-5, slab_thickness=2e-5, rtol=1e-10, solver="jacobi")
    for k in ("c11", "c13", "c33", "c44", "c66"):
        assert getattr(a, k) == pytest.approx(getattr(b, k), rel=1e-5), k


def test_floating_clusters_are_dropped_and_counted():
    """A block of A with a cavity holding a voxel of B and one of A that touch each other by
    an edge only (two clusters by faces, neither joined to the ends): both are dropped and
    counted, and the constants are those of the block with the cavity empty."""
    h = 1e-5
    empty = np.zeros((8, 8, 14), int)
    empty[2:7, 2:7, 4:9] = EMPTY
    phase = empty.copy()
    phase[4, 4, 6] = 1
    phase[5, 5, 6] = 0
    r = voxel_stiffness(phase, [A, B], h, slab_thickness=2 * h, rtol=1e-11)
    alone = voxel_stiffness(empty, [A, B], h, slab_thickness=2 * h, rtol=1e-11)
    assert r.metadata["dropped_clusters"] == 2
    assert r.metadata["dropped_voxels"] == 2
    assert alone.metadata["dropped_voxels"] == 0
    for k in ("c11", "c13", "c33", "c44", "c66"):
        assert getattr(r, k) == pytest.approx(getattr(alone, k), rel=1e-7), k
    assert r.density > alone.density         # the dropped voxels keep their mass


def test_bad_input_is_refused_by_name():
    with pytest.raises(ValueError, match="shear_modulus"):
        VoxelPhase(40e9, 0.0, 2650.0)
    with pytest.raises(ValueError, match="bulk_modulus"):
        VoxelPhase(-1.0, 3e9, 2650.0)
    with pytest.raises(ValueError, match="empty"):
        voxel_stiffness(np.full((3, 3, 8), EMPTY), [A], 1e-5, slab_thickness=2e-5)
    with pytest.raises(ValueError, match="no solid path"):
        phase = np.zeros((3, 3, 10), int)
        phase[:, :, 5] = EMPTY
        voxel_stiffness(phase, [A], 1e-5, slab_thickness=2e-5)
    with pytest.raises(ValueError, match="phase indices"):
        voxel_stiffness(np.full((3, 3, 8), 2), [A, B], 1e-5, slab_thickness=2e-5)
    with pytest.raises(ValueError, match="too short"):
        voxel_stiffness(np.zeros((3, 3, 4), int), [A], 1e-5, slab_thickness=2e-5)
    with pytest.raises(ValueError, match="cell_width"):
        voxel_stiffness(np.zeros((3, 3, 8), int), [A], 0.0, slab_thickness=2e-5)
    with pytest.raises(ValueError, match="solver"):
        voxel_stiffness(np.zeros((3, 3, 8), int), [A], 1e-5, slab_thickness=2e-5,
                        solver="lu")


def test_pack_phases_marks_grains_cement_and_pores(compacted_pack):
    import md

    lat = md.cement_lattice(compacted_pack, 2.0)
    cells = np.zeros(lat.index.size, bool)
    cells[::3] = True
    phase = pack_phases(compacted_pack, lat, cells)
    flat = phase.ravel(order="F")
    assert np.all(flat[lat.index[cells]] == 1)
    assert np.all(flat[lat.index[~cells]] == EMPTY)
    grain = np.ones(flat.size, bool)
    grain[lat.index] = False
    assert np.all(flat[grain] == 0)
    # A cell centre inside a grain is grain: check against the pack's spheres directly.
    nx, ny, nz = lat.shape
    i, j, k = np.unravel_index(np.flatnonzero(grain)[:200], (nx, ny, nz), order="F")
    c = np.stack([(i + 0.5) * lat.cell_width, (j + 0.5) * lat.cell_width,
                  lat.z0 + (k + 0.5) * lat.cell_width], axis=1)
    d = c[:, None, :] - compacted_pack.positions[None]
    box = np.array([compacted_pack.box.lx, compacted_pack.box.ly])
    d[..., :2] -= box * np.round(d[..., :2] / box)
    inside = np.linalg.norm(d, axis=2) < compacted_pack.radii[None]
    assert inside.any(axis=1).all()
    with pytest.raises(ValueError, match="thinner than a cell"):
        pack_phases(compacted_pack, lat, np.full(lat.index.size, 0.5))
