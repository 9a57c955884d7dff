"""Type stubs of the compiled core (``brdf_rs._brdf_rs``). Use the ``brdf_rs`` package."""

from collections.abc import Callable
from typing import Any

import numpy as np
import numpy.typing as npt

__version__: str

F64 = npt.NDArray[np.float64]
F32 = npt.NDArray[np.float32]

def eval_f64(
    model: str,
    wi: F64,
    wo: F64,
    n: F64 | None,
    tangent: F64 | None,
    params: dict[str, F64],
    normalized: bool,
    check: bool,
    check_params: bool,
    out: F64 | None = None,
) -> F64: ...
def eval_f32(
    model: str,
    wi: F32,
    wo: F32,
    n: F32 | None,
    tangent: F32 | None,
    params: dict[str, F32],
    normalized: bool,
    check: bool,
    check_params: bool,
    out: F32 | None = None,
) -> F32: ...
def check_params(model: str, params: dict[str, F64]) -> None: ...
def models() -> list[dict[str, Any]]: ...
def albedo(
    model: str,
    mu: F64,
    params: dict[str, F64],
    samples: int,
    sampler: str,
    sequence: str,
    seed: int,
    tol: float | None,
    max_samples: int | None,
    replicates: int,
    cell_ids: npt.NDArray[np.uint64] | None = None,
    progress: Callable[[int, int], object] | None = None,
    fold_azimuth: bool = True,
) -> tuple[F64, F64, npt.NDArray[np.uint64]]: ...
def sample(
    model: str,
    wi: F64,
    u: F64,
    n: F64 | None,
    tangent: F64 | None,
    params: dict[str, F64],
    sampler: str,
) -> tuple[F64, F64, F64]: ...
def pdf(
    model: str,
    wi: F64,
    wo: F64,
    n: F64 | None,
    tangent: F64 | None,
    params: dict[str, F64],
    sampler: str,
) -> F64: ...
def set_num_threads(n: int) -> None: ...
def num_threads() -> int: ...
def isa() -> str: ...
def render_scene(scene: dict[str, Any], only: str) -> tuple[F32, dict[str, Any]]: ...
def shade_gbuffer(
    material: dict[str, Any],
    lights: list[dict[str, Any]],
    n: F32,
    v: F32,
    positions: F32 | None,
    tangent: F32 | None,
    only: str,
) -> tuple[F32, dict[str, Any]]: ...
def tonemap_inplace(image: F32, tonemap: str, exposure: float) -> None: ...
def encode_srgb8(image: F32) -> npt.NDArray[np.uint8]: ...
def scene_counters(reset: bool = False) -> dict[str, int]: ...
