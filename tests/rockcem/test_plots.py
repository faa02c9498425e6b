"""Figures of rockcem.plots: panels, lines, labels with units, templates against direct calls,
atomic saving, cheap import, errors."""

import subprocess
import sys

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr

from rockcem import plots
from rockcem.plots import _style
from rockcem.fluids import gassmann
from rockcem.granular import constant_cement, contact_cement, soft_sand, stiff_sand
from rockcem.materials import fluid, mineral
from rockcem.models import patchy_cement_model
from rockcem.variables import build_dataset, variable_names

MODELS = ["hs_gassmann", "self_consistent", "generalized_gassmann", "patchy_cement"]
QUARTZ, CEMENT, WATER = mineral("quartz"), mineral("quartz_cement"), fluid("water")


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def scene(n=21, models=MODELS, gradients=None, attrs=True):
    """A hand-made scene Dataset: porosity falling and velocities rising with depth."""
    depth = np.linspace(0.0, 4000.0, n)
    z = depth / 4000.0
    m = np.arange(len(models))[:, None]
    lead, shape = ((), ())
    if gradients is not None:
        lead, shape = ("gradient",), (len(gradients),)
    g = np.ones(shape + (1,)) if gradients is None else (np.asarray(gradients)[:, None] / 30.0)
    porosity = np.clip(0.36 - 0.3 * z * g, 0.01, None)
    gm = g[..., None, :] if gradients is not None else g
    data = {
        "porosity": (lead + ("depth",), porosity),
        "cement_fraction": (lead + ("depth",), 0.36 - porosity),
        "pressure_effective": (("depth",), 1e-2 * depth + 5.0),
        "density": (lead + ("depth",), 2.65 - 1.61 * porosity),
        "vp": (lead + ("model", "depth"), (2.0 + 3.0 * z + 0.1 * m) * gm),
        "vs": (lead + ("model", "depth"), (1.0 + 2.0 * z + 0.05 * m) * gm),
    }
    coords = {"depth": (("depth",), depth), "model": (("model",), list(models))}
    if gradients is not None:
        coords["gradient"] = (("gradient",), np.asarray(gradients, dtype=float))
    meta = {"grain": "quartz", "cement": "quartz_cement", "fluid": "water",
            "critical_porosity": 0.36} if attrs else {}
    ds = build_dataset(data, coords, meta)
    if gradients is not None:
        ds["gradient"].attrs.update(units="degree_Celsius km-1", long_name="geothermal gradient")
    return ds


def labelled(ax, label):
    lines = [ln for ln in ax.get_lines() if ln.get_label() == label]
    assert len(lines) == 1, [ln.get_label() for ln in ax.get_lines()]
    return lines[0]


# ----------------------------------------------------------------------------- labels
@pytest.mark.parametrize("units, text", [
    ("km s-1", "km/s"), ("g cm-3", "g/cm³"), ("km s-1 g cm-3", "(km/s)·(g/cm³)"),
    ("degree_Celsius km-1", "°C/km"), ("degree_Celsius", "°C"), ("MPa", "MPa"), ("m2", "m²"),
    ("1", "–"), ("Myr", "Myr"), ("m s-2", "m/s²"),
])
def test_units_text(units, text):
    assert _style._units_text(units) == text


def test_every_registered_variable_gets_a_label_with_its_unit():
    for name in variable_names():
        label = _style._label(name)
        assert label.endswith(")") and "(" in label, label
    assert _style._label("vp") == "P-wave velocity (km/s)"
    assert _style._label("pressure_effective") == "Effective pressure (MPa)"
    assert _style._label("temperature") == "Temperature (°C)"


# ----------------------------------------------------------------------------- depth trends
def test_depth_trends_panels_lines_labels_and_inverted_depth():
    ds = scene()
    fig = plots.depth_trends(ds)
    names = ["porosity", "cement_fraction", "density", "vp", "vs"]
    assert len(fig.axes) == len(names)
    assert [len(ax.get_lines()) for ax in fig.axes] == [1, 1, 1, 4, 4]
    assert [ax.get_xlabel().replace("\n", " ") for ax in fig.axes] == [
        "Porosity (–)", "Quartz cement volume fraction (–)", "Bulk density (g/cm³)",
        "P-wave velocity (km/s)", "S-wave velocity (km/s)"]
    assert fig.axes[0].get_ylabel() == "Depth below the sediment surface (m)"
    for ax in fig.axes:
        assert ax.yaxis_inverted()
        assert ax.get_ylim() == (4000.0, 0.0)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert legend == ["Model 1 (HS–Krief–Gassmann)", "Model 2 (self-consistent)",
                      "Model 3 (generalized Gassmann)", "Model 4 (patchy cement)"]
    vp4 = labelled(fig.axes[3], "Model 4 (patchy cement)")
    np.testing.assert_array_equal(vp4.get_xdata(), ds.vp.sel(model="patchy_cement").values)
    np.testing.assert_array_equal(vp4.get_ydata(), ds.depth.values)


def test_depth_trends_chosen_variables_in_order():
    fig = plots.depth_trends(scene(), ["vs", "porosity"])
    assert [ax.get_xlabel() for ax in fig.axes] == ["S-wave velocity (km/s)", "Porosity (–)"]
    fig = plots.depth_trends(scene(), "pressure_effective")
    assert fig.axes[0].get_xlabel() == "Effective pressure (MPa)"


