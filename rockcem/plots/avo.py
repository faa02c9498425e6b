"""Figures of a stack scene's seismic response: the AVO class against depth of burial, the
intercept–gradient crossplot, the PP reflection coefficient against angle and the synthetic
traces against two-way time.

They draw the variables of a stack scene's Dataset (issue 31): ``avo_class``,
``avo_intercept``, ``avo_gradient`` and ``reflectivity_pp`` / ``reflectivity_pp_magnitude``
with dimensions among ``interface``, ``fluid``, ``model``, ``depth`` and ``angle``;
``synthetic`` (``fluid``, ``model``, ``twt``) and, where present, ``angle_gather``
(``fluid``, ``model``, ``twt``, ``angle``). A dimension among ``interface``, ``fluid`` and
``model`` that a selection reduced to one value (``rockcem plot --select fluid=gas``) is drawn
as one column, panel or line, still named.
"""

from __future__ import annotations

import numpy as np

from ._style import (_INK, _RC, _capital, _check_dataset, _figure, _label, _model_colour,
                     _model_label, _model_width, _require, _units_text)

__all__ = ["avo_class_depth", "avo_class_probability", "intercept_gradient_crossplot",
           "reflectivity_angle", "synthetic_section", "class_threshold"]

#: The dimensions the AVO figures draw; any other must be reduced to one value first.
_AVO_DIMS = ("interface", "fluid", "model", "depth", "angle", "twt", "gather_twt",
             "avo_class")
#: Light fill of each class region on the crossplot, by the class's position in
#: ``flag_values`` (Okabe–Ito hues).
_CLASS_COLOURS = ("#56B4E9", "#009E73", "#F0E442", "#E69F00", "#CC79A7", "#0072B2",
                  "#D55E00")
_FLUID_MARKERS = {"brine": "o", "gas": "^", "co2": "s", "oil": "D", "methane": "v"}
_EXTRA_MARKERS = ("P", "X", "*", "h")
_FLUID_NAMES = {"co2": "CO₂", "brine": "brine", "gas": "gas", "oil": "oil"}
#: Room (axes fraction) a class name needs from the points and its region's edges on the
#: crossplot.
_LABEL_ROOM = 0.03
#: The most depths of a trajectory the crossplot marks (coloured by depth); past it every k-th.
_MARKED = 40
#: The most traces an angle gather draws; with more angles, every k-th from the first (so that
#: the wiggles of a gather of 41 angles on a panel a few inches wide stay apart and readable).
_GATHER_TRACES = 11


# ----------------------------------------------------------------------------- helpers
def _fluid_text(fluid) -> str:
    return _FLUID_NAMES.get(str(fluid), str(fluid))


def _fluid_marker(fluid, index: int) -> str:
    return _FLUID_MARKERS.get(str(fluid), _EXTRA_MARKERS[index % len(_EXTRA_MARKERS)])


def _prepare(ds, names, purpose, expand=("interface", "fluid", "model")):
    """``ds`` checked and shaped for the AVO figures: the variables ``names`` present, every
    dimension of theirs other than :data:`_AVO_DIMS` of length one (dropped and named in the
    returned text), and the dimensions ``expand`` (``interface``, ``fluid`` and ``model``)
    even where a selection left one value as a scalar coordinate (or the Dataset has none: one
    unnamed member)."""
    _check_dataset(ds)
    arrays = [_require(ds, name, purpose) for name in names]
    held = []
    for da in arrays:
        for dim in da.dims:
            if dim in _AVO_DIMS or dim in held:
                continue
            if ds.sizes[dim] > 1:
                values = ds[dim].values if dim in ds.coords else np.arange(ds.sizes[dim])
                example = values[0]
                example = f"{example:g}" if isinstance(example, (float, np.floating)) else example
                raise ValueError(
                    f"{purpose} draws the dimensions {', '.join(_AVO_DIMS)}; {da.name!r} also "
                    f"has {dim!r} ({ds.sizes[dim]} values): select one first "
                    f"(ds.sel({dim}=...); rockcem plot --select {dim}={example})")
            held.append(dim)
    texts = []
    for dim in held:
        if dim in ds.coords:
            value = ds[dim].values[0]
            value = f"{value:g}" if isinstance(value, (float, np.floating)) else str(value)
            units = ds[dim].attrs.get("units")
            texts.append(f"{dim} = {value}"
                         + (f" {_units_text(units)}" if units not in (None, "", "1") else ""))
    ds = ds.isel({dim: 0 for dim in held})
    for dim in expand:
        if dim in ds.dims:
            continue
        if dim in ds.coords:
            ds = ds.expand_dims(dim)
        else:
            ds = ds.expand_dims({dim: [""]})
    return ds, "; ".join(texts)


def _names(ds, dim) -> list[str]:
    return [str(v) for v in ds[dim].values]


def _pick(ds, dim, chosen, purpose):
    """The members of ``dim`` to draw: all (``chosen`` None), or those named."""
    if chosen is None:
        return ds
    chosen = [chosen] if isinstance(chosen, str) else list(chosen)
    have = _names(ds, dim)
    missing = [c for c in chosen if str(c) not in have]
    if missing or not chosen:
        raise ValueError(f"{purpose}: {dim}={missing[0] if missing else chosen!r} is not in "
                         f"the Dataset ({dim}: {', '.join(have)})")
    return ds.isel({dim: [have.index(str(c)) for c in chosen]})


