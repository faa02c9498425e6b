"""Depth-trend figures: one panel per variable, depth downward, one line per model."""

from __future__ import annotations


import numpy as np

from ._style import (_INK, _LINESTYLES, _DEFAULT_TRENDS, _RC, _attrs, _label, _model_label,
                     _model_colour, _shade, _model_width, _capital, _sweep_text,
                     _check_dataset, _require, _figure)

__all__ = ["depth_trends"]


def depth_trends(ds, variables=None, *, fig=None):
    """Depth trends of scene variables, one panel per variable, depth increasing downward.

    Model-dependent variables (those with a ``model`` dimension) get one line per model in the
    model's colour; model-independent ones are drawn in dark grey. If the variables have one
    further (sweep) dimension, e.g. ``gradient``, each of its values gets its own line style
    and a lighter shade, and the legend gives its value and unit.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset: dimension ``depth`` (coordinate in m), optional ``model`` (labels such as
        ``"hs_gassmann"``) and at most one sweep dimension among the plotted variables.
    variables : sequence of str, optional
        Variables to plot, one panel each, in this order. Default: those of ``porosity``,
        ``cement_fraction``, ``illite_fraction``, ``density``, ``vp``, ``vs`` in ``ds``.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per variable, sharing the (inverted) depth axis.

    Raises
    ------
    ValueError
        If ``ds`` has no ``depth`` dimension, a variable is not in ``ds`` (the closest name is
        suggested) or lacks the depth dimension, or the variables have more than one sweep
        dimension besides ``depth`` and ``model`` (select one slice with ``ds.sel`` first).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> depth = np.linspace(0.0, 3000.0, 31)
    >>> vp = np.stack([2.0 + 1e-3 * depth, 2.1 + 1e-3 * depth])
    >>> ds = build_dataset({"porosity": (("depth",), 0.36 - 1e-4 * depth),
    ...                     "vp": (("model", "depth"), vp)},
    ...                    {"depth": (("depth",), depth),
    ...                     "model": (("model",), ["hs_gassmann", "patchy_cement"])})
    >>> fig = depth_trends(ds)
    >>> [ax.get_xlabel() for ax in fig.axes]
    ['Porosity (–)', 'P-wave velocity (km/s)']
    >>> bool(fig.axes[0].yaxis_inverted())
    True
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    _check_dataset(ds)
    if variables is None:
        variables = [v for v in _DEFAULT_TRENDS if v in ds.data_vars]
        if not variables:
            raise ValueError("ds has none of the default variables "
                             f"({', '.join(_DEFAULT_TRENDS)}); pass variables=")
    elif isinstance(variables, str):
        variables = [variables]
    variables = list(variables)
    if not variables:
        raise ValueError("variables must name at least one variable")
    arrays = []
    for name in variables:
        da = _require(ds, name, "depth_trends")
        if "depth" not in da.dims:
            raise ValueError(f"variable {name!r} has no 'depth' dimension (dims: {da.dims})")
        arrays.append(da)
    extra = sorted({str(d) for da in arrays for d in da.dims} - {"depth", "model"})
    if len(extra) > 1:
        raise ValueError(f"the variables have more than one sweep dimension ({', '.join(extra)}); "
                         "select one slice with ds.sel(...) or ds.isel(...) first, e.g. "
                         f"ds.sel({extra[0]}=...)")
    sweep = extra[0] if extra else None
    sweep_values = list(ds[sweep].values) if sweep else [None]
    models = list(ds["model"].values) if "model" in ds.dims else []
    depth = np.asarray(ds["depth"].values, dtype=float)

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.0 + 2.0 * len(variables), 5.2))
        axes = np.atleast_1d(fig.subplots(1, len(variables), sharey=True, squeeze=False)[0])
        for k, (ax, da) in enumerate(zip(axes, arrays, strict=True)):
            series = [(m, i) for i, m in enumerate(models)] if "model" in da.dims else [(None, 0)]
            swept = sweep is not None and sweep in da.dims
            for model, i in series:
                colour = _model_colour(model, i) if model is not None else _INK
                width = _model_width(i, len(models)) if model is not None else 1.4
                name = _model_label(model) if model is not None else str(da.name)
                for j, value in enumerate(sweep_values if swept else [None]):
                    sel = {"model": i} if model is not None else {}
                    if swept:
                        sel[sweep] = j
                    ax.plot(da.isel(sel).transpose("depth").values, depth,
                            color=_shade(colour, j, len(sweep_values)) if swept else colour,
                            linestyle=_LINESTYLES[j % len(_LINESTYLES)] if swept else "-",
                            linewidth=width, label=name if not swept else
                            f"{name}, {sweep} = {_sweep_text(sweep, value, ds)}")
            ax.set_xlabel(_label(da.name, ds, width=26))
            if len(arrays) > 1:
                ax.set_title(f"({chr(ord('a') + k)})", loc="left", fontweight="bold")
            ax.tick_params(labelleft=k == 0)
        axes[0].set_ylabel(_label("depth", ds))
        axes[0].set_ylim(depth.max(), depth.min())          # depth increases downward
        if any("model" in da.dims for da in arrays):
            fig.legend(handles=[Line2D([], [], color=_model_colour(m, i), label=_model_label(m),
                                       linewidth=_model_width(i, len(models)))
                                for i, m in enumerate(models)],
                       loc="outside upper center", ncols=min(len(models), 4 if len(variables) > 2
                                                             else 2))
        if sweep is not None and len(sweep_values) > 1:
            attrs = _attrs(sweep, ds)
            fig.legend(handles=[Line2D([], [], color=_shade(_INK, j, len(sweep_values)),
                                       linestyle=_LINESTYLES[j % len(_LINESTYLES)],
                                       label=_sweep_text(sweep, v, ds))
                                for j, v in enumerate(sweep_values)],
                       loc="outside lower center", ncols=min(len(sweep_values), 6),
                       title=_capital(str(attrs.get("long_name", sweep.replace("_", " ")))))
    return fig


# ----------------------------------------------------------------------------- velocity-porosity
