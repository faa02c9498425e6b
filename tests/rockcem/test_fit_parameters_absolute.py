"""rockcem.calibrate.fit_parameters with measurement errors takes observations of any sign
(a log porosity of 0 or below), fitting on (predicted - observed) / error, as ordinary weighted
least squares; without errors its residuals are relative and observations must be > 0."""

import numpy as np
import pytest

from rockcem.calibrate import fit_parameters


def test_weighted_fit_of_a_line_through_zero_and_negative_observations():
    x = np.linspace(-1.0, 1.0, 21)
    rng = np.random.default_rng(3)
    y = 0.02 + 0.05 * x + rng.normal(0.0, 0.004, x.size)      # crosses 0
    assert np.any(y <= 0.0)
    sigma = np.full(x.size, 0.004)
    r = fit_parameters(lambda a, b: {"porosity": a + b * x}, {"porosity": y},
                       {"a": (0.0, -1.0, 1.0), "b": (0.0, -1.0, 1.0)},
                       errors={"porosity": sigma}, absolute_errors=True)
    # closed form: weighted least squares with equal weights is np.polyfit, and its covariance
    # with absolute errors is sigma^2 (X^T X)^-1
    b, a = np.polyfit(x, y, 1)
    assert r.values["a"] == pytest.approx(a, abs=1e-9)
    assert r.values["b"] == pytest.approx(b, abs=1e-9)
    X = np.stack([np.ones_like(x), x], axis=1)
    cov = 0.004**2 * np.linalg.inv(X.T @ X)
    assert r.stderr["a"] == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-6)
    # misfit: absolute where an observation is not > 0
    assert r.misfit["porosity"] == pytest.approx(
        float(np.sqrt(np.mean((a + b * x - y) ** 2))), rel=1e-6)


def test_relative_residuals_still_need_positive_observations():
    with pytest.raises(ValueError, match="porosity"):
        fit_parameters(lambda a: {"porosity": a + 0 * np.ones(3)},
                       {"porosity": np.array([0.1, 0.0, 0.2])}, {"a": (0.1, 0.0, 1.0)})
