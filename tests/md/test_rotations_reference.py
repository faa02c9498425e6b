"""The continuum reference of one cemented contact between rigid grains
(benchmarks/md_rotations_reference.py) against closed forms, and the rigid-grain cement lattice,
with and without rotations, against that reference (docs/studies/md_rotations_reference.md)."""

from __future__ import annotations

import importlib
import os
import sys
from pathlib import Path

import numpy as np
import pytest

from md.cement import HARD_CEMENT
from md.cemented_contact import lattice_contact_stiffness, theory_contact_stiffness
from md.contact import QUARTZ, GrainMaterial

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"

G_C, M_C = HARD_CEMENT.shear_modulus, HARD_CEMENT.p_modulus
R = 1e-4


@pytest.fixture(scope="module")
def ref():
    """The benchmark module. Its ``_common`` pins the thread variables to 1 on import (for a
    benchmark process); here they are put back at once, since numba refuses a thread count
    that changes after its pool has started (later tests in the session would fail)."""
    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))
    saved = dict(os.environ)
    try:
        return importlib.import_module("md_rotations_reference")
    finally:
        os.environ.clear()
        os.environ.update(saved)


def test_confined_layer_between_rigid_plates_is_the_closed_form(ref):
    """A cylinder of radius a and thickness t = 2H bonded to two rigid plates, its rim held
    radially (uniaxial strain) and, in shear, following the affine simple shear: k_n = M_c A/t,
    k_t = G_c A/t with A = pi a^2, exactly (the elements hold linear fields)."""
    a, H = 0.5 * R, 0.1 * R
    area, t = np.pi * a**2, 2 * H
    for n in (1, 3):
        kn, kt = ref.axisymmetric_stiffness(0.5, 0.0, n, shear_modulus=G_C, p_modulus=M_C,
                                            radius=R, half_height=H, confined=True)
        assert kn == pytest.approx(M_C * area / t, rel=1e-10)
        assert kt == pytest.approx(G_C * area / t, rel=1e-10)


def test_torsion_of_a_layer_between_rigid_plates_is_saint_venant(ref):
    """A cylinder bonded to two rigid plates, the upper one turned about the axis, its rim
    free: Saint-Venant's torsion u_theta = theta r z / t is exact, k = G_c J / t with
    J = pi a^4 / 2."""
    a, H = 0.5 * R, 0.1 * R
    (k,) = ref.axisymmetric_stiffness(0.5, 0.0, 2, shear_modulus=G_C, p_modulus=M_C, radius=R,
                                      half_height=H, loads=("torsion",))
    assert k == pytest.approx(G_C * np.pi * a**4 / 2 / (2 * H), rel=1e-10)


def test_rotation_penalty_in_confined_shear_is_the_closed_form(ref):
    """With the rotation penalty d the affine simple shear gamma costs (G + d) gamma^2 / 2 per
    volume (strain and rotation both gamma/2): k_t = (G + d) A/t; compression has no rotation,
    k_n = M A/t."""
    a, H = 0.5 * R, 0.1 * R
    area, t, d = np.pi * a**2, 2 * H, 0.37 * G_C
    kn, kt = ref.axisymmetric_stiffness(0.5, 0.0, 2, shear_modulus=G_C, p_modulus=M_C,
                                        rotation_modulus=d, radius=R, half_height=H,
                                        confined=True)
    assert kn == pytest.approx(M_C * area / t, rel=1e-10)
    assert kt == pytest.approx((G_C + d) * area / t, rel=1e-10)


