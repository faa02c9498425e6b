"""Burial histories of scenes from tables: ``[path] kind = "horizons"`` and ``kind = "nodes"``.

A scene gives the table either as a CSV file (``table = "history.csv"``, relative to the scene
file, then to the working directory) or inline (``horizon``, ``time``, ``depth``,
``temperature`` arrays in the ``[path]`` table, in Myr, m and °C).

CSV columns, units in the header (``name (unit)`` or ``name [unit]``), ``#`` comments allowed:

- ``kind = "horizons"``: ``horizon``, ``time`` (or ``age``; Myr before present, ``Myr`` or
  ``Ma``), ``depth`` (``m`` or ``ft``, spelt as :data:`rockcem.wells.UNITS` lists them),
  ``temperature`` (``degC``, ``C``, ``°C`` or ``K``), one row per horizon and time
  (:func:`burial.horizons.horizon_paths`).
- ``kind = "nodes"``: ``time`` (Myr since deposition), ``depth``, ``temperature``: one history
  every depth follows (:func:`burial.horizons.shifted_path`).

A column without a unit, or with one not listed, is an error naming the column; feet and kelvin
are converted when the header says so (1 ft = 0.3048 m, T [°C] = T [K] − 273.15).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import NamedTuple

import numpy as np

from .wells import UNITS

__all__ = ["PATH_KINDS", "TableHistory", "read_history_table", "scene_history"]

#: Values of ``[path] kind``.
PATH_KINDS = ("linear", "horizons", "nodes")
#: Keys of ``[path]`` per kind (the others must not be given).
KIND_KEYS = {
    "linear": ("gradient", "sedimentation_rate", "heating_rate", "surface_temperature",
               "max_depth", "depth_step"),
    "horizons": ("table", "horizon", "time", "depth", "temperature"),
    "nodes": ("table", "time", "depth", "temperature", "depth_step"),
}
_COLUMNS = {"horizons": ("horizon", "time", "depth", "temperature"),
            "nodes": ("time", "depth", "temperature")}
_UNITS = {
    "time": {"MYR": (1.0, 0.0), "MA": (1.0, 0.0)},
    "depth": {key: (factor, 0.0) for key, factor in UNITS["depth"].items()},  # as read_well
    "temperature": {"DEGC": (1.0, 0.0), "C": (1.0, 0.0), "°C": (1.0, 0.0),
                    "DEGREE_CELSIUS": (1.0, 0.0), "K": (1.0, -273.15)},
}
_HEADER = re.compile(r"^\s*([A-Za-z_]+)\s*(?:[(\[]\s*([^)\]]*?)\s*[)\]])?\s*$")


#: Histories read from files: (path, inode, mtime, size, kind, depth_step) -> TableHistory.
_READ: dict = {}


class TableHistory(NamedTuple):
    """A scene's burial path from a table, and the horizon names (``None`` for nodes)."""

    path: object                    #: burial.BurialPath (horizons on the leading axis)
    horizon: np.ndarray | None


