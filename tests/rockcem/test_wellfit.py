"""Fitting a scene to well logs: recovery of known parameters, identifiability, calibration."""

import tomllib

import numpy as np
import pytest

from rockcem.runner import evaluate
from rockcem.scene import load_scene, run_scene, scene_from_dict
from rockcem.variables import build_dataset
from rockcem.wellfit import fit_scene
from rockcem.wells import well_misfit

TRUE = {"models.patchy_cement.coordination_number": 7.0, "models.patchy_cement.delta": 60.0}
SIGMA = {"vp": 0.05, "vs": 0.04, "density": 0.02}        # km/s, km/s, g/cm3


@pytest.fixture(scope="module")
def scene():
    raw = tomllib.loads(load_scene("carcione2022_sandstone").text)
    raw["path"].update(depth_step=20.0, max_depth=4000.0)
    raw["models"] = {"patchy_cement": raw["models"]["patchy_cement"]}
    return scene_from_dict(raw)


@pytest.fixture(scope="module")
def well(scene):
    """Synthetic logs: the scene at TRUE plus Gaussian noise of SIGMA, every 5 m."""
    ds = evaluate(scene.replace(**TRUE))
    rng = np.random.default_rng(20261125)
    z = np.arange(1000.0, 3800.0, 5.0)
    data = {}
    for v, s in SIGMA.items():
        clean = ds[v].sel(model="patchy_cement") if "model" in ds[v].dims else ds[v]
        data[v] = (("depth",), np.interp(z, ds.depth.values, clean.values)
                   + rng.normal(0.0, s, z.size))
    return build_dataset(data, {"depth": (("depth",), z)})


def test_fit_recovers_known_parameters_within_their_uncertainties(scene, well):
    fit = fit_scene(scene, well, list(TRUE), errors=SIGMA)
    r = fit.result
    assert r.success and not fit.unidentifiable and not fit.at_bound
    for k, true in TRUE.items():
        assert abs(r.values[k] - true) < 3.0 * r.stderr[k], (k, r.values[k], r.stderr[k])
        assert r.stderr[k] < 0.05 * true                # and the logs do constrain them
    # With the true errors the fit is statistically right: chi2/dof near 1.
    assert abs(r.chi2 / r.dof - 1.0) < 5.0 * np.sqrt(2.0 / r.dof)
    assert all(r.misfit[v] < r.misfit_initial[v] for v in ("vp", "vs"))
    assert fit.model == "patchy_cement" and fit.scene.models == ("patchy_cement",)
    # Only what the fit needs: density does not depend on the model's parameters.
    assert set(fit.scene.outputs) == {"vp", "vs"} and fit.variables == ("vp", "vs")


def _predictions_are_the_full_scene(fit, well):
    """The fit's predictions equal the full scene run at the fitted values."""
    full = evaluate(fit.fitted)
    for v in ("vp", "density"):
        model = full[v].sel(model="patchy_cement") if "model" in full[v].dims else full[v]
        np.testing.assert_allclose(fit.result.predicted[v],
                                   np.interp(well.depth.values, full.depth.values, model),
                                   rtol=1e-14)


def test_model_parameters_only_run_the_kinetics_once(scene, well, monkeypatch):
    import burial

    calls = []
    original = burial.quartz_cement
    monkeypatch.setattr(burial, "quartz_cement", lambda *a, **k: calls.append(1) or
                        original(*a, **k))
    fast = fit_scene(scene, well, list(TRUE), errors=SIGMA, variables=list(SIGMA))
    assert len(calls) == 1          # the rock state, shared by every trial
    # ... and the predictions are those of the full scene at the fitted values.
    _predictions_are_the_full_scene(fast, well)
    # Compaction keys leave the kinetics alone: computed once for the whole fit.
    before = len(calls)
    compaction = fit_scene(scene, well, [*TRUE, "sandstone.beta"], errors=SIGMA,
                           variables=list(SIGMA))
    assert len(calls) == before + 1 and compaction.result.success
    _predictions_are_the_full_scene(compaction, well)
    before = len(calls)
    slow = fit_scene(scene, well, ["sandstone.porosity0"], errors=SIGMA, variables=["density"])
    assert len(calls) > before + 5 and slow.result.success     # once per trial


