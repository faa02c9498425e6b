"""The MD scene's velocities against run time: each numerical knob of the shipped MD example.

What is measured is the MD member of the shipped example ``carcione2022_sandstone_md`` as
``rockcem run`` makes it: :func:`rockcem.scene.run_scene` on that scene (burial, the MD pack
compacted down the path and reconstructed to burial's intergranular volume, the coating grown
with burial and laid as a film while thin, the five constants of the transversely isotropic
sample, voxel finite elements where burial fills the pores, anisotropic Gassmann with water),
with the scene's defaults except what a study changes, at three representative depths
(``DEPTHS``): 2000 m (a thin film of coating), 3500 m (past a quarter of the pores: whole cells
of the lattice, the first such depth of the example, so its cement is grown from nothing as in
the example) and 5000 m (burial's pores full: voxel finite elements). Every run has one pack
(``samples = 1``). The quantities are the saturated vertical velocities ``vp``, ``vs`` (km/s:
what the scene reports) and the dry constants C11, C13, C33, C44, C66 (GPa) of
:func:`md.along_depth.carry_down`, read by wrapping the backend's
``rockcem._md_backend._carry_down_task`` (the wrapper returns its Dataset unchanged).

Studies (each knob alone, the others at the scene's defaults):

omega
    The lattice resolution Omega, one resolution per run (``resolution_check = 0``), on the
    scene's pack (size 4 x 4 x 12, seed 0). The voxel members run at
    :data:`md.along_depth.VOXEL_RESOLUTION_FACTOR` of it (the voxel Omega is a column). The
    pack's stage files are reused across Omega (the differences are the lattice's alone).
    Reference: the finest Omega (the error is a lower bound where the sequence has not
    converged: see its changes).
default
    The scene's own resolutions (Omega 6 with checks at 4 and 2.67): its stated resolution
    errors of vp and vs (the grid convergence index, :mod:`md.convergence`) against the
    observed difference of the Omega 6 value from the finest Omega of the omega study; and its
    cost. The Omega 6 values must equal the omega study's single-resolution run (checked).
rtol
    The static solvers' relative tolerance, scaled from the defaults (lattice
    :func:`md.static.static_stiffness` 1e-10, voxel :func:`md.voxel.sample_stiffness` 1e-8)
    by ``RTOL_SCALES``; passed by wrapping those two functions in their modules (they are
    looked up there at each call). Reference: the smallest scale.
strain_step
    The compaction increment of :func:`md.along_depth.carry_down` (default 5e-4, not a scene
    key: passed through the wrapper of ``_carry_down_task``); each value its own fresh pack
    (settled again: the settling is the same, the chain of compactions is not). Reference:
    the smallest step.
size
    Pack size (``models.md.size``) with ``--seeds`` settling seeds each (``models.md.seed``),
    each pack in its own fresh work folder, at the scene's Omega without checks. The
    sample-size error of one run is the seed standard deviation; the reference is the largest
    size's seed mean; the error of one run is ``sqrt(bias^2 + std^2)``.

Wall times (one process, numba compiled by a warm-up run first): ``seconds_members`` (the
members' own ``wall_time``, summed over the depths), ``seconds_pack`` (settling, compaction
and reconstruction of the run's pack: measured in the run that made its stage files, as
carry_down's time less its members), ``seconds_total`` = their sum, the cost of one
configuration, and ``seconds_scene`` (the whole ``run_scene`` call of the run, stage files
reused where they exist). The load average is recorded per run.

Output: ``results/md_scene_error_vs_time[_<tag>].{csv,nc,png}`` (one row per run and depth)
and ``results/md_scene_error_vs_time_summary[_<tag>].csv`` (per study, knob and depth: values,
errors against the reference, seed spread, times; the ``default`` rows hold the error-bar
check). Every output records the git commit (``git_commit``, ``git_tree``); the script
refuses to run with uncommitted changes under md/, rockcem/, burial/ or datasets/ unless
``--allow-dirty`` (then the tree is recorded and stamped as dirty), as
``benchmarks/md_scene_example.py`` does.

Run: ``python benchmarks/md_scene_error_vs_time.py [--quick]``. ``--quick`` (about 2 min):
a 3 x 3 x 8 pack, Omega 2, 2.67 and 4 with the error-bar check at 4/2.67/2, two tolerances,
two strain steps and two seeds; it exercises every study, for testing the script, not for
its numbers (written with the tag ``quick``). The per-run CSV is rewritten after every run
(``partial = 1`` in its metadata until the end), so an interrupted run can be summarised with
``--replot``. ``--replot`` redoes the summary and figure from the
per-run CSV.
"""

