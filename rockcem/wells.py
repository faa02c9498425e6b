"""Well logs: LAS 2.0 and CSV files read into an ``xarray.Dataset`` in the project's units.

:func:`read_well` returns the logs on one coordinate ``depth`` (m, increasing) with the variables
``vp``, ``vs`` (km/s), ``density`` (g/cm³) and ``porosity`` (fraction) that the file holds, named,
unit-labelled and described as in the variable registry, so that a log and a scene's Dataset can
be compared variable by variable.

Which curve is which: the first curve of :data:`ALIASES` present in the file, in the order
listed. Sonic logs are slownesses (``DT`` and friends) and become velocities,
:math:`v = 1/\\Delta t`: :math:`v\\,[\\mathrm{km/s}] = 304.8/\\Delta t\\,[\\mu s/ft]` (1 ft =
0.3048 m exactly) or :math:`1000/\\Delta t\\,[\\mu s/m]`. Neutron porosity (``NPHI``, ``TNPH``)
is an apparent porosity in the units of a calibration matrix; it is used only where no total
porosity curve is present, and the variable says so in its ``comment``.

Units come from the file: the ``~Curve`` section of a LAS file (for a depth curve without
one, the unit of ``STRT`` in ``~Well``), ``NAME (unit)`` or ``NAME [unit]`` column headers of
a CSV file. A curve that the reader uses and whose unit is
missing or not in :data:`UNITS` is an error — a log is never guessed to be in percent or in feet.
Null values (the LAS ``NULL``, default ``-999.25``) and empty CSV cells become NaN.
"""

from __future__ import annotations

import logging
import re
import warnings
from pathlib import Path

import numpy as np

from .validation import as_array, as_scalar, check_range

__all__ = ["ALIASES", "UNITS", "DEPTH_NAMES", "WELL_VARIABLES", "read_well", "read_las",
           "read_csv", "model_at_well", "well_misfit"]

#: Mnemonics of the depth (index) curve.
DEPTH_NAMES = ("DEPT", "DEPTH", "MD", "TVD")

#: Log mnemonics read for each variable, in order of preference, and the kind of each
#: (``slowness``, ``velocity``, ``density``, ``porosity``; ``neutron`` is porosity too).
ALIASES = {
    "vp": (("DT", "slowness"), ("DTC", "slowness"), ("DTCO", "slowness"), ("DT4P", "slowness"),
           ("DTP", "slowness"), ("AC", "slowness"), ("VP", "velocity"), ("PVEL", "velocity")),
    "vs": (("DTS", "slowness"), ("DTSM", "slowness"), ("DT4S", "slowness"),
           ("DTSH", "slowness"), ("VS", "velocity"), ("SVEL", "velocity")),
    "density": (("RHOB", "density"), ("RHOZ", "density"), ("DEN", "density"),
                ("DENS", "density"), ("RHO", "density")),
    "porosity": (("PHIT", "porosity"), ("PHI", "porosity"), ("POR", "porosity"),
                 ("TPOR", "porosity"), ("NPHI", "neutron"), ("TNPH", "neutron"),
                 ("NPOR", "neutron")),
}

#: Understood units (upper case, spaces removed, the micro sign ``µ`` or ``μ`` read as ``u``)
#: of each kind of curve, with the factor to the project's unit. Slownesses map to the factor
#: ``c`` of :math:`v = c/\Delta t` in km/s.
UNITS = {
    "depth": {"M": 1.0, "METER": 1.0, "METERS": 1.0, "METRE": 1.0, "METRES": 1.0,
              "FT": 0.3048, "F": 0.3048, "FEET": 0.3048, "FOOT": 0.3048},
    "slowness": {"US/FT": 304.8, "USEC/FT": 304.8, "US/F": 304.8, "US/M": 1000.0,
                 "USEC/M": 1000.0},
    "velocity": {"KM/S": 1.0, "M/S": 1e-3, "FT/S": 0.3048e-3},
    "density": {"G/CC": 1.0, "G/CM3": 1.0, "G/CM^3": 1.0, "GM/CC": 1.0, "G/C3": 1.0,
                "KG/M3": 1e-3, "KG/M^3": 1e-3},
    "porosity": {"V/V": 1.0, "FRAC": 1.0, "FRACTION": 1.0, "DEC": 1.0, "M3/M3": 1.0, "1": 1.0,
                 "%": 0.01, "PU": 0.01, "P.U.": 0.01},
}
UNITS["neutron"] = UNITS["porosity"]