def test_depth_trends_one_sweep_dimension():
    ds = scene(gradients=[25.0, 30.0, 35.0])
    fig = plots.depth_trends(ds, ["porosity", "vp", "pressure_effective"])
    assert [len(ax.get_lines()) for ax in fig.axes] == [3, 12, 1]
    shades = {ln.get_color() for ln in fig.axes[0].get_lines()}
    assert len(shades) == 3                                # one shade per member
    models, sweep = fig.legends
    assert len(models.get_texts()) == 4
    assert [t.get_text() for t in sweep.get_texts()] == ["25 °C/km", "30 °C/km", "35 °C/km"]
    assert sweep.get_title().get_text() == "Geothermal gradient (shade)"
    line = labelled(fig.axes[1], "Model 2 (self-consistent), gradient = 35 °C/km")
    np.testing.assert_array_equal(line.get_xdata(),
                                  ds.vp.sel(model="self_consistent", gradient=35.0).values)


def test_depth_trends_draw_every_member_of_two_sweep_dimensions():
    ds = scene(gradients=[25.0, 35.0]).expand_dims(rate=[20.0, 40.0])
    ds["vp"] = ds.vp * xr.DataArray([1.0, 1.1], dims="rate", coords={"rate": [20.0, 40.0]})
    ax = plots.depth_trends(ds, ["vp"]).axes[0]
    assert len(ax.get_lines()) == 4 * 2 * 2
    for rate in (20.0, 40.0):
        for g in (25.0, 35.0):
            line = labelled(ax, f"Model 4 (patchy cement), rate = {rate:g}, gradient = {g:g} °C/km")
            np.testing.assert_array_equal(line.get_xdata(), ds.vp.sel(
                model="patchy_cement", gradient=g, rate=rate).values)
    assert len({ln.get_color() for ln in ax.get_lines()
                if ln.get_label().startswith("Model 4")}) == 4
    ds["porosity"] = ds.porosity.isel(rate=0, drop=True)    # changes with the gradient only
    ax = plots.depth_trends(ds, ["porosity"]).axes[0]
    assert [ln.get_label() for ln in ax.get_lines()] == [
        "porosity, gradient = 25 °C/km", "porosity, gradient = 35 °C/km"]


