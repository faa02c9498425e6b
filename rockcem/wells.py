"""Well logs: LAS and CSV files read into an ``xarray.Dataset`` in the project's units.

:func:`read_well` returns the logs on one coordinate ``depth`` (m, increasing) with the variables
``vp``, ``vs`` (km/s), ``density`` (g/cm³) and ``porosity`` (fraction) that the file holds, named,
unit-labelled and described as in the variable registry, so that a log and a scene's Dataset can
be compared variable by variable (:func:`well_misfit`).

Parsing is ``lasio``'s: every LAS file it reads (versions 1.2, 2.0 and 3.0, wrapped or not, data
delimited by spaces, tabs or commas) is read here. This module chooses the curves, reads their
units and null values, checks the samples, and records what it did in a read report.

Which curve is which: the first mnemonic of :data:`ALIASES` present in the file with a unit
understood for its variable (a repeated mnemonic, which lasio names ``DT:1``, ``DT:2``, is not
chosen silently), unless ``curves=`` names one. Sonic logs are slownesses (``DT`` and friends)
and become velocities, :math:`v = 1/\\Delta t`: :math:`v\\,[\\mathrm{km/s}] = 304.8/\\Delta t\\,
[\\mu s/ft]` (1 ft = 0.3048 m exactly) or :math:`1000/\\Delta t\\,[\\mu s/m]`; a velocity curve
(unit ``m/s``, ``km/s``, ``ft/s``) is used as it is. A neutron porosity (``NPHI`` ...; units
``LPU``, ``SPU``, ``DPU`` are percent in limestone, sandstone, dolomite units) or a density
porosity (``DPHI`` ...) is an *apparent* porosity, in the units of a calibration matrix; it is used
only where no total-porosity curve is present, and the variable says so (``long_name``,
``comment``, ``log_label``).

Checks, in the project's units (:data:`RANGES`):

- A single bad sample (not a number, an undeclared null such as ``-9999``, a slowness, velocity
  or density ``<= 0``, a P velocity slower than water at 0 °C, 1.40 km/s, any value outside the
  range of its variable, such as a washout spike of RHOB 4.07 g/cm³) becomes NaN; a
  :class:`WellLogWarning` counts them per curve, and the report says why, with the first such
  sample.
- A curve is refused (``ValueError`` naming the file, curve, unit and what its median implies)
  only when its bulk says the unit is wrong: the median of its valid samples lies outside the
  range, as for DT in µs/m labelled µs/ft (median Vp below 1.4 km/s), or a porosity in percent
  has 95 % of its samples below 0.5 (a fraction).
- A curve the user did not name (``curves=``) never stops a read: a missing or unknown unit, or a
  repeated mnemonic, leaves its variable out, with a note in the report and a warning.

Units come from the file: the ``~Curve`` section of a LAS file (for a depth curve without one,
the unit of ``STRT`` in ``~Well``), ``NAME (unit)`` or ``NAME [unit]`` column headers of a CSV
file; a log is never guessed to be in percent or in feet. Null values: the LAS ``NULL`` (else
``-999.25``), empty CSV cells and ``-999.25`` in a CSV file, and whatever ``null=`` adds.

The read report (:func:`format_read_report`) is in the Dataset's attribute ``read_report``, a JSON
string: the file, its LAS version, wrapping and delimiter, the null values, the depth curve and
rows dropped for want of a depth, and per variable the mnemonic, unit, samples kept, null and
blanked, and why.

Shipped wells (``datasets/wells/*.las``) are read by name from any folder:
``read_well("synthetic_well")`` (:func:`shipped_wells`).

A LAS file of thousands of curves is slow to read, by lasio (0.32): each header item is checked
against every earlier one for a repeated mnemonic, each curve's data is looked up by a scan of
the curves and formatted for a debug message, so the time grows with the square of the curves
(37 s for the ``~Curve`` section of 5000 curves alone, over 120 s for the file of 200 rows on
the 2-core test machine, where pandas reads its data in 1.3 s); this module parses the header
twice (the curves, then the data), no lasio setting avoids the rest. Such a file is read far
faster written as CSV (``benchmarks/results/hostile_inputs_30.md``, ``w_las_5000``).
"""

