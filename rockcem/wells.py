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
"""

from __future__ import annotations

import itertools
import json
import logging
import re
import warnings
from pathlib import Path

import numpy as np

from .validation import as_array, as_scalar, check_range

__all__ = ["ALIASES", "DEPTH_NAMES", "MISFIT", "RANGES", "UNITS", "WELL_VARIABLES",
           "WellLogWarning", "format_read_report", "model_at_well", "read_csv", "read_las",
           "read_well", "shipped_wells", "well_misfit", "well_path"]


class WellLogWarning(UserWarning):
    """Samples blanked, or a curve left out, while reading a well log."""


#: Mnemonics of the depth (index) curve, the first curve of a file.
DEPTH_NAMES = ("DEPT", "DEPTH", "MD", "TVD")

#: Log mnemonics read for each variable, in order of preference. Whether a sonic curve is a
#: slowness or a velocity follows from its unit.
ALIASES = {
    "vp": ("DT", "DTC", "DTCO", "DT4P", "DTP", "AC", "ACTC", "VP", "PVEL"),
    "vs": ("DTS", "DTSM", "DT4S", "DTSH", "VS", "SVEL"),
    "density": ("RHOB", "RHOZ", "ZDEN", "DEN", "DENS", "RHO"),
    "porosity": ("PHIT", "PHI", "POR", "TPOR",                          # total porosity
                 "NPHI", "TNPH", "NPOR", "NPHI_SAN", "NPHS", "NPHI_LIM", "NPHL", "NPHI_DOL",
                 "NPHD", "CN",                                          # neutron (apparent)
                 "DPHI", "DPHI_SAN", "DPHS", "DPHI_LIM", "DPHL", "DPHI_DOL", "DPHD"),  # density
}

#: Understood units (upper case, spaces removed, the micro sign ``µ`` or ``μ`` read as ``u``)
#: of each kind of curve, with the factor to the project's unit. Slownesses map to the factor
#: ``c`` of :math:`v = c/\Delta t` in km/s. ``.1IN`` is the LAS depth unit of a tenth of an
#: inch; ``LPU``, ``SPU``, ``DPU`` are porosity percent in limestone, sandstone, dolomite units;
#: ``DECP`` and ``CFCF`` are fractions.
UNITS = {
    "depth": {"M": 1.0, "METER": 1.0, "METERS": 1.0, "METRE": 1.0, "METRES": 1.0,
              "FT": 0.3048, "F": 0.3048, "FEET": 0.3048, "FOOT": 0.3048,
              ".1IN": 0.00254, "0.1IN": 0.00254, "IN": 0.0254},
    "slowness": {"US/FT": 304.8, "USEC/FT": 304.8, "US/F": 304.8, "USEC/F": 304.8,
                 "US/FOOT": 304.8, "US/M": 1000.0, "USEC/M": 1000.0},
    "velocity": {"KM/S": 1.0, "KM/SEC": 1.0, "M/S": 1e-3, "M/SEC": 1e-3,
                 "FT/S": 0.3048e-3, "F/S": 0.3048e-3, "FT/SEC": 0.3048e-3},
    "density": {"G/CC": 1.0, "G/CM3": 1.0, "G/CM^3": 1.0, "G/CM**3": 1.0, "GM/CC": 1.0,
                "G/C3": 1.0, "GR/CC": 1.0, "GRM/CC": 1.0, "GM/CM3": 1.0,
                "KG/M3": 1e-3, "KG/M^3": 1e-3, "K/M3": 1e-3},
    "porosity": {"V/V": 1.0, "FRAC": 1.0, "FRACTION": 1.0, "DEC": 1.0, "DECP": 1.0,
                 "M3/M3": 1.0, "FT3/FT3": 1.0, "CFCF": 1.0, "VOL/VOL": 1.0, "1": 1.0,
                 "%": 0.01, "PU": 0.01, "P.U.": 0.01, "PERCENT": 0.01, "PCT": 0.01,
                 "PERCNT": 0.01, "LPU": 0.01, "SPU": 0.01, "DPU": 0.01},
}

#: Plausible range of a single sample of each variable, in the project's units. The lower bound
#: of vp is the speed of sound in water at 0 °C (1.40 km/s): a rock logged slower is a bad
#: sample (a gas sand can be slower, a sonic log rarely reads it right). A sample outside is
#: blanked; a curve whose median lies outside has the wrong unit.
RANGES = {"vp": (1.40, 7.5), "vs": (0.05, 4.5), "density": (1.0, 3.5), "porosity": (-0.15, 1.0)}

#: Null values written without being declared (blanked with a hint to pass ``null=``).
_SENTINELS = (-999.25, -999.0, -999.99, -9999.0, -9999.25, -9999.99, -99999.0, -32767.0,
              -2147483647.0)

_UNIT_TEXT = {"vp": "km/s", "vs": "km/s", "density": "g/cm3", "porosity": ""}
_MATRIX_UNITS = {"LPU": "limestone", "SPU": "sandstone", "DPU": "dolomite"}
_MATRIX_NAMES = {"_LIM": "limestone", "_SAN": "sandstone", "_DOL": "dolomite",
                 "NPHL": "limestone", "NPHS": "sandstone", "NPHD": "dolomite",
                 "DPHL": "limestone", "DPHS": "sandstone", "DPHD": "dolomite"}
_CHUNK_CHARS = 4_000_000                # text handed to lasio at a time (memory, not speed)


# ----------------------------------------------------------------------------- units, curves
def _unit_key(unit) -> str:
    # The micro sign (U+00B5) and the Greek mu (U+03BC) both upper-case to U+039C: read as u.
    key = re.sub(r"\s+", "", str(unit or ""))
    return key.replace("\u00b5", "u").replace("\u03bc", "u").upper()


def _kinds(variable):
    return {"vp": ("slowness", "velocity"), "vs": ("slowness", "velocity"),
            "density": ("density",), "porosity": ("porosity",)}[variable]


def _unit_kind(variable, unit):
    """``(kind, factor)`` of a curve of ``variable`` in ``unit``, or None if not understood."""
    key = _unit_key(unit)
    for kind in _kinds(variable):
        if key in UNITS[kind]:
            return kind, UNITS[kind][key]
    return None


def _known_units(variable):
    return ", ".join(u for kind in _kinds(variable) for u in UNITS[kind])


def _base(mnemonic) -> str:
    """A mnemonic without lasio's ``:1``, ``:2`` of a repeated one."""
    return re.sub(r":\d+$", "", str(mnemonic)).upper()


