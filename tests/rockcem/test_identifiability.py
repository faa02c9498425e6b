"""rockcem.calibrate.unidentifiable and correlation: which fitted parameters the data do not
determine, and the [identifiability] table of a calibration file.

The expected flags are computed independently of the fit: the normal-equation covariance of a
weighted straight line, sqrt(diag((X^T W X)^-1)), against the fitted value; an exactly collinear
design, whose normal matrix is singular.
"""

import numpy as np
import pytest

from rockcem.calibrate import (correlation, fit_parameters, load_calibration, unidentifiable,
                               write_calibration)

X = np.linspace(1.0, 3.0, 9)
SIGMA = 0.1 * X
NOISE = np.array([1, -1, 1, -1, 1, -1, 1, -1, 1]) * 0.5 * SIGMA
BOUNDS = {"a": (1.0, -10.0, 10.0), "b": (1.0, -10.0, 10.0)}


def line_fit(slope):
    y = 2.0 + slope * X + NOISE
    fit = fit_parameters(lambda a, b: {"y": a + b * X}, {"y": y}, BOUNDS,
                         errors={"y": SIGMA}, absolute_errors=True)
    design = np.stack([np.ones_like(X), X], axis=1) / SIGMA[:, None]
    beta = np.linalg.lstsq(design, y / SIGMA, rcond=None)[0]
    cov = np.linalg.inv(design.T @ design)
    return fit, beta, cov


def test_relative_test_flags_a_slope_smaller_than_its_error():
    """A slope of 0.01 under noise: its error (normal equations) exceeds its value, so the
    relative test flags it; the intercept, known to a few per cent, is not flagged, and
    neither is the slope without the relative test (its error is far inside the bounds)."""
    fit, beta, cov = line_fit(0.01)
    err_b = np.sqrt(cov[1, 1])
    assert err_b > abs(beta[1])                   # the premise, from the closed form
    assert np.sqrt(cov[0, 0]) < abs(beta[0]) / 5
    assert unidentifiable(fit, BOUNDS, relative=True) == ("b",)
    assert unidentifiable(fit, BOUNDS) == ()
    r = correlation(fit)
    assert r[0, 1] == pytest.approx(cov[0, 1] / np.sqrt(cov[0, 0] * cov[1, 1]), rel=1e-5)
    assert r[0, 0] == r[1, 1] == 1.0


def test_a_well_determined_slope_is_not_flagged():
    fit, beta, cov = line_fit(0.5)
    assert np.sqrt(cov[1, 1]) < abs(beta[1])
    assert unidentifiable(fit, BOUNDS, relative=True) == ()


def test_error_wider_than_the_bounds_is_flagged():
    """The same fit judged against bounds narrower than the slope's error."""
    fit, _, cov = line_fit(0.5)
    narrow = {"a": BOUNDS["a"], "b": (0.0, 0.5 * np.sqrt(cov[1, 1]))}
    assert unidentifiable(fit, narrow) == ("b",)


def test_collinear_parameters_are_both_flagged():
    """y = (a + b) x: only the sum is determined, the normal matrix is singular."""
    y = 1.5 * X + NOISE
    fit = fit_parameters(lambda a, b: {"y": (a + b) * X}, {"y": y}, BOUNDS,
                         errors={"y": SIGMA})
    assert unidentifiable(fit, BOUNDS) == ("a", "b")
    assert unidentifiable(fit, BOUNDS, correlation_limit=1.0) == ("a", "b")


def test_bad_arguments():
    fit, _, _ = line_fit(0.5)
    with pytest.raises(ValueError, match="correlation_limit"):
        unidentifiable(fit, BOUNDS, correlation_limit=0.0)
    with pytest.raises(ValueError, match="bounds"):
        unidentifiable(fit, {"a": (0.0, 1.0)})


def test_identifiability_table_round_trip(tmp_path):
    path = write_calibration(tmp_path / "c.toml", name="c", model="patchy_cement",
                             parameters={"coordination_number": 6.0,
                                         "contact_cement_limit": 0.05},
                             uncertainty={"coordination_number": 0.1},
                             identifiability={"unidentifiable": ["contact_cement_limit"],
                                              "first_fit_contact_cement_limit_err": np.inf})
    cal = load_calibration(path)
    assert cal["identifiability"]["unidentifiable"] == ["contact_cement_limit"]
    assert cal["identifiability"]["first_fit_contact_cement_limit_err"] == np.inf
    plain = write_calibration(tmp_path / "p.toml", name="p", model="patchy_cement",
                              parameters={"coordination_number": 6.0})
    assert "[identifiability]" not in plain.read_text()
    assert load_calibration(plain)["identifiability"] == {}
    with pytest.raises(ValueError, match="identifiability"):
        write_calibration(tmp_path / "bad.toml", name="b", model="patchy_cement",
                          parameters={"coordination_number": 6.0},
                          identifiability={"unidentifiable": "contact_cement_limit"})
    assert not (tmp_path / "bad.toml").exists()


def test_a_parameter_without_leverage_leaves_the_others_errors():
    """c does not enter the prediction: its Jacobian column is zero, its error infinite and its
    correlation undefined; a and b keep the errors of the straight line without c (normal
    equations) and are not flagged."""
    _, beta, cov = line_fit(0.5)
    y = 2.0 + 0.5 * X + NOISE
    bounds = {**BOUNDS, "c": (0.3, 0.0, 1.0)}
    fit = fit_parameters(lambda a, b, c: {"y": a + b * X}, {"y": y}, bounds,
                         errors={"y": SIGMA}, absolute_errors=True)
    assert fit.values["a"] == pytest.approx(beta[0], rel=1e-5)
    assert fit.stderr["a"] == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-5)
    assert fit.stderr["b"] == pytest.approx(np.sqrt(cov[1, 1]), rel=1e-5)
    assert np.isinf(fit.stderr["c"])
    r = correlation(fit)
    assert np.isnan(r[0, 2]) and np.isnan(r[2, 1]) and np.isfinite(r[0, 1])
    assert unidentifiable(fit, bounds, relative=True) == ("c",)