from __future__ import annotations

import _common  # noqa: I001  (first: pins threads before numpy is imported)

import argparse  # noqa: E402
import contextlib  # noqa: E402
import functools  # noqa: E402
import os  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402

NAME = "md_scene_error_vs_time"
SCENE = "carcione2022_sandstone_md"
#: Film of coating, whole cells of coating (the example's first), pores full (voxels), m.
DEPTHS = (2000.0, 3500.0, 5000.0)
#: The saturated vertical velocities (km/s) and the dry constants (GPa) compared.
VELOCITIES = ("vp", "vs")
CONSTANTS = ("c11", "c13", "c33", "c44", "c66")
QUANTITIES = VELOCITIES + CONSTANTS
#: carry_down's names of the constants (C33, C44 are its P and shear moduli).
_CD_NAMES = {"c11": "c11", "c13": "c13", "c33": "p_modulus", "c44": "shear_modulus",
             "c66": "c66"}
#: Default relative tolerances of the static solves (md.static.static_stiffness,
#: md.voxel.voxel_stiffness), scaled together by the rtol study.
RTOL_DEFAULT = {"lattice": 1e-10, "voxel": 1e-8}
UNITS = {"depth": "m", "vp": "km s-1", "vs": "km s-1", "vp_error_resolution": "km s-1",
         "vs_error_resolution": "km s-1", "c11": "GPa", "c13": "GPa", "c33": "GPa",
         "c44": "GPa", "c66": "GPa", "omega": "1", "omega_voxel": "1", "porosity_md": "1",
         "saturation": "1", "seconds_member": "s", "seconds_members": "s",
         "seconds_pack": "s", "seconds_total": "s", "seconds_scene": "s", "load_average": "1"}
#: Lowest relative error the figure shows.
FLOOR = 1e-9
STUDIES = ("omega", "default", "rtol", "strain_step", "size")
MARKERS = {"omega": "o-", "rtol": "^-", "strain_step": "D-", "size": "s--"}


# ----------------------------------------------------------------------------- the runs
class _Capture:
    """Wraps ``rockcem._md_backend._carry_down_task``: records each carry_down Dataset and its
    wall time, and adds ``extra`` keyword arguments (a knob carry_down takes that the scene
    does not)."""

    def __init__(self):
        import rockcem._md_backend as backend

        self.backend, self.original = backend, backend._carry_down_task
        self.extra, self.calls = {}, []

    def __call__(self, max_stress, cement_fraction, options):
        t0 = time.perf_counter()
        ds = self.original(max_stress, cement_fraction, {**options, **self.extra})
        self.calls.append((time.perf_counter() - t0, ds))
        return ds

    def __enter__(self):
        self.backend._carry_down_task = self
        return self

    def __exit__(self, *exc):
        self.backend._carry_down_task = self.original


@contextlib.contextmanager
def solver_rtol(scale):
    """The static solves of the MD members at ``scale`` times their default tolerances
    (:data:`RTOL_DEFAULT`): ``md.static.static_stiffness`` and ``md.voxel.sample_stiffness``
    wrapped in their modules, where ``md.along_depth`` looks them up at each call."""
    import md.static
    import md.voxel

    saved = md.static.static_stiffness, md.voxel.sample_stiffness
    if scale != 1.0:
        md.static.static_stiffness = functools.partial(
            saved[0], rtol=RTOL_DEFAULT["lattice"] * scale)
        md.voxel.sample_stiffness = functools.partial(
            saved[1], rtol=RTOL_DEFAULT["voxel"] * scale)
    try:
        yield
    finally:
        md.static.static_stiffness, md.voxel.sample_stiffness = saved


