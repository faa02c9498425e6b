"""AVO terms of an interface in a well log, beside a stack scene's (issue 31, item 6).

The log's P and S velocities and density are averaged over a window above and a window below a
depth the user gives (the blocked log of an interface), and the two averages are one interface:
Shuey's intercept and gradient (Shuey 1985, of the Aki & Richards 1980 linearisation, eq. 5.44)
and the AVO class of :func:`rockcem.reflectivity.avo_class`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["WellInterface", "well_interface_avo", "model_interface_table"]


class WellInterface(NamedTuple):
    """The blocked log on both sides of an interface and its AVO terms."""

    depth: float
    window: float
    vp1: float
    vs1: float
    rho1: float
    vp2: float
    vs2: float
    rho2: float
    n_above: int
    n_below: int
    intercept: float
    gradient: float
    curvature: float
    avo_class: str


def _mean(well, name, lo, hi, side, depth):
    z = well["depth"].values
    v = well[name].values
    sel = (z >= lo) & (z <= hi) & np.isfinite(v)
    if np.count_nonzero(sel) < 2:
        raise ValueError(f"the well has {np.count_nonzero(sel)} valid {name} samples in the "
                         f"window {side} the interface at {depth:g} m ({lo:g}-{hi:g} m); it "
                         "needs at least 2 (a wider --window, or an interface inside the log)")
    return float(np.mean(v[sel])), int(np.count_nonzero(sel))


def well_interface_avo(well, depth, *, window=20.0, threshold=None) -> WellInterface:
    """AVO terms of the interface at ``depth`` of a well log.

    Each side is the mean of the log over ``window`` metres: above, :math:`[z - w, z)`; below,
    :math:`(z, z + w]` (a sample exactly at :math:`z` belongs to neither). The two means are
    the media of :func:`rockcem.reflectivity.intercept_gradient` and
    :func:`rockcem.reflectivity.avo_class`.

    Parameters
    ----------
    well : xarray.Dataset
        A log read by :func:`rockcem.wells.read_well`, with ``vp``, ``vs`` and ``density``.
    depth : float
        The interface, m (the log's depth after its offset), inside the log.
    window : float, keyword-only
        Length of each window, m, > 0 (default 20).
    threshold : float, optional, keyword-only
        The class threshold of :func:`rockcem.reflectivity.avo_class` (default its own).

    Returns
    -------
    WellInterface

    Raises
    ------
    ValueError
        The well lacks one of the three logs, ``window`` is not positive, or a window holds
        fewer than two valid samples of a log.
    """
    from .reflectivity import AVO_CLASSES, AVO_THRESHOLD, avo_class, intercept_gradient

    missing = [n for n in ("vp", "vs", "density") if n not in well]
    if missing:
        raise ValueError(f"an interface of the well needs vp, vs and density logs; it has no "
                         f"{missing[0]} (name its curve with --curve {missing[0]}=MNEMONIC)")
    z, w = float(depth), float(window)
    if not np.isfinite(z):
        raise ValueError(f"interface depth must be a finite number of m; got {depth!r}")
    if not (np.isfinite(w) and w > 0):
        raise ValueError(f"window must be > 0 m; got {window!r}")
    above = {n: _mean(well, n, z - w, np.nextafter(z, -np.inf), "above", z)
             for n in ("vp", "vs", "density")}
    below = {n: _mean(well, n, np.nextafter(z, np.inf), z + w, "below", z)
             for n in ("vp", "vs", "density")}
    media = [above["vp"][0], above["vs"][0], above["density"][0],
             below["vp"][0], below["vs"][0], below["density"][0]]
    terms = intercept_gradient(*media)
    t = AVO_THRESHOLD if threshold is None else threshold
    code = int(avo_class(terms.intercept, terms.gradient, threshold=t))
    return WellInterface(z, w, *media, min(n for _, n in above.values()),
                         min(n for _, n in below.values()), float(terms.intercept),
                         float(terms.gradient), float(terms.curvature),
                         AVO_CLASSES[code - 1] if code else "none")


def model_interface_table(ds, depth):
    """A stack Dataset's intercept, gradient and class at the depth nearest ``depth``, one row
    per interface, fluid and model (a pandas DataFrame)."""
    import pandas as pd

    need = ("avo_intercept", "avo_gradient", "avo_class")
    if any(n not in ds for n in need):
        raise ValueError("the scene's file has no avo_intercept: --interface compares a stack "
                         "scene's AVO ([[layers]] with a [seismic] section) with the well's")
    z = ds["depth"].values
    k = int(np.argmin(np.abs(z - float(depth))))
    names = ds["avo_class"].attrs.get("flag_meanings", "").split()
    rows = []
    for i in ds["interface"].values:
        for f in ds["fluid"].values:
            for m in ds["model"].values:
                sel = dict(interface=i, fluid=f, model=m, depth=z[k])
                code = int(ds["avo_class"].sel(**sel))
                rows.append({"interface": i, "fluid": f, "model": m, "depth": z[k],
                             "A": float(ds["avo_intercept"].sel(**sel)),
                             "B": float(ds["avo_gradient"].sel(**sel)),
                             "class": names[code - 1] if code else "none"})
    return pd.DataFrame(rows)
