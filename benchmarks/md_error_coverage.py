"""How often the MD members' reported errors bound the difference to a finer reference.

An error bar is a claim. This study measures how often it holds, in two parts.

(a) Synthetic sequences (``--synthetic``, seconds). Values :math:`X(\\Omega) = X_\\infty (1 +
    a\\,\\Omega^{-p})` with the error at the finest resolution :math:`|a| 6^{-p}` drawn from 1 to
    10 %, orders :math:`p` 0.5, 1 and 2, and independent relative noise 0, 0.25, 0.5 and 1 % on
    every value (the lattice's noise is about 1 %). For each spacing of the three resolutions
    (6, 5, 4 — the former default — and 6, 4, 8/3 — ratio 1.5, the current one) and each rule
    of :func:`md.convergence.resolution_error` (``"gci"``, the default, and the former
    ``"richardson"``): the share of draws whose error covers :math:`|X(6) - X_{ref}|`, for the
    reference :math:`X(12)` (noisy, as in part b) and for :math:`X_\\infty`, and the median of
    error over true difference (how loose the bar is).

(b) MD members (``--md``, the expensive part). The scene ``--scene`` (default the shipped
    ``carcione2022_sandstone_md``) with its ``[models.md]`` table narrowed to ``--depths``,
    ``--schemes``, ``--size`` and one settling seed at a time (``--seeds``): each member (depth
    x scheme x seed) runs through :func:`rockcem.scene.run_scene` at ``--resolution`` with the
    scene's default checks (resolution / 1.5 and / 2.25) and again at ``--reference``
    (:math:`\\Omega \\ge 12`, no checks). A member is covered when its reported
    ``vp_error_resolution`` (``vs_error_resolution``) is at least :math:`|v - v_{ref}|`. Both
    runs use the same pack (same seed, same compaction), so the difference is the lattice's.
    The rate is printed and written with its binomial 90 % interval.

Output: ``results/md_error_coverage_synthetic.csv`` (a) and ``results/md_error_coverage.csv``
(b, one row per member: depth, scheme, seed, S_c, v, error, v_ref, covered, wall times) with
``results/md_error_coverage_summary.csv`` (the rates).
Run: ``python benchmarks/md_error_coverage.py --synthetic`` (seconds);
``python benchmarks/md_error_coverage.py --md`` (about an hour on this machine at the defaults).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import copy  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_error_coverage"
SPACINGS = {"6-5-4": (6.0, 5.0, 4.0), "6-4-2.67": (6.0, 4.0, 8.0 / 3.0)}


def synthetic(draws=2000, seed=0):
    """Part (a): coverage of each rule and spacing on noisy power-law sequences."""
    import pandas as pd

    from md.convergence import RULES, resolution_error

    rng = np.random.default_rng(seed)
    rows = []
    for p in (0.5, 1.0, 2.0):
        for noise in (0.0, 0.0025, 0.005, 0.01):
            e6 = rng.uniform(0.01, 0.10, draws) * rng.choice([-1.0, 1.0], draws)
            for label, omegas in SPACINGS.items():
                om = np.asarray([*omegas, 12.0])
                x = 1.0 + e6[None, :] * (6.0 / om[:, None]) ** p
                x = x * (1.0 + noise * rng.standard_normal(x.shape))
                for rule in RULES:
                    err, _ = resolution_error(om[:3], x[:3], rule=rule)
                    to_ref, to_limit = np.abs(x[0] - x[3]), np.abs(x[0] - 1.0)
                    rows.append({"order": p, "noise": noise, "spacing": label, "rule": rule,
                                 "coverage_ref12": float(np.mean(err >= to_ref)),
                                 "coverage_limit": float(np.mean(err >= to_limit)),
                                 "median_error_over_difference_ref12":
                                     float(np.median(err / np.maximum(to_ref, 1e-15))),
                                 "draws": draws})
    return pd.DataFrame(rows)


def _scene(name, depths, schemes, size, seed, resolution, check, check2, workdir,
           materials=None):
    """The scene ``name`` with only its ``[models.md]`` table, narrowed to one pack (``seed``)
    at ``resolution`` with the checks ``check``, ``check2`` (None: the scene's defaults; 0:
    none); ``materials`` (a dict, e.g. ``{"cement": "hard_cement"}``) replaces entries of its
    ``[materials]`` table."""
    from rockcem.scene import read_scene_toml, scene_from_dict

    data = copy.deepcopy(read_scene_toml(name)[0])
    data["materials"].update(materials or {})
    table = data["models"]["md"]
    table.update({"depths": list(depths), "schemes": list(schemes), "size": list(size),
                  "seed": int(seed), "samples": 1, "resolution": float(resolution),
                  "workdir": str(workdir)})
    for key, value in (("resolution_check", check), ("resolution_check2", check2)):
        table.pop(key, None)                # None: the scene's defaults
        if value is not None:
            table[key] = float(value)
    data["models"] = {"md": table}
    data["name"] = f"{name}_coverage"
    return scene_from_dict(data)


def md_members(args):
    """Part (b): run every member at the resolution with its checks and at the reference."""
    import pandas as pd

    from rockcem.scene import run_scene

    rows = []
    work = Path(tempfile.mkdtemp(prefix="md_coverage_"))
    for seed in args.seeds:
        t0 = time.perf_counter()
        scene = _scene(args.scene, args.depths, args.schemes, args.size, seed, args.resolution,
                       None, None, work / f"seed{seed}")
        ds = run_scene(scene)
        t1 = time.perf_counter()
        ref = run_scene(_scene(args.scene, args.depths, args.schemes, args.size, seed,
                               args.reference, 0.0, 0.0, work / f"seed{seed}"))
        t2 = time.perf_counter()
        for label in [m for m in ds.model.values if str(m).startswith("md")]:
            m, r = ds.sel(model=label), ref.sel(model=label)
            ran = np.isfinite(m.vp.values)
            for k in np.flatnonzero(ran):
                row = {"seed": seed, "model": str(label), "depth": float(ds.depth[k]),
                       "cement_saturation": float(ds.md_cement_saturation[k]),
                       "seconds_run": t1 - t0, "seconds_reference": t2 - t1}
                for v in ("vp", "vs"):
                    value, ref_value = float(m[v][k]), float(r[v][k])
                    err = float(m[f"{v}_error_resolution"][k])
                    row.update({v: value, f"{v}_error": err, f"{v}_ref": ref_value,
                                f"{v}_covered": bool(err >= abs(value - ref_value))})
                rows.append(row)
        print(f"seed {seed}: {t1 - t0:.0f} s at Omega {args.resolution:g}, {t2 - t1:.0f} s at "
              f"Omega {args.reference:g}", flush=True)
    return pd.DataFrame(rows)


def _interval(k, n, level=0.90):
    """Clopper-Pearson interval of a binomial rate (Clopper & Pearson 1934)."""
    from scipy.stats import beta

    a = 1.0 - level
    lo = beta.ppf(a / 2, k, n - k + 1) if k > 0 else 0.0
    hi = beta.ppf(1 - a / 2, k + 1, n - k) if k < n else 1.0
    return float(lo), float(hi)


def main(argv=None):
    import pandas as pd

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--synthetic", action="store_true")
    ap.add_argument("--md", action="store_true")
    ap.add_argument("--scene", default="carcione2022_sandstone_md")
    ap.add_argument("--depths", type=float, nargs="+",
                    default=[2000.0, 2500.0, 3000.0, 3500.0, 4000.0])
    ap.add_argument("--schemes", nargs="+", default=["coating", "contact"])
    ap.add_argument("--size", type=float, nargs=3, default=[3.0, 3.0, 8.0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--resolution", type=float, default=6.0)
    ap.add_argument("--reference", type=float, default=12.0)
    ap.add_argument("--tag", default="")
    args = ap.parse_args(argv)
    if not (args.synthetic or args.md):
        ap.error("give --synthetic, --md or both")
    attrs = _common.environment_attrs(benchmark=NAME, **_common.md_source_attrs())
    if args.synthetic:
        table = synthetic()
        _common.write_csv(table, _common.result_path(f"{NAME}_synthetic", "csv", args.tag),
                          attrs)
        print(table.to_string(index=False))
    if args.md:
        table = md_members(args)
        attrs.update(scene=args.scene, resolution=args.resolution, reference=args.reference,
                     size=" ".join(f"{s:g}" for s in args.size),
                     seeds=" ".join(map(str, args.seeds)))
        _common.write_csv(table, _common.result_path(NAME, "csv", args.tag), attrs)
        rows = []
        for v in ("vp", "vs"):
            for label, part in [("all", table), *table.groupby("model")]:
                k, n = int(part[f"{v}_covered"].sum()), len(part)
                lo, hi = _interval(k, n)
                rows.append({"velocity": v, "model": label, "members": n, "covered": k,
                             "rate": k / n, "rate_90_lo": lo, "rate_90_hi": hi,
                             "median_error_over_difference": float(np.median(
                                 part[f"{v}_error"] / np.maximum(
                                     np.abs(part[v] - part[f"{v}_ref"]), 1e-12)))})
        summary = pd.DataFrame(rows)
        _common.write_csv(summary, _common.result_path(f"{NAME}_summary", "csv", args.tag),
                          attrs)
        print(table.to_string(index=False))
        print(summary.to_string(index=False))


if __name__ == "__main__":
    main()
