"""The public boundary of the rockcem models (issue 24): ranges that catch unit mistakes,
model limits refused by the model's own argument names, extremes that stay finite."""

import warnings

import numpy as np
import pytest

from rockcem.contact_integral import cemented_contact_stiffness
from rockcem.elastic import velocities
from rockcem.fluids import gassmann, generalized_gassmann
from rockcem.frames import krief_factor
from rockcem.granular import cement_radius, contact_cement
from rockcem.inclusions import berryman_pq, self_consistent
from rockcem.materials import fluid, mineral
from rockcem.models import MAX_FRAME_EXCESS, hs_gassmann, patchy_cement_model

QUARTZ, CEMENT, WATER = mineral("quartz"), mineral("quartz_cement"), fluid("water")


@pytest.mark.parametrize("call, match", [
    # Units: a modulus in Pa, a density in kg/m3.
    (lambda: gassmann(10.0, 36.6e9, 2.25, 0.2), r"^K_min must lie in \[1e-09, 1e\+09\] GPa; "
                                                r"got 3.66e\+10; a modulus in Pa\?"),
    (lambda: velocities(36.6, 45.0, 2650.0), r"^density must lie in \[1e-06, 25\]"),
    (lambda: krief_factor(0.2, 1e300), r"^A must lie in \(0, 100\]"),
    (lambda: berryman_pq(40.0, 39.0, 2.2, 0.0, 1e-12), r"^aspect_ratio must lie in \[1e-08"),
    (lambda: self_consistent([40.0, 2.2], [39.0, 0.0], [0.9, 0.1], [1.0, 1e12]),
     r"^aspect_ratio"),
    # A matrix incompressible to float64 (K/G of 1e18): the shape factors divide by 1 - 2 nu.
    (lambda: berryman_pq(1e9, 1e-9, 0.0, 0.0, 0.5), r"Poisson ratio of the matrix \(K_m, G_m\)"),
    # A frame modulus above its solid's share: alpha_i < 0.
    (lambda: generalized_gassmann([30.0, 1.0], [40.0, 20.0], [0.5, 0.5], 2.2, 0.2),
     r"^K_frame must not exceed solid_fractions \* K_solid"),
    # Cement radius beyond the grain: the CCT fit's stiffness turns negative there.
    (lambda: contact_cement(36.6, 45.0, 36.6, 45.0, 0.0, 0.99, 9.0), r"^phi lies too far below "
                                                                      r"phic .*a/R reaches"),
    (lambda: patchy_cement_model(QUARTZ, CEMENT, 0.2, 0.05, 10.0, WATER,
                                 coordination_number=1e-6),
     r"coordination_number and critical_porosity: its radius a/R reaches"),
])
def test_refused_by_name(call, match):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValueError, match=match):
            call()


def test_patchy_cement_model_frame_no_stiffer_than_its_mineral():
    """At zero porosity, all pore space cement: Model 4's frame end member (self-consistent
    grain-cement mix) and its mineral modulus (HS average) differ by < 1e-4 for quartz cement:
    capped, so that Gassmann gives K_sat = K_dry = K_mineral; with epoxy as the cement the
    frame would be 10 % stiffer than what it is made of: refused, naming porosity."""
    r = patchy_cement_model(QUARTZ, CEMENT, 0.0, 0.36, 10.0, WATER, contact_cement_limit=0.36)
    assert r.K_dry == pytest.approx(r.K_sat, rel=1e-15)
    epoxy = mineral("epoxy")
    with pytest.raises(ValueError, match=r"^Model 4 does not hold at porosity 0, "
                                         r"cement_fraction 0.36"):
        patchy_cement_model(QUARTZ, epoxy, 0.0, 0.36, 10.0, WATER, contact_cement_limit=0.36)
    assert 0.0 < MAX_FRAME_EXCESS < 0.01


def test_cemented_contact_at_tiny_cement_radius_is_the_flat_punch():
    """The system scaled by alpha: a radius of 1e-300 no longer underflows to a singular
    matrix. For a rigid grain (large Lambda) S -> 2 alpha / (pi^2 Lambda) (flat punch, as the
    module's doctest); a bond far thicker than wide has no stiffness."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for alpha in (1e-300, 1e-100, 1e-8):
            S = float(cemented_contact_stiffness(alpha, 1e-300))
            assert np.isfinite(S) and S > 0.0
        S = float(cemented_contact_stiffness(0.3, 1e3))
        assert S == pytest.approx(2 * 0.3 / (np.pi**2 * 1e3), rel=1e-2)
        assert float(cemented_contact_stiffness(1e-8, 1e-3, 1e300)) < 1e-300
        # eps / alpha beyond 1e308: no stiffness left, exactly
        assert float(cemented_contact_stiffness(1e-10, 1e-3, 1e300)) == 0.0


def test_cement_radius_at_a_tiny_coordination_number_is_finite():
    """alpha = 2 ((phic - phi) / (3 n (1 - phic)))^(1/4) (eq. 16): 2 (0.05/(3e-300 0.6))^(1/4)
    without overflowing y = 4 x / (3 n)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = float(cement_radius(0.35, 0.4, 1e-300))
    assert a == pytest.approx(2.0 * (0.05 / (3e-300 * 0.6)) ** 0.25, rel=1e-12)


def test_models_name_porosity_not_phi_for_a_shape_mismatch():
    with pytest.raises(ValueError, match=r"porosity \(3,\), A \(2,\)"):
        hs_gassmann([QUARTZ], [1.0], [0.1, 0.2, 0.3], WATER, A=[3.0, 3.0])
