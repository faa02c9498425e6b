"""The probability of each AVO class along depth of the shipped uncertain stack (issue 32, item
5), made by one command.

``python benchmarks/avo_uncertain_scene.py`` runs the stack scene ``carcione2022_avo_uncertain``
(the shale of Carcione et al. 2022 over their sandstone on one linear path, brine and gas sands,
six uncertain inputs, 200 members) from the current code, about a minute on one core, and
writes

- ``benchmarks/results/avo_uncertain_scene.csv``: at 1, 2, 3 and 4 km, per model and fluid, the
  fraction of the members in each AVO class and the 0.1, 0.5 and 0.9 quantiles of the intercept
  A and gradient B (the scene's validity warnings and its run time in the ``#`` header);
- the figure of ``docs/user_guide/avo.md``, ``docs/carcione2022_avo_probability.png``
  (:func:`rockcem.plots.avo_class_probability`: every model, brine and gas).

Every output records the git commit of the checkout (CSV attributes ``git_commit`` and
``git_tree``, PNG metadata and a footer); the script refuses to run when tracked source files
have uncommitted changes (``--allow-dirty`` runs anyway and records the tree as dirty), as
``md_scene_example.py`` does.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import md_scene_example as example  # noqa: E402  (its provenance: the commit, a clean tree)

NAME = "avo_uncertain_scene"
SCENE = "carcione2022_avo_uncertain"
#: The figure of the docs page.
FIGURE = "carcione2022_avo_probability.png"
#: Depths of the table (m).
DEPTHS = (1000.0, 2000.0, 3000.0, 4000.0)


def table(ds, depths=DEPTHS):
    """The class fractions and the intercept's and gradient's quantiles of the (one)
    interface at ``depths``, one row per depth, model and fluid."""
    import pandas as pd

    import itertools

    sub = ds.isel(interface=0).sel(depth=list(depths))
    rows = []
    for z, model, fluid in itertools.product(sub.depth.values, sub.model.values,
                                             sub.fluid.values):
        at = sub.sel(depth=z, model=model, fluid=fluid)
        row = {"depth_m": float(z), "model": str(model), "fluid": str(fluid)}
        row.update({f"p_{str(c)}": float(v) for c, v in
                    zip(at.avo_class.values, at.avo_class_probability.values)})
        for name, short in (("avo_intercept", "A"), ("avo_gradient", "B")):
            row.update({f"{short}_q{q:g}": float(v) for q, v in
                        zip(at["quantile"].values, at[name].values)})
        rows.append(row)
    return pd.DataFrame(rows)


def save(fig, path, prov):
    """``fig`` as PNG, this script and the commit in its metadata and the commit in a footer."""
    import matplotlib.pyplot as plt

    stamp = example._stamp(prov)
    fig.text(0.995, 0.0, stamp, ha="right", va="top", fontsize=6, color="0.45")
    comment = f"git_commit={prov['git_commit']}; git_tree={prov['git_tree']}"

    def write(tmp):
        fig.savefig(tmp, format="png", dpi=100, bbox_inches="tight",
                    metadata={"Software": "benchmarks/avo_uncertain_scene.py", "Comment": comment})

    _common._atomic(path, write)
    plt.close(fig)


def run():
    """The shipped scene's Dataset, run from the current code, and its wall time (s)."""
    from rockcem.scene import load_scene, run_scene

    start = time.perf_counter()
    ds = run_scene(load_scene(SCENE))
    return ds, time.perf_counter() - start


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--allow-dirty", action="store_true",
                        help="run with uncommitted source changes, recorded as a dirty tree")
    prov = example.provenance(parser.parse_args(argv).allow_dirty)
    _common.announce_source()
    _common.use_agg()
    from rockcem import plots

    ds, seconds = run()
    values = table(ds)
    warnings = " | ".join(ds.attrs.get("validity_warnings", "").splitlines())
    _common.write_csv(values, _common.result_path(NAME, "csv"), {
        **_common.environment_attrs(scene=SCENE), **prov, "run_seconds": round(seconds, 1),
        "uncertain": ds.attrs["uncertain"], "validity_warnings": warnings})
    save(plots.avo_class_probability(ds), _common.ROOT / "docs" / FIGURE, prov)
    print(f"{SCENE}: {seconds:.1f} s ({example._stamp(prov)})")
    print(values.round(3).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