def _size_label(size):
    return "x".join(f"{s:g}" for s in size)


class Runs:
    """Scene runs at :data:`DEPTHS`, one fresh work folder per pack (size, seed, strain step),
    reused by the runs on that pack; a run already made is returned again."""

    def __init__(self, depths, root):
        from rockcem.scene import SCHEMA

        self.depths, self.root = [float(z) for z in depths], root
        self.defaults = {k: v[0] for k, v in SCHEMA["models.md"].items()}
        self.folders, self.pack_seconds, self.done = {}, {}, {}

    def __call__(self, *, size, seed=0, omegas=(6.0,), rtol_scale=1.0, strain_step=5e-4):
        from rockcem.scene import load_scene, run_scene

        omegas = tuple(float(w) for w in omegas) + (0.0,) * (3 - len(omegas))
        key = (tuple(size), int(seed), omegas, float(rtol_scale), float(strain_step))
        if key in self.done:
            return self.done[key]
        pack_key = (tuple(size), int(seed), float(strain_step))
        if pack_key not in self.folders:
            self.folders[pack_key] = tempfile.mkdtemp(
                prefix=f"{_size_label(size)}_s{seed}_e{strain_step:g}_", dir=self.root)
        scene = load_scene(SCENE).replace(**{
            "models.md.depths": self.depths, "models.md.samples": 1,
            "models.md.size": [float(s) for s in size], "models.md.seed": int(seed),
            "models.md.resolution": omegas[0], "models.md.resolution_check": omegas[1],
            "models.md.resolution_check2": omegas[2],
            "models.md.workdir": self.folders[pack_key]})
        if rtol_scale != 1.0:       # the members' stage files do not know the tolerance
            self._clear_members(pack_key)
        load0 = os.getloadavg()[0]
        with _Capture() as capture, solver_rtol(rtol_scale), \
                warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            capture.extra = {} if strain_step == 5e-4 else {"strain_step": float(strain_step)}
            t0 = time.perf_counter()
            ds = run_scene(scene)
            seconds_scene = time.perf_counter() - t0
        (seconds_cd, cd), = capture.calls
        if rtol_scale != 1.0:       # nor may a later run take them for the default's
            self._clear_members(pack_key)
        members = float(cd.wall_time.sum())
        if pack_key not in self.pack_seconds:       # its stage files were made in this call
            self.pack_seconds[pack_key] = seconds_cd - members
        load = 0.5 * (load0 + os.getloadavg()[0])
        at = ds.sel(model="md").sel(depth=self.depths, method="nearest")
        cd = cd.isel(scheme=0)
        rows = []
        for i, depth in enumerate(self.depths):
            full = float(at.md_porosity[i]) <= 0
            voxel = self._voxel_factor(omegas) * omegas[0] if full else np.nan
            row = dict(size=_size_label(size), seed=int(seed), omega=omegas[0],
                       omega_check=omegas[1], omega_check2=omegas[2], omega_voxel=voxel,
                       rtol_scale=float(rtol_scale), strain_step=float(strain_step),
                       n_grains=int(cd.attrs["n_grains"]), depth=depth,
                       regime="voxel" if full else self._regime(float(at.md_cement_saturation[i])),
                       stress_MPa=float(at.pressure_effective[i]),
                       cement_fraction=float(at.cement_fraction[i]),
                       porosity_md=float(at.md_porosity[i]),
                       saturation=float(at.md_cement_saturation[i]),
                       vp=float(at.vp[i]), vs=float(at.vs[i]),
                       vp_error_resolution=float(at.vp_error_resolution[i]),
                       vs_error_resolution=float(at.vs_error_resolution[i]),
                       asymptotic=float(at.md_resolution_asymptotic[i]),
                       seconds_member=float(cd.wall_time[i]), seconds_members=members,
                       seconds_pack=self.pack_seconds[pack_key],
                       seconds_total=self.pack_seconds[pack_key] + members,
                       seconds_scene=seconds_scene, load_average=load,
                       warnings=len(caught))
            for q in CONSTANTS:
                row[q] = float(cd[_CD_NAMES[q]][i]) / 1e9
            rows.append(row)
        self.done[key] = rows
        print(f"  {_size_label(size):>7s} seed {seed} Omega {'/'.join(f'{w:g}' for w in omegas if w)}"
              f" rtol x{rtol_scale:g} step {strain_step:g}: pack "
              f"{self.pack_seconds[pack_key]:6.1f} s, members "
              + " ".join(f"{r['seconds_member']:.1f}" for r in rows)
              + f" s (load {load:.1f}); vp " + " ".join(f"{r['vp']:.4f}" for r in rows)
              + ", vs " + " ".join(f"{r['vs']:.4f}" for r in rows) + " km/s", flush=True)
        return rows

    def _clear_members(self, pack_key):
        """Remove the member stage files of a pack's folder (carry_down's ``members/``)."""
        from pathlib import Path

        for path in Path(self.folders[pack_key]).glob("*/members/*.nc"):
            path.unlink()

    @staticmethod
    def _voxel_factor(omegas):
        """carry_down's voxel factor for these resolutions (its rule, from its constant)."""
        from md.along_depth import VOXEL_RESOLUTION_FACTOR

        low = min(w for w in omegas if w)
        return VOXEL_RESOLUTION_FACTOR if low * VOXEL_RESOLUTION_FACTOR >= 1 else 1.0

    @staticmethod
    def _regime(saturation):
        from md.growth import FILM_MAX_SATURATION

        return "film" if saturation <= FILM_MAX_SATURATION else "cells"


