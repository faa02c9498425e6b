"""Wall time of uncertain scenes: 10^3 and 10^4 members of the sandstone scene.

The scene is ``carcione2022_sandstone_uncertain`` (the sandstone of Carcione et al. 2022,
four models, five uncertain inputs) with ``uncertain.samples`` set to each member count, at
the 10 m depth step of that scene (601 depths; ``carcione2022_sandstone`` itself is at 1 m,
6001 depths, measured at 10^3 members). Cases:

* ``state_only``: the outputs of the rock state only (no model): the burial kinetics, which run
  member by member;
* ``four_models``: every output, Model 2 on its default ``numpy`` engine;
* ``four_models_sc_auto``: the same with ``models.self_consistent.engine = "auto"`` (its numba
  kernel from 5e4 points on);

one run each (the 10^4 runs take minutes), serially in one process with one thread, after a
warm-up of 16 members (imports and numba's compilation excluded); the wall time and the
process's CPU time (``cpu_seconds``: on a machine shared with other work the wall time is
longer). ``--dask`` adds the 10^4
``four_models_sc_auto`` case on a local dask cluster of two single-threaded processes.

Output: ``benchmarks/results/uncertainty_speed.{csv,nc}``. Run:
``python benchmarks/uncertainty_speed.py`` (``--members 1000`` for the small case only).
"""

from _common import announce_source, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import os  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402


def timed(scene, **kw):
    from rockcem.scene import run_scene

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t, cpu = time.perf_counter(), time.process_time()
        ds = run_scene(scene, max_members=10**6, **kw)
        return time.perf_counter() - t, ds, time.process_time() - cpu


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", type=int, nargs="+", default=[1000, 10_000])
    parser.add_argument("--dask", action="store_true")
    args = parser.parse_args(argv)
    import rockcem  # noqa: F401

    announce_source()
    from rockcem.scene import MODEL_OUTPUTS, load_scene

    base = load_scene("carcione2022_sandstone_uncertain")
    state = [n for n in base.outputs if n not in MODEL_OUTPUTS]
    cases = {"state_only": {"outputs": state},
             "four_models": {},
             "four_models_sc_auto": {"models.self_consistent.engine": "auto"}}
    rows = []
    for case, change in cases.items():
        timed(base.replace(**change, **{"uncertain.samples": 16}))      # warm-up
        for n in args.members:
            seconds, ds, cpu = timed(base.replace(**change, **{"uncertain.samples": n}))
            rows.append(dict(case=case, members=n, depths=ds.sizes["depth"], scheduler="serial",
                             seconds=seconds, cpu_seconds=cpu, ms_per_member=1e3 * seconds / n))
            print(rows[-1], flush=True)
    for case, change in (("four_models", {}), ("four_models_sc_auto",
                                               {"models.self_consistent.engine": "auto"})):
        fine = base.replace(**change, **{"uncertain.samples": 1000, "path.depth_step": 1.0})
        seconds, ds, cpu = timed(fine)
        rows.append(dict(case=case, members=1000, depths=ds.sizes["depth"], scheduler="serial",
                         seconds=seconds, cpu_seconds=cpu, ms_per_member=1e3 * seconds / 1000))
        print(rows[-1], flush=True)
    if args.dask:
        n = max(args.members)
        scene = base.replace(**{"models.self_consistent.engine": "auto",
                                "uncertain.samples": n})
        seconds, ds, _cpu = timed(scene, scheduler="local")    # (the workers' CPU not seen)
        rows.append(dict(case="four_models_sc_auto", members=n, depths=ds.sizes["depth"],
                         scheduler="dask_local_2", seconds=seconds,
                         ms_per_member=1e3 * seconds / n))
        print(rows[-1], flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="uncertainty_speed", cores=os.cpu_count() or 1,
                              target="10^4 members, 601 depths, four models in <= 60 s on 2 "
                                     "cores (issue 32)")
    out = xr.Dataset.from_dataframe(table).assign_attrs(attrs)
    out["seconds"].attrs["units"] = "s"
    out["ms_per_member"].attrs["units"] = "ms"
    out["cpu_seconds"].attrs["units"] = "s"
    write_csv(table, result_path("uncertainty_speed", "csv"), attrs)
    write_netcdf(out, result_path("uncertainty_speed", "nc"))
    print(table.to_string(index=False))


if __name__ == "__main__":
    main()
