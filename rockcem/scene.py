"""Scenes: a burial scene described once (TOML or Python), validated, and run to one Dataset.

A scene names its lithology, burial path, diagenetic parameters, materials, petro-elastic models
and output variables. :func:`run_scene` evaluates exactly that — a shale scene never touches the
quartz-cement kinetics, one model asked means one model computed, nothing imports numba — and
returns an ``xarray.Dataset`` (dimension ``depth``, plus ``model`` for model-dependent variables
and one dimension per swept parameter). :func:`write_dataset` writes it atomically.

The schema, with every default and unit, is :data:`SCHEMA`; ``rockcem scenes`` lists the shipped
scenes (``datasets/scenes/``). See ``datasets/scenes/carcione2022_sandstone.toml`` for a full
example.

Burial paths: ``[path] kind = "linear"`` (the linear basin model, the default), ``"horizons"``
(one history per horizon from a table, e.g. a basin-model export; the depth axis is the
horizons' present-day depths) or ``"nodes"`` (one history every depth follows); tables as a CSV
file (``table``) or inline arrays, see :mod:`rockcem.histories`.

Stacks: a scene with ``[[layers]]`` (and ``[stack]``) is several lithologies buried by one
path, a seal over a reservoir; :mod:`rockcem._scene_stack` describes its keys,
:mod:`rockcem._stack_dataset` its Dataset, and :func:`interface_properties` gives both sides
of its interfaces.

Scene calibrations: a top-level ``calibration = "<file>"`` names a calibration file with
``model = "scene"`` (written by ``rockcem fit``, :mod:`rockcem.wellfit`) whose ``[parameters]``
set ``"section.key"`` values (:func:`rockcem.calibrate.apply_scene_calibration`).

Calibrated parameters: ``[models.patchy_cement] calibration = "<file>"`` names a calibration file
(TOML, format ``rockcem-calibration/1``, written by :func:`md.calibrate.write_calibration` or
:func:`rockcem.calibrate.write_calibration`; see ``datasets/calibrations/README.md``) — a path
relative to the scene file (then to the working directory), or the name of a shipped one in
``datasets/calibrations/``. Its ``[parameters]`` set the model's parameters; a parameter the
model does not have, or one the scene sets as well, is an error. The Dataset records the
calibration used in its attributes ``calibration`` and ``calibration_json``.
"""

from __future__ import annotations

import copy
import difflib
import json
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._atomic import check_scene_name
from ._data import data_path
from ._stack_dataset import InterfaceProperties, interface_properties
from .variables import MODEL_OUTPUTS
from ._toml import toml_text, toml_value
from .variables import sweep_dimension

__all__ = ["SCHEMA", "Scene", "load_scene", "scene_from_dict", "scene_path", "shipped_scenes",
           "run_scene", "write_dataset", "MAX_SWEEP_MEMBERS", "sweep_size", "MODEL_OUTPUTS",
           "STATE_OUTPUTS", "FLUID_OUTPUTS", "CALIBRATED_MODELS", "interface_properties",
           "InterfaceProperties"]

_REQUIRED = object()

