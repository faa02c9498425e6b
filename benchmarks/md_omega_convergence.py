"""Cemented MD moduli against the lattice resolution Omega, for the grain-cement interface rules.

A compacted quartz pack (default 4 x 4 x 12 largest diameters, the MD scene's sample: settled
with the accelerated deposition and compacted to 10 MPa, seed 3) is cemented to S_c = 0.1 with
hard cement by three schemes - ``pendular`` (rings around the contacts, a region fixed in
space), ``coating`` and the source's ``contact`` growth - at each Omega, linearised with each
rule of ``--interfaces`` (default ``facet``, the default of ``md.acoustic_system``, ``patch``
and the source's ``paper``), and solved for the static P modulus (CG on the free particles).
With ``--pulse`` the pulse test runs too (first rule). For each scheme and rule the limit is a
least-squares fit M(Omega) = M_inf + C / Omega over Omega >= ``--fit-from`` (first order, as
the single contact of ``md_single_contact.py`` converges; its rms residual is the lattice
noise), beside the three-point Richardson limit M_inf + C Omega^-p (none when the last changes
do not shrink with one sign); the default Omega is the smallest from which every modulus lies
within 1 % of the fitted limit.
Cement geometry beside it: mean distance of the cement cells to the grains over R and the
grain surface the cement touches.

The source's full sample (8 x 8 x 32) takes ~30 min to settle and compact on one core and its
Omega sweep ~Omega^4; ``--size 8 8 32`` runs it when there is time.

Output: ``results/md_omega_convergence[_<tag>].{csv,nc,png}``.
Run: ``python benchmarks/md_omega_convergence.py [--omega 4 6 8 10 12] [--pulse]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_omega_convergence"


def richardson(omega, value):
    """Limit and order ``p`` of M(Omega) = M_inf + C Omega^-p through the three finest points
    (:func:`md.convergence.richardson` with orders 0.05-12); NaN where the last two changes do
    not shrink with one sign (not in the asymptotic range)."""
    from md.convergence import richardson as three_point

    o, v = np.asarray(omega, float)[-3:], np.asarray(value, float)[-3:]
    if len(o) < 3 or not abs(v[2] - v[1]) < abs(v[1] - v[0]):
        return np.nan, np.nan
    return three_point(o, v, order_range=(0.05, 12.0))


def first_order_fit(omega, value, omega_min):
    """Least-squares M_inf + C / Omega over Omega >= omega_min: (M_inf, rms relative residual)."""
    o, v = np.asarray(omega, float), np.asarray(value, float)
    keep = o >= omega_min
    if keep.sum() < 3:
        return np.nan, np.nan
    A = np.stack([np.ones(keep.sum()), 1.0 / o[keep]], axis=1)
    coef, *_ = np.linalg.lstsq(A, v[keep], rcond=None)
    rms = float(np.sqrt(np.mean((A @ coef / v[keep] - 1) ** 2)))
    return float(coef[0]), rms


STYLES = {"facet": "s-", "patch": "o-", "paper": "x--"}


def plot(df, lim_df, schemes, saturation, tag):
    """Modulus against Omega per scheme and rule; the fitted limit of the first rule where the
    fit holds (rms under 1 %)."""
    _common.use_agg()
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(schemes), figsize=(4 * len(schemes), 3.6), sharey=True,
                             squeeze=False)
    for ax, scheme in zip(axes[0], schemes):
        rules = list(dict.fromkeys(df.interface))
        for interface in rules:
            g = df[(df.scheme == scheme) & (df.interface == interface)]
            ax.plot(g.omega, g.modulus_GPa, STYLES.get(interface, "+-"), label=interface)
            lim = lim_df[(lim_df.scheme == scheme) & (lim_df.interface == interface)]
            if (interface == rules[0] and len(lim) and lim.fit_rms.values[0] < 0.01
                    and lim.modulus_limit_GPa.values[0] > 0):
                ax.axhline(lim.modulus_limit_GPa.values[0], color="C0", lw=0.7, ls=":",
                           label=f"{interface}: first-order limit")
        ax.set(title=f"{scheme}, S_c {saturation:g}", xlabel="Omega = R/c_w")
    axes[0, 0].set_ylabel("static P modulus (GPa)")
    axes[0, 0].legend(fontsize=8)
    _common.save_figure(fig, _common.result_path(NAME, "png", tag))


def replot(tag):
    """Redraw the figure from the CSV files of an earlier run."""
    import pandas as pd

    path = _common.result_path(NAME, "csv", tag)
    df = pd.read_csv(path, comment="#")
    lim_df = pd.read_csv(_common.result_path(NAME + "_limits", "csv", tag), comment="#")
    with open(path) as fh:
        sat = float(next(line for line in fh if line.startswith("# saturation:")).split(":")[1])
    plot(df, lim_df, list(dict.fromkeys(df.scheme)), sat, tag)


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md
    from md.interface import interface_area

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[4, 6, 8, 10, 12])
    ap.add_argument("--size", type=float, nargs=3, default=[4, 4, 12])
    ap.add_argument("--saturation", type=float, default=0.1)
    ap.add_argument("--schemes", nargs="+", default=["pendular", "coating", "contact"])
    ap.add_argument("--interfaces", nargs="+", default=["facet", "patch", "paper"],
                    choices=["facet", "patch", "paper"])
    ap.add_argument("--pulse", action="store_true")
    ap.add_argument("--fit-from", type=float, default=10.0,
                    help="smallest Omega of the first-order least-squares limit")
    ap.add_argument("--tag", default="")
    ap.add_argument("--replot", action="store_true", help="only redraw from the CSV files")
    args = ap.parse_args(argv)
    if args.replot:
        return replot(args.tag)
    _common.announce_source()
    size = tuple(args.size)
    work = _common.RESULTS / f"{NAME}_work" / ("pack_" + "x".join(f"{s:g}" for s in size))
    t0 = time.perf_counter()
    pack = md.prepare_pack(work, settle_options=dict(size=size, fall_stiffness_factor=1e-3,
                                                     seed=3),
                           compact_options=dict(target_stress=10e6), progress=True)
    t_pack = time.perf_counter() - t0
    R = float(pack.radii.mean())
    rows = []
    for omega in sorted(args.omega):
        t1 = time.perf_counter()
        lat = md.cement_lattice(pack, omega)
        t_lat = time.perf_counter() - t1
        for scheme in args.schemes:
            t1 = time.perf_counter()
            cem = md.grow_cement(lat, args.saturation, scheme)
            t_grow = time.perf_counter() - t1
            for interface in args.interfaces:
                t1 = time.perf_counter()
                system = md.acoustic_system(pack, lat, cem, md.HARD_CEMENT, interface=interface,
                                            rotations=False)
                t_sys = time.perf_counter() - t1
                t1 = time.perf_counter()
                st = md.static_modulus(system, "p")
                t_static = time.perf_counter() - t1
                ng = pack.n_grains
                gc = system.bond_j >= ng
                covered = interface_area(system.bond_normal[gc], lat.cell_width).sum() / (
                    4 * np.pi * np.sum(pack.radii**2))
                row = dict(omega=omega, scheme=scheme, interface=interface,
                           modulus_GPa=st.modulus / 1e9, vp_static=st.velocity,
                           n_cement=int(cem.sum()), cement_distance_over_R=float(
                               lat.distance[cem].mean()) / R,
                           surface_covered=float(covered) if interface != "paper" else np.nan,
                           seconds_lattice=t_lat, seconds_growth=t_grow,
                           seconds_system=t_sys, seconds_static=t_static,
                           vp_pulse=np.nan, vp_pulse_error=np.nan, seconds_pulse=np.nan)
                if args.pulse and interface == args.interfaces[0]:
                    t1 = time.perf_counter()
                    ds = md.pulse_test(system)
                    row.update(vp_pulse=float(ds.velocity), vp_pulse_error=float(
                        ds.velocity_error), seconds_pulse=time.perf_counter() - t1)
                rows.append(row)
                print(f"Omega {omega:4g} {scheme:8s} {interface:5s}: M {row['modulus_GPa']:8.3f}"
                      f" GPa, Vp static {st.velocity:7.1f} m/s, pulse {row['vp_pulse']:7.1f}"
                      f" ({t_sys + t_static:.1f} s)", flush=True)
    df = pd.DataFrame(rows)
    limits = []
    for (scheme, interface), g in df.groupby(["scheme", "interface"], sort=False):
        g = g.sort_values("omega")
        lim, p = richardson(g.omega, g.modulus_GPa)
        fit, rms = first_order_fit(g.omega, g.modulus_GPa, args.fit_from)
        err = g.modulus_GPa.values / fit - 1
        # default: the smallest Omega from which every modulus lies within 1 % of the limit
        ok = np.abs(err) <= 0.01
        tail = np.flatnonzero(~ok)
        first = 0 if tail.size == 0 else tail[-1] + 1
        change = np.diff(g.modulus_GPa.values) / g.modulus_GPa.values[:-1]
        df.loc[g.index, "modulus_vs_limit"] = err
        df.loc[g.index[1:], "change_from_previous"] = change
        limits.append(dict(scheme=scheme, interface=interface, modulus_limit_GPa=fit,
                           fit_rms=rms, richardson_limit_GPa=lim, richardson_order=p,
                           last_change=change[-1] if change.size else np.nan,
                           changes_shrink=bool(change.size >= 3 and np.all(
                               np.abs(change[-2:]) < np.abs(change[-3:-1]))),
                           default_omega=(float(g.omega.values[first])
                                          if first < len(g) and np.isfinite(fit) else np.nan)))
        print(f"{scheme:8s} {interface:5s}: limit {fit:.3f} GPa (fit rms {rms:.2%}; Richardson "
              f"{lim:.3f}, order {p:.2f}), last change "
              f"{limits[-1]['last_change']:+.2%}, within 1 % from Omega "
              f"{limits[-1]['default_omega']}")
    lim_df = pd.DataFrame(limits)
    attrs = _common.environment_attrs(
        benchmark=NAME, size=" ".join(f"{s:g}" for s in size), n_grains=pack.n_grains,
        saturation=args.saturation, cement="hard (Table II)", pack_seconds=t_pack,
        compaction="10 MPa", **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv", args.tag), attrs)
    _common.write_csv(lim_df, _common.result_path(NAME + "_limits", "csv", args.tag), attrs)
    ds = xr.Dataset.from_dataframe(df).assign_attrs(attrs)
    _common.write_netcdf(ds, _common.result_path(NAME, "nc", args.tag))
    plot(df, lim_df, args.schemes, args.saturation, args.tag)
    print(_common.markdown(df, {"omega": ("Omega", "g"), "scheme": ("scheme", "s"),
                                "interface": ("rule", "s"), "modulus_GPa": ("M (GPa)", ".3f"),
                                "change_from_previous": ("change", "+.2%"),
                                "modulus_vs_limit": ("vs limit", "+.2%"),
                                "vp_pulse": ("Vp pulse", ".0f"),
                                "seconds_static": ("static s", ".1f")}))


if __name__ == "__main__":
    main()
