"""How often the voxel members' reported errors bound the difference to a finer reference.

A depth whose pores burial fills is measured by voxel finite elements (:mod:`md.voxel`) at half
the member's resolutions (``md.along_depth.VOXEL_RESOLUTION_FACTOR``: voxel :math:`\\Omega` 3, 2,
1.33 for the default 6, 4, 2.67), and its resolution error is the grid convergence index over
those three (:func:`md.convergence.resolution_error`). This study measures how often that error
covers the difference to a finer reference, over members that differ in their pack (settling
seed) and in their mineral mix (grain and cement of the scene's ``[materials]`` table).

Each member (mix x seed x depth) is the scene ``--scene`` (default the shipped
``carcione2022_sandstone_md``) with its ``[models.md]`` table narrowed to one full-pore depth,
one pack of ``--size`` grain diameters and one settling seed, run through
:func:`rockcem.scene.run_scene` twice on the same pack (the same stage files: the same settling,
compaction and reconstruction; the difference is the voxels'):

* at ``--resolution`` (default 6) with the scene's default checks: the value X and its reported
  resolution error e (``vp_error_resolution``, ``vs_error_resolution``), voxels at Omega 3, 2, 1.33;
* at ``--reference`` (default 12) with checks at 1/2 and 1/3 of it: the reference X_ref at voxel
  Omega 6 (twice the member's finest voxels) and its own error e_ref (the same rule over voxel
  Omega 6, 3, 2).

A member is covered when e >= |X - X_ref|; it is covered with the reference's error when
e >= |X - X_ref| + e_ref (then it bounds the difference to anything within the reference's
error). For the dry constants C33 and C44 the same rule is applied to the moduli in the member's
stage file (as :func:`md.along_depth.carry_down` does for ``p_modulus_error``); their reference
also gets its Richardson limit (:func:`md.convergence.richardson` over voxel Omega 6, 3, 2; NaN
where the three have no credible order). The rates are printed and written with their binomial
90 % interval (Clopper & Pearson 1934).

Output: ``results/md_voxel_coverage.csv`` (one row per member, written after each member, so an
interrupted run keeps what it measured) and ``results/md_voxel_coverage_summary.csv`` (the rates
per quantity, per mix and over all).
Run: ``python benchmarks/md_voxel_coverage.py`` (1-3 min per member on one shared core at the
defaults; ``--budget-s`` stops starting members after that many seconds).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from md_error_coverage import _scene  # noqa: E402

NAME = "md_voxel_coverage"
#: Default mineral mixes, grain+cement from datasets/materials/minerals.toml: the example's
#: (Carcione et al. 2022, Table 1; shear moduli 39 and 30 GPa), quartz with Garcia & Medina's
#: hard cement (8.6 GPa) and Garcia & Medina's quartz with their soft cement (44 and 2.1 GPa;
#: Garcia & Medina 2007, Tables I-II). Epoxy (Poisson ratio 0.37) is refused by the scene: its
#: cement must be one the lattice represents, even where only voxels measure it.
MIXES = ("quartz+quartz_cement", "quartz+hard_cement", "quartz_garcia_medina+soft_cement")
QUANTITIES = ("vp", "vs", "c33", "c44")
_MODULI = {"c33": "p_modulus", "c44": "shear_modulus"}


def parse_mix(text):
    """``"grain+cement"`` -> ``{"grain": grain, "cement": cement}`` (names of the minerals
    catalogue)."""
    from rockcem.materials import mineral

    parts = text.split("+")
    if len(parts) != 2 or not all(parts):
        raise ValueError(f"a mix is 'grain+cement' (mineral names); got {text!r}")
    for name in parts:
        mineral(name)                       # a ValueError naming the catalogue if unknown
    return {"grain": parts[0], "cement": parts[1]}


def _member_files(workdir):
    """The two member stage files of one depth run at the resolution and at the reference, as
    ``(member, reference)``: the reference's first check is the member's finest value (the
    same voxels; equal to rounding)."""
    import xarray as xr

    files = sorted(Path(workdir).glob("*/members/*.nc"))
    data = [xr.load_dataset(f) for f in files]
    pairs = [(a, b) for a in data for b in data
             if a is not b and np.isclose(float(a.p_modulus), float(b.p_modulus_check),
                                          rtol=1e-9, atol=0.0)
             and np.isclose(float(a.shear_modulus), float(b.shear_modulus_check), rtol=1e-9,
                            atol=0.0)]
    if len(files) != 2 or len(pairs) != 1:
        raise RuntimeError(f"expected one member and one reference stage file in {workdir}; "
                           f"found {len(files)} files, {len(pairs)} matching pairs")
    return pairs[0]


def _moduli_rows(member, reference, omegas, ref_omegas):
    """C33 and C44 (GPa) with the resolution errors of the member and of the reference, and
    the reference's Richardson limit."""
    from md.convergence import resolution_error, richardson

    row = {}
    for label, name in _MODULI.items():
        values = [float(member[f"{name}{s}"]) / 1e9 for s in ("", "_check", "_check2")]
        refs = [float(reference[f"{name}{s}"]) / 1e9 for s in ("", "_check", "_check2")]
        # One column each: resolution_error takes arrays of members (a bare 1-d sequence
        # fails where it has an order: it assigns into a numpy scalar).
        err = resolution_error(omegas, np.asarray(values)[:, None])[0][0]
        ref_err = resolution_error(ref_omegas, np.asarray(refs)[:, None])[0][0]
        limit, order = richardson(ref_omegas, refs)
        row.update({label: values[0], f"{label}_error": float(err), f"{label}_ref": refs[0],
                    f"{label}_ref_error": float(ref_err), f"{label}_ref_limit": limit,
                    f"{label}_ref_order": order,
                    **{f"{label}_voxel_{k}": v for k, v in enumerate(values + refs)}})
    return row


