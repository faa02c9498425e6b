"""The MD members of a burial scene on one process, on two local processes and on a local dask
cluster of two workers, in the same run (issue 23, item 6).

A burial scene with ``[models.md]`` (default the shipped ``carcione2022_sandstone_md``) first
carries its pack down every depth, one stage after the other; the members (depth x scheme, each
at the scene's resolution and its ``resolution_check``) are then independent. Here the scene is
run once to make the pack stages (``results/md_scene_parallel_work``); then, for each
configuration in turn and ``--repeat`` times interleaved, the member files are deleted and the
scene is run again in a fresh child interpreter, so each time only the members are computed
(plus reading the stages back). Timings include the workers' start (imports, numba cache loads,
the dask cluster). The velocities of every run must equal the serial run's to the bit.

``--work FOLDER`` reuses the pack stages of an earlier run of the same scene (such as
``results/md_scene_example_work``) instead of making them first.

Output: ``results/md_scene_parallel[_<tag>].csv`` and the table on stdout. Run:
``python benchmarks/md_scene_parallel.py [--scene carcione2022_sandstone_md --repeat 2]``
(about three times the member time; the machine should be otherwise idle: the ratio measures
what a second core gives).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
from pathlib import Path  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402

NAME = "md_scene_parallel"

CHILD = r"""
import json, sys, time
sys.path.insert(0, {root!r})
from rockcem.scene import load_scene, run_scene
scene = load_scene({scene!r}).replace(**{{"models.md.workdir": {work!r}}})
t0 = time.perf_counter()
ds = run_scene(scene, scheduler={scheduler!r}, jobs={jobs})
seconds = time.perf_counter() - t0
md = [m for m in ds.model.values if str(m).startswith("md")]
print(json.dumps({{"seconds": seconds,
                  "member_seconds": float(ds.md_wall_time.sel(model=md).sum()),
                  "vp": ds.vp.sel(model=md).values.ravel().tolist()}}))
"""

CONFIGS = {"serial": (None, 1), "2 processes": (None, 2), "dask local, 2 workers": ("local", 2)}


def _child(root, scene, work, scheduler, jobs):
    code = CHILD.format(root=root, scene=scene, work=str(work), scheduler=scheduler, jobs=jobs)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main(argv=None):
    import numpy as np
    import pandas as pd

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--scene", default="carcione2022_sandstone_md")
    parser.add_argument("--repeat", type=int, default=2, help="interleaved runs per config")
    parser.add_argument("--tag", default="")
    parser.add_argument("--work", default=None,
                        help="stage folder of an earlier run of the same scene (e.g. "
                        "results/md_scene_example_work): its packs are reused, no first run")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error("--repeat must be >= 1")
    _common.announce_source()
    root = str(_common.ROOT)
    if args.work:
        work = Path(__file__).resolve().parent / args.work     # absolute stays absolute
        if not any(work.glob("*/pack")):
            parser.error(f"--work {args.work}: no pack stages there")
    else:
        work = _common.RESULTS / f"{NAME}_work"
        print(f"making the pack stages in {work} ...", flush=True)
        _child(root, args.scene, work, None, 1)
    rows, reference = [], None
    for rep in range(args.repeat):
        for label, (scheduler, jobs) in CONFIGS.items():
            for members in work.glob("*/members"):
                shutil.rmtree(members)
            res = _child(root, args.scene, work, scheduler, jobs)
            vp = np.asarray(res["vp"])
            if reference is None:
                reference = vp
            same = bool(np.array_equal(np.isnan(vp), np.isnan(reference))
                        and np.array_equal(vp[~np.isnan(vp)], reference[~np.isnan(reference)]))
            rows.append({"config": label, "run": rep, "seconds": res["seconds"],
                         "member_seconds": res["member_seconds"], "identical_vp": same})
            print(rows[-1], flush=True)
    frame = pd.DataFrame(rows)
    best = frame.groupby("config", sort=False)["seconds"].min()
    frame["speedup_vs_serial_best"] = frame["config"].map(best["serial"] / best)
    attrs = _common.environment_attrs(scene=args.scene, repeat=args.repeat)
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    print(frame.to_string(index=False))
    if not frame["identical_vp"].all():
        raise SystemExit("a parallel run changed the velocities")


if __name__ == "__main__":
    main()
