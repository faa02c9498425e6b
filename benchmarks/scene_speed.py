"""Speed of the scene runner: the full sandstone scene, and a 1000-member sweep serial vs dask.

* ``full_scene``: ``carcione2022_sandstone`` (four models, 1 m depth resolution to 6 km, 6001
  depths), best of 5 runs after a warm-up (imports excluded); the first run (with imports) is
  recorded too.
* ``sweep``: the same scene at 50 m resolution swept over 10 gradients x 10 grain sizes x 10
  bonding pre-stresses (1000 members), run serially and on a ``dask.distributed.LocalCluster``
  with one single-threaded worker per core; the speed-up is reported.

Output: ``benchmarks/results/scene_speed.{csv,nc,png}``. Run: ``python benchmarks/scene_speed.py``
(``--members-per-axis`` to shrink the sweep).
"""

from _common import best_of, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import os  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members-per-axis", type=int, default=10)
    args = parser.parse_args(argv)
    t0 = time.perf_counter()
    from rockcem.scene import load_scene, run_scene

    scene = load_scene("carcione2022_sandstone")
    run_scene(scene)
    first = time.perf_counter() - t0
    best, _, ds, _ = best_of(lambda: run_scene(scene), repeat=5)
    rows = [dict(case="full_scene_first_run_with_imports", members=1, depths=ds.sizes["depth"],
                 seconds=first),
            dict(case="full_scene", members=1, depths=ds.sizes["depth"], seconds=best)]
    n = args.members_per_axis
    sweep = scene.replace(**{"path.depth_step": 50.0})
    raw = sweep._raw()
    raw["sweep"] = {"path.gradient": np.linspace(20.0, 40.0, n).tolist(),
                    "sandstone.grain_size": np.linspace(0.1, 1.0, n).tolist(),
                    "models.patchy_cement.delta": np.linspace(20.0, 150.0, n).tolist()}
    from rockcem.scene import scene_from_dict

    big = scene_from_dict(raw)
    members = n**3
    t = time.perf_counter()
    serial = run_scene(big)
    t_serial = time.perf_counter() - t
    t = time.perf_counter()
    parallel = run_scene(big, scheduler="local")
    t_dask = time.perf_counter() - t
    xr.testing.assert_allclose(serial.drop_attrs(), parallel.drop_attrs(), rtol=1e-13)
    rows += [dict(case="sweep_serial", members=members, depths=serial.sizes["depth"],
                  seconds=t_serial),
             dict(case="sweep_dask_local", members=members, depths=serial.sizes["depth"],
                  seconds=t_dask)]
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="scene_speed", workers=os.cpu_count() or 1,
                              dask_speedup=t_serial / t_dask, target_full_scene_s=1.0)
    write_csv(table, result_path("scene_speed", "csv"), attrs)
    out = xr.Dataset.from_dataframe(table)
    out.attrs.update(attrs)
    out["seconds"].attrs["units"] = "s"
    write_netcdf(out, result_path("scene_speed", "nc"))
    print(table.to_string(index=False))
    print(f"dask LocalCluster speed-up over serial: {t_serial / t_dask:.2f}x on "
          f"{os.cpu_count()} cores")


if __name__ == "__main__":
    main()