def contrast(a, b):
    """WCAG 2 contrast ratio of two colours (relative luminance of sRGB, W3C definition)."""
    def luminance(colour):
        c = np.asarray(matplotlib.colors.to_rgb(colour))
        c = np.where(c <= 0.03928, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
        return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
    high, low = sorted((luminance(a), luminance(b)), reverse=True)
    return (high + 0.05) / (low + 0.05)


@pytest.mark.parametrize("colour", list(_style._MODEL_COLOURS.values()) + [_style._INK])
def test_sweep_shades_of_every_model_colour_stand_apart(colour):
    # Two members: at least 3:1 (the WCAG minimum for graphics); lighter-only shades of the
    # pink of Model 4 gave 1.9. Up to four members: neighbours at least 1.3:1.
    assert contrast(_style._shade(colour, 0, 2), _style._shade(colour, 1, 2)) >= 3.0
    for count in (3, 4):
        shades = [_style._shade(colour, j, count) for j in range(count)]
        assert min(contrast(a, b) for a, b in zip(shades, shades[1:])) >= 1.3
    assert _style._shade(colour, 0, 1) == matplotlib.colors.to_rgb(colour)


def test_depth_trends_draw_a_variable_the_sweep_leaves_unchanged_once():
    ds = scene(gradients=[25.0, 35.0])
    ds["porosity"] = ds.porosity.isel(gradient=0, drop=True).expand_dims(gradient=ds.gradient)
    fig = plots.depth_trends(ds, ["porosity", "vp"])
    (line,) = fig.axes[0].get_lines()
    assert line.get_label() == "porosity"
    np.testing.assert_array_equal(line.get_xdata(), ds.porosity.isel(gradient=0).values)
    assert fig.axes[0].get_title(loc="right") == "same for every gradient"
    assert len(fig.axes[1].get_lines()) == 8 and fig.axes[1].get_title(loc="right") == ""
    ds["porosity"] = ds.porosity * xr.DataArray([1.0, 1.0 + 1e-9], dims="gradient")
    assert len(plots.depth_trends(ds, ["porosity"]).axes[0].get_lines()) == 2


@pytest.mark.parametrize("select", [{"gradient": 35.0}, {"gradient": [35.0]}])
@pytest.mark.parametrize("kind", ["depth", "vp", "template"])
def test_a_selected_member_is_named_on_the_figure(kind, select):
    ds = scene(n=11, gradients=[25.0, 35.0]).sel(select)
    draw = {"depth": plots.depth_trends, "vp": plots.velocity_porosity,
            "template": plots.rock_physics_template}[kind]
    fig = draw(ds)
    texts = [lg.get_title().get_text() for lg in fig.legends]
    texts += [ax.get_title() for ax in fig.axes] + [fig.get_suptitle()]
    assert sum("Geothermal gradient: 35 °C/km" in t for t in texts) == 1, texts


@pytest.mark.parametrize("kind", ["depth", "vp", "template"])
def test_too_many_members_refused_naming_dimension_and_select(kind):
    ds = scene(n=5, gradients=[20.0, 25.0, 30.0, 35.0]).expand_dims(rate=[20.0, 40.0])
    ds["vp"] = ds.vp * xr.DataArray([1.0, 1.1], dims="rate", coords={"rate": [20.0, 40.0]})
    draw = {"depth": plots.depth_trends, "vp": plots.velocity_porosity,
            "template": plots.rock_physics_template}[kind]
    with pytest.raises(ValueError, match=r"8 \(rate 2 x gradient 4\).*'gradient'.*"
                                         r"--select gradient=20") as err:
        draw(ds)
    assert "\n" not in str(err.value)
    draw(ds.sel(gradient=[20.0, 30.0]))                   # 4 members: drawn


def temperature_axes(fig):
    return [c for ax in fig.axes for c in ax.child_axes if c.get_gid() == "temperature_axis"]


def test_depth_trends_temperature_axis():
    ds = scene().assign(temperature=lambda d: 15.0 + 0.03 * d.depth)
    fig = plots.depth_trends(ds, ["porosity", "vp"])
    fig.canvas.draw()
    (sec,) = temperature_axes(fig)
    assert sec.get_ylabel() == "Temperature (°C)"
    low, high = sec.get_ylim()                             # depth 4000 m down to 0 m
    assert low == pytest.approx(15.0 + 0.03 * 4000.0) and high == pytest.approx(15.0)
    assert temperature_axes(plots.depth_trends(ds, ["vp"], temperature_axis=False)) == []


def test_depth_trends_temperature_axis_per_gradient():
    ds = scene(gradients=[20.0, 30.0])
    ds["temperature"] = 15.0 + ds.gradient * ds.depth / 1000.0
    fig = plots.depth_trends(ds, ["vp"])
    fig.canvas.draw()
    secs = temperature_axes(fig)
    assert [ax.get_ylabel() for ax in secs] == [
        "Temperature, gradient = 20 °C/km (°C)", "Temperature, gradient = 30 °C/km (°C)"]
    assert [ax.get_ylim()[0] for ax in secs] == pytest.approx([15.0 + 80.0, 15.0 + 120.0])
    ds = scene(gradients=[30.0, 20.0, 25.0])                # past two: coolest and warmest
    ds["temperature"] = 15.0 + ds.gradient * ds.depth / 1000.0
    fig = plots.depth_trends(ds, ["vp"])
    assert [ax.get_ylabel() for ax in temperature_axes(fig)] == [
        "Temperature, gradient = 20 °C/km (°C)", "Temperature, gradient = 30 °C/km (°C)"]


def test_depth_trends_without_model_dimension_has_no_legend():
    ds = scene().sel(model="hs_gassmann", drop=True)
    fig = plots.depth_trends(ds, ["vp", "porosity"])
    assert [len(ax.get_lines()) for ax in fig.axes] == [1, 1]
    assert fig.legends == []


def test_depth_trends_draws_in_a_given_figure():
    fig = plt.figure(figsize=(8, 4))
    assert plots.depth_trends(scene(), ["vp"], fig=fig) is fig
    with pytest.raises(ValueError, match="empty"):
        plots.depth_trends(scene(), ["vp"], fig=fig)


def test_depth_trends_errors():
    ds = scene()
    with pytest.raises(ValueError, match="did you mean 'porosity'"):
        plots.depth_trends(ds, ["porosty"])
    with pytest.raises(ValueError, match="'depth' dimension"):
        plots.depth_trends(ds.isel(depth=0))
    with pytest.raises(ValueError, match="'depth' dimension"):
        plots.depth_trends(ds.assign(p0=ds.porosity.isel(depth=0)), ["p0"])
    with pytest.raises(ValueError, match="Dataset"):
        plots.depth_trends(ds.vp)
    with pytest.raises(ValueError, match="default variables"):
        plots.depth_trends(ds[["pressure_effective"]])


# ----------------------------------------------------------------------------- velocity-porosity
def direct_velocities(dry, phi):
    """Gassmann with the grain as mineral, density by mixing, velocities written out."""
    K = gassmann(dry.K, QUARTZ.K, WATER.K, phi)
    rho = (1.0 - phi) * QUARTZ.rho + phi * WATER.rho
    return np.sqrt((K + 4.0 / 3.0 * dry.G) / rho), np.sqrt(dry.G / rho)


def template_point(ax, key, near):
    line = next(ln for ln in ax.get_lines() if ln.get_gid() == f"template:{key}")
    x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    k = int(np.argmin(abs(x - near)))
    return x[k], y[k]


@pytest.mark.parametrize("velocity", ["vp", "vs"])
def test_velocity_porosity_templates_match_direct_calls(velocity):
    ds = scene()
    p = float(np.median(ds.pressure_effective))        # default pressure: the median
    fig = plots.velocity_porosity(ds, velocity=velocity)
    ax = fig.axes[0]
    col = 0 if velocity == "vp" else 1
    cases = {
        "soft_sand": (0.2, lambda phi: soft_sand(40.0, 39.0, phi, 0.36, 9.0, p)),
        "stiff_sand": (0.2, lambda phi: stiff_sand(40.0, 39.0, phi, 0.36, 9.0, p)),
        "contact_cement": (0.3, lambda phi: contact_cement(40.0, 39.0, 35.0, 30.0, phi, 0.36,
                                                           9.0, scheme=1)),
        "constant_cement": (0.2, lambda phi: constant_cement(40.0, 39.0, 35.0, 30.0, phi, 0.36,
                                                             9.0, 0.32)),
    }
    for key, (near, dry) in cases.items():
        phi, v = template_point(ax, key, near)
        assert abs(phi - near) < 3e-3
        assert v == pytest.approx(float(direct_velocities(dry(phi), phi)[col]), rel=1e-12), key
    assert ax.get_xlabel() == "Porosity (–)"
    assert ax.get_ylabel() == ("P-wave velocity (km/s)" if velocity == "vp"
                               else "S-wave velocity (km/s)")
    data = [ln for ln in ax.get_lines() if ln.get_gid().startswith("model:")]
    assert [ln.get_label() for ln in data] == [plots.MODEL_LABELS[m] for m in MODELS]
    np.testing.assert_array_equal(data[1].get_ydata(),
                                  ds[velocity].sel(model="self_consistent").values)
    assert len(fig.legends[0].get_texts()) == 8
    assert fig.legends[0].get_title().get_text().startswith("quartz grains, quartz cement,\nwater")


def test_velocity_porosity_defaults_and_overrides():
    ds = scene().drop_vars("pressure_effective")
    fig = plots.velocity_porosity(ds)                   # no pressure in ds: 20 MPa
    phi, v = template_point(fig.axes[0], "soft_sand", 0.1)
    assert v == pytest.approx(float(direct_velocities(
        soft_sand(40.0, 39.0, phi, 0.36, 9.0, 20.0), phi)[0]), rel=1e-12)
    fig = plots.velocity_porosity(scene(attrs=False), grain=QUARTZ, cement="quartz_cement",
                                  fluid="water", pressure=30.0, critical_porosity=0.4,
                                  coordination_number=8.0)
    phi, v = template_point(fig.axes[0], "stiff_sand", 0.2)
    K = gassmann(stiff_sand(40.0, 39.0, phi, 0.4, 8.0, 30.0).K, 40.0, 2.2, phi)
    G = stiff_sand(40.0, 39.0, phi, 0.4, 8.0, 30.0).G
    rho = (1 - phi) * 2.65 + phi * 1.04
    assert v == pytest.approx(float(np.sqrt((K + 4 / 3 * G) / rho)), rel=1e-12)
    line = next(ln for ln in fig.axes[0].get_lines() if ln.get_gid() == "template:constant_cement")
    assert max(line.get_xdata()) == pytest.approx(0.36)     # phib = 0.4 - 0.04


def test_velocity_porosity_sweep_members_are_separate_lines():
    ds = scene(n=11, gradients=[25.0, 35.0])
    fig = plots.velocity_porosity(ds)
    ax = fig.axes[0]
    line = labelled(ax, plots.MODEL_LABELS["hs_gassmann"] + ", gradient = 35 °C/km")
    np.testing.assert_array_equal(line.get_ydata(),
                                  ds.vp.sel(model="hs_gassmann", gradient=35.0).values)
    np.testing.assert_array_equal(line.get_xdata(), ds.porosity.sel(gradient=35.0).values)
    assert len([ln for ln in ax.get_lines() if ln.get_gid().startswith("model:")]) == 8
    assert [t.get_text() for t in fig.legends[1].get_texts()] == ["25 °C/km", "35 °C/km"]


def test_velocity_porosity_errors():
    ds = scene()
    with pytest.raises(ValueError, match="did you mean 'vp'"):
        plots.velocity_porosity(ds, velocity="vpp")
    with pytest.raises(ValueError, match="grain"):
        plots.velocity_porosity(scene(attrs=False))
    with pytest.raises(ValueError, match="porosity"):
        plots.velocity_porosity(ds.drop_vars("porosity"))
    with pytest.raises(ValueError, match="unknown mineral 'qartz'"):
        plots.velocity_porosity(ds, grain="qartz")
    with pytest.raises(ValueError, match="pressure"):
        plots.velocity_porosity(ds, pressure=0.0)
    with pytest.raises(ValueError, match="critical_porosity"):
        plots.velocity_porosity(ds, critical_porosity=0.03)


# ----------------------------------------------------------------------------- RPT
def test_rock_physics_template_lines_match_patchy_cement_model():
    fig = plots.rock_physics_template()
    ax = fig.axes[0]
    gids = [ln.get_gid() for ln in ax.get_lines()]
    porosity_lines = [g for g in gids if g.startswith("porosity=")]
    cement_lines = [g for g in gids if g.startswith("cement_fraction=")]
    assert len(porosity_lines) == 7 and len(cement_lines) == 3   # 0, 0.02, 0.05
    line = next(ln for ln in ax.get_lines() if ln.get_gid() == "porosity=0.2")
    x, y = np.asarray(line.get_xdata()), np.asarray(line.get_ydata())
    r = patchy_cement_model(QUARTZ, CEMENT, 0.2, 0.05, 20.0, WATER, critical_porosity=0.36)
    assert x[2] == pytest.approx(float(r.density * r.vp), rel=1e-12)   # cement 0.05 is 3rd
    assert y[2] == pytest.approx(float(r.vp / r.vs), rel=1e-12)
    # porosity 0.35 with cement 0.02 and 0.05 exceeds critical porosity: left out
    line = next(ln for ln in ax.get_lines() if ln.get_gid() == "porosity=0.35")
    assert np.isnan(np.asarray(line.get_ydata())[1:]).all()
    assert np.isfinite(np.asarray(line.get_ydata())[:1]).all()
    assert ax.get_xlabel() == "Acoustic impedance ((km/s)·(g/cm³))"
    assert ax.get_ylabel() == "Vp/Vs (–)"
    assert len(ax.texts) == 7                              # one label per iso-porosity line


def test_rock_physics_template_takes_the_scene_materials():
    ds = scene().assign_attrs(grain="quartz_han_guo", cement="epoxy_kaolinite",
                              critical_porosity=0.4)
    fig = plots.rock_physics_template(ds)
    ax = fig.axes[0]
    gids = [ln.get_gid() for ln in ax.get_lines()]
    assert "porosity=0.4" in gids and "porosity=0.45" not in gids
    assert ax.get_legend() is None                         # below the axes, covering nothing
    assert fig.legends[0].get_title().get_text().startswith(
        "Model 4 template: quartz han guo, epoxy kaolinite,")
    line = next(ln for ln in ax.get_lines() if ln.get_gid() == "porosity=0.2")
    # the template's pressure: the scene's median effective pressure
    pe = float(np.median(ds.pressure_effective.values))
    r = patchy_cement_model(mineral("quartz_han_guo"), mineral("epoxy_kaolinite"), 0.2, 0.05,
                            pe, WATER, critical_porosity=0.4)
    assert np.asarray(line.get_xdata())[2] == pytest.approx(float(r.density * r.vp), rel=1e-12)
    assert np.asarray(line.get_ydata())[2] == pytest.approx(float(r.vp / r.vs), rel=1e-12)
    ax = plots.rock_physics_template(ds, grain="quartz", cement="quartz_cement",
                                     critical_porosity=0.36).axes[0]
    line = next(ln for ln in ax.get_lines() if ln.get_gid() == "porosity=0.2")
    r = patchy_cement_model(QUARTZ, CEMENT, 0.2, 0.05, pe, WATER, critical_porosity=0.36)
    assert np.asarray(line.get_xdata())[2] == pytest.approx(float(r.density * r.vp), rel=1e-12)


def test_rock_physics_template_takes_the_scene_model_parameters_per_panel():
    from rockcem.scene import load_scene, run_scene

    ds = run_scene(load_scene("han_guo_mcct").replace(**{"path.depth_step": 500.0}))
    fig = plots.rock_physics_template(ds)
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == [f"thickness = {t:g}"
                                                 for t in (0.0, 0.01, 0.03, 0.05)]
    assert [ax.get_subplotspec().colspan.start for ax in panels] == [0, 1, 0, 1]   # 2 x 2
    grain, cement = mineral("quartz_han_guo"), mineral("epoxy_kaolinite")
    for ax, thickness in zip(panels, (0.0, 0.01, 0.03, 0.05)):
        r = patchy_cement_model(grain, cement, 0.2, 0.05, 20.0, WATER, critical_porosity=0.4,
                                coordination_number=8.5, scheme=2, thickness=thickness)
        line = next(ln for ln in ax.get_lines() if ln.get_gid() == "porosity=0.2")
        assert np.asarray(line.get_ydata())[2] == pytest.approx(float(r.vp / r.vs), rel=1e-12)
    one = plots.rock_physics_template(ds.sel(thickness=0.03))   # a selected member's own
    line = next(ln for ln in one.axes[0].get_lines() if ln.get_gid() == "porosity=0.2")
    r = patchy_cement_model(grain, cement, 0.2, 0.05, 20.0, WATER, critical_porosity=0.4,
                            coordination_number=8.5, scheme=2, thickness=0.03)
    assert np.asarray(line.get_ydata())[2] == pytest.approx(float(r.vp / r.vs), rel=1e-12)
    fixed = plots.rock_physics_template(ds, delta=40.0, coordination_number=6.0)
    line = next(ln for ln in fixed.axes[0].get_lines() if ln.get_gid() == "porosity=0.2")
    r = patchy_cement_model(grain, cement, 0.2, 0.05, 20.0, WATER, critical_porosity=0.4,
                            coordination_number=6.0, delta=40.0, scheme=2, thickness=0.0)
    assert np.asarray(line.get_ydata())[2] == pytest.approx(float(r.vp / r.vs), rel=1e-12)


def test_rock_physics_template_with_dataset_points_coloured_by_depth():
    ds = scene()
    fig = plots.rock_physics_template(ds, porosity=[0.1, 0.2, 0.3], cement_fraction=[0.0, 0.04])
    ax, bar = fig.axes
    assert len(ax.collections) == 4                        # one scatter per model
    points = ax.collections[3]
    d = ds.density.values * ds.vp.sel(model="patchy_cement").values
    np.testing.assert_allclose(points.get_offsets()[:, 0], d, rtol=1e-12)
    np.testing.assert_array_equal(points.get_array(), ds.depth.values)
    assert bar.get_ylabel() == "Depth below the sediment surface (m)"
    assert bar.yaxis_inverted()
    assert [t.get_text() for t in fig.legends[-1].get_texts()] == [plots.MODEL_LABELS[m]
                                                                  for m in MODELS]


def test_rock_physics_template_dense_data_get_sparse_marked_points():
    ds = scene(n=400, models=["patchy_cement"])
    ax = plots.rock_physics_template(ds, porosity=[0.2], cement_fraction=[0.0]).axes[0]
    dense, marked = ax.collections
    assert len(dense.get_offsets()) == 400 and 20 <= len(marked.get_offsets()) <= 25


def test_rock_physics_template_errors():
    with pytest.raises(ValueError, match="porosity"):
        plots.rock_physics_template(porosity=[0.0, 0.2])
    with pytest.raises(ValueError, match="cement_fraction"):
        plots.rock_physics_template(cement_fraction=[-0.01])
    with pytest.raises(ValueError, match="within critical_porosity"):
        plots.rock_physics_template(porosity=[0.35], cement_fraction=[0.05])
    with pytest.raises(ValueError, match="vs"):
        plots.rock_physics_template(scene().drop_vars("vs"))


# ----------------------------------------------------------------------------- coinciding models
def coinciding(n=41):
    """The hand-made scene with all four models giving the same velocities."""
    ds = scene(n=n)
    for name in ("vp", "vs"):
        ds[name] = ds[name].copy(data=np.broadcast_to(ds[name].isel(model=0).values,
                                                      ds[name].shape).copy())
    return ds


def model_artists(fig, kind):
    ax = fig.axes[0]
    if kind == "depth":
        found = {m: [ln for ln in ax.get_lines() if ln.get_label() == plots.MODEL_LABELS[m]]
                 for m in MODELS}
    else:
        pool = ax.get_lines() if kind == "vp" else ax.collections
        found = {m: [a for a in pool if a.get_gid() == f"model:{m}"] for m in MODELS}
    assert all(found.values()), found
    return {m: a[0] for m, a in found.items()}


@pytest.mark.parametrize("kind", ["depth", "vp"])
def test_coinciding_model_lines_differ_and_the_lower_is_wider(kind):
    ds = coinciding()
    fig = (plots.depth_trends(ds, ["vp"]) if kind == "depth" else plots.velocity_porosity(ds))
    lines = model_artists(fig, kind)
    looks = {m: (str(ln.get_linestyle()), ln.get_linewidth(), ln.get_marker())
             for m, ln in lines.items()}
    assert len(set(looks.values())) == 4, looks            # no two models drawn alike
    order = sorted(lines.values(), key=lambda ln: ln.get_zorder())
    widths = [ln.get_linewidth() for ln in order]
    assert widths == sorted(widths, reverse=True) and len(set(widths)) == 4
    if kind == "vp":                                       # markers at different depths
        starts = {ln.get_markevery()[0] for ln in lines.values()}
        assert len(starts) == 4


@pytest.mark.parametrize("count", [2, 3, 4])
def test_upper_model_lines_have_a_white_edge_that_leaves_the_lower_line_showing(count):
    # A thin line of a similar hue on a wide one (Model 3's green on Model 1's blue) blends
    # into it; a white edge sets it off, narrower than the line below so that one shows.
    ds = coinciding().isel(model=slice(0, count))
    lines = sorted(model_artists_of(plots.depth_trends(ds, ["vp"]), MODELS[:count]),
                   key=lambda ln: ln.get_zorder())
    assert lines[0].get_path_effects() == []
    for below, line in zip(lines, lines[1:]):
        (edge,) = line.get_path_effects()
        assert edge._gc["foreground"] == "white"
        assert line.get_linewidth() < edge._gc["linewidth"] < below.get_linewidth()


def model_artists_of(fig, models):
    return [ln for ln in fig.axes[0].get_lines()
            if ln.get_label() in [plots.MODEL_LABELS[m] for m in models]]


def test_coinciding_model_points_nest_in_the_template():
    fig = plots.rock_physics_template(coinciding(), porosity=[0.2], cement_fraction=[0.0])
    points = model_artists(fig, "template")
    order = sorted(points.values(), key=lambda c: c.get_zorder())
    sizes = [float(c.get_sizes()[0]) for c in order]
    assert sizes == sorted(sizes, reverse=True) and len(set(sizes)) == 4
    shapes = {c.get_paths()[0].vertices.round(3).tobytes() for c in points.values()}
    assert len(shapes) == 4


def colour_pixels(fig, colour):
    """Pixels of the rendered figure within 10/255 of ``colour`` in every channel."""
    fig.set_dpi(100)
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(float)
    target = 255.0 * np.asarray(matplotlib.colors.to_rgb(colour))
    return int((np.abs(rgb - target).max(axis=-1) <= 10.0).sum())


def pairs_coinciding(pairs):
    """Four models in two pairs: the models of a pair give the same velocities, the pairs
    lie 1 km/s apart."""
    ds = scene(n=41)
    base = ds.vp.isel(model=0).values
    offset = {m: float(k) for k, pair in enumerate(pairs) for m in pair}
    vp = np.stack([base + offset[m] for m in MODELS])
    return ds.assign(vp=ds.vp.copy(data=vp), vs=ds.vs.copy(data=vp / 1.7))


#: The six pairs of models in three renders: each split of the four models into two pairs.
SPLITS = [((MODELS[0], m), tuple(x for x in MODELS[1:] if x != m)) for m in MODELS[1:]]


@pytest.mark.parametrize("kind", ["depth", "vp"])
@pytest.mark.parametrize("pairs", SPLITS, ids=lambda p: "+".join("-".join(x) for x in p))
def test_two_coinciding_models_are_both_seen_in_the_rendered_figure(kind, pairs):
    ds = pairs_coinciding(pairs)
    fig = (plots.depth_trends(ds, ["vp"], fig=plt.figure(figsize=(3, 5))) if kind == "depth"
           else plots.velocity_porosity(ds))
    for legend in fig.legends:
        legend.set_visible(False)                          # count the curves only
    seen = {m: colour_pixels(fig, _style._MODEL_COLOURS[m]) for m in MODELS}
    assert min(seen.values()) >= 60, seen                  # a hidden curve leaves ~0


# ----------------------------------------------------------------------------- saving
def simple_figure(title="line"):
    fig, ax = plt.subplots(figsize=(2, 2))
    ax.plot([0, 1], [0, 1])
    ax.set_title(title)
    return fig


def test_save_figure_png_and_pdf_atomically(tmp_path):
    fig = simple_figure()
    out = plots.save_figure(fig, tmp_path / "a.png", dpi=50)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not plt.fignum_exists(fig.number)               # closed
    plots.save_figure(simple_figure(), str(tmp_path / "b.PDF"))
    assert (tmp_path / "b.PDF").read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png", "b.PDF"]


def test_failing_save_leaves_existing_file_and_no_temporary(tmp_path):
    target = tmp_path / "fig.png"
    target.write_bytes(b"old figure")
    fig = simple_figure(r"$\notacommand{x}$")              # mathtext error while drawing
    with pytest.raises(ValueError):
        plots.save_figure(fig, target)
    assert target.read_bytes() == b"old figure"
    assert [p.name for p in tmp_path.iterdir()] == ["fig.png"]
    assert not plt.fignum_exists(fig.number)
    with pytest.raises(ValueError, match="suffix|end in"):
        plots.save_figure(simple_figure(), tmp_path / "fig.jpeg")
    with pytest.raises(ValueError, match="does not exist"):
        plots.save_figure(simple_figure(), tmp_path / "missing" / "fig.png")
    assert [p.name for p in tmp_path.iterdir()] == ["fig.png"]


# ----------------------------------------------------------------------------- import cost
def test_import_does_not_load_pyplot_numba_or_xarray():
    code = ("import sys, rockcem.plots; "
            "print(','.join(m for m in ('matplotlib.pyplot', 'matplotlib', 'numba', 'xarray') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == ""


def test_public_api():
    assert set(plots.__all__) >= {"depth_trends", "velocity_porosity", "rock_physics_template",
                                  "save_figure"}
    for name in plots.__all__:
        obj = getattr(plots, name)
        if callable(obj):
            assert "Examples" in obj.__doc__ and "Parameters" in obj.__doc__


def test_template_lines_reach_the_scenes_cement():
    """Issue 22: the iso-cement lines went to 0.08 while the sandstone's cement reaches 0.28, so
    the deepest points fell outside them; issue 30: eleven of them crowded Vp/Vs 1.55-1.7, so
    now 0, 0.02, 0.05, 0.1, 0.2 as far as the data go, then the data's largest."""
    ds = scene()
    top = float(ds.cement_fraction.max())
    fig = plots.rock_physics_template(ds)
    cements = sorted(float(ln.get_gid().split("=")[1]) for ln in fig.axes[0].get_lines()
                     if str(ln.get_gid()).startswith("cement_fraction="))
    # up to the data's largest cement (rounded up), as far as the porosity grid (0.05, ...)
    # leaves room below critical porosity: 0.36 - 0.05
    assert top == pytest.approx(0.3) and cements == [0.0, 0.02, 0.05, 0.1, 0.2, 0.3]
    plt.close(fig)
    for top, lines in ((0.0, [0.0, 0.02, 0.05]), (0.061, [0.0, 0.02, 0.05]),
                       (0.0751, [0.0, 0.02, 0.05, 0.08]),
                       (0.2845, [0.0, 0.02, 0.05, 0.1, 0.2, 0.29]),
                       (0.35, [0.0, 0.02, 0.05, 0.1, 0.2, 0.31])):      # capped at 0.36 - 0.05
        fig = plots.rock_physics_template(ds.assign(
            cement_fraction=ds.cement_fraction * 0 + top))
        assert sorted(float(ln.get_gid().split("=")[1]) for ln in fig.axes[0].get_lines()
                      if str(ln.get_gid()).startswith("cement_fraction=")) == lines, top
        plt.close(fig)


def test_depth_trends_mark_the_flagged_intervals_per_model_and_panel():
    """Issue 30: a line about a model marks that model's curve on the panels that draw it (a
    band along the curve, in its colour), not every panel; a line about the rock's state
    shades every panel; a line for some sweep members marks those members' curves only."""
    from matplotlib.colors import to_rgb

    ds = scene(gradients=[20.0, 30.0]).assign_attrs(validity_warnings=(
        "Models 1 and 3 (Krief frame) at 0–1400 m: porosity above 0.324\n"
        "[gradient = 20] Model 4 (patchy cement) at 2000–2400 m: bonding pre-stress\n"
        "quartz cement at 3000–4000 m: overfill"))
    fig = plots.depth_trends(ds, ["porosity", "vp", "vs"])
    panels = fig.axes[:3]
    for ax in panels:                           # the rock's line: every panel, grey
        spans = [p for p in ax.patches if p.get_gid() == "flagged"]
        assert sorted(tuple(sorted((p.get_y(), p.get_y() + p.get_height()))) for p in spans) \
            == [(3000.0, 4000.0)]
    assert not [c for c in panels[0].collections if str(c.get_gid()).startswith("flagged:")]
    for ax in panels[1:]:
        bands = [c for c in ax.collections if str(c.get_gid()).startswith("flagged:")]
        # Models 1 and 3 for both gradients, Model 4 for gradient 20 only
        assert sorted(c.get_gid() for c in bands) == ["flagged:generalized_gassmann"] * 2 \
            + ["flagged:hs_gassmann"] * 2 + ["flagged:patchy_cement"]
        for band in bands:
            (segment,) = band.get_segments()
            top, base = (0.0, 1400.0) if "gassmann" in band.get_gid() else (2000.0, 2400.0)
            assert segment[:, 1].min() == top and segment[:, 1].max() == base   # 200 m step
        model1 = next(c for c in bands if c.get_gid() == "flagged:hs_gassmann")
        red, _, blue = to_rgb(model1.get_colors()[0])
        assert blue > red + 0.2                         # Model 1's blue, not grey
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert "model flagged (validity_warnings):\nband along its curve" in labels
    assert "flagged (validity_warnings)" in labels
    plt.close(fig)
    fig = plots.depth_trends(scene())               # no warnings: nothing shaded
    assert not [p for ax in fig.axes for p in ax.patches if p.get_gid() == "flagged"]
    assert not [c for ax in fig.axes for c in ax.collections
                if str(c.get_gid()).startswith("flagged")]
    plt.close(fig)


def test_depth_trends_draw_the_first_sweep_member_on_top():
    """Issue 30: where members coincide (outside a reservoir), the first (darkest: the brine
    baseline of a hydrocarbon sweep) is on top, not the last and lightest."""
    fig = plots.depth_trends(scene(gradients=[20.0, 30.0, 40.0]), ["vp"])
    lines = [ln for ln in fig.axes[0].get_lines() if "hs_gassmann" not in ln.get_label()
             and ln.get_label().startswith(plots.MODEL_LABELS["hs_gassmann"])]
    assert len(lines) == 3
    assert lines[0].get_zorder() > lines[1].get_zorder() > lines[2].get_zorder()
    plt.close(fig)


def test_fitted_values_are_written_as_a_reader_writes_them():
    """Issue 22: the fit figure's title showed raw keys and '± 0.081'."""
    from rockcem.plots.wells import _fitted_text

    assert _fitted_text("models.patchy_cement.coordination_number", 6.4812, 0.0813) == \
        "coordination number 6.481 ± 0.081"
    assert _fitted_text("models.patchy_cement.delta", 39.63, 1.52) == \
        "bonding pre-stress 39.6 ± 1.5 MPa"
    assert _fitted_text("models.patchy_cement.delta", 39.63, 0.0) == \
        "bonding pre-stress 39.63 MPa (error not determined)"


def test_fit_figure_legend_names_the_window_and_overlay_legend_is_outside():
    from rockcem.scene import load_scene, run_scene
    from rockcem.synthetic_well import synthetic_well
    from rockcem.wellfit import fit_scene

    scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 200.0})
    truth = run_scene(scene.replace(**{"models.patchy_cement.delta": 60.0}))
    well = synthetic_well(truth, np.arange(1000.0, 3000.0, 100.0), sigma={"vp": 0.01},
                          model="patchy_cement", seed=1)
    fit = fit_scene(scene, well, ["models.patchy_cement.delta"], model="patchy_cement")
    fig = plots.fit_figure(fit, well)
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    top, base = fit.depth_range
    assert f"fit window {top:g}–{base:g} m" in labels and "before" in labels
    assert fig.get_suptitle().startswith("bonding pre-stress ")
    assert "Model 4" in fig.get_suptitle()
    plt.close(fig)
    fig = plots.well_overlay(truth.sel(model="patchy_cement"), well)
    assert all(ax.get_legend() is None for ax in fig.axes)       # nothing over the data
    assert any("well" in t.get_text() or "vp" in t.get_text().lower()
               for leg in fig.legends for t in leg.get_texts())
    plt.close(fig)


