"""A stack of lithologies buried by one path: a seal over a reservoir (``[[layers]]``).

Private to the scene runner (:mod:`rockcem.scene`, :mod:`rockcem.runner`); issue 31. A stack
scene gives one ``[path]`` and ``[pressure]`` for every layer and its layers top to bottom as an
array of tables::

    name = "seal_over_sand"
    [path]
    depth_step = 50.0
    [stack]
    fluids = ["brine", "gas"]      # the reservoir layer's pore fluids: the fluid dimension
    reservoir = "reservoir"        # the layer whose pores hold them
    [fluid]                        # brine of every layer, and the hydrocarbon's saturation
    model = "batzle_wang"
    saturation = 0.8

    [[layers]]
    name = "seal"
    scene = "carcione2022_shale"   # its lithology, [shale], [materials] and [models]
    thickness = 2000.0             # m, in the synthetic column
    stand_in = "generalized_gassmann"
    [[layers]]
    name = "reservoir"
    lithology = "sandstone"
    [layers.sandstone]
    igv_final = 0.2
    [layers.models.hs_gassmann]

A third layer is one more ``[[layers]]`` table; every adjacent pair (upper over lower) is an
interface, named ``"upper/lower"``.

What each layer is
    A layer is the single-lithology scene made of its keys on the stack's path: ``lithology``
    with its section (``[layers.sandstone]`` or ``[layers.shale]``), ``[layers.materials]`` and
    ``[layers.models.*]``, exactly as a plain scene's. ``scene`` names a shipped scene or a scene
    file (relative to the stack's file first) to take them from; its ``[path]``, ``[pressure]``,
    ``[fluid]``, ``[sweep]`` and ``outputs`` are replaced by the stack's. The layer's own
    sections then override the referenced ones key by key, except ``[layers.models]``, which
    replaces the referenced scene's set of models whole (to choose fewer). Each layer is
    evaluated by :func:`rockcem.runner.evaluate` as that plain scene on the same depth grid: a
    shale by the smectite-illite kinetics and Athy, a sandstone by Walderhaug and the IGV.

The pore fluid
    ``[fluid]`` gives the brine of every layer (``model`` and ``salinity``, as a plain scene's:
    the catalogue fluid or Batzle & Wang brine at each depth's temperature and pore pressure,
    :mod:`rockcem._scene_fluid`). The reservoir layer (``[stack] reservoir``) is evaluated once
    per entry of ``[stack] fluids``: ``"brine"``, or a hydrocarbon sharing its pores at
    ``fluid.saturation`` with the ``[fluid]`` mixing law, at every depth: the interface is swept
    along depth, so the reservoir is wherever the interface is (``fluid.top`` and ``fluid.base``
    do not apply). Every other layer holds brine whatever the fluid member.

Models on the two sides of an interface
    The stack's models are those of any layer; a model pairs with the model of the same name on
    the other side. A layer without one of them (a shale has no patchy-cement Model 4) names
    ``stand_in``, one of its own models, which gives its side of the interface (and of the
    column) for every model it lacks; the variable ``model_of_layer(layer, model)`` records
    which model of each layer gives each member. The per-layer profiles stay as the layer's
    models give them (NaN for a model the layer does not have).

The synthetic column
    With thicknesses (every layer but the last; the last fills the column to the deepest
    depth), the layers follow each other from the surface: depth ``z`` belongs to layer ``i``
    where ``top_i <= z < top_i + thickness_i``. ``column_vp``, ``column_vs`` and
    ``column_density`` (fluid, model, depth) take at each depth the values of the layer that
    occupies it, at that depth's burial state.

Not in a stack (refused with a message): ``[sweep]``, a scene calibration and the MD backend.
"""

from __future__ import annotations

import datetime
import json
import re
from dataclasses import dataclass
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = ["STACK_FLUIDS", "StackLayer", "InterfaceProperties", "stack_scene_from_dict",
           "evaluate_stack", "interface_properties"]

