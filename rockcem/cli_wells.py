"""The well commands of the ``rockcem`` command line: ``compare``, ``fit``, ``wells`` and
``plot --well`` (each prints the well's read report: what was read, kept and blanked).

Kept apart from :mod:`rockcem.cli`, which registers them (:func:`add_commands`).
"""

from __future__ import annotations

import os
from pathlib import Path

from ._cli_files import no_such_file, output_file

__all__ = ["add_commands", "add_well_options", "plot_with_well"]


def _curves(items):
    """``--curve VARIABLE=MNEMONIC`` options as ``{variable: mnemonic or None}``."""
    curves = {}
    for item in items or []:
        var, eq, mnemonic = item.partition("=")
        if not eq or not var.strip() or not mnemonic.strip():
            raise ValueError(f"--curve {item}: expected VARIABLE=MNEMONIC, e.g. vp=DTCO "
                             "(or vp=none to leave vp out)")
        mnemonic = mnemonic.strip()
        curves[var.strip()] = None if mnemonic.lower() == "none" else mnemonic
    return curves


def _well(args):
    """The well of ``--well``, read with ``--curve``, ``--null`` and ``--depth-offset``; its
    read report printed (unless ``--quiet``, which prints the warnings instead)."""
    import sys
    import warnings

    from .wells import WellLogWarning, format_read_report, read_well

    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always", WellLogWarning)
        well = read_well(args.well, depth_offset=args.depth_offset,
                         null=getattr(args, "null", None),
                         curves=_curves(getattr(args, "curve", None)))
    for w in record:
        if not issubclass(w.category, WellLogWarning):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    if getattr(args, "quiet", False):
        for w in record:
            if issubclass(w.category, WellLogWarning):
                print(f"rockcem: warning: {w.message}", file=sys.stderr)
    else:
        print("read " + format_read_report(well))
    return well


def _scene_dataset(source):
    """A scene's Dataset: a netCDF file written by ``rockcem run``, or a scene to run."""
    import xarray as xr

    path = Path(source)
    if path.suffix == ".nc":
        if not path.is_file():
            raise ValueError(no_such_file(source))
        try:
            return xr.load_dataset(path, engine="netcdf4")
        except (OSError, ValueError) as exc:
            raise ValueError(f"{source} is not a readable netCDF file: {exc}") from None
    from .scene import load_scene, run_scene

    return run_scene(load_scene(source))


