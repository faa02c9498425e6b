"""Cement-lattice throughput of the MD acoustic stage: lattice-spring updates per second per core.

Measured: :func:`md._kernels_acoustic.lattice_forces` (the matrix-free force kernel of the cement
lattice springs, eq. 6 of García & Medina, over the neighbour table of
:class:`md.AcousticSystem`; one *lattice-spring update* = one bond processed: read both ends'
displacements, add the spring force to both ends) on pure cement blocks
(:func:`md.cement_block`, hard cement, cell width 1e-5 m, periodic in x and y) of about 1e4,
1e5, 1e6 and 1e7 nodes (``--sizes``; cubes; 9 bonds per node less the 5 z-stepping offsets of
the top layer), random displacements, single-threaded (the kernels are serial numba loops;
``_common`` pins every thread pool to 1 anyway), the best call of ``--rounds`` timing rounds
(round-robin over the blocks, each filling ``--min-time`` s per block) after a warm-up call.
The issue's target is >= 1e8 lattice-spring updates/s/core. Baseline in the same rounds: the
same forces over a bond list (``bi``, ``bj`` int32, ``bd`` int8 per bond; md's layout before the
neighbour table), compiled in this script and checked to give the same forces; reported as the
ratio table / bond list.

Memory-bandwidth bound, measured in the same run: the streaming bandwidth of the machine is
taken from ``np.copyto(b, a)`` on two ~1 GB float64 arrays (``--copy-gb``), best of 5, counting
``2 * a.nbytes`` bytes (read a, write b; the write-allocate read of ``b`` that x86 adds without
non-temporal stores is not counted, so this is the figure a simple STREAM-copy would report).
Byte model of the kernel (the least traffic a sweep must cause, with every node's data used from
cache across its bonds): per node its neighbour-table row (9 int32, 36 B) is streamed, the
displacement ``u`` read (3 float64, 24 B) and the force ``f`` read and written (48 B): 108 B per
node, amortised over the node's bonds (about 9): ``108 n_nodes / n_bonds`` ~ 12 B per bond; the
9-entry direction tables are cache resident and not counted. Bound = bandwidth / bytes-per-bond; the
ratio achieved/bound says how far the kernel is from being bandwidth-limited (for the 1e4 and
1e5 blocks the arrays fit in the last-level cache, so the DRAM bound does not bind there).

Memory of building the :class:`md.AcousticSystem` of the largest block: peak of
:mod:`tracemalloc` (numpy registers its buffers with it) and the rise of
``resource.getrusage(RUSAGE_SELF).ru_maxrss`` during the build (measured before anything else
large is allocated), and the bytes the finished system keeps, all per cement node.

Projection to the source's full sample (not run): 8 x 8 x 32 grain diameters, grain radius
0.19 mm, porosity 0.39, Omega = 10 (``c_w = R/10``): pore cells ``0.39 V / c_w^3``. Lattice bonds
per cement node and grain-cement bonds per cement node are measured on the small compacted pack
of ``md_pulse_error_vs_time.py`` (``--pack``, default ``results/md_pulse_pack/compact.nc``) at
Omega = 10 for S_c = 1 (every pore cell) and S_c = 0.1 (contact cement); if that file is absent,
9 bonds per node (the upper bound) is used. Time step: ``0.5 * 2 / omega_max`` of a cement block
of that cell width (time_step_factor 0.5; the pack's own, smaller, time step is reported beside
it); simulated time ``2 * sample height / 3000 m/s``. Projected wall time of one pulse test =
steps x lattice bonds / (updates/s of the largest block) -- the lattice springs only, a lower
bound -- and, second, steps x lattice bonds x (measured wall time of one full
``leapfrog_run`` step per lattice bond on the small pack at the same Omega and S_c: contact
bonds, particle update and slab signals included). Neither includes the static solve that
:func:`md.pulse_test` also runs.

Output: ``benchmarks/results/md_lattice_throughput.{csv,nc}`` and markdown tables on stdout.
Run: ``python benchmarks/md_lattice_throughput.py [--sizes 1e4 1e5 1e6 1e7] [--rounds 3]``
(about 1-2 min on the 2-core machine of docs/studies/index.md).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import resource  # noqa: E402
import time  # noqa: E402
import tracemalloc  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_lattice_throughput"
SIZES = (1e4, 1e5, 1e6, 1e7)
CELL = 1e-5                       # cell width of the blocks, m
TARGET = 1e8                      # lattice-spring updates / s / core (the issue)
# The source's full sample (García & Medina): 8 x 8 x 32 grain diameters.
SAMPLE_DIAMETERS = (8, 8, 32)
GRAIN_RADIUS = 0.19e-3
SAMPLE_POROSITY = 0.39
SAMPLE_OMEGA = 10.0
BYTES_PER_NODE = 9 * 4 + 24 + 48  # neighbour-table row (9 int32); u read; f read + write




def block_shape(n_nodes):
    side = max(3, round(float(n_nodes) ** (1.0 / 3.0)))
    return (side, side, side)


def system_nbytes(system):
    """Bytes held by the arrays of an AcousticSystem."""
    return int(sum(v.nbytes for v in vars(system).values() if isinstance(v, np.ndarray)))


def build_memory(shape):
    """Peak (tracemalloc), maxrss rise and retained bytes of building a cement block."""
    import md

    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    tracemalloc.start()
    t0 = time.perf_counter()
    block = md.cement_block(shape, CELL, md.HARD_CEMENT)
    seconds = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss1 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return block, dict(build_seconds=seconds, peak_traced_bytes=int(peak),
                       maxrss_rise_bytes=int(max(rss1 - rss0, 0)) * 1024,
                       retained_bytes=system_nbytes(block))


_BASELINE = None


def baseline_kernel():
    """The baseline: the same spring forces over a bond list (two int32 indices and an int8
    direction per bond, one bond after another, both ends scattered) -- md's layout before the
    neighbour table. Compiled here, not kept in the library."""
    global _BASELINE
    if _BASELINE is None:
        from numba import njit

        @njit(cache=True)
        def bond_list_forces(u, bi, bj, bd, lat_nrm, lat_kn, lat_kt, f):
            for b in range(bi.shape[0]):
                i = bi[b]
                j = bj[b]
                d = bd[b]
                k_t = lat_kt[d]
                dx = u[j, 0] - u[i, 0]
                dy = u[j, 1] - u[i, 1]
                dz = u[j, 2] - u[i, 2]
                dn = (lat_kn[d] - k_t) * (dx * lat_nrm[d, 0] + dy * lat_nrm[d, 1]
                                          + dz * lat_nrm[d, 2])
                fx = k_t * dx + dn * lat_nrm[d, 0]
                fy = k_t * dy + dn * lat_nrm[d, 1]
                fz = k_t * dz + dn * lat_nrm[d, 2]
                f[i, 0] += fx
                f[i, 1] += fy
                f[i, 2] += fz
                f[j, 0] -= fx
                f[j, 1] -= fy
                f[j, 2] -= fz

        _BASELINE = bond_list_forces
    return _BASELINE


def kernel_calls(system):
    """No-argument calls of the lattice kernel and of the bond-list baseline on ``system``
    with the same random displacements, warmed up (compilation or cache load, first touch of
    ``f``); checked to give the same forces."""
    from md._kernels_acoustic import lattice_forces
    from md.acoustic import _LATTICE_NORMALS

    rng = np.random.default_rng(0)
    u = rng.normal(scale=1e-9, size=(system.n_particles, 3))
    f, f_base = np.zeros_like(u), np.zeros_like(u)
    args = (u, system.lattice_neighbors, system.n_grains, _LATTICE_NORMALS, system.lattice_kn,
            system.lattice_kt, f, np.zeros(0), False, 2)
    bi, bj, bd = system.lattice_i, system.lattice_j, system.lattice_dir
    base = baseline_kernel()
    base_args = (u, bi, bj, bd, _LATTICE_NORMALS, system.lattice_kn, system.lattice_kt, f_base)
    lattice_forces(*args)
    base(*base_args)
    scale = np.abs(f_base).max()
    if not np.allclose(f, f_base, rtol=0.0, atol=1e-12 * scale):
        raise RuntimeError("lattice_forces and the bond-list baseline disagree")

    def call():
        lattice_forces(*args)

    def call_base():
        base(*base_args)
    return call, call_base


def copy_bandwidth(gigabytes, repeat=5):
    """Streaming bandwidth from np.copyto of two float64 arrays, bytes/s (2 x nbytes per copy)."""
    n = int(gigabytes * 1e9 / 8)
    a = np.ones(n)
    b = np.empty_like(a)
    np.copyto(b, a)                                         # fault in b's pages
    best, _, _, _ = _common.best_of(lambda: np.copyto(b, a), repeat)
    return 2 * a.nbytes / best, a.nbytes, best


def pack_ratios(pack_path, repeat_steps):
    """Bonds per cement node, time step and full leapfrog step time on the small pack at the
    sample's Omega, for S_c = 1 and 0.1 (None if the pack file is absent)."""
    import md
    from md._kernels_acoustic import leapfrog_run

    if not Path(pack_path).is_file():
        return None
    pack = md.load_pack(pack_path)
    lat = md.cement_lattice(pack, SAMPLE_OMEGA)
    out = {"pack_grains": pack.n_grains, "pack_mean_radius_m": float(pack.radii.mean()),
           "pack_cell_width_m": float(lat.cell_width),
           "pack_pore_fraction": lat.index.size / float(np.prod(lat.shape))}
    for sc, scheme in ((1.0, "coating"), (0.1, "contact")):
        cem = md.grow_cement(lat, sc, scheme)
        system = md.acoustic_system(pack, lat, cem, md.HARD_CEMENT, rotations=False)
        n_c = int(system.metadata["n_cement"])
        dt = 0.5 * 2.0 / system.max_frequency()
        # One pulse-test step, as md.pulse_test runs it (signals recorded every step).
        slab, n_slabs = system.slabs()
        flag = np.zeros(system.n_particles, np.int8)
        flag[slab == n_slabs - 1] = 1
        flag[slab == 0] = 2
        u = np.zeros((system.n_particles, 3))
        v = np.zeros_like(u)
        amp = 1e-4 * system.slab_thickness
        u[flag == 2, 2] = amp
        args = (u, v, 1.0 / system.masses, flag, slab, n_slabs, *system._kernel_args(), dt)

        def run(steps, args=args, n_slabs=n_slabs, amp=amp, dt=dt):
            rec = np.empty((steps, n_slabs))
            leapfrog_run(*args, 0.0, steps, amp, 1e3 * dt, 1, 2, rec)

        run(2)                                              # warm-up
        best, _, _, _ = _common.best_of(lambda: run(repeat_steps), 3)
        out[sc] = dict(n_cement=n_c, lattice_bonds_per_node=system.n_lattice_bonds / n_c,
                       grain_cement_bonds_per_node=(system.bond_i.size
                                                    - system.metadata["n_grain_contacts"]) / n_c,
                       pack_time_step_s=dt,
                       step_seconds_per_lattice_bond=best / repeat_steps / system.n_lattice_bonds,
                       pack_lattice_bonds=system.n_lattice_bonds,
                       pack_step_seconds=best / repeat_steps)
    return out



