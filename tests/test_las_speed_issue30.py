"""Issue 30: a LAS file of many curves is read in time linear in the curves, and to what lasio
itself reads.

rockcem reads LAS through lasio with lasio's quadratic steps made linear
(:func:`rockcem._well_files._fast_lasio`) and the numbers of a plain ~A block read by
``numpy.loadtxt`` (:meth:`rockcem._well_files._Las._numbers`). The references here are lasio's own
reads of the same text outside that block (lasio 0.32 as installed) and names written out by
hand from lasio's documented rule (repeated mnemonics become ``MNEM:1``, ``MNEM:2``, ...;
a blank one ``UNKNOWN``). The speed itself is measured by benchmarks/las_read_speed.py, not
asserted here.
"""

import numpy as np
import pytest

lasio = pytest.importorskip("lasio")

from rockcem import _well_files  # noqa: E402
from rockcem._well_files import _fast_lasio, _Las, _lasio_read  # noqa: E402
from rockcem.wells import read_well  # noqa: E402

DUPLICATES = """~Version
VERS. 2.0 :
WRAP. NO :
~Well
STRT.M 1000 :
STOP.M 1002 :
STEP.M 1 :
NULL. -999.25 :
WELL. W :
~Parameter
BHT.DEGC 60 : temperature
BHT.DEGC 61 : again
~Curve
DEPT.M : depth
DT.US/FT : sonic
RHOB.G/CC : density
dt.US/FT : sonic again, lower case
 .V/V : no mnemonic
DT.US/M : a third
 .OHMM : no mnemonic either
~A
1000 100 2.30 101 0.1 330 10
1001 102 2.31 103 0.2 335 11
1002 104 2.32 105 0.3 340 12
"""

#: lasio's names for the ~Curve section above (mnemonics upper-cased, its default): written by
#: hand from its rule, in section order.
EXPECTED = ["DEPT", "DT:1", "RHOB", "DT:2", "UNKNOWN:1", "DT:3", "UNKNOWN:2"]


def _names(las):
    return {name: [item.mnemonic for item in section]
            for name, section in (("version", las.version), ("well", las.well),
                                  ("params", las.params), ("curves", las.curves))}


def test_duplicate_mnemonics_get_lasios_suffixes(tmp_path):
    plain = lasio.read(DUPLICATES)                          # lasio's own rule, not ours
    assert [c.mnemonic for c in plain.curves] == EXPECTED
    fast = _lasio_read(DUPLICATES, "dup.las")
    assert _names(fast) == _names(plain)
    assert [p.mnemonic for p in fast.params] == ["BHT:1", "BHT:2"]
    header = _lasio_read(DUPLICATES, "dup.las", ignore_data=True)
    assert _names(header) == _names(plain)
    f = tmp_path / "dup.las"
    f.write_text(DUPLICATES)
    assert [m for m, _ in _Las(f).curves] == EXPECTED
    # the data are paired with those names as lasio pairs them
    for a, b in zip(fast.curves, plain.curves):
        np.testing.assert_array_equal(a.data, b.data)


def test_duplicate_rule_with_mnemonics_as_written_and_extra_data_columns():
    """``mnemonic_case="preserve"`` (no upper-casing: ``dt`` and ``DT`` differ), and data with
    more columns than the ~Curve section (lasio appends curves named ``UNKNOWN``, numbered)."""
    extra = DUPLICATES.replace("1000 100 2.30 101 0.1 330 10", "1000 100 2.30 101 0.1 330 10 7 8")
    extra = extra.replace("1001 102 2.31 103 0.2 335 11", "1001 102 2.31 103 0.2 335 11 7 8")
    extra = extra.replace("1002 104 2.32 105 0.3 340 12", "1002 104 2.32 105 0.3 340 12 7 8")
    for text in (DUPLICATES, extra):
        for case in ("preserve", "upper", "lower"):
            plain = lasio.read(text, mnemonic_case=case)
            with _fast_lasio():
                fast = lasio.read(text, mnemonic_case=case)
            assert _names(fast) == _names(plain), (case, text is extra)
    preserved = lasio.read(DUPLICATES, mnemonic_case="preserve")
    assert [c.mnemonic for c in preserved.curves] == ["DEPT", "DT:1", "RHOB", "dt", "UNKNOWN:1",
                                                      "DT:2", "UNKNOWN:2"]
    assert [c.mnemonic for c in lasio.read(extra).curves][-2:] == ["UNKNOWN:3", "UNKNOWN:4"]


