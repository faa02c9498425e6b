"""The variable registry (``datasets/variables.toml``): names, units and CF attributes.

Every package builds its ``xarray.Dataset`` through :func:`build_dataset`, so a variable has the
same name, units and ``long_name`` wherever it appears. This module does not import xarray until
a dataset is built.
"""

from __future__ import annotations

import difflib
from collections.abc import Mapping

import numpy as np

from ._data import read_toml

__all__ = ["MODEL_OUTPUTS", "variable_attrs", "variable_names", "build_dataset", "no_coordinate_fill",
           "sweep_dimension", "md_error_trusted"]


#: The variables a petro-elastic model gives (per model); the others are the rock state's.
MODEL_OUTPUTS = ("K_dry", "G_dry", "K_sat", "G_sat", "vp", "vs")


def variable_names() -> list[str]:
    """Names of all registered variables."""
    return list(read_toml("variables.toml"))


def variable_attrs(name: str) -> dict:
    """CF attributes (``units``, ``long_name``, …) of a registered variable.

    Examples
    --------
    >>> variable_attrs("vp")["units"]
    'km s-1'
    """
    table = read_toml("variables.toml")
    if name not in table:
        close = difflib.get_close_matches(name, table, n=1)
        hint = f"; did you mean {close[0]!r}?" if close else ""
        raise ValueError(f"unknown variable {name!r}{hint}")
    return dict(table[name])


def build_dataset(data: Mapping[str, tuple], coords: Mapping[str, tuple], attrs=None):
    """An ``xarray.Dataset`` whose variables and coordinates carry the registry's attributes.

    Parameters
    ----------
    data : mapping
        ``{name: (dims, values)}`` for registered variable names.
    coords : mapping
        ``{name: (dims, values)}`` coordinates (registered names get their attributes too).
    attrs : mapping, optional
        Global attributes (str, int or float values, netCDF-safe).
    """
    import xarray as xr

    def var(name, dims, values):
        values = np.asarray(values)
        if values.dtype == bool:
            values = values.astype(np.int8)   # netCDF has no bool; flags are 0/1
        try:
            meta = variable_attrs(name)
        except ValueError:
            if name in data:
                raise
            meta = {}
        if "flag_values" in meta:
            meta["flag_values"] = np.asarray(meta["flag_values"], dtype=values.dtype)
        return xr.Variable(dims, values, attrs=meta)

    ds = xr.Dataset({k: var(k, *v) for k, v in data.items()},
                    coords={k: var(k, *v) for k, v in coords.items()},
                    attrs=dict(attrs or {}))
    return no_coordinate_fill(ds)


def no_coordinate_fill(ds):
    """Write no ``_FillValue`` for the coordinates of ``ds`` (CF 1.11, sect. 2.5.1: coordinate
    variables have no missing values; xarray would otherwise give every float coordinate a NaN
    fill value). Sets the encoding in place and returns ``ds``."""
    for name in ds.coords:
        ds[name].encoding["_FillValue"] = None
    return ds


#: Dimension names a swept key cannot take (the Dataset's own): such a key is named with its
#: section too (``fluid.model`` sweeps along ``fluid_model``).
_RESERVED_DIMENSIONS = ("depth", "model", "horizon")


def sweep_dimension(dotted: str) -> str:
    """The Dataset dimension of a swept ``"section.key"``: the key (``path.gradient`` ->
    ``gradient``), or ``<section>_<key>`` where the key is a dimension of its own
    (``fluid.model`` -> ``fluid_model``)."""
    section, _, key = dotted.rpartition(".")
    return f"{section.rpartition('.')[2]}_{key}" if key in _RESERVED_DIMENSIONS else key


