"""Process-based reconstruction (md.reconstruct): the geometry of overlapping grains against
closed forms, compaction of a regular packing against its closed-form porosity, the flattened
contact's stiffness, and cement carried with the grains."""

import dataclasses

import numpy as np
import pytest
from scipy.optimize import brentq

import md
from md.reconstruct import (attach_cement, carried_cells, contact_circle_radius,
                            flattened_contact_radius, lens_volume, reconstruct,
                            union_porosity, union_solid_volume)

R = 1e-4


def cap(r, h):
    """Spherical cap of height h (Archimedes): pi h^2 (3r - h) / 3."""
    return np.pi * h * h * (3 * r - h) / 3


def lens_by_caps(r1, r2, d):
    """The lens as two caps cut by the plane of the intersection circle (independent of
    MathWorld's eq. 16)."""
    x = (d * d + r1 * r1 - r2 * r2) / (2 * d)
    return cap(r1, r1 - x) + cap(r2, r2 - (d - x))


def big_box():
    return md.Box(5e-3, 5e-3, 0.0, 5e-3)


@pytest.mark.parametrize("r2, d", [(R, 1.9 * R), (0.8 * R, 1.5 * R), (0.5 * R, 1.2 * R)])
def test_lens_volume_is_two_caps(r2, d):
    assert lens_volume(R, r2, d) == pytest.approx(lens_by_caps(R, r2, d), rel=1e-12)


def test_lens_volume_limits():
    assert lens_volume(R, R, 2.5 * R) == 0.0
    assert lens_volume(R, 0.3 * R, 0.5 * R) == pytest.approx(4 / 3 * np.pi * (0.3 * R) ** 3)


def test_contact_circle_radius_of_truncated_spheres():
    # Equal spheres: Pythagoras, a^2 = R^2 - (d/2)^2.
    d = 1.6 * R
    assert contact_circle_radius(R, R, d) == pytest.approx(np.sqrt(R**2 - (d / 2) ** 2),
                                                           rel=1e-12)
    # Unequal, small overlap: a^2 -> 2 R_f xi (twice the Hertz contact area).
    xi = 1e-6 * R
    r2 = 0.7 * R
    a = contact_circle_radius(R, r2, R + r2 - xi)
    assert a**2 == pytest.approx(2 * R * r2 / (R + r2) * xi, rel=1e-5)
    assert contact_circle_radius(R, R, 2.1 * R) == 0.0


def test_flattened_contact_radius_limits():
    rf = R / 2
    # No dissolution: Hertz's a = sqrt(R_f xi).
    assert flattened_contact_radius(R, R, 0.0, 2e-7) == pytest.approx(np.sqrt(rf * 2e-7))
    # No elastic part: the flat circle.
    xp = 0.2 * R
    assert flattened_contact_radius(R, R, xp, 0.0) == pytest.approx(
        np.sqrt(R**2 - ((2 * R - xp) / 2) ** 2), rel=1e-12)
    with pytest.raises(ValueError, match="overlap_dissolved"):
        flattened_contact_radius(R, R, -1e-9, 0.0)
    with pytest.raises(ValueError, match="overlap_elastic"):
        flattened_contact_radius(R, R, 0.0, -1e-9)


def test_union_of_two_and_three_overlapping_spheres():
    box = big_box()
    c = np.array([2e-3, 2e-3, 2e-3])
    # Two: sum of the spheres minus the lens; a plane through both centres halves it.
    x = np.stack([c, c + [0.0, 0.0, 1.5 * R]])
    r = np.array([R, 0.9 * R])
    two = 4 / 3 * np.pi * (R**3 + (0.9 * R) ** 3) - lens_by_caps(R, 0.9 * R, 1.5 * R)
    assert union_solid_volume(x, r, box, 0.0, 5e-3) == pytest.approx(two, rel=1e-12)
    x_flat = np.stack([c, c + [1.5 * R, 0.0, 0.0]])
    assert union_solid_volume(x_flat, r, box, 0.0, c[2]) == pytest.approx(two / 2, rel=1e-9)
    # Three equal collinear spheres, spacing d < R: the outer two overlap too, and their
    # lens lies inside the middle sphere, so the union is 3V - 2 lens(d) exactly.
    d = 0.9 * R
    x3 = np.stack([c, c + [0, 0, d], c + [0, 0, 2 * d]])
    three = 3 * 4 / 3 * np.pi * R**3 - 2 * lens_by_caps(R, R, d)
    got = union_solid_volume(x3, np.full(3, R), box, 0.0, 5e-3, samples=24)
    assert got == pytest.approx(three, rel=2e-3)


