"""Sobol' sensitivity indices of uncertain scene inputs (``[uncertain] sensitivity = true``,
rockcem._uncertain): against the closed form of an additive output, the invariants of an
input an output does not depend on, and the section's refusals."""

import copy
import json
import warnings

import numpy as np
import pytest

import rockcem._uncertain as uncertain
from rockcem.scene import load_scene, run_scene, scene_from_dict

GRADIENT_SD, SURFACE_SD = 3.0, 2.0          # degC/km, degC
#: Largest error of an index at N = 256 over 20 seeds (0..19) and 7 depths: 0.028 (first
#: order), 0.021 (total); the tolerance leaves room above it.
TOL = 0.05

BASE = {
    "name": "sobol", "lithology": "sandstone", "outputs": ["temperature", "porosity"],
    "path": {"sedimentation_rate": 40.0, "max_depth": 3000.0, "depth_step": 500.0},
    "sandstone": {"porosity0": 0.36},
    "models": {"hs_gassmann": {}},
    "uncertain": {
        "samples": 256, "sensitivity": True, "seed": 7,
        "path.gradient": {"distribution": "normal", "mean": 30.0, "sd": GRADIENT_SD},
        "path.surface_temperature": {"distribution": "normal", "mean": 15.0,
                                     "sd": SURFACE_SD},
        "sandstone.grain_size": {"distribution": "lognormal", "median": 0.25, "sigma": 0.2},
    },
}


def scene(**changes):
    raw = copy.deepcopy(BASE)
    for key, value in changes.items():
        if value is None:
            raw["uncertain"].pop(key)
        else:
            raw["uncertain"][key] = value
    return scene_from_dict(raw)


@pytest.fixture(scope="module")
def ds():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_scene(scene())


def test_temperature_indices_match_the_closed_form(ds):
    # T(z) = T0 + G z (z in km): Var T = z^2 sd_G^2 + sd_T0^2, additive, so the gradient's
    # first-order and total indices are both z^2 sd_G^2 / Var T, the surface temperature's the rest.
    z = ds.depth.values / 1000.0
    share = (z * GRADIENT_SD) ** 2 / ((z * GRADIENT_SD) ** 2 + SURFACE_SD ** 2)
    for kind in ("first", "total"):
        s = ds[f"temperature_sobol_{kind}"]
        assert s.dims == ("input", "depth")
        np.testing.assert_allclose(s.sel(input="path.gradient"), share, atol=TOL)
        np.testing.assert_allclose(s.sel(input="path.surface_temperature"), 1.0 - share,
                                   atol=TOL)
        # the standard error (central limit theorem for independent rows) bounds the error:
        # over seeds 0..19 the error stayed below 0.35 of it on the Sobol' design
        se = ds[f"temperature_sobol_{kind}_se"]
        err = np.abs(s.sel(input=["path.gradient", "path.surface_temperature"])
                     - np.stack([share, 1.0 - share]))
        assert (err <= se.sel(input=["path.gradient", "path.surface_temperature"])
                + 1e-12).all()
        assert float(se.max()) < 0.15                  # at N = 256 (measured up to 0.12)
    # the estimator's first-order and total indices of an additive output agree
    np.testing.assert_allclose(ds.temperature_sobol_first, ds.temperature_sobol_total, atol=TOL)


def test_an_input_the_output_does_not_depend_on_has_zero_indices(ds):
    # changing only the grain size leaves the temperature unchanged member by member
    # (f(A_B) = f(A)), so both estimators vanish exactly; at the surface so does the gradient's
    for kind in ("first", "total"):
        s = ds[f"temperature_sobol_{kind}"]
        np.testing.assert_array_equal(s.sel(input="sandstone.grain_size"), 0.0)
        np.testing.assert_array_equal(ds[f"temperature_sobol_{kind}_se"].sel(
            input="sandstone.grain_size"), 0.0)
        assert s.sel(input="path.gradient", depth=0.0) == 0.0