def _apparent(mnemonic, unit):
    """``("neutron" | "density" | None, matrix or None)`` of a porosity curve."""
    name, key = _base(mnemonic), _unit_key(unit)
    source = "neutron" if (name.startswith(("NPH", "TNPH", "NPOR", "CN"))
                           or key in _MATRIX_UNITS) else \
        "density" if name.startswith("DPH") else None
    matrix = _MATRIX_UNITS.get(key) or next(
        (m for k, m in _MATRIX_NAMES.items() if name.endswith(k)), None)
    return source, (matrix if source else None)


def _choose(source, curves, override):
    """The curve of each variable: ``{variable: (index, mnemonic, unit, kind, factor)}`` and
    the notes on variables left out, from the header ``curves = [(mnemonic, unit), ...]``."""
    if override is None:
        override = {}
    if not hasattr(override, "items"):
        raise ValueError("curves must be a mapping {variable: mnemonic}, e.g. {'vp': 'DTCO'}")
    unknown = [k for k in override if k not in WELL_VARIABLES]
    if unknown:
        raise ValueError(f"curves: {unknown[0]!r} is not a variable; use "
                         f"{', '.join(WELL_VARIABLES)}")
    names = [str(m).upper() for m, _ in curves]
    chosen, notes = {}, []
    for var in WELL_VARIABLES:
        if var in override:
            wanted = override[var]
            if wanted is None or str(wanted).strip().lower() in ("", "none"):
                notes.append({"variable": var, "status": "left out", "note": "curves= says so"})
                continue
            wanted = str(wanted).strip().upper()
            hits = [i for i, n in enumerate(names) if n == wanted and i > 0] or \
                [i for i, n in enumerate(names) if _base(n) == wanted and i > 0]
            if not hits:
                raise ValueError(f"{source}: no curve {wanted!r} for {var} (curves= or --curve);"
                                 f" the file has {', '.join(names[1:]) or 'none'}")
            if len(hits) > 1:
                raise ValueError(f"{source}: curve {wanted} appears {len(hits)} times "
                                 f"({', '.join(names[i] for i in hits)}); name one of them")
            i = hits[0]
            unit = curves[i][1]
            hit = _unit_kind(var, unit)
            if hit is None:
                what = f"unit {unit!r} is not understood" if _unit_key(unit) else "no unit given"
                raise ValueError(f"{source}: curve {names[i]!r} for {var}: {what}; use one of "
                                 f"{_known_units(var)}")
            chosen[var] = (i, names[i], str(unit), *hit)
            continue
        passed = []
        for alias in ALIASES[var]:
            hits = [i for i, n in enumerate(names) if _base(n) == alias and i > 0]
            if not hits:
                continue
            if len(hits) > 1:
                passed.append(f"{alias} appears {len(hits)} times "
                              f"({', '.join(names[i] for i in hits)}): name one with "
                              f"curves={{'{var}': '{names[hits[-1]]}'}}")
                continue
            i = hits[0]
            unit = curves[i][1]
            hit = _unit_kind(var, unit)
            if hit is None:
                what = f"unit {unit!r} not understood" if _unit_key(unit) else "no unit"
                passed.append(f"{names[i]}: {what} for {var}")
                continue
            chosen[var] = (i, names[i], str(unit), *hit)
            break
        if passed:
            notes.append({"variable": var, "status": "passed over" if var in chosen else
                          "left out", "note": "; ".join(passed)})
    return chosen, notes


