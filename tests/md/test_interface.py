"""The grain–cement interface (md.interface) and the single cemented contact
(md.cemented_contact): geometry against closed forms, patches against a graph library, and the
contact stiffness against the cemented-contact integral equation of Dvorkin et al. (1994)."""

import numpy as np
import pytest

from md.cement import HARD_CEMENT, CementMaterial, cement_lattice
from md.cemented_contact import (contact_system, lattice_contact_stiffness,
                                 theory_contact_stiffness)
from md.contact import QUARTZ
from md.interface import interface_area, interface_patches, patch_radius
from md.space import Box
from md.state import Pack

R = 1e-4


def one_grain(offset=(0.37, 0.61, 0.23)):
    """One grain of radius R inside a box of 3R, off the lattice planes."""
    side = 3.0 * R
    x = np.array([[side / 2 + offset[0] * 1e-5, side / 2 + offset[1] * 1e-5, 1.5 * R]])
    z = np.zeros_like(x)
    return Pack(x, z, z.copy(), np.full(1, R), Box(side, side, 0.0, 3.0 * R), QUARTZ,
                np.zeros((0, 2), np.int32), np.zeros((0, 3)))


def coat_bonds(omega, faces=True):
    """Grain–cement bonds of a grain whose every pore cell is cemented (the kernel)."""
    from md._kernels_acoustic import grain_cement_bonds

    pack = one_grain()
    lat = cement_lattice(pack, omega)
    nx, ny, nz = lat.shape
    where = np.full(nx * ny * nz, -1, np.int32)
    where[lat.index] = np.arange(lat.index.size, dtype=np.int32)
    args = (pack.positions, pack.radii, where, pack.box.lx, pack.box.ly, lat.z0,
            lat.cell_width, nx, ny, nz, faces)
    n = grain_cement_bonds(*args, True, np.zeros(0, np.int32), np.zeros(0, np.int32),
                           np.zeros((0, 3)))
    bi, bj, nrm = np.empty(n, np.int32), np.empty(n, np.int32), np.empty((n, 3))
    grain_cement_bonds(*args, False, bi, bj, nrm)
    return pack, lat, bj, nrm


def test_coated_sphere_interface_area_converges_to_its_surface():
    """Sum of the cells' interface areas of a fully coated sphere -> 4 pi R^2 (3.7 %, 1.6 %,
    1.4 % at Omega 8, 16, 32 for this placement of the grain on the lattice)."""
    err = []
    for omega in (8, 16, 32):
        _, lat, _, nrm = coat_bonds(omega)
        err.append(interface_area(nrm, lat.cell_width).sum() / (4 * np.pi * R**2) - 1)
    assert max(abs(e) for e in err) < 0.04 and abs(err[-1]) < 0.02


def test_bond_kernel_against_brute_force():
    """The kernel joins exactly the pore cells whose cube meets the sphere or one of whose face
    neighbours has its centre inside it (brute force over all pore cells)."""
    pack, lat, bj, _ = coat_bonds(7)
    c = lat.centres()
    x0, cw = pack.positions[0], lat.cell_width
    closest = np.clip(x0, c - cw / 2, c + cw / 2)
    want = np.sum((closest - x0) ** 2, axis=1) < R**2
    for step in np.vstack([np.eye(3), -np.eye(3)]) * cw:
        want |= np.sum((c + step - x0) ** 2, axis=1) < R**2
    assert np.array_equal(np.sort(bj), np.flatnonzero(want))
    _, _, bj_paper, _ = coat_bonds(7, faces=False)
    assert set(bj_paper) < set(bj)


@pytest.mark.parametrize("theta_in,theta_out", [(0.0, 0.4), (0.0, np.pi / 2), (0.3, 0.9)])
def test_patch_radius_is_the_outer_radius_of_a_cap_or_zone(theta_in, theta_out):
    """A spherical cap or zone theta_in < theta < theta_out about a tilted axis, sampled by
    midpoint quadrature: the patch radius is R sin(theta_out)."""
    t_edges = np.linspace(theta_in, theta_out, 401)
    t = 0.5 * (t_edges[1:] + t_edges[:-1])
    p = np.linspace(0, 2 * np.pi, 721)[:-1]
    t, p = np.meshgrid(t, p, indexing="ij")
    n = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    area = (R**2 * np.sin(t) * np.diff(t_edges)[0] * 2 * np.pi / 720).ravel()
    c, s = np.cos(0.7), np.sin(0.7)
    n = n @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T
    a = patch_radius(n, area, np.zeros(n.shape[0], np.int64), np.array([R]))
    assert a[0] == pytest.approx(R * np.sin(theta_out), rel=2e-4)


