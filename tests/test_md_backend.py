"""The MD engine as a model of a burial scene ([models.md]): a tiny pack carried down three
depths, cemented with burial's cement and saturated by Gassmann."""

import numpy as np
import pytest

from rockcem.scene import run_scene, scene_from_dict


def tiny(tmp_path, **md):
    table = {"depths": [1000.0, 2500.0, 4000.0], "size": [3.0, 3.0, 8.0],
             "resolution": 2.0, "resolution_check": 1.5, "resolution_check2": 0.0,
             "workdir": str(tmp_path / "md"),
             **md}
    return scene_from_dict({"name": "tiny_md", "lithology": "sandstone",
                            "path": {"max_depth": 4000.0, "depth_step": 100.0},
                            "sandstone": {"start_temperature": 70.0},    # cement from 1833 m
                            "models": {"hs_gassmann": {}, "md": table}})


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    path = tmp_path_factory.mktemp("md_scene")
    return run_scene(tiny(path)), path


def test_md_member_at_the_chosen_depths_only(result):
    ds, _ = result
    assert list(ds.model.values) == ["hs_gassmann", "md"]
    vp = ds.vp.sel(model="md")
    ran = np.isfinite(vp.values)
    assert ds.depth.values[ran].tolist() == [1000.0, 2500.0, 4000.0]
    assert np.all(np.isfinite(ds.vp.sel(model="hs_gassmann")))
    for name in ("md_porosity", "md_cement_saturation", "md_stress"):
        assert np.array_equal(np.isfinite(ds[name].values), ran)
    # Burial's rock: the pack compacted to burial's intergranular volume (reconstruction),
    # cemented with burial's cement (grown during burial, to the nearest lattice cell), so the
    # sample has burial's porosity within 0.01 (where that is above 0.02).
    frac, pack = ds.cement_fraction.values[ran], ds.md_pack_porosity.values[ran]
    np.testing.assert_allclose(pack, ds.intergranular_volume.values[ran], atol=1e-3)
    burial_phi = ds.porosity.values[ran]
    assert np.all(np.abs(ds.md_porosity.values[ran] - burial_phi)[burial_phi > 0.02] <= 0.01)
    # S_c is burial's cement over the pack's own porosity; the sample keeps the rest.
    np.testing.assert_allclose(ds.md_cement_saturation.values[ran], frac / pack, rtol=1e-12)
    np.testing.assert_allclose(ds.md_porosity.values[ran], pack - frac, rtol=1e-12)
    # Compacted to each depth's largest effective stress, overshooting by a few per cent
    # (the last tenth in increments of 1e-4 strain).
    target = ds.pressure_effective.values[ran]
    assert np.all(ds.md_stress.values[ran] >= target)
    assert np.all(ds.md_stress.values[ran] <= 1.05 * target)
    # Saturated density of quartz grains and quartz cement of the catalogue with water
    # (Carcione et al. 2022, eq. 24) at the sample's porosity.
    from rockcem.materials import fluid, mineral

    phi = ds.md_porosity.values[ran]
    beta = frac / (1 - phi)
    rho = (1 - phi) * (mineral("quartz").rho * (1 - beta) + mineral("quartz_cement").rho * beta) \
        + phi * fluid("water").rho
    md = ds.sel(model="md", depth=ds.depth[ran])
    np.testing.assert_allclose(md.md_density, rho, rtol=1e-12)
    # Vertical velocities of the transversely isotropic sample (the isotropic identity
    # vp^2 rho = K_sat + 4/3 G is tested with anisotropy = "isotropic" below).
    np.testing.assert_allclose(md.vs, np.sqrt(md.G_sat / md.md_density), rtol=1e-12)
    assert np.all(md.K_sat > md.K_dry) and np.all(md.G_sat == md.G_dry)
    # Bounds: an isotropic solid has Vp/Vs >= sqrt(4/3); the dry frame lies below the upper
    # Hashin-Shtrikman bound of its solid (quartz grains and cement) with empty pores.
    from rockcem.bounds import hashin_shtrikman_upper

    assert np.all(md.vp / md.vs >= np.sqrt(4 / 3))
    q, c = mineral("quartz"), mineral("quartz_cement")
    upper = hashin_shtrikman_upper([q.K, c.K, 0.0], [q.G, c.G, 0.0],
                                   np.stack([(1 - phi) * (1 - beta), (1 - phi) * beta, phi], -1))
    assert np.all(md.K_dry.values <= upper.K) and np.all(md.G_dry.values <= upper.G)
    assert np.all(md.vp_error_resolution >= 0) and np.all(np.isfinite(md.vp_error_resolution))
    assert np.all(np.isnan(md.vp_error_sample))              # one sample: no spread
    # No porosity gap to report.
    assert "porosity differs from burial's" not in ds.attrs["validity_warnings"]