def _compare(args) -> int:
    import pandas as pd

    from .wells import WELL_VARIABLES, well_misfit

    if args.interface is not None:
        given = [o for o, v in (("--intervals", args.intervals), ("--band", args.band),
                                ("--figure", args.figure), ("-o", args.output))
                 if v is not None]
        if given:
            raise ValueError(f"--interface and {given[0]} do not go together: compare the AVO "
                             "of one interface, or the logs per interval")
    # The files are checked before any work: a bad name must not come after the scene's run.
    table_out = None if args.output is None else output_file(args.output, None)
    png_out = None if args.figure is None else output_file(args.figure, None,
                                                           what="--figure", figure=True)
    if table_out is not None and png_out is not None \
            and os.path.realpath(table_out) == os.path.realpath(png_out):
        raise ValueError(f"-o and --figure name the same file: {table_out}")
    well = _well(args)                        # a bad log fails before the scene runs
    if args.interface is not None:
        return _compare_interface(args, well)
    ds = _scene_dataset(args.scene)
    # The quantiles of a scene with [uncertain] are no sweep; its members (members = true)
    # are other variables.
    sweeps = sorted({d for v in WELL_VARIABLES if v in ds.data_vars for d in ds[v].dims}
                    - {"depth", "model", "quantile"})
    if sweeps:
        raise ValueError(f"{args.scene} has sweep dimensions {', '.join(sweeps)}; compare one "
                         "member (rockcem plot --select, or a scene without [sweep])")
    if args.band is not None and "quantile" not in ds.dims:
        raise ValueError(f"--band {' '.join(f'{v:g}' for v in args.band)}: {args.scene} has "
                         "no quantiles (its scene has no [uncertain] section)")
    try:
        table = well_misfit(ds, well, intervals=args.intervals, band=args.band)
    except ValueError as exc:       # name the option the user gave
        if args.intervals is not None and str(exc).startswith("intervals "):
            raise ValueError(f"--{exc}") from None
        if args.band is not None and str(exc).startswith(("band ", "band quantile ")):
            raise ValueError(f"--{exc}") from None
        raise
    if args.intervals is not None and "n" in table.columns and not (table["n"] > 0).any():
        z = well.depth.values
        raise ValueError(f"--intervals {' '.join(f'{v:g}' for v in args.intervals)}: no sample "
                         f"of the well lies in them (the log covers {z[0]:g}-{z[-1]:g} m and "
                         f"the scene {float(ds.depth[0]):g}-{float(ds.depth[-1]):g} m)")
    name = well.attrs.get("well") or Path(args.well).name
    print(f"misfit of {ds.attrs.get('scene_name', args.scene)} to {name} per depth interval "
          "(m): rms and mean (bias) of model/log - 1 for vp, vs and density, of model - log "
          "for porosity (a fraction)")
    if "band" in table.columns:
        print(_band_header(table))
    if "porosity" in table.variable.values and "comment" in well.porosity.attrs:
        print(f"porosity log {well.porosity.attrs.get('source_mnemonic', '')}: "
              f"{well.porosity.attrs['comment']}")
    with pd.option_context("display.width", 140, "display.max_rows", 500):
        # One precision for every number: four decimals, never an exponent (a bias of 7.8e-05
        # beside an rms of 0.1186 read as two kinds of number).
        depths = {c: "{:g}".format for c in ("top", "base") if c in table.columns}
        print(table.to_string(index=False, float_format=lambda v: f"{v:.4f}",
                              formatters=depths))
    if table_out is not None:
        _write_table(table, table_out)
        if not args.quiet:
            print(f"wrote {table_out}")
    if png_out is not None:
        from .plots import save_figure, well_band, well_overlay

        fig = well_band(ds, well, band=args.band) if "quantile" in ds.dims else \
            well_overlay(ds, well)
        saved = save_figure(fig, png_out)
        if not args.quiet:
            print(f"wrote {saved}")
    return 0


def _band_header(table):
    """The line that says what the band's columns of ``compare`` are."""
    low, high = table["band"].iloc[0].split("-")
    nominal = 100.0 * (float(high) - float(low))
    return (f"band: the {low}-{high} quantile band of the members (quantiles, not exceedance: "
            f"about {nominal:.0f} % of a log's samples lie in it where the scene's spread is "
            "right); n_band: log samples compared with it, inside: the share of them within "
            "it, blank: log samples in the interval without a value (not counted)")


def _write_table(table, path):
    """The table of ``compare`` as CSV (one row per variable, model and interval; the
    columns as printed), written atomically."""
    from ._atomic import atomic_write

    def write(tmp):
        table.to_csv(tmp, index=False, float_format="%.10g")

    atomic_write(path, write)


def _compare_interface(args, well) -> int:
    """``compare --interface DEPTH``: the well's AVO terms at an interface beside a stack
    scene's at the same depth."""
    import pandas as pd

    from ._well_avo import model_interface_table, well_interface_avo

    try:
        w = well_interface_avo(well, args.interface, window=args.window)
    except ValueError as exc:
        raise ValueError(f"--interface {args.interface:g}: {exc}") from None
    ds = _scene_dataset(args.scene)
    table = model_interface_table(ds, args.interface)
    name = well.attrs.get("well") or Path(args.well).name
    print(f"AVO of the interface at {w.depth:g} m: {name} (means over {w.window:g} m above and "
          f"below; {w.n_above} and {w.n_below} samples) beside "
          f"{ds.attrs.get('scene_name', args.scene)} at {float(table['depth'].iloc[0]):g} m")
    print(f"well: vp {w.vp1:.3f} over {w.vp2:.3f} km/s, vs {w.vs1:.3f} over {w.vs2:.3f} km/s, "
          f"density {w.rho1:.3f} over {w.rho2:.3f} g/cm3: A {w.intercept:.4f}, "
          f"B {w.gradient:.4f}, class {w.avo_class}")
    with pd.option_context("display.width", 140, "display.max_rows", 500):
        print(table.drop(columns="depth").to_string(
            index=False, float_format=lambda v: f"{v:.4f}"))
    return 0


