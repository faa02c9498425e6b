"""md.calibrate: effective-medium parameters fitted to MD-like results and measurements.

The expected values are independent of the fit: synthetic data made by the model itself with
known parameters (recovered within the reported uncertainty, misfit zero for exact data), the
Xu 2023 Table 1 fit of rockcem.calibrate.fit_contact_cement, and the closed forms of the cement
radius.
"""

import json
import subprocess
import sys
import tomllib

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from md.calibrate import (MODELS, as_mineral, calibrate, calibrate_identified, total_error,
                          write_calibration)
from rockcem.calibrate import fit_contact_cement, fit_parameters, load_calibration
from rockcem.elastic import velocities
from rockcem.granular import cement_radius, contact_cement, patchy_cement
from rockcem.materials import mineral

GRAIN, HARD = mineral("quartz_garcia_medina"), mineral("hard_cement")
SAT = np.array([0.0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2])


def md_like(model="contact_cement", n=(5.0, 7.0), phi0=(0.39, 0.386), stress=(0.01, 12.0),
            scheme=1, noise=0.0, rng=None, **params):
    """An MD-scene-like Dataset (sample x saturation) whose vp is the model's, with eq. 11-like
    errors of 5 % and optional relative noise."""
    vp, porosity, density = [], [], []
    for ni, p0, s in zip(n, phi0, stress):
        phi = p0 * (1 - SAT)
        rho = (1 - p0) * GRAIN.rho + (p0 - phi) * HARD.rho
        if model == "contact_cement":
            eta = params.get("cement_efficiency", 1.0)
            m = contact_cement(GRAIN.K, GRAIN.G, HARD.K, HARD.G, p0 - eta * (p0 - phi), p0, ni,
                               scheme, params.get("thickness", 0.0))
        else:
            m = patchy_cement(GRAIN.K, GRAIN.G, HARD.K, HARD.G, phi, p0, ni, s, p0 - phi,
                              params.get("contact_cement_limit", 0.05), scheme, 0.0, 1.0,
                              params.get("delta", 0.0))
        v = velocities(m.K, m.G, rho).vp
        if noise:
            v = v * (1 + noise * rng.standard_normal(v.shape))
        vp.append(v)
        porosity.append(phi)
        density.append(rho)
    vp = np.array(vp)
    return xr.Dataset(
        {"vp": (("sample", "saturation"), vp), "vp_error": (("sample", "saturation"), 0.05 * vp),
         "porosity": (("sample", "saturation"), np.array(porosity)),
         "density": (("sample", "saturation"), np.array(density)),
         "porosity_uncemented": ("sample", list(phi0)),
         "coordination_number": ("sample", list(n)), "stress": ("sample", list(stress))},
        coords={"sample": ["loose", "compacted"], "saturation": SAT},
        attrs={"title": "synthetic MD-like results"})


# --- recovery of known parameters ---------------------------------------------------------------
@pytest.mark.parametrize("scheme", [1, 2])
def test_recovers_coordination_number_from_exact_data(scheme):
    data = md_like(scheme=scheme)
    truth = data.coordination_number.values
    fit = calibrate(data.drop_vars("coordination_number"), grain=GRAIN, cement=HARD,
                    scheme=scheme)
    np.testing.assert_allclose(fit.value.sel(parameter="coordination_number"), truth,
                               rtol=1e-6)
    assert float(fit.misfit.max()) < 1e-8 and bool(fit.success.all())
    assert float(fit.stderr.sel(parameter="coordination_number").max()) < 1e-6
    # CCT describes cemented contacts: the uncemented point is left out of the fit.
    assert not fit.used.sel(saturation=0.0).any() and fit.used.sel(saturation=0.1).all()
    assert int(fit.n_points.sel(sample="loose")) == 6


def test_recovers_mcct_thickness_and_efficiency_from_exact_data():
    data = md_like(thickness=0.03, cement_efficiency=0.4)
    fit = calibrate(data, free=["thickness", "cement_efficiency"], grain=GRAIN, cement=HARD)
    np.testing.assert_allclose(fit.value.sel(parameter="thickness"), 0.03, rtol=1e-5)
    np.testing.assert_allclose(fit.value.sel(parameter="cement_efficiency"), 0.4, rtol=1e-5)
    # n was held at the data's coordination number and is reported so.
    np.testing.assert_array_equal(fit.value.sel(parameter="coordination_number"), [5.0, 7.0])
    assert list(fit.fitted.values) == [False, True, True]
    assert "coordination_number" in fit.attrs["held_json"]