# ----------------------------------------------------------------------------- summaries
def _knob(study, row):
    return {"omega": f"{row['omega']:g}", "rtol": f"x{row['rtol_scale']:g}",
            "strain_step": f"{row['strain_step']:g}", "size": row["size"],
            "default": "/".join(f"{w:g}" for w in (row["omega"], row["omega_check"],
                                                    row["omega_check2"]) if w)}[study]


def sequence_summary(df, study, order_by, descending=False):
    """Per depth: each knob value's quantities, their change from the previous value (in
    the order of ``order_by``, coarse to fine: ascending, or ``descending``) and their
    relative error against the finest (the last)."""
    import pandas as pd

    out = []
    for depth, g in df[df.study == study].groupby("depth", sort=True):
        g = g.sort_values(order_by, ascending=not descending)
        ref = g.iloc[-1]
        prev = None
        for _, row in g.iterrows():
            rec = {k: row[k] for k in ("depth", "regime", "saturation", "omega", "omega_voxel",
                                       "size", "seconds_member", "seconds_members",
                                       "seconds_pack", "seconds_total")}
            rec.update(study=study, knob=_knob(study, row), seeds=1,
                       reference=_knob(study, ref))
            for q in QUANTITIES:
                rec[q] = row[q]
                rec[f"{q}_change"] = row[q] / prev[q] - 1 if prev is not None else np.nan
                rec[f"{q}_error"] = abs(row[q] / ref[q] - 1)
                rec[f"{q}_spread"] = np.nan
            prev = row
            out.append(rec)
    return pd.DataFrame(out)


