"""Burial histories from tables: horizons (hiatus, uplift, cooling) and shifted node tables."""

import tomllib

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from burial import intergranular_volume, quartz_cement, smectite_fraction
from burial.horizons import horizon_paths, shifted_path
from rockcem.constants import SECONDS_PER_MYR, STANDARD_GRAVITY
from rockcem.scene import load_scene, run_scene, scene_from_dict

S, G, T0 = 40.0, 30.0, 15.0          # m/Myr, degC/km, degC: the linear model of the paper


@pytest.fixture(scope="module")
def sandstone_raw():
    raw = tomllib.loads(load_scene("carcione2022_sandstone").text)
    raw["path"] = {"max_depth": 3000.0, "depth_step": 100.0}
    return raw


@pytest.fixture(scope="module")
def linear(sandstone_raw):
    return run_scene(scene_from_dict(sandstone_raw))


def _with_path(raw, path):
    return scene_from_dict({**raw, "path": path})


def test_horizons_encoding_the_linear_model_give_the_linear_scene(sandstone_raw, linear):
    z = linear.depth.values[1:]                     # the surface horizon has no history yet
    rows = [(f"h{k}", t, d, T0 + G * d / 1000.0) for k, zk in enumerate(z)
            for t, d in ((zk / S, 0.0), (0.0, zk))]
    h, t, d, T = (list(c) for c in zip(*rows))
    ds = run_scene(_with_path(sandstone_raw, {"kind": "horizons", "horizon": h, "time": t,
                                              "depth": d, "temperature": T}))
    np.testing.assert_array_equal(ds.depth.values, z)
    assert ds.horizon.values.tolist() == [f"h{k}" for k in range(z.size)]
    for name in ("porosity", "cement_fraction", "density", "vp", "vs", "temperature",
                 "pressure_effective"):
        np.testing.assert_allclose(ds[name].values, linear[name].isel(depth=slice(1, None)),
                                   rtol=1e-14, atol=1e-15, err_msg=name)


def test_nodes_table_of_the_linear_model_is_the_linear_scene(sandstone_raw, linear):
    # Only the corners of the linear path: the refinement to depth_step adds the others.
    ds = run_scene(_with_path(sandstone_raw, {
        "kind": "nodes", "time": [0.0, 3000.0 / S], "depth": [0.0, 3000.0],
        "temperature": [T0, T0 + G * 3.0], "depth_step": 100.0}))
    np.testing.assert_allclose(ds.depth.values, linear.depth.values, rtol=1e-14)
    for name in ("porosity", "cement_fraction", "vp"):
        np.testing.assert_allclose(ds[name].values, linear[name].values, rtol=1e-13,
                                   atol=1e-15, err_msg=name)


def _walderhaug_ode(path_t, path_T, phi0=0.36, D=0.3, f=0.65, start=None):
    """The same Walderhaug cement by a stiff ODE solver on the rate law (eqs. B.2-B.6)."""
    A0 = 6.0 * f / (D / 10.0)
    k = 60.09 * 1.98e-22 * A0 / (2.65 * phi0) * SECONDS_PER_MYR

    def rate(t, y):
        T = np.interp(t, path_t, path_T)
        on = 1.0 if start is None or T >= start else 0.0
        return [on * k * (phi0 - y[0]) * 10.0 ** (0.022 * T)]

    sol = solve_ivp(rate, (path_t[0], path_t[-1]), [0.0], method="Radau", rtol=1e-11,
                    atol=1e-14, t_eval=path_t, max_step=0.5, first_step=1e-6)
    return sol.y[0]


def test_hiatus_keeps_cement_below_onset_and_reheating_grows_it():
    # Burial to 95 degC, uplift and cooling to 70 degC (below the 80 degC onset), a 20-Myr
    # hiatus, then reburial and reheating to 100 degC.
    tbp = [100.0, 50.0, 40.0, 20.0, 0.0]
    z = [0.0, 2667.0, 1833.0, 1833.0, 2833.0]
    T = [15.0, 95.0, 70.0, 70.0, 100.0]
    h = horizon_paths(["A"] * 5, tbp, z, T)
    phip = quartz_cement(h.path, 0.36, 0.3, 0.65, start_temperature=80.0)[0]
    assert phip[2] > 0.0
    assert phip[3] == phip[2]                       # hiatus below the onset: constant, exactly
    assert phip[4] > phip[3]                        # grows on reheating
    reference = _walderhaug_ode(h.path.time[0], h.path.temperature[0], start=80.0)
    np.testing.assert_allclose(phip, reference, rtol=2e-6, atol=1e-12)