def md_error_trusted(ds, variable: str = "vp", *, model=None):
    """Total error of an MD member's ``variable`` and whether the member is trusted there.

    The one place that reads a scene Dataset's MD errors and flag (plots, the run summary and
    the example's table all call it). Where the Dataset has them, the runner's total error
    ``<variable>_error`` and flag ``md_trusted`` (1 where the member's total error is within
    its threshold fraction of the value, 0 flagged) are returned as they are. A Dataset written
    before those existed gets the fallback:

    - error: the resolution and sample-size errors (``<variable>_error_resolution``,
      ``<variable>_error_sample``) in quadrature, a part that is missing or NaN left out (NaN
      where both are);
    - trusted: ``md_resolution_asymptotic == 1`` (the resolutions were asymptotic or settled),
      and at every velocity the Dataset has (``vp``, ``vs``) a finite error below the value:
      a member whose error bar reaches zero is not trusted, whatever the resolution flag says.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset with a ``model`` dimension (MD members ``md`` or ``md_<scheme>``).
    variable : str
        ``"vp"`` or ``"vs"`` (any variable with ``<variable>_error...`` companions).
    model : str, optional
        One member; default all members (NaN for those that are not MD).

    Returns
    -------
    error : xarray.DataArray
        Total error, in the variable's units; NaN off the MD depths.
    trusted : xarray.DataArray
        1.0 trusted, 0.0 flagged at the member's MD depths (where ``variable`` is finite),
        NaN elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> ds = build_dataset(
    ...     {"vp": (("model", "depth"), [[2.0, 3.0], [np.nan, 3.2]]),
    ...      "vp_error_resolution": (("model", "depth"), [[np.nan, np.nan], [np.nan, 0.3]]),
    ...      "vp_error_sample": (("model", "depth"), [[np.nan, np.nan], [np.nan, 0.4]]),
    ...      "md_resolution_asymptotic": (("model", "depth"), [[np.nan, np.nan], [np.nan, 1]])},
    ...     {"depth": (("depth",), [500.0, 1000.0]), "model": (("model",), ["m4", "md"])})
    >>> error, trusted = md_error_trusted(ds, "vp", model="md")
    >>> error.values.round(3).tolist(), trusted.values.tolist()
    ([nan, 0.5], [nan, 1.0])
    """
    import xarray as xr

    if variable not in ds.data_vars:
        raise ValueError(f"md_error_trusted: the Dataset has no variable {variable!r}")
    value = ds[variable]
    ran = value.notnull()
    if f"{variable}_error" in ds.data_vars:
        error = ds[f"{variable}_error"]
    else:
        error = _quadrature(ds, variable)
    error = error.where(ran)
    if "md_trusted" in ds.data_vars:
        trusted = ds["md_trusted"].astype(float)
    else:
        asymptotic = ds["md_resolution_asymptotic"] if "md_resolution_asymptotic" in ds else \
            xr.full_like(value, np.nan, dtype=float)
        ok = asymptotic == 1
        for name in ("vp", "vs"):
            if name in ds.data_vars:
                err = ds[f"{name}_error"] if f"{name}_error" in ds.data_vars else \
                    _quadrature(ds, name)
                ok = ok & (err < np.abs(ds[name]))          # False where err is NaN
        trusted = ok.astype(float).where(asymptotic.notnull())
    trusted = trusted.where(ran)
    if model is not None:
        error, trusted = error.sel(model=model), trusted.sel(model=model)
    return error, trusted


def _quadrature(ds, variable):
    """Resolution and sample-size errors of ``variable`` in quadrature (a NaN part left out;
    NaN where both are NaN or absent)."""
    import xarray as xr

    parts = [ds[f"{variable}_error_{kind}"] for kind in ("resolution", "sample")
             if f"{variable}_error_{kind}" in ds.data_vars]
    if not parts:
        return xr.full_like(ds[variable], np.nan, dtype=float)
    total = sum((p.fillna(0.0) ** 2) for p in parts) ** 0.5
    known = parts[0].notnull()
    for p in parts[1:]:
        known = known | p.notnull()
    return total.where(known)
