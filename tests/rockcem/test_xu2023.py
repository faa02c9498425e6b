"""Xu 2023 Table 1: artificial sandstones against CCT, MCCT and the calibrated model."""

import numpy as np
import pandas as pd
import pytest

from rockcem._data import data_path
from rockcem.calibrate import fit_contact_cement, fit_parameters
from rockcem.elastic import velocities
from rockcem.granular import contact_cement
from rockcem.materials import mineral

GRAIN, CEMENT = mineral("quartz_han_guo"), mineral("epoxy_kaolinite")


@pytest.fixture(scope="module")
def table1():
    d = pd.read_csv(data_path("measurements", "xu2023_table1.csv"), comment="#")
    assert len(d) == 10
    return d


def test_xu2023_table1_cement_is_the_lost_porosity(table1):
    """The clay (cement) content is the porosity lost from the critical 0.4 (Xu 2023, Sect. 3.1),
    the volume the contact cement theory assumes."""
    np.testing.assert_allclose(table1.clay_content, 0.4 - table1.porosity, atol=0.011)


def predict(d, scheme, thickness, stiffness="fit"):
    m = contact_cement(GRAIN.K, GRAIN.G, CEMENT.K, CEMENT.G, d.porosity.values, 0.4, 8.5, scheme,
                       thickness, stiffness=stiffness)
    return velocities(m.K, m.G, d.density.values)


@pytest.mark.parametrize("scheme", [1, 2])
def test_xu2023_table1_cct_overestimates(table1, scheme):
    """Xu 2023, Fig. 10: CCT overestimates the velocities of these weakly cemented sandstones."""
    v = predict(table1, scheme, 0.0)
    assert np.all(v.vp * 1000 > table1.vp) and np.all(v.vs * 1000 > table1.vs)
    assert np.mean(v.vp * 1000 / table1.vp - 1) > 0.25


@pytest.mark.parametrize("scheme", [1, 2])
def test_xu2023_table1_mcct_closer(table1, scheme):
    """MCCT with the contact thickness Xu measures (0 to 0.05) removes most of the bias."""
    cct = predict(table1, scheme, 0.0)
    mcct = predict(table1, scheme, 0.04)
    for key in ("vp", "vs"):
        err_cct = np.sqrt(np.mean((getattr(cct, key) * 1000 / table1[key] - 1) ** 2))
        err_mcct = np.sqrt(np.mean((getattr(mcct, key) * 1000 / table1[key] - 1) ** 2))
        assert err_mcct < 0.5 * err_cct


@pytest.mark.parametrize("stiffness", ["fit", "integral"])
def test_xu2023_table1_calibrated_thickness(table1, stiffness):
    r = fit_contact_cement(GRAIN, CEMENT, table1.porosity, table1.density, table1.vp / 1000,
                           table1.vs / 1000, scheme=2, stiffness=stiffness)
    assert r.success
    eps = r.values["thickness"]
    assert 0.0 < eps < 0.1 and r.stderr["thickness"] < 0.5 * eps
    assert r.misfit["vp"] < 0.1 and r.misfit["vs"] < 0.1
    assert r.misfit["vp"] < r.misfit_initial["vp"]
    # The misfit is a true minimum: a small step either way is worse.
    for step in (-0.1, 0.1):
        v = predict(table1, 2, eps * (1 + step), stiffness)
        worse = np.sum((v.vp * 1000 / table1.vp - 1) ** 2 + (v.vs * 1000 / table1.vs - 1) ** 2)
        best = np.sum(table1.size and (r.predicted["vp"] * 1000 / table1.vp - 1) ** 2
                      + (r.predicted["vs"] * 1000 / table1.vs - 1) ** 2)
        assert worse > best


def test_fit_parameters_recovers_known_values(rng):
    """Synthetic data from known parameters are recovered (a line through noise-free points)."""
    x = np.linspace(1, 2, 20)
    obs = {"y": 3.0 + 0.5 * x}
    r = fit_parameters(lambda a, b: {"y": a + b * x}, obs, {"a": (1.0, 0.0, 10.0),
                                                           "b": (1.0, -5.0, 5.0)})
    assert r.values["a"] == pytest.approx(3.0, rel=1e-8)
    assert r.values["b"] == pytest.approx(0.5, rel=1e-8)
    assert r.misfit["y"] < 1e-10


@pytest.mark.parametrize("params,match", [
    ({"a": (5.0, 0.0, 1.0)}, "lower"),
    ({}, "at least one"),
])
def test_fit_parameters_bad_input(params, match):
    with pytest.raises(ValueError, match=match):
        fit_parameters(lambda **p: {"y": np.ones(3)}, {"y": np.ones(3)}, params)


def test_fit_contact_cement_unknown_parameter(table1):
    with pytest.raises(ValueError, match="free"):
        fit_contact_cement(GRAIN, CEMENT, table1.porosity, table1.density, 2.0, 1.2,
                           free={"coordination": (9, 5, 12)})
