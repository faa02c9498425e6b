"""Uncertain inputs of a stack of layers (``[[layers]]`` with ``[uncertain]``; issue 32).

Private to the scene loader and runner. A stack's ``[uncertain]`` takes, as a plain scene's
does (``docs/user_guide/scenes.md``, "Uncertain inputs"), numeric keys as distributions: the
stack's shared ``path.*``, ``pressure.*`` and ``fluid.*`` keys, named as in a plain scene,
and each layer's own keys named by the layer, ``"layers.<layer>.<section>.<key>"``. A
``[fluid]`` key goes to the layers and fluids that use it: ``fluid.salinity`` to every layer's
brine, the hydrocarbon's keys (``fluid.saturation``, ``fluid.gas_gravity``, ...) to the
reservoir's members with that hydrocarbon::

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

Checks (:mod:`rockcem._scene_stack`, when the scene is loaded). Each layer's scene gets an
``[uncertain]`` of its own: the shared keys and its keys with the layer's prefix removed
(``"sandstone.grain_size"``), with the section's ``samples``, ``seed``, ``design`` and
``quantiles``; it is checked there as a plain scene's is
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

With ``members = true`` every member is kept too, as ``<name>_members`` (dimension ``member``
first; ``avo_class_members`` the class codes), with the sampled inputs as ``member``
coordinates.

Not in an uncertain stack (refused by name): a layer with the MD backend and
``sensitivity = true``. No synthetic seismogram is made (it is not
pointwise in depth: a quantile trace would be no member's trace).
"""

from __future__ import annotations

import json

import numpy as np

__all__ = ["CLASS_LABELS", "evaluate_uncertain_stack", "stack_chunk"]

#: The labels of the ``avo_class`` dimension of ``avo_class_probability``: the classes of
#: :data:`rockcem.reflectivity.AVO_CLASSES`, then ``none`` (code 0: no class, or no rock on
#: one side), so that the fractions of every depth add up to one.
CLASS_LABELS = ("I", "IIp", "II", "III", "IV", "none")



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
                own = {k: v for k, v in shares[layer.name].items()
                       if k in sub.uncertain.get("keys", {})}
                layers[layer.name, member] = evaluate_chunk(sub, own) if own else _fixed(sub, m)
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
    Castagna & Swan 1997) and ``none``; the fractions of each depth add up to one. With
    ``members = true`` every member too, as ``<name>_members`` (``member`` first), and the
    sampled inputs as ``member`` coordinates (:func:`_member_names`).

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
    from ._uncertain import (QUANTILE_ATTRS, _input_attrs, _merge_member_warnings,
                             _uncertain_attrs, sample_inputs)
    from .runner import _global_attrs
    from .variables import no_coordinate_fill

    spec = scene.uncertain
    values = sample_inputs(spec)
    N = spec["samples"]
    q = np.asarray(spec["quantiles"])
    layers, seismic = _run_chunks(scene, values, scheduler, progress)
    axis = _depth_coords(scene.layers[0].scenes[next(iter(scene.layers[0].scenes))])
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
                coords = dict(axis)
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
        _add_seismic_quantiles(ds, scene, dict(seismic), q, ANGLE_ATTRS, _angles,
                               seismic_attrs)
        _cite(ds, ["AvsethLehocki2016", "Zoeppritz1919", "AkiRichards1980", "Shuey1985",
                   "RutherfordWilliams1989", "RossKinman1995", "CastagnaSwan1997"])
    names = _member_names(scene, ds)
    if spec["members"]:
        _add_members(ds, scene, layers, seismic, axis)
        ds.coords["member"] = ("member", np.arange(N), {
            "long_name": "member of the uncertain inputs"})
        for dotted, name in names.items():
            ds.coords[name] = ("member", values[dotted],
                               _input_attrs(dotted, spec["keys"][dotted]))
    ds.attrs.update(_uncertain_attrs(scene, names))
    ds.attrs["uncertain"] += ("; one draw of every key per member, shared by every layer and "
                              "every fluid of the reservoir; no synthetic seismogram")
    ds.attrs["uncertain_json"] = json.dumps(spec, sort_keys=True)
    return no_coordinate_fill(ds)


def _member_names(scene, ds):
    """The ``member`` coordinate name of each uncertain key: the key (``grain_size``); where
    two keys share it, or a variable of ``ds`` has it, the layer's name and the key's
    section before it (``seal_hs_gassmann_A``; ``fluid_saturation``)."""
    keys = list(scene.uncertain["keys"])
    short = [k.rpartition(".")[2] for k in keys]
    out = {}
    for dotted, name in zip(keys, short):
        if short.count(name) > 1 or name in ds.variables or name in ("member", "quantile"):
            parts = dotted.split(".")
            name = "_".join(p for p in parts[1:] if p != "models") if parts[0] == "layers" \
                else "_".join(parts)
        out[dotted] = name
    return out


def _add_members(ds, scene, layers, seismic, axis):
    """Every member as ``<name>_members`` (dimension ``member`` first): the layers' variables
    joined as :func:`rockcem._stack_dataset.join_layers` joins one run, and the reflectivity
    of :func:`rockcem._stack_seismic.reflect` (``avo_class_members`` with its CF flags)."""
    import xarray as xr

    from ._stack_dataset import joined
    from ._stack_seismic import seismic_attrs

    fluids, models = list(scene.sections["stack"]["fluids"]), list(scene.models)
    runs = {}
    for layer in scene.layers:
        for member, sub in layer.scenes.items():
            data, _warnings = layers[layer.name, member]
            coords = dict(axis)
            if any("model" in dims for dims, _a in data.values()):
                coords["model"] = ("model", np.array(sub.models, dtype=object))
            runs[layer.name, member] = xr.Dataset(
                {name: (("member",) + dims, a) for name, (dims, a) in data.items()},
                coords=coords)

    def member_ds(layer, fluid):
        return runs[layer.name, fluid if fluid in layer.scenes else "brine"]

    for name in dict.fromkeys(v for run in runs.values() for v in run.data_vars):
        dims, a = joined(name, scene.layers, fluids, models, member_ds)
        at = dims.index("member")
        attrs = {**ds[name].attrs, "cell_methods": "member: point"}
        ds[f"{name}_members"] = xr.Variable(
            ("member",) + dims[:at] + dims[at + 1:], np.moveaxis(a, at, 0), attrs=attrs)
    if not seismic:
        return
    attrs = seismic_attrs(seismic["missing"], scene.sections["seismic"]["class_threshold"])
    dims = ("member", "interface", "fluid", "model", "depth")
    for name, a in seismic.items():
        if name != "missing":
            ds[f"{name}_members"] = xr.Variable(dims + (("angle",) if a.ndim > 5 else ()), a,
                                                attrs={**attrs[name],
                                                       "cell_methods": "member: point"})


def _depth_coords(sub):
    """The depth axis of a layer's scene (the same for every member), and the horizons' names
    along it for a table of horizons."""
    from .runner import _Pipeline

    pipe = _Pipeline(sub)
    coords = {"depth": ("depth", pipe.now(pipe.path.depth))}
    if sub.sections["path"]["kind"] == "horizons":
        coords["horizon"] = ("depth", pipe.history.horizon.astype(object))
    return coords


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
        "long_name": "code of the AVO class (rockcem.reflectivity.AVO_CLASS_CODES; 0 none)",
        "units": "1"})
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