#: Every scene key: ``{section: {key: (default, type, unit, description)}}``; ``_REQUIRED``
#: marks keys without a default; type is "number", "integer", "string" or "strings". The
#: ``models`` section holds one table per model label.
SCHEMA: dict[str, dict[str, tuple]] = {
    "scene": {
        "name": (_REQUIRED, "string", "", "scene name, a plain file name (output <name>.nc)"),
        "description": ("", "string", "", "free text"),
        "lithology": (_REQUIRED, "string", "", "'sandstone' or 'shale'"),
        "outputs": (None, "strings", "",
                    "variables to compute and write (default: all for the lithology)"),
        "output": (None, "string", "", "netCDF file to write (default: <name>.nc)"),
        "calibration": (None, "string", "", "scene calibration file (rockcem fit) whose "
                        "[parameters] set 'section.key' values"),
    },
    "path": {
        "kind": ("linear", "string", "",
                 "'linear': the linear basin model of Carcione et al. 2022, eq. 2; 'horizons': "
                 "a table of histories, one per horizon; 'nodes': one history every depth "
                 "follows (rockcem.histories)"),
        "gradient": (30.0, "number", "degC/km", "geothermal gradient G"),
        "sedimentation_rate": (40.0, "number", "m/Myr", "burial rate S (or give heating_rate)"),
        "heating_rate": (None, "number", "degC/Myr", "H = G S; if given, S = H / G"),
        "surface_temperature": (15.0, "number", "degC", "T0"),
        "max_depth": (5000.0, "number", "m", "deepest depth of the profile"),
        "depth_step": (10.0, "number", "m", "depth resolution of the profile"),
        "table": (None, "string", "", "horizons/nodes: CSV file of the history, units in the "
                  "header (relative to the scene file)"),
        "horizon": (None, "strings", "", "horizons, inline: horizon name of each row"),
        "time": (None, "numbers", "Myr", "inline: time before present (horizons) or since "
                 "deposition (nodes) of each row"),
        "depth": (None, "numbers", "m", "inline: depth below the sediment surface of each row"),
        "temperature": (None, "numbers", "degC", "inline: temperature of each row"),
    },
    "pressure": {
        "sediment_density": (2.5, "number", "g/cm3",
                             "mean sediment density for the lithostatic pressure"),
        "water_density": (1.04, "number", "g/cm3", "water density for the hydrostatic pressure"),
    },
    "sandstone": {
        "porosity0": (0.36, "number", "1", "initial (critical) porosity"),
        "grain_size": (0.3, "number", "mm", "grain diameter D"),
        "quartz_fraction": (0.65, "number", "1", "detrital quartz fraction f"),
        "clay_coating": (0.0, "number", "1", "clay-coating factor"),
        "igv_final": (0.2, "number", "1", "IGV at infinite effective pressure"),
        "beta": (0.01, "number", "1/MPa", "compaction coefficient of eq. B.7"),
        "start_temperature": (None, "number", "degC", "no quartz cement below this temperature"),
    },
    "shale": {
        "porosity0": (0.35, "number", "1", "porosity at zero effective pressure (Athy)"),
        "beta": (0.01, "number", "1/MPa", "Athy coefficient"),
        "r0": (0.99, "number", "1", "initial smectite fraction of the clay"),
        "order": (5.0, "number", "", "reaction order n"),
        "activation_energy": (36.0, "number", "kcal/mol", "E"),
        "frequency_factor": (1.217e23, "number", "1/Myr", "c"),
    },
    "materials": {
        "grain": ("quartz", "string", "", "sandstone grain mineral (catalogue name)"),
        "cement": ("quartz_cement", "string", "", "sandstone cement mineral"),
        "smectite": ("smectite", "string", "", "shale smectite mineral"),
        "illite": ("illite", "string", "", "shale illite mineral"),
        "fluid": ("water", "string", "", "pore fluid"),
    },
    "fluid": {
        "model": ("constant", "string", "",
                  "'constant': the catalogue fluid materials.fluid at every depth (the sources' "
                  "water); 'batzle_wang': brine from each depth's temperature and pore pressure "
                  "(Batzle & Wang 1992)"),
        "salinity": (None, "number", "1", "batzle_wang: NaCl mass fraction of the brine, in "
                     "[0, 0.35) (default 0)"),
        "hydrocarbon": ("none", "string", "",
                        "'none', or the hydrocarbon sharing the pores with the brine: 'gas' "
                        "(Batzle & Wang), 'oil' (Batzle & Wang), 'co2' (Span-Wagner) or "
                        "'methane' (Setzmann-Wagner; co2 and methane need the fluids extra)"),
        "saturation": (None, "number", "1", "hydrocarbon saturation of the pore space in the "
                       "interval, in [0, 1] (required with a hydrocarbon)"),
        "mixing": ("wood", "string", "",
                   "'wood': uniform, Wood's fluid in each model; 'brie': Brie's fluid of "
                   "exponent brie_exponent; 'patchy': patches of brine and of hydrocarbon, each "
                   "model run with each, P-wave moduli averaged (White's patchy limit)"),
        "brie_exponent": (None, "number", "", "mixing = 'brie': exponent e, in [1, 40] "
                          "(default 3)"),
        "top": (None, "number", "m", "top of the hydrocarbon interval (default: the surface)"),
        "base": (None, "number", "m", "base of the hydrocarbon interval (default: the deepest "
                 "depth)"),
        "gas_gravity": (None, "number", "1", "gas (and live oil's dissolved gas): gravity "
                        "relative to air, in [0.5, 2] (default 0.6)"),
        "oil_api": (None, "number", "degAPI", "oil: API gravity, in [0, 150] (default 30)"),
        "gas_oil_ratio": (None, "number", "L/L", "oil: dissolved gas, litres of gas per litre of "
                          "oil, >= 0 (default 0: dead oil)"),
    },
    "stack": {
        "fluids": (["brine"], "strings", "",
                   "a stack: the pore fluids of the reservoir layer, one member of the fluid "
                   "dimension each: 'brine' (that of [fluid] model) and the hydrocarbons of "
                   "fluid.hydrocarbon ('gas', 'oil', 'co2', 'methane') at fluid.saturation, "
                   "at every depth"),
        "reservoir": (None, "string", "",
                      "a stack: the name of the layer whose pores hold the fluids (required "
                      "with a hydrocarbon among fluids); every other layer holds brine"),
    },
    "seismic": {
        "max_angle": (40.0, "number", "degree", "a stack: largest angle of incidence of the "
                      "reflectivity and the angle gather, in (0, 90)"),
        "angle_step": (1.0, "number", "degree", "a stack: step of the angles of incidence from "
                       "0, > 0"),
        "class_threshold": (None, "number", "1", "a stack: largest |intercept| of a near-zero "
                            "contrast (AVO classes IIp and II), in (0, 1) (default "
                            "rockcem.reflectivity.AVO_THRESHOLD, 0.03)"),
        "frequency": (25.0, "number", "Hz", "a stack: peak frequency of the Ricker wavelet of "
                      "the synthetics, > 0"),
        "wavelet": (None, "string", "", "a stack: a CSV file of the user's wavelet for the "
                    "synthetics instead of the Ricker (two columns, time in s and amplitude, "
                    "sampled at dt with a sample at time 0; relative to the scene file)"),
        "dt": (0.002, "number", "s", "a stack: sample interval of the synthetics, in "
               "[1e-5, 0.05]"),
        "gather_depth": (None, "number", "m", "a stack with thicknesses: depth of the column's "
                         "angle gather (default: the top of its second layer)"),
    },
    "layers": {
        "name": (_REQUIRED, "string", "", "a stack ([[layers]], top to bottom): the layer's "
                 "name (letters, digits, '_' and '-'; unique)"),
        "scene": (None, "string", "", "a shipped scene's name or a scene file (relative to "
                  "the stack's file) whose lithology, lithology section, [materials] and "
                  "[models] the layer takes; its path, pressure, fluid and sweep are replaced "
                  "by the stack's"),
        "lithology": (None, "string", "", "'sandstone' or 'shale' (required without scene)"),
        "thickness": (None, "number", "m", "thickness in the synthetic column (every layer "
                      "but the last, which fills the column to the deepest depth)"),
        "stand_in": (None, "string", "", "one of the layer's models that gives its side of "
                     "the interfaces for a model another layer has and it lacks"),
        "outputs": (None, "strings", "", "the layer's variables (default: all for its "
                    "lithology; vp, vs and density always)"),
    },
    "models.hs_gassmann": {
        "A": (3.0, "number", "", "Krief exponent"),
    },
    "models.self_consistent": {
        "aspect_ratio": (_REQUIRED, "number", "",
                         "pore aspect ratio (0.17 shale, 0.108 sandstone)"),
        "tol": (1e-12, "number", "", "Newton tolerance"),
        "engine": ("numpy", "string", "",
                   "solver: numpy (never imports numba), auto (numba kernel from 5e4 points "
                   "on, ~15x faster there) or numba"),
    },
    "models.generalized_gassmann": {
        "A": (3.0, "number", "", "Krief exponent"),
    },
    "models.patchy_cement": {
        "coordination_number": (9.0, "number", "", "C"),
        "contact_cement_limit": (0.05, "number", "1", "phi_p0, most cement at contacts"),
        "delta": (100.0, "number", "MPa", "bonding pre-stress"),
        "scheme": (1, "integer", "", "1: cement at contacts (eq. 16), 2: coating (eq. 18)"),
        "thickness": (0.0, "number", "1", "MCCT contact thickness"),
        "f": (1.0, "number", "1", "Hertz-Mindlin no-slip fraction"),
        "calibration": (None, "string", "",
                        "calibration file or shipped name whose [parameters] set the keys "
                        "above (datasets/calibrations/README.md)"),
    },
    "models.md": {
        "depths": (None, "numbers", "m", "depths the MD engine runs at (nearest profile depth; "
                   "or give count)"),
        "count": (None, "integer", "", "number of MD depths spread evenly over the profile "
                  "(below the surface); default 3 when depths is not given"),
        "schemes": (["coating"], "strings", "",
                    "cement location: coating (quartz overgrowths, the default), contact, "
                    "pore_body, pendular; one model member per scheme"),
        "size": ([4.0, 4.0, 12.0], "numbers", "grain diameters", "box of the MD pack"),
        "radius_spread": (0.1, "number", "1",
                          "grain radii uniform in [(1 - spread) D/2, D/2], D = grain_size"),
        "seed": (0, "integer", "", "random seed of settling and pore-body cement (>= 0)"),
        "samples": (1, "integer", "", "independent packs (seeds seed, seed + 1, ...): the "
                    "velocities are their mean, with the standard error as sample-size error"),
        "resolution": (6.0, "number", "cells per radius",
                       "cement lattice resolution Omega; a lattice of more than 10^7 cells "
                       "per member (rockcem._md_backend.MAX_LATTICE_CELLS; Omega 17 on the "
                       "default size) is refused before any work, with its memory and time"),
        "resolution_check": (None, "number", "cells per radius",
                             "coarser Omega for the resolution error (default resolution / "
                             "1.5, none below 1; 0 = none)"),
        "resolution_check2": (None, "number", "cells per radius",
                              "a third, coarser Omega: the grid convergence index with the "
                              "observed order, flagged where not asymptotic (default "
                              "resolution_check / 1.5 where that is >= 1; 0 = none)"),
        "anisotropy": ("ti", "string", "",
                       "'ti': the five constants of the transversely isotropic sample, its bulk "
                       "modulus under hydrostatic stress, anisotropic Gassmann, vertical "
                       "velocities and Thomsen's parameters; 'isotropic': K_dry = M - 4/3 G "
                       "and isotropic Gassmann (measure = 'pulse' needs it)"),
        "trust_threshold": (0.05, "number", "1",
                            "largest total error (resolution and sample size in quadrature) "
                            "of a trusted MD member, relative to its velocity; a member above "
                            "it, or whose error was not measured, is flagged (md_trusted = 0)"),
        "compaction": ("reconstruct", "string", "",
                       "'reconstruct': compacted past Hertzian contact to burial's "
                       "intergranular volume (grain centres moved together vertically, the "
                       "overlap removed as pressure solution; md.reconstruct); 'hertz': "
                       "elastic spheres only (porosity stays near 0.37)"),
        "cement_history": ("grown", "string", "",
                           "'grown': cement laid down in increments as the pack is carried "
                           "down, carried with the grains; 'fresh': each depth cemented afresh"),
        "interface": ("facet", "string", "", "grain-cement interface rule (md.interface)"),
        "measure": ("static", "string", "", "'static' moduli (long-wave limit) or 'pulse' test"),
        "full_sample": ("voxel", "string", "",
                        "how a depth whose pores burial fills is measured: 'voxel', finite "
                        "elements of grain and cement on the lattice's cells (md.voxel; within "
                        "0.1 % of the resolution limit, static only); 'lattice', the rigid "
                        "grains and cement lattice of every other depth"),
        "slab": (1.0, "number", "grain diameters", "slab thickness of the moduli measurement"),
        "fall_stiffness_factor": (1e-3, "number", "", "contact softening while grains fall"),
        "workdir": (None, "string", "", "folder of the MD stage files (default: "
                    "<output stem>_md_work beside the file written: rockcem run's -o, else "
                    "output); never a file or the output itself"),
    },
}
#: Model sections that take a calibration file.
CALIBRATED_MODELS = ("patchy_cement",)