#: The pore fluids a stack's reservoir may hold (``[stack] fluids``).
STACK_FLUIDS = ("brine", "gas", "oil", "co2", "methane")
_LAYER_NAME = re.compile(r"[A-Za-z0-9_-]+\Z")
_HEAD = ("name", "description", "output")
_TOP = _HEAD + ("path", "pressure", "fluid", "stack", "layers")
#: Keys of a plain scene that a stack does not take at its top level, and why.
_NOT_AT_TOP = {
    "lithology": "each layer names its own ([[layers]] lithology or scene)",
    "sandstone": "give it in its layer ([layers.sandstone])",
    "shale": "give it in its layer ([layers.shale])",
    "materials": "give it in its layer ([layers.materials])",
    "models": "give them in their layer ([layers.models.*])",
    "outputs": "give them per layer ([[layers]] outputs)",
    "sweep": "a stack has no [sweep]: its fluid dimension is [stack] fluids; run one stack "
             "per path",
    "calibration": "a scene calibration sets the keys of one lithology's scene, not a stack's",
}
_LAYER_SECTIONS = ("sandstone", "shale", "materials", "models")
#: Keys a layer does not take, and why.
_NOT_IN_LAYER = {
    "path": "the stack's [path] buries every layer",
    "pressure": "the stack's [pressure] holds for every layer",
    "fluid": "the stack's [fluid] and [stack] fluids give every layer's pore fluid",
    "sweep": "a stack has no [sweep]",
    "calibration": "a scene calibration applies to a plain scene, not a layer",
    "description": "describe the stack at its top level",
    "output": "the stack writes one file (its top-level output)",
}
#: Variables that change with the reservoir's pore fluid (the ``fluid`` dimension).
_FLUID_VARIABLES = ("K_sat", "G_sat", "vp", "vs", "density", "fluid_density",
                    "fluid_bulk_modulus", "fluid_velocity", "hydrocarbon_saturation")


@dataclass(frozen=True)
class StackLayer:
    """One layer of a stack: ``scenes`` maps each fluid of ``[stack] fluids`` to the plain
    scene evaluated for it (the reservoir: one per fluid; any other layer: its brine scene
    under ``"brine"``, which holds for every fluid)."""

    name: str
    lithology: str
    thickness: float | None
    stand_in: str | None
    scenes: dict


class InterfaceProperties(NamedTuple):
    """Both sides of every interface of a stack, each an ``xarray.DataArray`` with dims
    (interface, fluid, model, depth): the upper layer's (1) and the lower layer's (2) P and S
    velocity (km/s) and bulk density (g/cm3)."""

    vp1: object
    vs1: object
    rho1: object
    vp2: object
    vs2: object
    rho2: object


# ----------------------------------------------------------------------------- validation
def _fail(message):
    raise ValueError(message)