def test_lattice_continuum_is_the_bond_sum():
    """The long-wave energy of the cement lattice, summed bond by bond from
    md.cement.lattice_constants (9 bonds per cell: central C_n (x.F x)^2 |x|^2 and tangential
    C |F x|^2, halved), equals lattice_continuum's: for the rotating lattice (tangential term
    on the strain) the isotropic cement, for the translations-only one the isotropic
    (lambda', G') plus d w:w, for random displacement gradients."""
    from md.cement import lattice_constants

    if str(BENCH) not in sys.path:
        sys.path.insert(0, str(BENCH))
    ref = importlib.import_module("md_rotations_reference")
    cw = 1e-5
    bonds = np.array([(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (1, -1, 0), (1, 0, 1),
                      (1, 0, -1), (0, 1, 1), (0, 1, -1)], float) * cw
    rng = np.random.default_rng(7)
    for rotations in (True, False):
        Cn, C, _ = lattice_constants(HARD_CEMENT, cw, rotations=rotations)
        G, M, d = ref.lattice_continuum(HARD_CEMENT, rotations)
        lam = M - 2 * G
        for _ in range(3):
            F = rng.normal(size=(3, 3)) * 1e-4
            e, w = 0.5 * (F + F.T), 0.5 * (F - F.T)
            Ft = e if rotations else F
            bond = sum(0.5 * Cn * (x @ F @ x) ** 2 / (x @ x) + 0.5 * C * np.sum((Ft @ x) ** 2)
                       / (x @ x) for x in bonds) / cw**3
            continuum = 0.5 * lam * np.trace(e) ** 2 + G * np.sum(e * e) + d * np.sum(w * w)
            assert bond == pytest.approx(continuum, rel=1e-12)


def test_lattice_offset_is_checked_and_mirror_symmetric():
    """The cement cells' centres sit at (k + 1/2 + o) cell widths along each axis; offsets o
    and 1 - o are mirror images of the symmetric contact: the same stiffness; offsets
    outside [0, 1) cells, or not three of them, are refused by name."""
    from md.cemented_contact import contact_system

    off = np.array([0.2, 0.3, 0.35])
    system = contact_system(0.5, 8, lattice_offset=off)
    cw = system.metadata["cell_width"]
    frac = (system.positions[2:] / cw - 0.5 - off) % 1.0
    assert np.all(np.minimum(frac, 1 - frac) < 1e-9)
    a = lattice_contact_stiffness(0.5, 8, lattice_offset=(0.2, 0.3, 0.35))
    b = lattice_contact_stiffness(0.5, 8, lattice_offset=(0.8, 0.7, 0.65))
    np.testing.assert_allclose(a, b, rtol=1e-8)
    for bad in ((0.0, 0.0, 1.0), (-0.1, 0.0, 0.0), (0.5, 0.5), "x"):
        with pytest.raises(ValueError, match="lattice_offset"):
            lattice_contact_stiffness(0.5, 8, lattice_offset=bad)


def test_free_rim_layer_lies_between_its_bounds(ref):
    """With a free rim the bonded cylinder in compression lies between the unconfined column
    (E_c A/t, ends free to slide) and uniaxial strain (M_c A/t); in shear it is below the
    affine simple shear G_c A/t (free rim: the minimum of energy under fewer constraints)."""
    a, H = 0.5 * R, 0.1 * R
    area, t = np.pi * a**2, 2 * H
    nu = (M_C - 2 * G_C) / (2 * (M_C - G_C))
    E = 2 * G_C * (1 + nu)
    kn, kt = ref.axisymmetric_stiffness(0.5, 0.0, 8, shear_modulus=G_C, p_modulus=M_C,
                                        radius=R, half_height=H)
    assert E * area / t < kn < M_C * area / t
    assert kt < G_C * area / t


def test_thin_neck_tends_to_the_thin_layer_closed_form(ref):
    """As the neck thins (a/R 0.1, eps 1e-3 then 5e-4) the continuum approaches the rigid-grain
    limit of Dvorkin et al. (1994), pi M_c R ln(1 + a^2/2 eps) and pi G_c R ln(...): within
    1 % and closer for the thinner one (0.9927 / 0.9904, 0.9942 / 0.9928; the rest is the
    free rim, of the layer's thickness)."""
    gaps = []
    for eps in (1e-3, 5e-4):
        layer = theory_contact_stiffness(0.1, radius=R, thickness_ratio=eps,
                                         limit="rigid_grains")
        kn, kt = ref.axisymmetric_stiffness(0.1, eps, 8, shear_modulus=G_C, p_modulus=M_C,
                                            radius=R)
        gaps.append((1 - kn / layer.normal, 1 - kt / layer.tangential))
    gaps = np.array(gaps)
    assert np.all(gaps > 0) and np.all(gaps < 0.01)
    assert np.all(gaps[1] < gaps[0])


def test_continuum_neck_converges(ref):
    """a/R 0.5, eps 0.05: 8 and 16 elements a side agree to 3e-5 (the observed order is about
    4 from 16, 32 and 64 elements, and 64 is within 1e-8 of the Richardson limit)."""
    k8 = np.array(ref.axisymmetric_stiffness(0.5, 0.05, 8, shear_modulus=G_C, p_modulus=M_C,
                                             radius=R))
    k16 = np.array(ref.axisymmetric_stiffness(0.5, 0.05, 16, shear_modulus=G_C,
                                              p_modulus=M_C, radius=R))
    np.testing.assert_allclose(k8, k16, rtol=3e-5)


def test_richardson_recovers_a_known_order(ref):
    """y = 1 + 0.3 h^2: order 2 and the limit 1 from h = 1/4, 1/8, 1/16."""
    h = np.array([0.25, 0.125, 0.0625])
    p, lim, err = ref.richardson(h, 1 + 0.3 * h**2)
    assert p == pytest.approx(2.0, rel=1e-12) and lim == pytest.approx(1.0, rel=1e-12)
    assert err == pytest.approx(0.3 * 0.0625**2, rel=1e-12)


def test_rigid_grain_lattice_against_the_continuum(ref):
    """Grains 10^4 times stiffer than quartz (a/R 0.5), at (eps, Omega) (0.05, 16), (0.1, 12),
    (0.1, 16): both lattices within 6 % of the cement's continuum, normal and tangential
    (measured 1.001 / 1.048, 0.992 / 1.051, 0.961 / 1.014 translations only; 1.012 / 1.051,
    1.009 / 1.043, 0.977 / 0.994 rotating), the rotating lattice's tangential error no larger
    than the translations-only one's (+ 0.5 point). The rotating lattice tends to the cement,
    the translations-only one to its own long-wave continuum (lattice_continuum), so their
    ratio tends to that of the two continua: in normal it is there to 0.3 % already (1.0113
    against 1.0102, 1.0164 and 1.0169 against 1.0152), in shear it lies between 1 and the
    continua's ratio at eps 0.1 (0.992, 0.981 against 0.968)."""
    rigid = GrainMaterial(QUARTZ.shear_modulus * 1e4, QUARTZ.poisson_ratio, QUARTZ.density)
    for eps, omega in ((0.05, 16), (0.1, 12), (0.1, 16)):
        cont = {rot: np.array(ref.axisymmetric_stiffness(
            0.5, eps, 16, **dict(zip(("shear_modulus", "p_modulus", "rotation_modulus"),
                                     ref.lattice_continuum(HARD_CEMENT, rot))), radius=R))
            for rot in (False, True)}
        k = {rot: np.array(lattice_contact_stiffness(0.5, omega, radius=R, thickness_ratio=eps,
                                                     material=rigid, rotations=rot)) / cont[True]
             for rot in (False, True)}
        for rot in (False, True):
            assert np.all(np.abs(k[rot] - 1) < 0.06), (eps, omega, rot, k[rot])
        assert abs(k[True][1] - 1) <= abs(k[False][1] - 1) + 0.005, (eps, omega, k)
        limit = cont[True] / cont[False]
        assert abs(k[True][0] / k[False][0] - limit[0]) < 0.003, (eps, omega, k, limit)
        if eps == 0.1:
            assert limit[1] < k[True][1] / k[False][1] < 1.0, (eps, omega, k, limit)


def test_rotating_lattice_bends_and_twists_as_the_continuum(ref):
    """The rotating lattice's grain turned about y through its centre (bending) and about the
    axis (torsion), rigid grains, a/R 0.5, eps 0.1, Omega 16: within 2 % (bending, 0.992) and
    5 % (torsion, 0.976; 0.86-0.94 at Omega 12 and 24: the rim, r^3-weighted, is where the
    lattice's cells are coarsest) of the continuum."""
    from md.cemented_contact import _grain_reactions, contact_system

    rigid = GrainMaterial(QUARTZ.shear_modulus * 1e4, QUARTZ.poisson_ratio, QUARTZ.density)
    cont = np.array(ref.axisymmetric_stiffness(0.5, 0.1, 16, shear_modulus=G_C, p_modulus=M_C,
                                               radius=R, loads=("bending", "torsion")))
    system = contact_system(0.5, 16, radius=R, thickness_ratio=0.1, material=rigid,
                            rotations=True)
    k = np.array(_grain_reactions(system, (4, 5))) / cont
    assert abs(k[0] - 1) < 0.02 and abs(k[1] - 1) < 0.05, k


def test_interface_column_length_is_a_layer_in_series():
    """md.interface.interface_stiffness's ``column``: the cement's part of a bond is a layer of
    thickness L over the area A_i (M_c A_i/L, G_c A_i/L) in series with the grain's part, so
    1/k(L) - 1/k(c_w/2) = (L - c_w/2)/(M_c A_i) normal, /(G_c A_i) tangential, with A_i by
    hand: c_w^2 for a normal along z, c_w^2/0.8 for (0.6, 0, 0.8) (max(0.8, 0.7) = 0.8). No
    column is the half cell; bad lengths are refused by name."""
    from md.interface import interface_stiffness

    cw = 1e-5
    normal = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]])
    grain, cell = np.array([0, 0]), np.array([0, 1])
    table = np.full((2, 9), -1, np.int32)
    table[0, 0] = 3                         # the two cells are neighbours: one patch
    args = (grain, cell, normal, np.array([1e-4]), table, 2, cw, QUARTZ, HARD_CEMENT, "patch")
    kn0, kt0 = interface_stiffness(*args)
    kn1, kt1 = interface_stiffness(*args, column=np.full(2, 0.5 * cw))
    np.testing.assert_array_equal(kn0, kn1)
    np.testing.assert_array_equal(kt0, kt1)
    L = np.array([0.2 * cw, 0.9 * cw])
    kn, kt = interface_stiffness(*args, column=L)
    area = np.array([cw**2, cw**2 / 0.8])
    np.testing.assert_allclose(1 / kn - 1 / kn0, (L - 0.5 * cw) / (M_C * area), rtol=1e-9)
    np.testing.assert_allclose(1 / kt - 1 / kt0, (L - 0.5 * cw) / (G_C * area), rtol=1e-9)
    for bad in (np.zeros(2), np.full(3, cw), np.array([cw, np.nan])):
        with pytest.raises(ValueError, match="column"):
            interface_stiffness(*args, column=bad)


