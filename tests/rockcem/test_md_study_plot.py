"""`rockcem plot` on an MD study's file (Vp against cement saturation S_c, a panel per sample and
cement, error bars, the static velocity) and the MD study summary of `rockcem run`, on the
committed study outputs (benchmarks/results/garcia_medina_*.nc) and on hand-made Datasets."""

import subprocess
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
import numpy as np
import pytest
import xarray as xr
from matplotlib.container import ErrorbarContainer

from rockcem import cli, plots

RESULTS = Path(__file__).resolve().parents[2] / "benchmarks" / "results"
CEMENT = RESULTS / "garcia_medina_cement.nc"        # eq. 11 errors only
FULL = RESULTS / "garcia_medina_full.nc"            # eq. 11 and resolution errors
DIMS = ("sample", "cement", "scheme", "saturation")


@pytest.fixture(autouse=True)
def close_figures():
    yield
    plt.close("all")


def study(samples=("loose",), cements=("hard", "soft", "mixed"), schemes=("contact", "coating"),
          saturations=(0.0, 0.05, 0.1), resolution=True, static=True, units="km s-1"):
    """A hand-made MD study: Vp rising with S_c, faster for the later samples and schemes."""
    shape = tuple(map(len, (samples, cements, schemes, saturations)))
    sc = np.asarray(saturations)
    vp = (1.0 + 10.0 * sc + 0.5 * np.arange(shape[0])[:, None, None, None]
          + 0.2 * np.arange(shape[2])[None, None, :, None]) * np.ones(shape)
    kms = {"units": "km s-1"}
    data = {"vp": (DIMS, vp, {"units": units, "long_name": "P velocity of the pulse test"}),
            "vp_error": (DIMS, 0.03 + 0.1 * vp / vp.max(), kms)}
    if resolution:
        data["vp_error_resolution"] = (DIMS, 0.4 * sc * np.ones(shape), kms)
    if static:
        data["vp_static"] = (DIMS, vp + 0.1, {**kms, "long_name": "static velocity"})
    return xr.Dataset(data, coords={
        "sample": list(samples), "cement": list(cements), "scheme": list(schemes),
        "saturation": ("saturation", sc, {"units": "1", "long_name": "cement saturation S_c"})})


def bars(ax):
    """Half-lengths of the error bars of each pulse line of ``ax``, by scheme."""
    out = {}
    for container in ax.containers:
        assert isinstance(container, ErrorbarContainer) and container.has_yerr
        line, _, (collection,) = container.lines
        segments = collection.get_segments()
        out[line.get_gid().split(":", 1)[1]] = np.array([(s[1, 1] - s[0, 1]) / 2.0
                                                         for s in segments])
    return out


def gid_lines(ax, kind):
    return {ln.get_gid().split(":", 1)[1]: ln for ln in ax.get_lines()
            if (ln.get_gid() or "").startswith(f"{kind}:")}