def test_outside_a_read_lasio_is_its_own():
    """The linear methods act only inside :func:`_fast_lasio`: a section built by a user after
    rockcem read a file gets lasio's own append (suffixes at once) and look-up."""
    _lasio_read(DUPLICATES, "dup.las")                      # installs the wrappers
    section = lasio.SectionItems()
    section.append(lasio.HeaderItem("A"))
    section.append(lasio.HeaderItem("A"))
    assert [i.mnemonic for i in section] == ["A:1", "A:2"]
    assert section[1].mnemonic == "A:2" and section["A:1"] is section[0]


def test_header_parse_is_linear_in_the_curves(monkeypatch):
    """Mnemonic comparisons while a header of n curves is read: lasio's append compares each new
    item with every earlier one (n²/2, 2·10⁶ for n = 2000); the read here stays within a few per
    item. A count, not a time."""
    n = 2000
    text = ("~Version\nVERS. 2.0 :\nWRAP. NO :\n~Well\nNULL. -999.25 :\n~Curve\nDEPT.M : d\n"
            + "".join(f"C{j}.V/V : c\n" for j in range(n - 1)) + "~A\n"
            + " ".join(["1000"] + ["0.1"] * (n - 1)) + "\n")
    calls = [0]
    compare = lasio.SectionItems.mnemonic_compare

    def counting(self, one, two):
        calls[0] += 1
        return compare(self, one, two)

    monkeypatch.setattr(lasio.SectionItems, "mnemonic_compare", counting)
    las = _lasio_read(text, "wide.las")
    assert len(las.curves) == n
    assert calls[0] < 10 * n, calls[0]


def _plain_las(path, rows, *, null="-999.25", extra_lines=()):
    head = ("~Version\nVERS. 2.0 :\nWRAP. NO :\n~Well\nSTRT.M 1000 :\nSTOP.M 1003 :\n"
            f"STEP.M 1 :\nNULL. {null} :\nWELL. W :\n~Curve\nDEPT.M : depth\n"
            "DT.US/FT : sonic\nRHOB.G/CC : density\nGR.GAPI : gamma\n~A\n")
    path.write_text(head + "".join(extra_lines) + "".join(rows))
    return path


ROWS = ["1000 100.5 2.30 45\n",
        "# a comment line\n",
        "-999.25 -999.25 2.31 1e2\n",           # a null depth stays (lasio: not in the index)
        "\n",
        "1002\t1.25E+02  -999.25 -3.5 # trailing comment\n",
        "1003 nan 2.33 -999.250\n"]


_rng = np.random.default_rng(30)
RANDOM_ROWS = [" ".join(f"{v:.17g}" for v in (1000.0 + k, *(_rng.standard_normal(3)
                                                        * 10.0 ** _rng.integers(-300, 300, 3))))
               + "\n" for k in range(50)]


@pytest.mark.parametrize("rows, null", [
    (ROWS, "-999.25"),
    (ROWS, "-9999"),                             # -999.25 is then a number like any other
    (ROWS, ""),                                  # no null value: lasio replaces nothing
    (ROWS[:1], "-999.25"),                       # one row
    (["1000 100 2.3 1_0\n", "1001 101 2.4 11\n"], "-999.25"),   # genfromtxt's 1_0 = 10
    (["1000 100 2.3\n", "45 1001 101 2.4 11\n"], "-999.25"),    # a row over two lines
    (["1000 100 2.3 45 9\n", "1001 101 2.4 11 9\n"], "-999.25"),  # a fifth column
    (RANDOM_ROWS, "-999.25"),                    # 17 digits, exponents from -300 to 300
])
def test_columns_are_lasios_numbers(tmp_path, rows, null):
    """Every curve of :meth:`_Las.columns` (the pieces read, by ``numpy.loadtxt`` where it can)
    equals lasio's read of the whole file, NaN for NaN."""
    f = _plain_las(tmp_path / "p.las", rows, null=null)
    ref = lasio.read(str(f))
    src = _Las(f)
    got = src.columns(list(range(len(src.curves))))
    for j, col in enumerate(got):
        np.testing.assert_array_equal(col, np.asarray(ref.curves[j].data, dtype=float))
    if null == "-999.25" and rows is ROWS:
        assert np.isnan(got[1][1]) and got[0][1] == -999.25 and np.isnan(got[3][3])