def test_md_compaction_stages_overshoot_by_one_fine_increment(result):
    """Issue 30: the 1.05 bound above hides a five times larger last step. Each compaction
    stage file holds its record: the last tenth in increments of a fifth of carry_down's
    strain_step (5e-4), 1 - strain_k = (1 - 1e-4)^k exactly, stopped at the first increment
    whose vertical stress reaches the depth's target, so md_stress exceeds the target by less
    than that last increment's stress change (all earlier increments were short of it)."""
    import glob

    import md

    ds, path = result
    files = sorted(glob.glob(str(path / "md" / "*" / "pack" / "compact_*.nc")))
    assert len(files) == 3
    reached = {}
    for f in files:
        pack = md.load_pack(f)
        rec, target = pack.metadata["record"], pack.metadata["target_stress"]
        assert pack.metadata["strain_step"] == pytest.approx(1e-4, rel=1e-12)
        k = np.arange(1, len(rec["strain"]) + 1)
        np.testing.assert_allclose(1 - np.asarray(rec["strain"]), (1 - 1e-4) ** k, rtol=1e-12)
        s = np.asarray(rec["stress_zz"])
        assert s[-1] >= target and np.all(s[:-1] < target)
        reached[round(target / 1e6, 9)] = s[-1] / 1e6
    ran = np.isfinite(ds.vp.sel(model="md").values)
    for want, got in zip(ds.pressure_effective.values[ran], ds.md_stress.values[ran]):
        assert got == pytest.approx(reached[round(float(want), 9)], rel=1e-12)


def test_md_velocity_rises_down_the_path(result):
    """More stress and more cement at every deeper depth: the MD sample stiffens."""
    ds, _ = result
    vp = ds.vp.sel(model="md").dropna("depth")
    assert np.all(np.diff(vp.values) > 0) and np.all(np.diff(ds.vs.sel(model="md")
                                                             .dropna("depth").values) > 0)


def test_uncemented_depth_gives_the_packs_static_moduli(result):
    """Above the onset of quartz cement (S_c = 0) the MD dry moduli are those of the uncemented
    pack, computed here directly from the stage file with md (rotations, static solves): G is
    C44, K the transversely isotropic sample's bulk modulus under hydrostatic stress from its
    five constants (rockcem.anisotropy.ti_bulk_modulus), below M - 4/3 G."""
    import glob

    import md

    ds, path = result
    shallow = ds.sel(model="md", depth=1000.0)
    assert float(shallow.md_cement_saturation) == 0.0
    igv = float(ds.intergranular_volume.sel(depth=1000.0))
    packs = [md.load_pack(f) for f in glob.glob(str(path / "md" / "*" / "pack" /
                                                    "reconstruct_*.nc"))]
    [pack] = [p for p in packs if abs(p.metadata["porosity_target"] - igv) < 1e-9]
    system = md.acoustic_system(pack, slab_thickness=2 * pack.radii.max())
    from md.static import static_stiffness

    from rockcem.anisotropy import ti_bulk_modulus

    M = md.static_modulus(system, "p").modulus / 1e9
    G = md.static_modulus(system, "s").modulus / 1e9
    c = static_stiffness(system)
    K = ti_bulk_modulus(c.c11 / 1e9, c.c13 / 1e9, c.c33 / 1e9, c.c66 / 1e9)
    assert float(shallow.G_dry) == pytest.approx(G, rel=1e-9)
    assert float(shallow.K_dry) == pytest.approx(float(K), rel=1e-9)
    assert float(shallow.K_dry) < M - 4 / 3 * G


def test_resumed_run_equals_the_first(result, monkeypatch):
    """A second run reads every stage file back — no compaction, no solve — and gives the same
    Dataset."""
    import xarray as xr

    import md.protocols
    import md.static

    calls = []
    for module, name in ((md.protocols, "compact"), (md.static, "static_modulus")):
        real = getattr(module, name)
        monkeypatch.setattr(module, name,
                            lambda *a, _real=real, _name=name, **k: calls.append(_name)
                            or _real(*a, **k))
    ds, path = result
    again = run_scene(tiny(path))
    assert calls == []
    xr.testing.assert_identical(again.drop_attrs(), ds.drop_attrs())


def test_damaged_member_stage_files_are_redone(result, tmp_path):
    """Stage files cut short, emptied or missing a variable are redone, each with a warning
    naming it, and give the first run's Dataset again (the solve is deterministic; the wall
    time of the redone members is their own)."""
    import shutil

    import xarray as xr
    from md.along_depth import StageFileWarning

    ds, path = result
    shutil.copytree(path / "md", tmp_path / "md")
    members = sorted((tmp_path / "md").rglob("members/*.nc"))
    assert len(members) == 3
    members[0].write_bytes(b"")
    members[1].write_bytes(members[1].read_bytes()[:300])
    with xr.open_dataset(members[2]) as one:
        kept = one.drop_vars("c13").load()
    kept.to_netcdf(members[2])
    with pytest.warns(StageFileWarning) as record:
        again = run_scene(tiny(tmp_path))
    named = sorted(str(m) for m in members if any(str(m) in str(w.message) for w in record))
    assert named == sorted(map(str, members))
    xr.testing.assert_identical(again.drop_attrs().drop_vars("md_wall_time"),
                                ds.drop_attrs().drop_vars("md_wall_time"))
    with xr.open_dataset(members[2]) as redone:
        assert "c13" in redone


