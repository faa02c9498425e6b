"""MD moduli of the burial scene against run time: the lattice resolution Omega and the pack size.

The MD backend of a sandstone scene (``md.along_depth.carry_down``, docs/user_guide/md_along_depth.md)
settles one pack, compacts it down the depths' largest effective stress, cements it to each
depth's cement fraction and solves for the static P and shear moduli. Its two knobs that cost
run time are the cement lattice resolution Omega = R/c_w and the pack size; this report measures
both at the burial states of the shipped sandstone example (``carcione2022_sandstone``, run
through ``rockcem.scene.run_scene``: effective pressure and cement fraction at ``--depths``,
default 2000, 3000 and 4000 m; the path is a linear basin, so the present effective stress is
the largest). Grain and cement are the scene's (``[materials]``, mapped to the MD engine as the
scene runner maps them), the radii and every other MD setting the defaults of
``rockcem.scene.SCHEMA["models.md"]`` (coating cement, facet interface, static moduli, slab of
one diameter).

(a) Omega in ``--omega`` (default 2 3 4 5 6) on one pack (``--omega-size``, default the scene's
    4 x 4 x 12 diameters, seed ``--omega-seed``). The pack is settled and compacted once and
    reused across Omega on purpose (each Omega cements and solves the same compacted stages),
    so the Omega error is that of the lattice alone; the pack's time is counted in every
    Omega's total. Reference: the three-point Richardson limit of the three finest Omega
    (``md_omega_convergence.richardson``) where the sequence is asymptotic (its last three
    changes shrink with one sign, order 0.5-3), else the finest Omega (flagged per depth and
    modulus in the output; the errors are then lower bounds).
(b) Pack size in ``--sizes`` (default 3x3x8 4x4x12 5x5x16 6x6x20) at Omega ``--size-omega``
    (default 3, the scene's), ``--seeds`` settling seeds each (default 0 1 2), each pack in its
    own fresh work folder (the largest size only the first ``--seeds-largest``, default 2, to
    fit the time budget). The sample-size error of one run is the standard deviation across
    seeds; the reference is the largest size's seed mean, and the error of one run of a size
    is ``sqrt(bias^2 + std^2)`` (bias: its seed mean against the reference).

Wall times: ``seconds_pack`` (settling and compaction down the depths, one pack: carry_down's
total less its members), ``seconds_members`` (cement + linearisation + both static solves,
summed over the depths; carry_down's ``wall_time`` per member is in the rows) and their sum
``seconds_total``, the cost of one configuration. A warm-up run (small pack, coarse lattice,
not recorded) compiles the numba kernels first. The load average is recorded beside every run:
other work on the machine stretches the wall times.

Output: ``results/md_scene_error_vs_time[_<tag>].{csv,nc,png}`` (one row per run: study, knob,
depth, seed) and ``results/md_scene_error_vs_time_summary[_<tag>].csv`` (per study, knob and
depth: moduli, errors against the reference, seed spread, wall time).
Run: ``python benchmarks/md_scene_error_vs_time.py [--quick]`` (``--quick``: Omega 2 3 4,
sizes 3x3x8 4x4x12, seeds 0 1; a few minutes). ``--example [3:2 4:3]`` instead times the
shipped MD example (``carcione2022_sandstone_md``) at those resolution:check pairs
(``results/md_scene_error_vs_time_example.csv``): the cost the defaults must fit.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import os  # noqa: E402
import shutil  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_scene_error_vs_time"
MODULI = {"p_modulus": "P modulus M", "shear_modulus": "shear modulus G"}
UNITS = {"depth": "m", "stress_MPa": "MPa", "stress_reached_MPa": "MPa", "cement_fraction": "1",
         "porosity_pack": "1", "saturation": "1", "p_modulus": "GPa", "shear_modulus": "GPa",
         "density": "g cm-3", "vp_dry": "km s-1", "vs_dry": "km s-1", "omega": "1",
         "seconds_member": "s", "seconds_pack": "s", "seconds_members": "s",
         "seconds_total": "s", "load_average": "1"}


def _size_label(size):
    return "x".join(f"{s:g}" for s in size)


def _parse_size(text):
    parts = [float(p) for p in text.lower().split("x")]
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"a size is three numbers joined by x; got {text!r}")
    return tuple(parts)


def burial_states(scene_name, depths):
    """Effective stress (MPa), cement fraction and porosity of the scene at the nearest profile
    depths, and the scene; the MD settings of the scene runner (schema defaults, the scene's
    grain size and materials)."""
    from rockcem._md_backend import _materials  # the runner's own mapping, not a copy
    from rockcem.materials import mineral
    from rockcem.scene import SCHEMA, load_scene, run_scene

    scene = load_scene(scene_name)
    ds = run_scene(scene)
    pe = ds.pressure_effective.values
    if np.any(np.diff(pe) < 0):
        raise ValueError("effective pressure is not monotone in depth: the present stress is "
                         "not the largest (uplift); this benchmark needs a burial path")
    at = ds.sel(depth=np.asarray(depths, dtype=float), method="nearest")
    state = {"depth": at.depth.values.astype(float), "stress_MPa": at.pressure_effective.values,
             "cement_fraction": at.cement_fraction.values,
             "porosity_burial": at.porosity.values}
    md_defaults = {k: v[0] for k, v in SCHEMA["models.md"].items()}
    grain_size = scene.sections["sandstone"]["grain_size"]                   # mm
    r_max = grain_size / 2.0 * 1e-3
    m = scene.sections["materials"]
    grain, cement = _materials(mineral(m["grain"]), mineral(m["cement"]))
    settings = dict(schemes=tuple(md_defaults["schemes"]),
                    radius_range=((1.0 - md_defaults["radius_spread"]) * r_max, r_max),
                    material=grain, cement=cement,
                    fall_stiffness_factor=md_defaults["fall_stiffness_factor"],
                    interface=md_defaults["interface"], measure=md_defaults["measure"],
                    slab=md_defaults["slab"])
    return state, settings, md_defaults


class Runs:
    """carry_down runs, one fresh work folder per pack (size, seed), reused across Omega."""

    def __init__(self, state, settings, root):
        self.state, self.settings, self.root = state, settings, root
        self.folders, self.pack_seconds, self.done = {}, {}, {}

    def __call__(self, size, seed, omega):
        from md.along_depth import carry_down

        key = (tuple(size), int(seed), float(omega))
        if key in self.done:
            return self.done[key]
        pack_key = (tuple(size), int(seed))
        if pack_key not in self.folders:
            self.folders[pack_key] = tempfile.mkdtemp(prefix=f"{_size_label(size)}_s{seed}_",
                                                      dir=self.root)
        load0 = os.getloadavg()[0]
        t0 = time.perf_counter()
        res = carry_down(self.state["stress_MPa"], self.state["cement_fraction"], size=size,
                         seed=int(seed), resolution=float(omega), resolution_check=0.0,
                         workdir=self.folders[pack_key], **self.settings)
        total = time.perf_counter() - t0
        members = float(res.wall_time.sum())
        if pack_key not in self.pack_seconds:       # settled and compacted in this call
            self.pack_seconds[pack_key] = total - members
        load = 0.5 * (load0 + os.getloadavg()[0])
        rows = []
        for k, scheme in enumerate(res.scheme.values):
            r = res.isel(scheme=k)
            for i in range(res.sizes["point"]):
                rho = float(r.density[i])
                M, G = float(r.p_modulus[i]), float(r.shear_modulus[i])
                rows.append(dict(
                    size=_size_label(size), seed=int(seed), omega=float(omega),
                    scheme=str(scheme), n_grains=int(res.attrs["n_grains"]),
                    depth=self.state["depth"][i], stress_MPa=self.state["stress_MPa"][i],
                    stress_reached_MPa=float(res.stress_reached[i]) / 1e6,
                    cement_fraction=self.state["cement_fraction"][i],
                    porosity_burial=self.state["porosity_burial"][i],
                    porosity_pack=float(res.porosity_pack[i]),
                    saturation=float(r.saturation[i]),
                    cement_overflow=int(r.cement_overflow[i]),
                    p_modulus=M / 1e9, shear_modulus=G / 1e9, density=rho / 1e3,
                    vp_dry=np.sqrt(M / rho) / 1e3, vs_dry=np.sqrt(G / rho) / 1e3,
                    seconds_member=float(r.wall_time[i]),
                    seconds_pack=self.pack_seconds[pack_key], seconds_members=members,
                    seconds_total=self.pack_seconds[pack_key] + members, load_average=load))
        self.done[key] = rows
        print(f"  {_size_label(size):>8s} seed {seed} Omega {omega:g}: pack "
              f"{self.pack_seconds[pack_key]:6.1f} s, members {members:6.1f} s (load "
              f"{load:.1f}); M " + " ".join(f"{row['p_modulus']:7.3f}" for row in rows)
              + " GPa, G " + " ".join(f"{row['shear_modulus']:7.3f}" for row in rows),
              flush=True)
        return rows


#: A Richardson limit is the reference only inside this range of orders (first order is what
#: the single cemented contact shows, md_single_contact.py; 1.6 the pendular pack,
#: md_omega_convergence.py); an order far outside it extrapolates noise.
CREDIBLE_ORDER = (0.5, 3.0)


def omega_reference(omega, value):
    """Reference of an Omega sequence: ``(value, kind, order)``. The three-point Richardson
    limit of the three finest Omega (``md_omega_convergence.richardson``) where the sequence is
    in its asymptotic range: the last three changes have one sign and shrink, and the order
    lies in :data:`CREDIBLE_ORDER`. Otherwise the finest Omega (kind ``finest``; the errors
    against it are then lower bounds of the true resolution error)."""
    from md_omega_convergence import richardson

    v = np.asarray(value, float)
    change = np.diff(v)[-3:]
    lim, order = richardson(omega, v)
    asymptotic = (change.size == 3 and (np.all(change > 0) or np.all(change < 0))
                  and np.all(np.abs(change[1:]) < np.abs(change[:-1])))
    if asymptotic and np.isfinite(lim) and CREDIBLE_ORDER[0] <= order <= CREDIBLE_ORDER[1]:
        return float(lim), "richardson", float(order)
    return float(v[-1]), "finest", float(order)


def omega_summary(df):
    """Per depth and scheme: each Omega's moduli, their change from the next coarser Omega and
    their error against the reference (:func:`omega_reference`)."""
    import pandas as pd

    out = []
    for (depth, scheme), g in df.groupby(["depth", "scheme"], sort=True):
        g = g.sort_values("omega")
        ref = {var: omega_reference(g.omega.values, g[var].values) for var in MODULI}
        prev = None
        for _, row in g.iterrows():
            rec = dict(study="omega", knob=f"{row.omega:g}", depth=depth, scheme=scheme,
                       omega=row.omega, size=row["size"], n_grains=row.n_grains, seeds=1,
                       saturation=row.saturation, seconds_pack=row.seconds_pack,
                       seconds_members=row.seconds_members, seconds_total=row.seconds_total,
                       seconds_member=row.seconds_member)
            for var in MODULI:
                value, kind, order = ref[var]
                rec[var] = row[var]
                rec[f"{var}_std"] = np.nan
                rec[f"{var}_reference"] = value
                rec[f"{var}_reference_kind"] = kind
                rec[f"{var}_richardson_order"] = order
                rec[f"{var}_change"] = (row[var] / prev[var] - 1) if prev is not None else np.nan
                rec[f"{var}_error"] = abs(row[var] / value - 1)
                rec[f"{var}_spread"] = np.nan
                rec[f"{var}_bias"] = rec[f"{var}_error"]
            prev = row
            out.append(rec)
    return pd.DataFrame(out)


def size_summary(df, sizes):
    """Per size, depth and scheme: seed mean and standard deviation (ddof 1) of the moduli; the
    reference is the largest size's seed mean; the error of one run is sqrt(bias^2 + std^2)."""
    import pandas as pd

    order = {_size_label(s): k for k, s in enumerate(sizes)}
    largest = _size_label(max(sizes, key=np.prod))
    out = []
    for (depth, scheme), g in df.groupby(["depth", "scheme"], sort=True):
        ref = {var: g[g["size"] == largest][var].mean() for var in MODULI}
        for size, h in sorted(g.groupby("size"), key=lambda item: order[item[0]]):
            per_seed = h.drop_duplicates("seed")
            rec = dict(study="size", knob=size, depth=depth, scheme=scheme,
                       omega=h.omega.values[0], size=size, n_grains=h.n_grains.mean(),
                       seeds=len(per_seed), saturation=h.saturation.mean(),
                       seconds_pack=per_seed.seconds_pack.mean(),
                       seconds_members=per_seed.seconds_members.mean(),
                       seconds_total=per_seed.seconds_total.mean(),
                       seconds_member=h.seconds_member.mean())
            for var in MODULI:
                mean = h[var].mean()
                std = h[var].std(ddof=1) if len(h) > 1 else np.nan
                bias = abs(mean / ref[var] - 1)
                spread = std / mean
                rec[var] = mean
                rec[f"{var}_std"] = std
                rec[f"{var}_reference"] = ref[var]
                rec[f"{var}_reference_kind"] = f"mean of {largest}"
                rec[f"{var}_richardson_order"] = np.nan
                rec[f"{var}_change"] = np.nan
                rec[f"{var}_spread"] = spread
                rec[f"{var}_bias"] = bias
                rec[f"{var}_error"] = float(np.hypot(bias, spread)) if np.isfinite(spread) \
                    else bias
            out.append(rec)
    return pd.DataFrame(out)


