"""A scene with [uncertain] against a well (issue 32, item 6): the share of a log inside the
quantile band per interval (``well_misfit``, ``rockcem compare``), the band drawn under the
log (``plots.well_band``), and ``fit`` with the scene's distributions as priors (a maximum a
posteriori estimate).

The Datasets and logs are built by hand, their band edges linear in depth, and the expected
counts are counted by hand from the offsets planted in each log sample; the MAP checks compare
with the closed form of a linear-Gaussian model and with a brute-force minimisation of the
same objective on a grid."""

import numpy as np
import pytest

from rockcem.variables import build_dataset
from rockcem.wells import well_misfit

Z = np.array([0.0, 1000.0, 2000.0, 3000.0])
Q = [0.1, 0.5, 0.9]


def _band_dataset(quantiles=Q):
    """vp of models a and b and a density, on quantile x depth: model a's quantile 0.1 is
    2 + z/1000 km/s, its median 0.2 and its quantile 0.9 0.4 above; model b 1 km/s above a.
    Density (no model) 2.0 + 1e-4 z, 2.1 + 1e-4 z, 2.2 + 1e-4 z g/cm3."""
    offsets = {0.1: 0.0, 0.5: 0.2, 0.9: 0.4, 0.3: 0.1}
    a = np.stack([2.0 + 1e-3 * Z + offsets[q] for q in quantiles])            # (q, depth)
    vp = np.stack([a, a + 1.0], axis=1)                                     # (q, model, depth)
    density = np.stack([2.0 + 1e-4 * Z + offsets[q] / 2.0 for q in quantiles])
    return build_dataset({"vp": (("quantile", "model", "depth"), vp),
                          "density": (("quantile", "depth"), density)},
                         {"quantile": (("quantile",), list(quantiles)),
                          "model": (("model",), ["a", "b"]), "depth": (("depth",), Z)},
                         {"scene_name": "band"})


# Log depths and the offset of each sample above model a's quantile 0.1 (2 + z/1000): the band
# is 0 <= offset <= 0.4 (edges included); NaN a blank sample; 3500 m lies below the scene.
LOG_Z = np.array([250.0, 500.0, 750.0, 1000.0, 1250.0, 1750.0, 2000.0, 2250.0, 2750.0, 3000.0,
                  3500.0])
OFFSET = np.array([0.1, 0.5, np.nan, 0.0, -0.1, 0.3, 0.4, np.nan, 0.2, 0.45, np.nan])
#                  in   out  blank  edge  out   in   edge  blank  in   out   outside


def _well():
    vp = 2.0 + 1e-3 * LOG_Z + OFFSET
    vp[LOG_Z == 2000.0] = 2.4 + 1e-3 * 2000.0       # on the upper edge as the scene writes it
    density = 2.05 + 1e-4 * LOG_Z                   # inside its band everywhere
    return build_dataset({"vp": (("depth",), vp), "density": (("depth",), density)},
                         {"depth": (("depth",), LOG_Z)}, {"well": "HAND-1"})


def test_coverage_counted_by_hand_per_interval_and_model():
    table = well_misfit(_band_dataset(), _well(), intervals=[0.0, 1500.0, 3000.0])
    vp = table[table.variable == "vp"].set_index(["model", "top"])
    # [0, 1500): 250 in, 500 out, 750 blank, 1000 on the lower edge (in), 1250 out.
    assert vp.loc[("a", 0.0), "n_band"] == 4 and vp.loc[("a", 0.0), "blank"] == 1
    assert vp.loc[("a", 0.0), "inside"] == 2 / 4
    # [1500, 3000]: 1750 in, 2000 on the upper edge (in), 2250 blank, 2750 in, 3000 out;
    # 3500 m (below the scene, blank) is in no interval.
    assert vp.loc[("a", 1500.0), "n_band"] == 4 and vp.loc[("a", 1500.0), "blank"] == 1
    assert vp.loc[("a", 1500.0), "inside"] == 3 / 4
    # Model b's band is 1 km/s above: no sample inside.
    assert (vp.xs("b", level="model")["inside"] == 0.0).all()
    assert set(table.band) == {"0.1-0.9"}
    dens = table[table.variable == "density"]
    assert dens.model.tolist() == ["-", "-"] and (dens.inside == 1.0).all()
    assert dens.blank.tolist() == [0, 0]
    # The misfit is the median's (0.2 above quantile 0.1), over the same valid samples.
    z, o = LOG_Z[:5], (2.0 + 1e-3 * LOG_Z + OFFSET)[:5]
    ok = np.isfinite(o)
    rel = (2.2 + 1e-3 * z[ok]) / o[ok] - 1.0
    assert vp.loc[("a", 0.0), "n"] == 4
    np.testing.assert_allclose(vp.loc[("a", 0.0), ["rms", "bias"]].to_numpy(dtype=float),
                               [np.sqrt(np.mean(rel ** 2)), rel.mean()], rtol=1e-12)


