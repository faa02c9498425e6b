"""The ``rockcem`` command line.

Exit codes: 0 success, 2 bad input (one line on stderr, no traceback).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

from ._scheduler import check_scheduler
from ._cli_files import SCENE_FILE_ATTR, output_file, stage_folder, unasked_output

__all__ = ["main"]


def _positive_int(text: str) -> int:
    """argparse type: an integer >= 1 (a bad value exits with code 2 and one line)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1; got {text!r}")
    return value


def _materials(args) -> int:
    from .materials import fluids, minerals

    print(f"{'mineral':<22}{'K GPa':>8}{'G GPa':>8}{'rho g/cm3':>11}{'vp km/s':>9}"
          f"{'vs km/s':>9}  source")
    for name, m in minerals().items():
        print(f"{name:<22}{m.K:8.2f}{m.G:8.2f}{m.rho:11.3f}{m.vp:9.3f}{m.vs:9.3f}  {m.source}")
    print()
    print(f"{'fluid':<22}{'K GPa':>8}{'rho g/cm3':>11}  source")
    for name, f in fluids().items():
        print(f"{name:<22}{f.K:8.2f}{f.rho:11.3f}  {f.source}")
    return 0


def _whole_km(z):
    """The depths of ``z`` nearest the whole kilometres it spans (at most six), m."""
    import numpy as np

    km = np.arange(np.ceil(max(z[0], 1.0) / 1000.0), np.floor(z[-1] / 1000.0) + 1) * 1000
    km = km[np.linspace(0, km.size - 1, min(km.size, 6)).astype(int)] if km.size else z[-1:]
    return np.unique([z[np.argmin(np.abs(z - d))] for d in km])


def _stack_summary(ds) -> str:
    """The run summary of a stack scene: its layers and fluids and, with ``[seismic]``, the AVO
    class of each interface per fluid and model at a few depths (the whole kilometres, at most
    six)."""
    import numpy as np

    z = ds["depth"].values
    lines = [f"scene {ds.attrs.get('scene_name', '?')} (stack of "
             f"{ds.sizes['layer']} layers): {z.size} depths, {z[0]:g}-{z[-1]:g} m",
             "layers: " + ", ".join(f"{str(la)} ({str(li)})" for la, li in
                                    zip(ds["layer"].values, ds["lithology"].values)),
             "fluids of the reservoir: " + ", ".join(str(f) for f in ds["fluid"].values)]
    if "avo_class" in ds.data_vars:
        names = ds["avo_class"].attrs["flag_meanings"].split()
        at = _whole_km(z)
        width = max(len(str(m)) for m in ds["model"].values)
        for i in ds["interface"].values:
            lines.append(f"AVO class of {i} at " + ", ".join(f"{d:g}" for d in at) + " m:")
            for f in ds["fluid"].values:
                for m in ds["model"].values:
                    codes = ds["avo_class"].sel(interface=i, fluid=f, model=m, depth=at).values
                    cells = "  ".join(f"{names[c - 1] if c else '-':>4}" for c in codes)
                    lines.append(f"  {str(f):<8}{str(m):<{width}}  {cells}")
    elif "avo_class_probability" in ds.data_vars:
        prob = ds["avo_class_probability"]
        labels = [str(c) for c in prob["avo_class"].values]
        at = _whole_km(z)
        width = max(len(str(m)) for m in ds["model"].values)
        import json

        spec = json.loads(ds.attrs.get("uncertain_json", "{}"))
        lines.append(f"uncertain: {spec.get('samples', '?')} members; the most probable AVO "
                     "class and its share of the members")
        for i in ds["interface"].values:
            lines.append(f"AVO class of {i} at " + ", ".join(f"{d:g}" for d in at) + " m:")
            for f in ds["fluid"].values:
                for m in ds["model"].values:
                    p = prob.sel(interface=i, fluid=f, model=m, depth=at).transpose(
                        "depth", "avo_class").values
                    cells = "  ".join(f"{labels[k]:>4} {row[k]:.2f}"
                                      for row, k in zip(p, p.argmax(axis=1)))
                    lines.append(f"  {str(f):<8}{str(m):<{width}}  {cells}")
    if "synthetic" in ds:
        lines.append(f"synthetic: {ds.sizes['twt']} samples, {float(ds.twt[0]):g}-"
                     f"{float(ds.twt[-1]):g} s two-way time")
    for line in filter(None, ds.attrs.get("validity_warnings", "").split("\n")):
        lines.append(f"warning: {line}")
    return "\n".join(lines)


