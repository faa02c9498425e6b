"""Figures of scenes with uncertain inputs (issue 32): depth trends as quantile bands per model,
and the rock-physics template with the members' clouds.

A scene with ``[uncertain]`` writes, for every output, model and depth, the sample quantiles of
its members along a ``quantile`` dimension (probability of non-exceedance: quantile 0.1 is the
industry's P90, the low case) and, with ``members = true``, every member as ``<name>_members``
along ``member``. The quantiles of each variable are taken separately at each depth and model, so
a band's edge is not a member.
"""

from __future__ import annotations

import json

import numpy as np

from ._style import (_INK, _RC, _check_dataset, _figure, _label, _model_label,
                     _model_marker, _model_size, _model_style, _require)

__all__ = ["depth_bands", "member_template"]

#: Derived panels of :func:`depth_bands`, from the members: name -> the two variables and
#: whether the panel is their product (impedance, density times Vp) or ratio (Vp/Vs).
_DERIVED_PANELS = {"acoustic_impedance": ("density", "vp", "product"),
                   "vp_vs": ("vp", "vs", "ratio")}
#: Default depths (m) of the member clouds and of ``rockcem plot --kind sensitivity`` (issue 32,
#: Show: the sensitivity ranking at 2, 3 and 4 km).
DEFAULT_DEPTHS = (2000.0, 3000.0, 4000.0)


def member_count(ds):
    """The number of members the quantiles of ``ds`` are taken over, from its ``uncertain_json``
    attribute (``samples``; twice that for a Sobol' design, whose quantiles are those of its
    matrices A and B), else the length of its ``member`` dimension, else None.

    >>> import xarray as xr
    >>> member_count(xr.Dataset(attrs={"uncertain_json": '{"samples": 64, "sensitivity": true}'}))
    128
    """
    text = ds.attrs.get("uncertain_json")
    if text:
        spec = json.loads(text)
        return int(spec["samples"]) * (2 if spec.get("sensitivity") else 1)
    return int(ds.sizes["member"]) if "member" in ds.dims else None


def default_depths(ds) -> list[float]:
    """Depths (m) of the member clouds and of the tornado chart when none are given: 2, 3 and
    4 km (:data:`DEFAULT_DEPTHS`) as far as ``ds`` reaches, else a quarter, half and three
    quarters of its depth range.

    >>> import xarray as xr
    >>> default_depths(xr.Dataset(coords={"depth": [0.0, 1000.0, 2500.0]}))
    [2000.0]
    """
    low, high = float(ds["depth"].min()), float(ds["depth"].max())
    inside = [d for d in DEFAULT_DEPTHS if low <= d <= high]
    return inside or [low + q * (high - low) for q in (0.25, 0.5, 0.75)]


def _check_uncertain(ds, purpose):
    """``ds``'s quantiles, sorted, after the checks of :func:`depth_bands`."""
    _check_dataset(ds)
    if "quantile" not in ds.dims:
        raise ValueError(f"{purpose} draws the quantiles of a scene with [uncertain]; the "
                         "Dataset has no 'quantile' dimension (draw it with depth_trends)")
    q = np.asarray(ds["quantile"].values, dtype=float)
    if q.size < 2:
        raise ValueError(f"{purpose} shades the band between the lowest and the highest "
                         f"quantile: the Dataset has one quantile ({q[0]:g}); plot it with "
                         "depth_trends(ds.sel(quantile=...))")
    other = [str(d) for d in ds.dims if d not in ("depth", "model", "quantile", "member", "input")
             and ds.sizes[d] > 1]
    if other:
        d = other[0]
        example = ds[d].values[0]
        example = f"{example:g}" if isinstance(example, (int, float, np.number)) else example
        raise ValueError(f"{purpose} draws one sweep member's bands; this Dataset sweeps "
                         f"{', '.join(other)}: select one value of {d!r} first "
                         f"(ds.sel({d}=...); rockcem plot --select {d}={example})")
    return q