def test_uplift_does_not_decompact():
    h = horizon_paths(["A"] * 3 + ["B"] * 2, [60.0, 30.0, 0.0, 60.0, 0.0],
                      [0.0, 3000.0, 990.0, 0.0, 1000.0], [15.0, 105.0, 45.0, 15.0, 45.0])
    from burial import pressures

    p = pressures(h.path)
    uplifted = int(np.flatnonzero(h.horizon == "A")[0])
    pe_max = 1e-3 * STANDARD_GRAVITY * (2.5 - 1.04) * 3000.0      # eq. 1 at the deepest burial
    np.testing.assert_allclose(p.max_effective[uplifted, -1], pe_max, rtol=1e-14)
    igv = intergranular_volume(0.36, p.max_effective[:, -1], 0.2, 0.01)
    assert igv[uplifted] < igv[1 - uplifted]       # shallower now, compacted by its past
    np.testing.assert_allclose(igv[uplifted], intergranular_volume(0.36, pe_max, 0.2, 0.01),
                               rtol=1e-15)


def test_horizons_are_padded_with_zero_length_pieces():
    h = horizon_paths(["A"] * 4 + ["B"] * 2, [60, 40, 30, 0, 20, 0],
                      [0, 2000, 2000, 2500, 0, 400], [15, 75, 75, 90, 15, 27])
    assert h.horizon.tolist() == ["B", "A"] and h.age.tolist() == [20.0, 60.0]
    single = horizon_paths(["B"] * 2, [20, 0], [0, 400], [15, 27])
    np.testing.assert_array_equal(quartz_cement(h.path, 0.36, 0.3, 0.65)[0, -1],
                                  quartz_cement(single.path, 0.36, 0.3, 0.65)[0, -1])
    np.testing.assert_array_equal(smectite_fraction(h.path, 0.99)[0, -1],
                                  smectite_fraction(single.path, 0.99)[0, -1])
    np.testing.assert_array_equal(h.path.heating_rate[0, :2], [0.0, 0.0])


@pytest.mark.parametrize("columns, message", [
    ({"time": [10, 20, 0]}, r"row 2, column time: 20 Myr before present follows 10"),
    ({"time": [20, 10, 5]}, r"row 3, column time: horizon 'A' ends 5 Myr"),
    ({"temperature": [288.15, 320, 330]}, r"row 1, column temperature: .*kelvin"),
    ({"depth": [0, 30000, 9000]}, r"row 2, column depth: .*feet"),
    ({"depth": [10, 300, 900]}, r"row 1, column depth: horizon 'A' starts at 10 m"),
    ({"depth": [0, 300, float("nan")]}, r"row 3, column depth"),
])
def test_bad_horizon_tables_name_row_and_column(columns, message):
    table = {"horizon": ["A"] * 3, "time": [20, 10, 0], "depth": [0, 300, 900],
             "temperature": [15, 24, 42], **columns}
    with pytest.raises(ValueError, match=message):
        horizon_paths(table["horizon"], table["time"], table["depth"], table["temperature"])


def test_crossing_horizons_are_refused():
    with pytest.raises(ValueError, match=r"row 5, column depth: horizon 'B' .* below the "
                                         r"older horizon 'A' at 10 Myr.*cross"):
        horizon_paths(["A"] * 3 + ["B"] * 3, [30, 10, 0, 20, 10, 0],
                      [0, 500, 1000, 0, 600, 800], [15, 30, 45, 15, 33, 39])


def test_horizons_at_one_present_depth_are_refused():
    with pytest.raises(ValueError, match=r"row 4, column depth: horizons 'A' and 'B' both lie "
                                         r"at 500 m"):
        horizon_paths(["A", "A", "B", "B"], [30, 0, 20, 0], [0, 500, 0, 500],
                      [15, 30, 15, 30])


def test_shifted_path_refuses_uplift():
    with pytest.raises(ValueError, match="row 3, column depth: .*give horizons"):
        shifted_path([0, 10, 20], [0, 500, 400], [15, 30, 27])


