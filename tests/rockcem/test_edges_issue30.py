"""The hostile inputs of issue 30 outside pore fluids and labelled arrays: each gets a one-line
refusal naming the key or file, or is read as it should be (the before/after table is
benchmarks/results/hostile_inputs_30.md)."""

import os
import stat

import numpy as np
import pytest
import xarray as xr

from rockcem import cli
from rockcem.scene import load_scene, run_scene, scene_from_dict, write_dataset
from rockcem.wells import ALIASES, UNITS, format_read_report, read_well


def csv(folder, text, name="log.csv", encoding="utf-8"):
    path = folder / name
    path.write_bytes(text.encode(encoding))
    return path


def one_line_error(capsys, argv):
    """Exit code 2 and one line on stderr (returned)."""
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1, err
    return err[0]


# ----------------------------------------------------------------------------- well curves
def test_one_curve_read_as_two_variables_is_refused(tmp_path):
    f = csv(tmp_path, "DEPT (m),SON (us/ft)\n1000,100\n1010,101\n")
    with pytest.raises(ValueError, match=r"log.csv: curve SON would be read as both vp and vs"):
        read_well(f, curves={"vp": "SON", "vs": "SON"})


@pytest.mark.parametrize("var, other", [("vs", "vp"), ("vp", "vs")])
def test_every_sonic_mnemonic_of_the_other_wave_is_refused(tmp_path, var, other):
    """--curve vs=DT read the compressional sonic as Vs: each of the other wave's mnemonics
    named for a variable is refused, naming the curve."""
    word = "compressional" if other == "vp" else "shear"
    for mnemonic in ALIASES[other]:
        f = csv(tmp_path, f"DEPT (m),{mnemonic} (us/ft)\n1000,100\n1010,101\n")
        with pytest.raises(ValueError, match=rf"curve '{mnemonic}' for {var}: {mnemonic} is a "
                                             rf"{word} sonic mnemonic"):
            read_well(f, curves={var: mnemonic})


#: The factor of each unit spelling to the project's unit, by hand: 1 ft = 0.3048 m exactly, so
#: a slowness in µs/ft is a velocity of 304.8/value km/s and one in µs/m of 1000/value; 0.1 in
#: = 2.54 mm; percent is 0.01.
HAND = {
    "depth": {**dict.fromkeys(("M", "METER", "METERS", "METRE", "METRES"), 1.0),
              **dict.fromkeys(("FT", "F", "FEET", "FOOT"), 0.3048),
              ".1IN": 0.00254, "0.1IN": 0.00254, "IN": 0.0254},
    "slowness": {**dict.fromkeys(("US/FT", "USEC/FT", "US/F", "USEC/F", "US/FOOT"), 304.8),
                 **dict.fromkeys(("US/M", "USEC/M"), 1000.0)},
    "velocity": {**dict.fromkeys(("KM/S", "KM/SEC"), 1.0),
                 **dict.fromkeys(("M/S", "M/SEC"), 1e-3),
                 **dict.fromkeys(("FT/S", "F/S", "FT/SEC"), 0.3048e-3)},
    "density": {**dict.fromkeys(("G/CC", "G/CM3", "G/CM^3", "G/CM**3", "GM/CC", "G/C3",
                                 "GR/CC", "GRM/CC", "GM/CM3"), 1.0),
                **dict.fromkeys(("KG/M3", "KG/M^3", "K/M3"), 1e-3)},
    "porosity": {**dict.fromkeys(("V/V", "FRAC", "FRACTION", "DEC", "DECP", "M3/M3", "FT3/FT3",
                                  "CFCF", "VOL/VOL", "1"), 1.0),
                 **dict.fromkeys(("%", "PU", "P.U.", "PERCENT", "PCT", "PERCNT", "LPU", "SPU",
                                  "DPU"), 0.01)},
}


def test_the_hand_table_lists_every_unit_spelling():
    assert {k: set(v) for k, v in HAND.items()} == {k: set(v) for k, v in UNITS.items()}


