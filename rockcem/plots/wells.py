"""Well logs over the modelled depth trends and on the rock-physics template; a fit's
before/after figure."""

from __future__ import annotations

import numpy as np

__all__ = ["well_overlay", "well_band", "well_template", "fit_figure"]

_WELL_COLOUR = "#7F7F7F"
_WELL_VARIABLES = ("vp", "vs", "density", "porosity")


def _log_style(n):
    """Dots for sparse logs, a thin line for dense ones (drawn under the models)."""
    return ({"linestyle": "none", "marker": ".", "markersize": 3.0} if n <= 200 else
            {"linewidth": 0.6}) | {"color": _WELL_COLOUR, "alpha": 0.8, "zorder": 1.0}


def _shared(ds, well, variables):
    """The variables to draw: ``variables`` (default all of ``vp``, ``vs``, ``density``,
    ``porosity`` that the scene and the well both hold), each checked to be in both."""
    shared = [v for v in _WELL_VARIABLES if v in ds.data_vars and v in well.data_vars]
    variables = shared if variables is None else list(variables)
    missing = [v for v in variables if v not in shared]
    if missing or not variables:
        raise ValueError(f"variable {missing[0] if missing else None!r} is not in both the "
                         f"scene and the well (shared: {', '.join(shared) or 'none'})")
    return variables