def test_plain_blocks_are_not_handed_to_lasio(tmp_path, monkeypatch):
    """The fast read is taken for a plain file (with a null, comments, exponents), in each piece:
    lasio's data read is made to fail, and the read still succeeds with the planted values."""
    f = _plain_las(tmp_path / "p.las", ROWS)

    def refuse(self, text):
        raise AssertionError("lasio read the data")

    monkeypatch.setattr(_Las, "_read", refuse)
    for size in (30, 10_000):           # (a piece of comment lines alone goes to lasio)
        monkeypatch.setattr(_well_files, "_CHUNK_CHARS", size)
        dt = _Las(f).columns([1])[0]
        np.testing.assert_array_equal(dt, [100.5, np.nan, 125.0, np.nan])


def test_wide_las_reads_as_the_same_csv(tmp_path):
    """A LAS file of 1500 curves with two repeated mnemonics, read by read_well, gives what the
    same data as CSV give (the values planted; the repeated curves are not chosen)."""
    n, rows = 1500, 4
    depth = 2000.0 + np.arange(rows)
    dt = np.array([100.0, 101.5, 99.25, 98.0])
    rho = np.array([2.31, 2.32, 2.33, 2.34])
    names = ["DEPT", "DT", "RHOB"] + [f"C{j % 700}" for j in range(n - 3)]   # C0..C699 repeat
    units = ["M", "US/FT", "G/CC"] + ["V/V"] * (n - 3)
    other = np.round(np.linspace(0.0, 0.3, rows * (n - 3)).reshape(rows, n - 3), 6)
    data = np.column_stack([depth, dt, rho, other])
    las = tmp_path / "wide.las"
    las.write_text("~Version\nVERS. 2.0 :\nWRAP. NO :\n~Well\nNULL. -999.25 :\n~Curve\n"
                   + "".join(f"{m}.{u} : c\n" for m, u in zip(names, units)) + "~A\n"
                   + "".join(" ".join(f"{v:.6f}" for v in row) + "\n" for row in data))
    src = _Las(las)
    assert [m for m, _ in src.curves[3:6]] == ["C0:1", "C1:1", "C2:1"]
    assert src.curves[3 + 700][0] == "C0:2" and src.curves[3 + 1400][0] == "C0:3"
    assert src.curves[-1][0] == f"C{(n - 4) % 700}:3"
    ds = read_well(las)
    np.testing.assert_array_equal(ds["depth"].values, depth)
    np.testing.assert_allclose(ds["vp"].values, 0.3048 / dt * 1e3, rtol=1e-15)
    np.testing.assert_array_equal(ds["density"].values, rho)


def test_duplicate_rule_in_a_section_that_compares_without_case():
    """A section with ``mnemonic_transforms`` (lasio's for ``mnemonic_case`` upper or lower)
    finds ``a`` and ``A`` alike: both get a suffix, as lasio's own append gives them."""
    def build():
        section = lasio.SectionItems()
        section.mnemonic_transforms = True
        for m in ("a", "B", "A", "b", "c"):
            section.append(lasio.HeaderItem(m))
        return [i.mnemonic for i in section]

    plain = build()
    assert plain == ["a:1", "B:1", "A:2", "b:2", "c"]
    with _fast_lasio():
        assert build() == plain


def test_fewer_data_columns_than_curves_read_as_lasio_reads_them(tmp_path):
    """Rows of 3 values under 4 curves: lasio gives the fourth curve as NaN (and says so in its
    log); so does the read in pieces."""
    f = _plain_las(tmp_path / "short.las", ["1000 100 2.3\n", "1001 101 2.4\n"])
    assert np.isnan(lasio.read(str(f)).curves[3].data).all()
    dept, gr = _Las(f).columns([0, 3])
    np.testing.assert_array_equal(dept, [1000.0, 1001.0])
    assert gr.shape == (2,) and np.isnan(gr).all()