# ----------------------------------------------------------------------------- sources
def _as_float(values):
    """A column as float64 (text that is not a number, or an empty cell, as NaN) and the mask
    of entries that were text and not a number."""
    arr = np.asarray(values)
    if arr.dtype.kind in "fiub":
        return arr.astype(float, copy=False), np.zeros(arr.shape, dtype=bool)
    import pandas as pd

    out = pd.to_numeric(pd.Series(arr.ravel(), dtype=object), errors="coerce").to_numpy(float)
    text = pd.Series(arr.ravel(), dtype=object).astype(str).str.strip().str.upper()
    blank = pd.isna(pd.Series(arr.ravel(), dtype=object)).to_numpy() | \
        text.isin(["", "NAN", "NONE"]).to_numpy()
    return out, np.isnan(out) & ~blank


def _lasio_read(text, source, **kwargs):
    """``lasio.read`` of LAS text, its log messages held back and its errors one ValueError."""
    import lasio

    log = logging.getLogger("lasio")
    level = log.level
    log.setLevel(logging.CRITICAL)          # lasio logs what it skips; the report says it once
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return lasio.read(text, ignore_header_errors=False, **kwargs)
    except Exception as exc:  # noqa: BLE001 (lasio raises KeyError, LASHeaderError, ...)
        message = " ".join(str(exc).strip().splitlines()[-1:]) or type(exc).__name__
        raise ValueError(f"{source} is not a readable LAS file: {message}") from None
    finally:
        log.setLevel(level)


_DLM = re.compile(r"^\s*DLM\s*\.", re.IGNORECASE)
_COMMA_POLICY = None