_TOP_SECTIONS = {"path", "pressure", "sandstone", "shale", "materials", "fluid", "models",
                 "sweep", "uncertain"}
MODEL_LABELS = ("hs_gassmann", "self_consistent", "generalized_gassmann", "patchy_cement", "md")
#: Variables of the pore fluid (a scene with a [fluid] section writes them by default).
FLUID_OUTPUTS = ("fluid_density", "fluid_bulk_modulus", "fluid_velocity",
                 "hydrocarbon_saturation")
#: Variables of the rock state, per lithology.
STATE_OUTPUTS = {
    "sandstone": ("burial_time", "temperature", "pressure_confining", "pressure_pore",
                  "pressure_effective", "porosity", "cement_fraction", "intergranular_volume",
                  "pore_filled", "density"),
    "shale": ("burial_time", "temperature", "pressure_confining", "pressure_pore",
              "pressure_effective", "porosity", "smectite_fraction", "illite_fraction", "density"),
}


def _suggest(key, valid):
    close = difflib.get_close_matches(key, list(valid), n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else f" (valid: {', '.join(sorted(valid))})"


@dataclass(frozen=True)
class Scene:
    """A validated scene: ``sections`` maps each schema section to its complete parameters
    (defaults filled in, calibrated values applied); ``sweep`` maps ``"section.key"`` to the
    values to sweep; ``text`` is the scene as TOML; ``base_dir`` the folder of the scene file
    (relative calibration paths are looked up there); ``calibrations`` maps a model label to the
    calibration file it uses (:func:`rockcem.calibrate.load_calibration`)."""

    name: str
    lithology: str
    outputs: tuple
    output: str
    models: tuple
    sections: dict
    sweep: dict
    text: str
    description: str = ""
    base_dir: str | None = None
    calibrations: dict = field(default_factory=dict)
    #: A stack ([[layers]]; lithology "stack"): its layers, top to bottom
    #: (:class:`rockcem._scene_stack.StackLayer`); empty for a single-lithology scene.
    layers: tuple = ()
    #: The checked ``[uncertain]`` section (:func:`rockcem._uncertain_keys.validate_uncertain`);
    #: empty without one. ``sections`` hold each uncertain key's median.
    uncertain: dict = field(default_factory=dict)

    def replace(self, **params) -> Scene:
        """A copy with parameters changed, keys as ``"section.key"`` (``"path.gradient"``); the
        sweep is kept."""
        return self._with(params, keep_sweep=True)

    def _with(self, params, *, keep_sweep):
        raw = copy.deepcopy(self._raw())
        for dotted, value in params.items():
            *where, key = dotted.split(".")
            table = raw
            for part in where:
                table = table.setdefault(part, {})
            table[key] = value
        if not keep_sweep:
            raw.pop("sweep", None)
            raw["outputs"] = list(self.outputs)      # every member writes the same variables
        text = None if params or not keep_sweep else self.text
        return scene_from_dict(raw, text=text, base_dir=self.base_dir,
                               _sweep_member=not keep_sweep)

    def _raw(self) -> dict:
        return tomllib.loads(self.text)


def _is_number(value) -> bool:
    """A real number of Python or numpy (``np.float32(0.05)``, ``np.int64(3)``), not a bool."""
    return isinstance(value, (int, float, np.integer, np.floating)) and \
        not isinstance(value, (bool, np.bool_))


def _float(value) -> float:
    """A number as a Python float; a numpy float as the decimal it prints as
    (``np.float32(0.05)`` is 0.05, not its binary value 0.05000000074505806)."""
    return float(str(value)) if isinstance(value, np.floating) else float(value)


def _check_value(where, key, value, kind):
    """Check one value against its schema type; numbers come back as float."""
    if value is None:
        return None
    if kind == "number":
        ok = _is_number(value)
        value = _float(value) if ok else value
        if ok and not np.isfinite(value):
            raise ValueError(f"scene key {where}.{key} must be finite; got {value!r}")
    elif kind == "integer":
        ok = isinstance(value, (int, np.integer)) and not isinstance(value, bool)
        value = int(value) if ok else value
    elif kind == "string":
        ok = isinstance(value, str)
    elif kind == "numbers":
        ok = isinstance(value, list) and all(_is_number(v) for v in value)
        value = [_float(v) if isinstance(v, np.floating) else int(v)
                 if isinstance(v, np.integer) else v for v in value] if ok else value
    else:
        ok = isinstance(value, list) and all(isinstance(v, str) for v in value)
    if not ok:
        name = {"strings": "list of names", "numbers": "list of numbers"}.get(kind, kind)
        raise ValueError(f"scene key {where}.{key} must be a {name}; got {value!r}")
    return value


def _section(where, given, schema, uncertain=()):
    """A section's keys checked, defaults filled in; a required key that is ``uncertain``
    (``"section.key"``) is None until its distribution is checked."""
    if not isinstance(given, dict):
        raise ValueError(f"scene section [{where}] must be a table")
    unknown = [k for k in given if k not in schema]
    if unknown:
        raise ValueError(f"unknown scene key {where}.{unknown[0]}{_suggest(unknown[0], schema)}")
    out = {}
    for key, (default, kind, _unit, doc) in schema.items():
        if key in given:
            out[key] = _check_value(where, key, given[key], kind)
        elif default is _REQUIRED and f"{where}.{key}" in uncertain:
            out[key] = None
        elif default is _REQUIRED:
            raise ValueError(f"scene key {where}.{key} is required ({doc})")
        else:
            out[key] = default
    return out


def scene_from_dict(raw: dict, *, text: str | None = None, base_dir=None,
                    _sweep_member=False) -> Scene:
    """Validate a scene given as a dict (the parsed TOML) and fill in the defaults.

    ``base_dir`` is the folder relative calibration paths are looked up in first (that of the
    scene file). Raises ``ValueError`` naming the offending key, with the closest valid name for
    a typo, or the calibration file and what is wrong with it.
    """
    if not isinstance(raw, dict):
        raise ValueError("a scene must be a table of keys")
    if "layers" in raw:                 # a stack of lithologies on one path
        from ._scene_stack import stack_scene_from_dict

        return stack_scene_from_dict(raw, text=text, base_dir=base_dir)
    if "stack" in raw:
        raise ValueError("scene section [stack] applies to a stack of layers: give them as "
                         "[[layers]] (or remove [stack])")
    scene_cal, original = None, raw
    if raw.get("calibration") is not None:
        from .calibrate import apply_scene_calibration

        raw, scene_cal = apply_scene_calibration(raw, base_dir, SCHEMA)
    top = {k: v for k, v in raw.items() if k not in _TOP_SECTIONS}
    for k in raw:
        if k not in _TOP_SECTIONS and k not in SCHEMA["scene"]:
            raise ValueError(f"unknown scene key {k!r}"
                             f"{_suggest(k, set(SCHEMA['scene']) | _TOP_SECTIONS)}")
    head = _section("scene", top, SCHEMA["scene"])
    check_scene_name(head["name"])
    if head["output"] is not None and not head["output"].strip():
        raise ValueError("scene key output must name a file (leave it out for <name>.nc); "
                         f"got {head['output']!r}")
    lithology = head["lithology"]
    if lithology not in ("sandstone", "shale"):
        raise ValueError(f"scene key lithology must be 'sandstone' or 'shale'; got {lithology!r}")
    sections = {name: _section(name, raw.get(name, {}), SCHEMA[name])
                for name in ("path", "pressure", "materials", "fluid")}
    sections[lithology] = _section(lithology, raw.get(lithology, {}), SCHEMA[lithology])
    other = "shale" if lithology == "sandstone" else "sandstone"
    if other in raw:
        raise ValueError(f"scene section [{other}] does not apply to lithology {lithology!r}")
    models_raw = raw.get("models", {})
    if not isinstance(models_raw, dict):
        raise ValueError("scene section [models] must hold one table per model")
    for label in models_raw:
        if label not in MODEL_LABELS:
            raise ValueError(f"unknown model {label!r}{_suggest(label, MODEL_LABELS)}")
    if lithology == "shale" and "patchy_cement" in models_raw:
        raise ValueError("model 'patchy_cement' (Model 4) needs cement: sandstone scenes only")
    if lithology == "shale" and "md" in models_raw:
        raise ValueError("model 'md' (the MD grain pack) is a sandstone model: sandstone scenes "
                         "only")
    models = tuple(label for label in MODEL_LABELS if label in models_raw)
    calibrations = {} if scene_cal is None else {"scene": scene_cal}
    for label in models:
        given = models_raw[label]
        if label in CALIBRATED_MODELS and isinstance(given, dict) \
                and given.get("calibration") is not None:
            given, calibrations[label] = _apply_calibration(label, given, base_dir)
        sections[f"models.{label}"] = _section(f"models.{label}", given,
                                               SCHEMA[f"models.{label}"],
                                               raw.get("uncertain", {}))
    sweep = _validate_sweep(raw.get("sweep", {}), sections)
    uncertain, given = _uncertain(raw, sections, sweep, models, lithology, scene_cal,
                                  calibrations)
    _check_path_kind(given["path"], sections["path"], base_dir)
    _check_fluid(given["fluid"], sections["fluid"], sweep, _sweep_member)
    models_of_fluid = sweep.get("fluid.model", [sections["fluid"]["model"]])
    # Batzle & Wang's brine is water of the path's temperature and pressure: a catalogue fluid
    # other than water would be dropped without a word.
    if sections["materials"]["fluid"] != "water" and "constant" not in models_of_fluid:
        raise ValueError(f"scene key materials.fluid = {sections['materials']['fluid']!r} does "
                         "not apply to fluid.model = 'batzle_wang' (its brine is water of the "
                         "path's temperature and pressure); remove one of them")
    valid_outputs = STATE_OUTPUTS[lithology] + (MODEL_OUTPUTS if models else ())
    fluid_outputs, fluid_defaults = _fluid_outputs(sections["fluid"], sweep)
    outputs = head["outputs"]
    if outputs is None:
        outputs = list(valid_outputs) + (list(fluid_defaults) if "fluid" in raw else [])
    valid_outputs += fluid_outputs
    # "time" was the name of burial_time before it was renamed (a variable called "time" reads as
    # a CF time coordinate); scene files that still list it keep working.
    outputs = ["burial_time" if name == "time" else name for name in outputs]
    if not outputs:
        raise ValueError("scene key outputs must name at least one variable (leave it out for "
                         f"all of them: {', '.join(valid_outputs)})")
    for name in outputs:
        if name not in valid_outputs:
            hint = (" (model outputs need at least one model in [models])"
                    if name in MODEL_OUTPUTS else _suggest(name, valid_outputs))
            if name in FLUID_OUTPUTS:
                hint = (" (mixing = 'patchy' has no single pore fluid: each patch holds its "
                        "own)")
            raise ValueError(f"scene output {name!r} is not available for this scene{hint}")
    rates = [k for k in ("sedimentation_rate", "heating_rate")
             if k in given["path"] or f"path.{k}" in sweep]
    if len(rates) == 2:
        raise ValueError("scene keys path.sedimentation_rate and path.heating_rate both given "
                         "(set, swept or uncertain): heating_rate sets the burial rate "
                         "(S = H / G), so give one of them")
    for dotted in sweep:
        section, _, key = dotted.rpartition(".")
        if scene_cal is not None and dotted in scene_cal["parameters"]:
            raise ValueError(f"sweep {dotted}: that parameter is set by calibration "
                             f"{scene_cal['name']!r}; sweep the calibration file instead")
        cal = calibrations.get(section.removeprefix("models."))
        if section.startswith("models.") and cal is not None and key in cal["parameters"]:
            raise ValueError(f"sweep {dotted}: that parameter is set by calibration "
                             f"{cal['name']!r}; sweep the calibration file instead")
    from . import materials

    for key in ("grain", "cement", "fluid") if lithology == "sandstone" else \
            ("smectite", "illite", "fluid"):
        name = sections["materials"][key]
        try:
            (materials.fluid if key == "fluid" else materials.mineral)(name)
        except ValueError as exc:
            raise ValueError(f"scene key materials.{key}: {exc}") from None
    if text is None:
        text = _to_toml(original)
    return Scene(head["name"], lithology, tuple(outputs), head["output"] or f"{head['name']}.nc",
                 models, sections, sweep, text, head["description"],
                 None if base_dir is None else str(base_dir), calibrations, uncertain=uncertain)


def _uncertain(raw, sections, sweep, models, lithology, scene_cal, calibrations):
    """The checked ``[uncertain]`` section (empty without one), each uncertain key's median
    set in ``sections``, and the [path] and [fluid] keys given (fixed or uncertain) for the
    checks of which keys apply."""
    given = {"path": dict(raw.get("path", {})), "fluid": dict(raw.get("fluid", {}))}
    if "uncertain" not in raw:
        return {}, given
    from ._uncertain import nominal_value
    from ._uncertain_keys import validate_uncertain

    spec = validate_uncertain(raw["uncertain"], sections, sweep, models=models,
                              lithology=lithology)
    for dotted, entry in spec["keys"].items():
        section, _, key = dotted.rpartition(".")
        cal = calibrations.get(section.removeprefix("models.")) \
            if section.startswith("models.") else None
        for c, name in ((scene_cal, dotted), (cal, key)):
            if c is not None and name in c["parameters"]:
                raise ValueError(f"uncertain key {dotted}: that parameter is set by "
                                 f"calibration {c['name']!r}; remove one of them")
        table = raw.get("models", {}).get(section[7:], {}) if section.startswith("models.") \
            else raw.get(section, {})
        if isinstance(table, dict) and key in table:
            raise ValueError(f"scene key {dotted} is both set ({table[key]!r}) and uncertain; "
                             "remove one of them")
        sections[section][key] = nominal_value(entry)
        if section in given:
            given[section][key] = sections[section][key]
    return spec, given


def _apply_calibration(label, given, base_dir):
    """The model table with the calibration file's parameters applied, and the file's record."""
    from .calibrate import load_calibration

    where = f"models.{label}.calibration"
    name = _check_value(f"models.{label}", "calibration", given["calibration"], "string")
    try:
        cal = load_calibration(name, base_dir=base_dir)
    except ValueError as exc:
        raise ValueError(f"scene key {where}: {exc}") from None
    if cal.get("model") != label:
        raise ValueError(f"scene key {where}: calibration {cal['name']!r} is for model "
                         f"{cal.get('model')!r}, not {label!r}")
    knobs = [k for k in SCHEMA[f"models.{label}"] if k != "calibration"]
    foreign = [k for k in cal["parameters"] if k not in knobs]
    if foreign:
        raise ValueError(f"scene key {where}: parameter {foreign[0]!r} of calibration "
                         f"{cal['name']!r} ({cal['model']}) is not a parameter of model "
                         f"{label!r} (valid: {', '.join(knobs)})")
    twice = [k for k in cal["parameters"] if k in given]
    if twice:
        raise ValueError(f"scene key models.{label}.{twice[0]} is also set by calibration "
                         f"{cal['name']!r}; remove one of them")
    return {**given, **cal["parameters"]}, cal


#: The pore-fluid choices of [fluid]: models, hydrocarbons and mixing laws.
FLUID_MODELS = ("constant", "batzle_wang")
HYDROCARBONS = ("none", "gas", "oil", "co2", "methane")
MIXING_LAWS = ("wood", "brie", "patchy")
#: The ranges of the [fluid] numbers: (low, high, text); salinity's upper end is open.
FLUID_RANGES = {"salinity": (0.0, 0.35, "[0, 0.35)"), "saturation": (0.0, 1.0, "[0, 1]"),
                "brie_exponent": (1.0, 40.0, "[1, 40]"), "gas_gravity": (0.5, 2.0, "[0.5, 2]"),
                "oil_api": (0.0, 150.0, "[0, 150]"), "gas_oil_ratio": (0.0, 1e4, "[0, 1e4]"),
                "top": (0.0, np.inf, ">= 0 m"), "base": (0.0, np.inf, ">= 0 m")}
#: [fluid] keys and the hydrocarbons (or the model) they apply to.
_FLUID_KEY_USE = {"salinity": ("model", "batzle_wang"),
                  "saturation": ("hydrocarbon", HYDROCARBONS[1:]),
                  "mixing": ("hydrocarbon", HYDROCARBONS[1:]),
                  "brie_exponent": ("mixing", "brie"),
                  "top": ("hydrocarbon", HYDROCARBONS[1:]),
                  "base": ("hydrocarbon", HYDROCARBONS[1:]),
                  "gas_gravity": ("hydrocarbon", ("gas", "oil")),
                  "oil_api": ("hydrocarbon", ("oil",)),
                  "gas_oil_ratio": ("hydrocarbon", ("oil",))}


def _fluid_outputs(fluid, sweep):
    """The fluid variables a scene can write, and those it writes by default (with a [fluid]
    section): the fluid's density and the hydrocarbon saturation always (0 without one); its
    modulus and sound speed unless patches hold different fluids (mixing = 'patchy' with a
    hydrocarbon, in any sweep member); the saturation by default where a member has a
    hydrocarbon."""
    mixings = sweep.get("fluid.mixing", [fluid["mixing"]])
    carbons = sweep.get("fluid.hydrocarbon", [fluid["hydrocarbon"]])
    patches = "patchy" in mixings and any(h != "none" for h in carbons)
    valid = ("fluid_density",) + (() if patches else ("fluid_bulk_modulus", "fluid_velocity")) \
        + ("hydrocarbon_saturation",)
    default = valid if any(h != "none" for h in carbons) else valid[:-1]
    return valid, default


def _check_fluid(given, fluid, sweep, sweep_member):
    """[fluid]: the names are known, the numbers in their ranges, and no key is given that the
    chosen fluid does not use (unless the key that selects it is swept over values that do:
    ``"fluid.hydrocarbon" = ["none", "gas"]`` with a saturation)."""
    for key, valid in (("model", FLUID_MODELS), ("hydrocarbon", HYDROCARBONS),
                       ("mixing", MIXING_LAWS)):
        for value in sweep.get(f"fluid.{key}", [fluid[key]]):
            if value not in valid:
                raise ValueError(f"scene key fluid.{key} must be one of {', '.join(valid)}; "
                                 f"got {value!r}{_suggest(str(value), valid)}")
    if not sweep_member:
        for key, (selector, uses) in _FLUID_KEY_USE.items():
            if key not in given and f"fluid.{key}" not in sweep:
                continue
            choices = sweep.get(f"fluid.{selector}", [fluid[selector]])
            if not any(c == uses or c in uses for c in choices):
                uses = (uses,) if isinstance(uses, str) else uses
                chosen = (f"fluid.{selector} swept over {choices}"
                          if f"fluid.{selector}" in sweep else
                          f"fluid.{selector} = {fluid[selector]!r}")
                raise ValueError(f"scene key fluid.{key} does not apply to {chosen} (it "
                                 f"applies to {selector} {' or '.join(map(repr, uses))})")
    carbons = [h for h in sweep.get("fluid.hydrocarbon", [fluid["hydrocarbon"]]) if h != "none"]
    if carbons and fluid["saturation"] is None and "fluid.saturation" not in sweep:
        raise ValueError(f"scene key fluid.saturation is required with hydrocarbon = "
                         f"{carbons[0]!r} (the hydrocarbon's share of the pore space in the "
                         "interval, in [0, 1])")
    for key, (lo, hi, text) in FLUID_RANGES.items():
        for value in sweep.get(f"fluid.{key}", [fluid[key]]):
            if value is not None and not (lo <= value <= hi and not (key == "salinity"
                                                                      and value >= hi)):
                raise ValueError(f"scene key fluid.{key} must lie in {text}; got {value:g}")
    for top in sweep.get("fluid.top", [fluid["top"]]):          # every member's interval
        for base in sweep.get("fluid.base", [fluid["base"]]):
            if top is not None and base is not None and not top < base:
                raise ValueError(f"scene keys fluid.top ({top:g} m) and fluid.base "
                                 f"({base:g} m) must make an interval: top < base")
    eos = [h for h in carbons if h in ("co2", "methane")]
    if eos:         # the fluids of a reference equation of state (not gas or oil) need CoolProp
        from .pore_fluids.reference import _coolprop_problem

        problem = _coolprop_problem()
        if problem is not None:
            raise ValueError(f"scene key fluid.hydrocarbon = {eos[0]!r} needs CoolProp: "
                             f"{problem}")


def _check_path_kind(given, path, base_dir):
    """The keys given in [path] belong to its kind; a table history is read and checked."""
    from .histories import KIND_KEYS, PATH_KINDS, scene_history

    kind = path["kind"]
    if kind not in PATH_KINDS:
        raise ValueError(f"scene key path.kind must be one of {', '.join(PATH_KINDS)}; "
                         f"got {kind!r}")
    stray = [k for k in given if k != "kind" and k not in KIND_KEYS[kind]]
    if stray:
        raise ValueError(f"scene key path.{stray[0]} does not apply to kind = {kind!r} "
                         f"(its keys: {', '.join(KIND_KEYS[kind])})")
    if kind != "linear":
        scene_history(path, base_dir)


def _validate_sweep(sweep, sections):
    if not isinstance(sweep, dict):
        raise ValueError("scene section [sweep] must map 'section.key' to a list of values")
    out = {}
    names = set()
    for dotted, values in sweep.items():
        section, _, key = dotted.rpartition(".")
        if section not in sections or key not in sections[section]:
            valid = [f"{s}.{k}" for s in sections for k in sections[s]]
            raise ValueError(f"unknown sweep parameter {dotted!r}{_suggest(dotted, valid)}")
        if not isinstance(values, list) or not values:
            raise ValueError(f"sweep {dotted} must be a non-empty list of values")
        kind = SCHEMA[section][key][1]
        values = [_check_value(section, key, v, kind) for v in values]
        if sweep_dimension(dotted) in names:
            raise ValueError(f"two swept parameters share the name {sweep_dimension(dotted)!r}")
        names.add(sweep_dimension(dotted))
        out[dotted] = values
    return out


def _to_toml(raw: dict) -> str:
    """Minimal TOML writer for scene dicts (scalars, lists, nested tables, and a stack's
    ``[[layers]]``: a top-level list of tables, each followed by its sub-tables)."""
    def tables(v):
        return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)

    lines = [f"{k} = {toml_value(v)}" for k, v in raw.items()
             if not isinstance(v, dict) and not tables(v)]

    def table(prefix, d, header=None):
        scal = [f"{json.dumps(k) if '.' in k else k} = {toml_value(v)}" for k, v in d.items()
                if not isinstance(v, dict)]
        if header or scal or not any(isinstance(v, dict) for v in d.values()):
            lines.extend(["", header or f"[{prefix}]", *scal])
        for k, v in d.items():
            if isinstance(v, dict):         # a dotted key ([uncertain."path.gradient"]) quoted
                table(f"{prefix}.{json.dumps(k) if '.' in k else k}", v)

    for k, v in raw.items():
        if isinstance(v, dict):
            table(k, v)
        elif tables(v):
            for item in v:
                table(k, item, header=f"[[{k}]]")
    return "\n".join(lines) + "\n"


