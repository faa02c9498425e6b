"""The static solve of the shipped MD example's thick-cement members: iterative against direct.

The members of ``rockcem run carcione2022_sandstone_md`` that cost most are those whose quartz
coating is whole cells (3500-4000 m) or fills the pores (4500-6000 m). Their five transversely
isotropic constants (:func:`md.static.static_stiffness`) are solved on the free degrees of
freedom of the linearised sample, either by conjugate gradients preconditioned with the
per-particle blocks (``solver="cg"``) or by a sparse factor of the pinned, scaled, shifted
matrix :math:`A = D^{-1/2} K_{ff} D^{-1/2} + N N^T + \\delta I` refined by a few preconditioned
iterations (``solver="lu"``; :func:`md.static._pinned_matrix`), the factor being SuperLU's
(md's, :func:`md.static._factorise`), CHOLMOD's supernodal sparse Cholesky through
``cholespy`` (``cholmod``) or MKL PARDISO's through ``pypardiso`` (``pardiso``); the last two
are put in place of md's factor here (each method that is not installed is left out).

The members are built as the example builds them (:func:`md.along_depth.carry_down`): one pack
(default the example's 4 x 4 x 12 grain diameters, seed 0) settled, compacted down the
depths' effective stresses, reconstructed to burial's intergranular volume, the coating grown
with burial (carried from 3500 m on), at each resolution Omega. For each member and Omega:
the free degrees of freedom, the cement lattice's mean degree, which solver ``"auto"`` takes,
the time to grow its cement and build the linearised system, and for each method the wall
time of ``static_stiffness`` (set-up, factor and five solves;
best of ``--repeat`` runs, the methods interleaved round by round on one pinned core, one
BLAS/OpenMP thread), the factor alone and the peak resident memory above the start of the call;
and the largest relative difference of the five constants from the reference method's
(SuperLU where it ran, else conjugate gradients). A method whose matrix exceeds its cap
(:data:`CAPS`) is not run there.

Writes ``benchmarks/results/md_static_solver.csv``. Run:
``python benchmarks/md_static_solver.py [--omega 2.67 4 6] [--depths 3500 4000 4500]
[--repeat 2]`` (about 10 min on one core).
"""

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import os  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

NAME = "md_static_solver"
#: The example's thick-cement depths (benchmarks/results/md_scene_example.csv, commit fc35671):
#: effective stress (MPa), cement fraction and burial porosity. 5000-6000 m are 4500 m's
#: full sample at a higher stress (the same matrix size and shape).
DEPTHS = {3500.0: (50.111981, 0.110241, 0.186695),
          4000.0: (57.270836, 0.195584, 0.094656),
          4500.0: (64.429691, 0.284488, 0.0)}
METHODS = ("cg", "superlu", "cholmod", "pardiso")
#: Largest free degrees of freedom each method is run on, where the cement lattice is
#: film-like (mean degree <= md.static.FILM_DEGREE) and where it is well connected. SuperLU
#: on the full sample at 1.8e5 took over 2 min and 3.3 GB before it was stopped, at 5.5e5
#: 12 GB in 15 min; PARDISO there took 81 s and 5.8 GB (conjugate gradients 48 s, 0.5 GB).
CAPS = {"cg": (10**7, 10**7), "superlu": (400_000, 60_000), "cholmod": (400_000, 120_000),
        "pardiso": (400_000, 400_000)}
CONSTANTS = ("c11", "c13", "c33", "c44", "c66")


def _memory_gb(field):
    """A memory line of ``/proc/self/status`` (``VmHWM``: peak resident, ``VmRSS``: now), GB."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(field + ":"):
                return int(line.split()[1]) / 1e6
    return float("nan")


def _reset_peak():
    """Reset the process's peak resident memory (Linux: ``/proc/self/clear_refs`` 5)."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
    except OSError:
        pass


def _cholmod_factorise():
    """A ``md.static._factorise`` by CHOLMOD's sparse Cholesky factor :math:`A = LL^T`
    (``cholespy``: the lower triangle, its own ordering and BLAS), or None without it."""
    try:
        import cholespy
    except ImportError:
        return None
    import scipy.sparse as sp

    def factorise(A):
        lower = sp.tril(A, format="csc")
        chol = cholespy.CholeskySolverD(A.shape[0], lower.indptr.astype(np.int32),
                                        lower.indices.astype(np.int32), lower.data.copy(),
                                        cholespy.MatrixType.CSC)

        def solve(b):
            x = np.empty(b.size)
            chol.solve(np.ascontiguousarray(b, dtype=float), x)
            return x

        return solve

    return factorise