def test_recovers_patchy_cement_within_uncertainty(rng):
    """Noisy patchy-cement data (1 % relative noise, errors given as 1 %): the fitted n and
    phi_p0 lie within three standard errors of the truth, and chi2/dof is near 1."""
    data = md_like("patchy_cement", n=(6.0, 8.0), noise=0.01, rng=rng,
                   contact_cement_limit=0.03)
    data["vp_error"] = 0.01 * data.vp
    fit = calibrate(data, "patchy_cement", free=["coordination_number",
                                                 "contact_cement_limit"],
                    grain=GRAIN, cement=HARD, absolute_errors=True)
    for name, truth in (("coordination_number", [6.0, 8.0]), ("contact_cement_limit", 0.03)):
        err = np.abs(fit.value.sel(parameter=name) - truth) / fit.stderr.sel(parameter=name)
        assert float(err.max()) < 3.0, (name, fit.value.sel(parameter=name).values)
    red = fit.chi2 / fit.dof
    assert float(red.min()) > 0.1 and float(red.max()) < 4.0
    # Patchy cement holds Hertz-Mindlin: the uncemented point enters the fit.
    assert fit.used.all()


# --- weights ------------------------------------------------------------------------------------
def test_weights_discount_a_bad_point():
    """One corrupted point with a large error bar barely moves the weighted fit; the relative
    (unweighted) fit is pulled off."""
    data = md_like()
    data["vp"][1, 3] *= 1.5
    data["vp_error"][1, 3] = 100.0
    weighted = calibrate(data, grain=GRAIN, cement=HARD)
    plain = calibrate(data, grain=GRAIN, cement=HARD, errors=None)
    n_w = float(weighted.value.sel(sample="compacted", parameter="coordination_number"))
    n_p = float(plain.value.sel(sample="compacted", parameter="coordination_number"))
    assert abs(n_w - 7.0) < 1e-4 < abs(n_p - 7.0)
    assert "vp_error" in weighted.attrs["weights"] and "relative" in plain.attrs["weights"]


def test_weights_scale_of_the_errors(rng):
    """Scaling all errors by 3 leaves the fit and its scaled error unchanged and multiplies the
    absolute error by 3 (chi2 by 1/9)."""
    data = md_like(noise=0.02, rng=rng)
    a = calibrate(data, grain=GRAIN, cement=HARD, absolute_errors=True)
    big = data.assign(vp_error=3 * data.vp_error)
    b = calibrate(big, grain=GRAIN, cement=HARD, absolute_errors=True)
    c = calibrate(big, grain=GRAIN, cement=HARD)
    d = calibrate(data, grain=GRAIN, cement=HARD)
    np.testing.assert_allclose(a.value, b.value, rtol=1e-6)
    np.testing.assert_allclose(b.stderr, 3 * a.stderr, rtol=1e-4)
    np.testing.assert_allclose(c.stderr, d.stderr, rtol=1e-4)
    np.testing.assert_allclose(b.chi2, a.chi2 / 9, rtol=1e-4)


def test_fit_parameters_errors_line_fit():
    """Weighted straight line: the errors of intercept and slope are those of the normal
    equations, sqrt(diag((X^T W X)^-1)) with absolute errors."""
    x = np.linspace(1.0, 3.0, 9)
    sigma = 0.1 * x
    y = 2.0 + 0.5 * x + np.array([1, -1, 1, -1, 1, -1, 1, -1, 1]) * 0.3 * sigma
    r = fit_parameters(lambda a, b: {"y": a + b * x}, {"y": y}, {"a": (1.0, -10.0, 10.0),
                                                                "b": (1.0, -10.0, 10.0)},
                       errors={"y": sigma}, absolute_errors=True)
    X = np.stack([np.ones_like(x), x], axis=1) / sigma[:, None]
    expect = np.linalg.lstsq(X, y / sigma, rcond=None)[0]
    cov = np.linalg.inv(X.T @ X)
    assert r.values["a"] == pytest.approx(expect[0], rel=1e-7)
    assert r.values["b"] == pytest.approx(expect[1], rel=1e-7)
    assert r.stderr["a"] == pytest.approx(np.sqrt(cov[0, 0]), rel=1e-5)
    assert r.stderr["b"] == pytest.approx(np.sqrt(cov[1, 1]), rel=1e-5)
    assert r.dof == 7 and not any(r.at_bound.values())


