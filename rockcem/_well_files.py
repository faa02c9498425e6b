"""The well-log file formats read by :mod:`rockcem.wells`: LAS (through ``lasio``) and CSV.

Each reader (:class:`_Las`, :class:`_Csv`) gives what :func:`rockcem.wells._read` needs of a
file, whatever its layout: the header curves ``[(mnemonic, unit), ...]`` (the first the depth),
the file's null values, the data of chosen columns, the file line of a data row (for messages)
and a description of the format. A LAS file's data are handed to lasio in pieces of about
:data:`_CHUNK_CHARS` characters where its layout allows (memory a few times the file).

lasio 0.32 costs time quadratic in the number of curves (a file of 5000 curves took 110 s): each
header item appended is compared with every earlier one for a duplicate mnemonic, each curve's
data is assigned through a look-up by position that first compares the position with every
mnemonic, and each curve's data is formatted for a debug message. :func:`_lasio_read` reads
with lasio's own code and these three made linear (:func:`_fast_lasio`), the duplicate rule
and the look-up giving what lasio's give (tests/test_las_speed_issue30.py).
"""

from __future__ import annotations

import contextlib
import functools
import io
import logging
import re
import threading
import warnings

import numpy as np

from ._well_curves import _unit_key

_CHUNK_CHARS = 4_000_000                # text handed to lasio at a time (memory, not speed)


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


_FAST = threading.local()               # .on: this thread is in _fast_lasio; .index: see below
_INSTALL_LOCK = threading.Lock()


def _install_fast_lasio():
    """Put linear versions of ``SectionItems.append`` and ``SectionItems.__getitem__`` (by
    position) in front of lasio's, once; they act only in a thread inside :func:`_fast_lasio`
    and hand every other call to lasio's own. False where lasio's internals are not those of
    0.31-0.32 (lasio is then used as it is: the same result, slower)."""
    from lasio.las_items import HeaderItem, SectionItems

    with _INSTALL_LOCK:
        if getattr(SectionItems, "_rockcem_fast", False):
            return True
        if not (hasattr(SectionItems, "assign_duplicate_suffixes")
                and hasattr(HeaderItem, "set_session_mnemonic_only")
                and hasattr(HeaderItem, "useful_mnemonic")):
            return False
        append, getitem = SectionItems.append, SectionItems.__getitem__

        @functools.wraps(append)
        def fast_append(self, newitem):
            if not getattr(_FAST, "on", False):
                return append(self, newitem)
            list.append(self, newitem)
            _suffix_duplicates(self, newitem)
            return None

        @functools.wraps(getitem)
        def fast_getitem(self, key):
            # lasio compares an integer key with every mnemonic (text: never equal) before
            # indexing by position; the position is the answer it then gives.
            if type(key) is int and getattr(_FAST, "on", False):
                return list.__getitem__(self, key)
            return getitem(self, key)

        SectionItems.append, SectionItems.__getitem__ = fast_append, fast_getitem
        SectionItems._rockcem_fast = True
        return True


def _mnemonic_key(section, mnemonic):
    """The key under which lasio's ``SectionItems.mnemonic_compare`` finds two mnemonics equal
    (upper case where the section transforms mnemonics)."""
    return mnemonic.upper() if section.mnemonic_transforms else mnemonic


def _suffix_duplicates(section, newitem):
    """lasio's duplicate rule after ``newitem`` was appended to ``section``
    (``SectionItems.assign_duplicate_suffixes(newitem.useful_mnemonic)``): when more than one
    item has its mnemonic, they are named ``MNEM:1``, ``MNEM:2``, ... in section order. Kept
    linear by an index of the section's items by mnemonic, rebuilt if the section changed in
    another way than by appends."""
    index = _FAST.index
    entry = index.get(id(section))
    transforms = bool(section.mnemonic_transforms)
    if entry is None or entry[0] is not section or entry[1] != transforms \
            or entry[3] != len(section) - 1:
        groups: dict = {}
        for item in list.__iter__(section):
            groups.setdefault(_mnemonic_key(section, item.useful_mnemonic), []).append(item)
        entry = [section, transforms, groups, len(section)]
        index[id(section)] = entry
        group = groups[_mnemonic_key(section, newitem.useful_mnemonic)]
    else:
        group = entry[2].setdefault(_mnemonic_key(section, newitem.useful_mnemonic), [])
        group.append(newitem)
        entry[3] = len(section)
    if len(group) > 1:
        for i, item in enumerate(group, 1):
            item.set_session_mnemonic_only(item.useful_mnemonic + ":%d" % i)


@contextlib.contextmanager
def _fast_lasio():
    """lasio's reading made linear in the number of curves, in this thread, for the block:
    the two methods of :func:`_install_fast_lasio`, and numpy's print options cut to a few items
    (lasio formats each curve's data for a debug message, whether or not it is logged; numpy's
    print options are local to the context)."""
    if getattr(_FAST, "on", False) or not _install_fast_lasio():
        yield
        return
    _FAST.on, _FAST.index = True, {}
    try:
        with np.printoptions(threshold=4, edgeitems=1):
            yield
    finally:
        _FAST.on, _FAST.index = False, {}


