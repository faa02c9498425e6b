"""Figures of MD studies: velocity against cement saturation S_c, a panel per sample and cement."""

from __future__ import annotations

import re

import numpy as np

from ._style import _INK, _RC, _capital, _figure, _units_text

__all__ = ["md_study_velocity", "velocity_error"]

#: The dimensions of an MD study's velocities (:func:`md.experiment.run_md_scene`): rows,
#: columns and lines of the figure, then the x axis.
_STUDY_DIMS = ("sample", "cement", "scheme", "saturation")
_SCHEME_COLOURS = {"contact": "#0072B2", "coating": "#D55E00", "pore_body": "#009E73",
                   "pendular": "#CC79A7"}
_SCHEME_MARKERS = {"contact": "o", "coating": "s", "pore_body": "^", "pendular": "D"}
_EXTRA_COLOURS = ("#E69F00", "#56B4E9", "#000000")
_EXTRA_MARKERS = ("v", "P", "X")
#: Offset between the schemes' points along S_c, as a fraction of the S_c range: side by side,
#: their error bars do not hide one another.
_DODGE = 0.012


def velocity_error(ds, velocity="vp"):
    r"""The error bar of an MD study's pulse velocity: the eq. 11 error combined in quadrature
    with the resolution error where the study has one.

    :math:`\sigma = \sqrt{\sigma_{11}^2 + \sigma_\Omega^2}` with :math:`\sigma_{11}` the
    variable ``<velocity>_error`` (eq. 11 of [GarciaMedina2007]_, arrival-time error for
    :math:`\Delta L = R`) and :math:`\sigma_\Omega` the variable
    ``<velocity>_error_resolution`` (Richardson estimate from a second, coarser Ω). This is
    :func:`md.calibrate.total_error`, written again here because importing :mod:`md` loads
    numba, which ``rockcem plot`` must not; a test holds the two equal.

    Parameters
    ----------
    ds : xarray.Dataset
        An MD study's output (:func:`md.experiment.run_md_scene`).
    velocity : str, optional
        ``"vp"`` (default) or ``"vs"``.

    Returns
    -------
    xarray.DataArray or None
        The error in the units of ``<velocity>_error`` (km/s in the files md writes), or None
        when ``ds`` has no ``<velocity>_error``.

    Raises
    ------
    ValueError
        If the two errors are in different units.

    Examples
    --------
    >>> import xarray as xr
    >>> ds = xr.Dataset({"vp_error": ("saturation", [0.03], {"units": "km s-1"}),
    ...                  "vp_error_resolution": ("saturation", [0.04], {"units": "km s-1"})})
    >>> float(velocity_error(ds).round(6)[0])
    0.05
    """
    if f"{velocity}_error" not in ds.variables:
        return None
    err = ds[f"{velocity}_error"]
    res = ds.get(f"{velocity}_error_resolution")
    if res is None:
        return err
    if res.attrs.get("units") != err.attrs.get("units"):
        raise ValueError(f"{velocity}_error_resolution is in {res.attrs.get('units')!r}, "
                         f"{velocity}_error in {err.attrs.get('units')!r}; they must agree")
    return np.hypot(err, res).assign_attrs(units=err.attrs.get("units"))