def stack_scene_from_dict(raw, *, text=None, base_dir=None):
    """Validate a stack scene (a dict with ``layers``) and build each layer's plain scenes.

    Returns a :class:`rockcem.scene.Scene` with lithology ``"stack"``, sections ``path``,
    ``pressure``, ``fluid`` and ``stack``, no sweep, ``models`` the union of the layers' and
    ``layers`` the :class:`StackLayer` tuple, top to bottom. Raises ``ValueError`` naming the
    key (``layers[1].thickness``, with the closest valid name for a typo).
    """
    from ._atomic import check_scene_name
    from .scene import SCHEMA, Scene, _check_fluid, _check_path_kind, _section, _suggest, \
        _to_toml

    for key in raw:
        if key in _NOT_AT_TOP:
            _fail(f"scene key {key!r} does not apply to a stack of layers: {_NOT_AT_TOP[key]}")
        if key not in _TOP:
            _fail(f"unknown scene key {key!r} of a stack{_suggest(key, _TOP)}")
    head = _section("scene", {k: raw[k] for k in _HEAD if k in raw},
                    {k: SCHEMA["scene"][k] for k in _HEAD})
    check_scene_name(head["name"])
    if head["output"] is not None and not head["output"].strip():
        _fail("scene key output must name a file (leave it out for <name>.nc); got "
              f"{head['output']!r}")
    path = _section("path", raw.get("path", {}), SCHEMA["path"])    # once, for every layer
    _section("pressure", raw.get("pressure", {}), SCHEMA["pressure"])
    _check_path_kind(raw.get("path", {}), path, base_dir)
    stack = _section("stack", raw.get("stack", {}), SCHEMA["stack"])
    fluids = stack["fluids"]
    if not fluids:
        _fail("scene key stack.fluids must name at least one fluid (e.g. ['brine', 'gas'])")
    for f in fluids:
        if f not in STACK_FLUIDS:
            _fail(f"scene key stack.fluids: unknown fluid {f!r}{_suggest(f, STACK_FLUIDS)}")
    twice = sorted({f for f in fluids if fluids.count(f) > 1})
    if twice:
        _fail(f"scene key stack.fluids names {twice[0]!r} twice")
    given_fluid = raw.get("fluid", {})
    if not isinstance(given_fluid, dict):
        _fail("scene section [fluid] must be a table")
    if "hydrocarbon" in given_fluid:
        _fail("scene key fluid.hydrocarbon does not apply to a stack: the reservoir's fluids "
              "are [stack] fluids (e.g. ['brine', 'gas'])")
    for key in ("top", "base"):
        if key in given_fluid:
            _fail(f"scene key fluid.{key} does not apply to a stack: the reservoir layer holds "
                  "its fluid at every depth (the interface is swept along depth)")
    fluid = _section("fluid", given_fluid, SCHEMA["fluid"])
    carbons = [f for f in fluids if f != "brine"]
    _check_stack_fluid(given_fluid, fluid, fluids)
    _check_fluid(given_fluid, fluid, {"fluid.hydrocarbon": carbons or ["none"]}, True)

    layers_raw = raw["layers"]
    if not isinstance(layers_raw, list) or not all(isinstance(t, dict) for t in layers_raw):
        _fail("scene key layers must be an array of tables: [[layers]], one per layer, top "
              "to bottom")
    if len(layers_raw) < 2:
        _fail(f"a stack needs at least two layers ([[layers]], top to bottom); got "
              f"{len(layers_raw)} (one lithology is a plain scene: lithology = ...)")
    specs = [_layer_spec(i, t, base_dir) for i, t in enumerate(layers_raw)]
    names = [s["name"] for s in specs]
    for i, name in enumerate(names):
        if name in names[:i]:
            _fail(f"scene key layers[{i}].name: {name!r} names two layers (names are unique)")
    reservoir = stack["reservoir"]
    if reservoir is None and carbons:
        _fail(f"scene key stack.reservoir is required with stack.fluids {carbons}: the name "
              f"of the layer whose pores hold them (one of {', '.join(names)})")
    if reservoir is not None and reservoir not in names:
        _fail(f"scene key stack.reservoir: no layer {reservoir!r}{_suggest(reservoir, names)}")
    _check_thickness(specs, path)
    fluid_defaults = _default_fluid_outputs(fluid, carbons) if "fluid" in raw else ()
    layers = []
    for spec in specs:
        members = fluids if spec["name"] == reservoir else ["brine"]
        scenes = {f: _layer_scene(spec, raw, head["name"], given_fluid, f, fluid_defaults)
                  for f in members}
        layers.append(StackLayer(spec["name"], spec["lithology"], spec["thickness"],
                                 spec["stand_in"], scenes))
    models = _pair_models(specs, layers)
    first = layers[0].scenes[next(iter(layers[0].scenes))]
    outputs = tuple(dict.fromkeys(o for layer in layers for s in layer.scenes.values()
                                  for o in s.outputs))
    sections = {"path": first.sections["path"], "pressure": first.sections["pressure"],
                "fluid": fluid, "stack": stack}
    return Scene(head["name"], "stack", outputs, head["output"] or f"{head['name']}.nc",
                 models, sections, {}, text if text is not None else _to_toml(raw),
                 head["description"], None if base_dir is None else str(base_dir), {},
                 layers=tuple(layers))


