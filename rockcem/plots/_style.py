"""Shared style of the rockcem figures: labels with units, model colours, figure set-up."""

from __future__ import annotations

import difflib
import re
import textwrap

import numpy as np

from ..variables import variable_attrs


#: Legend label of each petro-elastic model, by its label in the ``model`` coordinate.
MODEL_LABELS = {
    "hs_gassmann": "Model 1 (HS–Krief–Gassmann)",
    "self_consistent": "Model 2 (self-consistent)",
    "generalized_gassmann": "Model 3 (generalized Gassmann)",
    "patchy_cement": "Model 4 (patchy cement)",
}
_MODEL_COLOURS = {"hs_gassmann": "#0072B2", "self_consistent": "#D55E00",
                  "generalized_gassmann": "#009E73", "patchy_cement": "#CC79A7"}
_EXTRA_COLOURS = ("#E69F00", "#56B4E9", "#F0E442", "#000000")
_MODEL_MARKERS = {"hs_gassmann": "o", "self_consistent": "s", "generalized_gassmann": "^",
                  "patchy_cement": "D"}
_EXTRA_MARKERS = ("v", "P", "X", "*")
_INK = "#262626"                      # model-independent lines and template lines
_LINESTYLES = ("-", "--", "-.", ":", (0, (5, 1.5, 1, 1.5, 1, 1.5)), (0, (1, 1)))
#: Line style of each model: with the widths of :func:`_model_width` (widest drawn first) two
#: models whose curves coincide (Models 1 and 3 nearly do) both stay visible.
_MODEL_LINESTYLES = {"hs_gassmann": "-", "self_consistent": (0, (6, 2)),
                     "generalized_gassmann": (0, (2.5, 1.5)),
                     "patchy_cement": (0, (6, 2.5, 1.5, 2.5))}
#: The most sweep members a figure draws (by shade, or one panel each); past it the figure
#: refuses and names the dimension to select a member of.
MAX_MEMBERS = 6
_DEFAULT_TRENDS = ("porosity", "cement_fraction", "illite_fraction", "density", "vp", "vs")
_SUFFIX_FORMATS = {".png": "png", ".pdf": "pdf", ".svg": "svg"}

#: Derived quantities that are not variables of a scene Dataset.
_DERIVED = {
    "acoustic_impedance": {"units": "km s-1 g cm-3", "long_name": "acoustic impedance"},
    "vp_vs": {"units": "1", "long_name": "Vp/Vs"},
}

_RC = {
    "font.size": 9.0, "axes.labelsize": 9.0, "axes.titlesize": 9.0, "legend.fontsize": 8.0,
    "xtick.labelsize": 8.0, "ytick.labelsize": 8.0, "axes.linewidth": 0.8,
    "xtick.direction": "in", "ytick.direction": "in", "xtick.top": True, "ytick.right": True,
    "lines.linewidth": 1.4, "legend.frameon": False, "savefig.dpi": 150,
    "axes.grid": True, "grid.color": "0.88", "grid.linewidth": 0.6, "axes.axisbelow": True,
}

_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")
_UNIT_NAMES = {"degree_Celsius": "°C", "degC": "°C", "celsius": "°C", "K": "K"}


# ----------------------------------------------------------------------------- labels
def _units_text(units: str) -> str:
    """UDUNITS string -> readable text: ``km s-1`` -> ``km/s``, ``1`` -> ``–``."""
    units = str(units).strip()
    if units in ("", "1"):
        return "–"
    factors = []
    for token in units.split():
        m = re.fullmatch(r"([^\d\-+^]+)\^?([-+]?\d+)?", token)
        if m is None:                       # not a plain product of powers: show it as it is
            return units
        factors.append((_UNIT_NAMES.get(m[1], m[1]), int(m[2] or 1)))
    groups = []                             # a positive factor with the negative ones after it
    for name, power in factors:
        if power > 0 or not groups:
            groups.append(([], []))
        groups[-1][0 if power > 0 else 1].append((name, abs(power)))

    def power_text(name, p):
        return name + (str(p).translate(_SUPERSCRIPT) if p != 1 else "")

    texts = []
    for num, den in groups:
        top = " ".join(power_text(*f) for f in num) or "1"
        if len(den) == 1:
            texts.append(f"{top}/{power_text(*den[0])}")
        elif den:
            texts.append(top + " " + " ".join(n + f"-{p}".translate(_SUPERSCRIPT) for n, p in den))
        else:
            texts.append(top)
    if len(texts) > 1:
        return "·".join(f"({t})" if "/" in t else t for t in texts)
    return texts[0]


