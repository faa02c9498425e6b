"""The four petro-elastic models of Carcione et al. 2022 (rockcem.models)."""

import numpy as np
import pytest

from rockcem.bounds import hashin_shtrikman
from rockcem.materials import Fluid, Mineral, fluid, mineral
from rockcem.models import (MODELS, bulk_density, generalized_gassmann_model, hs_gassmann,
                            patchy_cement_model, self_consistent_model)

QUARTZ, CEMENT, WATER = mineral("quartz"), mineral("quartz_cement"), fluid("water")
SMECTITE, ILLITE = mineral("smectite"), mineral("illite")


def sandstone_state(n=25):
    """A cementation trend: porosity 0.36 -> 0.02 as cement fills the pores (Carcione eq. B.4)."""
    phi = np.linspace(0.36, 0.02, n)
    phip = 0.36 - phi
    beta = np.stack([(1 - phi - phip) / (1 - phi), phip / (1 - phi)], -1)
    return phi, phip, beta


def run(name, phi, phip, beta, fl=WATER, pressure=20.0):
    if name == "patchy_cement":
        return patchy_cement_model(QUARTZ, CEMENT, phi, phip, pressure, fl)
    if name == "self_consistent":
        return self_consistent_model([QUARTZ, CEMENT], beta, phi, fl, aspect_ratio=0.108)
    return MODELS[name]([QUARTZ, CEMENT], beta, phi, fl)


def test_model1_single_mineral_closed_form():
    """Krief (eq. 3) + Gassmann (eqs. 4-6) + eqs. 22-25 written out for one mineral."""
    phi = 0.2
    r = hs_gassmann([QUARTZ], [1.0], phi, WATER)
    fac = (1 - phi) ** (3 / (1 - phi))
    Km, Gm = 40 * fac, 39 * fac
    a = 1 - Km / 40
    M = 1 / ((a - phi) / 40 + phi / 2.2)
    K = Km + a * a * M
    rho = 0.8 * 2.65 + 0.2 * 1.04
    assert float(r.K_sat) == pytest.approx(K, rel=1e-13)
    assert float(r.G_sat) == pytest.approx(Gm, rel=1e-13)
    assert float(r.density) == pytest.approx(rho, rel=1e-14)
    assert float(r.vp) == pytest.approx(np.sqrt((K + 4 / 3 * Gm) / rho), rel=1e-13)
    assert float(r.vs) == pytest.approx(np.sqrt(Gm / rho), rel=1e-13)


def test_models_1_and_3_coincide_for_one_mineral_and_nearly_for_two():
    phi, phip, beta = sandstone_state()
    one = [hs_gassmann([QUARTZ], [1.0], phi, WATER),
           generalized_gassmann_model([QUARTZ], [1.0], phi, WATER)]
    np.testing.assert_allclose(one[0].vp, one[1].vp, rtol=1e-13)
    m1 = hs_gassmann([QUARTZ, CEMENT], beta, phi, WATER)
    m3 = generalized_gassmann_model([QUARTZ, CEMENT], beta, phi, WATER)
    # Carcione et al. 2022, Sect. 6.2: "Models 1 and 3 giving almost identical results".
    np.testing.assert_allclose(m1.vp, m3.vp, rtol=2e-3)
    np.testing.assert_allclose(m1.vs, m3.vs, rtol=2e-3)


@pytest.mark.parametrize("name", list(MODELS))
def test_models_within_hs_bounds_and_monotone(name):
    phi, phip, beta = sandstone_state()
    r = run(name, phi, phip, beta)
    K = np.stack(np.broadcast_arrays(40.0, 35.0, 2.2), -1) * np.ones((phi.size, 1))
    G = np.stack(np.broadcast_arrays(39.0, 30.0, 0.0), -1) * np.ones((phi.size, 1))
    rock = np.stack([(1 - phi) * beta[:, 0], (1 - phi) * beta[:, 1], phi], -1)
    hs = hashin_shtrikman(K, G, rock)
    assert np.all(r.K_sat >= hs.K_lower * (1 - 1e-12))
    assert np.all(r.K_sat <= hs.K_upper * (1 + 1e-12))
    assert np.all(r.G_sat >= 0) and np.all(r.G_sat <= hs.G_upper * (1 + 1e-12))
    # Cement filling the pores raises density and both velocities (Carcione Figs. 16-19).
    assert np.all(np.diff(r.density) > 0)
    assert np.all(np.diff(r.vp) > 0) and np.all(np.diff(r.vs) > 0)
    assert np.all(r.K_dry <= r.K_sat + 1e-12)


