"""The scene runner: burial path → rock state → petro-elastic models → one ``xarray.Dataset``.

Private to :mod:`rockcem.scene`. Every quantity is computed on demand and at most once
(``functools.cached_property``), so a scene computes only what its outputs need: a shale scene
never touches the quartz-cement kinetics, a scene without model outputs runs no model, and a
scene asking for one model computes one model.
"""

from __future__ import annotations

import datetime
import itertools
import json
from functools import cached_property

import numpy as np

from .references import REFERENCES

__all__ = ["evaluate", "run", "sweep_members"]

_MODEL_LABELS_LONG = {
    "hs_gassmann": "Model 1: Hashin-Shtrikman + Krief + Gassmann",
    "self_consistent": "Model 2: self-consistent, spheroidal pores",
    "generalized_gassmann": "Model 3: multi-mineral Krief + generalized Gassmann",
    "patchy_cement": "Model 4: patchy cement + Gassmann",
    "md": "MD grain pack (md engine) + Gassmann",
}


def _section(name):
    """Prefix a ValueError raised while evaluating a scene section with the section's name."""
    from .validation import prefixed_errors

    return prefixed_errors(f"scene section [{name}]")


class _Pipeline:
    """Lazily evaluated quantities of one scene member."""

    def __init__(self, scene, *, scheduler=None, jobs=1, progress=False):
        self.scene = scene
        self.scheduler, self.jobs, self.progress = scheduler, jobs, progress
        self.sec = scene.sections
        self.lith = scene.sections[scene.lithology]

    @cached_property
    def path(self):
        import burial

        p = self.sec["path"]
        if p["kind"] != "linear":
            return self.history.path
        rate = p["sedimentation_rate"]
        if p["heating_rate"] is not None:
            if p["heating_rate"] <= 0:
                raise ValueError("scene key path.heating_rate must be > 0")
            rate = p["heating_rate"] / p["gradient"] * 1000.0 if p["gradient"] > 0 else -1.0
        with _section("path"):
            return burial.linear_path(p["gradient"], rate, p["surface_temperature"],
                                      p["max_depth"], depth_step=p["depth_step"])

    @cached_property
    def history(self):
        """A table history (``[path] kind = "horizons"`` or ``"nodes"``) and horizon names."""
        from .histories import scene_history

        return scene_history(self.sec["path"], self.scene.base_dir)

    def now(self, values):
        """Present-day values: every node of a 1-D path (the linear model and ``nodes``, whose
        nodes are the profile), the last node of each horizon of a table of horizons."""
        return values if self.path.depth.ndim == 1 else np.asarray(values)[..., -1]

    @cached_property
    def pressures(self):
        """Present-day pressures; ``max_effective`` is the largest along each path."""
        import burial

        with _section("pressure"):
            full = burial.pressures(self.path, **self.sec["pressure"])
        return type(full)(*(self.now(v) for v in full))

    @cached_property
    def quartz(self):
        """Present-day Walderhaug quartz cement (the kinetics only; no compaction)."""
        import burial

        s = self.lith
        with _section("sandstone"):
            return self.now(burial.quartz_cement(self.path, s["porosity0"], s["grain_size"],
                                                 s["quartz_fraction"], s["clay_coating"],
                                                 start_temperature=s["start_temperature"]))

    @cached_property
    def sandstone(self):
        import burial

        s = self.lith
        with _section("sandstone"):
            igv = burial.intergranular_volume(s["porosity0"], self.pressures.max_effective,
                                              s["igv_final"], s["beta"])
        return burial.sandstone_porosity(igv, self.quartz)

    @cached_property
    def shale_porosity(self):
        import burial

        with _section("shale"):
            return burial.athy_porosity(self.lith["porosity0"], self.pressures.max_effective,
                                        self.lith["beta"])

    @cached_property
    def smectite(self):
        import burial

        s = self.lith
        with _section("shale"):
            return self.now(burial.smectite_fraction(self.path, s["r0"], s["order"],
                                                     s["activation_energy"],
                                                     s["frequency_factor"]))

    @cached_property
    def materials(self):
        from . import materials

        m = self.sec["materials"]
        names = ("grain", "cement") if self.scene.lithology == "sandstone" else \
            ("smectite", "illite")
        return [materials.mineral(m[n]) for n in names], materials.fluid(m["fluid"])

    @cached_property
    def pore_fluid(self):
        """The pore fluid per present-day depth (:mod:`rockcem._scene_fluid`); the catalogue
        fluid itself, as one number, where ``[fluid]`` keeps it and adds no hydrocarbon (nothing
        of the path is computed for it then)."""
        from ._scene_fluid import SceneFluid, fluid_outputs, scene_fluid

        f = self.sec["fluid"]
        if f["model"] == "constant" and f["hydrocarbon"] == "none":
            fluid = self.materials[1]
            S = np.zeros(np.shape(self.now(self.path.depth)))
            return SceneFluid(fluid, fluid, None, S, fluid_outputs(fluid, S), [])
        return scene_fluid(f, self.sec["materials"]["fluid"], self.now(self.path.depth),
                           self.now(self.path.temperature), self.pressures.pore)

    @cached_property
    def porosity(self):
        return self.sandstone.porosity if self.scene.lithology == "sandstone" \
            else self.shale_porosity

    @cached_property
    def solid_fractions(self):
        """Fractions of the two solids per unit volume of solid (last axis)."""
        if self.scene.lithology == "shale":
            r = self.smectite
            return np.stack([r, 1.0 - r], axis=-1)
        phi, phip = self.sandstone.porosity, self.sandstone.cement_fraction
        beta_c = np.clip(phip / (1.0 - phi), 0.0, 1.0)
        return np.stack([1.0 - beta_c, beta_c], axis=-1)

    @cached_property
    def density(self):
        from .models import bulk_density

        minerals = self.materials[0]
        return bulk_density([m.rho for m in minerals], self.solid_fractions, self.porosity,
                            self.pore_fluid.outputs["fluid_density"])

    @cached_property
    def md(self):
        """The MD members: ``(models, per-depth diagnostics, per-model diagnostics)``; with
        patches of brine and hydrocarbon, each member's rock is the patchy combination of its
        two saturated rocks (the MD runs once for both: the fluid enters by Gassmann)."""
        from pathlib import Path

        from ._md_backend import md_model
        from ._scene_fluid import patchy_rock

        fluid = self.pore_fluid
        minerals = self.materials[0]
        out = Path(self.scene.output)
        with _section("models.md"):
            models, per_depth, per_model = md_model(
                self.now(self.path.depth), self.pressures.effective,
                self.pressures.max_effective, self.sandstone.cement_fraction, minerals[0],
                minerals[1], fluid.patches or [fluid.fluid], self.lith["grain_size"],
                self.sec["models.md"],
                intergranular_volume=self.sandstone.porosity + self.sandstone.cement_fraction,
                workdir=out.with_name(out.stem + "_md_work"),
                scheduler=self.scheduler, jobs=self.jobs, progress=self.progress)
        if fluid.patches is None:
            return models[0], per_depth, per_model[0]
        (brine, other), S = models, fluid.saturation
        for k, diagnostics in per_model[0].items():   # the patchy velocities' density
            diagnostics["md_density"] = (1.0 - S) * diagnostics["md_density"] \
                + S * per_model[1][k]["md_density"]
        return ({k: patchy_rock(brine[k], other[k], S) for k in brine}, per_depth, per_model[0])

    def model(self, label):
        fluid = self.pore_fluid
        if fluid.patches is None:
            return self._model(label, fluid.fluid)
        from ._scene_fluid import patchy_rock

        return patchy_rock(*(self._model(label, f) for f in fluid.patches), fluid.saturation)

    def _model(self, label, fluid, **override):
        from . import models

        minerals = self.materials[0]
        knobs = {k: v for k, v in self.sec[f"models.{label}"].items() if k != "calibration"}
        knobs.update(override)                  # (the validity rules' delta = 0)
        with _section(f"models.{label}"):
            if label == "patchy_cement":
                s = self.sandstone
                return models.patchy_cement_model(
                    minerals[0], minerals[1], s.porosity, s.cement_fraction,
                    self.pressures.effective, fluid, critical_porosity=self.lith["porosity0"],
                    **knobs)
            fn = {"hs_gassmann": models.hs_gassmann,
                  "self_consistent": models.self_consistent_model,
                  "generalized_gassmann": models.generalized_gassmann_model}[label]
            return fn(minerals, self.solid_fractions, self.porosity, fluid, **knobs)

    def state_variable(self, name):
        if name == "burial_time":
            return self.now(np.broadcast_to(self.path.time, self.path.depth.shape))
        if name == "temperature":
            return self.now(self.path.temperature)
        if name.startswith("pressure_"):
            return {"pressure_confining": self.pressures.confining,
                    "pressure_pore": self.pressures.pore,
                    "pressure_effective": self.pressures.effective}[name]
        if name == "porosity":
            return self.porosity
        if name == "density":
            return self.density
        if name in ("cement_fraction", "intergranular_volume", "pore_filled"):
            return getattr(self.sandstone, name)
        if name == "smectite_fraction":
            return self.smectite
        if name == "illite_fraction":
            return 1.0 - self.smectite
        if name in self.pore_fluid.outputs:
            return self.pore_fluid.outputs[name]
        raise ValueError(f"no state variable {name!r}")  # guarded by scene validation