def _check_stack_fluid(given, fluid, fluids):
    """Every [fluid] key given applies to one of the stack's fluids (the hydrocarbon's keys
    need a hydrocarbon among them, an oil's an oil, Brie's exponent Brie's mixing)."""
    from .scene import _FLUID_KEY_USE

    for key, (selector, uses) in _FLUID_KEY_USE.items():
        if key not in given or key in ("top", "base"):
            continue
        chosen = fluids if selector == "hydrocarbon" else [fluid[selector]]
        if not any(c == uses or c in uses for c in chosen):
            uses = (uses,) if isinstance(uses, str) else uses
            what = (f"stack.fluids = {fluids}" if selector == "hydrocarbon"
                    else f"fluid.{selector} = {fluid[selector]!r}")
            _fail(f"scene key fluid.{key} does not apply to {what} (it applies to "
                  f"{'the fluids' if selector == 'hydrocarbon' else selector} "
                  f"{' or '.join(map(repr, uses))})")


def _default_fluid_outputs(fluid, carbons):
    """The fluid variables every layer writes with a [fluid] section (the same for every layer
    and fluid member, so that they share one variable each)."""
    from .scene import _fluid_outputs

    return _fluid_outputs(fluid, {"fluid.hydrocarbon": carbons or ["none"]})[1]


def _layer_spec(i, given, base_dir):
    """A layer's keys, its referenced scene's sections merged in, checked."""
    from .scene import SCHEMA, _section, _suggest

    where = f"layers[{i}]"
    for key in given:
        if key in _NOT_IN_LAYER:
            _fail(f"scene key {where}.{key} does not apply to a layer: {_NOT_IN_LAYER[key]}")
        if key not in SCHEMA["layers"] and key not in _LAYER_SECTIONS:
            valid = tuple(SCHEMA["layers"]) + _LAYER_SECTIONS
            _fail(f"unknown scene key {where}.{key}{_suggest(key, valid)}")
    keys = _section(where, {k: v for k, v in given.items() if k in SCHEMA["layers"]},
                    SCHEMA["layers"])
    name = keys["name"]
    if not _LAYER_NAME.match(name):
        _fail(f"scene key {where}.name must be letters, digits, '_' or '-' (it names the "
              f"layer's coordinate and its interfaces 'upper/lower'); got {name!r}")
    where = f"layers[{i}] ({name})"
    base, layer_dir = {}, base_dir
    if keys["scene"] is not None:
        base, layer_dir = _referenced(keys["scene"], base_dir, f"{where}.scene")
    lithology = keys["lithology"] or base.get("lithology")
    if keys["lithology"] is not None and base.get("lithology") not in (None, keys["lithology"]):
        _fail(f"scene key {where}.lithology = {keys['lithology']!r} contradicts scene "
              f"{keys['scene']!r}, a {base['lithology']} scene")
    if lithology is None:
        _fail(f"scene key {where}.lithology is required ('sandstone' or 'shale'), or scene = "
              "a scene to take it from")
    if lithology not in ("sandstone", "shale"):
        _fail(f"scene key {where}.lithology must be 'sandstone' or 'shale'; got {lithology!r}")
    sections = {}
    for sec in ("sandstone", "shale", "materials"):
        own, ref = given.get(sec, {}), base.get(sec, {})
        for what, table in ((f"{where}.{sec}", own), (f"section [{sec}] of {keys['scene']}", ref)):
            if not isinstance(table, dict):
                _fail(f"scene {what} must be a table")
        if own or ref or sec in given:
            sections[sec] = {**ref, **own}
    sections["models"] = given["models"] if "models" in given else base.get("models", {})
    if not isinstance(sections["models"], dict):
        _fail(f"scene section {where}.models must hold one table per model")
    if not sections["models"]:
        _fail(f"layer {name!r} has no model: the interfaces need its vp and vs (give "
              "[layers.models.*] or a scene with models)")
    if "md" in sections["models"]:
        _fail(f"scene key {where}.models.md: the MD backend does not run in a stack yet; "
              "run the layer's MD as a plain scene")
    if keys["thickness"] is not None and not keys["thickness"] > 0:
        _fail(f"scene key {where}.thickness must be > 0 m; got {keys['thickness']:g}")
    if keys["stand_in"] is not None and keys["stand_in"] not in sections["models"]:
        _fail(f"scene key {where}.stand_in = {keys['stand_in']!r} is not one of the layer's "
              f"models ({', '.join(sections['models'])})")
    return {**keys, "lithology": lithology, "sections": sections, "where": where,
            "base_dir": layer_dir}


