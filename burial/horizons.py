"""Burial histories from tables: one history per horizon, or one history every depth follows.

A basin model exports, for each horizon (a surface deposited at one time), its depth below the
sediment surface and its temperature at a series of times before present. :func:`horizon_paths`
turns such a table into one :class:`burial.BurialPath` with the horizons on the leading axis, each
following its own piecewise-linear history from deposition to the present, so that hiatus
(constant depth and temperature), further burial, uplift, erosion and cooling are all exact
pieces of the path (the kinetics integrate each linear piece in closed form,
:mod:`burial._integrals`) and compaction follows the deepest burial
(:func:`burial.pressures` ``.max_effective``). The horizons are sorted by present-day depth,
which becomes the depth axis of the rock state.

:func:`shifted_path` is the table form of the linear basin model: one time–depth–temperature
history that every package follows, so that the package now at depth :math:`z` has been buried
for the time the history takes to reach :math:`z` and the nodes are the present-day profile.

Units: time Myr, depth m, temperature °C. Rows are counted from 1 in the order given; every
error names the row and the column.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from rockcem.validation import as_scalar, check_positive

# The bounds are those of every path (burial.path): a table in feet may trip the depth bound (feet
# cannot be told from metres in general, so tables state their units), a column in kelvin the
# temperature at deposition.
from .path import (MAX_DEPTH_M, MAX_PROFILE_NODES, MAX_SURFACE_TEMPERATURE_C, MAX_TEMPERATURE_C,
                   MIN_TEMPERATURE_C, BurialPath, path_from_nodes)

__all__ = ["HorizonPaths", "horizon_paths", "shifted_path", "MAX_DEPTH_M",
           "MAX_SURFACE_TEMPERATURE_C"]


class HorizonPaths(NamedTuple):
    """Horizon histories on one array, sorted by present-day depth."""

    path: BurialPath        #: time since deposition, depth, temperature: shape (horizons, nodes)
    horizon: np.ndarray     #: horizon names, shape (horizons,)
    age: np.ndarray         #: deposition time, Myr before present, shape (horizons,)


def _column(name, values, n=None, of="horizon"):
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"column {name}: must hold numbers only") from None
    if arr.ndim != 1:
        raise ValueError(f"column {name}: must be a flat list of values")
    if n is not None and arr.size != n:
        raise ValueError(f"column {name}: {arr.size} values, but column {of} has {n} rows")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        raise ValueError(f"row {bad[0] + 1}, column {name}: {values[bad[0]]!r} is not a finite "
                         "number")
    return arr


def _check_values(rows, depth, temperature, first):
    """Depth >= 0 and plausible, temperature in range and (at deposition) not kelvin."""
    for r, z in zip(rows, depth):
        if z < 0.0:
            raise ValueError(f"row {r + 1}, column depth: {z:g} m is above the sediment surface "
                             "(depth must be >= 0)")
        if z > MAX_DEPTH_M:
            raise ValueError(f"row {r + 1}, column depth: {z:g} m is deeper than "
                             f"{MAX_DEPTH_M:g} m; is the column in feet? (give it in m)")
    for r, T in zip(rows, temperature):
        if not MIN_TEMPERATURE_C <= T <= MAX_TEMPERATURE_C:
            raise ValueError(f"row {r + 1}, column temperature: {T:g} degC lies outside "
                             f"[{MIN_TEMPERATURE_C:g}, {MAX_TEMPERATURE_C:g}]; is the column "
                             "in kelvin?")
    if temperature[first] > MAX_SURFACE_TEMPERATURE_C:
        r = rows[first]
        raise ValueError(f"row {r + 1}, column temperature: {temperature[first]:g} degC at "
                         "deposition (depth 0); is the column in kelvin? (give it in degC)")


def horizon_paths(horizon, time_before_present, depth, temperature) -> HorizonPaths:
    """Burial paths of horizons from a basin-model table (one row per horizon and time).

    Each horizon's rows, in the order given, run forward in time from its deposition (the
    oldest row, at depth 0) to the present (time 0 before present); between rows depth and
    temperature vary linearly in time. Horizons with fewer rows are padded at deposition with
    copies of their first node (pieces of zero duration, which add nothing to the kinetic
    integrals and change no pressure), so that all share one array.

    Parameters
    ----------
    horizon : sequence of str, shape (rows,)
        Horizon name of each row.
    time_before_present : array_like, shape (rows,)
        Myr before present, ``>= 0``; strictly decreasing within a horizon, ending at 0.
    depth : array_like, shape (rows,)
        Depth below the sediment surface, m, in [0, :data:`MAX_DEPTH_M`]; 0 at deposition.
    temperature : array_like, shape (rows,)
        °C, in [:data:`burial.path.MIN_TEMPERATURE_C`, :data:`burial.path.MAX_TEMPERATURE_C`];
        at most :data:`MAX_SURFACE_TEMPERATURE_C` at deposition.

    Returns
    -------
    HorizonPaths
        ``path.time`` is time since each horizon's deposition.

    Raises
    ------
    ValueError
        Naming the row and the column: a missing or non-numeric value, time running backwards,
        a history that does not start at depth 0 or does not reach the present, a depth or
        temperature out of range (a sign of feet or kelvin), horizons that cross (a younger
        horizon below an older one at some time).

    Examples
    --------
    Burial, a hiatus, uplift; the younger horizon B is deposited during the hiatus:

    >>> h = horizon_paths(["A"] * 4 + ["B"] * 3, [60, 40, 30, 0, 35, 30, 0],
    ...                   [0, 2000, 2000, 1500, 0, 100, 50], [15, 75, 75, 60, 15, 18, 16])
    >>> h.horizon.tolist(), h.path.depth[:, -1].tolist(), h.age.tolist()
    (['B', 'A'], [50.0, 1500.0], [35.0, 60.0])
    """
    names = [str(h) for h in np.asarray(horizon, dtype=object).ravel()]
    n = len(names)
    if n == 0:
        raise ValueError("column horizon: the table has no rows")
    tbp = _column("time", time_before_present, n)
    z = _column("depth", depth, n)
    T = _column("temperature", temperature, n)
    groups: dict[str, list[int]] = {}
    for i, name in enumerate(names):
        if not name.strip():
            raise ValueError(f"row {i + 1}, column horizon: empty name")
        groups.setdefault(name, []).append(i)
    paths = []
    for name, rows in groups.items():
        rows = np.array(rows)
        if rows.size < 2:
            raise ValueError(f"row {rows[0] + 1}, column time: horizon {name!r} has one row; a "
                             "history needs at least deposition and the present")
        t = tbp[rows]
        back = np.flatnonzero(np.diff(t) >= 0.0)
        if back.size:
            r = rows[back[0] + 1]
            raise ValueError(f"row {r + 1}, column time: {t[back[0] + 1]:g} Myr before present "
                             f"follows {t[back[0]]:g} in horizon {name!r}; time must run "
                             "forward (time before present decreasing)")
        if t[-1] != 0.0:
            raise ValueError(f"row {rows[-1] + 1}, column time: horizon {name!r} ends "
                             f"{t[-1]:g} Myr before present; its history must reach the "
                             "present (0)")
        if z[rows[0]] != 0.0:
            raise ValueError(f"row {rows[0] + 1}, column depth: horizon {name!r} starts at "
                             f"{z[rows[0]]:g} m; its oldest row is its deposition, at depth 0")
        _check_values(rows, z[rows], T[rows], 0)
        paths.append((name, rows, t, z[rows], T[rows]))
    _check_order(paths)
    paths.sort(key=lambda p: (p[3][-1], -p[2][0]))
    for a, b in zip(paths, paths[1:]):
        if a[3][-1] == b[3][-1]:
            raise ValueError(f"row {b[1][-1] + 1}, column depth: horizons {a[0]!r} and "
                             f"{b[0]!r} both lie at {b[3][-1]:g} m today; the depth axis "
                             "needs distinct present-day depths (keep one of them)")
    width = max(p[1].size for p in paths)

    def padded(values):
        return np.array([np.concatenate([np.full(width - v.size, v[0]), v]) for v in values])

    age = np.array([p[2][0] for p in paths])
    t_since = padded([p[2][0] - p[2] for p in paths])
    path = BurialPath(t_since, padded([p[3] for p in paths]), padded([p[4] for p in paths]))
    return HorizonPaths(path, np.array([p[0] for p in paths]), age)


def _check_order(paths):
    """Older horizons lie at least as deep as younger ones wherever both exist."""
    ages = sorted({p[2][0] for p in paths}, reverse=True)  # oldest first
    groups = [[p for p in paths if p[2][0] == age] for age in ages]
    # Horizons deposited together keep no order among themselves; each one must lie above
    # every horizon of the next older age (and so, by transitivity, of all older ages).
    for older, younger in ((o, y) for a, b in zip(groups, groups[1:]) for o in a for y in b):
        # Compare on the union of both horizons' nodes while both exist (both linear between).
        times = np.union1d(older[2], younger[2])
        times = times[times <= younger[2][0]]
        zo = np.interp(-times, -older[2], older[3])
        zy = np.interp(-times, -younger[2], younger[3])
        tol = 1e-9 * np.maximum(1.0, np.abs(zo))
        cross = np.flatnonzero(zy > zo + tol)
        if cross.size:
            when = times[cross[0]]
            at = younger[2] == when
            rows = younger[1][at] if np.any(at) else older[1][older[2] == when]
            row = f"row {rows[0] + 1}, " if rows.size else ""
            raise ValueError(f"{row}column depth: horizon {younger[0]!r} (deposited "
                             f"{younger[2][0]:g} Myr before present) lies below the older "
                             f"horizon {older[0]!r} at {when:g} Myr before present "
                             f"({zy[cross[0]]:g} m > {zo[cross[0]]:g} m): horizons cross")


def shifted_path(time, depth, temperature, *, depth_step=None) -> BurialPath:
    """One burial history that every package follows, as the linear basin model does.

    The package now at the depth of node :math:`k` was deposited :math:`t_k` ago and has
    followed the history from its first node to node :math:`k`, so the values at the nodes are
    the present-day profile. The linear basin model is the special case :math:`z = S t`,
    :math:`T = T_0 + G z`. Depth must increase from node to node (with a hiatus or uplift the
    packages no longer follow one history: give horizons instead).

    Parameters
    ----------
    time : array_like, shape (n,)
        Time since deposition, Myr, strictly increasing from 0.
    depth : array_like, shape (n,)
        m, strictly increasing from 0.
    temperature : array_like, shape (n,)
        °C.
    depth_step : float, optional, keyword-only
        m, ``> 0``; if given, nodes are added on each linear piece so that no two reported
        depths are further apart than this (the path itself is unchanged), at most
        :data:`burial.path.MAX_PROFILE_NODES` in all.

    Returns
    -------
    BurialPath

    Examples
    --------
    >>> p = shifted_path([0, 10, 30], [0, 500, 1000], [15, 30, 45], depth_step=250)
    >>> p.depth.tolist(), p.time.tolist()
    ([0.0, 250.0, 500.0, 750.0, 1000.0], [0.0, 5.0, 10.0, 20.0, 30.0])
    """
    t = _column("time", time)
    z = _column("depth", depth, t.size, of="time")
    T = _column("temperature", temperature, t.size, of="time")
    rows = np.arange(t.size)
    if t.size < 2:
        raise ValueError("column time: a history needs at least two rows")
    if t[0] != 0.0 or z[0] != 0.0:
        raise ValueError(f"row 1, column {'time' if t[0] != 0.0 else 'depth'}: the history "
                         "starts at deposition, time 0 and depth 0")
    back = np.flatnonzero(np.diff(t) <= 0.0)
    if back.size:
        raise ValueError(f"row {back[0] + 2}, column time: {t[back[0] + 1]:g} Myr follows "
                         f"{t[back[0]]:g}; time must increase")
    up = np.flatnonzero(np.diff(z) <= 0.0)
    if up.size:
        raise ValueError(f"row {up[0] + 2}, column depth: {z[up[0] + 1]:g} m follows "
                         f"{z[up[0]]:g} m; in a history every depth follows, depth must "
                         "increase (for a hiatus or uplift give horizons)")
    _check_values(rows, z, T, 0)
    if depth_step is not None:
        dz = check_positive("depth_step", as_scalar("depth_step", depth_step))
        nodes = np.sum(np.ceil(np.diff(z) / dz - 1e-9)) + 1
        if nodes > MAX_PROFILE_NODES:
            raise ValueError(f"depth_step {dz:g} m gives {nodes:.3g} nodes down to "
                             f"{z[-1]:g} m; at most {MAX_PROFILE_NODES} (depth_step >= "
                             f"{z[-1] / (MAX_PROFILE_NODES - t.size):.3g} m)")
        new = [z[:1]]
        for z0, z1 in zip(z[:-1], z[1:]):
            k = int(np.ceil((z1 - z0) / dz - 1e-9))
            new.append(z0 + (z1 - z0) * np.arange(1, k + 1) / k)
        zn = np.concatenate(new)
        t, T, z = np.interp(zn, z, t), np.interp(zn, z, T), zn
    return path_from_nodes(t, z, T)