def _comma_policy():
    """lasio read policy of a comma-delimited data section: commas to spaces, then lasio's
    run-on fixes (not its comma decimal mark, which would join the numbers)."""
    global _COMMA_POLICY
    if _COMMA_POLICY is None:
        _COMMA_POLICY = [(re.compile(r"\s*,\s*"), " "), "run-on(-)", "run-on(.)"]
    return _COMMA_POLICY


class _Las:
    """A LAS file for :func:`_read`: header from lasio; data columns read by lasio, in pieces
    of about 4 MB of text for an unwrapped LAS 1.2/2.0 file (memory a few times the file,
    not 15), in one piece otherwise."""

    def __init__(self, path):
        self.path, self.source = path, path.name
        with self._open() as fh:
            head, self.a_line = [], None
            for n, line in enumerate(fh, 1):
                if n <= 100_000:                # a header; LAS 3.0 data are read by lasio
                    head.append(line)
                if line.lstrip()[:2].upper() == "~A":
                    self.a_line = n
                    break
            first = None
            if self.a_line is not None:
                for line in fh:
                    s = line.strip()
                    if s and not s.startswith("#"):
                        first = s
                        break
        if not any(line.lstrip().startswith("~") for line in head):
            raise ValueError(f"{self.source} is not a readable LAS file: no ~ sections")
        self.comma, self.whole = False, None
        if self.a_line is None:         # LAS 3.0 (~Log_Data ...): lasio reads it all at once
            self.whole = hdr = self._read(str(self.path))
        else:
            hdr = _lasio_read("".join(head), self.source, ignore_data=True)
        version = hdr.version.get("VERS")
        wrap = hdr.version.get("WRAP")
        dlm = hdr.version.get("DLM")
        self.version = str(getattr(version, "value", "") or "").strip() or "?"
        self.wrapped = str(getattr(wrap, "value", "")).strip().upper() == "YES"
        # lasio reads its own "DEPT..1IN" (unit .1IN) as mnemonic "DEPT." and unit "1IN".
        self.curves = [(c.mnemonic[:-1], "." + c.unit) if c.mnemonic.endswith(".") and
                       str(c.unit)[:1].isdigit() else (c.mnemonic, c.unit) for c in hdr.curves]
        if not self.curves:
            raise ValueError(f"{self.source}: no curves in the ~Curve section")
        null = hdr.well.get("NULL")
        try:
            self.nulls = [float(null.value)]
        except (AttributeError, TypeError, ValueError):
            self.nulls = [-999.25]
        well = hdr.well.get("WELL")
        self.well = str(getattr(well, "value", "") or "").strip()
        start = hdr.well.get("STRT")
        if not _unit_key(self.curves[0][1]) and start is not None and _unit_key(start.unit):
            self.curves[0] = (self.curves[0][0], start.unit)     # depth unit from ~Well STRT
        n = len(self.curves)
        # Comma-delimited: DLM says so (LAS 3.0), or the first data line has n fields between
        # commas, not n between spaces or each but the last ending in a comma (a decimal
        # comma, "1000,5 2,35", splits otherwise).
        words = first.split() if first else []
        self.comma = str(getattr(dlm, "value", "")).strip().upper() == "COMMA" or (
            first is not None and len(re.split(r"\s*,\s*", first)) == n
            and (len(words) != n or all(w.endswith(",") for w in words[:-1])))
        self.delimiter = "comma" if self.comma else "space"
        self.head = "".join(line for line in head if not (self.comma and _DLM.match(line)))
        self.pieces = (self.a_line is not None and not self.wrapped
                       and self.version[:1] in ("1", "2"))
        if self.a_line is None and self.version[:1] in ("1", "2"):
            raise ValueError(f"{self.source}: no ~A (data) section")

    def _read(self, text):
        policy = _comma_policy() if self.comma else "default"
        return _lasio_read(text, self.source, read_policy=policy)

    def columns(self, indices):
        """The data of curves ``indices`` (numbers, or text where lasio found text)."""
        parts = [[] for _ in indices]
        if self.whole is not None:
            self._take(self.whole, indices, parts)
            return [self._join(p) for p in parts]
        if self.pieces:
            try:
                for block in self._blocks():
                    self._take(self._read(self.head + block), indices, parts)
                return [self._join(p) for p in parts]
            except ValueError:
                parts = [[] for _ in indices]        # lasio's verdict on the whole file
        text = str(self.path)           # lasio reads the file, unless its DLM must go
        if self.comma:
            with self._open() as fh:
                text = "".join(line for line in fh if not _DLM.match(line))
        try:
            las = self._read(text)
        except ValueError as exc:
            raise ValueError(self._diagnose() or str(exc)) from None
        self._take(las, indices, parts)
        return [self._join(p) for p in parts]

    def _open(self):
        """The file as text, decoded as lasio decodes it."""
        import lasio.reader

        return lasio.reader.open_file(str(self.path))[0]

    def _blocks(self):
        """The data lines in blocks of about ``_CHUNK_CHARS`` characters."""
        with self._open() as fh:
            for _ in range(self.a_line):
                fh.readline()
            block, size = [], 0
            for line in fh:
                if line.lstrip().startswith("~"):
                    raise ValueError("a section after ~A")      # read whole, as lasio does
                block.append(line)
                size += len(line)
                if size >= _CHUNK_CHARS:
                    yield "".join(block)
                    block, size = [], 0
            if block:
                yield "".join(block)

    def _take(self, las, indices, parts):
        if len(las.curves) < len(self.curves):
            raise ValueError(f"{self.source}: the data has fewer columns than the ~Curve "
                             f"section's {len(self.curves)} curves")
        for part, i in zip(parts, indices):
            part.append(np.asarray(las.curves[i].data))

    @staticmethod
    def _join(part):
        if not part:
            return np.empty(0)
        if all(p.dtype.kind in "fiu" for p in part):
            return np.concatenate([p.astype(float, copy=False) for p in part])
        return np.concatenate([p.astype(object) for p in part])

    def _tokens(self):
        """``(line number, values on it)`` of the data lines (for messages only)."""
        split = re.compile(r"[\s,]+")
        with self._open() as fh:
            in_data = False
            for n, line in enumerate(fh, 1):
                s = line.strip()
                if not in_data:
                    in_data = s[:2].upper() == "~A" or (self.a_line is None and
                                                        s.upper().startswith("~LOG_DATA"))
                    continue
                if s.startswith("~"):
                    return
                if s and not s.startswith("#"):
                    yield n, len(split.split(s))

    def _diagnose(self):
        """A line-level message for data lasio cannot read, or None."""
        n = len(self.curves)
        total = 0
        for line, count in self._tokens():
            if not self.wrapped and count != n:
                return (f"{self.source}: line {line} has {count} values, the ~Curve section "
                        f"lists {n} curves (a truncated line)")
            total += count
        if total % n:
            return (f"{self.source}: the ~A section holds {total} values, not a whole number "
                    f"of rows of the {n} curves (a truncated line)")
        return None

    def lines(self, rows):
        """File line numbers at which the data rows ``rows`` (0-based, file order) start."""
        n, want, out, seen = len(self.curves), sorted({int(r) for r in rows}), {}, 0
        k = 0
        for line, count in self._tokens():
            while k < len(want) and want[k] * n < seen + count:
                out[want[k]] = line
                k += 1
            seen += count
            if k == len(want):
                break
        return [out.get(int(r)) for r in rows]

    def describe(self):
        wrapped = ", wrapped" if self.wrapped else ""
        comma = ", comma-delimited" if self.comma else ""
        return f"LAS {self.version}{wrapped}{comma}"


