"""The shipped AVO scene's results (issue 31, Show), made by one command.

``python benchmarks/avo_scene.py`` runs the stack scene ``carcione2022_avo`` (the shale of
Carcione et al. 2022 over their sandstone on one linear path; brine, gas and CO2 sands; needs
CoolProp for the CO2) from the current code, a few seconds on one core, and writes

- ``benchmarks/results/avo_scene.csv``: intercept A, gradient B, curvature C and the AVO class of
  the seal/reservoir interface at 1, 2, 3 and 4 km, one row per depth, model and fluid; and the
  depths where each model and fluid changes class, ``benchmarks/results/avo_scene_changes.csv``
  (both with the scene's validity warnings in their ``#`` header);
- the figures of the documentation page ``docs/user_guide/avo.md``:
  ``docs/carcione2022_avo_class.png`` (AVO class against depth, brine, gas and CO2, every model),
  ``docs/carcione2022_avo_crossplot.png`` (the A-B crossplot of Models 1, 3 and 4: Model 2's
  shallow gas and CO2 reach A = -0.96 and would squash the others into a corner),
  ``docs/carcione2022_avo_angle.png`` (R_PP against angle at 1, 2, 3 and 4 km) and
  ``docs/carcione2022_avo_synthetic.png`` (the normal-incidence synthetic of the column, every
  model, each trace scaled to its own peak, in a window around the seal/reservoir reflection,
  with the angle gathers at its top).

Every output records the git commit of the checkout (CSV attributes ``git_commit`` and
``git_tree``, PNG metadata and a footer). As ``md_scene_example.py`` does, the script refuses to
run when tracked files under ``md/``, ``rockcem/``, ``burial/`` or ``datasets/`` have uncommitted
changes; ``--allow-dirty`` runs anyway and records the tree as dirty.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import md_scene_example as example  # noqa: E402  (its provenance: the commit, a clean tree)

NAME = "avo_scene"
SCENE = "carcione2022_avo"
#: Depths of the table and of the R_PP-against-angle chart (m).
DEPTHS = (1000.0, 2000.0, 3000.0, 4000.0)
#: The models of the crossplot: Model 2 (self_consistent) left out, see the module docstring.
CROSSPLOT_MODELS = ("hs_gassmann", "generalized_gassmann", "patchy_cement")
#: Half-width (s) of the synthetic's window around the seal/reservoir reflection.
WINDOW = 0.3


def class_names(ds):
    """Code -> name of ``avo_class`` (its CF flags; 0, no class, as "none")."""
    attrs = ds["avo_class"].attrs
    names = dict(zip((int(v) for v in attrs["flag_values"]), attrs["flag_meanings"].split()))
    return {0: "none", **names}


def table(ds, depths=DEPTHS):
    """A, B, C and the class of the (one) interface at ``depths``, one row per depth, model
    and fluid."""
    import pandas as pd

    names = class_names(ds)
    sub = ds.isel(interface=0).sel(depth=list(depths))
    rows = []
    for z in sub.depth.values:
        for model in sub.model.values:
            for fluid in sub.fluid.values:
                at = sub.sel(depth=z, model=model, fluid=fluid)
                rows.append({"depth_m": float(z), "model": str(model), "fluid": str(fluid),
                             "intercept_A": float(at.avo_intercept),
                             "gradient_B": float(at.avo_gradient),
                             "curvature_C": float(at.avo_curvature),
                             "avo_class": names[int(at.avo_class)]})
    return pd.DataFrame(rows)


def class_changes(ds):
    """Where each model and fluid changes class along depth: one row per run of one class,
    ``model, fluid, from_m, to_m, avo_class`` (the depth samples of the run's ends)."""
    import numpy as np
    import pandas as pd

    names = class_names(ds)
    depth = ds.depth.values
    rows = []
    for model in ds.model.values:
        for fluid in ds.fluid.values:
            code = ds.avo_class.isel(interface=0).sel(model=model, fluid=fluid).values
            starts = np.concatenate([[0], np.flatnonzero(code[1:] != code[:-1]) + 1])
            ends = np.concatenate([starts[1:] - 1, [code.size - 1]])
            rows += [{"model": str(model), "fluid": str(fluid), "from_m": float(depth[a]),
                      "to_m": float(depth[b]), "avo_class": names[int(code[a])]}
                     for a, b in zip(starts, ends)]
    return pd.DataFrame(rows)


def synthetic_window(ds):
    """The synthetic around the seal/reservoir reflection: ``WINDOW`` s either side of the
    earliest and latest two-way time of the top of the reservoir among the models and fluids."""
    import numpy as np

    layer = ds.column_layer.values
    top = float(ds.depth.values[np.flatnonzero(layer != layer[0])[0]])
    times = ds.twt_of_depth.sel(depth=top).values
    return ds.sel(twt=slice(np.nanmin(times) - WINDOW, np.nanmax(times) + WINDOW))


def save(fig, path, prov):
    """``fig`` as PNG with the commit in a footer and in the PNG metadata (this script named
    as the software); closed."""
    import matplotlib.pyplot as plt

    fig.text(0.995, 0.0, example._stamp(prov), ha="right", va="top", fontsize=6,
             color="0.45")                          # below the axes' labels
    meta = {"Software": "benchmarks/avo_scene.py",
            "Comment": f"git_commit={prov['git_commit']}; git_tree={prov['git_tree']}"}
    try:
        _common._atomic(path, lambda tmp: fig.savefig(tmp, format="png", dpi=110,
                                                      bbox_inches="tight", metadata=meta))
    finally:
        plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--allow-dirty", action="store_true",
                        help="run with uncommitted source changes (recorded as a dirty tree)")
    args = parser.parse_args(argv)
    prov = example.provenance(args.allow_dirty)
    _common.announce_source()
    _common.use_agg()
    from rockcem import plots
    from rockcem.scene import load_scene, run_scene

    t0 = time.perf_counter()
    ds = run_scene(load_scene(SCENE))
    seconds = time.perf_counter() - t0
    attrs = {**_common.environment_attrs(scene=SCENE), **prov, "run_seconds": round(seconds, 1),
             "class_threshold": float(ds.avo_class.attrs["threshold"]),
             # one comment line: the scene's warnings joined by " | "
             "validity_warnings": " | ".join(ds.attrs.get("validity_warnings", "").splitlines())}
    values = table(ds)
    changes = class_changes(ds)
    _common.write_csv(values, _common.result_path(NAME, "csv"), attrs)
    _common.write_csv(changes, _common.result_path(f"{NAME}_changes", "csv"), attrs)
    docs = _common.ROOT / "docs"
    figures = {
        "class": plots.avo_class_depth(ds),
        "crossplot": plots.intercept_gradient_crossplot(ds.sel(model=list(CROSSPLOT_MODELS))),
        "angle": plots.reflectivity_angle(ds, list(DEPTHS)),
        "synthetic": plots.synthetic_section(synthetic_window(ds), scale="trace"),
    }
    for kind, fig in figures.items():
        save(fig, docs / f"{SCENE}_{kind}.png", prov)
    print(f"{SCENE}: {seconds:.1f} s ({example._stamp(prov)})")
    print(values.round(3).to_string(index=False))
    print(changes.to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