def _referenced(source, base_dir, where):
    """The TOML of a layer's ``scene`` (a file beside the stack's, a path, or a shipped
    scene's name) and its folder."""
    from .scene import read_scene_toml, scene_path
    from .validation import prefixed_errors

    candidate = Path(base_dir) / source if base_dir is not None else None
    with prefixed_errors(f"scene key {where}"):
        path = candidate if candidate is not None and candidate.is_file() else \
            scene_path(source)
        ref, _ = read_scene_toml(path)
    if "md" in ref:
        _fail(f"scene key {where}: {source!r} is an MD study scene, not a lithology")
    if "layers" in ref:
        _fail(f"scene key {where}: {source!r} is itself a stack; name a single-lithology scene")
    if ref.get("calibration") is not None:
        _fail(f"scene key {where}: {source!r} has a scene calibration, which a stack does not "
              "apply; name a scene without one")
    return ref, path.parent


def _check_thickness(specs, path):
    """Thicknesses make a column: none at all, or every layer's but the last's."""
    given = [s["thickness"] is not None for s in specs]
    if not any(given):
        return
    for s, has in zip(specs[:-1], given[:-1]):
        if not has:
            _fail(f"scene key {s['where']}.thickness is required: with thicknesses (the "
                  "synthetic column) every layer but the last has one")
    if given[-1]:
        _fail(f"scene key {specs[-1]['where']}.thickness: the last layer fills the column to "
              "the deepest depth; remove its thickness")
    top = sum(s["thickness"] for s in specs[:-1])
    if path["kind"] == "linear":
        deepest = path["max_depth"]
        if top >= deepest:
            _fail(f"scene keys layers.thickness: the layers above the last reach {top:g} m, "
                  f"at or below path.max_depth ({deepest:g} m): the last layer holds no depth")


def _layer_scene(spec, raw, stack_name, given_fluid, member, fluid_defaults):
    """The plain scene of a layer with one pore fluid (``member``: 'brine' or a hydrocarbon)."""
    from .scene import MODEL_OUTPUTS, STATE_OUTPUTS, scene_from_dict
    from .validation import prefixed_errors

    lith = spec["lithology"]
    outputs = list(spec["outputs"]) if spec["outputs"] is not None else \
        list(STATE_OUTPUTS[lith] + MODEL_OUTPUTS) + list(fluid_defaults)
    outputs += [v for v in ("vp", "vs", "density") if v not in outputs]
    layer = {"name": f"{stack_name}_{spec['name']}", "lithology": lith,
             "outputs": outputs, **spec["sections"]}
    for sec in ("path", "pressure"):
        if sec in raw:
            layer[sec] = raw[sec]
    if given_fluid or member != "brine":
        layer["fluid"] = _member_fluid(given_fluid, member)
    what = f"layer {spec['name']!r}" + (f" with {member}" if member != "brine" else "")
    with prefixed_errors(what):
        return scene_from_dict(layer, base_dir=spec["base_dir"])


def _member_fluid(given, member):
    """The [fluid] table of one fluid member: the brine's keys (model, salinity) always; the
    hydrocarbon's (saturation, mixing, and those of its kind) with a hydrocarbon."""
    from .scene import _FLUID_KEY_USE

    out = {k: given[k] for k in ("model", "salinity") if k in given}
    if member == "brine":
        return out
    out["hydrocarbon"] = member
    for key, value in given.items():
        if key in out or key in ("model", "salinity"):
            continue
        selector, uses = _FLUID_KEY_USE[key]
        if selector == "hydrocarbon" and member not in uses:
            continue
        out[key] = value
    return out