def _uncertain_summary(ds) -> list[str]:
    """Lines of the run summary for a scene with uncertain inputs: the members, and the
    quantiles of the porosity, density and each model's vp and vs at the deepest depth."""
    import json

    spec = json.loads(ds.attrs["uncertain_json"])
    q = [float(v) for v in ds["quantile"].values]
    lines = [f"uncertain: {spec['samples']} members ({spec['design']}, seed {spec['seed']}) of "
             + ", ".join(spec["keys"]) + "; quantiles " + ", ".join(f"{v:g}" for v in q)
             + " of the members (quantile 0.1 is the industry's P90, the low case)"]
    deep = ds.isel(depth=-1)
    z = float(ds.depth[-1])
    for name in ("porosity", "density"):
        if name in ds:
            values = " / ".join(f"{float(v):.4g}" for v in deep[name].values)
            lines.append(f"  {name} at {z:g} m: {values}")
    if "vp" in ds and "model" in ds.dims:
        for m in ds.model.values:
            v = deep.sel(model=m)
            text = " / ".join(f"{float(x):.3f}" for x in v.vp.values)
            if "vs" in ds:
                text += ", vs " + " / ".join(f"{float(x):.3f}" for x in v.vs.values)
            lines.append(f"  {m}: vp {text} km/s at {z:g} m")
    return lines


def _summary(ds) -> str:
    if ds.attrs.get("lithology") == "stack":
        return _stack_summary(ds)
    if "uncertain_json" in ds.attrs and "quantile" in ds.dims and \
            not [d for d in ds.dims if d not in ("depth", "model", "quantile", "member")]:
        lines = [f"scene {ds.attrs.get('scene_name', '?')} ({ds.attrs.get('lithology', '?')}): "
                 f"{ds.sizes['depth']} depths, {float(ds.depth[0]):g}-"
                 f"{float(ds.depth[-1]):g} m", *_uncertain_summary(ds)]
        for line in filter(None, ds.attrs.get("validity_warnings", "").split("\n")):
            lines.append(f"warning: {line}")
        return "\n".join(lines)
    lines = [(f"scene {ds.attrs.get('scene_name', '?')} ({ds.attrs.get('lithology', '?')}): "
              f"{ds.sizes['depth']} depths, {float(ds.depth[0]):g}-{float(ds.depth[-1]):g} m")]
    extra = [d for d in ds.dims if d not in ("depth", "model")]
    if extra:
        lines.append("sweep: " + ", ".join(f"{d} = {ds[d].values.tolist()}" for d in extra))
    deep = ds.isel(depth=-1)
    for name in ("porosity", "cement_fraction", "illite_fraction", "density"):
        if name in ds and not extra:
            lines.append(f"  {name} at {float(ds.depth[-1]):g} m: {float(deep[name]):.4g} "
                         f"{'' if ds[name].attrs.get('units') == '1' else ds[name].units}"
                         .rstrip())
    md = [str(m) for m in ds.model.values if str(m).startswith("md")] \
        if "model" in ds.dims else []
    if "vp" in ds and not extra:
        for m in ds.model.values:
            if str(m) in md:
                continue                    # run at a few depths: the table below
            v = deep.sel(model=m)
            vs = f", vs {float(v.vs):.3f}" if "vs" in ds else ""
            lines.append(f"  {m}: vp {float(v.vp):.3f}{vs} km/s at {float(ds.depth[-1]):g} m")
        lines.extend(_md_depth_table(ds, md))
    for line in filter(None, ds.attrs.get("validity_warnings", "").split("\n")):
        lines.append(f"warning: {line}")
    return "\n".join(lines)


def _md_depth_table(ds, members) -> list[str]:
    """Lines of the run summary for the MD members of a scene Dataset: per member, a row per
    MD depth with vp and vs and their total errors (km/s) and whether the member is trusted
    there (from :func:`rockcem.variables.md_error_trusted`: ``md_trusted``, or its fallback on
    a Dataset written before it existed)."""
    import numpy as np

    from .variables import md_error_trusted

    if not members:
        return []
    names = [v for v in ("vp", "vs") if v in ds.data_vars]
    source = "md_trusted" if "md_trusted" in ds.data_vars else \
        "md_resolution_asymptotic = 1 and error < value"
    lines = [f"  MD members at their depths ({', '.join(names)} in km/s ± total error;",
             f"  trusted: {source}):"]
    for m in members:
        errors = {v: md_error_trusted(ds, v, model=m) for v in names}
        ran = np.flatnonzero(np.isfinite(ds[names[0]].sel(model=m).values))
        lines.append(f"  {m}:")
        lines.append(f"    {'depth (m)':>9}" + "".join(f"  {v + ' ± error':>15}" for v in names)
                     + "  trusted")
        for k in ran:
            row = f"    {float(ds.depth[k]):>9g}"
            for v in names:
                value = float(ds[v].sel(model=m).values[k])
                error = float(errors[v][0].values[k])
                text = f"{value:.3f} ± " + (f"{error:.3f}" if np.isfinite(error) else "n/a")
                row += f"  {text:>15}"
            flag = float(errors[names[0]][1].values[k])
            row += "  " + ("yes" if flag == 1.0 else "no" if flag == 0.0 else "n/a")
            lines.append(row)
    return lines