from __future__ import annotations

import json
import warnings
from pathlib import Path

import numpy as np

# The module is split by concept (DESIGN): curves, units and checks (_well_curves), the file
# formats (_well_files) and the misfit (_well_misfit); their public names are re-exported here.
from ._well_curves import (
    ALIASES,
    DEPTH_NAMES,
    RANGES,
    UNITS,
    WELL_VARIABLES,
    _base,
    _check_curve,
    _choose,
    _label,
    _null_values,
    _unit_key,
)
from ._well_files import _as_float, _Csv, _Las
from ._well_misfit import MISFIT, model_at_well, well_misfit
from .validation import as_scalar, check_range

__all__ = ["ALIASES", "DEPTH_NAMES", "MISFIT", "RANGES", "UNITS", "WELL_VARIABLES",
           "WellLogWarning", "format_read_report", "model_at_well", "read_csv", "read_las",
           "read_well", "shipped_wells", "well_misfit", "well_path"]


class WellLogWarning(UserWarning):
    """Samples blanked, or a curve left out, while reading a well log."""


# ----------------------------------------------------------------------------- reading
def _depth_offset(value):
    """``depth_offset`` as a finite number of metres no larger than the deepest basin."""
    from burial.path import MAX_DEPTH_M

    return check_range("depth_offset (m)", as_scalar("depth_offset", value), -MAX_DEPTH_M,
                       MAX_DEPTH_M)