def _pardiso_factorise():
    """A ``md.static._factorise`` by MKL PARDISO (real symmetric positive definite, mtype 2,
    the upper triangle, one thread), or None without ``pypardiso``."""
    try:
        import pypardiso
    except ImportError:
        return None
    import scipy.sparse as sp

    def factorise(A):
        solver = pypardiso.PyPardisoSolver(mtype=2)
        upper = sp.triu(A, format="csr")
        solver.factorize(upper)

        def solve(b):
            return solver.solve(upper, b)

        return solve

    return factorise


def _versions():
    from importlib.metadata import PackageNotFoundError, version

    out = []
    for name in ("cholespy", "pypardiso", "mkl"):
        try:
            out.append(f"{name} {version(name)}")
        except PackageNotFoundError:
            out.append(f"{name} absent")
    return out


def _members(args, work):
    """The example's members at each depth and Omega, as (depth, omega, AcousticSystem)."""
    from md.acoustic import acoustic_system
    from md.along_depth import _compacted, _grown_cement, _key, _reconstructed
    from md.cement import cement_lattice
    from md.growth import coating_is_film
    from md.protocols import prepare_pack
    from rockcem._md_backend import _materials
    from rockcem.materials import mineral

    g, c = _materials(mineral("quartz"), mineral("quartz_cement"))
    r_max = 0.15e-3                                   # D = 0.3 mm
    settle = {"size": tuple(args.size), "radius_range": (0.9 * r_max, r_max), "material": g,
              "seed": args.seed, "fall_stiffness_factor": 1e-3}
    chain = _key({k: (v if k != "material" else repr(v)) for k, v in settle.items()})
    pack = prepare_pack(work / "pack", settle_options=settle)
    pack_file = work / "pack" / "settle.nc"
    grown = {}
    for depth in sorted(args.depths):
        stress, frac, phi = DEPTHS[depth]
        pack, chain, made = _compacted(pack, stress * 1e6, work / "pack", chain, 5e-4, False)
        pack_file = made or pack_file
        here, key, _ = _reconstructed(pack, phi + frac, work / "pack", chain, pack_file)
        fill = phi < 0.005                  # burial's pores full (as carry_down)
        if coating_is_film(here, frac):
            raise ValueError(f"{depth:g} m is a film coating: not a thick-cement member")
        for omega in args.omega:
            t0 = time.perf_counter()
            state, cfile, _, _ = _grown_cement(here, key, frac, "coating", omega, args.seed,
                                               grown.get(omega), work / "cement", fill)
            grown[omega] = state
            import xarray as xr

            with xr.open_dataset(cfile, engine="netcdf4") as ds:
                cells = ds["cells"].values.astype(bool)
            system = acoustic_system(here, cement_lattice(here, omega), cells, c,
                                     interface="facet", slab_thickness=2 * r_max)
            yield depth, omega, system, time.perf_counter() - t0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--omega", type=float, nargs="+", default=[2.67, 4.0, 6.0])
    parser.add_argument("--depths", type=float, nargs="+", default=sorted(DEPTHS),
                        choices=sorted(DEPTHS))
    parser.add_argument("--size", type=float, nargs=3, default=[4.0, 4.0, 12.0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--methods", nargs="+", default=list(METHODS), choices=METHODS)
    parser.add_argument("--cpu", type=int, default=None, help="core to pin to (default: the "
                        "last one this process may use)")
    parser.add_argument("--workdir", default=None)
    parser.add_argument("--output", default=None)
    args = parser.parse_args(argv)
    cpu = args.cpu if args.cpu is not None else max(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cpu})
    _common.announce_source()
    import md.static as static
    from threadpoolctl import threadpool_info

    native = static._factorise
    factorise = {"superlu": native, "cholmod": _cholmod_factorise(),
                 "pardiso": _pardiso_factorise()}
    methods = [m for m in args.methods if m == "cg" or factorise[m] is not None]
    work = Path(args.workdir or tempfile.mkdtemp(prefix="md_static_solver_"))
    rows = []
    for depth, omega, system, build in _members(args, work):
        setup = static._StaticSetup(system, rtol=1e-10, maxiter=None, parallel=False,
                                    solver="auto")
        n_free, degree, auto = setup.free_idx.size, static._lattice_degree(setup.system), \
            setup.solver
        run = [m for m in methods
               if n_free <= CAPS[m][int(degree > static.FILM_DEGREE)]]
        print(f"{depth:g} m, Omega {omega:g}: {n_free} free dof, lattice degree {degree:.2f}, "
              f"auto takes {auto}; methods {run}", flush=True)
        best = {m: dict(wall=np.inf, factor=np.inf, peak=0.0) for m in run}
        result = {}
        for _ in range(args.repeat):
            for m in run:                   # interleaved: each round runs every method once
                factor_time = []

                def timed(A, m=m):
                    t = time.perf_counter()
                    solve = factorise[m](A)
                    factor_time.append(time.perf_counter() - t)
                    return solve

                static._factorise = timed
                try:
                    base = _memory_gb("VmRSS")
                    _reset_peak()
                    t0 = time.perf_counter()
                    st = static.static_stiffness(system, solver="cg" if m == "cg" else "lu")
                    wall = time.perf_counter() - t0
                    peak = _memory_gb("VmHWM") - base
                finally:
                    static._factorise = native
                b = best[m]
                b["wall"] = min(b["wall"], wall)
                b["factor"] = min(b["factor"], factor_time[0] if factor_time else 0.0)
                b["peak"] = max(b["peak"], peak)
                b["iterations"] = sum(v[2] for v in st.loads.values())
                result[m] = {k: getattr(st, k) for k in CONSTANTS}
                print(f"  {m}: {wall:.2f} s (factor {b['factor']:.2f} s), peak "
                      f"{peak:.2f} GB, {b['iterations']} iterations", flush=True)
        ref = "superlu" if "superlu" in result else "cg"
        for m in run:
            diff = max(abs(result[m][k] - result[ref][k]) / abs(result[ref][k])
                       for k in CONSTANTS)
            rows.append({"depth_m": depth, "omega": omega, "free_dof": n_free,
                         "lattice_degree": degree, "auto_solver": auto, "build_s": build,
                         "method": m,
                         "wall_s": best[m]["wall"], "factor_s": best[m]["factor"],
                         "solve_s": best[m]["wall"] - best[m]["factor"],
                         "peak_gb": best[m]["peak"], "iterations": best[m]["iterations"],
                         "reference": ref, "max_rel_diff": diff,
                         **{f"{k}_gpa": result[m][k] / 1e9 for k in CONSTANTS}})
        del setup, system
    table = pd.DataFrame(rows)
    # Ratios side by side, from the same run: each method's wall time over conjugate gradients'.
    cg = table[table.method == "cg"].set_index(["depth_m", "omega"]).wall_s
    table["wall_over_cg"] = [w / cg.get((d, o), np.nan)
                             for d, o, w in zip(table.depth_m, table.omega, table.wall_s)]
    blas = "; ".join(f"{p.get('internal_api')} {p.get('version')} ({p.get('num_threads')} "
                     "threads)" for p in threadpool_info())
    attrs = {**_common.environment_attrs(), **_common.md_source_attrs(),
             "pinned_cpu": cpu, "repeat": args.repeat, "thread_pools": blas,
             "caps_free_dof": "; ".join(f"{k} {v[0]} film, {v[1]} connected"
                                        for k, v in CAPS.items()),
             "packages": "; ".join(_versions()),
             "md": f"one pack {args.size} diameters, seed {args.seed}, the example's coating "
                   "grown with burial, rotations, static TI constants (five loads)",
             "units": "times s, memory GB (peak resident above the call's start), moduli GPa"}
    out = args.output or _common.result_path(NAME, "csv")
    table = table.round({c: 6 for c in table.columns if c != "max_rel_diff"})
    _common.write_csv(table, out, attrs)
    with pd.option_context("display.width", 200, "display.max_columns", 40):
        print(table[["depth_m", "omega", "free_dof", "lattice_degree", "auto_solver", "method",
                     "wall_s", "factor_s", "peak_gb", "iterations", "max_rel_diff",
                     "wall_over_cg"]].round(4).to_string(index=False))


if __name__ == "__main__":
    main()