def size_summary(df):
    """Per size and depth: seed mean and standard deviation (ddof 1); reference the largest
    size's seed mean; the error of one run sqrt(bias^2 + std^2)."""
    import pandas as pd

    sub = df[df.study == "size"]
    if sub.empty:
        return pd.DataFrame()
    sizes = sorted(sub["size"].unique(), key=lambda s: np.prod([float(x) for x in s.split("x")]))
    out = []
    for depth, g in sub.groupby("depth", sort=True):
        ref = g[g["size"] == sizes[-1]]
        for size in sizes:
            h = g[g["size"] == size]
            rec = {k: h[k].mean() for k in ("saturation", "omega", "omega_voxel",
                                            "seconds_member", "seconds_members",
                                            "seconds_pack", "seconds_total")}
            rec.update(study="size", knob=size, depth=depth, regime=h.regime.values[0],
                       size=size, seeds=len(h), reference=f"mean of {sizes[-1]}")
            for q in QUANTITIES:
                mean = h[q].mean()
                spread = h[q].std(ddof=1) / abs(mean) if len(h) > 1 else np.nan
                bias = abs(mean / ref[q].mean() - 1)
                rec[q], rec[f"{q}_change"] = mean, np.nan
                rec[f"{q}_spread"] = spread
                rec[f"{q}_error"] = float(np.hypot(bias, spread)) if np.isfinite(spread) \
                    else bias
            out.append(rec)
    return pd.DataFrame(out)


def error_bar_check(df):
    """The scene's stated resolution error of vp and vs at its own resolutions (the ``default``
    run) against the observed difference of its finest-resolution value from the omega
    study's finest Omega, per depth: whether the bar bounds it. Also checks that the default
    run's values equal the omega study's run at the same Omega (the checks must not change
    them)."""
    import pandas as pd

    out = []
    omega = df[df.study == "omega"]
    for _, row in df[df.study == "default"].iterrows():
        g = omega[omega.depth == row.depth].sort_values("omega")
        if g.empty:
            continue
        ref, same = g.iloc[-1], g[g.omega == row.omega]
        rec = {k: row[k] for k in ("depth", "regime", "saturation", "omega", "omega_voxel",
                                   "seconds_member", "seconds_members", "seconds_pack",
                                   "seconds_total")}
        rec.update(study="default", knob=_knob("default", row), seeds=1,
                   reference=f"Omega {ref.omega:g}", size=row["size"],
                   asymptotic=row.asymptotic,
                   equals_single_run=float(np.allclose(
                       same[list(QUANTITIES)].to_numpy(float),
                       row[list(QUANTITIES)].to_numpy(float)[None, :], rtol=1e-12, atol=0))
                   if not same.empty else np.nan)
        for q in QUANTITIES:
            rec[q] = row[q]
            rec[f"{q}_error"] = abs(row[q] / ref[q] - 1)
            rec[f"{q}_change"] = rec[f"{q}_spread"] = np.nan
        for v in VELOCITIES:
            observed = abs(row[v] - ref[v])
            rec[f"{v}_error_resolution"] = row[f"{v}_error_resolution"]
            rec[f"{v}_observed"] = observed
            rec[f"{v}_bar_over_observed"] = row[f"{v}_error_resolution"] / observed \
                if observed > 0 else np.inf
            rec[f"{v}_bounds"] = float(row[f"{v}_error_resolution"] >= observed)
        out.append(rec)
    return pd.DataFrame(out)


def stage_reuse(df):
    """Runs of the rtol study whose members were read back from the default run's stage files
    instead of solved at their tolerance (the stage files do not record it): a member's wall
    time equal to the bit to the default's at the same depth can only have been read back.
    Returns their ``(rtol_scale, depth)`` pairs (empty when every member was solved)."""
    rtol = df[df.study == "rtol"]
    default = rtol[rtol.rtol_scale == 1.0].set_index("depth").seconds_member
    other = rtol[rtol.rtol_scale != 1.0]
    same = other.seconds_member.to_numpy() == default.reindex(other.depth).to_numpy()
    return list(zip(other.rtol_scale[same], other.depth[same]))


def summarize(df):
    import pandas as pd

    reused = stage_reuse(df)
    if reused:
        raise RuntimeError(f"rtol study: members read back from stage files, not solved at "
                           f"their tolerance (scale, depth): {reused}")

    parts = [sequence_summary(df, "omega", "omega"),
             sequence_summary(df, "rtol", "rtol_scale", descending=True),
             sequence_summary(df, "strain_step", "strain_step", descending=True),
             size_summary(df), error_bar_check(df)]
    return pd.concat([p for p in parts if not p.empty], ignore_index=True)


