"""Uncertain scene inputs ([uncertain], rockcem._uncertain): the checks of the section, the
sampled inputs, the members against the scene runner, and the quantiles against closed forms
within their sampling error."""

import copy
import warnings

import numpy as np
import pytest
from scipy import stats

from rockcem._uncertain import (evaluate_chunk, iman_conover, member_names,
                                quantile_standard_error, sample_inputs)
from rockcem._uncertain_keys import key_range
from rockcem.runner import evaluate
from rockcem.scene import load_scene, run_scene, scene_from_dict

#: A small sandstone scene: four models, 31 depths.
BASE = {
    "name": "small", "lithology": "sandstone",
    "path": {"sedimentation_rate": 40.0, "max_depth": 3000.0, "depth_step": 100.0},
    "sandstone": {"porosity0": 0.36},
    "models": {"hs_gassmann": {}, "self_consistent": {"aspect_ratio": 0.108},
               "generalized_gassmann": {}, "patchy_cement": {}},
}
GRADIENT = {"distribution": "normal", "mean": 30.0, "sd": 2.0}


def scene(uncertain, **changes):
    raw = copy.deepcopy(BASE)
    for dotted in uncertain:                 # an uncertain key is not set as well
        section, _, key = dotted.rpartition(".")
        if section.startswith("models.") and section[7:] in raw["models"]:
            raw["models"][section[7:]].pop(key, None)
        elif section in raw:
            raw[section].pop(key, None)
    for dotted, value in changes.items():
        *where, key = dotted.split(".")
        table = raw
        for part in where:
            table = table.setdefault(part, {})
        table[key] = value
    raw["uncertain"] = copy.deepcopy(uncertain)
    return scene_from_dict(raw)