@pytest.mark.parametrize("kind", ["slowness", "velocity", "density", "porosity"])
def test_every_unit_spelling_converts_by_its_hand_factor(tmp_path, kind):
    """One CSV per spelling: a sample whose value in the project's unit is known (3 km/s,
    2.5 g/cm³, a porosity of 0.25), written in that unit; and every depth spelling."""
    var, mnemonic, want = {"slowness": ("vp", "DT", 3.0), "velocity": ("vp", "VP", 3.0),
                           "density": ("density", "RHOB", 2.5),
                           "porosity": ("porosity", "PHIT", 0.25)}[kind]
    for unit, factor in HAND[kind].items():
        raw = factor / want if kind == "slowness" else want / factor
        f = csv(tmp_path, f"DEPT (m),{mnemonic} ({unit})\n1000,{raw!r}\n1010,{raw!r}\n")
        ds = read_well(f)
        np.testing.assert_allclose(ds[var].values, want, rtol=1e-12, err_msg=unit)
    for unit, factor in HAND["depth"].items():
        f = csv(tmp_path, f"DEPT ({unit}),DT (us/ft)\n1000,100\n2000,100\n")
        np.testing.assert_allclose(read_well(f).depth.values, [1000 * factor, 2000 * factor],
                                   rtol=1e-12, err_msg=unit)


#: The mnemonics of each variable, in order of preference, as read_well's documentation lists
#: them (typed from it, not copied from the table).
HAND_ALIASES = {
    "vp": "DT DTC DTCO DT4P DTP AC ACTC VP PVEL",
    "vs": "DTS DTSM DT4S DTSH VS SVEL",
    "density": "RHOB RHOZ ZDEN DEN DENS RHO",
    "porosity": "PHIT PHI POR TPOR NPHI TNPH NPOR NPHI_SAN NPHS NPHI_LIM NPHL NPHI_DOL NPHD CN "
                "DPHI DPHI_SAN DPHS DPHI_LIM DPHL DPHI_DOL DPHD",
}


def test_the_alias_table_is_the_documented_one():
    assert {k: " ".join(v) for k, v in ALIASES.items()} == HAND_ALIASES


@pytest.mark.parametrize("var", ["vp", "vs", "density", "porosity"])
def test_every_mnemonic_of_the_aliases_is_read(tmp_path, var):
    """Each alias alone in a file is chosen for its variable; the apparent porosities (neutron:
    NPH*, TNPH, NPOR, CN; density: DPH*) say so, the total ones do not."""
    unit, raw, want = {"vp": ("us/ft", 100.0, 3.048), "vs": ("us/ft", 200.0, 1.524),
                       "density": ("g/cc", 2.4, 2.4), "porosity": ("v/v", 0.2, 0.2)}[var]
    neutron = {"NPHI", "TNPH", "NPOR", "NPHI_SAN", "NPHS", "NPHI_LIM", "NPHL", "NPHI_DOL",
               "NPHD", "CN"}
    density = {"DPHI", "DPHI_SAN", "DPHS", "DPHI_LIM", "DPHL", "DPHI_DOL", "DPHD"}
    for mnemonic in HAND_ALIASES[var].split():
        f = csv(tmp_path, f"DEPT (m),{mnemonic} ({unit})\n1000,{raw}\n1010,{raw}\n")
        ds = read_well(f)
        assert list(ds.data_vars) == [var], mnemonic
        assert ds[var].attrs["source_mnemonic"] == mnemonic
        np.testing.assert_allclose(ds[var].values, want, rtol=1e-12)
        comment = ds[var].attrs.get("comment", "")
        if var == "porosity":
            source = "neutron" if mnemonic in neutron else "density" if mnemonic in density \
                else None
            assert (f"a {source} porosity, apparent" in comment) if source else not comment, \
                mnemonic


def test_rows_dropped_for_a_repeated_depth_are_in_the_read_report(tmp_path):
    f = csv(tmp_path, "DEPT (m),DT (us/ft)\n1000,100\n1000,101\n1010,102\n")
    with pytest.warns(UserWarning, match="1 data rows repeating an earlier depth"):
        ds = read_well(f)
    first = format_read_report(ds).splitlines()[0]
    assert "1 rows repeating an earlier depth left out (the first on line 3)" in first


def test_a_folder_named_like_a_log_is_said_to_be_a_folder(tmp_path):
    (tmp_path / "x.las").mkdir()
    with pytest.raises(ValueError, match=r"well file '.*x.las' is a folder, not a file"):
        read_well(tmp_path / "x.las")