@pytest.mark.parametrize("name", list(MODELS))
def test_models_agree_within_a_few_hundred_m_per_s(name):
    """Sect. 6.2: the four models give similar trends and values of the velocities."""
    phi, phip, beta = sandstone_state()
    ref = run("hs_gassmann", phi, phip, beta)
    r = run(name, phi, phip, beta)
    assert np.max(np.abs(r.vp - ref.vp)) < 0.5
    assert np.max(np.abs(r.vs - ref.vs)) < 0.5


def test_zero_porosity_limits():
    """Model 1 gives the HS mineral at phi = 0. Model 3's frame is the HS mineral there (the
    property stated after eq. 13), and eq. 10 adds (1 - K_s/V_K) K_R with K_R the Reuss modulus:
    at phi = 0, alpha_i = beta_i (1 - K_s/V_K) and M = K_R / (1 - K_s/V_K)."""
    beta = np.array([0.7, 0.3])
    K, G = np.array([40.0, 35.0]), np.array([39.0, 30.0])
    hs = hashin_shtrikman(K, G, beta).average
    r1 = hs_gassmann([QUARTZ, CEMENT], beta, 0.0, WATER)
    assert float(r1.K_sat) == pytest.approx(float(hs.K), rel=1e-13)
    assert float(r1.G_sat) == pytest.approx(float(hs.G), rel=1e-13)
    r3 = generalized_gassmann_model([QUARTZ, CEMENT], beta, 0.0, WATER)
    assert float(r3.K_dry) == pytest.approx(float(hs.K), rel=1e-13)
    assert float(r3.G_sat) == pytest.approx(float(hs.G), rel=1e-13)
    V = np.sum(beta * K)
    R = 1 / np.sum(beta / K)
    assert float(r3.K_sat) == pytest.approx(float(hs.K) + (1 - float(hs.K) / V) * R, rel=1e-12)


def test_shale_models_and_dry_pores():
    """Shale of smectite and illite (Sect. 6.1): dry pores give K_sat = K_dry."""
    beta = np.array([[0.9, 0.1], [0.2, 0.8]])
    phi = np.array([0.3, 0.1])
    dry = Fluid(0.0, 0.0, "vacuum")
    for fn in (hs_gassmann, generalized_gassmann_model):
        r = fn([SMECTITE, ILLITE], beta, phi, dry)
        np.testing.assert_allclose(r.K_sat, r.K_dry, rtol=1e-14)
    r = self_consistent_model([SMECTITE, ILLITE], beta, phi, WATER, aspect_ratio=0.17)
    assert np.all(r.vp[1] > r.vp[0])          # more illite, less porosity: faster


def test_self_consistent_spherical_pores_faster():
    """Sect. 6.1: with spherical pores Model 2 is faster than with gamma = 0.17."""
    beta = np.array([0.5, 0.5])
    flat = self_consistent_model([SMECTITE, ILLITE], beta, 0.25, WATER, aspect_ratio=0.17)
    round_ = self_consistent_model([SMECTITE, ILLITE], beta, 0.25, WATER, aspect_ratio=1.0)
    assert float(round_.vp) > float(flat.vp) and float(round_.vs) > float(flat.vs)