def read_history_table(path, kind) -> dict:
    """The columns of a history CSV file in Myr, m and °C: ``{column: array}``.

    Parameters
    ----------
    path : str or Path
        CSV file.
    kind : {"horizons", "nodes"}
        Which columns to expect (see the module docstring).

    Raises
    ------
    ValueError
        Naming the file, the column and (for a bad value) the row: a missing column or unit,
        an unknown unit, a value that is not a number.
    """
    import pandas as pd

    path = Path(path)
    try:
        table = pd.read_csv(path, comment="#", skipinitialspace=True, dtype=str,
                            keep_default_na=False)
    except (OSError, ValueError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise ValueError(f"history table {path.name}: not a readable CSV file: "
                         f"{str(exc).strip()}") from None
    found = {}
    for header in table.columns:
        m = _HEADER.match(str(header))
        name = m.group(1).lower() if m else str(header)
        name = "time" if name == "age" and kind == "horizons" else name
        if name in found:
            # pandas renames a repeated header 'x' to 'x.1'; an age and a time column both
            # give the time: whichever came last was used, with no word.
            raise ValueError(f"history table {path.name}: columns {found[name][0]!r} and "
                             f"{header!r} both give the {name}; keep one")
        found[name] = (header, m.group(2) if m else None)
    out = {}
    for col in _COLUMNS[kind]:
        if col not in found:
            raise ValueError(f"history table {path.name}: missing column {col!r} (columns: "
                             f"{', '.join(_COLUMNS[kind])}, with units in the header)")
        header, unit = found[col]
        values = table[header].str.strip().to_numpy()
        if col == "horizon":
            out[col] = values
            continue
        if not unit:
            raise ValueError(f"history table {path.name}: column {col!r} has no unit; write "
                             f"'{col} ({next(iter(_UNITS[col])).lower()})' in the header")
        key = re.sub(r"\s+", "", unit).upper()
        if key not in _UNITS[col]:
            raise ValueError(f"history table {path.name}: column {col!r}: unit {unit!r} is "
                             f"not understood; use one of {', '.join(_UNITS[col])}")
        if kind == "nodes" and col == "time" and key == "MA":
            raise ValueError(f"history table {path.name}: column 'time' is time since "
                             "deposition for kind = 'nodes': give it in Myr (Ma is an age, "
                             "before present)")
        scale, shift = _UNITS[col][key]
        nums = pd.to_numeric(pd.Series(values), errors="coerce").to_numpy(dtype=float)
        bad = np.flatnonzero(np.isnan(nums))
        if bad.size:
            raise ValueError(f"history table {path.name}: row {bad[0] + 1}, column {col}: "
                             f"{values[bad[0]]!r} is not a number")
        out[col] = nums * scale + shift
    return out


def _resolve(name, base_dir):
    """The table file: an absolute path; or relative to the scene file's folder, then to the
    working directory; or, a bare file name, one shipped in ``datasets/wells/`` (so a scene
    copied out of the shipped ones keeps its table)."""
    from ._data import data_path, find_file

    bare = len(Path(name).parts) == 1
    found, looked = find_file(name, base_dir, data_path("wells") / name if bare else None)
    if found is None:
        raise ValueError(f"scene key path.table: file {name!r} not found; looked for {looked}")
    return found


def scene_history(section, base_dir=None) -> TableHistory:
    """The burial path of a scene's ``[path]`` table of kind ``horizons`` or ``nodes``.

    Parameters
    ----------
    section : dict
        The validated ``[path]`` parameters of a scene.
    base_dir : str or Path, optional
        Folder of the scene file (a relative ``table`` is looked up there first).

    Raises
    ------
    ValueError
        Starting ``scene key path...``: the table given both as a file and inline, or not at
        all, and every error of :func:`read_history_table` and of
        :func:`burial.horizons.horizon_paths` / :func:`burial.horizons.shifted_path` (which name
        the row and the column).
    """
    from burial.horizons import horizon_paths, shifted_path

    kind = section["kind"]
    inline = [c for c in _COLUMNS[kind] if section.get(c) is not None]
    key = None
    if section.get("table") is not None:
        if inline:
            raise ValueError(f"scene key path.{inline[0]}: give the history either as "
                             "path.table or inline, not both")
        file = _resolve(section["table"], base_dir)
        stat = file.stat()
        key = (str(file.resolve()), stat.st_ino, stat.st_mtime_ns, stat.st_size, kind,
               section.get("depth_step"))
        if key in _READ:
            return _READ[key]
        columns = read_history_table(file, kind)
        where = f"scene key path.table ({file.name})"
    else:
        missing = [c for c in _COLUMNS[kind] if section.get(c) is None]
        if missing:
            raise ValueError(f"scene key path.{missing[0]} is required for kind = {kind!r} "
                             f"(or give path.table, a CSV file with columns "
                             f"{', '.join(_COLUMNS[kind])})")
        columns = {c: section[c] for c in _COLUMNS[kind]}
        where = "scene section [path] (inline arrays)"
    try:
        if kind == "horizons":
            h = horizon_paths(columns["horizon"], columns["time"], columns["depth"],
                              columns["temperature"])
            out = TableHistory(h.path, h.horizon)
        else:
            out = TableHistory(shifted_path(columns["time"], columns["depth"],
                                            columns["temperature"],
                                            depth_step=section.get("depth_step")), None)
    except ValueError as exc:
        raise ValueError(f"{where}: {exc}") from None
    if key is not None:
        # Validating a scene reads its table and running it needs the same history (twice
        # per sweep member): kept, read-only, while the file is unchanged.
        for arr in (out.path.time, out.path.depth, out.path.temperature, out.horizon):
            if arr is not None:
                arr.setflags(write=False)
        if len(_READ) >= 16:
            _READ.pop(next(iter(_READ)))
        _READ[key] = out
    return out