def test_a_csv_field_over_the_csv_modules_limit_names_the_file_and_line(tmp_path):
    f = csv(tmp_path, "DEPT (m),DT (us/ft)\n1000,100\n1010," + "1" * 200_000 + "\n")
    with pytest.raises(ValueError, match=r"log.csv: line 3 is not a line of a CSV well log"):
        read_well(f)


def test_a_latin1_csv_is_read(tmp_path):
    """A header written by a Windows program: µs/ft in latin-1 (the byte 0xb5)."""
    f = csv(tmp_path, "DEPT (m),DT (\u00b5s/ft)\n# caf\u00e9\n1000,100\n1010,80\n",
            encoding="latin-1")
    ds = read_well(f)
    np.testing.assert_allclose(ds.vp.values, [3.048, 3.81], rtol=1e-12)
    assert format_read_report(ds).startswith("log.csv (CSV, latin-1)")


def test_intervals_wholly_outside_the_well_exit_2(tmp_path, capsys):
    scene = scene_from_dict({"name": "s", "lithology": "sandstone",
                             "path": {"max_depth": 3000.0, "depth_step": 100.0},
                             "models": {"hs_gassmann": {}}})
    write_dataset(run_scene(scene), tmp_path / "s.nc")
    f = csv(tmp_path, "DEPT (m),DT (us/ft)\n1000,100\n1010,100\n")
    line = one_line_error(capsys, ["compare", str(tmp_path / "s.nc"), "--well", str(f),
                                   "--intervals", "2000", "2500", "-q"])
    assert line.startswith("rockcem: error: --intervals 2000-2500 m lie outside the depths the "
                           "well and the scene share (1000-1010 m)")
    assert cli.main(["compare", str(tmp_path / "s.nc"), "--well", str(f), "--intervals",
                     "900", "2000", "-q"]) == 0
    # The same refusal from Python (rockcem.wells.well_misfit), not rows of NaN.
    import xarray as xr

    from rockcem.wells import well_misfit

    with xr.open_dataset(tmp_path / "s.nc") as ds:
        with pytest.raises(ValueError, match="lie outside the depths"):
            well_misfit(ds.load(), read_well(f), intervals=[2000.0, 2500.0])


# ----------------------------------------------------------------------------- scenes
SMALL = ('name = "small"\nlithology = "sandstone"\n[path]\nmax_depth = 2000.0\n'
         'depth_step = 500.0\n[models.hs_gassmann]\nA = 3.0\n')


def test_a_scene_with_a_byte_order_mark_is_read(tmp_path):
    (tmp_path / "bom.toml").write_bytes(b"\xef\xbb\xbf" + SMALL.encode())
    assert load_scene(tmp_path / "bom.toml").name == "small"


def test_a_latin1_scene_names_the_file_and_line(tmp_path):
    (tmp_path / "s.toml").write_bytes(SMALL.replace('"small"\n', '"small"\n# caf\xe9\n')
                                      .encode("latin-1"))
    with pytest.raises(ValueError, match=r"scene file s.toml is not UTF-8, as TOML must be: "
                                         r"line 2 has the byte 0xe9"):
        load_scene(tmp_path / "s.toml")


def test_numpy_scalars_are_numbers_in_a_scene():
    scene = scene_from_dict({"name": "n", "lithology": "sandstone",
                             "sandstone": {"beta": np.float32(0.05)},
                             "path": {"max_depth": np.int64(3000), "depth_step": 100.0},
                             "models": {"md": {"count": np.int64(3),
                                               "size": [np.float64(4), np.int32(4), 12.0]}},
                             "sweep": {"path.gradient": [np.float32(30.1), 40]}})
    assert scene.sections["sandstone"]["beta"] == 0.05          # the decimal it prints as
    assert scene.sections["path"]["max_depth"] == 3000.0
    count = scene.sections["models.md"]["count"]
    assert count == 3 and type(count) is int
    assert scene.sections["models.md"]["size"] == [4.0, 4, 12.0]
    assert scene.sweep["path.gradient"] == [30.1, 40.0]
    assert "beta = 0.05\n" in scene.text
    with pytest.raises(ValueError, match="scene key sandstone.beta must be a number"):
        scene_from_dict({"name": "n", "lithology": "sandstone",
                         "sandstone": {"beta": np.bool_(True)}})


