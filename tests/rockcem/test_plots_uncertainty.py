"""Figures of scenes with uncertain inputs (issue 32): the quantile bands along depth
(rockcem.plots.depth_bands), the template with the members' clouds (member_template), and the
single-valued figures' refusal of a Dataset of quantiles; every Dataset built by hand."""

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

from rockcem import plots  # noqa: E402
from rockcem.plots.uncertainty import default_depths, member_count  # noqa: E402

DEPTH = np.array([0.0, 1000.0, 2000.0, 3000.0])
MODELS = ["hs_gassmann", "patchy_cement"]
Q = [0.1, 0.5, 0.9]
#: vp (quantile, model, depth), km/s: distinct numbers, so a band edge drawn from the wrong
#: quantile or model shows.
VP = np.array([[[2.0, 2.5, 3.0, 3.5], [2.1, 2.7, 3.2, 3.8]],
               [[2.2, 2.8, 3.3, 3.9], [2.3, 2.9, 3.5, 4.1]],
               [[2.6, 3.1, 3.7, 4.3], [2.7, 3.4, 3.9, 4.6]]])
POROSITY = np.array([[0.30, 0.25, 0.18, 0.10], [0.33, 0.28, 0.22, 0.15],
                     [0.35, 0.31, 0.26, 0.20]])          # (quantile, depth)


def bands(quantiles=Q, vp=VP):
    return xr.Dataset({"vp": (("quantile", "model", "depth"), vp),
                       "porosity": (("quantile", "depth"), POROSITY[:len(quantiles)]
                                    if len(quantiles) <= 3 else
                                    np.linspace(0.3, 0.35, len(quantiles))[:, None]
                                    + 0 * DEPTH)},
                      coords={"quantile": quantiles, "model": MODELS, "depth": DEPTH})


#: Three members at two depths: density (member, depth) and vp, vs (member, model, depth) for
#: one model; chosen so that the quantiles of the product differ from the product of the
#: quantiles (median of rho vp 6.0 against 2.2 x 2.5 = 5.5 at 1000 m).
RHO_M = np.array([[2.0, 2.1], [2.2, 2.3], [2.4, 2.5]])
VP_M = np.array([[2.0, 3.0], [3.0, 3.2], [2.5, 3.4]])
VS_M = np.array([[1.0, 1.5], [1.5, 2.0], [1.25, 2.0]])


def with_members():
    depth = np.array([1000.0, 2000.0])
    q = np.quantile(RHO_M, Q, axis=0)
    return xr.Dataset(
        {"density": (("quantile", "depth"), q),
         "vp": (("quantile", "model", "depth"), np.quantile(VP_M, Q, axis=0)[:, None]),
         "vs": (("quantile", "model", "depth"), np.quantile(VS_M, Q, axis=0)[:, None]),
         "density_members": (("member", "depth"), RHO_M),
         "vp_members": (("member", "model", "depth"), VP_M[:, None]),
         "vs_members": (("member", "model", "depth"), VS_M[:, None])},
        coords={"quantile": Q, "model": ["patchy_cement"], "depth": depth,
                "member": [0, 1, 2]},
        attrs={"lithology": "sandstone", "grain": "quartz", "cement": "quartz_cement",
               "fluid": "water", "critical_porosity": 0.36,
               "uncertain_json": '{"samples": 3, "sensitivity": false}'})


def _panel(fig, start):
    return next(ax for ax in fig.axes if ax.get_xlabel().startswith(start))


def _gid(ax, gid):
    found = [a for a in [*ax.lines, *ax.collections] if a.get_gid() == gid]
    assert len(found) == 1, (gid, [a.get_gid() for a in [*ax.lines, *ax.collections]])
    return found[0]


def test_band_fills_between_the_lowest_and_highest_quantile_per_model():
    fig = plots.depth_bands(bands())
    ax = _panel(fig, "P-wave")
    for i, model in enumerate(MODELS):
        vertices = _gid(ax, f"band:{model}").get_paths()[0].vertices
        for k, z in enumerate(DEPTH):
            xs = set(np.round(vertices[vertices[:, 1] == z, 0], 12))
            assert xs == {VP[0, i, k], VP[2, i, k]}, (model, z, xs)
    porosity = _panel(fig, "Porosity")
    vertices = _gid(porosity, "band:porosity").get_paths()[0].vertices
    assert set(np.round(vertices[vertices[:, 1] == 2000.0, 0], 12)) == {0.18, 0.26}
    assert porosity.yaxis_inverted()
    plt.close(fig)


