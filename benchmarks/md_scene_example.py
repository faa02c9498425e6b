"""The shipped sandstone example with the MD engine as a fifth model (issue 23, Show).

Runs the scene ``carcione2022_sandstone_md`` (stage files in
``results/md_scene_example_work``, so a rerun reads them back), writes its Dataset
(``results/carcione2022_sandstone_md.nc``), a table per MD depth
(``results/md_scene_example.csv``: the effective stress, which the path never lowers, and the
stress the pack reached; cement fraction, S_c, burial's and the MD porosity, vp and vs of both
MD members with their resolution errors, Model 4's vp and vs, member wall time) and the figures
``docs/carcione2022_sandstone_md.png`` (depth trends of the five models) and
``docs/carcione2022_sandstone_md_template.png`` (the rock-physics template with the MD points).
Run: ``python benchmarks/md_scene_example.py [-j 2]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

NAME = "md_scene_example"
SCENE = "carcione2022_sandstone_md"


def per_depth_table(ds):
    """The MD depths of a scene Dataset as a table (one row per depth)."""
    import numpy as np
    import pandas as pd

    ran = np.isfinite(ds.md_porosity.values)
    sub = ds.isel(depth=np.flatnonzero(ran))
    md = [str(m) for m in ds.model.values if str(m).startswith("md")]
    table = pd.DataFrame({
        "depth_m": sub.depth.values,
        "p_e_MPa": sub.pressure_effective.values,
        "md_stress_MPa": sub.md_stress.values,
        "cement_fraction": sub.cement_fraction.values,
        "S_c": sub.md_cement_saturation.values,
        "porosity_burial": sub.porosity.values,
        "porosity_md_pack": sub.md_pack_porosity.values,
        "porosity_md": sub.md_porosity.values})
    for m in md:
        for v in ("vp", "vs"):
            table[f"{v}_{m}"] = sub[v].sel(model=m).values
            table[f"{v}_error_resolution_{m}"] = sub[f"{v}_error_resolution"].sel(model=m).values
        table[f"wall_time_s_{m}"] = sub.md_wall_time.sel(model=m).values
    for v in ("vp", "vs"):
        table[f"{v}_patchy_cement"] = sub[v].sel(model="patchy_cement").values
    return table


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-j", "--jobs", type=int, default=1)
    args = parser.parse_args(argv)
    _common.announce_source()
    _common.use_agg()
    from rockcem.plots import depth_trends, rock_physics_template
    from rockcem.scene import load_scene, run_scene, write_dataset

    work = _common.RESULTS / f"{NAME}_work"
    scene = load_scene(SCENE).replace(**{"models.md.workdir": str(work)})
    t0 = time.perf_counter()
    ds = run_scene(scene, jobs=args.jobs, progress=True)
    seconds = time.perf_counter() - t0
    write_dataset(ds, _common.result_path(SCENE, "nc"))
    table = per_depth_table(ds)
    # The wall time of a run that read its stages back says nothing of the scene's cost: that is
    # benchmarks/md_scene_parallel.py's.
    attrs = _common.environment_attrs(scene=SCENE, jobs=args.jobs)
    _common.write_csv(table, _common.result_path(NAME, "csv"), attrs)
    docs = _common.ROOT / "docs"
    _common.save_figure(depth_trends(ds), docs / f"{SCENE}.png")
    _common.save_figure(rock_physics_template(ds), docs / f"{SCENE}_template.png")
    print(f"{SCENE}: {seconds:.1f} s on {args.jobs} process(es) (stage files read back count)")
    print(table.round(3).to_string(index=False))


if __name__ == "__main__":
    main()
