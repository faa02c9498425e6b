"""MD calibration (issue 7): effective-medium parameters fitted to the MD pulse tests and to the
measured sandstones of Xu 2023 Table 1; the sandstone burial scene with calibrated parameters.

MD (``results/garcia_medina_cement.nc`` of the shipped scene ``garcia_medina_cement``; run here if
missing or with ``--rerun``, its stage files in ``results/garcia_medina_cement_work/``): for
each sample (loose, compacted), cement (hard, soft of Table II) and cementation scheme, Vp(S_c)
is fitted with :func:`md.calibrate.calibrate` on the eq. 11 errors as weights (``vp_error``,
scaled by the residual variance). Grain: quartz of Table I; critical porosity: the sample's
uncemented porosity; the held coordination number: the sample's. The contact-cement radius is
paired with the MD scheme: scheme 1 (cement at contacts) for ``contact``, scheme 2 (coating) for
``coating`` and for ``pore_body`` (no contact-cement scheme places cement away from contacts;
coating is the softer of the two). Variants (column ``variant``):

- ``CCT``: contact cement theory as predicted, nothing fitted (the misfit at the start of the
  ``CCT eta`` fit, whose start is eta = 1);
- ``CCT eta``: CCT with the cement efficiency eta free (the fraction of the cement the theory
  sees as contact cement);
- ``CCT n``: CCT with the coordination number free;
- ``MCCT``: the contact thickness epsilon free (Han & Guo eq. 7), n held;
- ``patchy``: the dry patchy-cement frame (Model 4 of Carcione et al. 2022) at the sample's
  stress, n and the contact-cement limit phi_p0 free, delta held at 0 (no bonding pre-stress
  in the MD), f = 1. Points without cement enter this fit (Hertz-Mindlin); CCT fits leave them
  out.

Xu 2023 Table 1 (``datasets/measurements/xu2023_table1.csv``): quartz grains and
epoxy-kaolinite cement, critical porosity 0.4, n = 8.5 held, CCT scheme 1 and 2: ``CCT``
(epsilon = 0), ``MCCT 0.04`` (epsilon = 0.04, inside the 0-0.05 Xu measures; the value of
tests/rockcem/test_xu2023.py) and ``MCCT fit`` (epsilon free), by the same
:func:`md.calibrate.calibrate` on relative residuals of Vp and Vs (it reproduces
:func:`rockcem.calibrate.fit_contact_cement`).

Sandstone: the shipped scenes ``carcione2022_sandstone`` and ``carcione2022_sandstone_calibrated``
(the latter's patchy-cement parameters from ``datasets/calibrations/garcia_medina_compacted_patchy
.toml``, the ``patchy`` fit of the compacted sample with hard contact cement; ``--ship`` rewrites
that file from this run).

Output: ``results/md_calibration.{csv,nc,png}``; the table on stdout (markdown). Run:
``python benchmarks/md_calibration.py`` (about a minute with the MD results cached);
``--quick``: compacted sample and hard cement only, and a coarser sandstone scene (about 15 s).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

PAIR = {"contact": 1, "coating": 2, "pore_body": 2}
SHIPPED = "garcia_medina_compacted_patchy"
SHIP_SELECTION = {"sample": "compacted", "cement": "hard", "scheme": "contact"}
MD_VARIANTS = {
    "CCT eta": ("contact_cement", {"cement_efficiency": (1.0, 1e-3, 1.0)}),
    "CCT n": ("contact_cement", ["coordination_number"]),
    "MCCT": ("contact_cement", ["thickness"]),
    "patchy": ("patchy_cement", ["coordination_number", "contact_cement_limit"]),
}
PARAMS = ["coordination_number", "cement_efficiency", "thickness", "contact_cement_limit",
          "delta"]


def md_results(rerun):
    import xarray as xr

    path = _common.RESULTS / "garcia_medina_cement.nc"
    if rerun or not path.exists():
        from md.experiment import md_scene_from_dict, run_md_scene
        from rockcem.scene import read_scene_toml

        scene = md_scene_from_dict(read_scene_toml("garcia_medina_cement")[0])
        ds = run_md_scene(scene, workdir=_common.RESULTS / "garcia_medina_cement_work",
                          progress=True)
        _common.write_netcdf(ds, path)
    return xr.load_dataset(path)


def rows_of(fit, data, variant, obs, extra):
    """One table row per fit of a calibrate() Dataset."""
    rows = []
    each = [d for d in fit.value.dims if d != "parameter"]
    for idx in np.ndindex(*[fit.sizes[d] for d in each]):
        one = fit.isel(dict(zip(each, idx)))
        row = {"data": data, **{d: str(one[d].values) for d in each}, "variant": variant,
               **extra, "cct_scheme": int(fit.attrs["scheme"]),
               "free": fit.attrs["free_parameters"]}
        for p in PARAMS:
            if p in one.parameter.values:
                row[p] = float(one.value.sel(parameter=p))
                fitted = bool(one.fitted.sel(parameter=p))
                row[f"{p}_err"] = float(one.stderr.sel(parameter=p)) if fitted else np.nan
        initial = variant == "CCT"
        for k in obs:
            key = "misfit_initial" if initial else "misfit"
            row[f"misfit_{k}"] = float(one[key].sel(observed=k))
        if initial:                       # the prediction of CCT: eta = 1, nothing fitted
            row.update(cement_efficiency=1.0, cement_efficiency_err=np.nan, free="")
        row["reduced_chi2"] = np.nan if initial else float(one.chi2 / one.dof)
        row["at_bound"] = "" if initial else " ".join(
            str(p) for p in one.parameter.values if bool(one.at_bound.sel(parameter=p)))
        row["success"] = bool(one.success)
        rows.append(row)
    return rows


def fit_md(ds, quick):
    """All MD variants; returns table rows and {variant: fit Dataset over sample, cement,
    scheme}."""
    import xarray as xr

    from md.calibrate import calibrate
    from rockcem.materials import mineral

    grain = mineral("quartz_garcia_medina")
    samples = ["compacted"] if quick else list(ds.sample.values)
    cements = ["hard"] if quick else list(ds.cement.values)
    rows, fits, parts = [], {}, {}
    for variant, (model, free) in MD_VARIANTS.items():
        for cement in cements:
            for scheme in ds.scheme.values:
                sub = ds.sel(sample=samples, cement=[cement], scheme=[scheme])
                fit = calibrate(sub, model, free=free, grain=grain,
                                cement=mineral(f"{cement}_cement"), scheme=PAIR[str(scheme)])
                parts[(variant, cement, str(scheme))] = fit
                if variant == "CCT eta":
                    rows += rows_of(fit, "MD", "CCT", ["vp"], {})
                rows += rows_of(fit, "MD", variant, ["vp"], {})
        fits[variant] = xr.merge(
            [f[["vp_model", "misfit"]] for (v, *_), f in parts.items() if v == variant],
            compat="no_conflicts", join="outer", combine_attrs="drop")
    return rows, fits, parts


def fit_xu():
    """Xu 2023 Table 1 against CCT, MCCT (epsilon = 0.04) and the calibrated MCCT; returns the
    data, table rows and {(variant, scheme): {"vp": ..., "vs": ...}} predictions."""
    import xarray as xr

    from md.calibrate import calibrate
    from rockcem._data import data_path
    from rockcem.elastic import velocities
    from rockcem.granular import contact_cement
    from rockcem.materials import mineral

    t = pd.read_csv(data_path("measurements", "xu2023_table1.csv"), comment="#")
    data = xr.Dataset(
        {"vp": ("sample", t.vp.values / 1000, {"units": "km s-1"}),
         "vs": ("sample", t.vs.values / 1000, {"units": "km s-1"}),
         "porosity": ("sample", t.porosity.values), "density": ("sample", t.density.values)},
        coords={"sample": t["sample"].values},
        attrs={"title": "Xu 2023, Table 1 (ten artificial sandstones)",
               "critical_porosity": 0.4})
    grain, cement = mineral("quartz_han_guo"), mineral("epoxy_kaolinite")
    rows, preds = [], {}
    for scheme in (1, 2):
        for variant, eps in (("CCT", 0.0), ("MCCT 0.04", 0.04)):
            m = contact_cement(grain.K, grain.G, cement.K, cement.G, data.porosity.values, 0.4,
                               8.5, scheme, eps)
            v = velocities(m.K, m.G, data.density.values)
            preds[(variant, scheme)] = {"vp": v.vp, "vs": v.vs}
            rows.append({"data": "Xu 2023 Table 1", "variant": variant, "cct_scheme": scheme,
                         "free": "", "coordination_number": 8.5, "thickness": eps,
                         "success": True, "at_bound": "",
                         **{f"misfit_{k}": float(np.sqrt(np.mean(
                             (getattr(v, k) / data[k].values - 1) ** 2))) for k in ("vp", "vs")}})
        fit = calibrate(data, "contact_cement", free=["thickness"],
                        fixed={"coordination_number": 8.5}, grain=grain, cement=cement,
                        scheme=scheme, errors=None)
        preds[("MCCT fit", scheme)] = {k: fit[f"{k}_model"].values for k in ("vp", "vs")}
        rows += rows_of(fit, "Xu 2023 Table 1", "MCCT fit", ["vp", "vs"], {})
    return data, rows, preds


def sandstone(step):
    from rockcem.scene import load_scene, run_scene

    out = {}
    for name in ("carcione2022_sandstone", "carcione2022_sandstone_calibrated"):
        scene = load_scene(name).replace(**{"path.depth_step": step})
        out[name] = run_scene(scene)
    return out


def figure(ds, fits, xu, xu_fits, scenes, path):
    _common.use_agg()
    import matplotlib.pyplot as plt

    samples, cements = list(fits["patchy"].sample.values), list(fits["patchy"].cement.values)
    ncol = max(len(samples) * len(cements), 4)
    fig, axes = plt.subplots(2, ncol, figsize=(4 * ncol, 8), constrained_layout=True)
    colours = {"contact": "C3", "coating": "C0", "pore_body": "C2"}
    s = ds.saturation.values
    for j, (sample, cement) in enumerate([(a, b) for a in samples for b in cements]):
        ax = axes[0, j]
        for scheme in ds.scheme.values:
            sel = dict(sample=sample, cement=cement, scheme=scheme)
            ax.errorbar(s, ds.vp.sel(sel), ds.vp_error.sel(sel), fmt="o", ms=4, capsize=2,
                        color=colours[str(scheme)], label=f"MD {scheme}")
            ax.plot(s, fits["patchy"].vp_model.sel(sel), "-", color=colours[str(scheme)],
                    label="patchy fit" if scheme == "contact" else None)
            cct = fits["CCT eta"].vp_model.sel(sel).values
            ax.plot(s[1:], cct[1:], "--", color=colours[str(scheme)],
                    label="CCT eta fit" if scheme == "contact" else None)
            ax.plot(s[1:], fits["MCCT"].vp_model.sel(sel).values[1:], ":",
                    color=colours[str(scheme)], label="MCCT fit" if scheme == "contact" else None)
        ax.set_title(f"MD {sample}, {cement} cement")
        ax.set_xlabel("cement saturation S_c")
        ax.set_ylabel("Vp (km/s)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    for j in range(len(samples) * len(cements), ncol):
        axes[0, j].set_visible(False)
    for k, key in enumerate(("vp", "vs")):
        ax = axes[1, k]
        lim = [float(xu[key].min()) * 0.8, 3.6 if key == "vp" else 2.4]
        ax.plot(lim, lim, "k-", lw=0.8)
        for variant, marker in (("CCT", "^"), ("MCCT 0.04", "s"), ("MCCT fit", "o")):
            ax.plot(xu[key], xu_fits[(variant, 2)][key], marker, ls="none",
                    label=f"{variant} (scheme 2)")
        ax.set_xlabel(f"measured {key} (km/s)")
        ax.set_ylabel(f"predicted {key} (km/s)")
        ax.set_title(f"Xu 2023 Table 1: {key}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for k, key in enumerate(("vp", "vs")):
        ax = axes[1, 2 + k]
        for name, style in (("carcione2022_sandstone", "--"),
                            ("carcione2022_sandstone_calibrated", "-")):
            sc = scenes[name]
            ax.plot(sc[key].sel(model="patchy_cement"), sc.depth, style, color="C1",
                    label=("calibrated" if "calibrated" in name else "Carcione 2022")
                    + " patchy cement")
            if "calibrated" not in name:
                ax.plot(sc[key].sel(model="hs_gassmann"), sc.depth, ":", color="0.5",
                        label="Model 1 (HS + Krief)")
        ax.invert_yaxis()
        ax.set_xlabel(f"{key} (km/s)")
        ax.set_ylabel("depth (m)")
        ax.set_title(f"sandstone burial scene: {key}")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Effective-medium models calibrated to MD pulse tests (García & Medina) and "
                 "to Xu 2023 Table 1")
    return _common.save_figure(fig, path)


def main(argv=None):
    import xarray as xr

    from md.calibrate import write_calibration

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true",
                    help="compacted sample and hard cement only, coarse sandstone scene")
    ap.add_argument("--rerun", action="store_true", help="rerun the MD scene (about 2 min)")
    ap.add_argument("--ship", action="store_true",
                    help=f"rewrite datasets/calibrations/{SHIPPED}.toml from this run")
    ap.add_argument("--tag", default="", help="suffix of the result file names")
    args = ap.parse_args(argv)
    _common.announce_source()
    t0 = time.perf_counter()
    ds = md_results(args.rerun)
    rows, fits, parts = fit_md(ds, args.quick)
    if args.ship:
        path = _common.ROOT / "datasets" / "calibrations" / f"{SHIPPED}.toml"
        part = parts[("patchy", SHIP_SELECTION["cement"], SHIP_SELECTION["scheme"])]
        write_calibration(
            part, path, name=SHIPPED, **SHIP_SELECTION,
            description="Patchy-cement (Model 4) dry frame fitted to the MD pulse tests of the "
                        "compacted pack with hard contact cement (scene garcia_medina_cement: "
                        "4 x 4 x 12 largest diameters, resolution 3); n and phi_p0 fitted, "
                        "delta held at 0 (no bonding pre-stress in the MD). Written by "
                        "benchmarks/md_calibration.py --ship.")
        print(f"wrote {path}")
    xu, xu_rows, xu_fits = fit_xu()
    scenes = sandstone(50.0 if args.quick else 10.0)
    elapsed = time.perf_counter() - t0
    table = pd.DataFrame(rows + xu_rows)
    cols = ["data", "sample", "cement", "scheme", "variant", "cct_scheme", "free"]
    rest = [c for c in table.columns if c not in cols]
    table = table[cols + rest]
    attrs = _common.environment_attrs(quick=args.quick, wall_time_s=round(elapsed, 2),
                                      **_common.md_source_attrs())
    out = xr.Dataset.from_dataframe(table.reset_index(drop=True).rename_axis("row"))
    for variant, fit in fits.items():
        key = variant.replace(" ", "_").lower()
        out[f"vp_model_{key}"] = fit.vp_model.rename(
            {d: f"md_{d}" for d in fit.vp_model.dims})
    out["md_vp"] = ds.vp.rename({d: f"md_{d}" for d in ds.vp.dims}).sel(
        md_sample=out.md_sample, md_cement=out.md_cement)
    for name, sc in scenes.items():
        out[f"{name}_vp"] = sc.vp.sel(model="patchy_cement").rename(depth="depth")
    out.attrs.update({k: str(v) for k, v in attrs.items()})
    out.attrs["calibration_in_scene"] = scenes["carcione2022_sandstone_calibrated"].attrs.get(
        "calibration", "")
    _common.write_netcdf(out, _common.result_path("md_calibration", "nc", args.tag))
    _common.write_csv(table, _common.result_path("md_calibration", "csv", args.tag), attrs)
    figure(ds, fits, xu, xu_fits, scenes, _common.result_path("md_calibration", "png", args.tag))
    show = {"data": ("data", "s"), "sample": ("sample", "s"), "cement": ("cement", "s"),
            "scheme": ("MD scheme", "s"), "variant": ("model", "s"),
            "cct_scheme": ("CCT scheme", "d"), "coordination_number": ("n", ".3g"),
            "coordination_number_err": ("± n", ".2g"), "cement_efficiency": ("eta", ".3g"),
            "cement_efficiency_err": ("± eta", ".2g"), "thickness": ("eps", ".3g"),
            "thickness_err": ("± eps", ".2g"), "contact_cement_limit": ("phi_p0", ".3g"),
            "contact_cement_limit_err": ("± phi_p0", ".2g"), "misfit_vp": ("misfit Vp", ".3f"),
            "misfit_vs": ("misfit Vs", ".3f"), "at_bound": ("at bound", "s")}
    show = {k: v for k, v in show.items() if k in table.columns}
    print(_common.markdown(table.fillna({"sample": "", "cement": "", "scheme": "",
                                         "at_bound": ""}), show))
    print(f"total {elapsed:.1f} s")


if __name__ == "__main__":
    main()