# ----------------------------------------------------------------------------- the figure
def test_garcia_medina_cement_panels_error_bars_and_static_velocity():
    ds = xr.load_dataset(CEMENT)
    fig = plots.md_study_velocity(ds)
    axes = fig.axes
    assert len(axes) == ds.sizes["sample"] * ds.sizes["cement"] == 4
    assert [ax.get_title() for ax in axes] == [
        f"{s.capitalize()} pack ($\\sigma_{{zz}}$ {float(ds.stress.sel(sample=s)):.3g} MPa), "
        f"{c} cement" for s in ("loose", "compacted") for c in ("hard", "soft")]
    for row in (axes[:2], axes[2:]):            # a row shares its velocity axis ...
        assert row[0].get_shared_y_axes().joined(row[0], row[1])
        assert row[0].get_ylim() == row[1].get_ylim()
    assert not axes[0].get_shared_y_axes().joined(axes[0], axes[2])   # ... rows do not
    label = "P-wave velocity (km/s)"
    assert [ax.get_ylabel() for ax in axes] == [label, "", label, ""]
    assert axes[-1].get_xlabel() == "Cement saturation $S_\\mathrm{c}$ (–)"
    schemes = [str(s) for s in ds.scheme.values]
    for (i, j), ax in zip(np.ndindex(2, 2), axes):
        member = ds.isel(sample=i, cement=j)
        pulse, static = gid_lines(ax, "pulse"), gid_lines(ax, "static")
        assert list(pulse) == list(static) == schemes
        half = bars(ax)                         # no resolution error here: eq. 11 alone
        for scheme in schemes:
            m = member.sel(scheme=scheme)
            np.testing.assert_allclose(pulse[scheme].get_ydata(), m.vp, rtol=1e-12)
            np.testing.assert_allclose(static[scheme].get_ydata(), m.vp_static, rtol=1e-12)
            np.testing.assert_allclose(half[scheme], m.vp_error, rtol=1e-9)
            # side by side within 2 % of the S_c range of the true S_c
            np.testing.assert_allclose(pulse[scheme].get_xdata(), ds.saturation, rtol=0,
                                       atol=0.02 * 0.2)
    legends = [t.get_text() for lg in fig.legends for t in lg.get_texts()]
    assert legends == ["contact", "coating", "pore body",
                       "P velocity of the pulse test; bars: eq. 11 error",
                       "Long-wave velocity of the static modulus"]


def test_hand_made_study_error_bars_add_the_resolution_error_in_quadrature():
    ds = study()
    fig = plots.md_study_velocity(ds)
    assert len(fig.axes) == 3                                   # one row of three cements
    assert all(ax.get_shared_y_axes().joined(fig.axes[0], ax) for ax in fig.axes)
    expected = np.hypot(ds.vp_error, ds.vp_error_resolution)
    for j, ax in enumerate(fig.axes):
        for scheme, half in bars(ax).items():
            np.testing.assert_allclose(half, expected.isel(sample=0, cement=j)
                                       .sel(scheme=scheme), rtol=1e-9)
    assert "eq. 11 and resolution errors in quadrature" in fig.legends[1].get_texts()[0].get_text()


def test_hand_made_study_without_static_velocity_or_sample_dimension():
    ds = study(samples=("a", "b"), cements=("hard",), static=False, resolution=False)
    fig = plots.md_study_velocity(ds)
    assert len(fig.axes) == 2 and not gid_lines(fig.axes[0], "static")
    assert len(fig.legends[1].get_texts()) == 1                 # no static marker style
    one = ds.isel(sample=1)                                     # what --select sample=b leaves
    (ax,) = plots.md_study_velocity(one).axes
    assert ax.get_title() == "B pack, hard cement"
    np.testing.assert_allclose(gid_lines(ax, "pulse")["coating"].get_ydata(),
                               one.vp.sel(cement="hard", scheme="coating"), rtol=1e-12)


def test_velocity_error_is_md_calibrate_total_error():
    """The plot's error bar is md.calibrate.total_error (written again: md loads numba)."""
    from md.calibrate import total_error

    for path in (CEMENT, FULL):
        ds = xr.load_dataset(path)
        np.testing.assert_array_equal(plots.velocity_error(ds), total_error(ds))


@pytest.mark.parametrize("change, message", [
    (lambda ds: ds.rename(saturation="s"), "not an MD study: it has no 'saturation' dimension"),
    (lambda ds: ds.drop_vars("vp"), "not an MD study: it has no variable 'vp' or 'vs'"),
    (lambda ds: ds.expand_dims(depth=[1.0]), "dimension\\(s\\) depth"),
    (lambda ds: ds.assign(vp=ds.vp.assign_attrs(units="m s-1")),
     "vp_error is in 'km s-1' and vp in 'm s-1'"),
    (lambda ds: ds.assign(vp=ds.vp.drop_attrs()), "vp has no 'units' attribute"),
])
def test_md_study_velocity_errors(change, message):
    with pytest.raises(ValueError, match=message):
        plots.md_study_velocity(change(study()))


