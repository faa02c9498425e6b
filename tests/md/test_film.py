"""Cement films thinner than a cell: partly filled cells (md.growth.cement_fill, film_fill),
their acoustic system (md.acoustic_system with fill fractions) and the film bridges
(md.interface.film_bridges)."""

import numpy as np
import pytest
from scipy.integrate import quad

import md
from md.growth import (FILM_MAX_SATURATION, FILM_MAX_THICKNESS, cement_fill, coating_is_film,
                       film_fill)
from md.interface import film_bridges, film_thickness, nearest_grain
from md.observe import core_window, porosity
from md.static import static_moduli


@pytest.fixture(scope="module")
def lattice6(compacted_pack):
    return md.cement_lattice(compacted_pack, 4.0)


def _system(pack, lat, cells, rotations=True):
    return md.acoustic_system(pack, lat, cells, md.HARD_CEMENT, interface="facet",
                              rotations=rotations, slab_thickness=2 * pack.radii.max())


def test_film_fill_on_a_plane_is_the_layer_closed_form():
    # cells stacked on a flat grain surface: m per layer, centres at (k + 1/2) c_w, so layer k
    # spans [k, k + 1) cells of distance; a film of V cells is V/m cells thick
    cw, m, layers = 2e-6, 50, 6
    k = np.repeat(np.arange(layers), m)
    for volume in (3.0, 37.5, 50.0, 123.4):
        fill = film_fill((k + 0.5) * cw, cw, volume)
        np.testing.assert_allclose(fill, np.clip(volume / m - k, 0.0, 1.0), atol=1e-12)


@pytest.mark.parametrize("scheme", ["coating", "pendular", "contact", "pore_body"])
@pytest.mark.parametrize("fraction", [0.004, 0.03, 0.11])
def test_cement_fill_holds_the_requested_volume(compacted_pack, lattice6, scheme, fraction):
    fill, overflow = cement_fill(compacted_pack, lattice6, fraction, scheme, seed=2)
    lo, hi = core_window(compacted_pack)
    z = lattice6.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    box = compacted_pack.box
    volume = fraction * box.lx * box.ly * (hi - lo)
    held = fill[inside].sum() * lattice6.cell_width**3
    assert not overflow
    assert fill.min() >= 0.0 and fill.max() <= 1.0
    # far better than a cell: to 1e-9 of one cell's volume
    assert abs(held - volume) < 1e-9 * lattice6.cell_width**3
    if scheme == "coating":         # nested in distance: a cell nearer the grains is no emptier
        start = np.maximum(lattice6.distance - 0.5 * lattice6.cell_width, 0)
        full = fill == 1.0
        if full.any():
            assert start[full].max() <= start[fill < 1.0].min()
        if coating_is_film(compacted_pack, fraction):      # a film covers every grain
            assert np.all(fill[start == 0] > 0)


def test_cement_fill_bad_input(compacted_pack, lattice6):
    with pytest.raises(ValueError, match="fraction"):
        cement_fill(compacted_pack, lattice6, 1.5, "coating")
    with pytest.raises(ValueError, match="scheme"):
        cement_fill(compacted_pack, lattice6, 0.1, "coat")


def test_full_fills_equal_the_boolean_cells(compacted_pack, lattice6):
    cells = md.grow_cement(lattice6, 0.3, "coating")
    a = static_moduli(_system(compacted_pack, lattice6, cells), ("p", "s"))
    b = static_moduli(_system(compacted_pack, lattice6, cells.astype(float)), ("p", "s"))
    for w in ("p", "s"):
        assert a[w].modulus == b[w].modulus


@pytest.mark.parametrize("bad", [np.nan, 1.5, -0.1])
def test_fill_fractions_are_checked(compacted_pack, lattice6, bad):
    fill = np.zeros(lattice6.index.size)
    fill[:3] = [0.5, bad, 1.0]
    with pytest.raises(ValueError, match="cemented"):
        _system(compacted_pack, lattice6, fill)
    with pytest.raises(ValueError, match="cemented"):
        _system(compacted_pack, lattice6, np.zeros(lattice6.index.size - 1))
    with pytest.raises(ValueError, match="cemented"):
        _system(compacted_pack, lattice6, np.array(["a"] * lattice6.index.size))


@pytest.mark.parametrize("rotations", [True, False])
def test_film_system_keeps_the_mass(compacted_pack, lattice6, rotations):
    fill, _ = cement_fill(compacted_pack, lattice6, 0.05, "coating")
    assert 0 < fill.max() < 1
    s = _system(compacted_pack, lattice6, fill, rotations)
    grains = md.QUARTZ.density * 4 / 3 * np.pi * np.sum(compacted_pack.radii**3)
    cement = md.HARD_CEMENT.density * lattice6.cell_width**3 * fill.sum()
    np.testing.assert_allclose(s.masses.sum(), grains + cement, rtol=1e-12)
    assert s.metadata["n_film_bridges"] > 0


def test_film_thickness_of_a_shell():
    # a uniform shell of thickness t around one grain, as cell volumes owned by it
    R, t = 1e-4, 2e-6
    shell = 4 / 3 * np.pi * ((R + t) ** 3 - R**3)
    got = film_thickness(np.zeros(4, int), np.full(4, shell / 4), np.array([R]))
    np.testing.assert_allclose(got, t * (1 + t / R + t**2 / (3 * R**2)), rtol=1e-12)


