"""MD settling and compaction: the paper's sample, and accelerated vs faithful deposition.

1. ``accelerated_vs_faithful``: small samples (default 3 x 3 x 6 largest diameters) settled with
   the true contact stiffness throughout (``fall_stiffness_factor = 1``, the faithful run) and
   with softer contacts while falling (factors 1e-1, 1e-2, 1e-3), same seeds: porosity,
   coordination number, steps and wall time.
2. ``paper_sample``: the García & Medina sample (8 x 8 x 32 largest diameters, radii 0.18–0.20
   mm, quartz of Table I) settled with accelerated deposition and compacted to porosity 0.386,
   reporting the settled porosity and coordination (the paper: 41.2 %) and the confining stress
   the compaction takes (the paper: about 30 MPa). Skipped with ``--no-paper`` (it takes long).

Output: ``benchmarks/results/md_settle_compact.{csv,nc}``.
Run: ``python benchmarks/md_settle_compact.py [--seeds 3] [--no-paper]``
"""

from _common import RESULTS, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402

import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

from md.protocols import prepare_pack, settle  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--small", type=float, nargs=3, default=(3, 3, 6))
    parser.add_argument("--no-paper", action="store_true")
    args = parser.parse_args(argv)
    rows = []
    for factor in (1.0, 1e-1, 1e-2, 1e-3):
        for seed in range(args.seeds):
            t = time.perf_counter()
            p = settle(size=tuple(args.small), fall_stiffness_factor=factor, seed=seed,
                       kinetic_tolerance=1e-5)
            rows.append(dict(case="accelerated_vs_faithful", fall_stiffness_factor=factor,
                             seed=seed, n_grains=p.n_grains, porosity=p.metadata["porosity"],
                             coordination_number=p.metadata["coordination_number"],
                             steps=p.metadata["steps"], seconds=time.perf_counter() - t,
                             stress_zz_MPa=float("nan")))
            print(rows[-1], flush=True)
    if not args.no_paper:
        # Stages are saved in results/paper_sample/ and resumed: a run interrupted during the
        # compaction does not settle again (delete the folder to start over).
        workdir = RESULTS / "paper_sample"
        settle_options = dict(size=(8, 8, 32), fall_stiffness_factor=1e-3, seed=0,
                              kinetic_tolerance=1e-5)
        t = time.perf_counter()
        p = prepare_pack(workdir, settle_options=settle_options, progress=True)
        rows.append(dict(case="paper_sample_settled", fall_stiffness_factor=1e-3, seed=0,
                         n_grains=p.n_grains, porosity=p.metadata["porosity"],
                         coordination_number=p.metadata["coordination_number"],
                         steps=p.metadata["steps"], seconds=time.perf_counter() - t,
                         stress_zz_MPa=float("nan")))
        print(rows[-1], flush=True)
        t = time.perf_counter()
        c = prepare_pack(workdir, settle_options=settle_options,
                         compact_options=dict(target_porosity=0.386, strain_step=1e-3),
                         progress=True)
        rec = c.metadata["record"]
        rows.append(dict(case="paper_sample_compacted", fall_stiffness_factor=1e-3, seed=0,
                         n_grains=c.n_grains, porosity=rec["porosity"][-1],
                         coordination_number=rec["coordination_number"][-1],
                         steps=len(rec["strain"]), seconds=time.perf_counter() - t,
                         stress_zz_MPa=rec["stress_zz"][-1] / 1e6))
        print(rows[-1], flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="md_settle_compact", small_size=json.dumps(args.small),
                              paper_porosity_settled=0.412, paper_porosity_compacted=0.386,
                              paper_stress_MPa=30.0)
    write_csv(table, result_path("md_settle_compact", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path("md_settle_compact", "nc"))
    summary = table.groupby(["case", "fall_stiffness_factor"])[
        ["porosity", "coordination_number", "steps", "seconds"]].mean()
    print(summary.to_string())


if __name__ == "__main__":
    main()