def test_contact_bond_columns_are_the_cell_heights():
    """contact_system's ``bond_column``: "distance" makes each bond's column the distance of
    its cell centre from the sphere, |x_c - x_g| - R (at least column_floor c_w), "volume" half
    a cell's volume over A_i, computed here from the positions; the lattice is the same, and
    the default is "half_cell" to the bit. Unknown names and floors outside (0, 1] are
    refused by name."""
    from md.cemented_contact import contact_system
    from md.interface import interface_area

    base = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rotations=True)
    cw = base.metadata["cell_width"]
    g, c = base.bond_i, base.bond_j
    h = np.linalg.norm(base.positions[c] - base.positions[g], axis=1) - R
    assert np.all(h > 0) and h.min() < 0.1 * cw      # the floor is reached by some cell
    area = interface_area(base.bond_normal, cw)
    half = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rotations=True,
                          bond_column="half_cell")
    np.testing.assert_array_equal(half.bond_kt, base.bond_kt)
    for option, L in ((dict(bond_column="distance", column_floor=0.1),
                       np.maximum(h, 0.1 * cw)),
                      (dict(bond_column="volume"), 0.5 * cw**3 / area)):
        s = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rotations=True, **option)
        np.testing.assert_array_equal(s.lattice_kn, base.lattice_kn)
        np.testing.assert_allclose(1 / s.bond_kn - 1 / base.bond_kn,
                                   (L - 0.5 * cw) / (M_C * area), rtol=1e-8, atol=1e-20)
        np.testing.assert_allclose(1 / s.bond_kt - 1 / base.bond_kt,
                                   (L - 0.5 * cw) / (G_C * area), rtol=1e-8, atol=1e-20)
    with pytest.raises(ValueError, match="bond_column"):
        contact_system(0.5, 8, bond_column="distnce")
    for floor in (0.0, 1.5):
        with pytest.raises(ValueError, match="column_floor"):
            contact_system(0.5, 8, bond_column="distance", column_floor=floor)


