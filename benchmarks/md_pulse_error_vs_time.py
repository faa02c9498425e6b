"""Error against run time of the MD pulse test (knobs: lattice resolution Omega, time-step factor).

The acoustic stage of :mod:`md` (García & Medina, Sects. III B-G) has two accuracy knobs: the
resolution :math:`\\Omega = \\bar R / c_w` of the cement lattice (cells per mean grain radius)
and the time-step factor of the central-difference scheme (fraction of the stability limit
:math:`2/\\omega_{max}`). The source's App. B predicts the cost of a pulse test to grow as
:math:`\\Omega^4` (cement particles :math:`\\propto \\Omega^3`, time steps
:math:`\\propto \\Omega`). Three sweeps:

(a) ``resolution``: a small settled and compacted pack (4 x 4 x 12 largest diameters, 256
    grains, :func:`md.settle` with ``fall_stiffness_factor=1e-3``, ``seed=3``, then
    :func:`md.compact` to 10 MPa) with hard contact cement (:data:`md.HARD_CEMENT`,
    ``grow_cement(..., saturation, "contact")``, default :math:`S_c = 0.1`) on lattices of
    ``--omegas`` (default 2, 3, 4, 5, 6, 8, 10, 12, 14). Recorded per Omega: the P velocity of
    :func:`md.pulse_test` (eq. 11; default detectors and slabs of two largest diameters, time-step
    factor 0.5), its eq. 11 error bar, the least-squares ``velocity_fit`` and the static
    long-wave velocity; cement particles, lattice bonds, contact bonds (grain-grain and
    grain-cement) and time steps; and the wall time of each stage: lattice build
    (:func:`md.cement_lattice`), growth, :func:`md.acoustic_system`, the static solve alone
    (:func:`md.static_modulus`) and the pulse test (which includes its own static solve).
    Error: :math:`|V_p - V_p(\\Omega_{max})| / V_p(\\Omega_{max})` against the finest run (and the
    same for the static velocity). The cost exponent is the least-squares slope of
    log(pulse wall time) against log(Omega) over Omega >= ``--fit-from`` (default 4; smaller
    lattices are dominated by fixed costs), compared with 4; the same slope is given for the
    total time (lattice + growth + system + pulse) and for the work (bonds x time steps).
(b) ``time_step``: the same pack and cement at one Omega (``--factor-omega``, default 6) with
    ``time_step_factor`` in 1.0, 0.5, 0.25, 0.1, 0.05; error against the smallest factor.
(c) ``cement_block``: the homogeneous check, a pure cement block
    (``cement_block((3, 3, 20 s), 1e-5, HARD_CEMENT, slab_thickness=s * 1e-5)``) with slabs of
    ``s`` = 4, 8, 16, 32 cells; error of the pulse velocity against the exact 3000 m/s (the
    block's static velocity is exact to rounding): the peak of the square pulse runs 2-2.5 %
    slow on the lattice and the bias shrinks slowly with the slab (pulse) length.

Timing: best of up to ``--repeat`` runs (default 3) per stage, a stage stops repeating once its
runs took ``--budget`` s (default 10 s: the largest lattices run once), after an untimed warm-up
of every stage (numba compilation and cache loads excluded). Single-threaded (``_common``).

The pack is settled once (about 70-100 s) and kept in ``--workdir`` (default
``benchmarks/results/md_pulse_pack/``, files ``settle.nc`` and ``compact.nc`` of
:func:`md.prepare_pack`); later runs load it. Delete the folder to settle again.

Output: ``benchmarks/results/md_pulse_error_vs_time.{csv,nc,png}`` (one row per run, column
``sweep`` = resolution / time_step / cement_block) and a markdown table on stdout.

Run: ``python benchmarks/md_pulse_error_vs_time.py`` (about 3-4 min on the 2-core machine of the
studies, docs/studies/index.md, with the pack cached, plus the settling the first time);
``python benchmarks/md_pulse_error_vs_time.py --quick`` for a tiny run (Omega 2-4, three
factors, two blocks: about 20 s with the pack cached).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_pulse_error_vs_time"
OMEGAS = (2, 3, 4, 5, 6, 8, 10, 12, 14)
FACTORS = (1.0, 0.5, 0.25, 0.1, 0.05)
SLAB_CELLS = (4, 8, 16, 32)
SETTLE_OPTIONS = dict(size=(4, 4, 12), fall_stiffness_factor=1e-3, seed=3, kinetic_tolerance=1e-5)
COMPACT_OPTIONS = dict(target_stress=10e6, strain_step=2e-3)
BLOCK_CELL = 1e-5                    # cell width of the cement blocks, m
ERROR_FLOOR = 1e-6                   # plotted in place of an error of exactly 0




def load_or_prepare_pack(workdir):
    """The compacted 4 x 4 x 12 pack, from ``workdir`` if it was prepared before."""
    import md

    t0 = time.perf_counter()
    pack = md.prepare_pack(workdir, settle_options=SETTLE_OPTIONS, compact_options=COMPACT_OPTIONS)
    meta = pack.metadata
    expected = {"seed": SETTLE_OPTIONS["seed"],
                "fall_stiffness_factor": SETTLE_OPTIONS["fall_stiffness_factor"],
                "size_diameters": [float(s) for s in SETTLE_OPTIONS["size"]]}
    got = {k: meta.get(k) for k in expected}
    if got != expected or pack.stage != "compact":
        raise RuntimeError(f"the pack in {workdir} was made with {got} (stage {pack.stage!r}), "
                           f"not {expected}: delete the folder or give another --workdir")
    return pack, time.perf_counter() - t0


def timed(fn, args):
    best, _, result, warns = _common.best_of(fn, args.repeat, budget_s=args.budget)
    return best, result, warns


def run_pack_case(pack, omega, factor, args):
    """Lattice, growth, system, static solve and pulse test at one Omega and time-step factor."""
    import md

    t_lat, lat, w1 = timed(lambda: md.cement_lattice(pack, omega), args)
    t_grow, cem, w2 = timed(lambda: md.grow_cement(lat, args.saturation, "contact"), args)
    t_sys, system, w3 = timed(lambda: md.acoustic_system(pack, lat, cem, md.HARD_CEMENT,
                                                          rotations=False), args)
    t_static, st, w4 = timed(lambda: md.static_modulus(system, "p"), args)
    row = dict(omega=float(omega), time_step_factor=float(factor), slab_cells=0,
               n_particles=system.n_particles, n_cement=int(system.metadata["n_cement"]),
               n_lattice_bonds=int(system.lattice_i.size), n_contact_bonds=int(system.bond_i.size),
               cell_width_m=float(lat.cell_width), lattice_cells=int(np.prod(lat.shape)),
               pore_cells=int(lat.index.size), static_cg_iterations=int(st.iterations),
               seconds_lattice=t_lat, seconds_grow=t_grow, seconds_system=t_sys,
               seconds_static=t_static)
    try:
        t_pulse, ds, w5 = timed(lambda: md.pulse_test(system, "p", time_step_factor=factor), args)
    except (RuntimeError, ValueError) as exc:
        row.update(status=f"{type(exc).__name__}: {exc}", seconds_pulse=np.nan,
                   warnings=" | ".join(w1 + w2 + w3 + w4))
        return row
    row.update(_pulse_columns(ds), seconds_pulse=t_pulse,
               seconds_total=t_lat + t_grow + t_sys + t_pulse, status="ok",
               warnings=" | ".join(dict.fromkeys(w1 + w2 + w3 + w4 + w5)))
    return row


def _pulse_columns(ds):
    steps = int(ds.sizes["time"])                 # record_every = 1: one record per step
    return dict(velocity=float(ds.velocity), velocity_error_eq11=float(ds.velocity_error),
                velocity_fit=float(ds.velocity_fit), velocity_static=float(ds.velocity_static),
                n_steps=steps, time_step_s=float(ds.attrs["time_step_s"]),
                detectors=f"{ds.attrs['detectors'][0]}-{ds.attrs['detectors'][1]}",
                n_slabs=int(ds.sizes["slab"]))


def run_block_case(s, args):
    """The homogeneous check: a pure cement block with slabs of ``s`` cells, 20 slabs."""
    import md

    block = md.cement_block((3, 3, 20 * s), BLOCK_CELL, md.HARD_CEMENT,
                            slab_thickness=s * BLOCK_CELL)
    t_pulse, ds, warns = timed(lambda: md.pulse_test(block, "p"), args)
    row = dict(omega=np.nan, time_step_factor=0.5, slab_cells=int(s),
               n_particles=block.n_particles, n_cement=block.n_particles,
               n_lattice_bonds=int(block.lattice_i.size), n_contact_bonds=0,
               cell_width_m=BLOCK_CELL, seconds_pulse=t_pulse, seconds_total=t_pulse,
               status="ok", warnings=" | ".join(warns))
    row.update(_pulse_columns(ds))
    return row


def fit_exponent(x, y):
    """Least-squares slope of log y against log x (nan for fewer than two finite points)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    ok = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
    if ok.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(x[ok]), np.log(y[ok]), 1)[0])



