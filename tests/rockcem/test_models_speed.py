"""The faster paths of issue 32, item 2 (the four models < 1 s per 10^6 points together) give
the values of the equations.

What changed: the Hashin-Shtrikman bounds of phases whose moduli are the same at every point
(the minerals of Models 1, 3 and 4) with the extremes, shifts and denominators M_i + z as numbers
(points with an absent phase by the general code); the two-phase HS upper bound and Hill
average of the patchy-cement frame without stacking; Gassmann's and the
generalized Gassmann equations, the bulk density and the minerals' HS average inside the
models' blocks without the public checks (checked once per call instead); Model 4's mineral,
cap, Gassmann and density in blocks of points, its cement radius computed once.

Every reference below is written out here from the published equations with plain numpy
(nothing of rockcem but the materials and, for Model 4, the public dry frame), on inputs larger
than two blocks (rockcem.validation.BLOCK) with absent phases scattered over several blocks;
values agree to 1e-14 relative (the references round differently). The new paths of the bounds
do the operations of the general code: those are compared with it to the last bit.
"""

import numpy as np
import pytest
from scipy.optimize import root

from rockcem import granular, inclusions
from rockcem.bounds import (hashin_shtrikman, hashin_shtrikman_average, hashin_shtrikman_upper,
                            hill)
from rockcem.materials import Fluid, fluid, mineral
from rockcem.models import generalized_gassmann_model, hs_gassmann, patchy_cement_model
from rockcem.validation import BLOCK, check_fractions

N = 2 * BLOCK + 4321          # three blocks
RTOL = 1e-14
QUARTZ, CEMENT, ILLITE = mineral("quartz"), mineral("quartz_cement"), mineral("illite")
WATER = fluid("water")


def close(actual, expected, rtol=RTOL):
    actual, expected = np.asarray(actual), np.asarray(expected)
    assert actual.shape == expected.shape
    err = np.abs(actual - expected) / np.abs(expected)
    assert np.max(err) <= rtol, f"max relative difference {np.max(err):.3g}"


def hs_eq(K, G, f):
    """HS bounds of n phases (Berryman's form, Mavko et al. 2009, Sect. 4.1; eqs. C.1-C.2 of
    Carcione et al. 2022 for two phases), the extremes over the phases present: K-, G-, K+,
    G+."""
    present = f > 0

    def zeta(k, g):                    # zero for a phase without shear stiffness
        return np.where(g > 0, g / 6 * (9 * k + 8 * g) / np.where(g > 0, k + 2 * g, 1), 0.0)

    def bound(M, z):                   # a zero modulus present: an infinite sum, the bound -z
        with np.errstate(divide="ignore", invalid="ignore"):
            return 1 / np.sum(np.where(present, f / (M + z[..., None]), 0.0), -1) - z

    out = []
    for pick, fill in ((np.min, np.inf), (np.max, -np.inf)):
        k_e = pick(np.where(present, K, fill), -1)
        g_e = pick(np.where(present, G, fill), -1)
        out += [bound(K, 4 / 3 * g_e), bound(G, zeta(k_e, g_e))]
    return out


def solids_state(n_minerals, seed=32):
    """Porosity 0.36 -> 0.02 and random solid fractions, one mineral absent at every 997th
    point (in every block) and only the first present at every 4999th."""
    rng = np.random.default_rng(seed)
    phi = np.linspace(0.36, 0.02, N)
    beta = rng.uniform(0.05, 1.0, (N, n_minerals))
    beta[::997, -1] = 0.0
    beta[::4999, 1:] = 0.0
    beta /= beta.sum(-1, keepdims=True)
    return phi, beta


def finish_eq(K_dry, G_dry, K_sat, rho):
    """Eqs. 22-25 of Carcione et al. 2022: the velocities, km/s."""
    return np.sqrt((K_sat + 4 / 3 * G_dry) / rho), np.sqrt(G_dry / rho)


def gassmann_eq(K_dry, K_s, K_f, phi):
    """Eqs. 4-6 of Carcione et al. 2022, as printed; at zero porosity its limit, the mineral
    (there the frame is the mineral: 0/0 as printed)."""
    a = 1 - K_dry / K_s
    with np.errstate(invalid="ignore"):
        return np.where(phi > 0, K_dry + a * a / ((a - phi) / K_s + phi / K_f), K_s)


