"""Cement films thinner than a cell: error against run time in the resolution Omega (issue 29,
item 3).

A compacted pack (``--size`` largest diameters, default 4 x 4 x 8, seed 3, 10 MPa: the pack
of ``md_omega_convergence.py`` shortened) is cemented in its core window to the cement
fractions ``S_c * porosity`` of ``--saturations`` (default 0.03, 0.05, 0.1, 0.2: the onset of
quartz cement) at each ``--omega``, with rotations (the default of ``md.acoustic_system``;
``--translations``: without),
and its static P and S moduli solved (``md.static_moduli``). Two representations:

* ``cells`` (before): the coating as whole cells, the volume rule of
  ``md.along_depth.cement_cells`` (the growth order cut at the window's cell count);
* ``film`` (after): ``md.growth.cement_fill`` — the same volume to a fraction of a cell, the
  coating a film of uniform thickness in partly filled cells, whose grains are joined by the
  bridges the films make (``md.interface.film_bridges``).

The pendular scheme (``--pendular``, S_c 0.1) is run both ways too: it is made of whole
cells but for the last level, so its convergence must not change. Per row: M and G (GPa),
the change from the previous Omega, the difference to the finest Omega of the same
representation, and the wall times of the lattice, the fill, the system and the solve.

Output: ``results/md_film_convergence[_<tag>].csv`` and ``.png``.
Run: ``python benchmarks/md_film_convergence.py [--omega 4 5 6 8 10 12 14] [--size 4 4 8]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_film_convergence"


def member(pack, lat, fraction, scheme, method, slab, rotations=True):
    """One cemented member: moduli and wall times."""
    import md
    from md.along_depth import cement_cells
    from md.growth import cement_fill
    from md.static import static_moduli

    t0 = time.perf_counter()
    if method == "cells":
        fill, _ = cement_cells(pack, lat, fraction, scheme)
    else:
        fill, _ = cement_fill(pack, lat, fraction, scheme)
    t1 = time.perf_counter()
    system = md.acoustic_system(pack, lat, fill, md.HARD_CEMENT, interface="facet",
                                slab_thickness=slab, rotations=rotations)
    t2 = time.perf_counter()
    res = static_moduli(system, ("p", "s"))
    t3 = time.perf_counter()
    meta = system.metadata
    return dict(M_GPa=res["p"].modulus / 1e9, G_GPa=res["s"].modulus / 1e9,
                cement_cells=float(np.sum(fill)), full_cells=int(np.sum(fill == 1)),
                film_cells=int(meta.get("n_film_cells", 0)),
                bridges=int(meta.get("n_film_bridges", 0)),
                particles=int(system.n_particles),
                seconds_fill=t1 - t0, seconds_system=t2 - t1, seconds_solve=t3 - t2)


def plot(df, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, ((scheme, sat), g) in enumerate(df.groupby(["scheme", "saturation"], sort=False)):
        c = colors[k % len(colors)]
        for method, style in (("cells", "--"), ("film", "-")):
            h = g[g.method == method].sort_values("omega")
            label = f"{scheme} S_c {sat:g} ({method})"
            axes[0].plot(h.omega, h.M_GPa, style, marker="o", color=c, label=label)
            axes[1].plot(h.omega, h.G_GPa, style, marker="o", color=c)
            err = np.abs(h.M_error_vs_finest.values[:-1])
            axes[2].loglog(h.seconds_total.values[:-1], np.maximum(err, 1e-4), style,
                           marker="o", color=c)
    axes[0].set(xlabel="Ω (cells per grain radius)", ylabel="static M (GPa)")
    axes[1].set(xlabel="Ω", ylabel="static G (GPa)")
    axes[2].set(xlabel="wall time per member (s)", ylabel="|M / M(finest Ω) − 1|")
    axes[2].axhline(0.02, color="0.6", lw=0.8)
    axes[0].legend(fontsize=6, ncol=2)
    fig.suptitle("Cement films thinner than a cell: whole cells (dashed) and film (solid)")
    fig.tight_layout()
    _common.save_figure(fig, path)


def main(argv=None):
    import pandas as pd

    import md
    from md.observe import porosity

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[4, 5, 6, 8, 10, 12, 14])
    ap.add_argument("--size", type=float, nargs=3, default=[4, 4, 8])
    ap.add_argument("--saturations", type=float, nargs="*", default=[0.03, 0.05, 0.1, 0.2])
    ap.add_argument("--pendular", type=float, nargs="*", default=[0.1],
                    help="saturations of the pendular scheme (none: skip)")
    ap.add_argument("--cells-max-omega", type=float, default=12.0,
                    help="largest Omega of the whole-cell (before) runs")
    ap.add_argument("--tag", default="")
    ap.add_argument("--translations", action="store_true",
                    help="particles translate only (rotations=False of md.acoustic_system)")
    args = ap.parse_args(argv)
    _common.announce_source()
    size = tuple(args.size)
    work = _common.RESULTS / f"{NAME}_work" / ("pack_" + "x".join(f"{s:g}" for s in size))
    t0 = time.perf_counter()
    pack = md.prepare_pack(work, settle_options=dict(size=size, fall_stiffness_factor=1e-3,
                                                     seed=3),
                           compact_options=dict(target_stress=10e6), progress=False)
    t_pack = time.perf_counter() - t0
    phi = porosity(pack)
    slab = 2.0 * float(pack.radii.max())
    cases = [("coating", s) for s in args.saturations] + [("pendular", s)
                                                           for s in args.pendular]
    rows = []
    for omega in sorted(args.omega):
        t1 = time.perf_counter()
        lat = md.cement_lattice(pack, omega)
        t_lat = time.perf_counter() - t1
        for scheme, sat in cases:
            for method in ("cells", "film"):
                if method == "cells" and omega > args.cells_max_omega:
                    continue
                row = dict(scheme=scheme, saturation=sat, method=method, omega=omega,
                           seconds_lattice=t_lat,
                           **member(pack, lat, sat * phi, scheme, method, slab,
                                    not args.translations))
                row["seconds_total"] = (t_lat + row["seconds_fill"] + row["seconds_system"]
                                        + row["seconds_solve"])
                rows.append(row)
                print(f"Omega {omega:4g} {scheme:8s} S_c {sat:4g} {method:5s}: M "
                      f"{row['M_GPa']:7.3f} G {row['G_GPa']:7.3f} GPa  cells "
                      f"{row['cement_cells']:9.1f} (full {row['full_cells']}, film "
                      f"{row['film_cells']}, bridges {row['bridges']})  "
                      f"{row['seconds_total']:.1f} s", flush=True)
    df = pd.DataFrame(rows)
    for _, g in df.groupby(["scheme", "saturation", "method"], sort=False):
        g = g.sort_values("omega")
        for var in ("M", "G"):
            v = g[f"{var}_GPa"].values
            df.loc[g.index[1:], f"{var}_change"] = v[1:] / v[:-1] - 1
            df.loc[g.index, f"{var}_error_vs_finest"] = v / v[-1] - 1
    attrs = _common.environment_attrs(
        benchmark=NAME, size=" ".join(f"{s:g}" for s in size), n_grains=pack.n_grains,
        porosity=phi, cement="hard (Table II)", compaction="10 MPa",
        rotations="no" if args.translations else "yes",
        interface="facet", pack_seconds=t_pack, **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv", args.tag), attrs)
    plot(df, _common.result_path(NAME, "png", args.tag))
    show = df[["scheme", "saturation", "method", "omega", "M_GPa", "M_change", "G_GPa",
               "G_change", "seconds_total"]]
    print(show.to_string(index=False, float_format=lambda x: f"{x:.4g}"))


if __name__ == "__main__":
    main()