def _attrs(name: str, ds=None) -> dict:
    """Attributes of ``name``: the registry first, then derived quantities, then the Dataset."""
    try:
        return variable_attrs(name)
    except ValueError:
        if name in _DERIVED:
            return dict(_DERIVED[name])
        if ds is not None and name in ds.variables:
            return dict(ds[name].attrs)
        return {}


def _label(name: str, ds=None, *, width: int | None = None) -> str:
    """Axis label "Quantity (unit)" of a variable, wrapped to ``width`` characters."""
    attrs = _attrs(name, ds)
    quantity = re.sub(r"\s*\([^)]*\)", "", str(attrs.get("long_name", name.replace("_", " "))))
    label = f"{_capital(quantity)} ({_units_text(attrs.get('units', '1'))})"
    return textwrap.fill(label, width) if width else label


def _model_label(model) -> str:
    model = str(model)
    if model == "md":
        return "MD grain pack"
    if model.startswith("md_"):                 # one member per cement scheme
        return f"MD grain pack, {model[3:].replace('_', ' ')} cement"
    return MODEL_LABELS.get(model, model)


def _model_colour(model, index: int) -> str:
    return _MODEL_COLOURS.get(str(model), _EXTRA_COLOURS[index % len(_EXTRA_COLOURS)])


def _model_marker(model, index: int) -> str:
    return _MODEL_MARKERS.get(str(model), _EXTRA_MARKERS[index % len(_EXTRA_MARKERS)])


def _shade(colour, index: int, count: int):
    """``colour`` for the ``index``-th of ``count`` sweep values: from 35 % darker (towards
    black) to 50 % lighter (towards white), so that even two members of a light colour (the
    pink of Model 4) stand apart; a near-black colour (the dark grey of model-independent
    lines), which cannot darken, from itself to 70 % lighter. ``colour`` itself for a single
    value."""
    from matplotlib.colors import to_rgb

    rgb = to_rgb(colour)
    if count < 2:
        return rgb
    dark, light = (-0.35, 0.5) if max(rgb) > 0.2 else (0.0, 0.7)
    t = dark + (light - dark) * index / (count - 1)
    return tuple(c * (1.0 + t) if t < 0 else c + (1.0 - c) * t for c in rgb)


def _model_linestyle(model, index: int):
    return _MODEL_LINESTYLES.get(str(model), _LINESTYLES[index % len(_LINESTYLES)])


def _model_style(model, index: int, count: int) -> dict:
    """Colour, line style, width, marker and z-order of the ``index``-th of ``count`` models:
    the first drawn widest and lowest, so that later, thinner, differently dashed lines over it
    leave it visible where two models coincide."""
    from matplotlib import patheffects

    style = {"color": _model_colour(model, index), "linestyle": _model_linestyle(model, index),
             "linewidth": _model_width(index, count), "marker": _model_marker(model, index),
             "zorder": 2.0 + 0.01 * index}
    if index > 0:       # a thin white edge, half the width step: set off from the line below
        edge = style["linewidth"] + 1.0 / (count - 1)
        style["path_effects"] = [patheffects.withStroke(linewidth=edge, foreground="white")]
    return style


def _model_size(index: int, count: int) -> float:
    """Marker-size factor of the ``index``-th of ``count`` models: the first drawn largest, so
    that points of coinciding models nest instead of hiding one another."""
    return 1.0 + 1.2 * (count - 1 - index) / (count - 1) if count > 1 else 1.0


def _model_width(index: int, count: int) -> float:
    """Line width of the ``index``-th of ``count`` models: wider first, so that models that
    coincide (Models 1 and 3 nearly do) stay visible under one another."""
    return 1.0 + 2.0 * (count - 1 - index) / (count - 1) if count > 1 else 1.4


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


#: Sweep values of ``fluid.hydrocarbon`` as a reader names them.
_HYDROCARBONS = {"none": "brine only (no hydrocarbon)", "gas": "gas", "oil": "oil",
                 "co2": "CO₂", "methane": "methane"}


