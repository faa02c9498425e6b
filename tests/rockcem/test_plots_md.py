"""Honest display of MD members (issue 29, item 6): errors and trust read in one place, the
template at the MD sample's own density with propagated error bars, per-member flags on the
depth trends, and the run summary's table of MD depths. Expected values are worked by hand."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from rockcem import plots  # noqa: E402
from rockcem.variables import build_dataset, md_error_trusted  # noqa: E402

NAN = np.nan


def md_dataset(**extra):
    """Five depths (0-2000 m), Model 4 at each and two MD members at 1000 and 2000 m (values
    given below at 0, 1000 and 2000 m; 500 and 1500 m interpolated, or NaN for the MD)."""
    depth = [0.0, 500.0, 1000.0, 1500.0, 2000.0]
    models = ["patchy_cement", "md_coating", "md_contact"]

    def five(values):
        values = np.asarray(values, dtype=float)
        return np.interp(depth, [0.0, 1000.0, 2000.0], values) if np.isfinite(values).all() \
            else np.array([values[0], NAN, values[1], NAN, values[2]])

    def per_model(m4, coat, cont):
        return (("model", "depth"), np.array([five(m4), five(coat), five(cont)]))

    data = {
        "porosity": (("depth",), five([0.36, 0.30, 0.20])),
        "cement_fraction": (("depth",), five([0.0, 0.02, 0.10])),
        "density": (("depth",), five([2.05, 2.15, 2.31])),
        "vp": per_model([2.6, 3.0, 3.6], [NAN, 2.0, 3.0], [NAN, 2.5, 3.2]),
        "vs": per_model([1.5, 1.8, 2.2], [NAN, 0.8, 1.6], [NAN, 1.2, 1.9]),
        # coating: 0.03, 0.04 -> 0.05 at 1000 m; contact: vs error 1.3 >= vs 1.2 at 1000 m
        "vp_error_resolution": per_model([NAN] * 3, [NAN, 0.03, 0.3], [NAN, 0.1, 0.05]),
        "vp_error_sample": per_model([NAN] * 3, [NAN, 0.04, 0.4], [NAN, NAN, 0.0]),
        "vs_error_resolution": per_model([NAN] * 3, [NAN, 0.02, 0.1], [NAN, 1.3, 0.02]),
        "vs_error_sample": per_model([NAN] * 3, [NAN, 0.0, 0.0], [NAN, NAN, 0.0]),
        "md_resolution_asymptotic": per_model([NAN] * 3, [NAN, 1, 0], [NAN, 1, 1]),
        "md_density": per_model([NAN] * 3, [NAN, 2.10, 2.25], [NAN, 2.10, 2.25]),
    }
    data.update(extra)
    return build_dataset(data, {"depth": (("depth",), depth), "model": (("model",), models)},
                         {"grain": "quartz", "cement": "quartz_cement", "fluid": "water",
                          "lithology": "sandstone"})


def test_fallback_error_is_the_quadrature_sum_and_flag_needs_error_below_value():
    ds = md_dataset()
    error, trusted = md_error_trusted(ds, "vp", model="md_coating")
    np.testing.assert_allclose(error.values, [NAN, NAN, 0.05, NAN, 0.5], rtol=1e-12)  # 3-4-5
    assert trusted.values[[2, 4]].tolist() == [1.0, 0.0]
    assert np.isnan(trusted.values[[0, 1, 3]]).all()
    error, trusted = md_error_trusted(ds, "vs", model="md_contact")
    # a NaN part (the sample error) is left out
    np.testing.assert_allclose(error.values, [NAN, NAN, 1.3, NAN, 0.02], rtol=1e-12)
    # asymptotic at 1000 m, but its vs error (1.3) reaches vs (1.2): not trusted
    assert trusted.values[[2, 4]].tolist() == [0.0, 1.0]
    error, trusted = md_error_trusted(ds, "vp", model="patchy_cement")
    assert np.isnan(error.values).all() and np.isnan(trusted.values).all()


def test_total_error_and_md_trusted_are_read_when_present():
    nan = [NAN] * 5
    ds = md_dataset(vp_error=(("model", "depth"), [nan, [NAN, NAN, 0.2, NAN, 0.1], nan]),
                    md_trusted=(("model", "depth"), [nan, [NAN, NAN, 0, NAN, 1], nan]))
    error, trusted = md_error_trusted(ds, "vp", model="md_coating")
    np.testing.assert_allclose(error.values[[2, 4]], [0.2, 0.1])
    assert trusted.values[[2, 4]].tolist() == [0.0, 1.0]


def _offsets(fig, gid):
    return np.concatenate([c.get_offsets() for ax in fig.axes for c in ax.collections
                           if c.get_gid() == gid] or [np.empty((0, 2))])


#: Model 4 slower near the surface (Vp/Vs 1.8/0.7 = 2.57, impedance 2.05 * 1.8 = 3.69 at
#: 0 m), so that the axes, which span the template and the profiles' models, hold every MD
#: point of md_dataset (the MD values as there).
TALL = {"vp": (("model", "depth"), np.array([[1.8, 2.4, 3.0, 3.3, 3.6],
                                               [NAN, NAN, 2.0, NAN, 3.0],
                                               [NAN, NAN, 2.5, NAN, 3.2]])),
        "vs": (("model", "depth"), np.array([[0.7, 1.2, 1.8, 2.0, 2.2],
                                               [NAN, NAN, 0.8, NAN, 1.6],
                                               [NAN, NAN, 1.2, NAN, 1.9]]))}


def test_template_puts_md_points_at_md_density_with_propagated_bars():
    fig = plots.rock_physics_template(md_dataset(**TALL))
    # md_coating at 1000 m is trusted: impedance 2.10 * 2.0 (not burial's 2.15 * 2.0)
    np.testing.assert_allclose(_offsets(fig, "model:md_coating"), [[4.2, 2.5]], rtol=1e-12)
    np.testing.assert_allclose(_offsets(fig, "model:md_coating:untrusted"),
                               [[2.25 * 3.0, 3.0 / 1.6]], rtol=1e-12)
    bars = [seg for ax in fig.axes for c in ax.collections
            if c.get_gid() == "errorbar:md_coating" for seg in c.get_segments()]
    horizontal = [s for s in bars if np.isclose(s[0][1], s[1][1])]
    vertical = [s for s in bars if np.isclose(s[0][0], s[1][0])]
    # sigma_I = rho sigma_vp = 2.10 * 0.05; sigma_r = 2.5 sqrt((0.05/2)^2 + (0.02/0.8)^2)
    widths = sorted(abs(s[1][0] - s[0][0]) / 2 for s in horizontal)
    assert widths[0] == pytest.approx(2.10 * 0.05, rel=1e-9)
    heights = sorted(abs(s[1][1] - s[0][1]) / 2 for s in vertical)
    assert heights[0] == pytest.approx(2.5 * np.hypot(0.05 / 2.0, 0.02 / 0.8), rel=1e-9)
    plt.close(fig)


def test_template_lower_bar_stops_at_zero_and_leaves_the_axis_alone():
    """md_contact at 1000 m: vs 1.2 +- 1.3, so Vp/Vs 2.083 +- (more than itself)."""
    fig = plots.rock_physics_template(md_dataset(**TALL))
    ax = fig.axes[0]
    segments = [s for c in ax.collections if c.get_gid() == "errorbar:md_contact"
                for s in c.get_segments()]
    assert min(min(p[1] for p in s) for s in segments) == 0.0    # clipped, not below
    assert any(c.get_linestyle()[0][1] is not None for c in ax.collections
               if c.get_gid() == "errorbar:md_contact")            # dashed: untrusted
    assert ax.get_ylim()[0] > 1.0          # the bar does not drag the axis to zero
    plt.close(fig)


def test_template_axes_span_the_template_and_profiles_and_mark_md_points_beyond():
    """Issue 30: MD points up to Vp/Vs 3.1 squashed the template. The axes span the template
    and Model 4's profile (Vp/Vs 1.64-1.73); md_coating at 1000 m (Vp/Vs 2.0/0.8 = 2.5,
    impedance 2.10 * 2.0 = 4.2, left of the template too) and 2000 m (3.0/1.6 = 1.875) and
    md_contact at 1000 m (2.5/1.2 = 2.083) are drawn at the top edge, with their values."""
    ds = md_dataset()
    fig = plots.rock_physics_template(ds)
    ax = fig.axes[0]
    (left, right), (bottom, top) = ax.get_xlim(), ax.get_ylim()
    assert 1.73 < top < 1.875 and bottom < 1.64
    marks = [ln for ln in ax.get_lines() if str(ln.get_gid()).startswith("beyond:")]
    assert sorted(ln.get_gid() for ln in marks) == ["beyond:md_coating"] * 2 \
        + ["beyond:md_contact"]
    at = sorted((ln.get_xdata()[0], ln.get_ydata()[0], ln.get_marker()) for ln in marks)
    assert at == [(left, top, "^"), (2.10 * 2.5, top, "^"), (2.25 * 3.0, top, "^")]
    assert 4.2 < left                                      # the coating at 1000 m: clamped
    texts = {t.get_text() for t in ax.texts}
    assert {"Vp/Vs 2.50", "Vp/Vs 1.88", "Vp/Vs 2.08"} <= texts
    # the points within the axes are drawn as before; none of those beyond
    assert _offsets(fig, "model:md_coating").shape == (0, 2)
    assert _offsets(fig, "model:md_coating:untrusted").shape == (0, 2)
    inside = _offsets(fig, "model:md_contact")            # 2000 m: 3.2 / 1.9
    np.testing.assert_allclose(inside, [[2.25 * 3.2, 3.2 / 1.9]], rtol=1e-12)
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert "MD point beyond the axes\n(at the edge, with its value)" in labels
    plt.close(fig)
    fig = plots.rock_physics_template(md_dataset(**TALL))   # all within: no marks
    assert not [ln for ln in fig.axes[0].get_lines() if str(ln.get_gid()).startswith("beyond")]
    plt.close(fig)


def test_depth_trends_mark_untrusted_points_hollow_and_band_each_member():
    ds = md_dataset().assign_attrs(validity_warnings=(
        "MD model at 1000–2000 m: the MD sample's porosity exceeds burial's by 0.02–0.07\n"
        "quartz cement at 1500–2000 m: overfill"))
    fig = plots.depth_trends(ds, ["porosity", "vp", "vs"])
    porosity, vp, vs = fig.axes[:3]
    # the MD lines of the warnings shade nothing on their own; the cement one shades everything
    spans = sorted((round(p.get_y()), round(p.get_y() + p.get_height()))
                   for p in porosity.patches if p.get_gid() == "flagged")
    assert spans == [(1500, 2000)]
    assert not [p for p in porosity.patches if str(p.get_gid()).startswith("untrusted")]
    for ax in (vp, vs):
        bands = {p.get_gid(): p for p in ax.patches if str(p.get_gid()).startswith("untrusted")}
        # coating untrusted at 2000 m (not asymptotic); contact at 1000 m (vs error >= vs)
        assert set(bands) == {"untrusted:md_coating", "untrusted:md_contact"}
        coat, cont = bands["untrusted:md_coating"], bands["untrusted:md_contact"]
        assert coat.get_y() <= 2000.0 <= coat.get_y() + coat.get_height()      # stripes
        assert cont.get_y() <= 1000.0 <= cont.get_y() + cont.get_height()
        hollow = [ln for ln in ax.lines if ln.get_gid() == "untrusted" and len(ln.get_xdata())]
        assert sorted(float(ln.get_ydata()[0]) for ln in hollow) == [1000.0, 2000.0]
        assert all(ln.get_markerfacecolor() in ("white", "w", (1.0, 1.0, 1.0, 1.0))
                   for ln in hollow)
        assert ax.get_xlim()[0] > 0.3          # the untrusted bar leaves the axis alone
    plt.close(fig)


def test_run_summary_tables_the_md_depths():
    from rockcem.cli import _summary

    text = _summary(md_dataset().assign_attrs(scene_name="x"))
    assert "md_coating: vp nan" not in text
    lines = text.splitlines()
    assert "1500" not in text                          # only the MD depths
    start = lines.index("  md_contact:")
    assert lines[start + 2].split() == ["1000", "2.500", "±", "0.100", "1.200", "±", "1.300",
                                        "no"]
    assert lines[start + 3].split() == ["2000", "3.200", "±", "0.050", "1.900", "±", "0.020",
                                        "yes"]
    coat = lines.index("  md_coating:")
    assert lines[coat + 2].split()[1:4] == ["2.000", "±", "0.050"]