def load_scene(source) -> Scene:
    """Load and validate a scene from a TOML file path or the name of a shipped scene."""
    raw, text = read_scene_toml(source)
    if "md" in raw:
        raise ValueError(f"{source} is an MD scene (a table [md]): run it with `rockcem run` or "
                         "md.experiment.run_md_scene")
    return scene_from_dict(raw, text=text, base_dir=scene_path(source).parent)


def scene_path(source) -> Path:
    """The file of a scene file path or shipped scene name."""
    path = Path(source)
    if not path.suffix and not path.exists():
        shipped = shipped_scenes()
        if str(source) not in shipped:
            raise ValueError(f"no scene file {source!r} and no shipped scene of that name"
                             f"{_suggest(str(source), shipped)}")
        path = shipped[str(source)]
    if not path.is_file():
        raise ValueError(f"scene file {str(source)!r} not found")
    return path


def read_scene_toml(source) -> tuple[dict, str]:
    """The parsed TOML and text of a scene file path or shipped scene name (not validated)."""
    path = scene_path(source)
    text = toml_text(path, f"scene file {path.name}")
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"scene file {path.name} is not valid TOML: {exc}") from None
    return raw, text


def shipped_scenes() -> dict[str, Path]:
    """The scenes shipped in ``datasets/scenes/``: ``{name: path}``."""
    folder = data_path("scenes")
    return {p.stem: p for p in sorted(folder.glob("*.toml"))}