def _pair_models(specs, layers):
    """The stack's models (every layer's, in the schema's order); a layer without one of them
    needs a stand-in (and one with every model none)."""
    from .scene import MODEL_LABELS

    union = tuple(m for m in MODEL_LABELS if any(m in s["sections"]["models"] for s in specs))
    for spec in specs:
        own = spec["sections"]["models"]
        missing = [m for m in union if m not in own]
        if missing and spec["stand_in"] is None:
            other = next(s["name"] for s in specs if missing[0] in s["sections"]["models"])
            _fail(f"layer {spec['name']!r} has no model {missing[0]!r}, which layer {other!r} "
                  f"has: give it [layers.models.{missing[0]}] where its lithology has that "
                  f"model, or {spec['where']}.stand_in = one of its models "
                  f"({', '.join(own)}) to give its side of the interface for it")
        if not missing and spec["stand_in"] is not None:
            _fail(f"scene key {spec['where']}.stand_in: the layer has every model of the stack "
                  f"({', '.join(union)}), so nothing to stand in for; remove it")
    return union


# ----------------------------------------------------------------------------- evaluation
def evaluate_stack(scene):
    """The Dataset of a stack scene: each layer evaluated as its plain scene on the stack's
    path (:func:`rockcem.runner.evaluate`), the reservoir once per fluid, joined along
    ``layer`` and ``fluid``; the interfaces and, with thicknesses, the synthetic column."""
    from .runner import evaluate
    from .validation import prefixed_errors

    stack = scene.sections["stack"]
    fluids = list(stack["fluids"])
    runs = {}
    for layer in scene.layers:
        for member, sub in layer.scenes.items():
            with prefixed_errors(f"layer {layer.name!r}"
                                 + (f" with {member}" if member != "brine" else "")):
                runs[layer.name, member] = evaluate(sub)
    first = runs[scene.layers[0].name, next(iter(scene.layers[0].scenes))]
    depth = first["depth"].values
    models = list(scene.models)
    names = [layer.name for layer in scene.layers]

    def member_ds(layer, f):
        return runs[layer.name, f if f in layer.scenes else "brine"]

    variables = list(dict.fromkeys(v for ds in runs.values() for v in ds.data_vars))
    data = {}
    for name in variables:
        data[name] = _joined(name, scene.layers, fluids, models, member_ds, depth.size)
    model_of = np.array([[m if m in layer.scenes[next(iter(layer.scenes))].models
                          else layer.stand_in for m in models] for layer in scene.layers],
                        dtype=object)
    pairs = list(zip(names[:-1], names[1:]))
    coords = {"depth": (("depth",), depth),
              "layer": (("layer",), np.array(names, dtype=object)),
              "lithology": (("layer",), np.array([la.lithology for la in scene.layers],
                                                  dtype=object)),
              "fluid": (("fluid",), np.array(fluids, dtype=object)),
              "model": (("model",), np.array(models, dtype=object)),
              "interface": (("interface",), np.array([f"{a}/{b}" for a, b in pairs],
                                                     dtype=object)),
              "upper_layer": (("interface",), np.array([a for a, _ in pairs], dtype=object)),
              "lower_layer": (("interface",), np.array([b for _, b in pairs], dtype=object))}
    if "horizon" in first.coords:
        coords["horizon"] = (("depth",), first["horizon"].values)
    ds = _build(scene, data, coords, runs, model_of)
    if all(layer.thickness is not None for layer in scene.layers[:-1]):
        _add_column(ds, scene)
    return ds


def _joined(name, layers, fluids, models, member_ds, n_depth):
    """One variable of every layer: dims (layer[, fluid][, model], depth), NaN where a layer
    does not have it (a shale's cement) or the model."""
    per_model = any("model" in member_ds(la, f)[name].dims for la in layers for f in fluids
                    if name in member_ds(la, f))
    by_fluid = name in _FLUID_VARIABLES or any(
        name in member_ds(la, fluids[0]) and not all(
            np.array_equal(member_ds(la, fluids[0])[name].values,
                           member_ds(la, f)[name].values, equal_nan=True) for f in fluids)
        for la in layers)
    present = [member_ds(la, f)[name] for la in layers for f in fluids
               if name in member_ds(la, f)]
    dtype = np.result_type(*(v.dtype for v in present))
    complete = len(present) == len(layers) * len(fluids) and (
        not per_model or all(v.sizes.get("model") == len(models) for v in present))
    if not complete or dtype.kind not in "iub":
        dtype = np.result_type(dtype, np.float64)
    shape = (len(layers),) + ((len(fluids),) if by_fluid else ()) + \
        ((len(models),) if per_model else ()) + (n_depth,)
    out = np.full(shape, np.nan if dtype.kind == "f" else 0, dtype=dtype)
    for i, la in enumerate(layers):
        for j, f in enumerate(fluids if by_fluid else fluids[:1]):
            ds = member_ds(la, f)
            if name not in ds:
                continue
            target = out[i, j] if by_fluid else out[i]
            if per_model:
                for k, m in enumerate(models):
                    if m in ds["model"].values:
                        target[k] = ds[name].sel(model=m).values
            else:
                target[...] = ds[name].values
    dims = ("layer",) + (("fluid",) if by_fluid else ()) + (("model",) if per_model else ()) \
        + ("depth",)
    return dims, out


