"""The LAS look-alikes of datasets/wells/ (real layouts, planted faults) and the real CWLS
example: each fault of issue 21 read as the planted values say.

The look-alikes copy the layout and faults of public wells that cannot be shipped here (see
datasets/wells/README.md); their values are the sandstone scene plus noise. The expected values
below come from the planting (which row, which value), and the file's own numbers are read with
lasio directly and converted by the definitions (1 ft = 0.3048 m, v = 1/slowness), never from
the reader under test.

Regenerate the files (deterministic; needs the sandstone scene)::

    python tests/rockcem/test_wells_lookalikes.py datasets/wells
"""

import logging
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

lasio = pytest.importorskip("lasio")

from rockcem._data import data_path
from rockcem.wells import WellLogWarning, format_read_report, read_well

FOOT = 0.3048                    # m, exact
SIGMA = {"vp": 0.06, "vs": 0.04, "density": 0.025, "porosity": 0.012}
# The planted faults: (file, curve) -> (row index, value written there).
SPIKE = ("lookalike_nova_scotia.las", "RHOB", 100, 4.07)        # g/cm3, washout spike
JUNK = ("lookalike_nova_scotia.las", "DT", 180, -0.035)         # us/ft, junk sample
NS_TOP_NULL = 5             # rows at the top of lookalike_nova_scotia.las without DT, DTS
NORTH_SEA_UNLOGGED = 100    # rows at the top of lookalike_north_sea.las: RHOB, NPHI -9999
NORTH_SEA_DT_END = 10       # rows at the bottom of lookalike_north_sea.las: DT -9999
NPHI_LPU_OFFSET = -3.0      # p.u.: the neutron of lookalike_north_sea.las reads phi - 3 %
KANSAS_REPEATS = 3          # the last row of lookalike_kansas_comma.las written 3 more times


# ----------------------------------------------------------------------------- the generator
def _logs(depth_m, seed):
    """The sandstone scene's patchy-cement logs at ``depth_m`` plus noise of SIGMA."""
    from rockcem.scene import load_scene, run_scene
    from rockcem.synthetic_well import synthetic_well

    scene = load_scene("carcione2022_sandstone").replace(**{"path.depth_step": 10.0})
    return synthetic_well(run_scene(scene), depth_m, model="patchy_cement", seed=seed,
                          sigma=SIGMA, name="LOOKALIKE")


def _write(path, curves, *, well, version=2.0, wrap=False, other="", null=-999.25):
    las = lasio.LASFile()
    las.well["WELL"].value = well
    las.well["NULL"].value = null
    las.well["COMP"].value = "ROCKCEM LOOK-ALIKE (SYNTHETIC DATA)"
    for name, unit, values, descr in curves:
        las.append_curve(name, np.asarray(values, dtype=float), unit=unit, descr=descr)
    las.other = other
    with open(path, "w", newline="\n") as fh:
        las.write(fh, version=version, wrap=wrap, fmt="%.4f")
    return path