# ----------------------------------------------------------------------------- running
#: Most members a sweep may have unless ``run_scene(max_members=...)`` (``rockcem run
#: --max-members``) says otherwise. A member of the shipped scenes takes 0.02-0.2 s (1 200-6 000
#: depths, 2-4 models), so this many is minutes to half an hour on one core; a mistyped sweep of
#: 10^6 members is refused up front instead of starting a run of days.
MAX_SWEEP_MEMBERS = 10_000


def sweep_size(scene: Scene) -> int:
    """Members of the scene's sweep: the product of the swept lists' lengths (1 without one)."""
    return int(np.prod([len(v) for v in scene.sweep.values()], dtype=float)) \
        if scene.sweep else 1


def run_scene(scene: Scene, *, scheduler=None, jobs=1, progress=False,
              max_members=MAX_SWEEP_MEMBERS):
    """Run a scene: burial → rock state → models → one ``xarray.Dataset``.

    Parameters
    ----------
    scene : Scene
        From :func:`load_scene` or :func:`scene_from_dict`.
    scheduler : None, "local" or str, keyword-only
        Where to run the members of a sweep: ``None`` serially in this process; ``"local"`` on a
        new ``dask.distributed.LocalCluster``; any other string is the address of an existing
        dask scheduler (``"tcp://host:8786"``). Needs the ``dask`` extra. A scene without a
        sweep runs its MD members (``[models.md]``: depths and schemes, once the pack has been
        carried down) there instead.
    jobs : int, keyword-only
        Local processes for the MD members when ``scheduler`` is None (workers of the local
        cluster with ``scheduler="local"``); default 1.
    progress : bool, keyword-only
        Show a progress bar over the sweep members.
    max_members : int, keyword-only
        Most sweep members to run (with ``[uncertain]``: sweep members times samples); default
        :data:`MAX_SWEEP_MEMBERS`. A larger run is refused before any work (raise this to run
        it anyway).

    Returns
    -------
    xarray.Dataset

    Raises
    ------
    ValueError
        A sweep larger than ``max_members``; ``jobs`` not an integer >= 1; a ``scheduler``
        address where no dask scheduler answers (refused within
        :data:`rockcem._scheduler.SCHEDULER_CONNECT_TIMEOUT_S`).
    """
    from ._scheduler import check_scheduler
    from .runner import run

    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a Scene (load_scene or scene_from_dict); got "
                         f"{type(scene).__name__}")
    for name, value in (("jobs", jobs), ("max_members", max_members)):
        if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool)
                and value >= 1):
            raise ValueError(f"{name} must be an integer >= 1; got {value!r}")
    members = sweep_size(scene)
    if scene.uncertain:
        n = scene.uncertain["samples"]
        # Sobol' indices run N (d + 2) members: the two base designs and one per input.
        per = n * (len(scene.uncertain["keys"]) + 2) if scene.uncertain.get("sensitivity") \
            else n
        total = members * per
        if total > max_members:
            what = (f"{n} x ({len(scene.uncertain['keys'])} inputs + 2) for the Sobol' indices"
                    if per != n else f"{n} uncertain samples")
            raise ValueError(f"the scene has {total} members ({what} x {members} sweep "
                             f"members), above max_members = {max_members}; pass "
                             f"max_members={total} (rockcem run --max-members {total}) to run "
                             "it anyway")
    if members > max_members:
        shape = " x ".join(f"{len(v)} {k.rpartition('.')[2]}" for k, v in scene.sweep.items())
        raise ValueError(f"the sweep has {members} members ({shape}), above max_members = "
                         f"{max_members}; pass max_members={members} (rockcem run "
                         f"--max-members {members}) to run it anyway")
    check_scheduler(scheduler)
    return run(scene, scheduler=scheduler, jobs=jobs, progress=progress)


def write_dataset(ds, path) -> Path:
    """Write a Dataset to netCDF (netCDF4 engine) atomically: temporary file, then rename."""
    from ._atomic import atomic_write

    return atomic_write(path, lambda tmp: ds.to_netcdf(tmp, engine="netcdf4"))

