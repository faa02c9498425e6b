"""Well-log reader: LAS round trips through lasio, CSV headers, units, nulls, per-sample
blanking and per-curve refusals, curve choice, the read report, and the misfit of compare.

Expected values come from the definitions (1 ft = 0.3048 m exactly, v = distance / time) and
from the values planted in each file, never from the reader's output."""

import json
import warnings

import numpy as np
import pytest

from rockcem.wells import WellLogWarning, format_read_report, read_well

lasio = pytest.importorskip("lasio")

FOOT = 0.3048   # m, exact by definition (international foot, 1959)


def _las(path, curves, *, null=-999.25, wrap=False, version=2.0):
    las = lasio.LASFile()
    for name, unit, values in curves:
        las.append_curve(name, np.asarray(values, dtype=float), unit=unit)
    las.well["NULL"].value = null
    las.well["WELL"].value = "TEST-1"
    las.write(str(path), version=version, wrap=wrap)
    return path


def _quiet(f, **kwargs):
    """read_well with any WellLogWarning an error (the file must read cleanly)."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", WellLogWarning)
        return read_well(f, **kwargs)


def _warned(f, **kwargs):
    """read_well and the text of its WellLogWarnings."""
    with pytest.warns(WellLogWarning) as record:
        ds = read_well(f, **kwargs)
    return ds, " | ".join(str(w.message) for w in record
                          if issubclass(w.category, WellLogWarning))


def test_las_round_trip_feet_and_microseconds_per_foot(tmp_path):
    depth_ft = np.array([3000.0, 3000.5, 3001.0, 3001.5])
    dt = np.array([100.0, 95.5, -999.25, 80.0])          # us/ft, one null sample
    dts = np.array([180.0, 170.0, 160.0, 150.0])
    rhob = np.array([2.30, 2.35, 2.40, 2.45])             # g/cm3
    nphi = np.array([25.0, 24.0, 23.0, 22.0])             # percent
    f = _las(tmp_path / "w.las", [("DEPT", "FT", depth_ft), ("DT", "US/FT", dt),
                                  ("DTS", "US/FT", dts), ("RHOB", "G/CC", rhob),
                                  ("NPHI", "%", nphi)])
    ds = _quiet(f)
    # Expected values from the definitions: v = distance / time, 1 ft = 0.3048 m.
    np.testing.assert_allclose(ds.depth.values, depth_ft * FOOT, rtol=1e-15)
    expected_vp = FOOT / (dt * 1e-6) / 1000.0
    np.testing.assert_allclose(ds.vp.values[[0, 1, 3]], expected_vp[[0, 1, 3]], rtol=1e-14)
    assert np.isnan(ds.vp.values[2])
    np.testing.assert_allclose(ds.vs.values, FOOT / (dts * 1e-6) / 1000.0, rtol=1e-14)
    np.testing.assert_allclose(ds.density.values, rhob, rtol=1e-15)
    np.testing.assert_allclose(ds.porosity.values, nphi / 100.0, rtol=1e-15)
    assert ds.vp.attrs["units"] == "km s-1" and ds.depth.attrs["units"] == "m"
    assert ds.vp.attrs["source_mnemonic"] == "DT"
    assert "neutron" in ds.porosity.attrs["comment"]
    assert ds.porosity.attrs["long_name"] == "log porosity (apparent, from NPHI)"
    assert ds.porosity.attrs["log_label"] == "NPHI, apparent"
    assert ds.attrs["well"] == "TEST-1"


def test_las_in_metres_and_microseconds_per_metre_decreasing_depth(tmp_path):
    depth = np.array([2000.0, 1999.0, 1998.0])            # logged upwards
    dt = np.array([400.0, 500.0, 250.0])                   # us/m
    f = _las(tmp_path / "m.las", [("DEPTH", "M", depth), ("DTCO", "us/m", dt),
                                  ("PHIT", "v/v", [0.1, 0.2, 0.3])])
    ds = _quiet(f, depth_offset=100.0)
    np.testing.assert_allclose(ds.depth.values, [1898.0, 1899.0, 1900.0], rtol=0)
    np.testing.assert_allclose(ds.vp.values, [4.0, 2.0, 2.5], rtol=1e-15)
    np.testing.assert_allclose(ds.porosity.values, [0.3, 0.2, 0.1])
    assert "comment" not in ds.porosity.attrs
    assert ds.porosity.attrs["long_name"] == "log porosity (PHIT)"


def test_csv_units_from_header(tmp_path):
    f = tmp_path / "w.csv"
    f.write_text("# a comment line\nDEPT (ft),VP [m/s],RHOB (kg/m3),PHIT (frac)\n"
                 "1000,3000,2300,0.2\n2000,,2400,-999.25\n")
    ds = _quiet(f)
    np.testing.assert_allclose(ds.depth.values, [304.8, 609.6], rtol=1e-15)
    assert ds.vp.values[0] == 3.0 and np.isnan(ds.vp.values[1])
    np.testing.assert_allclose(ds.density.values, [2.3, 2.4], rtol=1e-15)
    assert np.isnan(ds.porosity.values[1])


@pytest.mark.parametrize("kind, unit, raw, expected", [
    # Issue 21: spellings real files use. Factors from the definitions.
    ("DEPT", "M", 1000.0, 1000.0), ("DEPT", "F", 1000.0, 304.8),
    ("DEPT", "FT", 1000.0, 304.8), ("DEPT", ".1IN", 120000.0, 120000.0 * 0.00254),
    ("DT", "US/F", 100.0, FOOT / 100e-6 / 1e3), ("DT", "US/FT", 100.0, FOOT / 100e-6 / 1e3),
    ("DT", "US/M", 400.0, 1.0 / 400e-6 / 1e3), ("DT", "usec/ft", 100.0, FOOT / 100e-6 / 1e3),
    ("RHOB", "G/CC", 2.3, 2.3), ("RHOB", "G/CM3", 2.3, 2.3), ("RHOB", "G/C3", 2.3, 2.3),
    ("RHOB", "K/M3", 2300.0, 2.3), ("RHOB", "KG/M3", 2300.0, 2.3),
    ("NPHI", "LPU", 25.0, 0.25), ("NPHI", "PU", 25.0, 0.25), ("NPHI", "%", 25.0, 0.25),
    ("NPHI", "DECP", 0.25, 0.25), ("NPHI", "V/V", 0.25, 0.25), ("NPHI", "CFCF", 0.25, 0.25),
])
def test_unit_spellings(tmp_path, kind, unit, raw, expected):
    curves = [("DEPT", unit if kind == "DEPT" else "M", [raw, raw + 10.0] if kind == "DEPT"
               else [1000.0, 1010.0])]
    if kind != "DEPT":
        curves.append((kind, unit, [raw, raw]))
    else:
        curves.append(("RHOB", "G/CC", [2.3, 2.4]))
    ds = _quiet(_las(tmp_path / "u.las", curves))
    var = {"DEPT": "depth", "DT": "vp", "RHOB": "density", "NPHI": "porosity"}[kind]
    np.testing.assert_allclose(ds[var].values[0], expected, rtol=1e-14)


@pytest.mark.parametrize("curves, message", [
    ([("TIME", "S", [1.0, 2.0]), ("DT", "US/FT", [100.0, 90.0])], "no depth curve"),
    ([("DEPT", "FT", [1.0, 2.0]), ("DT", "FURLONG", [100.0, 90.0])],
     r"no curve to read \(vp: DT: unit 'FURLONG' not understood for vp\)"),
    ([("DEPT", "YD", [1.0, 2.0]), ("DT", "US/FT", [100.0, 90.0])], "'YD' is not understood"),
    ([("DEPT", "M", [1.0, 2.0]), ("RHOB", "", [2.3, 2.4])],
     r"no curve to read \(density: RHOB: no unit for density\)"),
    ([("DEPT", "M", [1.0, 2.0]), ("GR", "API", [50.0, 60.0])], "no curve to read; known"),
])
def test_bad_las_gets_one_clear_line(tmp_path, curves, message):
    f = _las(tmp_path / "bad.las", curves)
    with pytest.raises(ValueError, match=message) as info:
        read_well(f)
    assert "\n" not in str(info.value) and "bad.las" in str(info.value)


@pytest.mark.parametrize("curve, unit, values, message", [
    # Issue 21: DT in us/m labelled us/ft (Vp about 0.7 km/s) was accepted.
    ("DT", "US/FT", [420.0, 400.0, 440.0, 380.0, 100.0],
     (r"bad.las: curve DT \(US/FT\): its median, 400 US/FT, gives vp 0\.762 km/s, slower "
      r"than water \(1\.4 km/s\): the unit is wrong \(in US/M it would be 2\.5 km/s\)")),
    ("RHOB", "G/CC", [2300.0, 2400.0, 2350.0, 2.3, 2250.0],
     (r"curve RHOB \(G/CC\): its median, 2300 G/CC, gives density 2300 g/cm3, outside "
      r"\[1, 3\.5\] g/cm3: the unit is wrong \(in KG/M3 it would be 2\.3 g/cm3\)")),
    ("NPHI", "V/V", [25.0, 24.0, 23.0], r"gives porosity 24, outside \[-0\.15, 1\]"),
    ("NPHI", "%", [0.25, 0.3, 0.2, 0.22],
     r"curve NPHI \(%\): 95 % of its samples are below 0\.29.*look like a fraction"),
])
def test_a_curve_is_refused_only_when_its_bulk_says_the_unit_is_wrong(tmp_path, curve, unit,
                                                                       values, message):
    depth = 1000.0 + np.arange(len(values))
    f = _las(tmp_path / "bad.las", [("DEPT", "M", depth), (curve, unit, values)])
    with pytest.raises(ValueError, match=message) as info:
        read_well(f)
    assert "\n" not in str(info.value) and "--curve" in str(info.value)


def test_bad_single_samples_become_nan_and_are_counted_per_curve(tmp_path):
    """Issue 21: one washout spike or junk sample refused the whole file."""
    dt = np.full(20, 100.0)                    # us/ft: 3.048 km/s
    dt[[2, 5]] = [0.0, -0.035]                 # not positive
    dt[8] = 250.0                              # 1.22 km/s: slower than water
    dt[11] = 30.0                              # 10.2 km/s: above 7.5
    rhob = np.full(20, 2.3)
    rhob[[3, 4]] = [4.07, 0.4]                 # a washout spike, a value below 1 g/cm3
    f = _las(tmp_path / "s.las", [("DEPT", "M", 1000.0 + np.arange(20.0)),
                                  ("DT", "US/FT", dt), ("RHOB", "G/CC", rhob)])
    ds, message = _warned(f)
    assert np.flatnonzero(np.isnan(ds.vp.values)).tolist() == [2, 5, 8, 11]
    assert np.flatnonzero(np.isnan(ds.density.values)).tolist() == [3, 4]
    np.testing.assert_allclose(np.delete(ds.vp.values, [2, 5, 8, 11]), FOOT / 100e-6 / 1e3)
    assert ("DT (US/FT): 4 of 20 samples blanked: 2 not positive (first 0 US/FT at 1002 M), "
            "1 slower than water (< 1.4 km/s) (first 250 US/FT at 1008 M), 1 above 7.5 km/s "
            "(first 30 US/FT at 1011 M)") in message
    assert ("RHOB (G/CC): 2 of 20 samples blanked: 1 below 1 g/cm3 (first 0.4 G/CC at 1004 "
            "M), 1 above 3.5 g/cm3 (first 4.07 G/CC at 1003 M)") in message
    report = json.loads(ds.attrs["read_report"])
    vp = next(c for c in report["curves"] if c["variable"] == "vp")
    assert (vp["kept"], vp["samples"], vp["null"]) == (16, 20, 0)
    assert {k: v["count"] for k, v in vp["blanked"].items()} == {
        "not positive": 2, "slower than water (< 1.4 km/s)": 1, "above 7.5 km/s": 1}
    assert ds.vp.attrs["samples_blanked"] == 4 and ds.density.attrs["samples_blanked"] == 2


def test_null_takes_one_value_or_several(tmp_path):
    dt = [100.0, -9999.0, 90.0, -1.0, 80.0]
    f = _las(tmp_path / "n.las", [("DEPT", "M", [1.0, 2.0, 3.0, 4.0, 5.0]), ("DT", "US/FT", dt)])
    ds = _quiet(f, null=[-9999, -1.0])
    assert np.flatnonzero(np.isnan(ds.vp.values)).tolist() == [1, 3]
    assert json.loads(ds.attrs["read_report"])["curves"][0]["null"] == 2
    assert json.loads(ds.attrs["read_report"])["null_values"] == [-999.25, -9999.0, -1.0]
    csv = tmp_path / "n.csv"
    csv.write_text("DEPT (m),DT (us/ft)\n1,100\n2,-9999\n3,90\n")
    assert np.isnan(_quiet(csv, null=-9999).vp.values[1])
    with pytest.raises(ValueError, match="null contains NaN"):
        read_well(csv, null=np.nan)


def test_unknown_unit_on_an_unused_or_unnamed_curve_never_stops_a_read(tmp_path):
    """Issue 21: a neutron in a unit not understood stopped a file whose DT and RHOB were
    fine. An unused curve is never looked at; a default choice passed over is noted."""
    f = _las(tmp_path / "x.las", [("DEPT", "M", [1.0, 2.0]), ("DT", "US/M", [400.0, 410.0]),
                                  ("RHOB", "G/CC", [2.3, 2.4]), ("NPHI", "XPU", [25.0, 24.0]),
                                  ("GR", "FURLONG", [50.0, 60.0])])
    ds, message = _warned(f)
    assert set(ds.data_vars) == {"vp", "density"}
    assert message == "x.las: porosity left out: NPHI: unit 'XPU' not understood for porosity"
    assert "GR" not in ds.attrs["read_report"]
    assert "porosity  -  left out: NPHI: unit 'XPU'" in format_read_report(ds)
    # A total porosity present: the neutron is not even looked at.
    g = _las(tmp_path / "y.las", [("DEPT", "M", [1.0, 2.0]), ("PHIT", "V/V", [0.2, 0.3]),
                                  ("NPHI", "XPU", [25.0, 24.0])])
    np.testing.assert_array_equal(_quiet(g).porosity, [0.2, 0.3])
    # Named by the user, an unknown unit is an error.
    with pytest.raises(ValueError, match=r"x.las: curve 'NPHI' for porosity: unit 'XPU' is not"):
        read_well(f, curves={"porosity": "NPHI"})


def test_curve_choice_overridable(tmp_path):
    f = _las(tmp_path / "c.las", [("DEPT", "M", [1.0, 2.0]), ("DT", "US/M", [400.0, 500.0]),
                                  ("DTCO", "US/M", [250.0, 200.0]),
                                  ("VPX", "M/S", [3000.0, 3100.0]), ("PHIT", "V/V", [0.2, 0.3])])
    np.testing.assert_allclose(_quiet(f).vp, [2.5, 2.0])                     # DT by default
    np.testing.assert_allclose(_quiet(f, curves={"vp": "DTCO"}).vp, [4.0, 5.0])
    np.testing.assert_allclose(_quiet(f, curves={"vp": "vpx"}).vp, [3.0, 3.1])  # a velocity
    assert "porosity" not in _quiet(f, curves={"porosity": None}).data_vars
    with pytest.raises(ValueError, match=r"c.las: no curve 'DTSM' for vs.*the file has DT, "
                                         r"DTCO, VPX, PHIT"):
        read_well(f, curves={"vs": "DTSM"})
    with pytest.raises(ValueError, match="curves: 'sonic' is not a variable"):
        read_well(f, curves={"sonic": "DT"})


def test_repeated_mnemonics_are_never_chosen_silently(tmp_path):
    las = lasio.LASFile()
    las.append_curve("DEPT", np.array([1000.0, 1001.0]), unit="M")
    las.append_curve("DT", np.array([100.0, 101.0]), unit="US/FT")
    las.append_curve("DT", np.array([110.0, 111.0]), unit="US/FT")   # lasio: DT:1, DT:2
    las.append_curve("RHOB", np.array([2.3, 2.4]), unit="G/CC")
    las.write(str(tmp_path / "dup.las"), version=2.0, wrap=False)
    ds, message = _warned(tmp_path / "dup.las")
    assert "vp" not in ds and "DT appears 2 times (DT:1, DT:2): name one with " \
                               "curves={'vp': 'DT:2'}" in message
    np.testing.assert_allclose(_quiet(tmp_path / "dup.las", curves={"vp": "DT:2"}).vp,
                               [FOOT / 110e-6 / 1e3, FOOT / 111e-6 / 1e3], rtol=1e-14)
    with pytest.raises(ValueError, match=r"curve DT appears 2 times \(DT:1, DT:2\)"):
        read_well(tmp_path / "dup.las", curves={"vp": "DT"})


def test_text_in_a_used_curve_is_blanked_and_text_curves_skipped(tmp_path):
    las = lasio.LASFile()
    las.append_curve("DEPT", np.array([1000.0, 1001.0]), unit="M")
    las.append_curve("DT", np.array([100.0, 101.0]), unit="US/FT")
    las.append_curve("LITH", np.array(["SAND", "SHALE"], dtype=object), unit="")
    las.write(str(tmp_path / "lith.las"), version=2.0, wrap=False)
    np.testing.assert_allclose(_quiet(tmp_path / "lith.las").vp, [3.048, 304.8 / 101.0],
                               rtol=1e-15)
    f = tmp_path / "w.csv"
    f.write_text("DEPT (m),DT (us/ft),LITH\n1000,100,SAND\n1010,abc,SHALE\n1020,90,SAND\n")
    ds, message = _warned(f)
    assert np.isnan(ds.vp.values[1]) and "1 not a number (first text at 1010 m)" in message


def test_rows_without_a_depth_and_repeated_depths(tmp_path):
    f = tmp_path / "d.csv"
    f.write_text("DEPT (m),DT (us/m)\n1000,400\n,410\n1010,420\n1010,430\n1020,440\n")
    ds, message = _warned(f)
    np.testing.assert_allclose(ds.depth, [1000.0, 1010.0, 1020.0])
    np.testing.assert_allclose(ds.vp, [2.5, 1000.0 / 420.0, 1000.0 / 440.0])   # first kept
    assert "1 data rows without a depth left out (the first on line 3)" in message
    assert ("1 data rows repeating an earlier depth left out (the first: 1010 m on line 5, "
            "as on line 4)") in message
    g = _las(tmp_path / "r.las", [("DEPT", "M", [1.0, 1.0, 1.0, 1.0, 2.0]),
                                  ("RHOB", "G/CC", [2.3, 2.4, 2.5, 2.6, 2.7])])
    with pytest.raises(ValueError, match=r"r.las: depth curve 'DEPT' is not an index: 3 of 5 "
                                         r"rows repeat a depth \(as 1 M on lines \d+ and \d+\)"):
        read_well(g)


def test_las_1_2_and_wrapped_files_are_read(tmp_path):
    """Issue 21: LAS 1.2 and wrapped LAS were refused although lasio reads both."""
    depth = 1000.0 + np.arange(6.0)
    curves = [("DEPT", "M", depth), ("DT", "US/M", 400.0 + depth - 1000.0),
              ("RHOB", "K/M3", np.full(6, 2300.0)), ("NPHI", "V/V", np.full(6, 0.25)),
              *[(f"R{k}", "OHMM", np.full(6, 10.0)) for k in range(8)]]
    for version in (1.2, 2.0):
        f = _las(tmp_path / f"w{version}.las", curves, wrap=True, version=version)
        assert f.read_text().count("\n") > 40          # really wrapped
        ds = _quiet(f)
        np.testing.assert_allclose(ds.vp, 1000.0 / (400.0 + depth - 1000.0), rtol=1e-14)
        np.testing.assert_allclose(ds.density, 2.3, rtol=1e-15)
        assert format_read_report(ds).startswith(f"w{version}.las (LAS {version}, wrapped)")


def test_truncated_line_named_and_broken_line_read_as_lasio_does(tmp_path):
    f = _las(tmp_path / "w.las", [("DEPT", "M", [1.0, 2.0, 3.0]),
                                  ("DT", "US/M", [400.0, 410.0, 420.0]),
                                  ("RHOB", "G/CC", [2.3, 2.4, 2.5])])
    lines = f.read_text().splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("~A")) + 2
    parts = lines[i].split()
    broken = lines[:i] + [" ".join(parts[:2]), parts[2]] + lines[i + 1:]
    f.write_text("\n".join(broken) + "\n")                 # one row over two lines
    np.testing.assert_allclose(_quiet(f).density, [2.3, 2.4, 2.5])
    truncated = lines[:i] + [" ".join(parts[:2])] + lines[i + 1:]
    f.write_text("\n".join(truncated) + "\n")
    with pytest.raises(ValueError, match=rf"w.las: line {i + 1} has 2 values, the ~Curve "
                                         r"section lists 3 curves \(a truncated line\)"):
        read_well(f)


def test_comma_delimited_with_or_without_spaces_and_dlm(tmp_path):
    head = ("~Version\nVERS. 2.0 :\nWRAP. NO :\n{dlm}~Well\nNULL. -999.25 :\nWELL. C :\n"
            "~Curve\nDEPT.M :\nDT.US/M :\nRHOB.G/CC :\n~A\n")
    for dlm in ("", "DLM. COMMA :\n"):
        for sep in (",", ", "):
            f = tmp_path / "c.las"
            f.write_text(head.format(dlm=dlm) + "\n".join(
                sep.join(row) for row in (("1000.0", "400.0", "2.3"),
                                          ("1001.0", "-999.25", "2.4"),
                                          ("1002.0", "500.0", "2.5"))) + "\n")
            ds = _quiet(f)
            np.testing.assert_allclose(ds.vp, [2.5, np.nan, 2.0], rtol=1e-15)
            np.testing.assert_allclose(ds.density, [2.3, 2.4, 2.5], rtol=1e-15)


def test_read_in_pieces_equals_read_at_once(tmp_path, monkeypatch):
    """The memory-bounded read (data handed to lasio in pieces) gives what one read gives,
    whatever the piece boundaries."""
    from rockcem import _well_files

    rng = np.random.default_rng(7)
    n = 300
    f = _las(tmp_path / "p.las", [("DEPT", "FT", 5000.0 + 0.5 * np.arange(n)),
                                  ("DT", "US/FT", 80.0 + rng.random(n)),
                                  ("RHOB", "G/CC", 2.2 + 0.2 * rng.random(n)),
                                  ("GR", "GAPI", 50.0 + rng.random(n))])
    whole = _quiet(f)
    for size in (1, 97, 1000):
        monkeypatch.setattr(_well_files, "_CHUNK_CHARS", size)
        pieces = _quiet(f)
        for v in ("vp", "density"):
            np.testing.assert_array_equal(pieces[v].values, whole[v].values)


def test_unknown_format_and_missing_file(tmp_path):
    with pytest.raises(ValueError, match="unknown format"):
        read_well(tmp_path / "log.dlis")
    with pytest.raises(ValueError, match="not found"):
        read_well(tmp_path / "none.las")
    junk = tmp_path / "junk.las"
    junk.write_text("hello\n")
    with pytest.raises(ValueError, match="not a readable LAS file"):
        read_well(junk)


@pytest.mark.parametrize("text, message", [
    ("DEPT (m),DT (us/ft)\n1000,100,5\n", r"line 2 has 3 fields, the header 2"),   # not a label
    ("DEPT (m),DT (us/ft)\n1000,100\n1010\n", r"line 3 has 1 fields, the header 2"),
    ("DEPT (m),DT (us/ft)\n", "no data rows"),
    ("", "empty file"),
])
def test_csv_lines_of_the_wrong_width_are_refused(tmp_path, text, message):
    f = tmp_path / "w.csv"
    f.write_text(text)
    with pytest.raises(ValueError, match=message) as info:
        read_well(f)
    assert "w.csv" in str(info.value)


def test_micro_sign_and_greek_mu_in_slowness_units(tmp_path):
    f = tmp_path / "mu.csv"
    f.write_text("DEPT (m),DT (\u00b5s/ft),DTS [\u03bcs/m]\n1000,100,500\n")
    ds = _quiet(f)
    np.testing.assert_allclose(ds.vp.values, [FOOT / 100e-6 / 1000.0], rtol=1e-15)
    np.testing.assert_allclose(ds.vs.values, [2.0], rtol=1e-15)


def test_depth_unit_from_the_start_depth_when_the_curve_has_none(tmp_path):
    f = _las(tmp_path / "d.las", [("DEPT", "FT", [1000.0, 1010.0]),
                                  ("DT", "US/FT", [100.0, 90.0])])
    f.write_text(f.read_text().replace("DEPT.FT", "DEPT.  "))
    np.testing.assert_allclose(_quiet(f).depth, [304.8, 307.848], rtol=1e-15)
    f.write_text(f.read_text().replace("STRT.FT", "STRT.  ").replace("STOP.FT", "STOP.  ")
                 .replace("STEP.FT", "STEP.  "))
    with pytest.raises(ValueError, match="depth curve 'DEPT': no unit given"):
        read_well(f)


@pytest.mark.parametrize("offset, match", [
    (np.nan, "depth_offset contains NaN"), (np.inf, "depth_offset"), (-np.inf, "depth_offset"),
    (1e300, r"depth_offset \(m\) must lie in \[-20000, 20000\]"), ([1.0, 2.0], "depth_offset"),
])
def test_depth_offset_must_be_a_finite_depth(tmp_path, offset, match):
    """NaN or inf gave NaN or -inf depths."""
    f = tmp_path / "w.csv"
    f.write_text("DEPT (m),DT (us/ft)\n1000,100\n2000,80\n")
    with pytest.raises(ValueError, match=match):
        read_well(f, depth_offset=offset)
    np.testing.assert_array_equal(read_well(f, depth_offset=25.0).depth, [975.0, 1975.0])


def test_shipped_well_by_name_from_any_folder(tmp_path, monkeypatch):
    """Issue 21: shipped well files resolved only from the repository root."""
    monkeypatch.chdir(tmp_path)
    for given in ("synthetic_well", "synthetic_well.las", "datasets/wells/synthetic_well.las"):
        assert _quiet(given).attrs["source_file"] == "synthetic_well.las"
    with pytest.raises(ValueError, match=r"well file 'synthetic_wel' not found; did you mean "
                                         r"synthetic_well\?"):
        read_well("synthetic_wel")
    with pytest.raises(ValueError, match=r"well file 'elsewhere/x.las' not found$"):
        read_well("elsewhere/x.las")


# ----------------------------------------------------------------------------- misfit
def _pair(model, log, name="vp", attrs=None):
    from rockcem.variables import build_dataset

    z = 100.0 * (1.0 + np.arange(len(log)))
    scene = build_dataset({name: (("depth",), model)}, {"depth": (("depth",), z)})
    well = build_dataset({name: (("depth",), log)}, {"depth": (("depth",), z)})
    well[name].attrs.update(attrs or {})
    return scene, well


def test_misfit_counts_the_deepest_sample():
    from rockcem.wells import well_misfit

    scene, well = _pair([2.0, 2.5, 3.0], [2.2, 2.5, 2.4])
    rows = well_misfit(scene, well)
    assert rows.n.tolist() == [3] and rows.misfit.tolist() == ["model/log - 1"]
    # m/o - 1 = -1/11, 0, 1/4 (the deepest sample included).
    np.testing.assert_allclose(rows.bias, (-1.0 / 11.0 + 0.25) / 3.0, rtol=1e-14)
    split = well_misfit(scene, well, intervals=[100.0, 200.0, 300.0])
    assert split.n.tolist() == [1, 2]


def test_porosity_misfit_is_absolute_and_zeros_are_not_dropped():
    """Issue 21: a relative porosity misfit blew up near 0 and dropped zeros silently."""
    from rockcem.wells import well_misfit

    scene, well = _pair([0.10, 0.20, 0.05], [0.0, 0.25, 0.05], "porosity",
                        {"log_label": "NPHI, apparent"})
    row = well_misfit(scene, well).iloc[0]
    assert row.n == 3 and row.misfit == "model - log" and row.log == "NPHI, apparent"
    np.testing.assert_allclose(row.bias, (0.10 - 0.05 + 0.0) / 3.0, rtol=1e-14)
    np.testing.assert_allclose(row.rms, np.sqrt((0.01 + 0.0025) / 3.0), rtol=1e-14)
    scene, well = _pair([2.0, 2.5], [0.0, 2.5])
    with pytest.raises(ValueError, match=r"log vp is 0 at 100 m; its misfit is relative"):
        well_misfit(scene, well)


@pytest.mark.parametrize("intervals, match", [
    # Issue 24: `compare --intervals nan 1000` printed a table of NaN with exit code 0.
    ([np.nan, 300.0], "intervals contains NaN"),
    ([100.0, np.inf], "finite"),
    ([-np.inf, 300.0], "finite"),
    ([300.0, 100.0], "increasing"),
    (["100", "300"], "intervals must be a real number"),
])
def test_misfit_intervals_must_be_finite_and_increasing(intervals, match):
    from rockcem.wells import well_misfit

    scene, _ = _pair([2.0, 2.5, 3.0], [2.0, 2.5, 3.0])
    with pytest.raises(ValueError, match=match):
        well_misfit(scene, scene, intervals=intervals)


# ----------------------------------------------------------------------------- the CLI
@pytest.fixture
def scene_nc(tmp_path):
    """A small scene file (two models, vp and porosity over 0-3000 m) for compare."""
    from rockcem.scene import write_dataset
    from rockcem.variables import build_dataset

    z = np.linspace(0.0, 3000.0, 31)
    vp = np.stack([2.0 + 1e-3 * z, 2.1 + 1e-3 * z], axis=1)
    ds = build_dataset({"vp": (("depth", "model"), vp),
                        "porosity": (("depth",), 0.4 - 1e-4 * z)},
                       {"depth": (("depth",), z), "model": (("model",), ["a", "b"])},
                       {"scene_name": "small"})
    return write_dataset(ds, tmp_path / "small.nc")


def test_cli_compare_prints_the_read_report_and_the_misfit_kinds(tmp_path, scene_nc, capsys):
    from rockcem.cli import main

    z = np.array([1000.0, 1500.0, 2000.0])
    f = _las(tmp_path / "w.las", [("DEPT", "M", z), ("DT", "US/M", 1e3 / (2.0 + 1e-3 * z)),
                                  ("DTCO", "US/M", [300.0, -9999.0, 250.0]),
                                  ("NPHI", "LPU", 100.0 * (0.4 - 1e-4 * z))])
    assert main(["compare", str(scene_nc), "--well", str(f)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("read w.las (LAS 2.0): well TEST-1, 3 rows; depth DEPT (M)")
    assert "porosity  NPHI (LPU)  kept 3 of 3" in out
    assert "model/log - 1 for vp, vs and density, of model - log for porosity" in out
    assert ("porosity log NPHI: a neutron porosity, apparent: in the units of the tool's "
            "calibration matrix (limestone units), not the total porosity of the rock") in out
    lines = out.splitlines()
    head = next(i for i, line in enumerate(lines) if line.split()[:1] == ["variable"])
    assert lines[head].split() == ["variable", "model", "top", "base", "n", "rms", "bias",
                                   "misfit", "log"]
    table = [line.split() for line in lines[head + 1:]]
    assert [row[:2] for row in table] == [["vp", "a"], ["vp", "b"], ["porosity", "-"]]
    assert table[0][4] == "3" and abs(float(table[0][5])) < 1e-6   # model a is the log
    rel = 0.1 / (2.0 + 1e-3 * z)                                 # model b: 0.1 km/s faster
    np.testing.assert_allclose([float(v) for v in table[1][5:7]],
                               [np.sqrt(np.mean(rel ** 2)), rel.mean()], atol=5e-5)   # 4 decimals
    assert table[2][-5:] == ["model", "-", "log", "NPHI,", "apparent"]
    assert table[0][-4:] == ["model/log", "-", "1", "DT"]
    # --curve, --null: another curve, and its -9999 as a null; --quiet: no report.
    assert main(["compare", str(scene_nc), "--well", str(f), "--curve", "vp=DTCO",
                 "--null", "-9999", "--curve", "porosity=none", "-q"]) == 0
    captured = capsys.readouterr()
    assert not captured.out.startswith("read") and captured.err == ""
    rows = [line.split() for line in captured.out.splitlines()[1:]]
    assert [row[:5] for row in rows[1:]] == [["vp", "a", "1000", "2000", "2"],
                                             ["vp", "b", "1000", "2000", "2"]]   # no porosity
    assert rows[1][-1] == "DTCO"


def test_cli_bad_well_one_line(tmp_path, scene_nc, capsys):
    from rockcem.cli import main

    truncated = tmp_path / "t.las"
    truncated.write_text("~V\nVERS. 2.0 :\nWRAP. NO :\n~W\nNULL. -999.25 :\n~C\nDEPT.M :\n"
                         "DT.US/M :\n~A\n1000 400\n1001\n1002 410\n")
    junk = tmp_path / "junk.las"
    junk.write_text("~V\nhello\n")
    for f, extra in ((truncated, []), (junk, []), (truncated, ["--curve", "vp"]),
                     (truncated, ["--curve", "sonic=DT"])):
        assert main(["compare", str(scene_nc), "--well", str(f), *extra]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rockcem: error:"), err
    assert main(["compare", str(scene_nc), "--well", str(truncated)]) == 2
    assert "t.las: line 11 has 1 values" in capsys.readouterr().err


def test_cli_compare_nan_interval_one_line(tmp_path, scene_nc, capsys):
    from rockcem.cli import main

    f = tmp_path / "w.csv"
    f.write_text("DEPT (m),DT (us/ft)\n1000,100\n2000,80\n")
    for args in (["--intervals", "nan", "1000"], ["--depth-offset", "inf"]):
        assert main(["compare", str(scene_nc), "--well", str(f), *args]) == 2
        captured = capsys.readouterr()
        assert captured.err.count("\n") == 1 and captured.err.startswith("rockcem: error:")
        assert "nan" not in captured.out.lower()


def test_cli_wells_lists_the_shipped_wells(capsys):
    from rockcem.cli import main

    assert main(["wells"]) == 0
    out = capsys.readouterr().out
    assert "synthetic_well " in out and "lookalike_north_sea" in out