def md_study_velocity(ds, velocity=None, *, static=True, fig=None):
    """Velocity against cement saturation S_c of an MD study: a panel per sample (rows) and
    cement (columns), a line per cementation scheme.

    The pulse-test velocity is drawn with filled markers, a solid line and error bars
    (:func:`velocity_error`: the eq. 11 error of [GarciaMedina2007]_, in quadrature with the
    resolution error where the study has one); the velocity of the static modulus (the
    long-wave limit, ``<velocity>_static``) with open markers of the same shape and colour on a
    dotted line. The schemes' points stand side by side, offset along S_c by 1.2 % of its
    range per scheme (centred on the true S_c), so that their error bars do not hide one
    another. Panels of a row share the velocity axis, every panel the S_c axis; the
    velocity axis starts at 0 when an error bar would reach below it. Each panel is titled
    with its sample (and the sample's vertical stress, where ``ds`` has ``stress``) and cement;
    a dimension reduced to one value (``rockcem plot --select sample=loose``) gives one row,
    column or line, still named. Labels take the quantities' units from ``ds``'s attributes.

    Parameters
    ----------
    ds : xarray.Dataset
        An MD study's output (:func:`md.experiment.run_md_scene`, e.g. the scenes
        ``garcia_medina_full`` and ``garcia_medina_cement``): dimension ``saturation``
        (S_c, fraction) and any of ``sample``, ``cement``, ``scheme`` (labels, dimensions or
        scalar coordinates); velocities in ``ds[velocity].attrs["units"]``, the errors and the
        static velocity in the same units.
    velocity : str, optional
        ``"vp"`` or ``"vs"``; default the one of the two that ``ds`` has.
    static : bool, optional
        Draw ``<velocity>_static`` where ``ds`` has it; default True.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in; default a new one sized for the panels.

    Returns
    -------
    matplotlib.figure.Figure
        ``len(sample) × len(cement)`` axes in row-major order, then a legend of the schemes and
        of the marker styles above the panels. Lines carry the ``gid`` ``"pulse:<scheme>"`` and
        ``"static:<scheme>"``.

    Raises
    ------
    ValueError
        If ``ds`` is not an MD study (no ``saturation`` dimension, or no velocity over it), the
        velocity has another dimension, or a variable lacks units or has other units than the
        velocity.

    Examples
    --------
    >>> import numpy as np, xarray as xr
    >>> sc = [0.0, 0.05, 0.1]
    >>> v = np.array([1.7, 2.1, 2.4]) * np.ones((2, 1, 2, 1))
    >>> kms = {"units": "km s-1"}
    >>> ds = xr.Dataset(
    ...     {"vp": (("sample", "cement", "scheme", "saturation"), v, kms),
    ...      "vp_error": (("sample", "cement", "scheme", "saturation"), 0.05 + 0 * v, kms),
    ...      "vp_static": (("sample", "cement", "scheme", "saturation"), v + 0.1, kms)},
    ...     coords={"sample": ["loose", "compacted"], "cement": ["hard"],
    ...             "scheme": ["contact", "coating"],
    ...             "saturation": ("saturation", sc, {"units": "1",
    ...                                               "long_name": "cement saturation S_c"})})
    >>> fig = md_study_velocity(ds)
    >>> [ax.get_title() for ax in fig.axes]
    ['Loose pack, hard cement', 'Compacted pack, hard cement']
    >>> fig.axes[0].get_ylabel(), fig.axes[-1].get_xlabel()
    ('P-wave velocity (km/s)', 'Cement saturation $S_\\\\mathrm{c}$ (–)')
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    if not (hasattr(ds, "data_vars") and hasattr(ds, "dims")):
        raise ValueError(f"ds must be an xarray.Dataset; got {type(ds).__name__}")
    name = _velocity_name(ds, velocity)
    da = ds[name]
    other = [str(d) for d in da.dims if d not in _STUDY_DIMS]
    if other:
        raise ValueError(f"{name} has the dimension(s) {', '.join(other)}, which an MD study's "
                         f"figure does not draw (it draws {', '.join(_STUDY_DIMS)}); select "
                         "one value of each first")
    units = da.attrs.get("units")
    if not units:
        raise ValueError(f"{name} has no 'units' attribute; the figure labels its axis from it")
    err = velocity_error(ds, name)
    static_da = ds.get(f"{name}_static") if static else None
    for other_da in (err, static_da):
        if other_da is not None and other_da.attrs.get("units") != units:
            shown = other_da.name or f"{name}_error"
            raise ValueError(f"{shown} is in {other_da.attrs.get('units')!r} and {name} in "
                             f"{units!r}; they must agree")
    rows, cols, schemes = (_labels(ds, da, d) for d in _STUDY_DIMS[:3])
    x = np.asarray(ds["saturation"].values, dtype=float)
    span = float(np.ptp(x)) if x.size > 1 else 1.0

    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    with plt.rc_context(_RC):
        fig = _figure(fig, (1.2 + 3.0 * len(cols), 1.3 + 2.6 * len(rows)))
        axes = fig.subplots(len(rows), len(cols), sharex=True, sharey="row", squeeze=False)
        panels = [(rc, cc) for rc in enumerate(rows) for cc in enumerate(cols)]
        for (r, sample), (c, cement) in panels:
            ax = axes[r, c]
            low = np.inf
            for k, scheme in enumerate(schemes):
                sel = {d: i for d, i in (("sample", r), ("cement", c), ("scheme", k))
                       if d in da.dims}
                style = _scheme_style(scheme, k)
                y = np.asarray(da.isel(sel).transpose("saturation").values, dtype=float)
                yerr = (None if err is None else
                        np.asarray(err.isel({d: i for d, i in sel.items() if d in err.dims})
                                   .transpose("saturation").values, dtype=float))
                at = x + _DODGE * span * (k - (len(schemes) - 1) / 2.0)
                drawn = ax.errorbar(at, y, yerr=yerr, linestyle="-", linewidth=1.3,
                                    markersize=5.0, capsize=2.5, elinewidth=0.9,
                                    label=_text(scheme), zorder=3.0 + 0.01 * k, **style)
                drawn.lines[0].set_gid(f"pulse:{scheme}")
                if yerr is not None:
                    bottom = y - yerr
                    if np.any(np.isfinite(bottom)):
                        low = min(low, float(np.nanmin(bottom)))
                if static_da is not None:
                    ys = static_da.isel({d: i for d, i in sel.items() if d in static_da.dims})
                    ax.plot(at, np.asarray(ys.transpose("saturation").values, dtype=float),
                            linestyle=":", linewidth=1.0, markersize=5.0,
                            markerfacecolor="white", markeredgewidth=1.1,
                            gid=f"static:{scheme}", zorder=2.5 + 0.01 * k, **style)
            if low < 0.0:           # a velocity below 0 means nothing: cut the bar there
                ax.set_ylim(bottom=0.0)
            ax.set_title(_title(ds, sample, cement))
            if r == len(rows) - 1:
                ax.set_xlabel(_saturation_label(ds))
            if c == 0:
                ax.set_ylabel(_velocity_label(name, units))
        handles = [Line2D([], [], linestyle="-", label=_text(s), **_scheme_style(s, k))
                   for k, s in enumerate(schemes)]
        scheme_title = (_capital(_plain(ds["scheme"], "scheme")) if "scheme" in ds.coords
                        else "Scheme")
        fig.legend(handles=handles, loc="outside upper center", ncols=len(handles),
                   title=scheme_title)
        bars = ("bars: eq. 11 and resolution errors in quadrature"
                if f"{name}_error_resolution" in ds.variables else "bars: eq. 11 error")
        kinds = [Line2D([], [], color=_INK, marker="o", linestyle="-",
                        label=_capital(_plain(da, "pulse-test velocity"))
                        + (f"; {bars}" if err is not None else ""))]
        if static_da is not None:
            kinds.append(Line2D([], [], color=_INK, marker="o", linestyle=":",
                                markerfacecolor="white",
                                label=_capital(_plain(static_da, "static velocity"))))
        fig.legend(handles=kinds, loc="outside lower center",   # one column under one panel
                   ncols=len(kinds) if len(cols) > 1 else 1)
    return fig


# ----------------------------------------------------------------------------- helpers
def _velocity_name(ds, velocity):
    """The velocity variable of an MD study, or a one-line ValueError saying what ds is."""
    dims = ", ".join(map(str, ds.dims)) or "none"
    if "saturation" not in ds.dims:
        raise ValueError(f"ds is not an MD study: it has no 'saturation' dimension (cement "
                         f"saturation S_c; dimensions: {dims}); a scene Dataset with a "
                         "'depth' dimension is drawn by depth_trends")
    names = [velocity] if velocity is not None else ["vp", "vs"]
    for name in names:
        if name in ds.data_vars and "saturation" in ds[name].dims:
            return name
    if velocity is not None and velocity not in ("vp", "vs"):
        raise ValueError(f"velocity must be 'vp' or 'vs'; got {velocity!r}")
    raise ValueError(f"ds is not an MD study: it has no variable {' or '.join(map(repr, names))} "
                     f"over 'saturation' (variables: {', '.join(map(str, ds.data_vars))})")


def _labels(ds, da, dim):
    """Values of ``dim`` drawn: the coordinate's labels if ``da`` varies along it, its single
    value if it is a scalar coordinate, else ``[None]``."""
    if dim in da.dims:
        return [str(v) for v in ds[dim].values]
    if dim in ds.coords and ds[dim].ndim == 0:
        return [str(ds[dim].values.item())]
    return [None]


def _scheme_style(scheme, index):
    colour = _SCHEME_COLOURS.get(scheme, _EXTRA_COLOURS[index % len(_EXTRA_COLOURS)])
    marker = _SCHEME_MARKERS.get(scheme, _EXTRA_MARKERS[index % len(_EXTRA_MARKERS)])
    return {"color": colour, "marker": marker}


def _text(label):
    return "all" if label is None else str(label).replace("_", " ")


def _plain(da, default):
    """``long_name`` of ``da`` without its parenthetical remarks (``default`` if none)."""
    return re.sub(r"\s*\([^)]*\)", "", str(da.attrs.get("long_name", default))).strip()


def _title(ds, sample, cement):
    parts = []
    if sample is not None:
        text = f"{_text(sample)} pack"
        stress = ds.get("stress")           # per sample, or one value of a selected sample
        if (stress is not None and stress.attrs.get("units")
                and stress.dims in (("sample",), ())):
            value = float(stress.sel(sample=sample) if stress.dims else stress)
            if np.isfinite(value):
                text += (rf" ($\sigma_{{zz}}$ {value:.3g} "
                         f"{_units_text(stress.attrs['units'])})")
        parts.append(text)
    if cement is not None:
        parts.append(f"{_text(cement)} cement")
    return _capital(", ".join(parts))


def _saturation_label(ds):
    sat = ds["saturation"]
    quantity = _capital(_plain(sat, "cement saturation S_c")).replace("S_c", r"$S_\mathrm{c}$")
    units = sat.attrs.get("units")
    return f"{quantity} ({_units_text(units)})" if units is not None else quantity


def _velocity_label(name, units):
    quantity = {"vp": "P-wave velocity", "vs": "S-wave velocity"}[name]
    return f"{quantity} ({_units_text(units)})"
