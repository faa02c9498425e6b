"""Bonded-contact cement (md.bonded): bond stiffness limits and closed forms, the 6-dof
linearised operator, and static moduli of lattices with known moduli."""

import numpy as np
import pytest
from scipy.integrate import quad

from md.bond_stiffness import _layer_integrals, bond_cement_volume, bond_stiffness
from md.bonded import bonded_moduli, bonded_system, static_moduli
from md.contact import QUARTZ
from md.space import Box
from md.state import Pack

G_GRAIN, NU_GRAIN = QUARTZ.shear_modulus, QUARTZ.poisson_ratio
K_GRAIN = 2 * G_GRAIN * (1 + NU_GRAIN) / (3 * (1 - 2 * NU_GRAIN))
E_STAR = 2 * G_GRAIN * (1 + NU_GRAIN) / (1 - NU_GRAIN**2)       # E/(1 - nu^2)


def gap(r, R):
    return 2 * (R - np.sqrt(R * R - r * r))


@pytest.mark.parametrize("R,a,w0", [(1.0, 0.5, 0.02), (2e-4, 1e-4, 1e-9), (1.0, 1.0, 0.3),
                                    (1.0, 0.05, 1e-3)])
def test_layer_integrals_match_quadrature(R, a, w0):
    j0, j2 = _layer_integrals(R, a, w0)
    q0 = quad(lambda r: r / (w0 + gap(r, R)), 0, a, epsabs=0, epsrel=1e-13, limit=200)[0]
    q2 = quad(lambda r: r**3 / (w0 + gap(r, R)), 0, a, epsabs=0, epsrel=1e-13, limit=200)[0]
    assert j0 == pytest.approx(q0, rel=1e-9)
    assert j2 == pytest.approx(q2, rel=1e-9)


def test_rigid_cement_gives_the_welded_punch_pair():
    """Cement 1e9 times stiffer than the grains: the bond is a welded disc of radius a between
    two half-spaces in series (Johnson 1985): a E*, 4 G a/(2 - nu), (2/3) E* a^3, (8/3) G a^3."""
    R, alpha = 2e-4, 0.4
    a = alpha * R
    s = bond_stiffness(R, alpha, 0.0, K_GRAIN, G_GRAIN, 1e9 * K_GRAIN, 1e9 * G_GRAIN)
    assert s.normal == pytest.approx(a * E_STAR, rel=1e-6)
    assert s.shear == pytest.approx(4 * G_GRAIN * a / (2 - NU_GRAIN), rel=1e-6)
    assert s.bending == pytest.approx(2 / 3 * E_STAR * a**3, rel=1e-6)
    assert s.twisting == pytest.approx(8 / 3 * G_GRAIN * a**3, rel=1e-6)


def test_rigid_grains_give_the_thin_layer_integral():
    """Grains 1e9 times stiffer than the cement: the cement layer alone,
    k_n = 2 pi M_c int r dr / t(r), t the gap 2 eps R + 2 (R - sqrt(R^2 - r^2)), k_s with
    G_c, bending pi M_c int r^3/t, twisting 2 pi G_c."""
    R, alpha, eps, Kc, Gc = 1e-4, 0.5, 0.02, 6.8e9, 2.0e9
    Mc = Kc + 4 * Gc / 3
    s = bond_stiffness(R, alpha, eps, 1e9 * K_GRAIN, 1e9 * G_GRAIN, Kc, Gc)

    def t(r):
        return 2 * eps * R + gap(r, R)                   # eps is half the axial gap over R
    i0 = quad(lambda r: r / t(r), 0, alpha * R, epsabs=0, epsrel=1e-12)[0]
    i2 = quad(lambda r: r**3 / t(r), 0, alpha * R, epsabs=0, epsrel=1e-12)[0]
    assert s.normal == pytest.approx(2 * np.pi * Mc * i0, rel=1e-6)
    assert s.shear == pytest.approx(2 * np.pi * Gc * i0, rel=1e-6)
    assert s.bending == pytest.approx(np.pi * Mc * i2, rel=1e-6)
    assert s.twisting == pytest.approx(2 * np.pi * Gc * i2, rel=1e-6)