# ----------------------------------------------------------------------------- figure
def plot(summary, prov, tag):
    """Relative error of vp and vs against the wall time of one configuration, log-log, one
    panel each; colour = depth, marker = knob (labelled by its value); the third panel the
    scene's stated resolution error against the observed difference."""
    _common.use_agg()
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FixedLocator, FormatStrFormatter, NullFormatter
    from md_scene_example import save_figure

    depths = sorted(summary.depth.unique())
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.0), squeeze=False)
    names = {"omega": "Omega", "rtol": "solver rtol", "strain_step": "strain step",
             "size": "pack size"}
    for ax, var in zip(axes[0], VELOCITIES):
        for c, depth in enumerate(depths):
            color = f"C{c}"
            for study, style in MARKERS.items():
                g = summary[(summary.study == study) & (summary.depth == depth)]
                if g.empty:
                    continue
                err = g[f"{var}_error"].to_numpy(float)
                ok = err > 0
                if not ok.any():
                    continue
                ax.plot(g.seconds_total.to_numpy(float)[ok], err[ok], style, color=color,
                        ms=5, lw=1, label=f"{depth:g} m ({g.regime.values[0]}): {names[study]}")
                for x, y, knob in zip(g.seconds_total.to_numpy(float)[ok], err[ok],
                                      g.knob.values[ok]):
                    ax.annotate(knob, (x, y), textcoords="offset points", xytext=(3, 3),
                                fontsize=7, color=color)
                if study == "size":
                    ax.plot(g.seconds_total, g[f"{var}_spread"], "s", mfc="none", color=color,
                            ms=7, lw=0)
        ax.set(xlabel="wall time of one configuration, pack + members (s)",
               ylabel="relative error", title=f"{var} (saturated, vertical)", xscale="log",
               yscale="log", ylim=(FLOOR, 1.0))
        lo, hi = summary.seconds_total.min(), summary.seconds_total.max()
        ticks = [t for t in (5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)
                 if lo / 1.5 <= t <= hi * 1.5]
        ax.xaxis.set_major_locator(FixedLocator(ticks))
        ax.xaxis.set_major_formatter(FormatStrFormatter("%g"))
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax = axes[0, 2]
    check = summary[summary.study == "default"]
    for c, depth in enumerate(depths):
        g = check[check.depth == depth]
        for var, marker in (("vp", "o"), ("vs", "s")):
            if g.empty:
                continue
            ax.plot(g[f"{var}_observed"], g[f"{var}_error_resolution"], marker, color=f"C{c}",
                    ms=7, mfc="none" if var == "vs" else f"C{c}",
                    label=f"{depth:g} m {var}")
    finite = np.array([]) if check.empty else check[
        [f"{v}_{k}" for v in VELOCITIES for k in ("observed", "error_resolution")]].to_numpy(float)
    finite = finite[np.isfinite(finite) & (finite > 0)]
    if finite.size:
        span = np.array([finite.min() / 3, finite.max() * 3])
        ax.plot(span, span, "k-", lw=0.8, label="bar = difference")
        ax.set(xscale="log", yscale="log", xlim=span, ylim=span)
    ax.set(xlabel="observed |v(scene's Omega) - v(finest Omega)| (km/s)",
           ylabel="stated resolution error (km/s)",
           title="the scene's error bar against the observed difference\n"
                 "(above the line: the bar bounds it)")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    if not check.empty:
        ax.legend(fontsize=7)
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=4,
               bbox_to_anchor=(0.35, -0.2))
    fig.suptitle(f"{SCENE}'s MD member, error against wall time; each knob against its finest "
                 "value (Omega: a lower bound where not converged); open squares: seed spread "
                 f"of one pack;\nerrors below {FLOOR:g} (the solver tolerance's) lie under the "
                 "axis", fontsize=9, y=1.04)
    save_figure(fig, _common.result_path(NAME, "png", tag), prov)


