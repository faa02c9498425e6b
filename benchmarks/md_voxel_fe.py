"""Voxel finite elements (md.voxel) against the MD cement lattice on densely cemented samples.

Two samples, each at several resolutions Omega (cells per grain radius; the voxels are the
cells of the MD cement lattice):

1. ``full``: the pack of ``benchmarks/md_full_cement.py`` (3 x 3 x 10 diameters, seed 0,
   64.5 MPa, reconstructed to IGV 0.2845), its pores full of cement: the five constants against
   the Hashin-Shtrikman bounds of its grains and cement (``rockcem.bounds``; the pack's
   fractions and those of the voxels of the measured band) and against the lattice's numbers
   (``benchmarks/results/md_full_cement.csv``), with the wall time and peak memory of each
   member; at one Omega also the solver's tolerance, the preconditioner and the measured band's
   margin.
2. ``coating``: the densely coated members of the shipped MD example
   (``carcione2022_sandstone_md``) at 3500 and 4000 m: the scene run at those two depths
   (one pack, seed 0, cement grown during burial as the scene grows it: the 4000 m member
   carries the 3500 m cement), at its Omega 6 with checks 4 and 2.67; the lattice's constants
   are those of the scene's member files, the voxel constants are solved on the same packs and
   cement cells (the scene's stage files). ``bare``: the 3500 m pack without cement, voxel
   elements (grains welded where their voxels touch) against the MD pack's Hertzian contacts
   (:func:`md.static.static_stiffness`).

Each member runs in a fresh process (its peak memory is its own), one core, the repeats
interleaved over Omega (other jobs share the machine: the best of the repeats is reported and
the spread kept). Writes ``benchmarks/results/md_voxel_fe.csv``. Run:
``python benchmarks/md_voxel_fe.py [--omega 2 3 4 6] [--repeats 2] [--part full coating]
[--keep-other-parts] [--merge-from FILE]`` (the committed file: ``--part full --repeats 2``
and ``--part coating --repeats 1 --output FILE`` side by side, then ``--part
--keep-other-parts --merge-from FILE``).
"""

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import glob  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

NAME = "md_voxel_fe"
CONSTANTS = ("c33", "c11", "c44", "c66", "c13")
#: The lattice's constants in the member files (md.along_depth.MODULI) by voxel name.
LATTICE = {"c33": "p_modulus", "c44": "shear_modulus", "c11": "c11", "c13": "c13", "c66": "c66"}
SCENE = "carcione2022_sandstone_md"
COATING_DEPTHS = [3500.0, 4000.0]


def _materials():
    from rockcem._md_backend import _materials as convert
    from rockcem.materials import mineral

    return convert(mineral("quartz"), mineral("quartz_cement"))


def _peak_memory_mb():
    """This process's peak resident memory, MB: ``VmHWM`` of ``/proc/self/status`` (reset by
    ``exec``, where ``getrusage``'s ``ru_maxrss`` keeps the forking parent's peak)."""
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmHWM:"):
                return float(line.split()[1]) / 1024.0
    return float("nan")


def _band_fractions(phase, band):
    """Grain, cement and pore fractions of the voxels of the measured band (node planes
    ``band``), where the stress and strain are taken."""
    inner = phase[:, :, band[0]:band[1]]
    return {"grain_band": float(np.mean(inner == 0)), "cement_band": float(np.mean(inner == 1)),
            "pore_band": float(np.mean(inner < 0))}


def _hs_columns(row, fractions, tag):
    """Hashin-Shtrikman bounds of quartz grains, quartz cement and empty pores (GPa)."""
    from rockcem.bounds import hashin_shtrikman
    from rockcem.materials import mineral

    qz, qc = mineral("quartz"), mineral("quartz_cement")
    hs = hashin_shtrikman([qz.K, qc.K, 0.0], [qz.G, qc.G, 0.0], fractions)
    row[f"hs_upper_M_{tag}"] = float(hs.upper.K + 4.0 / 3.0 * hs.upper.G)
    row[f"hs_lower_M_{tag}"] = float(hs.lower.K + 4.0 / 3.0 * hs.lower.G)
    row[f"hs_upper_G_{tag}"] = float(hs.upper.G)
    row[f"hs_lower_G_{tag}"] = float(hs.lower.G)
    row[f"hs_upper_K_{tag}"] = float(hs.upper.K)
    return row