def test_bond_stiffness_monotone_in_radius_thickness_and_cement():
    R = 1e-4
    alphas = np.linspace(0.1, 0.6, 6)
    by_a = bond_stiffness(R, alphas, 0.02, K_GRAIN, G_GRAIN, 15e9, 8e9)
    by_h = bond_stiffness(R, 0.5, np.linspace(0.0, 0.1, 6), K_GRAIN, G_GRAIN, 15e9, 8e9)
    soft = bond_stiffness(R, 0.5, 0.02, K_GRAIN, G_GRAIN, 6.8e9, 2.0e9)
    hard = bond_stiffness(R, 0.5, 0.02, K_GRAIN, G_GRAIN, 15e9, 8e9)
    for field in range(4):
        assert np.all(np.diff(by_a[field]) > 0)
        assert np.all(np.diff(by_h[field]) < 0)
        assert hard[field] > soft[field] > 0
        assert np.all(np.isfinite(by_h[field]))          # h = 0 included: finite


def test_cement_volume_matches_quadrature():
    R, alpha, eps = 1.5e-4, 0.45, 0.03
    ref = quad(lambda r: 2 * np.pi * r * (2 * eps * R + gap(r, R)), 0, alpha * R, epsabs=0,
               epsrel=1e-12)[0]
    assert bond_cement_volume(R, alpha, eps) == pytest.approx(ref, rel=1e-9)


def test_bad_inputs(expect_value_error):
    expect_value_error(lambda: bond_stiffness(1e-4, 0.0, 0.0, K_GRAIN, G_GRAIN, 1e9, 1e9),
                       "radius_ratio")
    expect_value_error(lambda: bond_stiffness(1e-4, 0.3, -0.1, K_GRAIN, G_GRAIN, 1e9, 1e9),
                       "thickness_ratio")
    expect_value_error(lambda: bond_stiffness(1e-4, 0.3, 0.0, K_GRAIN, G_GRAIN, -1e9, 1e9),
                       "cement_bulk")
    pack, _ = lattice_pack()
    expect_value_error(lambda: bonded_system(pack, 1.5, cement_bulk=1e9, cement_shear=1e9),
                       "radius_ratio")
    expect_value_error(lambda: bonded_system(pack, 0.3, 0.6, cement_bulk=1e9, cement_shear=1e9),
                       "thickness_ratio")


# --- the linearised sample -----------------------------------------------------------------

def lattice_pack(n=(3, 3, 8), R=1e-4, jitter=0.0, seed=0):
    """Grains on a simple cubic lattice of spacing 2R(1 + 1e-9) (touching, without the Hertz
    overlap that round-off would leave), periodic in x, y; with ``jitter`` the centres are
    moved at random by up to that fraction of R."""
    nx, ny, nz = n
    d = 2 * R * (1 + 1e-9)
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    x = np.stack([(i.ravel() + 0.5) * d, (j.ravel() + 0.5) * d, R + k.ravel() * d], -1)
    x += jitter * R * np.random.default_rng(seed).uniform(-1, 1, x.shape)
    z = np.zeros_like(x)
    return Pack(x, z, z.copy(), np.full(len(x), R), Box(nx * d, ny * d, 0.0, nz * d + R),
                QUARTZ, np.zeros((0, 2), np.int32), np.zeros((0, 3))), d


def test_simple_cubic_lattice_moduli_closed_form():
    """Bonded simple cubic lattice of spacing d: K = k_n/(3d) (C11 = k_n/d, C12 = 0) and, with
    free rotations that stay zero by symmetry, G = k_s/(2d); the affine moduli are the same.
    ``slab=0.5`` puts the core planes halfway between grain layers, so the core holds whole
    layers of horizontal bonds."""
    pack, d = lattice_pack()
    system = bonded_system(pack, 0.4, 0.0, cement_bulk=15e9, cement_shear=8e9, slab=0.5)
    assert np.ptp(system.kn) == 0 and system.metadata["coordination_number"] == 6.0
    m = static_moduli(system)
    assert m.bulk == pytest.approx(system.kn[0] / (3 * d), rel=1e-9)
    assert m.shear == pytest.approx(system.ks[0] / (2 * d), rel=1e-9)
    assert m.bulk_affine == pytest.approx(m.bulk, rel=1e-9)
    assert m.shear_affine == pytest.approx(m.shear, rel=1e-9)


@pytest.fixture(scope="module")
def jittered():
    pack, d = lattice_pack(n=(4, 4, 8), jitter=0.08, seed=3)
    return bonded_system(pack, 0.35, 0.0, cement_bulk=15e9, cement_shear=8e9,
                         contact_gap=0.5 * d)