# ----------------------------------------------------------------------------- output
def finish(df, attrs, tag):
    """Summary, CSV, netCDF and PNG from the per-run rows."""
    import xarray as xr

    summary = summarize(df)
    _common.write_csv(df, _common.result_path(NAME, "csv", tag), attrs)
    _common.write_csv(summary, _common.result_path(NAME + "_summary", "csv", tag), attrs)
    ds = xr.Dataset.from_dataframe(df.rename_axis("run"))
    summ = xr.Dataset.from_dataframe(summary.rename_axis("entry").add_prefix("summary_"))
    for data in (ds, summ):
        for var in data.data_vars:
            base = var.removeprefix("summary_")
            base = base.removesuffix("_observed")
            if base in UNITS:
                data[var].attrs["units"] = UNITS[base]
    _common.write_netcdf(xr.merge([ds, summ]).assign_attrs(attrs),
                         _common.result_path(NAME, "nc", tag))
    plot(summary, {"git_commit": attrs["git_commit"], "git_tree": attrs["git_tree"]}, tag)
    fmt = {"study": ("study", "s"), "knob": ("knob", "s"), "depth": ("depth m", "g"),
           "regime": ("regime", "s"), "vp": ("vp", ".4f"), "vp_error": ("vp err", ".2%"),
           "vs": ("vs", ".4f"), "vs_error": ("vs err", ".2%"), "c33": ("C33", ".3f"),
           "c33_error": ("err", ".2%"), "c44": ("C44", ".3f"), "c44_error": ("err", ".2%"),
           "seconds_member": ("member s", ".1f"), "seconds_total": ("total s", ".1f")}
    print(_common.markdown(summary, fmt))
    check = summary[summary.study == "default"]
    if not check.empty:
        print(_common.markdown(check, {
            "depth": ("depth m", "g"), "knob": ("Omega", "s"), "vp_error_resolution":
            ("vp bar", ".4f"), "vp_observed": ("vp diff", ".4f"), "vp_bounds": ("bounds", "g"),
            "vs_error_resolution": ("vs bar", ".4f"), "vs_observed": ("vs diff", ".4f"),
            "vs_bounds": ("bounds", "g"), "equals_single_run": ("= single run", "g")}))
    return summary


def read_attrs(path):
    """The ``# key: value`` metadata lines of a CSV written by :func:`_common.write_csv`."""
    attrs = {}
    with open(path) as fh:
        for line in fh:
            if not line.startswith("# "):
                break
            key, _, value = line[2:].rstrip("\n").partition(": ")
            attrs[key] = value
    return attrs


def _sizes(texts):
    out = []
    for text in texts:
        try:
            size = tuple(float(p) for p in text.lower().split("x"))
        except ValueError:
            size = ()
        if len(size) != 3:
            raise SystemExit(f"{NAME}: --sizes: a size is three numbers joined by x (4x4x12); "
                             f"got {text!r}")
        out.append(size)
    return out


