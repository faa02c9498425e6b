"""One cemented contact on the cement lattice against the cemented-contact integral equation.

Two touching quartz grains joined by hard or soft contact cement (Table II) of radius a
(a/R 0.2-0.5; 0.1 needs Omega of several hundred before the gap R alpha^2 holds a cell
centre), built at increasing resolution Omega with both grain-cement interface rules of
``md.interface`` (``patch``, the default, and the source's per-cell ``paper`` rule). The
static normal and tangential stiffness of the bond
(``md.cemented_contact.lattice_contact_stiffness``, a sparse direct solve; the patch rule with
the cement particles translating only and with them rotating too, ``rotations`` of
``md.acoustic_system``, the default of the MD engine) are compared with
the integral equation of Dvorkin et al. (1994) that
``rockcem.contact_integral.cemented_contact_stiffness`` solves (k = pi M_c R S_n, pi G_c R S_t)
and with its rigid-cement limit (the welded contact). For the patch rule the last two
resolutions give a first-order Richardson estimate of the lattice's own limit.

Output: ``results/md_single_contact.{csv,nc,png}``.
Run: ``python benchmarks/md_single_contact.py [--omega 8 16 32 48] [--alpha 0.2 0.3 0.5]``.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_single_contact"


def contact_rows(alpha, cement, name, omegas):
    """Lattice against theory for one cement radius and cement, both rules, every Omega."""
    from md.cemented_contact import lattice_contact_stiffness, theory_contact_stiffness

    th = theory_contact_stiffness(alpha, cement=cement)
    welded = theory_contact_stiffness(alpha, limit="rigid_cement")
    rows = []
    for interface, rotations in (("patch", False), ("patch", True), ("paper", False)):
        for omega in sorted(omegas):
            t0 = time.perf_counter()
            try:
                k = lattice_contact_stiffness(alpha, omega, cement=cement, interface=interface,
                                              rotations=rotations)
            except ValueError as err:
                print(f"a/R {alpha} Omega {omega:g}: {err}")
                continue
            rows.append(dict(cement=name, alpha=alpha, interface=interface,
                             rotations="yes" if rotations else "no", omega=omega,
                             kn=k.normal, kt=k.tangential, kn_theory=th.normal,
                             kt_theory=th.tangential, kn_welded=welded.normal,
                             kt_welded=welded.tangential, kn_ratio=k.normal / th.normal,
                             kt_ratio=k.tangential / th.tangential,
                             seconds=time.perf_counter() - t0))
            r = rows[-1]
            print(f"{name} a/R {alpha} {interface:5s} rot {rotations:d} Omega {omega:3g}: "
                  f"kn/theory "
                  f"{r['kn_ratio']:.3f} kt/theory {r['kt_ratio']:.3f} ({r['seconds']:.1f} s)",
                  flush=True)
    return rows


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--omega", type=float, nargs="+", default=[8, 16, 24, 32, 48])
    ap.add_argument("--alpha", type=float, nargs="+", default=[0.2, 0.3, 0.4, 0.5])
    ap.add_argument("--cement", nargs="+", default=["hard", "soft"], choices=["hard", "soft"])
    args = ap.parse_args(argv)
    _common.announce_source()
    rows = []
    for name in args.cement:
        cement = md.HARD_CEMENT if name == "hard" else md.SOFT_CEMENT
        for alpha in args.alpha:
            rows += contact_rows(alpha, cement, name, args.omega)
    df = pd.DataFrame(rows)
    # First-order Richardson limit of the patch rule from its two finest resolutions.
    extra = []
    for (name, alpha, interface, rotations), g in df.groupby(["cement", "alpha", "interface",
                                                               "rotations"]):
        g = g.sort_values("omega")
        if interface != "patch" or len(g) < 2:
            continue
        o1, o2 = g.omega.values[-2:]
        rich = {}
        for key in ("kn_ratio", "kt_ratio"):
            f1, f2 = g[key].values[-2:]
            rich[key] = f2 + (f2 - f1) * o1 / (o2 - o1)       # error ~ 1/Omega
        extra.append(dict(cement=name, alpha=alpha, interface="patch_richardson",
                          rotations=rotations, omega=np.inf,
                          kn_ratio=rich["kn_ratio"], kt_ratio=rich["kt_ratio"]))
    df = pd.concat([df, pd.DataFrame(extra)], ignore_index=True)
    attrs = _common.environment_attrs(
        benchmark=NAME, grain="quartz (Table I)", cements="hard and soft (Table II)",
        theory="rockcem.contact_integral.cemented_contact_stiffness, panels 64",
        normalisation="k_n = pi M_c R S_n, k_t = pi G_c R S_t", **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv"), attrs)
    _common.write_netcdf(xr.Dataset.from_dataframe(df).assign_attrs(attrs),
                         _common.result_path(NAME, "nc"))
    _common.use_agg()
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, key, title in zip(axes, ("kn_ratio", "kt_ratio"), ("normal", "tangential")):
        for (name, alpha, interface, rotations), g in df[np.isfinite(df.omega)].groupby(
                ["cement", "alpha", "interface", "rotations"]):
            if alpha != 0.5 and interface != "patch":
                continue
            style = ("x--" if interface == "paper" else ("o-" if rotations == "yes" else "s:"))
            ax.plot(g.omega, g[key], style, color="C0" if name == "hard" else "C1",
                    alpha=1.0 if alpha == 0.5 else 0.45,
                    label=f"{name}, a/R {alpha:g}, {interface}"
                          f"{', rot.' if rotations == 'yes' else ''}")
        ax.axhline(1.0, color="k", lw=0.8)
        ax.set(xlabel="resolution Omega = R/c_w", title=f"{title} stiffness / integral equation",
               xscale="log")
    axes[0].set_ylabel("lattice / Dvorkin et al. (1994)")
    axes[1].legend(fontsize=7, ncol=2)
    _common.save_figure(fig, _common.result_path(NAME, "png"))
    print(_common.markdown(df, {"cement": ("cement", "s"), "alpha": ("a/R", "g"),
                                "interface": ("rule", "s"), "rotations": ("rot.", "s"),
                                "omega": ("Omega", "g"),
                                "kn_ratio": ("k_n / theory", ".3f"),
                                "kt_ratio": ("k_t / theory", ".3f"), "seconds": ("s", ".1f")}))


if __name__ == "__main__":
    main()
