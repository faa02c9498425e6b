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

__all__ = ["variable_attrs", "variable_names", "build_dataset", "no_coordinate_fill",
           "sweep_dimension"]


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
