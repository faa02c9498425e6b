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

The MD backend
    A sandstone layer may have ``[layers.models.md]``: the MD members give that layer's side
    of the interfaces at the MD depths (the other layers' sides by their ``stand_in``), NaN
    elsewhere. Its stage files lie in ``<stack output stem>_<layer>_md_work``; the reservoir's
    fluid members share them (the MD frame does not depend on the fluid), so it runs once.

Uncertain inputs
    ``[uncertain]`` takes the stack's ``path.*``, ``pressure.*`` and ``fluid.*`` keys (a fluid
    key in the layers and fluids that use it) and each layer's keys as
    ``"layers.<name>.<section>.<key>"`` (``"layers.reservoir.sandstone.grain_size"``,
    ``"layers.seal.models.hs_gassmann.A"``); :mod:`rockcem._uncertain_stack` checks them (each
    layer's scene checks its own, as a plain scene's ``[uncertain]``) and runs the members.

Not in a stack (refused with a message): ``[sweep]`` and a scene calibration.

This module reads and checks the keys; :mod:`rockcem._stack_dataset` evaluates the layers and
builds the Dataset.
"""

from __future__ import annotations

import difflib
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np


__all__ = ["STACK_FLUIDS", "StackLayer", "StackUncertain", "stack_scene_from_dict"]

#: The pore fluids a stack's reservoir may hold (``[stack] fluids``).
STACK_FLUIDS = ("brine", "gas", "oil", "co2", "methane")
_LAYER_NAME = re.compile(r"[A-Za-z0-9_-]+\Z")
_HEAD = ("name", "description", "output")
_TOP = _HEAD + ("path", "pressure", "fluid", "stack", "seismic", "layers", "uncertain")
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
    split = split_uncertain(raw)
    sampled = split.fluid_keys() if split else []       # uncertain [fluid] keys: given
    _check_stack_fluid({**given_fluid, **dict.fromkeys(sampled)}, fluid, fluids)
    _check_fluid(given_fluid, fluid, {"fluid.hydrocarbon": carbons or ["none"],
                                      **{f"fluid.{k}": [None] for k in sampled}}, True)

    layers_raw = raw["layers"]
    if not isinstance(layers_raw, list) or not all(isinstance(t, dict) for t in layers_raw):
        _fail("scene key layers must be an array of tables: [[layers]], one per layer, top "
              "to bottom")
    if len(layers_raw) < 2:
        _fail(f"a stack needs at least two layers ([[layers]], top to bottom); got "
              f"{len(layers_raw)} (one lithology is a plain scene: lithology = ...)")
    specs = [_layer_spec(i, t, base_dir, split.layer_keys(t.get("name")) if split else ())
             for i, t in enumerate(layers_raw)]
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
    shared = {sec: dict(raw[sec]) for sec in ("path", "pressure") if sec in raw}
    if isinstance(shared.get("path", {}).get("table"), str):
        from .histories import _resolve         # relative to the stack's file, not a layer's

        shared["path"]["table"] = str(_resolve(shared["path"]["table"], base_dir))
    layers = []
    for spec in specs:
        members = fluids if spec["name"] == reservoir else ["brine"]
        scenes = {f: _layer_scene(spec, shared, head["name"], given_fluid, f, fluid_defaults,
                                  layer_uncertain(split, spec, f))
                  for f in members}
        layers.append(StackLayer(spec["name"], spec["lithology"], spec["thickness"],
                                 spec["stand_in"], scenes))
    models = _pair_models(specs, layers)
    first = layers[0].scenes[next(iter(layers[0].scenes))]
    outputs = tuple(dict.fromkeys(o for layer in layers for s in layer.scenes.values()
                                  for o in s.outputs))
    for key in sampled:                 # the nominal value (the median) of an uncertain key
        fluid[key] = next(sub.sections["fluid"][key] for layer in layers
                          for sub in layer.scenes.values() if f"fluid.{key}" in
                          sub.uncertain.get("keys", {}))
    sections = {"path": first.sections["path"], "pressure": first.sections["pressure"],
                "fluid": fluid, "stack": stack}
    if "seismic" in raw:                # reflectivity, AVO and synthetics only when asked
        seismic = _section("seismic", raw["seismic"], SCHEMA["seismic"])
        sections["seismic"] = _check_seismic(raw["seismic"], seismic, specs, base_dir)
    return Scene(head["name"], "stack", outputs, head["output"] or f"{head['name']}.nc",
                 models, sections, {}, text if text is not None else _to_toml(raw),
                 head["description"], None if base_dir is None else str(base_dir), {},
                 layers=tuple(layers), uncertain=stack_uncertain(split, layers))


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


def _layer_spec(i, given, base_dir, uncertain=()):
    """A layer's keys, its referenced scene's sections merged in, checked; the layer's
    ``uncertain`` keys (``"section.key"``) are dropped from the referenced scene's sections
    (the distribution replaces the referenced value; one the layer sets itself stays, and its
    scene refuses it as both set and uncertain)."""
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
        ref = {k: v for k, v in ref.items() if f"{sec}.{k}" not in uncertain}
        if own or ref or sec in given:
            sections[sec] = {**ref, **own}
    sections["models"] = given["models"] if "models" in given else {
        label: ({k: v for k, v in table.items() if f"models.{label}.{k}" not in uncertain}
                if isinstance(table, dict) else table)
        for label, table in base.get("models", {}).items()}
    if not isinstance(sections["models"], dict):
        _fail(f"scene section {where}.models must hold one table per model")
    if not sections["models"]:
        _fail(f"layer {name!r} has no model: the interfaces need its vp and vs (give "
              "[layers.models.*] or a scene with models)")
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


def _check_seismic(given, seismic, specs, base_dir):
    """The ``[seismic]`` keys in their ranges; the threshold's default filled in; a user's
    wavelet read (its samples replace the file name: ``wavelet_time``, ``wavelet_amplitude``)."""
    from .reflectivity import AVO_THRESHOLD

    checks = (("max_angle", 0.0, 90.0, "in (0, 90) degrees"),
              ("angle_step", 0.0, np.inf, "> 0 degrees"),
              ("frequency", 0.0, np.inf, "> 0 Hz"))
    for key, lo, hi, valid in checks:
        value = seismic[key]
        if not lo < value < hi:
            _fail(f"scene key seismic.{key} must be {valid}; got {value:g}")
    if seismic["angle_step"] > seismic["max_angle"]:
        _fail(f"scene key seismic.angle_step ({seismic['angle_step']:g}) must not exceed "
              f"seismic.max_angle ({seismic['max_angle']:g})")
    if not 1e-5 <= seismic["dt"] <= 0.05:
        _fail(f"scene key seismic.dt must lie in [1e-5, 0.05] s; got {seismic['dt']:g}")
    if seismic["class_threshold"] is None:
        seismic["class_threshold"] = AVO_THRESHOLD
    elif not 0.0 < seismic["class_threshold"] < 1.0:
        _fail("scene key seismic.class_threshold must lie in (0, 1); got "
              f"{seismic['class_threshold']:g}")
    if seismic["wavelet"] is not None:
        if "frequency" in given:
            _fail("scene keys seismic.wavelet and seismic.frequency: give one (the frequency "
                  "is that of the Ricker wavelet a user's wavelet replaces)")
        seismic.update(_read_wavelet(seismic["wavelet"], seismic["dt"], base_dir))
    if seismic["gather_depth"] is not None and specs[0]["thickness"] is None:
        _fail("scene key seismic.gather_depth needs the synthetic column: give every layer "
              "but the last a thickness")
    return seismic


def _read_wavelet(name, dt, base_dir):
    """``seismic.wavelet``: a CSV file of two columns, time (s) and amplitude, ``#`` comments
    and one header line allowed, sampled at ``dt`` with one sample at time 0."""
    where = f"scene key seismic.wavelet = {name!r}"
    path = Path(name) if base_dir is None else Path(base_dir) / name
    if not path.is_file():
        _fail(f"{where}: no such file{'' if base_dir is None else f' (beside the scene: {path})'}")
    try:
        with open(path, encoding="utf-8-sig") as fh:
            rows = [line for line in fh if line.strip() and not line.lstrip().startswith("#")]
        try:
            float(rows[0].split(",")[0])
        except ValueError:
            rows = rows[1:]                     # a header line
        data = np.array([[float(v) for v in row.split(",")] for row in rows], dtype=float)
    except (ValueError, IndexError, UnicodeDecodeError) as exc:
        _fail(f"{where}: not a CSV file of two numeric columns, time (s) and amplitude ({exc})")
    if data.ndim != 2 or data.shape[1] != 2 or data.shape[0] < 3:
        _fail(f"{where}: needs two columns, time (s) and amplitude, and at least 3 rows")
    if not np.all(np.isfinite(data)):
        _fail(f"{where}: holds a value that is not a finite number")
    t, a = data[:, 0], data[:, 1]
    if not np.allclose(np.diff(t), dt, rtol=1e-6, atol=0.0):
        _fail(f"{where}: its times must be sampled at seismic.dt = {dt:g} s")
    if np.count_nonzero(np.abs(t) <= 1e-6 * dt) != 1:
        _fail(f"{where}: its times must have one sample at time 0 (the reflection's time)")
    if not np.any(a != 0):
        _fail(f"{where}: its amplitudes are all zero")
    return {"wavelet_time": t.tolist(), "wavelet_amplitude": a.tolist()}


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


def _layer_scene(spec, shared, stack_name, given_fluid, member, fluid_defaults,
                 uncertain=None):
    """The plain scene of a layer with one pore fluid (``member``: 'brine' or a hydrocarbon),
    on the stack's ``shared`` [path] and [pressure]; ``uncertain``, the layer's own
    ``[uncertain]`` table (plain ``"section.key"`` names), if any."""
    from .scene import MODEL_OUTPUTS, STATE_OUTPUTS, scene_from_dict
    from .validation import prefixed_errors

    lith = spec["lithology"]
    outputs = list(spec["outputs"]) if spec["outputs"] is not None else \
        list(STATE_OUTPUTS[lith] + MODEL_OUTPUTS) + list(fluid_defaults)
    outputs += [v for v in ("vp", "vs", "density") if v not in outputs]
    layer = {"name": f"{stack_name}_{spec['name']}", "lithology": lith,
             "outputs": outputs, **spec["sections"]}
    layer.update(shared)
    if given_fluid or member != "brine":
        layer["fluid"] = _member_fluid(given_fluid, member)
    if uncertain:
        layer["uncertain"] = uncertain
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


# ----------------------------------------------------------------------------- uncertain
_SHARED = ("path", "pressure")
_NOT_IN_STACK = {
    "sensitivity": "Sobol' indices are not computed for a stack yet; run a layer as a plain "
                   "scene with sensitivity = true",
}


@dataclass
class StackUncertain:
    """A stack's ``[uncertain]`` split: ``top`` (samples, seed, ...), ``keys`` (stack
    dotted name -> its table, in the order given) and ``where`` (stack dotted name ->
    ``(layer name or None for a shared key, the plain "section.key")``)."""

    top: dict
    keys: dict
    where: dict

    def layer_keys(self, name):
        """The plain keys uncertain in layer ``name`` (its own, not the shared ones)."""
        return {plain for layer, plain in self.where.values() if layer == name}

    def fluid_keys(self):
        """The uncertain ``[fluid]`` keys (``saturation``), shared by the layers they apply
        to."""
        return [plain.partition(".")[2] for layer, plain in self.where.values()
                if layer is None and plain.startswith("fluid.")]


def split_uncertain(raw):
    """The ``[uncertain]`` table of a stack scene ``raw`` split by layer, checked for what
    belongs to a stack: each key shared (``path.*``, ``pressure.*``, not set in the stack's
    section) or a layer's (``layers.<layer>.<section>.<key>``, the layer named). None
    without ``[uncertain]``."""
    table = raw.get("uncertain")
    if table is None:
        return None
    if not isinstance(table, dict):
        _fail("scene section [uncertain] must be a table")
    names = [t.get("name") for t in raw["layers"] if isinstance(t, dict)
             and isinstance(t.get("name"), str)] if isinstance(raw["layers"], list) else []
    example = f"layers.{names[-1] if names else 'reservoir'}.sandstone.grain_size"
    top, keys, where = {}, {}, {}
    for dotted, entry in table.items():
        if not isinstance(entry, dict):
            if entry not in (False, None) and dotted in _NOT_IN_STACK:
                _fail(f"scene key uncertain.{dotted} does not apply to a stack of layers: "
                      f"{_NOT_IN_STACK[dotted]}")
            top[dotted] = entry
            continue
        section, _, key = dotted.partition(".")
        if dotted == "layers" or (section == "layers" and "distribution" not in entry):
            _fail(f"scene section [uncertain.layers...]: quote the key, "
                  f"[uncertain.\"{example}\"] (a dotted key unquoted is a table in a table)")
        if section in _SHARED and "." not in key:
            given = raw.get(section, {})
            if isinstance(given, dict) and key in given:
                _fail(f"scene key {dotted} is both set ({given[key]!r}) and uncertain; remove "
                      "one of them")
            where[dotted] = (None, dotted)
        elif section == "layers":
            layer, _, plain = key.partition(".")
            if layer not in names:
                close = difflib.get_close_matches(layer, names, n=1, cutoff=0.6)
                hint = f"; did you mean {close[0]!r}?" if close else \
                    f" (layers: {', '.join(names)})"
                _fail(f"uncertain key {dotted!r}: no layer {layer!r}{hint}")
            if "." not in plain:
                _fail(f"uncertain key {dotted!r}: name the layer's key as "
                      f"layers.{layer}.<section>.<key> (e.g. {example!r})")
            where[dotted] = (layer, plain)
        elif section == "fluid" and "." not in key:
            given = raw.get("fluid", {})
            if isinstance(given, dict) and key in given:
                _fail(f"scene key {dotted} is both set ({given[key]!r}) and uncertain; remove "
                      "one of them")
            where[dotted] = (None, dotted)
        else:
            _fail(f"uncertain key {dotted!r} does not name a key of a stack: the shared "
                  f"path.<key>, pressure.<key> and fluid.<key>, or a layer's as "
                  f"layers.<layer>.<section>.<key> (e.g. {example!r})")
        keys[dotted] = entry
    if not keys:
        _fail(f"scene section [uncertain] names no key: add a table such as "
              f"[uncertain.\"{example}\"] distribution = \"normal\", ...")
    return StackUncertain(top, keys, where)


def layer_uncertain(split, spec, member):
    """The ``[uncertain]`` table of the layer of ``spec`` holding pore fluid ``member``
    (plain key names: the shared ``path``, ``pressure`` and those ``[fluid]`` keys the member's
    fluid uses, and the layer's own), or None where no key applies to it; a layer with the MD
    backend is refused by name."""
    if split is None:
        return None
    if "md" in spec["sections"]["models"]:
        _fail(f"scene section [uncertain] does not apply to a stack whose layer "
              f"{spec['name']!r} runs the MD backend ([layers.models.md]): an MD member takes "
              "minutes, 10^3 members days; remove [uncertain] or that layer's MD model")
    from .scene import _FLUID_KEY_USE

    def applies(plain):
        section, _, key = plain.partition(".")
        if section != "fluid" or key == "salinity":
            return True
        selector, uses = _FLUID_KEY_USE[key]    # the hydrocarbon's keys (or its mixing's)
        return member != "brine" and (selector != "hydrocarbon" or member in uses)

    keys = {plain: split.keys[dotted] for dotted, (layer, plain) in split.where.items()
            if layer in (None, spec["name"]) and applies(plain)}
    if not keys:
        return None
    top = {k: v for k, v in split.top.items() if k != "rank_correlations"}
    return {**top, **keys}


def stack_uncertain(split, layers):
    """The stack's checked ``[uncertain]`` spec over its own key names (the shape
    :func:`rockcem._uncertain_keys.validate_uncertain` gives a plain scene's), from its layers'
    checked specs; empty without ``[uncertain]``."""
    if split is None:
        return {}
    from ._uncertain_keys import _check_correlations     # the check of a plain scene's

    specs = [(layer.name, sub.uncertain) for layer in layers for sub in layer.scenes.values()
             if sub.uncertain]
    first = specs[0][1]
    keys = {}
    for dotted, (layer, plain) in split.where.items():
        keys[dotted] = next(spec["keys"][plain] for name, spec in specs
                            if layer in (None, name) and plain in spec["keys"])
    names = list(keys)
    C = _check_correlations(split.top.get("rank_correlations"), names)
    if C is not None and first["samples"] <= len(names) + 1:
        _fail(f"scene key uncertain.samples = {first['samples']}: rank correlations between "
              f"{len(names)} inputs need more than {len(names) + 1} members")
    return {**{k: first[k] for k in ("samples", "seed", "design", "quantiles", "members")},
            "keys": keys, "correlation": None if C is None else C.tolist(),
            "sensitivity": False}
