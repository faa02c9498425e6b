"""Figures of scene results: depth trends, velocity–porosity with the contact-model family, and
the rock-physics template (acoustic impedance against Vp/Vs); of scenes with uncertain inputs:
quantile bands along depth (:func:`depth_bands`), the template with the members' clouds
(:func:`member_template`) and the tornado of Sobol' indices (:func:`sobol_tornado`); and of MD
studies: velocity against cement saturation S_c (:func:`md_study_velocity`).

Every axis is labelled with the quantity and its unit from the variable registry
(:func:`rockcem.variables.variable_attrs`), written one way throughout: the ``long_name`` without
its parenthetical remarks, capitalised, and the UDUNITS string in readable form — ``km s-1`` as
``km/s``, ``g cm-3`` as ``g/cm³``, ``degree_Celsius`` as ``°C`` and ``1`` (a fraction or ratio)
as ``–``. So ``vp`` is labelled "P-wave velocity (km/s)".

Models have fixed colours (Okabe–Ito, safe for colour-blind readers) and fixed legend labels, so
the same model looks the same in every figure. Importing this module imports neither matplotlib
nor xarray; :mod:`matplotlib.pyplot` is imported inside the functions.
"""

from __future__ import annotations

from ._save import figure_path, save_figure
from ._style import MAX_MEMBERS, MODEL_LABELS
from .avo import (avo_class_depth, avo_class_probability, intercept_gradient_crossplot,
                  reflectivity_angle, synthetic_section)
from .depth import depth_trends
from .md_study import md_study_velocity, velocity_error
from .sensitivity import sobol_tornado
from .templates import rock_physics_template, velocity_porosity
from .uncertainty import depth_bands, member_template
from .wells import fit_figure, well_band, well_overlay, well_template

__all__ = ["MAX_MEMBERS", "MODEL_LABELS", "avo_class_depth", "avo_class_probability",
           "depth_bands", "depth_trends",
           "figure_path", "fit_figure", "intercept_gradient_crossplot", "md_study_velocity",
           "member_template",
           "reflectivity_angle", "rock_physics_template", "save_figure", "sobol_tornado",
           "synthetic_section",
           "velocity_error", "velocity_porosity", "well_band", "well_overlay", "well_template"]
