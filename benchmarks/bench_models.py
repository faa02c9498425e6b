"""Speed of the four petro-elastic models, and of the vectorised self-consistent solver.

Part 1 runs every model of :mod:`rockcem.models` (``hs_gassmann``, ``self_consistent_model``,
``generalized_gassmann_model``, ``patchy_cement_model``) over ``--n`` depth points (default 10^6)
of a quartz-cemented, water-saturated sandstone (see ``_common.sandstone_profile``) and reports the
best wall time and points per second, single-threaded. Target (reported, not asserted): 10^6
points of every model in under 1 s on one core.

Part 2 compares :func:`rockcem.inclusions.self_consistent` (quartz spheres, cement spheres, water
spheroids of aspect ratio 0.108), vectorised over all points, with a per-point baseline that solves
the same two equations (eq. 8 of Carcione et al. 2022) with ``scipy.optimize.root`` (hybr), on the
same ``--baseline-n`` points (default 2000) sampled evenly along the profile. It reports the speed
ratio and the largest relative difference of K and G. Target: vectorised at least 100x faster.
``self_consistent`` takes its numpy path below 5·10^4 points and its numba kernel from there on
(``rockcem.inclusions._NUMBA_MIN_POINTS``): the 2000-point run is the numpy path, the
``--throughput-n`` run (default 10^5) and Model 2 over 10^6 points the kernel; the kernel is
also timed and checked against scipy on the 2000 baseline points (``sc_solver_numba_kernel``).

With ``--baseline PATH`` (another copy of the package, e.g. ``git archive <commit> rockcem
datasets | tar -x -C PATH``) Part 1 also times that copy's four models on the same inputs,
interleaved with this checkout's run by run (order swapped every run, best of ``--repeat``
each), checks that both give the same values, and reports the speed ratio: the comparison for
a machine whose load changes (issue 32).

Both parts end with a summary line: the four models' best times per 10^6 points and their sum
(target of issue 32: < 1 s together), and with ``--baseline`` the same for the interleaved runs
of both copies and the ratio of the sums. ``--quick`` runs Part 1 alone (with ``--baseline`` if
given) and writes no files: the measurement of the four models in well under 2 minutes.

Run: ``python benchmarks/bench_models.py [--n N] [--repeat K] [--baseline-n M] [--baseline PATH]
[--quick]``.
Output: ``benchmarks/results/bench_models.{csv,nc,png}`` (none with ``--quick``).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

TARGET_MODEL_S = 1.0          # 10^6 points of every model in under 1 s
TARGET_SC_SPEEDUP = 100.0     # vectorised SC vs per-point scipy
SC_TOLS = (1e-12, 1e-10, 1e-8)  # self_consistent_model default first, then fallbacks


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--n", type=int, default=10**6, help="depth points (default 1e6)")
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per case, best kept")
    parser.add_argument("--budget", type=float, default=20.0,
                        help="stop repeating a case after this many seconds (default 20)")
    parser.add_argument("--baseline-n", type=int, default=2000,
                        help="points for the per-point scipy baseline (default 2000)")
    parser.add_argument("--throughput-n", type=int, default=10**5,
                        help="points for the vectorised SC throughput run (default 1e5)")
    parser.add_argument("--tag", default="",
                        help="suffix of the result file names, e.g. a commit (default none)")
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--baseline", default="",
                        help="a copy of rockcem (with datasets/) to time Part 1 against, "
                             "interleaved (default none)")
    parser.add_argument("--quick", action="store_true",
                        help="the four models only (Part 1), no files written")
    args = parser.parse_args(argv)

    import pandas as pd
    import xarray as xr

    from rockcem import models
    from rockcem.inclusions import self_consistent
    from rockcem.materials import fluid, mineral

    _common.announce_source()

    t_start = time.perf_counter()
    quartz, cement, water = mineral("quartz"), mineral("quartz_cement"), fluid("water")
    state = _common.sandstone_profile(args.n)
    phi, beta = state["porosity"], state["solid_fractions"]
    phip, pe = state["cement_fraction"], state["effective_pressure"]
    rows = []

    def record(case, kind, n, best, times, warns, tol=np.nan, status="ok", note=""):
        rows.append({"case": case, "kind": kind, "n_points": int(n), "best_s": best,
                     "runs": len(times), "mean_s": float(np.mean(times)) if times else np.nan,
                     "median_s": float(np.median(times)) if times else np.nan,
                     "points_per_s": n / best if best > 0 else np.nan, "tol": tol,
                     "status": status, "warnings": " | ".join(warns), "note": note})
        print(f"{case:32s} n={n:>8d}  best {best:9.4f} s  {n / best:12.4g} points/s"
              f"  ({len(times)} run(s)) {status}" + (f"  WARNINGS: {warns}" if warns else ""),
              flush=True)

    if args.baseline:
        _baseline_part(args, state, rows, record)

    # ---- Part 1: the four models over n points
    simple = {
        "hs_gassmann": lambda: models.hs_gassmann([quartz, cement], beta, phi, water),
        "generalized_gassmann": lambda: models.generalized_gassmann_model(
            [quartz, cement], beta, phi, water),
        "patchy_cement": lambda: models.patchy_cement_model(quartz, cement, phi, phip, pe, water),
    }
    results = {}
    for name, fn in simple.items():
        best, times, res, warns = _common.best_of(fn, args.repeat, budget_s=args.budget)
        record(name, "model", args.n, best, times, warns)
        results[name] = res

    # self_consistent_model: default tol first. A cheap probe on every 10th point tells whether
    # it raises, so that a failure does not cost a full 1e6-point run before the fallback.
    sc_failures = []
    probe = slice(None, None, 10)
    for tol in SC_TOLS:
        try:
            t0 = time.perf_counter()
            models.self_consistent_model([quartz, cement], beta[probe], phi[probe], water,
                                         aspect_ratio=0.108, tol=tol)
        except RuntimeError as exc:
            sc_failures.append(f"tol={tol:g} on every 10th point ({phi[probe].size} points) "
                               f"raised RuntimeError after {time.perf_counter() - t0:.1f} s: {exc}")
            print("self_consistent_model", sc_failures[-1], flush=True)
            continue
        try:
            best, times, res, warns = _common.best_of(
                lambda tol=tol: models.self_consistent_model(
                    [quartz, cement], beta, phi, water, aspect_ratio=0.108, tol=tol),
                args.repeat, budget_s=args.budget)
        except RuntimeError as exc:
            sc_failures.append(f"tol={tol:g} on {args.n} points raised RuntimeError: {exc}")
            print("self_consistent_model", sc_failures[-1], flush=True)
            continue
        status = "ok" if tol == SC_TOLS[0] else f"default tol {SC_TOLS[0]:g} raised RuntimeError"
        record("self_consistent", "model", args.n, best, times, warns, tol=tol, status=status,
               note="; ".join(sc_failures))
        results["self_consistent"] = res
        break
    else:
        rows.append({"case": "self_consistent", "kind": "model", "n_points": args.n,
                     "best_s": np.nan, "runs": 0, "mean_s": np.nan, "points_per_s": np.nan,
                     "tol": np.nan, "status": "failed at every tol", "warnings": "",
                     "note": "; ".join(sc_failures)})

    for name, res in results.items():
        finite = all(np.all(np.isfinite(v)) for v in res)
        if not finite:
            print(f"WARNING: {name} returned non-finite values", flush=True)
    _summary(rows)
    if args.quick:
        print(f"total benchmark time {time.perf_counter() - t_start:.1f} s (--quick: no files "
              "written)")
        return

    # ---- Part 2: vectorised self_consistent vs per-point scipy root (water-filled pores)
    idx = np.unique(np.linspace(0, args.n - 1, args.baseline_n).round().astype(int))
    sub = {k: v[idx] for k, v in state.items()}
    K, G, frac, aspect = _common.sandstone_sc_phases(sub, water.K, 0.108)
    best_v, times_v, m_vec, warns_v = _common.best_of(
        lambda: self_consistent(K, G, frac, aspect), max(args.repeat, 5), budget_s=args.budget)
    record("sc_solver_vectorised", "sc_solver", idx.size, best_v, times_v, warns_v, tol=1e-12)
    best_b, times_b, (K_b, G_b, ok_b, nfev_b), warns_b = _common.best_of(
        lambda: _common.self_consistent_scipy(K, G, frac, aspect), 1)
    record("sc_solver_pointwise_scipy", "sc_solver", idx.size, best_b, times_b, warns_b,
           status="ok" if ok_b.all() else f"{int((~ok_b).sum())} points not converged",
           note=f"scipy.optimize.root hybr, mean nfev {nfev_b.mean():.1f}")
    dK = _common.relative_difference(m_vec.K, K_b)
    dG = _common.relative_difference(m_vec.G, G_b)
    speedup = best_b / best_v

    # The same points through the numba kernel, which self_consistent takes only from
    # inclusions._NUMBA_MIN_POINTS points on (set to 0 here for this one case).
    from rockcem import inclusions

    saved, inclusions._NUMBA_MIN_POINTS = inclusions._NUMBA_MIN_POINTS, 0
    try:
        best_n, times_n, m_num, warns_n = _common.best_of(
            lambda: self_consistent(K, G, frac, aspect), max(args.repeat, 5),
            budget_s=args.budget)
    finally:
        inclusions._NUMBA_MIN_POINTS = saved
    dK_n = _common.relative_difference(m_num.K, K_b)
    dG_n = _common.relative_difference(m_num.G, G_b)
    record("sc_solver_numba_kernel", "sc_solver", idx.size, best_n, times_n, warns_n, tol=1e-12,
           note=f"max rel. diff vs scipy: K {dK_n.max():.3g}, G {dG_n.max():.3g}")

    # The same solver at a size where the per-call overhead no longer dominates.
    n_t = min(args.throughput_n, args.n)
    idx_t = np.unique(np.linspace(0, args.n - 1, n_t).round().astype(int))
    K_t, G_t, frac_t, aspect_t = _common.sandstone_sc_phases(
        {k: v[idx_t] for k, v in state.items()}, water.K, 0.108)
    best_t, times_t, _, warns_t = _common.best_of(
        lambda: self_consistent(K_t, G_t, frac_t, aspect_t), args.repeat, budget_s=args.budget)
    record("sc_solver_vectorised_throughput", "sc_solver", idx_t.size, best_t, times_t, warns_t,
           tol=1e-12)
    speedup_per_point = (best_b / idx.size) / (best_t / idx_t.size)

    total = time.perf_counter() - t_start
    print(f"\nSC solver, {idx.size} points: vectorised {best_v * 1e3:.2f} ms, per-point scipy "
          f"{best_b:.2f} s -> speed-up {speedup:.0f}x (target >= {TARGET_SC_SPEEDUP:.0f}x); "
          f"per-point cost ratio at {idx_t.size} points: {speedup_per_point:.0f}x")
    print(f"max relative difference vectorised vs scipy: K {dK.max():.3g}, G {dG.max():.3g}; "
          f"scipy converged at {int(ok_b.sum())}/{ok_b.size} points")
    print(f"numba kernel on the same {idx.size} points: {best_n * 1e3:.2f} ms "
          f"({best_b / best_n:.0f}x the per-point scipy baseline), max relative difference vs "
          f"scipy: K {dK_n.max():.3g}, G {dG_n.max():.3g}")
    for r in rows:
        if r["kind"] == "model" and np.isfinite(r["best_s"]):
            t1e6 = r["best_s"] * 1e6 / r["n_points"]
            print(f"{r['case']:22s} {t1e6:8.3f} s per 1e6 points "
                  f"({'meets' if t1e6 < TARGET_MODEL_S else 'misses'} the < 1 s target)")
    print(f"total benchmark time {total:.1f} s")

    # ---- output
    frame = pd.DataFrame(rows)
    attrs = _common.environment_attrs(
        title="rockcem petro-elastic model and SC solver speed",
        benchmark="bench_models",
        n_points=args.n, repeat=args.repeat, budget_s=args.budget,
        rock_state="quartz grain + quartz_cement (Carcione 2022 Table 1), water; porosity "
                   "0.36 -> 0.02, cement 0.20 s^2, effective pressure 0-60 MPa over depth 0-5000 m",
        sc_aspect_ratio=0.108,
        sc_speedup=speedup, sc_speedup_per_point_at_throughput_n=speedup_per_point,
        sc_baseline_points=int(idx.size), sc_throughput_points=int(idx_t.size),
        sc_max_rel_diff_K=float(dK.max()), sc_max_rel_diff_G=float(dG.max()),
        sc_numba_speedup=best_b / best_n,
        sc_numba_max_rel_diff_K=float(dK_n.max()), sc_numba_max_rel_diff_G=float(dG_n.max()),
        sc_baseline_converged=int(ok_b.sum()), sc_baseline_mean_nfev=float(nfev_b.mean()),
        self_consistent_model_failures="; ".join(sc_failures),
        target_model_s_per_1e6=TARGET_MODEL_S, target_sc_speedup=TARGET_SC_SPEEDUP,
        total_run_s=total,
    )
    _common.write_csv(frame, _common.result_path("bench_models", "csv", args.tag), attrs)
    ds = xr.Dataset(
        {
            "kind": ("case", frame["kind"].astype(str).values,
                     {"long_name": "model or sc_solver"}),
            "n_points": ("case", frame["n_points"].values.astype("int64"),
                         {"units": "1", "long_name": "number of points"}),
            "best_time": ("case", frame["best_s"].values,
                          {"units": "s", "long_name": "best wall time of the timed runs"}),
            "mean_time": ("case", frame["mean_s"].values,
                          {"units": "s", "long_name": "mean wall time of the timed runs"}),
            "median_time": ("case", frame["median_s"].values,
                            {"units": "s", "long_name": "median wall time of the timed runs"}),
            "runs": ("case", frame["runs"].values.astype("int64"),
                     {"units": "1", "long_name": "number of timed runs"}),
            "points_per_second": ("case", frame["points_per_s"].values,
                                  {"units": "s-1", "long_name": "points per second (best run)"}),
            "time_per_1e6_points": ("case", frame["best_s"].values * 1e6 / frame["n_points"].values,
                                    {"units": "s", "long_name": "best wall time scaled to 1e6 "
                                                               "points"}),
            "tol": ("case", frame["tol"].values.astype(float),
                    {"units": "1", "long_name": "SC solver tolerance (NaN: not applicable)"}),
            "status": ("case", frame["status"].astype(str).values, {"long_name": "status"}),
        },
        coords={"case": frame["case"].astype(str).values},
        attrs=attrs,
    )
    _common.write_netcdf(ds, _common.result_path("bench_models", "nc", args.tag))
    if not args.no_plot:
        _plot(frame, args.n, args.tag)
    stem = _common.result_path("bench_models", "", args.tag)
    print(f"wrote {stem}{{csv,nc" + ("" if args.no_plot else ",png") + "}")


MODEL_CASES = ("hs_gassmann", "self_consistent", "generalized_gassmann", "patchy_cement")


def _summary(rows):
    """Print the four models' best times per 10^6 points and their sum (issue 32's target: < 1 s
    together), for this checkout alone and, where there, for the interleaved runs of both
    copies."""
    def line(label, suffix, kind):
        best = {r["case"][:len(r["case"]) - len(suffix)]: r["best_s"] * 1e6 / r["n_points"]
                for r in rows if r["kind"] == kind and r["case"].endswith(suffix)}
        if not all(np.isfinite(best.get(c, np.nan)) for c in MODEL_CASES):
            return None
        total = sum(best[c] for c in MODEL_CASES)
        print(f"{label}: " + ", ".join(f"{c} {best[c]:.3f}" for c in MODEL_CASES)
              + f" s per 1e6 points; together {total:.3f} s (target < {TARGET_MODEL_S:g} s: "
              + ("met)" if total < TARGET_MODEL_S else "missed)"), flush=True)
        return total

    print()
    line("this checkout alone, best", "", "model")
    mine = line("this checkout interleaved, best", "_interleaved", "model_interleaved")
    base = line("--baseline interleaved, best", "_baseline", "model_baseline")
    if mine and base:
        print(f"together: --baseline / this checkout = {base / mine:.2f}x", flush=True)


def _load_package(path):
    """Import the rockcem at ``path`` beside the one already imported; returns its models and
    materials modules and a context manager under which its calls must run (the current
    package's modules are put back).

    The context manager puts the other copy's modules into ``sys.modules`` for the time of a
    call: a module imported at call time inside the package (``from . import _sc_kernels``,
    the numba kernel of the self-consistent solver) is looked up there, and would otherwise be
    this checkout's.
    """
    import contextlib
    import importlib
    import sys

    def ours():
        return {k: v for k, v in sys.modules.items() if k == "rockcem" or k.startswith("rockcem.")}

    mine = ours()
    for k in mine:
        del sys.modules[k]
    sys.path.insert(0, path)
    try:
        other = importlib.import_module("rockcem.models"), importlib.import_module(
            "rockcem.materials")
        try:
            importlib.import_module("rockcem._sc_kernels")
        except ImportError:
            pass
        theirs = ours()
    finally:
        sys.path.remove(path)
        for k in [k for k in sys.modules if k == "rockcem" or k.startswith("rockcem.")]:
            del sys.modules[k]
        sys.modules.update(mine)
    if not other[0].__file__.startswith(str(path)):
        raise SystemExit(f"--baseline {path}: imported {other[0].__file__} instead")

    @contextlib.contextmanager
    def active():
        saved = ours()
        for k in saved:
            del sys.modules[k]
        sys.modules.update(theirs)
        try:
            yield
        finally:
            for k in ours():
                del sys.modules[k]
            sys.modules.update(saved)

    return other + (active,)


def _baseline_part(args, state, rows, record):
    """Part 1 against another copy of the package, interleaved run by run."""
    import warnings

    from rockcem import materials, models

    base_models, base_materials, active = _load_package(args.baseline)
    phi, beta = state["porosity"], state["solid_fractions"]
    phip, pe = state["cement_fraction"], state["effective_pressure"]

    def calls(M, mat):
        q, c, w = mat.mineral("quartz"), mat.mineral("quartz_cement"), mat.fluid("water")
        return {"hs_gassmann": lambda: M.hs_gassmann([q, c], beta, phi, w),
                "self_consistent": lambda: M.self_consistent_model([q, c], beta, phi, w,
                                                                   aspect_ratio=0.108),
                "generalized_gassmann": lambda: M.generalized_gassmann_model([q, c], beta, phi,
                                                                             w),
                "patchy_cement": lambda: M.patchy_cement_model(q, c, phi, phip, pe, w)}

    mine, base = calls(models, materials), calls(base_models, base_materials)

    def under(fn):
        def call():
            with active():
                return fn()
        return call

    base = {k: under(fn) for k, fn in base.items()}
    for name in mine:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            a, b = mine[name](), base[name]()        # also the warm-up (numba's first call)
        diff = max(float(np.max(_common.relative_difference(x, y))) for x, y in zip(a, b))
        times = {"this": [], "baseline": []}
        for r in range(args.repeat):
            order = [("this", mine[name]), ("baseline", base[name])]
            for who, fn in order if r % 2 == 0 else order[::-1]:
                t0 = time.perf_counter()
                fn()
                times[who].append(time.perf_counter() - t0)
        best, best_base = min(times["this"]), min(times["baseline"])
        med, med_base = np.median(times["this"]), np.median(times["baseline"])
        note = (f"interleaved with --baseline {args.baseline}: {best_base:.4f} s there, "
                f"{best_base / best:.2f}x (medians {med_base:.4f} / {med:.4f} s, "
                f"{med_base / med:.2f}x); max rel. difference of the outputs {diff:.2g}")
        record(f"{name}_baseline", "model_baseline", args.n, best_base, times["baseline"], [],
               note=f"the --baseline copy, interleaved with {name}_interleaved")
        record(f"{name}_interleaved", "model_interleaved", args.n, best, times["this"], [],
               note=note)
        print(f"{name:22s} this {best:.4f} s, baseline {best_base:.4f} s: {best_base / best:.2f}x"
              f"; medians {med:.4f} / {med_base:.4f} s: {med_base / med:.2f}x"
              f" (outputs within {diff:.2g})", flush=True)


def _plot(frame, n, tag=""):
    _common.use_agg()
    import matplotlib.pyplot as plt

    f = frame[np.isfinite(frame["best_s"])]
    fig, ax = plt.subplots(figsize=(7.5, 1.2 + 0.38 * len(f)))
    palette = {"model": "C0", "model_interleaved": "C2", "model_baseline": "0.6"}
    colors = [palette.get(k, "C1") for k in f["kind"]]
    labels = [f"{c} (n={p:g})" for c, p in zip(f["case"], f["n_points"])]
    ax.barh(labels, f["points_per_s"], color=colors)
    from matplotlib.patches import Patch

    names = {"model": "model", "model_interleaved": "model, interleaved with --baseline",
             "model_baseline": "model of the --baseline copy"}
    handles = [Patch(color=c, label=names[k]) for k, c in palette.items() if k in set(f["kind"])]
    handles.append(Patch(color="C1", label="SC solver"))
    ax.tick_params(axis="y", labelsize=8)
    ax.axvline(1e6 / TARGET_MODEL_S, color="k", ls="--", lw=1, label="target: 1e6 points/s")
    ax.set_xscale("log")
    ax.set_xlabel("points per second (best run, one core)")
    ax.set_title(f"rockcem speed, sandstone profile (models at n={n:g})")
    ax.invert_yaxis()
    line = ax.get_legend_handles_labels()[0]
    ax.legend(handles=line + handles, loc="lower left", fontsize=8, framealpha=0.9)
    _common.save_figure(fig, _common.result_path("bench_models", "png", tag))


if __name__ == "__main__":
    main()
