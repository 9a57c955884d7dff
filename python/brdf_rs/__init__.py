"""brdf-rs: evaluate, integrate and tabulate reflectance models (BRDFs), fast and accurately.

Conventions: directions point away from the surface (``wi`` toward the light, ``wo``
toward the viewer), ``n`` defaults to +z; family-A models return ``f(wi, wo)`` in 1/sr
without the cosine factor, family-B shading terms include the light's cosine. See
``brdf_rs.models()`` and the docs for every model's formula and source.
"""

from . import lut, reference
from ._albedo import (
    Albedo,
    Energy,
    EnergyCompensation,
    Table,
    TableFileError,
    TablePreview,
    albedo,
    albedo_table,
    dfg_table,
    energy,
    energy_compensation_table,
)
from ._api import Model, eval, isa, models, num_threads, set_num_threads
from ._brdf_rs import __version__
from ._sampling import pdf, sample
from ._stress import StressReport, stress
from .scene import (
    Scene,
    SceneError,
    encode_png,
    example_scenes,
    load_scene,
    parse_scene,
    render,
    save_image,
    scene_tables,
    shade,
    tonemap,
)

__all__ = [
    "Albedo",
    "Energy",
    "EnergyCompensation",
    "Model",
    "Scene",
    "SceneError",
    "StressReport",
    "Table",
    "TableFileError",
    "TablePreview",
    "__version__",
    "albedo",
    "albedo_table",
    "dfg_table",
    "encode_png",
    "energy",
    "energy_compensation_table",
    "eval",
    "example_scenes",
    "isa",
    "load_scene",
    "lut",
    "models",
    "num_threads",
    "parse_scene",
    "pdf",
    "reference",
    "render",
    "sample",
    "save_image",
    "scene_tables",
    "set_num_threads",
    "shade",
    "stress",
    "tonemap",
]
