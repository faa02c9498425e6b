"""Wall time of uncertain scenes: this checkout against a baseline commit, side by side.

The scene is ``carcione2022_sandstone_uncertain`` (the sandstone of Carcione et al. 2022,
four models, five uncertain inputs, 601 depths at its 10 m step) with ``uncertain.samples`` set
to the member count (10^4 by default) and ``models.self_consistent.engine = "auto"`` (Model 2's
numba kernel from 5e4 points on). Cases:

* ``state_only``: the outputs of the rock state only (the burial kinetics; no model), serial;
* ``four_models``: every output, serially in one process (one thread), and on a local dask
  cluster of two single-threaded processes (``dask_local_2``; the cluster's start-up is inside
  the time, as a user's run has it).

Each case runs in its own Python process, once with the baseline's rockcem (a detached git
worktree of ``--baseline``, default the commit this branch left main at) and once with this
checkout's, the two interleaved (the order alternating from one repeat to the next) so that the
load of a shared machine falls on both alike; each process first runs 300 members untimed
(imports, numba's compilation and its cache). The load average (1 min) is recorded before each
run. The summary gives per case the median time of each tree and the ratio baseline / this.

Output: ``benchmarks/results/uncertainty_speed.{csv,nc}`` (every run) and
``uncertainty_speed_summary.csv`` (the ratios). Run:
``python benchmarks/uncertainty_speed.py`` (``--members 1000 --repeats 1`` for a quick look).
"""

from _common import ROOT, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import json  # noqa: E402
import os  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

#: (case, scheduler) pairs measured.
CASES = (("state_only", "serial"), ("four_models", "serial"), ("four_models", "dask_local_2"))
#: The commit this branch (members-fast) left main at.
BASELINE = "5eba356"


def _scene(case, n):
    from rockcem.scene import MODEL_OUTPUTS, load_scene

    base = load_scene("carcione2022_sandstone_uncertain").replace(
        **{"models.self_consistent.engine": "auto", "uncertain.samples": n})
    if case == "state_only":
        return base.replace(outputs=[o for o in base.outputs if o not in MODEL_OUTPUTS])
    return base


def one(case, n, scheduler, tree):
    """Run one case in this process (the rockcem of ``tree``): ``{seconds, cpu_seconds}``."""
    import rockcem
    from rockcem.scene import run_scene

    if not Path(rockcem.__file__).resolve().is_relative_to(Path(tree).resolve()):
        raise SystemExit(f"rockcem imported from {rockcem.__file__}, not from {tree}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        run_scene(_scene(case, 300), max_members=10**6)                 # warm-up
        t, cpu = time.perf_counter(), time.process_time()
        ds = run_scene(_scene(case, n), max_members=10**6,
                       scheduler=None if scheduler == "serial" else "local")
        seconds, cpu = time.perf_counter() - t, time.process_time() - cpu
    return {"seconds": seconds, "cpu_seconds": cpu, "depths": int(ds.sizes["depth"])}


def _spawn(case, n, scheduler, tree):
    env = dict(os.environ, ROCKCEM_BENCH_PATH=str(tree), PYTHONPATH=str(tree))
    out = subprocess.run([sys.executable, __file__, "--one", case, str(n), scheduler, str(tree)],
                         env=env, capture_output=True, text=True, check=True, cwd=tree)
    return json.loads(out.stdout.strip().splitlines()[-1])


def _git(*cmd):
    return subprocess.run(["git", "-C", str(ROOT), *cmd], capture_output=True, text=True,
                          check=True).stdout.strip()


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--baseline", default=BASELINE)
    parser.add_argument("--one", nargs=4, metavar=("CASE", "N", "SCHEDULER", "TREE"),
                        help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one:
        case, n, scheduler, tree = args.one
        print(json.dumps(one(case, int(n), scheduler, tree)))
        return
    this = _git("rev-parse", "HEAD")
    baseline = _git("rev-parse", args.baseline)
    dirty = _git("status", "--porcelain", "--untracked-files=no", "--", "rockcem", "burial")
    print(f"this checkout {this[:10]} (uncommitted: {dirty or 'none'}); baseline "
          f"{baseline[:10]}", flush=True)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        base_tree = Path(tmp) / "baseline"
        _git("worktree", "add", "--detach", str(base_tree), baseline)
        try:
            trees = [("baseline", base_tree, baseline), ("this", ROOT, this)]
            for repeat in range(args.repeats):
                for case, scheduler in CASES:
                    for label, tree, rev in (trees if repeat % 2 == 0 else trees[::-1]):
                        load = os.getloadavg()[0]
                        r = _spawn(case, args.members, scheduler, tree)
                        rows.append(dict(tree=label, commit=rev[:10], case=case,
                                         scheduler=scheduler, members=args.members,
                                         depths=r["depths"], repeat=repeat,
                                         seconds=r["seconds"], cpu_seconds=r["cpu_seconds"],
                                         load_1min=load))
                        print(rows[-1], flush=True)
        finally:
            _git("worktree", "remove", "--force", str(base_tree))
    table = pd.DataFrame(rows)
    median = table.groupby(["case", "scheduler", "members", "tree"])["seconds"].median()
    summary = median.unstack("tree").reset_index()
    summary["ratio_baseline_over_this"] = summary["baseline"] / summary["this"]
    summary = summary.rename(columns={"baseline": "baseline_seconds", "this": "this_seconds"})
    attrs = environment_attrs(
        benchmark="uncertainty_speed", cores=os.cpu_count() or 1, baseline_commit=baseline,
        this_commit=this, load_1min_median=float(table["load_1min"].median()),
        target="10^4 members, 601 depths, four models in <= 60 s on 2 cores (issue 32)",
        note="medians over the repeats; the machine may be shared (load_1min before each run)")
    out = xr.Dataset.from_dataframe(table).assign_attrs(attrs)
    out["seconds"].attrs["units"] = "s"
    out["cpu_seconds"].attrs["units"] = "s"
    write_csv(table, result_path("uncertainty_speed", "csv"), attrs)
    write_csv(summary, result_path("uncertainty_speed", "csv", "summary"), attrs)
    write_netcdf(out, result_path("uncertainty_speed", "nc"))
    print(table.to_string(index=False))
    print(summary.to_string(index=False))


if __name__ == "__main__":
    main()
