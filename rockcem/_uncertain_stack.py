"""Uncertain inputs of a stack of layers (``[[layers]]`` with ``[uncertain]``; issue 32).

Private to the scene loader and runner. A stack's ``[uncertain]`` takes, as a plain scene's
does (``docs/user_guide/scenes.md``, "Uncertain inputs"), numeric keys as distributions: the
stack's shared ``path.*`` and ``pressure.*`` keys, named as in a plain scene, and each layer's
own keys named by the layer, ``"layers.<layer>.<section>.<key>"``::

    [uncertain]
    samples = 200
    seed = 7

    [uncertain."path.gradient"]                      # every layer's path
    distribution = "normal"
    mean = 30.0
    sd = 2.5

    [uncertain."layers.reservoir.sandstone.grain_size"]
    distribution = "lognormal"
    median = 0.3
    sigma = 0.3

    [uncertain."layers.seal.models.hs_gassmann.A"]   # the seal's Krief exponent
    distribution = "uniform"
    lower = 2.5
    upper = 3.5

Checks. Each layer's scene gets an ``[uncertain]`` of its own: the shared keys and its keys
with the layer's prefix removed (``"sandstone.grain_size"``), with the section's ``samples``,
``seed``, ``design`` and ``quantiles``; it is checked there as a plain scene's is
(:func:`rockcem._uncertain_keys.validate_uncertain`: the key's valid range on that layer, the
distribution's share outside it, a key both set by the layer and uncertain). A key the layer's
referenced ``scene`` sets is replaced by its distribution. ``rank_correlations`` are checked
over the stack's keys (:func:`rockcem._uncertain_keys._check_correlations`).

Sampling. One design over all the stack's keys (:func:`rockcem._uncertain.sample_inputs`, in
the order the keys are given): a member is one draw of every key, shared by every layer and
every fluid of the reservoir, so a shared key moves both sides of an interface together.

Evaluation. The members run in chunks of :data:`rockcem._uncertain.CHUNK_MEMBERS`; in a chunk
each layer (and each fluid of the reservoir) is evaluated on all the chunk's members by
:func:`rockcem._uncertain.evaluate_chunk` (its models once on all (member, depth) points where
the pore fluid is one catalogue fluid; member by member otherwise), a layer without uncertain
keys once; the reflectivity of every member is then computed at once
(:func:`rockcem._stack_seismic.reflect`). The Dataset holds the layers' variables and the
reflectivity quantities as quantiles of the members along ``quantile``, as a plain uncertain
scene's, and ``avo_class_probability``: the fraction of the members in each AVO class per
interface, fluid, model and depth along ``avo_class``.

Not in an uncertain stack (refused by name): a layer with the MD backend, ``fluid.*`` keys,
``members = true`` and ``sensitivity = true``. No synthetic seismogram is made (it is not
pointwise in depth: a quantile trace would be no member's trace).
"""

from __future__ import annotations

import difflib
import json
from dataclasses import dataclass

import numpy as np

__all__ = ["CLASS_LABELS", "evaluate_uncertain_stack", "layer_uncertain", "split_uncertain",
           "stack_uncertain"]

