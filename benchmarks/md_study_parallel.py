"""An MD study on two processes against one, in the same run: wall time and peak memory
(issue 12, item 7).

The study is an MD scene (``md.experiment.run_md_scene``); its members (one pulse test each:
sample, cement, scheme, saturation, resolution) are independent and run on ``jobs`` processes.
Here the scene ``garcia_medina_cement`` (4 x 4 x 12 largest diameters) is run at ``--omega``
(default 8) on one pack, compacted sample only, hard and soft cement, the three schemes,
S_c 0.02-0.2 (``--saturations``): first with one process, then with two, each from an empty
pulse folder (the pack is made once, before the timed runs, and shared). Each configuration runs
in its own child interpreter, so the timings include the workers' start (imports, numba cache
loads) and the peak resident memory of the child and its workers is read from
``ru_maxrss`` of the children (the largest single process) and, for two processes, from the
workers' own reports (their sum is the study's peak).

Output: ``results/md_study_parallel.csv`` and the table on stdout. Run:
``python benchmarks/md_study_parallel.py`` (a few minutes; the machine should be otherwise idle:
the ratio measures what a second core gives, and any other load takes from it).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

NAME = "md_study_parallel"

CHILD = r"""
import json, resource, sys, time
sys.path.insert(0, {root!r})
from md.experiment import md_scene_from_dict, run_md_scene
scene = md_scene_from_dict(json.loads({scene!r}))
t0 = time.perf_counter()
ds = run_md_scene(scene, workdir={work!r}, jobs={jobs})
seconds = time.perf_counter() - t0
print(json.dumps({{"seconds": seconds, "member_seconds": ds.attrs["member_wall_time_s"],
                  "self_rss": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024,
                  "children_rss": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024,
                  "vp": ds.vp.values.ravel().tolist()}}))
"""


def main(argv=None):
    import numpy as np
    import pandas as pd

    from md.experiment import md_scene_from_dict
    from md.protocols import prepare_pack
    from rockcem.scene import read_scene_toml

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, default=8.0)
    ap.add_argument("--saturations", type=float, nargs="+", default=[0.02, 0.05, 0.1, 0.2])
    ap.add_argument("--jobs", type=int, nargs="+", default=[1, 2])
    args = ap.parse_args(argv)
    _common.announce_source()
    raw = read_scene_toml("garcia_medina_cement")[0]
    raw["md"].update(samples=["compacted"], resolution=args.omega, saturations=args.saturations)
    scene = md_scene_from_dict(raw)
    p = scene["md"]
    work = _common.RESULTS / f"{NAME}_work"
    prepare_pack(work / "pack", settle_options={
        "size": tuple(p["size"]), "radius_range": tuple(p["radius_range"]), "seed": p["seed"],
        "fall_stiffness_factor": p["fall_stiffness_factor"]},
        compact_options={"target_stress": p["compaction_stress"] * 1e6}, progress=True)
    rows, vps = [], {}
    for jobs in args.jobs:
        shutil.rmtree(work / "pulse", ignore_errors=True)
        code = CHILD.format(root=str(_common.ROOT), scene=json.dumps(scene), work=str(work),
                            jobs=jobs)
        t0 = time.perf_counter()
        res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             check=True)
        wall = time.perf_counter() - t0
        out = json.loads(res.stdout.strip().splitlines()[-1])
        vps[jobs] = np.array(out["vp"])
        rows.append(dict(jobs=jobs, wall_s=wall, study_s=out["seconds"],
                         member_sum_s=out["member_seconds"],
                         peak_rss_main_GB=out["self_rss"] / 1e9,
                         peak_rss_largest_worker_GB=out["children_rss"] / 1e9))
        print(f"jobs {jobs}: {wall:.1f} s wall ({out['seconds']:.1f} s in run_md_scene, "
              f"members {out['member_seconds']:.1f} s)", flush=True)
    frame = pd.DataFrame(rows)
    base = frame.wall_s.iloc[0]
    frame["speed_up_vs_first"] = base / frame.wall_s
    same = all(np.array_equal(vps[args.jobs[0]], v) for v in vps.values())
    print("\n| processes | wall s | summed member s | speed-up | peak RSS main / largest "
          "worker (GB) |\n|---:|---:|---:|---:|---:|")
    for r in frame.itertuples():
        print(f"| {r.jobs} | {r.wall_s:.1f} | {r.member_sum_s:.1f} | {r.speed_up_vs_first:.2f} "
              f"| {r.peak_rss_main_GB:.2f} / {r.peak_rss_largest_worker_GB:.2f} |")
    print(f"velocities identical across process counts: {same}")
    attrs = _common.environment_attrs(
        benchmark=NAME, omega=args.omega, saturations=str(args.saturations),
        members=len(args.saturations) * 6 + 1, identical_results=int(same),
        **_common.md_source_attrs())
    _common.write_csv(frame, _common.result_path(NAME, "csv"), attrs)


if __name__ == "__main__":
    main()