def test_indices_undefined_where_the_output_does_not_vary(ds):
    # the porosity at the surface is porosity0 in every member
    for kind in ("first", "total"):
        s = ds[f"porosity_sobol_{kind}"]
        assert np.isnan(s.sel(depth=0.0)).all()
        assert np.isfinite(s.sel(depth=3000.0)).all()
        assert s.attrs["units"] == "1" and "N = 256" in s.attrs["description"]


def test_quantiles_come_from_the_two_independent_halves(ds):
    # 2N members of A and B: the median temperature at 3 km near 15 + 30 * 3
    assert ds.temperature.sel(quantile=0.5, depth=3000.0) == pytest.approx(105.0, abs=1.0)
    assert ds.attrs["uncertain"].startswith("512 members")
    assert json.loads(ds.attrs["uncertain_json"])["design"] == "sobol"
    assert list(ds.input.values) == ["path.gradient", "path.surface_temperature",
                                     "sandstone.grain_size"]


def test_cost_counts_the_whole_design(monkeypatch):
    # N (d + 2) = 256 * 5 members: the memory limit is checked on all of them before the work
    monkeypatch.setattr(uncertain, "MAX_UNCERTAIN_BYTES", 8 * 14 * 1000)
    with pytest.raises(ValueError, match="1280 members of 14 values"):
        run_scene(scene())


@pytest.mark.parametrize("changes, match", [
    ({"samples": 200}, r"samples = 200 with sensitivity = true.*power of two.*128 or 256"),
    ({"rank_correlations": [["path.gradient", "sandstone.grain_size", 0.3]]},
     "sensitivity = true does not apply with uncertain.rank_correlations.*independent"),
    ({"design": "lhs"}, "design = 'lhs' does not apply"),
    ({"members": True}, "sensitivity = true does not apply with uncertain.members"),
    ({"sensitivity": "yes"}, "uncertain.sensitivity must be true or false"),
])
def test_refused_by_name(changes, match):
    with pytest.raises(ValueError, match=match):
        scene(**changes)


def test_refused_beside_a_sweep():
    raw = copy.deepcopy(BASE)
    raw["sweep"] = {"sandstone.porosity0": [0.34, 0.36]}
    with pytest.raises(ValueError, match=r"sensitivity = true does not apply beside a \[sweep\]"):
        scene_from_dict(raw)


def test_no_output_with_indices_is_refused():
    raw = copy.deepcopy(BASE)
    raw["outputs"] = ["burial_time"]
    with pytest.raises(ValueError, match="sensitivity = true needs one of the outputs"):
        run_scene(scene_from_dict(raw))


def test_design_goes_through_the_truncated_distribution():
    # a gradient normal(30, 20) truncated at 0 (its valid range is (0, top]): the inverse
    # CDF the Saltelli design maps through is scipy's truncnorm
    from scipy.stats import truncnorm

    s = scene(**{"path.gradient": {"distribution": "normal", "mean": 30.0, "sd": 20.0,
                                   "truncate": True}})
    entry = s.uncertain["keys"]["path.gradient"]
    low, top = entry["range"][:2]
    u = np.linspace(0.01, 0.99, 25)
    expected = truncnorm.ppf(u, (low - 30.0) / 20.0, (top - 30.0) / 20.0, loc=30.0, scale=20.0)
    np.testing.assert_allclose(uncertain._TruncatedInverse(entry).ppf(u), expected, rtol=1e-10)


def test_max_members_counts_the_sobol_design():
    """With sensitivity the run is N (d + 2) members: 16 x (3 + 2) = 80 is over a limit of 64
    that N alone (16) is under."""
    scene = load_scene("carcione2022_sandstone_uncertain").replace(
        **{"uncertain.samples": 16, "uncertain.sensitivity": True, "uncertain.design": "sobol"})
    d = len(scene.uncertain["keys"])
    with pytest.raises(ValueError, match=rf"has {16 * (d + 2)} members \(16 x \({d} inputs "
                                         r"\+ 2\) for the Sobol' indices"):
        run_scene(scene, max_members=64)
