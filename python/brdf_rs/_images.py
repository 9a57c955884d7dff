"""Images: tone maps, and the files (PNG, EXR, NPY) rendered radiance is saved as."""

from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any

import numpy as np

from . import _arrays, _atomic, _png
from . import _brdf_rs as _core

__all__ = ["TONEMAPS", "apply_tonemap", "encode_png", "save_image", "tonemap"]

#: The tone maps, the first a scene's default (the core's list).
TONEMAPS = tuple(_core.TONEMAPS)


def apply_tonemap(image: np.ndarray, kind: str, exposure: float) -> np.ndarray:
    """:func:`tonemap` in place on a C-contiguous float32 ``image`` (returned)."""
    if not isinstance(kind, str) or kind not in TONEMAPS:
        raise ValueError(f"tonemap: expected one of {', '.join(TONEMAPS)}, got {kind!r}")
    # Any finite float64 number of stops: the scale is applied in float64 and rounded
    # once, so 0 stays 0 and an overflow is ±inf (compared without a conversion, so a
    # 400-digit integer is refused, not an OverflowError).
    if not (_arrays.is_real(exposure) and bool(abs(exposure) <= sys.float_info.max)):
        raise ValueError(
            f"exposure: expected a finite number of stops, got {_arrays.show(exposure)}"
        )
    if kind == "none" and exposure == 0:
        return image
    _core.tonemap_inplace(image, kind, float(exposure))
    return image


def tonemap(image: Any, kind: str = "reinhard", exposure: float = 0.0) -> np.ndarray:
    """Returns ``image × 2^exposure`` through a tone map (a new float32 array).

    ``"clamp"``: min(max(x, 0), 1); ``"reinhard"``: x/(1 + x); ``"aces"``: Narkowicz's
    fit of the ACES filmic curve; ``"none"``: exposure only. Any finite ``exposure`` is
    valid: the product is rounded to float32 as computed exactly, so 0 stays 0 however
    large the exposure, a product beyond float32's range is ±inf (1 after a tone map),
    and finite input never gives NaN. A NaN pixel raises ``ValueError`` naming its index.
    """
    with np.errstate(over="ignore"):  # beyond float32's range is inf, as in any float32 image
        out = np.array(_arrays.as_numeric("image", image), dtype=np.float32, order="C", copy=True)
    _no_nan("image", out)
    return apply_tonemap(out, kind, exposure)


def _no_nan(name: str, image: np.ndarray) -> None:
    """Refuses a NaN pixel, naming its index (a tone map or an 8-bit encoding would turn
    it into a colour silently)."""
    bad = _arrays.first_bad(~np.isnan(image))
    if bad is not None:
        raise ValueError(f"{name}{bad} = nan: a pixel must be a number")


def encode_png(image: np.ndarray) -> bytes:
    """The bytes of the PNG file :func:`save_image` writes for ``image`` (display values
    in [0, 1], shape ``(height, width, 3)``): 8-bit sRGB, encoded by pypng (the ``png``
    extra). In a notebook, ``IPython.display.Image(brdf_rs.encode_png(image))`` shows a
    rendered image."""
    image = _image("image", image)
    _no_nan("image", image)
    return _png.encode(_core.encode_srgb8(image))


def _image(name: str, image: Any) -> np.ndarray:
    with np.errstate(over="ignore"):  # beyond float32's range is inf, as in any float32 image
        a = np.ascontiguousarray(_arrays.as_numeric(name, image), dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(
            f"{name}: expected shape (height, width, 3) with at least one pixel, got {a.shape}"
        )
    return a


def save_image(path: str | os.PathLike[str], image: np.ndarray) -> Path:
    """Writes an image by its suffix: ``.png`` (8-bit sRGB of display values in [0, 1],
    needs pypng: the ``png`` extra), ``.exr`` (float32 RGB, needs OpenEXR: the ``exr``
    extra) or ``.npy`` (float32).

    The file is replaced in one step: ``path`` holds either its old content or the whole
    image, never part of it, even when the write fails or is interrupted or several
    processes write the same path at once. An ``OSError`` names ``path``."""
    if not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"path: expected a file name (str or path), got {type(path).__name__}")
    path = Path(path)
    image = _image("image", image)
    suffix = path.suffix.lower()
    if suffix == ".png":
        _no_nan("image", image)
        _png.write(path, _core.encode_srgb8(image))
    elif suffix == ".exr":
        from . import _exr

        _exr.write(path, {"RGB": image})
    elif suffix == ".npy":
        with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
            np.save(f, image)
    else:
        raise ValueError(f"path: unknown image format {suffix!r}; use .png, .exr or .npy")
    return path
