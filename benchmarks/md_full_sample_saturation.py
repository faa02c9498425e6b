"""Vp against cement saturation on the source's full MD sample (García & Medina, Sect. IV).

The compacted full sample of ``md_full_sample.py`` (8 x 8 x 32 largest diameters, 2 730 grains,
10.6 MPa; prepared there, reused from ``results/md_full_sample/``) is cemented at resolution
``--omega`` (default 6) with contact and coating cement (``--schemes``) at S_c = 0 ... 0.2, hard
cement of Table II, and P-wave pulse tests measure Vp with its eq. 11 error. 15 detector slabs
keep that error near 2 %, so the shape of Vp(S_c) -- the source finds it concave for contact
cement -- shows above it, which the small pack of the MD scene (5 slabs) cannot.

Output: ``results/md_full_sample_saturation.{csv,nc,png}``.
Run: ``python benchmarks/md_full_sample_saturation.py [--omega 6]`` (about 6 min after the pack
exists; preparing the pack takes about 30 min once).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from md_full_sample import COMPACT_OPTIONS, SETTLE_OPTIONS  # noqa: E402

NAME = "md_full_sample_saturation"
SATURATIONS = (0.0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2)


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, default=6.0)
    ap.add_argument("--schemes", nargs="+", default=["contact", "coating"])
    ap.add_argument("--saturations", type=float, nargs="+", default=list(SATURATIONS))
    ap.add_argument("--workdir", default=str(_common.RESULTS / "md_full_sample"))
    ap.add_argument("--no-plot", action="store_true")
    args = ap.parse_args(argv)
    _common.announce_source()
    t_all = time.perf_counter()
    pack = md.prepare_pack(args.workdir, settle_options=SETTLE_OPTIONS,
                           compact_options=COMPACT_OPTIONS, progress=True)
    lat = md.cement_lattice(pack, args.omega)
    rows = []
    for scheme in args.schemes:
        for sc in sorted(args.saturations):
            t0 = time.perf_counter()
            cem = md.grow_cement(lat, sc, scheme)
            system = md.acoustic_system(pack, lat, cem, md.HARD_CEMENT)
            ds = md.pulse_test(system, "p")
            rows.append(dict(scheme=scheme, saturation=sc, vp=float(ds.velocity),
                             vp_error=float(ds.velocity_error), vp_fit=float(ds.velocity_fit),
                             vp_static=float(ds.velocity_static), density=float(ds.density),
                             n_particles=system.n_particles, seconds=time.perf_counter() - t0))
            r = rows[-1]
            print(f"{scheme:8s} S_c {sc:4.2f}: Vp {r['vp']:7.1f} +- {r['vp_error']:5.1f} m/s "
                  f"(fit {r['vp_fit']:7.1f}, static {r['vp_static']:7.1f})  "
                  f"[{r['seconds']:.1f} s]", flush=True)
    frame = pd.DataFrame(rows)
    total = time.perf_counter() - t_all
    # Shape: second differences of the fitted Vp over the S_c grid (divided differences).
    shape_rows = []
    for scheme, g in frame.groupby("scheme", sort=False):
        s, v = g.saturation.to_numpy(), g.vp_fit.to_numpy()
        slope = np.diff(v) / np.diff(s)
        curv = np.diff(slope) / (0.5 * (s[2:] - s[:-2]))
        shape_rows.append((scheme, slope, curv))
        print(f"{scheme}: slopes {np.round(slope, 0)} m/s per unit S_c; second differences "
              f"{np.round(curv, 0)}")
    attrs = _common.environment_attrs(
        title="md full sample: Vp against cement saturation", benchmark=NAME,
        omega=args.omega, schemes=" ".join(args.schemes), cement="HARD_CEMENT",
        pack_grains=pack.n_grains, pack_porosity=pack.metadata["record"]["porosity"][-1],
        pack_stress_zz_Pa=pack.metadata["record"]["stress_zz"][-1], total_run_s=total,
        **_common.md_source_attrs())
    _common.write_csv(frame, _common.result_path(NAME, "csv"), attrs)
    out = xr.Dataset.from_dataframe(frame)
    out.attrs.update(attrs)
    _common.write_netcdf(out, _common.result_path(NAME, "nc"))
    print(f"total {total:.1f} s")
    if args.no_plot:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5.5, 4))
    for k, (scheme, g) in enumerate(frame.groupby("scheme", sort=False)):
        ax.errorbar(g.saturation, g.vp / 1e3, yerr=g.vp_error / 1e3, fmt="o-", color=f"C{k}",
                    capsize=3, label=f"{scheme} (pulse, eq. 11)")
        ax.plot(g.saturation, g.vp_static / 1e3, ":", color=f"C{k}", label=f"{scheme} static")
    ax.set(xlabel="cement saturation S_c", ylabel="Vp (km/s)",
           title=f"full sample, {pack.n_grains} grains, Omega = {args.omega:g}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    _common.save_figure(fig, _common.result_path(NAME, "png"))
    plt.close(fig)


if __name__ == "__main__":
    main()