def _class_scale(ds):
    """The AVO class codes and names, from the CF attributes ``flag_values`` and
    ``flag_meanings`` of ``ds["avo_class"]``."""
    attrs = ds["avo_class"].attrs
    if "flag_values" not in attrs or "flag_meanings" not in attrs:
        raise ValueError("avo_class has no CF attributes flag_values and flag_meanings: the "
                         "figures label the classes from them")
    values = [int(v) for v in np.atleast_1d(attrs["flag_values"])]
    meanings = str(attrs["flag_meanings"]).split()
    if len(values) != len(meanings) or not values:
        raise ValueError(f"avo_class has {len(values)} flag_values and {len(meanings)} "
                         "flag_meanings; they must pair one to one")
    return values, meanings


def class_threshold(ds) -> float:
    """The intercept threshold of the AVO classification of ``ds``.

    The attribute ``threshold`` of ``ds["avo_class"]`` (the value the classification was
    computed with); where it has none, the default of the classification,
    :data:`rockcem.reflectivity.AVO_THRESHOLD`.

    Parameters
    ----------
    ds : xarray.Dataset
        A Dataset with ``avo_class``.

    Returns
    -------
    float
        The threshold (a reflection coefficient, dimensionless, in (0, 1)).

    Raises
    ------
    ValueError
        If ``ds`` has no ``avo_class`` or its ``threshold`` is not a number in (0, 1).

    Examples
    --------
    >>> import xarray as xr
    >>> class_threshold(xr.Dataset({"avo_class": ("depth", [1], {"threshold": 0.025})}))
    0.025
    """
    if "avo_class" not in ds.variables:
        raise ValueError("the Dataset has no avo_class: run a stack scene with [seismic]")
    from ..reflectivity import AVO_THRESHOLD as default

    value = ds["avo_class"].attrs.get("threshold", default)
    try:
        value = float(np.asarray(value).item())
    except (TypeError, ValueError):
        value = float("nan")
    if not 0.0 < value < 1.0:
        raise ValueError(f"avo_class's attribute threshold must be a number in (0, 1); got "
                         f"{ds['avo_class'].attrs.get('threshold')!r}")
    return value


def _classify(intercept, gradient, threshold):
    """AVO class codes of intercept A and gradient B (:func:`rockcem.reflectivity.avo_class`):
    the classes of Rutherford & Williams (1989) with Ross & Kinman's (1995) IIp and Castagna &
    Swan's (1997) IV, placed in the A-B plane as by Castagna & Swan (1997, Table 1), by a
    threshold ``t`` on A:

    ========  =================  ======
    class     intercept A        B
    ========  =================  ======
    I (1)     A >= t             B < 0
    IIp (2)   0 <= A < t         B < 0
    II (3)    -t < A < 0         B < 0
    III (4)   A <= -t            B < 0
    IV (5)    A < 0              B >= 0
    ========  =================  ======

    and 0 for A >= 0 with B >= 0 (no class)."""
    from ..reflectivity import avo_class

    return np.asarray(avo_class(intercept, gradient, threshold=threshold))


def _model_line(model, index) -> dict:
    """Colour and label of a model's line; a model-less Dataset's single member in ink."""
    if model == "":
        return {"color": _INK, "label": "model"}
    return {"color": _model_colour(model, index), "label": _model_label(model)}


def _row_title(fluid, interface, interfaces) -> str:
    text = _capital(_fluid_text(fluid)) if fluid else ""
    if len(interfaces) > 1 or not text:
        text = ", ".join(t for t in (text, interface) if t)
    return text


def _angle_label(ds) -> str:
    """Label of the angle axis: "Angle of incidence (°)" for an angle in degrees."""
    return _label("angle", ds).replace("(degree)", "(°)").replace("(degrees)", "(°)")


def _depth_axis(ax, depth):
    ax.set_ylim(float(np.max(depth)), float(np.min(depth)))        # depth increases downward


def _held_legend(fig, handles, held, ncols):
    fig.legend(handles=handles, loc="outside upper center", ncols=ncols,
               title=held or None)


