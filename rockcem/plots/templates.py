"""Rock-physics templates: velocity against porosity with the contact-model family, and
acoustic impedance against Vp/Vs with iso-porosity and iso-cement lines."""

from __future__ import annotations

import difflib

import numpy as np

from ._style import (_INK, _RC, _held, _label, _model_label, _model_marker, _model_size,
                     _model_style, _members, _shade, _sweep_legend, _check_dataset, _require,
                     _material, _figure)

__all__ = ["velocity_porosity", "rock_physics_template"]


def _shown(material, default: str) -> str:
    """A material's catalogue name as legend text (``quartz_cement`` -> ``quartz cement``)."""
    return (material.name or default).replace("_", " ")


def _saturated(dry, grain, fluid, porosity):
    """Velocities (km/s) of a dry frame saturated by Gassmann with the grain as the mineral."""
    from ..elastic import velocities
    from ..fluids import gassmann

    K_sat = gassmann(dry.K, grain.K, fluid.K, porosity)
    density = (1.0 - porosity) * grain.rho + porosity * fluid.rho
    return velocities(K_sat, dry.G, density)


def _broken(x, y, saturation):
    """``x`` and ``y`` along depth with a NaN between two depths whose hydrocarbon saturation
    differs (a reservoir's top or base), so that the line breaks there instead of joining the
    brine sand to the reservoir's with a segment that reads as a trend.

    >>> x, y = _broken([0.3, 0.29, 0.28], [3.0, 2.0, 2.1], [0.0, 0.8, 0.8])
    >>> x.tolist(), y.tolist()
    ([0.3, nan, 0.29, 0.28], [3.0, nan, 2.0, 2.1])
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    saturation = np.broadcast_to(np.asarray(saturation, dtype=float), x.shape)
    cuts = np.flatnonzero(saturation[1:] != saturation[:-1]) + 1
    return np.insert(x, cuts, np.nan), np.insert(y, cuts, np.nan)


def _contact_templates(grain, cement, fluid, pressure, coordination_number, critical_porosity):
    """``{key: (label, porosity, Velocities)}`` of the contact-model family, brine-saturated."""
    from ..granular import constant_cement, contact_cement, soft_sand, stiff_sand

    phic, n = critical_porosity, coordination_number
    phib = phic - 0.04
    full = np.linspace(0.0, phic, 181)
    cct = np.linspace(max(phic - 0.10, 0.0), phic, 61)   # CCT holds for a few per cent of cement
    below_b = np.linspace(0.0, phib, 161)
    g, c = grain, cement
    dry = {
        "soft_sand": ("Soft sand", full, soft_sand(g.K, g.G, full, phic, n, pressure)),
        "stiff_sand": ("Stiff sand", full, stiff_sand(g.K, g.G, full, phic, n, pressure)),
        "contact_cement": ("Contact cement", cct,
                           contact_cement(g.K, g.G, c.K, c.G, cct, phic, n, scheme=1)),
        "constant_cement": (f"Constant cement ($\\phi_b$ = {phib:.2f})", below_b,
                            constant_cement(g.K, g.G, c.K, c.G, below_b, phic, n, phib, scheme=1)),
    }
    return {k: (label, phi, _saturated(m, grain, fluid, phi)) for k, (label, phi, m) in dry.items()}


def velocity_porosity(ds, *, velocity="vp", grain=None, cement=None, fluid=None, pressure=None,
                      coordination_number=None, critical_porosity=None, fig=None):
    r"""Velocity against porosity, per model, over the contact-model family of templates.

    The templates are the dry-rock models of :mod:`rockcem.granular` — soft sand, stiff sand
    (Hertz–Mindlin at the given pressure), contact cement (scheme 1, drawn from :math:`\phi_c`
    down to :math:`\phi_c - 0.1`, the small cement amounts where its fits hold) and constant
    cement at :math:`\phi_b = \phi_c - 0.04` — saturated by Gassmann
    (:func:`rockcem.fluids.gassmann`) with the grain as the mineral, with density
    :math:`(1-\phi)\rho_\mathrm{grain} + \phi\rho_\mathrm{fluid}` and velocities by
    :func:`rockcem.elastic.velocities`. Each template line carries ``gid``
    ``"template:<model>"`` (e.g. ``"template:soft_sand"``).

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset with ``porosity`` and the chosen velocity (optionally per ``model``).
    velocity : {"vp", "vs"}
        Velocity to plot, km/s.
    grain, cement : str or Mineral, optional
        Grain and cement (catalogue names for :func:`rockcem.materials.mineral`); default
        ``ds.attrs["grain"]`` and ``ds.attrs["cement"]``.
    fluid : str or Fluid, optional
        Pore fluid; default ``ds.attrs["fluid"]``.
    pressure : float, optional
        Effective pressure of the Hertz–Mindlin contacts, MPa, ``> 0``; default the median of
        ``ds["pressure_effective"]`` if present, else 20.
    coordination_number : float, optional
        Grain contacts per grain; default the scene's Model 4 value
        (``ds.attrs["parameters_json"]``), else 9.
    critical_porosity : float, optional
        :math:`\phi_c`, in (0.04, 1); default ``ds.attrs.get("critical_porosity", 0.36)``.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        One axes: the data as lines with markers (``gid`` ``"model:<label>"``; each model its
        own colour, line style, width and marker, the first widest and lowest, markers of
        different models at different depths, so coinciding models stay visible; one line
        along depth per sweep member, in its own shade, the first on top, with a legend of the
        swept values; broken where the hydrocarbon saturation changes, at a reservoir's top
        and base),
        the templates as dark grey lines.

    Raises
    ------
    ValueError
        For an unknown ``velocity``, missing variables, materials that are neither given nor in
        ``ds.attrs``, parameters out of range, or more than
        :data:`~rockcem.plots.MAX_MEMBERS` sweep members (the message names the dimension to
        select values of); a Dataset of quantiles of uncertain members (dimension
        ``quantile``: a point of two variables' quantiles is no member's; the message names
        :func:`~rockcem.plots.depth_bands` and how to select one quantile).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> depth = np.linspace(500.0, 3000.0, 11)
    >>> ds = build_dataset({"porosity": (("depth",), 0.34 - 8e-5 * depth),
    ...                     "vp": (("depth",), 1.8 + 1e-3 * depth)},
    ...                    {"depth": (("depth",), depth)},
    ...                    {"grain": "quartz", "cement": "quartz_cement", "fluid": "water"})
    >>> fig = velocity_porosity(ds)
    >>> sorted(ln.get_gid() for ln in fig.axes[0].lines if ln.get_gid().startswith("template"))[:2]
    ['template:constant_cement', 'template:contact_cement']
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    _check_dataset(ds)
    if "quantile" in ds.dims:
        raise ValueError(_QUANTILE_REFUSAL.format(
            what="velocity_porosity",
            instead="each variable's quantile band along depth with depth_bands "
                    "(rockcem plot --kind band)"))
    ds, held = _held(ds)
    if velocity not in ("vp", "vs"):
        close = difflib.get_close_matches(str(velocity), ["vp", "vs"], n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise ValueError(f"velocity must be 'vp' or 'vs'; got {velocity!r}{hint}")
    v = _require(ds, velocity, "velocity_porosity")
    phi = _require(ds, "porosity", "velocity_porosity")
    grain = _material(grain, "Mineral", ds, "grain")
    cement = _material(cement, "Mineral", ds, "cement")
    fluid = _material(fluid, "Fluid", ds, "fluid")
    if pressure is None:
        pe = ds["pressure_effective"].values if "pressure_effective" in ds.data_vars else []
        pe = np.asarray(pe, dtype=float)[np.isfinite(pe)]
        pressure = float(np.median(pe)) if pe.size else 20.0
    pressure = float(pressure)
    if not (np.isfinite(pressure) and pressure > 0.0):
        raise ValueError(f"pressure must be > 0 MPa; got {pressure:g}")
    phic = float(ds.attrs.get("critical_porosity", 0.36) if critical_porosity is None
                 else critical_porosity)
    if not 0.04 < phic < 1.0:
        raise ValueError(f"critical_porosity must lie in (0.04, 1); got {phic:g}")
    if coordination_number is None:
        coordination_number = _scene_knobs(ds).get("coordination_number", 9.0)
    templates = _contact_templates(grain, cement, fluid, pressure, float(coordination_number),
                                   phic)

    import matplotlib.pyplot as plt
    import xarray as xr
    from matplotlib.lines import Line2D

    phi, v = xr.broadcast(phi, v)
    dims, members = _members(ds, [phi, v], "velocity_porosity", "one shade of each model's colour")
    saturation = ds["hydrocarbon_saturation"] if "hydrocarbon_saturation" in ds.data_vars \
        else xr.zeros_like(ds["depth"], dtype=float)
    models = list(ds["model"].values) if "model" in v.dims else [None]
    # About 20 markers a line, each model's from another start (distinct when they coincide).
    step = max(len(models), (phi.sizes["depth"] + 1) // 20)
    with plt.rc_context(_RC):
        fig = _figure(fig, (6.8, 4.0 + (0.5 if len(members) > 1 else 0.0)))
        ax = fig.add_subplot()
        handles = []
        for i, model in enumerate(models):
            style = (_model_style(model, i, len(models)) if model is not None else
                     {"color": _INK, "linestyle": "-", "linewidth": 1.2, "marker": "o",
                      "zorder": 2.0})
            label = _model_label(model) if model is not None else "data"
            for j, (isel, text) in enumerate(members):
                sel = dict(isel, **({"model": i} if model is not None else {}))
                # Markers of the models fall on different depths (offset starts), so that
                # models whose points coincide keep their markers visible; the first member
                # (a hydrocarbon sweep's brine) on top where members coincide.
                x, y = _broken(phi.isel(sel).values, v.isel(sel).values,
                               saturation.isel({k: n for k, n in sel.items()
                                                if k in saturation.dims}).values)
                ax.plot(x, y, **{**style, "color": _shade(style["color"], j, len(members)),
                                 "zorder": style["zorder"] + 0.005 * (len(members) - 1 - j)
                                 / len(members)},
                        markersize=4.0 * _model_size(i, len(models)), markeredgewidth=0.4,
                        markeredgecolor="white",
                        markevery=(i * step // len(models), step),
                        label=f"{label}, {text}" if text else label,
                        gid=f"model:{model}" if model is not None else "data")
            handles.append(Line2D([], [], **style, markersize=4.0 * _model_size(i, len(models)),
                                  markeredgewidth=0.4, markeredgecolor="white", label=label))
        styles = {"soft_sand": "--", "stiff_sand": "-", "contact_cement": "-.",
                  "constant_cement": ":"}
        for key, (label, porosity, vel) in templates.items():
            ax.plot(porosity, getattr(vel, velocity), color=_INK, linestyle=styles[key],
                    linewidth=1.1, label=label, gid=f"template:{key}", zorder=1.5)
        ax.set_xlabel(_label("porosity"))
        ax.set_ylabel(_label(velocity))
        ax.set_xlim(-0.01, phic + 0.02)
        # Contact cement at vanishing cement drops far below Hertz-Mindlin (the C terms of the
        # fits); let it run off the axes rather than squash the data.
        finite = v.values[np.isfinite(v.values)]
        low = float(getattr(templates["soft_sand"][2], velocity)[-1])
        ax.set_ylim(bottom=0.9 * min(low, finite.min()) if finite.size else 0.9 * low)
        handles += [ln for ln in ax.get_lines() if str(ln.get_gid()).startswith("template:")]
        fig.legend(handles=handles, loc="outside right upper", title=(
            f"{_shown(grain, 'grain')} grains, {_shown(cement, 'cement')},\n"
            f"{_shown(fluid, 'fluid')}; $p_e$ = {pressure:.3g} MPa,\n"
            f"$n$ = {coordination_number:g}, $\\phi_c$ = {phic:g}"),
            title_fontsize=7.5, alignment="left")
        _sweep_legend(fig, dims, members, ds, held)
    return fig


# ----------------------------------------------------------------------------- RPT
#: The template's default iso-cement lines (cement volume fractions); then the data's largest.
_CEMENT_LINES = (0.0, 0.02, 0.05, 0.1, 0.2)
_TEMPLATE_DEFAULTS = {"grain": "quartz", "cement": "quartz_cement", "fluid": "water",
                      "critical_porosity": 0.36}


def rock_physics_template(ds=None, *, grain=None, cement=None, fluid=None,
                          critical_porosity=None, pressure=None, porosity=None,
                          cement_fraction=None,
                          coordination_number=None, delta=None, fig=None):
    r"""Rock-physics template: acoustic impedance against Vp/Vs from the patchy-cement model.

    Lines of constant porosity and of constant cement fraction from
    :func:`rockcem.models.patchy_cement_model` (Model 4) on the grid ``porosity`` x
    ``cement_fraction``; combinations with :math:`\phi + \phi_p > \phi_c` are left out.
    Impedance :math:`\rho V_P` (km/s·g/cm³) is on the horizontal axis and :math:`V_P/V_S` on the
    vertical one, as in the templates of Ødegaard and Avseth. With ``ds`` the Dataset's points
    are drawn over it, one marker shape and size per model (the first largest and lowest, so
    coinciding models nest), coloured by depth; a swept Dataset gets one panel per sweep
    member (at most :data:`~rockcem.plots.MAX_MEMBERS`), titled with its swept values (a
    hydrocarbon in words: "CO₂ in brine, saturation 0.8 at 2000-2500 m"). The axes span the
    template and the models run along the whole profile; a point of a model run at a few
    depths (MD) beyond them is drawn at the edge as a triangle pointing out, with its value
    (``gid`` ``"beyond:<model>"``), so that one poorly resolved point (Vp/Vs 3) does not
    squash the template.

    Parameters
    ----------
    ds : xarray.Dataset, optional
        Scene Dataset with ``density``, ``vp`` and ``vs`` (optionally per ``model``). A
        Dataset of another lithology (attribute ``lithology``, e.g. a shale) is refused
        unless ``grain`` and ``cement`` are given: the template is that of a cemented sand.
        A Dataset of quantiles of uncertain members (dimension ``quantile``) is refused with a
        ValueError naming :func:`~rockcem.plots.member_template` (the members' clouds) and how
        to select one quantile.
    grain, cement : str or Mineral, optional
        Grain and cement materials; default those of ``ds.attrs`` (a sandstone scene's),
        else quartz and quartz cement.
    fluid : str or Fluid, optional
        Pore fluid; default ``ds.attrs["fluid"]``, else water.
    critical_porosity : float, optional
        :math:`\phi_c`, in (0, 1); default ``ds.attrs["critical_porosity"]``, else 0.36.
    pressure : float, optional
        Effective pressure, MPa, ``>= 0``; default the median of ``ds["pressure_effective"]``
        if present, else 20.
    porosity : array_like, shape (m,), optional
        Porosities of the iso-porosity lines, in (0, ``critical_porosity``]; default 0.05,
        0.10, … up to ``critical_porosity``.
    cement_fraction : array_like, shape (k,), optional
        Cement fractions of the iso-cement lines, in [0, ``critical_porosity``); default 0,
        0.02, 0.05, 0.1 and 0.2 as far as the data's largest cement fraction goes, and that
        (rounded up; so that the deepest, most cemented points lie within the lines).
    coordination_number : float, optional
        Coordination number of the pack; default the scene's (``ds.attrs["parameters_json"]``,
        section ``models.patchy_cement``), else 9.
    delta : float, optional
        Bonding pre-stress of the uncemented contacts, MPa; default the scene's, else 100 (as
        Model 4 of Carcione et al. 2022); a small value (e.g. 0) spreads the iso-cement lines.
        The scene's other Model 4 parameters (``scheme``, ``thickness``,
        ``contact_cement_limit``, ``f``) are used as well, and a sweep over one of them gets
        each panel's own template.
    fig : matplotlib.figure.Figure, optional
        Empty figure to draw in.

    Returns
    -------
    matplotlib.figure.Figure
        The template axes (iso-porosity lines with ``gid`` ``"porosity=<value>"``, iso-cement
        lines with ``gid`` ``"cement_fraction=<value>"``), one per sweep member, and, with
        ``ds``, the points (``gid`` ``"model:<label>"``) and a depth colour bar.

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> depth = np.linspace(1000.0, 3000.0, 5)
    >>> ds = build_dataset({"density": (("depth",), np.full(5, 2.3)),
    ...                     "vp": (("depth",), np.linspace(3.0, 4.2, 5)),
    ...                     "vs": (("depth",), np.linspace(1.7, 2.5, 5))},
    ...                    {"depth": (("depth",), depth)})
    >>> fig = rock_physics_template(ds)
    >>> fig.axes[0].get_xlabel(), fig.axes[0].get_ylabel()
    ('Acoustic impedance ((km/s)·(g/cm³))', 'Vp/Vs (–)')
    >>> import matplotlib.pyplot as plt; plt.close(fig)
    """
    held = ""
    if ds is not None:
        _check_dataset(ds)
        if "quantile" in ds.dims:
            raise ValueError(_QUANTILE_REFUSAL.format(
                what="rock_physics_template",
                instead="the members' clouds with member_template (a scene run with "
                        "members = true in [uncertain]; rockcem plot --kind template)"))
        ds, held = _held(ds)
    t = _template_setup(ds, grain=grain, cement=cement, fluid=fluid,
                        critical_porosity=critical_porosity, pressure=pressure,
                        porosity=porosity, cement_fraction=cement_fraction,
                        coordination_number=coordination_number, delta=delta)
    if ds is not None:
        data = [_require(ds, n, "rock_physics_template") for n in ("density", "vp", "vs")]
    phi, phip, ok, knobs, grids, grid = (t[k] for k in ("phi", "phip", "ok", "knobs", "grids",
                                                       "grid"))

    import matplotlib.pyplot as plt

    members, dims = [({}, "")], []
    if ds is not None:
        import xarray as xr

        density, vp, vs = xr.broadcast(*data)
        density = _md_density(ds, density)
        dims, members = _members(ds, [density, vp, vs], "rock_physics_template",
                                 "one panel each")
    ncols = 2 if len(members) == 4 else min(len(members), 3)      # 2 x 2, not 3 + 1
    nrows = -(-len(members) // ncols)
    with plt.rc_context(_RC):
        size = (6.2, 5.4) if ds is not None else (5.4, 5.0)
        if len(members) > 1:
            size = (3.3 * ncols + 1.0, 3.2 * nrows + 0.9)
        fig = _figure(fig, size)
        axes = fig.subplots(nrows, ncols, sharex=True, sharey=True, squeeze=False).ravel()
        for ax in axes[len(members):]:
            ax.remove()
        axes = axes[:len(members)]
        for k, ax in enumerate(axes):
            own = _member_knobs(ds, members[k][0], coordination_number, delta)
            _template_lines(ax, *grid({**knobs, **own}), phi, phip, ok,
                            legend=(k == 0) and fig, title=_template_title(t) + (
                                (" (swept: panel titles)" if len(members) > 1
                                 else " (swept: title)") if own else ""))
            if len(members) > 1:
                ax.set_title(members[k][1], fontsize=8.0)
            elif held:                                 # the member a selection holds
                ax.set_title(held, fontsize=8.0)
            if k % ncols == 0:
                ax.set_ylabel(_label("vp_vs"))
            if k >= len(members) - ncols:
                ax.set_xlabel(_label("acoustic_impedance"))
            ax.margins(x=0.06, y=0.08)
        if ds is not None:
            extent = np.array([(np.nanmin(a), np.nanmax(a)) for key in grids
                               for a in grids[key]]).reshape(-1, 2, 2)
            _data_points(fig, axes, ds, density, vp, vs, members,
                         template=(extent[:, 0, 0].min(), extent[:, 0, 1].max(),
                                   extent[:, 1, 0].min(), extent[:, 1, 1].max()))
        if held and len(members) > 1:
            fig.suptitle(held, fontsize=8.0)
    return fig


def _template_title(t) -> str:
    """The legend title of a template from :func:`_template_setup`'s ``t``: its materials,
    pressure, critical porosity and Model 4 parameters."""
    return (f"Model 4 template: {_shown(t['grain'], 'grain')}, "
            f"{_shown(t['cement'], 'cement')},\n{_shown(t['fluid'], 'fluid')}, "
            f"{t['pressure']:.3g} MPa, $\\phi_c$ = {t['phic']:g}, "
            f"$n$ = {t['knobs']['coordination_number']:g}, "
            f"$\\delta$ = {t['knobs']['delta']:g} MPa")


def _template_figure(ds, *, fig=None, **keywords):
    """One panel of the template of :func:`rock_physics_template` for ``ds`` without its data
    points (the members' clouds of :func:`rockcem.plots.member_template` go on it):
    ``(fig, ax)``. ``keywords`` are those of :func:`_template_setup`."""
    t = _template_setup(ds, **keywords)
    fig = _figure(fig, (6.6, 5.6))
    ax = fig.add_subplot()
    _template_lines(ax, *t["grid"](t["knobs"]), t["phi"], t["phip"], t["ok"], legend=fig,
                    title=_template_title(t))
    ax.set_xlabel(_label("acoustic_impedance"))
    ax.set_ylabel(_label("vp_vs"))
    ax.margins(x=0.06, y=0.08)
    return fig, ax


#: Why the single-valued figures refuse a Dataset of quantiles (issue 32).
_QUANTILE_REFUSAL = (
    "{what} draws one value per depth; this Dataset holds quantiles of uncertain members "
    "(dimension 'quantile'), and a point of quantiles of several variables is no member's: "
    "draw {instead}, or select one quantile (ds.sel(quantile=0.5); rockcem plot --select "
    "quantile=0.5)")


def _template_setup(ds, *, grain=None, cement=None, fluid=None, critical_porosity=None,
                    pressure=None, porosity=None, cement_fraction=None,
                    coordination_number=None, delta=None):
    """The template of :func:`rock_physics_template` for ``ds`` (or None): its materials,
    critical porosity, pressure, porosity and cement grids (``phi``, ``phip``, the admissible
    ``ok``), Model 4 parameters (``knobs``) and ``grid(knobs)``, the cached impedance and
    Vp/Vs on the grid (``grids`` holds those computed)."""
    from ..models import patchy_cement_model

    from ..models import patchy_cement_model

    if ds is not None:
        lithology = ds.attrs.get("lithology", "sandstone")
        if lithology != "sandstone" and (grain is None or cement is None):
            raise ValueError(
                f"rock_physics_template draws the patchy-cement (Model 4) template of a "
                f"cemented sand; the Dataset is a {lithology} scene: pass grain= and cement= "
                "to draw a sandstone template under it anyway")
    given = {"grain": grain, "cement": cement, "fluid": fluid,
             "critical_porosity": critical_porosity}
    attrs = dict(ds.attrs) if ds is not None else {}
    scene_fluid = fluid is None and "fluid" in attrs
    for key, value in given.items():           # given, else the scene's, else the default
        if value is None:
            given[key] = attrs.get(key, _TEMPLATE_DEFAULTS[key])
    grain = _material(given["grain"], "Mineral", None, "grain")
    cement = _material(given["cement"], "Mineral", None, "cement")
    fluid = _material(None, "Fluid", ds, "fluid") if scene_fluid else \
        _material(given["fluid"], "Fluid", None, "fluid")
    phic = float(given["critical_porosity"])
    if not 0.0 < phic < 1.0:
        raise ValueError(f"critical_porosity must lie in (0, 1); got {phic:g}")
    if porosity is None:
        porosity = np.arange(1, int(phic / 0.05 + 1e-9) + 1) * 0.05
    if pressure is None:
        pe = ds["pressure_effective"].values if ds is not None and \
            "pressure_effective" in ds.data_vars else []
        pe = np.asarray(pe, dtype=float)[np.isfinite(pe)]
        pressure = float(np.median(pe)) if pe.size else 20.0
    if not (np.isfinite(float(pressure)) and float(pressure) >= 0.0):
        raise ValueError(f"pressure must be >= 0 MPa; got {pressure!r}")
    if cement_fraction is None:
        cmax = ds["cement_fraction"].values if ds is not None and \
            "cement_fraction" in ds.data_vars else []
        cmax = np.asarray(cmax, dtype=float)[np.isfinite(cmax)]
        top = float(cmax.max()) if cmax.size else 0.0
        # A line needs a porosity of the grid beside it: cement + porosity <= phic.
        cap = phic - float(np.min(porosity))
        last = min(np.ceil(top * 100.0) / 100.0, np.floor(cap * 100.0) / 100.0)
        # Few lines, spaced as the cement's effect (fast at first): the iso-cement lines of a
        # bonded pack crowd together (delta = 100 MPa: within Vp/Vs 1.55-1.7).
        cement_fraction = [c for c in _CEMENT_LINES if c <= 0.05 or c < last - 0.02]
        if cement_fraction[-1] < last - 0.02:          # the data's own, rounded up
            cement_fraction.append(float(last))
    phi = np.atleast_1d(np.asarray(porosity, dtype=float))
    phip = np.atleast_1d(np.asarray(cement_fraction, dtype=float))
    if phi.ndim != 1 or np.any(~np.isfinite(phi)) or np.any((phi <= 0.0) | (phi > phic)):
        raise ValueError(f"porosity must be a 1-D array of values in (0, {phic:g}]")
    if phip.ndim != 1 or np.any(~np.isfinite(phip)) or np.any((phip < 0.0) | (phip >= phic)):
        raise ValueError(f"cement_fraction must be a 1-D array of values in [0, {phic:g})")
    P, C = np.meshgrid(phi, phip, indexing="ij")
    ok = P + C <= phic * (1.0 + 1e-12)
    if not ok.any():
        raise ValueError("no porosity + cement_fraction combination is within critical_porosity")
    knobs = _scene_knobs(ds)
    knobs.update({k: float(v) for k, v in (("coordination_number", coordination_number),
                                           ("delta", delta)) if v is not None})
    knobs.setdefault("coordination_number", 9.0)
    knobs.setdefault("delta", 100.0)
    grids = {}

    def grid(member_knobs):
        """Impedance and Vp/Vs of the template with these Model 4 parameters (cached)."""
        key = tuple(sorted(member_knobs.items()))
        if key not in grids:
            rock = patchy_cement_model(grain, cement, P[ok], C[ok], pressure, fluid,
                                       critical_porosity=phic, **member_knobs)
            impedance, ratio = np.full(P.shape, np.nan), np.full(P.shape, np.nan)
            impedance[ok] = rock.density * rock.vp
            ratio[ok] = rock.vp / rock.vs
            grids[key] = impedance, ratio
        return grids[key]
    return {"grain": grain, "cement": cement, "fluid": fluid, "phic": phic,
            "pressure": float(pressure), "phi": phi, "phip": phip, "ok": ok, "knobs": knobs,
            "grids": grids, "grid": grid}


#: Model 4 parameters of a scene that the template takes (keywords of patchy_cement_model).
_MODEL4_KNOBS = ("coordination_number", "contact_cement_limit", "delta", "scheme", "thickness",
                 "f")


def _scene_knobs(ds) -> dict:
    """The scene's Model 4 parameters from ``ds.attrs["parameters_json"]`` (empty if none)."""
    import json

    text = ds.attrs.get("parameters_json") if ds is not None else None
    if not text:
        return {}
    section = json.loads(text).get("models.patchy_cement") or {}
    return {k: section[k] for k in _MODEL4_KNOBS if section.get(k) is not None}


def _member_knobs(ds, isel, coordination_number, delta) -> dict:
    """Model 4 parameters swept in ``ds`` (attribute ``sweep``) at one member (or at the value
    a selection left as a scalar coordinate), except those given explicitly."""
    import json

    if ds is None or not ds.attrs.get("sweep"):
        return {}
    given = {"coordination_number": coordination_number, "delta": delta}
    own = {}
    for dotted in json.loads(ds.attrs["sweep"]):
        section, _, key = dotted.rpartition(".")
        if section != "models.patchy_cement" or key not in _MODEL4_KNOBS \
                or given.get(key) is not None:
            continue
        if key in isel:
            value = ds[key].values[isel[key]].item()
        elif key in ds.coords and ds[key].ndim == 0:          # one member selected
            value = ds[key].values.item()
        else:
            continue
        own[key] = int(value) if key == "scheme" else float(value)
    return own


def _template_lines(ax, impedance, ratio, phi, phip, ok, *, legend, title):
    """Iso-porosity (dark) and iso-cement (dashed, shades of brown) lines of the template."""
    import matplotlib.pyplot as plt
    from matplotlib import patheffects
    from matplotlib.lines import Line2D

    cmap = plt.get_cmap("YlOrBr")
    cement_colour = [cmap(0.45 + 0.5 * j / max(len(phip) - 1, 1)) for j in range(len(phip))]
    halo = [patheffects.withStroke(linewidth=2.0, foreground="white")]
    template = [Line2D([], [], color=_INK, linewidth=1.0, label="constant porosity $\\phi$")]
    drawn = [j for j in range(len(phip)) if ok[:, j].any()]
    # Past six lines, the middle ones share one legend entry (a sandstone's lines run on to its
    # largest cement fraction in steps of 0.04).
    middle = drawn[5:-1] if len(drawn) > 6 else []
    for j in drawn:
        c = phip[j]
        ax.plot(impedance[:, j], ratio[:, j], color=cement_colour[j], linewidth=1.2,
                linestyle="--", marker="." if ok[:, j].sum() == 1 else "",
                gid=f"cement_fraction={c:g}", zorder=3)
        if j in middle and j != middle[0]:
            continue
        text = (f"cement fraction $\\phi_p$ = {phip[middle[0]]:g} … {phip[middle[-1]]:g}"
                if middle and j == middle[0] else f"cement fraction $\\phi_p$ = {c:g}")
        template.append(Line2D([], [], color=cement_colour[j], linewidth=1.2, linestyle="--",
                               label=text))
    leftmost = np.nanargmax(phi * ok.any(axis=1))
    for i, p in enumerate(phi):
        if ok[i].any():
            ax.plot(impedance[i], ratio[i], color=_INK, linewidth=1.0,
                    marker="." if ok[i].sum() == 1 else "", gid=f"porosity={p:g}", zorder=3.5)
            # at the most-cemented end, below the line: the least-cemented end is where the
            # data of an uncemented or lightly cemented sand lie
            j = np.flatnonzero(ok[i])[np.argmax(phip[ok[i]])]
            ax.annotate(f"$\\phi$ = {p:g}" if i == leftmost else f"{p:g}",
                        (impedance[i, j], ratio[i, j]), xytext=(0, -4),
                        textcoords="offset points", ha="center", va="top", fontsize=7,
                        color=_INK, path_effects=halo, zorder=4)
    if legend:                      # below the panels, where it covers no line or point
        legend.legend(handles=template, loc="outside lower center", ncols=3,
                      title_fontsize=7.5, title=title.replace("\n", " "))


def _md_density(ds, density):
    """``density`` (broadcast over ``model``) with the MD members' own ``md_density``: the MD
    sample is more porous than burial's rock, so burial's ``density`` overstates its
    impedance (by 1.6–4.5 % in the shipped example)."""
    if "model" not in density.dims or "md_density" not in ds.data_vars:
        return density
    import xarray as xr

    is_md = xr.DataArray([str(m).startswith("md") for m in ds["model"].values],
                         dims="model", coords={"model": ds["model"]})
    md = ds["md_density"].broadcast_like(density)
    return xr.where(is_md & md.notnull(), md, density).transpose(*density.dims)


def _md_errors(ds, density, vp, vs):
    """Errors of the template's axes at the MD points, and their flag:
    ``(sigma_impedance, sigma_ratio, trusted)`` broadcast like ``vp`` (NaN off the MD depths
    and for the other models), or None where the Dataset has no MD errors.

    First-order propagation of the velocity errors of
    :func:`rockcem.variables.md_error_trusted`: impedance :math:`I = \\rho V_P` with the MD
    sample's density taken as exact, :math:`\\sigma_I = \\rho\\,\\sigma_{V_P}`;
    :math:`r = V_P/V_S`, :math:`\\sigma_r = r\\sqrt{(\\sigma_{V_P}/V_P)^2 +
    (\\sigma_{V_S}/V_S)^2}`, the two errors added as independent (they come from the same
    lattices and move together, which would shrink the ratio's error: the bar is the larger,
    cautious one)."""
    if "model" not in vp.dims or not any(f"vp_error{k}" in ds.data_vars
                                         for k in ("", "_resolution", "_sample")):
        return None
    import xarray as xr

    from ..variables import md_error_trusted

    error_p, trusted = md_error_trusted(ds, "vp")
    error_s, _ = md_error_trusted(ds, "vs")
    error_p, error_s, trusted = (a.broadcast_like(vp).transpose(*vp.dims)
                                 for a in (error_p, error_s, trusted))
    sigma_i = density * error_p
    ratio = vp / vs
    sigma_r = ratio * np.sqrt((error_p / vp) ** 2 + (error_s / vs) ** 2)
    return xr.broadcast(sigma_i, sigma_r, trusted)


def _data_points(fig, axes, ds, density, vp, vs, members, template):
    """The Dataset's points on each panel (one sweep member a panel): a marker and size per
    model (the first largest and lowest, so coinciding points nest), colour by depth, one
    depth colour bar for all panels. The axes span ``template`` (impedance and Vp/Vs ranges,
    ``(x0, x1, y0, y1)``) and the points of the models run along the profile; MD points carry
    error bars (:func:`_md_errors`; the lower bar stops at zero), filled where trusted and
    hollow where not, and an MD point beyond the axes is drawn at the edge
    (:func:`_beyond`). The bars of untrusted points are dashed and drawn after the axis
    limits are fixed, so that a bar as large as its value leaves the template's scale alone."""
    import matplotlib.pyplot as plt
    import xarray as xr
    from matplotlib.lines import Line2D

    depth = xr.broadcast(ds["depth"], vp)[0]
    models = list(ds["model"].values) if "model" in vp.dims else [None]
    norm = plt.Normalize(float(ds["depth"].min()), float(ds["depth"].max()))
    cmap = plt.get_cmap("viridis_r")
    errors = _md_errors(ds, density, vp, vs)
    few_depths = [errors is not None and str(m).startswith("md") for m in models]
    later = []
    handles = {}
    x0, x1, y0, y1 = template
    for ax, (isel, _text) in zip(axes, members):   # the profiles' models: they set the axes
        for i, model in enumerate(models):
            if few_depths[i]:
                continue
            sel = dict(isel, **({"model": i} if model is not None else {}))
            d, p, s = (a.isel(sel).values.ravel() for a in (density, vp, vs))
            good = (s > 0.0) & np.isfinite(d * p / s)
            marker = _model_marker(model, i)
            grow = _model_size(i, len(models))
            label = _model_label(model) if model is not None else "data"
            few = good.sum() <= 300                    # edges only where they stay visible
            x, y = (d * p)[good], p[good] / s[good]
            if x.size:
                x0, x1, y0, y1 = min(x0, x.min()), max(x1, x.max()), min(y0, y.min()), \
                    max(y1, y.max())
            z = depth.isel(sel).values.ravel()[good]
            ax.scatter(x, y, c=z, cmap="viridis_r", norm=norm, marker=marker,
                       s=(14 if few else 6) * grow, linewidths=0.3 if few else 0.0,
                       edgecolors="0.25", zorder=2 + 0.01 * i, alpha=0.85, label=label,
                       gid=f"model:{model}" if model is not None else "data")
            if not few:                                # every k-th point marked, ~25 a model
                k = slice(i * (-(-x.size // 25)) // len(models), None, -(-x.size // 25))
                ax.scatter(x[k], y[k], c=z[k], cmap="viridis_r", norm=norm, marker=marker,
                           s=18 * grow, linewidths=0.4, edgecolors="0.2", zorder=2.2 + 0.01 * i,
                           gid=f"model:{model}" if model is not None else "data")
            handles[i] = Line2D([], [], linestyle="none", marker=marker,
                                markersize=4.5 * np.sqrt(grow), markerfacecolor="0.8",
                                markeredgecolor="0.25", label=label)
    pad_x, pad_y = 0.06 * (x1 - x0), 0.08 * (y1 - y0)
    limits = (x0 - pad_x, x1 + pad_x), (y0 - pad_y, y1 + pad_y)
    for ax in axes:
        ax.set_xlim(*limits[0])
        ax.set_ylim(*limits[1])
        ax.set_autoscale_on(False)
    beyond = 0
    for ax, (isel, _text) in zip(axes, members):   # the MD points, at a few depths
        for i, model in enumerate(models):
            if not few_depths[i]:
                continue
            sel = dict(isel, **({"model": i} if model is not None else {}))
            d, p, s = (a.isel(sel).values.ravel() for a in (density, vp, vs))
            good = s > 0.0
            marker = _model_marker(model, i)
            grow = _model_size(i, len(models))
            sig_i, sig_r, flag = (a.isel(sel).values.ravel()[good] for a in errors)
            z = depth.isel(sel).values.ravel()[good]
            x, y = (d * p)[good], p[good] / s[good]
            out = _beyond(ax, x, y, cmap(norm(z)), limits, gid=f"beyond:{model}")
            beyond += int(out.sum())
            later.extend(_md_points(ax, x[~out], y[~out], sig_i[~out], sig_r[~out],
                                    flag[~out] == 1.0, cmap(norm(z[~out])), marker=marker,
                                    size=14 * grow, zorder=2 + 0.01 * i, gid=f"model:{model}"))
            handles[i] = Line2D([], [], linestyle="none", marker=marker,
                                markersize=4.5 * np.sqrt(grow), markerfacecolor="0.8",
                                markeredgecolor="0.25", label=_model_label(model))
    for draw in later:
        draw()
    handles = [handles[i] for i in sorted(handles)]
    if any(few_depths):
        flag = "md_trusted = 0" if "md_trusted" in ds.data_vars else \
            "md_resolution_asymptotic = 0 or error ≥ value"
        handles += [Line2D([], [], linestyle="none", marker="o", markerfacecolor="0.6",
                           markeredgecolor="0.25", label="MD trusted (filled; bars: total error)"),
                    Line2D([], [], linestyle="none", marker="o", markerfacecolor="white",
                           markeredgecolor="0.25",
                           label=f"MD not trusted (hollow, dashed bars;\n{flag})")]
        if beyond:
            handles.append(Line2D([], [], linestyle="none", marker="^", markerfacecolor="white",
                                  markeredgecolor="0.25",
                                  label="MD point beyond the axes\n(at the edge, with its value)"))
    fig.legend(handles=handles, loc="outside upper center", ncols=2 if len(axes) == 1 else 4)
    points = plt.cm.ScalarMappable(norm=norm, cmap=cmap)
    bar = fig.colorbar(points, ax=list(axes), pad=0.02, shrink=1.0 if len(axes) == 1 else 0.8)
    bar.set_label(_label("depth"))
    bar.ax.invert_yaxis()                              # depth increases downward


def _beyond(ax, x, y, colours, limits, *, gid):
    """Points outside ``limits`` (``(x0, x1), (y0, y1)``) drawn at the edge they cross as a
    hollow triangle pointing out, labelled with the coordinate that is off the axes
    (``"Vp/Vs 3.1"``, ``"AI 18.2"``); returns which points those are."""
    (a, b), (c, d) = limits
    out = (x < a) | (x > b) | (y < c) | (y > d)
    for k in np.flatnonzero(out):
        px, py = np.clip(x[k], a, b), np.clip(y[k], c, d)
        marker = "^" if y[k] > d else "v" if y[k] < c else ">" if x[k] > b else "<"
        text = f"Vp/Vs {y[k]:.2f}" if not c <= y[k] <= d else f"AI {x[k]:.1f}"
        ax.plot([px], [py], linestyle="none", marker=marker, markersize=6.0,
                markerfacecolor="white", markeredgecolor=colours[k], markeredgewidth=1.3,
                clip_on=False, zorder=5, gid=gid)
        ax.annotate(text, (px, py), xytext=(0, -9 if y[k] > d else 4), textcoords="offset points",
                    ha="center", va="top" if y[k] > d else "bottom", fontsize=6.5,
                    color="0.25", zorder=5, annotation_clip=False)
    return out


def _md_points(ax, x, y, sigma_x, sigma_y, trusted, colours, *, marker, size, zorder, gid):
    """MD points of the template with error bars in their depth colours: trusted ones filled,
    their bars drawn now; untrusted ones hollow, their dashed bars returned as a drawing to be
    called once the axis limits are fixed. Lower bars stop at zero."""
    def bars(sigma, value):
        sigma = np.where(np.isfinite(sigma), sigma, 0.0)
        return np.stack([np.minimum(sigma, np.abs(value)), sigma])

    ex, ey = bars(sigma_x, x), bars(sigma_y, y)

    def draw_bars(keep, dashed):
        for k in np.flatnonzero(keep):
            drawn = ax.errorbar(x[k], y[k], xerr=ex[:, k:k + 1], yerr=ey[:, k:k + 1],
                                fmt="none", ecolor=colours[k], elinewidth=0.8, capsize=1.5,
                                zorder=zorder - 0.005, alpha=0.45 if dashed else 0.9)
            for line in drawn.lines[2]:
                line.set_gid(f"errorbar:{gid[6:]}")
                if dashed:
                    line.set_linestyle((0, (2.5, 1.5)))

    draw_bars(trusted, dashed=False)
    ax.scatter(x[trusted], y[trusted], c=colours[trusted], marker=marker, s=size,
               linewidths=0.3, edgecolors="0.25", zorder=zorder, gid=gid)
    ax.scatter(x[~trusted], y[~trusted], facecolors="white", edgecolors=colours[~trusted],
               marker=marker, s=size, linewidths=1.1, zorder=zorder, gid=gid + ":untrusted")
    return [lambda: draw_bars(~trusted, dashed=True)]


# ----------------------------------------------------------------------------- saving