_HEADER = re.compile(r"^\s*([^\s(\[]+)\s*(?:[(\[]\s*([^)\]]*?)\s*[)\]])?\s*$")


class _Csv:
    """A CSV well log for :func:`_read`: units in the header (``DEPT (ft),DT (us/ft)``)."""

    wrapped, delimiter, version, well = False, "comma", "", ""

    def __init__(self, path):
        import pandas as pd

        self.path, self.source = path, path.name
        self.data_lines = _csv_rows(path, self.source)
        try:
            self.table = pd.read_csv(path, comment="#", skipinitialspace=True, index_col=False)
        except (ValueError, pd.errors.ParserError, UnicodeDecodeError) as exc:
            raise ValueError(f"{self.source} is not a readable CSV file: "
                             f"{str(exc).strip()}") from None
        self.curves = []
        for j, header in enumerate(self.table.columns):
            match = _HEADER.match(str(header))
            if match is None:
                raise ValueError(f"{self.source}: column {j + 1} header {header!r} is not "
                                 "'NAME' or 'NAME (unit)'")
            self.curves.append((match.group(1), match.group(2) or ""))
        if not self.curves:
            raise ValueError(f"{self.source}: no columns")
        self.nulls = [-999.25]

    def columns(self, indices):
        return [self.table.iloc[:, i].to_numpy() for i in indices]

    def lines(self, rows):
        return [self.data_lines[int(r)] for r in rows]

    def describe(self):
        return "CSV"