# ----------------------------------------------------------------------------- class vs depth
def avo_class_depth(ds, *, interface=None, fig=None):
    """AVO class against depth of burial (the chart of [AvsethLehocki2016]_, their Fig. 6):
    one column per fluid, one row per interface, one line per model.

    The class is on a categorical axis whose ticks and labels are the CF attributes
    ``flag_values`` and ``flag_meanings`` of ``avo_class`` (in their order, e.g. I, IIp, II,
    III, IV); depth increases downward. Each model's line steps from one class to the next
    halfway between the depth samples where the class changes; a depth without a class (code
    0, e.g. no contrast) leaves a gap. The models' lines are set side by side, a fraction of a
    class apart, so that models of the same class stay visible.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset with ``avo_class`` (dimensions among ``interface``, ``fluid``,
        ``model``, ``depth``; int codes with CF ``flag_values`` and ``flag_meanings``).
    interface : str or sequence of str, optional
        The interfaces to draw (``"seal/reservoir"``); default all, a row each.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        ``len(interface) × len(fluid)`` axes in row-major order, then a legend of the models.
        Lines carry the ``gid`` ``"class:<model>"``.

    Raises
    ------
    ValueError
        If ``ds`` has no ``depth`` dimension or no ``avo_class``, ``avo_class`` lacks its CF
        flag attributes or has a dimension other than those above with more than one value, or
        ``interface`` names an interface that is not in ``ds``.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> ds = xr.Dataset(
    ...     {"avo_class": (("fluid", "model", "depth"), np.array([[[4, 3, 1]], [[4, 4, 3]]],
    ...                    dtype="int8"), {"flag_values": [1, 2, 3, 4, 5],
    ...                                    "flag_meanings": "I IIp II III IV"})},
    ...     coords={"fluid": ["brine", "gas"], "model": ["hs_gassmann"],
    ...             "depth": ("depth", [1000.0, 2000.0, 3000.0], {"units": "m"})})
    >>> fig = avo_class_depth(ds)
    >>> [ax.get_title() for ax in fig.axes]
    ['Brine', 'Gas']
    >>> [t.get_text() for t in fig.axes[0].get_xticklabels()]
    ['I', 'IIp', 'II', 'III', 'IV']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    ds, held = _prepare(ds, ["avo_class"], "avo_class_depth")
    ds = _pick(ds, "interface", interface, "avo_class_depth")
    values, meanings = _class_scale(ds)
    lookup = np.full(max(max(values), 0) + 1, np.nan)      # code -> its flag position
    lookup[[v for v in values if v >= 0]] = [k for k, v in enumerate(values) if v >= 0]
    classes = ds["avo_class"].transpose("interface", "fluid", "model", "depth").values
    depth = np.asarray(ds["depth"].values, dtype=float)
    interfaces, fluids, models = (_names(ds, d) for d in ("interface", "fluid", "model"))
    edges = np.concatenate([[depth[0]], 0.5 * (depth[1:] + depth[:-1]), [depth[-1]]])
    step = min(0.12, 0.6 / len(models))

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.2 + 2.3 * len(fluids), 0.9 + 4.0 * len(interfaces)))
        axes = fig.subplots(len(interfaces), len(fluids), sharex=True, sharey=True,
                            squeeze=False)
        for r, face in enumerate(interfaces):
            for c, fluid in enumerate(fluids):
                ax = axes[r, c]
                for i, model in enumerate(models):
                    code = classes[r, c, i].astype(float)
                    known = np.isfinite(code) & (code >= 0) & (code < lookup.size)
                    x = np.full(code.shape, np.nan)
                    x[known] = lookup[code[known].astype(int)]
                    x += (i - 0.5 * (len(models) - 1)) * step
                    ax.plot(np.repeat(x, 2), np.repeat(edges, 2)[1:-1], linewidth=1.8,
                            solid_capstyle="butt", gid=f"class:{model}",
                            zorder=2.0 + 0.01 * i, **_model_line(model, i))
                ax.set_title(_row_title(fluid, face, interfaces))
                ax.set_xticks(range(len(values)), meanings)
                ax.set_xlim(-0.5, len(values) - 0.5)
                ax.grid(False, axis="y")
                if c == 0:
                    ax.set_ylabel(_label("depth", ds))
                if r == len(interfaces) - 1:
                    ax.set_xlabel("AVO class")
        _depth_axis(axes[0, 0], depth)
        handles = [Line2D([], [], linewidth=1.8, **_model_line(m, i))
                   for i, m in enumerate(models)]
        title = "; ".join(t for t in (held, interfaces[0] if len(interfaces) == 1
                                      and interfaces[0] else "") if t)
        _held_legend(fig, handles, title, min(len(models), 4))
    return fig


# ----------------------------------------------------------------------------- class probability
#: Fill of the "none" share (no class, or no rock on one side) of the class probabilities.
_NO_CLASS_COLOUR = "#D9D9D9"


def avo_class_probability(ds, *, interface=None, model=None, fig=None):
    """The probability of each AVO class against depth of burial, for a stack with uncertain
    inputs: one row per interface and model, one column per fluid, the classes' fractions of
    the members stacked from 0 to 1.

    At each depth the bands are, left to right, the fractions of the members in each class
    along the ``avo_class`` dimension of ``avo_class_probability`` (I, IIp, II, III, IV, then
    ``none``: no class or no rock on one side, in grey); they fill the panel's width, since
    the fractions add up to one. Between depth samples the band edges are joined by straight
    lines. Depth increases downward.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset with ``avo_class_probability`` (dimensions ``avo_class``,
        ``depth`` and among ``interface``, ``fluid``, ``model``), as
        :func:`rockcem.scene.run_scene` gives it for a stack with ``[uncertain]``.
    interface : str or sequence of str, optional
        The interfaces to draw; default all.
    model : str or sequence of str, optional
        The models to draw (``"patchy_cement"``); default all, a row each.
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw in (default: a new one, sized for the panels).

    Returns
    -------
    matplotlib.figure.Figure
        ``len(interface) × len(model) × len(fluid)`` axes in row-major order (rows: the
        models of the first interface, then of the next), and a legend of the classes. The
        bands carry the ``gid`` ``"probability:<class>"``.

    Raises
    ------
    ValueError
        If ``ds`` has no ``depth`` dimension or no ``avo_class_probability``, the variable has
        no ``avo_class`` dimension or another dimension with more than one value, or
        ``interface`` or ``model`` names one that is not in ``ds``.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> p = np.zeros((6, 2, 3))                   # class, fluid, depth
    >>> p[0, 0] = 1.0                             # brine: class I at every depth
    >>> p[2, 1], p[3, 1] = [0.25, 0.5, 1.0], [0.75, 0.5, 0.0]       # gas: II and III
    >>> ds = xr.Dataset(
    ...     {"avo_class_probability": (("avo_class", "fluid", "depth"), p)},
    ...     coords={"avo_class": ["I", "IIp", "II", "III", "IV", "none"],
    ...             "fluid": ["brine", "gas"],
    ...             "depth": ("depth", [1000.0, 2000.0, 3000.0], {"units": "m"})})
    >>> fig = avo_class_probability(ds)
    >>> [ax.get_title() for ax in fig.axes]
    ['Brine', 'Gas']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    purpose = "avo_class_probability"
    ds, held = _prepare(ds, [purpose], purpose)
    if "avo_class" not in ds[purpose].dims:
        raise ValueError(f"{purpose} needs the dimension 'avo_class' of the variable {purpose} "
                         f"(its dimensions: {', '.join(map(str, ds[purpose].dims))})")
    ds = _pick(_pick(ds, "interface", interface, purpose), "model", model, purpose)
    p = ds[purpose].transpose("interface", "model", "fluid", "avo_class", "depth").values
    labels = _names(ds, "avo_class")
    colours = [_NO_CLASS_COLOUR if label == "none" else _CLASS_COLOURS[k % len(_CLASS_COLOURS)]
               for k, label in enumerate(labels)]
    depth = np.asarray(ds["depth"].values, dtype=float)
    interfaces, models, fluids = (_names(ds, d) for d in ("interface", "model", "fluid"))
    rows = [(i, face, j, m) for i, face in enumerate(interfaces) for j, m in enumerate(models)]

    import matplotlib.pyplot as plt
    from matplotlib.patches import Patch

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.2 + 2.3 * len(fluids), 0.9 + 3.0 * len(rows)))
        axes = fig.subplots(len(rows), len(fluids), sharex=True, sharey=True, squeeze=False)
        for r, (i, face, j, m) in enumerate(rows):
            for c, fluid in enumerate(fluids):
                ax = axes[r, c]
                low = np.zeros(depth.size)
                for k, label in enumerate(labels):
                    high = low + np.nan_to_num(p[i, j, c, k])
                    ax.fill_betweenx(depth, low, high, color=colours[k], linewidth=0,
                                     gid=f"probability:{label}")
                    low = high
                parts = [_capital(_fluid_text(fluid)) if fluid else "",
                         _model_label(m) if m and len(models) > 1 else "",
                         face if len(interfaces) > 1 else ""]
                ax.set_title(", ".join(t for t in parts if t), fontsize="medium")
                ax.set_xlim(0.0, 1.0)
                ax.grid(False)
                if c == 0:
                    ax.set_ylabel(_label("depth", ds))
                if r == len(rows) - 1:
                    ax.set_xlabel("Fraction of the members")
        _depth_axis(axes[0, 0], depth)
        handles = [Patch(color=colours[k], label=f"class {label}" if label != "none"
                         else "no class") for k, label in enumerate(labels)]
        title = "; ".join(t for t in (held, _model_label(models[0]) if len(models) == 1
                                      and models[0] else "",
                                      interfaces[0] if len(interfaces) == 1 and interfaces[0]
                                      else "") if t)
        _held_legend(fig, handles, title, len(labels))
    return fig


