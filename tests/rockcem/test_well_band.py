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