def test_patches_against_connected_components(rng):
    """Union–find patches = connected components of the graph 'same grain and a lattice bond'."""
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    system = contact_system(0.5, 12)
    cell = system.bond_j.astype(np.int64) - 2
    label = interface_patches(system.bond_i, cell, system.lattice_neighbors, 2)
    # Two grains; each grain's cells form one ring here, plus a random split of the bonds.
    li, lj = system.lattice_i - 2, system.lattice_j - 2
    # The facet rule splits by the neighbour too: a random partner per bond.
    partner = rng.integers(0, 3, cell.size)
    for grain_of_bond, part in ((system.bond_i, None), (rng.integers(0, 2, cell.size), None),
                                (system.bond_i, partner)):
        label = interface_patches(grain_of_bond, cell, system.lattice_neighbors, 2, part)
        rows, cols = [], []
        for b1 in range(cell.size):
            for b2 in range(cell.size):
                if grain_of_bond[b1] != grain_of_bond[b2]:
                    continue
                if part is not None and part[b1] != part[b2]:
                    continue
                c1, c2 = cell[b1], cell[b2]
                if np.any((li == c1) & (lj == c2)) or np.any((li == c2) & (lj == c1)):
                    rows.append(b1)
                    cols.append(b2)
        graph = sp.coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(cell.size,) * 2)
        n, ref = connected_components(graph, directed=False)
        assert label.max() + 1 == n
        # same partition: a one-to-one map between the labellings
        pairs = set(zip(label.tolist(), ref.tolist()))
        assert len(pairs) == n


def test_bond_partners_against_brute_force(rng):
    """The grain whose surface is nearest a cell centre, its own grain excepted, by the k-d tree
    against all grains with the minimum image in x and y."""
    from md.interface import bond_partners

    box = Box(2e-3, 1.5e-3, 0.0, 3e-3)
    n = 40
    x = rng.uniform([0, 0, 0.2e-3], [box.lx, box.ly, 2.8e-3], (n, 3))
    r = rng.uniform(1.8e-4, 2.0e-4, n)
    m = 300
    grain = rng.integers(0, n, m)
    cells = rng.uniform([-0.1e-3, -0.1e-3, 0.0], [box.lx + 0.1e-3, box.ly + 0.1e-3, 3e-3],
                        (m, 3))
    got = bond_partners(grain, cells, x, r, box, k=n)
    d = cells[:, None, :] - x[None, :, :]
    d[..., 0] -= box.lx * np.round(d[..., 0] / box.lx)
    d[..., 1] -= box.ly * np.round(d[..., 1] / box.ly)
    gap = np.linalg.norm(d, axis=-1) - r[None, :]
    gap[np.arange(m), grain] = np.inf
    np.testing.assert_array_equal(got, np.argmin(gap, axis=1))
    # The default search (8 nearest centres) finds the same in a pack of near-equal radii.
    np.testing.assert_array_equal(bond_partners(grain, cells, x, r, box), got)


@pytest.fixture(scope="module")
def small_pack(compacted_pack):
    return compacted_pack


@pytest.mark.parametrize("scheme", ["pendular", "contact"])
def test_facet_interface_cement_never_softens_the_pack(small_pack, scheme):
    """Adding cement to a pack cannot lower its static modulus (the cement of S_c holds that of
    any smaller S_c; a stiffer spring network is stiffer). The facet rule keeps this; the patch
    rule does not once the necks of a grain join (md.interface docstring)."""
    import md

    lat = cement_lattice(small_pack, 7.0)
    sats = (0.05, 0.1, 0.2, 0.3)
    grown = md.cement_sweep(lat, sats, scheme)
    assert all(np.all(grown[k + 1][grown[k]]) for k in range(len(sats) - 1))   # nested
    moduli = [md.static_modulus(md.acoustic_system(small_pack, lat, cells, HARD_CEMENT,
                                                   interface="facet"), "p", rtol=1e-8).modulus
              for cells in grown]
    assert np.all(np.diff(moduli) > 0), moduli


# --- one cemented contact ------------------------------------------------------------------