def plot(summary, tag):
    """Relative error against the wall time of one configuration, log-log, one panel per
    modulus; colour = depth, circles = Omega (labelled), squares = pack size (labelled; error of
    one run, sqrt(bias^2 + seed std^2)), open squares = the seed spread alone."""
    _common.use_agg()
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter

    depths = sorted(summary.depth.unique())
    fig, axes = plt.subplots(1, len(MODULI), figsize=(12, 4.8), squeeze=False)
    for ax, (var, title) in zip(axes[0], MODULI.items()):
        for c, depth in enumerate(depths):
            color = f"C{c}"
            for study, style in (("omega", "o-"), ("size", "s--")):
                g = summary[(summary.study == study) & (summary.depth == depth)]
                if g.empty:
                    continue
                err = g[f"{var}_error"].values
                ok = err > 0
                sat = summary[summary.depth == depth].saturation.values[0]
                ax.plot(g.seconds_total.values[ok], err[ok], style, color=color, ms=5, lw=1,
                        label=f"{depth:g} m, S_c {sat:.3f}: "
                              + ("Omega" if study == "omega" else "pack size"))
                for x, y, knob in zip(g.seconds_total.values[ok], err[ok], g.knob.values[ok]):
                    ax.annotate(knob, (x, y), textcoords="offset points", xytext=(3, 3),
                                fontsize=7, color=color)
                if study == "size":
                    ax.plot(g.seconds_total, g[f"{var}_spread"], "s", mfc="none", color=color,
                            ms=7, lw=0)
        ax.set(xlabel="wall time of one configuration (s)", ylabel="relative error",
               title=title)
        positive = summary[[f"{var}_error", f"{var}_spread"]].to_numpy()
        if not np.any(positive[np.isfinite(positive)] > 0):
            ax.text(0.5, 0.5, "no errors to plot\n(one value per knob)", ha="center",
                    transform=ax.transAxes)
            continue
        ax.set(xscale="log", yscale="log")
        ticks = [t for t in (10, 20, 50, 100, 200, 500, 1000, 2000, 5000)
                 if summary.seconds_total.min() / 1.5 <= t <= summary.seconds_total.max() * 1.5]
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=3,
               bbox_to_anchor=(0.5, -0.12))
    kinds = sorted({k for var in MODULI for k in
                    summary[summary.study == "omega"][f"{var}_reference_kind"].unique()})
    fig.suptitle("MD scene, error against wall time. Circles: Omega against "
                 + (" / ".join(kinds).replace("finest", "the finest Omega (a lower bound)"))
                 + ";\nfilled squares: pack size, one run against the largest size's seed "
                 "mean, sqrt(bias^2 + seed std^2); open squares: the seed spread alone",
                 fontsize=9, y=1.05)
    _common.save_figure(fig, _common.result_path(NAME, "png", tag))