def test_blank_samples_below_the_scene_are_not_counted():
    """One interval over the depths both cover (250-3000 m): the blank sample at 3500 m lies
    outside it; the two blanks inside are counted once each."""
    row = well_misfit(_band_dataset(), _well(), variables=["vp"]).iloc[0]
    assert (row.model, row.n_band, row.blank) == ("a", 8, 2)
    assert row.inside == 5 / 8
    # An interval reaching below the scene (0-4000 m): the blank at 3500 m has no band to be
    # compared with and is not counted either.
    row = well_misfit(_band_dataset(), _well(), variables=["vp"],
                      intervals=[0.0, 4000.0]).iloc[0]
    assert (row.n_band, row.blank, row.inside) == (8, 2, 5 / 8)


def test_band_choice_and_refusals():
    ds = _band_dataset([0.1, 0.3, 0.5, 0.9])
    # quantile 0.3 sits 0.1 above 0.1: the 0.1-0.3 band holds offsets 0 to 0.1 only
    # (250: 0.1 on its edge, 1000: 0.0), of the 8 valid samples.
    row = well_misfit(ds, _well(), variables=["vp"], band=(0.1, 0.3)).iloc[0]
    assert row.band == "0.1-0.3" and row.inside == 2 / 8
    with pytest.raises(ValueError, match=r"band quantile 0.2 is not a quantile .* 0.1, 0.3, "):
        well_misfit(ds, _well(), band=(0.1, 0.2))
    with pytest.raises(ValueError, match="band must be two quantiles LOW < HIGH"):
        well_misfit(ds, _well(), band=(0.9, 0.1))
    with pytest.raises(ValueError, match=r"the median, quantile 0.5 is not a quantile"):
        well_misfit(ds.sel(quantile=[0.1, 0.9]), _well())
    plain = ds.sel(quantile=0.5, drop=True)
    assert "inside" not in well_misfit(plain, _well()).columns       # no band: as before
    with pytest.raises(ValueError, match="band 0.1 0.9 needs a scene Dataset with quantiles"):
        well_misfit(plain, _well(), band=(0.1, 0.9))


def test_band_figure_draws_the_band_the_median_and_the_log():
    import matplotlib.pyplot as plt

    from rockcem import plots

    ds, well = _band_dataset(), _well()
    fig = plots.well_band(ds, well, models=["a"])
    try:
        ax_vp, ax_rho = fig.axes
        bands = {c.get_gid(): c for c in ax_vp.collections}
        assert set(bands) == {"band:vp:a"}                       # model b not asked for
        xy = bands["band:vp:a"].get_paths()[0].vertices
        for z in Z:                                              # the edges at each depth
            x = xy[np.isclose(xy[:, 1], z), 0]
            np.testing.assert_allclose([x.min(), x.max()], [2.0 + 1e-3 * z, 2.4 + 1e-3 * z],
                                       rtol=1e-14)
        lines = {line.get_gid(): line for line in ax_vp.lines}
        np.testing.assert_allclose(lines["median:vp:a"].get_xdata(), 2.2 + 1e-3 * Z)
        np.testing.assert_allclose(lines["median:vp:a"].get_ydata(), Z)
        np.testing.assert_array_equal(lines["well:vp"].get_xdata(), well.vp.values)
        assert lines["well:vp"].get_zorder() > lines["median:vp:a"].get_zorder() \
            > bands["band:vp:a"].get_zorder()                   # the log over the band
        assert {c.get_gid() for c in ax_rho.collections} == {"band:density:-"}
        rho = {line.get_gid(): line for line in ax_rho.lines}
        np.testing.assert_allclose(rho["median:density:-"].get_xdata(), 2.1 + 1e-4 * Z)
        assert ax_vp.get_ylim() == (3500.0, 0.0)                 # depth down, both ranges
    finally:
        plt.close(fig)
    with pytest.raises(ValueError, match="model 'c' is not in the scene Dataset"):
        plots.well_band(ds, well, models=["c"])
    with pytest.raises(ValueError, match="well_band needs a scene Dataset with quantiles"):
        plots.well_band(ds.sel(quantile=0.5, drop=True), well)