def test_median_line_is_quantile_half_and_other_quantiles_are_dotted():
    fig = plots.depth_bands(bands())
    ax = _panel(fig, "P-wave")
    for i, model in enumerate(MODELS):
        line = _gid(ax, f"median:{model}")
        np.testing.assert_array_equal(line.get_xdata(), VP[1, i])
        np.testing.assert_array_equal(line.get_ydata(), DEPTH)
    assert not [ln for ln in ax.lines if str(ln.get_gid()).startswith("quantile=")]
    plt.close(fig)
    five = np.stack([VP[0], VP[0] + 0.1, VP[1], VP[2] - 0.1, VP[2]])
    fig = plots.depth_bands(bands([0.05, 0.25, 0.5, 0.75, 0.95], five))
    ax = _panel(fig, "P-wave")
    np.testing.assert_array_equal(_gid(ax, "quantile=0.25:patchy_cement").get_xdata(),
                                  VP[0, 1] + 0.1)
    np.testing.assert_array_equal(_gid(ax, "median:patchy_cement").get_xdata(), VP[1, 1])
    vertices = _gid(ax, "band:hs_gassmann").get_paths()[0].vertices
    assert set(np.round(vertices[vertices[:, 1] == 0.0, 0], 12)) == {2.0, 2.6}
    plt.close(fig)


def test_unsorted_quantiles_band_still_spans_lowest_to_highest():
    ds = bands().isel(quantile=[2, 0, 1])                 # 0.9, 0.1, 0.5
    fig = plots.depth_bands(ds, "vp")
    vertices = _gid(fig.axes[0], "band:hs_gassmann").get_paths()[0].vertices
    assert set(np.round(vertices[vertices[:, 1] == 3000.0, 0], 12)) == {3.5, 4.3}
    np.testing.assert_array_equal(_gid(fig.axes[0], "median:hs_gassmann").get_xdata(),
                                  VP[1, 0])
    plt.close(fig)


def test_impedance_and_vp_vs_panels_are_quantiles_of_the_members():
    fig = plots.depth_bands(with_members())
    labels = [ax.get_xlabel().replace("\n", " ") for ax in fig.axes]
    assert labels[-2].startswith("Acoustic impedance") and labels[-1] == "Vp/Vs (–)"
    ai = _gid(fig.axes[-2], "median:patchy_cement")
    # rho vp of the members at 1000 m: 4.0, 6.6, 6.0 -> median 6.0 (not 2.2 x 2.5 = 5.5);
    # at 2000 m: 6.3, 7.36, 8.5 -> 7.36
    np.testing.assert_allclose(ai.get_xdata(), [6.0, 7.36], rtol=1e-12)
    # quantile 0.1 and 0.9 of (4.0, 6.0, 6.6), linear: 4.0 + 0.2 * 2.0 and 6.0 + 0.8 * 0.6
    vertices = _gid(fig.axes[-2], "band:patchy_cement").get_paths()[0].vertices
    np.testing.assert_allclose(sorted(set(vertices[vertices[:, 1] == 1000.0, 0])),
                               [4.4, 6.48], rtol=1e-12)
    ratio = _gid(fig.axes[-1], "median:patchy_cement")
    np.testing.assert_allclose(ratio.get_xdata(), [2.0, 1.7], rtol=1e-12)   # vp/vs: 2, 2, 2
    plt.close(fig)                                         # and 2, 1.6, 1.7


def test_impedance_without_members_refused_saying_members_true():
    with pytest.raises(ValueError, match=r"members = true"):
        plots.depth_bands(bands(), ["vp", "acoustic_impedance"])
    fig = plots.depth_bands(bands())                       # default: no such panel
    assert [ax.get_xlabel() for ax in fig.axes] == ["Porosity (–)", "P-wave velocity (km/s)"]
    plt.close(fig)


