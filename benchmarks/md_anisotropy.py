"""Anisotropy of the compacted MD pack: the five TI constants, the bulk modulus, Thomsen's
parameters and anisotropic against isotropic Gassmann (issue 29, item 5).

A 4 x 4 x 12 quartz pack (``md.settle``, radii 0.135-0.150 mm, as ``md.along_depth``) is
compacted to each vertical stress in turn (5, 20, 40 MPa by default) and linearised with
rotations, bare and with coating cement (``md.grow_cement``, hard cement, Omega 3) at each
saturation S_c (fraction of pore cells). ``md.static_stiffness`` gives C11, C12, C13, C31, C33,
C44, C66 (GPa). Reported per member:

* the bulk modulus under hydrostatic stress ``K_reuss`` (1/K = sum S_ij over the normal block)
  against ``K_iso = C33 - 4/3 C44``, what the scene's MD backend now takes for K_dry, and the
  Voigt-type ``K_voigt = C_iijj / 9``;
* Thomsen's epsilon, gamma, delta (eqs. 8a, 8b, 17 of Thomsen 1986);
* the sample's own checks of the TI reading: reciprocity ``C13 / C31 - 1`` and
  ``(C11 - C12) / 2 C66 - 1`` (both zero for a transversely isotropic sample; the in-plane
  stress of a band 8 grain diameters high and 4 across carries sample noise, and a square
  periodic cell 4 grains across is not isotropic in the plane). ``C12 / (C11 - 2 C66) - 1``
  is recorded too: the same check, amplified by the small difference C11 - 2 C66;
* vertical Vp and Vs saturated with brine (K_f 2.5 GPa, 1.03 g/cm3; quartz K_0 from
  ``md.QUARTZ``) by anisotropic Gassmann (``rockcem.anisotropy.ti_gassmann``: C33_sat) and by
  isotropic Gassmann of K_iso (``rockcem.fluids.gassmann``: M_sat = K_sat + 4/3 C44), the
  porosity from the density (grain and cement 2650 kg/m3).

Output: ``results/md_anisotropy.csv``.
Run: ``python benchmarks/md_anisotropy.py [--stress 5 20 40] [--saturation 0 0.05 0.15]
[--seeds 0 1]`` (about 3 min on one core).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_anisotropy"
BRINE_K, BRINE_RHO = 2.5, 1.03          # GPa, g/cm3
SIZE, RADII, OMEGA = (4.0, 4.0, 12.0), (1.35e-4, 1.5e-4), 3.0


def member_row(pack, saturation, seed):
    """One member: the stiffness of ``pack`` bare (``saturation`` 0) or with coating cement."""
    import md
    from md.static import PA_PER_GPA, static_stiffness
    from rockcem.anisotropy import ti_gassmann, vertical_velocities
    from rockcem.fluids import gassmann

    t0 = time.perf_counter()
    if saturation > 0:
        lat = md.cement_lattice(pack, OMEGA)
        system = md.acoustic_system(pack, lat, md.grow_cement(lat, saturation, "coating",
                                                              seed=seed))
    else:
        system = md.acoustic_system(pack)
    st = static_stiffness(system)
    seconds = time.perf_counter() - t0
    c = {k: getattr(st, k) / PA_PER_GPA for k in ("c11", "c12", "c13", "c31", "c33", "c44",
                                                   "c66")}
    k_reuss, k_voigt = st.bulk_reuss / PA_PER_GPA, st.bulk_voigt / PA_PER_GPA
    k_iso = c["c33"] - 4.0 / 3.0 * c["c44"]
    rho = st.density / 1e3                                   # g/cm3
    phi = 1.0 - st.density / md.QUARTZ.density
    K0 = md.QUARTZ.bulk_modulus / PA_PER_GPA
    rho_sat = rho + phi * BRINE_RHO
    sat = ti_gassmann(c["c11"], c["c13"], c["c33"], c["c44"], c["c66"], K0, BRINE_K, phi)
    v_aniso = vertical_velocities(sat.c33, sat.c44, rho_sat)
    k_sat_iso = gassmann(k_iso, K0, BRINE_K, phi)
    vp_iso = float(np.sqrt((k_sat_iso + 4.0 / 3.0 * c["c44"]) / rho_sat))
    v_dry = vertical_velocities(c["c33"], c["c44"], rho)
    return dict(
        stress_MPa=pack.metadata.get("stress_zz", np.nan) / 1e6, seed=seed,
        cement_saturation=saturation, porosity=phi, density=rho, **c,
        K_reuss=k_reuss, K_voigt=k_voigt, K_iso=k_iso, K_iso_over_reuss=k_iso / k_reuss,
        epsilon=st.epsilon, gamma=st.gamma, delta=st.delta,
        reciprocity=c["c13"] / c["c31"] - 1.0,
        ti_c66=(c["c11"] - c["c12"]) / (2.0 * c["c66"]) - 1.0,
        ti_c12=c["c12"] / (c["c11"] - 2.0 * c["c66"]) - 1.0,
        vp_dry=float(v_dry.vp), vs_dry=float(v_dry.vs),
        vp_sat_aniso=float(v_aniso.vp), vp_sat_iso=vp_iso,
        vp_iso_over_aniso=vp_iso / float(v_aniso.vp), K_sat_aniso_c33=float(sat.c33),
        seconds=seconds)


def main(argv=None):
    import pandas as pd

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--stress", type=float, nargs="+", default=[5.0, 20.0, 40.0],
                    help="vertical stresses, MPa, in increasing order")
    ap.add_argument("--saturation", type=float, nargs="+", default=[0.0, 0.05, 0.15],
                    help="coating cement saturations S_c (0: bare)")
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    args = ap.parse_args(argv)
    _common.announce_source()
    rows = []
    for seed in args.seeds:
        t0 = time.perf_counter()
        pack = md.settle(size=SIZE, radius_range=RADII, fall_stiffness_factor=1e-3, seed=seed)
        print(f"seed {seed}: settled {pack.n_grains} grains in {time.perf_counter() - t0:.0f} s",
              flush=True)
        for stress in sorted(args.stress):
            pack = md.compact(pack, target_stress=stress * 1e6, stress_measure="stress_zz",
                              strain_step=5e-4)
            for s in args.saturation:
                rows.append(member_row(pack, s, seed))
                r = rows[-1]
                print(f"seed {seed} {stress:g} MPa S_c {s:g}: C11 {r['c11']:.2f} C13 "
                      f"{r['c13']:.2f} C33 {r['c33']:.2f} C44 {r['c44']:.2f} C66 "
                      f"{r['c66']:.2f} GPa, K_reuss {r['K_reuss']:.2f} K_iso {r['K_iso']:.2f}, "
                      f"eps {r['epsilon']:.3f} gam {r['gamma']:.3f} del {r['delta']:.3f}, "
                      f"Vp sat aniso {r['vp_sat_aniso']:.3f} iso {r['vp_sat_iso']:.3f} km/s",
                      flush=True)
    df = pd.DataFrame(rows)
    attrs = _common.environment_attrs(
        benchmark=NAME, pack=f"md.settle size {SIZE}, radii {RADII} m, quartz; md.compact "
        "stress_zz, strain_step 5e-4", cement=f"hard, coating, Omega {OMEGA:g}",
        fluid=f"brine K {BRINE_K} GPa, rho {BRINE_RHO} g/cm3",
        units="moduli GPa, density g/cm3, velocities km/s", **_common.md_source_attrs())
    _common.write_csv(df, _common.result_path(NAME, "csv"), attrs)
    print(_common.markdown(df, {
        "stress_MPa": ("MPa", "g"), "seed": ("seed", "g"), "cement_saturation": ("S_c", "g"),
        "porosity": ("phi", ".3f"), "c11": ("C11", ".2f"), "c13": ("C13", ".2f"),
        "c33": ("C33", ".2f"), "c44": ("C44", ".2f"), "c66": ("C66", ".2f"),
        "K_reuss": ("K TI", ".2f"), "K_iso": ("M-4/3G", ".2f"),
        "K_iso_over_reuss": ("ratio", ".2f"), "epsilon": ("eps", ".3f"),
        "gamma": ("gam", ".3f"), "delta": ("del", ".3f"), "reciprocity": ("C13/C31-1", ".3f"),
        "ti_c66": ("(C11-C12)/2C66-1", ".3f"), "vp_sat_aniso": ("Vp aniso", ".3f"),
        "vp_sat_iso": ("Vp iso", ".3f")}))


if __name__ == "__main__":
    main()
