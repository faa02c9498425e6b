"""The misfit of a scene to a well log: :func:`well_misfit` and how each variable is measured.

:data:`MISFIT` says, and :func:`_misfit` computes, the misfit of each variable, relative for
vp, vs and density, absolute for porosity; :func:`rockcem.wellfit.fit_scene` fits on the same
residuals. Re-exported by :mod:`rockcem.wells`.
"""

from __future__ import annotations

import itertools

import numpy as np

from ._well_curves import WELL_VARIABLES
from .validation import as_array

#: How :func:`well_misfit` measures each variable's misfit: relative for velocities and density
#: (``model/log - 1``), absolute for porosity, a fraction near 0 where a ratio blows up
#: (``model - log``, in porosity units).
MISFIT = {"vp": "model/log - 1", "vs": "model/log - 1", "density": "model/log - 1",
          "porosity": "model - log"}


def model_at_well(ds, well, name):
    """Scene variable ``name`` at the well's depths, linear in depth between scene depths.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset (dimension ``depth``, optional ``model``; no sweep dimensions).
    well : xarray.Dataset
        From :func:`rockcem.wells.read_well`.
    name : str
        A variable of both.

    Returns
    -------
    xarray.DataArray
        Dimensions ``depth`` (the well's) and ``model`` where the scene variable has it; NaN
        where the well lies outside the scene's depth range (never extrapolated).
    """
    extra = [d for d in ds[name].dims if d not in ("depth", "model")]
    if extra:
        raise ValueError(f"scene variable {name} has sweep dimensions {extra}; select one "
                         "member first (ds.isel(...))")
    return ds[name].interp(depth=well.depth.values, method="linear")


def _is_md(label) -> bool:
    """Whether a model label is an MD member (``md``, ``md_<scheme>``): valued at its own
    depths only."""
    return str(label) == "md" or str(label).startswith("md_")


def _sparse_points(ds, values):
    """Depths where an MD member has a value (None where it has none or is not 1-d)."""
    finite = np.isfinite(values.values)
    if values.ndim != 1 or not finite.any():
        return None
    return ds.depth.values[finite]


def _relative(name) -> bool:
    """Whether the misfit of variable ``name`` is relative, ``model/log - 1`` (:data:`MISFIT`)."""
    return MISFIT[name] == "model/log - 1"


def _misfit_scale(name, reference):
    """What ``model - log`` is divided by in the misfit of variable ``name``: ``reference`` (the
    log, for :func:`well_misfit`) where the misfit is relative, 1 where it is absolute
    (:data:`MISFIT`). The residuals of :func:`rockcem.wellfit.fit_scene` are scaled by it."""
    return np.asarray(reference, dtype=float) if _relative(name) else 1.0


def _misfit(model, log, name):
    """The misfit of ``model`` to ``log`` of variable ``name`` as :data:`MISFIT` says:
    ``model/log - 1`` or ``model - log``, i.e. ``(model - log)/scale``
    (:func:`_misfit_scale`)."""
    return (model - log) / _misfit_scale(name, log)


def _point_misfit(ds, values, log, points, name):
    """Misfit at each of ``points``, the log the mean of its samples within half a scene depth
    step (NaN where the log has no finite sample there)."""
    z = log.depth.values
    half = 0.5 * float(np.median(np.diff(ds.depth.values)))    # >= 2 depths: checked above
    out = np.full(points.size, np.nan)
    for k, p in enumerate(points):
        near = log.values[(z >= p - half) & (z <= p + half)]
        near = near[np.isfinite(near)]
        if near.size:
            out[k] = _misfit(float(values.sel(depth=p)), near.mean(), name)
    return out


def band_quantiles(ds, band=None):
    """The quantiles of a scene Dataset's band and of its median: ``(low, high, median)``.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset; its band needs a ``quantile`` dimension (a scene with ``[uncertain]``).
    band : (float, float), optional
        The band's lower and upper quantiles, two of the Dataset's. Default: its lowest and
        highest (0.1 and 0.9 by default, the 0.1-0.9 quantile band).

    Returns
    -------
    (float, float, float) or None
        None for a Dataset without quantiles and no ``band``.

    Raises
    ------
    ValueError
        ``band`` given for a Dataset without quantiles, quantiles it does not hold, a band
        whose lower quantile is not below its upper one, or a Dataset without the median 0.5
        (the misfit is that of the median).
    """
    if "quantile" not in ds.dims:
        if band is None:
            return None
        raise ValueError(f"band {_band_text(band)} needs a scene Dataset with quantiles (a "
                         "scene with [uncertain]); this one has no quantile dimension")
    q = np.asarray(ds["quantile"].values, dtype=float)

    def held(p, what):
        k = np.flatnonzero(np.isclose(q, p, rtol=0.0, atol=1e-9))
        if not k.size:
            raise ValueError(f"{what} {p:g} is not a quantile of the scene Dataset (it has "
                             f"{', '.join(f'{v:g}' for v in q)})")
        return float(q[k[0]])

    if q.size < 2:
        raise ValueError(f"the scene Dataset has one quantile ({q[0]:g}); a band needs two")
    median = held(0.5, "the median, quantile")
    if band is None:
        return float(q.min()), float(q.max()), median
    values = as_array("band", band)
    if values.shape != (2,) or not np.all(np.isfinite(values)) or not values[0] < values[1]:
        raise ValueError(f"band must be two quantiles LOW < HIGH of the scene Dataset (it has "
                         f"{', '.join(f'{v:g}' for v in q)}); got {_band_text(band)}")
    return held(values[0], "band quantile"), held(values[1], "band quantile"), median