@pytest.mark.parametrize("minerals", [[QUARTZ, CEMENT], [QUARTZ, CEMENT, ILLITE]])
def test_model1_equals_its_equations(minerals):
    """Eqs. C.1-C.3 (HS average), 3 (Krief), 4-6 (Gassmann), 24 (density), 22-25."""
    phi, beta = solids_state(len(minerals))
    K = np.array([m.K for m in minerals])
    G = np.array([m.G for m in minerals])
    rho_s = np.array([m.rho for m in minerals])
    r = hs_gassmann(minerals, beta, phi, WATER)
    K_lo, G_lo, K_hi, G_hi = hs_eq(K, G, beta)
    K_s, G_s = (K_lo + K_hi) / 2, (G_lo + G_hi) / 2
    factor = (1 - phi) ** (3.0 / (1 - phi))
    K_dry, G_dry = K_s * factor, G_s * factor
    K_sat = gassmann_eq(K_dry, K_s, WATER.K, phi)
    rho = (1 - phi) * (beta @ rho_s) + phi * WATER.rho
    for got, want in zip(r, (K_dry, G_dry, K_sat, G_dry, rho, *finish_eq(K_dry, G_dry, K_sat,
                                                                           rho))):
        close(got, want)


@pytest.mark.parametrize("minerals", [[QUARTZ, CEMENT], [QUARTZ, CEMENT, ILLITE]])
def test_model3_equals_its_equations(minerals):
    """Eqs. 13-14 (multi-mineral Krief with the HS average), 10-12 (generalized Gassmann, the
    square of eq. 10 as in rockcem.fluids), mu = sum mu_mi, 24, 22-25; with a fluid modulus per
    point."""
    phi, beta = solids_state(len(minerals), seed=33)
    K = np.array([m.K for m in minerals])
    G = np.array([m.G for m in minerals])
    rho_s = np.array([m.rho for m in minerals])
    brine = Fluid(np.linspace(2.2, 2.9, N), np.linspace(1.0, 1.1, N), "brine")
    r = generalized_gassmann_model(minerals, beta, phi, brine)
    K_lo, G_lo, K_hi, G_hi = hs_eq(K, G, beta)
    K_s, G_s = (K_lo + K_hi) / 2, (G_lo + G_hi) / 2
    factor = ((1 - phi) ** (3.0 / (1 - phi)))[:, None]
    K_mi = (K_s / (beta @ K))[:, None] * beta * K * factor
    G_mi = (G_s / (beta @ G))[:, None] * beta * G * factor
    alpha_i = beta - K_mi / K
    M = 1 / (np.sum((alpha_i - beta * phi[:, None]) / K, -1) + phi / brine.K)
    K_dry, G_dry = K_mi.sum(-1), G_mi.sum(-1)
    K_sat = K_dry + alpha_i.sum(-1) ** 2 * M
    rho = (1 - phi) * (beta @ rho_s) + phi * brine.rho
    for got, want in zip(r, (K_dry, G_dry, K_sat, G_dry, rho, *finish_eq(K_dry, G_dry, K_sat,
                                                                           rho))):
        close(got, want)


@pytest.mark.parametrize("limit", [0.05, 0.36])
def test_model4_equals_its_equations_from_the_dry_frame(limit):
    """From the public dry frame (granular.patchy_cement, with the model's defaults written
    out) on: the HS average of grain and cement in the rock's proportions (eqs. C.1-C.3), the
    frame capped at it, Gassmann (eqs. 4-6), density (eq. 24), velocities; no cement at every
    997th point (the cement absent from the mineral); with all the cement at the contacts
    (``limit`` 0.36) and no porosity at every 1009th point, where the frame exceeds the
    mineral by < 1e-4 and is capped."""
    s = np.linspace(0.0, 1.0, N)
    phi = 0.36 - 0.34 * s
    phip = 0.2 * s**2
    phip[::997] = 0.0
    if limit == 0.36:
        phi[::1009], phip[::1009] = 0.0, 0.36
    pe = 60.0 * s
    r = patchy_cement_model(QUARTZ, CEMENT, phi, phip, pe, WATER, contact_cement_limit=limit)
    dry = granular.patchy_cement(QUARTZ.K, QUARTZ.G, CEMENT.K, CEMENT.G, phi, 0.36, 9.0, pe,
                                 phip, limit, 1, 0.0, 1.0, 100.0)
    beta_c = np.clip(phip / (1 - phi), 0, 1)
    beta = np.stack([1 - beta_c, beta_c], -1)
    K_lo, _, K_hi, _ = hs_eq(np.array([QUARTZ.K, CEMENT.K]), np.array([QUARTZ.G, CEMENT.G]),
                             beta)
    K_s = (K_lo + K_hi) / 2
    assert np.any(dry.K > K_s) == (limit == 0.36)
    K_dry = np.minimum(dry.K, K_s)
    K_sat = gassmann_eq(K_dry, K_s, WATER.K, phi)
    rho = (1 - phi) * ((1 - beta_c) * QUARTZ.rho + beta_c * CEMENT.rho) + phi * WATER.rho
    for got, want in zip(r, (K_dry, dry.G, K_sat, dry.G, rho, *finish_eq(K_dry, dry.G, K_sat,
                                                                           rho))):
        close(got, want)