def _lasio_read(text, source, **kwargs):
    """``lasio.read`` of LAS text (through :func:`_fast_lasio`), its log messages held back and
    its errors one ValueError."""
    import lasio

    log = logging.getLogger("lasio")
    level = log.level
    log.setLevel(logging.CRITICAL)          # lasio logs what it skips; the report says it once
    try:
        with warnings.catch_warnings(), _fast_lasio():
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
    """A LAS file for :func:`rockcem.wells._read`: header from lasio; data columns read by
    lasio, in pieces of about 4 MB of text for an unwrapped LAS 1.2/2.0 file (memory a few
    times the file, not 15), in one piece otherwise."""

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
        # the null lasio's numpy engine sets to NaN (in every curve but the first): the ~Well
        # item whose mnemonic is NULL, not one of repeated ones (NULL:1, NULL:2)
        self.lasio_null = hdr.well["NULL"].value if "NULL" in hdr.well.keys() else None
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
                    numbers = self._numbers(block)
                    if numbers is None:
                        self._take(self._read(self.head + block), indices, parts)
                    else:
                        for part, i in zip(parts, indices):
                            part.append(numbers[:, i].copy())
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

    def _numbers(self, block):
        """The data lines ``block`` as lasio's numpy engine reads them, or None where this
        cannot say so (lasio reads the block then).

        lasio reads the ~A section of a file that is not wrapped with ``numpy.genfromtxt``
        (space-delimited, ``#`` comments, every field a number) and sets its null to NaN in every
        curve but the first (lasio 0.32, ``reader.read_data_section_iterative_numpy_engine`` and
        ``LASFile.read``). ``numpy.loadtxt`` reads the same fields to the same numbers (both
        through CPython's correctly rounded float parsing) in a fraction of the time (0.03 s
        against lasio's 0.8 s for 115 rows of 5000 curves here), and accepts a subset of the
        fields ``genfromtxt`` accepts (not ``1_0``, not non-ASCII digits): a block it refuses,
        or with another number of columns than the ~Curve section's, is left to lasio.
        """
        null = self.lasio_null
        if self.comma or not (null is None or isinstance(null, (int, float, np.number))
                              and not isinstance(null, bool)):
            return None
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("error")      # "input contained no data": lasio's case
                arr = np.loadtxt(io.StringIO(block), dtype=float, comments="#", ndmin=2)
        except (ValueError, UserWarning):
            return None
        if arr.shape[1] != len(self.curves) or arr.shape[0] == 0:
            return None
        if null is not None:
            rest = arr[:, 1:]
            rest[rest == null] = np.nan
        return arr

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
    """A CSV well log for :func:`rockcem.wells._read`: units in the header
    (``DEPT (ft),DT (us/ft)``)."""

    wrapped, delimiter, version, well = False, "comma", "", ""

    def __init__(self, path):
        import pandas as pd

        self.path, self.source = path, path.name
        self.encoding = _csv_encoding(path)
        self.data_lines = _csv_rows(path, self.source, self.encoding)
        try:
            self.table = pd.read_csv(path, comment="#", skipinitialspace=True, index_col=False,
                                     encoding=self.encoding)
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
        return "CSV" if self.encoding == "utf-8-sig" else f"CSV, {self.encoding}"


def _csv_encoding(path):
    """``"utf-8-sig"`` (UTF-8, a byte-order mark dropped) for a CSV file that is UTF-8, else
    ``"latin-1"`` (every byte a character: a header ``DT (µs/ft)`` written by a Windows
    program is read, not refused; lasio reads a LAS file's bytes in the same spirit)."""
    with open(path, "rb") as fh:
        data = fh.read()
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return "latin-1"
    return "utf-8-sig"


def _csv_rows(path, source, encoding="utf-8-sig"):
    """The line numbers of the data lines of a CSV log, each checked to have as many fields as
    its header (pandas would take a first extra field for a row label, or fill a short line
    with NaN)."""
    import csv

    with open(path, newline="", encoding=encoding) as fh:
        reader = csv.reader(line.partition("#")[0] for line in fh)
        try:
            lines = [(i, row) for i, row in enumerate(reader, 1)
                     if any(f.strip() for f in row) or len(row) > 1]
        except csv.Error as exc:        # a field over csv.field_size_limit() (128 kB), ...
            raise ValueError(f"{source}: line {reader.line_num} is not a line of a CSV well "
                             f"log: {exc}") from None
    if not lines:
        raise ValueError(f"{source}: empty file")
    width = len(lines[0][1])
    for i, row in lines[1:]:
        if len(row) != width:
            raise ValueError(f"{source}: line {i} has {len(row)} fields, the header "
                             f"{width} (a wrapped or truncated line)")
    return [i for i, _ in lines[1:]]