def well_overlay(ds, well, variables=None, *, depth=None, fig=None):
    """Well logs drawn over a scene's depth trends (one panel per shared variable).

    The panels are those of :func:`rockcem.plots.depth_trends` (models in their colours); the
    logs are drawn in grey beneath them, labelled with the well's name and the log's mnemonic
    (``"NPHI, apparent"`` for an apparent porosity: a neutron or density porosity).

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset (no sweep dimension; select a member first).
    well : xarray.Dataset
        From :func:`rockcem.wells.read_well` (depth m, vp/vs km/s, density g/cm³, porosity).
    variables : sequence of str, optional
        Default: those of ``vp``, ``vs``, ``density``, ``porosity`` both hold.
    depth : (float, float), optional
        Depth range shown, m; default the scene's and the well's together.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        The depth-trend axes with the log lines (``gid`` ``"well:<variable>"``).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> z = np.linspace(0.0, 3000.0, 31)
    >>> ds = build_dataset({"vp": (("depth",), 2.0 + 1e-3 * z)}, {"depth": (("depth",), z)})
    >>> well = build_dataset({"vp": (("depth",), [3.1, 3.9])}, {"depth": (("depth",), [1000.0,
    ...                      2000.0])})
    >>> fig = well_overlay(ds, well)
    >>> [line.get_gid() for line in fig.axes[0].lines if line.get_gid()]
    ['well:vp']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    from .depth import depth_trends

    variables = _shared(ds, well, variables)
    fig = depth_trends(ds, list(variables), temperature_axis=False, fig=fig)
    name = well.attrs.get("well") or well.attrs.get("source_file") or "well"
    z = well.depth.values
    logs = []
    for ax, v in zip(fig.axes, variables):
        values = well[v].values
        # log_label (rockcem.wells): the mnemonic, and "NPHI, apparent" for a neutron or
        # density porosity, which is not the total porosity the scene models.
        log = well[v].attrs.get("log_label") or well[v].attrs.get("source_mnemonic", v)
        line, = ax.plot(values, z, label=f"{name} ({log})",
                        gid=f"well:{v}", **_log_style(np.isfinite(values).sum()))
        logs.append(line)
    # One legend of the logs below the panels, where it covers no data (inside a panel it
    # covered the density and porosity logs).
    fig.legend(handles=logs, loc="outside lower center", ncols=min(len(logs), 4),
               fontsize=7.5, frameon=False)
    lo = min(float(ds.depth.min()), float(z.min())) if depth is None else float(depth[0])
    hi = max(float(ds.depth.max()), float(z.max())) if depth is None else float(depth[1])
    fig.axes[0].set_ylim(hi, lo)
    return fig


def well_band(ds, well, variables=None, *, models=None, band=None, depth=None, fig=None):
    """Well logs over a scene's quantile band and median (a scene with ``[uncertain]``).

    One panel per curve both hold: for each model (model-independent variables in dark grey)
    the band between two quantiles of the members shaded, the median (quantile 0.5) as a line,
    and the log in grey drawn over them. These are quantiles (probability of non-exceedance):
    the default 0.1-0.9 band holds about 80 % of a well-calibrated model's samples; the share
    of each log inside it per interval is the ``inside`` column of
    :func:`rockcem.wells.well_misfit` (``rockcem compare``).

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset with a ``quantile`` dimension holding 0.5 (no sweep dimension).
    well : xarray.Dataset
        From :func:`rockcem.wells.read_well` (depth m, vp/vs km/s, density g/cm³, porosity).
    variables : sequence of str, optional
        Curves drawn, one panel each (default every one of ``vp``, ``vs``, ``density``,
        ``porosity`` that the scene and the well share).
    models : sequence of str, optional
        Models drawn (default all of the Dataset's).
    band : (float, float), optional
        The band's quantiles, two of the Dataset's; default its lowest and highest.
    depth : (float, float), optional
        Top and base drawn, m (default from the shallower to the deeper end of the scene and
        the log).
    fig : matplotlib.figure.Figure, optional
        An empty figure to draw the panels in.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per variable: the bands (``gid`` ``"band:<variable>:<model>"``, model ``"-"``
        for a model-independent variable), the medians (``"median:<variable>:<model>"``) and
        the logs (``"well:<variable>"``).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> z = np.linspace(0.0, 3000.0, 4)
    >>> vp = np.stack([2.0 + 1e-3 * z, 2.2 + 1e-3 * z, 2.4 + 1e-3 * z])   # quantile, depth
    >>> ds = build_dataset({"vp": (("quantile", "depth"), vp)},
    ...                    {"quantile": (("quantile",), [0.1, 0.5, 0.9]),
    ...                     "depth": (("depth",), z)})
    >>> well = build_dataset({"vp": (("depth",), [3.1, 3.9])}, {"depth": (("depth",), [1000.0,
    ...                      2000.0])})
    >>> fig = well_band(ds, well)
    >>> ax = fig.axes[0]
    >>> [a.get_gid() for a in ax.collections + ax.lines if a.get_gid()]
    ['band:vp:-', 'median:vp:-', 'well:vp']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    import matplotlib.pyplot as plt

    from .._well_misfit import _at_quantile, band_quantiles
    from ._style import _INK, _RC, _label, _model_colour, _model_label

    if "quantile" not in ds.dims:
        raise ValueError("well_band needs a scene Dataset with quantiles (a scene with "
                         "[uncertain]); draw this one with well_overlay")
    low, high, median = band_quantiles(ds, band)
    variables = _shared(ds, well, variables)
    extra = sorted({d for v in variables for d in ds[v].dims} - {"quantile", "model", "depth"})
    if extra:
        raise ValueError(f"the scene Dataset has sweep dimensions {', '.join(extra)}; select "
                         "one member first (ds.sel(...))")
    all_models = ds.model.values.tolist() if "model" in ds.dims else []
    models = all_models if models is None else list(models)
    unknown = [m for m in models if m not in all_models]
    if unknown:
        raise ValueError(f"model {unknown[0]!r} is not in the scene Dataset (models: "
                         f"{', '.join(map(str, all_models)) or 'none'})")
    at = {q: _at_quantile(ds, q) for q in (low, high, median)}
    z = ds.depth.values
    name = well.attrs.get("well") or well.attrs.get("source_file") or "well"
    with plt.rc_context(_RC):
        if fig is None:
            fig = plt.figure(figsize=(1.2 + 2.3 * len(variables), 5.6), layout="constrained")
        axes = np.atleast_1d(fig.subplots(1, len(variables), sharey=True, squeeze=False)[0])
        handles = []
        for ax, v in zip(axes, variables):
            drawn = [(m, _model_colour(m, i)) for i, m in enumerate(all_models)
                     if m in models] if "model" in ds[v].dims else [("-", _INK)]
            for m, colour in drawn:
                lo, hi, mid = (at[q][v].sel(model=m) if m != "-" else at[q][v]
                               for q in (low, high, median))
                what = _model_label(m) if m != "-" else "scene"
                patch = ax.fill_betweenx(z, lo.values, hi.values, color=colour, alpha=0.25,
                                         linewidth=0.0, zorder=1.0, gid=f"band:{v}:{m}",
                                         label=f"{what}: quantiles {low:g}–{high:g}")
                line, = ax.plot(mid.values, z, color=colour, linewidth=1.4, zorder=2.0,
                                gid=f"median:{v}:{m}", label=f"{what}: median")
                handles += [patch, line]
            log = well[v].attrs.get("log_label") or well[v].attrs.get("source_mnemonic", v)
            style = _log_style(np.isfinite(well[v].values).sum()) | {"zorder": 3.0}
            line, = ax.plot(well[v].values, well.depth.values, label=f"{name} ({log})",
                            gid=f"well:{v}", **style)
            handles.append(line)
            ax.set_xlabel(_label(v, ds, width=26))
        axes[0].set_ylabel(_label("depth", ds))
        zw = well.depth.values
        top = min(float(z.min()), float(zw.min())) if depth is None else float(depth[0])
        base = max(float(z.max()), float(zw.max())) if depth is None else float(depth[1])
        axes[0].set_ylim(base, top)
        unique = list({h.get_label(): h for h in handles}.values())
        fig.legend(handles=unique, loc="outside lower center", ncols=min(len(unique), 4),
                   fontsize=7.5, frameon=False)
    return fig


def well_template(ds, well, *, fig=None, **template):
    """The rock-physics template with the scene's points and the well's samples over it.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset with ``density``, ``vp``, ``vs``.
    well : xarray.Dataset
        Logs with ``density``, ``vp`` and ``vs``.
    fig : matplotlib.figure.Figure, optional
    **template
        Passed to :func:`rockcem.plots.rock_physics_template` (materials, pressure, grid).

    Returns
    -------
    matplotlib.figure.Figure
        The template, with the well's samples in grey (``gid`` ``"well"``).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> z = np.linspace(1000.0, 3000.0, 5)
    >>> logs = {"density": (("depth",), np.full(5, 2.3)),
    ...         "vp": (("depth",), np.linspace(3.0, 4.2, 5)),
    ...         "vs": (("depth",), np.linspace(1.7, 2.5, 5))}
    >>> ds = build_dataset(logs, {"depth": (("depth",), z)})
    >>> fig = well_template(ds, ds)
    >>> [line.get_gid() for line in fig.axes[0].lines if line.get_gid() == "well"]
    ['well']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    from .templates import rock_physics_template

    need = [v for v in ("density", "vp", "vs") if v not in well.data_vars]
    if need:
        raise ValueError(f"the template needs the well's density, vp and vs; it has no "
                         f"{need[0]}")
    fig = rock_physics_template(ds, fig=fig, **template)
    ax = fig.axes[0]
    impedance = well.density.values * well.vp.values
    ratio = well.vp.values / well.vs.values
    name = str(well.attrs.get("well") or "well")
    ax.plot(impedance, ratio, linestyle="none", marker=".", markersize=2.5,
            color=_WELL_COLOUR, alpha=0.6, zorder=2.0, gid="well", label=name)
    n = int(np.isfinite(impedance * ratio).sum())
    ax.text(0.02, 0.02, f"grey dots: well {name} ({n} samples)", transform=ax.transAxes,
            fontsize=7.0, color="#555555", ha="left", va="bottom")
    return fig


def _unit(dotted):
    """`` unit`` of a scene key from the scene schema (empty for counts and fractions)."""
    from ..scene import SCHEMA

    section, _, key = dotted.rpartition(".")
    unit = SCHEMA.get(section, {}).get(key, (None, None, ""))[2]
    return f" {unit}" if unit not in ("", "1") else ""


def _fitted_text(dotted, value, stderr):
    """A fitted scene key as a reader writes it: its name in words (the variable registry's
    ``long_name``, else the key with spaces) and the value with its standard error, both to the
    error's second significant digit (``coordination number 6.48 ± 0.08``)."""
    import math

    from ..variables import variable_attrs

    key = dotted.rpartition(".")[2]
    try:
        name = variable_attrs(key).get("long_name", key.replace("_", " "))
    except ValueError:
        name = key.replace("_", " ")
    if not (np.isfinite(stderr) and stderr > 0):
        return f"{name} {value:.4g}{_unit(dotted)} (error not determined)"
    digits = max(0, 1 - math.floor(math.log10(stderr)))
    return f"{name} {value:.{digits}f} ± {stderr:.{digits}f}{_unit(dotted)}"


def fit_figure(fit, well, *, fig=None):
    """Before/after figure of a scene fitted to a well (:func:`rockcem.wellfit.fit_scene`).

    One panel per fitted log: the log in grey, the scene at its starting values (dashed) and
    at the fitted values (solid), the fit's depth window shaded, and the fitted values with
    their uncertainties in the title.

    Parameters
    ----------
    fit : rockcem.wellfit.SceneFit
        From :func:`rockcem.wellfit.fit_scene`.
    well : xarray.Dataset
        The logs it was fitted to.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        One axes per fitted log (lines with ``gid`` ``"before"`` and ``"after"``).

    Examples
    --------
    A well made from the sandstone scene with delta = 60 MPa, fitted from the scene's 100:

    >>> import numpy as np
    >>> from rockcem.scene import load_scene, run_scene
    >>> from rockcem.synthetic_well import synthetic_well
    >>> from rockcem.wellfit import fit_scene
    >>> scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 100.0})
    >>> truth = run_scene(scene.replace(**{"models.patchy_cement.delta": 60.0}))
    >>> well = synthetic_well(truth, np.arange(1000.0, 3000.0, 50.0), sigma={"vp": 0.0},
    ...                       model="patchy_cement")
    >>> fit = fit_scene(scene, well, ["models.patchy_cement.delta"], model="patchy_cement")
    >>> round(fit.result.values["models.patchy_cement.delta"], 3)
    60.0
    >>> fig = fit_figure(fit, well)
    >>> sorted(line.get_gid() for line in fig.axes[0].lines if line.get_gid())
    ['after', 'before']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    import matplotlib.pyplot as plt

    from matplotlib.patches import Patch

    from ..runner import evaluate
    from ._style import _RC, _label, _model_label

    before, after = evaluate(fit.scene), evaluate(fit.fitted)
    variables = list(fit.variables)
    with plt.rc_context(_RC):
        if fig is None:
            fig = plt.figure(figsize=(1.2 + 2.3 * len(variables), 5.6), layout="constrained")
        axes = np.atleast_1d(fig.subplots(1, len(variables), sharey=True, squeeze=False)[0])
        for ax, v in zip(axes, variables):
            ax.plot(well[v].values, well.depth.values, label="well",
                    **_log_style(np.isfinite(well[v].values).sum()))
            for ds, style, text in ((before, {"linestyle": "--", "color": "#0072B2"},
                                     "before"),
                                    (after, {"linestyle": "-", "color": "#D55E00"}, "after")):
                da = ds[v].sel(model=fit.model) if "model" in ds[v].dims else ds[v]
                ax.plot(da.values, ds.depth.values, linewidth=1.6, label=text, gid=text,
                        **style)
            ax.axhspan(*fit.depth_range, color="#F0E442", alpha=0.15, zorder=0)
            ax.set_xlabel(_label(v, after, width=26))
        axes[0].set_ylabel(_label("depth", after))
        z = well.depth.values
        axes[0].set_ylim(max(float(after.depth.max()), float(z.max())),
                         min(float(after.depth.min()), float(z.min())))
        top, base = fit.depth_range
        handles = axes[0].get_legend_handles_labels()[0] + [Patch(
            color="#F0E442", alpha=0.3, linewidth=0,
            label=f"fit window {top:g}–{base:g} m")]
        fig.legend(handles=handles, loc="outside lower center", ncols=len(handles),
                   fontsize=7.5, frameon=False)
        r = fit.result
        fig.suptitle("; ".join(_fitted_text(k, r.values[k], r.stderr[k]) for k in r.values)
                     + (f"  ·  {_model_label(fit.model)}" if fit.model else ""), fontsize=9.0)
    return fig