def _run_md(raw, args, scene_file) -> int:
    """An MD scene (a TOML with an [md] table): packs, cement, pulse tests (numba's md)."""
    from md.experiment import md_scene_from_dict, run_md_scene

    from .scene import write_dataset

    scene = md_scene_from_dict(raw)
    if args.max_members is not None:
        raise ValueError("--max-members bounds the sweep of a scene; an MD scene has no sweep")
    out = output_file(args.output, scene["output"])
    if args.output is None:
        unasked_output(out, scene_file)
    # Stage files beside the output (<stem>_work), unless the scene names a folder.
    work = scene["md"]["workdir"] or Path(out).with_name(Path(out).stem + "_work")
    stage_folder(work, out, what="md.workdir" if scene["md"]["workdir"] else "the stage folder")
    ds = run_md_scene(scene, workdir=work, jobs=args.jobs, scheduler=args.scheduler,
                      progress=not args.quiet)
    ds.attrs[SCENE_FILE_ATTR] = str(Path(scene_file).resolve())
    path = write_dataset(ds, out)
    if not args.quiet:
        print(_md_summary(ds))
        print(f"wrote {path}")
    return 0


#: Rows of the MD study summary: label, variable suffix (after ``vp``/``vs``).
_MD_ROWS = (("pulse", ""), ("± eq. 11", "_error"), ("± resolution", "_error_resolution"),
            ("static", "_static"))