_COORD_ATTRS = {
    "layer": {"long_name": "layer of the stack, top to bottom"},
    "lithology": {"long_name": "lithology of the layer"},
    "fluid": {"long_name": "pore fluid of the reservoir layer"},
    "interface": {"long_name": "interface, upper/lower layer"},
    "upper_layer": {"long_name": "layer above the interface"},
    "lower_layer": {"long_name": "layer below the interface"},
}


def _build(scene, data, coords, runs, model_of):
    """The stack's Dataset: the registry's attributes on the layers' variables, the
    coordinates described, the model pairing and the global attributes."""
    import xarray as xr

    from .variables import build_dataset

    ds = build_dataset(data, coords, _stack_attrs(scene, runs, model_of))
    for name, attrs in _COORD_ATTRS.items():
        ds[name].attrs.update(attrs)
    ds["model_of_layer"] = xr.Variable(
        ("layer", "model"), model_of,
        attrs={"long_name": "model of the layer that gives its side of the interfaces and of "
               "the column at each model (the model itself, or the layer's stand_in)"})
    return ds


def _stack_attrs(scene, runs, model_of):
    from . import __version__

    stack, f = scene.sections["stack"], scene.sections["fluid"]
    refs = dict.fromkeys(line for ds in runs.values()
                         for line in ds.attrs.get("references", "").split("\n") if line)
    warnings = {}                        # line -> (layer, fluid members it holds for)
    for (layer, member), ds in runs.items():
        for line in filter(None, ds.attrs.get("validity_warnings", "").split("\n")):
            warnings.setdefault((layer, line), []).append(member)
    lines = []
    for (layer, line), members in warnings.items():
        every = len(members) == sum(1 for la, _ in runs if la == layer)
        lines.append(f"[layer {layer}{'' if every else ', ' + ', '.join(members)}] {line}")
    brine = (f"Batzle & Wang brine, salinity {f['salinity'] or 0.0:g}"
             if f["model"] == "batzle_wang" else "the catalogue fluid of each layer's materials")
    carbons = [x for x in stack["fluids"] if x != "brine"]
    pore = f"{brine} in every layer" + (
        f"; layer {stack['reservoir']}: {', '.join(carbons)} at saturation "
        f"{f['saturation']:g} at every depth, {f['mixing']} mixing" if carbons else "")
    pairing = "; ".join(f"{layer.name}: {m} by {model_of[i, k]}"
                        for i, layer in enumerate(scene.layers)
                        for k, m in enumerate(scene.models) if model_of[i, k] != m)
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    attrs = {
        "Conventions": "CF-1.10",
        "title": f"rockcem stack scene {scene.name}",
        "scene_name": scene.name,
        "scene_description": scene.description,
        "lithology": "stack",
        "layers": " ".join(layer.name for layer in scene.layers),
        "layer_lithologies": " ".join(layer.lithology for layer in scene.layers),
        "reservoir": stack["reservoir"] or "",
        "scene_toml": scene.text,
        "parameters_json": json.dumps({layer.name: {m: s.sections for m, s in
                                                    layer.scenes.items()}
                                       for layer in scene.layers}, sort_keys=True),
        "models": " ".join(scene.models),
        "model_pairing": pairing or "every layer has every model",
        "pore_fluid": pore,
        "source": f"rockcem {__version__}",
        "rockcem_version": __version__,
        "history": f"{now} created by rockcem {__version__}",
        "references": "\n".join(refs),
    }
    if lines:
        attrs["validity_warnings"] = "\n".join(lines)
    return attrs