#: The labels of the ``avo_class`` dimension of ``avo_class_probability``: the classes of
#: :data:`rockcem.reflectivity.AVO_CLASSES`, then ``none`` (code 0: no class, or no rock on
#: one side), so that the fractions of every depth add up to one.
CLASS_LABELS = ("I", "IIp", "II", "III", "IV", "none")
_SHARED = ("path", "pressure")
_NOT_IN_STACK = {
    "members": "keeping every member is not done for a stack yet (its quantiles and AVO class "
               "probabilities are); run a layer as a plain scene to keep its members",
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


def _fail(message):
    raise ValueError(message)


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
    names = [t.get("name") for t in raw["layers"] if isinstance(t.get("name"), str)]
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
        elif section == "fluid":
            _fail(f"uncertain key {dotted!r}: a stack's [fluid] keys are not sampled yet (the "
                  "fluid is shared by every layer and fluid member); sample them in a plain "
                  "scene")
        else:
            _fail(f"uncertain key {dotted!r} does not name a key of a stack: the shared "
                  f"path.<key> and pressure.<key>, or a layer's as "
                  f"layers.<layer>.<section>.<key> (e.g. {example!r})")
        keys[dotted] = entry
    if not keys:
        _fail(f"scene section [uncertain] names no key: add a table such as "
              f"[uncertain.\"{example}\"] distribution = \"normal\", ...")
    return StackUncertain(top, keys, where)


def layer_uncertain(split, spec):
    """The ``[uncertain]`` table of the layer of ``spec`` (plain key names) or None where no
    key applies to it; a layer with the MD backend is refused by name."""
    if split is None:
        return None
    if "md" in spec["sections"]["models"]:
        _fail(f"scene section [uncertain] does not apply to a stack whose layer "
              f"{spec['name']!r} runs the MD backend ([layers.models.md]): an MD member takes "
              "minutes, 10^3 members days; remove [uncertain] or that layer's MD model")
    keys = {plain: split.keys[dotted] for dotted, (layer, plain) in split.where.items()
            if layer in (None, spec["name"])}
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
    from ._uncertain_keys import _check_correlations

    specs = {layer.name: layer.scenes[next(iter(layer.scenes))].uncertain for layer in layers}
    first = next(s for s in specs.values() if s)
    keys = {}
    for dotted, (layer, plain) in split.where.items():
        source = specs[layer] if layer is not None else first
        keys[dotted] = source["keys"][plain]
    names = list(keys)
    C = _check_correlations(split.top.get("rank_correlations"), names)
    if C is not None and first["samples"] <= len(names) + 1:
        _fail(f"scene key uncertain.samples = {first['samples']}: rank correlations between "
              f"{len(names)} inputs need more than {len(names) + 1} members")
    return {**{k: first[k] for k in ("samples", "seed", "design", "quantiles", "members")},
            "keys": keys, "correlation": None if C is None else C.tolist(),
            "sensitivity": False}


# ----------------------------------------------------------------------------- evaluation
def _layer_values(scene, values):
    """``{layer name: {plain key: ndarray}}``: each layer's share of the members' values."""
    out = {layer.name: {} for layer in scene.layers}
    for dotted, v in values.items():
        section, _, rest = dotted.partition(".")
        if section == "layers":
            layer, _, plain = rest.partition(".")
            out[layer][plain] = v
        else:
            for layer in out:
                out[layer][dotted] = v
    return out


def _fixed(sub, m):
    """A layer without uncertain keys: its one run as ``m`` identical members."""
    from .runner import evaluate

    ds = evaluate(sub)
    data = {name: (var.dims, np.broadcast_to(var.values, (m,) + var.shape))
            for name, var in ds.data_vars.items()}
    lines = [w for w in ds.attrs.get("validity_warnings", "").split("\n") if w]
    return data, [lines] * m


def stack_chunk(scene, values):
    """Evaluate one chunk of an uncertain stack's members.

    Parameters
    ----------
    scene : Scene
        The stack, with ``[uncertain]``.
    values : dict
        ``{stack dotted key: ndarray (m,)}``, the chunk's members.

    Returns
    -------
    layers : dict
        ``{(layer, fluid member): ({name: (dims, ndarray (m, ...))}, warnings per member)}``
        (:func:`rockcem._uncertain.evaluate_chunk`).
    seismic : dict
        With ``[seismic]``: the variables of :func:`rockcem._stack_seismic.reflect`, each
        ndarray (m, interface, fluid, model, depth[, angle]); empty without it.
    """
    from ._stack_dataset import side_arrays
    from ._stack_seismic import _angles, reflect
    from ._uncertain import evaluate_chunk
    from .validation import prefixed_errors

    m = len(next(iter(values.values())))
    shares = _layer_values(scene, values)
    layers = {}
    for layer in scene.layers:
        for member, sub in layer.scenes.items():
            with prefixed_errors(f"layer {layer.name!r}"
                                 + (f" with {member}" if member != "brine" else "")):
                layers[layer.name, member] = evaluate_chunk(sub, shares[layer.name]) \
                    if sub.uncertain else _fixed(sub, m)
    seismic = {}
    if "seismic" in scene.sections:
        sides = side_arrays(scene, {key: {n: data[n][1] for n in ("vp", "vs", "density")}
                                    for key, (data, _w) in layers.items()})
        s = scene.sections["seismic"]
        seismic = reflect(sides, _angles(s), s["class_threshold"])
    return layers, seismic


def _run_chunks(scene, values, scheduler, progress):
    """Every member of ``values`` through :func:`stack_chunk`, in chunks, serially or on dask:
    ``(layers, seismic)`` as it returns them over all N members. Refused before the run
    where the members' values would take more than :data:`rockcem._uncertain.MAX_UNCERTAIN_BYTES`
    (measured on one member)."""
    from ._uncertain import CHUNK_MEMBERS, MAX_UNCERTAIN_BYTES

    N = len(next(iter(values.values())))
    one_layers, one_seismic = stack_chunk(scene, {k: v[:1] for k, v in values.items()})
    arrays = [a for data, _w in one_layers.values() for _d, a in data.values()] + \
        [a for k, a in one_seismic.items() if k != "missing"]
    per_member = sum(np.asarray(a).size for a in arrays)
    if 8 * per_member * N > MAX_UNCERTAIN_BYTES:
        _fail(f"scene [uncertain]: {N} members of a stack of {per_member} values each take "
              f"{8 * per_member * N / 2 ** 30:.3g} GiB, above "
              f"{MAX_UNCERTAIN_BYTES / 2 ** 30:g} GiB; lower uncertain.samples, raise "
              "path.depth_step or seismic.angle_step")
    bounds = list(range(0, N, CHUNK_MEMBERS)) + [N]
    chunks = [{k: v[a:b] for k, v in values.items()} for a, b in zip(bounds, bounds[1:])]
    layers = {key: ({name: (dims, np.empty((N,) + np.shape(a)[1:], dtype=np.asarray(a).dtype))
                     for name, (dims, a) in data.items()}, [None] * N)
              for key, (data, _w) in one_layers.items()}
    seismic = {k: np.empty((N,) + a.shape[1:], dtype=a.dtype)
               for k, a in one_seismic.items() if k != "missing"}
    missing = [0, 0]

    def put(index, part):
        lo, hi = bounds[index], bounds[index + 1]
        for key, (data, warnings) in part[0].items():
            for name, (_dims, a) in data.items():
                layers[key][0][name][1][lo:hi] = a
            layers[key][1][lo:hi] = warnings
        for k, a in part[1].items():
            if k == "missing":
                missing[0] += a[0]
                missing[1] += a[1]
            else:
                seismic[k][lo:hi] = a

    for index, part in _chunk_results(scene, chunks, scheduler, progress):
        put(index, part)
    if seismic:
        seismic["missing"] = tuple(missing)
    return layers, seismic


def _chunk_results(scene, chunks, scheduler, progress):
    """``(index, stack_chunk(scene, chunks[index]))`` for every chunk, serially in order or
    on dask (one task a chunk, each result released once read)."""
    if scheduler is None:
        indices = range(len(chunks))
        if progress:
            from tqdm.auto import tqdm

            indices = tqdm(indices, desc=scene.name, unit="chunk")
        for index in indices:
            yield index, stack_chunk(scene, chunks[index])
        return
    from ._scheduler import dask_client

    with dask_client(scheduler, 2, what="running an uncertain stack's members on dask") as client:
        futures = client.map(stack_chunk, [scene] * len(chunks), chunks, pure=False)
        if progress:
            from dask.distributed import progress as dask_progress

            dask_progress(futures)
        for index, future in enumerate(futures):
            yield index, future.result()
            future.release()


def evaluate_uncertain_stack(scene, *, scheduler=None, progress=False):
    """Run the members of a stack with ``[uncertain]``: one Dataset of quantiles and AVO class
    probabilities.

    The layers' variables (dims ``quantile, layer[, fluid][, model], depth``) and, with
    ``[seismic]``, ``avo_intercept``, ``avo_gradient``, ``avo_curvature`` (``quantile,
    interface, fluid, model, depth``), ``reflectivity_pp`` and ``reflectivity_pp_magnitude``
    (``angle`` last) are the sample quantiles of the members (``numpy.quantile``, linear,
    Hyndman & Fan 1996 type 7), each taken separately at each layer, fluid, model, depth and
    angle. ``avo_class_probability`` (``avo_class, interface, fluid, model, depth``) is the
    fraction of the members in each class of :data:`CLASS_LABELS`: the classes of
    :func:`rockcem.reflectivity.avo_class` (Rutherford & Williams 1989; Ross & Kinman 1995;
    Castagna & Swan 1997) and ``none``; the fractions of each depth add up to one.

    Parameters
    ----------
    scene : Scene
        A stack scene with ``[uncertain]``.
    scheduler : None, "local" or str, keyword-only
        Where the chunks of members run, as a plain uncertain scene's
        (:func:`rockcem.scene.run_scene`): serially, or one dask task a chunk.
    progress : bool, keyword-only
        Show a progress bar over the chunks.

    Returns
    -------
    xarray.Dataset
        The stack's Dataset: quantiles along ``quantile``, class fractions along
        ``avo_class``, the layers' validity warnings counting the members they concern.

    Raises
    ------
    ValueError
        A member outside a model's range (naming the layer and the member's sampled inputs),
        or a run whose members would take more than 4 GiB of memory.
    """
    import xarray as xr

    from ._stack_dataset import join_layers
    from ._stack_seismic import ANGLE_ATTRS, _angles, _cite, seismic_attrs
    from ._uncertain import (QUANTILE_ATTRS, _merge_member_warnings, _uncertain_attrs,
                             member_names, sample_inputs)
    from .runner import _global_attrs
    from .variables import no_coordinate_fill

    spec = scene.uncertain
    values = sample_inputs(spec)
    N = spec["samples"]
    q = np.asarray(spec["quantiles"])
    layers, seismic = _run_chunks(scene, values, scheduler, progress)
    depth = _depth(scene.layers[0].scenes[next(iter(scene.layers[0].scenes))])
    per_quantile = []
    for i in range(q.size):
        runs = {}
        for layer in scene.layers:
            for member, sub in layer.scenes.items():
                data, warnings = layers[layer.name, member]
                attrs = {"references": _global_attrs(sub)["references"]}
                lines = _merge_member_warnings(warnings, N)
                if lines:
                    attrs["validity_warnings"] = "\n".join(lines)
                coords = {"depth": ("depth", depth)}
                if any("model" in dims for dims, _a in data.values()):
                    coords["model"] = ("model", np.array(sub.models, dtype=object))
                runs[layer.name, member] = xr.Dataset(
                    {name: (dims, np.quantile(np.asarray(a, dtype=float), q[i], axis=0))
                     for name, (dims, a) in data.items()}, coords=coords, attrs=attrs)
        per_quantile.append(join_layers(scene, runs))
    ds = per_quantile[0]
    for name in list(ds.data_vars):
        var = ds[name]
        if "depth" not in var.dims or var.dtype.kind not in "fiub":
            continue
        attrs = dict(var.attrs)
        attrs.pop("flag_values", None)
        attrs.pop("flag_meanings", None)
        attrs["cell_methods"] = "member: quantile"
        stacked = np.stack([np.asarray(d[name].values, dtype=float) for d in per_quantile])
        ds[name] = xr.Variable(("quantile",) + var.dims, stacked, attrs=attrs)
    ds.coords["quantile"] = ("quantile", q, dict(QUANTILE_ATTRS))
    if seismic:
        _add_seismic_quantiles(ds, scene, seismic, q, ANGLE_ATTRS, _angles, seismic_attrs)
        _cite(ds, ["AvsethLehocki2016", "Zoeppritz1919", "AkiRichards1980", "Shuey1985",
                   "RutherfordWilliams1989", "RossKinman1995", "CastagnaSwan1997"])
    ds.attrs.update(_uncertain_attrs(scene, member_names(scene)))
    ds.attrs["uncertain"] += ("; one draw of every key per member, shared by every layer and "
                              "every fluid of the reservoir; no synthetic seismogram")
    ds.attrs["uncertain_json"] = json.dumps(spec, sort_keys=True)
    return no_coordinate_fill(ds)


def _depth(sub):
    """The depth axis of a layer's scene (the same for every member)."""
    from .runner import _Pipeline

    pipe = _Pipeline(sub)
    return pipe.now(pipe.path.depth)


def _add_seismic_quantiles(ds, scene, seismic, q, angle_attrs, angles_of, attrs_of):
    """The quantiles of the members' reflectivity and the fraction of them in each class."""
    import xarray as xr

    from .reflectivity import AVO_CLASS_CODES

    s = scene.sections["seismic"]
    ds.coords["angle"] = ("angle", angles_of(s), angle_attrs)
    attrs = attrs_of(seismic.pop("missing"), s["class_threshold"])
    dims = ("interface", "fluid", "model", "depth")
    codes = seismic.pop("avo_class")
    for name, a in seismic.items():
        extra = ("angle",) if a.ndim > len(dims) + 1 else ()
        ds[name] = xr.Variable(("quantile",) + dims + extra, np.quantile(a, q, axis=0),
                               attrs={**attrs[name], "cell_methods": "member: quantile"})
    meaning = attrs["avo_class"]
    codes_of = tuple(AVO_CLASS_CODES) + (0,)
    fraction = np.stack([np.mean(codes == c, axis=0) for c in codes_of])
    ds.coords["avo_class"] = ("avo_class", np.array(CLASS_LABELS, dtype=object), {
        "long_name": "AVO class (Rutherford & Williams 1989; Ross & Kinman 1995; Castagna & "
                     "Swan 1997); none: no class, or no rock on one side"})
    ds.coords["avo_class_code"] = ("avo_class", np.array(codes_of, dtype=np.int8), {
        "long_name": "code of the AVO class (rockcem.reflectivity.AVO_CLASS_CODES; 0 none)"})
    ds["avo_class_probability"] = xr.Variable(("avo_class",) + dims, fraction, attrs={
        "units": "1",
        "long_name": "fraction of the members in the AVO class",
        "cell_methods": "member: mean",
        "threshold": meaning["threshold"],
        "comment": "the fraction of the uncertain members whose interface falls in each class "
                   "(the class of rockcem.reflectivity.avo_class, intercept threshold "
                   f"{meaning['threshold']:g}); the fractions add up to one at every "
                   "interface, fluid, model and depth",
        "missing_inputs": meaning["missing_inputs"]})