def _covered(row, quantity):
    """Coverage flags and the bar-over-difference ratio of one quantity of a row."""
    x, e = row[quantity], row[f"{quantity}_error"]
    d = abs(x - row[f"{quantity}_ref"])
    row.update({f"{quantity}_difference": d, f"{quantity}_covered": bool(e >= d),
                f"{quantity}_covered_with_ref_error":
                    bool(e >= d + row[f"{quantity}_ref_error"]),
                f"{quantity}_error_over_difference": e / max(d, 1e-15)})
    limit = row.get(f"{quantity}_ref_limit", np.nan)
    if np.isfinite(limit):
        row[f"{quantity}_covered_limit"] = bool(e >= abs(x - limit))
    return row


def member(args, mix, seed, depth, workdir):
    """One member: the scene at the resolution (default checks) and at the reference."""
    from md.along_depth import VOXEL_RESOLUTION_FACTOR
    from rockcem.scene import run_scene

    materials = parse_mix(mix)
    common = (args.scene, [depth], ["coating"], args.size, seed)
    t0 = time.perf_counter()
    ds = run_scene(_scene(*common, args.resolution, None, None, workdir, materials))
    t1 = time.perf_counter()
    ref_omegas = [args.reference, args.reference / 2.0, args.reference / 3.0]
    ref = run_scene(_scene(*common, args.reference, ref_omegas[1], ref_omegas[2], workdir,
                           materials))
    t2 = time.perf_counter()
    k = int(np.argmin(np.abs(ds.depth.values - depth)))
    m, r = ds.sel(model="md").isel(depth=k), ref.sel(model="md").isel(depth=k)
    if not float(ds.md_cement_saturation[k]) == 1.0:
        raise ValueError(f"depth {depth:g} m is not a full-pore depth of {args.scene} (S_c "
                         f"{float(ds.md_cement_saturation[k]):.3f}): its member is not voxels")
    omegas = [args.resolution, args.resolution / 1.5, args.resolution / 2.25]
    row = {"mix": mix, "grain": materials["grain"], "cement": materials["cement"], "seed": seed,
           "depth": float(ds.depth[k]), "pack_porosity": float(ds.md_pack_porosity[k]),
           "voxel_omegas": " ".join(f"{w * VOXEL_RESOLUTION_FACTOR:.4g}"
                                    for w in omegas + ref_omegas),
           "seconds_run": t1 - t0, "seconds_reference": t2 - t1}
    for v in ("vp", "vs"):
        row.update({v: float(m[v]), f"{v}_error": float(m[f"{v}_error_resolution"]),
                    f"{v}_ref": float(r[v]), f"{v}_ref_error": float(r[f"{v}_error_resolution"])})
    files = _member_files(workdir)
    # The voxel solves' own times (three resolutions each), kept in the stage files: a resumed
    # run's seconds_run and seconds_reference count only what it did not find there.
    row.update(seconds_member_voxels=float(files[0].wall_time),
               seconds_reference_voxels=float(files[1].wall_time))
    row.update(_moduli_rows(*files, [w * VOXEL_RESOLUTION_FACTOR for w in omegas],
                            [w * VOXEL_RESOLUTION_FACTOR for w in ref_omegas]))
    for q in QUANTITIES:
        _covered(row, q)
    return row


