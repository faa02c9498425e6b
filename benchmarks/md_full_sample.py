"""The source's full MD sample: wall time and memory of every stage, and Vp against the lattice
resolution Omega for both grain-cement interface rules (issue 12, item 3).

García & Medina's sample: 8 x 8 x 32 largest grain diameters of quartz (Table I), settled
sequentially (accelerated deposition, fall stiffness factor 1e-3) and compacted between frozen
slabs to 30 MPa — the pack of the shipped scene ``garcia_medina_full`` (``--pack-dir``, default
``results/garcia_medina_full_work/pack``; made there and resumed, ``md.prepare_pack``). Cement of
``--schemes`` (default ``pendular`` and the source's ``contact``) grown to S_c = 0.1
(``--saturation``; hard cement of Table II) on lattices of cell width R/Omega; linearised with
each ``--interfaces`` rule (``patch``, the default of the engine, and the source's per-cell
``paper``); static long-wave P modulus (CG) and P-wave pulse test. Each stage is timed once and
the peak resident memory read from ``ru_maxrss`` after it.

Per scheme and interface: static and pulse Vp at each Omega with the wall time from lattice to
pulse test; the Richardson limit and order through the three finest Omega (where the changes
shrink with one sign), the two-point limits of the two finest Omega at orders 1 and 1.6 (the
orders measured on the small pack, ``md_omega_convergence.py``), and the smallest Omega whose Vp
is within 1 % of the limit (none where no limit exists or none is that close).

Output: ``results/md_full_sample[_<tag>].{csv,nc}`` (one row per stage, scheme, interface and
Omega) and ``results/md_full_sample_limits[_<tag>].csv``.
Run: ``python benchmarks/md_full_sample.py [--omega 4 6 8 10] [--schemes pendular contact]
[--interfaces patch paper]`` (about half an hour on one core with the pack made).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from md_omega_convergence import richardson  # noqa: E402

NAME = "md_full_sample"
# The pack of the scene garcia_medina_full (its settle and compaction options).
SETTLE_OPTIONS = dict(size=(8.0, 8.0, 32.0), radius_range=(1.8e-4, 2.0e-4), seed=0,
                      fall_stiffness_factor=1e-3)
COMPACT_OPTIONS = dict(target_stress=30e6)


def rss_bytes():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def limits(omega, v):
    """Richardson limit and order (three finest), two-point limits at orders 1 and 1.6 (two
    finest), and the smallest Omega within 1 % of the three-point limit (NaN if none)."""
    o, v = np.asarray(omega, float), np.asarray(v, float)
    lim, order = richardson(o, v)
    two = {}
    for q in (1.0, 1.6):
        two[q] = (float(v[-1] + (v[-1] - v[-2]) / ((o[-1] / o[-2]) ** q - 1.0))
                  if len(o) >= 2 else np.nan)
    ok = o[np.abs(v / lim - 1.0) <= 0.01] if np.isfinite(lim) else []
    return dict(limit=lim, order=order, limit_order1=two[1.0], limit_order16=two[1.6],
                omega_within_1pc=float(ok.min()) if len(ok) else np.nan)


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[4.0, 6.0, 8.0, 10.0],
                    help="resolutions R/c_w (default 4 6 8 10)")
    ap.add_argument("--saturation", type=float, default=0.1)
    ap.add_argument("--schemes", nargs="+", default=["pendular", "contact"])
    ap.add_argument("--interfaces", nargs="+", default=["patch", "paper"])
    ap.add_argument("--pack-dir", default=str(_common.RESULTS / "garcia_medina_full_work" / "pack"))
    ap.add_argument("--tag", default="")
    args = ap.parse_args(argv)
    _common.announce_source()
    rows = []

    def stage(name, fn, omega=np.nan, scheme="", interface="", **sizes):
        t0 = time.perf_counter()
        out = fn()
        rows.append(dict(stage=name, scheme=scheme, interface=interface, omega=omega,
                         seconds=time.perf_counter() - t0, peak_rss_bytes=rss_bytes(),
                         **{k: (v(out) if callable(v) else v) for k, v in sizes.items()}))
        r = rows[-1]
        print(f"{name:>8s} {scheme:>9s} {interface:>5s} (Omega {omega:g}): "
              f"{r['seconds']:8.1f} s, peak RSS {r['peak_rss_bytes'] / 1e9:.2f} GB "
              + " ".join(f"{k}={r[k]}" for k in sizes), flush=True)
        return out

    t_all = time.perf_counter()
    pack = stage("pack", lambda: md.prepare_pack(args.pack_dir, settle_options=SETTLE_OPTIONS,
                                                 compact_options=COMPACT_OPTIONS, progress=True),
                 n_grains=lambda p: p.n_grains)
    rec = pack.metadata["record"]
    summary = []
    for omega in sorted(args.omega):
        t_lat = time.perf_counter()
        lat = stage("lattice", lambda: md.cement_lattice(pack, omega), omega,
                    pore_cells=lambda lt: int(lt.index.size),
                    lattice_cells=lambda lt: int(np.prod(lt.shape)))
        lattice_s = time.perf_counter() - t_lat
        for scheme in args.schemes:
            t_grow = time.perf_counter()
            cem = stage("grow", lambda: md.grow_cement(lat, args.saturation, scheme), omega,
                        scheme, cement_cells=lambda c: int(c.sum()))
            grow_s = time.perf_counter() - t_grow
            for interface in args.interfaces:
                t0 = time.perf_counter()
                system = stage("system", lambda: md.acoustic_system(
                    pack, lat, cem, md.HARD_CEMENT, interface=interface, rotations=False),
                    omega, scheme, interface, n_particles=lambda s: s.n_particles,
                    lattice_bonds=lambda s: s.n_lattice_bonds,
                    contact_bonds=lambda s: int(s.bond_i.size))
                static = stage("static", lambda: md.static_modulus(system, "p"), omega, scheme,
                               interface, cg_iterations=lambda s: int(s.iterations))
                ds = stage("pulse", lambda: md.pulse_test(system, "p"), omega, scheme,
                           interface, steps=lambda d: int(d.sizes["time"]),
                           n_slabs=lambda d: int(d.sizes["slab"]),
                           vp=lambda d: float(d.velocity),
                           vp_error=lambda d: float(d.velocity_error))
                seconds = time.perf_counter() - t0 + lattice_s + grow_s
                summary.append(dict(scheme=scheme, interface=interface, omega=omega,
                                    seconds=seconds, vp=float(ds.velocity),
                                    vp_error=float(ds.velocity_error),
                                    vp_fit=float(ds.velocity_fit),
                                    vp_static=float(ds.velocity_static),
                                    modulus_static_GPa=float(static.modulus) / 1e9))
                r = summary[-1]
                print(f"{scheme} / {interface}, Omega {omega:g}: Vp {r['vp']:.1f} +- "
                      f"{r['vp_error']:.1f} m/s, static {r['vp_static']:.1f} m/s, "
                      f"{seconds:.1f} s", flush=True)
    total = time.perf_counter() - t_all
    table = pd.DataFrame(summary)
    lim_rows = []
    for (scheme, interface), g in table.groupby(["scheme", "interface"], sort=False):
        g = g.sort_values("omega")
        for quantity in ("vp", "vp_static"):
            lim_rows.append(dict(scheme=scheme, interface=interface, quantity=quantity,
                                 **limits(g.omega, g[quantity])))
    lim = pd.DataFrame(lim_rows)
    print("\n| scheme | interface | Omega | wall s | Vp pulse (m/s) | +- eq. 11 | Vp static |"
          "\n|---|---|---:|---:|---:|---:|---:|")
    for r in summary:
        print(f"| {r['scheme']} | {r['interface']} | {r['omega']:g} | {r['seconds']:.0f} | "
              f"{r['vp']:.0f} | {r['vp_error']:.0f} | {r['vp_static']:.0f} |")
    print("\n| scheme | interface | quantity | Richardson limit | order | limit (order 1) | "
          "limit (order 1.6) | Omega within 1 % |\n|---|---|---|---:|---:|---:|---:|---:|")
    for r in lim_rows:
        print(f"| {r['scheme']} | {r['interface']} | {r['quantity']} | {r['limit']:.0f} | "
              f"{r['order']:.2f} | {r['limit_order1']:.0f} | {r['limit_order16']:.0f} | "
              f"{r['omega_within_1pc']:g} |")
    attrs = _common.environment_attrs(
        title="md full sample (8 x 8 x 32 diameters): stage wall times and Vp against Omega",
        benchmark=NAME, omegas=" ".join(f"{o:g}" for o in sorted(args.omega)),
        saturation=args.saturation, schemes=" ".join(args.schemes),
        interfaces=" ".join(args.interfaces), cement="HARD_CEMENT",
        pack_porosity=rec["porosity"][-1], pack_stress_zz_Pa=rec["stress_zz"][-1],
        total_run_s=total, note="the pack stage is near zero when resumed from its folder",
        **_common.md_source_attrs())
    frame = pd.concat([pd.DataFrame(rows), table.assign(stage="summary")], ignore_index=True)
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    _common.write_csv(lim, _common.result_path(NAME + "_limits", "csv", args.tag), attrs)
    out = xr.Dataset.from_dataframe(frame)
    out.attrs.update(attrs)
    _common.write_netcdf(out, _common.result_path(NAME, "nc", args.tag))


if __name__ == "__main__":
    main()
