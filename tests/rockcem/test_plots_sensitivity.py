"""The tornado chart of Sobol' indices (rockcem.plots.sobol_tornado) on a Dataset built by
hand: each bar's width is the Dataset's index, the inputs sorted by the total index."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402

from rockcem.plots import sobol_tornado  # noqa: E402

INPUTS = ["path.gradient", "sandstone.grain_size", "pressure.sediment_density"]
TOTAL = np.array([[0.6, 0.2], [0.3, 0.7], [0.1, 0.05]])       # (input, depth)
FIRST = np.array([[0.5, 0.15], [0.25, 0.6], [0.05, 0.0]])


def _ds(model_dim=True):
    dims = ("input", "model", "depth") if model_dim else ("input", "depth")

    def arr(a):
        return np.stack([a, a / 2], axis=1) if model_dim else a

    coords = {"input": INPUTS, "depth": [1000.0, 2000.0]}
    if model_dim:
        coords["model"] = ["hs_gassmann", "patchy_cement"]
    return xr.Dataset({"vp_sobol_total": (dims, arr(TOTAL)),
                       "vp_sobol_first": (dims, arr(FIRST)),
                       "vp_sobol_total_se": (dims, arr(TOTAL * 0 + 0.02))}, coords=coords)


def _bars(ax, kind):
    return {p.get_gid().split(":", 1)[1]: (p.get_width(), p.get_y() + p.get_height() / 2)
            for p in ax.patches if str(p.get_gid()).startswith(kind + ":")}


def test_bars_are_the_indices_sorted_by_total():
    fig = sobol_tornado(_ds(), "vp", depths=[990.0, 2100.0], model="hs_gassmann")
    for ax, k in zip(fig.axes, (0, 1)):
        total, first = _bars(ax, "total"), _bars(ax, "first")
        for i, name in enumerate(INPUTS):
            assert total[name][0] == pytest.approx(TOTAL[i, k])
            assert first[name][0] == pytest.approx(FIRST[i, k])
        heights = [total[name][1] for name in INPUTS]       # larger total higher up
        assert np.argsort(heights).tolist() == np.argsort(TOTAL[:, k]).tolist()
    assert [ax.get_title() for ax in fig.axes] == ["1000 m", "2000 m"]
    half = _bars(sobol_tornado(_ds(), "vp", depths=[1000.0], model="patchy_cement").axes[0],
                 "total")
    assert half["path.gradient"][0] == pytest.approx(0.3)


def test_refusals():
    with pytest.raises(ValueError, match="no vs_sobol_total"):
        sobol_tornado(_ds(), "vs", model="hs_gassmann")
    with pytest.raises(ValueError, match="model must name one of"):
        sobol_tornado(_ds(), "vp")
    with pytest.raises(ValueError, match="'md' is not one of"):
        sobol_tornado(_ds(), "vp", model="md")
    fig = sobol_tornado(_ds(model_dim=False), "vp", depths=[1000.0])   # no model dimension
    assert len(fig.axes) == 1
