"""Burial's rock in MD (issue 29 items 1-2): the MD sample's porosity against burial's, and the
velocity change of each choice, on the sandstone example (carcione2022_sandstone_md).

Four runs of the scene's MD member on one small pack (3 x 3 x 8 grain diameters, Omega 3, the
coating scheme, one resolution), sharing the Hertzian stage files:

* ``reconstruct/grown`` (the default): compacted on to burial's intergranular volume by
  process-based reconstruction (md.reconstruct), cement grown during burial;
* ``reconstruct/fresh``: the same packs, each depth cemented afresh;
* ``hertz/grown`` and ``hertz/fresh``: Hertzian compaction only (porosity near 0.37).

Writes benchmarks/results/md_burial_rock.csv: per depth burial's porosity, IGV and cement; the
MD pack and sample porosity of each compaction; vp and vs of each run; the differences
reconstruct - hertz (grown cement) and grown - fresh (each compaction); vp of the scene's
other models (Carcione et al.'s Models 1-4) for comparison. Run:
``python benchmarks/md_burial_rock.py [--depths 1000 2500 ...]`` (about 5 min on one core).
"""

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

SCENE = "carcione2022_sandstone_md"
NAME = "md_burial_rock"
RUNS = [("reconstruct", "grown"), ("reconstruct", "fresh"), ("hertz", "grown"),
        ("hertz", "fresh")]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--depths", type=float, nargs="+",
                        default=[1000.0, 2000.0, 2500.0, 3000.0, 4000.0, 5000.0, 6000.0])
    parser.add_argument("--workdir", default=None, help="stage files (default: a temporary "
                        "folder)")
    parser.add_argument("--output", default=None)
    args = parser.parse_args(argv)
    _common.announce_source()
    from rockcem.scene import load_scene, run_scene

    work = Path(args.workdir or tempfile.mkdtemp(prefix="md_burial_rock_"))
    base = load_scene(SCENE)
    rows, walls = {}, {}
    for compaction, history in RUNS:
        scene = base.replace(**{"models.md.workdir": str(work), "models.md.size": [3.0, 3.0, 8.0],
                                "models.md.resolution": 3.0, "models.md.resolution_check": 0.0,
                                "models.md.resolution_check2": 0.0,
                                "models.md.schemes": ["coating"], "models.md.samples": 1,
                                "models.md.depths": args.depths,
                                "models.md.compaction": compaction,
                                "models.md.cement_history": history})
        t0 = time.perf_counter()
        ds = run_scene(scene)
        walls[f"{compaction}/{history}"] = time.perf_counter() - t0
        ran = np.isfinite(ds.vp.sel(model="md").values)
        sub = ds.isel(depth=ran)
        tag = f"{compaction}_{history}"
        rows.setdefault("depth_m", sub.depth.values)
        rows.setdefault("burial_porosity", sub.porosity.values)
        rows.setdefault("burial_igv", sub.intergranular_volume.values)
        rows.setdefault("burial_cement", sub.cement_fraction.values)
        rows[f"md_pack_porosity_{compaction}"] = sub.md_pack_porosity.values
        rows[f"md_porosity_{compaction}"] = sub.md_porosity.values
        rows[f"vp_{tag}"] = sub.vp.sel(model="md").values
        rows[f"vs_{tag}"] = sub.vs.sel(model="md").values
    for m in sub.model.values:                  # the scene's other models, for comparison
        if m != "md":
            rows[f"vp_{m}"] = sub.vp.sel(model=m).values
    table = pd.DataFrame(rows)
    for v in ("vp", "vs"):
        table[f"d{v}_reconstruct_minus_hertz"] = (table[f"{v}_reconstruct_grown"]
                                                  - table[f"{v}_hertz_grown"])
        for c in ("reconstruct", "hertz"):
            table[f"d{v}_grown_minus_fresh_{c}"] = table[f"{v}_{c}_grown"] - table[f"{v}_{c}_fresh"]
    table["porosity_gap_reconstruct"] = table["md_porosity_reconstruct"] - table["burial_porosity"]
    table["porosity_gap_hertz"] = table["md_porosity_hertz"] - table["burial_porosity"]
    attrs = {**_common.environment_attrs(scene=SCENE),
             "md": "size 3x3x8 diameters, Omega 3, coating, one pack, one resolution",
             "wall_time_s": "; ".join(f"{k} {v:.0f}" for k, v in walls.items()),
             "units": "porosity 1, velocities km s-1"}
    out = args.output or _common.result_path(NAME, "csv")
    _common.write_csv(table.round(5), out, attrs)
    with pd.option_context("display.width", 200, "display.max_columns", 40):
        print(table.round(4).to_string(index=False))
    print(attrs["wall_time_s"])


if __name__ == "__main__":
    main()