def test_degenerate_parameters_are_reported_unidentifiable(scene, well):
    # The Walderhaug rate depends on quartz fraction and grain size only through f/D (eq. B.5).
    fit = fit_scene(scene, well, ["sandstone.grain_size", "sandstone.quartz_fraction"],
                    variables=["vp", "density"])
    assert set(fit.unidentifiable) == {"sandstone.grain_size", "sandstone.quartz_fraction"}
    assert abs(fit.correlation[0, 1]) > 0.999
    assert "UNIDENTIFIABLE" in fit.summary()


def test_parameter_the_logs_do_not_see(scene, well):
    # Density does not depend on the patchy-cement frame: that model is not even run.
    with pytest.raises(ValueError, match="belongs to a model the fitted logs"):
        fit_scene(scene, well, ["models.patchy_cement.delta"], variables=["density"])


def test_calibration_file_round_trip(scene, well, tmp_path):
    fit = fit_scene(scene, well, list(TRUE), errors=SIGMA, depth=(1500.0, 3500.0))
    assert fit.depth_range == (1500.0, 3500.0)
    path = fit.write_calibration(tmp_path / "cal.toml")
    raw = tomllib.loads(scene.text)
    raw["calibration"] = "cal.toml"
    for k in TRUE:                                       # the file sets them now
        del raw["models"]["patchy_cement"][k.rpartition(".")[2]]
    calibrated = scene_from_dict(raw, base_dir=tmp_path)
    for k, v in fit.result.values.items():
        section, _, key = k.rpartition(".")
        assert calibrated.sections[section][key] == v
    ds = run_scene(calibrated)
    assert "cal.toml" in ds.attrs["calibration"] or path.name in ds.attrs["calibration"]
    # Setting a calibrated key in the scene as well is refused.
    raw["models"]["patchy_cement"]["delta"] = 10.0
    with pytest.raises(ValueError, match="also set by calibration"):
        scene_from_dict(raw, base_dir=tmp_path)


def test_misfit_per_model_and_interval(scene, well):
    ds = run_scene(scene.replace(**TRUE))
    table = well_misfit(ds, well, intervals=[1000.0, 2000.0, 3800.0])
    vp = table[table.variable == "vp"]
    assert vp.model.tolist() == ["patchy_cement"] * 2 and vp.n.tolist() == [200, 360]
    # At the true parameters the misfit is the noise: rms of sigma/vp.
    z = well.depth.values
    for (_, row), sel in zip(vp.iterrows(), ((z < 2000), (z >= 2000))):
        expected = np.sqrt(np.mean((SIGMA["vp"] / well.vp.values[sel]) ** 2))
        assert abs(row.rms - expected) < 0.2 * expected
    assert table[table.variable == "density"].model.tolist() == ["-", "-"]


@pytest.mark.parametrize("free, message", [
    (["sandstone.nope"], "not a key of this scene"),
    (["models.patchy_cement.scheme"], "not numeric"),
    (["pressure.water_density"], "no default bounds"),
    ({"sandstone.beta": (0.1, 0.01)}, "need lower < upper"),
])
def test_bad_free_parameters(scene, well, free, message):
    with pytest.raises(ValueError, match=message):
        fit_scene(scene, well, free)