def _md_summary(ds, *, width=100) -> str:
    """The summary ``rockcem run`` prints of an MD study's output: for every sample, cement and
    scheme, a block of rows against cement saturation S_c — the pulse velocity, its eq. 11
    error, its resolution error and the velocity of the static modulus (those of the four
    that ``ds`` has), each to 3 decimals in the units of its attributes (named once above the
    table). A table wider than ``width`` characters is split into several over S_c."""
    import textwrap

    import numpy as np

    v = next(n for n in ("vp", "vs") if n in ds.data_vars)
    keys = [d for d in ("sample", "cement", "scheme") if d in ds[v].dims]
    rows = [(label, f"{v}{suffix}") for label, suffix in _MD_ROWS if f"{v}{suffix}" in ds]
    lines = textwrap.wrap(f"MD scene {ds.attrs.get('scene_name', '?')}: {v} against cement "
                          f"saturation S_c, per {', '.join(keys) or 'member'}:", width)
    tag = max(len(label) for label, _ in rows)
    for label, name in rows:
        attrs = ds[name].attrs
        lines.extend(textwrap.wrap(f"{label:<{tag}}  {attrs.get('long_name', name)} "
                                   f"({attrs.get('units', 'no units')})", width,
                                   initial_indent="  ", subsequent_indent=" " * (tag + 4)))
    labels = [[str(x) for x in ds[d].values] for d in keys]
    widths = [max(map(len, ls)) for ls in labels]
    sat = [f"{x:g}" for x in ds["saturation"].values]
    cells = {name: ds[name].transpose(*keys, "saturation").values for _, name in rows}
    cell = max(7, max(map(len, sat)) + 2)
    left = sum(w + 2 for w in widths) + tag
    per_table = max(1, (width - left) // cell)
    for start in range(0, len(sat), per_table):
        cols = slice(start, start + per_table)
        lines.append(f"{'S_c':>{left}}" + "".join(f"{x:>{cell}}" for x in sat[cols]))
        previous = [None] * len(keys)
        for index in np.ndindex(*(len(ls) for ls in labels)):
            names = [ls[i] for ls, i in zip(labels, index)]
            head = "".join((n if names[:k + 1] != previous[:k + 1] else "").ljust(w + 2)
                           for k, (n, w) in enumerate(zip(names, widths)))
            previous = names
            for k, (label, name) in enumerate(rows):
                values = cells[name][index][cols]
                lines.append((head if k == 0 else " " * len(head)) + f"{label:<{tag}}"
                             + "".join(f"{x:>{cell}.3f}" for x in values))
    return "\n".join(lines)


def _run(args) -> int:
    from .scene import read_scene_toml, run_scene, scene_from_dict, scene_path, write_dataset

    check_scheduler(args.scheduler, name="--scheduler")
    raw, text = read_scene_toml(args.scene)
    scene_file = scene_path(args.scene)
    if "md" in raw:
        return _run_md(raw, args, scene_file)
    scene = scene_from_dict(raw, text=text, base_dir=scene_file.parent)
    out = output_file(args.output, scene.output)
    if args.output is None:
        unasked_output(out, scene_file)
    if scene.layers:                    # a stack: its MD layers' stages follow -o
        scene = dataclasses.replace(scene, output=str(out))
    elif "md" in scene.models:
        # The stage folder follows the file written (-o), as the docs say: <output
        # stem>_md_work, unless models.md.workdir names one.
        scene = dataclasses.replace(scene, output=str(out))
        work = scene.sections["models.md"]["workdir"]
        stage_folder(work or Path(out).with_name(Path(out).stem + "_md_work"), out,
                     what="models.md.workdir" if work else "the stage folder")
    limit = {} if args.max_members is None else {"max_members": args.max_members}
    ds = run_scene(scene, scheduler=args.scheduler, jobs=args.jobs, progress=not args.quiet,
                   **limit)
    ds.attrs[SCENE_FILE_ATTR] = str(scene_file.resolve())
    path = write_dataset(ds, out)
    if not args.quiet:
        print(_summary(ds))
        print(f"wrote {path}")
    return 0


def _demo(args) -> int:
    from .scene import load_scene, run_scene, write_dataset

    from .scene import scene_path

    scene = load_scene("carcione2022_sandstone")
    output_file(None, f"{scene.name}.nc")
    unasked_output(f"{scene.name}.nc", scene_path(scene.name))
    output_file(None, f"{scene.name}.png", figure=True)
    ds = run_scene(scene, progress=not args.quiet)
    ds.attrs[SCENE_FILE_ATTR] = str(scene_path(scene.name).resolve())
    nc = write_dataset(ds, f"{scene.name}.nc")
    png = None
    try:
        from .plots import depth_trends, save_figure
    except ImportError:  # plots are optional for the demo's data file
        depth_trends = None
    if depth_trends is not None:
        png = save_figure(depth_trends(ds), f"{scene.name}.png")
    if not args.quiet:
        print(_summary(ds))
        print(f"wrote {nc}" + (f" and {png}" if png else ""))
    return 0


def _plot(args) -> int:
    from pathlib import Path

    import xarray as xr

    from . import plots

    path = Path(args.file)
    if not path.is_file():
        from ._cli_files import no_such_file

        raise ValueError(no_such_file(args.file))
    if args.output is not None:
        output_file(args.output, None, figure=True)
    try:
        ds = xr.load_dataset(path, engine="netcdf4")
    except (OSError, ValueError) as exc:
        raise ValueError(f"{args.file} is not a readable netCDF file: {exc}") from None
    asked = args.kind
    args.kind = _plot_kind(ds, args, path)
    if args.depth and args.kind not in ("avo", "sensitivity", "template"):
        raise ValueError("--depth chooses the depths of the reflectivity chart of --kind avo, "
                         "of the tornado of --kind sensitivity and of the member clouds of "
                         "--kind template")
    if args.variable is not None and args.kind != "sensitivity":
        raise ValueError("--variable chooses the output of --kind sensitivity")
    if (args.twt or args.trace_scale) and args.kind != "synthetic":
        raise ValueError(f"--{'twt' if args.twt else 'trace-scale'} applies to --kind "
                         "synthetic")
    if args.kind == "md-study":
        ds = _select(ds, args.select or [])
        out = output_file(args.output, _default_figure(path, args), figure=True)
        saved = plots.save_figure(plots.md_study_velocity(ds), out)
        if not args.quiet:
            print(f"wrote {saved}")
        return 0
    if args.kind in ("vp-porosity", "template") and ds.attrs.get("lithology") != "sandstone":
        drawn = {"vp-porosity": "the contact models", "template": "the patchy-cement template"}
        raise ValueError(f"--kind {args.kind} draws {drawn[args.kind]} of a sandstone; "
                         f"{path.name} is not a sandstone scene")
    ds = _select(ds, args.select or [])
    if args.well:
        from .cli_wells import plot_with_well

        return plot_with_well(ds, args, path)
    if args.kind in ("avo", "synthetic"):
        return _plot_seismic(ds, args, path)
    if args.kind == "avo-probability" or "avo_class_probability" in ds.data_vars:
        if args.kind != "avo-probability":
            raise ValueError(f"--kind {args.kind} draws a single scene's output; {path.name} "
                             f"is a stack with [uncertain]: draw it with --kind avo-probability")
        out = output_file(args.output, _default_figure(path, args), figure=True)
        saved = plots.save_figure(plots.avo_class_probability(ds), out)
        if not args.quiet:
            print(f"wrote {saved}")
        return 0
    if asked is None and args.kind == "band" and "quantile" not in ds.dims:
        args.kind = "depth"                 # --select quantile=...: that quantile's trends
    if args.kind in ("band", "sensitivity") or "quantile" in ds.dims:
        return _plot_uncertain(ds, args, path)
    if args.depth:
        raise ValueError(f"--depth chooses the depths of the member clouds of --kind template; "
                         f"{path.name} has no members (a scene with [uncertain] members = true)")
    draw = {"depth": plots.depth_trends, "vp-porosity": plots.velocity_porosity,
            "template": plots.rock_physics_template}[args.kind]
    out = output_file(args.output, _default_figure(path, args), figure=True)
    saved = plots.save_figure(draw(ds), out)
    if not args.quiet:
        print(f"wrote {saved}")
    return 0


def _plot_uncertain(ds, args, path) -> int:
    """The figures of a scene with ``[uncertain]``: ``band`` (quantile bands along depth, per
    model; ``depth`` is the same figure), ``sensitivity`` (the tornado of the Sobol' indices of
    ``--variable`` at ``--depth``, one row per model), ``template`` (the members' clouds; a
    Dataset without members is refused, as is a single-valued kind such as ``vp-porosity`` on
    quantiles, each in one line naming what to do)."""
    from . import plots

    members = "member" in ds.dims and "vp_members" in ds.data_vars
    if args.kind == "band" and "quantile" not in ds.dims:
        raise ValueError(f"--kind band draws the quantile bands of a scene with [uncertain]; "
                         f"{path.name} has no quantile dimension (plot it with --kind depth)")
    if args.kind == "sensitivity" and not any(str(v).endswith("_sobol_total")
                                              for v in ds.data_vars):
        raise ValueError(f"--kind sensitivity draws Sobol' indices; {path.name} has none: run "
                         "the scene with sensitivity = true in [uncertain]")
    if args.kind == "template" and not members:
        raise ValueError(f"--kind template of a scene with [uncertain] draws the members' "
                         f"clouds; {path.name} keeps the quantiles only: run the scene with "
                         "members = true in [uncertain] (or --select quantile=0.5 for the "
                         "medians)")
    if args.kind == "vp-porosity":
        raise ValueError(f"--kind vp-porosity draws one value per depth; {path.name} holds "
                         "quantiles of uncertain members: --kind band draws them, or "
                         "--select quantile=0.5 draws one quantile")
    out = output_file(args.output, _default_figure(path, args), figure=True)
    if args.kind in ("band", "depth"):
        fig = plots.depth_bands(ds)
    elif args.kind == "template":
        fig = plots.member_template(ds, args.depth)
    else:
        fig = _sensitivity_figure(ds, args.variable or "vp", args.depth)
    saved = plots.save_figure(fig, out)
    if not args.quiet:
        print(f"wrote {saved}")
    return 0


def _sensitivity_figure(ds, variable, depths):
    """The tornado of :func:`rockcem.plots.sobol_tornado` of ``variable`` at ``depths`` (default
    :func:`rockcem.plots.uncertainty.default_depths`), one row per model of its indices."""
    import matplotlib.pyplot as plt

    from . import plots
    from .plots.uncertainty import default_depths

    name = f"{variable}_sobol_total"
    if name not in ds.data_vars:
        have = sorted(str(v).removesuffix("_sobol_total") for v in ds.data_vars
                      if str(v).endswith("_sobol_total"))
        raise ValueError(f"--variable {variable}: the file has no Sobol' indices of it (it has "
                         f"those of {', '.join(have)})")
    depths = depths or default_depths(ds)
    low, high = float(ds["depth"].min()), float(ds["depth"].max())
    outside = [d for d in depths if not low <= d <= high]
    if outside:
        raise ValueError(f"--depth {outside[0]:g}: outside the file's depths ({low:g}-{high:g} m)")
    models = [str(m) for m in ds["model"].values] if "model" in ds[name].dims else [None]
    inputs = ds.sizes["input"]
    fig = plt.figure(figsize=(3.2 * len(depths) + 1.8, (0.45 * inputs + 1.6) * len(models)),
                     layout="constrained")
    rows = fig.subfigures(len(models), 1, squeeze=False)[:, 0]
    for row, model in zip(rows, models):
        plots.sobol_tornado(ds, variable, depths, model=model, fig=row)
    return fig


#: The figures of ``rockcem plot --kind avo``: the suffix each adds to the name, and its function.
_AVO_FIGURES = (("class", "avo_class_depth"), ("crossplot", "intercept_gradient_crossplot"),
                ("angle", "reflectivity_angle"))


def _plot_seismic(ds, args, path) -> int:
    """``--kind synthetic``: the synthetic traces, one file. ``--kind avo``: three files, the
    name (``-o``, else ``<stem>[_<selection>]_avo.png``) with ``_class`` (AVO class against
    depth), ``_crossplot`` (intercept against gradient) and ``_angle`` (R_PP against angle at
    ``--depth``, default :func:`_avo_depths`) before its suffix. Every file is checked before
    any is drawn, and every figure drawn before any is written."""
    from . import plots

    name = args.output if args.output is not None else _default_figure(path, args)
    if args.kind == "synthetic":
        out = output_file(args.output, name, figure=True)
        if args.twt:
            t0, t1 = args.twt
            t = ds["twt"].values
            if not (t0 < t1 and ((t >= t0) & (t <= t1)).sum() >= 2):
                raise ValueError(f"--twt {t0:g} {t1:g}: give a window of two-way time (s), "
                                 f"first below second, holding at least two samples of the "
                                 f"synthetic (it covers {t[0]:g}-{t[-1]:g} s)")
            ds = ds.sel(twt=slice(t0, t1))
        scale = "trace" if args.trace_scale else "common"
        saved = [plots.save_figure(plots.synthetic_section(ds, scale=scale), out)]
    else:
        name = Path(name)
        outs = [output_file(None if args.output is None else
                            str(name.with_name(f"{name.stem}_{part}{name.suffix}")),
                            name.with_name(f"{name.stem}_{part}{name.suffix}"), figure=True)
                for part, _ in _AVO_FIGURES]
        depths = args.depth or _avo_depths(ds)
        figures = []
        try:
            for part, draw in _AVO_FIGURES:
                extra = {"depths": depths} if part == "angle" else {}
                figures.append(getattr(plots, draw)(ds, **extra))
        except ValueError:
            import matplotlib.pyplot as plt

            for fig in figures:
                plt.close(fig)
            raise
        saved = [plots.save_figure(fig, out) for fig, out in zip(figures, outs)]
    if not args.quiet:
        print("wrote " + ", ".join(map(str, saved)))
    return 0


def _avo_depths(ds) -> list[float]:
    """Depths (m) of the reflectivity chart of ``rockcem plot --kind avo`` when ``--depth`` is
    not given: the whole kilometres within the file's depth range (four evenly spread of them
    where there are more), else the depths at a quarter, half and three quarters of the
    range."""
    import numpy as np

    low, high = float(ds["depth"].min()), float(ds["depth"].max())
    km = np.arange(np.ceil(low / 1000.0), np.floor(high / 1000.0) + 1.0) * 1000.0
    if km.size > 4:
        km = km[np.round(np.linspace(0, km.size - 1, 4)).astype(int)]
    if km.size >= 2:
        return km.tolist()
    return [low + q * (high - low) for q in (0.25, 0.5, 0.75)]


def _default_figure(path, args):
    """``<stem>[_<selection>]_<kind>.png`` beside the file: each ``--select KEY=VALUE`` adds
    ``KEY-VALUE`` (characters other than letters, digits, ``.`` and ``-`` become ``_``), so
    figures of different members do not replace each other."""
    import re

    tags = [re.sub(r"[^A-Za-z0-9.-]+", "_", item.replace("=", "-"))
            for item in (args.select or [])]
    return path.with_name("_".join([path.stem, *tags, args.kind]) + ".png")


def _plot_kind(ds, args, path) -> str:
    """The figure ``rockcem plot`` draws of ``ds``: ``--kind``, or by default ``depth`` for a
    scene's output (dimension ``depth``; ``band`` for one with ``[uncertain]``'s ``quantile``
    dimension; ``avo`` for a stack's with ``avo_class``) and
    ``md-study`` for an MD study's (dimension ``saturation``, no ``depth``); a one-line ValueError for a file that is neither, or a kind
    that does not fit the file."""
    dims = ", ".join(map(str, ds.dims)) or "none"
    if "depth" in ds.dims:
        if args.kind == "md-study":
            raise ValueError(f"--kind md-study draws an MD study (dimension saturation); "
                             f"{path.name} is a scene's output (dimensions: {dims})")
        if args.kind in ("avo", "synthetic") and "avo_class_probability" in ds.data_vars:
            raise ValueError(f"{path.name} is a stack with [uncertain]: draw the probability "
                             f"of each AVO class along depth with --kind avo-probability "
                             f"(an uncertain stack has no single class or synthetic)")
        need = {"avo": "avo_class", "synthetic": "synthetic",
                "avo-probability": "avo_class_probability"}.get(args.kind)
        if need == "avo_class_probability" and need not in ds.data_vars:
            raise ValueError(f"{path.name} has no avo_class_probability: run a stack scene "
                             f"with [seismic] and [uncertain]")
        if need is not None and need not in ds.data_vars:
            raise ValueError(f"{path.name} has no {need}: run a stack scene with [seismic] "
                             f"to compute the AVO variables and synthetics")
        if args.kind is None and "avo_class" in ds.data_vars and not args.well:
            return "avo"                    # a stack with [seismic]: its AVO charts
        if args.kind is None and "avo_class_probability" in ds.data_vars and not args.well:
            return "avo-probability"        # ... and with [uncertain]: each class's share
        if args.kind is None and "quantile" in ds.dims and not args.well:
            return "band"                   # [uncertain]: quantile bands along depth
        return args.kind or "depth"
    if "saturation" not in ds.dims:
        raise ValueError(f"{path.name} is neither a scene's output (dimension depth) nor an MD "
                         f"study's (dimension saturation); its dimensions: {dims}")
    if args.kind not in (None, "md-study") or args.well:
        asked = f"--kind {args.kind}" if args.kind not in (None, "md-study") else "--well"
        raise ValueError(f"{path.name} is an MD study (velocity against cement saturation): "
                         f"{asked} draws a scene's output along depth; plot the file without it")
    return "md-study"


def _select(ds, selections):
    """``ds`` reduced by ``--select KEY=VALUE`` options (KEY a sweep dimension, or the scene key
    ``section.key`` that made it; several values of one key accumulate)."""
    import numpy as np

    chosen = {}
    for item in selections:
        key, eq, text = item.partition("=")
        from .variables import sweep_dimension

        dim = sweep_dimension(key.strip()) if "." in key else key.strip()
        if not eq or not dim or not text.strip():
            raise ValueError(f"--select {item!r}: expected KEY=VALUE, e.g. gradient=30")
        if dim not in ds.dims or dim == "depth":
            sweeps = [str(d) for d in ds.dims if d != "depth"]
            raise ValueError(f"--select {item}: {dim!r} is not a sweep dimension of the file "
                             f"(dimensions: {', '.join(sweeps) or 'none'})")
        values = ds[dim].values
        if np.issubdtype(values.dtype, np.number):
            try:
                value = float(text)
            except ValueError:
                raise ValueError(f"--select {item}: {text!r} is not a number") from None
            match = np.flatnonzero(np.isclose(values.astype(float), value, rtol=1e-9, atol=0))
        else:
            match = np.flatnonzero(values.astype(str) == text.strip())
        if match.size == 0:
            shown = ", ".join(f"{v:g}" if isinstance(v, (int, float, np.number)) else str(v)
                              for v in values)
            raise ValueError(f"--select {item}: no such value of {dim} (values: {shown})")
        picked = chosen.setdefault(dim, [])
        if int(match[0]) not in picked:         # the same value twice is that value once
            picked.append(int(match[0]))
    # One model stays a model dimension (its colour and line style); a single value of a
    # sweep dimension becomes a scalar coordinate, which the figure names.
    return ds.isel({d: i if len(i) > 1 or d == "model" else i[0] for d, i in chosen.items()})


def _scenes(args) -> int:
    import tomllib

    from .scene import scene_path, shipped_scenes

    if args.name is None:
        if args.output is not None:
            raise ValueError("-o writes one shipped scene: give its name (rockcem scenes NAME "
                             "-o FILE)")
        for name, path in shipped_scenes().items():
            with open(path, "rb") as fh:
                desc = tomllib.load(fh).get("description", "")
            print(f"{name:<40} {desc}")
        return 0
    if args.name not in shipped_scenes():
        scene_path(args.name)               # no such scene: the message with "did you mean"
        raise ValueError(f"{args.name!r} is a file, not a shipped scene: rockcem scenes "
                         "lists them")
    text = shipped_scenes()[args.name].read_text()
    if args.output is None:
        sys.stdout.write(text)
        return 0
    from ._atomic import atomic_write

    out = output_file(args.output, None)
    path = atomic_write(out, lambda tmp: Path(tmp).write_text(text))
    print(f"wrote {path}: edit it, then rockcem run {path}")
    return 0


def _schema(args) -> int:
    from .scene import _REQUIRED, SCHEMA

    def shown(default):
        return "required" if default is _REQUIRED else "-" if default is None else repr(default)

    # Columns as wide as their widest entry (a long unit or default never runs into the next).
    rows = [row for keys in SCHEMA.values() for row in keys.items()]
    w_key = max(len(k) for k, _ in rows)
    w_kind = max(len(v[1]) for _, v in rows)
    w_unit = max(len(v[2]) for _, v in rows)
    w_default = max(len(shown(v[0])) for _, v in rows)
    for section, keys in SCHEMA.items():
        print(f"[{section}]" if section != "scene" else "(top level)")
        for key, (default, kind, unit, doc) in keys.items():
            print(f"  {key:<{w_key}}  {kind:<{w_kind}}  {unit:<{w_unit}}  "
                  f"default {shown(default):<{w_default}}  {doc}")
    print("[sweep]\n  \"section.key\" = [values, ...]  one dimension per swept parameter")
    print("\nMD scenes (a table [md] instead of the sections above; run by the md engine):")
    from md.experiment import schema_lines

    for line in schema_lines():
        print("  " + line)
    return 0


def _parser() -> argparse.ArgumentParser:
    from . import __version__
    from .cli_wells import add_commands, add_well_options

    parser = argparse.ArgumentParser(prog="rockcem", description="Rock physics of burial history.")
    parser.add_argument("--version", action="version", version=f"rockcem {__version__}")
    sub = parser.add_subparsers(dest="command", required=True)
    p = sub.add_parser("materials", help="list the mineral and fluid catalogue")
    p.set_defaults(func=_materials)
    p = sub.add_parser("scenes", help="list the shipped scenes, or print or write one out to "
                                      "start from")
    p.add_argument("name", nargs="?", default=None,
                   help="a shipped scene: print its TOML (or write it with -o)")
    p.add_argument("-o", "--output", help="file to write the scene to (its data files, such as "
                                          "a horizon table or a calibration, resolve by name "
                                          "from anywhere)")
    p.set_defaults(func=_scenes)
    p = sub.add_parser("schema", help="list every scene key with its type, unit and default")
    p.set_defaults(func=_schema)
    p = sub.add_parser("run", help="run a scene (a TOML file or a shipped scene name)")
    p.add_argument("scene", help="scene file or shipped scene name (see `rockcem scenes`)")
    p.add_argument("-o", "--output", help="netCDF file to write (default: the scene's output)")
    p.add_argument("--scheduler", default=None,
                   help="run a sweep, or the MD members of a scene or an MD study, on dask: "
                        "'local' or a scheduler address (needs [dask])")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    p.add_argument("-j", "--jobs", type=_positive_int, default=1,
                   help="processes for the MD members (pulse tests of an MD study, depths and "
                        "schemes of [models.md]); workers of --scheduler local (default 1)")
    p.add_argument("--max-members", type=_positive_int, default=None,
                   help="most sweep members to run (default "
                        "rockcem.scene.MAX_SWEEP_MEMBERS, 10000); a larger sweep is refused "
                        "before any work")
    p.set_defaults(func=_run)
    p = sub.add_parser("plot", help="draw a figure of a scene's netCDF file")
    p.add_argument("file", help="netCDF file written by `rockcem run`")
    p.add_argument("--kind", choices=["depth", "vp-porosity", "template", "band", "sensitivity",
                                      "avo", "avo-probability", "synthetic", "md-study"],
                   default=None,
                   help="depth trends (the default for a scene's file without [uncertain]), "
                        "velocity-porosity, the rock-physics template; of a scene with "
                        "[uncertain], band (quantile "
                        "bands along depth per model, the median as a line; the default), "
                        "sensitivity (the tornado of Sobol' indices of --variable at --depth, "
                        "one row per model; needs sensitivity = true) or template (the members' "
                        "clouds at --depth; needs members = true); of a stack scene's file, avo "
                        "(three files: the "
                        "AVO class against depth, the intercept-gradient crossplot and R_PP "
                        "against angle, the name with _class, _crossplot, _angle before its "
                        "suffix; the default for a stack with [seismic]) or synthetic (the "
                        "synthetic traces), and of a stack with [uncertain], avo-probability "
                        "(the share of the members in each AVO class against depth; the "
                        "default there); or an MD study's "
                        "velocity against cement saturation (the default, and the only kind, "
                        "for an MD study's file)")
    p.add_argument("--depth", action="append", type=float, metavar="M",
                   help="--kind avo: a depth (m) of the R_PP-against-angle chart (repeat for "
                        "more; default the whole kilometres within the file's range, at most "
                        "four); --kind sensitivity: a depth of the tornado, --kind template of "
                        "a file with members: a depth of the clouds (default 2000, 3000, 4000 "
                        "as far as the file reaches)")
    p.add_argument("--variable", default=None, metavar="NAME",
                   help="--kind sensitivity: the output whose Sobol' indices are drawn "
                        "(temperature, porosity, density, vp or vs; default vp)")
    p.add_argument("--twt", type=float, nargs=2, metavar=("T0", "T1"),
                   help="--kind synthetic: the window of two-way time drawn, s (default the "
                        "whole synthetic)")
    p.add_argument("--trace-scale", action="store_true",
                   help="--kind synthetic: scale each trace to its own peak (default one gain "
                        "for every trace of a row, so amplitudes compare)")
    p.add_argument("--select", action="append", metavar="KEY=VALUE",
                   help="draw only these values of a sweep dimension (e.g. gradient=30 or "
                        "path.gradient=30; repeat for more values or dimensions), or of "
                        "model or quantile (quantile=0.5: the medians as depth trends)")
    p.add_argument("-o", "--output", help="figure file (.png, .pdf, .svg)")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="print nothing (with --well: the read report's warnings only)")
    add_well_options(p, required=False)
    p.set_defaults(func=_plot)
    add_commands(sub)
    p = sub.add_parser("demo", help="run the sandstone example; write a netCDF file and a figure")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    p.set_defaults(func=_demo)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of the ``rockcem`` console script."""
    import warnings

    from .validity import RockcemValidityWarning

    parser = _parser()
    args = parser.parse_args(argv)
    try:
        with warnings.catch_warnings():
            # The run summary prints the validity warnings (and the file holds them): as
            # Python warnings too they would reach the terminal twice.
            warnings.simplefilter("ignore", RockcemValidityWarning)
            return args.func(args)
    except (ValueError, FileNotFoundError) as exc:
        print(f"rockcem: error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into `head` and friends
        return 0
    except KeyboardInterrupt:  # Ctrl-C: one line, the shell's code for SIGINT
        print("rockcem: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