def write_lookalikes(folder):
    """Write the four look-alikes into ``folder`` (see datasets/wells/README.md)."""
    folder = Path(folder)
    rng = np.random.default_rng(21)
    # Nova Scotia (P-129, Kennetcook #2): LAS 2.0 wrapped, depth m, sonic us/ft, a spike.
    z = np.arange(600.0, 2600.0 + 1.0, 8.0)
    w = _logs(z, seed=2101)
    dt, dts, rhob = 304.8 / w.vp.values, 304.8 / w.vs.values, w.density.values.copy()
    dt[:NS_TOP_NULL] = dts[:NS_TOP_NULL] = -999.25
    rhob[SPIKE[2]] = SPIKE[3]
    dt[JUNK[2]] = JUNK[3]
    _write(folder / SPIKE[0], [
        ("DEPT", "m", z, "Depth"), ("CALI", "in", 8.5 + 0.1 * rng.standard_normal(z.size),
                                    "Caliper"),
        ("DT", "us/ft", dt, "Compressional slowness"), ("DTS", "us/ft", dts, "Shear slowness"),
        ("RHOB", "g/cm3", rhob, "Bulk density"),
        ("NPHI_SAN", "m3/m3", w.porosity.values, "Neutron porosity, sandstone matrix"),
        ("GR", "gAPI", 60.0 + 10.0 * rng.standard_normal(z.size), "Gamma ray"),
        *[(f"RLA{k}", "ohm.m", 5.0 + rng.standard_normal(z.size), "Laterolog resistivity")
          for k in range(1, 6)]],
        well="LOOKALIKE P-129", wrap=True,
        other=f"Look-alike of a Nova Scotia well (P-129): LAS 2.0 wrapped. Synthetic data "
              f"(scene carcione2022_sandstone, patchy_cement, plus noise). Planted: RHOB "
              f"{SPIKE[3]} g/cm3 at {z[SPIKE[2]]:g} m (a washout spike), DT {JUNK[3]} us/ft at "
              f"{z[JUNK[2]]:g} m; no sonic above {z[NS_TOP_NULL]:g} m.")
    # Dutch North Sea (F03-02): nulls written as -9999 under a header NULL of -999.25, LPU.
    z = np.arange(900.0, 2400.0 + 1.0, 6.0)
    w = _logs(z, seed=2102)
    nphi = 100.0 * w.porosity.values + NPHI_LPU_OFFSET
    rhob, dt = w.density.values.copy(), 304.8 / w.vp.values
    nphi[:NORTH_SEA_UNLOGGED] = rhob[:NORTH_SEA_UNLOGGED] = -9999.0
    dt[-NORTH_SEA_DT_END:] = -9999.0
    _write(folder / "lookalike_north_sea.las", [
        ("DEPT", "M", z, "Index curve"), ("SP", "MV", 40.0 + 5.0 * rng.standard_normal(z.size),
                                          "IEL"),
        ("ILD", "OHMM", 2.0 + 0.2 * rng.standard_normal(z.size), "IEL"),
        ("NPHI", "LPU", nphi, "SNP"), ("RHOB", "G/C3", rhob, "FDC"),
        ("CAL1", "IN", 12.25 + 0.2 * rng.standard_normal(z.size), "FDC"),
        ("GR", "GAPI", 55.0 + 8.0 * rng.standard_normal(z.size), "BHC"),
        ("DT", "US/F", dt, "BHC")],
        well="LOOKALIKE F03-02",
        other=f"Look-alike of a Dutch North Sea well: nulls written as -9999 while the header "
              f"says -999.25; neutron in LPU reading phi{NPHI_LPU_OFFSET:+g} p.u. Synthetic data "
              f"(scene carcione2022_sandstone, patchy_cement, plus noise). RHOB and NPHI not "
              f"logged above {z[NORTH_SEA_UNLOGGED]:g} m, DT not below "
              f"{z[-NORTH_SEA_DT_END - 1]:g} m.")
    # Kansas (Wellington KGS 1-32): comma-delimited LAS 2.0 in feet, the last row repeated.
    zf = np.arange(2000.0, 9500.0 + 1.0, 30.0)
    w = _logs(zf * FOOT, seed=2103)
    f = _write(folder / "lookalike_kansas_comma.las", [
        ("DEPT", "F", zf, "Depth"), ("GR", "api", 70.0 + 12.0 * rng.standard_normal(zf.size),
                                     "Gamma ray"),
        ("DT", "us/ft", 304.8 / w.vp.values, "Sonic"), ("RHOB", "g/cc", w.density.values,
                                                      "Bulk density"),
        ("NPHI", "DECP", w.porosity.values, "Neutron porosity (decimal)"),
        ("CALI", "in", 7.9 + 0.1 * rng.standard_normal(zf.size), "Caliper")],
        well="LOOKALIKE KGS 1-32",
        other=f"Look-alike of a Kansas well: comma-delimited data section, neutron in DECP, "
              f"the last row written {KANSAS_REPEATS + 1} times. Synthetic data (scene "
              f"carcione2022_sandstone, patchy_cement, plus noise).")
    lines = f.read_text().splitlines()
    a = next(i for i, line in enumerate(lines) if line.startswith("~A"))
    data = [" " + ",".join(line.split()) for line in lines[a + 1:] if line.strip()]
    head = [line for line in lines[:a + 1] if not line.startswith("DLM")]   # none in 2.0
    f.write_text("\n".join(head + data + data[-1:] * KANSAS_REPEATS) + "\n")
    # LAS 1.2, wrapped, the CWLS example's units (us/m, kg/m3, v/v) with plausible values.
    z = np.arange(1000.0, 2000.0 + 1.0, 10.0)
    w = _logs(z, seed=2104)
    extra = [(f"R{k:02d}", "OHMM", 10.0 + rng.standard_normal(z.size), "Resistivity")
             for k in range(6)]
    _write(folder / "lookalike_las12_wrapped.las", [
        ("DEPT", "M", z, "Depth"), ("DT", "US/M", 1000.0 / w.vp.values, "Sonic travel time"),
        ("RHOB", "K/M3", 1000.0 * w.density.values, "Bulk density"),
        ("NPHI", "V/V", w.porosity.values, "Neutron porosity"), *extra],
        well="LOOKALIKE LAS 1.2", version=1.2, wrap=True,
        other="Look-alike of a LAS 1.2 wrapped file with the units of the CWLS example (us/m, "
              "kg/m3). Synthetic data (scene carcione2022_sandstone, patchy_cement, plus noise).")