def test_csv_table_with_units_in_the_header(sandstone_raw, tmp_path):
    (tmp_path / "h.csv").write_text(
        "horizon,age (Ma),depth (ft),temperature (K)\n"
        "A,30,0,288.15\nA,0,3280.84,318.15\nB,10,0,288.15\nB,0,328.084,291.15\n")
    (tmp_path / "bad.csv").write_text("horizon,age (Ma),depth,temperature (degC)\nA,1,0,15\n")
    (tmp_path / "nocol.csv").write_text("horizon,age (Ma),temperature (degC)\nA,1,15\n")
    ds = run_scene(scene_from_dict({**sandstone_raw, "path": {"kind": "horizons",
                                                              "table": "h.csv"}},
                                   base_dir=tmp_path))
    np.testing.assert_allclose(ds.depth.values, [100.0, 1000.0], rtol=1e-6)
    np.testing.assert_allclose(ds.temperature.values, [18.0, 45.0], rtol=1e-12)
    for name, message in (("bad.csv", "column 'depth' has no unit"),
                          ("nocol.csv", "missing column 'depth'")):
        with pytest.raises(ValueError, match=message):
            scene_from_dict({**sandstone_raw, "path": {"kind": "horizons", "table": name}},
                            base_dir=tmp_path)


@pytest.mark.parametrize("header", ["horizon,age (Ma),time (Myr),depth (m),temperature (degC)",
                                    "horizon,time (Myr),age (Ma),depth (m),temperature (degC)",
                                    "horizon,time (Ma),depth (m),Time (Myr),temperature (degC)"])
def test_csv_table_with_two_time_columns_is_refused(tmp_path, header):
    """Issue 24: with both an age and a time column the last one was used, with no word."""
    from rockcem.histories import read_history_table

    f = tmp_path / "h.csv"
    f.write_text(header + "\nA,30,20,0,15\nA,0,0,1000,45\n")
    with pytest.raises(ValueError, match=r"h.csv: columns '.*' and '.*' both give the time; "
                                         "keep one"):
        read_history_table(f, "horizons")


@pytest.mark.parametrize("path, message", [
    ({"kind": "horizons", "gradient": 30.0}, "path.gradient does not apply to kind"),
    ({"kind": "linear", "table": "x.csv"}, "path.table does not apply to kind"),
    ({"kind": "horizons"}, "path.horizon is required"),
    ({"kind": "horizons", "table": "none.csv"}, "file 'none.csv' not found"),
    ({"kind": "wells"}, "path.kind must be one of"),
])
def test_bad_path_sections(sandstone_raw, path, message):
    with pytest.raises(ValueError, match=message):
        _with_path(sandstone_raw, path)


def test_nodes_table_from_csv(sandstone_raw, linear, tmp_path):
    (tmp_path / "n.csv").write_text("time (Myr),depth (ft),temperature (degC)\n"
                                    "0,0,15\n75,9842.519685,105\n")
    (tmp_path / "ma.csv").write_text("time (Ma),depth (m),temperature (degC)\n0,0,15\n")
    ds = run_scene(scene_from_dict({**sandstone_raw, "path": {
        "kind": "nodes", "table": "n.csv", "depth_step": 100.0}}, base_dir=tmp_path))
    assert ds.depth.size == 31 and abs(float(ds.depth[-1]) - 3000.0) < 1e-3
    np.testing.assert_allclose(ds.porosity.values, linear.porosity.values, rtol=1e-6)
    with pytest.raises(ValueError, match="time since deposition .* Myr"):
        scene_from_dict({**sandstone_raw, "path": {"kind": "nodes", "table": "ma.csv"}},
                        base_dir=tmp_path)


def test_shale_horizons_encoding_the_linear_model_give_the_linear_scene():
    raw = tomllib.loads(load_scene("carcione2022_shale").text)
    raw.pop("sweep", None)
    raw["path"] = {"gradient": G, "max_depth": 3000.0, "depth_step": 250.0}
    linear = run_scene(scene_from_dict(raw))
    z = linear.depth.values[1:]
    rows = [(f"h{k}", t, d, T0 + G * d / 1000.0) for k, zk in enumerate(z)
            for t, d in ((zk / S, 0.0), (0.0, zk))]
    h, t, d, T = (list(c) for c in zip(*rows))
    ds = run_scene(_with_path(raw, {"kind": "horizons", "horizon": h, "time": t, "depth": d,
                                    "temperature": T}))
    for name in ("illite_fraction", "porosity", "vp"):
        np.testing.assert_allclose(ds[name].values, linear[name].isel(depth=slice(1, None)),
                                   rtol=1e-13, atol=1e-15, err_msg=name)


