"""md.static_stiffness: the five TI constants by static solves (issue 29, item 5)."""

import numpy as np
import pytest

from md.acoustic import acoustic_system, cement_block
from md.cement import HARD_CEMENT, SOFT_CEMENT, cement_lattice, grow_cement
from md.static import PA_PER_GPA, static_moduli, static_stiffness
from rockcem.anisotropy import thomsen, ti_bulk_modulus

CW = 1e-5


@pytest.mark.parametrize("cement", [HARD_CEMENT, SOFT_CEMENT])
@pytest.mark.parametrize("rotations,rel44", [(True, 5e-4), (False, 1e-9)])
def test_cement_block_is_isotropic_with_the_lattice_constants(cement, rotations, rel44):
    """A pure cement block: C11 = C33 = M and C12 = C13 = C31 = lambda = C_n/c_w, the lattice's
    own constants (md.cement.lattice_constants' docstring: rho Vp^2 = 3C_n/c_w + 3C/c_w^3;
    simple shear C_n/c_w + 3C/2c_w^3 with rotations, C_n/c_w + 3C/c_w^3 without); C66 by the
    affine in-plane simple shear equals it exactly, C44 (end slabs translated rigidly) up to
    the rotation mismatch layer at the end slabs (1e-4 of the S velocity on 24 cells, as
    tests/md/test_acoustic.py). The bulk modulus under hydrostatic stress is then M - 4/3 G
    and Thomsen's parameters vanish (delta only with rotations: without them the lattice's
    pure shear, in C11 - C12, is not its simple shear)."""
    block = cement_block((4, 4, 24), CW, cement, rotations=rotations)
    Cn, C = block.metadata["lattice_Cn"], block.metadata["lattice_C"]
    M = 3 * Cn / CW + 3 * C / CW**3
    lam = Cn / CW
    G = Cn / CW + (1.5 if rotations else 3.0) * C / CW**3
    st = static_stiffness(block)
    assert M == pytest.approx(cement.density * cement.vp**2, rel=1e-12)
    for got, want in ((st.c11, M), (st.c33, M), (st.c12, lam), (st.c13, lam), (st.c31, lam),
                      (st.c66, G)):
        assert got == pytest.approx(want, rel=1e-8)
    assert st.c44 == pytest.approx(G, rel=rel44)
    assert st.density == pytest.approx(cement.density, rel=1e-12)
    assert st.epsilon == pytest.approx(0.0, abs=1e-8)
    assert st.gamma == pytest.approx(0.0, abs=rel44)
    if rotations:
        assert st.c12 == pytest.approx(st.c11 - 2 * st.c66, rel=1e-8)
        assert st.bulk_reuss == pytest.approx(M - 4 / 3 * G, rel=1e-8)
        assert st.bulk_voigt == pytest.approx(M - 4 / 3 * G, rel=1e-8)
        assert st.delta == pytest.approx(0.0, abs=2 * rel44)


@pytest.fixture(scope="module")
def packs(compacted_pack):
    """The stored 96-grain pack bare and with a 10 % coating (Omega 3), linearised with
    rotations, and their stiffnesses."""
    lat = cement_lattice(compacted_pack, 3.0)
    out = {}
    for name, system in (("bare", acoustic_system(compacted_pack)),
                         ("coated", acoustic_system(compacted_pack, lat,
                                                    grow_cement(lat, 0.1, "coating")))):
        out[name] = (system, static_stiffness(system))
    return out


@pytest.mark.parametrize("name", ["bare", "coated"])
def test_c33_and_c44_are_the_static_moduli(packs, name):
    """C33 and C44 are static_moduli's P and S moduli (the same solves, measured alike)."""
    system, st = packs[name]
    ref = static_moduli(system)
    assert st.c33 == pytest.approx(ref["p"].modulus, rel=1e-12)
    assert st.c44 == pytest.approx(ref["s"].modulus, rel=1e-12)
    assert st.density == pytest.approx(ref["p"].density, rel=1e-15)


@pytest.mark.parametrize("name", ["bare", "coated"])
def test_band_virial_equals_the_reaction(packs, name):
    """The stress of the band (virial, each bond weighted by its segment inside) on
    horizontal planes equals the end slab's reaction over the area (every free particle is
    in equilibrium, so each horizontal plane carries the same force): sigma_zz of the z load
    and sigma_zx of the xz load, to the solver's tolerance."""
    _, st = packs[name]
    strain, stress, _ = st.loads["z"]
    assert stress[2, 2] == pytest.approx(st.c33 * strain[2, 2], rel=1e-8)
    strain, stress, _ = st.loads["xz"]
    assert stress[2, 0] == pytest.approx(st.c44 * 2 * strain[0, 2], rel=1e-8)