def test_band_refusals():
    plain = bands().isel(quantile=1, drop=True)
    with pytest.raises(ValueError, match="no 'quantile' dimension"):
        plots.depth_bands(plain)
    with pytest.raises(ValueError, match=r"one quantile \(0.5\)"):
        plots.depth_bands(bands().isel(quantile=[1]))
    swept = xr.concat([bands(), bands()], dim=xr.DataArray([20.0, 30.0], dims="gradient",
                                                          name="gradient"))
    with pytest.raises(ValueError, match=r"sweeps gradient: select one value of 'gradient'.*"
                                         r"--select gradient=20"):
        plots.depth_bands(swept)
    with pytest.raises(ValueError, match="did you mean 'porosity'"):
        plots.depth_bands(bands(), ["porosty"])


def test_single_valued_figures_on_quantiles_band_or_refuse_by_name():
    fig = plots.depth_trends(bands())                      # the median and the band
    assert _gid(_panel(fig, "P-wave"), "band:patchy_cement") is not None
    plt.close(fig)
    ds = bands().assign(density=(("quantile", "depth"), 2.0 + POROSITY),
                        vs=bands().vp / 1.8)
    ds.attrs.update(grain="quartz", cement="quartz_cement", fluid="water")
    for draw, instead in ((plots.velocity_porosity, "depth_bands"),
                          (plots.rock_physics_template, "member_template")):
        with pytest.raises(ValueError, match=rf"quantiles of uncertain members.*{instead}.*"
                                             r"quantile=0.5"):
            draw(ds)
    fig = plots.rock_physics_template(ds.sel(quantile=0.5))   # one quantile chosen: drawn
    assert [c for c in fig.axes[0].collections if c.get_gid() == "model:patchy_cement"]
    plt.close(fig)


def test_member_clouds_one_point_per_member_at_each_depth():
    ds = with_members()
    fig = plots.member_template(ds, depths=[1010.0, 1990.0])   # snap to 1000 and 2000 m
    ax = fig.axes[0]
    clouds = {c.get_gid(): c.get_offsets() for c in ax.collections
              if str(c.get_gid()).startswith("members:")}
    assert sorted(clouds) == ["members:patchy_cement:1000", "members:patchy_cement:2000"]
    for k, z in enumerate((1000, 2000)):
        points = np.asarray(clouds[f"members:patchy_cement:{z}"])
        assert points.shape == (3, 2)
        expected = np.column_stack([RHO_M[:, k] * VP_M[:, k], VP_M[:, k] / VS_M[:, k]])
        np.testing.assert_allclose(points, expected, rtol=1e-12)
    x0, x1 = ax.get_xlim()
    assert x0 < 4.0 and x1 > 8.5                            # every member inside the axes
    colours = {gid: tuple(c.get_facecolor()[0][:3]) for c in ax.collections
               if str(gid := c.get_gid()).startswith("members:")}
    assert len(set(colours.values())) == 2                  # one colour per depth
    legend = [t.get_text() for lg in fig.legends for t in lg.get_texts()]
    assert "1000 m" in legend and "2000 m" in legend
    plt.close(fig)


def test_member_template_refusals():
    with pytest.raises(ValueError, match=r"has none .*members = true in \[uncertain\]"):
        plots.member_template(bands())
    with pytest.raises(ValueError, match="range 1000-2000 m; got 5000"):
        plots.member_template(with_members(), depths=[5000.0])
    with pytest.raises(ValueError, match="at least one depth"):
        plots.member_template(with_members(), depths=[])


def test_member_count_and_default_depths():
    assert member_count(with_members()) == 3
    sobol = xr.Dataset(attrs={"uncertain_json": '{"samples": 256, "sensitivity": true}'})
    assert member_count(sobol) == 512                       # A and B of the Saltelli design
    assert member_count(xr.Dataset(coords={"member": np.arange(7)})) == 7
    assert default_depths(xr.Dataset(coords={"depth": [0.0, 6000.0]})) == [2000.0, 3000.0,
                                                                         4000.0]
    assert default_depths(xr.Dataset(coords={"depth": [0.0, 1000.0]})) == [250.0, 500.0, 750.0]
    fig = plots.depth_bands(with_members(), "vp")
    legend = " ".join(t.get_text() for lg in fig.legends for t in lg.get_texts())
    assert "quantile 0.1–0.9 of 3 members" in legend
    plt.close(fig)