def _global_attrs(scene):
    from . import __version__

    keys = ["Carcione2022", "Walton1987", "Mavko2009"]
    if "self_consistent" in scene.models:
        keys.append("Berryman1980")
    if "generalized_gassmann" in scene.models:
        keys.append("Carcione2005")
    if "patchy_cement" in scene.models:
        keys += ["DvorkinNur1996", "Avseth2016", "GangiCarlson1996"]
    params = {k: v for k, v in scene.sections.items()}
    return {
        **_calibration_attrs(scene),
        "Conventions": "CF-1.10",
        "title": f"rockcem scene {scene.name}",
        "scene_name": scene.name,
        "scene_description": scene.description,
        "lithology": scene.lithology,
        "scene_toml": scene.text,
        "parameters_json": json.dumps(params, sort_keys=True),
        "models": " ".join(scene.models),
        "source": f"rockcem {__version__}",
        "rockcem_version": __version__,
        "history": f"{datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')}"
                   f" created by rockcem {__version__}",
        "references": "\n".join(f"[{k}] {REFERENCES[k]}" for k in keys),
        **({"grain": scene.sections["materials"]["grain"],
            "cement": scene.sections["materials"]["cement"],
            "critical_porosity": scene.sections["sandstone"]["porosity0"]}
           if scene.lithology == "sandstone" else
           {"smectite": scene.sections["materials"]["smectite"],
            "illite": scene.sections["materials"]["illite"]}),
        "fluid": (scene.sections["materials"]["fluid"]
                  if scene.sections["fluid"]["model"] == "constant" else "brine"),
        "pore_fluid": _fluid_attr(scene.sections),
    }


