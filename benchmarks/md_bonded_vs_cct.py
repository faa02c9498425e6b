"""Bonded-contact MD samples against the contact cement theories (Xu 2023, Sect. 2.3, Figs. 4-6).

An isotropically confined quartz pack (``--size`` largest diameters, confined to ``--stress``
MPa mean stress with :func:`md.compact` ``isotropic=True``; stages cached and resumed in
``results/md_bonded_pack/``) is bonded at every contact with :mod:`md.bonded` and its static bulk
and shear moduli are computed by sparse solves:

* contact bonding (h = 0), a/R from 0.30 to 0.55, cement (K, G) = (15, 8) GPa (Xu's Fig. 4),
  against CCT (``rockcem.granular.contact_cement``, scheme 1, ``stiffness="fit"``, the handbook
  polynomials, and ``"integral"``, the solved contact problem);
* distant bonding, a/R from 0.30 to 0.55 and contact thickness 0.01 to 0.05, cement (6.8, 2.0)
  GPa (Figs. 5-6), against MCCT (the same function with ``thickness`` = that value). Xu's axis
  "h/R" is read as MCCT's :math:`\varepsilon`, which in eqs. 1 and 6 of Han & Guo (and in
  :func:`rockcem.granular.contact_cement`) is half the axial gap over R; the bonds of
  :mod:`md.bonded` take the same :math:`\varepsilon` (axial gap :math:`2\varepsilon R`).

The theories are evaluated for the sample's own coordination number and uncemented porosity
(:math:`\\phi_c`), with the cement porosity from the bond radius by inverting eq. A-9
(:func:`rockcem.granular.cement_porosity`), so that :func:`rockcem.granular.cement_radius`
returns the bond's a/R. Besides them: the sample's affine
(unrelaxed) moduli, and the CCT averaging (eq. A-3) applied to the bond stiffness of the MD
sample, :math:`K = n(1-\\phi_c)S_n/(12\\pi\\bar R)`,
:math:`G = n(1-\\phi_c)(S_n + \\tfrac32 S_s)/(20\\pi \\bar R)` -- which separates the contact law
(bond stiffness vs CCT's contact stiffness) from the averaging (affine vs relaxed). Velocities:
the static Vp, Vs from the relaxed moduli and the dry density (cement of the grain density), and
the P-wave pulse test (:func:`md.pulse_test`) of the same bonds in the translational acoustic
operator (:func:`md.bonded.bonded_acoustic_system`, grain rotations locked) with its own static
cross-check. In eq. A-3
the contact stiffness :math:`S` relates the force to the approach of one grain to the contact
plane, half the centre-to-centre approach, so :math:`S = 2k` for the bond stiffness :math:`k` of
:mod:`md.bonded` (with :math:`S = 2k` eq. A-3 is the exact affine bulk modulus of equal spheres).

Grains: md's quartz (G = 44 GPa, nu = 0.08, K = 37.7 GPa; Xu: 38, 44 GPa).

Usage: ``python benchmarks/md_bonded_vs_cct.py [--size 5 5 10] [--stress 1] [--quick]``.
Writes ``results/md_bonded_vs_cct.{csv,nc,png}`` and markdown tables on stdout.
"""

from __future__ import annotations

import _common  # noqa: F401  (first: threads, sys.path)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from _common import (RESULTS, environment_attrs, markdown, md_source_attrs,  # noqa: E402
                     result_path, save_figure, write_csv, write_netcdf)

NAME = "md_bonded_vs_cct"
CONTACT_CEMENT = (15e9, 8e9)          # Xu 2023, Sect. 2.3 (contact bonding)
DISTANT_CEMENT = (6.8e9, 2.0e9)       # Xu 2023, Sect. 2.3 (distant bonding)
RADIUS_RATIOS = (0.30, 0.35, 0.40, 0.45, 0.50, 0.55)
THICKNESS_RATIOS = (0.01, 0.02, 0.03, 0.04, 0.05)