def _sweep_text(dim: str, value, ds) -> str:
    """Legend text of one sweep value: the value and its unit (``25 °C/km``); a hydrocarbon
    in words, with its saturation and interval where the Dataset's ``pore_fluid`` says them
    (``"CO₂ in brine, saturation 0.8 at 2000-2500 m"``)."""
    if dim == "hydrocarbon":
        import re

        name = _HYDROCARBONS.get(str(value), str(value))
        if str(value) == "none":
            return name
        where = re.search(rf"\b{re.escape(str(value))} at saturation ([^ ]+) \(([^)]*)\)",
                          str(ds.attrs.get("pore_fluid", "")))
        return f"{name} in brine" + (f", saturation {where[1]} at {where[2]}" if where else "")
    value = f"{value:g}" if isinstance(value, (int, float, np.number)) else str(value)
    units = _attrs(dim, ds).get("units")
    return f"{value} {_units_text(units)}" if units not in (None, "", "1") else value


def _members(ds, arrays, purpose: str, how: str):
    """Sweep members of ``arrays``: ``(dims, [(isel, label), ...])`` over the product of their
    dimensions other than ``depth`` and ``model``, in ``ds``'s order.

    Raises a one-line ValueError naming the largest dimension and how to select a member when
    there are more than :data:`MAX_MEMBERS` members."""
    dims = [str(d) for d in ds.dims if d not in ("depth", "model")
            and any(d in a.dims for a in arrays)]
    sizes = [ds.sizes[d] for d in dims]
    count = int(np.prod(sizes)) if dims else 1
    if count > MAX_MEMBERS:
        big = dims[int(np.argmax(sizes))]
        example = ds[big].values[0]
        example = f"{example:g}" if isinstance(example, (int, float, np.number)) else example
        raise ValueError(
            f"{purpose} draws at most {MAX_MEMBERS} sweep members ({how}); this Dataset has "
            f"{count} ({' x '.join(f'{d} {n}' for d, n in zip(dims, sizes))}): select values "
            f"of {big!r} first (ds.sel({big}=...); rockcem plot --select {big}={example})")
    members = []
    for index in np.ndindex(*sizes):
        isel = dict(zip(dims, index))
        label = ", ".join(_member_text(d, ds[d].values[i], ds) for d, i in isel.items())
        members.append((isel, label))
    return dims, members


def _member_text(dim: str, value, ds) -> str:
    """One swept value in a title or label: ``"gradient = 30 °C/km"``; a hydrocarbon by
    :func:`_sweep_text` alone (``"gas in brine, saturation 0.8 at 2000-2500 m"``)."""
    text = _sweep_text(dim, value, ds)
    return text if dim == "hydrocarbon" else f"{dim} = {text}"


def _held(ds):
    """``ds`` with its single-valued sweep dimensions (other than ``depth`` and ``model``) made
    scalar coordinates, and a text naming every scalar coordinate with its value and unit
    (``"Geothermal gradient: 30 °C/km"``; empty if none): what a selection such as
    ``rockcem plot --select gradient=30`` or ``ds.sel(gradient=30)`` holds fixed, so that the
    figure can say which member it shows."""
    single = {d: 0 for d in ds.dims if d not in ("depth", "model") and ds.sizes[d] == 1}
    if single:
        ds = ds.isel(single)
    parts = []
    for name, coord in ds.coords.items():
        if coord.ndim == 0 and name != "depth":
            value = coord.values.item()
            text = _model_label(value) if name == "model" else _sweep_text(name, value, ds)
            long_name = _attrs(str(name), ds).get("long_name", str(name).replace("_", " "))
            parts.append(f"{_capital(str(long_name))}: {text}")
    return ds, "; ".join(parts)


def _sweep_legend(fig, dims, members, ds, held=""):
    """Legend of the sweep members' shades, below the figure; for a single member only the
    text ``held`` (the values a selection holds fixed; nothing if empty)."""
    from matplotlib.lines import Line2D

    if len(members) < 2:
        if not held:
            return None
        return fig.legend(handles=[], loc="outside lower center", title=held)
    return fig.legend(handles=[Line2D([], [], color=_shade(_INK, j, len(members)), linewidth=2.0,
                                      label=text.split(" = ", 1)[-1] if len(dims) == 1
                                      else text)
                               for j, (_, text) in enumerate(members)],
                      loc="outside lower center", ncols=min(len(members), 6),
                      title=_sweep_title(dims, ds) + " (shade)" + (f"; {held}" if held else ""))