_PROJECT_UNITS = {"depth": "m", "slowness": "km/s", "velocity": "km/s", "density": "g/cm3",
                  "porosity": "fraction", "neutron": "fraction"}
_RANGES = {"vp": (0.1, 10.0), "vs": (0.01, 7.0), "density": (0.5, 4.0),
           "porosity": (-0.15, 1.0)}


def _unit_key(unit) -> str:
    # The micro sign (U+00B5) and the Greek mu (U+03BC) both upper-case to U+039C: read as u.
    key = re.sub(r"\s+", "", str(unit or ""))
    return key.replace("\u00b5", "u").replace("\u03bc", "u").upper()


def _factor(where, kind, unit):
    key = _unit_key(unit)
    if not key:
        raise ValueError(f"{where}: no unit given; use one of {', '.join(UNITS[kind])}")
    if key not in UNITS[kind]:
        raise ValueError(f"{where}: unit {unit!r} is not understood for a {kind} curve; "
                         f"use one of {', '.join(UNITS[kind])}")
    return UNITS[kind][key]


def _numbers(where, values):
    """A curve as floats, or a ValueError naming the first value that is not a number."""
    try:
        return np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        arr = np.asarray(values, dtype=object).ravel()
        for row, value in enumerate(arr, 1):
            try:
                float(value)
            except (TypeError, ValueError):
                raise ValueError(f"{where}: {value!r} in data row {row} is not a "
                                 "number") from None
        raise


def _depth_offset(value):
    """``depth_offset`` as a finite number of metres no larger than the deepest basin."""
    from burial.path import MAX_DEPTH_M

    return check_range("depth_offset (m)", as_scalar("depth_offset", value), -MAX_DEPTH_M,
                       MAX_DEPTH_M)


def _dataset(source, columns, *, well="", null=-999.25, depth_offset=0.0):
    """The Dataset from ``columns = [(mnemonic, unit, values), ...]``, depth first."""
    from .variables import build_dataset

    name, depth_unit, depth = columns[0]
    if _unit_key(name) not in DEPTH_NAMES:
        raise ValueError(f"{source}: no depth curve: the first curve is {name!r}; it must be "
                         f"one of {', '.join(DEPTH_NAMES)}")
    depth = _numbers(f"{source}: depth curve {name!r}", depth)
    if depth.size == 0:
        raise ValueError(f"{source}: no data rows")
    if not np.all(np.isfinite(depth)) or np.any(depth == null):
        row = int(np.flatnonzero(~np.isfinite(depth) | (depth == null))[0])
        raise ValueError(f"{source}: depth curve {name!r} has no value in data row {row + 1}")
    depth = depth * _factor(f"{source}: depth curve {name!r}", "depth", depth_unit) \
        - _depth_offset(depth_offset)
    order = np.argsort(depth, kind="stable")
    depth = depth[order]
    if np.any(np.diff(depth) <= 0.0):
        k = int(np.flatnonzero(np.diff(depth) <= 0.0)[0]) + 1
        row = int(order[k])
        raise ValueError(f"{source}: depth {depth[k]:g} m repeats "
                         f"(data row {row + 1}); depths must be distinct")
    found = {}
    for n, u, v in columns[1:]:                   # lasio names a repeated DT "DT:1", "DT:2"
        found.setdefault(_unit_key(re.sub(r":\d+$", "", str(n))), []).append((n, u, v))
    data = {}
    for var, names in ALIASES.items():
        hit = next(((m, kind) for m, kind in names if m in found), None)
        if hit is None:
            continue
        mnemonic, kind = hit
        if len(found[mnemonic]) > 1:
            raise ValueError(f"{source}: curve {mnemonic} appears {len(found[mnemonic])} times "
                             f"({', '.join(c[0] for c in found[mnemonic])}); keep the one to "
                             "use")
        label, unit, values = found[mnemonic][0]
        where = f"{source}: curve {label!r}"
        factor = _factor(where, kind, unit)
        raw = _numbers(where, values)[order]
        raw = np.where(raw == null, np.nan, raw)
        if kind == "slowness":
            if np.any(raw <= 0.0):
                bad = int(order[np.flatnonzero(raw <= 0.0)[0]])
                raise ValueError(f"{where}: slowness {raw[raw <= 0.0][0]:g} {unit} in data "
                                 f"row {bad + 1} is not > 0")
            value = factor / raw
        else:
            value = factor * raw
        lo, hi = _RANGES[var]
        outside = np.isfinite(value) & ((value < lo) | (value > hi))
        if np.any(outside):
            bad = int(order[np.flatnonzero(outside)[0]])
            raise ValueError(f"{where}: {var} {value[outside][0]:g} "
                             f"{_PROJECT_UNITS[kind]} in data row {bad + 1} lies outside "
                             f"[{lo:g}, {hi:g}]; is the unit {unit!r} right?")
        attrs = {"source_mnemonic": label, "source_units": str(unit)}
        if kind == "neutron":
            attrs["comment"] = ("neutron porosity (apparent, in the units of the tool's "
                                "calibration matrix); no total-porosity curve in the file")
        data[var] = (("depth",), value, attrs)
    if not data:
        names = ", ".join(m for v in ALIASES.values() for m, _ in v)
        raise ValueError(f"{source}: no curve to read; known mnemonics: {names}")
    ds = build_dataset({k: v[:2] for k, v in data.items()}, {"depth": (("depth",), depth)},
                       {"title": f"well {well}".strip(), "well": str(well),
                        "source_file": str(source), "depth_offset_m": float(depth_offset),
                        "source_depth_curve": f"{name} ({depth_unit})"})
    for k, v in data.items():
        ds[k].attrs.update(v[2])
    return ds