# ----------------------------------------------------------------------------- the tests
def _lasio(name, **kwargs):
    """The file's curves as lasio reads them (independent of rockcem.wells)."""
    logging.getLogger("lasio").setLevel(logging.CRITICAL)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return lasio.read(str(data_path("wells", name)), **kwargs)


def _warned(record):
    return [str(w.message) for w in record if issubclass(w.category, WellLogWarning)]


def test_washout_spike_and_junk_sample_are_blanked_not_refused():
    """Issue 21: one RHOB 4.07 g/cm3 or one DT -0.035 us/ft refused the whole file."""
    name = SPIKE[0]
    las = _lasio(name)
    with pytest.warns(WellLogWarning) as record:
        ds = read_well(data_path("wells", name))
    depth = las.index * 1.0                                      # m
    np.testing.assert_allclose(ds.depth, depth, rtol=1e-15)
    rhob = las["RHOB"].copy()
    assert rhob[SPIKE[2]] == SPIKE[3]
    rhob[SPIKE[2]] = np.nan
    np.testing.assert_array_equal(ds.density.values, rhob)       # only the spike is gone
    dt = las["DT"].copy()
    assert dt[JUNK[2]] == JUNK[3] and np.isnan(dt[:NS_TOP_NULL]).all()
    dt[JUNK[2]] = np.nan
    np.testing.assert_allclose(ds.vp.values, FOOT / (dt * 1e-6) / 1e3, rtol=1e-14)
    assert ds.density.attrs["samples_blanked"] == 1 and ds.vp.attrs["samples_blanked"] == 1
    assert ds.vs.attrs["samples_blanked"] == 0
    messages = " | ".join(_warned(record))
    assert "RHOB (g/cm3): 1 of 251 samples blanked: 1 above 3.5 g/cm3 (first 4.07 g/cm3 at " \
           f"{depth[SPIKE[2]]:g} m)" in messages
    assert f"DT (us/ft): 1 of 251 samples blanked: 1 not positive (first -0.035 us/ft at " \
           f"{depth[JUNK[2]]:g} m)" in messages
    report = format_read_report(ds)
    assert "LAS 2.0, wrapped" in report
    assert f"DT (us/ft)  kept {251 - NS_TOP_NULL - 1} of 251, null {NS_TOP_NULL}, blanked 1" \
        in report


def test_nulls_written_as_minus_9999_under_a_header_of_minus_999_25():
    """Issue 21: `null=` worked for CSV only; -9999 data under NULL -999.25 were unreadable."""
    name = "lookalike_north_sea.las"
    las = _lasio(name)
    assert str(las.well["NULL"].value).startswith("-999.25")
    with warnings.catch_warnings():
        warnings.simplefilter("error", WellLogWarning)
        ds = read_well(data_path("wells", name), null=-9999)      # nothing to warn about
    n = las.index.size
    assert np.isnan(ds.density.values[:NORTH_SEA_UNLOGGED]).all()
    assert np.isfinite(ds.density.values[NORTH_SEA_UNLOGGED:]).all()
    assert np.isnan(ds.vp.values[-NORTH_SEA_DT_END:]).all()
    np.testing.assert_allclose(ds.porosity.values[NORTH_SEA_UNLOGGED:],
                               las["NPHI"][NORTH_SEA_UNLOGGED:] / 100.0, rtol=1e-15)
    assert ds.porosity.attrs["long_name"] == "log porosity (apparent, from NPHI)"
    assert "limestone units" in ds.porosity.attrs["comment"]
    report = format_read_report(ds)
    assert "nulls -999.25, -9999" in report
    assert f"RHOB (G/C3)  kept {n - NORTH_SEA_UNLOGGED} of {n}, null {NORTH_SEA_UNLOGGED}\n" \
        in report + "\n"
    # Not told: the -9999 samples are still blanked, each counted, with the hint.
    with pytest.warns(WellLogWarning) as record:
        plain = read_well(data_path("wells", name))
    np.testing.assert_array_equal(plain.density.values, ds.density.values)
    messages = " | ".join(_warned(record))
    assert f"RHOB (G/C3): {NORTH_SEA_UNLOGGED} of {n} samples blanked: {NORTH_SEA_UNLOGGED} " \
           "undeclared null" in messages and "pass null=-9999" in messages
    assert f"DT (US/F): {NORTH_SEA_DT_END} of {n} samples blanked" in messages


