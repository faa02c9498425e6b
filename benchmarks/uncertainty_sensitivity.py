"""Which input drives the spread: the Sobol' indices of the shipped uncertain sandstone at 2, 3
and 4 km, at increasing sample sizes, until the ranking holds.

The scene is ``carcione2022_sandstone_uncertain`` (five uncertain inputs: the gradient, the
grain size, the clay coating, the onset of quartz cementation and the overburden density; four
models) with ``[uncertain] sensitivity = true``: the Saltelli design of base N (N (d + 2) =
7 N members), first-order indices by Saltelli et al. (2010), Table 2 (b), total indices by
Jansen (1999), with their standard errors (``rockcem._uncertain.saltelli_indices``). Two keys
differ from the shipped scene, neither changing a value at 2, 3 or 4 km: ``path.max_depth =
4000`` (the deeper nodes are not needed; the sampled inputs are the same, since no input's
valid range is cut by either depth) and the outputs, those the indices are given for
(temperature, porosity, density, vp, vs). The depth step stays 10 m.

For each N of ``--samples`` (default 64, 256, 1024, 4096) the script writes one row per output,
model, depth and input: the first-order and total indices, their standard errors, the input's
rank by total index, and the run's wall time. The convergence check (printed, and in the
study's page): between the two largest N the ranking by total index of every output is the same
and every index moved by less than its combined standard error
(:math:`\\sqrt{se_1^2 + se_2^2}`), or the row says by how much it did not.

Every output records the git commit of the checkout; the script refuses to run when tracked
files under ``rockcem/``, ``burial/`` or ``datasets/`` have uncommitted changes (their results
would name a commit that did not make them), unless ``--allow-dirty``.

Output: ``benchmarks/results/uncertainty_sensitivity.csv``. Run:
``python benchmarks/uncertainty_sensitivity.py`` (about 2 minutes on one core).
"""

from _common import ROOT, announce_source, environment_attrs, result_path, write_csv

import argparse  # noqa: E402
import os  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from md_scene_example import git_state  # noqa: E402

SCENE = "carcione2022_sandstone_uncertain"
#: Depths of the ranking, m.
DEPTHS = (2000.0, 3000.0, 4000.0)
#: Source folders whose uncommitted changes would make the results disagree with the commit.
SOURCES = ("rockcem", "burial", "datasets")
OUTPUTS = ["temperature", "porosity", "density", "vp", "vs"]


def provenance(allow_dirty):
    """``{git_commit, git_tree}``; exits with code 2 on a dirty tree unless ``allow_dirty``."""
    commit, changed = git_state(ROOT)
    changed = [c for c in changed if c.startswith(tuple(s + "/" for s in SOURCES))]
    if changed and not allow_dirty:
        print(f"uncertainty_sensitivity.py: refusing to run: uncommitted changes under "
              f"{', '.join(SOURCES)}: {' '.join(changed)}; commit them or pass --allow-dirty",
              file=sys.stderr)
        sys.exit(2)
    return {"git_commit": commit, "git_tree": "clean" if not changed else
            "dirty: " + " ".join(changed)}


def indices(N, seed):
    """The Sobol' indices of the scene at base N: ``(rows, seconds)``."""
    from rockcem.scene import load_scene, run_scene

    scene = load_scene(SCENE).replace(**{
        "uncertain.sensitivity": True, "uncertain.design": "sobol", "uncertain.samples": N,
        "uncertain.seed": seed, "path.max_depth": 4000.0, "outputs": OUTPUTS})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        ds = run_scene(scene, max_members=10**7)
        seconds = time.perf_counter() - t
    ds = ds.sel(depth=list(DEPTHS))
    rows = []
    for name in OUTPUTS:
        first = ds[f"{name}_sobol_first"]
        models = list(ds["model"].values) if "model" in first.dims else [""]
        for model in models:
            pick = (lambda v: v.sel(model=model) if model else v)
            f, t_, fse, tse = (pick(ds[f"{name}_sobol_{k}"]) for k in
                               ("first", "total", "first_se", "total_se"))
            for depth in DEPTHS:
                total = t_.sel(depth=depth).values
                order = np.argsort(-total, kind="stable")
                rank = np.empty(len(order), dtype=int)
                rank[order] = np.arange(1, len(order) + 1)
                for j, key in enumerate(ds["input"].values):
                    rows.append(dict(
                        samples=N, members=N * (len(ds["input"]) + 2), output=name,
                        model=model, depth=depth, input=str(key),
                        first=float(f.sel(depth=depth).values[j]),
                        first_se=float(fse.sel(depth=depth).values[j]),
                        total=float(total[j]), total_se=float(tse.sel(depth=depth).values[j]),
                        rank=int(rank[j]), seconds=seconds))
    return rows, seconds


def convergence(table):
    """Per output, model and depth between the two largest N: whether the ranking by total
    index is the same, and the largest index change over its combined standard error."""
    big, small = sorted(table["samples"].unique())[-2:][::-1]
    keys = ["output", "model", "depth", "input"]
    a = table[table["samples"] == big].set_index(keys)
    b = table[table["samples"] == small].set_index(keys)
    out = []
    for (output, model, depth), part in a.groupby(level=[0, 1, 2]):
        other = b.loc[part.index]
        z = [np.abs(part[k] - other[k]) / np.hypot(part[f"{k}_se"], other[f"{k}_se"])
             for k in ("first", "total")]
        out.append(dict(output=output, model=model, depth=depth,
                        ranking_same=bool(np.all(part["rank"].values == other["rank"].values)),
                        max_change_over_se=float(np.nanmax(np.concatenate(z))),
                        ranking=" > ".join(part.sort_values("rank").index.get_level_values(
                            "input"))))
    return pd.DataFrame(out), big, small


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, nargs="+", default=[64, 256, 1024, 4096])
    parser.add_argument("--seed", type=int, default=2022)
    parser.add_argument("--allow-dirty", action="store_true")
    args = parser.parse_args(argv)
    prov = provenance(args.allow_dirty)
    import rockcem  # noqa: F401

    announce_source()
    rows = []
    for N in args.samples:
        part, seconds = indices(N, args.seed)
        rows += part
        print(f"N = {N}: {N * 7} members in {seconds:.1f} s (load {os.getloadavg()[0]:.1f})",
              flush=True)
    table = pd.DataFrame(rows)
    attrs = environment_attrs(
        benchmark="uncertainty_sensitivity", scene=SCENE, seed=args.seed,
        design="Saltelli (scipy.stats.sobol_indices), base N per row; first-order Saltelli "
               "et al. 2010 Table 2 (b), total Jansen 1999; standard errors of the N summands",
        changed_keys="path.max_depth = 4000, outputs = temperature porosity density vp vs",
        load_1min=float(os.getloadavg()[0]), **prov)
    write_csv(table, result_path("uncertainty_sensitivity", "csv"), attrs)
    check, big, small = convergence(table)
    print(f"convergence between N = {small} and N = {big}:")
    print(check.to_string(index=False))


if __name__ == "__main__":
    main()
