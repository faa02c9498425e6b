"""The AVO and synthetic figures (rockcem.plots.avo) and `rockcem plot --kind avo|synthetic`
on a stack Dataset built by hand with the variables of the issue-31 schema."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_rgba

from rockcem import cli, plots
from rockcem.plots import avo

MODELS = ["hs_gassmann", "patchy_cement"]
FLUIDS = ["brine", "gas", "co2"]
DEPTH = np.arange(1000.0, 4501.0, 500.0)
FLAGS = {"flag_values": np.array([1, 2, 3, 4, 5], dtype="int8"),
         "flag_meanings": "I IIp II III IV"}
# Intercept A and gradient B of each fluid along depth (first model), with the class each
# pair has by the rule of Castagna & Swan (1997, Table 1) and Ross & Kinman (1995, IIp) at
# the threshold 0.02 on A, assigned by hand: I A >= 0.02, B < 0; IIp 0 <= A < 0.02, B < 0;
# II -0.02 < A < 0, B < 0; III A <= -0.02, B < 0; IV A < 0, B >= 0. Every pair is at least
# 0.005 from a boundary, so the second model (A + 0.003) has the same classes.
A = {"brine": [-0.05, -0.01, 0.01, 0.04, 0.06, 0.08, 0.09, 0.10],
     "gas": [-0.12, -0.10, -0.08, -0.05, -0.03, -0.01, 0.01, 0.03],
     "co2": [-0.11, -0.09, -0.07, -0.04, -0.025, -0.005, 0.015, 0.04]}
B = {"brine": [-0.10, -0.08, -0.07, -0.09, -0.11, -0.12, -0.13, -0.14],
     "gas": [0.04, 0.02, -0.15, -0.20, -0.22, -0.20, -0.18, -0.16],
     "co2": [0.03, -0.10, -0.14, -0.18, -0.20, -0.19, -0.17, -0.15]}
CLASS = {"brine": [4, 3, 2, 1, 1, 1, 1, 1],
         "gas": [5, 5, 4, 4, 4, 3, 2, 1],
         "co2": [5, 4, 4, 4, 4, 3, 2, 1]}
SHIFT = [0.0, 0.003]                     # the second model's intercept, A + 0.003
ANGLE = np.arange(0.0, 61.0, 2.0)
# The reflectivity of an acoustic (fluid over fluid) interface, a closed form with a critical
# angle (Aki & Richards 1980, eq. 5.35 with Vs = 0): R = (Z2 cos t1 - Z1 cos t2) /
# (Z2 cos t1 + Z1 cos t2), cos t2 = sqrt(1 - (v2 sin t1 / v1)^2), imaginary (decaying) beyond
# the critical angle asin(v1 / v2), where |R| = 1.
V1, RHO1 = 2.5, 2.3
V2 = {"brine": 3.2, "gas": 2.2, "co2": 2.3}       # brine: faster below, critical at 51.4°
RHO2 = {"brine": 2.4, "gas": 2.1, "co2": 2.15}
TWT = np.arange(0.0, 1.0001, 0.004)
F_PEAK = 25.0


def acoustic_r(v2, rho2, angle):
    t1 = np.radians(angle)
    cos2 = np.sqrt((1.0 - (v2 * np.sin(t1) / V1) ** 2).astype(complex))
    cos2 = np.where(cos2.imag < 0.0, -cos2, cos2)
    z1, z2 = RHO1 * V1, rho2 * v2
    return (z2 * np.cos(t1) - z1 * cos2) / (z2 * np.cos(t1) + z1 * cos2)


def ricker(t, t0):
    """Ricker (1953) wavelet of peak frequency F_PEAK centred at t0."""
    a = (np.pi * F_PEAK * (t - t0)) ** 2
    return (1.0 - 2.0 * a) * np.exp(-a)


def stack(gather=False, threshold=0.02, meanings=None):
    """A stack Dataset with the schema's variables: one interface, three fluids, two models,
    eight depths; every AVO class appears."""
    shape = (1, len(FLUIDS), len(MODELS), DEPTH.size)
    a = np.zeros(shape)
    b = np.zeros(shape)
    cls = np.zeros(shape, dtype="int8")
    for f, fluid in enumerate(FLUIDS):
        for m, shift in enumerate(SHIFT):
            a[0, f, m] = np.asarray(A[fluid]) + shift
            b[0, f, m] = B[fluid]
            cls[0, f, m] = CLASS[fluid]
    r = np.stack([acoustic_r(V2[f], RHO2[f], ANGLE) for f in FLUIDS])  # (fluid, angle)
    r = np.broadcast_to(r[None, :, None, None, :], shape + (ANGLE.size,))
    dims = ("interface", "fluid", "model", "depth")
    one = {"units": "1"}
    flags = dict(FLAGS, flag_meanings=meanings or FLAGS["flag_meanings"],
                 threshold=threshold, long_name="AVO class")
    traces = np.zeros((len(FLUIDS), len(MODELS), TWT.size))
    for f, fluid in enumerate(FLUIDS):
        for m in range(len(MODELS)):
            traces[f, m] = a[0, f, m, 3] * ricker(TWT, 0.4) - 0.05 * (1 + f) * ricker(TWT, 0.7)
    data = {
        "avo_intercept": (dims, a, one), "avo_gradient": (dims, b, one),
        "avo_curvature": (dims, 0.5 * a, one), "avo_class": (dims, cls, flags),
        "reflectivity_pp": (dims + ("angle",), r.real, one),
        "reflectivity_pp_magnitude": (dims + ("angle",), np.abs(r), one),
        "synthetic": (("fluid", "model", "twt"), traces, one),
        "twt_of_depth": (("fluid", "model", "depth"),
                         np.broadcast_to(2.0 * DEPTH / 2500.0, traces.shape[:2] + DEPTH.shape),
                         {"units": "s"}),
    }
    if gather:
        sin2 = np.sin(np.radians(ANGLE)) ** 2
        data["angle_gather"] = (("fluid", "model", "twt", "angle"),
                                traces[..., None] * (1.0 - 2.0 * sin2))
    return xr.Dataset(data, coords={
        "interface": ["seal/reservoir"], "fluid": FLUIDS, "model": MODELS,
        "depth": ("depth", DEPTH, {"units": "m"}),
        "angle": ("angle", ANGLE, {"units": "degree", "long_name": "angle of incidence"}),
        "twt": ("twt", TWT, {"units": "s", "long_name": "two-way time"})})


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def by_gid(ax, prefix, kind="lines"):
    return [a for a in getattr(ax, kind) if str(a.get_gid()).startswith(prefix)]


# ----------------------------------------------------------------------------- class vs depth
def test_the_hand_made_dataset_has_every_class():
    assert set(np.unique(stack()["avo_class"].values)) == {1, 2, 3, 4, 5}


def test_class_depth_draws_a_line_per_model_at_each_depth_class():
    fig = plots.avo_class_depth(stack())
    assert [ax.get_title() for ax in fig.axes] == ["Brine", "Gas", "CO₂"]
    for ax, fluid in zip(fig.axes, FLUIDS):
        lines = by_gid(ax, "class:")
        assert [ln.get_gid() for ln in lines] == [f"class:{m}" for m in MODELS]
        offsets = []
        for line in lines:
            x, y = line.get_xdata(), line.get_ydata()
            # each depth is a vertical segment at its class, spanning the depth sample
            assert np.all((y[0::2] <= DEPTH) & (DEPTH <= y[1::2]))
            offset = x[0::2] - (np.asarray(CLASS[fluid]) - 1)   # flag position of the class
            assert np.allclose(offset, offset[0]) and abs(offset[0]) < 0.3
            offsets.append(offset[0])
        assert offsets[0] != offsets[1]           # side by side, not on top of each other
        assert ax.yaxis_inverted()


def test_class_axis_is_labelled_from_flag_meanings():
    fig = plots.avo_class_depth(stack())
    assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == ["I", "IIp", "II", "III",
                                                                    "IV"]
    fig = plots.avo_class_depth(stack(meanings="c1 c2p c2 c3 c4"))
    assert [t.get_text() for t in fig.axes[0].get_xticklabels()] == ["c1", "c2p", "c2", "c3",
                                                                    "c4"]


def test_class_zero_leaves_a_gap():
    ds = stack()
    ds["avo_class"][0, 0, 0, 2] = 0
    line = by_gid(plots.avo_class_depth(ds).axes[0], "class:hs_gassmann")[0]
    x = line.get_xdata()
    assert np.isnan(x[4:6]).all() and np.isfinite(np.delete(x, [4, 5])).all()


def test_class_depth_refuses_missing_flags_and_extra_dimensions():
    ds = stack()
    del ds["avo_class"].attrs["flag_meanings"]
    with pytest.raises(ValueError, match="flag_values and flag_meanings"):
        plots.avo_class_depth(ds)
    swept = xr.concat([stack(), stack()], dim=xr.DataArray([20.0, 30.0], dims="gradient",
                                                           name="gradient"))
    with pytest.raises(ValueError, match=r"'gradient' \(2 values\).*--select gradient=20"):
        plots.avo_class_depth(swept)
    fig = plots.avo_class_depth(swept.sel(gradient=[30.0]))   # one value: drawn, and named
    assert "gradient = 30" in fig.legends[0].get_title().get_text()


def test_a_selected_fluid_is_one_column():
    fig = plots.avo_class_depth(stack().sel(fluid="gas"))
    assert [ax.get_title() for ax in fig.axes] == ["Gas"]


def test_two_interfaces_are_rows_and_panels_and_one_can_be_chosen():
    upper = stack()
    lower = stack().assign_coords(interface=["reservoir/base"])
    lower["avo_intercept"] = -lower["avo_intercept"]
    ds = xr.concat([upper, lower], dim="interface", data_vars="minimal", coords="minimal",
                   compat="override")
    ds["synthetic"] = upper["synthetic"]
    fig = plots.avo_class_depth(ds)
    assert [ax.get_title() for ax in fig.axes] == [
        f"{f}, {i}" for i in ("seal/reservoir", "reservoir/base")
        for f in ("Brine", "Gas", "CO₂")]
    fig = plots.intercept_gradient_crossplot(ds)
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    assert [ax.get_title() for ax in panels] == ["seal/reservoir", "reservoir/base"]
    (points,) = by_gid(panels[1], "trajectory:gas:hs_gassmann", "collections")
    assert np.allclose(points.get_offsets()[:, 0], -np.asarray(A["gas"]))
    fig = plots.reflectivity_angle(ds, [2000.0], interface="reservoir/base")
    assert [ax.get_title() for ax in fig.axes] == [f"{f}, depth 2000 m"
                                                   for f in ("Brine", "Gas", "CO₂")]
    assert fig.legends[0].get_title().get_text() == "reservoir/base"
    with pytest.raises(ValueError, match=r"interface='top/seal' is not in the Dataset "
                                         r"\(interface: seal/reservoir, reservoir/base\)"):
        plots.avo_class_depth(ds, interface="top/seal")


# ----------------------------------------------------------------------------- crossplot
def colorbar(fig):
    (bar,) = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
    return bar


def test_crossplot_draws_each_fluid_and_model_trajectory_coloured_by_depth():
    fig = plots.intercept_gradient_crossplot(stack())
    ax = fig.axes[0]
    points = by_gid(ax, "trajectory:", "collections")
    assert sorted(p.get_gid() for p in points) == sorted(
        f"trajectory:{f}:{m}" for f in FLUIDS for m in MODELS)
    for p in points:
        _, fluid, model = p.get_gid().split(":")
        xy = p.get_offsets()
        assert np.allclose(xy[:, 0], np.asarray(A[fluid]) + SHIFT[MODELS.index(model)])
        assert np.allclose(xy[:, 1], B[fluid])
        assert np.allclose(p.get_array(), DEPTH)
        assert (p.norm.vmin, p.norm.vmax) == (DEPTH.min(), DEPTH.max())
    bar = colorbar(fig)
    assert sorted(bar.get_ylim()) == [DEPTH.min(), DEPTH.max()]
    assert bar.get_ylabel().startswith("Depth") and bar.get_ylabel().endswith("(m)")


def test_crossplot_marks_every_kth_depth_of_a_dense_profile_and_draws_the_whole_line():
    depth = np.linspace(1000.0, 4500.0, 200)
    ds = stack().isel(depth=np.repeat(np.arange(DEPTH.size), 25)).assign_coords(depth=depth)
    ax = plots.intercept_gradient_crossplot(ds).axes[0]
    for fluid in FLUIDS:
        for i, model in enumerate(MODELS):
            (path,) = by_gid(ax, f"path:{fluid}:{model}")
            assert len(path.get_xdata()) == 200
            (points,) = by_gid(ax, f"trajectory:{fluid}:{model}", "collections")
            marked = np.asarray(points.get_array())
            assert marked.size == 40                 # every 5th of 200 depths
            assert np.array_equal(marked, depth[np.flatnonzero(np.isin(depth, marked))])
            assert np.allclose(np.diff(marked), 5 * (depth[1] - depth[0]))


def test_crossplot_background_trend_is_the_brine_least_squares_line_through_the_origin():
    fig = plots.intercept_gradient_crossplot(stack())
    (trend,) = by_gid(fig.axes[0], "background_trend")
    a = np.concatenate([np.asarray(A["brine"]) + s for s in SHIFT])
    b = np.concatenate([B["brine"]] * 2)
    # B = m A minimising sum (B - m A)^2: d/dm = 0 gives m = sum(A B) / sum(A^2)
    slope = np.dot(a, b) / np.dot(a, a)
    x, y = trend.get_xdata(), trend.get_ydata()
    assert np.allclose(y, slope * x, rtol=1e-12)
    assert not by_gid(plots.intercept_gradient_crossplot(stack().sel(fluid=["gas", "co2"]))
                      .axes[0], "background_trend")


def region_colour(ax, a, b):
    """The RGBA of the class-region image at (a, b)."""
    (image,) = [im for im in ax.images if im.get_gid() == "class_regions"]
    x0, x1, y0, y1 = image.get_extent()
    rgba = image.get_array()
    rows, cols = rgba.shape[:2]
    return rgba[int((b - y0) / (y1 - y0) * rows), int((a - x0) / (x1 - x0) * cols)]


def test_crossplot_class_regions_agree_with_the_classes_of_the_points():
    ds = stack()
    ax = plots.intercept_gradient_crossplot(ds).axes[0]
    colour = {}
    for fluid in FLUIDS:
        for k in range(DEPTH.size):
            rgba = tuple(np.round(region_colour(ax, A[fluid][k], B[fluid][k]), 6))
            assert rgba[3] > 0.0                             # inside a class region
            colour.setdefault(CLASS[fluid][k], set()).add(rgba)
    assert len(colour) == 5 and all(len(c) == 1 for c in colour.values())   # one per class
    assert len(set().union(*colour.values())) == 5                          # all different
    labels = {t.get_gid(): t.get_text() for t in ax.texts}
    assert set(labels.values()) <= set("I IIp II III IV".split())
    assert {"I", "III", "IV"} <= set(labels.values())         # the wide regions named inside
    legend = ax.figure.legends[0]
    assert [t.get_text() for t in legend.get_texts()][-5:] == [
        "class I", "class IIp", "class II", "class III", "class IV"]
    lines = by_gid(ax, "quadrants")
    assert len(lines) == 2 and {tuple(ln.get_xdata()) for ln in lines} >= {(0.0, 0.0)}


def test_crossplot_reads_the_threshold_attribute():
    ax = plots.intercept_gradient_crossplot(stack()).axes[0]
    ax5 = plots.intercept_gradient_crossplot(stack(threshold=0.05)).axes[0]
    # (0.04, -0.09) is class I at the threshold 0.02 (brine at 2500 m), IIp at 0.05
    i = region_colour(ax, 0.04, -0.09)
    iip = region_colour(ax, 0.01, -0.07)                  # brine at 2000 m: IIp
    assert np.allclose(region_colour(ax5, 0.04, -0.09), iip)
    assert not np.allclose(i, iip)
    ds = stack()
    del ds["avo_class"].attrs["threshold"]
    from rockcem.reflectivity import AVO_THRESHOLD as default   # the classification's own

    assert avo.class_threshold(ds) == default
    for bad in (-1.0, 0.0, 1.0, "high"):
        ds["avo_class"].attrs["threshold"] = bad
        with pytest.raises(ValueError, match=rf"threshold must be a number in \(0, 1\); "
                                             rf"got {bad!r}"):
            plots.intercept_gradient_crossplot(ds)


# ----------------------------------------------------------------------------- R(angle)
def test_reflectivity_angle_draws_re_and_magnitude_beyond_critical():
    fig = plots.reflectivity_angle(stack(), [1000.0, 3100.0])
    assert len(fig.axes) == 2 * len(FLUIDS)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles[:3] == ["Brine, depth 1000 m", "Gas, depth 1000 m", "CO₂, depth 1000 m"]
    assert titles[3] == "Brine, depth 3000 m"                 # the nearest sample to 3100 m
    critical = np.degrees(np.arcsin(V1 / V2["brine"]))
    for ax, fluid in zip(fig.axes, FLUIDS * 2):
        res = by_gid(ax, "re:")
        assert [ln.get_gid() for ln in res] == [f"re:{m}" for m in MODELS]
        exact = acoustic_r(V2[fluid], RHO2[fluid], ANGLE)
        assert np.allclose(res[0].get_ydata(), exact.real, rtol=0, atol=1e-12)
        magnitudes = by_gid(ax, "magnitude:")
        if fluid != "brine":
            assert magnitudes == []                       # slower below: no critical angle
            continue
        assert len(magnitudes) == len(MODELS)
        x, y = magnitudes[0].get_xdata(), magnitudes[0].get_ydata()
        drawn = np.isfinite(x)
        assert np.array_equal(x[drawn], ANGLE[ANGLE > critical])
        assert np.allclose(y[drawn], 1.0, rtol=0, atol=1e-12)   # total reflection
    # the ink entries of the legend name the line style they stand for, not a curve
    texts = [t.get_text() for t in fig.legends[0].get_texts()]
    assert texts[-2:] == ["solid: Re R_PP (exact)",
                          "dashed: |R_PP| where complex (beyond critical)"]
    fig = plots.reflectivity_angle(stack().sel(fluid=["gas", "co2"]), [2000.0])
    assert "dashed: |R_PP| where complex (beyond critical)" not in [
        t.get_text() for t in fig.legends[0].get_texts()]


def test_reflectivity_angle_refuses_depths_outside_the_range():
    with pytest.raises(ValueError, match="depths must lie within .* 1000-4500 m; got 5000"):
        plots.reflectivity_angle(stack(), [2000.0, 5000.0])
    with pytest.raises(ValueError, match="depths must name at least one depth"):
        plots.reflectivity_angle(stack(), [])


# ----------------------------------------------------------------------------- synthetics
def test_synthetic_section_draws_a_wiggle_per_model_and_fluid():
    ds = stack()
    fig = plots.synthetic_section(ds)
    assert [ax.get_title() for ax in fig.axes] == ["Brine", "Gas", "CO₂"]
    peak = np.abs(ds["synthetic"].values).max()
    for f, ax in enumerate(fig.axes):
        traces = by_gid(ax, "trace:")
        assert [t.get_gid() for t in traces] == [f"trace:{m}" for m in MODELS]
        assert len(by_gid(ax, "fill:", "collections")) == len(MODELS)
        for m, line in enumerate(traces):
            # trace m at x = m, one gain for all: the largest amplitude spans 0.45
            expected = m + 0.45 * ds["synthetic"].values[f, m] / peak
            assert np.allclose(line.get_xdata(), expected, rtol=0, atol=1e-12)
            assert np.array_equal(line.get_ydata(), TWT)
        assert ax.yaxis_inverted()
    assert fig.axes[0].get_ylabel() == "Two-way time (s)"


def test_synthetic_section_scaled_trace_by_trace():
    ds = stack(gather=True)
    fig = plots.synthetic_section(ds, scale="trace")
    for f, ax in enumerate(fig.axes[:len(FLUIDS)]):
        for m, line in enumerate(by_gid(ax, "trace:")):
            trace = ds["synthetic"].values[f, m]
            assert np.allclose(line.get_xdata(), m + 0.45 * trace / np.abs(trace).max(),
                               rtol=0, atol=1e-12)
    gather = ds["angle_gather"].values[0, 0]                  # brine, first model
    lines = by_gid(fig.axes[len(FLUIDS)], "gather:hs_gassmann:")
    drawn = ANGLE[::3]                                        # 31 angles: every 3rd, 11
    widest = max(np.abs(ln.get_xdata() - a).max() for ln, a in zip(lines, drawn))
    assert widest == pytest.approx(0.45 * 6.0)                # 0.45 of the 6° spacing
    assert np.abs(gather).max() > 0
    assert "each trace scaled to its own peak" in fig.legends[0].get_title().get_text()
    with pytest.raises(ValueError, match="scale must be 'common' or 'trace'; got 'loud'"):
        plots.synthetic_section(ds, scale="loud")


def test_wiggle_fill_covers_the_positive_lobes_to_the_zero_crossings():
    t = np.array([0.0, 1.0, 2.0, 3.0])
    y = np.array([-1.0, 3.0, 1.0, -1.0])          # crossings at t = 0.25 and 2.5
    fig, ax = plt.subplots()
    avo._wiggle(ax, 0.0, y, t, "C0", "trace", "fill")
    (fill,) = ax.collections
    path = fill.get_paths()[0].vertices
    area = 0.5 * abs(np.dot(path[:, 0], np.roll(path[:, 1], 1))
                     - np.dot(path[:, 1], np.roll(path[:, 0], 1)))
    # the positive part of the piecewise-linear trace: triangle 0.25-1 (height 3), trapezoid
    # 1-2 (3 and 1), triangle 2-2.5 (height 1)
    assert area == pytest.approx(0.5 * 0.75 * 3 + 0.5 * (3 + 1) + 0.5 * 0.5 * 1, rel=1e-12)


def test_synthetic_section_adds_the_angle_gathers():
    fig = plots.synthetic_section(stack(gather=True))
    assert len(fig.axes) == (1 + len(MODELS)) * len(FLUIDS)
    gather = fig.axes[len(FLUIDS)]                 # the first model's gather, brine
    assert gather.get_title() == "Brine: Model 1 gather"
    # 31 angles 0-60° by 2°: at most 11 traces, every 3rd (0, 6, ..., 60), each the
    # Dataset's trace at its angle
    lines = by_gid(gather, "gather:hs_gassmann:")
    assert [ln.get_gid() for ln in lines] == [f"gather:hs_gassmann:{a:g}"
                                              for a in np.arange(0.0, 61.0, 6.0)]
    gathers = stack(gather=True)["angle_gather"]
    values = gathers.sel(fluid="brine", model="hs_gassmann")
    gain = 0.45 * 6.0 / np.abs(gathers.values).max()    # one gain (the peak is at 0°, drawn)
    for line in lines[1:3]:
        angle = float(line.get_gid().split(":")[-1])
        expected = angle + gain * values.sel(angle=angle).values
        assert np.allclose(line.get_xdata(), expected, rtol=0, atol=1e-12)


def test_a_gather_of_few_angles_draws_every_one():
    ds = stack(gather=True).isel(angle=slice(0, 11))          # 11 angles: all drawn
    fig = plots.synthetic_section(ds)
    assert len(by_gid(fig.axes[len(FLUIDS)], "gather:hs_gassmann:")) == 11


# ----------------------------------------------------------------------------- CLI
@pytest.fixture
def stack_file(tmp_path):
    path = tmp_path / "stack.nc"
    stack().to_netcdf(path, engine="netcdf4")
    return path


def test_cli_plot_avo_writes_three_pngs(stack_file, capsys):
    assert cli.main(["plot", str(stack_file), "--kind", "avo"]) == 0
    names = [f"stack_avo_{part}.png" for part in ("class", "crossplot", "angle")]
    for name in names:
        assert (stack_file.parent / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert capsys.readouterr().out.strip() == "wrote " + ", ".join(
        str(stack_file.parent / n) for n in names)
    out = stack_file.parent / "fig.svg"
    assert cli.main(["plot", str(stack_file), "--kind", "avo", "-o", str(out), "-q",
                     "--select", "fluid=gas"]) == 0
    for part in ("class", "crossplot", "angle"):
        assert (stack_file.parent / f"fig_{part}.svg").read_text().lstrip().startswith("<?xml")


def test_cli_plot_avo_depths_and_selection(stack_file, drawn, capsys):
    assert cli.main(["plot", str(stack_file), "--kind", "avo", "--select", "fluid=gas"]) == 0
    assert capsys.readouterr().out.strip() == "wrote " + ", ".join(   # the selection named
        str(stack_file.parent / f"stack_fluid-gas_avo_{part}.png")
        for part in ("class", "crossplot", "angle"))
    classes, crossplot, angle = drawn
    assert [ax.get_title() for ax in classes.axes] == ["Gas"]
    # default depths: the whole kilometres within 1000-4500 m
    assert [ax.get_title() for ax in angle.axes] == [f"Gas, depth {z} m"
                                                     for z in (1000, 2000, 3000, 4000)]
    assert cli.main(["plot", str(stack_file), "--kind", "avo", "--depth", "2500"]) == 0
    assert [ax.get_title() for ax in drawn[-1].axes] == [
        f"{f}, depth 2500 m" for f in ("Brine", "Gas", "CO₂")]


@pytest.mark.parametrize("low, high, expected", [
    (1000.0, 4500.0, [1000.0, 2000.0, 3000.0, 4000.0]),   # the whole kilometres
    (0.0, 10000.0, [0.0, 3000.0, 7000.0, 10000.0]),       # 11 of them: 4 at indices 0 3 7 10
    (1200.0, 1900.0, [1375.0, 1550.0, 1725.0]),           # none: the quartiles
    (900.0, 1100.0, [950.0, 1000.0, 1050.0]),             # one: the quartiles
])
def test_cli_default_depths_of_the_angle_chart(low, high, expected):
    ds = xr.Dataset(coords={"depth": np.linspace(low, high, 5)})
    assert cli._avo_depths(ds) == pytest.approx(expected, abs=1e-9)


def test_cli_plot_synthetic_writes_one_png(stack_file, capsys):
    assert cli.main(["plot", str(stack_file), "--kind", "synthetic"]) == 0
    png = stack_file.parent / "stack_synthetic.png"
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert capsys.readouterr().out.strip() == f"wrote {png}"


def test_cli_refuses_a_file_without_avo_variables_in_one_line(tmp_path, capsys, drawn):
    path = tmp_path / "plain.nc"
    xr.Dataset({"vp": (("model", "depth"), np.ones((1, 3)), {"units": "km s-1"})},
               coords={"model": ["hs_gassmann"], "depth": [0.0, 1.0, 2.0]}).to_netcdf(path)
    for kind, name in (("avo", "avo_class"), ("synthetic", "synthetic")):
        assert cli.main(["plot", str(path), "--kind", kind]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1, err
        assert err.startswith(f"rockcem: error: plain.nc has no {name}: run a stack scene "
                              "with [seismic]")
    assert drawn == [] and sorted(p.name for p in tmp_path.iterdir()) == ["plain.nc"]


def test_cli_depth_outside_the_range_and_depth_with_another_kind(stack_file, capsys):
    assert cli.main(["plot", str(stack_file), "--kind", "avo", "--depth", "9000"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "got 9000" in err
    assert sorted(p.name for p in stack_file.parent.iterdir()) == ["stack.nc"]  # none written
    assert cli.main(["plot", str(stack_file), "--kind", "synthetic", "--depth", "2000"]) == 2
    assert "--depth chooses the depths" in capsys.readouterr().err