def _derived(ds, name, q):
    """The quantiles ``q`` of acoustic impedance or Vp/Vs over the members (their product or
    ratio member by member, then :func:`numpy.quantile`, linear, as the scene's quantiles)."""
    a, b, how = _DERIVED_PANELS[name]
    need = [f"{v}_members" for v in (a, b)]
    missing = [v for v in need if v not in ds.data_vars]
    if missing:
        raise ValueError(f"{name} is not a quantile of the other variables (the quantile of "
                         f"a product is not the product of the quantiles): it needs the "
                         f"members ({', '.join(missing)}); run the scene with members = true "
                         "in [uncertain]")
    import xarray as xr

    x, y = xr.broadcast(ds[need[0]], ds[need[1]])
    value = x * y if how == "product" else x / y
    dims = [d for d in value.dims if d != "member"]
    data = np.quantile(np.asarray(value.transpose("member", *dims).values, dtype=float), q,
                       axis=0)
    return xr.DataArray(data, dims=("quantile", *dims),
                        coords={d: value[d] for d in dims if d in value.coords}, name=name)


def depth_bands(ds, variables=None, *, fig=None):
    """Depth trends of a scene with uncertain inputs: per model, the band between the lowest
    and the highest quantile shaded and the median (quantile 0.5) as a line, depth increasing
    downward; one panel per variable.

    The band of each model is shaded in its colour (``gid`` ``"band:<model>"``; a
    model-independent variable's in grey, ``"band:<variable>"``), the median drawn in the
    model's colour, line style and width as :func:`~rockcem.plots.depth_trends` draws a model
    (``gid`` ``"median:<model>"``), and quantiles between the lowest and the highest other than
    0.5 as thin lines (``"quantile=<q>:<model>"``). Quantiles are those of the members, taken
    separately per variable, model and depth (probability of non-exceedance: quantile 0.1 is the
    industry's P90, the low case); a band's edge is not one member's curve.

    Acoustic impedance :math:`\\rho V_P` and :math:`V_P/V_S` are not quantiles of the other
    variables (the quantile of a product is not the product of the quantiles): their panels are
    the quantiles of the members' own impedance and ratio, drawn when the Dataset keeps the
    members (``members = true`` in ``[uncertain]``).

    Parameters
    ----------
    ds : xarray.Dataset
        A scene Dataset with a ``quantile`` dimension of at least two quantiles, ``depth`` and
        optionally ``model``; the members (``<name>_members`` along ``member``) for the
        ``acoustic_impedance`` and ``vp_vs`` panels. Any other dimension (a sweep beside
        ``[uncertain]``) must be selected first.
    variables : sequence of str, optional
        Panels, in this order: variables of ``ds`` with the dimensions ``quantile`` and
        ``depth``, and ``"acoustic_impedance"`` and ``"vp_vs"``. Default: those of
        ``porosity``, ``cement_fraction``, ``illite_fraction``, ``density``, ``vp`` and ``vs``
        in ``ds``, then ``acoustic_impedance`` and ``vp_vs`` where the members are kept.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per variable, sharing the (inverted) depth axis.

    Raises
    ------
    ValueError
        ``ds`` has no ``depth`` or ``quantile`` dimension, a single quantile, or another
        dimension of more than one value (named, with how to select one); a variable is not in
        ``ds`` (the closest name suggested) or lacks ``quantile`` or ``depth``;
        ``acoustic_impedance`` or ``vp_vs`` is asked for without the members (the message says
        ``members = true``).

    Examples
    --------
    >>> import numpy as np
    >>> import xarray as xr
    >>> depth = np.linspace(0.0, 3000.0, 31)
    >>> vp = 2.0 + 1e-3 * depth + np.array([-0.2, 0.0, 0.2])[:, None, None] * [[1.0], [1.5]]
    >>> ds = xr.Dataset({"vp": (("quantile", "model", "depth"), vp)},
    ...                 coords={"quantile": [0.1, 0.5, 0.9], "depth": depth,
    ...                         "model": ["hs_gassmann", "patchy_cement"]})
    >>> fig = depth_bands(ds)
    >>> fig.axes[0].get_xlabel()
    'P-wave velocity (km/s)'
    >>> sorted(c.get_gid() for c in fig.axes[0].collections)
    ['band:hs_gassmann', 'band:patchy_cement']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    q = _check_uncertain(ds, "depth_bands")
    from ._style import _panels

    variables = _panels(ds, variables, [
        name for name, (a, b, _) in _DERIVED_PANELS.items()
        if f"{a}_members" in ds.data_vars and f"{b}_members" in ds.data_vars])
    arrays = []
    for name in variables:
        if name in _DERIVED_PANELS and name not in ds.data_vars:
            arrays.append(_derived(ds, name, q))
            continue
        da = _require(ds, name, "depth_bands")
        if "quantile" not in da.dims or "depth" not in da.dims:
            raise ValueError(f"variable {name!r} needs the dimensions 'quantile' and 'depth' "
                             f"(its dims: {da.dims})")
        arrays.append(da)
    order = np.argsort(q)
    low, high = int(order[0]), int(order[-1])
    middle = [int(k) for k in order[1:-1]]
    median = next((k for k in range(q.size) if abs(q[k] - 0.5) < 1e-12), None)
    models = [str(m) for m in ds["model"].values] if "model" in ds.dims else []
    depth = np.asarray(ds["depth"].values, dtype=float)

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.0 + 2.0 * len(variables), 5.4))
        axes = np.atleast_1d(fig.subplots(1, len(variables), sharey=True, squeeze=False)[0])
        for k, (ax, da) in enumerate(zip(axes, arrays, strict=True)):
            series = list(enumerate(models)) if "model" in da.dims else [(0, None)]
            for i, model in series:
                if model is not None:
                    style = _model_style(model, i, len(models))
                    sel = {"model": i}
                else:
                    style = {"color": _INK, "linestyle": "-", "linewidth": 1.4, "zorder": 2.0}
                    sel = {}
                style.pop("marker", None)
                values = np.asarray(da.isel(sel).transpose("quantile", "depth").values,
                                    dtype=float)
                tag = model if model is not None else str(da.name)
                ax.fill_betweenx(depth, values[low], values[high], color=style["color"],
                                 alpha=0.18 if model is not None else 0.25, linewidth=0,
                                 zorder=1.0 + 0.01 * i, gid=f"band:{tag}")
                for j in middle:
                    if j == median:
                        continue
                    ax.plot(values[j], depth, color=style["color"], linewidth=0.6,
                            linestyle=":", zorder=style["zorder"] - 0.005,
                            gid=f"quantile={q[j]:g}:{tag}")
                if median is not None:
                    ax.plot(values[median], depth, **style, gid=f"median:{tag}",
                            label=_model_label(model) if model is not None else str(da.name))
            ax.set_xlabel(_label(str(da.name), ds, width=26))
            if len(arrays) > 1:
                ax.set_title(f"({chr(ord('a') + k)})", loc="left", fontweight="bold")
            ax.tick_params(labelleft=k == 0)
        axes[0].set_ylabel(_label("depth", ds))
        axes[0].set_ylim(depth.max(), depth.min())          # depth increases downward
        handles = []
        if any("model" in da.dims for da in arrays):
            for i, m in enumerate(models):
                style = _model_style(m, i, len(models))
                handles.append(Line2D([], [], **{key: v for key, v in style.items()
                                                 if key in ("color", "linestyle", "linewidth")},
                                      label=_model_label(m)))
        n = member_count(ds)
        of = f" of {n} members" if n else " of the members"
        band = f"band: quantile {q[low]:g}–{q[high]:g}{of}"
        handles.append(Patch(color="0.55", alpha=0.35, linewidth=0, label=band))
        handles.append(Line2D([], [], color="0.3", linewidth=1.4,
                              label="line: median (quantile 0.5)" if median is not None
                              else "no median: quantile 0.5 not in the Dataset"))
        if middle and any(j != median for j in middle):
            handles.append(Line2D([], [], color="0.3", linewidth=0.6, linestyle=":",
                                  label="dotted: quantile " + ", ".join(
                                      f"{q[j]:g}" for j in middle if j != median)))
        fig.legend(handles=handles, loc="outside upper center",
                   ncols=min(len(handles), 4 if len(variables) > 2 else 2))
        fig.legend(handles=[], loc="outside lower center", title=(
            "Quantiles of each variable taken separately at each depth and model (a band's "
            "edge is not one member);\nquantile 0.1 is the industry's P90 (the low case)"),
            title_fontsize=7.5)
    return fig


def member_template(ds, depths=None, *, fig=None, **template):
    """The rock-physics template with the members' clouds: acoustic impedance against
    :math:`V_P/V_S` of every member, per model, at a few depths, over the patchy-cement
    template of :func:`~rockcem.plots.rock_physics_template`.

    Each cloud is one model's members at one depth (``gid`` ``"members:<model>:<depth>"``, one
    point per member), in the model's marker and the depth's colour (one colour per depth, from
    the depth colour map of the template); the template's lines are
    those :func:`~rockcem.plots.rock_physics_template` draws for the Dataset (its grain, cement,
    fluid, critical porosity, median effective pressure and Model 4 parameters). The members'
    impedance is :math:`\\rho V_P` of each member's own density and velocity.

    Parameters
    ----------
    ds : xarray.Dataset
        A scene run with ``members = true`` in ``[uncertain]``: ``density_members``,
        ``vp_members`` and ``vs_members`` along ``member`` (and ``model``) and ``depth``.
    depths : sequence of float, optional
        Depths of the clouds, m; each snaps to the nearest depth of the Dataset. Default 2, 3
        and 4 km as far as the Dataset reaches (:func:`default_depths`).
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.
    **template
        Keywords of :func:`~rockcem.plots.rock_physics_template` for the template's lines
        (``grain``, ``cement``, ``fluid``, ``critical_porosity``, ``pressure``, ``porosity``,
        ``cement_fraction``, ``coordination_number``, ``delta``).

    Returns
    -------
    matplotlib.figure.Figure
        The template axes with the clouds; the legend names the models' markers and the
        depths' colours.

    Raises
    ------
    ValueError
        The Dataset has no members (the message says ``members = true``), ``depths`` is empty
        or holds a depth outside the Dataset's range, or the template's own checks fail.

    Examples
    --------
    >>> import numpy as np
    >>> import xarray as xr
    >>> rng = np.random.default_rng(0)
    >>> vp = 3.0 + 0.1 * rng.standard_normal((20, 3))
    >>> ds = xr.Dataset({"density_members": (("member", "depth"), np.full((20, 3), 2.3)),
    ...                  "vp_members": (("member", "depth"), vp),
    ...                  "vs_members": (("member", "depth"), vp / 1.7)},
    ...                 coords={"member": np.arange(20), "depth": [1000.0, 2000.0, 3000.0]})
    >>> fig = member_template(ds, depths=[2000.0])
    >>> [len(c.get_offsets()) for c in fig.axes[0].collections
    ...  if str(c.get_gid()).startswith("members:")]
    [20]
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    from .templates import _template_figure

    _check_dataset(ds)
    need = ("density_members", "vp_members", "vs_members")
    missing = [v for v in need if v not in ds.data_vars]
    if missing or "member" not in ds.dims:
        raise ValueError(f"member_template draws the members, and the Dataset has none "
                         f"({', '.join(missing) or 'no member dimension'}): run the scene with "
                         "members = true in [uncertain]")
    other = [str(d) for d in ds.dims if d not in ("depth", "model", "quantile", "member")
             and ds.sizes[d] > 1]
    if other:
        raise ValueError(f"member_template draws one sweep member's clouds; this Dataset sweeps "
                         f"{', '.join(other)}: select one value of {other[0]!r} first")
    z = np.asarray(ds["depth"].values, dtype=float)
    depths = default_depths(ds) if depths is None else [float(d) for d in np.atleast_1d(depths)]
    if not depths:
        raise ValueError("depths must name at least one depth (m)")
    outside = [d for d in depths if not (np.isfinite(d) and z.min() <= d <= z.max())]
    if outside:
        raise ValueError(f"depths must lie in the Dataset's range {z.min():g}-{z.max():g} m; "
                         f"got {', '.join(f'{d:g}' for d in outside)}")
    at = sorted({float(z[np.argmin(np.abs(z - d))]) for d in depths})

    import matplotlib.pyplot as plt
    import xarray as xr
    from matplotlib.lines import Line2D

    density, vp, vs = xr.broadcast(*(ds[v] for v in need))
    models = [str(m) for m in ds["model"].values] if "model" in vp.dims else [None]
    points = {}
    for i, model in enumerate(models):
        sel = {"model": i} if model is not None else {}
        for d in at:
            r, p, s = (np.asarray(a.isel(sel).sel(depth=d).transpose("member").values,
                                  dtype=float) for a in (density, vp, vs))
            good = np.isfinite(r * p / s) & (s > 0.0)
            points[model, d] = ((r * p)[good], (p / s)[good])
    xs = np.concatenate([x for x, _ in points.values()] or [np.zeros(0)])
    ys = np.concatenate([y for _, y in points.values()] or [np.zeros(0)])
    with plt.rc_context(_RC):
        fig, ax = _template_figure(ds, fig=fig, **template)
        # One colour per depth, spread over the depth colour map (shallow light, deep dark),
        # so that two clouds a kilometre apart stand apart.
        cmap = plt.get_cmap("viridis_r")
        colour = {d: cmap(0.15 + 0.75 * k / max(len(at) - 1, 1)) for k, d in enumerate(at)}
        handles = []
        for i, model in enumerate(models):
            marker = _model_marker(model, i)
            grow = _model_size(i, len(models))
            for d in at:
                x, y = points[model, d]
                ax.scatter(x, y, color=colour[d], marker=marker, s=7 * grow, alpha=0.45,
                           linewidths=0.0, zorder=2 + 0.01 * i,
                           gid=f"members:{model if model is not None else 'data'}:{d:g}")
            handles.append(Line2D([], [], linestyle="none", marker=marker,
                                  markersize=4.5 * np.sqrt(grow), markerfacecolor="0.6",
                                  markeredgecolor="none",
                                  label=_model_label(model) if model is not None else "members"))
        handles += [Line2D([], [], linestyle="none", marker="o", markersize=6.0,
                           markerfacecolor=colour[d], markeredgecolor="none", label=f"{d:g} m")
                    for d in at]
        if xs.size:
            x0, x1 = ax.get_xlim()
            y0, y1 = ax.get_ylim()
            x0, x1 = min(x0, xs.min()), max(x1, xs.max())
            y0, y1 = min(y0, ys.min()), max(y1, ys.max())
            ax.set_xlim(x0 - 0.03 * (x1 - x0), x1 + 0.03 * (x1 - x0))
            ax.set_ylim(y0 - 0.03 * (y1 - y0), y1 + 0.03 * (y1 - y0))
        fig.legend(handles=handles, loc="outside right upper",
                   title=f"{ds.sizes['member']} members\n(marker: model;\ncolour: depth)",
                   title_fontsize=7.5, alignment="left")
    return fig