@pytest.mark.parametrize("kw,match", [
    ({"errors": {"z": np.ones(3)}}, "errors"),
    ({"errors": {"y": np.zeros(3)}}, "errors"),
    ({"absolute_errors": True}, "needs errors"),
])
def test_fit_parameters_bad_errors(kw, match):
    with pytest.raises(ValueError, match=match):
        fit_parameters(lambda a: {"y": a * np.ones(3)}, {"y": np.ones(3)},
                       {"a": (1.0, 0.0, 2.0)}, **kw)


# --- the same routine on measurements -----------------------------------------------------------
def test_xu2023_table1_same_fit_as_fit_contact_cement():
    from rockcem._data import data_path

    t = pd.read_csv(data_path("measurements", "xu2023_table1.csv"), comment="#")
    grain, cement = mineral("quartz_han_guo"), mineral("epoxy_kaolinite")
    data = xr.Dataset({"vp": ("sample", t.vp.values / 1000), "vs": ("sample", t.vs.values / 1000),
                       "porosity": ("sample", t.porosity.values),
                       "density": ("sample", t.density.values)},
                      attrs={"critical_porosity": 0.4})
    fit = calibrate(data, free=["thickness"], fixed={"coordination_number": 8.5},
                    grain=grain, cement=cement, scheme=2)
    ref = fit_contact_cement(grain, cement, t.porosity, t.density, t.vp / 1000, t.vs / 1000,
                             scheme=2)
    assert fit.value.dims == ("parameter",)                    # one joint fit
    assert float(fit.value.sel(parameter="thickness")) == pytest.approx(
        ref.values["thickness"], rel=1e-9)
    assert float(fit.stderr.sel(parameter="thickness")) == pytest.approx(
        ref.stderr["thickness"], rel=1e-6)
    for k in ("vp", "vs"):
        assert float(fit.misfit.sel(observed=k)) == pytest.approx(ref.misfit[k], rel=1e-9)
    np.testing.assert_allclose(fit.vp_model, ref.predicted["vp"], rtol=1e-12)


# --- bonded-contact results (a/R, h/R grids) ----------------------------------------------------
@pytest.mark.parametrize("scheme", [1, 2])
@pytest.mark.parametrize("eps", [0.0, 0.03])
def test_radius_porosity_inverts_cement_radius(scheme, eps):
    """The porosity md.calibrate uses for bonded data (rockcem.granular.cement_porosity)."""
    from rockcem.granular import cement_porosity

    alpha = np.linspace(0.05, 0.55, 11)
    phi = cement_porosity(alpha, 0.4, 6.0, scheme, eps)
    np.testing.assert_allclose(cement_radius(phi, 0.4, 6.0, scheme, eps), alpha, rtol=1e-12)


def test_bonded_contact_moduli_fit():
    """A part-1-like Dataset (K, G over a/R x h/R, materials in attributes): n recovered."""
    alpha = np.array([0.3, 0.4, 0.5, 0.55])
    eps = np.array([0.01, 0.03, 0.05])
    A, E = np.meshgrid(alpha, eps, indexing="ij")
    y = A**2 * (A**2 / 4 + E)                                   # cement_radius inverted, n = 6
    phi = 0.38 - 0.75 * 6.0 * y * (1 - 0.38)
    m = contact_cement(GRAIN.K, GRAIN.G, HARD.K, HARD.G, phi, 0.38, 6.0, 1, E)
    data = xr.Dataset(
        {"K": (("radius_ratio", "thickness_ratio"), m.K),
         "G": (("radius_ratio", "thickness_ratio"), m.G),
         "porosity": 0.38, "coordination_number": 4.0},
        coords={"radius_ratio": alpha, "thickness_ratio": eps},
        attrs={"grain_K": GRAIN.K, "grain_G": GRAIN.G, "cement_K": HARD.K, "cement_G": HARD.G})
    fit = calibrate(data)
    assert float(fit.value.sel(parameter="coordination_number")) == pytest.approx(6.0, rel=1e-6)
    assert float(fit.misfit.max()) < 1e-8
    assert fit.K_model.dims == ("radius_ratio", "thickness_ratio")
    with pytest.raises(ValueError, match="radius_ratio"):
        calibrate(data, free=["cement_efficiency"])


