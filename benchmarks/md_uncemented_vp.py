"""Vp of the uncemented MD pack compacted to a stress, against the source's 1.7 km/s at 30 MPa.

A pack settled by sequential deposition (``--size`` largest diameters, default 6 x 6 x 16,
``fall_stiffness_factor`` 1) is compacted between frozen slabs to each of ``--stresses`` (MPa,
sigma_zz, default 10, 20, 30, 40) in turn; at each the linearised pack (no cement) gives the
long-wave P velocity of its static modulus (:func:`md.acoustic.static_modulus`) and the pulse
velocity with its eq. 11 error (:func:`md.acoustic.pulse_test`). García & Medina (Sect. IV)
report Vp = 1.7 km/s for their sample compacted to porosity 0.386 at P_c ≈ 30 MPa.

Stages are saved in ``results/md_uncemented_vp_parts/`` and reused. Output:
``benchmarks/results/md_uncemented_vp.{csv,nc}``.
Run: ``python benchmarks/md_uncemented_vp.py [--size 6 6 16] [--stresses 10 20 30 40]``
"""

from _common import RESULTS, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402

import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

from md.acoustic import acoustic_system, pulse_test, static_modulus  # noqa: E402
from md.protocols import compact, prepare_pack  # noqa: E402
from md.state import load_pack, save_pack  # noqa: E402

PARTS = RESULTS / "md_uncemented_vp_parts"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=float, nargs=3, default=(6, 6, 16))
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--stresses", type=float, nargs="+", default=(10.0, 20.0, 30.0, 40.0))
    parser.add_argument("--strain-step", type=float, default=1e-3)
    parser.add_argument("--no-pulse", action="store_true")
    args = parser.parse_args(argv)
    size = tuple(args.size)
    tag = f"{'x'.join(f'{s:g}' for s in size)}_seed{args.seed}"
    t = time.perf_counter()
    pack = prepare_pack(PARTS / tag, settle_options=dict(
        size=size, seed=args.seed, fall_stiffness_factor=1.0, kinetic_tolerance=1e-5))
    rows = [dict(stage="settle", seconds=time.perf_counter() - t)]
    strain = 0.0
    for target in sorted(args.stresses):
        path = PARTS / tag / f"compact_{target:g}MPa.nc"
        t = time.perf_counter()
        if path.exists():
            pack = load_pack(path)
        else:
            pack = compact(pack, target_stress=target * 1e6, strain_step=args.strain_step)
            save_pack(pack, path)
        md = pack.metadata
        strain += md["record"]["strain"][-1]
        system = acoustic_system(pack, rotations=False)
        static = static_modulus(system, "p")
        row = dict(stage="compact", target_stress_MPa=target, strain=strain,
                   stress_zz_MPa=md["stress_zz"] / 1e6, stress_mean_MPa=md["stress_mean"] / 1e6,
                   porosity=md["porosity"], coordination_number=md["coordination_number"],
                   n_slabs=system.slabs()[1], vp_static=static.velocity)
        if not args.no_pulse:
            ds = pulse_test(system, "p")
            row.update(vp_pulse=float(ds["velocity"]), vp_pulse_error=float(ds["velocity_error"]),
                       vp_fit=float(ds["velocity_fit"]))
        row["seconds"] = time.perf_counter() - t
        rows.append(row)
        print(row, flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="md_uncemented_vp", size_diameters=json.dumps(size),
                              seed=args.seed, source_vp_km_s=1.7, source_stress_MPa=30.0,
                              source_porosity=0.386, units_velocity="m s-1")
    write_csv(table, result_path("md_uncemented_vp", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path("md_uncemented_vp", "nc"))


if __name__ == "__main__":
    main()