def one(spec):
    """One voxel member (in this process): ``spec`` holds ``pack`` (a pack file), ``cells``
    (a cement stage file; None: every pore cell cemented; ``"bare"``: none), ``omega``,
    ``slab`` (m), and the options of :func:`md.voxel.voxel_stiffness`. Returns its constants
    (GPa), the voxel fractions, wall time and peak memory."""
    from md.cement import cement_lattice
    from md.along_depth import _load_cells
    from md.state import load_pack
    from md.voxel import pack_phases, sample_stiffness

    grain, cement = _materials()
    t0 = time.perf_counter()
    pack = load_pack(spec["pack"])
    lat = cement_lattice(pack, spec["omega"])
    cells = np.ones(lat.index.size, bool) if spec["cells"] is None else \
        np.zeros(lat.index.size, bool) if spec["cells"] == "bare" else _load_cells(spec["cells"])
    r = sample_stiffness(pack, lat, cells, cement, grain=grain, slab_thickness=spec["slab"],
                         **spec["options"])
    wall = time.perf_counter() - t0
    phase = pack_phases(pack, lat, cells)
    out = {k: getattr(r, k) / 1e9 for k in (*CONSTANTS, "c12", "c31", "bulk_reuss")}
    out.update(density=r.density, wall_s=wall, setup_s=r.metadata["setup_s"],
               solve_s=r.metadata["solve_s"], free_dof=r.metadata["free_dof"],
               iterations=sum(r.metadata["iterations"].values()),
               dropped_voxels=r.metadata["dropped_voxels"],
               dropped_clusters=r.metadata["dropped_clusters"],
               grain_voxels=float(np.mean(phase == 0)), cement_voxels=float(np.mean(phase == 1)),
               pore_voxels=float(np.mean(phase < 0)),
               **_band_fractions(phase, r.metadata["band"]),
               peak_rss_mb=_peak_memory_mb())
    return out