# ----------------------------------------------------------------------------- A-B crossplot
def intercept_gradient_crossplot(ds, *, interface=None, fig=None):
    """Intercept A against gradient B of every fluid and model along depth, over the class
    regions and the brine background trend (Castagna & Swan 1997, their Figs. 3–5).

    Each fluid (a marker) and model (the colour of its thin connecting line) is a trajectory
    of points coloured by depth, with one depth colour bar (m) spanning the Dataset's depth
    range. Behind them:

    - the class regions, shaded and labelled with ``avo_class``'s ``flag_meanings``, as the
      classification rule draws them: :func:`rockcem.reflectivity.avo_class` evaluated on a
      fine grid of the axes, with the threshold :func:`class_threshold` reads from
      ``avo_class``'s attributes (default :data:`rockcem.reflectivity.AVO_THRESHOLD`);
    - the quadrants: the lines A = 0 and B = 0;
    - the background trend: the least-squares line through the origin, B = m A with
      m = ΣAB / ΣA², of the brine points of the panel (every model and depth) — the brine
      trend of the Dataset itself, not the Castagna & Swan (1997) line from Vp/Vs; drawn
      where ``fluid`` has ``"brine"``.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset with ``avo_intercept``, ``avo_gradient`` and ``avo_class``
        (dimensions among ``interface``, ``fluid``, ``model``, ``depth``).
    interface : str or sequence of str, optional
        Interfaces of ``ds``, one panel each; default every one.
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw in (default: a new figure, wider with each panel).

    Returns
    -------
    matplotlib.figure.Figure
        One axes per interface, then the depth colour bar. On each axes: the scatters
        (``gid`` ``"trajectory:<fluid>:<model>"``) and their lines (``"path:<fluid>:<model>"``),
        the class regions (an image, ``"class_regions"``) and their names
        (``"class_label:<name>"``), the quadrant lines (``"quadrants"``) and the trend
        (``"background_trend"``).

    Raises
    ------
    ValueError
        As :func:`avo_class_depth`, and if the Dataset lacks ``avo_intercept`` or
        ``avo_gradient``.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> dims = ("fluid", "depth")
    >>> ds = xr.Dataset(
    ...     {"avo_intercept": (dims, [[0.06, 0.03], [-0.05, -0.03]]),
    ...      "avo_gradient": (dims, [[-0.12, -0.07], [-0.2, -0.15]]),
    ...      "avo_class": (dims, np.array([[1, 1], [4, 4]], dtype="int8"),
    ...                    {"flag_values": [1, 2, 3, 4, 5],
    ...                     "flag_meanings": "I IIp II III IV"})},
    ...     coords={"fluid": ["brine", "gas"],
    ...             "depth": ("depth", [2000.0, 3000.0], {"units": "m"})})
    >>> fig = intercept_gradient_crossplot(ds)
    >>> fig.axes[0].get_xlabel(), fig.axes[-1].get_ylabel()
    ('Intercept A (–)', 'Depth below the sediment surface (m)')
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    ds, held = _prepare(ds, ["avo_intercept", "avo_gradient", "avo_class"],
                        "intercept_gradient_crossplot")
    ds = _pick(ds, "interface", interface, "intercept_gradient_crossplot")
    values, meanings = _class_scale(ds)
    threshold = class_threshold(ds)
    order = ("interface", "fluid", "model", "depth")
    A = ds["avo_intercept"].transpose(*order).values.astype(float)
    B = ds["avo_gradient"].transpose(*order).values.astype(float)
    depth = np.asarray(ds["depth"].values, dtype=float)
    interfaces, fluids, models = (_names(ds, d) for d in ("interface", "fluid", "model"))

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.6 + 4.6 * len(interfaces), 5.0))
        axes = fig.subplots(1, len(interfaces), sharex=True, sharey=True, squeeze=False)[0]
        norm = plt.Normalize(float(depth.min()), float(depth.max()))
        cmap = plt.get_cmap("viridis_r")
        # every depth a marker up to _MARKED depths; past that every k-th (the line is whole)
        every = max(1, -(-depth.size // _MARKED))
        for r, (ax, face) in enumerate(zip(axes, interfaces)):
            for f, fluid in enumerate(fluids):
                for i, model in enumerate(models):
                    a, b = A[r, f, i], B[r, f, i]
                    ok = np.isfinite(a) & np.isfinite(b)
                    line = _model_line(model, i)
                    ax.plot(a[ok], b[ok], color=line["color"],
                            linewidth=0.8 if every == 1 else 1.4, alpha=0.8, zorder=2.0,
                            gid=f"path:{fluid}:{model}")
                    k = np.flatnonzero(ok)[(i * every) // len(models)::every]
                    ax.scatter(a[k], b[k], c=depth[k], cmap=cmap, norm=norm,
                               marker=_fluid_marker(fluid, f), s=22, edgecolors=line["color"],
                               linewidths=0.6, zorder=2.5, gid=f"trajectory:{fluid}:{model}")
            if len(interfaces) > 1 or interfaces[0]:
                ax.set_title(face)
            ax.set_xlabel("Intercept A (–)")
        axes[0].set_ylabel("Gradient B (–)")
        limits = _crossplot_limits(A, B, threshold)
        shown = set()                                   # the classes in the panels
        for r, ax in enumerate(axes):
            ax.set_xlim(*limits[0])
            ax.set_ylim(*limits[1])
            ax.set_autoscale_on(False)
            shown.update(_class_regions(ax, limits, threshold, values, meanings, A[r], B[r]))
            ax.axhline(0.0, color=_INK, linewidth=0.8, zorder=1.5, gid="quadrants")
            ax.axvline(0.0, color=_INK, linewidth=0.8, zorder=1.5, gid="quadrants")
            ax.grid(False)
            trend = _brine_trend(A[r], B[r], fluids)
            if trend is not None:
                x = np.array(limits[0])
                ax.plot(x, trend * x, color=_INK, linestyle=(0, (4, 2)), linewidth=1.0,
                        zorder=1.8, gid="background_trend",
                        label=f"brine trend B = {trend:.3g} A")
        # the fluids' markers above the panels, the models' lines and the trend below
        top = [Line2D([], [], linestyle="none", marker=_fluid_marker(fl, f),
                      markerfacecolor="0.75", markeredgecolor="0.25",
                      label=_fluid_text(fl) or "data") for f, fl in enumerate(fluids)]
        bottom = [Line2D([], [], linewidth=1.4, **_model_line(m, i))
                  for i, m in enumerate(models) if m]
        if any(ln.get_gid() == "background_trend" for ax in axes for ln in ax.get_lines()):
            bottom.append(Line2D([], [], color=_INK, linestyle=(0, (4, 2)), linewidth=1.0,
                                 label="brine trend B = m A (least squares)"))
        title = f"class threshold on A: {threshold:g}" + (
            "" if every == 1 else f"; markers every {every * float(np.median(np.diff(depth))):g}"
                                  " m, coloured by depth")
        from matplotlib.patches import Patch

        top += [Patch(facecolor=_CLASS_COLOURS[k % len(_CLASS_COLOURS)], alpha=0.35,
                      edgecolor="none", label=f"class {meanings[k]}") for k in sorted(shown)]
        _held_legend(fig, top, "; ".join(t for t in (held, title) if t), min(len(top), 8))
        if bottom:
            fig.legend(handles=bottom, loc="outside lower center", ncols=min(len(bottom), 3))
        bar = fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=list(axes),
                           pad=0.02)
        bar.set_label(_label("depth", ds))
        bar.ax.invert_yaxis()                          # depth increases downward
    return fig


def _crossplot_limits(A, B, threshold):
    """Axis limits that hold every point, both quadrant lines and the threshold band."""
    a, b = A[np.isfinite(A)], B[np.isfinite(B)]
    reach = max(1.6 * threshold, 0.01)
    x0, x1 = min(a.min(initial=0.0), -reach), max(a.max(initial=0.0), reach)
    y0, y1 = min(b.min(initial=0.0), -reach), max(b.max(initial=0.0), reach)
    px, py = 0.08 * (x1 - x0), 0.08 * (y1 - y0)
    return (x0 - px, x1 + px), (y0 - py, y1 + py)


def _class_regions(ax, limits, threshold, values, meanings, A, B, cells=400):
    """Shade each class region of the classification rule on ``ax`` and name it where it is
    farthest (in the axes' proportions) from the points ``A``, ``B`` within the region, when
    that place is at least :data:`_LABEL_ROOM` from them and from the region's edges (a
    narrow region is named by the legend alone). Returns the positions (in ``values``) of
    the classes shown."""
    (x0, x1), (y0, y1) = limits
    a = x0 + (np.arange(cells) + 0.5) * (x1 - x0) / cells
    b = y0 + (np.arange(cells) + 0.5) * (y1 - y0) / cells
    AA, BB = np.meshgrid(a, b)
    codes = _classify(AA, BB, threshold)
    from matplotlib.colors import to_rgba

    ok = np.isfinite(A) & np.isfinite(B)
    points = np.column_stack([(A[ok] - x0) / (x1 - x0), (B[ok] - y0) / (y1 - y0)])
    points = points[::max(1, len(points) // 2000)]
    coarse = slice(cells // 80, None, cells // 40)        # 40 x 40 candidate places
    rgba = np.zeros(codes.shape + (4,))
    shown = []
    for k, (value, name) in enumerate(zip(values, meanings)):
        inside = codes == value
        if not inside.any():
            continue
        shown.append(k)
        rgba[inside] = to_rgba(_CLASS_COLOURS[k % len(_CLASS_COLOURS)], 0.22)
        mask = inside[coarse, coarse]
        if mask.any():
            # the candidate inside the region farthest from the points, the region's edge
            # and the axes' edges (all in axes fractions)
            n = mask.shape[0]
            grid = (np.arange(n) + 0.5) / n
            xy = np.column_stack([grid[np.nonzero(mask)[1]], grid[np.nonzero(mask)[0]]])
            out = np.column_stack([grid[np.nonzero(~mask)[1]], grid[np.nonzero(~mask)[0]]])
            gaps = [np.minimum.reduce([xy[:, 0], 1.0 - xy[:, 0], xy[:, 1], 1.0 - xy[:, 1]])]
            for other in (points, out):
                if other.size:
                    gaps.append(np.min(np.hypot(xy[:, None, 0] - other[None, :, 0],
                                                xy[:, None, 1] - other[None, :, 1]), axis=1))
            room = np.minimum.reduce(gaps)
            j = int(np.argmax(room))
            if room[j] >= _LABEL_ROOM:
                ax.text(x0 + xy[j, 0] * (x1 - x0), y0 + xy[j, 1] * (y1 - y0), name,
                        ha="center", va="center", fontsize=10, fontweight="bold",
                        color="0.35", zorder=1.2, gid=f"class_label:{name}")
    ax.imshow(rgba, extent=(x0, x1, y0, y1), origin="lower", aspect="auto",
              interpolation="nearest", zorder=0.5, gid="class_regions")
    return shown


def _brine_trend(A, B, fluids):
    """Slope m of the least-squares line B = m A through the origin of the brine points
    (arrays ``(fluid, model, depth)``), or None without brine or without a brine contrast."""
    if "brine" not in fluids:
        return None
    a, b = A[fluids.index("brine")].ravel(), B[fluids.index("brine")].ravel()
    ok = np.isfinite(a) & np.isfinite(b)
    denominator = float(np.sum(a[ok] ** 2))
    if denominator == 0.0:
        return None
    return float(np.sum(a[ok] * b[ok]) / denominator)


# ----------------------------------------------------------------------------- R(angle)
def reflectivity_angle(ds, depths, *, interface=None, fig=None):
    """The PP reflection coefficient against angle of incidence at chosen depths: one row per
    depth (and interface), one column per fluid, one colour per model (the first model's
    line widest and lowest, so that models whose curves coincide, as Models 1 and 3 nearly do,
    stay visible).

    The real part of the exact (Zoeppritz) R_PP, ``reflectivity_pp``, is drawn solid over
    every angle; where R_PP is complex — beyond a critical angle, where ``|R_PP|``
    (``reflectivity_pp_magnitude``) exceeds ``|Re R_PP|`` by more than 1e-9 — its magnitude
    is drawn dashed over those angles (it is 1 beyond the P critical angle of a solid–solid
    interface only without converted waves; the dashed line shows what the Dataset holds).
    Each depth is the sample of ``ds`` nearest to the one asked for; the row says which.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset with ``reflectivity_pp`` and ``reflectivity_pp_magnitude``
        (dimensions among ``interface``, ``fluid``, ``model``, ``depth``, ``angle``).
    depths : float or sequence of float
        Depths (m) within the Dataset's depth range.
    interface : str or sequence of str, optional
        The interfaces to draw; default all.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        ``len(interface) · len(depths) × len(fluid)`` axes in row-major order (interface
        outer), then a legend (a colour per model; the line styles, in ink, as
        ``"solid: Re R_PP (exact)"`` and, where drawn,
        ``"dashed: |R_PP| where complex (beyond critical)"``).
        Lines carry the ``gid`` ``"re:<model>"`` and
        ``"magnitude:<model>"`` (the latter only where R_PP is complex).

    Raises
    ------
    ValueError
        If a variable is missing, ``depths`` is empty or a depth lies outside the Dataset's
        depth range, or as :func:`avo_class_depth`.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> angle = np.arange(0.0, 41.0, 10.0)
    >>> r = 0.1 - 0.2 * np.sin(np.radians(angle)) ** 2
    >>> dims = ("depth", "angle")
    >>> ds = xr.Dataset({"reflectivity_pp": (dims, [r, r]),
    ...                  "reflectivity_pp_magnitude": (dims, [abs(r), abs(r)])},
    ...                 coords={"depth": ("depth", [1000.0, 2000.0], {"units": "m"}),
    ...                         "angle": ("angle", angle, {"units": "degree",
    ...                                   "long_name": "angle of incidence"})})
    >>> fig = reflectivity_angle(ds, [1900.0])
    >>> fig.axes[0].get_title()
    'depth 2000 m'
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    ds, held = _prepare(ds, ["reflectivity_pp", "reflectivity_pp_magnitude"],
                        "reflectivity_angle")
    ds = _pick(ds, "interface", interface, "reflectivity_angle")
    if "angle" not in ds["reflectivity_pp"].dims:
        raise ValueError("reflectivity_pp has no 'angle' dimension: reflectivity_angle draws "
                         "it against angle")
    depth = np.asarray(ds["depth"].values, dtype=float)
    wanted = np.atleast_1d(np.asarray(depths, dtype=float))
    if wanted.size == 0:
        raise ValueError("depths must name at least one depth (m)")
    low, high = depth.min(), depth.max()
    bad = wanted[~((wanted >= low) & (wanted <= high))]
    if bad.size:
        raise ValueError(f"depths must lie within the Dataset's depth range "
                         f"{low:g}-{high:g} m; got {bad[0]:g}")
    picked = [int(np.argmin(np.abs(depth - z))) for z in wanted]
    order = ("interface", "fluid", "model", "depth", "angle")
    re = ds["reflectivity_pp"].transpose(*order).values.astype(float)
    mag = ds["reflectivity_pp_magnitude"].transpose(*order).values.astype(float)
    angle = np.asarray(ds["angle"].values, dtype=float)
    interfaces, fluids, models = (_names(ds, d) for d in ("interface", "fluid", "model"))
    rows = [(r, k) for r in range(len(interfaces)) for k in picked]

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.2 + 3.0 * len(fluids), 0.9 + 2.4 * len(rows)))
        axes = fig.subplots(len(rows), len(fluids), sharex=True, sharey=True, squeeze=False)
        for row, (r, k) in enumerate(rows):
            for c, fluid in enumerate(fluids):
                ax = axes[row, c]
                for i, model in enumerate(models):
                    line = _model_line(model, i)
                    width = _model_width(i, len(models))
                    ax.plot(angle, re[r, c, i, k], linewidth=width, zorder=2.0 + 0.01 * i,
                            gid=f"re:{model}", **line)
                    complex_ = mag[r, c, i, k] - np.abs(re[r, c, i, k]) > 1e-9
                    if complex_.any():
                        ax.plot(np.where(complex_, angle, np.nan),
                                np.where(complex_, mag[r, c, i, k], np.nan),
                                linestyle=(0, (4, 2)), linewidth=width, color=line["color"],
                                zorder=2.0 + 0.01 * i, gid=f"magnitude:{model}")
                ax.axhline(0.0, color="0.5", linewidth=0.6, zorder=1.0)
                title = [_capital(_fluid_text(fluid)) if fluid else "",
                         interfaces[r] if len(interfaces) > 1 else "",
                         f"depth {depth[k]:g} m"]
                ax.set_title(", ".join(t for t in title if t))
                if c == 0:
                    ax.set_ylabel("PP reflection coefficient (–)")
                if row == len(rows) - 1:
                    ax.set_xlabel(_angle_label(ds))
        ax.set_xlim(angle.min(), angle.max())
        handles = [Line2D([], [], linewidth=1.4, **_model_line(m, i))
                   for i, m in enumerate(models) if m]
        handles.append(Line2D([], [], color=_INK, linewidth=1.4, label="solid: Re R_PP (exact)"))
        if any(str(ln.get_gid()).startswith("magnitude:") for ax in axes.flat
               for ln in ax.get_lines()):
            handles.append(Line2D([], [], color=_INK, linewidth=1.2, linestyle=(0, (4, 2)),
                                  label="dashed: |R_PP| where complex (beyond critical)"))
        title = "; ".join(t for t in (held, interfaces[0] if len(interfaces) == 1
                                      and interfaces[0] else "") if t)
        _held_legend(fig, handles, title, min(len(handles), 3))
    return fig


