"""Settling and compaction on this checkout against another revision of it, in the same run.

A change to the MD kernels is measured against the code it replaces: the revision ``--rev``
(default ``HEAD``) is unpacked by ``git archive`` into a temporary folder, and each version runs
in its own child interpreter (its own numba cache), alternately, ``--repeat`` times: settle a
pack of ``--size`` largest diameters (seed ``--seed``, accelerated deposition, the scenes'
fall stiffness factor 1e-3) and compact it between frozen slabs to ``--stress`` MPa. A small
pack is settled first in each child so that compilation stays out of the clock. Reported: wall
time of each stage (best of the repeats), steps, and a SHA-256 of the final positions, so that
a change meant to be a pure speed-up is seen to give the same pack to the bit.

Output: ``results/md_engine_versions[_<tag>].csv`` and a table on stdout. Run:
``python benchmarks/md_engine_versions.py [--rev HEAD] [--size 4 4 12] [--repeat 3] [--tag T]``
(about 5 minutes on one core; the machine should be otherwise idle). The source's full sample:
``--size 8 8 32 --stress 30 --repeat 1 --tag full`` (about 45 minutes).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

NAME = "md_engine_versions"

CHILD = r"""
import hashlib, json, sys, time
sys.path.insert(0, {root!r})
import md
md.settle(size=(3, 3, 5), fall_stiffness_factor=1e-3, seed=1)      # compile outside the clock
t0 = time.perf_counter()
pack = md.settle(size={size!r}, fall_stiffness_factor=1e-3, seed={seed})
t1 = time.perf_counter()
comp = md.compact(pack, target_stress={stress!r})
t2 = time.perf_counter()
print(json.dumps({{"settle_s": t1 - t0, "compact_s": t2 - t1, "path": md.__file__,
                  "settle_steps": int(pack.metadata["steps"]),
                  "compaction_increments": len(comp.metadata["record"]["strain"]),
                  "porosity": float(comp.metadata["record"]["porosity"][-1]),
                  "positions_sha256": hashlib.sha256(comp.positions.tobytes()).hexdigest()}}))
"""


def run_child(root, args):
    code = CHILD.format(root=str(root), size=tuple(args.size), seed=args.seed,
                        stress=args.stress * 1e6)
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None):
    import pandas as pd

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rev", default="HEAD", help="baseline git revision (default HEAD)")
    ap.add_argument("--size", type=float, nargs=3, default=[4.0, 4.0, 12.0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--stress", type=float, default=10.0, help="compaction sigma_zz, MPa")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--tag", default="", help="result file tag")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")
    _common.announce_source()
    commit = subprocess.run(["git", "-C", str(_common.ROOT), "rev-parse", args.rev],
                            capture_output=True, text=True, check=True).stdout.strip()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        archive = subprocess.run(["git", "-C", str(_common.ROOT), "archive", commit],
                                 capture_output=True, check=True).stdout
        subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
        versions = {"this checkout": _common.ROOT, f"{args.rev} ({commit[:10]})": Path(tmp)}
        for k in range(args.repeat):
            for label, root in versions.items():
                out = run_child(root, args)
                rows.append(dict(version=label, repeat=k, **out))
                print(f"{label}: settle {out['settle_s']:.1f} s, compact {out['compact_s']:.1f} s,"
                      f" positions {out['positions_sha256'][:12]}", flush=True)
    frame = pd.DataFrame(rows)
    best = frame.groupby("version", sort=False).agg(
        settle_s=("settle_s", "min"), compact_s=("compact_s", "min"),
        settle_steps=("settle_steps", "first"),
        compaction_increments=("compaction_increments", "first"),
        porosity=("porosity", "first"), positions_sha256=("positions_sha256", "first"))
    base = best.iloc[1]
    best["settle_speed_up"] = base.settle_s / best.settle_s
    best["compact_speed_up"] = base.compact_s / best.compact_s
    same = frame.positions_sha256.nunique() == 1
    print("\n| version | settle s (best) | compact s (best) | settle speed-up | compact speed-up "
          "| steps | porosity |\n|---|---:|---:|---:|---:|---:|---:|")
    for label, r in best.iterrows():
        print(f"| {label} | {r.settle_s:.1f} | {r.compact_s:.1f} | {r.settle_speed_up:.2f} | "
              f"{r.compact_speed_up:.2f} | {r.settle_steps} | {r.porosity:.4f} |")
    print(f"final positions identical to the bit across versions and repeats: {same}")
    attrs = _common.environment_attrs(
        benchmark=NAME, baseline_rev=args.rev, baseline_commit=commit,
        size=" ".join(f"{s:g}" for s in args.size), seed=args.seed,
        compaction_stress_MPa=args.stress, repeat=args.repeat, identical_positions=int(same),
        **_common.md_source_attrs())
    _common.write_csv(best.reset_index(), _common.result_path(NAME, "csv", args.tag), attrs)


if __name__ == "__main__":
    main()
