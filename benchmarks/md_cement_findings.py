"""García & Medina's findings from the MD scene ``garcia_medina_cement``, in one figure.

Runs the shipped MD scene (or reuses ``results/garcia_medina_cement.nc``; its stage files live in
``results/garcia_medina_cement_work/`` and make a rerun resume) and draws Vp against cement
saturation S_c for the loose and the compacted sample, hard and soft cement (Table II), the
three cementation schemes with their eq. 11 error bars, and beside them the contact cement
theory of App. A (``rockcem.granular.contact_cement``, scheme 1: cement at the contacts, scheme
2: cement as a coating) for the sample's porosity and coordination number.

Usage: ``python benchmarks/md_cement_findings.py [--rerun]``. Writes
``results/md_cement_findings.png`` and a CSV/netCDF of the velocities with the ratios the paper
quotes (Vp at S_c = 0.1 over Vp at S_c = 0).
"""

from __future__ import annotations

import _common  # noqa: F401  (first: threads, sys.path)

import argparse

import numpy as np
from _common import (RESULTS, environment_attrs, result_path, save_figure, write_csv,
                     write_netcdf)


def theory(ds, sample, cement, scheme):
    """CCT Vp (km/s) of the sample at the scene's saturations (quartz grains of Table I)."""
    from md.cement import HARD_CEMENT, SOFT_CEMENT
    from md.contact import QUARTZ
    from rockcem.granular import contact_cement

    c = {"hard": HARD_CEMENT, "soft": SOFT_CEMENT}[cement]
    G0, K0 = QUARTZ.shear_modulus / 1e9, QUARTZ.bulk_modulus / 1e9
    Gc = c.shear_modulus / 1e9
    Kc = c.p_modulus / 1e9 - 4 / 3 * Gc
    phi0 = float(ds.porosity_uncemented.sel(sample=sample))
    n = float(ds.coordination_number.sel(sample=sample))
    phi = phi0 * (1 - ds.saturation.values)
    m = contact_cement(K0, G0, Kc, Gc, phi, phi0, n, scheme=scheme)
    rho = (1 - phi0) * 2.65 + (phi0 - phi) * c.density / 1e3
    return np.sqrt((m.K + 4 / 3 * m.G) / rho)


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd
    import xarray as xr

    from md.experiment import md_scene_from_dict, run_md_scene
    from rockcem.scene import read_scene_toml

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rerun", action="store_true", help="run the scene even if its file exists")
    args = ap.parse_args(argv)
    path = RESULTS / "garcia_medina_cement.nc"
    if args.rerun or not path.exists():
        scene = md_scene_from_dict(read_scene_toml("garcia_medina_cement")[0])
        ds = run_md_scene(scene, workdir=RESULTS / "garcia_medina_cement_work", progress=True)
        write_netcdf(ds, path)
    ds = xr.load_dataset(path)
    colours = {"contact": "C3", "coating": "C0", "pore_body": "C2"}
    fig, axes = plt.subplots(2, 2, figsize=(10, 8), sharex=True, constrained_layout=True)
    rows = []
    for i, sample in enumerate(ds.sample.values):
        for j, cement in enumerate(ds.cement.values):
            ax = axes[i, j]
            for scheme in ds.scheme.values:
                v = ds.vp.sel(sample=sample, cement=cement, scheme=scheme)
                e = ds.vp_error.sel(sample=sample, cement=cement, scheme=scheme)
                ax.errorbar(ds.saturation, v, e, marker="o", ms=4, capsize=2,
                            color=colours[str(scheme)], label=f"MD {scheme.replace('_', '-')}")
                ratio = float(v.sel(saturation=0.1) / v.sel(saturation=0.0))
                rows.append({"sample": sample, "cement": cement, "scheme": scheme,
                             "vp_0": float(v.sel(saturation=0.0)),
                             "vp_0.1": float(v.sel(saturation=0.1)), "ratio_0.1": ratio})
            s = ds.saturation.values
            ax.plot(s[s > 0], theory(ds, sample, cement, 1)[s > 0], "k-", lw=1,
                    label="CCT, cement at contacts")
            ax.plot(s[s > 0], theory(ds, sample, cement, 2)[s > 0], "k--", lw=1,
                    label="CCT, coating cement")
            phi0 = float(ds.porosity_uncemented.sel(sample=sample))
            ax.set_title(f"{sample} (phi0 = {phi0:.3f}, "
                         f"Z = {float(ds.coordination_number.sel(sample=sample)):.2f}), "
                         f"{cement} cement")
            ax.set_ylabel("Vp (km/s)")
            ax.grid(alpha=0.3)
    for ax in axes[-1]:
        ax.set_xlabel("cement saturation S_c")
    axes[0, 0].legend(fontsize=8)
    fig.suptitle("MD pulse tests: cement location and stiffness (García & Medina, Figs. 8-12)")
    save_figure(fig, result_path("md_cement_findings", "png"))
    table = pd.DataFrame(rows)
    attrs = environment_attrs()
    out = xr.Dataset.from_dataframe(table.set_index(["sample", "cement", "scheme"]))
    out.attrs.update({k: str(v) for k, v in attrs.items()})
    write_netcdf(out, result_path("md_cement_findings", "nc"))
    write_csv(table, result_path("md_cement_findings", "csv"), attrs)
    print(table.to_string(index=False, float_format=lambda x: f"{x:.3g}"))


if __name__ == "__main__":
    main()