@pytest.fixture
def band_files(tmp_path):
    from rockcem.scene import write_dataset

    nc = write_dataset(_band_dataset(), tmp_path / "band.nc")
    well = _well()
    csv = tmp_path / "w.csv"
    rows = ["DEPT (m),VP (km/s),RHOB (g/cm3)"]
    for z, v, r in zip(LOG_Z, well.vp.values, well.density.values):
        rows.append(f"{z:.1f},{'' if np.isnan(v) else repr(float(v))},{float(r)!r}")
    csv.write_text("\n".join(rows) + "\n")
    return nc, csv


def test_cli_compare_prints_and_writes_the_band(tmp_path, band_files, capsys):
    import pandas as pd

    from rockcem.cli import main

    nc, csv = band_files
    out_csv, png = tmp_path / "table.csv", tmp_path / "band.png"
    assert main(["compare", str(nc), "--well", str(csv), "--intervals", "0", "1500", "3000",
                 "-o", str(out_csv), "--figure", str(png)]) == 0
    out = capsys.readouterr().out
    assert "the 0.1-0.9 quantile band of the members" in out and "about 80 %" in out
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.split()[:1] == ["variable"])
    assert lines[head].split()[:11] == ["variable", "model", "top", "base", "n", "rms", "bias",
                                        "band", "n_band", "inside", "blank"]
    first = lines[head + 1].split()
    assert first[:4] == ["vp", "a", "0", "1500"] and first[7:11] == ["0.1-0.9", "4", "0.5000",
                                                                    "1"]
    written = pd.read_csv(out_csv)
    assert written.columns.tolist()[:11] == lines[head].split()[:11]
    a = written[(written.variable == "vp") & (written.model == "a")]
    assert a.inside.tolist() == [0.5, 0.75] and a.blank.tolist() == [1, 1]
    assert written[written.variable == "density"].inside.tolist() == [1.0, 1.0]
    assert png.stat().st_size > 0 and f"wrote {png}" in out
    # plot --well draws the band too (was: "--well needs one member: select ... quantile").
    assert main(["plot", str(nc), "--well", str(csv), "-o", str(tmp_path / "p.png"),
                 "-q"]) == 0
    assert (tmp_path / "p.png").stat().st_size > 0


def test_cli_band_on_a_dataset_without_quantiles_one_line(tmp_path, band_files, capsys):
    from rockcem.cli import main
    from rockcem.scene import write_dataset

    nc, csv = band_files
    plain = write_dataset(_band_dataset().sel(quantile=0.5, drop=True), tmp_path / "plain.nc")
    for args in ([str(plain), "--band", "0.1", "0.9"],
                 [str(nc), "--band", "0.1", "0.7"],
                 [str(nc), "--interface", "1000", "--band", "0.1", "0.9"]):
        assert main(["compare", *args, "--well", str(csv), "-q"]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rockcem: error:"), err
    assert main(["compare", str(plain), "--band", "0.1", "0.9", "--well", str(csv), "-q"]) == 2
    assert "--band 0.1 0.9: " in capsys.readouterr().err


# ------------------------------------------------------------------ fit with priors (MAP)
SIGMA = 0.01            # the porosity log's noise, fraction
LOG_DEPTHS = np.arange(300.0, 1500.0, 20.0)


def _with_uncertain(scene, key, entry):
    """``scene`` with ``key`` uncertain (``entry``: its [uncertain] table)."""
    from rockcem.scene import scene_from_dict

    raw = scene._raw()
    section, _, name = key.rpartition(".")
    raw[section].pop(name, None)
    raw["uncertain"] = {"samples": 10, key: entry}
    return scene_from_dict(raw, base_dir=scene.base_dir)


@pytest.fixture(scope="module")
def porosity_case():
    """A porosity log made from the sandstone (100 m steps) at porosity0 = 0.36 plus noise of
    SIGMA, 300-1480 m (no quartz cement above 75 degC, where the porosity is linear in
    porosity0: checked), and the forward model there: ``m0`` at 0.36, slope ``J``."""
    import warnings

    from rockcem.scene import load_scene, run_scene
    from rockcem.synthetic_well import synthetic_well

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 100.0})
        runs = {p: run_scene(scene.replace(**{"sandstone.porosity0": p}))
                for p in (0.34, 0.36, 0.38)}
    at = {p: np.interp(LOG_DEPTHS, ds.depth.values, ds.porosity.values)
          for p, ds in runs.items()}
    well = synthetic_well(runs[0.36], LOG_DEPTHS, sigma={"porosity": SIGMA}, seed=7)
    # Linear in porosity0 near 0.36: the second difference over steps of 0.02 is below 3e-7,
    # so over the 0.013 the priors below move the answer the model leaves its tangent by
    # < 1.3e-7 (1e-5 of the log's noise): the closed forms of a linear-Gaussian model hold.
    curvature = at[0.38] - 2.0 * at[0.36] + at[0.34]
    assert np.max(np.abs(curvature)) < 3e-7
    return scene, well, at[0.36], (at[0.38] - at[0.34]) / 0.04