def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--omegas", type=float, nargs="+", default=OMEGAS,
                        help="lattice resolutions of the sweep; the largest is the reference")
    parser.add_argument("--factors", type=float, nargs="+", default=FACTORS,
                        help="time-step factors; the smallest is the reference")
    parser.add_argument("--factor-omega", type=float, default=6.0,
                        help="Omega of the time-step sweep (default 6)")
    parser.add_argument("--slab-cells", type=int, nargs="+", default=SLAB_CELLS,
                        help="slab thicknesses of the cement-block check, cells")
    parser.add_argument("--saturation", type=float, default=0.1, help="S_c (default 0.1)")
    parser.add_argument("--fit-from", type=float, default=4.0,
                        help="smallest Omega in the cost-exponent fit (default 4)")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per stage (best kept)")
    parser.add_argument("--budget", type=float, default=10.0,
                        help="a stage stops repeating after this many seconds (default 10)")
    parser.add_argument("--workdir", type=Path, default=_common.RESULTS / "md_pulse_pack",
                        help="folder of the cached pack (default results/md_pulse_pack)")
    parser.add_argument("--quick", action="store_true",
                        help="tiny run: Omega 2 3 4, factors 1 0.5 0.25 at Omega 3, blocks 4 8")
    parser.add_argument("--tag", default="",
                        help="suffix of the result file names, e.g. a commit (default none)")
    parser.add_argument("--no-plot", action="store_true")
    args = parser.parse_args(argv)
    if args.quick:
        args.omegas, args.factors, args.factor_omega = (2, 3, 4), (1.0, 0.5, 0.25), 3.0
        args.slab_cells, args.repeat, args.fit_from = (4, 8), 1, 2.0
    omegas = sorted({float(o) for o in args.omegas})
    factors = sorted({float(f) for f in args.factors}, reverse=True)
    slabs = sorted({int(s) for s in args.slab_cells})

    import pandas as pd
    import xarray as xr

    import md

    _common.announce_source()
    md_src = _common.md_source_attrs()
    print(f"md from {md_src['md_path']}, uncommitted: {md_src['git_uncommitted_md_files']}, "
          f"sources sha256 {md_src['md_source_sha256'][:12]}", flush=True)

    t_start = time.perf_counter()
    pack, t_pack = load_or_prepare_pack(args.workdir)
    print(f"pack: {pack.n_grains} grains, porosity {pack.metadata['record']['porosity'][-1]:.3f}, "
          f"sigma_zz {pack.metadata['record']['stress_zz'][-1] / 1e6:.1f} MPa "
          f"({t_pack:.1f} s to load or prepare)", flush=True)

    # Warm-up: numba compilation / cache loads of every kernel the sweeps call.
    t0 = time.perf_counter()
    lat = md.cement_lattice(pack, 2.0)
    md.pulse_test(md.acoustic_system(pack, lat, md.grow_cement(lat, args.saturation, "contact"),
                                     rotations=False))
    md.pulse_test(md.cement_block((3, 3, 80), BLOCK_CELL, slab_thickness=4 * BLOCK_CELL))
    print(f"warm-up {time.perf_counter() - t0:.1f} s", flush=True)

    rows = []
    for omega in omegas:
        rows.append(dict(sweep="resolution", **run_pack_case(pack, omega, 0.5, args)))
        _report(rows[-1])
    for factor in factors:
        rows.append(dict(sweep="time_step", **run_pack_case(pack, args.factor_omega, factor, args)))
        _report(rows[-1])
    for s in slabs:
        rows.append(dict(sweep="cement_block", **run_block_case(s, args)))
        _report(rows[-1])
    frame = pd.DataFrame(rows)

    # Errors against the reference of each sweep.
    frame["reference_velocity"] = np.nan
    frame["reference_velocity_static"] = np.nan
    ok = frame.status == "ok"
    for sweep, ref_idx in (("resolution", frame[(frame.sweep == "resolution") & ok].omega.idxmax()
                            if ((frame.sweep == "resolution") & ok).any() else None),
                           ("time_step",
                            frame[(frame.sweep == "time_step") & ok].time_step_factor.idxmin()
                            if ((frame.sweep == "time_step") & ok).any() else None)):
        if ref_idx is None:
            continue
        sel = frame.sweep == sweep
        frame.loc[sel, "reference_velocity"] = frame.velocity[ref_idx]
        frame.loc[sel, "reference_velocity_static"] = frame.velocity_static[ref_idx]
    blk = frame.sweep == "cement_block"
    frame.loc[blk, "reference_velocity"] = md.HARD_CEMENT.vp
    frame.loc[blk, "reference_velocity_static"] = md.HARD_CEMENT.vp
    frame["rel_error"] = _common.relative_difference(frame.velocity, frame.reference_velocity)
    frame["rel_error_fit"] = _common.relative_difference(frame.velocity_fit,
                                                         frame.reference_velocity)
    frame["rel_error_static"] = _common.relative_difference(frame.velocity_static,
                                                            frame.reference_velocity_static)
    frame["rel_error_bar_eq11"] = frame.velocity_error_eq11 / frame.velocity
    frame["lattice_bond_steps"] = frame.n_lattice_bonds * frame.n_steps
    frame["bond_steps"] = (frame.n_lattice_bonds + frame.n_contact_bonds) * frame.n_steps

    res = frame[(frame.sweep == "resolution") & ok]
    fit = res[res.omega >= args.fit_from]
    exponents = {
        "cost_exponent_pulse": fit_exponent(fit.omega, fit.seconds_pulse),
        "cost_exponent_total": fit_exponent(fit.omega, fit.seconds_total),
        "cost_exponent_static": fit_exponent(fit.omega, fit.seconds_static),
        "work_exponent_bond_steps": fit_exponent(fit.omega, fit.bond_steps),
        "exponent_n_cement": fit_exponent(fit.omega, fit.n_cement),
        "exponent_n_steps": fit_exponent(fit.omega, fit.n_steps),
    }
    total = time.perf_counter() - t_start
    print(f"total benchmark time {total:.1f} s")

    # ---- output
    attrs = _common.environment_attrs(
        title="md pulse test: error against wall time, knobs Omega and time_step_factor",
        benchmark=NAME, quick=bool(args.quick),
        pack=f"md.settle({SETTLE_OPTIONS}) then md.compact({COMPACT_OPTIONS})",
        pack_grains=pack.n_grains, pack_porosity=float(pack.metadata["record"]["porosity"][-1]),
        pack_stress_zz_Pa=float(pack.metadata["record"]["stress_zz"][-1]),
        pack_workdir=str(args.workdir), cement="HARD_CEMENT (3000, 1800 m/s, 2650 kg/m3)",
        scheme="contact", saturation=args.saturation, omegas=json.dumps(omegas),
        factors=json.dumps(factors), factor_omega=args.factor_omega,
        slab_cells=json.dumps(slabs), block_cell_width_m=BLOCK_CELL,
        reference_resolution=f"the largest Omega ({max(omegas):g}) at time_step_factor 0.5",
        reference_time_step=f"the smallest factor ({min(factors):g}) at Omega "
                            f"{args.factor_omega:g}",
        reference_cement_block="exact cement P velocity, 3000 m/s",
        timing=f"best of up to {args.repeat} runs per stage, {args.budget:g} s budget per stage, "
               "after an untimed warm-up; seconds_pulse includes pulse_test's own static solve",
        fit_from_omega=args.fit_from, predicted_cost_exponent=4.0,
        total_run_s=total, **exponents, **md_src)
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    units = {"omega": "1", "time_step_factor": "1", "slab_cells": "1", "velocity": "m s-1",
             "velocity_error_eq11": "m s-1", "velocity_fit": "m s-1", "velocity_static": "m s-1",
             "reference_velocity": "m s-1", "reference_velocity_static": "m s-1",
             "time_step_s": "s", "cell_width_m": "m"}
    data = {}
    for col in frame.columns:
        values = frame[col].to_numpy()
        if values.dtype == object:
            values = values.astype(str)
        unit = units.get(col, "s" if col.startswith("seconds") else
                         ("1" if col.startswith(("rel_error", "n_")) else None))
        data[col] = ("case", values, {"units": unit} if unit else {})
    ds = xr.Dataset(data, coords={"case": ("case", np.arange(len(frame)))}, attrs=attrs)
    _common.write_netcdf(ds, _common.result_path(NAME, "nc", args.tag))
    if not args.no_plot:
        _plot(frame, exponents, args)

    cols_res = {"omega": ("Omega", "g"), "n_cement": ("cement particles", "d"),
                "n_lattice_bonds": ("lattice bonds", "d"), "n_steps": ("steps", "d"),
                "velocity": ("Vp (m/s)", ".0f"), "velocity_error_eq11": ("eq. 11 ± (m/s)", ".0f"),
                "rel_error": ("error vs finest", ".3f"), "velocity_static": ("V static", ".0f"),
                "rel_error_static": ("static error", ".3f"),
                "seconds_pulse": ("pulse (s)", ".3f"), "seconds_total": ("total (s)", ".3f")}
    print(f"\n(a) resolution sweep, S_c = {args.saturation:g}, time_step_factor 0.5\n")
    print(_common.markdown(frame[frame.sweep == "resolution"], cols_res))
    print(f"\ncost exponent (Omega >= {args.fit_from:g}): "
          f"pulse {exponents['cost_exponent_pulse']:.2f}"
          f", total {exponents['cost_exponent_total']:.2f}, static solve "
          f"{exponents['cost_exponent_static']:.2f}, work (bonds x steps) "
          f"{exponents['work_exponent_bond_steps']:.2f} = cement particles "
          f"{exponents['exponent_n_cement']:.2f} + steps {exponents['exponent_n_steps']:.2f} "
          "(App. B: 4)")
    cols_dt = {"time_step_factor": ("factor", "g"), "time_step_s": ("dt (s)", ".3g"),
               "n_steps": ("steps", "d"), "velocity": ("Vp (m/s)", ".1f"),
               "rel_error": ("error vs smallest", ".2e"), "seconds_pulse": ("pulse (s)", ".3f")}
    print(f"\n(b) time-step sweep at Omega = {args.factor_omega:g}\n")
    print(_common.markdown(frame[frame.sweep == "time_step"], cols_dt))
    cols_blk = {"slab_cells": ("slab (cells)", "d"), "n_particles": ("particles", "d"),
                "n_steps": ("steps", "d"), "velocity": ("Vp (m/s)", ".1f"),
                "rel_error": ("error vs 3000", ".4f"), "velocity_fit": ("Vp fit (m/s)", ".1f"),
                "rel_error_fit": ("fit error", ".4f"),
                "rel_error_bar_eq11": ("eq. 11 ± / Vp", ".4f"),
                "seconds_pulse": ("pulse (s)", ".3f")}
    print("\n(c) cement block (3 x 3 x 20 slabs), P wave\n")
    print(_common.markdown(frame[frame.sweep == "cement_block"], cols_blk))
    bad = frame[frame.status != "ok"]
    for _, r in bad.iterrows():
        print(f"FAILED {r.sweep} Omega={r.omega:g} factor={r.time_step_factor:g}: {r.status}")
    stem = _common.result_path(NAME, "", args.tag)
    print(f"wrote {stem}{{csv,nc" + ("" if args.no_plot else ",png") + "}")