def _free_keys(items):
    free = {}
    for item in items:
        key, eq, bounds = item.partition("=")
        if not eq:
            free[key.strip()] = None
            continue
        lo, colon, hi = bounds.partition(":")
        try:
            free[key.strip()] = (float(lo), float(hi))
        except ValueError:
            raise ValueError(f"--free {item}: expected KEY or KEY=LOWER:UPPER") from None
        if not colon:
            raise ValueError(f"--free {item}: expected KEY or KEY=LOWER:UPPER")
    return free


def _fit(args) -> int:
    from .plots import fit_figure, save_figure
    from .scene import load_scene, scene_path
    from .wellfit import fit_scene

    if Path(args.scene).suffix == ".nc":
        raise ValueError(f"{args.scene}: fit takes a scene (TOML file or shipped name), not "
                         "the netCDF output of a run")
    scene = load_scene(args.scene)
    # Both files are checked before the fit: a bad --figure must not come after the TOML.
    stem = scene_path(args.scene).stem
    cal_out = output_file(args.output, f"{stem}_well_fit.toml")
    png_out = output_file(args.figure, f"{stem}_well_fit.png", what="--figure", figure=True)
    if os.path.realpath(cal_out) == os.path.realpath(png_out):
        raise ValueError(f"-o and --figure name the same file: {cal_out}")
    well = _well(args)
    free = _free_keys(args.free)                  # bounds None: rockcem.wellfit's defaults
    errors = None
    if args.error:
        errors = {}
        for item in args.error:
            name, _, value = item.partition("=")
            try:
                errors[name.strip()] = float(value)
            except ValueError:
                raise ValueError(f"--error {item}: expected LOG=SIGMA, e.g. vp=0.05") from None
    try:
        fit = fit_scene(scene, well, free, model=args.model, variables=args.log,
                        depth=args.depth, errors=errors, prior=args.prior)
    except ValueError as exc:       # name the options the user gave
        text = str(exc)
        if text.startswith("prior: give errors"):
            raise ValueError("--prior needs --error for each fitted log (e.g. --error "
                             "vp=0.05): the errors weigh the logs against the priors") from None
        if text.startswith("prior: "):
            raise ValueError(f"--{text}") from None
        if "takes its bounds from its prior" in text:
            raise ValueError(f"--free {text.removeprefix('free parameter ')}".replace(
                "give it without bounds", "give it as --free KEY with --prior")) from None
        raise
    if not args.quiet:
        print(fit.summary())
    cal = fit.write_calibration(cal_out)
    png = save_figure(fit_figure(fit, well), png_out)
    if not args.quiet:
        keys = ", ".join(fit.result.values)
        print(f"wrote {cal} and {png}\nto use it: add  calibration = \"{cal}\"  at the top of "
              f"the scene and remove the keys it sets ({keys})")
    return 0


def plot_with_well(ds, args, path):
    """``rockcem plot FILE --well LOG``: the logs over the depth trends (over the quantile band
    and the median for a scene with ``[uncertain]``) or the template."""
    from . import plots

    if args.kind not in ("depth", "template"):
        raise ValueError("--well draws on --kind depth or --kind template")
    # The quantiles of a scene with [uncertain] are drawn as a band on --kind depth.
    band = args.kind == "depth" and "quantile" in ds.dims
    sweeps = [d for d in ds.dims if d not in ("depth", "model")
              and not (band and d in ("quantile", "member"))]
    if sweeps:
        raise ValueError(f"--well needs one member: select values of {', '.join(sweeps)} "
                         "with --select")
    out = output_file(args.output, path.with_name(f"{path.stem}_{args.kind}_well.png"),
                      figure=True)
    well = _well(args)
    fig = plots.well_band(ds, well) if band else plots.well_overlay(ds, well) \
        if args.kind == "depth" else plots.well_template(ds, well)
    saved = plots.save_figure(fig, out)
    if not args.quiet:
        print(f"wrote {saved}")
    return 0