def _csv_rows(path, source):
    """The line numbers of the data lines of a CSV log, each checked to have as many fields as
    its header (pandas would take a first extra field for a row label, or fill a short line
    with NaN)."""
    import csv

    try:
        with open(path, newline="", encoding="utf-8") as fh:
            lines = [(i, row) for i, row in enumerate(csv.reader(
                line.partition("#")[0] for line in fh), 1)
                if any(f.strip() for f in row) or len(row) > 1]
    except UnicodeDecodeError as exc:
        raise ValueError(f"{source} is not a readable CSV file: {str(exc).strip()}") from None
    if not lines:
        raise ValueError(f"{source}: empty file")
    width = len(lines[0][1])
    for i, row in lines[1:]:
        if len(row) != width:
            raise ValueError(f"{source}: line {i} has {len(row)} fields, the header "
                             f"{width} (a wrapped or truncated line)")
    return [i for i, _ in lines[1:]]


# ----------------------------------------------------------------------------- checks
def _null_values(null):
    if null is None:
        return []
    values = as_array("null", null).ravel()
    if not np.all(np.isfinite(values)):
        raise ValueError(f"null must be finite numbers; got {values.tolist()}")
    return [float(v) for v in values]


def _fmt(value):
    return f"{value:.4g}"


def _check_curve(source, var, mnemonic, unit, kind, factor, raw, text, nulls, zraw, zunit):
    """Blank the bad samples of one curve; refuse it if its bulk says the unit is wrong.

    Returns ``(values in the project's unit, report entry)``; ``values`` is None when the
    curve has no valid sample."""
    lo, hi = RANGES[var]
    shown = _UNIT_TEXT[var] or "(fraction)"
    null = np.isnan(raw) & ~text
    for v in nulls:
        null |= raw == v
    sentinel = np.zeros(raw.shape, dtype=bool)
    for v in _SENTINELS:
        if v not in nulls:
            sentinel |= raw == v
    usable = ~(null | text | sentinel)
    positive = kind in ("slowness", "velocity", "density")
    not_positive = usable & (raw <= 0.0) if positive else np.zeros(raw.shape, dtype=bool)
    valid = usable & ~not_positive
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.where(valid, factor / raw if kind == "slowness" else factor * raw, np.nan)
    entry = {"variable": var, "mnemonic": mnemonic, "unit": str(unit), "kind": kind,
             "samples": int(raw.size), "null": int(null.sum())}
    if not valid.any():
        entry.update(status="left out", kept=0, blanked=_reasons(
            raw, zraw, zunit, unit, ((text, "not a number"), (sentinel, "undeclared null"),
                                     (not_positive, "not positive"))),
            note="no valid sample")
        return None, entry
    median = float(np.median(value[valid]))
    if not lo <= median <= hi:
        raise ValueError(_wrong_unit(source, var, mnemonic, unit, kind, factor, median))
    if kind == "porosity" and factor == 0.01:
        p95 = float(np.percentile(raw[valid], 95.0))
        if p95 < 0.5:
            raise ValueError(f"{source}: curve {mnemonic} ({unit}): 95 % of its samples are "
                             f"below {p95:.3g} {unit}, porosity {p95 * factor:.3g}: the values "
                             f"look like a fraction, not percent; correct the unit, or leave "
                             f"the curve out (curves={{'{var}': None}}, --curve {var}=none)")
    below = valid & (value < lo)
    above = valid & (value > hi)
    value[below | above] = np.nan
    units = f" {_UNIT_TEXT[var]}" if _UNIT_TEXT[var] else ""
    entry["blanked"] = _reasons(raw, zraw, zunit, unit, (
        (text, "not a number"), (sentinel, "undeclared null"), (not_positive, "not positive"),
        (below, f"slower than water (< {lo:g}{units})" if var == "vp" else
         f"below {lo:g}{units}"),
        (above, f"above {hi:g}{units}")))
    entry.update(status="read", kept=int(np.isfinite(value).sum()))
    entry["median"] = f"{_fmt(median)} {shown}"
    if sentinel.any():
        found = sorted({float(v) for v in raw[sentinel]})
        entry["note"] = ("values " + ", ".join(f"{v:g}" for v in found) + " look like nulls "
                         "the header does not declare: pass null=" +
                         (f"{found[0]:g}" if len(found) == 1 else
                          "[" + ", ".join(f"{v:g}" for v in found) + "]") +
                         f" (--null {found[0]:g})")
    return value, entry