def _fluid_attr(sections):
    """The pore fluid in words: the catalogue fluid, or Batzle & Wang brine, and a
    hydrocarbon with its saturation, interval and mixing law."""
    f = sections["fluid"]
    text = (f"Batzle & Wang brine, salinity {f['salinity'] or 0.0:g}"
            if f["model"] == "batzle_wang" else sections["materials"]["fluid"])
    if f["hydrocarbon"] != "none":
        where = (f"{f['top'] if f['top'] is not None else 0:g}-"
                 f"{f['base']:g} m" if f["base"] is not None else
                 f"below {f['top']:g} m" if f["top"] is not None else "every depth")
        text += (f"; {f['hydrocarbon']} at saturation {f['saturation']:g} ({where}), "
                 f"{f['mixing']} mixing")
    return text


def _calibration_attrs(scene):
    """Which calibration files set model parameters: a readable line and one JSON string."""
    if not scene.calibrations:
        return {}
    used = {label: {k: cal[k] for k in ("name", "model", "path", "sha256", "data",
                                        "parameters", "uncertainty", "misfit")}
            for label, cal in scene.calibrations.items()}
    line = "; ".join(f"{label}: {cal['name']} ({cal['path']}, sha256 {cal['sha256'][:12]}): "
                     + ", ".join(f"{k} = {v:.6g}" for k, v in cal["parameters"].items())
                     for label, cal in scene.calibrations.items())
    return {"calibration": line, "calibration_json": json.dumps(used, sort_keys=True)}


