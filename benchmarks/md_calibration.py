"""MD calibration (issue 7; re-fit to the full-size study, issue 12): effective-medium
parameters fitted to the MD pulse tests and to the measured sandstones of Xu 2023 Table 1; the
sandstone burial scene with calibrated parameters.

MD, ``--study`` (which MD output is fitted):

- ``full`` (default): ``results/garcia_medina_full.nc`` of the shipped scene
  ``garcia_medina_full`` (the source's study at its own size, 8 x 8 x 32 largest diameters,
  with a resolution check). It is read, never run here (about an hour and a half on two
  processes): if missing, the script exits with code 2 and the command that makes it,
  ``rockcem run garcia_medina_full -o benchmarks/results/garcia_medina_full.nc -j 2``.
- ``small``: ``results/garcia_medina_cement.nc`` of the quick-look scene
  ``garcia_medina_cement`` (4 x 4 x 12); run here if missing or with ``--rerun``, its stage
  files in ``results/garcia_medina_cement_work/``.

A cached file whose scene (``scene_json``) differs from the shipped scene of that name is used,
with a warning naming the keys that differ.

For each sample (loose, compacted), cement (hard, soft of Table II) and cementation scheme,
Vp(S_c) is fitted with :func:`md.calibrate.calibrate`, weighted by :func:`md.calibrate.total_error`:
the eq. 11 error of the pulse test (``vp_error``) and, where the study has one (the full
study's ``resolution_check``), its resolution error (``vp_error_resolution``, first-order
Richardson estimate of the distance to the Omega -> infinity limit) in quadrature, scaled by the
residual variance. Grain: quartz of Table I; critical porosity: the sample's uncemented
porosity; the held coordination number: the sample's. The contact-cement radius is paired with
the MD scheme: scheme 1 (cement at contacts) for ``contact``, scheme 2 (coating) for
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
  out;
- ``patchy shipped``: the fit that becomes the shipped calibration (compacted sample, hard
  contact cement): :func:`md.calibrate.calibrate_identified` fits n and phi_p0, and if phi_p0
  is unidentifiable (error infinite, wider than its bounds or than its value, or |r| > 0.999
  with n) holds it at 0.05, the value of Carcione et al. 2022 (eq. 17; the scene default), and
  fits n alone.

Column ``unidentifiable`` lists the fitted parameters the data do not determine (same rule).

Xu 2023 Table 1 (``datasets/measurements/xu2023_table1.csv``): quartz grains and
epoxy-kaolinite cement, critical porosity 0.4, n = 8.5 held, CCT scheme 1 and 2: ``CCT``
(epsilon = 0), ``MCCT 0.04`` (epsilon = 0.04, inside the 0-0.05 Xu measures; the value of
tests/rockcem/test_xu2023.py) and ``MCCT fit`` (epsilon free), by the same
:func:`md.calibrate.calibrate` on relative residuals of Vp and Vs (it reproduces
:func:`rockcem.calibrate.fit_contact_cement`).

Sandstone: the shipped scenes ``carcione2022_sandstone`` and ``carcione2022_sandstone_calibrated``
(the latter's patchy-cement parameters from ``datasets/calibrations/garcia_medina_compacted_patchy
.toml``). ``--ship`` rewrites that file from the ``patchy shipped`` fit of this run, with its
``[identifiability]`` table (the two-parameter fit, the n-phi_p0 correlation, what was held
and why); ``--ship --dry-run`` prints the file instead of writing it (checked by
:func:`rockcem.calibrate.load_calibration` either way).

Output: ``results/md_calibration_<study>.{csv,nc,png}`` (``--tag T`` appends ``_T``); the table
on stdout (markdown). Run: ``python benchmarks/md_calibration.py [--study full|small]`` (about a
minute with the MD results at hand); ``--quick``: compacted sample and hard cement only, and a
coarser sandstone scene (about 15 s).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

PAIR = {"contact": 1, "coating": 2, "pore_body": 2, "pendular": 1}
SHIPPED = "garcia_medina_compacted_patchy"
#: The shipped fit: compacted sample, hard cement, contact cement - the pendular rings about the
#: contacts where the study has them (the contact cement whose shape is fixed in space, so its
#: moduli converge in Omega: benchmarks/md_omega_convergence.py), else the source's contact
#: growth.
SHIP_SELECTION = {"sample": "compacted", "cement": "hard", "scheme": "pendular"}
MD_VARIANTS = {
    "CCT eta": ("contact_cement", {"cement_efficiency": (1.0, 1e-3, 1.0)}),
    "CCT n": ("contact_cement", ["coordination_number"]),
    "MCCT": ("contact_cement", ["thickness"]),
    "patchy": ("patchy_cement", ["coordination_number", "contact_cement_limit"]),
}
PARAMS = ["coordination_number", "cement_efficiency", "thickness", "contact_cement_limit",
          "delta"]
STUDIES = {"full": "garcia_medina_full", "small": "garcia_medina_cement"}
#: phi_p0 where the MD data do not determine it: Carcione et al. 2022, eq. 17 and the text after
#: it (0.1 instead changes their results little); the default of the scene schema.
HOLD = {"contact_cement_limit": 0.05}
HOLD_REASON = ("the MD data do not determine phi_p0 (rockcem.calibrate.unidentifiable); held at "
               "0.05, the value of Carcione et al. 2022 (eq. 17: the most cement bonded at "
               "contacts; 0.1 changes their results little) and the default of the scene schema")


def md_results(study, rerun):
    """The MD study's output Dataset, with ``vp_error_total`` (:func:`md.calibrate.total_error`)
    added; the full study is read, never run."""
    import json

    import xarray as xr

    from md.calibrate import total_error
    from md.experiment import md_scene_from_dict, run_md_scene
    from rockcem.scene import read_scene_toml

    name = STUDIES[study]
    path = _common.RESULTS / f"{name}.nc"
    scene = md_scene_from_dict(read_scene_toml(name)[0])
    if rerun or not path.exists():
        ds = run_md_scene(scene, workdir=_common.RESULTS / f"{name}_work", progress=True)
        _common.write_netcdf(ds, path)
    ds = xr.load_dataset(path)
    cached = json.loads(ds.attrs.get("scene_json", "{}")).get("md", {})
    differ = sorted(k for k in set(cached) | set(scene["md"])
                    if cached.get(k) != scene["md"].get(k))
    if differ:
        print(f"md_calibration: warning: {path.name} was made with another {name} scene ("
              + ", ".join(f"{k} {cached.get(k)!r} now {scene['md'].get(k)!r}" for k in differ)
              + ")" + ("; --rerun remakes it" if study == "small" else ""), file=sys.stderr)
    ds["vp_error_total"] = total_error(ds)
    return ds


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
        row["unidentifiable"] = "" if initial else " ".join(
            str(p) for p in one.parameter.values if bool(one.unidentifiable.sel(parameter=p)))
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
                                cement=mineral(f"{cement}_cement"), scheme=PAIR[str(scheme)],
                                errors={"vp": "vp_error_total"})
                parts[(variant, cement, str(scheme))] = fit
                if variant == "CCT eta":
                    rows += rows_of(fit, "MD", "CCT", ["vp"], {})
                rows += rows_of(fit, "MD", variant, ["vp"], {})
        fits[variant] = xr.merge(
            [f[["vp_model", "misfit"]] for (v, *_), f in parts.items() if v == variant],
            compat="no_conflicts", join="outer", combine_attrs="drop")
    return rows, fits, parts


def ship_fit(ds):
    """The fit that becomes the shipped calibration (:data:`SHIP_SELECTION`): n and phi_p0,
    phi_p0 held at :data:`HOLD` where the data do not determine it; and its table rows."""
    from md.calibrate import calibrate_identified
    from rockcem.materials import mineral

    sel = dict(SHIP_SELECTION)
    if sel["scheme"] not in ds.scheme.values:
        sel["scheme"] = "contact"
    fit = calibrate_identified(ds.sel(sel), "patchy_cement", free=MD_VARIANTS["patchy"][1],
                               hold=HOLD, reason=HOLD_REASON,
                               grain=mineral("quartz_garcia_medina"),
                               cement=mineral(f"{sel['cement']}_cement"),
                               scheme=PAIR[sel["scheme"]], errors={"vp": "vp_error_total"})
    return fit, rows_of(fit, "MD", "patchy shipped", ["vp"], dict(sel))


def ship(fit, ds, dry_run):
    """Write (or with ``dry_run`` print) the shipped calibration file from ``fit``."""
    import json

    from md.calibrate import write_calibration
    from rockcem.calibrate import load_calibration

    p = json.loads(ds.attrs.get("scene_json", "{}")).get("md", {})
    scheme = str(fit["scheme"].values) if "scheme" in fit.coords else "contact"
    held = json.loads(fit.attrs["identifiability_json"])["held"]
    size = " x ".join(f"{v:g}" for v in p.get("size", [])) or "?"
    check = (f", resolution check at Omega = {p['resolution_check']:g}"
             if p.get("resolution_check") else "")
    weights = ("eq. 11 and resolution errors in quadrature" if "vp_error_resolution" in ds
               else "eq. 11 errors")
    fitted = ("n fitted; phi_p0 held at " + ", ".join(f"{v:g}" for v in held.values())
              + " (unidentifiable in the fit of n and phi_p0: see [identifiability])"
              if held else "n and phi_p0 fitted (both identifiable: see [identifiability])")
    description = (
        f"Patchy-cement (Model 4) dry frame fitted to the MD pulse tests of the compacted pack "
        f"with hard contact cement ({scheme} scheme; scene {ds.attrs.get('scene_name', '?')}: "
        f"{size} largest "
        f"diameters, resolution Omega = {p.get('resolution', float('nan')):g}, interface "
        f"{p.get('interface', 'paper')}{check}; Vp weighted by the {weights}); {fitted}; "
        f"delta held at 0 (no bonding pre-stress in the MD). Written by "
        f"benchmarks/md_calibration.py --ship.")
    target = _common.ROOT / "datasets" / "calibrations" / f"{SHIPPED}.toml"
    if not dry_run:
        write_calibration(fit, target, name=SHIPPED, description=description)
        load_calibration(target)
        print(f"wrote {target}")
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = write_calibration(fit, Path(tmp) / f"{SHIPPED}.toml", name=SHIPPED,
                                 description=description)
        load_calibration(path)
        print(f"--dry-run: would write {target}:\n")
        print(path.read_text())


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
    colours = {"contact": "C3", "coating": "C0", "pore_body": "C2", "pendular": "C1"}
    s = ds.saturation.values
    for j, (sample, cement) in enumerate([(a, b) for a in samples for b in cements]):
        ax = axes[0, j]
        for scheme in ds.scheme.values:
            sel = dict(sample=sample, cement=cement, scheme=scheme)
            ax.errorbar(s, ds.vp.sel(sel), ds.vp_error_total.sel(sel), fmt="o", ms=4, capsize=2,
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
    import json

    import xarray as xr

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--study", choices=list(STUDIES), default="full",
                    help="MD output to fit: full (garcia_medina_full, read only) or small "
                         "(garcia_medina_cement, run if missing); default full")
    ap.add_argument("--quick", action="store_true",
                    help="compacted sample and hard cement only, coarse sandstone scene")
    ap.add_argument("--rerun", action="store_true",
                    help="rerun the small MD scene (a few minutes; refused for full)")
    ap.add_argument("--ship", action="store_true",
                    help=f"rewrite datasets/calibrations/{SHIPPED}.toml from this run")
    ap.add_argument("--dry-run", action="store_true",
                    help="with --ship: print the calibration file instead of writing it")
    ap.add_argument("--tag", default="", help="suffix of the result file names")
    args = ap.parse_args(argv)
    if args.dry_run and not args.ship:
        ap.error("--dry-run goes with --ship")
    full = _common.RESULTS / f"{STUDIES['full']}.nc"
    if args.study == "full" and (args.rerun or not full.exists()):
        why = "the full study is not run here (about an hour and a half)" if args.rerun \
            else f"no {full}"
        print(f"md_calibration: {why}; make it with `rockcem run {STUDIES['full']} -o "
              f"benchmarks/results/{STUDIES['full']}.nc -j 2`", file=sys.stderr)
        raise SystemExit(2)
    _common.announce_source()
    t0 = time.perf_counter()
    ds = md_results(args.study, args.rerun)
    rows, fits, parts = fit_md(ds, args.quick)
    shipped, ship_rows = ship_fit(ds)
    rows += ship_rows
    if args.ship:
        ship(shipped, ds, args.dry_run)
    xu, xu_rows, xu_fits = fit_xu()
    scenes = sandstone(50.0 if args.quick else 10.0)
    elapsed = time.perf_counter() - t0
    table = pd.DataFrame(rows + xu_rows)
    cols = ["data", "sample", "cement", "scheme", "variant", "cct_scheme", "free"]
    rest = [c for c in table.columns if c not in cols]
    table = table[cols + rest]
    attrs = _common.environment_attrs(quick=args.quick, wall_time_s=round(elapsed, 2),
                                      study=args.study, md_scene=STUDIES[args.study],
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
    out.attrs["shipped_fit_identifiability_json"] = shipped.attrs["identifiability_json"]
    out.attrs["calibration_in_scene"] = scenes["carcione2022_sandstone_calibrated"].attrs.get(
        "calibration", "")
    stem = f"md_calibration_{args.study}"
    _common.write_netcdf(out, _common.result_path(stem, "nc", args.tag))
    _common.write_csv(table, _common.result_path(stem, "csv", args.tag), attrs)
    figure(ds, fits, xu, xu_fits, scenes, _common.result_path(stem, "png", args.tag))
    show = {"data": ("data", "s"), "sample": ("sample", "s"), "cement": ("cement", "s"),
            "scheme": ("MD scheme", "s"), "variant": ("model", "s"),
            "cct_scheme": ("CCT scheme", "d"), "coordination_number": ("n", ".3g"),
            "coordination_number_err": ("± n", ".2g"), "cement_efficiency": ("eta", ".3g"),
            "cement_efficiency_err": ("± eta", ".2g"), "thickness": ("eps", ".3g"),
            "thickness_err": ("± eps", ".2g"), "contact_cement_limit": ("phi_p0", ".3g"),
            "contact_cement_limit_err": ("± phi_p0", ".2g"), "misfit_vp": ("misfit Vp", ".3f"),
            "misfit_vs": ("misfit Vs", ".3f"), "at_bound": ("at bound", "s"),
            "unidentifiable": ("unidentifiable", "s")}
    show = {k: v for k, v in show.items() if k in table.columns}
    print(_common.markdown(table.fillna({"sample": "", "cement": "", "scheme": "",
                                         "at_bound": "", "unidentifiable": ""}), show))
    ident = json.loads(shipped.attrs["identifiability_json"])
    print("shipped fit (compacted, hard, "
          f"{shipped['scheme'].values if 'scheme' in shipped.coords else 'contact'}): "
          "two-parameter fit "
          + ", ".join(f"{k} = {ident['values'][k]:.4g} ± {ident['stderr'][k]:.2g}"
                      for k in ident["free"])
          + ", correlation " + ", ".join(f"{k} {v:+.3f}" for k, v in ident["correlation"].items())
          + f"; unidentifiable: {', '.join(ident['unidentifiable']) or 'none'}; held: "
          + (", ".join(f"{k} = {v:g}" for k, v in ident["held"].items()) or "none"))
    print(f"total {elapsed:.1f} s")


if __name__ == "__main__":
    main()