def _reasons(raw, zraw, zunit, unit, masks):
    """``{reason: {"count": n, "first": "value unit at depth"}}`` of the non-empty masks."""
    out = {}
    for mask, reason in masks:
        n = int(mask.sum())
        if n:
            k = int(np.flatnonzero(mask)[0])
            value = raw[k]
            out[reason] = {"count": n, "first": (f"{value:g} {unit}".strip() if
                                                 np.isfinite(value) else "text") +
                           f" at {zraw[k]:g} {zunit}".rstrip()}
    return out


def _wrong_unit(source, var, mnemonic, unit, kind, factor, median):
    """The message refusing a curve whose median lies outside its variable's range."""
    lo, hi = RANGES[var]
    what = f"{var} {_fmt(median)} {_UNIT_TEXT[var]}".rstrip()
    if var == "vp" and median < lo:
        why = f"slower than water ({lo:g} km/s)"
    else:
        why = f"outside [{lo:g}, {hi:g}] {_UNIT_TEXT[var]}".rstrip()
    raw_median = factor / median if kind == "slowness" else median / factor
    others = []
    for k in _kinds(var):
        for u, f in UNITS[k].items():
            if u == _unit_key(unit) or f == factor and k == kind:
                continue
            v = f / raw_median if k == "slowness" else f * raw_median
            if lo <= v <= hi and not any(f"{_fmt(v)}" in o for o in others):
                others.append(f"in {u} it would be {_fmt(v)} {_UNIT_TEXT[var]}".rstrip())
    hint = f" ({'; '.join(others[:2])})" if others else ""
    return (f"{source}: curve {mnemonic} ({unit}): its median, {_fmt(raw_median)} {unit}, "
            f"gives {what}, {why}: the unit is wrong{hint}; correct the unit in the file, or "
            f"choose another curve or none (curves={{'{var}': ...}}, "
            f"--curve {var}=MNEMONIC or {var}=none)")