def sc_pack(layers=6, n=3, lam=0.0):
    """A simple cubic packing of touching spheres (spacing 2R), n x n per layer, periodic in
    x and y; the core window from the second layer's centre to the second-last's."""
    i, j, k = np.meshgrid(np.arange(n), np.arange(n), np.arange(layers), indexing="ij")
    x = np.stack([(i.ravel() + 0.5) * 2 * R, (j.ravel() + 0.5) * 2 * R,
                  R + k.ravel() * 2 * R * (1 - lam)], axis=1)
    z = np.zeros_like(x)
    box = md.Box(2 * R * n, 2 * R * n, 0.0, 2 * R * layers)
    window = [R + 2 * R * (1 - lam), R + (layers - 2) * 2 * R * (1 - lam)]
    return md.Pack(x, z, z.copy(), np.full(x.shape[0], R), box, md.QUARTZ,
                   np.zeros((0, 2), np.int32), np.zeros((0, 3)),
                   metadata={"core_window_m": window})


def sc_porosity(lam):
    """Closed form: a cell 2R x 2R x 2R(1 - lam) holds one sphere less one lens."""
    h = 2 * R * (1 - lam)
    return 1 - (4 / 3 * np.pi * R**3 - lens_by_caps(R, R, h)) / (4 * R * R * h)


def test_porosity_of_a_vertically_compacted_cubic_packing():
    assert md.observe.porosity(sc_pack()) == pytest.approx(1 - np.pi / 6, abs=1e-12)
    for lam in (0.05, 0.2, 0.35):
        assert union_porosity(sc_pack(lam=lam)) == pytest.approx(sc_porosity(lam), abs=1e-9)
        assert md.observe.porosity(sc_pack(lam=lam)) == pytest.approx(sc_porosity(lam),
                                                                       abs=1e-9)


def test_reconstruct_reaches_the_closed_form_compaction():
    target = 0.30
    lam = brentq(lambda l: sc_porosity(l) - target, 0.0, 0.5)
    out = reconstruct(sc_pack(), target)
    assert out.metadata["compaction_factor"] == pytest.approx(lam, abs=2e-4)
    assert md.observe.porosity(out) == pytest.approx(target, abs=1e-4)
    # Every vertical pair overlaps by 2R lam, all of it dissolved (no elastic overlap before).
    assert out.overlap_dissolved.size == 9 * 5
    np.testing.assert_allclose(out.overlap_dissolved, 2 * R * out.metadata["compaction_factor"],
                               rtol=1e-9)
    # A pack already below the target is left as it is.
    same = reconstruct(sc_pack(), 0.6)
    assert same.metadata["compaction_factor"] == 0.0
    assert not same.metadata["reconstruct_reached"]
    with pytest.raises(ValueError, match="intergranular_volume"):
        reconstruct(sc_pack(), 1.2)
    with pytest.raises(ValueError, match="tolerance"):
        reconstruct(sc_pack(), 0.3, tolerance=0.5)


def test_reconstructed_pack_saves_and_loads(tmp_path):
    out = reconstruct(sc_pack(), 0.35)
    back = md.load_pack(md.save_pack(out, tmp_path / "p.nc"))
    np.testing.assert_array_equal(back.overlap_dissolved, out.overlap_dissolved)
    np.testing.assert_array_equal(back.pairs, out.pairs)
    assert md.load_pack(md.save_pack(sc_pack(), tmp_path / "q.nc")).overlap_dissolved is None
    with pytest.raises(ValueError, match="overlap_dissolved"):
        dataclasses.replace(out, overlap_dissolved=np.zeros(3))


def test_flattened_contact_in_the_linearised_stiffness():
    """_contact_bonds_grains: normal stiffness 2 E_f a with Digby's a^2 = b^2 + R_f xi_e,
    b the flat of the dissolved overlap (Pythagoras), and 8 G_f a tangentially."""
    from md.acoustic import _contact_bonds_grains

    xi_p, xi_e = 0.1 * R, 1e-4 * R
    c = np.array([1e-3, 1e-3, 1e-3])
    x = np.stack([c, c + [0, 0, 2 * R - xi_p - xi_e]])
    z = np.zeros_like(x)
    pack = md.Pack(x, z, z.copy(), np.full(2, R), md.Box(2e-3, 2e-3, 0, 2e-3), md.QUARTZ,
                   np.array([[0, 1]], np.int32), np.zeros((1, 3)),
                   overlap_dissolved=np.array([xi_p]))
    b2 = R**2 - ((2 * R - xi_p) / 2) ** 2
    a = np.sqrt(b2 + R / 2 * xi_e)
    out = _contact_bonds_grains(pack, np.ones(2), 0.0)
    assert out[3][0] == pytest.approx(2 * md.QUARTZ.E_f * a, rel=1e-9)
    assert out[4][0] == pytest.approx(8 * md.QUARTZ.G_f * a, rel=1e-9)
    hertz = _contact_bonds_grains(dataclasses.replace(pack, overlap_dissolved=None),
                                  np.ones(2), 0.0)
    assert hertz[3][0] == pytest.approx(2 * md.QUARTZ.E_f * np.sqrt(R / 2 * (xi_p + xi_e)))


