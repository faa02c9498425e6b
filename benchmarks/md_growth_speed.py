"""Cement growth speed: the numba kernels of :func:`md.grow_cement` against the plain-Python
version they replaced, on cement lattices of increasing size.

Measured: wall time of ``grow_cement(lat, S_c, scheme)`` for the three schemes of García & Medina
(Sects. III C–E: contact, coating, pore body) at ``--saturations`` (default S_c = 0.1 and 1),
new (the library: binary-heap / sum-tree kernels, O(n log n)) against old
(:func:`_grow_cement_reference` below: the pure-Python version before the kernels, kept here
verbatim: heapq and a Python set; its pore-body scheme rebuilds the frontier array at every
step, O(n^2)). Lattices: :func:`md.cement_lattice` of one pack at increasing resolution
``Omega`` (``--omegas``; pore cells grow as Omega^3: about 6e3 to 1e7 for the default pack).
The pack is the compacted 256-grain pack of ``md_pulse_error_vs_time.py`` (``--pack``, default
``results/md_pulse_pack/compact.nc``) when it exists, else a synthetic one (jittered simple
cubic, 4 x 4 x 16 grains of radius 0.19 mm, slightly overlapping), as recorded in the metadata.

Timing: ``time.perf_counter``, best of ``--repeat`` calls (a case stops repeating once its calls
took ``--budget`` s), after a warm-up call that compiles or loads the numba cache. The old
version runs only where its predicted time stays below ``--old-budget`` s (default 60):
predicted from its time at the previous size as ``t (n / n_prev)^a``, a = 2 for pore body (its
frontier grows with n) and 1.2 otherwise; skipped cases are left empty. Checks, same run:
contact and coating cells of new and old are compared cell for cell (they must be identical);
pore-body cells cannot be (the random streams differ), so their count and the mean distance of
the cemented cells to the grains (the scheme's statistic) are compared, for one seed: at small
S_c the growth is strongly correlated and this single-seed difference is sampling noise of
several per cent (over 30 seeds at Omega 3 the means of new and old agree within 1.5 standard
errors at S_c = 0.02, 0.1 and 0.5). The scaling exponent of
the new kernels is the log-log slope of time against n over the sizes from 1e5 cells up.

Output: ``benchmarks/results/md_growth_speed.{csv,nc}`` and a markdown table on stdout.
Run: ``python benchmarks/md_growth_speed.py [--quick]`` (about 10 min on the 2-core machine of
docs/studies/index.md; ``--quick``: three small lattices, under a minute, written as
``md_growth_speed_quick.*``).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import heapq  # noqa: E402
import os  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_growth_speed"
OMEGAS = (2.0, 3.0, 4.0, 6.0, 10.0, 16.0, 24.0)
QUICK_OMEGAS = (2.0, 3.0, 4.0)
SCHEMES = ("contact", "coating", "pore_body")
OLD_EXPONENT = {"contact": 1.2, "coating": 1.2, "pore_body": 2.0}


# ----------------------------------------------------------------------------- the old version
def _neighbour_map_reference(lat):
    """Face neighbours of each pore cell, vectorised numpy, int64 (the version before the
    numba kernel)."""
    nx, ny, nz = lat.shape
    where = np.full(nx * ny * nz, -1, dtype=np.int64)
    where[lat.index] = np.arange(lat.index.size)
    i = lat.index % nx
    j = (lat.index // nx) % ny
    k = lat.index // (nx * ny)
    nbrs = []
    for di, dj, dk in ((1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)):
        kk = k + dk
        ok = (kk >= 0) & (kk < nz)
        flat = ((i + di) % nx) + nx * (((j + dj) % ny) + ny * np.clip(kk, 0, nz - 1))
        nbrs.append(np.where(ok, where[flat], -1))
    return np.stack(nbrs, axis=1)


def _grow_cement_reference(lat, saturation, scheme="contact", *, seed=0):
    """``md.grow_cement`` before the numba kernels (pure Python: heapq, a set, numpy Generator);
    same semantics, O(n log n) contact, O(n^2) pore body."""
    from md.cement import CONTACT, SURFACE

    n = lat.index.size
    target = int(round(saturation * n))
    cemented = np.zeros(n, dtype=bool)
    if target == 0:
        return cemented
    dist = lat.distance.astype(float)
    if scheme == "coating":
        order = np.lexsort((np.arange(n), dist))
        cemented[order[:target]] = True
        return cemented
    nbrs = _neighbour_map_reference(lat)
    if scheme == "contact":
        contact = np.flatnonzero(lat.kind == CONTACT)
        first = contact[np.lexsort((contact, dist[contact]))][:target]
        cemented[first] = True
        count = first.size
        heap = [(dist[c], int(c)) for c in np.unique(nbrs[first].ravel()) if c >= 0
                and not cemented[c]]
        heapq.heapify(heap)
        while count < target:
            if not heap:                           # disconnected pores: seed the closest left
                rest = np.flatnonzero(~cemented)
                heap = [(dist[rest[np.argmin(dist[rest])]], int(rest[np.argmin(dist[rest])]))]
            _, c = heapq.heappop(heap)
            if cemented[c]:
                continue
            cemented[c] = True
            count += 1
            for nb in nbrs[c]:
                if nb >= 0 and not cemented[nb]:
                    heapq.heappush(heap, (dist[nb], int(nb)))
        return cemented
    rng = np.random.default_rng(seed)
    surface = np.flatnonzero(lat.kind == SURFACE)
    n_seeds = max(1, min(target, surface.size // 50 + 1))
    seeds = rng.choice(surface if surface.size else np.arange(n), size=n_seeds, replace=False)
    cemented[seeds] = True
    count = n_seeds
    frontier = {int(c) for c in nbrs[seeds].ravel() if c >= 0 and not cemented[c]}
    while count < target:
        if not frontier:
            rest = np.flatnonzero(~cemented)
            frontier = {int(rng.choice(rest))}
        cand = np.fromiter(frontier, dtype=np.int64)
        w = np.maximum(dist[cand], 1e-12)
        c = int(cand[rng.choice(cand.size, p=w / w.sum())])
        frontier.discard(c)
        cemented[c] = True
        count += 1
        frontier.update(int(nb) for nb in nbrs[c] if nb >= 0 and not cemented[nb])
    return cemented


# ----------------------------------------------------------------------------- lattices
def synthetic_pack():
    """4 x 4 x 16 grains of radius about 0.19 mm on a jittered simple-cubic lattice (spacing
    0.98 diameters, so neighbours overlap slightly and have contact cells)."""
    import md

    rng = np.random.default_rng(0)
    radius, (nx, ny, nz) = 0.19e-3, (4, 4, 16)
    spacing = 2 * radius * 0.98
    i, j, k = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    x = np.stack([i.ravel(), j.ravel(), k.ravel()], -1) * spacing + radius
    x += rng.uniform(-0.01, 0.01, x.shape) * radius
    r = radius * rng.uniform(0.99, 1.01, len(x))
    z = np.zeros_like(x)
    return md.Pack(x, z.copy(), z.copy(), r,
                   md.Box(nx * spacing, ny * spacing, 0.0, nz * spacing + 2 * radius),
                   md.QUARTZ, np.zeros((0, 2), np.int32), np.zeros((0, 3)))


def load_pack(path):
    import md

    if path is not None and Path(path).is_file():
        return md.load_pack(path), f"{path} (compacted pack)"
    return synthetic_pack(), "synthetic jittered simple-cubic pack, 256 grains, R = 0.19 mm"


# ----------------------------------------------------------------------------- timing
def compare(scheme, new, old, lat):
    """'identical' / 'DIFFERENT' for the deterministic schemes; relative difference of the mean
    distance of the cemented cells for pore body."""
    if old is None:
        return "", np.nan
    d = lat.distance.astype(float)
    mean_new = d[new].mean() if new.any() else 0.0
    mean_old = d[old].mean() if old.any() else 0.0
    rel = float(_common.relative_difference(mean_new, mean_old))
    if scheme == "pore_body":
        return ("same count" if new.sum() == old.sum() else "COUNT DIFFERS"), rel
    return ("identical" if np.array_equal(new, old) else "DIFFERENT"), rel


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--omegas", type=float, nargs="+", default=None,
                        help=f"lattice resolutions Omega (default {' '.join(map(str, OMEGAS))})")
    parser.add_argument("--saturations", type=float, nargs="+", default=(0.1, 1.0),
                        help="cement saturations S_c (default 0.1 1)")
    parser.add_argument("--repeat", type=int, default=3,
                        help="timed calls per case, best kept (default 3)")
    parser.add_argument("--budget", type=float, default=20.0,
                        help="stop repeating a case after this many s (default 20)")
    parser.add_argument("--old-budget", type=float, default=60.0,
                        help="run the old version only where its predicted time is below this "
                             "(s, default 60)")
    parser.add_argument("--pack", type=Path,
                        default=_common.RESULTS / "md_pulse_pack" / "compact.nc",
                        help="pack file (default the compacted pack of md_pulse_error_vs_time; "
                             "a synthetic pack if absent)")
    parser.add_argument("--quick", action="store_true",
                        help=f"Omega {' '.join(map(str, QUICK_OMEGAS))}, one call per case, "
                             "old budget 10 s; results tagged _quick unless --tag")
    parser.add_argument("--tag", default="",
                        help="suffix of the result file names, e.g. a commit (default none)")
    args = parser.parse_args(argv)
    omegas = args.omegas or (QUICK_OMEGAS if args.quick else OMEGAS)
    repeat = 1 if args.quick else args.repeat
    old_budget = min(args.old_budget, 10.0) if args.quick else args.old_budget
    tag = args.tag or ("quick" if args.quick else "")

    import pandas as pd
    import xarray as xr

    import md

    _common.announce_source()
    md_src = _common.md_source_attrs()
    print(f"md from {md_src['md_path']}, uncommitted: {md_src['git_uncommitted_md_files']}, "
          f"sources sha256 {md_src['md_source_sha256'][:12]}", flush=True)
    t_start = time.perf_counter()
    load_start = os.getloadavg()[0]
    pack, pack_note = load_pack(args.pack)
    print(f"pack: {pack_note}", flush=True)
    small = md.cement_lattice(pack, 1.5)
    for scheme in SCHEMES:                                   # compile / load the numba cache
        md.grow_cement(small, 0.5, scheme)

    rows = []
    last_old = {}                                            # (scheme, S_c) -> (n, seconds)
    for omega in sorted(omegas):
        t0 = time.perf_counter()
        lat = md.cement_lattice(pack, omega)
        t_lattice = time.perf_counter() - t0
        n = int(lat.index.size)
        print(f"Omega {omega:g}: {n} pore cells, lattice {lat.shape} built in {t_lattice:.2f} s",
              flush=True)
        for scheme in SCHEMES:
            for sc in args.saturations:
                best_new, t_new, cem_new, warn_new = _common.best_of(
                    lambda: md.grow_cement(lat, sc, scheme), repeat, budget_s=args.budget)
                prev = last_old.get((scheme, sc))
                predicted = (np.nan if prev is None else
                             prev[1] * (n / prev[0]) ** OLD_EXPONENT[scheme])
                best_old, cem_old, runs_old, warn_old = np.nan, None, 0, []
                if not (predicted > old_budget):
                    best_old, t_old, cem_old, warn_old = _common.best_of(
                        lambda: _grow_cement_reference(lat, sc, scheme),
                        repeat if not predicted * repeat >= args.budget else 1,
                        budget_s=args.budget)
                    runs_old = len(t_old)
                    last_old[(scheme, sc)] = (n, best_old)
                check, rel = compare(scheme, cem_new, cem_old, lat)
                rows.append(dict(omega=omega, n_cells=n, scheme=scheme, saturation=sc,
                                 lattice_seconds=t_lattice, new_seconds=best_new,
                                 new_runs=len(t_new), new_ns_per_cell=1e9 * best_new / n,
                                 old_seconds=best_old, old_runs=runs_old,
                                 old_predicted_seconds=predicted,
                                 speedup=best_old / best_new, check=check,
                                 mean_distance_rel_diff=rel,
                                 warnings=" | ".join(warn_new + warn_old)))
                r = rows[-1]
                old_text = (f"old {best_old:9.3f} s ({r['speedup']:8.1f}x)" if runs_old else
                            f"old skipped (predicted {predicted:.3g} s)")
                print(f"  {scheme:9s} S_c {sc:<4g} new {best_new:8.4f} s "
                      f"({r['new_ns_per_cell']:7.1f} ns/cell)  {old_text}  {check}", flush=True)
    total = time.perf_counter() - t_start

    frame = pd.DataFrame(rows)
    slopes = {}
    for scheme in SCHEMES:
        for sc in args.saturations:
            sub = frame[(frame.scheme == scheme) & (frame.saturation == sc)
                        & (frame.n_cells >= 1e5)]
            if len(sub) >= 2:
                slope = np.polyfit(np.log(sub.n_cells), np.log(sub.new_seconds), 1)[0]
                slopes[f"new_scaling_exponent_{scheme}_Sc{sc:g}"] = float(slope)
    print("\nscaling exponents of the new kernels (log-log slope, n >= 1e5): "
          + ", ".join(f"{k[len('new_scaling_exponent_'):]} {v:.2f}" for k, v in slopes.items()))
    bad = frame[frame.check.isin(["DIFFERENT", "COUNT DIFFERS"])]
    attrs = _common.environment_attrs(
        title="md cement growth: numba kernels against the plain-Python version",
        benchmark=NAME, source="García & Medina, Sects. III C-E (contact, coating, pore body)",
        new="md.grow_cement (md._kernels_cement: contact_growth, pore_body_growth)",
        old="_grow_cement_reference in this script (heapq, Python set; pore body O(n^2))",
        pack=pack_note, pack_grains=int(pack.n_grains),
        timing=f"best of {repeat} calls per case (stop after {args.budget:g} s), after a "
               "warm-up call; old version only where predicted below "
               f"{old_budget:g} s (t_prev (n/n_prev)^a, a = 2 pore body, 1.2 otherwise)",
        checks="contact, coating: new == old cell for cell; pore body: same count, relative "
               "difference of the mean distance of cemented cells (different random streams)",
        all_checks_passed=int(bad.empty), total_run_s=total,
        load_average_1min_start=load_start, load_average_1min_end=os.getloadavg()[0],
        load_note="other people's jobs share this machine; the load average says how much",
        **slopes, **md_src)
    _common.write_csv(frame, _common.result_path(NAME, "csv", tag), attrs)

    # netCDF: (omega, scheme, saturation).
    sats = sorted(set(args.saturations))
    omega_sorted = sorted(set(frame.omega))
    shape = (len(omega_sorted), len(SCHEMES), len(sats))
    variables = {"new_seconds": ("s", "best wall time of md.grow_cement"),
                 "old_seconds": ("s", "best wall time of the plain-Python version (NaN: not run)"),
                 "old_predicted_seconds": ("s", "old time predicted from the previous size"),
                 "speedup": ("1", "old_seconds / new_seconds"),
                 "new_ns_per_cell": ("ns", "new wall time per pore cell"),
                 "mean_distance_rel_diff": ("1", "relative difference of the mean distance of "
                                                 "cemented cells, new vs old")}
    data = {}
    for name, (unit, long_name) in variables.items():
        values = np.full(shape, np.nan)
        for _, r in frame.iterrows():
            values[omega_sorted.index(r.omega), SCHEMES.index(r.scheme),
                   sats.index(r.saturation)] = r[name]
        data[name] = (("omega", "scheme", "saturation"), values,
                      {"units": unit, "long_name": long_name})
    identical = np.full(shape, -1, dtype=np.int8)
    for _, r in frame.iterrows():
        if r.check in ("identical", "DIFFERENT"):
            identical[omega_sorted.index(r.omega), SCHEMES.index(r.scheme),
                      sats.index(r.saturation)] = int(r.check == "identical")
    data["identical"] = (("omega", "scheme", "saturation"), identical,
                         {"units": "1", "long_name": "new cells == old cells (1), differ (0), "
                                                     "not compared (-1)"})
    n_cells = frame.groupby("omega").n_cells.first().reindex(omega_sorted).to_numpy()
    t_lat = frame.groupby("omega").lattice_seconds.first().reindex(omega_sorted).to_numpy()
    data["n_cells"] = ("omega", n_cells, {"units": "1", "long_name": "pore cells of the lattice"})
    data["lattice_seconds"] = ("omega", t_lat, {"units": "s",
                                                "long_name": "md.cement_lattice wall time"})
    ds = xr.Dataset(data, coords={
        "omega": ("omega", np.array(omega_sorted), {"units": "1", "long_name":
                                                    "resolution Omega, cells per grain radius"}),
        "scheme": ("scheme", np.array(SCHEMES)),
        "saturation": ("saturation", np.array(sats), {"units": "1",
                                                      "long_name": "cement saturation S_c"})},
        attrs=attrs)
    _common.write_netcdf(ds, _common.result_path(NAME, "nc", tag))

    print(f"\ngrow_cement, one core; total benchmark time {total:.0f} s\n")
    print(_common.markdown(frame, {"omega": ("Omega", "g"), "n_cells": ("pore cells", "d"),
                                   "scheme": ("scheme", "s"), "saturation": ("S_c", "g"),
                                   "new_seconds": ("new, s", ".4g"),
                                   "new_ns_per_cell": ("new, ns/cell", ".0f"),
                                   "old_seconds": ("old, s", ".4g"),
                                   "speedup": ("old/new", ".1f"), "check": ("check", "s"),
                                   "mean_distance_rel_diff": ("mean d, new vs old", ".3f")}))
    if not bad.empty:
        print(f"\n{len(bad)} CHECKS FAILED")
    stem = _common.result_path(NAME, "", tag)
    print(f"wrote {stem}{{csv,nc}}")
    return 0 if bad.empty else 1


if __name__ == "__main__":
    raise SystemExit(main())