def test_scene_calibration_refusals(scene, tmp_path):
    from rockcem.calibrate import write_calibration

    write_calibration(tmp_path / "bad_key.toml", name="b", model="scene",
                      parameters={"sandstone.nope": 1.0})
    write_calibration(tmp_path / "model.toml", name="m", model="patchy_cement",
                      parameters={"delta": 1.0})
    write_calibration(tmp_path / "beta.toml", name="beta", model="scene",
                      parameters={"sandstone.beta": 0.02})
    raw = tomllib.loads(scene.text)
    for file, change, message in (
            ("bad_key.toml", {}, "'sandstone.nope' .* is not a numeric scene key"),
            ("model.toml", {}, r"calibrates model 'patchy_cement'; name it in "
                               r"\[models.patchy_cement\]"),
            ("beta.toml", {"sweep": {"sandstone.beta": [0.01, 0.02]}},
             "sweep sandstone.beta: that parameter is set by calibration 'beta'")):
        given = {**raw, **change, "calibration": file}
        given["sandstone"] = {k: v for k, v in raw["sandstone"].items() if k != "beta"}
        with pytest.raises(ValueError, match=message):
            scene_from_dict(given, base_dir=tmp_path)
    applied = scene_from_dict({**raw, "calibration": "beta.toml", "sandstone": {
        k: v for k, v in raw["sandstone"].items() if k != "beta"}}, base_dir=tmp_path)
    assert applied.sections["sandstone"]["beta"] == 0.02
    assert applied.calibrations["scene"]["name"] == "beta"



def test_relative_uncertainties_match_the_scatter_of_repeated_fits():
    """Without errors, each log is weighted by its own scatter: over independent noise
    realisations the spread of the fitted value equals the reported standard error. One
    variance pooled over a 2 % sonic and a 15 % porosity log (porosity does not depend on the
    Krief exponent) overstated the error about 5-fold, and weights from the noisy log itself
    biased the fit by most of a standard error."""
    raw = tomllib.loads(load_scene("carcione2022_sandstone").text)
    raw["path"].update(depth_step=100.0, max_depth=4000.0)
    raw["models"] = {"hs_gassmann": {"A": 3.0}}
    scene = scene_from_dict(raw)
    true = {"models.hs_gassmann.A": 2.5}
    ds = evaluate(scene.replace(**true))
    z = np.arange(1000.0, 3800.0, 20.0)
    clean = {v: np.interp(z, ds.depth.values, ds[v].values.squeeze())
             for v in ("vp", "vs", "porosity")}
    relative = {"vp": 0.02, "vs": 0.03, "porosity": 0.15}           # multiplicative noise
    rng = np.random.default_rng(7)
    values, errors = [], []
    for _ in range(40):
        logs = {v: (("depth",), clean[v] * (1.0 + rng.normal(0.0, s, z.size)))
                for v, s in relative.items()}
        fit = fit_scene(scene, build_dataset(logs, {"depth": (("depth",), z)}), list(true),
                        variables=list(relative))
        values.append(fit.result.values["models.hs_gassmann.A"])
        errors.append(fit.result.stderr["models.hs_gassmann.A"])
    spread = np.std(values, ddof=1)
    # 40 realisations: the sample standard deviation is good to about 11 % (one sigma).
    assert abs(spread / np.mean(errors) - 1.0) < 0.35, (spread, np.mean(errors))
    # Unbiased: the mean of 40 fits within 3 of its standard errors (the weights from the
    # noisy logs, m/o - 1, put it 0.75 of a single fit's standard error high).
    assert abs(np.mean(values) - 2.5) < 3.0 * spread / np.sqrt(40)


def test_non_positive_log_values_are_named(scene, well):
    bad = well.copy(deep=True)
    bad["density"].values[10] = 0.0
    with pytest.raises(ValueError, match=r"log density is 0 at 1050 m; the fit needs positive"):
        fit_scene(scene, bad, ["sandstone.beta"], variables=["density"])