def _band_text(band):
    try:
        return " ".join(f"{float(v):g}" for v in band)
    except (TypeError, ValueError):
        return repr(band)


def _at_quantile(ds, p):
    """``ds`` at quantile ``p`` (one of its own), the quantile dimension dropped."""
    k = int(np.flatnonzero(np.isclose(ds["quantile"].values, p, rtol=0.0, atol=1e-9))[0])
    return ds.isel(quantile=k, drop=True)


def well_misfit(ds, well, *, intervals=None, variables=None, band=None):
    r"""Misfit of each model to a well log in each depth interval; for a scene with
    ``[uncertain]``, also the share of the log inside the scene's quantile band.

    For every variable both hold (:data:`WELL_VARIABLES`), every model (model-independent
    variables under the label ``"-"``) and every interval ``[top, base)``: the number of log
    samples ``n`` with a finite value inside the scene's depth range, the root-mean-square
    misfit and the mean misfit (bias) of the model :math:`m` (at the log's depths, linear
    between scene depths) to the log :math:`o`, measured as :data:`MISFIT` says: relative,
    :math:`m/o - 1`, for vp, vs and density; absolute, :math:`m - o`, for porosity (a fraction:
    a ratio would blow up near 0 porosity). The last interval includes its base. An MD member
    (``md``, ``md_<scheme>``: valued at its own depths, NaN elsewhere) is compared point by
    point: at each of its depths :math:`o` is the mean of the log's samples within half a scene
    depth step of it (the depth a continuous model's sample stands for), and ``n`` counts those
    depths.

    A scene Dataset with a ``quantile`` dimension (a scene with ``[uncertain]``) is measured by
    its median (quantile 0.5) as above, and by its band between two quantiles
    :math:`q_l < q_h` (default its lowest and highest, 0.1 and 0.9: the 0.1-0.9 quantile band,
    which holds about 80 % of a well-calibrated model's samples): both edges are taken at the
    log's depths as the median is (linear between scene depths), and ``inside`` is the share
    of the log's samples :math:`o` with :math:`b_l \le o \le b_h` among the ``n_band``
    samples with a value of the log and of both edges. ``blank`` counts the log's samples in
    the interval, within the scene's depths, that have no value (blanked or null): they are
    not counted in ``n_band``. The quantiles are those of the members at each depth, so the
    band is pointwise: the share of a log inside it says how well the spread of the inputs
    covers the log's scatter at each depth, not the probability of the log as a whole.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset without sweep dimensions (``quantile`` allowed).
    well : xarray.Dataset
        From :func:`rockcem.wells.read_well`.
    intervals : sequence of float, optional
        Interval boundaries, m, finite and increasing (``[1000, 2000, 3000]`` gives two
        intervals).
        Default: one interval over the depths both cover.
    variables : sequence of str, optional
        Default: all shared ones.
    band : (float, float), optional, keyword-only
        Quantiles of the band, two of the Dataset's (:func:`band_quantiles`); default its
        lowest and highest where it has a ``quantile`` dimension, no band where it has none.

    Returns
    -------
    pandas.DataFrame
        Columns ``variable``, ``model``, ``top``, ``base``, ``n``, ``rms``, ``bias``,
        ``misfit`` (``"model/log - 1"`` or ``"model - log"``) and ``log`` (the log's mnemonic;
        ``"NPHI, apparent"`` for an apparent porosity); with a band also ``band`` (its
        quantiles, ``"0.1-0.9"``), ``n_band``, ``inside`` (a fraction) and ``blank``.

    Raises
    ------
    ValueError
        No shared variable or depth range, bad intervals, a log of vp, vs or density with a
        value ``<= 0`` (a relative misfit needs positive values; none is dropped silently), or
        a band the Dataset cannot give (:func:`band_quantiles`).

    Examples
    --------
    >>> import numpy as np
    >>> from rockcem.variables import build_dataset
    >>> z = np.array([0.0, 1000.0, 2000.0])
    >>> vp = np.array([[2.0, 2.5, 3.0], [2.2, 2.7, 3.2], [2.4, 2.9, 3.4]])   # quantile, depth
    >>> ds = build_dataset({"vp": (("quantile", "depth"), vp)},
    ...                    {"quantile": (("quantile",), [0.1, 0.5, 0.9]),
    ...                     "depth": (("depth",), z)})
    >>> well = build_dataset({"vp": (("depth",), [2.6, 3.5, np.nan, 2.8])},
    ...                      {"depth": (("depth",), [500.0, 1000.0, 1500.0, 2000.0])})
    >>> row = well_misfit(ds, well).iloc[0]
    >>> int(row.n_band), int(row.blank), float(row.inside)
    (3, 1, 0.3333333333333333)
    """
    import pandas as pd

    shared = [v for v in WELL_VARIABLES if v in ds.data_vars and v in well.data_vars]
    if variables is not None:
        unknown = [v for v in variables if v not in shared]
        if unknown:
            raise ValueError(f"variable {unknown[0]!r} is not in both the scene and the well "
                             f"(shared: {', '.join(shared) or 'none'})")
        shared = list(variables)
    if not shared:
        raise ValueError("the scene and the well share no variable of "
                         f"{', '.join(WELL_VARIABLES)}")
    lo = max(float(ds.depth.min()), float(well.depth.min()))
    hi = min(float(ds.depth.max()), float(well.depth.max()))
    if lo >= hi:
        raise ValueError(f"the well ({float(well.depth.min()):g}-{float(well.depth.max()):g} m)"
                         f" and the scene ({float(ds.depth.min()):g}-"
                         f"{float(ds.depth.max()):g} m) share no depth range")
    edges = as_array("intervals", [lo, hi] if intervals is None else intervals)
    if edges.ndim != 1 or edges.size < 2 or not np.all(np.isfinite(edges)) \
            or np.any(np.diff(edges) <= 0):
        raise ValueError(f"intervals must be at least two finite, increasing depths (m); got "
                         f"{edges.tolist()}")
    if edges[-1] < lo or edges[0] > hi:
        raise ValueError(f"intervals {edges[0]:g}-{edges[-1]:g} m lie outside the depths the "
                         f"well and the scene share ({lo:g}-{hi:g} m)")
    z = well.depth.values
    quantiles = band_quantiles(ds, band)
    full = ds
    if quantiles is not None:
        ds = _at_quantile(full, quantiles[2])
    in_scene = (z >= float(ds.depth.min())) & (z <= float(ds.depth.max()))
    rows = []
    for name in shared:
        log = well[name]
        if _relative(name) and np.any(log.values <= 0.0):
            k = int(np.flatnonzero(log.values <= 0.0)[0])
            raise ValueError(f"log {name} is {log.values[k]:g} at {z[k]:g} m; its misfit is "
                             "relative (model/log - 1) and needs values > 0")
        label = log.attrs.get("log_label") or log.attrs.get("source_mnemonic") or name
        modelled = model_at_well(ds, well, name)
        if quantiles is not None:
            edges_at = [model_at_well(_at_quantile(full, q), well, name)
                        for q in quantiles[:2]]
        labels = modelled.model.values.tolist() if "model" in modelled.dims else ["-"]
        for model in labels:
            own = ds[name].sel(model=model) if model != "-" else ds[name]
            points = _sparse_points(ds, own) if _is_md(model) else None
            if points is not None:          # a model at a few depths (the MD backend)
                zz, mis = points, _point_misfit(ds, own, log, points, name)
            else:
                m = modelled.sel(model=model).values if model != "-" else modelled.values
                zz, mis = z, _misfit(m, log.values, name)
            for k, (top, base) in enumerate(itertools.pairwise(edges)):
                below = (zz <= base) if k == edges.size - 2 else (zz < base)
                sel = (zz >= top) & below & np.isfinite(mis)
                n = int(sel.sum())
                row = {"variable": name, "model": model, "top": top, "base": base, "n": n,
                       "rms": float(np.sqrt(np.mean(mis[sel] ** 2))) if n else np.nan,
                       "bias": float(np.mean(mis[sel])) if n else np.nan,
                       "misfit": MISFIT[name], "log": str(label)}
                if quantiles is not None:
                    low, high = (e.sel(model=model).values if model != "-" else e.values
                                 for e in edges_at)
                    here = (z >= top) & ((z <= base) if k == edges.size - 2 else (z < base))
                    row.update(_coverage(log.values, low, high, here & in_scene))
                    row["band"] = f"{quantiles[0]:g}-{quantiles[1]:g}"
                rows.append(row)
    table = pd.DataFrame(rows)
    if quantiles is not None:       # the band's columns after the median's, before the log's
        order = [c for c in table.columns if c not in ("misfit", "log")]
        table = table[order[:7] + ["band", "n_band", "inside", "blank", "misfit", "log"]]
    return table


def _coverage(log, low, high, where):
    """``n_band``, ``inside`` and ``blank`` of :func:`well_misfit`: among the samples
    ``where``, those with a value of the log and both band edges, the share of them with
    ``low <= log <= high``, and those without a value of the log."""
    valid = where & np.isfinite(log) & np.isfinite(low) & np.isfinite(high)
    n = int(valid.sum())
    inside = (log[valid] >= low[valid]) & (log[valid] <= high[valid])
    return {"n_band": n, "inside": float(inside.mean()) if n else np.nan,
            "blank": int((where & ~np.isfinite(log)).sum())}
