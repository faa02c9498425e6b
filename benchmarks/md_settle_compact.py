"""MD pack preparation: sequential vs all-at-once deposition, and compaction to 100 MPa.

1. ``deposition``: packs of ``--size`` largest diameters (default 6 x 6 x 8) settled with the
   source's sequential deposition (grains dropped in waves at random x, y) and with the faster
   release of all grains from a lattice, same seeds (``--seeds``, default 3), with the true
   contact stiffness throughout (``fall_stiffness_factor = 1``): core porosity (between the
   slabs a compaction freezes; the source: 0.412), porosity from the floor, coordination,
   steps and wall time. Sequential variants (``--variants NAME:SEEDS``): each wave released at
   rest (``deposition_gentle``, seed 0) and ten times the drag (``deposition_drag500``,
   seeds 0-2).
2. ``compaction``: the first sequential pack compacted between frozen slabs to
   ``--stresses`` (MPa, default 10, 30, 100) in steps of ``--strain-step``: core porosity,
   sigma_zz and mean stress (virial with tangential forces), the force on the top slab per area,
   and the overlaps against the Hertz estimate of the mean stress
   (:func:`md.observe.expected_overlap`): mean, 99th percentile and largest, and the blow-up
   limit (:func:`md._dynamics.overlap_limit`).

Every case is saved as it finishes (``results/md_settle_compact_parts/``) and reused by a later
run, so an interrupted run resumes. Output: ``benchmarks/results/md_settle_compact.{csv,nc}``.
Run: ``python benchmarks/md_settle_compact.py [--size 6 6 8] [--seeds 3] [--no-compaction]``
"""

from _common import RESULTS, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

from md._dynamics import overlap_limit  # noqa: E402
from md.observe import (coordination_number, expected_overlap, group_force,  # noqa: E402
                        pair_geometry, porosity)
from md.protocols import compact, settle  # noqa: E402
from md.state import load_pack, save_pack  # noqa: E402

PARTS = RESULTS / "md_settle_compact_parts"


#: Sequential deposition of seed 0 with one setting changed: each wave released at rest just
#: above the pile (no impact speed), and a fluid ten times more viscous (terminal 2 cm/s).
VARIANTS = {"gentle": dict(drop_height=1e-6), "drag500": dict(drag=500.0)}


def _settled(size, protocol, seed, variant=""):
    path = PARTS / (f"settle_{protocol}_{'x'.join(f'{s:g}' for s in size)}_seed{seed}"
                    + (f"_{variant}" if variant else "") + ".nc")
    if path.exists():
        return load_pack(path)
    t = time.perf_counter()
    pack = settle(size=size, protocol=protocol, seed=seed, fall_stiffness_factor=1.0,
                  kinetic_tolerance=1e-5, **VARIANTS.get(variant, {}))
    pack = pack.__class__(**{**pack.__dict__, "metadata": {
        **pack.metadata, "seconds": time.perf_counter() - t}})
    save_pack(pack, path)
    return pack