def _ascii_rows(text, n_curves, source):
    """Check that every line of the ~A section holds one value per curve (no wrapped lines)."""
    lines = text.splitlines()
    start = next((i for i, line in enumerate(lines) if line.lstrip().upper().startswith("~A")),
                 None)
    if start is None:
        raise ValueError(f"{source}: no ~A (data) section")
    for i, line in enumerate(lines[start + 1:], start + 2):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if stripped.startswith("~"):
            break
        count = len(stripped.replace(",", " ").split())
        if count != n_curves:
            raise ValueError(f"{source}: line {i} has {count} values, the ~Curve section lists "
                             f"{n_curves} curves (a wrapped or truncated line)")


def read_las(path, *, depth_offset=0.0):
    """Read a LAS 2.0 file (unwrapped) with ``lasio``; see :func:`read_well`."""
    import lasio

    path = Path(path)
    source = path.name
    if not path.is_file():
        raise ValueError(f"well file {str(path)!r} not found")
    text = path.read_text(errors="replace")
    if re.search(r"^\s*WRAP\s*\.\s*YES\b", text, flags=re.IGNORECASE | re.MULTILINE):
        raise ValueError(f"{source}: wrapped LAS (WRAP. YES) is not read; write it unwrapped "
                         "(lasio: las.write(file, wrap=False))")
    log = logging.getLogger("lasio")
    level = log.level
    log.setLevel(logging.CRITICAL)          # lasio logs what it skips; our errors say it once
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            las = lasio.read(str(path), ignore_header_errors=False)
    except Exception as exc:                # lasio raises KeyError, LASHeaderError, ...
        raise ValueError(f"{source} is not a readable LAS file: {str(exc).strip()}") from None
    finally:
        log.setLevel(level)
    version = las.version.get("VERS")
    if version is None or not str(version.value).strip().startswith("2"):
        given = "none" if version is None else str(version.value).strip()
        raise ValueError(f"{source}: LAS version {given}; only LAS 2.0 is read")
    if not las.curves:
        raise ValueError(f"{source}: no curves")
    _ascii_rows(text, len(las.curves), source)
    null = las.well.get("NULL")
    null = float(null.value) if null is not None and str(null.value).strip() else -999.25
    well = las.well.get("WELL")
    columns = [(c.mnemonic, c.unit, c.data) for c in las.curves]
    start = las.well.get("STRT")
    if not str(columns[0][1] or "").strip() and start is not None and str(start.unit).strip():
        columns[0] = (columns[0][0], start.unit, columns[0][2])    # depth unit from ~Well STRT
    return _dataset(source, columns, well=getattr(well, "value", "") or "", null=null,
                    depth_offset=depth_offset)