@pytest.fixture(scope="module")
def contact_sequence():
    """a/R = 0.5, touching grains, Omega 8, 16, 32: lattice / theory, both rules."""
    theory = theory_contact_stiffness(0.5)
    out = {}
    for interface in ("patch", "paper"):
        ks = [lattice_contact_stiffness(0.5, om, interface=interface) for om in (8, 16, 32)]
        out[interface] = np.array([[k.normal / theory.normal, k.tangential / theory.tangential]
                                   for k in ks])
    return out


def test_patch_interface_converges_to_the_integral_equation(contact_sequence):
    """Patch rule: successive changes shrink (first order), within 10 % (normal) and 25 %
    (tangential) of the integral equation at Omega 32 (0.937, 0.793); Omega 48 (benchmark) is
    3.4 % and 16.5 % below it."""
    r = contact_sequence["patch"]
    steps = np.abs(np.diff(r, axis=0))
    assert np.all(steps[1] < 0.6 * steps[0])
    assert abs(r[-1, 0] - 1) < 0.10 and abs(r[-1, 1] - 1) < 0.25


def test_paper_interface_stiffens_without_bound(contact_sequence):
    """The per-cell rule grows roughly like Omega and passes the welded (rigid-cement)
    contact, which no cement can exceed."""
    r = contact_sequence["paper"]
    welded = theory_contact_stiffness(0.5, limit="rigid_cement")
    theory = theory_contact_stiffness(0.5)
    assert np.all(np.diff(r[:, 0]) > 0.4)
    assert r[-1, 0] * theory.normal > 1.5 * welded.normal


def test_rigid_cement_limit_is_the_welded_contact():
    """Cement 900x stiffer: the patch rule gives two flat punches of the patch's outer radius
    in series, the welded contact (0.992, 0.978 at Omega 8, 16), although the resolved cement
    misses the core r < sqrt(R c_w) where the gap is under a cell."""
    stiff = CementMaterial(HARD_CEMENT.vp * 30, HARD_CEMENT.vs * 30, HARD_CEMENT.density)
    welded = theory_contact_stiffness(0.5, limit="rigid_cement")
    r = [lattice_contact_stiffness(0.5, om, cement=stiff).normal / welded.normal
         for om in (8, 16, 24)]
    assert np.all(np.abs(np.array(r) - 1) < 0.03)


def test_theory_limits_bracket_the_integral_equation():
    """Integral equation between its limits: rigid grains (thin layer, eps > 0) and rigid
    cement (welded) are both stiffer than the elastic pair."""
    for eps in (0.01, 0.05):
        k = theory_contact_stiffness(0.3, thickness_ratio=eps)
        for limit in ("rigid_grains", "rigid_cement"):
            assert np.all(np.array(theory_contact_stiffness(0.3, thickness_ratio=eps,
                                                            limit=limit)) > np.array(k))


def test_bad_contact_input():
    with pytest.raises(ValueError, match="radius_ratio"):
        lattice_contact_stiffness(1.5, 8)
    with pytest.raises(ValueError, match="resolution"):
        lattice_contact_stiffness(0.5, 1)
    with pytest.raises(ValueError, match="raise the resolution"):
        lattice_contact_stiffness(0.1, 4)
    with pytest.raises(ValueError, match="thickness_ratio > 0"):
        theory_contact_stiffness(0.3, limit="rigid_grains")
    for limit in (None, "rigid_grains", "rigid_cement"):       # no negative stiffness
        with pytest.raises(ValueError, match="radius_ratio"):
            theory_contact_stiffness(-0.2, thickness_ratio=0.01, limit=limit)
        with pytest.raises(ValueError, match="radius_ratio"):
            theory_contact_stiffness(1.5, thickness_ratio=0.01, limit=limit)
        with pytest.raises(ValueError, match="thickness_ratio"):
            theory_contact_stiffness(0.3, thickness_ratio=-0.01, limit=limit)
        with pytest.raises(ValueError, match="radius must"):
            theory_contact_stiffness(0.3, radius=-1e-4, thickness_ratio=0.01, limit=limit)
    with pytest.raises(ValueError, match="radius must"):
        lattice_contact_stiffness(0.5, 8, radius=0.0)
    with pytest.raises(ValueError, match="interface"):
        lattice_contact_stiffness(0.5, 8, interface="cell")