def test_bad_md_tables(tmp_path):
    with pytest.raises(ValueError, match="depths must lie within the profile"):
        run_scene(tiny(tmp_path, depths=[5000.0]))
    with pytest.raises(ValueError, match="unknown scene key models.md.shemes"):
        tiny(tmp_path, shemes=["contact"])
    with pytest.raises(ValueError, match="sandstone scenes only"):
        scene_from_dict({"name": "s", "lithology": "shale", "models": {"md": {}}})
    with pytest.raises(ValueError, match=r"schemes must be distinct names"):
        run_scene(tiny(tmp_path, schemes=["glue"]))


def test_uplifted_depth_is_unloaded_to_its_present_stress(tmp_path):
    """The shipped horizons example (600 m of uplift): the pack is compacted to the horizon's
    largest effective stress, then unloaded to its present one before it is cemented."""
    from rockcem.scene import read_scene_toml, scene_path

    raw, _ = read_scene_toml("synthetic_basin_horizons")
    raw["models"] = {"md": {"depths": [1500.0], "size": [3.0, 3.0, 8.0], "resolution": 2.0,
                            "resolution_check": 0.0, "workdir": str(tmp_path / "md")}}
    raw["outputs"] = ["pressure_effective", "vp", "vs"]
    scene = scene_from_dict(raw, base_dir=scene_path("synthetic_basin_horizons").parent)
    ds = run_scene(scene).sel(depth=1500.0)
    from rockcem.runner import _Pipeline

    pipe = _Pipeline(scene)
    k = int(np.flatnonzero(pipe.now(pipe.path.depth) == 1500.0)[0])
    largest, present = pipe.pressures.max_effective[k], pipe.pressures.effective[k]
    assert present < 0.9 * largest                           # this horizon was uplifted
    assert float(ds.md_stress) >= largest
    # Unloaded to the first increment at or below the present stress (steps of 1e-4 strain).
    assert present * 0.9 < float(ds.md_stress_present) <= present
    assert np.isfinite(float(ds.vp.sel(model="md")))
    assert np.isnan(float(ds.vp_error_resolution.sel(model="md")))  # no resolution_check


def test_unloading_lowers_the_stress_and_keeps_the_contacts(compacted_pack_md):
    """md.compact(unload=True): the vertical stress falls to the target, the porosity rises by
    a little (elastic grains: the unloading strain is about the stress drop over the P
    modulus), and refused without a target stress."""
    import md

    loaded = compacted_pack_md
    target = 0.5 * loaded.metadata["stress_zz"]
    un = md.compact(loaded, target_stress=target, unload=True, strain_step=1e-4)
    assert 0.7 * target < un.metadata["stress_zz"] <= target
    assert 0 < un.metadata["porosity"] - loaded.metadata["porosity"] < 0.01
    with pytest.raises(ValueError, match="unload=True takes target_stress"):
        md.compact(loaded, target_porosity=0.35, unload=True)


@pytest.fixture(scope="module")
def compacted_pack_md(tmp_path_factory):
    import md

    pack = md.settle(size=(3, 3, 6), fall_stiffness_factor=1e-3, seed=4)
    return md.compact(pack, target_stress=10e6)


def test_md_members_on_dask_equal_the_serial_run(result):
    """Once the pack is carried down, the members run on a local dask cluster of two workers
    (the mechanism of --scheduler, which also takes a scheduler address) and give the serial
    moduli to the bit."""
    import shutil

    import xarray as xr

    ds, path = result
    for members in path.glob("md/*/members"):
        shutil.rmtree(members)
    again = run_scene(tiny(path), scheduler="local", jobs=2)
    keep = [v for v in ds.data_vars if v != "md_wall_time"]
    xr.testing.assert_identical(again[keep].drop_attrs(), ds[keep].drop_attrs())
    assert list(path.glob("md/*/members/*.nc"))


@pytest.mark.parametrize("scheme", ["coating", "contact", "pore_body"])
def test_cement_cells_fill_the_core_with_the_fraction(compacted_pack_md, scheme):
    """md.along_depth.cement_cells: the cemented cells inside the core window hold the cement
    fraction of its volume to within one cell, for every scheme; more cement than the window's
    pores cements them all and says so."""
    import md
    from md.along_depth import cement_cells
    from md.observe import core_window

    pack = compacted_pack_md
    lat = md.cement_lattice(pack, 2.0)
    lo, hi = core_window(pack)
    z = lat.centres()[:, 2]
    inside = (z >= lo) & (z < hi)
    volume = pack.box.lx * pack.box.ly * (hi - lo)
    cell = lat.cell_width**3
    for fraction in (0.02, 0.1, 0.2):
        cells, overflow = cement_cells(pack, lat, fraction, scheme, seed=1)
        assert not overflow
        assert abs((cells & inside).sum() * cell - fraction * volume) <= cell
    cells, overflow = cement_cells(pack, lat, 0.9, scheme, seed=1)
    assert overflow and cells[inside].all()


