"""The cemented-contact integral equation (rockcem.contact_integral) and MCCT."""

import numpy as np
import pytest
from scipy.special import ellipe

from rockcem.contact_integral import _unit_matrix, cemented_contact_stiffness
from rockcem.granular import _cct_stiffness, contact_cement


def test_kernel_matrix_uniform_pressure():
    """Boussinesq: a uniform pressure on the unit disk displaces the surface at radius u by
    (1 - nu^2)/(pi E) * 4 E(u) (Johnson, Contact Mechanics, eq. 3.30): the kernel matrix applied
    to ones must give 4 E(u), E the complete elliptic integral of the second kind (modulus u)."""
    mid, moment, W = _unit_matrix(96)
    np.testing.assert_allclose(W @ np.ones(mid.size), 4.0 * ellipe(mid**2), rtol=1e-9)
    np.testing.assert_allclose(moment.sum(), 0.5, rtol=1e-14)


def test_flat_punch_limit():
    """Stiff cement bond between rigid-ish grains: S -> 2 alpha / (pi^2 Lambda) as Lambda -> inf
    (two half-spaces loaded by a rigid circular punch of radius alpha)."""
    for alpha in (0.1, 0.3, 0.5):
        S = float(cemented_contact_stiffness(alpha, 1e4))
        assert S == pytest.approx(2 * alpha / (np.pi**2 * 1e4), rel=3e-3)


@pytest.mark.parametrize("Lambda", [0.1, 0.2, 0.5, 1.0])
@pytest.mark.parametrize("alpha", [0.1, 0.2, 0.3, 0.4, 0.5])
def test_normal_stiffness_matches_handbook_fit(Lambda, alpha):
    """Dvorkin & Nur's polynomial fit of S_n reproduces the solved equation within its quoted
    range (checked: within 5 % for 0.1 <= Lambda_n <= 1)."""
    Sn_fit, _ = _cct_stiffness(alpha, Lambda, 1.0, 0.1)
    assert float(cemented_contact_stiffness(alpha, Lambda)) == pytest.approx(Sn_fit, rel=0.05)


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.25, 0.4])
@pytest.mark.parametrize("Lambda_t", [0.2, 0.5, 1.0])
def test_tangential_stiffness_matches_handbook_fit(nu, Lambda_t):
    _, St_fit = _cct_stiffness(0.3, 1.0, Lambda_t, nu)
    S = float(cemented_contact_stiffness(0.3, Lambda_t * (1 - nu / 2)))
    assert S == pytest.approx(St_fit, rel=0.08)


def test_convergence_with_panels():
    """Successive refinements converge (differences shrink by a factor > 2 per doubling)."""
    args = ([0.1, 0.3, 0.5], [0.05, 0.5, 2.0], [0.0, 0.01, 0.05])
    vals = [cemented_contact_stiffness(*args, panels=n) for n in (24, 48, 96, 192)]
    diffs = [np.max(np.abs(b - a) / b) for a, b in zip(vals, vals[1:])]
    assert diffs[1] < diffs[0] / 2 and diffs[2] < diffs[1] / 2
    assert diffs[2] < 5e-4


def test_thickness_softens_and_is_continuous_at_zero():
    eps = np.array([0.0, 1e-10, 1e-3, 0.01, 0.03, 0.1])
    S = cemented_contact_stiffness(0.3, 0.05, eps)
    assert S[1] == pytest.approx(S[0], rel=1e-7)
    assert np.all(np.diff(S) < 0)
    # Thick gap: the foundation dominates, S -> (alpha^2 / 2) / eps (uniform stress 1/eps).
    thick = float(cemented_contact_stiffness(0.3, 0.05, 1e3))
    assert thick == pytest.approx(0.3**2 / 2 / 1e3, rel=1e-3)


def test_vectorised_equals_loop(rng):
    a = rng.uniform(0.05, 0.5, 7)
    lam = rng.uniform(0.01, 5, 7)
    e = rng.uniform(0, 0.1, 7)
    vec = cemented_contact_stiffness(a, lam, e, chunk=3)
    loop = [float(cemented_contact_stiffness(*x)) for x in zip(a, lam, e)]
    np.testing.assert_allclose(vec, loop, rtol=1e-12)


@pytest.mark.parametrize("kwargs,match", [
    (dict(alpha=0.0, Lambda=1.0), "alpha"),
    (dict(alpha=0.3, Lambda=-1.0), "Lambda"),
    (dict(alpha=0.3, Lambda=1.0, thickness=-1e-3), "thickness"),
    (dict(alpha=0.3, Lambda=1.0, panels=2), "panels"),
])
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        cemented_contact_stiffness(**kwargs)


# --- MCCT through contact_cement -----------------------------------------------------------------
GRAIN, CEMENT = (38.0, 44.0), (2.24, 1.57)   # Han & Guo / Xu 2023 quartz and epoxy-kaolinite


@pytest.mark.parametrize("stiffness", ["fit", "integral"])
@pytest.mark.parametrize("scheme", [1, 2])
def test_mcct_tends_to_cct(stiffness, scheme):
    phi = np.array([0.39, 0.3, 0.2])
    zero = contact_cement(*GRAIN, *CEMENT, phi, 0.4, 8.5, scheme, 0.0, stiffness=stiffness)
    tiny = contact_cement(*GRAIN, *CEMENT, phi, 0.4, 8.5, scheme, 1e-9, stiffness=stiffness)
    np.testing.assert_allclose(tiny.K, zero.K, rtol=1e-6)
    np.testing.assert_allclose(tiny.G, zero.G, rtol=1e-6)


@pytest.mark.parametrize("scheme", [1, 2])
def test_mcct_softens_with_thickness(scheme):
    """Han & Guo, Fig. 4: velocities fall with contact thickness, for both cement schemes."""
    eps = [0.0, 0.01, 0.02, 0.03, 0.05]
    m = contact_cement(*GRAIN, *CEMENT, 0.3, 0.4, 8.5, scheme, eps)
    assert np.all(np.diff(m.K) < 0) and np.all(np.diff(m.G) < 0)


def test_contact_cement_integral_zero_cement():
    m = contact_cement(40.0, 39.0, 35.0, 30.0, 0.4, 0.4, 9.0, stiffness="integral")
    assert float(m.K) == 0.0 and float(m.G) == 0.0


def test_contact_cement_bad_stiffness_option():
    with pytest.raises(ValueError, match="stiffness"):
        contact_cement(40.0, 39.0, 35.0, 30.0, 0.3, 0.4, 9.0, stiffness="exact")


def test_gap_without_cement_has_no_stiffness():
    """Grains apart (thickness > 0) with no cement between them carry no load."""
    for stiffness in ("fit", "integral"):
        m = contact_cement(*GRAIN, *CEMENT, 0.4, 0.4, 8.5, 2, 0.02, stiffness=stiffness)
        assert float(m.K) == 0.0 and float(m.G) == 0.0