def evaluate(scene, *, scheduler=None, jobs=1, progress=False):
    """The Dataset of one scene member (no sweep); its MD members (if any) run on
    ``scheduler`` / ``jobs`` (:func:`md._tasks.run_tasks`), the members of its uncertain
    inputs (``[uncertain]``, :func:`rockcem._uncertain.evaluate_uncertain`) there too."""
    from .variables import build_dataset

    if scene.layers and scene.uncertain:    # its members (rockcem._uncertain_stack)
        from ._uncertain_stack import evaluate_uncertain_stack

        return evaluate_uncertain_stack(scene, scheduler=scheduler, progress=progress)
    if scene.layers:                    # a stack of lithologies (rockcem._scene_stack)
        from ._stack_dataset import evaluate_stack

        ds = evaluate_stack(scene, scheduler=scheduler, jobs=jobs, progress=progress)
        if "seismic" in scene.sections:     # reflectivity, AVO and synthetics when asked
            from ._stack_seismic import add_seismic

            add_seismic(ds, scene)
        return ds
    if scene.uncertain:                 # members of uncertain inputs (rockcem._uncertain)
        from ._uncertain import evaluate_uncertain

        return evaluate_uncertain(scene, scheduler=scheduler, progress=progress)
    pipe = _Pipeline(scene, scheduler=scheduler, jobs=jobs, progress=progress)
    depth = pipe.now(pipe.path.depth)
    data = {}
    for name in scene.outputs:
        if name not in ("K_dry", "G_dry", "K_sat", "G_sat", "vp", "vs"):
            data[name] = (("depth",), np.asarray(pipe.state_variable(name)))
    wanted = [n for n in scene.outputs if n in ("K_dry", "G_dry", "K_sat", "G_sat", "vp", "vs")]
    coords = {"depth": (("depth",), depth)}
    if scene.sections["path"]["kind"] == "horizons":
        coords["horizon"] = (("depth",), pipe.history.horizon.astype(object))
    labels = list(scene.models)
    if wanted:
        results = []
        for label in scene.models:
            if label == "md":
                md_models, per_depth, per_model = pipe.md
                results += list(md_models.values())
            else:
                results.append(pipe.model(label))
        if "md" in scene.models:
            at = labels.index("md")
            labels[at:at + 1] = list(md_models)
        for name in wanted:
            data[name] = (("model", "depth"), np.stack([getattr(r, name) for r in results]))
        coords["model"] = (("model",), np.array(labels, dtype=object))
        if "md" in scene.models:
            data.update({k: (("depth",), v) for k, v in per_depth.items()})
            for k in next(iter(per_model.values())):
                data[k] = (("model", "depth"), np.stack(
                    [per_model[m][k] if m in per_model else np.full(depth.shape, np.nan)
                     for m in labels]))
    attrs = _global_attrs(scene)
    warnings = _validity_warnings(scene, pipe, computed_models=bool(wanted),
                                  results=dict(zip(labels, results)) if wanted else {})
    if "pore_fluid" in pipe.__dict__:
        warnings += pipe.pore_fluid.warnings
        if attrs["fluid"] == "brine":
            # The templates' fluid (plots): the brine at the median of the profile.
            brine = pipe.pore_fluid.brine
            attrs["brine_bulk_modulus"] = float(np.median(brine.K))
            attrs["brine_density"] = float(np.median(brine.rho))
    if "md" in pipe.__dict__:
        from ._md_backend import md_warnings

        warnings += md_warnings(depth, pipe.porosity, pipe.md[1], pipe.md[2])
    if warnings:
        attrs["validity_warnings"] = "\n".join(warnings)
    ds = build_dataset(data, coords, attrs)
    if "model" in ds.coords:
        ds["model"].attrs["description"] = "; ".join(
            f"{m}: {_MODEL_LABELS_LONG.get(m, _MODEL_LABELS_LONG['md'] + ', ' + m[3:] + ' cement')}"
            for m in labels)
    return ds