# --- the Dataset --------------------------------------------------------------------------------
def test_dataset_layout_and_netcdf_round_trip(tmp_path):
    data = md_like().expand_dims(cement=["hard"])
    fit = calibrate(data, free=["coordination_number", "thickness"], grain=GRAIN, cement=HARD)
    assert fit.value.dims == ("cement", "sample", "parameter")
    assert fit.covariance.dims == ("cement", "sample", "cov_i", "cov_j")
    assert list(fit.cov_i.values) == ["coordination_number", "thickness"]
    assert fit.vp_model.dims == fit.vp.dims == ("cement", "sample", "saturation")
    assert list(fit.parameter_units.values) == ["1", "1", "1"]
    assert fit.attrs["calibration_model"] == "contact_cement" and fit.attrs["scheme"] == 1
    assert fit.attrs["grain_G"] == GRAIN.G and "GarciaMedina2007" in fit.attrs["references"]
    path = tmp_path / "fit.nc"
    fit.to_netcdf(path, engine="netcdf4")
    xr.testing.assert_identical(xr.load_dataset(path, engine="netcdf4"), fit)


def test_as_mineral_converts_md_materials():
    """md's SI materials (Tables I-II of García & Medina) equal the catalogue entries."""
    from md import HARD_CEMENT, QUARTZ, SOFT_CEMENT

    for md_mat, name in ((QUARTZ, "quartz_garcia_medina"), (HARD_CEMENT, "hard_cement"),
                         (SOFT_CEMENT, "soft_cement")):
        got, want = as_mineral(md_mat), mineral(name)
        assert (got.K, got.G, got.rho) == pytest.approx((want.K, want.G, want.rho), rel=1e-12)
    with pytest.raises(ValueError, match="grain"):
        as_mineral(3.0, "grain")