def sc_spheres(K, G, f):
    """Berryman's self-consistent moduli of spheres (eq. 8 of Carcione et al. 2022 with the
    sphere's P = (K + 4/3 mu)/(K_i + 4/3 mu), Q = (mu + zeta)/(mu_i + zeta)), by scipy's root
    (hybr) to round-off."""
    def residual(x):
        k, g = x
        z = g / 6 * (9 * k + 8 * g) / (k + 2 * g)
        return [np.sum(f * (K - k) * (k + 4 / 3 * g) / (K + 4 / 3 * g)),
                np.sum(f * (G - g) * (g + z) / (G + z))]
    sol = root(residual, [f @ K, f @ G], method="hybr", tol=1e-15)
    assert np.max(np.abs(residual(sol.x))) < 1e-13
    return sol.x


def test_model4_patchy_frame_equals_its_equations_with_absent_patches_and_no_pressure():
    """Steps 3-6 of granular.patchy_cement written out (Hertz-Mindlin, HS upper mix of the
    cemented and uncemented patches, Hill interpolation to the self-consistent end member) where
    the two-phase mixes take their edge paths: no cement (cemented patch absent), all contact
    cement (phip = phic: the uncemented patch absent), and no pressure and no pre-stress
    (Hertz-Mindlin moduli 0: zero denominators in the Reuss average)."""
    K0, G0, Kc, Gc, phic, n = QUARTZ.K, QUARTZ.G, CEMENT.K, CEMENT.G, 0.36, 9.0
    rng = np.random.default_rng(4)
    phip = rng.uniform(0.0, 0.05, N)
    phip[::4] = 0.0
    phip[1::4] = phic
    phi = rng.uniform(0.0, phic, N)
    p = rng.uniform(0.0, 60.0, N)
    p[::3] = 0.0
    limit = phic
    got = granular.patchy_cement(K0, G0, Kc, Gc, phi, phic, n, p, phip, limit, 1, 0.0, 1.0, 0.0)
    nu = (3 * K0 - 2 * G0) / (2 * (3 * K0 + G0))
    K_hm = np.cbrt(n**2 * (1 - phic) ** 2 * G0**2 * (p / 1000) / (18 * np.pi**2 * (1 - nu) ** 2))
    G_hm = (5 - 4 * nu) / (5 * (2 - nu)) * np.cbrt(
        3 * n**2 * (1 - phic) ** 2 * G0**2 * (p / 1000) / (2 * np.pi**2 * (1 - nu) ** 2))
    cct = granular.contact_cement(K0, G0, Kc, Gc, phic - np.minimum(phip, limit), phic, n)
    frac = phip / phic
    f = np.stack([frac, 1 - frac], -1)
    _, _, K_b, G_b = hs_eq(np.stack([cct.K, K_hm], -1), np.stack([cct.G, G_hm], -1), f)
    K_s, G_s = sc_spheres(np.array([K0, Kc]), np.array([G0, Gc]), np.array([1 - phic, phic]))
    x = phi / phic
    with np.errstate(divide="ignore"):
        K_r = np.where(K_b > 0, 1 / ((1 - x) / K_s + x / np.where(K_b > 0, K_b, 1)), 0.0)
        G_r = np.where(G_b > 0, 1 / ((1 - x) / G_s + x / np.where(G_b > 0, G_b, 1)), 0.0)
    K = 0.5 * ((1 - x) * K_s + x * K_b + K_r)
    G = 0.5 * ((1 - x) * G_s + x * G_b + G_r)
    close(got.K, K)
    close(got.G, G)


def test_model4_refusal_names_the_largest_excess_over_all_blocks():
    """A cement much softer than the grain makes the frame stiffer than its mineral at zero
    porosity, the more the larger the cement fraction (refused from about 0.33 on): the
    message names the point of the largest excess, in the third block, not the first point
    refused (first block)."""
    epoxy = mineral("epoxy")
    phip = np.full(N, 0.34)
    phip[2 * BLOCK + 17] = 0.36
    with pytest.raises(ValueError, match=r"^Model 4 does not hold at porosity 0, "
                                         r"cement_fraction 0.36: its dry frame"):
        patchy_cement_model(QUARTZ, epoxy, np.zeros(N), phip, 10.0, WATER,
                            contact_cement_limit=0.36)