@pytest.mark.parametrize("name", ["bare", "coated"])
def test_affine_loads_strain_the_interior_as_imposed(packs, name):
    """The x, y, xy loads strain the interior by exactly the imposed in-plane strain (the
    fluctuations are periodic; the in-plane entries are set, not measured, so this checks the
    measured z-derivatives are small): |eps_zz|, |eps_xz|, |eps_yz| below a tenth of it."""
    _, st = packs[name]
    for key in ("x", "y", "xy"):
        strain, _, it = st.loads[key]
        size = np.abs(strain[:2, :2]).max()
        assert np.abs(strain[:, 2]).max() < 0.1 * size, key
        assert it <= 10                      # LU-preconditioned CG: a few iterations


@pytest.mark.parametrize("name,tol", [("bare", 0.06), ("coated", 0.12)])
def test_maxwell_reciprocity(packs, name, tol):
    """C13 (lateral stress of the z load) and C31 (vertical stress of the x and y loads) are
    the same constant by the symmetry of the stiffness. Each is measured in the interior band
    (the in-plane stress by the virial of its bonds), so they agree to the band's
    sample noise, not to the solver's: 3.5 % bare and 8 % coated on this 96-grain pack
    (3 grains across), measured; the tolerance holds that with margin. On the 4 x 4 x 12
    packs of benchmarks/md_anisotropy.py the difference is recorded per member."""
    _, st = packs[name]
    assert st.c13 == pytest.approx(st.c31, rel=tol)


@pytest.mark.parametrize("name", ["bare", "coated"])
def test_pack_bulk_modulus_and_thomsen(packs, name):
    """The compacted pack is stiffer along its compaction axis (C33 > C11, C44 > C66: epsilon
    and gamma < 0); its bulk modulus under hydrostatic stress lies below the Voigt-type
    C_iijj/9 (Cauchy-Schwarz on a positive-definite stiffness) and below C33 - 4/3 C44, the
    isotropic reading now used (18-28 % above on the scene's packs, issue 29); the derived
    values are rockcem.anisotropy's of the constants."""
    _, st = packs[name]
    assert 0 < st.bulk_reuss <= st.bulk_voigt
    assert st.bulk_reuss < st.bulk_isotropic
    assert st.c33 > st.c11 and st.c44 > st.c66
    assert st.epsilon < 0 and st.gamma < 0
    gpa = {k: getattr(st, k) / PA_PER_GPA for k in ("c11", "c13", "c33", "c44", "c66")}
    assert np.allclose(thomsen(**gpa), (st.epsilon, st.gamma, st.delta), rtol=1e-14)
    # ti_bulk_modulus's closed form with the measured C12 (C66 = (C11 - C12)/2), against the
    # numerical inverse of the normal block that static_stiffness takes.
    assert st.bulk_reuss / PA_PER_GPA == pytest.approx(float(ti_bulk_modulus(
        gpa["c11"], gpa["c13"], gpa["c33"], (st.c11 - st.c12) / 2 / PA_PER_GPA)), rel=1e-12)
    C = np.array([[st.c11, st.c12, st.c13], [st.c12, st.c11, st.c13],
                  [st.c13, st.c13, st.c33]])
    assert st.bulk_voigt == pytest.approx(C.sum() / 9, rel=1e-12)


@pytest.mark.parametrize("name,tol", [("bare", 0.3), ("coated", 0.1)])
def test_transverse_isotropy_relation(packs, name, tol):
    """C66 (in-plane simple shear) against (C11 - C12)/2 (uniaxial x and y strain): equal for a
    transversely isotropic sample, exactly so for the isotropic block above. A compacted pack is
    TI only statistically: on this pack, 3 grains across a square periodic cell, they differ by
    24 % bare and 6.5 % coated (measured); on the 4 x 4 x 12 packs of
    benchmarks/md_anisotropy.py by at most 17 % (median 5 %) over 18 members. The tolerance
    holds the measured difference with margin and fails on a factor-of-two error in either.
    (Written as C12 = C11 - 2 C66 the same check is ill-conditioned: C11 - 2 C66 is a small
    difference of large numbers.)"""
    _, st = packs[name]
    assert (st.c11 - st.c12) / 2 == pytest.approx(st.c66, rel=tol)