def _read(src, *, null=None, curves=None, depth_offset=0.0):
    """The Dataset of a source (:class:`rockcem._well_files._Las`, ``_Csv``)."""
    from .variables import build_dataset

    source = src.source
    offset = _depth_offset(depth_offset)
    extra = _null_values(null)
    nulls = list(dict.fromkeys(src.nulls + extra))
    name, zunit = src.curves[0]
    if _base(name) not in DEPTH_NAMES:
        raise ValueError(f"{source}: no depth curve: the first curve is {name!r}; it must be "
                         f"one of {', '.join(DEPTH_NAMES)}")
    if not _unit_key(zunit):
        raise ValueError(f"{source}: depth curve {name!r}: no unit given; use one of "
                         f"{', '.join(UNITS['depth'])}")
    if _unit_key(zunit) not in UNITS["depth"]:
        raise ValueError(f"{source}: depth curve {name!r}: unit {zunit!r} is not understood; "
                         f"use one of {', '.join(UNITS['depth'])}")
    zfactor = UNITS["depth"][_unit_key(zunit)]
    chosen, notes = _choose(source, src.curves, curves)
    if not chosen:
        why = "; ".join(f"{n['variable']}: {n['note']}" for n in notes)
        known = ", ".join(m for v in ALIASES.values() for m in v)
        raise ValueError(f"{source}: no curve to read" + (f" ({why})" if why else
                                                           f"; known mnemonics: {known}"))
    indices = [0] + [c[0] for c in chosen.values()]
    data = src.columns(list(dict.fromkeys(indices)))
    data = dict(zip(dict.fromkeys(indices), data))
    zraw = _as_float(data[0])[0]
    if zraw.size == 0:
        raise ValueError(f"{source}: no data rows")
    nodepth = ~np.isfinite(zraw) | np.isin(zraw, nulls)
    report = {"file": source, "format": src.describe(), "well": src.well,
              "rows": int(zraw.size), "null_values": nulls,
              "depth": {"mnemonic": str(name), "unit": str(zunit),
                        "rows_without_depth": int(nodepth.sum())},
              "depth_offset_m": offset, "curves": []}
    messages = []
    if nodepth.all():
        raise ValueError(f"{source}: depth curve {name!r} has no value in any data row")
    if nodepth.any():
        line = src.lines([int(np.flatnonzero(nodepth)[0])])[0]
        messages.append(f"{int(nodepth.sum())} data rows without a depth left out (the first "
                        f"on line {line})")
        report["depth"]["first_without_depth_line"] = line
    keep = np.flatnonzero(~nodepth)
    depth = zraw[keep] * zfactor - offset
    order = np.argsort(depth, kind="stable")              # equal depths: file order
    repeat = np.zeros(keep.size, dtype=bool)
    repeat[order[1:]] = np.diff(depth[order]) <= 0.0
    if repeat.any():
        n = int(repeat.sum())
        r0 = int(np.flatnonzero(repeat)[0])
        first = int(keep[r0])
        earlier = int(keep[order[int(np.flatnonzero(order == r0)[0]) - 1]])
        lines = src.lines([earlier, first])
        if 2 * n > keep.size:
            raise ValueError(f"{source}: depth curve {name!r} is not an index: {n} of "
                             f"{keep.size} rows repeat a depth (as {zraw[first]:g} {zunit} on "
                             f"lines {lines[0]} and {lines[1]})")
        messages.append(f"{n} data rows repeating an earlier depth left out (the first: "
                        f"{zraw[first]:g} {zunit} on line {lines[1]}, as on line {lines[0]})")
        report["depth"]["rows_repeating_a_depth"] = n
        report["depth"]["first_repeat_line"] = lines[1]
        keep = keep[~repeat]
        depth = depth[~repeat]
        order = np.argsort(depth, kind="stable")
    depth = depth[order]
    variables, attrs = {}, {}
    for note in notes:
        report["curves"].append(note)
        if note["status"] == "left out" and note["note"] != "curves= says so":
            messages.append(f"{note['variable']} left out: {note['note']}")
    for var, (i, mnemonic, unit, kind, factor) in chosen.items():
        raw, text = _as_float(data[i])
        raw, text = raw[keep], text[keep]
        value, entry = _check_curve(source, var, mnemonic, unit, kind, factor, raw, text,
                                    nulls, zraw[keep], zunit)
        report["curves"].append(entry)
        blanked = sum(r["count"] for r in entry.get("blanked", {}).values())
        if blanked:
            why = ", ".join(f"{r['count']} {reason} (first {r['first']})"
                            for reason, r in entry["blanked"].items())
            messages.append(f"{mnemonic} ({unit}): {blanked} of {raw.size} samples blanked: "
                            f"{why}" + (f"; {entry['note']}" if "note" in entry else ""))
        if value is None:
            messages.append(f"{var} left out: {mnemonic} has no valid sample")
            continue
        long_name, log_label, comment = _label(var, mnemonic, unit)
        variables[var] = (("depth",), value[order])
        attrs[var] = {"source_mnemonic": mnemonic, "source_units": str(unit),
                      "log_label": log_label, "samples_blanked": int(blanked)}
        if long_name:
            attrs[var]["long_name"] = long_name
        if comment:
            attrs[var]["comment"] = comment
    if not variables:
        raise ValueError(f"{source}: no curve to read: " + "; ".join(
            f"{e['variable']} {e.get('mnemonic', '')}: {e.get('note', '')}"
            for e in report["curves"]))
    report["curves"].sort(key=lambda e: WELL_VARIABLES.index(e["variable"]))
    ds = build_dataset(variables, {"depth": (("depth",), depth)},
                       {"title": f"well {src.well}".strip(), "well": src.well,
                        "source_file": source, "depth_offset_m": offset,
                        "source_depth_curve": f"{name} ({zunit})",
                        "read_report": json.dumps(report)})
    for k, v in attrs.items():
        ds[k].attrs.update(v)
    for message in messages:
        warnings.warn(f"{source}: {message}", WellLogWarning, stacklevel=3)
    return ds


def read_las(path, *, depth_offset=0.0, null=None, curves=None):
    """Read a LAS file (any version and layout lasio reads); see :func:`read_well`."""
    path = well_path(path)
    return _read(_Las(path), null=null, curves=curves, depth_offset=depth_offset)


def read_csv(path, *, depth_offset=0.0, null=None, curves=None):
    """Read a CSV well log, units in the header (``DEPT (ft),DT (us/ft),RHOB (g/cc)``);
    see :func:`read_well`."""
    path = well_path(path)
    return _read(_Csv(path), null=null, curves=curves, depth_offset=depth_offset)


