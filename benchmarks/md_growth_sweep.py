"""One growth for a saturation sweep (``md.cement_sweep``) against regrowing at every saturation.

The MD scene's saturation sweep (S_c 0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2) on the lattice of the
4 x 4 x 12 compacted pack of ``md_omega_convergence.py`` at Omega 12, for every scheme: the
wall time of ``md.grow_cement`` called once per saturation (baseline) and of one
``md.cement_sweep`` (one growth to the largest S_c, prefixes of its order), best of 3, in the
same run. The cemented cells are checked identical.

Output: ``results/md_growth_sweep.csv``.
Run: ``python benchmarks/md_growth_sweep.py [--omega 12]`` (after ``md_omega_convergence.py``
has made the pack).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_growth_sweep"
SATURATIONS = [0.0, 0.01, 0.02, 0.05, 0.1, 0.15, 0.2]


def main(argv=None):
    import pandas as pd

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, default=12.0)
    args = ap.parse_args(argv)
    _common.announce_source()
    pack = md.load_pack(_common.RESULTS / "md_omega_convergence_work" / "pack_4x4x12"
                        / "compact.nc")
    lat = md.cement_lattice(pack, args.omega)
    rows = []
    for scheme in md.cement.SCHEMES:
        def regrow():
            return np.stack([md.grow_cement(lat, s, scheme, seed=1) for s in SATURATIONS])

        def sweep():
            return md.cement_sweep(lat, SATURATIONS, scheme, seed=1)

        assert np.array_equal(regrow(), sweep())
        t_regrow = _common.best_of(regrow, 3)[0]
        t_sweep = _common.best_of(sweep, 3)[0]
        rows.append(dict(scheme=scheme, omega=args.omega, pore_cells=int(lat.index.size),
                         seconds_regrow=t_regrow, seconds_sweep=t_sweep,
                         speedup=t_regrow / t_sweep))
        print(f"{scheme:9s}: regrow {t_regrow:.3f} s, sweep {t_sweep:.3f} s, "
              f"x{t_regrow / t_sweep:.2f}", flush=True)
    df = pd.DataFrame(rows)
    attrs = _common.environment_attrs(benchmark=NAME, saturations=str(SATURATIONS),
                                      **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv"), attrs)


if __name__ == "__main__":
    main()
