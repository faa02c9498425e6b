"""Speed of reading a wide LAS file against the same data as CSV (issue 30: 5000 curves, 110 s).

For each number of curves (default 500, 1500 and 5000; 200 depth rows, unwrapped LAS 2.0 with
space-delimited data, values with 4 decimals), the script writes one LAS file and one CSV file of
the same data (the same mnemonics, units and numbers) and times
:func:`rockcem.wells.read_well` on each in the same process, best of ``--repeat`` runs after a
warm-up read of a small file (imports excluded). It checks that both reads give the same
Dataset and reports the ratio LAS / CSV.

Output: ``benchmarks/results/las_read_speed[_<tag>].csv``. Run:
``python benchmarks/las_read_speed.py`` (this checkout); the "before" row of the study page was
measured with ``ROCKCEM_BENCH_PATH=<checkout of the earlier commit> python
benchmarks/las_read_speed.py --tag before --repeat 1``.
"""

from _common import announce_source, best_of, environment_attrs, result_path, write_csv

import argparse  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

ROWS = 200


def write_pair(folder: Path, n_curves: int, rows: int = ROWS, seed: int = 0):
    """A LAS file and a CSV file of the same ``n_curves`` curves (depth, sonic, then fractions)
    over ``rows`` depths; returns their paths."""
    rng = np.random.default_rng(seed)
    depth = 1000.0 + np.arange(rows, dtype=float)
    dt = np.round(rng.uniform(60.0, 140.0, rows), 4)
    other = np.round(rng.uniform(0.0, 0.4, (rows, n_curves - 2)), 4)
    data = np.column_stack([depth, dt, other])
    names = ["DEPT", "DT"] + [f"C{j}" for j in range(n_curves - 2)]
    units = ["M", "US/FT"] + ["V/V"] * (n_curves - 2)
    lines = ["~Version", "VERS. 2.0 :", "WRAP. NO :", "~Well",
             f"STRT.M {depth[0]:g} :", f"STOP.M {depth[-1]:g} :", "STEP.M 1 :",
             "NULL. -999.25 :", "WELL. W :", "~Curve"]
    lines += [f"{m}.{u} : c" for m, u in zip(names, units)]
    lines.append("~A")
    lines += [" ".join(f"{v:.4f}" for v in row) for row in data]
    las = folder / f"wide_{n_curves}.las"
    las.write_text("\n".join(lines) + "\n")
    csv = folder / f"wide_{n_curves}.csv"
    header = ",".join(f"{m} ({u})" for m, u in zip(names, units))
    csv.write_text(header + "\n" + "\n".join(",".join(f"{v:.4f}" for v in row) for row in data)
                   + "\n")
    return las, csv


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--curves", type=int, nargs="+", default=[500, 1500, 5000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--tag", default="", help="suffix of the result file (e.g. before)")
    args = parser.parse_args(argv)
    from rockcem.wells import read_well

    announce_source()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        small_las, small_csv = write_pair(folder, 10)
        read_well(small_las), read_well(small_csv)           # warm-up: imports excluded
        for n in args.curves:
            las, csv = write_pair(folder, n)
            t_csv, _, from_csv, _ = best_of(lambda: read_well(csv), args.repeat, budget_s=60)
            t_las, _, from_las, _ = best_of(lambda: read_well(las), args.repeat, budget_s=60)
            same = all(np.array_equal(from_las[v].values, from_csv[v].values, equal_nan=True)
                       for v in from_csv.data_vars) and \
                set(from_las.data_vars) == set(from_csv.data_vars) and \
                np.array_equal(from_las["depth"].values, from_csv["depth"].values)
            if not same:
                raise SystemExit(f"{n} curves: the LAS and CSV reads differ")
            rows.append(dict(curves=n, rows=ROWS, las_mb=las.stat().st_size / 1e6,
                             las_s=t_las, csv_s=t_csv, ratio=t_las / t_csv))
            print(f"{n:5d} curves: LAS {t_las:7.2f} s, CSV {t_csv:6.2f} s, "
                  f"LAS/CSV {t_las / t_csv:6.2f}", flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(benchmark="las_read_speed", repeat=args.repeat,
                              timing="best of repeat runs after a warm-up read, wall s")
    write_csv(table, result_path("las_read_speed", "csv", args.tag), attrs)
    print(table.to_string(index=False))


if __name__ == "__main__":
    main()
