"""Writing OpenEXR files through the optional ``OpenEXR`` package (the ``exr`` extra):
one helper for the images, the tables' previews and the LUTs."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from . import _atomic


def write(
    path: Path, channels: Mapping[str, np.ndarray], attributes: Mapping[str, Any] | None = None
) -> None:
    """Writes ``channels`` (name to pixels: ``"RGB"`` for an interleaved H x W x 3 array,
    or one 2-D array per channel) as a ZIP-compressed scanline EXR, with the extra header
    ``attributes``, atomically."""
    try:
        import OpenEXR
    except ImportError:
        raise ImportError(
            "writing .exr needs the OpenEXR package: pip install brdf-rs[exr]"
        ) from None
    header: dict[str, Any] = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
    }
    header.update(attributes or {})
    pixels = {name: np.ascontiguousarray(v) for name, v in channels.items()}
    with _atomic.atomic_write(path) as tmp, OpenEXR.File(header, pixels) as f:
        f.write(str(tmp))
