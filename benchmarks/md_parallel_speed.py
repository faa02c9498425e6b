"""Pulse-test time steps and static solve on 2 numba threads against 1, in the same run.

The linearised system of the 4 x 4 x 12 compacted pack of ``md_omega_convergence.py`` with
pendular hard cement (S_c 0.1) at Omega 12. Timed, best of 3: a block of leapfrog steps with
the serial scatter kernel (``md._kernels_acoustic.leapfrog_run``, the baseline) and with the
gather kernel (``md._kernels_parallel.leapfrog_run_parallel``) on 1 and 2 threads; and the static
P modulus (CG) with the serial and the 2-thread operator. The machine has 2 cores shared with
other jobs, so the ratios are what this machine gave at the time, not the cores' capacity.

Output: ``results/md_parallel_speed.csv``.
Run: ``python benchmarks/md_parallel_speed.py [--omega 12] [--steps 200]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)
import os  # noqa: E402

os.environ["NUMBA_NUM_THREADS"] = "2"       # this benchmark measures the threads

import argparse  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_parallel_speed"


def main(argv=None):
    import numba
    import pandas as pd

    import md
    from md._kernels_acoustic import leapfrog_run
    from md._kernels_parallel import leapfrog_run_parallel

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, default=12.0)
    ap.add_argument("--steps", type=int, default=200)
    args = ap.parse_args(argv)
    _common.announce_source()
    pack = md.load_pack(_common.RESULTS / "md_omega_convergence_work" / "pack_4x4x12"
                        / "compact.nc")
    lat = md.cement_lattice(pack, args.omega)
    system = md.acoustic_system(pack, lat, md.grow_cement(lat, 0.1, "pendular"),
                                rotations=False)          # the threaded kernels translate only
    slab, n_slabs = system.slabs()
    n = system.n_particles
    flag = np.zeros(n, np.int8)
    flag[slab == 0] = 2
    flag[slab == n_slabs - 1] = 1
    inv_m = 1.0 / system.masses
    dt = 0.5 * 2.0 / system.max_frequency()
    amp = 1e-4 * system.slab_thickness
    rec = np.empty((args.steps, n_slabs))

    def steps(run, table_args):
        u = np.zeros((n, 3))
        v = np.zeros((n, 3))
        run(u, v, inv_m, flag, slab, n_slabs, *table_args, dt, 0.0, args.steps, amp, 1.0, 1,
            2, rec)
        return u

    serial_args, gather_args = system._kernel_args(), system.gather_args()
    u_serial = steps(leapfrog_run, serial_args)
    rows = []
    t_serial = _common.best_of(lambda: steps(leapfrog_run, serial_args), 3)[0]
    rows.append(dict(case="pulse steps, serial scatter kernel", threads=1, seconds=t_serial))
    for threads in (1, 2):
        numba.set_num_threads(threads)
        u_par = steps(leapfrog_run_parallel, gather_args)
        assert np.allclose(u_par, u_serial, rtol=1e-9, atol=1e-12 * np.abs(u_serial).max())
        t = _common.best_of(lambda: steps(leapfrog_run_parallel, gather_args), 3)[0]
        rows.append(dict(case="pulse steps, gather kernel", threads=threads, seconds=t))
    numba.set_num_threads(1)
    t_s1 = _common.best_of(lambda: md.static_modulus(system), 2)[0]
    rows.append(dict(case="static solve, serial operator", threads=1, seconds=t_s1))
    numba.set_num_threads(2)
    t_s2 = _common.best_of(lambda: md.static_modulus(system, parallel=True), 2)[0]
    rows.append(dict(case="static solve, gather operator", threads=2, seconds=t_s2))
    df = pd.DataFrame(rows)
    df["ratio_to_serial"] = [t_serial / r for r in df.seconds[:3]] + [1.0, t_s1 / t_s2]
    df["particles"] = n
    df["steps"] = args.steps
    print(df.to_string(index=False))
    attrs = _common.environment_attrs(benchmark=NAME, omega=args.omega,
                                      **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv"), attrs)


if __name__ == "__main__":
    main()
