"""PNG files through pypng (the optional ``png`` extra): every PNG the package writes.

Rendered images (8-bit sRGB) and the 16-bit previews of albedo tables both go through
:func:`encode` / :func:`write`; :func:`decode` / :func:`read` read a PNG's pixels and its
``tEXt`` chunks back (what :class:`~brdf_rs.TablePreview` needs). pypng does the image
data (filters, zlib, chunk layout and CRCs); its ``Writer`` writes no text chunks, so
:func:`encode` takes the chunks pypng wrote, puts a ``tEXt`` chunk per key before the
image data, and writes them out with ``png.write_chunks``.
"""

from __future__ import annotations

import io
import os
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from . import _atomic

__all__ = ["SIGNATURE", "decode", "encode", "read", "write"]

SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _pypng(doing: str) -> Any:
    try:
        import png
    except ImportError:
        raise ImportError(f"{doing} needs pypng: pip install 'brdf-rs[png]'") from None
    return png


def _text_chunk(key: str, value: str) -> tuple[bytes, bytes]:
    """A ``tEXt`` chunk: keyword (Latin-1, 1 to 79 characters), NUL, text (Latin-1)."""
    if not 1 <= len(key) <= 79:
        raise ValueError(f"PNG text key {key!r}: 1 to 79 characters")
    return b"tEXt", key.encode("latin-1") + b"\0" + value.encode("latin-1")


def _chunks(pixels: np.ndarray, text: Mapping[str, str] | None) -> list[tuple[bytes, bytes]]:
    png = _pypng("saving a PNG")
    a = np.asarray(pixels)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in (1, 2, 3, 4) or a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"pixels: expected shape (height, width[, 1..4]); got {a.shape}")
    if a.dtype not in (np.uint8, np.uint16):
        raise TypeError(f"pixels: expected uint8 or uint16; got {a.dtype}")
    height, width, channels = a.shape
    writer = png.Writer(
        width,
        height,
        greyscale=channels <= 2,
        alpha=channels in (2, 4),
        bitdepth=8 * a.dtype.itemsize,
    )
    # Rows as PNG packs them (big-endian samples): pypng filters and compresses them.
    packed = np.ascontiguousarray(a, dtype=a.dtype.newbyteorder(">")).reshape(height, -1)
    out = io.BytesIO()
    writer.write_packed(out, (row.tobytes() for row in packed))
    chunks: list[tuple[bytes, bytes]] = list(png.Reader(bytes=out.getvalue()).chunks())
    first_idat = next(i for i, (kind, _) in enumerate(chunks) if kind == b"IDAT")
    chunks[first_idat:first_idat] = [_text_chunk(k, v) for k, v in (text or {}).items()]
    return chunks


def encode(pixels: np.ndarray, text: Mapping[str, str] | None = None) -> bytes:
    """A PNG file's bytes for ``pixels``: uint8 or uint16, shape ``(height, width)`` or
    ``(height, width, channels)`` with 1 to 4 channels (grey, grey + alpha, RGB, RGBA);
    ``text`` (Latin-1) becomes ``tEXt`` chunks. Needs pypng (the ``png`` extra)."""
    chunks = _chunks(pixels, text)
    out = io.BytesIO()
    _pypng("saving a PNG").write_chunks(out, chunks)
    return out.getvalue()


def write(
    path: str | os.PathLike[str], pixels: np.ndarray, text: Mapping[str, str] | None = None
) -> Path:
    """Writes :func:`encode`'s file to ``path`` atomically (``path`` holds either its
    old content or the whole image)."""
    chunks = _chunks(pixels, text)
    png = _pypng("saving a PNG")
    with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
        png.write_chunks(f, chunks)
    return Path(path)


def decode(data: bytes) -> tuple[np.ndarray, dict[str, str]]:
    """Pixels (uint8 or uint16, shape ``(height, width, channels)``) and ``tEXt`` chunks
    of a PNG file's bytes. Raises ``ValueError`` for anything else or a damaged file;
    ``ImportError`` without pypng (the ``png`` extra)."""
    png = _pypng("reading a PNG")
    if not data.startswith(SIGNATURE):
        raise ValueError("not a PNG file (no PNG signature)")
    try:
        text = {}
        for kind, body in png.Reader(bytes=data).chunks():
            if kind == b"tEXt":
                key, _, value = body.partition(b"\0")
                text[key.decode("latin-1")] = value.decode("latin-1")
        width, height, rows, info = png.Reader(bytes=data).asDirect()
        dtype = np.uint16 if info["bitdepth"] > 8 else np.uint8
        pixels = np.array([np.asarray(row, dtype=dtype) for row in rows], dtype=dtype)
    except (png.Error, ValueError, zlib.error) as exc:
        raise ValueError(f"damaged PNG file: {exc}") from None
    return pixels.reshape(height, width, info["planes"]), text


def read(path: str | os.PathLike[str]) -> tuple[np.ndarray, dict[str, str]]:
    """:func:`decode` of the file at ``path``; a ``ValueError`` names ``path``."""
    data = Path(path).read_bytes()
    try:
        return decode(data)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
