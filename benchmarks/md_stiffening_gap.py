"""Why the MD stiffens more with contact cement than García & Medina's (issue 12): the source's
choices switched on one at a time, on the same packs.

The full-size study (``garcia_medina_full``) raises the compacted pack's Vp by +91 % (hard) and
+39 % (soft) from S_c 0 to 0.1 of contact cement, where the source reports about +25 % and +12 %
(Fig. 11) from the same uncemented 1.7 km/s. This script starts from the engine's choices and
switches to the source's, one at a time and then all together:

``engine``
    the study's own: sequential deposition (compacted core porosity 0.36), lattice resolution
    Omega 6, the ``facet`` interface (converges with Omega), tangent Hertz stiffness
    :math:`2E_fa`, lattice constants from the wave speeds;
``omega``
    the source's resolution, Omega 10 (c_w = R/10, Sect. III B);
``paper_interface``
    the source's per-cell grain–cement spring, eq. 4 with a contact of diameter c_w;
``secant``
    the source's eq. 4 read literally: the normal stiffness of eq. 1, :math:`\\tfrac43 E_fa`
    (two thirds of the tangent), for grain–grain and (with the per-cell interface) grain–cement
    bonds;
``paper_lattice``
    the lattice constants of eq. 9 (1 % fast in P);
``loose_pack``
    a pack released all at once from a lattice (``protocol="lattice"``), looser than sequential
    deposition: compacted to the same stress its porosity is close to the source's 0.386;
``source_pack``
    instead, sequential deposition through ten times the fluid drag (500 1/s), which settles
    near the source's loose porosity 0.412 (0.410 on 6 x 6 x 8 packs, ``md_settle_compact``;
    0.403 at the default size here) and compacts to its 0.386.

Each row is a configuration, scheme (default the source's ``contact`` growth) and cement. The
measure is the static long-wave P velocity of the linearised sample (``md.static_modulus``) at
S_c = 0 and ``--saturation``, and their ratio; with ``--pulse`` also the pulse test's Vp and its
eq. 11 error. The pulse lies below the static velocity: by 2-17 % on the 6 x 6 x 16 pack, whose
short length disperses the pulse (more in the cemented samples, so the pulse ratios scatter
more than the static ones), and by 2-5 % on the full sample. The CCT velocities (Dvorkin & Nur
schemes 1 and 2, the solved contact problem, ``_common.cct_vp``, at the pack's porosity and
coordination) are printed beside them: the source places its compacted sample between the two
(Sect. IV).

Packs: ``--size`` largest diameters (default 6 x 6 x 16, 768 grains), seed ``--seed``,
compacted to ``--stress`` MPa of sigma_zz (the first strain increment past it: 30-34 MPa), made
once in
``results/md_stiffening_gap_work/<pack>_<size>_seed<seed>/`` and resumed from there
(``md.prepare_pack``; the drag-500 pack takes about 10 minutes of one core at the default size).

Output: ``results/md_stiffening_gap[_<tag>].{csv,nc}`` (one row per configuration, scheme and
cement), and a markdown table on stdout.
Run: ``python benchmarks/md_stiffening_gap.py [--pulse] [--size 8 8 32 --configs engine
paper_lattice --tag full]`` (a few minutes on one core with the packs made).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_stiffening_gap"

#: Settling options of each pack (the rest: size, seed, radii, fall stiffness factor 1e-3).
PACKS = {"sequential": dict(protocol="sequential"), "lattice": dict(protocol="lattice"),
         "drag500": dict(protocol="sequential", drag=500.0, max_time=30.0)}
#: The engine's own configuration (Omega "engine" is --omega-engine, "source" --omega-source).
ENGINE = {"pack": "sequential", "omega": "engine", "interface": "facet",
          "normal_stiffness": "tangent", "lattice_rule": "waves"}
#: The source's choices, in the order the ladder switches them on.
SWITCHES = {"omega": {"omega": "source"}, "paper_interface": {"interface": "paper"},
            "secant": {"normal_stiffness": "secant"}, "paper_lattice": {"lattice_rule": "paper"},
            "loose_pack": {"pack": "lattice"}, "source_pack": {"pack": "drag500"}}
#: The switches also tried alone, from the engine's configuration (rows ``only_<switch>``).
ALONE = ("omega", "paper_interface", "secant", "loose_pack", "source_pack")


def configurations():
    """``(label, configuration)``: the engine's, each switch on top of the ones before (the
    ladder; ``source_pack`` takes the place of ``loose_pack``), and the switches of
    :data:`ALONE` on their own."""
    out, cumulative = [("engine", ENGINE)], dict(ENGINE)
    for name, change in SWITCHES.items():
        cumulative = {**cumulative, **change}
        out.append((name, cumulative))
    return out + [(f"only_{name}", {**ENGINE, **SWITCHES[name]}) for name in ALONE]


def _static_and_pulse(system, pulse):
    """Static P velocity, and (with ``pulse``) the pulse-test Vp and its eq. 11 error, m/s."""
    import md

    t0 = time.perf_counter()
    st = md.static_modulus(system, "p")
    out = {"vp_static": st.velocity, "modulus_GPa": st.modulus / 1e9,
           "vp_pulse": np.nan, "vp_pulse_error": np.nan}
    if pulse:
        ds = md.pulse_test(system, "p")
        out.update(vp_pulse=float(ds.velocity), vp_pulse_error=float(ds.velocity_error))
    out["seconds"] = time.perf_counter() - t0
    return out


def main(argv=None):
    import pandas as pd
    import xarray as xr

    import md

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=float, nargs=3, default=[6.0, 6.0, 16.0])
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--stress", type=float, default=30.0, help="compaction sigma_zz, MPa")
    ap.add_argument("--omega-engine", type=float, default=6.0)
    ap.add_argument("--omega-source", type=float, default=10.0)
    ap.add_argument("--saturation", type=float, default=0.1)
    ap.add_argument("--schemes", nargs="+", default=["contact"],
                    choices=["contact", "coating", "pore_body", "pendular"])
    ap.add_argument("--cements", nargs="+", default=["hard", "soft"], choices=["hard", "soft"])
    ap.add_argument("--configs", nargs="+", default=None,
                    choices=[label for label, _ in configurations()],
                    help="labels to run (default: the whole ladder and the single switches)")
    ap.add_argument("--pulse", action="store_true", help="also the pulse test (eqs. 10-11)")
    ap.add_argument("--restitution", type=float, default=None,
                    help="restitution of every contact dashpot (default the material's 0.9)")
    ap.add_argument("--tag", default="")
    args = ap.parse_args(argv)
    _common.announce_source()
    cements = {"hard": md.HARD_CEMENT, "soft": md.SOFT_CEMENT}
    omegas = {"engine": args.omega_engine, "source": args.omega_source}
    configs = [(label, c) for label, c in configurations()
               if args.configs is None or label in args.configs]
    size_tag = "x".join(f"{s:g}" for s in args.size)

    packs, pack_rows = {}, {}
    for protocol in sorted({c["pack"] for _, c in configs}):
        folder = _common.RESULTS / f"{NAME}_work" / f"{protocol}_{size_tag}_seed{args.seed}"
        packs[protocol] = md.prepare_pack(
            folder,
            settle_options=dict(size=tuple(args.size), radius_range=(1.8e-4, 2.0e-4),
                                seed=args.seed, fall_stiffness_factor=1e-3, **PACKS[protocol]),
            compact_options=dict(target_stress=args.stress * 1e6), progress=True)
        rec = packs[protocol].metadata["record"]
        settled = md.load_pack(folder / "settle.nc").metadata
        pack_rows[protocol] = dict(
            settled_porosity=settled["porosity"], porosity=rec["porosity"][-1],
            stress_zz_MPa=rec["stress_zz"][-1] / 1e6,
            coordination=rec["coordination_number"][-1], n_grains=packs[protocol].n_grains)
        pr = pack_rows[protocol]
        print(f"pack {protocol}: {pr['n_grains']} grains, core porosity "
              f"{pr['settled_porosity']:.3f} settled, {pr['porosity']:.3f} at sigma_zz "
              f"{pr['stress_zz_MPa']:.1f} MPa, coordination {pr['coordination']:.2f}", flush=True)

    lattices, growths, uncemented = {}, {}, {}
    rows = []
    measured = {}                  # a configuration met twice (only_omega = omega) runs once
    theory = {}
    for label, config in configs:
        protocol, normal = config["pack"], config["normal_stiffness"]
        interface, lrule = config["interface"], config["lattice_rule"]
        pack, pr = packs[protocol], pack_rows[protocol]
        omega = omegas[config["omega"]]
        if (protocol, omega) not in lattices:
            lattices[protocol, omega] = md.cement_lattice(pack, omega)
        lat = lattices[protocol, omega]
        if (protocol, normal) not in uncemented:
            uncemented[protocol, normal] = _static_and_pulse(
                md.acoustic_system(pack, normal_stiffness=normal, restitution=args.restitution,
                                   rotations=False),
                args.pulse)
        bare = uncemented[protocol, normal]
        for scheme in args.schemes:
            if (protocol, omega, scheme) not in growths:
                growths[protocol, omega, scheme] = md.grow_cement(lat, args.saturation, scheme)
            cemented = growths[protocol, omega, scheme]
            for cname in args.cements:
                cement = cements[cname]
                key = (protocol, omega, interface, normal, lrule, scheme, cname)
                if key not in measured:
                    measured[key] = _static_and_pulse(md.acoustic_system(
                        pack, lat, cemented, cement, rule=lrule, interface=interface,
                        normal_stiffness=normal, restitution=args.restitution,
                        rotations=False), args.pulse)
                got = measured[key]
                if (protocol, cname) not in theory:     # depends on the pack and cement only
                    theory[protocol, cname] = [1e3 * float(_common.cct_vp(
                        pr["porosity"], pr["coordination"], cement, args.saturation, k,
                        stiffness="integral")) for k in (1, 2)]
                cct1, cct2 = theory[protocol, cname]
                rows.append(dict(
                    config=label, scheme=scheme, cement=cname, pack=protocol, omega=omega,
                    interface=interface, normal_stiffness=normal, lattice_rule=lrule, **pr,
                    saturation=args.saturation, cement_cells=int(cemented.sum()),
                    vp0_static=bare["vp_static"], vp_static=got["vp_static"],
                    ratio_static=got["vp_static"] / bare["vp_static"],
                    vp0_pulse=bare["vp_pulse"], vp0_pulse_error=bare["vp_pulse_error"],
                    vp_pulse=got["vp_pulse"], vp_pulse_error=got["vp_pulse_error"],
                    ratio_pulse=got["vp_pulse"] / bare["vp_pulse"],
                    modulus0_GPa=bare["modulus_GPa"], modulus_GPa=got["modulus_GPa"],
                    cct1=cct1, cct2=cct2, seconds=got["seconds"]))
                r = rows[-1]
                print(f"{label:>22s} {scheme} {cname}: static Vp {r['vp0_static']:.0f} -> "
                      f"{r['vp_static']:.0f} m/s (x{r['ratio_static']:.3f}), pulse "
                      f"{r['vp0_pulse']:.0f} -> {r['vp_pulse']:.0f}; CCT {cct1:.0f} / "
                      f"{cct2:.0f}; {r['seconds']:.1f} s", flush=True)
    frame = pd.DataFrame(rows)
    columns = {
        "config": ("configuration", "s"), "scheme": ("scheme", "s"), "cement": ("cement", "s"),
        "pack": ("pack", "s"), "settled_porosity": ("settled φ", ".3f"),
        "porosity": ("φ", ".3f"), "coordination": ("n", ".2f"), "omega": ("Ω", "g"),
        "interface": ("interface", "s"), "normal_stiffness": ("k_n", "s"),
        "vp0_static": ("Vp S_c 0 (m/s)", ".0f"),
        "vp_static": (f"Vp S_c {args.saturation:g} (m/s)", ".0f"),
        "ratio_static": ("ratio", ".3f")}
    if args.pulse:
        columns.update(vp0_pulse=("pulse S_c 0", ".0f"), vp_pulse=("pulse cemented", ".0f"),
                       vp_pulse_error=("± eq. 11", ".0f"), ratio_pulse=("pulse ratio", ".3f"))
    columns.update(cct1=("CCT 1 (m/s)", ".0f"), cct2=("CCT 2 (m/s)", ".0f"))
    print()
    print(_common.markdown(frame, columns))
    attrs = _common.environment_attrs(
        title="md: the source's choices switched one at a time, contact cement stiffening",
        benchmark=NAME, size=" ".join(f"{s:g}" for s in args.size), seed=args.seed,
        compaction_stress_MPa=args.stress, saturation=args.saturation,
        schemes=" ".join(args.schemes), pulse=int(args.pulse),
        restitution=args.restitution if args.restitution is not None else "material (0.9)",
        measure="static long-wave P velocity (md.static_modulus); pulse Vp with --pulse",
        **_common.md_source_attrs())
    _common.write_csv(frame, _common.result_path(NAME, "csv", args.tag), attrs)
    out = xr.Dataset.from_dataframe(frame)
    out.attrs.update(attrs)
    _common.write_netcdf(out, _common.result_path(NAME, "nc", args.tag))


if __name__ == "__main__":
    main()
