"""Depth-trend figures: one panel per variable, depth downward, one line per model."""

from __future__ import annotations


import numpy as np

from ._style import (_INK, _DEFAULT_TRENDS, _RC, _held, _label, _model_label, _model_marker,
                     _model_style,
                     _shade, _members, _member_text, _sweep_legend, _check_dataset, _require, _panels,
                     _figure)

__all__ = ["depth_trends"]


def depth_trends(ds, variables=None, *, temperature_axis=True, fig=None):
    """Depth trends of scene variables, one panel per variable, depth increasing downward.

    Model-dependent variables (those with a ``model`` dimension) get one line per model in the
    model's colour, line style and width (the first model widest and lowest, so that models
    whose curves coincide both stay visible); model-independent ones are drawn in dark grey.
    Every member of a sweep (the other dimensions of the variables, e.g. ``gradient``, and
    their product when there are several) is drawn, each in its own shade (darkest first, and
    on top where members coincide: the first, e.g. brine without hydrocarbon, stays visible
    outside a reservoir), with a second legend giving the swept values and units; past
    :data:`~rockcem.plots.MAX_MEMBERS` members the figure refuses and names the dimension to
    select values of. A variable that is the same at every value of a sweep dimension (the
    porosity of a sweep over a Model 4 parameter) is drawn once, and its panel says "same for
    every <dimension>". A single-valued sweep dimension or scalar coordinate (what
    ``ds.sel(gradient=30)`` leaves) is named with its value below the figure. A Dataset of
    quantiles of uncertain members (a ``quantile`` dimension of two or more) is drawn by
    :func:`~rockcem.plots.depth_bands`: per model the band between the lowest and the highest
    quantile and the median line (``temperature_axis`` does not apply).

    The depths the Dataset's ``validity_warnings`` name are marked where they apply: a line
    about a model ("Model 2 (self-consistent) at 0–3032 m: …", "Models 1 and 3 …") by a
    translucent band along that model's curve, in its colour, on the panels that draw it
    (a collection with ``gid`` ``"flagged:<model>"``); a line about the rock (quartz cement, the pore fluid) by a
    grey band across every panel (``gid`` ``"flagged"``). A line for some sweep members only
    (``"[gradient = 20] …"``) marks those members' curves.

    With ``temperature_axis`` and a ``temperature`` variable in ``ds``, the right edge of the
    last panel carries a temperature scale read from it (one scale per distinct temperature
    profile of the sweep, labelled with its member, e.g. for a gradient sweep; past two, those
    of the coolest and the warmest member).

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset: dimension ``depth`` (coordinate in m), optional ``model`` (labels such as
        ``"hs_gassmann"``) and sweep dimensions.
    variables : sequence of str, optional
        Variables to plot, one panel each, in this order. Default: those of ``porosity``,
        ``cement_fraction``, ``illite_fraction``, ``density``, ``vp``, ``vs`` in ``ds``.
    temperature_axis : bool, optional
        Draw the temperature scale(s) (secondary axes with ``gid`` ``"temperature_axis"``)
        when ``ds`` has ``temperature`` rising strictly with depth; default True.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per variable, sharing the (inverted) depth axis, then the temperature
        scales.

    Raises
    ------
    ValueError
        If ``ds`` has no ``depth`` dimension, a variable is not in ``ds`` (the closest name is
        suggested) or lacks the depth dimension, or the sweep has more than
        :data:`~rockcem.plots.MAX_MEMBERS` members (the message names the dimension to
        select values of).

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
    if "quantile" in ds.dims and ds.sizes["quantile"] > 1:
        from .uncertainty import depth_bands        # quantiles of uncertain members: bands

        return depth_bands(ds, variables, fig=fig)
    ds, held = _held(ds)
    variables = _panels(ds, variables)
    arrays, notes = [], []
    for name in variables:
        da = _require(ds, name, "depth_trends")
        if "depth" not in da.dims:
            raise ValueError(f"variable {name!r} has no 'depth' dimension (dims: {da.dims})")
        alike = [d for d in da.dims if d not in ("depth", "model") and _alike(da, d)]
        arrays.append(da.isel({d: 0 for d in alike}, drop=True))
        notes.append(f"same for every {', '.join(d.replace('_', ' ') for d in alike)}"
                     if alike else "")
    dims, members = _members(ds, arrays, "depth_trends", "one shade of each model's colour")
    models = list(ds["model"].values) if "model" in ds.dims else []
    depth = np.asarray(ds["depth"].values, dtype=float)
    # The MD lines of the warnings are per member: shaded below, each in its colour.
    flags = _flags("\n".join(line for line in ds.attrs.get("validity_warnings", "").splitlines()
                             if not line.startswith("MD ")))
    half = 0.006 * (depth.max() - depth.min())      # a single flagged depth: a thin band

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.0 + 2.0 * len(variables) + (0.6 if temperature_axis else 0.0),
                            5.2))
        axes = np.atleast_1d(fig.subplots(1, len(variables), sharey=True, squeeze=False)[0])
        points = set()                  # models drawn as points with error bars
        untrusted = {}                  # MD member -> (index, its untrusted depths)
        later = []                      # error bars of untrusted points: drawn last, so that
        #                                 they leave the axis limits to the trusted data
        for k, (ax, da) in enumerate(zip(axes, arrays, strict=True)):
            series = [(m, i) for i, m in enumerate(models)] if "model" in da.dims else [(None, 0)]
            for model, i in series:
                style = (_model_style(model, i, len(models)) if model is not None else
                         {"color": _INK, "linestyle": "-", "linewidth": 1.4, "zorder": 2.0})
                style.pop("marker", None)
                name = _model_label(model) if model is not None else str(da.name)
                drawn = set()
                for j, (isel, _text) in enumerate(members):
                    sel = {d: v for d, v in isel.items() if d in da.dims}
                    if tuple(sel.items()) in drawn:
                        continue                    # this variable does not change here
                    drawn.add(tuple(sel.items()))
                    colour = _shade(style["color"], j, len(members)) if sel else style["color"]
                    text = ", ".join(_member_text(d, ds[d].values[v], ds)
                                     for d, v in sel.items())
                    if model is not None:
                        sel["model"] = i
                    values = da.isel(sel).transpose("depth").values
                    label = f"{name}, {text}" if text else name
                    # the first member on top where members coincide (darkest; the baseline)
                    above = 0.005 * (len(members) - 1 - j) / len(members)
                    ok = np.isfinite(values)
                    if ok.sum() < 0.5 * ok.size:    # a model run at a few depths (MD): points
                        points.add(model)
                        err, trusted = _error_bars(ds, da.name, sel, ok)
                        if trusted is not None and not trusted.all():
                            untrusted.setdefault(model, (i, set()))[1].update(
                                depth[ok][~trusted])
                        later.extend(_points(ax, values[ok], depth[ok], err, trusted,
                                             color=colour, marker=_model_marker(model, i),
                                             zorder=style["zorder"] + 1, label=label))
                    else:
                        ax.plot(values, depth, **{**style, "color": colour,
                                                  "zorder": style["zorder"] + above}, label=label)
                        if model is not None:
                            _flag_curve(ax, flags, model, _member_key(ds, isel), values, depth,
                                        half, colour, style)
            ax.set_xlabel(_label(da.name, ds, width=26))
            if len(arrays) > 1:
                ax.set_title(f"({chr(ord('a') + k)})", loc="left", fontweight="bold")
            if notes[k]:                        # one line stands for several sweep members
                ax.set_title(notes[k], loc="right", fontsize=7.0, color="0.35")
            ax.tick_params(labelleft=k == 0)
        axes[0].set_ylabel(_label("depth", ds))
        axes[0].set_ylim(depth.max(), depth.min())          # depth increases downward
        for ax in axes:
            ax.autoscale_view()
            ax.set_autoscale_on(False)
        for draw in later:
            draw()
        flagged = [(top, base) for intervals, which, members in flags if which is None
                   and members is None for top, base in intervals]
        for top, base in flagged:           # where the rock's own state is out of range
            if base - top < 2.0 * half:
                top, base = 0.5 * (top + base) - half, 0.5 * (top + base) + half
            for ax in axes:
                ax.axhspan(top, base, color="0.55", alpha=0.12, linewidth=0, zorder=0.5,
                           gid="flagged")
        banded = _untrusted_bands(axes, arrays, untrusted, models, 2.0 * half)
        if temperature_axis:
            _temperature_axes(axes[-1], ds, members)
        from matplotlib.patches import Patch

        shade = [Patch(color="0.55", alpha=0.25, linewidth=0,
                       label="flagged (validity_warnings)")] if flagged else []
        if any(str(c.get_gid()).startswith("flagged:") for ax in axes for c in ax.collections):
            shade.append(Line2D([], [], color="0.55", alpha=0.3, linewidth=6.0,
                                solid_capstyle="butt",
                                label="model flagged (validity_warnings):\nband along its curve"))
        if any(str(m).startswith("md") for m in points):
            flag = "md_trusted = 0" if "md_trusted" in ds.data_vars else \
                "md_resolution_asymptotic = 0 or error ≥ value"
            shade.append(Line2D([], [], color="0.3", marker="o", linestyle="none",
                                label="MD trusted (filled)"))
            hollow = Line2D([], [], color="0.3", marker="o", markerfacecolor="white",
                            linestyle="none",
                            label="MD not trusted: hollow, dashed bar"
                            + (", band in its colour" if banded else "") + f"\n({flag})")
            shade.append(hollow)
        if any("model" in da.dims for da in arrays):
            handles = [Line2D([], [], color=_model_style(m, i, len(models))["color"],
                              marker=_model_marker(m, i), linestyle="none",
                              label=_model_label(m)) if m in points else
                       Line2D([], [], **{k: v for k, v in _model_style(m, i, len(models)).items()
                                         if k in ("color", "linestyle", "linewidth")},
                              label=_model_label(m))
                       for i, m in enumerate(models)]
            fig.legend(handles=handles + shade,
                       loc="outside upper center", ncols=min(len(models) + len(shade),
                                                             4 if len(variables) > 2 else 2))
        elif shade:
            fig.legend(handles=shade, loc="outside upper center")
        _sweep_legend(fig, dims, members, ds, held)
    return fig


def flagged_intervals(warnings: str) -> list[tuple[float, float]]:
    r"""The depth intervals (top, base), m, named by a Dataset's ``validity_warnings`` lines that
    hold for the whole Dataset (``"... at 0–1479 m: ..."``; a line for some sweep members only,
    which starts with ``[``, is left out, as is a line without an interval).

    >>> flagged_intervals("Model 1 (Krief frame) at 0–1479 m: porosity above 0.324\n"
    ...                   "[gradient = 20] quartz cement at 4455 m: overfill\n"
    ...                   "MD model at 1000, 2500 m: burial's cement overflows")
    [(0.0, 1479.0), (1000.0, 1000.0), (2500.0, 2500.0)]
    """
    import re

    number = r"-?\d[\d.e+]*"
    item = rf"{number}(?:–{number})?"
    out = []
    for line in warnings.splitlines():
        if line.startswith("["):
            continue
        match = re.search(rf" at ({item}(?:, {item})*) m[:,]", line)
        if match:                        # "0–1479", or a list of depths "1000, 2000, 3000"
            for part in match.group(1).split(", "):
                top, _, base = part.partition("–")
                out.append((float(top), float(base) if base else float(top)))
    return out


#: Model numbers of the warning lines (Carcione et al. 2022) -> scene labels.
_MODEL_NUMBERS = {"1": "hs_gassmann", "2": "self_consistent", "3": "generalized_gassmann",
                  "4": "patchy_cement"}


def _flags(warnings: str) -> list[tuple[list, tuple | None, set | None]]:
    r"""Each ``validity_warnings`` line as ``(intervals, models, members)``: its depth intervals
    (:func:`flagged_intervals`), the model labels it names (``"Models 1 and 3 (…"``; None for a
    line about the rock's state) and the sweep members it holds for (``"[gradient = 20; …] …"``;
    None for all), each member as its ``"dim = value, …"`` text.

    >>> flags = _flags("Models 1 and 3 (Krief frame) at 0–1479 m: x\n"
    ...                "[gradient = 20] Model 2 (self-consistent) at 0–1190 m: y\n"
    ...                "quartz cement at 4454 m: z")
    >>> flags[0]
    ([(0.0, 1479.0)], ('hs_gassmann', 'generalized_gassmann'), None)
    >>> flags[1]
    ([(0.0, 1190.0)], ('self_consistent',), {'gradient = 20'})
    >>> flags[2]
    ([(4454.0, 4454.0)], None, None)
    """
    import re

    out = []
    for line in warnings.splitlines():
        members = None
        if line.startswith("["):
            head, _, line = line[1:].partition("] ")
            members = set(head.split("; "))
        intervals = flagged_intervals(line)
        if not intervals:
            continue
        named = re.match(r"Models? ([1-4](?:(?:, | and )[1-4])*) \(", line)
        which = tuple(_MODEL_NUMBERS[n] for n in re.findall(r"[1-4]", named.group(1))) \
            if named else None
        out.append((intervals, which, members))
    return out


def _member_key(ds, isel) -> str:
    """A sweep member as the runner names it in a warning line (``"gradient = 20"``)."""
    return ", ".join(f"{d} = {ds[d].values[i]:g}" if isinstance(ds[d].values[i], (int, float))
                     else f"{d} = {ds[d].values[i]}" for d, i in isel.items())


def _flag_curve(ax, flags, model, member, values, depth, half, colour, style):
    """A translucent band along ``model``'s curve over the depths its warning lines name for
    this member (a single depth widened to ``2 * half``), below the curve."""
    where = np.zeros(depth.shape, dtype=bool)
    for intervals, which, members in flags:
        if which is None or str(model) not in which or (members is not None
                                                        and member not in members):
            continue
        for top, base in intervals:
            if base - top < 2.0 * half:
                top, base = 0.5 * (top + base) - half, 0.5 * (top + base) + half
            where |= (depth >= top) & (depth <= base)
    where &= np.isfinite(values)
    if where.any():                     # a collection, not a line: ax.lines are the data's
        from matplotlib.collections import LineCollection

        edges = np.flatnonzero(np.diff(where.astype(int))) + 1
        runs = [r for r in np.split(np.arange(depth.size), edges) if where[r[0]]]
        ax.add_collection(LineCollection(
            [np.column_stack([values[r], depth[r]]) for r in runs], colors=[colour], alpha=0.3,
            linewidths=style["linewidth"] + 5.0, capstyle="butt", zorder=style["zorder"] - 0.6,
            gid=f"flagged:{model}"), autolim=False)


def _error_bars(ds, name, sel, ok):
    """Error bars and trust of a variable drawn as points, at the depths ``ok``:
    ``(error, trusted)`` from :func:`rockcem.variables.md_error_trusted` (the total error, or
    the resolution and sample-size errors in quadrature; ``md_trusted``, or its fallback), each
    None where the Dataset has no errors (``trusted`` also where it has no MD flag)."""
    from ..variables import md_error_trusted

    if not any(f"{name}_error{kind}" in ds.data_vars
               for kind in ("", "_resolution", "_sample")):
        return None, None
    error, trusted = md_error_trusted(ds, name)
    error = np.asarray(error.isel(sel).transpose("depth").values, dtype=float)[ok]
    flag = np.asarray(trusted.isel(sel).transpose("depth").values, dtype=float)[ok]
    has_flag = "md_trusted" in ds.data_vars or "md_resolution_asymptotic" in ds.data_vars
    return error, (flag == 1.0) if has_flag else None


def _points(ax, values, depth, error, trusted, *, color, marker, zorder, label):
    """Points with horizontal error bars: trusted ones filled, the others hollow. The lower
    bar stops at zero (a velocity is positive). Returns the drawing of the untrusted points'
    bars, to be called once the axis limits are fixed (a bar as large as its value would
    otherwise stretch the axis to zero)."""
    if trusted is None:
        trusted = np.ones(values.shape, dtype=bool)
    if error is None:
        error = np.full(values.shape, np.nan)
    bars = np.stack([np.minimum(error, np.abs(values)), error])     # lower, upper
    bars = np.where(np.isfinite(bars), bars, 0.0)
    common = {"color": color, "elinewidth": 0.9, "capsize": 2.0, "linestyle": "none",
              "markersize": 4.5, "zorder": zorder}
    ax.errorbar(values[trusted], depth[trusted], xerr=bars[:, trusted], marker=marker,
                label=label, **common)
    ax.plot(values[~trusted], depth[~trusted], marker=marker, markerfacecolor="white",
            markeredgecolor=color, markeredgewidth=1.1, linestyle="none", markersize=4.5,
            zorder=zorder + 0.01, gid="untrusted")

    def draw():
        if (~trusted).any():
            drawn = ax.errorbar(values[~trusted], depth[~trusted], xerr=bars[:, ~trusted],
                                fmt="none", ecolor=color, elinewidth=0.9, capsize=2.0,
                                zorder=zorder - 0.01)
            for bar in drawn.lines[2]:
                bar.set_linestyle((0, (2.5, 1.5)))
                bar.set_gid("untrusted")
    return [draw]


def _untrusted_bands(axes, arrays, untrusted, models, width):
    """Thin bands at each MD member's untrusted depths, in the member's colour, on the panels
    that draw that member; members flagged at the same depth share the band in stripes, so
    every member's flag stays visible. Returns whether any band was drawn."""
    from ._style import _model_colour

    if not untrusted:
        return False
    order = sorted(untrusted, key=lambda m: untrusted[m][0])
    count = len(order)
    for k, model in enumerate(order):
        i, where = untrusted[model]
        colour = _model_colour(model, i)
        for ax, da in zip(axes, arrays):
            if "model" not in da.dims:
                continue
            for z in sorted(where):
                top = z - 0.5 * width + width * k / count
                ax.axhspan(top, top + width / count, color=colour, alpha=0.3, linewidth=0,
                           zorder=0.5, gid=f"untrusted:{model}")
    return True


def _alike(da, dim) -> bool:
    """Whether ``da`` is the same (to 1e-12, NaN equal to NaN) at every value of ``dim``:
    then one line stands for all of them (porosity in a sweep of a Model 4 parameter), where
    one line per member would draw them on top of one another, the last over the rest."""
    if da.sizes[dim] < 2:
        return False
    values = np.asarray(da.transpose(dim, ...).values, dtype=float)
    return bool(np.allclose(values, values[:1], rtol=1e-12, atol=0.0, equal_nan=True))


def _temperature_axes(ax, ds, members):
    """Temperature scales on the right of ``ax``: one for every distinct temperature profile of
    the sweep members (one when the sweep leaves temperature unchanged; past two, those of the
    coolest and the warmest member at the deepest depth), each from the
    Dataset's ``temperature`` by linear interpolation in depth. Profiles whose temperature does
    not rise strictly with depth cannot be a scale and are left out."""
    if "temperature" not in ds.data_vars or "depth" not in ds["temperature"].dims:
        return []
    temperature = ds["temperature"]
    depth = np.asarray(ds["depth"].values, dtype=float)
    profiles = []
    for isel, text in members:
        sel = {d: v for d, v in isel.items() if d in temperature.dims}
        if "model" in temperature.dims:
            sel["model"] = 0
        t = np.asarray(temperature.isel(sel).transpose("depth").values, dtype=float)
        if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)):
            continue
        if any(np.allclose(t, other, rtol=0, atol=1e-9) for other, _ in profiles):
            continue
        profiles.append((t, text if sel.keys() - {"model"} else ""))
    if len(profiles) == 1:                  # the sweep leaves temperature unchanged
        profiles = [(profiles[0][0], "")]
    elif len(profiles) > 2:                 # the coolest and the warmest; more scales would
        profiles.sort(key=lambda p: p[0][-1])   # take more room than the panels
        profiles = [profiles[0], profiles[-1]]
    axes = []
    for k, (t, text) in enumerate(profiles):
        def to_temperature(z, t=t):
            return np.interp(z, depth, t, left=np.nan, right=np.nan)

        def to_depth(temp, t=t):
            return np.interp(temp, t, depth, left=np.nan, right=np.nan)

        sec = ax.secondary_yaxis(1.0 if k == 0 else 1.0 + 0.34 * k,
                                 functions=(to_temperature, to_depth))
        label = _label("temperature", ds)
        sec.set_ylabel(label if not text else label.replace(" (", f", {text} (", 1))
        sec.set_gid("temperature_axis")
        axes.append(sec)
    if axes:
        ax.tick_params(axis="y", which="both", right=False)
    return axes