def _csv_rows(path, source):
    """Check that every data line of a CSV log has as many fields as its header (pandas
    would take a first extra field for a row label, or fill a short line with NaN)."""
    import csv

    try:
        with open(path, newline="", encoding="utf-8") as fh:
            lines = [(i, row) for i, row in enumerate(csv.reader(
                line.partition("#")[0] for line in fh), 1) if any(f.strip() for f in row)]
    except UnicodeDecodeError as exc:
        raise ValueError(f"{source} is not a readable CSV file: {str(exc).strip()}") from None
    if not lines:
        raise ValueError(f"{source}: empty file")
    width = len(lines[0][1])
    for i, row in lines[1:]:
        if len(row) != width:
            raise ValueError(f"{source}: line {i} has {len(row)} fields, the header "
                             f"{width} (a wrapped or truncated line)")


_HEADER = re.compile(r"^\s*([^\s(\[]+)\s*(?:[(\[]\s*([^)\]]*?)\s*[)\]])?\s*$")


def read_csv(path, *, null=-999.25, depth_offset=0.0):
    """Read a CSV well log, units in the header (``DEPT (ft),DT (us/ft),RHOB (g/cc)``);
    see :func:`read_well`."""
    import pandas as pd

    path = Path(path)
    source = path.name
    if not path.is_file():
        raise ValueError(f"well file {str(path)!r} not found")
    _csv_rows(path, source)
    try:
        table = pd.read_csv(path, comment="#", skipinitialspace=True, index_col=False)
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise ValueError(f"{source} is not a readable CSV file: {str(exc).strip()}") from None
    columns = []
    for j, header in enumerate(table.columns):
        match = _HEADER.match(str(header))
        if match is None:
            raise ValueError(f"{source}: column {j + 1} header {header!r} is not 'NAME' or "
                             "'NAME (unit)'")
        # Converted to numbers only if used (a text column such as a lithology is skipped).
        columns.append((match.group(1), match.group(2) or "", table[header].to_numpy()))
    if not columns:
        raise ValueError(f"{source}: no columns")
    return _dataset(source, columns, null=null, depth_offset=depth_offset)


def read_well(path, *, depth_offset=0.0, null=-999.25):
    r"""Read a well log (LAS 2.0 or CSV) into the project's units.

    Parameters
    ----------
    path : str or Path
        A ``.las`` file (LAS 2.0, unwrapped; the first curve is the depth) or a ``.csv`` file
        (first column the depth; headers ``NAME (unit)`` or ``NAME [unit]``; ``#`` comments).
    depth_offset : float, keyword-only
        m, subtracted from the log depth to give depth below the sediment surface, the depth of
        the scenes (e.g. the kelly-bushing height plus the water depth), finite, in
        [-:data:`burial.path.MAX_DEPTH_M`, :data:`burial.path.MAX_DEPTH_M`]. Default 0. The depth
        curve is taken as true vertical depth: the measured depth (``MD``) of a deviated well
        must be converted first.
    null : float, keyword-only
        Null value of a CSV file (default ``-999.25``, the LAS convention); a LAS file gives
        its own (``NULL`` in ``~Well``).

    Returns
    -------
    xarray.Dataset
        Coordinate ``depth`` (m, increasing); of ``vp``, ``vs`` (km/s), ``density`` (g/cm³) and
        ``porosity`` (fraction) those the file has (:data:`ALIASES`), NaN where the log is null.
        Each variable records ``source_mnemonic`` and ``source_units``.

    Raises
    ------
    ValueError
        One line naming the file and what is wrong: no depth curve, a unit not in
        :data:`UNITS` or missing, a wrapped or truncated line, a repeated depth, a slowness
        ``<= 0``, a value outside the plausible range of its variable (a sign of a wrong unit),
        no known curve.

    Examples
    --------
    A CSV log in feet and µs/ft:

    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "log.csv"
    >>> _ = f.write_text("DEPT (ft),DT (us/ft)\n1000,100\n2000,80\n")
    >>> ds = read_well(f)
    >>> ds.depth.values.tolist(), ds.vp.values.tolist()
    ([304.8, 609.6], [3.048, 3.81])
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix == ".las":
        return read_las(path, depth_offset=depth_offset)
    if suffix in (".csv", ".txt"):
        return read_csv(path, null=null, depth_offset=depth_offset)
    raise ValueError(f"well file {path.name!r}: unknown format {path.suffix!r}; give a .las "
                     "(LAS 2.0) or .csv file")


#: Variables a well and a scene share, in the order they are compared.
WELL_VARIABLES = ("vp", "vs", "density", "porosity")


def model_at_well(ds, well, name):
    """Scene variable ``name`` at the well's depths, linear in depth between scene depths.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset (dimension ``depth``, optional ``model``; no sweep dimensions).
    well : xarray.Dataset
        From :func:`read_well`.
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