def summarise(table):
    """Coverage rates per quantity, over all members and per mix."""
    import pandas as pd
    from scipy.stats import binomtest

    rows = []
    for q in QUANTITIES:
        for label, part in [("all", table), *table.groupby("mix", sort=False)]:
            n, k = len(part), int(part[f"{q}_covered"].sum())
            ci = binomtest(k, n).proportion_ci(confidence_level=0.90, method="exact")
            limit = part.get(f"{q}_covered_limit", pd.Series(dtype=object)).dropna()
            rows.append({"quantity": q, "mix": label, "members": n, "covered": k,
                         "rate": k / n, "rate_90_lo": ci.low, "rate_90_hi": ci.high,
                         "covered_with_ref_error": int(part[f"{q}_covered_with_ref_error"].sum()),
                         "with_limit": len(limit), "covered_limit": int(limit.astype(bool).sum()),
                         "median_error_over_difference":
                             float(np.median(part[f"{q}_error_over_difference"])),
                         "median_relative_error": float(np.median(part[f"{q}_error"] / part[q])),
                         "median_relative_difference":
                             float(np.median(part[f"{q}_difference"] / part[q]))})
    return pd.DataFrame(rows)


def main(argv=None):
    import pandas as pd

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="carcione2022_sandstone_md")
    ap.add_argument("--mixes", nargs="+", default=list(MIXES),
                    help="grain+cement mineral names (datasets/materials/minerals.toml)")
    ap.add_argument("--seeds", type=int, nargs="+", default=list(range(8)))
    ap.add_argument("--depths", type=float, nargs="+", default=[4500.0])
    ap.add_argument("--size", type=float, nargs=3, default=[3.0, 3.0, 8.0])
    ap.add_argument("--resolution", type=float, default=6.0)
    ap.add_argument("--reference", type=float, default=12.0)
    ap.add_argument("--workdir", default=None,
                    help="stage files (kept: a rerun resumes); default a fresh temporary folder")
    ap.add_argument("--budget-s", type=float, default=np.inf,
                    help="start no member after this many seconds (those done are written)")
    ap.add_argument("--tag", default="")
    args = ap.parse_args(argv)
    for mix in args.mixes:
        try:
            parse_mix(mix)
        except ValueError as exc:
            ap.error(f"--mixes: {exc}")
    if not args.reference >= 1.5 * args.resolution:
        ap.error(f"--reference must be at least 1.5 times --resolution ({args.resolution:g}); "
                 f"got {args.reference:g}")
    _common.announce_source()
    attrs = _common.environment_attrs(benchmark=NAME, **_common.md_source_attrs(),
                                      scene=args.scene, resolution=args.resolution,
                                      reference=args.reference,
                                      size=" ".join(f"{s:g}" for s in args.size),
                                      mixes=" ".join(args.mixes),
                                      seeds=" ".join(map(str, args.seeds)),
                                      depths=" ".join(f"{d:g}" for d in args.depths))
    work = Path(args.workdir or tempfile.mkdtemp(prefix="md_voxel_coverage_"))
    start, rows = time.perf_counter(), []
    for seed in args.seeds:                 # seed-major: a cut run keeps the mixes balanced
        for mix in args.mixes:
            for depth in args.depths:
                if time.perf_counter() - start > args.budget_s:
                    break
                # One folder per member: the two runs share its pack, no other member's.
                row = member(args, mix, seed, depth, work / mix / f"seed{seed}" / f"{depth:g}")
                rows.append(row)
                _common.write_csv(pd.DataFrame(rows), _common.result_path(NAME, "csv", args.tag),
                                  attrs)
                print(f"{mix} seed {seed} {depth:g} m: vp {row['vp']:.4f} +- "
                      f"{row['vp_error']:.4f} (ref {row['vp_ref']:.4f}), vs {row['vs']:.4f} +- "
                      f"{row['vs_error']:.4f} (ref {row['vs_ref']:.4f}), c33 {row['c33']:.3f} +- "
                      f"{row['c33_error']:.3f} (ref {row['c33_ref']:.3f}); "
                      f"{row['seconds_run']:.0f} + {row['seconds_reference']:.0f} s (voxels "
                      f"{row['seconds_member_voxels']:.0f} + "
                      f"{row['seconds_reference_voxels']:.0f} s)", flush=True)
    table = pd.DataFrame(rows)
    summary = summarise(table)
    _common.write_csv(summary, _common.result_path(f"{NAME}_summary", "csv", args.tag), attrs)
    print(summary.to_string(index=False))


if __name__ == "__main__":
    main()