def quiet_run(s, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return run_scene(s, **kw)


# --- the section's checks -------------------------------------------------------------------
@pytest.mark.parametrize("uncertain, match", [
    ({"samples": 8, "path.gradiant": GRADIENT}, "unknown uncertain key 'path.gradiant'.*"
                                                "path.gradient"),
    ({"samples": 8, "materials.grain": GRADIENT}, "'materials.grain' is not a number"),
    ({"samples": 8, "models.patchy_cement.scheme": GRADIENT}, "is not a number.*integer"),
    ({"samples": 8, "models.md.resolution": GRADIENT}, "MD keys are not sampled.*minutes"),
    ({"samples": 8, "path.depth_step": GRADIENT}, "depth axis"),
    ({"samples": 8, "path.gradient": {**GRADIENT, "sd": 0.0}}, r"path.gradient\"\.sd must be > 0"),
    ({"samples": 8, "path.gradient": {"distribution": "uniform", "lower": 30, "upper": 30}},
     r"lower \(30\) must be below upper"),
    ({"samples": 8, "path.gradient": {"distribution": "triangular", "lower": 20, "mode": 45,
                                      "upper": 40}}, "mode .* must lie in"),
    ({"samples": 8, "path.gradient": {"distribution": "gamma", "mean": 30}},
     "distribution must be one of"),
    ({"samples": 8, "path.gradient": {**GRADIENT, "spread": 1.0}}, "'spread' is not a parameter"),
    ({"samples": 8, "path.gradient": {"distribution": "normal", "mean": 30}}, "sd is missing"),
    ({"samples": 1000, "design": "sobol", "path.gradient": GRADIENT}, "use 512 or 1024"),
    ({"samples": 8, "design": "grid", "path.gradient": GRADIENT}, "design must be one of"),
    ({"samples": 1, "path.gradient": GRADIENT}, "samples must be an integer >= 2"),
    ({"samples": 8, "quantiles": [0.9, 0.1], "path.gradient": GRADIENT}, "increasing"),
    ({"samples": 8, "quantiles": [0.0, 0.5], "path.gradient": GRADIENT}, r"in \(0, 1\)"),
    ({"samples": 8, "seed": -1, "path.gradient": GRADIENT}, "seed must be an integer >= 0"),
    ({"samples": 8, "sample": 9, "path.gradient": GRADIENT}, "unknown scene key uncertain.sample"),
    ({"samples": 8}, "names no key"),
    ({"samples": 8, "path": {"gradient": GRADIENT}},
     r'quote the key, \[uncertain."path.gradient"\]'),
    ({"samples": 3, "path.gradient": GRADIENT, "sandstone.grain_size": GRADIENT,
      "rank_correlations": [["path.gradient", "sandstone.grain_size", 0.5]]},
     "need more than 3 members"),
    ({"samples": 8, "path.gradient": {"distribution": "normal", "mean": 30, "sd": 30}},
     r"puts 0.159 of its probability outside the valid range \(0, 161.667\] degC/km of "
     r"path.gradient.*truncate = true"),
    ({"samples": 8, "path.gradient": {"distribution": "uniform", "lower": -10, "upper": -5,
                                      "truncate": True}}, "wholly outside"),
    ({"samples": 8, "path.gradient": GRADIENT, "sandstone.grain_size": GRADIENT,
      "rank_correlations": [["path.gradient", "sandstone.clay_coating", 0.5]]},
     "'sandstone.clay_coating' is not an uncertain key"),
    ({"samples": 8, "path.gradient": GRADIENT, "sandstone.grain_size": GRADIENT,
      "rank_correlations": [["path.gradient", "sandstone.grain_size", 1.0]]}, r"in \(-1, 1\)"),
])
def test_bad_sections_are_refused_by_name(uncertain, match):
    with pytest.raises(ValueError, match=match):
        scene(uncertain)


def test_swept_set_and_absent_keys_are_refused():
    with pytest.raises(ValueError, match="path.gradient is both swept and uncertain"):
        scene({"samples": 8, "path.gradient": GRADIENT}, **{"sweep": {"path.gradient": [20.0]}})
    with pytest.raises(ValueError, match=r"path.gradient is both set \(30.0\) and uncertain"):
        scene({"samples": 8, "path.gradient": GRADIENT}, **{"path.gradient": 30.0})
    raw = copy.deepcopy(BASE)
    del raw["models"]["hs_gassmann"]
    raw["uncertain"] = {"samples": 8, "models.hs_gassmann.A": GRADIENT}
    with pytest.raises(ValueError, match="model 'hs_gassmann' is not in the scene's"):
        scene_from_dict(raw)
    with pytest.raises(ValueError, match="sedimentation_rate and path.heating_rate both given"):
        scene({"samples": 8, "path.heating_rate": {"distribution": "uniform", "lower": 0.5,
                                                   "upper": 1.5}})
    raw = copy.deepcopy(BASE)
    raw["models"]["md"] = {"count": 1}
    raw["uncertain"] = {"samples": 8, "path.gradient": GRADIENT}
    with pytest.raises(ValueError, match=r"\[models.md\].*minutes"):
        scene_from_dict(raw)


def test_members_above_max_members_are_refused_before_work():
    s = scene({"samples": 64, "path.gradient": GRADIENT})
    with pytest.raises(ValueError, match="64 members.*max_members = 10"):
        run_scene(s, max_members=10)


# The valid range of each key is the one the scene's evaluation checks a fixed value against:
# just outside it the scene run refuses the fixed value, at (or just inside) it the run goes.
RANGE_KEYS = ["path.gradient", "path.sedimentation_rate", "path.surface_temperature",
              "pressure.sediment_density", "pressure.water_density", "sandstone.porosity0",
              "sandstone.grain_size", "sandstone.quartz_fraction", "sandstone.clay_coating",
              "sandstone.igv_final",
              "sandstone.beta", "sandstone.start_temperature", "models.hs_gassmann.A",
              "models.self_consistent.aspect_ratio", "models.patchy_cement.coordination_number",
              "models.patchy_cement.delta", "models.patchy_cement.f",
              "models.patchy_cement.contact_cement_limit",
              "models.patchy_cement.thickness"]


@pytest.mark.parametrize("dotted", RANGE_KEYS)
def test_key_range_is_the_fixed_values_check(dotted):
    plain = scene_from_dict(copy.deepcopy(BASE))
    low, high, low_open, high_open, _unit = key_range(dotted, plain.sections)
    for end, is_open, outward in ((low, low_open, -np.inf), (high, high_open, np.inf)):
        if not np.isfinite(end):
            continue
        outside = end if is_open else np.nextafter(end, outward)
        outside = outside if end == 0 or is_open else end + np.sign(outward) * 1e-9 * max(
            abs(end), 1.0)
        inside = np.nextafter(end, -outward) if is_open else end
        with pytest.raises(ValueError):
            evaluate(plain.replace(**{dotted: float(outside)}))
        try:        # inside its range; another rule (Model 4's contact radius) may refuse it
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                evaluate(plain.replace(**{dotted: float(inside)}))
        except ValueError as exc:
            assert "must lie in" not in str(exc) and "contact model holds" in str(exc), exc


# --- the sampled inputs ---------------------------------------------------------------------
def test_latin_hypercube_puts_one_member_in_each_stratum():
    s = scene({"samples": 50, "seed": 4, "sandstone.clay_coating":
               {"distribution": "uniform", "lower": 0.0, "upper": 1.0}})
    x = sample_inputs(s.uncertain)["sandstone.clay_coating"]
    assert sorted(np.floor(x * 50).astype(int)) == list(range(50))


def test_truncated_normal_quantiles_are_scipy_truncnorm():
    """Truncated to the gradient's range (0, 161.7] at a 3000 m path (500 degC there), a
    normal(30, 30) is scipy's truncnorm; a Latin hypercube of 400 lands within a stratum."""
    s = scene({"samples": 400, "path.gradient": {"distribution": "normal", "mean": 30,
                                                 "sd": 30, "truncate": True}})
    x = sample_inputs(s.uncertain)["path.gradient"]
    top = (500.0 - 15.0) / 3.0
    assert x.min() > 0.0 and x.max() <= top
    exact = stats.truncnorm((0 - 30) / 30, (top - 30) / 30, loc=30, scale=30)
    p = (np.arange(400) + 0.5) / 400
    # each sorted member lies in its stratum [i/n, (i+1)/n] of the truncated distribution
    assert np.all(exact.cdf(np.sort(x)) - p <= 0.5 / 400 + 1e-12)
    assert np.all(p - exact.cdf(np.sort(x)) <= 0.5 / 400 + 1e-12)
    assert s.sections["path"]["gradient"] == pytest.approx(exact.median(), rel=1e-12)


def test_rank_correlation_imposed_and_marginals_kept():
    u = {"distribution": "uniform", "lower": 0.0, "upper": 0.5}
    base = {"samples": 2000, "seed": 7, "path.gradient": GRADIENT,
            "sandstone.clay_coating": u}
    plain = sample_inputs(scene(base).uncertain)
    paired = sample_inputs(scene({**base, "rank_correlations": [
        ["path.gradient", "sandstone.clay_coating", -0.6]]}).uncertain)
    for k in plain:
        assert np.array_equal(np.sort(plain[k]), np.sort(paired[k]))
    rho = stats.spearmanr(paired["path.gradient"], paired["sandstone.clay_coating"])[0]
    assert rho == pytest.approx(-0.6, abs=0.03)
    assert abs(stats.spearmanr(plain["path.gradient"], plain["sandstone.clay_coating"])[0]) < 0.06


def test_iman_conover_three_inputs():
    rng = np.random.default_rng(0)
    x = rng.random((3000, 3))
    target = np.array([[1.0, 0.5, -0.3], [0.5, 1.0, 0.2], [-0.3, 0.2, 1.0]])
    got = stats.spearmanr(iman_conover(x, target, rng)).statistic
    np.testing.assert_allclose(got, target, atol=0.03)


def test_sobol_design_runs_in_powers_of_two():
    s = scene({"samples": 64, "design": "sobol", "path.gradient": GRADIENT})
    x = sample_inputs(s.uncertain)["path.gradient"]
    assert x.shape == (64,) and len(np.unique(x)) == 64


# --- the members ----------------------------------------------------------------------------
#: Inputs of the rock state and of each model's parameters.
MANY = {"samples": 6, "seed": 11, "members": True,
        "path.gradient": GRADIENT,
        "sandstone.grain_size": {"distribution": "lognormal", "median": 0.3, "sigma": 0.3},
        "sandstone.clay_coating": {"distribution": "uniform", "lower": 0.0, "upper": 0.4},
        "sandstone.start_temperature": {"distribution": "triangular", "lower": 60, "mode": 75,
                                        "upper": 90},
        "pressure.sediment_density": {"distribution": "normal", "mean": 2.4, "sd": 0.05},
        "models.hs_gassmann.A": {"distribution": "uniform", "lower": 2.5, "upper": 3.5},
        "models.generalized_gassmann.A": {"distribution": "uniform", "lower": 2.5,
                                          "upper": 3.5},
        "models.self_consistent.aspect_ratio": {"distribution": "uniform", "lower": 0.08,
                                                "upper": 0.15},
        "models.patchy_cement.coordination_number": {"distribution": "uniform", "lower": 7,
                                                     "upper": 10},
        "models.patchy_cement.delta": {"distribution": "uniform", "lower": 40, "upper": 100}}


def test_members_are_the_scene_runs_of_their_inputs():
    """Each member of the Dataset is the scene run with its sampled inputs set as fixed values
    (Scene.replace, the whole scene validation), and the quantiles are those of the members."""
    s = scene(MANY)
    ds = quiet_run(s)
    assert ds["vp_members"].dims == ("member", "model", "depth")
    assert ds["vp"].dims == ("quantile", "model", "depth")
    assert list(ds["quantile"].values) == [0.1, 0.5, 0.9]
    assert ds["hs_gassmann_A"].dims == ("member",)
    names = member_names(s)
    for i in (0, 5):
        raw = copy.deepcopy(BASE)
        for dotted, name in names.items():
            *where, key = dotted.split(".")
            table = raw
            for part in where:
                table = table.setdefault(part, {})
            table[key] = float(ds[name].values[i])
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            one = evaluate(scene_from_dict(raw))
        for name in one.data_vars:
            np.testing.assert_allclose(ds[f"{name}_members"].values[i], one[name].values,
                                       rtol=1e-12, atol=1e-14, err_msg=name)
    np.testing.assert_allclose(ds["vs"].values, np.quantile(ds["vs_members"].values,
                                                            [0.1, 0.5, 0.9], axis=0))


def assert_together_is_one_by_one(s):
    """The chunk's models run on all (member, depth) points equal each member's own run."""
    from rockcem._uncertain import _evaluate_each

    values = sample_inputs(s.uncertain)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        together, w1 = evaluate_chunk(s, values)
        each, w2 = _evaluate_each(s, values, s.uncertain["samples"])
    assert together.keys() == each.keys()
    for name in together:
        np.testing.assert_allclose(together[name][1], each[name][1], rtol=1e-12, atol=1e-14,
                                   err_msg=name)
    assert w1 == w2


def test_members_together_equal_members_one_by_one():
    assert_together_is_one_by_one(scene(MANY))


def test_shale_members_together_equal_members_one_by_one():
    assert_together_is_one_by_one(scene_from_dict({
        "name": "shale", "lithology": "shale", "path": {"max_depth": 3000.0, "depth_step": 100.0},
        "models": {"hs_gassmann": {}, "self_consistent": {"aspect_ratio": 0.17}},
        "uncertain": {"samples": 5, "path.gradient": GRADIENT, "shale.r0": {
            "distribution": "uniform", "lower": 0.6, "upper": 0.99},
            "models.hs_gassmann.A": {"distribution": "uniform", "lower": 2.0, "upper": 4.0}}}))


def test_fluid_scene_runs_member_by_member():
    s = scene({"samples": 3, "path.gradient": GRADIENT, "fluid.salinity":
               {"distribution": "uniform", "lower": 0.0, "upper": 0.1}},
              **{"fluid.model": "batzle_wang"})
    ds = quiet_run(s)
    assert ds["fluid_density"].dims == ("quantile", "depth")
    assert np.all(np.diff(ds["fluid_density"].values[:, 10]) >= 0)


def test_member_out_of_a_models_range_is_named():
    """A member whose inputs are each in range but break a rule between keys (Model 4's contact
    cement limit 0.3 above the member's critical porosity) is refused, its inputs named."""
    s = scene({"samples": 4, "seed": 1, "sandstone.porosity0":
               {"distribution": "uniform", "lower": 0.25, "upper": 0.45}},
              **{"models.patchy_cement.contact_cement_limit": 0.3})
    with pytest.raises(ValueError, match=r"uncertain member \(sandstone.porosity0 = 0\.2\d+\)"
                                         r".*must not exceed critical_porosity"):
        quiet_run(s)


def test_validity_warnings_count_their_members():
    """The cement-overfill rule holds for the members whose own run says so."""
    u = {"samples": 12, "seed": 3, "members": True,
         "path.gradient": {"distribution": "uniform", "lower": 20.0, "upper": 45.0}}
    s = scene(u, **{"path.max_depth": 5000.0, "path.depth_step": 250.0,
                    "sandstone.porosity0": 0.36})
    ds = quiet_run(s)
    expect = 0
    for g in ds["gradient"].values:
        member = scene_from_dict({**copy.deepcopy(BASE), "path": {
            "sedimentation_rate": 40.0, "max_depth": 5000.0, "depth_step": 250.0,
            "gradient": float(g)}})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            text = evaluate(member).attrs.get("validity_warnings", "")
        expect += "overfill" in text
    assert 0 < expect < 12
    line = next(w for w in ds.attrs["validity_warnings"].split("\n") if "overfill" in w)
    assert line.startswith(f"[{expect} of 12 members; depths and values of member ")


def test_a_rule_whose_threshold_follows_the_members_is_one_line():
    """Krief's porosity limit is a fraction of each member's depositional porosity, so the
    members' lines differ in their numbers; they are one rule, counted over every member, and
    a different model's rule stays a line of its own."""
    u = {"samples": 6, "seed": 2,
         "sandstone.porosity0": {"distribution": "uniform", "lower": 0.36, "upper": 0.42}}
    ds = quiet_run(scene(u))
    lines = [w for w in ds.attrs["validity_warnings"].split("\n") if "Krief" in w]
    assert len(lines) == 1
    assert lines[0].startswith("[6 of 6 members; depths and values of member 0]")


def test_members_beside_a_sweep_are_refused():
    with pytest.raises(ValueError, match="members = true does not apply beside a"):
        scene({"samples": 4, "members": True, "path.gradient": GRADIENT},
              **{"sweep": {"sandstone.quartz_fraction": [0.6, 0.7]}})


def test_sweep_and_uncertain_compose():
    s = scene({"samples": 4, "path.gradient": GRADIENT},
              **{"sweep": {"sandstone.quartz_fraction": [0.6, 0.7]}})
    ds = quiet_run(s)
    assert ds["vp"].dims == ("quartz_fraction", "quantile", "model", "depth")
    one = quiet_run(scene({"samples": 4, "path.gradient": GRADIENT},
                          **{"sandstone.quartz_fraction": 0.7}))
    np.testing.assert_array_equal(ds["vp"].sel(quartz_fraction=0.7).values, one["vp"].values)


def test_written_and_read_back(tmp_path):
    from rockcem.scene import write_dataset

    xr = pytest.importorskip("xarray")
    s = scene({"samples": 4, "members": True, "path.gradient": GRADIENT})
    back = xr.load_dataset(write_dataset(quiet_run(s), tmp_path / "u.nc"))
    assert back["quantile"].attrs["long_name"] == "quantile of the members"
    assert "P90" in back["quantile"].attrs["description"]
    assert back["gradient"].attrs["units"] == "degC/km"
    again = scene_from_dict(__import__("tomllib").loads(s.text))
    assert again.uncertain == s.uncertain


# --- the estimator --------------------------------------------------------------------------
@pytest.mark.parametrize("design, n", [("random", 400), ("lhs", 200)])
def test_temperature_quantiles_match_the_closed_form(design, n):
    """T(z) = T0 + G z is linear in a normal G: its p-quantile is T0 + (mu + sd z_p) z. The
    estimate lies within 3 standard errors of a sample quantile (Walker 1968)."""
    s = scene({"samples": n, "design": design, "seed": 5, "path.gradient": GRADIENT},
              **{"outputs": ["temperature"]})
    ds = quiet_run(s)
    z = 2000.0
    q = np.array([0.1, 0.5, 0.9])
    exact = 15.0 + (30.0 + 2.0 * stats.norm.ppf(q)) * z / 1000.0
    got = ds["temperature"].sel(depth=z).values
    se = quantile_standard_error(q, n, stats.norm.pdf(stats.norm.ppf(q)) / (2.0 * z / 1000.0))
    assert np.all(np.abs(got - exact) < 3.0 * se), (got - exact) / se


def test_shipped_scene_loads_and_runs_small():
    s = load_scene("carcione2022_sandstone_uncertain")
    keys = set(s.uncertain["keys"])
    assert keys == {"path.gradient", "sandstone.grain_size", "sandstone.clay_coating",
                    "sandstone.start_temperature", "pressure.sediment_density"}
    small = s.replace(**{"uncertain.samples": 8, "path.depth_step": 500.0})
    ds = quiet_run(small)
    assert ds["vp"].shape == (3, 4, 13)
    assert np.all(np.diff(ds["vp"].values, axis=0) >= 0)       # P10 <= P50 <= P90


def test_chunks_on_dask_equal_the_serial_run():
    pytest.importorskip("dask.distributed")
    xr = pytest.importorskip("xarray")
    s = scene({"samples": 300, "path.gradient": GRADIENT},        # two chunks of members
              **{"path.depth_step": 500.0, "outputs": ["porosity", "vp"]})
    serial, on_dask = quiet_run(s), quiet_run(s, scheduler="local")
    xr.testing.assert_identical(serial.drop_attrs(), on_dask.drop_attrs())
    assert serial.attrs["validity_warnings"] == on_dask.attrs["validity_warnings"]


def test_horizon_histories_together_equal_one_by_one():
    """A table of horizon histories: each member's state is its horizons' present-day ends."""
    from rockcem.scene import read_scene_toml, scene_path

    raw, _ = read_scene_toml("synthetic_basin_horizons")
    del raw["sandstone"]["grain_size"]
    raw["uncertain"] = {"samples": 4, "sandstone.grain_size": {
        "distribution": "lognormal", "median": 0.3, "sigma": 0.3},
        "pressure.sediment_density": {"distribution": "uniform", "lower": 2.3, "upper": 2.5}}
    s = scene_from_dict(raw, base_dir=scene_path("synthetic_basin_horizons").parent)
    assert_together_is_one_by_one(s)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = evaluate(s)
    assert "horizon" in ds.coords and ds["vp"].dims == ("quantile", "model", "depth")


def test_run_summary_of_uncertain_members():
    """The summary names the members and inputs and prints each quantile of vp at the
    deepest depth as the Dataset holds it (not the quantile axis as a sweep)."""
    from rockcem.cli import _summary

    scene = load_scene("carcione2022_sandstone_uncertain").replace(
        **{"uncertain.samples": 8, "path.depth_step": 500.0})
    ds = run_scene(scene)
    text = _summary(ds)
    assert "sweep:" not in text
    assert text.splitlines()[1].startswith("uncertain: 8 members (lhs, seed 2022) of path.gradient")
    vp = ds["vp"].sel(model="patchy_cement").isel(depth=-1).values
    want = " / ".join(f"{float(x):.3f}" for x in vp)
    assert f"patchy_cement: vp {want}" in text