def read_attrs(path):
    """The ``# key: value`` metadata lines of a CSV written by :func:`_common.write_csv`."""
    attrs = {}
    with open(path) as fh:
        for line in fh:
            if not line.startswith("# "):
                break
            key, _, value = line[2:].rstrip("\n").partition(": ")
            attrs[key] = value
    return attrs


def finish(df, attrs, tag):
    """Summary, CSV, netCDF and PNG from the per-run rows."""
    import pandas as pd
    import xarray as xr

    sizes = sorted({tuple(float(x) for x in s.split("x")) for s in df[df.study == "size"]["size"]},
                   key=np.prod)
    parts = [omega_summary(df[df.study == "omega"])]
    if sizes:                                   # not with --skip-size
        parts.append(size_summary(df[df.study == "size"], sizes))
    summary = pd.concat(parts, ignore_index=True)
    _common.write_csv(df, _common.result_path(NAME, "csv", tag), attrs)
    _common.write_csv(summary, _common.result_path(NAME + "_summary", "csv", tag), attrs)
    ds = xr.Dataset.from_dataframe(df.rename_axis("run"))
    for var, unit in UNITS.items():
        if var in ds:
            ds[var].attrs["units"] = unit
    summ = xr.Dataset.from_dataframe(summary.rename_axis("entry").add_prefix("summary_"))
    for var in summ.data_vars:
        base = var.removeprefix("summary_")
        if base in UNITS:
            summ[var].attrs["units"] = UNITS[base]
        elif base.startswith(tuple(MODULI)) and base.endswith(("_std", "_reference")):
            summ[var].attrs["units"] = "GPa"
    _common.write_netcdf(xr.merge([ds, summ]).assign_attrs(attrs),
                         _common.result_path(NAME, "nc", tag))
    plot(summary, tag)
    print(_common.markdown(summary, {
        "study": ("study", "s"), "knob": ("knob", "s"), "depth": ("depth m", "g"),
        "saturation": ("S_c", ".3f"), "p_modulus": ("M GPa", ".3f"),
        "p_modulus_std": ("± seeds", ".3f"), "p_modulus_change": ("change", "+.1%"),
        "p_modulus_error": ("M err", ".1%"), "shear_modulus": ("G GPa", ".3f"),
        "shear_modulus_std": ("± seeds", ".3f"), "shear_modulus_change": ("change", "+.1%"),
        "shear_modulus_error": ("G err", ".1%"), "seconds_pack": ("pack s", ".1f"),
        "seconds_members": ("members s", ".1f"), "seconds_total": ("total s", ".1f")}))
    return summary


