"""The tornado chart of Sobol' sensitivity indices (issue 32): which uncertain input drives the
spread of an output at chosen depths."""

from __future__ import annotations

import numpy as np

from ._style import _label

__all__ = ["sobol_tornado"]


def sobol_tornado(ds, variable="vp", depths=(2000.0, 3000.0, 4000.0), *, model=None, fig=None):
    """Sobol' indices of ``variable`` at ``depths``: one panel per depth, one bar pair per
    uncertain input, sorted by the total index (largest on top).

    The wide light bar is the total index (the input's share of the variance with all its
    interactions; Jansen 1999), the narrow dark bar inside it the first-order index (its share
    alone; Saltelli et al. 2010), both with their standard errors as whiskers where the Dataset
    has them (``<variable>_sobol_first_se``, ``..._total_se``).

    Parameters
    ----------
    ds : xarray.Dataset
        A scene run with ``[uncertain] sensitivity = true``: ``<variable>_sobol_first`` and
        ``<variable>_sobol_total`` along ``input`` (and ``model``), ``depth``.
    variable : str
        The output: ``temperature``, ``porosity``, ``density``, ``vp`` or ``vs`` (those the
        scene computed).
    depths : sequence of float
        Depths, m; each snaps to the nearest depth of the Dataset.
    model : str, optional
        The model (required where the indices have a ``model`` dimension of more than one).
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        ``len(depths)`` axes; the bars carry the ``gid`` ``"total:<input>"`` and
        ``"first:<input>"``.

    Raises
    ------
    ValueError
        The Dataset has no indices of ``variable``, ``model`` is missing or unknown, or
        ``depths`` is empty.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = xr.Dataset({"vp_sobol_total": (("input", "depth"), [[0.7], [0.2]]),
    ...                  "vp_sobol_first": (("input", "depth"), [[0.6], [0.1]])},
    ...                 coords={"input": ["path.gradient", "sandstone.grain_size"],
    ...                         "depth": [3000.0]})
    >>> fig = sobol_tornado(ds, "vp", depths=[3000.0])
    >>> [t.get_text() for t in fig.axes[0].get_yticklabels()]   # largest total on top
    ['sandstone.grain_size', 'path.gradient']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    first_name, total_name = f"{variable}_sobol_first", f"{variable}_sobol_total"
    if first_name not in ds or total_name not in ds:
        raise ValueError(f"the Dataset has no {total_name}: run the scene with [uncertain] "
                         "sensitivity = true (and the variable among its outputs)")
    picked = {}
    if "model" in ds[total_name].dims:
        models = [str(m) for m in ds["model"].values]
        if model is None and len(models) > 1:
            raise ValueError(f"model must name one of {', '.join(models)}")
        if model is not None and model not in models:
            raise ValueError(f"model {model!r} is not one of {', '.join(models)}")
        picked["model"] = model if model is not None else models[0]
    depths = [float(d) for d in np.atleast_1d(depths)]
    if not depths:
        raise ValueError("depths must name at least one depth (m)")
    z = ds["depth"].values
    at = [float(z[np.argmin(np.abs(z - d))]) for d in depths]
    inputs = [str(k) for k in ds["input"].values]

    def values(name, depth):
        if name not in ds:
            return np.full(len(inputs), np.nan)
        return np.asarray(ds[name].sel(depth=depth, **picked).transpose("input").values,
                          dtype=float)

    import matplotlib.pyplot as plt

    if fig is None:
        fig = plt.figure(figsize=(3.2 * len(at) + 1.8, 0.45 * len(inputs) + 1.6),
                         layout="constrained")
    axes = fig.subplots(1, len(at), sharex=True, squeeze=False)[0]
    for ax, depth in zip(axes, at):
        total, first = values(total_name, depth), values(first_name, depth)
        t_se, f_se = values(f"{total_name}_se", depth), values(f"{first_name}_se", depth)
        order = np.argsort(np.where(np.isfinite(total), total, -np.inf), kind="stable")
        y = np.arange(len(inputs))
        for row, k in zip(y, order):
            ax.barh(row, total[k], height=0.7, color="#9ecae1", gid=f"total:{inputs[k]}",
                    xerr=None if not np.isfinite(t_se[k]) else t_se[k], ecolor="#6b6b6b",
                    capsize=2)
            ax.barh(row, first[k], height=0.35, color="#08519c", gid=f"first:{inputs[k]}",
                    xerr=None if not np.isfinite(f_se[k]) else f_se[k], ecolor="#333333",
                    capsize=2)
        ax.set_yticks(y, [inputs[k] for k in order])
        ax.set_xlim(0.0, 1.05)
        ax.set_title(f"{depth:g} m")
        ax.set_xlabel("Sobol' index (–)")
    what = _label(variable, ds) if variable in ds else variable
    fig.suptitle(f"{what}" + (f", {picked['model']}" if "model" in picked else "")
                 + ": total (light) and first-order (dark) Sobol' indices")
    return fig