@pytest.fixture(scope="module")
def fluids_sweep():
    """The shipped hydrocarbon sweep (brine, gas, CO2 at 2000-2500 m) at a 250 m step."""
    from rockcem.scene import load_scene, run_scene

    pytest.importorskip("CoolProp")
    return run_scene(load_scene("sandstone_fluids").replace(**{"path.depth_step": 250.0}))


def test_hydrocarbon_members_titled_in_words(fluids_sweep):
    """Issue 30: a panel titled 'hydrocarbon = co2'."""
    fig = plots.rock_physics_template(fluids_sweep)
    titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
    assert titles == ["brine only (no hydrocarbon)",
                      "gas in brine, saturation 0.8 at 2000-2500 m",
                      "CO₂ in brine, saturation 0.8 at 2000-2500 m"]
    plt.close(fig)
    fig = plots.depth_trends(fluids_sweep, ["vp"])
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert "CO₂ in brine, saturation 0.8 at 2000-2500 m" in labels
    assert "Model 1 (HS–Krief–Gassmann), brine only (no hydrocarbon)" in [
        ln.get_label() for ln in fig.axes[0].get_lines()]
    plt.close(fig)


def test_velocity_porosity_breaks_at_the_reservoir_and_keeps_the_brine_on_top(fluids_sweep):
    """Issue 30: the segments joining the brine sand to the reservoir's (at 2000 and 2500 m)
    read as trends; the brine baseline was drawn under the lightest member."""
    ds = fluids_sweep
    fig = plots.velocity_porosity(ds)
    lines = [ln for ln in fig.axes[0].get_lines() if ln.get_gid() == "model:hs_gassmann"]
    brine, gas, co2 = lines
    assert brine.get_zorder() > gas.get_zorder() > co2.get_zorder()
    assert np.isfinite(np.asarray(brine.get_ydata(), dtype=float)).all()
    y = np.asarray(gas.get_ydata(), dtype=float)
    depth = ds.depth.values
    # breaks between 1750 and 2000 m and between 2500 and 2750 m: after the 8th and 11th depth
    assert np.flatnonzero(np.isnan(y)).tolist() == [8, 12]
    vp = ds.vp.sel(model="hs_gassmann", hydrocarbon="gas").values
    np.testing.assert_array_equal(y[np.isfinite(y)], vp)
    assert depth[7] == 1750.0 and depth[8] == 2000.0 and depth[10] == 2500.0
    plt.close(fig)