def test_rigid_motions_cost_nothing(jittered, rng):
    """Per link: a rigid translation and a rigid rotation (u = w x x, theta = w) give zero
    relative displacement and rotation; K is symmetric and positive semidefinite."""
    B = jittered._b_matrices
    w = rng.normal(size=3)
    t = rng.normal(size=3)
    m = B.shape[0]
    q = np.zeros((m, 12))
    q[:, 0:3] = t
    q[:, 3:6] = w
    q[:, 6:9] = t + np.cross(w, jittered.branch)
    q[:, 9:12] = w
    assert np.abs(np.einsum("mai,mi->ma", B, q)).max() < 1e-12 * np.abs(q).max()
    K = jittered.stiffness_matrix()
    assert abs(K - K.T).max() <= 1e-12 * abs(K).max()
    # Positive semidefinite: the smallest eigenvalue of the (scaled) dense matrix is >= 0 up to
    # round-off (the rigid translations make some of them zero).
    Kd = K.toarray()
    scale = 1.0 / np.sqrt(np.abs(np.diag(Kd)))
    w = np.linalg.eigvalsh(Kd * scale[:, None] * scale[None, :])
    assert w.min() > -1e-9 * w.max() and np.sum(w < 1e-9 * w.max()) >= 3


def test_relaxed_moduli_do_not_exceed_affine(jittered):
    """Relaxation lowers the energy. On a nearly affine lattice (jitter 0.08 R) relaxed and
    affine moduli agree within 1 %; with more disorder (0.25 R) relaxation lowers both by
    several per cent, more than the estimator's noise."""
    m = static_moduli(jittered)
    assert m.bulk == pytest.approx(m.bulk_affine, rel=0.01)
    assert m.shear == pytest.approx(m.shear_affine, rel=0.01)
    pack, d = lattice_pack(n=(4, 4, 8), jitter=0.25, seed=3)
    rough = static_moduli(bonded_system(pack, 0.35, 0.0, cement_bulk=15e9, cement_shear=8e9,
                                        contact_gap=0.5 * d))
    assert rough.bulk < 0.98 * rough.bulk_affine
    assert rough.shear < 0.98 * rough.shear_affine


def test_distant_bonding_is_softer_and_grid_dataset():
    """A gap h bridged by cement softens the sample (Xu 2023, Fig. 6); the grid Dataset holds
    K, G over a/R and h/2R in GPa with porosity rising with h (the grains shrink by 1 - eps)."""
    pack, _ = lattice_pack(n=(3, 3, 6))
    ds = bonded_moduli(pack, [0.3, 0.5], [0.0, 0.02, 0.05], cement_bulk=6.8e9,
                       cement_shear=2.0e9)
    assert ds.K.dims == ("radius_ratio", "thickness_ratio") and ds.K.attrs["units"] == "GPa"
    assert np.all(np.diff(ds.K.values, axis=1) < 0) and np.all(np.diff(ds.G.values, axis=1) < 0)
    assert np.all(np.diff(ds.K.values, axis=0) > 0)
    assert np.all(np.diff(ds.porosity.values, axis=1) > 0)
    assert float(ds.coordination_number) == 6.0


def test_static_velocities_and_density_of_the_grid():
    """vp = sqrt((K + 4/3 G)/rho), vs = sqrt(G/rho) in km/s with the dry density of grains and
    bond cement (g/cm3); a lighter cement lowers the density and raises the velocities."""
    pack, _ = lattice_pack(n=(3, 3, 6))
    heavy = bonded_moduli(pack, [0.4], [0.0], cement_bulk=15e9, cement_shear=8e9)
    light = bonded_moduli(pack, [0.4], [0.0], cement_bulk=15e9, cement_shear=8e9,
                          cement_density=1000.0)
    rho = float(heavy.density[0, 0])
    assert rho == pytest.approx((1 - float(heavy.porosity_uncemented[0])) * 2.65
                                + float(heavy.cement_fraction[0, 0]) * 2.65, rel=1e-12)
    K, G = float(heavy.K[0, 0]), float(heavy.G[0, 0])
    assert float(heavy.vp[0, 0]) == pytest.approx(np.sqrt((K + 4 * G / 3) / rho), rel=1e-12)
    assert float(heavy.vs[0, 0]) == pytest.approx(np.sqrt(G / rho), rel=1e-12)
    assert float(light.density[0, 0]) < rho and float(light.vp[0, 0]) > float(heavy.vp[0, 0])