def _validity_warnings(scene, pipe, *, computed_models, results):
    """:func:`rockcem.validity.validity_warnings` on what the scene computed (nothing more is
    computed for them: porosity and the cement flag only where the outputs needed them; of the
    models, only Model 4's dry frame once more, without its bonding pre-stress)."""
    from .validity import validity_warnings

    done = pipe.__dict__                     # cached_property values computed so far
    if "porosity" not in done:
        return []
    filled = done["sandstone"].pore_filled if "sandstone" in done else None
    shear = {}
    if "self_consistent" in results:
        shear["self_consistent"] = (results["self_consistent"].G_sat,
                                    results["self_consistent"].G_dry)
    if "patchy_cement" in results:
        fluid = pipe.pore_fluid.patches[0] if pipe.pore_fluid.patches else pipe.pore_fluid.fluid
        shear["patchy_cement"] = (results["patchy_cement"].G_dry,
                                  pipe._model("patchy_cement", fluid, delta=0.0).G_dry)
    return validity_warnings(pipe.now(pipe.path.depth), done["porosity"],
                             porosity0=pipe.lith["porosity0"],
                             models=scene.models if computed_models else (),
                             pore_filled=filled, shear_moduli=shear)


def sweep_members(scene):
    """``(coords, member)`` for every combination of the swept values of a scene: ``coords``
    maps each swept key's name to its value, ``member`` is the scene with those values and no
    sweep."""
    from .variables import sweep_dimension

    keys = list(scene.sweep)
    for combo in itertools.product(*(scene.sweep[k] for k in keys)):
        coords = {sweep_dimension(k): v for k, v in zip(keys, combo)}
        yield coords, (scene._with(dict(zip(keys, combo)), keep_sweep=False) if keys else scene)


def _run_chunk(chunk):
    """Evaluate a list of (index, coords, scene) sweep members (one task on a worker)."""
    return [(index, evaluate(member)) for index, _coords, member in chunk]


def run(scene, *, scheduler=None, jobs=1, progress=False):
    """Run a scene and its sweep (serially, or on dask.distributed in chunks of members); a
    scene without a sweep runs its MD members there."""
    import xarray as xr

    if not scene.sweep:
        return _warned(evaluate(scene, scheduler=scheduler, jobs=jobs, progress=progress))
    from .variables import sweep_dimension

    dims = [sweep_dimension(k) for k in scene.sweep]
    values = [scene.sweep[k] for k in scene.sweep]
    members = [(index, coords, member) for index, (coords, member)
               in zip(np.ndindex(*[len(v) for v in values]), sweep_members(scene))]
    if scheduler is None:
        if progress:
            # tqdm.auto only when asked: in a notebook without ipywidgets its import warns.
            from tqdm.auto import tqdm

            members = tqdm(members, desc=scene.name, unit="member")
        results = [(index, evaluate(member)) for index, _c, member in members]
    else:
        results = _run_dask(members, scheduler, progress)
    # The sweep is a full Cartesian product: fill one array per variable directly (much faster
    # than concatenating a Dataset per member).
    template = results[0][1]
    shape = tuple(len(v) for v in values)
    data = {}
    for name, var in template.data_vars.items():
        arr = np.empty(shape + var.shape, dtype=var.dtype)
        for index, ds in results:
            arr[index] = ds[name].values
        data[name] = xr.Variable(tuple(dims) + var.dims, arr, attrs=var.attrs)
    coords = dict(template.coords)
    for key, vals in zip(dims, values):
        coords[key] = xr.Variable((key,), np.asarray(vals), attrs=_sweep_attrs(key))
    out = xr.Dataset(data, coords=coords, attrs=dict(template.attrs))
    out.attrs["sweep"] = json.dumps(scene.sweep)
    _merge_warnings(out, results, dims, values)
    _merge_fluid(out, results, dims, values)
    from .variables import no_coordinate_fill

    no_coordinate_fill(out)
    out.attrs["scene_toml"] = scene.text
    used = sorted({ds.attrs["calibration_json"] for _, ds in results
                   if "calibration_json" in ds.attrs})
    if len(used) > 1:                     # the sweep runs over calibration files
        out.attrs["calibration"] = "varies over the sweep: " + " | ".join(
            sorted({ds.attrs["calibration"] for _, ds in results}))
        out.attrs["calibration_json"] = json.dumps([json.loads(u) for u in used])
    return _warned(out)


