"""MD scenes: validation, the CLI route, resumable stages and the cement ordering."""

import pytest

from md.experiment import md_scene_from_dict, schema_lines


def scene(**md):
    base = {"size": [3, 3, 8], "samples": ["loose"], "schemes": ["contact", "pore_body"],
            "cements": ["hard"], "saturations": [0.0, 0.1], "seed": 2}
    return {"name": "tiny", "output": "tiny.nc", "md": {**base, **md}}


@pytest.mark.parametrize("md,match", [
    ({"sheme": ["contact"]}, "did you mean 'schemes'"),
    ({"schemes": ["glue"]}, "valid: contact, coating, pore_body"),
    ({"saturations": [0.1, 1.5]}, r"\[0, 1\]"),
    ({"size": [3, 3]}, "md.size must be three positive finite numbers"),
    ({"compaction_stress": -1.0}, "MPa"),
    ({"wave": "x"}, "'p' or 's'"),
    ({"resolution": "fine"}, "finite number"),
    ({"resolution_check": 4.0}, "resolution_check"),
])
def test_bad_scene_keys(md, match):
    with pytest.raises(ValueError, match=match):
        md_scene_from_dict(scene(**md))


def test_schema_lists_every_key():
    assert len(schema_lines()) == len(md_scene_from_dict(scene())["md"])


@pytest.mark.slow
def test_md_scene_runs_from_the_cli_and_resumes(tmp_path, run_cli):
    toml = tmp_path / "tiny.toml"
    toml.write_text('name = "tiny"\noutput = "tiny.nc"\n[md]\nsize = [3, 3, 8]\nseed = 2\n'
                    'samples = ["loose"]\nschemes = ["contact", "pore_body"]\n'
                    'cements = ["hard"]\nsaturations = [0.0, 0.1]\nrotations = false\n'
                    f'workdir = "{tmp_path / "work"}"\n')
    out = tmp_path / "tiny.nc"
    res = run_cli(["run", str(toml), "-o", str(out), "--jobs", "2"], tmp_path)
    assert res.returncode == 0, res.stderr
    assert out.exists() and "static" in res.stdout and "± eq. 11" in res.stdout
    import xarray as xr

    with xr.open_dataset(out) as ds:
        vp = ds.vp.sel(sample="loose", cement="hard")
        # Cement raises the velocity, contact cement most (García & Medina, Fig. 12; the
        # source's translations only).
        assert float(vp.sel(scheme="contact", saturation=0.1)) > \
            float(vp.sel(scheme="pore_body", saturation=0.1)) > 0
        assert float(vp.sel(scheme="contact", saturation=0.1)) > \
            2 * float(vp.sel(scheme="contact", saturation=0.0))
        assert float(ds.porosity.sel(sample="loose", saturation=0.1)) < \
            float(ds.porosity_uncemented.sel(sample="loose"))
        # Both stresses of the pack, named and in MPa: a settled pack carries its weight only.
        assert ds.stress.attrs["units"] == ds.stress_mean.attrs["units"] == "MPa"
        assert 0 < float(ds.stress_mean.sel(sample="loose")) < 0.01
    stages = sorted(p.name for p in (tmp_path / "work").rglob("*.nc") if p.name[0] != ".")
    # One stage file per pulse test; the uncemented pack is one test for both schemes.
    assert stages == ["loose_hard_contact_sc0.1_omega3.nc", "loose_hard_pore_body_sc0.1_omega3.nc",
                      "loose_uncemented.nc", "settle.nc"]
    # A second run resumes from the saved stages: none is rewritten, the result is the same.
    stage_files = [p for p in (tmp_path / "work").rglob("*.nc") if p.name[0] != "."]
    before = {p: p.stat().st_mtime_ns for p in stage_files}
    first = xr.load_dataset(out)
    assert run_cli(["run", str(toml), "-o", str(out), "-q"], tmp_path).returncode == 0
    assert {p: p.stat().st_mtime_ns for p in stage_files} == before
    xr.testing.assert_identical(xr.load_dataset(out).drop_attrs(), first.drop_attrs())
    # The pulse tests run on two processes give what one process gives, to the bit.
    for f in (tmp_path / "work" / "pulse").glob("*.nc"):
        f.unlink()
    assert run_cli(["run", str(toml), "-o", str(out), "-q", "-j", "1"], tmp_path).returncode == 0
    serial = xr.load_dataset(out).drop_vars("wall_time").drop_attrs()
    xr.testing.assert_identical(serial, first.drop_vars("wall_time").drop_attrs())


def test_run_md_scene_rejects_missing_table():
    with pytest.raises(ValueError, match=r"\[md\]"):
        md_scene_from_dict({"name": "x"})


@pytest.mark.parametrize("jobs", ["0", "-2", "two"])
def test_cli_jobs_must_be_a_positive_integer(tmp_path, run_cli, jobs):
    res = run_cli(["run", "garcia_medina_cement", "-j", jobs], tmp_path)
    assert res.returncode == 2
    assert f"--jobs: must be an integer >= 1; got '{jobs}'" in res.stderr
    assert "Traceback" not in res.stderr and not list(tmp_path.iterdir())
