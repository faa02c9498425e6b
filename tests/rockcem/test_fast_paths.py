"""The fast paths of issue 32 (per-point speed) give the values of the equations.

The granular functions now check their arguments once, evaluate in cache-sized blocks
(rockcem.validation.blockwise) with rearranged arithmetic (Hertz-Mindlin's shear modulus as a
multiple of the bulk modulus, CCT's quadratics in Horner form, the radius of eq. 16 as a fourth
root, a denominator that is one number inverted once); the models and the bounds evaluate in
blocks of points. Here every such path is compared, on random valid inputs larger than two
blocks, with the equations written out directly (to 1e-14), or, where the arithmetic did not
change, with the same function on pieces small enough to take no block path (exactly).
"""

import numpy as np
import pytest

from rockcem import granular, inclusions, models
from rockcem.bounds import hashin_shtrikman, hill
from rockcem.materials import Fluid, mineral
from rockcem.validation import BLOCK, blockwise

N = 2 * BLOCK + 1234          # more than two blocks: the block path
RTOL = 1e-14


def close(actual, expected, rtol=RTOL):
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape
    err = np.abs(actual - expected) / np.abs(expected)
    assert np.max(err) <= rtol, f"max relative difference {np.max(err):.3g}"


@pytest.fixture(scope="module")
def rock():
    """Random valid grain and cement moduli, critical porosity, coordination number, pressure,
    slip factor and pre-stress, one per point."""
    rng = np.random.default_rng(32)
    return {
        "K0": rng.uniform(20.0, 80.0, N), "G0": rng.uniform(10.0, 60.0, N),
        "Kc": rng.uniform(20.0, 80.0, N), "Gc": rng.uniform(10.0, 60.0, N),
        "phic": rng.uniform(0.3, 0.45, N), "n": rng.uniform(5.0, 12.0, N),
        "p": rng.uniform(0.5, 60.0, N), "f": rng.uniform(0.0, 1.0, N),
        "delta": rng.uniform(0.0, 50.0, N), "u": rng.uniform(0.0, 1.0, N),
    }


def nu(K, G):
    return (3 * K - 2 * G) / (2 * (3 * K + G))


def hm_eq(K0, G0, phic, n, p_mpa, f, delta):
    """Eqs. D.1-D.2 of Carcione et al. (2022) with slip factor and pre-stress, as written."""
    p = (p_mpa + delta) / 1000.0
    v = nu(K0, G0)
    K = np.cbrt(n**2 * (1 - phic) ** 2 * G0**2 * p / (18 * np.pi**2 * (1 - v) ** 2))
    G = (2 + 3 * f - v * (1 + 3 * f)) / (5 * (2 - v)) \
        * np.cbrt(3 * n**2 * (1 - phic) ** 2 * G0**2 * p / (2 * np.pi**2 * (1 - v) ** 2))
    return K, G


def hs_interp_eq(Ka, Ga, Kb, Gb, x, Kr, Gr):
    """Modified HS interpolation (Mavko et al. 2009, Sect. 7.9), as written."""
    z = Gr / 6 * (9 * Kr + 8 * Gr) / (Kr + 2 * Gr)
    K = 1 / (x / (Ka + 4 / 3 * Gr) + (1 - x) / (Kb + 4 / 3 * Gr)) - 4 / 3 * Gr
    G = 1 / (x / (Ga + z) + (1 - x) / (Gb + z)) - z
    return K, G


def cct_eq(K0, G0, Kc, Gc, phi, phic, n, scheme):
    """Eq. 15 of Carcione et al. (2022) with the handbook's fits, eq. 16 or 18 for the radius,
    and Lambda_n as Dvorkin & Nur print it."""
    v0, vc = nu(K0, G0), nu(Kc, Gc)
    if scheme == 1:
        alpha = 2 * ((phic - phi) / (3 * n * (1 - phic))) ** 0.25
    else:
        alpha = np.sqrt(2 * (phic - phi) / (3 * (1 - phic)))
    Ln = 2 * Gc * (1 - v0) * (1 - vc) / (np.pi * G0 * (1 - 2 * vc))
    Lt = Gc / (np.pi * G0)
    Sn = (-0.024153 * Ln**-1.3646 * alpha**2 + 0.20405 * Ln**-0.89008 * alpha
          + 0.00024649 * Ln**-1.9864)
    St = (-1e-2 * (2.26 * v0**2 + 2.07 * v0 + 2.3) * Lt ** (0.079 * v0**2 + 0.1754 * v0 - 1.342)
          * alpha**2
          + (0.0573 * v0**2 + 0.0937 * v0 + 0.202) * Lt ** (0.0274 * v0**2 + 0.0529 * v0 - 0.8765)
          * alpha
          + 1e-4 * (9.654 * v0**2 + 4.945 * v0 + 3.1)
          * Lt ** (0.01867 * v0**2 + 0.4011 * v0 - 1.8186))
    K = n * (1 - phic) * (Kc + 4 / 3 * Gc) * Sn / 6
    return K, 3 / 5 * K + 3 / 20 * n * (1 - phic) * Gc * St