def _warned(ds):
    """``ds``, its validity warnings issued once each as a
    :class:`rockcem.validity.RockcemValidityWarning` (after a sweep's merge: once per run)."""
    from .validity import issue_warnings

    issue_warnings(ds.attrs.get("validity_warnings", "").split("\n"),
                   prefix=f"scene {ds.attrs.get('scene_name', '?')}: ")
    return ds


def _merge_warnings(out, results, dims, values):
    """One ``validity_warnings`` attribute for a sweep: each line once, with the members it
    holds for unless it holds for all."""
    members = {}
    for index, ds in results:
        for line in filter(None, ds.attrs.get("validity_warnings", "").split("\n")):
            members.setdefault(line, []).append(
                ", ".join(f"{d} = {v[i]:g}" if isinstance(v[i], (int, float)) else f"{d} = {v[i]}"
                          for d, v, i in zip(dims, values, index)))
    out.attrs.pop("validity_warnings", None)
    if members:
        out.attrs["validity_warnings"] = "\n".join(
            line if len(where) == len(results) else f"[{'; '.join(where)}] {line}"
            for line, where in members.items())


def _merge_fluid(out, results, dims, values):
    """The pore fluid of a sweep in its attributes: one description if every member has the
    same, else each member's; the templates' brine only where every member has the same."""
    texts = {}
    for index, ds in results:
        member = ", ".join(f"{d} = {v[i]}" for d, v, i in zip(dims, values, index))
        texts.setdefault(ds.attrs.get("pore_fluid", ""), []).append(member)
    if len(texts) > 1:
        out.attrs["pore_fluid"] = "varies over the sweep: " + " | ".join(
            f"[{'; '.join(members)}] {text}" for text, members in texts.items())
    for key in ("brine_bulk_modulus", "brine_density"):
        seen = {ds.attrs.get(key) for _, ds in results}
        if len(seen) > 1:                       # a sweep over the brine: no one template fluid
            out.attrs.pop(key, None)
            out.attrs["brine_varies"] = "the brine differs between sweep members"


def _sweep_attrs(key):
    """CF attributes of a swept parameter, from the variable registry."""
    from .variables import variable_attrs

    try:
        return variable_attrs(key)
    except ValueError:
        return {"long_name": key.replace("_", " ")}


def _run_dask(members, scheduler, progress):
    from ._scheduler import dask_client

    with dask_client(scheduler, 2, what="running a sweep on dask") as client:
        n_workers = max(len(client.scheduler_info().get("workers", {})), 1)
        n_chunks = min(len(members), 8 * n_workers)
        chunks = [list(c) for c in np.array_split(np.arange(len(members)), n_chunks)]
        futures = client.map(_run_chunk, [[members[i] for i in c] for c in chunks], pure=False)
        if progress:
            from dask.distributed import progress as dask_progress

            dask_progress(futures)
        return [item for part in client.gather(futures) for item in part]
