"""Synthetic well logs from a scene, and LAS 2.0 writing.

:func:`synthetic_well` samples a scene's Dataset at log depths and adds Gaussian noise of given
standard deviations; :func:`write_las` writes logs as an unwrapped LAS 2.0 file with ``lasio``
(depth in ft or m, sonic slownesses in µs/ft or µs/m, density g/cm³, porosity v/v), atomically.
Together they make the shipped synthetic example (``datasets/wells/README.md``) and test fits
against known parameters.
"""

from __future__ import annotations

import numpy as np

__all__ = ["synthetic_well", "write_las"]

_FOOT = 0.3048          # m, exact


def synthetic_well(ds, depth, *, sigma, model=None, seed=0, name="SYNTHETIC"):
    """Logs sampled from a scene at ``depth`` (linear between scene depths) plus noise.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset (no sweep dimension).
    depth : array_like, shape (n,)
        Log depths, m, increasing, inside the scene's depth range.
    sigma : mapping
        ``{variable: standard deviation}`` for each of ``vp``, ``vs`` (km/s), ``density``
        (g/cm³), ``porosity`` (fraction) to log; 0 gives the noise-free model.
    model : str, optional
        The model ``vp``/``vs`` come from (needed when ``ds`` has several).
    seed : int
        Seed of ``numpy.random.default_rng``.
    name : str
        Well name.

    Returns
    -------
    xarray.Dataset
        As :func:`rockcem.wells.read_well` returns.
    """
    from .variables import build_dataset

    z = np.asarray(depth, dtype=float)
    if z.ndim != 1 or z.size < 2 or np.any(np.diff(z) <= 0):
        raise ValueError("depth must be an increasing 1-D array of at least two depths")
    if z[0] < float(ds.depth.min()) or z[-1] > float(ds.depth.max()):
        raise ValueError(f"depth {z[0]:g}-{z[-1]:g} m lies outside the scene's "
                         f"{float(ds.depth.min()):g}-{float(ds.depth.max()):g} m")
    rng = np.random.default_rng(seed)
    data = {}
    for v, s in sigma.items():
        if v not in ds.data_vars:
            raise ValueError(f"the scene has no {v!r} to log")
        if not s >= 0:
            raise ValueError(f"sigma[{v!r}] must be >= 0; got {s!r}")
        da = ds[v]
        if "model" in da.dims:
            if model is None and da.sizes["model"] != 1:
                raise ValueError(f"the scene has models {ds.model.values.tolist()}: name one")
            da = da.sel(model=model) if model is not None else da.isel(model=0)
        data[v] = (("depth",), np.interp(z, ds.depth.values, da.values)
                   + rng.normal(0.0, s, z.size))
    attrs = {"title": f"well {name}", "well": name, "source_file": "",
             "comment": "synthetic: scene " + str(ds.attrs.get("scene_name", "")) + " plus "
                        "Gaussian noise, sigma " + ", ".join(f"{k} {v:g}"
                                                            for k, v in sigma.items())}
    return build_dataset(data, {"depth": (("depth",), z)}, attrs)


def write_las(well, path, *, feet=True, comment=""):
    """Write logs as a LAS 2.0 file (unwrapped) with ``lasio``, atomically.

    Parameters
    ----------
    well : xarray.Dataset
        Logs on ``depth`` (m): any of ``vp``, ``vs`` (km/s), ``density``, ``porosity``.
    path : str or Path
        The ``.las`` file.
    feet : bool, keyword-only
        Depth in ft and slownesses in µs/ft (the usual LAS units); else m and µs/m.
    comment : str, keyword-only
        Written in the ``~Other`` section (e.g. that the data are synthetic).

    Returns
    -------
    pathlib.Path
    """
    import lasio

    from ._atomic import atomic_write

    length = _FOOT if feet else 1.0
    unit = "FT" if feet else "M"
    las = lasio.LASFile()
    las.well["WELL"].value = str(well.attrs.get("well", ""))
    las.well["NULL"].value = -999.25
    las.append_curve("DEPT", well.depth.values / length, unit=unit, descr="depth")
    # v [km/s] = (length [m] / 1000) / (dt [us] * 1e-6) -> dt = 1000 * length / v.
    for v, mnemonic, descr in (("vp", "DT", "compressional slowness"),
                               ("vs", "DTS", "shear slowness")):
        if v in well:
            dt = 1000.0 * length / well[v].values
            las.append_curve(mnemonic, np.where(np.isfinite(dt), dt, -999.25),
                             unit=f"US/{unit}", descr=descr)
    if "density" in well:
        las.append_curve("RHOB", np.nan_to_num(well.density.values, nan=-999.25), unit="G/CC",
                         descr="bulk density")
    if "porosity" in well:
        las.append_curve("PHIT", np.nan_to_num(well.porosity.values, nan=-999.25), unit="V/V",
                         descr="total porosity")
    las.other = comment

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as fh:
            las.write(fh, version=2.0, wrap=False, fmt="%.6f")

    return atomic_write(path, write)