def _closed_form(well, m0, J, mean=None, sd=None):
    """Least squares (no prior) or the posterior mode and sd of porosity0 for the linear model
    m0 + J (x - 0.36), Gaussian noise SIGMA and a normal prior (mean, sd):
    x = (A x_LS + mean/sd^2) / (A + 1/sd^2), A = sum(J^2)/SIGMA^2."""
    o = well.porosity.values
    A = np.sum(J ** 2) / SIGMA ** 2
    x_ls = 0.36 + np.sum(J * (o - m0)) / np.sum(J ** 2)
    if mean is None:
        return x_ls, 1.0 / np.sqrt(A)
    return (A * x_ls + mean / sd ** 2) / (A + 1.0 / sd ** 2), 1.0 / np.sqrt(A + 1.0 / sd ** 2)


def _fit(scene, well, **kw):
    import warnings

    from rockcem.wellfit import fit_scene

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = fit_scene(scene, well, ["sandstone.porosity0"], variables=["porosity"],
                        errors={"porosity": SIGMA}, **kw)
    return fit.result.values["sandstone.porosity0"], fit.result.stderr["sandstone.porosity0"], \
        fit


def test_map_with_a_weak_prior_is_the_least_squares_answer(porosity_case):
    scene, well, m0, J = porosity_case
    x_ls, s_ls = _closed_form(well, m0, J)
    got_ls, err_ls, _ = _fit(scene, well)
    assert abs(got_ls - x_ls) < 2e-7 and err_ls == pytest.approx(s_ls, rel=1e-4)
    weak = _with_uncertain(scene, "sandstone.porosity0", {
        "distribution": "normal", "mean": 0.40, "sd": 5.0, "truncate": True})
    x_map, _ = _closed_form(well, m0, J, 0.40, 5.0)
    assert abs(x_map - x_ls) < 1e-8                 # the weak prior moves it by 3e-9
    got, err, fit = _fit(weak, well, prior=True)
    assert abs(got - x_ls) < 2e-7 and err == pytest.approx(s_ls, rel=1e-4)
    assert "normal(mean 0.4, sd 5) on [0.2, 1)" in fit.summary()     # 1 excluded
    assert fit.result.values.keys() == {"sandstone.porosity0"}


def test_map_with_a_tight_prior_far_from_the_truth_is_pulled_by_the_closed_form(porosity_case):
    scene, well, m0, J = porosity_case
    x_ls, s_ls = _closed_form(well, m0, J)
    mean, sd = x_ls + 10.0 * s_ls, s_ls / 2.0     # 10 standard errors away, 4x as tight
    x_map, s_map = _closed_form(well, m0, J, mean, sd)
    assert x_map - x_ls == pytest.approx(0.8 * (mean - x_ls), rel=1e-12)    # 4/(1 + 4)
    tight = _with_uncertain(scene, "sandstone.porosity0",
                            {"distribution": "normal", "mean": mean, "sd": sd})
    got, err, fit = _fit(tight, well, prior=True)
    assert abs(got - x_map) < 2e-7 and err == pytest.approx(s_map, rel=1e-3)
    assert "maximum a posteriori" in fit.weights