def _overlap_row(pack):
    """Overlaps of the contacts in the core against the Hertz estimate of the mean stress."""
    x, r = pack.positions, pack.radii
    lo, hi = pack.metadata["core_window_m"]
    d, _, xi = pair_geometry(x, r, pack.pairs, pack.box)
    mid = x[pack.pairs[:, 0], 2] + 0.5 * d[:, 2]
    core = (xi > 0) & (mid > lo) & (mid < hi)
    frozen = np.zeros(pack.n_grains, bool)
    frozen[pack.metadata["frozen_grains"]] = True
    top = frozen & (x[:, 2] > hi)
    f_top = group_force(x, r, pack.pairs, pack.box, pack.material, top, pack.history)[2]
    mobile = np.ones(pack.n_grains, bool)
    mobile[pack.metadata["frozen_grains"]] = False
    z = 2.0 * np.count_nonzero(core) / max(np.count_nonzero(
        mobile & (x[:, 2] > lo) & (x[:, 2] < hi)), 1)
    est = float(expected_overlap(pack.metadata["stress_mean"], float(r.mean()),
                                 pack.metadata["porosity"], z, pack.material))
    limit = overlap_limit(x, r, pack.pairs, pack.box, pack.material)
    xc = xi[core]
    return dict(slab_stress_MPa=f_top / (pack.box.lx * pack.box.ly) / 1e6,
                coordination_core=z, overlap_mean_R=xc.mean() / r.mean(),
                overlap_p99_R=np.percentile(xc, 99) / r.mean(), overlap_max_R=xc.max() / r.mean(),
                overlap_hertz_estimate_R=est / r.mean(), overlap_limit_R=limit / r.mean())


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=3)
    parser.add_argument("--size", type=float, nargs=3, default=(6, 6, 8))
    parser.add_argument("--stresses", type=float, nargs="+", default=(10.0, 30.0, 100.0))
    parser.add_argument("--strain-step", type=float, default=2e-3)
    parser.add_argument("--protocols", nargs="+", default=("sequential", "lattice"))
    parser.add_argument("--variants", nargs="*", default=("gentle:1", "drag500:3"),
                        help="NAME[:SEEDS], variants of seed 0 (or of seeds 0 .. SEEDS-1)")
    parser.add_argument("--no-compaction", action="store_true")
    args = parser.parse_args(argv)
    size = tuple(args.size)
    PARTS.mkdir(parents=True, exist_ok=True)
    rows = []
    for seed in range(args.seeds):
        for protocol in args.protocols:
            p = _settled(size, protocol, seed)
            rows.append(dict(case="deposition", protocol=protocol, seed=seed,
                             n_grains=p.n_grains, porosity=p.metadata["porosity"],
                             porosity_from_floor=p.metadata["porosity_from_floor"],
                             coordination_number=coordination_number(p),
                             steps=p.metadata["steps"], seconds=p.metadata["seconds"]))
            print(rows[-1], flush=True)
    for item in args.variants:
        variant, _, count = item.partition(":")
        if variant not in VARIANTS:
            parser.error(f"--variants: unknown variant {variant!r}; valid: {', '.join(VARIANTS)}")
        for seed in range(int(count or 1)):
            p = _settled(size, "sequential", seed, variant)
            rows.append(dict(case=f"deposition_{variant}", protocol="sequential", seed=seed,
                             n_grains=p.n_grains, porosity=p.metadata["porosity"],
                             porosity_from_floor=p.metadata["porosity_from_floor"],
                             coordination_number=coordination_number(p),
                             steps=p.metadata["steps"], seconds=p.metadata["seconds"]))
            print(rows[-1], flush=True)
    if not args.no_compaction:
        pack = _settled(size, args.protocols[0], 0)
        strain = 0.0                      # summed over the successive compactions
        for target in sorted(args.stresses):
            path = PARTS / f"compact_{args.protocols[0]}_{target:g}MPa.nc"
            if path.exists():
                pack = load_pack(path)
            else:
                t = time.perf_counter()
                pack = compact(pack, target_stress=target * 1e6, strain_step=args.strain_step)
                pack = pack.__class__(**{**pack.__dict__, "metadata": {
                    **pack.metadata, "seconds": time.perf_counter() - t}})
                save_pack(pack, path)
            md = pack.metadata
            strain += md["record"]["strain"][-1]
            rows.append(dict(case="compaction", protocol=args.protocols[0], seed=0,
                             n_grains=pack.n_grains, porosity=porosity(pack),
                             coordination_number=md["coordination_number"],
                             steps=md["compaction_steps"], seconds=md["seconds"],
                             target_stress_MPa=target, strain=strain,
                             stress_zz_MPa=md["stress_zz"] / 1e6,
                             stress_mean_MPa=md["stress_mean"] / 1e6, **_overlap_row(pack)))
            print(rows[-1], flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="md_settle_compact", size_diameters=json.dumps(size),
                              source_porosity_settled=0.412, source_porosity_compacted=0.386,
                              source_stress_MPa=30.0)
    write_csv(table, result_path("md_settle_compact", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path("md_settle_compact", "nc"))
    dep = table[table.case == "deposition"]
    print(dep.groupby("protocol")[["porosity", "porosity_from_floor", "coordination_number",
                                   "steps", "seconds"]].agg(["mean", "std"]).to_string())


if __name__ == "__main__":
    main()