def main(argv=None):
    import pandas as pd

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--depths", type=float, nargs="+", default=list(DEPTHS))
    ap.add_argument("--omega", type=float, nargs="+", default=[2.67, 4.0, 6.0, 8.0, 10.0])
    ap.add_argument("--rtol-scales", type=float, nargs="+", default=[1e4, 1e2, 1.0, 1e-2])
    ap.add_argument("--strain-steps", type=float, nargs="+", default=[5e-4, 2.5e-4])
    ap.add_argument("--sizes", nargs="+", default=["3x3x8", "4x4x12", "5x5x16"])
    ap.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    ap.add_argument("--seeds-largest", type=int, default=2,
                    help="the largest size runs only the first N of --seeds (time budget)")
    ap.add_argument("--studies", nargs="+", choices=STUDIES, default=list(STUDIES))
    ap.add_argument("--quick", action="store_true", help="small, to test the script")
    ap.add_argument("--allow-dirty", action="store_true",
                    help="run with uncommitted source changes (recorded as a dirty tree)")
    ap.add_argument("--tag", default="")
    ap.add_argument("--replot", action="store_true",
                    help="only recompute the summary, netCDF and figure from the per-run CSV")
    args = ap.parse_args(argv)
    if args.replot:
        path = _common.result_path(NAME, "csv", args.tag)
        if not path.exists():
            raise SystemExit(f"{NAME}: --replot: no {path} (run the benchmark first)")
        finish(pd.read_csv(path, comment="#", keep_default_na=True), read_attrs(path),
               args.tag)
        return 0
    from md_scene_example import provenance

    prov = provenance(args.allow_dirty)
    from rockcem.scene import SCHEMA

    defaults = {k: v[0] for k, v in SCHEMA["models.md"].items()}
    base_size = tuple(defaults["size"])
    omega0 = float(defaults["resolution"])
    triple = (omega0, omega0 / 1.5, omega0 / 1.5**2)     # the scene's default checks
    sizes = _sizes(args.sizes)
    if args.quick:
        base_size, omega0 = (3.0, 3.0, 8.0), 4.0
        args.omega, triple = [2.0, 2.67, 4.0], (4.0, 2.67, 2.0)
        args.rtol_scales, args.strain_steps = [1e2, 1.0], [1e-3, 5e-4]
        sizes, args.seeds, args.seeds_largest = [(3.0, 3.0, 8.0)], [0, 1], 2
        args.tag = args.tag or "quick"
    _common.announce_source()
    md_attrs = _common.md_source_attrs()
    t_start = time.perf_counter()
    root = tempfile.mkdtemp(prefix=NAME + "_")
    rows = []
    try:
        runs = Runs(args.depths, root)
        # warm-up: compile (or load) the numba kernels outside the timed runs
        Runs(args.depths[-1:], root)(size=(3.0, 3.0, 8.0), seed=99, omegas=(2.0,))
        partial = {**prov, "partial": 1, "command": " ".join(sys.argv)}

        def add(study, got):
            rows.extend(dict(r, study=study) for r in got)
            _common.write_csv(pd.DataFrame(rows), _common.result_path(NAME, "csv", args.tag),
                              partial)

        studies = set(args.studies)
        if "omega" in studies:
            print(f"omega: {_size_label(base_size)}, seed 0", flush=True)
            for w in sorted(args.omega):
                add("omega", runs(size=base_size, omegas=(w,)))
        if "default" in studies:
            print(f"default: Omega {'/'.join(f'{w:g}' for w in triple)}", flush=True)
            add("default", runs(size=base_size, omegas=triple))
        if "rtol" in studies:
            print(f"rtol at Omega {omega0:g}", flush=True)
            for s in sorted(args.rtol_scales, reverse=True):
                add("rtol", runs(size=base_size, omegas=(omega0,), rtol_scale=s))
        if "strain_step" in studies:
            print(f"strain_step at Omega {omega0:g}", flush=True)
            for e in sorted(args.strain_steps, reverse=True):
                add("strain_step", runs(size=base_size, omegas=(omega0,), strain_step=e))
        if "size" in studies:
            print(f"size at Omega {omega0:g}", flush=True)
            largest = max(sizes, key=np.prod)
            for size in sizes:
                for seed in args.seeds[:args.seeds_largest] if size == largest else args.seeds:
                    add("size", runs(size=size, seed=seed, omegas=(omega0,)))
    finally:
        shutil.rmtree(root, ignore_errors=True)
    wall = time.perf_counter() - t_start
    attrs = {**_common.environment_attrs(
        benchmark=NAME, scene=SCENE, depths=" ".join(f"{z:g}" for z in args.depths),
        quick=bool(args.quick), benchmark_wall_seconds=round(wall, 1), **md_attrs), **prov,
        "partial": 0}
    finish(pd.DataFrame(rows), attrs, args.tag)
    print(f"benchmark wall time {wall:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
