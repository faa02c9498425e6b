"""The shipped sandstone example with the MD engine as a fifth model (issue 23, Show), made
reproducible by one command (issue 29, item 6).

``python benchmarks/md_scene_example.py [-j 2]`` runs the scene ``carcione2022_sandstone_md``
from the current code (fresh stage files in a temporary folder unless ``--workdir`` names one to
keep and resume from) and writes

- its Dataset, ``benchmarks/results/carcione2022_sandstone_md.nc``;
- a table per MD depth, ``benchmarks/results/md_scene_example.csv``: the effective stress, which
  the path never lowers, and the stress the pack reached; cement fraction, S_c, burial's and the
  MD porosity; vp and vs of every MD member with their resolution and total errors and whether
  the member is trusted there (:func:`rockcem.variables.md_error_trusted`); Model 4's vp and vs;
  member wall time;
- the figures ``docs/carcione2022_sandstone_md.png`` (depth trends of the five models) and
  ``docs/carcione2022_sandstone_md_template.png`` (the rock-physics template with the MD points).

``--reduced`` runs a small version instead (the same scene on a 3 x 3 x 6 pack at three depths,
Omega 3 with the checks below it, two packs for the sample-size error; about 20 s on one core)
and writes only its table, ``benchmarks/results/md_scene_example_reduced.csv``, one row per
value with its stated error: the file ``tests/test_md_example_repro.py`` compares a fresh run
with.

Every output records the git commit of the checkout (netCDF and CSV attributes ``git_commit``
and ``git_tree``, PNG metadata and a footer). The script refuses to run when tracked files under
``md/``, ``rockcem/``, ``burial/`` or ``datasets/`` have uncommitted changes, since its outputs
would then name a commit that did not make them; ``--allow-dirty`` runs anyway and records
``git_tree = "dirty: <files>"`` (and says so on the terminal and in the figures).
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

NAME = "md_scene_example"
SCENE = "carcione2022_sandstone_md"
#: Source folders whose uncommitted changes would make the outputs disagree with the commit.
SOURCES = ("md", "rockcem", "burial", "datasets")
#: The reduced example: the shipped scene made small (keys of the scene, see ``rockcem schema``).
REDUCED = {
    "models.md.depths": [1000.0, 2500.0, 4000.0],
    "models.md.size": [3.0, 3.0, 6.0],
    "models.md.resolution": 3.0,
    "models.md.samples": 2,
    "path.depth_step": 100.0,
}
#: Relative tolerance of a reduced-example value whose stated error is 0 or not given
#: (deterministic quantities: burial's, the MD sample's porosity and density, Model 4).
TIGHT_RTOL = 1e-6


# ----------------------------------------------------------------------------- provenance
def git_state(root=_common.ROOT):
    """``(commit, changed)``: the HEAD commit of the checkout and the tracked files under
    :data:`SOURCES` that differ from it (uncommitted changes, staged or not)."""
    def git(*cmd):
        try:
            return subprocess.run(["git", "-C", str(root), *cmd], capture_output=True,
                                  text=True, timeout=30, check=True).stdout
        except (OSError, subprocess.SubprocessError):
            return None

    commit = (git("rev-parse", "HEAD") or "").strip() or "unknown (not a git checkout)"
    status = git("status", "--porcelain", "--untracked-files=no", "--", *SOURCES)
    changed = [line[3:] for line in (status or "").splitlines() if line.strip()]
    if status is None:
        changed = ["(git status failed)"]
    return commit, changed


def provenance(allow_dirty: bool) -> dict:
    """The git commit and tree state every output records; exits (code 2) on a dirty tree
    unless ``allow_dirty``."""
    commit, changed = git_state()
    if changed and not allow_dirty:
        print(f"{Path(__file__).name}: refusing to run: uncommitted changes to tracked files "
              f"under {', '.join(SOURCES)}:\n  " + "\n  ".join(changed)
              + "\nCommit them (the outputs name the commit that made them) or pass "
              "--allow-dirty to record the tree as dirty.", file=sys.stderr)
        sys.exit(2)
    tree = "clean" if not changed else "dirty: " + " ".join(changed)
    if changed:
        print("=" * 78 + f"\nWARNING: DIRTY TREE. The outputs are recorded as made from commit "
              f"{commit[:10]} PLUS uncommitted changes to:\n  " + "\n  ".join(changed)
              + "\n" + "=" * 78, flush=True)
    return {"git_commit": commit, "git_tree": tree}


def _stamp(prov) -> str:
    dirty = "" if prov["git_tree"] == "clean" else " + UNCOMMITTED CHANGES (dirty tree)"
    return f"rockcem commit {prov['git_commit'][:10]}{dirty}"


def save_figure(fig, path, prov):
    """Save ``fig`` as PNG with the commit in a footer and in the PNG metadata; close it."""
    import matplotlib.pyplot as plt

    fig.text(0.995, 0.002, _stamp(prov), ha="right", va="bottom", fontsize=6, color="0.45")
    meta = {"Software": f"benchmarks/{Path(__file__).name}",
            "Comment": f"git_commit={prov['git_commit']}; git_tree={prov['git_tree']}"}
    try:
        return _common._atomic(path, lambda tmp: fig.savefig(
            tmp, format="png", dpi=120, bbox_inches="tight", metadata=meta))
    finally:
        plt.close(fig)


# ----------------------------------------------------------------------------- tables
def _members(ds):
    return [str(m) for m in ds.model.values if str(m).startswith("md")]


def per_depth_table(ds):
    """The MD depths of a scene Dataset as a table (one row per depth)."""
    import numpy as np
    import pandas as pd

    from rockcem.variables import md_error_trusted

    ran = np.isfinite(ds.md_porosity.values)
    sub = ds.isel(depth=np.flatnonzero(ran))
    table = pd.DataFrame({
        "depth_m": sub.depth.values,
        "p_e_MPa": sub.pressure_effective.values,
        "md_stress_MPa": sub.md_stress.values,
        "cement_fraction": sub.cement_fraction.values,
        "S_c": sub.md_cement_saturation.values,
        "porosity_burial": sub.porosity.values,
        "porosity_md_pack": sub.md_pack_porosity.values,
        "porosity_md": sub.md_porosity.values})
    for m in _members(ds):
        for v in ("vp", "vs"):
            error, trusted = md_error_trusted(sub, v, model=m)
            table[f"{v}_{m}"] = sub[v].sel(model=m).values
            table[f"{v}_error_resolution_{m}"] = sub[f"{v}_error_resolution"].sel(model=m).values
            table[f"{v}_error_{m}"] = error.values
        table[f"trusted_{m}"] = trusted.values
        for name in ("thomsen_epsilon", "thomsen_gamma", "thomsen_delta"):
            if name in sub:
                table[f"{name.split('_')[1]}_{m}"] = sub[name].sel(model=m).values
        table[f"wall_time_s_{m}"] = sub.md_wall_time.sel(model=m).values
    for v in ("vp", "vs"):
        table[f"{v}_patchy_cement"] = sub[v].sel(model="patchy_cement").values
    return table


def value_table(ds):
    """The reduced example's values, one row each: ``quantity, model, depth_m, value, error``
    (``error`` the stated total error of an MD velocity, NaN where the Dataset says it was not
    measured, 0 for a quantity that carries none), and ``trusted`` (the member's flag, for MD
    velocities; not compared)."""
    import numpy as np
    import pandas as pd

    from rockcem.variables import md_error_trusted

    depths = ds.depth.values[np.isfinite(ds.md_porosity.values)]
    sub = ds.sel(depth=depths)
    rows = []

    def add(quantity, model, values, errors=None, trusted=None):
        for k, z in enumerate(depths):
            rows.append({"quantity": quantity, "model": model, "depth_m": float(z),
                         "value": float(values[k]),
                         "error": 0.0 if errors is None else float(errors[k]),
                         "trusted": "" if trusted is None else
                         {1.0: "yes", 0.0: "no"}.get(float(trusted[k]), "")})

    for name in ("porosity", "cement_fraction", "md_porosity", "md_pack_porosity"):
        add(name, "", sub[name].values)
    for m in _members(ds):
        add("md_density", m, sub.md_density.sel(model=m).values)
        for v in ("vp", "vs"):
            error, trusted = md_error_trusted(sub, v, model=m)
            add(v, m, sub[v].sel(model=m).values, error.values, trusted.values)
    for v in ("vp", "vs"):
        add(v, "patchy_cement", sub[v].sel(model="patchy_cement").values)
    return pd.DataFrame(rows)


# ----------------------------------------------------------------------------- main
def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-j", "--jobs", type=int, default=1)
    parser.add_argument("--reduced", action="store_true",
                        help="the small example and its table only (tests/test_md_example_repro)")
    parser.add_argument("--allow-dirty", action="store_true",
                        help="run with uncommitted source changes (recorded as a dirty tree)")
    parser.add_argument("--workdir", default=None,
                        help="folder of the MD stage files, kept (a rerun resumes from them; "
                        "recorded); default a fresh temporary folder")
    parser.add_argument("--output", default=None,
                        help="the table's path (default benchmarks/results/<name>.csv)")
    args = parser.parse_args(argv)
    prov = provenance(args.allow_dirty)
    _common.announce_source()
    _common.use_agg()
    from rockcem.scene import load_scene, run_scene, write_dataset

    with tempfile.TemporaryDirectory(prefix=f"{NAME}_") as tmp:
        work = Path(args.workdir) if args.workdir else Path(tmp)
        scene = load_scene(SCENE).replace(**{"models.md.workdir": str(work)})
        if args.reduced:
            scene = scene.replace(**REDUCED)
        t0 = time.perf_counter()
        ds = run_scene(scene, jobs=args.jobs, progress=not args.reduced)
        seconds = time.perf_counter() - t0
    attrs = {**_common.environment_attrs(scene=SCENE, jobs=args.jobs), **prov,
             "stage_files": f"resumed from / kept in {work}" if args.workdir else "fresh",
             "run_seconds": round(seconds, 1)}
    if args.reduced:
        attrs["reduced"] = "; ".join(f"{k} = {v}" for k, v in REDUCED.items())
        attrs["tight_rtol"] = TIGHT_RTOL
        table = value_table(ds)
        out = args.output or _common.result_path(f"{NAME}_reduced", "csv")
        _common.write_csv(table, out, attrs)
        print(f"{SCENE} (reduced): {seconds:.1f} s; wrote {out} ({_stamp(prov)})")
        print(table.to_string(index=False))
        return 0
    ds.attrs.update(prov)
    write_dataset(ds, _common.result_path(SCENE, "nc"))
    table = per_depth_table(ds)
    _common.write_csv(table, args.output or _common.result_path(NAME, "csv"), attrs)
    from rockcem.plots import depth_trends, rock_physics_template

    docs = _common.ROOT / "docs"
    save_figure(depth_trends(ds), docs / f"{SCENE}.png", prov)
    save_figure(rock_physics_template(ds), docs / f"{SCENE}_template.png", prov)
    print(f"{SCENE}: {seconds:.1f} s on {args.jobs} process(es) ({_stamp(prov)})")
    print(table.round(3).to_string(index=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())