def _label(var, mnemonic, unit):
    """``(long_name, log_label, comment)`` of a well variable."""
    if var != "porosity":
        return None, mnemonic, None
    source, matrix = _apparent(mnemonic, unit)
    if source is None:
        return f"log porosity ({mnemonic})", mnemonic, None
    units = f" ({matrix} units)" if matrix else ""
    comment = (f"a {source} porosity, apparent: in the units of the tool's calibration "
               f"matrix{units}, not the total porosity of the rock")
    return f"log porosity (apparent, from {mnemonic})", f"{mnemonic}, apparent", comment


# ----------------------------------------------------------------------------- reading
def _depth_offset(value):
    """``depth_offset`` as a finite number of metres no larger than the deepest basin."""
    from burial.path import MAX_DEPTH_M

    return check_range("depth_offset (m)", as_scalar("depth_offset", value), -MAX_DEPTH_M,
                       MAX_DEPTH_M)


def _read(src, *, null=None, curves=None, depth_offset=0.0):
    """The Dataset of a source (:class:`_Las`, :class:`_Csv`)."""
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


# ----------------------------------------------------------------------------- comparing
#: Variables a well and a scene share, in the order they are compared.
WELL_VARIABLES = ("vp", "vs", "density", "porosity")

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


def _misfit(model, log, relative):
    return model / log - 1.0 if relative else model - log


def _point_misfit(ds, values, log, points, relative):
    """Misfit at each of ``points``, the log the mean of its samples within half a scene depth
    step (NaN where the log has no finite sample there)."""
    z = log.depth.values
    half = 0.5 * float(np.median(np.diff(ds.depth.values)))    # >= 2 depths: checked above
    out = np.full(points.size, np.nan)
    for k, p in enumerate(points):
        near = log.values[(z >= p - half) & (z <= p + half)]
        near = near[np.isfinite(near)]
        if near.size:
            out[k] = _misfit(float(values.sel(depth=p)), near.mean(), relative)
    return out


def well_misfit(ds, well, *, intervals=None, variables=None):
    r"""Misfit of each model to a well log in each depth interval.

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
        Columns ``variable``, ``model``, ``top``, ``base``, ``n``, ``rms``, ``bias``,
        ``misfit`` (``"model/log - 1"`` or ``"model - log"``) and ``log`` (the log's mnemonic;
        ``"NPHI, apparent"`` for an apparent porosity).

    Raises
    ------
    ValueError
        No shared variable or depth range, bad intervals, or a log of vp, vs or density with a
        value ``<= 0`` (a relative misfit needs positive values; none is dropped silently).
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
        relative = MISFIT[name] == "model/log - 1"
        log = well[name]
        if relative and np.any(log.values <= 0.0):
            k = int(np.flatnonzero(log.values <= 0.0)[0])
            raise ValueError(f"log {name} is {log.values[k]:g} at {z[k]:g} m; its misfit is "
                             "relative (model/log - 1) and needs values > 0")
        label = log.attrs.get("log_label") or log.attrs.get("source_mnemonic") or name
        modelled = model_at_well(ds, well, name)
        labels = modelled.model.values.tolist() if "model" in modelled.dims else ["-"]
        for model in labels:
            own = ds[name].sel(model=model) if model != "-" else ds[name]
            points = _sparse_points(ds, own) if _is_md(model) else None
            if points is not None:          # a model at a few depths (the MD backend)
                zz, mis = points, _point_misfit(ds, own, log, points, relative)
            else:
                m = modelled.sel(model=model).values if model != "-" else modelled.values
                zz, mis = z, _misfit(m, log.values, relative)
            for k, (top, base) in enumerate(itertools.pairwise(edges)):
                below = (zz <= base) if k == edges.size - 2 else (zz < base)
                sel = (zz >= top) & below & np.isfinite(mis)
                n = int(sel.sum())
                rows.append({"variable": name, "model": model, "top": top, "base": base,
                             "n": n,
                             "rms": float(np.sqrt(np.mean(mis[sel] ** 2))) if n else np.nan,
                             "bias": float(np.mean(mis[sel])) if n else np.nan,
                             "misfit": MISFIT[name], "log": str(label)})
    return pd.DataFrame(rows)
