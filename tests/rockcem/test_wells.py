"""Well-log reader: LAS 2.0 round trips through lasio, CSV headers, and the refusals."""

import numpy as np
import pytest

from rockcem.wells import read_well

lasio = pytest.importorskip("lasio")

FOOT = 0.3048   # m, exact by definition (international foot, 1959)


def _las(path, curves, *, null=-999.25, wrap=False):
    las = lasio.LASFile()
    for name, unit, values in curves:
        las.append_curve(name, np.asarray(values, dtype=float), unit=unit)
    las.well["NULL"].value = null
    las.well["WELL"].value = "TEST-1"
    las.write(str(path), version=2.0, wrap=wrap)
    return path


def test_las_round_trip_feet_and_microseconds_per_foot(tmp_path):
    depth_ft = np.array([3000.0, 3000.5, 3001.0, 3001.5])
    dt = np.array([100.0, 95.5, -999.25, 80.0])          # us/ft, one null sample
    dts = np.array([180.0, 170.0, 160.0, 150.0])
    rhob = np.array([2.30, 2.35, 2.40, 2.45])             # g/cm3
    nphi = np.array([25.0, 24.0, 23.0, 22.0])             # percent
    f = _las(tmp_path / "w.las", [("DEPT", "FT", depth_ft), ("DT", "US/FT", dt),
                                  ("DTS", "US/FT", dts), ("RHOB", "G/CC", rhob),
                                  ("NPHI", "%", nphi)])
    ds = read_well(f)
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
    assert ds.attrs["well"] == "TEST-1"


def test_las_in_metres_and_microseconds_per_metre_decreasing_depth(tmp_path):
    depth = np.array([2000.0, 1999.0, 1998.0])            # logged upwards
    dt = np.array([400.0, 500.0, 250.0])                   # us/m
    f = _las(tmp_path / "m.las", [("DEPTH", "M", depth), ("DTCO", "us/m", dt),
                                  ("PHIT", "v/v", [0.1, 0.2, 0.3])])
    ds = read_well(f, depth_offset=100.0)
    np.testing.assert_allclose(ds.depth.values, [1898.0, 1899.0, 1900.0], rtol=0)
    np.testing.assert_allclose(ds.vp.values, [4.0, 2.0, 2.5], rtol=1e-15)
    np.testing.assert_allclose(ds.porosity.values, [0.3, 0.2, 0.1])
    assert "comment" not in ds.porosity.attrs


def test_csv_units_from_header(tmp_path):
    f = tmp_path / "w.csv"
    f.write_text("# a comment line\nDEPT (ft),VP [m/s],RHOB (kg/m3),PHIT (frac)\n"
                 "1000,3000,2300,0.2\n2000,,2400,-999.25\n")
    ds = read_well(f)
    np.testing.assert_allclose(ds.depth.values, [304.8, 609.6], rtol=1e-15)
    assert ds.vp.values[0] == 3.0 and np.isnan(ds.vp.values[1])
    np.testing.assert_allclose(ds.density.values, [2.3, 2.4], rtol=1e-15)
    assert np.isnan(ds.porosity.values[1])


@pytest.mark.parametrize("curves, message", [
    ([("TIME", "S", [1.0, 2.0]), ("DT", "US/FT", [100.0, 90.0])], "no depth curve"),
    ([("DEPT", "FT", [1.0, 2.0]), ("DT", "FURLONG", [100.0, 90.0])], "'FURLONG' is not"),
    ([("DEPT", "YD", [1.0, 2.0]), ("DT", "US/FT", [100.0, 90.0])], "'YD' is not"),
    ([("DEPT", "M", [1.0, 2.0]), ("RHOB", "", [2.3, 2.4])], "no unit given"),
    ([("DEPT", "M", [1.0, 1.0]), ("RHOB", "G/CC", [2.3, 2.4])], "repeats"),
    ([("DEPT", "M", [1.0, 2.0]), ("NPHI", "V/V", [25.0, 24.0])], "is the unit 'V/V' right"),
    ([("DEPT", "M", [1.0, 2.0]), ("GR", "API", [50.0, 60.0])], "no curve to read"),
])
def test_bad_las_gets_one_clear_line(tmp_path, curves, message):
    f = _las(tmp_path / "bad.las", curves)
    with pytest.raises(ValueError, match=message) as info:
        read_well(f)
    assert "\n" not in str(info.value) and "bad.las" in str(info.value)


def test_wrapped_lines_are_refused(tmp_path):
    f = _las(tmp_path / "w.las", [("DEPT", "M", [1.0, 2.0, 3.0]),
                                  ("DT", "US/M", [400.0, 410.0, 420.0]),
                                  ("RHOB", "G/CC", [2.3, 2.4, 2.5])])
    text = f.read_text()
    lines = text.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("~A")) + 2
    parts = lines[i].split()
    lines[i:i + 1] = [" ".join(parts[:2]), parts[2]]      # one data line broken in two
    f.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError, match=r"line \d+ has 2 values.*3 curves"):
        read_well(f)
    g = _las(tmp_path / "wrap.las", [("DEPT", "M", [1.0, 2.0]), ("DT", "US/M", [400.0, 410.0])],
             wrap=True)
    with pytest.raises(ValueError, match="WRAP. YES"):
        read_well(g)