def replot(tag):
    """Summary, netCDF and figure again from the per-run CSV of an earlier run (its metadata
    kept: they describe the code and machine that made the numbers)."""
    import pandas as pd

    path = _common.result_path(NAME, "csv", tag)
    finish(pd.read_csv(path, comment="#"), read_attrs(path), tag)


def _pair(text):
    try:
        omega, check = (float(x) for x in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"a pair is OMEGA:CHECK; got {text!r}") from None
    return omega, check


def example_timings(scene_name, pairs, tag):
    """Wall time of the shipped MD example (``rockcem.scene.run_scene``, its own depths,
    schemes and pack) at each ``(resolution, resolution_check)``, each in a fresh work folder:
    the cost the defaults must fit. Writes ``results/<NAME>_example[_<tag>].csv``."""
    import pandas as pd

    from rockcem.scene import load_scene, run_scene

    rows = []
    for omega, check in pairs:
        root = tempfile.mkdtemp(prefix=f"{NAME}_example_")
        try:
            scene = load_scene(scene_name).replace(**{
                "models.md.resolution": omega, "models.md.resolution_check": check,
                "models.md.workdir": root})
            load0 = os.getloadavg()[0]
            t0 = time.perf_counter()
            ds = run_scene(scene)
            total = time.perf_counter() - t0
        finally:
            shutil.rmtree(root, ignore_errors=True)
        md = [m for m in ds.model.values if str(m).startswith("md")]
        wall = ds.md_wall_time.sel(model=md)
        depths = wall.dropna("depth", how="all").depth.values
        w = wall.transpose("model", "depth").values
        slow = np.unravel_index(np.nanargmax(w), w.shape)
        row = dict(scene=scene_name, omega=omega, check=check, depths=len(depths),
                   members=int(np.isfinite(wall.values).sum()), schemes=" ".join(md),
                   size=_size_label(scene.sections["models.md"]["size"]),
                   seconds_total=total, seconds_members=float(wall.sum()),
                   seconds_rest=total - float(wall.sum()),
                   slowest_member_s=float(w[slow]),
                   slowest_member=f"{md[slow[0]]} {wall.depth.values[slow[1]]:g} m",
                   load_average=0.5 * (load0 + os.getloadavg()[0]))
        rows.append(row)
        print(f"  {scene_name} Omega {omega:g} (check {check:g}): {total:.1f} s, members "
              f"{row['seconds_members']:.1f} s ({row['members']}), slowest "
              f"{row['slowest_member']} {row['slowest_member_s']:.1f} s (load "
              f"{row['load_average']:.1f})", flush=True)
    df = pd.DataFrame(rows)
    attrs = _common.environment_attrs(benchmark=NAME + " --example", **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME + "_example", "csv", tag), attrs)
    print(_common.markdown(df, {
        "omega": ("Omega", "g"), "check": ("check", "g"), "members": ("members", "d"),
        "seconds_total": ("scene s", ".1f"), "seconds_members": ("members s", ".1f"),
        "seconds_rest": ("pack + rest s", ".1f"), "slowest_member": ("slowest", "s"),
        "slowest_member_s": ("its s", ".1f")}))
    return df