def test_samples_average_independent_packs(result):
    """samples = 2: the velocities are the mean of the packs of seeds 0 and 1 (each run alone
    as a one-sample scene) and the sample-size error the standard error of that mean,
    |v0 - v1| / 2."""
    ds, path = result
    one = run_scene(tiny(path, seed=1)).sel(model="md")
    both = run_scene(tiny(path, samples=2)).sel(model="md")
    zero = ds.sel(model="md")
    for v in ("vp", "vs"):
        np.testing.assert_allclose(both[v], (zero[v] + one[v]) / 2, rtol=1e-12)
        np.testing.assert_allclose(both[f"{v}_error_sample"], abs(zero[v] - one[v]) / 2,
                                   rtol=1e-12)
    assert np.all(np.isfinite(both.vp_error_sample.dropna("depth")))


def test_three_resolutions_give_the_grid_convergence_index(result):
    """With ``resolution_check2`` each MD depth's error is Roache's grid convergence index of
    its three velocities (md.convergence): 1.25 |v - v1| / (r^q - 1) with the observed order q
    (clipped to 0.5-1) where the three are in the asymptotic range, else 3 times the larger
    first-order step, flagged (md_resolution_asymptotic 0) and named in the warnings. The
    velocities themselves do not move (the same members at the finest resolution)."""
    from md.convergence import ORDER_CLIP, SAFETY_FALLBACK, SAFETY_OBSERVED, richardson

    two, path = result
    om = (2.0, 1.5, 1.2)
    three = run_scene(tiny(path, resolution=om[0], resolution_check=om[1],
                           resolution_check2=om[2]))
    ran = np.isfinite(three.vp.sel(model="md").values)
    m2, m3 = two.sel(model="md").isel(depth=ran), three.sel(model="md").isel(depth=ran)
    np.testing.assert_array_equal(m3.vp, m2.vp)
    asym = m3.md_resolution_asymptotic.values
    assert set(np.unique(asym)) <= {0.0, 1.0}
    # Two resolutions: no three-point check was made (NaN, not a failed check; no warning).
    assert np.all(np.isnan(two.md_resolution_asymptotic.sel(model="md").values))
    assert "asymptotic range" not in two.attrs.get("validity_warnings", "")
    # Recompute from coarse-only runs at each resolution (their finest value is that
    # resolution's vp).
    for k in range(asym.size):
        vps = [float(m3.vp.values[k])]
        for w in om[1:]:
            single = run_scene(tiny(path, resolution=w, resolution_check=0.0))
            vps.append(float(single.sel(model="md").vp.isel(depth=ran).values[k]))
        # vp's error follows vp's own three values; md_resolution_asymptotic is 1 only where
        # vp's and vs's both are in the asymptotic range.
        _, p = richardson(om, vps)
        if vps[0] == vps[1] == vps[2]:                   # uncemented: no lattice, no error
            want = 0.0
        elif np.isfinite(p):
            assert asym[k] in (0.0, 1.0)
            q = min(max(p, ORDER_CLIP[0]), ORDER_CLIP[1])
            want = SAFETY_OBSERVED * abs(vps[0] - vps[1]) / ((om[0] / om[1]) ** q - 1.0)
        else:
            assert asym[k] == 0
            want = SAFETY_FALLBACK * max(abs(vps[0] - vps[1]) / (om[0] / om[1] - 1.0),
                                         abs(vps[1] - vps[2]) / (om[1] / om[2] - 1.0))
        assert m3.vp_error_resolution.values[k] == pytest.approx(want, rel=1e-9)
    warned = "not in the asymptotic range" in three.attrs.get("validity_warnings", "")
    assert warned == bool(np.any(asym == 0))
    assert asym[0] == 1 and m3.vp_error_resolution.values[0] == 0     # 1000 m: no cement