def shipped_wells() -> dict[str, Path]:
    """The LAS files shipped in ``datasets/wells/``: ``{name: path}`` (the name is the file
    name without ``.las``)."""
    from ._data import data_path

    return {p.stem: p for p in sorted(data_path("wells").glob("*.las"))}


def well_path(source) -> Path:
    """The file of a well: a path, or a shipped well's name (``synthetic_well``, with or
    without ``.las``, or as ``datasets/wells/<name>.las`` from any folder)."""
    path = Path(source)
    if path.is_file():
        return path
    if path.is_dir():
        raise ValueError(f"well file {str(source)!r} is a folder, not a file")
    parent = path.parent.parts
    if not parent or parent[-2:] == ("datasets", "wells"):
        shipped = shipped_wells()
        stem = path.stem if path.suffix.lower() == ".las" else path.name
        if stem in shipped:
            return shipped[stem]
    import difflib

    names = list(shipped_wells())
    close = difflib.get_close_matches(path.stem, names, n=1, cutoff=0.6)
    hint = f"; did you mean {close[0]}?" if close else \
        f"; shipped wells: {', '.join(names)}" if not parent else ""
    raise ValueError(f"well file {str(source)!r} not found{hint}")


def read_well(path, *, depth_offset=0.0, null=None, curves=None):
    r"""Read a well log (LAS or CSV) into the project's units, with a report of what was read.

    Parameters
    ----------
    path : str or Path
        A ``.las`` file (any LAS version and layout lasio reads: 1.2, 2.0, 3.0, wrapped or
        not, space-, tab- or comma-delimited; the first curve is the depth), a ``.csv`` file
        (first column the depth; headers ``NAME (unit)`` or ``NAME [unit]``; ``#`` comments),
        or the name of a shipped well (:func:`shipped_wells`), found from any folder.
    depth_offset : float, keyword-only
        m, subtracted from the log depth to give depth below the sediment surface, the depth of
        the scenes (e.g. the kelly-bushing height plus the water depth), finite, in
        [-:data:`burial.path.MAX_DEPTH_M`, :data:`burial.path.MAX_DEPTH_M`]. Default 0. The depth
        curve is taken as true vertical depth: the measured depth (``MD``) of a deviated well
        must be converted first.
    null : float or sequence of float, optional, keyword-only
        Null values besides the file's own (the LAS ``NULL`` of ``~Well``, ``-999.25`` where
        there is none; ``-999.25`` and empty cells in a CSV file), e.g. ``-9999`` for data
        written with -9999 under a header that says -999.25.
    curves : mapping, optional, keyword-only
        ``{variable: mnemonic}`` overriding the choice by :data:`ALIASES` (``{"vp": "DTCO"}``;
        a repeated mnemonic as lasio names it, ``"DT:2"``), or ``{variable: None}`` to leave a
        variable out. Variables: ``vp``, ``vs`` (a slowness or a velocity, by its unit),
        ``density``, ``porosity``. A named curve must exist and have a unit understood for its
        variable (:data:`UNITS`); a curve chosen by the aliases whose unit is missing or not
        understood is passed over (the next alias is tried), with a note in the report.

        Aliases, in order of preference: vp ``DT, DTC, DTCO, DT4P, DTP, AC, ACTC, VP, PVEL``;
        vs ``DTS, DTSM, DT4S, DTSH, VS, SVEL``; density ``RHOB, RHOZ, ZDEN, DEN, DENS, RHO``;
        porosity ``PHIT, PHI, POR, TPOR``, then neutron ``NPHI, TNPH, NPOR, NPHI_SAN, NPHS,
        NPHI_LIM, NPHL, NPHI_DOL, NPHD, CN``, then density porosity ``DPHI, DPHI_SAN, DPHS,
        DPHI_LIM, DPHL, DPHI_DOL, DPHD`` (both apparent porosities).

    Returns
    -------
    xarray.Dataset
        Coordinate ``depth`` (m, increasing); of ``vp``, ``vs`` (km/s), ``density`` (g/cm³) and
        ``porosity`` (fraction) those the file has, NaN where the log is null or a sample was
        blanked. Each variable records ``source_mnemonic``, ``source_units``, ``log_label``
        and ``samples_blanked``; an apparent porosity says so in ``long_name`` and
        ``comment``. Attribute ``read_report``: the read report as JSON
        (:func:`format_read_report`).

    Warns
    -----
    WellLogWarning
        Samples blanked (per curve: how many and why), a variable left out (a curve with no
        valid sample, or whose unit is not understood), rows without a depth left out.

    Raises
    ------
    ValueError
        One line naming the file and what is wrong: no depth curve, or a depth unit not in
        :data:`UNITS`; a curve named in ``curves`` that is missing or whose unit is not
        understood; a curve whose median says its unit is wrong (and what the median implies);
        a repeated depth (naming both lines of the file); a truncated data line; no curve to
        read.

    Examples
    --------
    A CSV log in feet and µs/ft:

    >>> import tempfile, pathlib
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "log.csv"
    >>> _ = f.write_text("DEPT (ft),DT (us/ft)\n1000,100\n2000,80\n")
    >>> ds = read_well(f)
    >>> ds.depth.values.tolist(), ds.vp.values.tolist()
    ([304.8, 609.6], [3.048, 3.81])
    >>> print(format_read_report(ds))                      # doctest: +NORMALIZE_WHITESPACE
    log.csv (CSV): 2 rows; depth DEPT (ft); nulls -999.25
      vp        DT (us/ft)  kept 2 of 2
    """
    if Path(path).suffix.lower() not in ("", ".las", ".csv", ".txt"):
        raise ValueError(f"well file {Path(path).name!r}: unknown format {Path(path).suffix!r};"
                         " give a .las or .csv file")
    path = well_path(path)
    suffix = path.suffix.lower()
    if suffix == ".las":
        return _read(_Las(path), null=null, curves=curves, depth_offset=depth_offset)
    if suffix in (".csv", ".txt"):
        return _read(_Csv(path), null=null, curves=curves, depth_offset=depth_offset)
    raise ValueError(f"well file {path.name!r}: unknown format {path.suffix!r}; give a .las "
                     "or .csv file")