def test_hertz_mindlin_blocks_equal_the_equations(rock):
    r = rock
    m = granular.hertz_mindlin(r["K0"], r["G0"], r["phic"], r["n"], r["p"], r["f"], r["delta"])
    K, G = hm_eq(r["K0"], r["G0"], r["phic"], r["n"], r["p"], r["f"], r["delta"])
    close(m.K, K)
    close(m.G, G)


@pytest.mark.parametrize("stiff", [False, True])
def test_soft_and_stiff_sand_blocks_equal_the_equations(rock, stiff):
    r = rock
    phi = r["u"] * r["phic"]
    fn = granular.stiff_sand if stiff else granular.soft_sand
    m = fn(r["K0"], r["G0"], phi, r["phic"], r["n"], r["p"], r["f"], r["delta"])
    Khm, Ghm = hm_eq(r["K0"], r["G0"], r["phic"], r["n"], r["p"], r["f"], r["delta"])
    ref = (r["K0"], r["G0"]) if stiff else (Khm, Ghm)
    K, G = hs_interp_eq(Khm, Ghm, r["K0"], r["G0"], phi / r["phic"], *ref)
    close(m.K, K)
    close(m.G, G)


def test_soft_sand_at_zero_pressure_keeps_its_limit():
    """At zero pressure and pre-stress the Hertz-Mindlin end member is 0: the lower bound is 0 at
    any porosity above 0 (the exact limit, through the general harmonic mean), the mineral at 0."""
    phi = np.linspace(0.0, 0.4, N)
    m = granular.soft_sand(36.6, 45.0, phi, 0.4, 8.6, 0.0)
    assert m.K[0] == 36.6 and m.G[0] == 45.0
    assert np.all(m.K[1:] == 0.0) and np.all(m.G[1:] == 0.0)


@pytest.mark.parametrize("scheme", [1, 2])
def test_contact_cement_blocks_equal_the_equations(rock, scheme):
    r = rock
    phi = r["phic"] - 0.04 * r["u"]
    m = granular.contact_cement(r["K0"], r["G0"], r["Kc"], r["Gc"], phi, r["phic"], r["n"],
                                scheme)
    K, G = cct_eq(r["K0"], r["G0"], r["Kc"], r["Gc"], phi, r["phic"], r["n"], scheme)
    close(m.K, K)
    close(m.G, G)
    alpha = granular.cement_radius(phi, r["phic"], r["n"], scheme)
    expected = (2 * ((r["phic"] - phi) / (3 * r["n"] * (1 - r["phic"]))) ** 0.25 if scheme == 1
                else np.sqrt(2 * (r["phic"] - phi) / (3 * (1 - r["phic"]))))
    close(alpha, expected)


@pytest.mark.parametrize("stiff", [False, True])
def test_constant_and_increasing_cement_blocks_equal_the_equations(rock, stiff):
    r = rock
    phib = r["phic"] - 0.04 * r["u"]
    phi = phib * r["u"][::-1]
    fn = granular.increasing_cement if stiff else granular.constant_cement
    # phib one number (the common use: a scalar end member) and phib per point
    for pb, ph in ((0.29, 0.29 * r["u"]), (phib, phi)):
        m = fn(r["K0"], r["G0"], r["Kc"], r["Gc"], ph, r["phic"], r["n"], pb)
        Kb, Gb = cct_eq(r["K0"], r["G0"], r["Kc"], r["Gc"], pb, r["phic"], r["n"], 1)
        ref = (r["K0"], r["G0"]) if stiff else (Kb, Gb)
        K, G = hs_interp_eq(Kb, Gb, r["K0"], r["G0"], ph / pb, *ref)
        close(m.K, K)
        close(m.G, G)


def test_patchy_cement_blocks_equal_its_building_blocks(rock):
    """Steps 1-6 of the docstring with the public building blocks, unblocked (one call per
    slice of at most BLOCK points)."""
    r = rock
    K0, G0, Kc, Gc, phic, n, p = 40.0, 39.0, 35.0, 30.0, 0.36, 9.0, r["p"]
    phip = 0.2 * r["u"]
    phi = (phic - phip) * r["u"][::-1]
    m = granular.patchy_cement(K0, G0, Kc, Gc, phi, phic, n, p, phip, 0.05, 1, 0.0,
                               r["f"], r["delta"])
    end_s = inclusions.self_consistent([K0, Kc], [G0, Gc], [1 - phic, phic])
    for s in (slice(0, BLOCK), slice(BLOCK, 2 * BLOCK), slice(2 * BLOCK, None)):
        cct = granular.contact_cement(K0, G0, Kc, Gc, phic - np.minimum(phip[s], 0.05), phic, n)
        hm = granular.hertz_mindlin(K0, G0, phic, n, p[s], r["f"][s], r["delta"][s])
        frac = phip[s] / phic
        b = hashin_shtrikman(np.stack([cct.K, hm.K], -1), np.stack([cct.G, hm.G], -1),
                             np.stack([frac, 1 - frac], -1)).upper
        x = phi[s] / phic
        h = hill(np.stack(np.broadcast_arrays(end_s.K, b.K), -1),
                 np.stack(np.broadcast_arrays(end_s.G, b.G), -1), np.stack([1 - x, x], -1))
        close(m.K[s], h.K)
        close(m.G[s], h.G)