def test_the_not_asymptotic_warning_describes_both_errors(result):
    """Where md_resolution_asymptotic (vp's and vs's flags together) is 0, each velocity's
    resolution error follows its own three values (md.convergence, rule "gci"): three times
    the larger first-order step where they have no credible order, the grid convergence index
    of their order where they do; the warning says so. Checked for vp from single-resolution
    runs (their stage files are those of the test above)."""
    from md.convergence import ORDER_CLIP, SAFETY_FALLBACK, SAFETY_OBSERVED, richardson

    _, path = result
    om = (2.0, 1.5, 1.2)
    three = run_scene(tiny(path, resolution=om[0], resolution_check=om[1],
                           resolution_check2=om[2]))
    assert "the resolution error of a velocity without one is three times the larger " \
        "first-order step" in three.attrs["validity_warnings"]
    ran = np.isfinite(three.vp.sel(model="md").values)
    m3 = three.sel(model="md").isel(depth=ran)
    vps = [m3.vp.values] + [run_scene(tiny(path, resolution=w, resolution_check=0.0))
                            .sel(model="md").vp.isel(depth=ran).values for w in om[1:]]
    flagged = m3.md_resolution_asymptotic.values == 0
    assert flagged.any()
    for k in np.flatnonzero(flagged):
        column = [v[k] for v in vps]
        _, p = richardson(om, column)
        if np.isfinite(p):
            q = min(max(p, ORDER_CLIP[0]), ORDER_CLIP[1])
            want = SAFETY_OBSERVED * abs(column[0] - column[1]) / ((om[0] / om[1]) ** q - 1.0)
        else:
            want = SAFETY_FALLBACK * max(abs(column[0] - column[1]) / (om[0] / om[1] - 1.0),
                                         abs(column[1] - column[2]) / (om[1] / om[2] - 1.0))
        np.testing.assert_allclose(m3.vp_error_resolution.values[k], want, rtol=1e-9)


@pytest.mark.parametrize("given,want", [((6.0, None, None), (4.0, 8.0 / 3.0)),
                                        ((2.0, None, None), (4.0 / 3.0, 0.0)),
                                        ((1.4, None, None), (0.0, 0.0)),
                                        ((6.0, 5.0, None), (5.0, 10.0 / 3.0)),
                                        ((6.0, 0.0, None), (0.0, 0.0)),
                                        ((6.0, 3.0, 0.0), (3.0, 0.0))])
def test_default_coarser_resolutions(given, want):
    """Each check defaults to the previous resolution over 1.5, none below Omega 1; a given
    value (0 = none) is kept."""
    from md.convergence import MIN_RATIO
    from rockcem._md_backend import resolve_checks

    assert MIN_RATIO == 1.5
    keys = ("resolution", "resolution_check", "resolution_check2")
    out = resolve_checks(dict(zip(keys, given)))
    assert out["resolution_check"] == pytest.approx(want[0], rel=1e-15)
    assert out["resolution_check2"] == pytest.approx(want[1], rel=1e-15)


def test_compare_takes_md_members_point_by_point(result):
    """well_misfit on a scene with an MD member: the continuous model is compared at every log
    sample, the MD member at its own depths against the log's mean within half a depth step
    (a log that is 2.0 km/s there and 9.9 km/s elsewhere sees only the 2.0)."""
    import xarray as xr

    from rockcem.wells import well_misfit

    ds, _ = result
    z = np.arange(0.0, 4000.01, 0.5)
    step = float(np.median(np.diff(ds.depth.values)))
    md_depths = ds.depth.values[np.isfinite(ds.vp.sel(model="md").values)]
    near = np.min(np.abs(z[:, None] - md_depths[None, :]), axis=1) <= step / 2
    log = np.where(near, 2.0, 9.9)
    well = xr.Dataset({"vp": ("depth", log)}, coords={"depth": z})
    table = well_misfit(ds, well, variables=["vp"]).set_index("model")
    want = ds.vp.sel(model="md", depth=md_depths).values / 2.0 - 1.0
    row = table.loc["md"]
    assert row.n == md_depths.size == 3
    assert row.rms == pytest.approx(np.sqrt(np.mean(want ** 2)), rel=1e-12)
    assert row.bias == pytest.approx(np.mean(want), rel=1e-12)
    assert table.loc["hs_gassmann"].n > 1000                 # every log sample in range


def test_compare_takes_an_md_member_at_most_depths_point_by_point():
    """An MD member valued at half or more of the scene's depths (NaN between) is still
    compared at its own depths, not interpolated into NaN."""
    import xarray as xr

    from rockcem.wells import well_misfit

    depth = np.arange(0.0, 600.0, 100.0)
    vp = np.array([[2.0, 2.1, 2.2, 2.3, 2.4, 2.5], [2.0, np.nan, 2.4, np.nan, 2.8, np.nan]])
    ds = xr.Dataset({"vp": (("model", "depth"), vp)},
                    coords={"model": ["hs_gassmann", "md"], "depth": depth})
    z = np.arange(0.0, 500.01, 1.0)
    well = xr.Dataset({"vp": ("depth", np.full(z.size, 2.0))}, coords={"depth": z})
    row = well_misfit(ds, well, variables=["vp"]).set_index("model").loc["md"]
    want = np.array([2.0, 2.4, 2.8]) / 2.0 - 1.0
    assert row.n == 3
    assert row.rms == pytest.approx(np.sqrt(np.mean(want ** 2)), rel=1e-12)


def test_fitting_the_md_member_is_refused(result):
    import xarray as xr

    from rockcem.wellfit import fit_scene

    _, path = result
    well = xr.Dataset({"vp": ("depth", np.full(5, 3.0))},
                      coords={"depth": np.linspace(1000.0, 3000.0, 5)})
    with pytest.raises(ValueError, match="MD backend"):
        fit_scene(tiny(path), well, {"path.gradient": (30.0, 20.0, 40.0)}, model="md")