# ----------------------------------------------------------------------------- synthetics
def synthetic_section(ds, *, scale="common", fig=None):
    """Normal-incidence synthetic traces against two-way time, and the angle gathers where the
    Dataset has them.

    The first row has one panel per fluid with one wiggle trace per model (positive lobes
    filled in the model's colour), two-way time increasing downward. Where ``ds`` has
    ``angle_gather`` (dimensions ``fluid``, ``model``, ``angle`` and ``gather_twt``, its own
    time window, or ``twt``), one row per model
    follows with that model's gather: a trace per angle (at most :data:`_GATHER_TRACES`: with
    more angles every k-th, from the first, k the smallest that keeps the count within it),
    positive lobes filled. With
    ``scale="common"`` every trace of a row is scaled by one gain, so that the largest
    amplitude of the row spans 0.45 of the trace spacing: amplitudes compare across fluids and
    models (and across angles); with ``scale="trace"`` each trace (each gather) by its own, so
    that a weak trace beside a strong one stays readable, and the legend says so.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset with ``synthetic`` (dimensions among ``fluid``, ``model``,
        ``twt``; coordinate ``twt`` in s).
    scale : {"common", "trace"}, optional
        One gain for every trace of a row (default), or one per trace (per gather).
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        ``(1 + len(model)) × len(fluid)`` axes with an angle gather, else ``len(fluid)``, in
        row-major order, then a legend. Wiggles carry the ``gid`` ``"trace:<model>"`` (and
        ``"gather:<model>:<angle>"``), their fills ``"fill:<model>"``
        (``"fill:<model>:<angle>"``).

    Raises
    ------
    ValueError
        If ``ds`` has no ``synthetic`` or it has no ``twt`` dimension, or as
        :func:`avo_class_depth`.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> t = np.arange(0.0, 0.5, 0.004)
    >>> w = np.exp(-((t - 0.25) / 0.01) ** 2)
    >>> ds = xr.Dataset({"synthetic": (("fluid", "twt"), [0.1 * w, -0.2 * w])},
    ...                 coords={"fluid": ["brine", "gas"], "depth": [0.0],
    ...                         "twt": ("twt", t, {"units": "s",
    ...                                            "long_name": "two-way time"})})
    >>> fig = synthetic_section(ds)
    >>> [ax.get_title() for ax in fig.axes], fig.axes[0].get_ylabel()
    (['Brine', 'Gas'], 'Two-way time (s)')
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    if scale not in ("common", "trace"):
        raise ValueError(f"scale must be 'common' or 'trace'; got {scale!r}")
    names = ["synthetic"] + (["angle_gather"] if "angle_gather" in ds.data_vars else [])
    ds, held = _prepare(ds, names, "synthetic_section", expand=("fluid", "model"))
    if "twt" not in ds["synthetic"].dims:
        raise ValueError("synthetic has no 'twt' dimension: synthetic_section draws it "
                         "against two-way time")
    twt = np.asarray(ds["twt"].values, dtype=float)
    fluids, models = _names(ds, "fluid"), _names(ds, "model")
    traces = ds["synthetic"].transpose("fluid", "model", "twt").values.astype(float)
    gather = None
    if "angle_gather" in ds.data_vars:
        tdim = "gather_twt" if "gather_twt" in ds["angle_gather"].dims else "twt"
        if not {tdim, "angle"} <= set(ds["angle_gather"].dims):
            raise ValueError("angle_gather must have the dimensions angle and twt (or "
                             "gather_twt)")
        angle = np.asarray(ds["angle"].values, dtype=float)
        every = max(1, -(-(angle.size - 1) // (_GATHER_TRACES - 1)))
        gather = ds["angle_gather"].transpose("fluid", "model", "angle", tdim).values
        gather = gather[:, :, ::every].astype(float)
        angle = angle[::every]
        gather_twt = np.asarray(ds[tdim].values, dtype=float)
    rows = 1 + (len(models) if gather is not None else 0)

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.2 + max(1.0, 0.55 * len(models)) * 1.6 * len(fluids),
                            0.9 + 4.2 * rows))
        axes = fig.subplots(rows, len(fluids), sharey="row", squeeze=False)
        gain = np.full(traces.shape[:2], 0.45 / _peak(traces)) if scale == "common" else \
            0.45 / np.vectorize(_peak, signature="(n)->()")(traces)
        for c, fluid in enumerate(fluids):
            ax = axes[0, c]
            for i, model in enumerate(models):
                colour = _model_line(model, i)["color"]
                _wiggle(ax, i, gain[c, i] * traces[c, i], twt, colour, f"trace:{model}",
                        f"fill:{model}")
            ax.set_xticks(range(len(models)),
                          [_short_model(m) for m in models])
            ax.set_xlim(-0.7, len(models) - 0.3)
            ax.set_title(_capital(_fluid_text(fluid)) if fluid else "synthetic")
            ax.grid(False, axis="x")
        if gather is not None:
            spacing = float(np.min(np.diff(angle))) if angle.size > 1 else 1.0
            gain = np.full(gather.shape[:2], 0.45 * spacing / _peak(gather)) \
                if scale == "common" else \
                0.45 * spacing / np.vectorize(_peak, signature="(a,n)->()")(gather)
            for i, model in enumerate(models):
                colour = _model_line(model, i)["color"]
                for c, fluid in enumerate(fluids):
                    ax = axes[1 + i, c]
                    for j, theta in enumerate(angle):
                        _wiggle(ax, theta, gain[c, i] * gather[c, i, j], gather_twt, colour,
                                f"gather:{model}:{theta:g}", f"fill:{model}:{theta:g}")
                    ax.set_xlim(angle.min() - spacing, angle.max() + spacing)
                    ax.set_xlabel(_angle_label(ds))
                    ax.set_title(": ".join(t for t in (_capital(_fluid_text(fluid)),
                                                       _short_model(model) + " gather"
                                                       if model else "angle gather") if t))
                    ax.grid(False, axis="x")
        for ax in axes[:, 0]:
            ax.set_ylabel(_label("twt", ds))
        axes[0, 0].set_ylim(twt.max(), twt.min())            # time increases downward
        if gather is not None:
            for row in axes[1:]:
                row[0].set_ylim(gather_twt.max(), gather_twt.min())
        handles = [Line2D([], [], linewidth=6.0, alpha=0.7, **_model_line(m, i))
                   for i, m in enumerate(models) if m]
        note = ("each trace scaled to its own peak" if scale == "trace" else
                "one gain for every trace of a row")
        _held_legend(fig, handles, "; ".join(t for t in (held, note) if t),
                     min(max(len(handles), 1), 4))
    return fig


def _peak(values) -> float:
    peak = float(np.nanmax(np.abs(values), initial=0.0))
    return peak if peak > 0.0 else 1.0


def _short_model(model) -> str:
    """A model's short name: "Model 1" of "Model 1 (HS–Krief–Gassmann)"; other labels whole."""
    return _model_label(model).split(" (")[0] if model else "trace"


def _wiggle(ax, x0, trace, twt, colour, gid, fill_gid):
    """A wiggle trace at ``x0``, its positive lobes filled in ``colour``."""
    ok = np.isfinite(trace)
    y = np.where(ok, trace, 0.0)
    # the zero crossings (linear between samples) added, so that the fill of the positive
    # part ends where the trace crosses zero
    i = np.flatnonzero(y[:-1] * y[1:] < 0.0)
    cross = twt[i] + (twt[i + 1] - twt[i]) * y[i] / (y[i] - y[i + 1])
    order = np.argsort(np.concatenate([twt, cross]), kind="stable")
    t = np.concatenate([twt, cross])[order]
    lobe = np.maximum(np.concatenate([y, np.zeros(i.size)])[order], 0.0)
    ax.fill_betweenx(t, x0, x0 + lobe, color=colour, alpha=0.7, linewidth=0.0, zorder=2.0,
                     gid=fill_gid)
    ax.plot(np.where(ok, x0 + y, np.nan), twt, color=_INK, linewidth=0.7, zorder=2.5, gid=gid)