def three_solids(seed):
    """Quartz, smectite and illite (Carcione et al. 2022, Table 1) and random fractions, the
    quartz absent at every 773rd point and only it present at every 1231st."""
    rng = np.random.default_rng(seed)
    K, G = np.array([40.0, 9.0, 33.0]), np.array([39.0, 6.0, 28.0])
    f = rng.uniform(0.0, 1.0, (N, 3))
    f[1::773, 0] = 0.0
    f[2::1231, 1:] = 0.0
    return K, G, f / f.sum(-1, keepdims=True)


@pytest.mark.parametrize("fn, picks", [(hashin_shtrikman, (0, 1, 2, 3)),
                                       (hashin_shtrikman_upper, (2, 3)),
                                       (hashin_shtrikman_average, "mean")])
def test_hs_of_fixed_moduli_equals_the_equations_and_each_point_its_own(fn, picks):
    """Three solids, the same at every point (denominators as numbers), absent phases at points
    in every block (the general code there): the equations to 1e-14, and each point's value
    the same whether computed with its neighbours or alone."""
    K, G, f = three_solids(5)
    got = fn(K, G, f)
    eq = hs_eq(K, G, f)
    want = [(eq[0] + eq[2]) / 2, (eq[1] + eq[3]) / 2] if picks == "mean" else \
        [eq[i] for i in picks]
    for a, b in zip(got, want):
        close(a, b)
    for i in (0, 1, 2, 1 + 773 * 90, 2 + 1231 * 55, 2 * BLOCK + 5):
        for a, b in zip(got, fn(K, G, f[i])):
            assert a[i] == b


def test_hs_of_fixed_moduli_bit_identical_to_the_general_path():
    """The path for moduli the same at every point does the general path's operations: the
    same values to the last bit as the same moduli given one row per point (a copy, not a
    broadcast view: the general path), absent phases included."""
    K, G, f = three_solids(6)
    rows = np.ascontiguousarray(np.broadcast_to(K, f.shape)), \
        np.ascontiguousarray(np.broadcast_to(G, f.shape))
    for fn in (hashin_shtrikman, hashin_shtrikman_upper, hashin_shtrikman_average):
        for a, b in zip(fn(K, G, f), fn(*rows, f)):
            np.testing.assert_array_equal(a, b)


def test_patchy_frame_bit_identical_to_its_public_building_blocks():
    """The two-phase HS upper mix and Hill average without stacking do the operations of the
    n-phase code: granular.patchy_cement equals its steps through the public functions (the
    general path of hashin_shtrikman and hill, moduli one per point) to the last bit."""
    rng = np.random.default_rng(8)
    K0, G0, Kc, Gc, phic, n = QUARTZ.K, QUARTZ.G, CEMENT.K, CEMENT.G, 0.36, 9.0
    phip = rng.uniform(0.0, 0.05, N)
    phip[::4] = 0.0
    phi = rng.uniform(0.0, phic, N)
    p = rng.uniform(0.0, 60.0, N)
    m = granular.patchy_cement(K0, G0, Kc, Gc, phi, phic, n, p, phip, 0.05, 1, 0.0, 1.0, 10.0)
    hm = granular.hertz_mindlin(K0, G0, phic, n, p, 1.0, 10.0)
    cct = granular.contact_cement(K0, G0, Kc, Gc, phic - np.minimum(phip, 0.05), phic, n)
    end = inclusions.self_consistent([K0, Kc], [G0, Gc], [1 - phic, phic])
    frac = np.clip(phip / phic, 0.0, 1.0)
    b = hashin_shtrikman_upper(np.stack([cct.K, hm.K], -1), np.stack([cct.G, hm.G], -1),
                               np.stack([frac, 1.0 - frac], -1))
    x = phi / phic
    h = hill(np.stack(np.broadcast_arrays(end.K, b.K), -1),
             np.stack(np.broadcast_arrays(end.G, b.G), -1), np.stack([1.0 - x, x], -1))
    np.testing.assert_array_equal(m.K, h.K)
    np.testing.assert_array_equal(m.G, h.G)


def test_fractions_checked_by_their_distance_from_one():
    """The reductions of check_fractions refuse a sum off by more than atol on either side
    and accept one within it (the same test as |sum - 1| > atol)."""
    base = np.full((3 * BLOCK, 2), 0.5)
    for off in (2e-6, -2e-6):
        bad = base.copy()
        bad[2 * BLOCK + 1, 1] += off
        with pytest.raises(ValueError, match=r"sum to 1 .* got a sum of "
                                             + ("1" if off > 0 else "0.99999")):
            check_fractions("f", bad)
    ok = base.copy()
    ok[5, 0] += 0.9e-6
    assert check_fractions("f", ok) is ok
