"""The source's full MD sample at resolution Omega = 10: wall time and memory of every stage.

García & Medina's sample: 8 x 8 x 32 largest grain diameters of quartz (Table I), settled
(accelerated deposition, fall stiffness factor 1e-3, as ``md_settle_compact.py``) and compacted
between frozen slabs to 10 MPa; cut into a cement lattice of cell width R/10; contact cement
grown to S_c = 0.1 (``--saturation``; hard cement of Table II); linearised; P-wave pulse test
with its static cross-check. Each stage is timed once (they are long) and the peak resident
memory is read from ``ru_maxrss`` after it. The pack stages are saved in
``results/md_full_sample/`` and resumed (``md.prepare_pack``), so a rerun skips the settling
(about 20-40 min on one core) and measures the rest; ``--stage-times`` of a settled run are
kept in the CSV of that run only.

With several ``--omega`` values the lattice-to-pulse stages run at each resolution, and Vp is
reported against the finest one with the wall time: the error-against-run-time study of the
knob Omega on the full sample (15 detector slabs, so the eq. 11 error is a few per cent).

Output: ``results/md_full_sample[_<tag>].{csv,nc}`` (one row per stage and Omega: seconds, peak
RSS, sizes, Vp) and the pulse-test Dataset of the finest Omega
``results/md_full_sample_pulse.nc``.
Run: ``python benchmarks/md_full_sample.py [--omega 4 6 8 10] [--saturation 0.1]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_full_sample"
SETTLE_OPTIONS = dict(size=(8, 8, 32), fall_stiffness_factor=1e-3, seed=0, kinetic_tolerance=1e-5)
COMPACT_OPTIONS = dict(target_stress=10e6, strain_step=1e-3)


def rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[10.0],
                    help="resolutions R/c_w, run in increasing order (default 10)")
    ap.add_argument("--saturation", type=float, default=0.1)
    ap.add_argument("--scheme", default="contact")
    ap.add_argument("--workdir", default=str(_common.RESULTS / "md_full_sample"))
    ap.add_argument("--tag", default="")
    args = ap.parse_args(argv)
    _common.announce_source()
    rows = []

    def stage(name, fn, omega=np.nan, **sizes):
        t0 = time.perf_counter()
        out = fn()
        rows.append(dict(stage=name, omega=omega, seconds=time.perf_counter() - t0,
                         peak_rss_bytes=rss_bytes(),
                         **{k: (v(out) if callable(v) else v) for k, v in sizes.items()}))
        r = rows[-1]
        print(f"{name:>10s} (Omega {omega:g}): {r['seconds']:9.1f} s, peak RSS "
              f"{r['peak_rss_bytes'] / 1e9:.2f} GB "
              + " ".join(f"{k}={r[k]}" for k in sizes), flush=True)
        return out

    t_all = time.perf_counter()
    pack = stage("pack", lambda: md.prepare_pack(args.workdir, settle_options=SETTLE_OPTIONS,
                                                 compact_options=COMPACT_OPTIONS, progress=True),
                 n_grains=lambda p: p.n_grains)
    rec = pack.metadata["record"]
    results = {}
    for omega in sorted(args.omega):
        t_omega = time.perf_counter()
        lat = stage("lattice", lambda: md.cement_lattice(pack, omega), omega,
                    pore_cells=lambda lt: int(lt.index.size),
                    lattice_cells=lambda lt: int(np.prod(lt.shape)))
        cem = stage("grow", lambda: md.grow_cement(lat, args.saturation, args.scheme), omega,
                    cement_cells=lambda c: int(c.sum()))
        system = stage("system", lambda: md.acoustic_system(pack, lat, cem, md.HARD_CEMENT),
                       omega, n_particles=lambda s: s.n_particles,
                       lattice_bonds=lambda s: s.n_lattice_bonds,
                       contact_bonds=lambda s: int(s.bond_i.size))
        stage("static", lambda: md.static_modulus(system, "p"), omega,
              cg_iterations=lambda s: int(s.iterations))
        ds = stage("pulse", lambda: md.pulse_test(system, "p", progress=True), omega,
                   steps=lambda d: int(d.sizes["time"]), n_slabs=lambda d: int(d.sizes["slab"]),
                   vp=lambda d: float(d.velocity), vp_error=lambda d: float(d.velocity_error),
                   vp_fit=lambda d: float(d.velocity_fit),
                   vp_static=lambda d: float(d.velocity_static))
        results[omega] = (ds, time.perf_counter() - t_omega)
        print(f"Omega {omega:g}: Vp {float(ds.velocity):.1f} +- {float(ds.velocity_error):.1f}"
              f" m/s (fit {float(ds.velocity_fit):.1f}, static "
              f"{float(ds.velocity_static):.1f}); {results[omega][1]:.1f} s for lattice to "
              "pulse", flush=True)
    total = time.perf_counter() - t_all
    finest = max(results)
    ds = results[finest][0]
    vp, err = float(ds.velocity), float(ds.velocity_error)
    for omega, (d, seconds) in sorted(results.items()):
        rows.append(dict(stage="omega_summary", omega=omega, seconds=seconds,
                         vp=float(d.velocity), vp_error=float(d.velocity_error),
                         vp_fit=float(d.velocity_fit), vp_static=float(d.velocity_static),
                         vp_rel_diff_to_finest=float(d.velocity) / vp - 1.0,
                         vp_fit_rel_diff_to_finest=float(d.velocity_fit)
                         / float(ds.velocity_fit) - 1.0,
                         vp_static_rel_diff_to_finest=float(d.velocity_static)
                         / float(ds.velocity_static) - 1.0))
    print("\n| Omega | s (lattice to pulse) | Vp (m/s) | +- eq. 11 | fit | static | "
          "fit vs finest |\n|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        if r["stage"] == "omega_summary":
            print(f"| {r['omega']:g} | {r['seconds']:.1f} | {r['vp']:.1f} | {r['vp_error']:.1f}"
                  f" | {r['vp_fit']:.1f} | {r['vp_static']:.1f} | "
                  f"{r['vp_fit_rel_diff_to_finest']:+.4f} |")
    frame = pd.DataFrame(rows)
    attrs = _common.environment_attrs(
        title="md full sample (8 x 8 x 32 diameters): stage wall times and Vp against Omega",
        benchmark=NAME, omegas=" ".join(f"{o:g}" for o in sorted(args.omega)),
        finest_omega=finest, saturation=args.saturation, scheme=args.scheme,
        cement="HARD_CEMENT", pack_porosity=rec["porosity"][-1],
        pack_stress_zz_Pa=rec["stress_zz"][-1], vp_m_s=vp, vp_error_m_s=err,
        vp_fit_m_s=float(ds.velocity_fit), vp_static_m_s=float(ds.velocity_static),
        time_step_s=float(ds.attrs["time_step_s"]), total_run_s=total,
        note="the pack stage is near zero when resumed from results/md_full_sample/",
        **_common.md_source_attrs())
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    out = xr.Dataset.from_dataframe(frame)
    out.attrs.update(attrs)
    _common.write_netcdf(out, _common.result_path(NAME, "nc", args.tag))
    ds.attrs.update({k: (str(v) if isinstance(v, (tuple, list)) else v)
                     for k, v in ds.attrs.items()})
    _common.write_netcdf(ds, _common.result_path(NAME + "_pulse", "nc", args.tag))


if __name__ == "__main__":
    main()