def test_bonded_sample_in_the_pulse_test_operator():
    """The acoustic operator of a bonded simple cubic lattice: its static P-wave modulus is
    C11 = k_n/d (translations only, as the 6-dof solve under uniaxial strain, where the
    grains do not rotate); its mass holds the grains and the bond cement; the pulse travels
    near the long-wave velocity sqrt(C11/rho)."""
    from md.acoustic import pulse_test, static_modulus
    from md.bonded import bonded_acoustic_system

    pack, d = lattice_pack(n=(3, 3, 24))
    bonded = bonded_system(pack, 0.4, 0.0, cement_bulk=15e9, cement_shear=8e9)
    system = bonded_acoustic_system(bonded, slab_thickness=2 * d)
    grains = QUARTZ.density * 4 / 3 * np.pi * pack.radii**3
    cement = QUARTZ.density * bonded.bond_volume.sum()
    assert system.masses.sum() == pytest.approx(grains.sum() + cement, rel=1e-12)
    st = static_modulus(system, "p")
    assert st.modulus == pytest.approx(bonded.kn[0] / d, rel=1e-9)
    ds = pulse_test(system, "p")
    assert float(ds.velocity_fit) == pytest.approx(st.velocity, rel=0.1)


def test_grid_records_the_porosity_of_each_thickness_and_rejects_bad_knobs(expect_value_error):
    """The grains shrink with eps, so porosity_uncemented varies along thickness_ratio and
    equals each bonded_system's own; a slab <= 0 (no prescribed grains) and a non-finite
    strain are errors, not silent affine or NaN moduli."""
    from md.bonded import static_moduli as moduli

    pack, _ = lattice_pack(n=(3, 3, 6))
    ds = bonded_moduli(pack, [0.3], [0.0, 0.05], cement_bulk=6.8e9, cement_shear=2.0e9)
    for h in (0.0, 0.05):
        one = bonded_system(pack, 0.3, h, cement_bulk=6.8e9, cement_shear=2.0e9)
        assert float(ds.porosity_uncemented.sel(thickness_ratio=h)) == pytest.approx(
            one.metadata["porosity_uncemented"], rel=1e-12)
    assert float(ds.porosity_uncemented[1]) > float(ds.porosity_uncemented[0])
    expect_value_error(lambda: bonded_system(pack, 0.3, cement_bulk=1e9, cement_shear=1e9,
                                             slab=0.0), "slab")
    system = bonded_system(pack, 0.3, cement_bulk=1e9, cement_shear=1e9)
    expect_value_error(lambda: moduli(system, strain=np.inf), "strain")


def test_distant_bonding_refers_to_the_shrunk_grains():
    """With eps > 0 the grains shrink to R/(1 + eps), so touching pairs end 2 eps R' apart and
    the bonds are built on R' (a = alpha R', h = 2 eps R')."""
    pack, d = lattice_pack(n=(3, 3, 6))
    eps = 0.04
    system = bonded_system(pack, 0.3, eps, cement_bulk=6.8e9, cement_shear=2.0e9)
    R1 = pack.radii[0] / (1 + eps)
    assert system.radii == pytest.approx(np.full(pack.n_grains, R1), rel=1e-14)
    gap = np.linalg.norm(system.branch, axis=1) - 2 * R1
    assert gap == pytest.approx(np.full(gap.size, 2 * eps * R1), rel=1e-6)
    ref = bond_stiffness(R1, 0.3, eps, K_GRAIN, G_GRAIN, 6.8e9, 2.0e9)
    assert system.kn == pytest.approx(np.full(gap.size, ref.normal), rel=1e-12)


def test_moduli_do_not_depend_on_where_the_core_is_cut():
    """K and G come from tractions on horizontal planes, exact for any band: on a jittered
    lattice they change by well under 1 % when the end slabs (and so the core) change, while
    the in-plane xy estimate moves by per cents."""
    pack, d = lattice_pack(n=(5, 5, 12), jitter=0.08, seed=0)
    runs = [static_moduli(bonded_system(pack, 0.35, 0.0, cement_bulk=15e9, cement_shear=8e9,
                                        contact_gap=0.5 * d, slab=slab))
            for slab in (0.75, 1.0, 1.5)]
    K = np.array([m.bulk for m in runs])
    G = np.array([m.shear for m in runs])
    assert np.ptp(K) < 3e-3 * K.mean() and np.ptp(G) < 3e-3 * G.mean()