def test_self_consistent_model_numba_path(monkeypatch):
    """Model 2 from 5e4 points on runs on the numba kernel (exact Jacobian, continuation); the
    same rock state on the numpy path (every point from its HS bound) gives the same result,
    and the dry moduli are self_consistent's with empty pores."""
    pytest.importorskip("numba")
    from rockcem import inclusions

    phi, _, beta = sandstone_state(3000)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 0)
    fast = run("self_consistent", phi, None, beta)
    monkeypatch.setattr(inclusions, "_NUMBA_MIN_POINTS", 2**62)
    ref = run("self_consistent", phi, None, beta)
    for name in fast._fields:
        np.testing.assert_allclose(getattr(fast, name), getattr(ref, name), rtol=1e-10,
                                   atol=1e-12, err_msg=name)
    frac = np.concatenate([(1 - phi)[:, None] * beta, phi[:, None]], -1)
    dry = inclusions.self_consistent([QUARTZ.K, CEMENT.K, 0.0], [QUARTZ.G, CEMENT.G, 0.0], frac,
                                     [1.0, 1.0, 0.108])
    np.testing.assert_allclose(fast.K_dry, dry.K, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(fast.G_dry, dry.G, rtol=1e-10, atol=1e-12)


def test_patchy_cement_contact_vs_coating_small_difference():
    """Fig. 19: cement at contacts or coating the grains differs little in Model 4."""
    phi, phip, _ = sandstone_state()
    a = patchy_cement_model(QUARTZ, CEMENT, phi, phip, 30.0, WATER, scheme=1)
    b = patchy_cement_model(QUARTZ, CEMENT, phi, phip, 30.0, WATER, scheme=2)
    assert np.all(b.vp <= a.vp + 1e-12)            # coating spreads the cement: softer
    assert np.max(np.abs(a.vp - b.vp) / a.vp) < 0.08


def test_broadcasting_and_inputs_not_mutated():
    phi, phip, beta = sandstone_state(6)
    phi0, beta0 = phi.copy(), beta.copy()
    r = hs_gassmann([QUARTZ, CEMENT], beta.reshape(2, 3, 2), phi.reshape(2, 3), WATER)
    assert r.vp.shape == (2, 3)
    np.testing.assert_array_equal(phi, phi0)
    np.testing.assert_array_equal(beta, beta0)


@pytest.mark.parametrize("call,match", [
    (lambda: hs_gassmann([QUARTZ, CEMENT], [0.5, 0.6], 0.2, WATER), "solid_fractions"),
    (lambda: hs_gassmann([QUARTZ, CEMENT], [1.0], 0.2, WATER), "solid_fractions"),
    (lambda: hs_gassmann([QUARTZ], [1.0], 1.2, WATER), "porosity"),
    (lambda: hs_gassmann([QUARTZ], [1.0], 0.2, "water"), "fluid"),
    (lambda: hs_gassmann(["quartz"], [1.0], 0.2, WATER), "minerals"),
    (lambda: self_consistent_model([QUARTZ], [1.0], 0.2, WATER, aspect_ratio=-1), "aspect_ratio"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.4, 0.0, 10.0, WATER),
     "porosity must not exceed critical_porosity"),
    # Model 4 names its own keyword (the scene key), never the building blocks' n or phic.
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 1.0, WATER, coordination_number=-1),
     r"^coordination_number must lie in \(0, 20\]"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 1.0, WATER, coordination_number=1e300),
     r"^coordination_number must lie in \(0, 20\]"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 1.0, WATER, coordination_number="9"),
     r"^coordination_number must be a real number, got text"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 1.0, WATER, critical_porosity=1.2),
     r"^critical_porosity must lie in \(0, 1\)"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.1, 1.0, WATER, contact_cement_limit=0.5),
     r"^contact_cement_limit must not exceed critical_porosity"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 1e300, WATER),
     r"^pressure must lie in \[0, 1000\]"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 10.0, WATER, delta=np.inf),
     r"^delta must lie in \[0, 1000\]"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, 10.0, WATER, scheme=3), r"^scheme"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, [0.3, 0.2], 0.0, [1.0, 2.0, 3.0], WATER),
     r"porosity \(2,\).*pressure \(3,\)"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.0, -1.0, WATER), "pressure"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.3, 0.8, 1.0, WATER), "porosity \\+ cement"),
])
def test_models_bad_input(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_bulk_density_closed_form():
    """Eq. 24 by hand: (1 - phi) (0.7 * 2.65 + 0.3 * 2.8) + phi * 1.04, two depths."""
    phi = np.array([0.1, 0.3])
    want = (1 - phi) * (0.7 * 2.65 + 0.3 * 2.8) + phi * 1.04
    np.testing.assert_allclose(bulk_density([2.65, 2.8], [0.7, 0.3], phi, 1.04), want,
                               rtol=1e-15)
    np.testing.assert_array_equal(bulk_density([2.65], [1.0], [0.0, 1.0], 0.0), [2.65, 0.0])


@pytest.mark.parametrize("args, match", [
    # Issue 24: porosity 1.2 and negative densities gave a density with no word.
    (([2.65], [1.0], 1.2, 1.0), r"^porosity must lie in \[0, 1\]; got 1.2"),
    (([2.65], [1.0], -0.1, 1.0), r"^porosity"),
    (([-2.65], [1.0], 0.2, 1.0), r"^mineral_density must lie in \(0, 25\]"),
    (([2.65], [1.0], 0.2, -1.0), r"^fluid_density must lie in \[0, 25\]"),
    (([2.65], [1.0], 0.2, np.inf), r"^fluid_density"),
    (([2.65], [1.0], 0.2, np.nan), r"^fluid_density contains NaN"),
    (([2.65], [1.0], 0.2, None), r"^fluid_density must be a real number"),
    (([2.65, 2.8], [0.7, 0.4], 0.2, 1.0), r"^solid_fractions must sum to 1"),
    (([2.65, 2.8], [1.0], 0.2, 1.0), r"^solid_fractions has 1 phase"),
    (([2.65], [1.0], [0.1, 0.2], [1.0, 1.0, 1.0]), r"porosity \(2,\), fluid_density \(3,\)"),
])
def test_bulk_density_bad_input(args, match):
    with pytest.raises(ValueError, match=match):
        bulk_density(*args)


def test_mineral_dataclass_validation():
    with pytest.raises(ValueError, match="K"):
        Mineral(-1.0, 1.0, 2.0)