def test_docstrings_hold_no_escaped_control_characters():
    """A TeX command in a non-raw docstring (\\alpha, \\varepsilon) turns into a control
    character (BEL, VT) and the formula is lost."""
    import inspect

    import md.cemented_contact
    import md.interface

    for module in (md.cemented_contact, md.interface):
        for obj in (module, *(getattr(module, n) for n in module.__all__)):
            doc = inspect.getdoc(obj) or ""
            assert not any(c in doc for c in "\a\b\f\v"), obj


def test_facet_punch_around_a_contact_is_the_annulus():
    """interface_stiffness, rule "facet": the cells of a grain's facet toward a grain it touches
    share the punch of the annulus outside the contact, 2 E* (a_p - a_c) (a rigid flat punch's
    stiffness is linear in its radius, Johnson 1985 Sect. 3.8), where the facet alone has
    2 E* a_p. With a rigid cement the bonds are the grain's punch alone, so the facet's sum
    drops by exactly 2 E* a_c (normal) and 8 G a_c/(2 - nu) (tangential); facets toward grains
    it does not touch are unchanged, and a contact wider than the facet leaves MIN_ANNULUS of
    it."""
    from md.interface import MIN_ANNULUS, interface_stiffness

    R, cw = 1e-4, 1e-5
    # Grain 0 with two facets of three cells each: toward grain 1 (touching) and grain 2.
    normals = np.array([[0, 0, 1.0], [0.1, 0, 0.995], [-0.1, 0, 0.995],
                        [1.0, 0, 0], [0.995, 0.1, 0], [0.995, -0.1, 0]])
    normals /= np.linalg.norm(normals, axis=1)[:, None]
    grain = np.zeros(6, np.int64)
    cell = np.arange(6, dtype=np.int64)
    partner = np.array([1, 1, 1, 2, 2, 2])
    table = np.full((6, 9), -1, np.int32)          # each facet's cells joined in a chain
    for a, b in ((0, 1), (1, 2), (3, 4), (4, 5)):
        table[a, 0], table[b, 1] = 3 + b, 3 + a
    rigid = CementMaterial(6.0e5, 3.5e5, 2650.0)  # ~10^4 times quartz's moduli
    args = (grain, cell, normals, np.full(3, R), table, 3, cw, QUARTZ, rigid, "facet",
            partner)
    kn0, kt0 = interface_stiffness(*args)
    a_c = 2e-6
    kn1, kt1 = interface_stiffness(*args, contact_pairs=np.array([[1, 0]]),
                                   contact_radius=np.array([a_c]))
    nu, E, G = QUARTZ.poisson_ratio, QUARTZ.young_modulus, QUARTZ.shear_modulus
    np.testing.assert_allclose(kn0[:3].sum() - kn1[:3].sum(), 2 * E / (1 - nu**2) * a_c,
                               rtol=2e-3)
    np.testing.assert_allclose(kt0[:3].sum() - kt1[:3].sum(), 8 * G / (2 - nu) * a_c,
                               rtol=2e-3)
    np.testing.assert_array_equal(kn0[3:], kn1[3:])
    kn2, _ = interface_stiffness(*args, contact_pairs=np.array([[0, 1]]),
                                 contact_radius=np.array([R]))
    np.testing.assert_allclose(kn2[:3].sum(), MIN_ANNULUS * kn0[:3].sum(), rtol=2e-3)


def test_rotating_contact_shears_the_rigid_grain_layer():
    """With rotations, grains 10^4 times stiffer than quartz and a gap of 0.1 R on the axis
    (a/R 0.5): the lattice's tangential stiffness is within 6 % and its normal within 10 % of
    the thin layer's closed form pi G_c R ln(1 + a^2/2 eps), pi M_c R ln(...) at Omega 16 and
    24 (0.970 / 0.929, 0.958 / 0.931). With the grain-cement bond at the grain's surface the
    cells' own rotation took half the shear of the cement column next to each grain: 0.54
    and 0.59 tangential."""
    from md.contact import GrainMaterial

    rigid = GrainMaterial(QUARTZ.shear_modulus * 1e4, QUARTZ.poisson_ratio, QUARTZ.density)
    layer = theory_contact_stiffness(0.5, thickness_ratio=0.05, limit="rigid_grains")
    for omega in (16, 24):
        k = lattice_contact_stiffness(0.5, omega, thickness_ratio=0.05, material=rigid,
                                      rotations=True)
        assert abs(k.tangential / layer.tangential - 1) < 0.06
        assert abs(k.normal / layer.normal - 1) < 0.10