def test_md_member_takes_the_depths_fluid(result):
    """Issue 20: the MD member is saturated with the scene's fluid at each MD depth (Batzle-Wang
    brine here; the frame is the same MD run, read back from its stage files)."""
    from rockcem import pore_fluids as pf
    from rockcem.bounds import hashin_shtrikman_average
    from rockcem.constants import STANDARD_ATMOSPHERE
    from rockcem.fluids import gassmann
    from rockcem.materials import mineral

    ds, path = result
    scene = tiny(path)
    brine = run_scene(scene_from_dict({
        "name": "tiny_md", "lithology": "sandstone",
        "path": {"max_depth": 4000.0, "depth_step": 100.0},
        "sandstone": {"start_temperature": 70.0},
        "fluid": {"model": "batzle_wang", "salinity": 0.1},
        "models": {"hs_gassmann": {}, "md": {k: v for k, v in scene.sections["models.md"].items()
                                             if v is not None}}}))
    ran = np.isfinite(ds.vp.sel(model="md").values)
    w, b = ds.sel(model="md").isel(depth=ran), brine.sel(model="md").isel(depth=ran)
    np.testing.assert_allclose(b.K_dry, w.K_dry, rtol=1e-12)
    phi, phi_pack = b.md_porosity.values, b.md_pack_porosity.values
    beta_c = (phi_pack - phi) / (1.0 - phi)
    q, c = mineral("quartz"), mineral("quartz_cement")
    K_min = hashin_shtrikman_average([q.K, c.K], [q.G, c.G],
                                     np.stack([1 - beta_c, beta_c], axis=-1)).K
    fluid = pf.brine(b.temperature.values, b.pressure_pore.values + STANDARD_ATMOSPHERE, 0.1)
    np.testing.assert_allclose(b.K_sat, gassmann(b.K_dry.values, K_min, fluid.K, phi),
                               rtol=1e-10)
    assert np.all(b.K_sat.values != w.K_sat.values)


def test_md_member_in_patches_of_brine_and_gas(result):
    """Patchy saturation of the MD member: the P-wave compliance average of its brine- and its
    gas-saturated rocks (each read back from the same MD runs), NaN where MD did not run."""

    ds, path = result
    scene = tiny(path)
    md_table = {k: v for k, v in scene.sections["models.md"].items() if v is not None}

    def run(fluid):
        return run_scene(scene_from_dict({
            "name": "tiny_md", "lithology": "sandstone",
            "path": {"max_depth": 4000.0, "depth_step": 100.0},
            "sandstone": {"start_temperature": 70.0}, "fluid": fluid,
            "models": {"hs_gassmann": {}, "md": md_table}})).sel(model="md")

    base = {"model": "batzle_wang", "hydrocarbon": "gas", "top": 2000.0, "base": 4000.0}
    patchy = run({**base, "saturation": 0.6, "mixing": "patchy"})
    brine = run({"model": "batzle_wang"})
    gas = run({**base, "saturation": 1.0})
    ran = np.isfinite(ds.vp.sel(model="md").values)
    assert np.isnan(patchy.vp.values[~ran]).all()
    inside = ran & (ds.depth.values >= 2000.0)
    b, g, p = (d.isel(depth=inside) for d in (brine, gas, patchy))
    M = 1.0 / (0.4 / (b.K_sat + 4 / 3 * b.G_sat) + 0.6 / (g.K_sat + 4 / 3 * g.G_sat))
    np.testing.assert_allclose(p.K_sat + 4 / 3 * p.G_sat, M, rtol=1e-10)
    rho = 0.4 * b.md_density + 0.6 * g.md_density
    np.testing.assert_allclose(p.md_density, rho, rtol=1e-12)
    np.testing.assert_allclose(p.vp, np.sqrt(M / rho), rtol=1e-10)
    # between the two patches' rocks, and a possible solid (Vp/Vs of an isotropic solid)
    M_brine, M_gas = b.K_sat + 4 / 3 * b.G_sat, g.K_sat + 4 / 3 * g.G_sat
    assert np.all((M >= M_gas) & (M <= M_brine * (1 + 1e-12)))
    assert np.all(p.vp / p.vs >= np.sqrt(4 / 3))