def test_map_with_a_triangular_prior_matches_a_grid_minimisation(porosity_case):
    """A prior whose support starts above the data's answer (triangular 0.365, 0.39, 0.42):
    the objective 1/2 sum(((m - o)/SIGMA)^2) - ln p, its density written out by hand, minimised
    on a grid of 1e-8 in porosity0."""
    scene, well, m0, J = porosity_case
    a, c, b = 0.365, 0.39, 0.42
    x = np.arange(a + 1e-8, c, 1e-8)
    o = well.porosity.values
    r0 = m0 - 0.36 * J - o                       # residual = r0 + J x, expanded
    data = 0.5 * (np.sum(r0 ** 2) + 2.0 * x * np.sum(r0 * J) + x ** 2 * np.sum(J ** 2)) \
        / SIGMA ** 2
    density = 2.0 * (x - a) / ((b - a) * (c - a))          # rising side of the triangle
    objective = data - np.log(density)
    k = np.argmin(objective)
    tri = _with_uncertain(scene, "sandstone.porosity0",
                          {"distribution": "triangular", "lower": a, "mode": c, "upper": b})
    got, err, fit = _fit(tri, well, prior=True)
    # The optimiser stops on a relative change of 1e-8 in the objective (least_squares' ftol in
    # rockcem.calibrate.fit_parameters): within 3e-7 here, 1e-3 of the standard error.
    assert abs(got - x[k]) < 0.005 * err
    assert np.interp(got, x, objective) - objective[k] < 1e-6
    assert a < got < a + 0.001                  # held off the data's answer by the prior


def test_map_with_a_lognormal_prior_matches_a_grid_minimisation(porosity_case):
    """lognormal(median 0.38, sigma 0.005): -ln p = ln x + (ln x - ln 0.38)^2 / (2 0.005^2) + c,
    minimised with the data's term on a grid of 1e-5, then of 1e-9 around its minimum."""
    scene, well, m0, J = porosity_case
    o = well.porosity.values

    def objective(x):
        r = (m0[:, None] + J[:, None] * (x - 0.36) - o[:, None]) / SIGMA
        return 0.5 * np.sum(r ** 2, axis=0) + np.log(x) \
            + (np.log(x) - np.log(0.38)) ** 2 / (2.0 * 0.005 ** 2)

    x = np.arange(0.30, 0.45, 1e-5)
    x = np.arange(x[np.argmin(objective(x))] - 2e-5, x[np.argmin(objective(x))] + 2e-5, 1e-9)
    x_grid = x[np.argmin(objective(x))]
    prior = _with_uncertain(scene, "sandstone.porosity0",
                            {"distribution": "lognormal", "median": 0.38, "sigma": 0.005})
    got, err, _ = _fit(prior, well, prior=True)
    assert abs(got - x_grid) < 0.001 * err
    assert 0.3575 + 0.003 < got < 0.38 - 0.003   # between the data's answer and the prior's


def test_map_bounds_are_the_priors_range(porosity_case):
    """A uniform prior on 0.37-0.40, above the data's answer (0.3575): flat inside, so the
    estimate is its lower end, on the bound."""
    scene, well, _, _ = porosity_case
    uniform = _with_uncertain(scene, "sandstone.porosity0",
                              {"distribution": "uniform", "lower": 0.37, "upper": 0.40})
    got, _, fit = _fit(uniform, well, prior=True)
    assert got == pytest.approx(0.37, abs=1e-12) and fit.at_bound == ("sandstone.porosity0",)


def test_fit_of_an_uncertain_scene_holds_the_other_keys_at_their_medians():
    """Was: the fit ran and then failed on 'both set and uncertain'. The medians are those of
    the shipped distributions: normal 30 and 2.4, lognormal median 0.3, uniform 0-0.4 0.2,
    triangular 60-75-90 75."""
    from rockcem.scene import load_scene
    from rockcem.synthetic_well import synthetic_well

    scene = load_scene("carcione2022_sandstone_uncertain").replace(
        **{"path.depth_step": 100.0})
    plain = _band_dataset()      # any well: the porosity log of a known Dataset
    well = synthetic_well(plain.assign(porosity=0.3 - 0.0 * plain.density.sel(quantile=0.5)),
                          np.arange(500.0, 2000.0, 100.0), sigma={"porosity": 0.0})
    _, _, fit = _fit(scene, well)
    keys = ("path.gradient", "pressure.sediment_density", "sandstone.grain_size",
            "sandstone.clay_coating", "sandstone.start_temperature")
    medians = [30.0, 2.4, 0.3, 0.2, 75.0]
    np.testing.assert_allclose([fit.held[k] for k in keys], medians, rtol=1e-12)
    for scene_fitted in (fit.scene, fit.fitted):          # the scene the fit ran
        np.testing.assert_allclose([scene_fitted.sections[k.rpartition(".")[0]][
            k.rpartition(".")[2]] for k in keys], medians, rtol=1e-12)
        assert not scene_fitted.uncertain
    assert "uncertain keys held at their medians: path.gradient = 30" in fit.summary()
    with pytest.raises(ValueError, match=r"prior: none of the free parameters "
                                         r"\(sandstone.porosity0\) is uncertain"):
        _fit(scene, well, prior=True)