def main(argv=None):
    import pandas as pd

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default="carcione2022_sandstone")
    ap.add_argument("--depths", type=float, nargs="+", default=[2000.0, 3000.0, 4000.0])
    ap.add_argument("--omega", type=float, nargs="+", default=[2, 3, 4, 5, 6])
    ap.add_argument("--omega-size", type=float, nargs=3, default=None,
                    help="pack of the Omega study (default the scene's size)")
    ap.add_argument("--omega-seed", type=int, default=None, help="default the scene's seed")
    ap.add_argument("--sizes", type=_parse_size, nargs="+",
                    default=[(3, 3, 8), (4, 4, 12), (5, 5, 16), (6, 6, 20)])
    ap.add_argument("--size-omega", type=float, default=None,
                    help="Omega of the size study (default the scene's resolution)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--seeds-largest", type=int, default=2,
                    help="the largest size runs only the first N of --seeds (time budget)")
    ap.add_argument("--skip-size", action="store_true", help="run the Omega study (a) only")
    ap.add_argument("--quick", action="store_true",
                    help="Omega 2 3 4, sizes 3x3x8 4x4x12, seeds 0 1")
    ap.add_argument("--keep-work", action="store_true", help="keep the stage files")
    ap.add_argument("--tag", default="")
    ap.add_argument("--replot", action="store_true",
                    help="only recompute the summary, netCDF and figure from the per-run CSV")
    ap.add_argument("--example", nargs="*", type=_pair, metavar="OMEGA:CHECK",
                    help="instead: time the shipped MD example (--example-scene) at these "
                    "resolution:resolution_check pairs (default 3:2 4:3)")
    ap.add_argument("--example-scene", default="carcione2022_sandstone_md")
    args = ap.parse_args(argv)
    if args.replot:
        return replot(args.tag)
    if args.example is not None:
        _common.announce_source()
        return example_timings(args.example_scene, args.example or [(3.0, 2.0), (4.0, 3.0)],
                               args.tag)
    if args.quick:
        args.omega, args.sizes, args.seeds = [2, 3, 4], [(3, 3, 8), (4, 4, 12)], [0, 1]
        args.seeds_largest = 2
    _common.announce_source()
    md_attrs = _common.md_source_attrs()
    t_start = time.perf_counter()
    state, settings, md_defaults = burial_states(args.scene, args.depths)
    omega_size = tuple(args.omega_size or md_defaults["size"])
    omega_seed = md_defaults["seed"] if args.omega_seed is None else args.omega_seed
    size_omega = args.size_omega or md_defaults["resolution"]
    print("burial states: " + "; ".join(
        f"{z:g} m: {p:.2f} MPa, cement {c:.4f}" for z, p, c in
        zip(state["depth"], state["stress_MPa"], state["cement_fraction"])), flush=True)
    root = tempfile.mkdtemp(prefix=NAME + "_")
    try:
        runs = Runs(state, settings, root)
        # warm-up: compile (or load) the numba kernels outside the timed runs
        warm = Runs({k: v[:1] for k, v in state.items()}, settings, root)
        warm((3.0, 3.0, 8.0), 99, 2.0)
        rows = []
        print(f"(a) Omega on {_size_label(omega_size)}, seed {omega_seed}", flush=True)
        for omega in sorted(args.omega):
            rows += [dict(r, study="omega") for r in runs(omega_size, omega_seed, omega)]
        print(f"(b) pack size at Omega {size_omega:g}", flush=True)
        for size in [] if args.skip_size else args.sizes:
            last = size == max(args.sizes, key=np.prod)
            for seed in args.seeds[:args.seeds_largest] if last else args.seeds:
                rows += [dict(r, study="size") for r in runs(size, seed, size_omega)]
    finally:
        if args.keep_work:
            print(f"stage files kept in {root}")
        else:
            shutil.rmtree(root, ignore_errors=True)
    wall = time.perf_counter() - t_start
    attrs = _common.environment_attrs(
        benchmark=NAME, scene=args.scene, depths=" ".join(f"{z:g}" for z in state["depth"]),
        omega_size=_size_label(omega_size), omega_seed=omega_seed, size_omega=size_omega,
        seeds=" ".join(map(str, args.seeds)), seeds_largest=args.seeds_largest,
        schemes=" ".join(settings["schemes"]), interface=settings["interface"],
        measure=settings["measure"], slab=settings["slab"],
        radius_range_m=" ".join(f"{r:.4g}" for r in settings["radius_range"]),
        benchmark_wall_seconds=wall, **md_attrs)
    finish(pd.DataFrame(rows), attrs, args.tag)
    print(f"benchmark wall time {wall:.0f} s")


if __name__ == "__main__":
    main()