def run_one(spec):
    """:func:`one` in a fresh process (one core, its own peak memory)."""
    done = subprocess.run([sys.executable, __file__, "--one", json.dumps(spec)],
                          capture_output=True, text=True, check=False,
                          cwd=str(Path(__file__).parent))
    if done.returncode != 0:
        raise RuntimeError(f"voxel member {spec} failed:\n{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def _best(rows):
    """The constants of the first repeat (they are deterministic) and the best time."""
    out = dict(rows[0])
    for k in ("wall_s", "setup_s", "solve_s"):
        out[k] = min(r[k] for r in rows)
        out[f"{k}_max"] = max(r[k] for r in rows)
    out["peak_rss_mb"] = max(r["peak_rss_mb"] for r in rows)
    out["repeats"] = len(rows)
    return out


def full_part(args, work):
    """Part 1: the full-pore sample of md_full_cement at each Omega."""
    import md_full_cement

    from md.state import load_pack

    # md_full_cement's own pack building (its lattice at Omega 2, cheap, builds the stages).
    md_full_cement.main(["--omega", "2", "--workdir", str(work / "full"),
                         "--output", str(work / "full_lattice_w2.csv")])
    lattice2 = pd.read_csv(work / "full_lattice_w2.csv", comment="#")
    pack_file = glob.glob(str(work / "full" / "*" / "pack" / "reconstruct_*.nc"))[0]
    pack = load_pack(pack_file)
    slab = 2.0 * float(pack.radii.max())          # carry_down's slab = 1 diameter
    committed = pd.read_csv(_common.result_path("md_full_cement", "csv"), comment="#")
    lattice = pd.concat([lattice2, committed]).drop_duplicates("omega", keep="last") \
        .set_index("omega")
    base = {"solver": "amg", "rtol": 1e-8, "margin": 0.5}
    specs = [(om, base) for om in args.omega]
    # The knobs at one Omega: tolerance, preconditioner, margin of the measured band.
    knob_omega = args.knob_omega
    for options in ({**base, "rtol": 1e-6}, {**base, "rtol": 1e-10},
                    {**base, "solver": "jacobi"}, {**base, "margin": 0.0},
                    {**base, "margin": 1.0}):
        specs.append((knob_omega, options))
    runs = {i: [] for i in range(len(specs))}
    for rep in range(args.repeats):                   # interleaved repeats
        for i, (om, options) in enumerate(specs):
            print(f"full: Omega {om:g} {options} (repeat {rep + 1})", flush=True)
            runs[i].append(run_one({"pack": pack_file, "cells": None, "omega": om,
                                    "slab": slab, "options": options}))
    rows = []
    for i, (om, options) in enumerate(specs):
        r = _best(runs[i])
        phi = float(lattice2.porosity.iloc[0])
        beta = float(lattice2.cement_per_solid.iloc[0])
        fr_pack = [(1 - phi) * (1 - beta), (1 - phi) * beta, phi]
        fr_vox = [r["grain_band"], r["cement_band"], r["pore_band"]]
        row = {"part": "full", "depth_m": np.nan, "omega": om, **{f"opt_{k}": v for k, v in
                                                                  options.items()}, **r}
        _hs_columns(row, fr_pack, "pack")
        _hs_columns(row, fr_vox, "voxel")
        row["lambda_solid"] = row["hs_upper_K_pack"] - 2.0 / 3.0 * row["hs_upper_G_pack"]
        if om in lattice.index:
            for k in CONSTANTS:
                row[f"lattice_{k}"] = float(lattice.loc[om, k.upper()])
            row["lattice_wall_s"] = float(lattice.loc[om, "member_wall_time_s"])
        rows.append(row)
    return rows


def coating_part(args, work):
    """Part 2: the example's coated members at 3500 and 4000 m, lattice and voxel."""
    import xarray as xr

    from rockcem.scene import load_scene, run_scene

    folder = work / "coating"
    scene = load_scene(SCENE).replace(**{"models.md.workdir": str(folder),
                                         "models.md.depths": COATING_DEPTHS,
                                         "models.md.samples": 1})
    t0 = time.perf_counter()
    run_scene(scene, jobs=1, progress=False)
    print(f"coating: the scene at {COATING_DEPTHS} m took {time.perf_counter() - t0:.0f} s",
          flush=True)
    chain = next(p for p in folder.iterdir() if (p / "members").is_dir())
    # One member file per depth: the newest (a member made by other md sources stays beside
    # it; its lattice constants are the same).
    newest = {}
    for f in sorted(chain.glob("members/*.nc"), key=lambda p: p.stat().st_mtime):
        newest[f.name.split("_c")[-1].rsplit("_", 1)[0]] = f
    members = list(newest.values())
    packs = sorted(chain.glob("pack/reconstruct_*.nc"),
                   key=lambda p: -float(p.name.split("_")[1]))     # IGV falls with depth
    slab = None
    specs, meta = [], []
    for depth, member, pack_file in zip(COATING_DEPTHS, sorted(
            members, key=lambda p: float(p.name.split("_c")[-1].rsplit("_", 1)[0])), packs):
        frac = member.name.split("_c")[-1].rsplit("_", 1)[0]
        with xr.open_dataset(member) as ds:
            lat_values = {k: float(ds[k]) for k in ds.data_vars}
        if slab is None:
            from md.state import load_pack
            slab = 2.0 * float(load_pack(pack_file).radii.max())
        omegas = [6.0, 4.0, 6.0 / 1.5**2]
        for om, suffix in zip(omegas, ("", "_check", "_check2")):
            cells = glob.glob(str(chain / "cement" / f"coating_w{om:g}_c{frac}_*.nc"))
            if len(cells) != 1:
                raise RuntimeError(f"no unique cement stage file for Omega {om:g}, c {frac}")
            spec = {"pack": str(pack_file), "cells": cells[0], "omega": om, "slab": slab,
                    "options": {"solver": "amg", "rtol": 1e-8, "margin": 0.5}}
            specs.append(spec)
            meta.append({"part": "coating", "depth_m": depth, "omega": om,
                         "cement_fraction": float(frac),
                         **{f"lattice_{k}": lat_values[f"{v}{suffix}"] / 1e9
                            for k, v in LATTICE.items()},
                         "lattice_member_wall_s": lat_values["wall_time"]})
    # The same 3500 m pack without cement: the welded grain contacts of the voxel sample
    # against the MD pack's Hertzian (flattened) contacts (md.static on grains alone).
    from md.acoustic import acoustic_system
    from md.state import load_pack
    from md.static import static_stiffness

    bare = load_pack(packs[0])
    st = static_stiffness(acoustic_system(bare, slab_thickness=slab))
    contacts = {f"lattice_{k}": getattr(st, k) / 1e9 for k in CONSTANTS}
    for om in args.bare_omega:
        specs.append({"pack": str(packs[0]), "cells": "bare", "omega": om, "slab": slab,
                      "options": {"solver": "amg", "rtol": 1e-8, "margin": 0.5}})
        meta.append({"part": "bare", "depth_m": COATING_DEPTHS[0], "omega": om,
                     "cement_fraction": 0.0, **contacts})
    runs = {i: [] for i in range(len(specs))}
    for rep in range(args.repeats):
        for i, spec in enumerate(specs):
            print(f"{meta[i]['part']}: {meta[i]['depth_m']:g} m, Omega {spec['omega']:g} "
                  f"(repeat {rep + 1})", flush=True)
            runs[i].append(run_one(spec))
    rows = [{**meta[i], **_best(runs[i])} for i in range(len(specs))]
    return [_hs_columns(r, [r["grain_band"], r["cement_band"], r["pore_band"]], "voxel")
            for r in rows]


def _made_by(path):
    """The commit and command a table of this script names in its header."""
    with open(path) as fh:
        return "; ".join(line[2:].strip() for line in fh
                         if line.startswith(("# git_commit", "# command")))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--omega", type=float, nargs="+", default=[2.0, 3.0, 4.0, 6.0])
    parser.add_argument("--knob-omega", type=float, default=4.0)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--bare-omega", type=float, nargs="*", default=[2.0, 8.0 / 3.0, 4.0])
    parser.add_argument("--part", nargs="*", default=["full", "coating"])
    parser.add_argument("--merge-from", default=None,
                        help="a table this script wrote: its rows of the parts not run now")
    parser.add_argument("--workdir", default=None)
    parser.add_argument("--output", default=None)
    parser.add_argument("--keep-other-parts", action="store_true",
                        help="keep the rows of the parts not run now from the output file")
    parser.add_argument("--one", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.one is not None:
        print(json.dumps(one(json.loads(args.one))))
        return 0
    _common.announce_source()
    work = Path(args.workdir or tempfile.mkdtemp(prefix="md_voxel_fe_"))
    rows = []
    if "full" in args.part:
        rows += full_part(args, work)
    if "coating" in args.part:
        rows += coating_part(args, work)
    out = args.output or _common.result_path(NAME, "csv")
    parts = {"coating": ("coating", "bare")}.get
    mine = {p for part in args.part for p in (parts(part) or (part,))}
    if args.keep_other_parts and Path(out).exists():     # the rows of the parts not run now
        old = pd.read_csv(out, comment="#")
        rows = old[~old.part.isin(mine)].to_dict("records") + rows
    if args.merge_from:
        other = pd.read_csv(args.merge_from, comment="#")
        rows = rows + other[~other.part.isin(mine)].to_dict("records")
    table = pd.DataFrame(rows)
    attrs = {**_common.environment_attrs(), **_common.md_source_attrs(),
             "md": "voxel finite elements (md.voxel) on the MD cement lattice's cells; full: "
                   "md_full_cement's pack, pores full; coating: carcione2022_sandstone_md at "
                   f"{COATING_DEPTHS} m, one pack (seed 0), grown cement",
             "timing": f"each member in a fresh process on one core, {args.repeats} "
                       "interleaved repeats, best and worst kept; other jobs share the machine",
             "units": "moduli GPa, times s, memory MB"}
    if args.merge_from:
        attrs["merged_parts_made_by"] = _made_by(args.merge_from)
    if args.keep_other_parts and Path(out).exists():
        attrs["kept_parts_made_by"] = _made_by(out)
    _common.write_csv(table.round({c: 6 for c in table.columns if c != "opt_rtol"}), out,
                      attrs)
    cols = ["part", "depth_m", "omega", "opt_solver", "opt_rtol", "opt_margin", *CONSTANTS,
            "wall_s", "peak_rss_mb"]
    with pd.option_context("display.width", 220, "display.max_columns", 40):
        print(table[[c for c in cols if c in table]].round(3).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