def theory(K0, G0, Kc, Gc, phic, n, alpha, eps, stiffness):
    """CCT (eps = 0) or MCCT moduli (GPa) at bond radius ``alpha`` and thickness ``eps``."""
    from rockcem.granular import cement_porosity, contact_cement

    phi = cement_porosity(alpha, phic, n, 1, eps)
    m = contact_cement(K0, G0, Kc, Gc, phi, phic, n, scheme=1, thickness=eps,
                       stiffness=stiffness)
    return np.asarray(m.K, dtype=float), np.asarray(m.G, dtype=float)


def bond_averaging(system):
    """Eq. A-3 applied to the sample's bond stiffnesses (mean over bonds; S = 2k), GPa."""
    meta = system.metadata
    n, phic = meta["coordination_number"], meta["porosity_uncemented"]
    ri, rj = system.radii[system.pair_i], system.radii[system.pair_j]
    R = float(np.mean(2 * ri * rj / (ri + rj)))
    kn, ks = 2.0 * float(system.kn.mean()), 2.0 * float(system.ks.mean())
    K = n * (1 - phic) * kn / (12 * np.pi * R)
    G = n * (1 - phic) * (kn + 1.5 * ks) / (20 * np.pi * R)
    return K / 1e9, G / 1e9


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md
    from md.bonded import bonded_acoustic_system, bonded_system, static_moduli

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, nargs=3, default=(5, 5, 10),
                    help="pack size in largest diameters (default 5 5 10)")
    ap.add_argument("--stress", type=float, default=1.0,
                    help="isotropic confining (mean) stress, MPa (default 1)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--quick", action="store_true",
                    help="3 x 3 x 6 pack, three radii, two thicknesses (a smoke run)")
    ap.add_argument("--no-plot", action="store_true")
    args = ap.parse_args(argv)
    size = (3, 3, 6) if args.quick else tuple(args.size)
    radii = RADIUS_RATIOS[::2] if args.quick else RADIUS_RATIOS
    thick = THICKNESS_RATIOS[::4] if args.quick else THICKNESS_RATIOS
    t_start = time.perf_counter()
    workdir = RESULTS / ("md_bonded_pack_quick" if args.quick else "md_bonded_pack")
    settle_options = dict(size=size, fall_stiffness_factor=1e-2, seed=args.seed,
                          kinetic_tolerance=1e-5)
    compact_options = dict(target_stress=args.stress * 1e6, strain_step=5e-4, isotropic=True)
    pack = md.prepare_pack(workdir, settle_options=settle_options,
                           compact_options=compact_options, progress=True)
    rec = pack.metadata["record"]
    print(f"pack: {pack.n_grains} grains, mean stress {rec['stress_mean'][-1] / 1e6:.2f} MPa, "
          f"sigma_zz {rec['stress_zz'][-1] / 1e6:.2f} MPa, porosity {rec['porosity'][-1]:.4f}",
          flush=True)
    G0 = md.QUARTZ.shear_modulus / 1e9
    K0 = md.QUARTZ.bulk_modulus / 1e9
    rows = []
    cases = [("contact", a, 0.0, CONTACT_CEMENT) for a in radii]
    cases += [("distant", a, h, DISTANT_CEMENT) for h in thick for a in radii]
    for mode, a, h, (Kc, Gc) in cases:
        t0 = time.perf_counter()
        system = bonded_system(pack, a, h, cement_bulk=Kc, cement_shear=Gc)
        m = static_moduli(system)
        seconds = time.perf_counter() - t0
        meta = system.metadata
        n, phic = meta["coordination_number"], meta["porosity_uncemented"]
        row = dict(mode=mode, radius_ratio=a, thickness_ratio=h, cement_K=Kc / 1e9,
                   cement_G=Gc / 1e9, K_md=m.bulk / 1e9, G_md=m.shear / 1e9,
                   K_md_affine=m.bulk_affine / 1e9, G_md_affine=m.shear_affine / 1e9,
                   G_xz=m.shear_components[0] / 1e9, G_yz=m.shear_components[1] / 1e9,
                   G_xy=m.shear_components[2] / 1e9, coordination_number=n,
                   porosity_uncemented=phic, porosity=meta["porosity"],
                   n_bonds=meta["n_bonds"], solve_seconds=seconds)
        row["K_bond_avg"], row["G_bond_avg"] = bond_averaging(system)
        # Velocities: static (6 dof, grains rotate) and the pulse test of the same bonds in the
        # translational acoustic operator (cement of the grain density).
        rho = (meta["grain_volume_fraction"] + meta["cement_fraction"]) * meta["grain_density"]
        row["density"] = rho / 1e3
        row["vp_static"] = float(np.sqrt((m.bulk + 4 * m.shear / 3) / rho)) / 1e3
        row["vs_static"] = float(np.sqrt(m.shear / rho)) / 1e3
        t1 = time.perf_counter()
        pulse = md.pulse_test(bonded_acoustic_system(system), "p")
        row["vp_pulse"] = float(pulse.velocity) / 1e3
        row["vp_pulse_error"] = float(pulse.velocity_error) / 1e3
        row["vp_pulse_fit"] = float(pulse.velocity_fit) / 1e3
        row["vp_static_no_rotation"] = float(pulse.velocity_static) / 1e3
        row["pulse_seconds"] = time.perf_counter() - t1
        for stiff in ("fit", "integral"):
            K, G = theory(K0, G0, Kc / 1e9, Gc / 1e9, phic, n, a, h, stiff)
            row[f"K_cct_{stiff}"], row[f"G_cct_{stiff}"] = float(K), float(G)
        for s in ("fit", "integral"):
            row[f"K_ratio_{s}"] = row["K_md"] / row[f"K_cct_{s}"]
            row[f"G_ratio_{s}"] = row["G_md"] / row[f"G_cct_{s}"]
        rows.append(row)
        print(f"{mode:8s} a/R {a:.2f} h/R {h:.2f}: K {row['K_md']:.3f} G {row['G_md']:.3f} GPa"
              f" (affine {row['K_md_affine']:.3f}, {row['G_md_affine']:.3f}); theory fit "
              f"{row['K_cct_fit']:.3f}, {row['G_cct_fit']:.3f}; integral "
              f"{row['K_cct_integral']:.3f}, {row['G_cct_integral']:.3f}  [{seconds:.2f} s]",
              flush=True)
    frame = pd.DataFrame(rows)
    total = time.perf_counter() - t_start
    attrs = environment_attrs(
        title="bonded-contact MD samples vs CCT / MCCT (Xu 2023 Figs. 4-6)", benchmark=NAME,
        pack_size_diameters=" x ".join(f"{s:g}" for s in size), pack_grains=pack.n_grains,
        confining_mean_stress_MPa=rec["stress_mean"][-1] / 1e6,
        confining_stress_zz_MPa=rec["stress_zz"][-1] / 1e6,
        grain_K_GPa=K0, grain_G_GPa=G0,
        theory="rockcem.granular.contact_cement scheme 1 at the sample's n and phi_c, cement "
               "porosity from a/R by inverting eq. A-9",
        total_run_s=total, **md_source_attrs())
    write_csv(frame, result_path(NAME, "csv"), attrs)
    ds = xr.Dataset.from_dataframe(frame)
    ds.attrs.update(attrs)
    write_netcdf(ds, result_path(NAME, "nc"))
    cols = {"radius_ratio": ("a/R", ".2f"), "thickness_ratio": ("eps", ".2f"),
            "K_md": ("K MD", ".3f"), "K_cct_fit": ("K CCT fit", ".3f"),
            "K_cct_integral": ("K CCT integral", ".3f"), "K_ratio_integral": ("MD/int", ".2f"),
            "G_md": ("G MD", ".3f"), "G_cct_fit": ("G CCT fit", ".3f"),
            "G_cct_integral": ("G CCT integral", ".3f"), "G_ratio_integral": ("MD/int", ".2f"),
            "K_md_affine": ("K affine", ".3f"), "G_md_affine": ("G affine", ".3f"),
            "K_bond_avg": ("K eq. A-3, bonds", ".3f"), "G_bond_avg": ("G eq. A-3, bonds", ".3f")}
    vcols = {"radius_ratio": ("a/R", ".2f"), "thickness_ratio": ("eps", ".2f"),
             "density": ("rho g/cm3", ".3f"), "vp_static": ("Vp static (km/s)", ".3f"),
             "vs_static": ("Vs static", ".3f"),
             "vp_static_no_rotation": ("Vp static, no rotation", ".3f"),
             "vp_pulse": ("Vp pulse", ".3f"), "vp_pulse_error": ("+- eq. 11", ".3f")}
    print("\nContact bonding vs CCT (GPa)\n")
    print(markdown(frame[frame["mode"] == "contact"], cols))
    print("\nDistant bonding vs MCCT (GPa)\n")
    print(markdown(frame[frame["mode"] == "distant"], cols))
    print("\nVelocities (dry; pulse test in the translational operator, rotations locked)\n")
    print(markdown(frame[frame["thickness_ratio"].isin([0.0, max(thick)])], vcols))
    print(f"\ntotal {total:.1f} s")
    if args.no_plot:
        return
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    c = frame[frame["mode"] == "contact"]
    ax = axes[0]
    for q, col in (("K", "C0"), ("G", "C1")):
        ax.plot(c.radius_ratio, c[f"{q}_md"], "o-", color=col, label=f"{q} MD (relaxed)")
        ax.plot(c.radius_ratio, c[f"{q}_md_affine"], "o:", color=col, alpha=0.6,
                label=f"{q} MD (affine)")
        ax.plot(c.radius_ratio, c[f"{q}_cct_fit"], "--", color=col, label=f"{q} CCT (fit)")
        ax.plot(c.radius_ratio, c[f"{q}_cct_integral"], "-.", color=col,
                label=f"{q} CCT (integral)")
    ax.set(xlabel="a/R", ylabel="modulus (GPa)", title="contact bonding (Fig. 4)")
    ax.legend(fontsize=7)
    d = frame[frame["mode"] == "distant"]
    ax = axes[1]
    for k, h in enumerate(sorted(d.thickness_ratio.unique())):
        s = d[d.thickness_ratio == h]
        ax.plot(s.radius_ratio, s.K_md, "o-", color=f"C{k}", label=f"K MD, eps {h:.2f}")
        ax.plot(s.radius_ratio, s.K_cct_integral, "--", color=f"C{k}")
    ax.set(xlabel="a/R", ylabel="K (GPa)", title="distant bonding (Fig. 5): MD o-, MCCT --")
    ax.legend(fontsize=7)
    ax = axes[2]
    a_fix = 0.5 if 0.5 in set(d.radius_ratio) else float(d.radius_ratio.max())
    s = d[np.isclose(d.radius_ratio, a_fix)]
    for q, col in (("K", "C0"), ("G", "C1")):
        ax.plot(s.thickness_ratio, s[f"{q}_md"], "o-", color=col, label=f"{q} MD")
        ax.plot(s.thickness_ratio, s[f"{q}_cct_fit"], "--", color=col, label=f"{q} MCCT (fit)")
        ax.plot(s.thickness_ratio, s[f"{q}_cct_integral"], "-.", color=col,
                label=f"{q} MCCT (integral)")
    ax.set(xlabel="epsilon = h/(2R)", ylabel="modulus (GPa)",
           title=f"distant bonding, a/R = {a_fix:g} (Fig. 6)")
    ax.legend(fontsize=7)
    fig.suptitle(f"md.bonded, {pack.n_grains} grains, n = {frame.coordination_number.iloc[0]:.2f}"
                 f", phi_c = {frame.porosity_uncemented.iloc[0]:.3f}")
    fig.tight_layout()
    save_figure(fig, result_path(NAME, "png"))
    plt.close(fig)


if __name__ == "__main__":
    main()