def test_cement_carried_with_its_grain():
    """A cell attached to a grain lands one cell over when the grain moves one cell width."""
    x = np.array([[2.5e-4, 2.5e-4, 3e-4]])
    z = np.zeros_like(x)
    pack = md.Pack(x, z, z.copy(), np.array([R]), md.Box(6e-4, 6e-4, 0, 6e-4), md.QUARTZ,
                   np.zeros((0, 2), np.int32), np.zeros((0, 3)))
    lat = md.cement_lattice(pack, 4.0)
    cells = lat.distance < 0.3 * lat.cell_width          # a shell around the grain
    grain, offset = attach_cement(pack, lat, cells)
    assert np.all(grain == 0)
    assert np.array_equal(carried_cells(pack, lat, grain, offset), cells)
    moved = dataclasses.replace(pack, positions=x + [lat.cell_width, 0, 0])
    lat2 = md.cement_lattice(moved, 4.0)
    got = lat2.centres()[carried_cells(moved, lat2, grain, offset)]
    want = lat.centres()[cells] + [lat.cell_width, 0, 0]
    want[:, 0] %= 6e-4
    key = lambda p: set(map(tuple, np.round(p / lat.cell_width, 3)))   # noqa: E731
    assert key(got) == key(want)


def test_grown_cement_keeps_the_carried_cells(compacted_pack):
    from md.along_depth import cement_cells

    lat = md.cement_lattice(compacted_pack, 2.0)
    first, _ = cement_cells(compacted_pack, lat, 0.05, "coating")
    grown, _ = cement_cells(compacted_pack, lat, 0.12, "pore_body", carried=first)
    assert np.all(grown[first]) and grown.sum() > first.sum()
    lo, hi = md.observe.core_window(compacted_pack)
    zc = lat.centres()[:, 2]
    inside = (zc >= lo) & (zc < hi)
    volume = compacted_pack.box.lx * compacted_pack.box.ly * (hi - lo)
    assert np.count_nonzero(grown & inside) * lat.cell_width**3 / volume == \
        pytest.approx(0.12, abs=lat.cell_width**3 / volume)
    full, _ = cement_cells(compacted_pack, lat, 0.1, "coating", carried=first, fill=True)
    assert full.all()


def test_union_porosity_of_a_random_overlapping_pack_against_monte_carlo():
    """Thirty grains overlapping by up to half a radius, many three at a time (periodic in x
    and y, cut by the window's planes): the union porosity against a Monte Carlo count of
    200 000 random points, within four standard errors."""
    rng = np.random.default_rng(7)
    box = md.Box(8 * R, 8 * R, 0.0, 8 * R)
    x = rng.uniform([0, 0, 1 * R], [8 * R, 8 * R, 7 * R], size=(30, 3))
    r = rng.uniform(0.9 * R, 1.1 * R, 30)
    lo, hi = 2 * R, 6 * R
    got = 1 - union_solid_volume(x, r, box, lo, hi) / (64 * R * R * (hi - lo))
    n = 200_000
    pts = rng.uniform([0, 0, lo], [8 * R, 8 * R, hi], size=(n, 3))
    covered = np.zeros(n, bool)
    for xg, rg in zip(x, r):
        d = pts - xg
        d[:, :2] -= 8 * R * np.round(d[:, :2] / (8 * R))
        covered |= np.einsum("ij,ij->i", d, d) < rg * rg
    ref = 1 - covered.mean()
    assert abs(got - ref) < 4 * np.sqrt(ref * (1 - ref) / n)