def _sides(ds, name):
    """``name`` of every layer as a numpy array (layer, fluid, model, depth), each model's
    values those of the layer's model that gives its side (``model_of_layer``)."""
    var = ds[name]
    for dim in ("fluid", "model"):
        if dim not in var.dims:
            var = var.expand_dims({dim: ds[dim].size})
    values = var.transpose("layer", "fluid", "model", "depth").values
    models = [str(m) for m in ds["model"].values]
    pick = [[models.index(str(m)) for m in row] for row in ds["model_of_layer"].values]
    return np.stack([values[i][:, row, :] for i, row in enumerate(pick)])


def interface_properties(ds):
    """Both sides of every interface of a stack's Dataset: upper layer (1) over lower (2).

    The AVO join is then one call, e.g. ``zoeppritz_pp(*interface_properties(ds), angle)``.
    Each model's values on a side are those of the model of the same name, or of the layer's
    ``stand_in`` where it lacks it (the Dataset's ``model_of_layer``); a layer's bulk density
    (one per depth and fluid) is broadcast over the models.

    Parameters
    ----------
    ds : xarray.Dataset
        A stack scene's Dataset (:func:`rockcem.scene.run_scene` of a scene with
        ``[[layers]]``, or the file it wrote), with ``vp``, ``vs`` and ``density``.

    Returns
    -------
    InterfaceProperties
        ``(vp1, vs1, rho1, vp2, vs2, rho2)``, DataArrays with dims (interface, fluid, model,
        depth): km/s, km/s, g/cm3.

    Raises
    ------
    ValueError
        ``ds`` is not a stack's Dataset, or lacks vp, vs or density.
    """
    import xarray as xr

    need = ("interface", "upper_layer", "lower_layer", "model_of_layer", "vp", "vs", "density")
    missing = [n for n in need if n not in ds.variables]
    if missing:
        raise ValueError(f"ds must be a stack scene's Dataset (a scene with [[layers]]); it "
                         f"has no {missing[0]!r}")
    sides = {name: _sides(ds, name) for name in ("vp", "vs", "density")}
    layers = [str(la) for la in ds["layer"].values]
    coords = {"interface": ds["interface"].values, "fluid": ds["fluid"].values,
              "model": ds["model"].values, "depth": ds["depth"].values}
    out = []
    for end in ("upper_layer", "lower_layer"):
        index = [layers.index(str(la)) for la in ds[end].values]
        for name in ("vp", "vs", "density"):
            out.append(xr.DataArray(sides[name][index], dims=("interface", "fluid", "model",
                                                               "depth"),
                                    coords=coords, name=name, attrs=dict(ds[name].attrs)))
    return InterfaceProperties(*out)


def _add_column(ds, scene):
    """The synthetic column: each depth takes the layer that occupies it (from the surface,
    top inclusive), at that depth's burial state; ``column_layer`` names it."""
    import xarray as xr

    thickness = [layer.thickness for layer in scene.layers[:-1]]
    bases = np.cumsum(thickness)
    depth = ds["depth"].values
    index = np.searchsorted(bases, depth, side="right")     # top_i <= z < base_i
    ds["column_layer"] = xr.Variable(
        ("depth",), ds["layer"].values[index].astype(object),
        attrs={"long_name": "layer of the synthetic column at the depth (from the surface, "
               "thicknesses " + ", ".join(f"{la.name} {la.thickness:g} m"
                                          for la in scene.layers[:-1])
               + f", {scene.layers[-1].name} below)"})
    at = np.arange(depth.size)
    for name, out in (("vp", "column_vp"), ("vs", "column_vs"), ("density", "column_density")):
        side = _sides(ds, name)                             # layer, fluid, model, depth
        attrs = dict(ds[name].attrs)
        attrs["long_name"] = f"{attrs.get('long_name', name)} of the synthetic column"
        ds[out] = xr.Variable(("fluid", "model", "depth"),
                              np.moveaxis(side[index, :, :, at], 0, -1), attrs=attrs)