def format_read_report(report) -> str:
    """The read report of :func:`read_well` as text: a line for the file, one per variable.

    Parameters
    ----------
    report : xarray.Dataset, str or dict
        A Dataset from :func:`read_well`, its ``read_report`` attribute, or that parsed.
    """
    if hasattr(report, "attrs"):
        report = report.attrs.get("read_report", "{}")
    if isinstance(report, str):
        report = json.loads(report)
    if not report:
        return "no read report"
    depth = report["depth"]
    well = f" well {report['well']}," if report.get("well") else ""
    nulls = ", ".join(f"{v:g}" for v in report["null_values"])
    first = (f"{report['file']} ({report['format']}):{well} {report['rows']} rows; depth "
             f"{depth['mnemonic']} ({depth['unit']}); nulls {nulls}")
    lines = [first]
    if depth.get("rows_without_depth"):
        lines[0] += f"; {depth['rows_without_depth']} rows without a depth left out"
    if depth.get("rows_repeating_a_depth"):
        lines[0] += (f"; {depth['rows_repeating_a_depth']} rows repeating an earlier depth "
                     f"left out (the first on line {depth.get('first_repeat_line')})")
    if report.get("depth_offset_m"):
        lines[0] += f"; depth offset {report['depth_offset_m']:g} m"
    for e in report["curves"]:
        what = f"{e['mnemonic']} ({e['unit']})" if "mnemonic" in e else "-"
        head = f"  {e['variable']:<9} {what}"
        if e["status"] in ("read", "left out") and "samples" in e:
            text = f"kept {e['kept']} of {e['samples']}"
            if e["null"]:
                text += f", null {e['null']}"
            blanked = e.get("blanked", {})
            if blanked:
                text += f", blanked {sum(r['count'] for r in blanked.values())}: " + "; ".join(
                    f"{r['count']} {reason} (first {r['first']})" for reason, r in
                    blanked.items())
            if e["status"] == "left out":
                text += f"; left out: {e.get('note', '')}"
            elif e.get("note"):
                text += f"; {e['note']}"
            lines.append(f"{head}  {text}")
        else:
            lines.append(f"{head}  {e['status']}: {e.get('note', '')}")
    return "\n".join(lines)
