"""What grain and cement rotations change in the linearised sample (issue 23, item 4).

On packs of ``--size`` largest diameters (default 4 x 4 x 12, radii 0.18-0.20 mm of García &
Medina) settled with ``--seeds`` and compacted to ``--stress`` MPa (default 30, the source's
compacted sample), this records:

* uncemented: static P (M, uniaxial strain) and S (G, simple shear) moduli and the dry Vp/Vs
  with translations only (the source's eqs. 4-6) and with rotations (the default), against
  ``md.bonded`` (6 degrees of freedom per grain, periodic strain; vanishing bonds beside the same
  Hertz-Mindlin contacts: its G_xz and its affine, unrelaxed shear modulus) and against
  Hertz-Mindlin at the pack's own porosity, coordination number and mean stress for slip
  factors f = 0, 0.5, 1;
* cemented: hard contact and coating cement at S_c 0.02-0.2, resolution ``--omega``, static
  Vp and Vs with and without rotations: how far the source's P results move and the cemented
  Vp/Vs.

Output: ``results/md_rotations[_<tag>].csv`` and ``.nc``, the table on stdout. Run:
``python benchmarks/md_rotations.py [--size 4 4 12 --seeds 0 1 --omega 4]`` (a few minutes);
``--film`` lays the coating as a film in partly filled cells (``md.growth.film_fill``).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

NAME = "md_rotations"


def _pack(size, seed, stress, work):
    import md

    path = work / f"pack_{'x'.join(f'{s:g}' for s in size)}_s{seed}_{stress:g}MPa.nc"
    if path.exists():
        return md.load_pack(path)
    pack = md.settle(size=tuple(size), fall_stiffness_factor=1e-3, seed=seed)
    pack = md.compact(pack, target_stress=stress * 1e6)
    md.save_pack(pack, path)
    return pack


def _moduli(system):
    import md

    p, s = md.static_modulus(system, "p"), md.static_modulus(system, "s")
    return p.modulus / 1e9, s.modulus / 1e9, p.density


def main(argv=None):
    import numpy as np
    import pandas as pd

    import md
    from md.observe import coordination_number, porosity
    from rockcem.granular import hertz_mindlin

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=float, nargs=3, default=[4.0, 4.0, 12.0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--stress", type=float, default=30.0, help="MPa")
    parser.add_argument("--omega", type=float, default=4.0)
    parser.add_argument("--saturations", type=float, nargs="+", default=[0.02, 0.05, 0.1, 0.2])
    parser.add_argument("--film", action="store_true",
                        help="coating as a film in partly filled cells (md.growth.film_fill, "
                             "the same volume as grow_cement's cells)")
    parser.add_argument("--tag", default="")
    args = parser.parse_args(argv)
    src = _common.announce_source()
    work = _common.RESULTS / f"{NAME}_work"
    work.mkdir(parents=True, exist_ok=True)
    q = md.QUARTZ
    K0 = 2 * q.shear_modulus * (1 + q.poisson_ratio) / (3 * (1 - 2 * q.poisson_ratio)) / 1e9
    rows = []
    for seed in args.seeds:
        pack = _pack(args.size, seed, args.stress, work)
        phi, cn = porosity(pack), coordination_number(pack)
        mean = pack.metadata["stress_mean"] / 1e6
        base = {"seed": seed, "n_grains": pack.n_grains, "porosity": phi,
                "coordination_number": cn, "stress_zz_MPa": pack.metadata["stress_zz"] / 1e6,
                "stress_mean_MPa": mean}
        for rot in (False, True):
            t0 = time.perf_counter()
            M, G, rho = _moduli(md.acoustic_system(pack, rotations=rot))
            rows.append({**base, "case": "uncemented", "rotations": rot, "scheme": "",
                         "saturation": 0.0, "M_GPa": M, "G_GPa": G, "vp_vs": np.sqrt(M / G),
                         "vp_km_s": np.sqrt(M / rho * 1e3), "vs_km_s": np.sqrt(G / rho * 1e3),
                         "seconds": time.perf_counter() - t0})
        bonded = md.bonded_static_moduli(md.bonded_system(pack, 1e-3, cement_bulk=1e6,
                                                          cement_shear=1e6))
        rows.append({**base, "case": "md.bonded", "rotations": True, "scheme": "",
                     "saturation": 0.0, "K_GPa": bonded.bulk / 1e9,
                     "G_GPa": bonded.shear_components[0] / 1e9,
                     "G_affine_GPa": bonded.shear_affine / 1e9,
                     "M_GPa": (bonded.bulk + 4 / 3 * bonded.shear) / 1e9,
                     "vp_vs": float(np.sqrt((bonded.bulk + 4 / 3 * bonded.shear)
                                            / bonded.shear))})
        for f in (0.0, 0.5, 1.0):
            hm = hertz_mindlin(K0, q.shear_modulus / 1e9, phi, cn, mean, f=f)
            M = float(hm.K + 4 / 3 * hm.G)
            rows.append({**base, "case": f"Hertz-Mindlin f={f:g}", "rotations": True,
                         "scheme": "", "saturation": 0.0, "K_GPa": float(hm.K),
                         "G_GPa": float(hm.G), "M_GPa": M, "vp_vs": float(np.sqrt(M / hm.G))})
        lat = md.cement_lattice(pack, args.omega)
        for scheme in ("contact", "coating"):
            for sat in args.saturations:
                if args.film and scheme == "coating":
                    from md.growth import film_fill

                    cells = film_fill(lat.distance, lat.cell_width, sat * lat.index.size)
                else:
                    cells = md.grow_cement(lat, sat, scheme)
                for rot in (False, True):
                    t0 = time.perf_counter()
                    M, G, rho = _moduli(md.acoustic_system(pack, lat, cells, md.HARD_CEMENT,
                                                           rotations=rot))
                    rows.append({**base, "case": "cemented", "rotations": rot,
                                 "scheme": scheme, "saturation": sat, "M_GPa": M, "G_GPa": G,
                                 "vp_vs": np.sqrt(M / G), "vp_km_s": np.sqrt(M / rho * 1e3),
                                 "vs_km_s": np.sqrt(G / rho * 1e3),
                                 "seconds": time.perf_counter() - t0})
                print(rows[-2]["scheme"], sat, "Vp trans/rot",
                      round(rows[-2]["vp_km_s"], 3), round(rows[-1]["vp_km_s"], 3), flush=True)
    frame = pd.DataFrame(rows)
    attrs = _common.environment_attrs(size=str(args.size), seeds=str(args.seeds),
                                      stress_MPa=args.stress, omega=args.omega,
                                      coating="film" if args.film else "cells",
                                      md_sources=src.get("md_source_sha256", ""))
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    ds = frame.to_xarray()
    ds.attrs.update({k: str(v) for k, v in attrs.items()})
    _common.write_netcdf(ds, _common.result_path(NAME, "nc", args.tag))
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        print(frame.drop(columns=["seconds"], errors="ignore").round(3).to_string(index=False))


if __name__ == "__main__":
    main()