SCENE_TOML = """name = "band_fit"
lithology = "sandstone"

[path]
gradient = 30.0
sedimentation_rate = 40.0
max_depth = 2000.0
depth_step = 100.0

[uncertain]
samples = 10

[uncertain."sandstone.porosity0"]
distribution = "normal"
mean = 0.40
sd = 0.002
"""


def test_cli_fit_with_prior_and_its_refusals(tmp_path, capsys):
    from rockcem.cli import main

    scene = tmp_path / "band_fit.toml"
    scene.write_text(SCENE_TOML)
    well = tmp_path / "w.csv"
    z = np.arange(300.0, 1500.0, 100.0)
    well.write_text("DEPT (m),PHIT (v/v)\n" + "".join(
        f"{d:g},{0.36 * np.exp(-1e-4 * d):.6f}\n" for d in z))
    base = ["fit", str(scene), "--well", str(well), "--log", "porosity", "-o",
            str(tmp_path / "cal.toml"), "--figure", str(tmp_path / "fit.png")]
    assert main([*base, "--free", "sandstone.porosity0", "--prior", "--error",
                 "porosity=0.005", "-q"]) == 0
    assert "maximum a posteriori with priors sandstone.porosity0 normal(mean 0.4, sd 0.002)" \
        in (tmp_path / "cal.toml").read_text()
    for extra, says in (
            (["--free", "sandstone.porosity0", "--prior"], "--prior needs --error"),
            (["--free", "sandstone.porosity0=0.3:0.5", "--prior", "--error", "porosity=0.005"],
             "takes its bounds from its prior"),
            (["--free", "sandstone.beta", "--prior", "--error", "porosity=0.005"],
             "--prior: none of the free parameters")):
        assert main([*base, *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rockcem: error:") and says in err, err


def test_prior_bounds_of_the_shipped_distributions():
    """The bounds of each prior of the shipped scene: its valid range within the support; the
    lognormal's infinite upper end at its quantile 1 - 1e-12, 0.3 exp(0.3 z) with
    z = 7.034 (the normal's upper 1e-12 point); normal residuals (x - mean)/sd."""
    from scipy.stats import norm

    from rockcem.scene import load_scene
    from rockcem.wellfit import _prior

    keys = load_scene("carcione2022_sandstone_uncertain").uncertain["keys"]
    bounds = {k: _prior(e)[1] for k, e in keys.items()}
    assert bounds["sandstone.grain_size"][1] == pytest.approx(
        0.3 * np.exp(0.3 * norm.isf(1e-12)), rel=1e-9)
    assert bounds["sandstone.clay_coating"] == (0.0, 0.4)
    assert bounds["sandstone.start_temperature"] == (60.0, 90.0)
    assert 0.0 < bounds["path.gradient"][0] < 1e-300          # open at 0
    residual, _, text = _prior(keys["path.gradient"])
    assert text.endswith("on (0, 80.8333]")
    assert residual(35.0) == pytest.approx(2.0, rel=1e-12)    # (35 - 30)/2.5
    assert residual(27.5) == pytest.approx(-1.0, rel=1e-12)
    residual, _, _ = _prior(keys["sandstone.start_temperature"])
    # triangular 60-75-90: ln p(75) - ln p(66) = ln(15/6); r = -sqrt(2 ln 2.5)
    assert residual(66.0) == pytest.approx(-np.sqrt(2.0 * np.log(15.0 / 6.0)), rel=1e-12)


def test_cli_compare_outputs_checked_before_the_work(tmp_path, band_files, capsys):
    from rockcem.cli import main

    nc, csv = band_files
    (tmp_path / "folder").mkdir()
    for extra, says in ((["-o", str(tmp_path / "folder")], "-o"),
                        (["--figure", str(tmp_path / "x.xyz")], "--figure must end in .png"),
                        (["-o", str(tmp_path / "same.png"), "--figure",
                          str(tmp_path / "same.png")], "-o and --figure name the same file")):
        assert main(["compare", str(nc), "--well", str(csv), *extra]) == 2
        captured = capsys.readouterr()
        assert captured.err.count("\n") == 1 and says in captured.err, captured.err
        assert captured.out == ""                # refused before the well is read
    assert sorted(p.name for p in tmp_path.iterdir()) == ["band.nc", "folder", "w.csv"]