def test_cli_bad_well_one_line(tmp_path, capsys):
    from rockcem.cli import main

    g = _las(tmp_path / "wrap.las", [("DEPT", "M", [1.0, 2.0]), ("DT", "US/M", [400.0, 410.0])],
             wrap=True)
    junk = tmp_path / "junk.las"
    junk.write_text("~V\nhello\n")
    for f in (g, junk):
        assert main(["compare", "carcione2022_shale", "--well", str(f)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and err.startswith("rockcem: error:"), err


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


def test_las_version_named_plainly(tmp_path):
    f = _las(tmp_path / "v.las", [("DEPT", "M", [1.0, 2.0]), ("DT", "US/M", [400.0, 410.0])])
    f.write_text(f.read_text().replace("VERS.   2.0", "VERS.   1.2"))
    with pytest.raises(ValueError, match=r"v.las: LAS version 1.2; only LAS 2.0 is read$"):
        read_well(f)


def test_misfit_counts_the_deepest_sample():
    from rockcem.variables import build_dataset
    from rockcem.wells import well_misfit

    z = np.array([100.0, 200.0, 300.0])
    scene = build_dataset({"vp": (("depth",), [2.0, 2.5, 3.0])}, {"depth": (("depth",), z)})
    well = build_dataset({"vp": (("depth",), [2.2, 2.5, 2.4])}, {"depth": (("depth",), z)})
    rows = well_misfit(scene, well)
    assert rows.n.tolist() == [3]
    # m/o - 1 = -1/11, 0, 1/4 (the deepest sample included).
    np.testing.assert_allclose(rows.bias, (-1.0 / 11.0 + 0.25) / 3.0, rtol=1e-14)
    split = well_misfit(scene, well, intervals=[100.0, 200.0, 300.0])
    assert split.n.tolist() == [1, 2]


def test_micro_sign_and_greek_mu_in_slowness_units(tmp_path):
    f = tmp_path / "mu.csv"
    f.write_text("DEPT (m),DT (\u00b5s/ft),DTS [\u03bcs/m]\n1000,100,500\n")
    ds = read_well(f)
    np.testing.assert_allclose(ds.vp.values, [FOOT / 100e-6 / 1000.0], rtol=1e-15)
    np.testing.assert_allclose(ds.vs.values, [2.0], rtol=1e-15)


def test_text_curves_skipped_repeated_curves_refused(tmp_path):
    las = lasio.LASFile()
    las.append_curve("DEPT", np.array([1000.0, 1001.0]), unit="M")
    las.append_curve("DT", np.array([100.0, 101.0]), unit="US/FT")
    las.append_curve("LITH", np.array(["SAND", "SHALE"], dtype=object), unit="")
    las.write(str(tmp_path / "lith.las"), version=2.0, wrap=False)
    np.testing.assert_allclose(read_well(tmp_path / "lith.las").vp, [3.048, 304.8 / 101.0],
                               rtol=1e-15)
    las.append_curve("DT", np.array([110.0, 111.0]), unit="US/FT")   # lasio: DT:1, DT:2
    las.write(str(tmp_path / "dup.las"), version=2.0, wrap=False)
    with pytest.raises(ValueError, match=r"dup.las: curve DT appears 2 times \(DT:1, DT:2\)"):
        read_well(tmp_path / "dup.las")
    f = tmp_path / "w.csv"
    f.write_text("DEPT (m),DT (us/ft),LITH\n1000,100,SAND\n1010,abc,SHALE\n")
    with pytest.raises(ValueError, match=r"w.csv: curve 'DT': 'abc' in data row 2 is not a "
                                         r"number"):
        read_well(f)


def test_depth_unit_from_the_start_depth_when_the_curve_has_none(tmp_path):
    f = _las(tmp_path / "d.las", [("DEPT", "FT", [1000.0, 1010.0]),
                                  ("DT", "US/FT", [100.0, 90.0])])
    f.write_text(f.read_text().replace("DEPT.FT", "DEPT.  "))
    np.testing.assert_allclose(read_well(f).depth, [304.8, 307.848], rtol=1e-15)
    f.write_text(f.read_text().replace("STRT.FT", "STRT.  ").replace("STOP.FT", "STOP.  ")
                 .replace("STEP.FT", "STEP.  "))
    with pytest.raises(ValueError, match="depth curve 'DEPT': no unit given"):
        read_well(f)


@pytest.mark.parametrize("intervals, match", [
    # Issue 24: `compare --intervals nan 1000` printed a table of NaN with exit code 0.
    ([np.nan, 300.0], "intervals contains NaN"),
    ([100.0, np.inf], "finite"),
    ([-np.inf, 300.0], "finite"),
    ([300.0, 100.0], "increasing"),
    (["100", "300"], "intervals must be a real number"),
])
def test_misfit_intervals_must_be_finite_and_increasing(intervals, match):
    from rockcem.variables import build_dataset
    from rockcem.wells import well_misfit

    z = np.array([100.0, 200.0, 300.0])
    scene = build_dataset({"vp": (("depth",), [2.0, 2.5, 3.0])}, {"depth": (("depth",), z)})
    with pytest.raises(ValueError, match=match):
        well_misfit(scene, scene, intervals=intervals)


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


def test_cli_compare_nan_interval_one_line(tmp_path, capsys):
    from rockcem.cli import main

    f = tmp_path / "w.csv"
    f.write_text("DEPT (m),DT (us/ft)\n1000,100\n2000,80\n")
    for args in (["--intervals", "nan", "1000"], ["--depth-offset", "inf"]):
        assert main(["compare", "carcione2022_shale", "--well", str(f), *args]) == 2
        captured = capsys.readouterr()
        assert captured.err.count("\n") == 1 and captured.err.startswith("rockcem: error:")
        assert "nan" not in captured.out.lower()
