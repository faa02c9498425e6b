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

``--scene garcia_medina_full`` times a subset of the full-size study the same way (its pack,
8 x 8 x 32 diameters, is made in ``results/md_study_parallel_full_work/pack`` before the timed
runs, about half an hour, unless the scene's own ``settle.nc`` and ``compact.nc`` are copied
there; ``--omega`` must then exceed the scene's ``resolution_check``, 4;
``--samples``, ``--schemes``, ``--cements`` and ``--saturations`` choose the members, each also
run at the scene's ``resolution_check``).

Output: ``results/md_study_parallel[_<tag>].csv`` (tag ``full`` by default for the full
scene) and the table on stdout. Run:
``python benchmarks/md_study_parallel.py [--scene garcia_medina_full --omega 6 --schemes contact
pendular --saturations 0.05 0.1]`` (a few minutes; two for that subset; the machine should
be otherwise idle: the ratio measures what a second core gives, and any other load takes from
it).
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
    ap.add_argument("--scene", default="garcia_medina_cement",
                    choices=["garcia_medina_cement", "garcia_medina_full"])
    ap.add_argument("--schemes", nargs="+", default=None, help="default: the scene's")
    ap.add_argument("--cements", nargs="+", default=None, help="default: the scene's")
    ap.add_argument("--samples", nargs="+", default=["compacted"],
                    choices=["loose", "compacted"])
    ap.add_argument("--tag", default=None,
                    help="result file tag (default: none, 'full' with garcia_medina_full)")
    args = ap.parse_args(argv)
    _common.announce_source()
    raw = read_scene_toml(args.scene)[0]
    raw["md"].update(samples=args.samples, resolution=args.omega, saturations=args.saturations)
    for key in ("schemes", "cements"):
        if getattr(args, key) is not None:
            raw["md"][key] = getattr(args, key)
    scene = md_scene_from_dict(raw)
    p = scene["md"]
    full = args.scene == "garcia_medina_full"
    tag = args.tag if args.tag is not None else ("full" if full else "")
    work = _common.RESULTS / (f"{NAME}_full_work" if full else f"{NAME}_work")
    prepare_pack(work / "pack", settle_options={
        "size": tuple(p["size"]), "radius_range": tuple(p["radius_range"]), "seed": p["seed"],
        "fall_stiffness_factor": p["fall_stiffness_factor"]},
        compact_options=({"target_stress": p["compaction_stress"] * 1e6}
                         if "compacted" in p["samples"] else None), progress=True)
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
    # distinct pulse tests: cemented members (again at the resolution check, if any), and one
    # uncemented member per sample where S_c = 0 is asked for
    n_cemented = (sum(sat > 0 for sat in args.saturations) * len(p["schemes"])
                  * len(p["cements"]) * len(p["samples"]))
    attrs = _common.environment_attrs(
        benchmark=NAME, scene=args.scene, omega=args.omega,
        resolution_check=p["resolution_check"], saturations=str(args.saturations),
        schemes=" ".join(p["schemes"]), cements=" ".join(p["cements"]),
        samples=" ".join(p["samples"]),
        members=(n_cemented * (2 if p["resolution_check"] else 1)
                 + (len(p["samples"]) if 0 in args.saturations else 0)),
        identical_results=int(same), **_common.md_source_attrs())
    _common.write_csv(frame, _common.result_path(NAME, "csv", tag), attrs)


if __name__ == "__main__":
    main()