def test_total_error_and_trust(result):
    """vp_error is the resolution and sample-size errors in quadrature; a member is trusted
    only where both are measured and within trust_threshold of its velocities: with one pack
    no member is (its sample error is unmeasured, NaN, never 0), and the warnings name the
    depths."""
    ds, path = result
    one = ds.sel(model="md")
    ran = np.isfinite(one.vp.values)
    assert np.all(np.isnan(one.vp_error.values[ran]))
    assert np.all(one.md_trusted.values[ran] == 0) and np.all(np.isnan(one.md_trusted[~ran]))
    assert "is not trusted" in ds.attrs["validity_warnings"]
    both = run_scene(tiny(path, samples=2, trust_threshold=0.5))
    m = both.sel(model="md").isel(depth=ran)
    for v in ("vp", "vs"):
        want = np.sqrt(m[f"{v}_error_resolution"] ** 2 + m[f"{v}_error_sample"] ** 2)
        np.testing.assert_allclose(m[f"{v}_error"], want, rtol=1e-12)
    rel = np.maximum(m.vp_error / m.vp, m.vs_error / m.vs).values
    np.testing.assert_array_equal(m.md_trusted.values == 1, rel <= 0.5)
    with pytest.raises(ValueError, match="trust_threshold"):
        run_scene(tiny(path, trust_threshold=1.5))


def test_saturated_moduli_of_an_isotropic_frame_equal_isotropic_gassmann():
    """Five constants of an isotropic frame (C11 = C33, C13 = C33 - 2 C44, C66 = C44): the TI
    reading (bulk modulus under hydrostatic stress, anisotropic Gassmann, vertical velocity)
    equals the isotropic one, and Thomsen's parameters are 0."""
    from rockcem._md_backend import saturated_moduli

    c33, c44 = np.array([[9.0, 20.0]]), np.array([[3.0, 8.0]])
    c = {"p_modulus": c33, "shear_modulus": c44, "c11": c33.copy(), "c13": c33 - 2 * c44,
         "c66": c44.copy()}
    args = (37.0, np.array([2.4, 2.6]), np.array([[0.3, 0.1]]), np.array([[2.2, 2.5]]))
    ti = saturated_moduli(c, *args, ti=True)
    iso = saturated_moduli(c, *args, ti=False)
    for a, b in zip(ti[:5], iso[:5]):
        np.testing.assert_allclose(a, b, rtol=1e-12)
    np.testing.assert_allclose(np.stack(ti[5:8]), 0.0, atol=1e-12)
    assert ti[8].all() and np.all(np.isnan(np.stack(iso[5:8])))


def test_saturated_moduli_of_a_ti_frame():
    """A TI frame (C11 < C33, as a vertically compacted pack): the dry bulk modulus is the
    Reuss sum of the compliance (numpy's inverse of the 6x6 stiffness), below C33 - 4/3 C44;
    the vertical S velocity is sqrt(C44 / rho); a sample whose constants are not positive
    definite falls back to the isotropic reading and is not sound."""
    from rockcem._md_backend import saturated_moduli

    c11, c13, c33, c44, c66 = 6.0, 1.5, 9.0, 3.0, 2.4
    c = {k: np.array([v, v]) for k, v in zip(("c11", "c13", "p_modulus", "shear_modulus",
                                              "c66"), (c11, c13, c33, c44, c66))}
    c["c13"] = np.array([c13, 9.0])                 # 81 > 9 (6 - 2.4): not positive definite
    K_dry, G, K_sat, vp, vs, eps, gam, dlt, sound = saturated_moduli(c, 37.0, 2.4, 0.25, 2.2)
    C = np.zeros((6, 6))
    c12 = c11 - 2 * c66
    C[:3, :3] = [[c11, c12, c13], [c12, c11, c13], [c13, c13, c33]]
    C[3, 3] = C[4, 4] = c44
    C[5, 5] = c66
    assert K_dry[0] == pytest.approx(1.0 / np.linalg.inv(C)[:3, :3].sum(), rel=1e-12)
    assert K_dry[0] < c33 - 4 / 3 * c44
    assert sound.tolist() == [True, False]
    assert K_dry[1] == pytest.approx(c33 - 4 / 3 * c44)
    np.testing.assert_allclose(vs, np.sqrt(c44 / 2.2), rtol=1e-12)
    assert eps[0] < 0 and gam[0] == pytest.approx((c66 - c44) / (2 * c44))
    assert np.isnan(eps[1])
    assert vp[0] > np.sqrt(c33 / 2.2)               # the fluid stiffens C33


def test_md_member_reports_thomsen_and_keeps_the_isotropic_option(result):
    """The default reads the five constants (Thomsen's parameters finite at the MD depths,
    NaN elsewhere); anisotropy = 'isotropic' is the former K_dry = M - 4/3 G with isotropic
    Gassmann on the same C33 and C44: the same vertical S velocity, and a dry bulk modulus
    above the TI sample's bulk modulus under hydrostatic stress (M - 4/3 G leaves out the
    softer horizontal directions)."""
    ds, path = result
    md = ds.sel(model="md")
    ran = np.isfinite(md.vp.values)
    sound = md.md_within_bounds.values[ran] == 1
    for name in ("thomsen_epsilon", "thomsen_gamma", "thomsen_delta"):
        assert np.all(np.isfinite(md[name].values[ran][sound]))
        assert np.all(np.isnan(md[name].values[~ran]))
    iso = run_scene(tiny(path, anisotropy="isotropic")).sel(model="md").isel(depth=ran)
    assert np.all(np.isnan(iso.thomsen_epsilon))
    np.testing.assert_allclose(iso.vs, md.vs.values[ran], rtol=1e-12)
    np.testing.assert_allclose(iso.G_dry, md.G_dry.values[ran], rtol=1e-12)
    assert np.all(md.K_dry.values[ran][sound] < iso.K_dry.values[sound])
    np.testing.assert_allclose(iso.vp, np.sqrt((iso.K_sat + 4 / 3 * iso.G_sat) / iso.md_density),
                               rtol=1e-12)