def add_well_options(p, *, required):
    """The options naming a well log and how to read it."""
    p.add_argument("--well", required=required,
                   help="well log: a LAS file (1.2, 2.0, 3.0, wrapped or not) or a CSV file "
                        "(units from the header), or a shipped well's name "
                        "(`rockcem wells`)")
    p.add_argument("--depth-offset", type=float, default=0.0, metavar="M",
                   help="subtracted from the log depth to give depth below the sediment "
                        "surface (m; default 0)")
    p.add_argument("--curve", action="append", metavar="VARIABLE=MNEMONIC",
                   help="the log curve of vp, vs, density or porosity, e.g. vp=DTCO, or "
                        "vp=none to leave vp out (repeat; default: the first known mnemonic, "
                        "rockcem.wells.ALIASES)")
    p.add_argument("--null", action="append", type=float, metavar="VALUE",
                   help="a null value besides the file's own, e.g. --null -9999 (repeat)")


def _wells(args) -> int:
    """``rockcem wells``: the shipped wells, one line each."""
    import warnings

    from .wells import WellLogWarning, read_well, shipped_wells

    for name, path in shipped_wells().items():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", WellLogWarning)
            try:
                well = read_well(path)
            except ValueError as exc:
                print(f"{name:<32} ({exc})")
                continue
        z = well.depth.values
        print(f"{name:<32} {', '.join(well.data_vars):<30} {z[0]:7.1f}-{z[-1]:7.1f} m  "
              f"{well.attrs.get('well', '')}")
    return 0


def add_commands(sub):
    """Register ``compare``, ``wells`` and ``fit`` on the CLI's subparsers."""
    p = sub.add_parser("compare", help="misfit of each model to a well log per depth interval")
    p.add_argument("scene", help="netCDF file of `rockcem run`, or a scene to run")
    add_well_options(p, required=True)
    p.add_argument("--intervals", type=float, nargs="+", metavar="DEPTH",
                   help="interval boundaries in m (default: one interval over the overlap)")
    p.add_argument("--interface", type=float, metavar="DEPTH",
                   help="a stack scene's AVO: the well's intercept, gradient and class at the "
                   "interface at DEPTH m (log means over --window above and below) beside the "
                   "scene's at that depth")
    p.add_argument("--window", type=float, default=20.0, metavar="M",
                   help="with --interface: length of each averaging window, m (default 20)")
    p.add_argument("--band", type=float, nargs=2, metavar=("LOW", "HIGH"),
                   help="a scene with [uncertain]: the quantiles of the band the share of the "
                        "log inside is counted in (default the lowest and highest, 0.1 0.9)")
    p.add_argument("-o", "--output", metavar="CSV",
                   help="write the table as CSV too (columns as printed)")
    p.add_argument("--figure", metavar="PNG",
                   help="draw the logs over the scene (.png, .pdf or .svg): over the quantile "
                        "band and the median for a scene with [uncertain]")
    p.add_argument("-q", "--quiet", action="store_true",
                   help="no read report (what was read and blanked is then warned on stderr)")
    p.set_defaults(func=_compare)
    p = sub.add_parser("wells", help="list the shipped wells (names for --well)")
    p.set_defaults(func=_wells)
    p = sub.add_parser("fit", help="fit numeric scene keys to a well log by least squares (or "
                                   "a maximum a posteriori estimate with --prior)")
    p.add_argument("scene", help="scene file or shipped scene name")
    add_well_options(p, required=True)
    p.add_argument("--free", action="append", required=True, metavar="KEY[=LO:HI]",
                   help="scene key to fit, 'section.key' (repeat; bounds default for the "
                        "common keys, rockcem.wellfit.DEFAULT_BOUNDS)")
    p.add_argument("--model", help="model vp/vs come from (needed with several models)")
    p.add_argument("--log", action="append", choices=["vp", "vs", "density", "porosity"],
                   help="log to fit (repeat; default all the scene and well share)")
    p.add_argument("--depth", type=float, nargs=2, metavar=("TOP", "BASE"),
                   help="depth window in m")
    p.add_argument("--error", action="append", metavar="LOG=SIGMA",
                   help="standard deviation of a log in its units (repeat for every fitted "
                        "log; default: relative residuals)")
    p.add_argument("-o", "--output", help="calibration file to write "
                                          "(default <scene>_well_fit.toml)")
    p.add_argument("--prior", action="store_true",
                   help="use the scene's [uncertain] distributions of the free keys as priors "
                        "(their ranges as bounds): a maximum a posteriori estimate; needs "
                        "--error")
    p.add_argument("--figure", help="before/after figure (default <scene>_well_fit.png)")
    p.add_argument("-q", "--quiet", action="store_true", help="no report")
    p.set_defaults(func=_fit)