def _report(r):
    if r.get("status") != "ok":
        print(f"{r['sweep']:12s} Omega={r['omega']:g} factor={r['time_step_factor']:g}: "
              f"{r['status']}", flush=True)
        return
    print(f"{r['sweep']:12s} Omega={r['omega']:4g} factor={r['time_step_factor']:5g} "
          f"slab={r['slab_cells']:2d}  cement {r['n_cement']:7d} lattice bonds "
          f"{r['n_lattice_bonds']:8d} steps {r['n_steps']:5d}  Vp {r['velocity']:7.1f} "
          f"± {r['velocity_error_eq11']:5.1f} (fit {r['velocity_fit']:7.1f}, static "
          f"{r['velocity_static']:7.1f})  pulse {r['seconds_pulse']:7.3f} s total "
          f"{r['seconds_total']:7.3f} s" + (f"  WARNINGS: {r['warnings']}" if r["warnings"]
                                             else ""), flush=True)


def _plot(frame, exponents, args):
    _common.use_agg()
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    (ax, bx), (cx, dx) = axes
    res = frame[(frame.sweep == "resolution") & (frame.status == "ok")]
    sub = res[res.omega < res.omega.max()]               # the reference has no error to draw
    for col, label, style in (("rel_error", "pulse Vp (eq. 11)", "o-"),
                              ("rel_error_static", "static velocity", "s--")):
        ax.plot(sub.seconds_pulse, np.maximum(sub[col], ERROR_FLOOR), style, label=label, ms=4)
    for _, r in sub.iterrows():
        ax.annotate(f"{r.omega:g}", (r.seconds_pulse, max(r.rel_error, ERROR_FLOOR)),
                    textcoords="offset points", xytext=(4, 4), fontsize=7)
    ax.plot(sub.seconds_pulse, sub.rel_error_bar_eq11, "x:", label="eq. 11 error bar / Vp",
            ms=4)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("pulse-test wall time, s (one core)")
    ax.set_ylabel(f"relative difference vs Omega = {res.omega.max():g}")
    ax.set_title(f"(a) resolution sweep, S_c = {args.saturation:g}, factor 0.5 (labels: Omega;"
                 f"\nreference Omega = {res.omega.max():g}, {res.seconds_pulse.max():.3g} s, "
                 "not drawn)", fontsize=9)
    ax.grid(True, which="both", ls=":")
    ax.legend(fontsize=8)

    dt = frame[(frame.sweep == "time_step") & (frame.status == "ok")]
    dt_ref = dt[dt.time_step_factor == dt.time_step_factor.min()]
    dt = dt[dt.time_step_factor > dt.time_step_factor.min()]
    bx.plot(dt.seconds_pulse, np.maximum(dt.rel_error, ERROR_FLOOR), "o-", ms=4,
            label="pulse Vp")
    for _, r in dt.iterrows():
        bx.annotate(f"{r.time_step_factor:g}", (r.seconds_pulse, max(r.rel_error, ERROR_FLOOR)),
                    textcoords="offset points", xytext=(4, 4), fontsize=7)
    bx.set_xscale("log")
    bx.set_yscale("log")
    bx.set_xlabel("pulse-test wall time, s (one core)")
    bx.set_ylabel(f"relative difference vs factor {dt_ref.time_step_factor.min():g}"
                  if len(dt_ref) else "relative difference")
    bx.set_title(f"(b) time-step sweep at Omega = {args.factor_omega:g} (labels: factor;\n"
                 f"reference factor {dt_ref.time_step_factor.min():g}, "
                 f"{dt_ref.seconds_pulse.max():.3g} s, not drawn; errors of 0 at "
                 f"{ERROR_FLOOR:g})", fontsize=9)
    bx.grid(True, which="both", ls=":")
    bx.legend(fontsize=8)

    blk = frame[frame.sweep == "cement_block"]
    cx.plot(blk.slab_cells, blk.rel_error, "o-", label="Vp (two detectors, eq. 11)")
    cx.plot(blk.slab_cells, blk.rel_error_fit, "s--", label="Vp fit (all detectors)")
    cx.plot(blk.slab_cells, blk.rel_error_bar_eq11, "x:", label="eq. 11 error bar / Vp")
    cx.set_xscale("log", base=2)
    cx.set_yscale("log")
    cx.set_xlabel("slab thickness (cells); pulse = 2 slabs")
    cx.set_ylabel("relative error vs 3000 m/s")
    cx.set_title("(c) pure cement block, P wave", fontsize=9)
    cx.grid(True, which="both", ls=":")
    cx.legend(fontsize=8)

    dx.loglog(res.omega, res.seconds_pulse, "o-", label="pulse test")
    dx.loglog(res.omega, res.seconds_total, "s--", label="lattice + growth + system + pulse")
    dx.loglog(res.omega, res.seconds_static, "^:", label="static solve alone")
    fit = res[res.omega >= args.fit_from]
    if len(fit):
        o = res.omega.to_numpy()
        ref = fit.seconds_pulse.iloc[-1] * (o / fit.omega.iloc[-1]) ** 4
        dx.loglog(o, ref, "k:", lw=1, label="Omega^4 (App. B)")
    dx.set_xlabel("Omega (cells per mean grain radius)")
    dx.set_ylabel("wall time, s")
    dx.set_title(f"cost: fitted exponent {exponents['cost_exponent_pulse']:.2f} (pulse), "
                 f"{exponents['cost_exponent_total']:.2f} (total), Omega >= {args.fit_from:g}",
                 fontsize=9)
    dx.grid(True, which="both", ls=":")
    dx.legend(fontsize=8)
    fig.suptitle("MD pulse test: error against run time", fontsize=11)
    fig.tight_layout()
    _common.save_figure(fig, _common.result_path(NAME, "png", args.tag))


if __name__ == "__main__":
    main()