def test_a_repeated_select_is_that_value_once(tmp_path):
    ds = xr.Dataset({"vp": (("gradient", "depth"), np.arange(6.0).reshape(2, 3))},
                    coords={"gradient": [30.0, 40.0], "depth": [0.0, 1.0, 2.0]})
    twice = cli._select(ds, ["gradient=30", "path.gradient=30"])
    xr.testing.assert_identical(twice, cli._select(ds, ["gradient=30"]))
    assert float(twice.gradient) == 30.0 and twice.vp.values.tolist() == [0.0, 1.0, 2.0]


def test_plot_quiet_prints_nothing(tmp_path, capsys):
    (tmp_path / "small.toml").write_text(SMALL)
    assert cli.main(["run", str(tmp_path / "small.toml"), "-o", str(tmp_path / "s.nc"),
                     "-q"]) == 0
    capsys.readouterr()
    assert cli.main(["plot", str(tmp_path / "s.nc"), "-q", "-o", str(tmp_path / "f.png")]) == 0
    assert capsys.readouterr().out == "" and (tmp_path / "f.png").stat().st_size > 0


def test_a_copied_scene_does_not_replace_the_originals_output(tmp_path, capsys, monkeypatch):
    """An output never destroys a file it was not asked to write: a copy keeps the name."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a.toml").write_text(SMALL)
    (tmp_path / "b.toml").write_text(SMALL.replace("A = 3.0", "A = 4.0"))
    assert cli.main(["run", "a.toml", "-q"]) == 0
    first = (tmp_path / "small.nc").read_bytes()
    line = one_line_error(capsys, ["run", "b.toml", "-q"])
    assert "output file small.nc exists and is the output of another scene file" in line
    assert str(tmp_path / "a.toml") in line and "-o" in line
    assert (tmp_path / "small.nc").read_bytes() == first
    assert cli.main(["run", "a.toml", "-q"]) == 0              # its own output: replaced
    assert cli.main(["run", "b.toml", "-o", "small.nc", "-q"]) == 0      # asked by name
    (tmp_path / "small.nc").write_bytes(b"a file of the user's\n")
    line = one_line_error(capsys, ["run", "a.toml", "-q"])
    assert "small.nc exists and is not the output of a rockcem run" in line
    assert (tmp_path / "small.nc").read_bytes() == b"a file of the user's\n"


# ----------------------------------------------------------------------------- atomic writes
@pytest.mark.parametrize("umask, want", [(0o022, 0o644), (0o027, 0o640), (0o077, 0o600)])
def test_a_new_atomic_write_gets_the_mode_a_new_file_gets(tmp_path, umask, want):
    """mkstemp alone makes a private 0o600 file: a new output is 0o666 less the umask."""
    from rockcem._atomic import atomic_write

    old = os.umask(umask)
    try:
        atomic_write(tmp_path / "new.txt", lambda tmp: open(tmp, "w").write("x"))
        open(tmp_path / "plain.txt", "w").close()
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "new.txt").stat().st_mode) == want
    assert stat.S_IMODE((tmp_path / "plain.txt").stat().st_mode) == want


def test_calibration_file_with_a_bom_or_latin1(tmp_path):
    """A calibration file is read as scenes are (rockcem._toml.toml_text): a UTF-8 byte-order
    mark is dropped; a latin-1 byte is refused naming the file and the line."""
    from rockcem._data import data_path
    from rockcem.calibrate import load_calibration

    shipped = data_path("calibrations", "garcia_medina_compacted_patchy.toml").read_bytes()
    bom = tmp_path / "bom.toml"
    bom.write_bytes(b"\xef\xbb\xbf" + shipped)
    assert load_calibration(bom)["parameters"] == load_calibration(
        "garcia_medina_compacted_patchy")["parameters"]
    latin = tmp_path / "latin.toml"
    latin.write_bytes(shipped.replace(b"\n", b"\n# caf\xe9\n", 1))
    with pytest.raises(ValueError, match=r"calibration file .*latin.toml is not UTF-8.*line 2"):
        load_calibration(latin)