def test_rotation_ties_cost_only_the_relative_turn(ref):
    """The study springs of --twist: a common rotation of a grain and its cells costs nothing;
    a cell turned by t about an axis s relative to its grain costs k t^2 |P s|^2 / 2, with
    P = I ("all") or n n^T ("drilling": only the turn about the bond normal)."""
    from md.cemented_contact import contact_system

    system = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rotations=True)
    k = 2.0
    n, dof = system.n_particles, system.dof
    b = 5                                   # one bond: grain g, cell c, normal nb
    g, c, nb = system.bond_i[b], system.bond_j[b], system.bond_normal[b]
    cells_of_g = system.bond_j[system.bond_i == g]
    perp = np.cross(nb, [1.0, 0.0, 0.0])
    perp /= np.linalg.norm(perp)
    for which in ("all", "drilling"):
        T = ref.rotation_ties(system, which, k)
        u = np.zeros((n, dof))
        u[[g, *cells_of_g], 3:] = [0.3, -0.2, 0.5]
        assert abs(u.ravel() @ T @ u.ravel()) < 1e-12
        for axis, drilling_cost in ((nb, 1.0), (perp, 0.0)):
            u = np.zeros((n, dof))
            u[c, 3:] = 0.7 * axis
            # the cell's other bonds (to the same or the other grain) count too
            bonds = np.flatnonzero(system.bond_j == c)
            nn = system.bond_normal[bonds] @ axis
            want = 0.5 * k * 0.49 * (bonds.size if which == "all" else np.sum(nn**2))
            assert u.ravel() @ T @ u.ravel() / 2 == pytest.approx(want, rel=1e-12)
            if which == "drilling" and bonds.size == 1:
                assert want == pytest.approx(0.5 * k * 0.49 * drilling_cost)


def test_rim_shift_widens_the_cemented_cells():
    """contact_system's ``rim_shift`` s: the cement cells are those whose centre lies within
    a + s c_w of the axis (and outside both spheres, checked here from the positions); s = 0
    is the default to the bit; shifts outside [0, 1) cells are refused by name."""
    from md.cemented_contact import contact_system

    base = contact_system(0.5, 8, radius=R, thickness_ratio=0.05)
    wide = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rim_shift=0.5)
    cw = base.metadata["cell_width"]
    for system, limit in ((base, 0.5 * R), (wide, 0.5 * R + 0.5 * cw)):
        rho = np.hypot(*system.positions[2:, :2].T)
        assert rho.max() <= limit
    rho_w = np.hypot(*wide.positions[2:, :2].T)
    assert np.any((rho_w > 0.5 * R) & (rho_w <= 0.5 * R + 0.5 * cw))
    zero = contact_system(0.5, 8, radius=R, thickness_ratio=0.05, rim_shift=0.0)
    np.testing.assert_array_equal(zero.positions, base.positions)
    for bad in (-0.1, 1.0):
        with pytest.raises(ValueError, match="rim_shift"):
            contact_system(0.5, 8, rim_shift=bad)