def _sweep_title(dims, ds) -> str:
    """Legend title of the sweep: the long names of its dimensions."""
    return ", ".join(_capital(str(_attrs(d, ds).get("long_name", d.replace("_", " "))))
                     for d in dims)


# ----------------------------------------------------------------------------- input checks
def _check_dataset(ds, what="ds"):
    if not (hasattr(ds, "data_vars") and hasattr(ds, "dims")):
        raise ValueError(f"{what} must be an xarray.Dataset; got {type(ds).__name__}")
    if "depth" not in ds.dims:
        dims = ", ".join(map(str, ds.dims)) or "none"
        study = ("; an MD study (dimension saturation) is drawn by md_study_velocity"
                 if "saturation" in ds.dims else "")
        raise ValueError(f"{what} has no 'depth' dimension (dimensions: {dims}); plots need the "
                         f"scene Dataset with depth as a dimension{study}")


def _require(ds, name: str, purpose: str):
    if name not in ds.data_vars:
        choices = list(map(str, ds.data_vars))
        close = difflib.get_close_matches(name, choices, n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise ValueError(f"{purpose} needs the variable {name!r}, which is not in the "
                         f"Dataset{hint} (variables: {', '.join(choices) or 'none'})")
    return ds[name]


def _material(value, kind: str, ds, attr: str):
    from ..materials import Fluid, Mineral, fluid, mineral

    if value is None:
        if ds is None or attr not in ds.attrs:
            raise ValueError(f"{attr} is not given and the Dataset has no attribute {attr!r}; "
                             f"pass {attr}= (a catalogue name or a {kind})")
        value = ds.attrs[attr]
        if attr == "fluid" and value == "brine":
            # A scene's Batzle-Wang brine, which varies with depth: its median over the profile.
            if "brine_bulk_modulus" in ds.attrs:
                return Fluid(float(ds.attrs["brine_bulk_modulus"]),
                             float(ds.attrs["brine_density"]), name="brine (median)")
            # A sweep over the brine: the member shown, from its own fluid variables (brine
            # where no hydrocarbon shares the pores).
            have = all(v in ds.data_vars and ds[v].dims == ("depth",)
                       for v in ("fluid_bulk_modulus", "fluid_density"))
            if not have:
                raise ValueError("the Dataset's brine differs between its sweep members: select "
                                 "one member (--select, ds.sel) or pass fluid= (a catalogue "
                                 "name or a rockcem.materials.Fluid) for the template lines")
            brine = ds["hydrocarbon_saturation"].values == 0.0 \
                if "hydrocarbon_saturation" in ds.data_vars else True
            K = np.asarray(ds["fluid_bulk_modulus"].values)[brine]
            rho = np.asarray(ds["fluid_density"].values)[brine]
            return Fluid(float(np.median(K)), float(np.median(rho)), name="brine (median)")
    if isinstance(value, str):
        return mineral(value) if kind == "Mineral" else fluid(value)
    if isinstance(value, Mineral if kind == "Mineral" else Fluid):
        return value
    raise ValueError(f"{attr} must be a catalogue name or a rockcem.materials.{kind}; "
                     f"got {type(value).__name__}")


def _figure(fig, figsize):
    import matplotlib.pyplot as plt

    if fig is None:
        return plt.figure(figsize=figsize, layout="constrained")
    if fig.axes:
        raise ValueError("fig must be an empty matplotlib Figure (it already has axes)")
    fig.set_layout_engine("constrained")
    return fig


# ----------------------------------------------------------------------------- depth trends


def _panels(ds, variables, extra=()) -> list[str]:
    """The panels' variables: ``variables`` as a list (a string is one), or by default those of
    :data:`_DEFAULT_TRENDS` in ``ds`` followed by ``extra``; a one-line
    ValueError when there are none."""
    if variables is None:
        variables = [v for v in _DEFAULT_TRENDS if v in ds.data_vars] + list(extra)
        if not variables:
            raise ValueError("ds has none of the default variables "
                             f"({', '.join(_DEFAULT_TRENDS)}); pass variables=")
    elif isinstance(variables, str):
        variables = [variables]
    variables = list(variables)
    if not variables:
        raise ValueError("variables must name at least one variable")
    return variables