def _point_misfit(ds, values, log, points):
    """Relative misfit m/o - 1 at each of ``points``, o the mean of the log within half a
    scene depth step (NaN where the log has no finite sample there)."""
    z = log.depth.values
    half = 0.5 * float(np.median(np.diff(ds.depth.values)))    # >= 2 depths: checked above
    out = np.full(points.size, np.nan)
    for k, p in enumerate(points):
        near = log.values[(z >= p - half) & (z <= p + half)]
        near = near[np.isfinite(near)]
        if near.size:
            out[k] = float(values.sel(depth=p)) / near.mean() - 1.0
    return out


def well_misfit(ds, well, *, intervals=None, variables=None):
    r"""Misfit of each model to a well log in each depth interval.

    For every variable both hold (:data:`WELL_VARIABLES`), every model (model-independent
    variables under the label ``"-"``) and every interval ``[top, base)``: the number of log
    samples ``n`` with a finite value inside the scene's depth range, the root-mean-square
    relative misfit :math:`\sqrt{\overline{(m/o - 1)^2}}` and the mean relative bias
    :math:`\overline{m/o - 1}` (:math:`m` the model at the log's depths, linear between scene
    depths; :math:`o` the log). The last interval includes its base. An MD member (``md``,
    ``md_<scheme>``: valued at its own depths, NaN elsewhere) is compared point by point: at each of
    its depths :math:`o` is the mean of the log's samples within half a scene depth step of it
    (the depth a continuous model's sample stands for), and ``n`` counts those depths.

    Parameters
    ----------
    ds : xarray.Dataset
        Scene Dataset without sweep dimensions.
    well : xarray.Dataset
        From :func:`read_well`.
    intervals : sequence of float, optional
        Interval boundaries, m, finite and increasing (``[1000, 2000, 3000]`` gives two
        intervals).
        Default: one interval over the depths both cover.
    variables : sequence of str, optional
        Default: all shared ones.

    Returns
    -------
    pandas.DataFrame
        Columns ``variable``, ``model``, ``top``, ``base``, ``n``, ``rms``, ``bias``.
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
    z = well.depth.values
    rows = []
    for name in shared:
        modelled = model_at_well(ds, well, name)
        labels = modelled.model.values.tolist() if "model" in modelled.dims else ["-"]
        for label in labels:
            own = ds[name].sel(model=label) if label != "-" else ds[name]
            points = _sparse_points(ds, own) if _is_md(label) else None
            if points is not None:          # a model at a few depths (the MD backend)
                zz, rel = points, _point_misfit(ds, own, well[name], points)
            else:
                m = modelled.sel(model=label).values if label != "-" else modelled.values
                zz, rel = z, m / well[name].values - 1.0
            for k, (top, base) in enumerate(zip(edges[:-1], edges[1:])):
                below = (zz <= base) if k == edges.size - 2 else (zz < base)
                sel = (zz >= top) & below & np.isfinite(rel)
                n = int(sel.sum())
                rows.append({"variable": name, "model": label, "top": top, "base": base,
                             "n": n,
                             "rms": float(np.sqrt(np.mean(rel[sel] ** 2))) if n else np.nan,
                             "bias": float(np.mean(rel[sel])) if n else np.nan})
    return pd.DataFrame(rows)