def test_comma_delimited_data_and_repeated_rows_name_lines_that_exist():
    """Issue 21: a comma-delimited data section got a message naming a row that did not
    exist. lasio reads it (commas as delimiters); the repeated last rows are left out, and the
    message names their lines in the file."""
    name = "lookalike_kansas_comma.las"
    path = data_path("wells", name)
    lines = path.read_text().splitlines()
    a = next(i for i, line in enumerate(lines) if line.startswith("~A"))
    assert not any(line.startswith("DLM") for line in lines)      # commas, undeclared
    rows = [[float(v) for v in line.split(",")] for line in lines[a + 1:]]   # by hand
    with pytest.warns(WellLogWarning) as record:
        ds = read_well(path)
    n = len(rows) - KANSAS_REPEATS
    table = np.array(rows[:n])
    np.testing.assert_allclose(ds.depth, table[:, 0] * FOOT, rtol=1e-15)
    np.testing.assert_allclose(ds.vp, FOOT / (table[:, 2] * 1e-6) / 1e3, rtol=1e-14)
    np.testing.assert_allclose(ds.density, table[:, 3], rtol=1e-15)
    np.testing.assert_allclose(ds.porosity, table[:, 4], rtol=1e-15)     # DECP: a fraction
    first_line = a + 1 + n + 1                 # 1-based line of the first repeat
    message = " | ".join(_warned(record))
    assert f"{KANSAS_REPEATS} data rows repeating an earlier depth left out (the first: " \
           f"{table[-1, 0]:g} F on line {first_line}, as on line {first_line - 1})" in message
    assert lines[first_line - 1] == lines[first_line - 2]
    assert "comma-delimited" in format_read_report(ds)


def test_las_1_2_wrapped_lookalike_in_microseconds_per_metre_and_kg_per_m3():
    """Issue 21: LAS 1.2 and wrapped LAS were refused although lasio reads both."""
    name = "lookalike_las12_wrapped.las"
    las = _lasio(name)
    assert str(las.version["VERS"].value) == "1.2" and las.version["WRAP"].value == "YES"
    ds = read_well(data_path("wells", name))
    np.testing.assert_allclose(ds.vp, 1000.0 / las["DT"], rtol=1e-14)       # km/s from us/m
    np.testing.assert_allclose(ds.density, las["RHOB"] / 1000.0, rtol=1e-15)  # K/M3
    np.testing.assert_allclose(ds.porosity, las["NPHI"], rtol=1e-15)
    assert format_read_report(ds).startswith(f"{name} (LAS 1.2, wrapped)")


def test_the_cwls_las_1_2_wrapped_example_reads_what_it_can():
    """The LAS standard's own wrapped 1.2 example (from lasio, MIT): DT is all null, RHOB is
    labelled K/M (not a density unit): neither stops the read of NPHI."""
    name = "cwls_las12_wrapped_example.las"
    with pytest.warns(WellLogWarning) as record:
        ds = read_well(data_path("wells", name))
    np.testing.assert_allclose(ds.depth, [909.5, 909.625, 909.75, 909.875, 910.0])
    # NPHI as printed in the file, from 910 m down to 909.5 m.
    np.testing.assert_allclose(ds.porosity, [0.3140, 0.2886, 0.2730, 0.2765, 0.2996][::-1])
    assert set(ds.data_vars) == {"porosity"}
    messages = " | ".join(_warned(record))
    assert "density left out: RHOB: unit 'K/M' not understood for density" in messages
    assert "vp left out: DT has no valid sample" in messages


def test_shipped_lookalikes_resolve_by_name_from_any_folder(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for given in ("lookalike_las12_wrapped", "lookalike_las12_wrapped.las",
                  "datasets/wells/lookalike_las12_wrapped.las"):
        assert read_well(given).attrs["source_file"] == "lookalike_las12_wrapped.las"
    with pytest.raises(ValueError, match="did you mean lookalike_las12_wrapped"):
        read_well("lookalike_las12_wraped")


if __name__ == "__main__":                  # regenerate: python <this file> datasets/wells
    write_lookalikes(sys.argv[1] if len(sys.argv) > 1 else ".")