def test_crossing_an_older_horizon_of_a_pair_deposited_together_is_refused():
    # A and B were deposited together (30 Ma); the younger C sinks below A but not below B.
    with pytest.raises(ValueError, match=r"horizon 'C' .* below the older horizon 'A'"):
        horizon_paths(["A", "A", "B", "B", "C", "C"], [30, 0, 30, 0, 20, 0],
                      [0, 1000, 0, 1500, 0, 1200], [15, 45, 15, 60, 15, 51])


def test_illite_on_a_hiatus_and_uplift_path_matches_a_stiff_ode():
    """Pytte-Reynolds kinetics (eq. A.1) on burial, a hot hiatus, uplift with cooling and
    reburial: the exact piecewise integral against Radau on dr/dt = -c r^n exp(-E/RT)."""
    from rockcem.constants import GAS_CONSTANT_CAL, ZERO_CELSIUS_IN_KELVIN

    tbp = [90.0, 60.0, 45.0, 25.0, 10.0, 0.0]
    z = [0.0, 3000.0, 3000.0, 1800.0, 1800.0, 2600.0]
    T = [15.0, 105.0, 105.0, 69.0, 69.0, 93.0]
    h = horizon_paths(["A"] * 6, tbp, z, T)
    r0, n, E, c = 0.99, 5.0, 36.0, 1.217e23
    r = smectite_fraction(h.path, r0, n, E, c)[0]
    t_nodes, T_nodes = h.path.time[0], h.path.temperature[0]
    a = E * 1000.0 / GAS_CONSTANT_CAL

    def rate(t, y):
        TK = np.interp(t, t_nodes, T_nodes) + ZERO_CELSIUS_IN_KELVIN
        return [-c * y[0] ** n * np.exp(-a / TK)]

    sol = solve_ivp(rate, (0.0, t_nodes[-1]), [r0], method="Radau", rtol=1e-11, atol=1e-14,
                    t_eval=t_nodes, max_step=0.25)
    np.testing.assert_allclose(r, sol.y[0], rtol=1e-7)
    assert r[4] < r[2] and r[5] < r[4]         # reacts on through the cool hiatus, a little


def test_cli_bad_history_table_one_line(sandstone_raw, tmp_path, capsys):
    from rockcem.cli import main

    (tmp_path / "w.csv").write_text("horizon,age (Ma),depth (m),temperature (degC)\n"
                                    "A,10,0,15\nA,0,500,30,7\n")
    scene = tmp_path / "s.toml"
    scene.write_text('name = "s"\nlithology = "sandstone"\n[path]\nkind = "horizons"\n'
                     'table = "w.csv"\n[models.hs_gassmann]\n')
    assert main(["run", str(scene), "-q"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "w.csv" in err and "line 3" in err, err


def test_history_depth_units_spelt_as_the_well_reader_takes_them(tmp_path):
    from rockcem.histories import read_history_table

    for unit, factor in (("feet", 0.3048), ("F", 0.3048), ("metres", 1.0)):
        f = tmp_path / "h.csv"
        f.write_text(f"horizon,age (Ma),depth ({unit}),temperature (degC)\nA,10,0,15\n"
                     "A,0,1000,25\n")
        np.testing.assert_array_equal(read_history_table(f, "horizons")["depth"],
                                      [0.0, 1000.0 * factor])


def test_a_history_file_is_read_once_per_version(sandstone_raw, tmp_path, monkeypatch):
    import rockcem.histories as histories

    reads = []
    original = histories.read_history_table
    monkeypatch.setattr(histories, "read_history_table",
                        lambda *a: reads.append(1) or original(*a))
    f = tmp_path / "h.csv"
    f.write_text("horizon,age (Ma),depth (m),temperature (degC)\nA,30,0,15\nA,0,1000,45\n")
    scene = scene_from_dict({**sandstone_raw, "path": {"kind": "horizons", "table": "h.csv"}},
                            base_dir=tmp_path)
    assert run_scene(scene).depth.values.tolist() == [1000.0] and len(reads) == 1
    f.write_text("horizon,age (Ma),depth (m),temperature (degC)\nA,30,0,15\nA,0,1500.0,60\n")
    assert run_scene(scene).depth.values.tolist() == [1500.0] and len(reads) == 2