# ----------------------------------------------------------------------------- rockcem plot
def test_cli_plot_draws_an_md_study_file(tmp_path, capsys):
    out = tmp_path / "study.png"
    assert cli.main(["plot", str(CEMENT), "-o", str(out)]) == 0
    assert out.stat().st_size > 10_000 and capsys.readouterr().out == f"wrote {out}\n"


def test_cli_plot_md_study_select_and_refusals(tmp_path, drawn, capsys):
    assert cli.main(["plot", str(CEMENT), "--select", "sample=compacted"]) == 0
    assert [ax.get_title()[:14] for ax in drawn[-1].axes] == ["Compacted pack"] * 2
    for extra in (["--kind", "template"], ["--kind", "depth"], ["--well", "x.las"]):
        assert cli.main(["plot", str(CEMENT), *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "is an MD study" in err, err
    scene = tmp_path / "scene.nc"
    xr.Dataset({"vp": ("depth", [2.0, 3.0])}, coords={"depth": [0.0, 1.0]}).to_netcdf(scene)
    assert cli.main(["plot", str(scene), "--kind", "md-study"]) == 2
    assert "is a scene's output" in capsys.readouterr().err


def test_cli_plot_refuses_a_file_with_neither_depth_nor_saturation(tmp_path, drawn, capsys):
    path = tmp_path / "other.nc"
    xr.Dataset({"vp": ("x", [2.0, 3.0])}).to_netcdf(path)
    assert cli.main(["plot", str(path)]) == 2
    err = capsys.readouterr().err
    assert err == ("rockcem: error: other.nc is neither a scene's output (dimension depth) nor "
                   "an MD study's (dimension saturation); its dimensions: x\n")
    assert drawn == []


def test_cli_plot_of_an_md_study_does_not_load_numba(tmp_path):
    code = ("import sys; from rockcem import cli; "
            f"assert cli.main(['plot', {str(CEMENT)!r}, '-o', {str(tmp_path / 'f.png')!r}]) == 0; "
            "print('numba' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.splitlines()[-1] == "False"


# ----------------------------------------------------------------------------- the summary
def rows(text, label, count):
    """The values of every row labelled ``label`` in the summary, in order, as printed."""
    out, table = [], False
    for line in text.splitlines():
        tokens = line.split()
        table = table or tokens[:1] == ["S_c"]            # the legend above is not a row
        width = len(label.split())
        if (table and len(tokens) >= count + width
                and tokens[-count - width:-count] == label.split()):
            out.append(tokens[-count:])
    return out


@pytest.mark.parametrize("path", [FULL, CEMENT], ids=["full", "cement"])
def test_md_summary_prints_static_velocity_and_errors_of_the_committed_file(path):
    ds = xr.load_dataset(path)
    text = cli._md_summary(ds)
    assert max(map(len, text.splitlines())) <= 100
    n = ds.sizes["saturation"]
    for label, name in [("pulse", "vp"), ("± eq. 11", "vp_error"), ("static", "vp_static"),
                        ("± resolution", "vp_error_resolution")]:
        printed = rows(text, label, n)
        if name not in ds:
            assert printed == [] and f"{label} " not in text
            continue
        values = ds[name].transpose(*DIMS).values.reshape(-1, n)      # sample, cement, scheme
        assert printed == [[f"{x:.3f}" for x in v] for v in values], name
        assert f"{ds[name].attrs['long_name']} (km s-1)" in text.replace("\n" + " " * 16, " ")
    assert ("resolution" in text) == (path == FULL)


def test_md_summary_splits_a_wide_table_over_s_c():
    ds = study(saturations=tuple(np.linspace(0.0, 0.2, 15)))
    text = cli._md_summary(ds, width=80)
    assert max(map(len, text.splitlines())) <= 80
    headers = [line.split()[1:] for line in text.splitlines() if line.lstrip().startswith("S_c")]
    printed = [x for header in headers for x in header]
    assert printed == [f"{x:g}" for x in ds.saturation.values] and len(headers) > 1