def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES,
                        help="cement nodes of the blocks (cubes), default 1e4 1e5 1e6 1e7")
    parser.add_argument("--rounds", type=int, default=3,
                        help="timing rounds over all blocks (default 3; best call kept)")
    parser.add_argument("--min-time", type=float, default=0.5,
                        help="kernel calls per block and round fill at least this many s "
                             "(default 0.5)")
    parser.add_argument("--copy-gb", type=float, default=1.0,
                        help="size of each array of the bandwidth copy, GB (default 1)")
    parser.add_argument("--pack", type=Path,
                        default=_common.RESULTS / "md_pulse_pack" / "compact.nc",
                        help="compacted pack for the bonds-per-node ratios of the projection")
    parser.add_argument("--pack-steps", type=int, default=20,
                        help="leapfrog steps timed on the pack (default 20)")
    parser.add_argument("--tag", default="",
                        help="suffix of the result file names, e.g. a commit (default none)")
    args = parser.parse_args(argv)

    import pandas as pd
    import xarray as xr

    import md

    _common.announce_source()
    md_src = _common.md_source_attrs()
    print(f"md from {md_src['md_path']}, uncommitted: {md_src['git_uncommitted_md_files']}, "
          f"sources sha256 {md_src['md_source_sha256'][:12]}", flush=True)
    t_start = time.perf_counter()
    md.cement_block((3, 3, 3), CELL)                         # compile / load lattice_bonds
    shapes = sorted({block_shape(n) for n in args.sizes}, key=lambda s: np.prod(s))

    # ---- memory of the largest build, first (ru_maxrss is a high-water mark)
    largest, mem = build_memory(shapes[-1])
    n_big = largest.n_particles
    print(f"largest block {shapes[-1]}: {n_big} nodes, built in {mem['build_seconds']:.2f} s; "
          f"tracemalloc peak {mem['peak_traced_bytes'] / 1e6:.1f} MB "
          f"({mem['peak_traced_bytes'] / n_big:.0f} B/node), maxrss rise "
          f"{mem['maxrss_rise_bytes'] / 1e6:.1f} MB, kept {mem['retained_bytes'] / 1e6:.1f} MB "
          f"({mem['retained_bytes'] / n_big:.0f} B/node)", flush=True)

    # ---- streaming bandwidth (same run, same process)
    bandwidth, copy_bytes, copy_s = copy_bandwidth(args.copy_gb)
    print(f"np.copyto of {copy_bytes / 1e9:.2f} GB: {copy_s * 1e3:.1f} ms, "
          f"{bandwidth / 1e9:.2f} GB/s (2 x nbytes)", flush=True)

    # ---- the kernel. Timing rounds go round-robin over the blocks (``--rounds``), each round
    # calling the kernel for at least ``--min-time`` s per block, so that a burst of load from
    # other processes hits a few calls of every block rather than all calls of one; the best
    # call per block is kept (its median is recorded too).
    systems = [largest if shape == shapes[-1] else md.cement_block(shape, CELL, md.HARD_CEMENT)
               for shape in shapes]
    del largest
    calls = [kernel_calls(system) for system in systems]
    times = [([], []) for _ in shapes]
    warnings_seen = [[] for _ in shapes]
    for _ in range(max(1, args.rounds)):
        for k, pair in enumerate(calls):
            for which, call in enumerate(pair):
                t0 = time.perf_counter()
                call()
                first = time.perf_counter() - t0
                n_calls = max(1, math.ceil(args.min_time / max(first, 1e-9)))
                _, t_run, _, warns = _common.best_of(call, n_calls, budget_s=args.min_time)
                times[k][which].extend([first, *t_run])
                warnings_seen[k].extend(w for w in warns if w not in warnings_seen[k])
    rows = []
    for shape, system, (t_all, t_base), warns in zip(shapes, systems, times, warnings_seen):
        n_nodes, n_bonds = system.n_particles, system.n_lattice_bonds
        best, best_base = min(t_all), min(t_base)
        bytes_per_bond = BYTES_PER_NODE * n_nodes / n_bonds
        rate, rate_base = n_bonds / best, n_bonds / best_base
        bound = bandwidth / bytes_per_bond
        working_set = system.lattice_neighbors.nbytes + 48 * n_nodes          # table, u, f
        rows.append(dict(case="kernel", shape="x".join(map(str, shape)), n_nodes=n_nodes,
                         n_bonds=n_bonds, bonds_per_node=n_bonds / n_nodes, runs=len(t_all),
                         seconds=best, seconds_median=float(np.median(t_all)),
                         updates_per_s=rate, updates_per_s_median=n_bonds / np.median(t_all),
                         ns_per_update=1e9 / rate,
                         baseline_updates_per_s=rate_base,
                         baseline_updates_per_s_median=n_bonds / np.median(t_base),
                         speedup_vs_baseline=rate / rate_base,
                         bytes_per_bond=bytes_per_bond, working_set_bytes=working_set,
                         bandwidth_bound_updates_per_s=bound, ratio_to_bound=rate / bound,
                         target_met=bool(rate >= TARGET),
                         target_met_median=bool(n_bonds / np.median(t_all) >= TARGET),
                         warnings=" | ".join(warns)))
        r = rows[-1]
        print(f"{r['shape']:>11s}: {n_nodes:9d} nodes {n_bonds:10d} bonds  {best * 1e3:9.3f} ms"
              f"  {rate:.3g} updates/s ({1e9 / rate:.2f} ns; median of {len(t_all)} calls "
              f"{r['updates_per_s_median']:.3g}); bond-list baseline {rate_base:.3g} "
              f"(x{rate / rate_base:.2f}); bound {bound:.3g} ({bytes_per_bond:.2f} B/bond)"
              f"  ratio {rate / bound:.3f}  target 1e8 {'met' if rate >= TARGET else 'NOT met'}",
              flush=True)
    del systems, calls
    rate_big = rows[-1]["updates_per_s"]

    # ---- projection to the full sample
    d = 2.0 * GRAIN_RADIUS
    volume = np.prod(SAMPLE_DIAMETERS) * d**3
    height = SAMPLE_DIAMETERS[2] * d
    cw = GRAIN_RADIUS / SAMPLE_OMEGA
    pore_cells = SAMPLE_POROSITY * volume / cw**3
    omega_block = md.cement_block((4, 4, 4), cw, md.HARD_CEMENT).max_frequency()
    dt = 0.5 * 2.0 / omega_block
    sim_time = 2.0 * height / md.HARD_CEMENT.vp
    steps = math.ceil(sim_time / dt)
    ratios = pack_ratios(args.pack, args.pack_steps)
    ratio_note = (f"measured on {args.pack} at Omega {SAMPLE_OMEGA:g}" if ratios else
                  f"{args.pack} absent: 9 lattice bonds per node (upper bound)")
    for sc in (1.0, 0.1):
        n_c = sc * pore_cells
        per = ratios[sc] if ratios else {}
        bpn = per.get("lattice_bonds_per_node", 9.0)
        bonds = n_c * bpn
        step_lat = bonds / rate_big
        step_full = bonds * per.get("step_seconds_per_lattice_bond", np.nan)
        rows.append(dict(case="projection", saturation=sc, n_nodes=round(n_c),
                         n_bonds=round(bonds), bonds_per_node=bpn,
                         grain_cement_bonds_per_node=per.get("grain_cement_bonds_per_node",
                                                             np.nan),
                         time_step_s=dt, pack_time_step_s=per.get("pack_time_step_s", np.nan),
                         steps=steps, simulated_time_s=sim_time,
                         step_seconds_lattice=step_lat, wall_s_lattice=steps * step_lat,
                         step_seconds_per_lattice_bond_pack=per.get(
                             "step_seconds_per_lattice_bond", np.nan),
                         step_seconds_full=step_full, wall_s_full=steps * step_full,
                         wall_s_full_pack_dt=(step_full * math.ceil(
                             sim_time / per["pack_time_step_s"]) if per else np.nan)))
    total = time.perf_counter() - t_start
    print(f"total benchmark time {total:.1f} s")

    # ---- output
    frame = pd.DataFrame(rows)
    pack_attrs = {}
    if ratios:
        pack_attrs = {"pack_grains": ratios["pack_grains"],
                      "pack_cell_width_m": ratios["pack_cell_width_m"],
                      "pack_pore_fraction": ratios["pack_pore_fraction"]}
        for sc in (1.0, 0.1):
            for k in ("n_cement", "pack_lattice_bonds", "pack_step_seconds"):
                pack_attrs[f"pack_Sc{sc:g}_{k}"] = ratios[sc][k]
    attrs = _common.environment_attrs(
        title="md cement lattice: lattice-spring updates per second per core",
        benchmark=NAME, kernel="md._kernels_acoustic.lattice_forces (serial numba)",
        blocks=f"md.cement_block(shape, {CELL:g} m, HARD_CEMENT), random u (scale 1e-9 m)",
        timing=f"{args.rounds} rounds round-robin over the blocks, calls filling "
               f"{args.min_time:g} s per block and round, best call kept; after a warm-up call",
        target_updates_per_s=TARGET,
        byte_model=f"{BYTES_PER_NODE} B per node (neighbour-table row 36 B, u read 24 B, f "
                   "read+write 48 B) amortised over its bonds",
        baseline="the same spring forces over a bond list (bi, bj int32, bd int8; md's "
                 "layout before the neighbour table), compiled in this script, same u, "
                 "checked equal, timed in the same rounds",
        bandwidth_method=f"np.copyto(b, a), float64 arrays of {copy_bytes} B each, best of 5, "
                         "2 x nbytes per copy (write-allocate traffic not counted)",
        copy_bandwidth_bytes_per_s=bandwidth, copy_seconds=copy_s,
        largest_block_shape=json.dumps(list(shapes[-1])), largest_block_nodes=n_big,
        build_seconds=mem["build_seconds"], build_peak_traced_bytes=mem["peak_traced_bytes"],
        build_peak_traced_bytes_per_node=mem["peak_traced_bytes"] / n_big,
        build_maxrss_rise_bytes=mem["maxrss_rise_bytes"],
        build_maxrss_rise_bytes_per_node=mem["maxrss_rise_bytes"] / n_big,
        system_retained_bytes=mem["retained_bytes"],
        system_retained_bytes_per_node=mem["retained_bytes"] / n_big,
        sample=f"{SAMPLE_DIAMETERS} grain diameters, R = {GRAIN_RADIUS:g} m, porosity "
               f"{SAMPLE_POROSITY:g}, Omega {SAMPLE_OMEGA:g} (not run)",
        sample_volume_m3=volume, sample_height_m=height, sample_cell_width_m=cw,
        sample_pore_cells=pore_cells, sample_time_step_s=dt, sample_steps=steps,
        sample_simulated_time_s=sim_time,
        time_step_method="time_step_factor 0.5 x 2 / omega_max of cement_block((4,4,4), c_w)",
        projection_rate_updates_per_s=rate_big, bonds_per_node_source=ratio_note,
        projection_note="wall_s_lattice: lattice springs only at the largest block's rate "
                        "(lower bound); wall_s_full: lattice bonds x full leapfrog step time "
                        "per lattice bond measured on the small pack; neither includes the "
                        "static solve of pulse_test",
        total_run_s=total, **pack_attrs, **md_src)
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    kern = frame[frame.case == "kernel"]
    proj = frame[frame.case == "projection"]
    kvars = {"shape": ("1", "block cells nx x ny x nz"), "n_bonds": ("1", "lattice bonds"),
             "bonds_per_node": ("1", "lattice bonds per node"), "runs": ("1", "timed calls"),
             "seconds": ("s", "best wall time of one lattice_forces call"),
             "seconds_median": ("s", "median wall time of one lattice_forces call"),
             "updates_per_s": ("s-1", "lattice-spring updates per second, one core"),
             "updates_per_s_median": ("s-1", "the same from the median call"),
             "ns_per_update": ("ns", "wall time per lattice-spring update"),
             "bytes_per_bond": ("B", "bytes moved per bond (byte model)"),
             "working_set_bytes": ("B", "bi, bj, bd, u, f"),
             "bandwidth_bound_updates_per_s": ("s-1", "copy bandwidth / bytes per bond"),
             "ratio_to_bound": ("1", "achieved / bandwidth bound"),
             "baseline_updates_per_s": ("s-1", "bond-list baseline, updates per second"),
             "baseline_updates_per_s_median": ("s-1", "the same from the median call"),
             "speedup_vs_baseline": ("1", "updates_per_s / baseline_updates_per_s"),
             "target_met": ("1", "updates_per_s >= 1e8"),
             "target_met_median": ("1", "updates_per_s_median >= 1e8")}
    pvars = {"n_nodes": ("1", "projected cement particles"),
             "n_bonds": ("1", "projected lattice bonds"),
             "bonds_per_node": ("1", "lattice bonds per cement particle"),
             "grain_cement_bonds_per_node": ("1", "grain-cement bonds per cement particle"),
             "time_step_s": ("s", "time step of a cement block, factor 0.5"),
             "pack_time_step_s": ("s", "time step of the small pack at Omega 10, factor 0.5"),
             "steps": ("1", "time steps of one pulse test"),
             "step_seconds_lattice": ("s", "lattice springs per step at the measured rate"),
             "wall_s_lattice": ("s", "one pulse test, lattice springs only"),
             "step_seconds_per_lattice_bond_pack": ("s", "full step per lattice bond, pack"),
             "step_seconds_full": ("s", "full step projected from the pack"),
             "wall_s_full": ("s", "one pulse test, full step, block time step"),
             "wall_s_full_pack_dt": ("s", "one pulse test, full step, pack time step")}
    data = {}
    for name, (unit, ln) in kvars.items():
        if name.startswith("target_met"):
            values = kern[name].astype(bool).to_numpy().astype(np.int8)
        elif name == "shape":
            values = kern[name].astype(str).to_numpy()
        else:
            values = kern[name].to_numpy(dtype=float)
        data[f"kernel_{name}"] = ("n_nodes", values, {"units": unit, "long_name": ln})
    for name, (unit, ln) in pvars.items():
        data[f"sample_{name}"] = ("saturation", proj[name].to_numpy(dtype=float),
                                  {"units": unit, "long_name": ln})
    ds = xr.Dataset(data, coords={
        "n_nodes": ("n_nodes", kern.n_nodes.to_numpy(), {"long_name": "cement nodes of the block"}),
        "saturation": ("saturation", proj.saturation.to_numpy(),
                       {"long_name": "cement saturation S_c of the projected sample"})},
        attrs=attrs)
    _common.write_netcdf(ds, _common.result_path(NAME, "nc", args.tag))

    print("\nlattice_forces, one core\n")
    print(_common.markdown(kern, {"shape": ("block", "s"), "n_nodes": ("nodes", "d"),
                          "n_bonds": ("bonds", "d"), "seconds": ("s per call", ".4g"),
                          "updates_per_s": ("updates/s (best)", ".3g"),
                          "updates_per_s_median": ("updates/s (median)", ".3g"),
                          "baseline_updates_per_s": ("bond list (best)", ".3g"),
                          "speedup_vs_baseline": ("x bond list", ".2f"),
                          "ns_per_update": ("ns/update", ".2f"),
                          "bytes_per_bond": ("B/bond", ".2f"),
                          "bandwidth_bound_updates_per_s": ("bound (updates/s)", ".3g"),
                          "ratio_to_bound": ("achieved/bound", ".3f"),
                          "target_met": (">= 1e8", ""),
                          "target_met_median": ("median >= 1e8", "")}))
    print(f"\ncopy bandwidth {bandwidth / 1e9:.2f} GB/s; building the {n_big}-node block: "
          f"tracemalloc peak {mem['peak_traced_bytes'] / n_big:.0f} B/node, maxrss rise "
          f"{mem['maxrss_rise_bytes'] / n_big:.0f} B/node, kept "
          f"{mem['retained_bytes'] / n_big:.0f} B/node")
    print(f"\nfull sample {SAMPLE_DIAMETERS} diameters, Omega {SAMPLE_OMEGA:g} (c_w = "
          f"{cw * 1e6:.1f} um): {pore_cells:.3g} pore cells, dt {dt:.3g} s, {steps} steps for "
          f"{sim_time * 1e6:.2f} us; bonds per node: {ratio_note}\n")
    print(_common.markdown(proj, {"saturation": ("S_c", "g"), "n_nodes": ("cement nodes", ".3g"),
                          "bonds_per_node": ("bonds/node", ".2f"),
                          "n_bonds": ("lattice bonds", ".3g"),
                          "step_seconds_lattice": ("s/step (lattice)", ".3g"),
                          "wall_s_lattice": ("pulse test (lattice only), s", ".0f"),
                          "step_seconds_full": ("s/step (full, from pack)", ".3g"),
                          "wall_s_full": ("pulse test (full), s", ".0f"),
                          "wall_s_full_pack_dt": ("pulse test (full, pack dt), s", ".0f")}))
    stem = _common.result_path(NAME, "", args.tag)
    print(f"wrote {stem}{{csv,nc}}")


if __name__ == "__main__":
    main()
