"""`rockcem plot` on swept files (every member drawn, --select, one-line refusals) and the
validity warnings in the run summary."""

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

from rockcem import cli, plots
from rockcem.scene import run_scene, scene_from_dict, write_dataset

SWEPT = {"name": "t", "lithology": "sandstone",
         "path": {"max_depth": 3000.0, "depth_step": 250.0},
         "models": {"hs_gassmann": {}, "patchy_cement": {}},
         "sweep": {"path.gradient": [20.0, 30.0, 40.0], "sandstone.grain_size": [0.2, 0.4, 0.6]}}


@pytest.fixture(scope="module")
def swept_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("swept")
    write_dataset(run_scene(scene_from_dict(SWEPT)), folder / "s.nc")
    return folder / "s.nc"


def test_plot_refuses_nine_members_naming_the_dimension_and_select(swept_file, drawn, capsys):
    for kind in ("depth", "vp-porosity", "template"):
        assert cli.main(["plot", str(swept_file), "--kind", kind]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "9 (gradient 3 x grain_size 3)" in err, err
        assert "--select gradient=20" in err
    assert drawn == []


def test_plot_select_draws_every_remaining_member(swept_file, drawn, capsys):
    args = ["plot", str(swept_file), "--select", "sandstone.grain_size=0.4"]
    assert cli.main(args + ["--kind", "template"]) == 0
    panels = [ax for ax in drawn[-1].axes if ax.get_label() != "<colorbar>"]
    assert [ax.get_title() for ax in panels] == [f"gradient = {g} °C/km" for g in (20, 30, 40)]
    assert cli.main(args + ["--select", "gradient=20", "--select", "gradient=40"]) == 0
    vp = next(ax for ax in drawn[-1].axes if ax.get_xlabel().startswith("P-wave"))
    labels = [ln.get_label() for ln in vp.get_lines()]
    assert labels == [f"{m}, gradient = {g} °C/km" for m in (plots.MODEL_LABELS["hs_gassmann"],
                                                              plots.MODEL_LABELS["patchy_cement"])
                      for g in (20, 40)]
    assert cli.main(args + ["--select", "path.gradient=30", "--kind", "vp-porosity"]) == 0
    (ax,) = drawn[-1].axes
    assert len([ln for ln in ax.get_lines() if ln.get_gid().startswith("model:")]) == 2


@pytest.mark.parametrize("select, message", [
    ("porosity=0.2", "'porosity' is not a sweep dimension of the file (dimensions: gradient, "),
    ("gradient=25", "no such value of gradient (values: 20, 30, 40)"),
    ("gradient=warm", "'warm' is not a number"),
    ("gradient", "expected KEY=VALUE"),
])
def test_plot_select_errors_in_one_line(swept_file, drawn, capsys, select, message):
    assert cli.main(["plot", str(swept_file), "--select", select]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1, err


def test_run_summary_lists_the_validity_warnings():
    ds = run_scene(scene_from_dict(dict(SWEPT, sweep={}, path={"max_depth": 6000.0,
                                                                "depth_step": 100.0})))
    text = cli._summary(ds)
    loose = ds.depth.values[ds.porosity.values > 0.9 * 0.36]
    filled = ds.depth.values[ds.pore_filled.values == 1]
    assert loose[0] == 0.0 and filled[-1] == 6000.0
    assert (f"warning: Models 1 (Krief frame) at 0–{loose[-1]:g} m: porosity above 0.324"
            not in text)                                   # Model 3 is not in this scene
    assert f"warning: Model 1 (Krief frame) at 0–{loose[-1]:g} m: porosity above 0.324" in text
    assert f"warning: quartz cement at {filled[0]:g}–6000 m" in text
    assert np.all(np.diff(loose) == 100.0)                 # one interval from the surface


def test_plot_select_one_model_keeps_its_style_and_names_the_held_values(swept_file, drawn):
    args = ["plot", str(swept_file), "--select", "grain_size=0.4", "--select", "gradient=30"]
    assert cli.main(args + ["--select", "model=patchy_cement"]) == 0
    vp = next(ax for ax in drawn[-1].axes if ax.get_xlabel().startswith("P-wave"))
    (line,) = vp.get_lines()
    assert line.get_label() == plots.MODEL_LABELS["patchy_cement"]     # not a bare "vp"
    (held,) = drawn[-1].legends[1:]
    assert held.get_title().get_text() == ("Geothermal gradient: 30 °C/km; "
                                           "Grain diameter: 0.4 mm")


def test_plot_template_of_a_shale_file_refused_in_one_line(tmp_path, drawn, capsys):
    shale = {"name": "sh", "lithology": "shale", "models": {"hs_gassmann": {}},
             "path": {"max_depth": 2000.0, "depth_step": 500.0}}
    path = write_dataset(run_scene(scene_from_dict(shale)), tmp_path / "sh.nc")
    for kind in ("template", "vp-porosity"):
        assert cli.main(["plot", str(path), "--kind", kind]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "is not a sandstone scene" in err, err
    assert drawn == []
    ds = run_scene(scene_from_dict(shale))
    with pytest.raises(ValueError, match="shale scene: pass grain= and cement="):
        plots.rock_physics_template(ds)


def test_figures_of_different_selections_get_their_own_default_names(swept_file, monkeypatch,
                                                                      capsys):
    """Two --select plots of one file write two files (the second no longer replaces the
    first); the name carries the selection."""
    from rockcem import plots

    saved = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path, **_: saved.append(path) or path)
    for g in ("20", "40"):
        assert cli.main(["plot", str(swept_file), "--select", f"gradient={g}", "--select",
                         "sandstone.grain_size=0.4"]) == 0
    names = [p.name for p in saved]
    assert names == ["s_gradient-20_sandstone.grain_size-0.4_depth.png",
                     "s_gradient-40_sandstone.grain_size-0.4_depth.png"]
    assert all(p.parent == swept_file.parent for p in saved)


def test_mistyped_file_name_gets_a_did_you_mean(swept_file, capsys, monkeypatch):
    """A file name one letter off an existing one: one line naming the close name; a name
    close to nothing: the plain message."""
    monkeypatch.chdir(swept_file.parent)
    assert cli.main(["plot", "ss.nc"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no such file: ss.nc; did you mean s.nc?" in err
    wrong = str(swept_file.parent / "t.nc")
    assert cli.main(["plot", wrong]) == 2
    assert f"did you mean {swept_file}?" in capsys.readouterr().err
    assert cli.main(["plot", "completely_different_name.nc"]) == 2
    err = capsys.readouterr().err
    assert "no such file: completely_different_name.nc" in err and "did you mean" not in err


# ----------------------------------------------------------------------------- [uncertain]
def _uncertain_file(folder, *, members=False, sobol=False):
    """A small file as a scene with [uncertain] writes it (built by hand): quantiles 0.1, 0.5,
    0.9 of vp, vs, density and porosity at 3 depths, 2 models; with ``members`` 4 members, with
    ``sobol`` the Sobol' indices of vp along 2 inputs."""
    import xarray as xr

    depth = [1000.0, 2000.0, 3000.0]
    models = ["hs_gassmann", "patchy_cement"]
    vp = np.array([3.0, 3.5, 4.0])[None, None, :] + np.array([-0.2, 0.0, 0.2])[:, None, None] \
        + np.array([0.0, 0.1])[None, :, None]
    data = {"vp": (("quantile", "model", "depth"), vp),
            "vs": (("quantile", "model", "depth"), vp / 1.7),
            "density": (("quantile", "depth"), 2.2 + 0.1 * vp[:, 0]),
            "porosity": (("quantile", "depth"), 0.3 - 0.02 * vp[:, 0])}
    coords = {"quantile": [0.1, 0.5, 0.9], "model": models, "depth": depth}
    if members:
        rng = np.random.default_rng(1)
        m = 3.5 + 0.1 * rng.standard_normal((4, 2, 3))
        data.update(vp_members=(("member", "model", "depth"), m),
                    vs_members=(("member", "model", "depth"), m / 1.7),
                    density_members=(("member", "depth"), 2.3 + 0.0 * m[:, 0]))
        coords["member"] = np.arange(4)
    if sobol:
        coords["input"] = ["path.gradient", "sandstone.grain_size"]
        total = np.full((2, 2, 3), 0.5)
        data.update(vp_sobol_total=(("input", "model", "depth"), total),
                    vp_sobol_first=(("input", "model", "depth"), 0.8 * total))
    ds = xr.Dataset(data, coords=coords,
                    attrs={"lithology": "sandstone", "grain": "quartz",
                           "cement": "quartz_cement", "fluid": "water",
                           "critical_porosity": 0.36,
                           "uncertain_json": '{"samples": 4, "sensitivity": false}'})
    name = folder / f"u{'_m' if members else ''}{'_s' if sobol else ''}.nc"
    ds.to_netcdf(name, engine="netcdf4")
    return name


def test_plot_uncertain_default_is_the_band_figure(tmp_path, drawn, capsys):
    path = _uncertain_file(tmp_path)
    for extra in ([], ["--kind", "band"], ["--kind", "depth"]):
        assert cli.main(["plot", str(path), *extra]) == 0, capsys.readouterr().err
        vp = next(ax for ax in drawn[-1].axes if ax.get_xlabel().startswith("P-wave"))
        assert sorted(c.get_gid() for c in vp.collections) == ["band:hs_gassmann",
                                                               "band:patchy_cement"]
    assert capsys.readouterr().out.count("u_band.png") == 2         # the default name
    # one quantile selected: that quantile's depth trends (no band)
    assert cli.main(["plot", str(path), "--select", "quantile=0.5"]) == 0
    vp = next(ax for ax in drawn[-1].axes if ax.get_xlabel().startswith("P-wave"))
    assert not [c for c in vp.collections if str(c.get_gid()).startswith("band:")]
    np.testing.assert_allclose(vp.get_lines()[0].get_xdata(), [3.0, 3.5, 4.0])


@pytest.mark.parametrize("members, sobol, args, message", [
    (False, False, ["--kind", "template"],
     "keeps the quantiles only: run the scene with members = true in [uncertain]"),
    (False, False, ["--kind", "sensitivity"], "sensitivity = true in [uncertain]"),
    (False, False, ["--kind", "vp-porosity"], "--kind band draws them"),
    (False, False, ["--variable", "vs"], "--variable chooses the output of --kind sensitivity"),
    (False, False, ["--kind", "band", "--depth", "2000"], "--depth chooses"),
    (False, True, ["--kind", "sensitivity", "--variable", "vs"], "no Sobol' indices of it"),
    (False, True, ["--kind", "sensitivity", "--depth", "9000"], "outside the file's depths"),
    (True, False, ["--kind", "template", "--depth", "9000"], "range 1000-3000 m; got 9000"),
])
def test_plot_uncertain_wrong_kind_exits_2_in_one_line(tmp_path, drawn, capsys, members,
                                                       sobol, args, message):
    path = _uncertain_file(tmp_path, members=members, sobol=sobol)
    assert cli.main(["plot", str(path), *args]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err, err
    assert drawn == []


def test_plot_band_of_a_file_without_quantiles_exits_2(swept_file, drawn, capsys):
    assert cli.main(["plot", str(swept_file), "--kind", "band"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "has no quantile dimension" in err, err


def test_plot_uncertain_template_and_sensitivity(tmp_path, drawn, capsys):
    path = _uncertain_file(tmp_path, members=True)
    assert cli.main(["plot", str(path), "--kind", "template", "--depth", "2000"]) == 0
    clouds = [c for c in drawn[-1].axes[0].collections
              if str(c.get_gid()).startswith("members:")]
    assert sorted(c.get_gid() for c in clouds) == ["members:hs_gassmann:2000",
                                                   "members:patchy_cement:2000"]
    assert [len(c.get_offsets()) for c in clouds] == [4, 4]
    path = _uncertain_file(tmp_path, sobol=True)
    assert cli.main(["plot", str(path), "--kind", "sensitivity", "--depth", "1000",
                     "--depth", "3000"]) == 0
    fig = drawn[-1]
    rows = fig.subfigs
    assert [r._suptitle.get_text().split(",")[1].split(":")[0].strip() for r in rows] == \
        ["hs_gassmann", "patchy_cement"]
    assert [ax.get_title() for ax in fig.axes] == ["1000 m", "3000 m"] * 2
    assert cli.main(["plot", str(path), "--kind", "sensitivity",
                     "--select", "model=patchy_cement"]) == 0
    assert [ax.get_title() for ax in drawn[-1].axes] == ["2000 m", "3000 m"]   # default: 2-4 km
    #                                                                  as far as the file goes


def test_plot_help_names_the_uncertain_kinds(capsys):
    with pytest.raises(SystemExit):
        cli.main(["plot", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for words in ("band (quantile bands along depth per model", "--variable NAME",
                  "needs sensitivity = true", "needs members = true"):
        assert words in text, words