def test_model4_solves_its_zero_porosity_end_member_once(monkeypatch):
    """Guards the slowdown found in issue 32: critical_porosity broadcast to every point made
    patchy_cement solve the self-consistent end member once per point (2.2 s of 3 s per 10^6
    points). One number in, one solve."""
    calls = []
    solve = inclusions.self_consistent

    def counting(K, G, fractions, *args, **kwargs):
        calls.append(np.shape(fractions))
        return solve(K, G, fractions, *args, **kwargs)

    monkeypatch.setattr(inclusions, "self_consistent", counting)
    phi = np.linspace(0.02, 0.3, 1000)
    models.patchy_cement_model(mineral("quartz"), mineral("quartz_cement"), phi, 0.05 * phi,
                               np.linspace(1, 60, 1000), Fluid(2.25, 1.0, "water"))
    assert calls == [(2,)]


def _water_per_point(size):
    return Fluid(np.linspace(2.2, 2.9, size), np.linspace(1.0, 1.1, size), "brine")


@pytest.mark.parametrize("name", ["hs_gassmann", "generalized_gassmann", "patchy_cement"])
def test_models_by_blocks_equal_the_model_on_pieces(name):
    """The models evaluate blocks of points: the same values, to the last bit, as the model
    on pieces that take no block path; a fluid per point and two leading axes included."""
    q, c = mineral("quartz"), mineral("quartz_cement")
    shape = (2, BLOCK + 617)
    s = np.linspace(0.0, 1.0, 2 * shape[1]).reshape(shape)
    phi, cement = 0.36 - 0.34 * s, 0.2 * s**2
    beta_c = cement / (1 - phi)
    beta = np.stack([1 - beta_c, beta_c], -1)
    fluid = _water_per_point(phi.size)
    fluid = Fluid(fluid.K.reshape(shape), fluid.rho.reshape(shape), "brine")

    def run(sl):
        f = Fluid(fluid.K[sl], fluid.rho[sl], "brine")
        if name == "patchy_cement":
            return models.patchy_cement_model(q, c, phi[sl], cement[sl], 60 * s[sl], f)
        return models.MODELS[name]([q, c], beta[sl], phi[sl], f)

    whole = run(np.s_[:, :])
    for row in range(shape[0]):
        for part in (slice(0, BLOCK), slice(BLOCK, None)):
            piece = run(np.s_[row, part])
            for a, b in zip(whole, piece):
                np.testing.assert_array_equal(a[row, part], b)


def test_bounds_by_blocks_equal_the_bounds_on_pieces():
    rng = np.random.default_rng(7)
    f = rng.uniform(0, 1, (N, 3))
    f[:, 2] = 0.0                          # an absent phase at some points
    f[::3, 2] = rng.uniform(0, 1, len(f[::3]))
    f /= f.sum(-1, keepdims=True)
    K = np.array([40.0, 2.2, 20.0])
    G = np.array([39.0, 0.0, 10.0])
    whole_hs = hashin_shtrikman(K, G, f)
    whole_hill = hill(K, G, f)
    for s in (slice(0, BLOCK), slice(BLOCK, 2 * BLOCK), slice(2 * BLOCK, None)):
        for a, b in zip(whole_hs, hashin_shtrikman(K, G, f[s])):
            np.testing.assert_array_equal(a[s], b)
        for a, b in zip(whole_hill, hill(K, G, f[s])):
            np.testing.assert_array_equal(a[s], b)


def test_blockwise_shapes_and_broadcast_inputs():
    """Results of the inputs' broadcast shape; a broadcast view enters as one number; small
    inputs as they are, writable."""
    a = np.arange(6.0 * BLOCK).reshape(3, 2 * BLOCK)
    b = np.broadcast_to(np.float64(2.0), a.shape)
    seen = []

    def kernel(x, y):
        seen.append(np.ndim(y))
        return x * y, y + 0.0

    out = blockwise(kernel, a, b)
    assert set(seen) == {0}
    np.testing.assert_array_equal(out[0], 2.0 * a)
    assert out[1].shape == a.shape and np.all(out[1] == 2.0)
    small = blockwise(kernel, np.ones(3), 2.0)
    assert small[1].shape == (3,) and small[1].flags.writeable


@pytest.mark.parametrize("fn", [granular.constant_cement, granular.increasing_cement])
def test_bounding_models_keep_the_shape_of_one_element_inputs(fn):
    """The path for one phib (end members one number each) returns the inputs' broadcast shape,
    size-1 axes of the other arguments included, and the values of the general path."""
    phi = np.linspace(0.0, 0.3, 5)
    m = fn([[36.6]], 45.0, 36.6, 45.0, phi, 0.4, 8.6, 0.37)
    assert m.K.shape == m.G.shape == (1, 5)
    general = fn(36.6, 45.0, 36.6, 45.0, phi, 0.4, 8.6, np.full(5, 0.37))
    close(m.K[0], general.K)
    close(m.G[0], general.G)
