"""García & Medina's findings from an MD scene, in one figure and a table.

``--scene garcia_medina_full`` (default): the source's study at its own size (8 x 8 x 32
diameters, ``results/garcia_medina_full.nc``, made by ``rockcem run garcia_medina_full -o
benchmarks/results/garcia_medina_full.nc -j 2``; about an hour and a half, so it is never started
from here). ``--scene garcia_medina_cement``: the quick-look scene (4 x 4 x 12 diameters at
Omega 3; run here if ``results/garcia_medina_cement.nc`` is missing or with ``--rerun``).

The figure draws Vp against cement saturation S_c for the loose and the compacted sample, hard
and soft cement (Table II), each cementation scheme with its eq. 11 error bars and, where the
scene has a resolution check, a band of the eq. 11 and resolution errors in quadrature and the
velocities at the coarser resolution (open markers); beside them the contact cement theory of
App. A (``rockcem.granular.contact_cement``, scheme 1: cement at the contacts, scheme 2: as a
coating) for the sample's porosity and coordination number.

The table checks the source's findings (Sect. IV, Figs. 8-12): the order contact > coating >
pore body at every S_c > 0 (and whether the gaps exceed the errors), the concavity of the
contact-cement Vp(S_c) (second divided differences), and Vp(S_c = 0.1) / Vp(0) against the
source's x10 (loose, hard), x7 (loose, soft), +25 % (compacted, hard) and +12 % (compacted, soft).

Usage: ``python benchmarks/md_cement_findings.py [--scene NAME] [--rerun]``. Writes
``results/md_cement_findings[_full].{png,csv,nc}`` and ``..._checks.csv``.
"""

from __future__ import annotations

import _common  # (first: threads, sys.path)

import argparse
import json

import numpy as np
from _common import (RESULTS, environment_attrs, result_path, save_figure, write_csv,
                     write_netcdf)


def theory(ds, sample, cement, scheme):
    """CCT Vp (km/s) of the sample at the scene's saturations (quartz grains of Table I)."""
    from md.cement import HARD_CEMENT, SOFT_CEMENT

    c = {"hard": HARD_CEMENT, "soft": SOFT_CEMENT}[cement]
    return _common.cct_vp(float(ds.porosity_uncemented.sel(sample=sample)),
                          float(ds.coordination_number.sel(sample=sample)), c,
                          ds.saturation.values, scheme)


#: Vp(S_c = 0.1) / Vp(0) of contact cement in the source (Sect. IV): (sample, cement) -> ratio.
SOURCE_RATIO = {("loose", "hard"): 10.0, ("loose", "soft"): 7.0,
                ("compacted", "hard"): 1.25, ("compacted", "soft"): 1.12}
COLOURS = {"contact": "C3", "coating": "C0", "pore_body": "C2", "pendular": "C1"}


def total_error(ds):
    """Eq. 11 and resolution errors in quadrature (km/s): :func:`md.calibrate.total_error`."""
    from md.calibrate import total_error as combined

    return combined(ds, "vp")


def checks(ds):
    """The source's findings, one row per (sample, cement, finding)."""
    err = total_error(ds)
    rows = []
    schemes = [s for s in ("contact", "coating", "pore_body") if s in ds.scheme.values]
    for sample in ds.sample.values:
        for cement in ds.cement.values:
            sel = dict(sample=sample, cement=cement)
            v, e = ds.vp.sel(**sel), err.sel(**sel)
            pos = ds.saturation.values[ds.saturation.values > 0]
            if len(schemes) == 3:
                a, b, c = (v.sel(scheme=k, saturation=pos) for k in schemes)
                ea, eb, ec = (e.sel(scheme=k, saturation=pos) for k in schemes)
                order = bool(np.all((a > b) & (b > c)))
                beyond = bool(np.all((a - b > np.hypot(ea, eb)) & (b - c > np.hypot(eb, ec))))
                rows.append(dict(sample=sample, cement=cement,
                                 finding="contact > coating > pore body at every S_c > 0",
                                 md=f"{order}", beyond_errors=f"{beyond}", source="True"))
            if "contact" in ds.scheme.values:
                vc = v.sel(scheme="contact").values
                sc = ds.saturation.values
                slope = np.diff(vc) / np.diff(sc)
                curv = np.diff(slope) / (0.5 * (sc[2:] - sc[:-2]))
                rows.append(dict(sample=sample, cement=cement,
                                 finding="contact Vp(S_c) concave (all second differences < 0)",
                                 md=f"{bool(np.all(curv < 0))}" if curv.size else "n/a",
                                 beyond_errors="", source="True"))
                if 0.1 in sc and 0.0 in sc:
                    r = float(v.sel(scheme="contact", saturation=0.1)
                              / v.sel(scheme="contact", saturation=0.0))
                    rel = float(np.hypot(e.sel(scheme="contact", saturation=0.1)
                                         / v.sel(scheme="contact", saturation=0.1),
                                         e.sel(scheme="contact", saturation=0.0)
                                         / v.sel(scheme="contact", saturation=0.0)))
                    rows.append(dict(sample=sample, cement=cement,
                                     finding="contact Vp(0.1) / Vp(0)",
                                     md=f"{r:.2f} +- {r * rel:.2f}", beyond_errors="",
                                     source=f"{SOURCE_RATIO.get((str(sample), str(cement)))}"))
    return rows


