"""Type stubs of the compiled core (``brdf_rs._brdf_rs``). Use the ``brdf_rs`` package.

Checked against the built module by ``python -m mypy.stubtest brdf_rs._brdf_rs`` (CI):
names, parameters and defaults must match the PyO3 signatures. Arrays are read in place
(any strides) and must already have the dtype named here; the Python layer
(``brdf_rs._arrays``) converts everything else before calling in.
"""

from collections.abc import Callable
from typing import Any, TypeAlias, final

import numpy as np
import numpy.typing as npt

from ._spec import ModelSpec, ToolDefaults

__all__ = [
    "DEFAULT_REPLICATES",
    "MAX_IMAGE_SIDE",
    "PARALLEL_TANGENT_EPSILONS",
    "SAMPLERS",
    "SEQUENCES",
    "TONEMAPS",
    "PreparedModel",
    "__version__",
    "albedo",
    "check_albedo_options",
    "check_param_names",
    "check_params",
    "choice_option",
    "encode_srgb8",
    "eval_f32",
    "eval_f64",
    "eval_fast",
    "ggx_dielectric_energy_table",
    "integer_option",
    "isa",
    "max_num_threads",
    "models",
    "num_threads",
    "param_admits",
    "pdf",
    "prepare_model",
    "render_scene",
    "sample",
    "scene_counters",
    "set_num_threads",
    "shade_gbuffer",
    "tonemap_inplace",
    "tool_defaults",
    "view_albedo",
]

__version__: str
DEFAULT_REPLICATES: int
SAMPLERS: list[str]
SEQUENCES: list[str]
TONEMAPS: list[str]
MAX_IMAGE_SIDE: int
PARALLEL_TANGENT_EPSILONS: float

_F64: TypeAlias = npt.NDArray[np.float64]
_F32: TypeAlias = npt.NDArray[np.float32]

def eval_f64(
    model: str,
    wi: _F64,
    wo: _F64,
    n: _F64 | None,
    tangent: _F64 | None,
    params: dict[str, _F64],
    normalized: bool,
    check: bool,
    check_params: bool,
    out: _F64 | None = None,
    precision: str = "accurate",
) -> _F64: ...
def eval_f32(
    model: str,
    wi: _F32,
    wo: _F32,
    n: _F32 | None,
    tangent: _F32 | None,
    params: dict[str, _F32],
    normalized: bool,
    check: bool,
    check_params: bool,
    out: _F32 | None = None,
    precision: str = "accurate",
) -> _F32: ...
def eval_fast(
    model: object,
    wi: object,
    wo: object,
    n: object,
    tangent: object,
    params: dict[str, Any],
    normalized: object,
    check: object,
    out: object,
    precision: str = "accurate",
) -> _F64 | _F32 | None: ...
def prepare_model(model: str, params: dict[str, _F64]) -> PreparedModel | None: ...

@final
class PreparedModel:
    def eval(
        self,
        wi: object,
        wo: object,
        n: object,
        tangent: object,
        normalized: object,
        check: object,
        out: object,
        precision: str = "accurate",
    ) -> _F64 | _F32 | None: ...

def check_param_names(model: str, names: list[str]) -> None: ...
def check_params(model: str, params: dict[str, _F64]) -> None: ...
def models() -> list[ModelSpec]: ...
def tool_defaults() -> ToolDefaults: ...
def param_admits(model: str, param: str, value: float) -> bool: ...
def view_albedo(model: str, mu_o: _F64, alpha: _F64) -> _F64: ...
def ggx_dielectric_energy_table() -> _F32: ...
def albedo(
    model: str,
    mu: _F64,
    params: dict[str, _F64],
    options: dict[str, Any],
    cell_ids: npt.NDArray[np.uint64] | None = None,
    progress: Callable[[int, int], object] | None = None,
    fold_azimuth: bool = True,
    phi: _F64 | None = None,
    average_azimuth: bool = False,
) -> tuple[_F64, _F64, npt.NDArray[np.uint64]]: ...
def sample(
    model: str,
    wi: _F64,
    u: _F64,
    n: _F64 | None,
    tangent: _F64 | None,
    params: dict[str, _F64],
    sampler: object,
) -> tuple[_F64, _F64, _F64]: ...
def pdf(
    model: str,
    wi: _F64,
    wo: _F64,
    n: _F64 | None,
    tangent: _F64 | None,
    params: dict[str, _F64],
    sampler: object,
) -> _F64: ...
def check_albedo_options(given: dict[str, Any]) -> dict[str, Any]: ...
def integer_option(
    name: str, value: object, lo: int, hi: int | None = None, hi_text: str = ""
) -> int: ...
def choice_option(name: str, value: object, choices: list[str]) -> str: ...
def set_num_threads(n: int) -> None: ...
def max_num_threads() -> int: ...
def num_threads() -> int: ...
def isa() -> str: ...
def render_scene(scene: dict[str, Any], only: str) -> tuple[_F32, dict[str, Any]]: ...
def shade_gbuffer(
    material: dict[str, Any],
    lights: list[dict[str, Any]],
    n: _F32,
    v: _F32,
    positions: _F32 | None,
    tangent: _F32 | None,
    only: str,
) -> tuple[_F32, dict[str, Any]]: ...
def tonemap_inplace(image: _F32, tonemap: str, exposure: float) -> None: ...
def encode_srgb8(image: _F32) -> npt.NDArray[np.uint8]: ...
def scene_counters(reset: bool = False) -> dict[str, int]: ...