def test_nearest_grain_is_the_nearest_surface():
    box = md.Box(1e-3, 1e-3, 0.0, 1e-3)
    x = np.array([[2e-4, 5e-4, 5e-4], [6e-4, 5e-4, 5e-4]])
    r = np.array([1.5e-4, 5e-5])
    pts = np.array([[3.9e-4, 5e-4, 5e-4], [5.0e-4, 5e-4, 5e-4], [9.5e-4, 5e-4, 5e-4]])
    # surfaces at 3.5e-4 and 5.5e-4 along x; the last point is nearer grain 0 across the
    # periodic boundary (2e-4 + 1e-3 - 9.5e-4 - 1.5e-4 = 1e-4 < 9.5e-4 - 6.5e-4 = 3e-4)
    assert nearest_grain(pts, x, r, box).tolist() == [0, 1, 0]


def _two_grains(gap, R=1e-4):
    box = md.Box(1e-2, 1e-2, 0.0, 1e-2)
    x = np.array([[5e-3, 5e-3, 5e-3], [5e-3, 5e-3, 5e-3 + 2 * R + gap]])
    return x, np.array([R, R]), box


def test_bridge_of_rigid_cement_is_the_welded_contact():
    # two touching grains, films t each: the bridge is the disc where the gap
    # 2(R - sqrt(R^2 - rho^2)) < 2t; with rigid cement, the welded contact of that radius
    # (two rigid punches in series, Johnson 1985): a E/(1 - nu^2) and 4 G a/(2 - nu)
    R, t = 1e-4, 2e-6
    x, r, box = _two_grains(0.0, R)
    rigid = md.CementMaterial(3000.0e4, 1800.0e4, 2650.0)
    i, j, n, kn, kt, *_ = film_bridges(x, r, box, np.full(2, t), md.QUARTZ, rigid)
    a = np.sqrt(R**2 - (R - t) ** 2)
    g = md.QUARTZ
    assert i.tolist() == [0] and j.tolist() == [1]
    np.testing.assert_allclose(n[0], [0, 0, 1])
    np.testing.assert_allclose(kn, a * g.young_modulus / (1 - g.poisson_ratio**2), rtol=2e-3)
    np.testing.assert_allclose(kt, 4 * g.shear_modulus * a / (2 - g.poisson_ratio), rtol=2e-3)


def test_bridge_across_a_gap_of_rigid_grains_is_the_layer_integral():
    # rigid grains: the cement layer alone, k_n = 2 pi M_c int_0^a rho drho / gap(rho)
    R, t, h0 = 1e-4, 3e-6, 1e-6
    x, r, box = _two_grains(h0, R)
    rigid = md.GrainMaterial(44.0e15, 0.08, 2650.0)
    c = md.HARD_CEMENT
    _, _, _, kn, kt, *_ = film_bridges(x, r, box, np.full(2, t), rigid, c)
    a = np.sqrt(R**2 - (R - (2 * t - h0) / 2) ** 2)
    layer = quad(lambda p: p / (h0 + 2 * (R - np.sqrt(R * R - p * p))), 0, a,
                 epsabs=0, epsrel=1e-12)[0]
    np.testing.assert_allclose(kn, 2 * np.pi * c.p_modulus * layer, rtol=1e-4)
    np.testing.assert_allclose(kt, 2 * np.pi * c.shear_modulus * layer, rtol=1e-4)
    # no bridge once the films do not reach across
    assert film_bridges(x, r, box, np.full(2, 0.4 * h0), rigid, c)[0].size == 0


def test_thin_coating_converges_in_omega(compacted_pack):
    # S_c 0.1 of the pore space, a film 0.02 R thick: at most 2 % per resolution step
    frac = 0.1 * porosity(compacted_pack)
    values = []
    for omega in (4.0, 6.0, 8.0):
        lat = md.cement_lattice(compacted_pack, omega)
        fill, _ = cement_fill(compacted_pack, lat, frac, "coating")
        r = static_moduli(_system(compacted_pack, lat, fill), ("p", "s"))
        values.append([r["p"].modulus, r["s"].modulus])
    change = np.abs(np.diff(values, axis=0) / np.array(values[:-1]))
    assert np.all(change < 0.02), change


def test_coating_is_a_film_up_to_its_thickness_and_saturation_limits(compacted_pack):
    # the representation follows the film's thickness (volume over the grains' surface in the
    # window) and its saturation (over the window's porosity), never the resolution: a film (no
    # full cell) below both FILM_MAX_THICKNESS and FILM_MAX_SATURATION, else cells
    pack = compacted_pack
    lo, hi = core_window(pack)
    inside = (pack.positions[:, 2] >= lo) & (pack.positions[:, 2] < hi)
    surface = 4 * np.pi * np.sum(pack.radii[inside] ** 2)
    by_thickness = FILM_MAX_THICKNESS * surface * pack.radii.mean() / (
        pack.box.lx * pack.box.ly * (hi - lo))
    by_saturation = FILM_MAX_SATURATION * porosity(pack)
    limit = min(by_thickness, by_saturation)
    for omega in (3.0, 5.0):
        lat = md.cement_lattice(pack, omega)
        thin, _ = cement_fill(pack, lat, 0.9 * limit, "coating")
        thick, _ = cement_fill(pack, lat, 1.1 * limit, "coating")
        assert thin.max() < 1.0 and np.count_nonzero(thin) > 0
        assert np.count_nonzero(thick == 1.0) > 0.9 * np.count_nonzero(thick)
    assert coating_is_film(pack, 0.99 * limit) and not coating_is_film(pack, 1.01 * limit)