def test_uplift_keeps_the_largest_stress_porosity(tmp_path):
    """carry_down: a depth uplifted from 20 to 10 MPa keeps burial's intergranular volume under
    reconstruction (no porosity regained), while the Hertzian pack regains some as it
    unloads; the unloaded stress is the present one."""
    from md.along_depth import carry_down

    kw = dict(present_stress=[20.0, 10.0], size=(3.0, 3.0, 7.0), resolution=1.0,
              workdir=tmp_path)
    rec = carry_down([20.0, 20.0], [0.0, 0.0], intergranular_volume=[0.28, 0.28], **kw)
    np.testing.assert_allclose(rec.porosity_pack, 0.28, atol=2e-4)
    assert rec.stress_present.values[1] <= 10e6 < rec.stress_present.values[0]
    assert rec.compaction_factor.values[1] > rec.compaction_factor.values[0] > 0
    hertz = carry_down([20.0, 20.0], [0.0, 0.0], compaction="hertz", **kw)
    assert hertz.porosity_pack.values[1] > hertz.porosity_pack.values[0]
    with pytest.raises(ValueError, match="intergranular_volume"):
        carry_down([20.0], [0.0], compaction="reconstruct", workdir=tmp_path)
    with pytest.raises(ValueError, match="compaction must be one of"):
        carry_down([20.0], [0.0], compaction="squash", workdir=tmp_path)
    with pytest.raises(ValueError, match="cement_history must be one of"):
        carry_down([20.0], [0.0], cement_history="old", workdir=tmp_path)


def test_thin_coating_is_a_film_and_thick_cement_is_carried(tmp_path):
    """carry_down with grown cement: a coating that is a film (md.growth.coating_is_film) is
    laid as fill fractions holding the
    depth's cement exactly (cement_window = the fraction, to rounding); thicker cement is
    whole cells carried down (its window's cement within a cell of the fraction); the same
    moduli as a film laid afresh (cement_history='fresh') where the coating is a film."""
    from md.along_depth import carry_down
    from md.growth import coating_is_film

    kw = dict(size=(3.0, 3.0, 6.0), resolution=3.0, workdir=tmp_path, schemes=("coating",),
              intergranular_volume=[0.33, 0.30])
    grown = carry_down([15.0, 40.0], [0.004, 0.25], **kw)
    fresh = carry_down([15.0, 40.0], [0.004, 0.25], cement_history="fresh", **kw)
    assert grown.cement_window.values[0, 0] == pytest.approx(0.004, rel=1e-12)
    cell = grown.cement_window.values[1, 0] - 0.25
    assert abs(cell) < 0.01 and cell != 0.0              # whole cells, to one cell
    assert grown.p_modulus.values[0, 0] == fresh.p_modulus.values[0, 0]
    import glob

    from md.state import load_pack

    packs = [load_pack(f) for f in sorted(glob.glob(str(tmp_path / "*" / "pack" /
                                                          "reconstruct_*.nc")))]
    films = [coating_is_film(p, 0.004) for p in packs] + [coating_is_film(p, 0.25)
                                                           for p in packs]
    assert films[:len(packs)] == [True] * len(packs) and not any(films[len(packs):])


def test_fully_cemented_sample_below_the_voigt_bound(tmp_path):
    """A sample whose pores burial fills (porosity 0, grains and cement of the same quartz
    family) is a solid of grain and cement: for any microstructure its strain energy under a
    uniform strain is at most the Voigt average of its phases', so C33 <= sum f_i M_i and
    C44 <= sum f_i G_i (Hill 1963). The facet punch around a flattened contact is the annulus
    outside the contact (md.interface.interface_stiffness, contact_radius); counting the
    contact's punch and the facet's both (the former rule) gave C33 above the bound."""
    from md.along_depth import carry_down
    from rockcem._md_backend import _materials
    from rockcem.materials import mineral

    g, c = mineral("quartz"), mineral("quartz_cement")
    grain, cement = _materials(g, c)
    ds = carry_down([60.0], [0.28], intergranular_volume=[0.28], size=(3.0, 3.0, 8.0),
                    resolution=3.0, material=grain, cement=cement, workdir=tmp_path,
                    schemes=("coating",)).isel(point=0, scheme=0)
    assert float(ds.porosity) < 0.005
    phi_pack, phi = float(ds.porosity_pack), float(ds.porosity)
    beta = (phi_pack - phi) / (1.0 - phi)           # cement per solid
    M_voigt = ((1 - beta) * (g.K + 4 / 3 * g.G) + beta * (c.K + 4 / 3 * c.G)) * 1e9
    G_voigt = ((1 - beta) * g.G + beta * c.G) * 1e9
    assert float(ds.p_modulus) < M_voigt and float(ds.c11) < M_voigt
    assert float(ds.shear_modulus) < G_voigt and float(ds.c66) < G_voigt