def test_rotating_contact_converges_to_the_integral_equation():
    """With rotations the patch rule converges as without (first order, successive changes
    shrink) and is within 10 % (normal) and 25 % (tangential) of the integral equation at
    Omega 32 (0.942, 0.773; without rotations 0.937, 0.793)."""
    theory = theory_contact_stiffness(0.5)
    r = np.array([[k.normal / theory.normal, k.tangential / theory.tangential]
                  for k in (lattice_contact_stiffness(0.5, om, interface="patch",
                                                      rotations=True) for om in (8, 16, 32))])
    steps = np.abs(np.diff(r, axis=0))
    assert np.all(steps[1] < 0.6 * steps[0])
    assert abs(r[-1, 0] - 1) < 0.10 and abs(r[-1, 1] - 1) < 0.25


def test_rigid_motion_of_the_rotating_contact_costs_nothing():
    """u = omega x x, theta = omega on every particle: zero force and moment (the bonds'
    contact points move with the bodies, whichever point on the line of centres)."""
    system = contact_system(0.5, 12, rotations=True)
    omega = np.array([0.3, -0.5, 0.8]) * 1e-6
    u = np.zeros((system.n_particles, 6))
    u[:, :3] = np.cross(omega, system.positions)
    u[:, 3:] = omega
    scale = np.max(np.abs(system.forces(np.pad(u[:, :3], ((0, 0), (0, 3))))))
    assert np.max(np.abs(system.forces(u))) <= 1e-9 * scale


def test_grain_cement_bond_carries_the_column_shear():
    """One cell at height h above the surface of a held grain, the cement above it in the
    simple shear u_x = gamma (z - R) with the cell at the macroscopic rotation theta_y =
    gamma/2: the bond's force is k_t gamma h, the continuum's shear of the cement column from
    the grain's surface to the cell centre (with the bond at the grain's surface the cell's
    rotation took back h gamma/2 of it), no moment on the cell, and on the grain that force
    at the arm R + h."""
    from md.acoustic import AcousticSystem, grain_cement_arms

    Rg, h, kt, gamma = 1e-4, 3e-6, 2.0e5, 1e-3
    x = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, Rg + h]])
    nrm = np.array([[0.0, 0.0, 1.0]])
    arm_g, arm_c = grain_cement_arms(x[1:] - x[:1], nrm)
    assert arm_g[0] == pytest.approx(Rg + h) and arm_c[0] == 0.0
    one, zero = np.ones(1), np.zeros(1)
    system = AcousticSystem(x, np.ones(2), 1, Box(1.0, 1.0, -1.0, 1.0), np.zeros(1, np.int32),
                            np.ones(1, np.int32), nrm, 3.0 * kt * one, kt * one, zero, zero,
                            np.zeros((1, 9), np.int32), np.zeros(9), np.zeros(9), 1.0,
                            arm_i=arm_g, arm_j=arm_c, lattice_arm=np.zeros(9),
                            inertia=np.ones(2))
    u = np.zeros((2, 6))
    u[1, 0] = gamma * h
    u[1, 4] = 0.5 * gamma
    f = system.forces(u)
    assert f[0, 0] == pytest.approx(kt * gamma * h, rel=1e-12)
    assert f[1, 0] == pytest.approx(-kt * gamma * h, rel=1e-12)
    assert np.all(f[1, 3:] == 0.0)
    assert f[0, 4] == pytest.approx((Rg + h) * kt * gamma * h, rel=1e-12)


def test_pair_index_matches_a_brute_force_search():
    """md.interface.pair_index: the row of each unordered pair in the table, -1 where absent,
    the first of repeated rows, against a loop over the table."""
    from md.interface import pair_index

    rng = np.random.default_rng(3)
    n = 12
    table = rng.integers(0, n, size=(40, 2))
    query = np.concatenate([rng.integers(0, n, size=(60, 2)), table[::-1][:10, ::-1]])
    got = pair_index(table, query, n)
    for q, g in zip(query, got):
        rows = [k for k, t in enumerate(table) if sorted(t) == sorted(q)]
        assert g == (rows[0] if rows else -1)
    assert pair_index(table[:0], query, n).tolist() == [-1] * len(query)
    assert pair_index(table, [[-1, 3]], n).tolist() == [-1]
