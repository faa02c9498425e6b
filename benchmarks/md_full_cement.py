"""A sample whose pores burial fills: the MD frame against the bounds of its solid, against Ω.

Below 4450 m in the sandstone example (carcione2022_sandstone_md) burial's pores are full of
quartz cement: the sample is a solid of quartz grains and quartz cement, whose moduli lie
between the Hashin-Shtrikman bounds of the two (and below their Voigt average for any
microstructure, Hill 1963). One pack (3 x 3 x 10 grain diameters, seed 0) compacted to the
example's 64.5 MPa and reconstructed to its intergranular volume (0.2845), filled with
whole-cell cement, its five transversely isotropic constants solved at each resolution Ω.

Writes ``benchmarks/results/md_full_cement.csv``: per Ω the constants C33, C44, C11, C13,
C66 (GPa), their ratio to the Hashin-Shtrikman upper bound (C33 and C11 over the bound's
P modulus, C44 and C66 over its shear modulus), the step from the previous Ω and the wall
time of the member (compaction and settling shared, not counted); then the first-order
Richardson limit of each constant from the two finest resolutions. Run:
``python benchmarks/md_full_cement.py [--omega 3 4 6 9]`` (Ω 9 takes about 5 min and 1.4 GB
on one core).
"""

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

NAME = "md_full_cement"
#: The example's deepest MD depths (4500-6000 m): largest effective stress and cement.
STRESS_MPA = 64.5
CEMENT = 0.2845
CONSTANTS = ("p_modulus", "shear_modulus", "c11", "c13", "c66")
LABELS = {"p_modulus": "C33", "shear_modulus": "C44", "c11": "C11", "c13": "C13",
          "c66": "C66"}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--omega", type=float, nargs="+", default=[3.0, 4.0, 6.0, 9.0])
    parser.add_argument("--size", type=float, nargs=3, default=[3.0, 3.0, 10.0])
    parser.add_argument("--workdir", default=None, help="stage files (default: a temporary "
                        "folder)")
    parser.add_argument("--output", default=None)
    args = parser.parse_args(argv)
    _common.announce_source()
    from md.along_depth import carry_down
    from rockcem._md_backend import _materials
    from rockcem.bounds import hashin_shtrikman, voigt
    from rockcem.materials import mineral

    grain, cement = mineral("quartz"), mineral("quartz_cement")
    g, c = _materials(grain, cement)
    work = Path(args.workdir or tempfile.mkdtemp(prefix="md_full_cement_"))
    rows = []
    for omega in sorted(args.omega):
        t0 = time.perf_counter()
        ds = carry_down([STRESS_MPA], [CEMENT], intergranular_volume=[CEMENT],
                        schemes=("coating",), size=tuple(args.size), material=g, cement=c,
                        resolution=omega, workdir=work, anisotropy="ti")
        wall = time.perf_counter() - t0
        d = ds.isel(point=0, scheme=0)
        phi, phi_pack = float(d.porosity), float(d.porosity_pack)
        beta = (phi_pack - phi) / (1.0 - phi)
        fractions = [(1 - phi) * (1 - beta), (1 - phi) * beta, phi]
        hs = hashin_shtrikman([grain.K, cement.K, 0.0], [grain.G, cement.G, 0.0], fractions)
        vo = voigt([grain.K, cement.K, 0.0], [grain.G, cement.G, 0.0], fractions)
        M_up = float(hs.upper.K + 4.0 / 3.0 * hs.upper.G)
        row = {"omega": omega, "porosity": phi, "cement_per_solid": beta,
               "hs_upper_M": M_up, "hs_upper_G": float(hs.upper.G),
               "hs_lower_M": float(hs.lower.K + 4.0 / 3.0 * hs.lower.G),
               "hs_lower_G": float(hs.lower.G),
               "voigt_M": float(vo.K + 4.0 / 3.0 * vo.G), "voigt_G": float(vo.G),
               "member_wall_time_s": float(d.wall_time), "run_wall_time_s": wall}
        for name in CONSTANTS:
            row[LABELS[name]] = float(d[name]) / 1e9
        for name, bound in (("C33", M_up), ("C11", M_up), ("C44", float(hs.upper.G)),
                            ("C66", float(hs.upper.G))):
            row[f"{name}_over_hs_upper"] = row[name] / bound
        rows.append(row)
        print(f"Omega {omega:g}: " + ", ".join(f"{LABELS[n]} {row[LABELS[n]]:.2f}"
                                              for n in CONSTANTS)
              + f" GPa (HS upper M {M_up:.2f}, G {hs.upper.G:.2f}); {wall:.0f} s", flush=True)
    table = pd.DataFrame(rows)
    for name in ("C33", "C44", "C11", "C66"):
        table[f"{name}_step"] = table[name].pct_change()
    limits = {}
    if len(table) >= 2:                  # first-order Richardson limit of the two finest
        o1, o0 = table.omega.iloc[-2], table.omega.iloc[-1]
        for name in ("C33", "C44", "C11", "C66"):
            x1, x0 = table[name].iloc[-2], table[name].iloc[-1]
            limits[name] = x0 + (x0 - x1) / (o0 / o1 - 1.0)
    attrs = {**_common.environment_attrs(), **_common.md_source_attrs(),
             "md": f"one pack {args.size} diameters, seed 0, {STRESS_MPA} MPa, reconstructed "
                   f"to IGV {CEMENT}, coating cement {CEMENT} (pores full), rotations, static "
                   "TI constants",
             "materials": "quartz grains, quartz_cement (rockcem.materials)",
             "richardson_first_order_limit_GPa": "; ".join(f"{k} {v:.2f}"
                                                           for k, v in limits.items()),
             "units": "moduli GPa, times s"}
    out = args.output or _common.result_path(NAME, "csv")
    _common.write_csv(table.round(5), out, attrs)
    with pd.option_context("display.width", 200, "display.max_columns", 40):
        print(table.round(3).to_string(index=False))
    print("first-order limits:", attrs["richardson_first_order_limit_GPa"])


if __name__ == "__main__":
    main()
