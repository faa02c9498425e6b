"""The shipped scene with uncertain inputs, its figure and its wall time (issue 32, items 5
and 7), made by one command.

``python benchmarks/uncertain_scene.py`` runs ``carcione2022_sandstone_uncertain`` (the
sandstone of Carcione et al. 2022 with five uncertain inputs, 500 members on a Latin
hypercube, 601 depths, four models) from the current code, twice, in one process on one thread:

- as shipped (quantiles only), timed: its wall time, with the machine's load average before and
  after (other work on the machine slows it);
- with ``members = true`` (every member kept; the same seed and design, so the same members and
  quantiles, which the script checks), timed too: the members give the acoustic impedance and
  Vp/Vs panels their own quantiles (the quantile of a product is not the product of the
  quantiles).

It writes ``docs/carcione2022_sandstone_uncertain.png`` (:func:`rockcem.plots.depth_bands` of
the second run: per model the band between quantiles 0.1 and 0.9 and the median) and
``benchmarks/results/uncertain_scene.csv`` (one row per run: wall time, load averages, CPU
count). Every output records the git commit of the checkout (CSV attributes ``git_commit`` and
``git_tree``, PNG metadata and a footer); as ``md_scene_example.py`` does, the script refuses to
run when tracked files under ``md/``, ``rockcem/``, ``burial/`` or ``datasets/`` have
uncommitted changes, unless ``--allow-dirty`` (then the tree is recorded as dirty).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import md_scene_example as example  # noqa: E402  (its provenance: the commit, a clean tree)

NAME = "uncertain_scene"
SCENE = "carcione2022_sandstone_uncertain"


def timed(scene):
    """``(Dataset, wall seconds, load average before, after)`` of one run of ``scene``."""
    from rockcem.scene import run_scene

    before = os.getloadavg()[0]
    t0 = time.perf_counter()
    ds = run_scene(scene, progress=False)
    seconds = time.perf_counter() - t0
    return ds, seconds, before, os.getloadavg()[0]


def save(fig, path, prov):
    """``fig`` as PNG with the commit in a footer and in the PNG metadata, which names this
    script as the software; the figure is closed."""
    import matplotlib.pyplot as plt

    meta = {"Software": f"benchmarks/{os.path.basename(__file__)}",
            "Comment": "; ".join(f"{k}={prov[k]}" for k in ("git_commit", "git_tree"))}
    fig.text(0.995, 0.0, example._stamp(prov), ha="right", va="top", fontsize=6, color="0.45")

    def write(tmp):
        fig.savefig(tmp, format="png", dpi=110, metadata=meta, bbox_inches="tight")

    _common._atomic(path, write)
    plt.close(fig)                  # (a failed write ends the script: no figure left open)


def main(argv=None):
    _common.use_agg()
    cli = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    cli.add_argument("--allow-dirty", action="store_true",
                     help="run with uncommitted source changes (recorded as a dirty tree)")
    prov = example.provenance(cli.parse_args(argv).allow_dirty)
    _common.announce_source()
    import numpy as np
    import pandas as pd

    from rockcem import plots
    from rockcem.scene import load_scene, read_scene_toml, scene_from_dict, scene_path

    shipped = load_scene(SCENE)
    raw, _ = read_scene_toml(SCENE)
    raw["uncertain"]["members"] = True
    kept = scene_from_dict(raw, base_dir=scene_path(SCENE).parent)
    rows, runs = [], {}
    for label, scene in (("as shipped (quantiles)", shipped), ("members = true", kept)):
        ds, seconds, before, after = timed(scene)
        runs[label] = ds
        rows.append({"run": label, "members": int(scene.uncertain["samples"]),
                     "depths": int(ds.sizes["depth"]), "models": int(ds.sizes["model"]),
                     "wall_s": round(seconds, 2), "load_1min_before": round(before, 2),
                     "load_1min_after": round(after, 2), "cpu_count": os.cpu_count()})
        print(f"{SCENE}, {label}: {seconds:.1f} s (load average {before:.2f} before, "
              f"{after:.2f} after, {os.cpu_count()} CPUs)", flush=True)
    a, b = runs["as shipped (quantiles)"], runs["members = true"]
    same = max(float(np.nanmax(np.abs(a[v].values - b[v].values))) for v in a.data_vars)
    if same != 0.0:
        raise SystemExit(f"the run with members differs from the shipped one by {same:g}")
    attrs = {**_common.environment_attrs(scene=SCENE), **prov,
             "quantiles_identical_between_runs": 1}
    _common.write_csv(pd.DataFrame(rows), _common.result_path(NAME, "csv"), attrs)
    fig = plots.depth_bands(b)
    shipped_s = rows[0]["wall_s"]
    note = fig.legends[-1].get_title()         # depth_bands' note below the panels
    note.set_text(f"{SCENE}: {rows[0]['members']} members (Latin hypercube), "
                  f"{shipped_s:.1f} s on one core (rockcem run: the first run in its "
                  "process).\n" + note.get_text())
    save(fig, _common.ROOT / "docs" / f"{SCENE}.png", prov)
    print(f"wrote docs/{SCENE}.png and benchmarks/results/{NAME}.csv "
          f"({example._stamp(prov)})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
