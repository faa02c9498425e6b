"""The Dataset of a stack scene (:mod:`rockcem._scene_stack`): the layers evaluated and joined.

Private to the scene runner. Each layer is run as its plain scene (:func:`rockcem.runner.evaluate`;
the reservoir once per fluid), and the runs joined: the layers' variables with a ``layer``
dimension (and ``fluid`` where the fluid changes them), the ``interface`` coordinate with
``upper_layer`` and ``lower_layer``, ``model_of_layer`` (which of a layer's models gives its side
at each model: the model itself or its ``stand_in``) and, with thicknesses, the synthetic
column. :func:`interface_properties` gives both sides of every interface.
"""

from __future__ import annotations

import datetime
import json
from typing import NamedTuple

import numpy as np

__all__ = ["InterfaceProperties", "evaluate_stack", "interface_properties", "join_layers",
           "joined", "side_arrays"]

#: Variables that change with the reservoir's pore fluid (the ``fluid`` dimension).
_FLUID_VARIABLES = ("K_sat", "G_sat", "vp", "vs", "density", "fluid_density",
                    "fluid_bulk_modulus", "fluid_velocity", "hydrocarbon_saturation")


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


# ----------------------------------------------------------------------------- evaluation
def evaluate_stack(scene, *, scheduler=None, jobs=1, progress=False):
    """The Dataset of a stack scene: each layer evaluated as its plain scene on the stack's
    path (:func:`rockcem.runner.evaluate`), the reservoir once per fluid, joined along
    ``layer`` and ``fluid``; the interfaces and, with thicknesses, the synthetic column.

    A layer with the MD backend runs it on ``scheduler`` / ``jobs``; its stage files lie in
    ``<stack output stem>_<layer>_md_work`` (or the layer's ``models.md.workdir``), shared by
    its fluid members: the MD frame does not depend on the pore fluid (it enters by Gassmann),
    so the second and later fluids read the first one's stages instead of running again."""
    import dataclasses
    from pathlib import Path

    from .runner import evaluate
    from .validation import prefixed_errors

    runs = {}
    for layer in scene.layers:
        for member, sub in layer.scenes.items():
            with prefixed_errors(f"layer {layer.name!r}"
                                 + (f" with {member}" if member != "brine" else "")):
                if "md" in sub.models:
                    out = Path(scene.output)
                    sub = dataclasses.replace(
                        sub, output=str(out.with_name(f"{out.stem}_{layer.name}{out.suffix}")))
                runs[layer.name, member] = evaluate(sub, scheduler=scheduler, jobs=jobs,
                                                    progress=progress)
    return join_layers(scene, runs)


def join_layers(scene, runs):
    """The stack's Dataset from its layers' runs: ``runs`` maps ``(layer name, fluid member)``
    to the layer's Dataset for that member (its dims ``[model,] depth``); the joined
    variables, the interfaces, ``model_of_layer`` and, with thicknesses, the column."""
    stack = scene.sections["stack"]
    fluids = list(stack["fluids"])
    first = runs[scene.layers[0].name, next(iter(scene.layers[0].scenes))]
    depth = first["depth"].values
    models = list(scene.models)
    names = [layer.name for layer in scene.layers]

    def member_ds(layer, f):
        return runs[layer.name, f if f in layer.scenes else "brine"]

    variables = list(dict.fromkeys(v for ds in runs.values() for v in ds.data_vars))
    data = {}
    for name in variables:
        data[name] = joined(name, scene.layers, fluids, models, member_ds)
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


def joined(name, layers, fluids, models, member_ds):
    """One variable of every layer: dims (layer[, fluid][, model], depth), NaN where a layer
    does not have it (a shale's cement) or the model. ``member_ds(layer, fluid)`` gives the
    layer's Dataset for the fluid; a variable of it with dims ``[model,] ...`` (``depth``, or
    ``member, depth`` for the members of an uncertain stack) keeps the dims after ``model``
    (``tail``) as they are."""
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
    tail = tuple(d for d in present[0].dims if d != "model")
    shape = (len(layers),) + ((len(fluids),) if by_fluid else ()) + \
        ((len(models),) if per_model else ()) + tuple(present[0].sizes[d] for d in tail)
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
                        target[k] = ds[name].sel(model=m).transpose(*tail).values
            else:
                target[...] = ds[name].transpose(*tail).values
    dims = ("layer",) + (("fluid",) if by_fluid else ()) + (("model",) if per_model else ()) \
        + tail
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


def side_arrays(scene, values):
    """Both sides of every interface of a stack from its layers' raw arrays (the members of an
    uncertain stack, :mod:`rockcem._uncertain_stack`), as :func:`interface_properties` pairs
    them from a Dataset.

    Parameters
    ----------
    scene : Scene
        The stack.
    values : dict
        ``{(layer name, fluid member): {"vp": ndarray (m, layer models, depth), "vs": ...,
        "density": ndarray (m, depth)}}``, the layer's models in its scene's order.

    Returns
    -------
    list of ndarray
        ``[vp1, vs1, rho1, vp2, vs2, rho2]``, each (m, interface, fluid, model, depth).
    """
    fluids = list(scene.sections["stack"]["fluids"])
    per_layer = {name: [] for name in ("vp", "vs", "density")}
    for layer in scene.layers:
        own = list(layer.scenes[next(iter(layer.scenes))].models)
        columns = [own.index(m if m in own else layer.stand_in) for m in scene.models]
        for name in per_layer:
            rows = []
            for f in fluids:
                a = np.asarray(values[layer.name, f if f in layer.scenes else "brine"][name],
                               dtype=float)
                rows.append(a[:, columns, :] if a.ndim == 3 else
                            np.repeat(a[:, None, :], len(columns), axis=1))
            per_layer[name].append(np.stack(rows, axis=1))          # m, fluid, model, depth
    out = []
    for end in (slice(None, -1), slice(1, None)):
        for name in ("vp", "vs", "density"):
            out.append(np.stack(per_layer[name][end], axis=1))
    return out


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