def main(argv=None):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd
    import xarray as xr

    from md.experiment import md_scene_from_dict, run_md_scene
    from rockcem.scene import read_scene_toml

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="garcia_medina_full",
                    choices=["garcia_medina_full", "garcia_medina_cement"])
    ap.add_argument("--rerun", action="store_true",
                    help="run the quick-look scene even if its file exists")
    args = ap.parse_args(argv)
    path = RESULTS / f"{args.scene}.nc"
    tag = "full" if args.scene == "garcia_medina_full" else ""
    if args.scene == "garcia_medina_full" and not path.exists():
        raise SystemExit(f"md_cement_findings: no {path}; make it with `rockcem run "
                         f"garcia_medina_full -o {path} -j 2` (about an hour and a half)")
    if args.scene == "garcia_medina_cement" and (args.rerun or not path.exists()):
        scene = md_scene_from_dict(read_scene_toml(args.scene)[0])
        ds = run_md_scene(scene, workdir=RESULTS / f"{args.scene}_work", progress=True)
        write_netcdf(ds, path)
    ds = xr.load_dataset(path)
    err_total = total_error(ds)
    colours = COLOURS
    # One y-scale for the four panels: the samples and cements compare at a glance.
    fig, axes = plt.subplots(2, 2, figsize=(10, 8), sharex=True, sharey=True,
                             constrained_layout=True)
    rows = []
    for i, sample in enumerate(ds.sample.values):
        for j, cement in enumerate(ds.cement.values):
            ax = axes[i, j]
            for scheme in ds.scheme.values:
                v = ds.vp.sel(sample=sample, cement=cement, scheme=scheme)
                e = ds.vp_error.sel(sample=sample, cement=cement, scheme=scheme)
                ax.errorbar(ds.saturation, v, e, marker="o", ms=4, capsize=2,
                            color=colours[str(scheme)], label=f"MD {scheme.replace('_', '-')}")
                if "vp_error_resolution" in ds:
                    et = err_total.sel(sample=sample, cement=cement, scheme=scheme)
                    ax.fill_between(ds.saturation, v - et, v + et, color=colours[str(scheme)],
                                    alpha=0.15, lw=0)
                    ax.plot(ds.saturation, ds.vp_resolution_check.sel(
                        sample=sample, cement=cement, scheme=scheme), "o", mfc="none", ms=5,
                        color=colours[str(scheme)], alpha=0.7)
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
    md_keys = json.loads(ds.attrs["scene_json"])["md"]
    size = " x ".join(f"{x:g}" for x in md_keys["size"])
    note = (f"; open markers: Omega = {md_keys.get('resolution_check', 0):g}, band: eq. 11 and "
            "resolution error" if "vp_error_resolution" in ds else "")
    fig.suptitle("MD pulse tests: cement location and stiffness (García & Medina, Figs. 8-12)\n"
                 f"{args.scene}: {size} diameters, Omega = {float(ds.attrs['resolution']):g}, "
                 f"{ds.attrs['interface']} interface{note}", fontsize=10)
    save_figure(fig, result_path("md_cement_findings", "png", tag))
    table = pd.DataFrame(rows)
    attrs = environment_attrs(scene=args.scene)
    out = xr.Dataset.from_dataframe(table.set_index(["sample", "cement", "scheme"]))
    out.attrs.update({k: str(v) for k, v in attrs.items()})
    write_netcdf(out, result_path("md_cement_findings", "nc", tag))
    write_csv(table, result_path("md_cement_findings", "csv", tag), attrs)
    print(table.to_string(index=False, float_format=lambda x: f"{x:.3g}"))
    found = pd.DataFrame(checks(ds))
    write_csv(found, result_path("md_cement_findings_checks", "csv", tag), attrs)
    print("\n| sample | cement | finding | MD | beyond the errors | source |\n"
          "|---|---|---|---|---|---|")
    for r in found.itertuples():
        print(f"| {r.sample} | {r.cement} | {r.finding} | {r.md} | {r.beyond_errors} | "
              f"{r.source} |")


if __name__ == "__main__":
    main()