def test_robust_uncertainties_when_the_scatter_is_not_a_fixed_fraction():
    """Sonic noise growing from 0.01 to 0.2 km/s with depth: relative weights are wrong
    within each log, and only the sandwich covariance (White 1980) gives the spread of
    repeated fits (the usual s^2 (J^T W J)^-1 overstated it 1.5-fold here)."""
    raw = tomllib.loads(load_scene("carcione2022_sandstone").text)
    raw["path"].update(depth_step=100.0, max_depth=4000.0)
    raw["models"] = {"hs_gassmann": {"A": 3.0}}
    scene = scene_from_dict(raw)
    ds = evaluate(scene.replace(**{"models.hs_gassmann.A": 2.5}))
    z = np.arange(1000.0, 3800.0, 20.0)
    clean = {v: np.interp(z, ds.depth.values, ds[v].values.squeeze()) for v in ("vp", "vs")}
    sd = {"vp": 0.01 + 0.2 * (z / 3800.0) ** 4, "vs": 0.01 + 0.15 * (z / 3800.0) ** 4}
    rng = np.random.default_rng(11)
    values, errors = [], []
    for _ in range(60):
        logs = {v: (("depth",), clean[v] + rng.normal(0.0, sd[v])) for v in clean}
        fit = fit_scene(scene, build_dataset(logs, {"depth": (("depth",), z)}),
                        ["models.hs_gassmann.A"])
        values.append(fit.result.values["models.hs_gassmann.A"])
        errors.append(fit.result.stderr["models.hs_gassmann.A"])
    assert "sandwich" in fit.weights
    # 60 realisations: the sample standard deviation is good to about 9 % (one sigma).
    assert abs(np.std(values, ddof=1) / np.mean(errors) - 1.0) < 0.25


def test_porosity_is_fitted_on_the_absolute_misfit_of_compare(scene):
    """The fit's porosity residual is compare's misfit, model - log (a fraction), not
    model/log - 1, which a few log samples near 0 porosity blow up: the fitted value minimises
    the rms porosity misfit that well_misfit reports, and the fit reports that misfit."""
    true = 0.03
    ds = evaluate(scene.replace(**{"sandstone.beta": true}))
    z = np.arange(1000.0, 3800.0, 5.0)
    log = np.interp(z, ds.depth.values, ds.porosity.values)
    log += np.random.default_rng(3).normal(0.0, 0.01, z.size)
    log[::100] = 0.002                                    # a few samples near 0 porosity
    well = build_dataset({"porosity": (("depth",), log)}, {"depth": (("depth",), z)})
    fit = fit_scene(scene, well, ["sandstone.beta"], variables=["porosity"])
    r = fit.result
    beta, err = r.values["sandstone.beta"], r.stderr["sandstone.beta"]
    assert r.success and abs(beta - true) < 3.0 * err

    def rms(b):
        table = well_misfit(evaluate(scene.replace(**{"sandstone.beta": b})), well,
                            intervals=list(fit.depth_range))
        return float(table.set_index("variable").rms["porosity"])

    # The fit minimises compare's misfit: a tenth of a standard error either way raises it.
    # (Relative residuals, the log's or the first model's, put beta about one error lower.)
    at = rms(beta)
    assert at < rms(beta - 0.1 * err) and at < rms(beta + 0.1 * err)
    # ... and reports it: rms of model - log, before and after (relative: 14.7 -> 12.1).
    assert r.misfit["porosity"] == pytest.approx(at, rel=1e-10)
    assert r.misfit["porosity"] < r.misfit_initial["porosity"] < 0.1
    assert "porosity model - log" in fit.summary() and "porosity model - log" in fit.weights
    # A log porosity of 0 (or a little below: a neutron log in a tight streak) is a fine
    # absolute misfit, and the fit takes it as compare does.
    zero = well.copy(deep=True)
    zero["porosity"].values[:2] = [0.0, -0.004]
    fit0 = fit_scene(scene, zero, ["sandstone.beta"], variables=["porosity"])
    table = well_misfit(evaluate(fit0.fitted), zero, intervals=list(fit0.depth_range))
    assert fit0.result.misfit["porosity"] == pytest.approx(
        float(table.set_index("variable").rms["porosity"]), rel=1e-10)
    assert np.isfinite(fit0.result.stderr["sandstone.beta"])