def test_samples_on_local_processes_equal_the_serial_run(result):
    """With jobs > 1 the packs of samples >= 2 are carried down side by side on local
    processes; the Dataset equals the serial run's."""
    _, path = result
    serial = run_scene(tiny(path, samples=2))
    parallel = run_scene(tiny(path, samples=2), jobs=2)
    for name in ("vp", "vs", "vp_error", "vs_error_sample", "md_porosity", "md_trusted"):
        np.testing.assert_array_equal(parallel[name].values, serial[name].values)


def test_saturated_moduli_without_pores_are_the_dry_ones():
    """Porosity 0 (burial's pores full): no fluid to substitute, the saturated rock is the dry
    one (Gassmann's formula at phi = 0 would give K_min whatever the frame); a frame a hair
    above its mineral (a voxel sample approaches the bound from above) is read, not refused."""
    from rockcem._md_backend import saturated_moduli

    K, G = 37.2, 33.1                       # an isotropic solid, 0.1 % above K_min = 37.16
    c33 = np.array([K + 4 / 3 * G, K + 4 / 3 * G])
    c = {"p_modulus": c33, "shear_modulus": np.full(2, G), "c11": c33.copy(),
         "c13": c33 - 2 * G, "c66": np.full(2, G)}
    phi, rho = np.array([0.0, 0.0]), 2.65
    for ti in (True, False):
        K_dry, G_dry, K_sat, vp, vs, eps, gam, dlt, sound = saturated_moduli(
            c, 37.16, 2.4, phi, rho, ti=ti)
        np.testing.assert_allclose(K_sat, K, rtol=1e-12)
        np.testing.assert_allclose(vp, np.sqrt((K + 4 / 3 * G) / rho), rtol=1e-12)
        np.testing.assert_allclose(vs, np.sqrt(G / rho), rtol=1e-12)
        assert sound.all()
        if ti:
            np.testing.assert_allclose(np.stack([eps, gam, dlt]), 0.0, atol=1e-12)


def test_full_pores_are_measured_by_voxels_at_the_bound(tmp_path):
    """A depth whose pores burial fills (5000 m) is measured by voxel finite elements
    (full_sample = 'voxel', the default): its dry moduli lie within 0.5 % of the
    Hashin-Shtrikman bounds of grain and cement at the sample's fractions (bounds 0.05 %
    apart), its error is small and the member trusted; 'lattice' gives the cement lattice's
    softer frame, far below the bound at this resolution; a pulse test with voxels is refused
    by name."""
    from rockcem.bounds import hashin_shtrikman_upper

    from rockcem.materials import mineral

    def run(full_sample):
        scene = scene_from_dict({
            "name": "full_md", "lithology": "sandstone",
            "path": {"max_depth": 5000.0, "depth_step": 100.0},
            "models": {"md": {"depths": [5000.0], "size": [3.0, 3.0, 6.0], "resolution": 3.0,
                              "samples": 2, "full_sample": full_sample,
                              "workdir": str(tmp_path / "md")}}})
        return scene, run_scene(scene).sel(model="md", depth=5000.0)

    scene, ds = run("voxel")
    assert float(ds.md_porosity) == 0.0 and float(ds.md_trusted) == 1.0
    assert float(ds.md_cement_saturation) == 1.0
    grain, cement = (mineral(scene.sections["materials"][n]) for n in ("grain", "cement"))
    frac = float(ds.md_pack_porosity)          # the cement: the uncemented pack's pores
    upper = hashin_shtrikman_upper([grain.K, cement.K], [grain.G, cement.G],
                                   [1.0 - frac, frac])
    M_hs = upper.K + 4 / 3 * upper.G
    rho = float(ds.density)
    assert float(ds.vp) ** 2 * rho == pytest.approx(M_hs, rel=5e-3)
    assert float(ds.vs) ** 2 * rho == pytest.approx(upper.G, rel=5e-3)
    assert float(ds.vp_error) < 0.01 * float(ds.vp)
    lattice = run("lattice")[1]
    assert float(lattice.vp) < 0.95 * float(ds.vp)
    with pytest.raises(ValueError, match="full_sample = 'voxel' is a static solve"):
        run_scene(scene_from_dict({
            "name": "p", "lithology": "sandstone", "path": {"max_depth": 5000.0},
            "models": {"md": {"measure": "pulse", "anisotropy": "isotropic",
                              "workdir": str(tmp_path / "p")}}}))