def test_import_md_calibrate_is_light():
    code = ("import sys, md.calibrate; "
            "print(','.join(m for m in ('rockcem', 'xarray', 'scipy.optimize') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


# --- bad input ----------------------------------------------------------------------------------
BAD = [
    ({"model": "soft_sand"}, "model"),
    ({"free": ["coordination"]}, "free parameter 'coordination'"),
    ({"free": []}, "at least one"),
    ({"fixed": {"coordination_number": 5.0}}, "fixed parameter"),
    ({"scheme": 3}, "scheme"),
    ({"observed": ["vs"]}, "observed"),
    ({"errors": {"vp": "vp_err"}}, "errors"),
    ({"each": ["depth"]}, "each"),
    ({"stiffness": "exact"}, "stiffness"),
    ({"free": {"coordination_number": (30.0, 2.0, 20.0)}}, "lower"),
    ({"model": "patchy_cement", "free": ["delta"], "pressure": -1.0}, "pressure"),
    ({"critical_porosity": 1.5}, "critical_porosity"),
]


@pytest.mark.parametrize("kw,match", BAD)
def test_bad_input(kw, match):
    with pytest.raises(ValueError, match=match):
        calibrate(md_like(), **{"grain": GRAIN, "cement": HARD, **kw})


@pytest.mark.parametrize("drop,match", [
    ("density", "density"), ("porosity", "porosity"),
    ("porosity_uncemented", "critical_porosity"), ("stress", "pressure"),
])
def test_missing_data(drop, match):
    with pytest.raises(ValueError, match=match):
        calibrate(md_like().drop_vars(drop), "patchy_cement", free=["delta"], grain=GRAIN,
                  cement=HARD)


def test_missing_materials_and_too_few_points():
    with pytest.raises(ValueError, match="grain"):
        calibrate(md_like())
    one = md_like().isel(saturation=[0, 1])
    with pytest.raises(ValueError, match="usable points"):
        calibrate(one, free=["coordination_number", "thickness"], grain=GRAIN, cement=HARD)


# --- calibration files --------------------------------------------------------------------------
def test_write_calibration_round_trip(tmp_path):
    data = md_like(thickness=0.02)
    fit = calibrate(data, free=["thickness"], grain=GRAIN, cement=HARD)
    path = write_calibration(fit, tmp_path / "cal.toml", sample="compacted", description="t")
    cal = load_calibration(path)
    assert cal["name"] == "cal" and cal["model"] == "contact_cement"
    assert cal["parameters"] == {"coordination_number": 7.0,
                                 "thickness": pytest.approx(0.02, rel=1e-6), "scheme": 1}
    assert set(cal["uncertainty"]) == {"thickness"} and "vp" in cal["misfit"]
    assert "sample = compacted" in cal["data"]
    raw = tomllib.loads(path.read_text())
    assert raw["fit"]["grain"] == "quartz_garcia_medina" and raw["fit"]["points"] == 6
    with pytest.raises(ValueError, match="select one fit"):
        write_calibration(fit, tmp_path / "x.toml")
    with pytest.raises(ValueError, match="selection"):
        write_calibration(fit, tmp_path / "x.toml", sample="medium")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cal.toml"]


def test_models_table_is_consistent():
    for model, table in MODELS.items():
        for name, (default, start, lo, hi, _unit, _doc) in table.items():
            assert lo <= default <= hi and lo <= start <= hi, (model, name)


def _stiff_bonded_fit(alpha, phic):
    """The coordination number a contact-cement fit with a generous bound (2, 60) gives to
    stiff bonded data (cement radius ratios ``alpha``): the best n lies beyond every cap."""
    import xarray as xr

    import md

    K = np.array([40.0, 45.0, 50.0])
    ds = xr.Dataset({"K": ("radius_ratio", K), "G": ("radius_ratio", K * 1.1),
                     "porosity": ("radius_ratio", np.full(3, 0.35)),
                     "porosity_uncemented": ((), phic)},
                    coords={"radius_ratio": alpha},
                    attrs={"grain_K": 37.7, "grain_G": 44.0, "cement_K": 15.0,
                           "cement_G": 8.0})
    fit = md.calibrate.calibrate(ds, "contact_cement",
                                 free={"coordination_number": (9.0, 2.0, 60.0)},
                                 observed=["K", "G"])
    return float(fit.value.sel(parameter="coordination_number"))


def test_bonded_fit_keeps_n_where_the_cement_fits():
    """Bonded data (cement radius given): the upper bound of a free coordination number is cut
    where eq. 7 of Han & Guo would need more cement than the pore space holds, so a fit with
    a generous bound ends inside the admissible range instead of failing on phi < 0."""
    alpha = np.array([0.6, 0.65, 0.7])
    phic = 0.40
    n_max = np.min(phic / ((1 - phic) * 0.75 * alpha**2 * (0.25 * alpha**2)))
    assert n_max < 20.0                           # below the models' own largest n
    n = _stiff_bonded_fit(alpha, phic)
    assert 0.9 * n_max < n <= n_max


def test_free_coordination_number_stays_within_the_models_range():
    """A generous bound (2, 60) on n is cut at the models' largest coordination number
    (rockcem.granular.MAX_COORDINATION_NUMBER), so a fit that wants more stops there instead
    of failing inside the model."""
    from rockcem.granular import MAX_COORDINATION_NUMBER

    n = _stiff_bonded_fit(np.array([0.5, 0.55, 0.6]), 0.40)    # cement room up to n = 27
    assert 0.9 * MAX_COORDINATION_NUMBER < n <= MAX_COORDINATION_NUMBER


# --- identifiability and the full-size study ----------------------------------------------------
def test_a_parameter_without_leverage_is_flagged():
    """phi_p0 confined to [0.1, 0.4] while the data's cement fractions stay below 0.08: the
    model caps the contact cement at min(phi_p, phi_p0) = phi_p, so the prediction does not
    depend on phi_p0 at all (checked on the model itself), and the fit flags it; n, which
    moves Vp, is not flagged in a fit of its own."""
    data = md_like("patchy_cement", n=(6.0, 8.0))
    phip = (data.porosity_uncemented - data.porosity).values
    assert phip.max() < 0.1
    lo, hi = (patchy_cement(GRAIN.K, GRAIN.G, HARD.K, HARD.G, data.porosity.values[1], 0.386,
                            8.0, 12.0, phip[1], limit) for limit in (0.1, 0.4))
    np.testing.assert_array_equal(lo.K, hi.K)
    fit = calibrate(data, "patchy_cement", free={"coordination_number": (7.0, 2.0, 20.0),
                                                 "contact_cement_limit": (0.2, 0.1, 0.4)},
                    grain=GRAIN, cement=HARD)
    assert fit.unidentifiable.sel(parameter="contact_cement_limit").all()
    assert np.isinf(fit.stderr.sel(parameter="contact_cement_limit")).all()
    alone = calibrate(data, "patchy_cement", free=["coordination_number"], grain=GRAIN,
                      cement=HARD)
    assert not alone.unidentifiable.any()
    np.testing.assert_allclose(alone.value.sel(parameter="coordination_number"), [6.0, 8.0],
                               rtol=1e-6)
    assert alone.correlation.dims == ("sample", "cov_i", "cov_j")


FULL_SAT = np.array([0.0, 0.02, 0.05, 0.1, 0.2])


def full_like(rng, saturation=FULL_SAT, n=6.0, limit=0.05, noise=0.01):
    """A Dataset of the full study's schema (md.experiment.run_md_scene with resolution_check:
    sample x cement x scheme x saturation) whose vp is the patchy-cement model's at
    coordination number ``n`` (compacted; n - 1.5 loose) and contact-cement limit ``limit``,
    with relative noise; eq. 11 errors 0.8 % and resolution errors 0.6 % of vp (1 % together),
    0 at S_c = 0 as in the study."""
    sat = np.asarray(saturation, dtype=float)
    samples, cements, schemes = ["loose", "compacted"], ["hard", "soft"], \
        ["contact", "coating", "pore_body"]
    phi0, stress, coord = np.array([0.39, 0.386]), np.array([0.01, 30.0]), [n - 1.5, n]
    cem = {"hard": HARD, "soft": mineral("soft_cement")}
    shape = (2, 2, 3, sat.size)
    vp, rho = np.empty(shape), np.empty(shape)
    for (i, j, k) in np.ndindex(shape[:3]):
        c, phi = cem[cements[j]], phi0[i] * (1 - sat)
        rho[i, j, k] = (1 - phi0[i]) * GRAIN.rho + (phi0[i] - phi) * c.rho
        m = patchy_cement(GRAIN.K, GRAIN.G, c.K, c.G, phi, phi0[i], coord[i], stress[i],
                          phi0[i] - phi, limit, 1 if k == 0 else 2)
        vp[i, j, k] = velocities(m.K, m.G, rho[i, j, k]).vp
    dims = ("sample", "cement", "scheme", "saturation")
    observed = vp * (1 + noise * rng.standard_normal(shape))
    res = np.where(sat > 0, 0.006 * vp, 0.0)
    return xr.Dataset(
        {"vp": (dims, observed), "vp_error": (dims, 0.008 * vp),
         "vp_error_resolution": (dims, res), "vp_resolution_check": (dims, observed + res),
         "wall_time": (dims, np.full(shape, 60.0)), "vp_fit": (dims, observed),
         "vp_static": (dims, vp), "density": (dims, rho),
         "porosity": (("sample", "saturation"), np.outer(phi0, 1 - sat)),
         "porosity_uncemented": ("sample", phi0), "coordination_number": ("sample", coord),
         "stress": ("sample", stress), "stress_mean": ("sample", 0.8 * stress)},
        coords={"sample": samples, "cement": cements, "scheme": schemes, "saturation": sat},
        attrs={"title": "synthetic full-size MD study", "scene_name": "synthetic"})


def test_total_error_adds_the_resolution_error_in_quadrature(rng):
    data = full_like(rng)
    total = total_error(data)
    np.testing.assert_allclose(total, np.sqrt(data.vp_error**2 + data.vp_error_resolution**2),
                               rtol=1e-14)
    np.testing.assert_allclose(total.sel(saturation=0.0), data.vp_error.sel(saturation=0.0))
    assert total.name == "vp_error_total" and "quadrature" in total.attrs["long_name"]
    xr.testing.assert_equal(total_error(data.drop_vars("vp_error_resolution")).drop_attrs(),
                            data.vp_error.rename("vp_error_total").drop_attrs())
    with pytest.raises(ValueError, match="vs_error"):
        total_error(data, "vs")


SHIP = {"sample": "compacted", "cement": "hard", "scheme": "contact"}
PATCHY = dict(free=["coordination_number", "contact_cement_limit"],
              hold={"contact_cement_limit": 0.05}, reason="the rockcem default",
              grain=GRAIN, cement=HARD, scheme=1, errors={"vp": "vp_error_total"},
              absolute_errors=True)


def test_full_study_fit_holds_phi_p0_the_data_cannot_see(rng, tmp_path):
    """Saturations up to 0.1 (cement fractions <= 0.039) and phi_p0 = 0.05: no point reaches
    the cap, phi_p0 is flagged in the two-parameter fit, held at 0.05 and n fitted alone is
    recovered within its error; the calibration file records all of it."""
    data = full_like(rng, saturation=FULL_SAT[:4])
    data["vp_error_total"] = total_error(data)
    fit = calibrate_identified(data.sel(SHIP), "patchy_cement", **PATCHY)
    ident = json.loads(fit.attrs["identifiability_json"])
    assert ident["unidentifiable"] == ["contact_cement_limit"]
    assert ident["held"] == {"contact_cement_limit": 0.05}
    assert list(fit.cov_i.values) == ["coordination_number"]
    n, err = (float(fit[v].sel(parameter="coordination_number")) for v in ("value", "stderr"))
    assert abs(n - 6.0) < 3 * err and 0 < err < 0.5
    # The first fit gave n the error of the fit with phi_p0 held: the same as the re-fit's.
    assert ident["stderr"]["coordination_number"] == pytest.approx(err, rel=1e-3)
    assert not fit.unidentifiable.any()
    assert float(fit.value.sel(parameter="contact_cement_limit")) == 0.05
    path = write_calibration(fit, tmp_path / "cal.toml")
    cal = load_calibration(path)
    assert set(cal["uncertainty"]) == {"coordination_number"}
    assert cal["parameters"]["contact_cement_limit"] == 0.05
    assert "(sample = compacted, cement = hard, scheme = contact)" in cal["data"]
    assert cal["identifiability"]["held"] == ["contact_cement_limit"]
    assert cal["identifiability"]["reason"] == "the rockcem default"
    raw = tomllib.loads(path.read_text())
    assert "contact_cement_limit (held: unidentifiable)" in raw["fit"]["held"]
    assert raw["fit"]["unidentifiable"] == []


def test_full_study_fit_keeps_phi_p0_the_data_determine(rng, tmp_path):
    """Saturations up to 0.2 and phi_p0 = 0.03: the two highest points lie past the cap, both
    parameters are determined and recovered within three errors, nothing is held."""
    data = full_like(rng, limit=0.03)
    data["vp_error_total"] = total_error(data)
    fit = calibrate_identified(data.sel(SHIP), "patchy_cement", **PATCHY)
    ident = json.loads(fit.attrs["identifiability_json"])
    assert ident["unidentifiable"] == [] and ident["held"] == {}
    for name, truth in (("coordination_number", 6.0), ("contact_cement_limit", 0.03)):
        value, err = (float(fit[v].sel(parameter=name)) for v in ("value", "stderr"))
        assert abs(value - truth) < 3 * err, (name, value, err)
    r = ident["correlation"]["coordination_number/contact_cement_limit"]
    assert r == pytest.approx(float(fit.correlation[0, 1]))
    cal = load_calibration(write_calibration(fit, tmp_path / "cal.toml"))
    assert cal["identifiability"]["unidentifiable"] == []
    assert set(cal["uncertainty"]) == {"coordination_number", "contact_cement_limit"}


def test_calibrate_identified_bad_input(rng):
    data = full_like(rng)
    one = data.sel(SHIP)
    kw = {k: v for k, v in PATCHY.items() if k not in ("hold", "errors")}
    with pytest.raises(ValueError, match="select one label"):
        calibrate_identified(data.sel(cement="hard", scheme="contact"), "patchy_cement",
                             hold={}, **kw)
    with pytest.raises(ValueError, match="not free"):
        calibrate_identified(one, "patchy_cement", hold={"delta": 0.0}, **kw)
    with pytest.raises(ValueError, match="hold"):
        calibrate_identified(one, "patchy_cement", hold={"contact_cement_limit": 0.9}, **kw)
