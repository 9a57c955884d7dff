"""PNG files with the standard library only (``zlib``): every PNG the package writes.

Rendered images (8-bit sRGB) and the 16-bit previews of albedo tables both go through
:func:`encode`, so writing a PNG needs no optional package. Rows are filtered the way
libpng does by default (per row, the filter of the five with the smallest sum of
absolute differences), then compressed with zlib at level 6. :func:`decode` reads
non-interlaced greyscale, grey + alpha, RGB and RGBA files of 8 or 16 bits per sample
(what :func:`encode` writes, and what most tools write), checks every chunk's CRC, and
returns the text chunks (``tEXt``, ``zTXt``, ``iTXt``) with the pixels.
"""

from __future__ import annotations

import os
import struct
import zlib
from collections.abc import Mapping
from pathlib import Path
from typing import BinaryIO

import numpy as np

from . import _atomic

__all__ = ["decode", "encode", "read", "write"]

SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: Colour type by the number of channels (and back).
_COLOUR_TYPES = {1: 0, 2: 4, 3: 2, 4: 6}
_CHANNELS = {v: k for k, v in _COLOUR_TYPES.items()}


def _chunk(kind: bytes, data: bytes) -> bytes:
    crc = zlib.crc32(kind + data) & 0xFFFFFFFF
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", crc)


def _text_chunk(key: str, value: str) -> bytes:
    """``tEXt`` when the value is Latin-1, else ``iTXt`` (UTF-8, uncompressed)."""
    if not 1 <= len(key) <= 79 or key != key.strip() or "  " in key:
        raise ValueError(f"PNG text key {key!r}: 1 to 79 characters, no surrounding spaces")
    try:
        return _chunk(b"tEXt", key.encode("latin-1") + b"\0" + value.encode("latin-1"))
    except UnicodeEncodeError:
        data = key.encode("latin-1") + b"\0\0\0\0\0" + value.encode("utf-8")
        return _chunk(b"iTXt", data)


def _paeth(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The Paeth predictor (PNG spec 9.4) of int16 arrays, elementwise."""
    p = a + b - c
    pa, pb, pc = np.abs(p - a), np.abs(p - b), np.abs(p - c)
    return np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, b, c))


#: The cost of a filtered byte: its distance from 0 as a signed byte (libpng's heuristic).
_COST = np.minimum(np.arange(256), 256 - np.arange(256)).astype(np.uint8)


def _filtered(raw: np.ndarray, bpp: int) -> np.ndarray:
    """Each row (uint8, shape (height, stride)) with its filter byte in front, the
    filter chosen per row by the smallest sum of absolute (signed) differences."""
    x = raw.astype(np.int16)
    left = np.zeros_like(x)
    left[:, bpp:] = x[:, :-bpp]
    up = np.zeros_like(x)
    up[1:] = x[:-1]
    upleft = np.zeros_like(x)
    upleft[:, bpp:] = up[:, :-bpp]
    predictions = (None, left, up, (left + up) >> 1, _paeth(left, up, upleft))
    best = np.zeros(raw.shape, dtype=np.uint8)
    best_cost = np.full(raw.shape[0], np.iinfo(np.uint64).max, dtype=np.uint64)
    kinds = np.zeros(raw.shape[0], dtype=np.uint8)
    for kind, predicted in enumerate(predictions):
        rows = raw if predicted is None else (x - predicted).astype(np.uint8)  # modulo 256
        cost = _COST[rows].sum(axis=1, dtype=np.uint64)
        better = cost < best_cost
        best[better], best_cost[better], kinds[better] = rows[better], cost[better], kind
    return np.concatenate([kinds[:, None], best], axis=1)


def encode(pixels: np.ndarray, text: Mapping[str, str] | None = None) -> bytes:
    """A PNG file's bytes for ``pixels``: uint8 or uint16, shape ``(height, width)`` or
    ``(height, width, channels)`` with 1 to 4 channels (grey, grey + alpha, RGB, RGBA);
    ``text`` becomes ``tEXt`` chunks (``iTXt`` for text outside Latin-1)."""
    a = np.asarray(pixels)
    if a.ndim == 2:
        a = a[:, :, None]
    if a.ndim != 3 or a.shape[2] not in _COLOUR_TYPES or a.shape[0] < 1 or a.shape[1] < 1:
        raise ValueError(f"pixels: expected shape (height, width[, 1..4]); got {a.shape}")
    if a.dtype not in (np.uint8, np.uint16):
        raise TypeError(f"pixels: expected uint8 or uint16; got {a.dtype}")
    height, width, channels = a.shape
    depth = 8 * a.dtype.itemsize
    raw = np.ascontiguousarray(a, dtype=a.dtype.newbyteorder(">")).view(np.uint8)
    raw = raw.reshape(height, width * channels * a.dtype.itemsize)
    rows = _filtered(raw, channels * a.dtype.itemsize)
    header = struct.pack(">IIBBBBB", width, height, depth, _COLOUR_TYPES[channels], 0, 0, 0)
    parts = [SIGNATURE, _chunk(b"IHDR", header)]
    parts += [_text_chunk(k, v) for k, v in (text or {}).items()]
    parts += [_chunk(b"IDAT", zlib.compress(rows.tobytes(), 6)), _chunk(b"IEND", b"")]
    return b"".join(parts)


def write(
    path: str | os.PathLike[str], pixels: np.ndarray, text: Mapping[str, str] | None = None
) -> Path:
    """Writes :func:`encode`'s bytes to ``path`` atomically (``path`` holds either its
    old content or the whole image)."""
    data = encode(pixels, text)
    with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
        _write_file(f, data)
    return Path(path)


def _write_file(f: BinaryIO, data: bytes) -> None:
    f.write(data)


def _text(kind: bytes, data: bytes) -> tuple[str, str]:
    key, _, rest = data.partition(b"\0")
    if kind == b"tEXt":
        return key.decode("latin-1"), rest.decode("latin-1")
    if kind == b"zTXt":
        return key.decode("latin-1"), zlib.decompress(rest[1:]).decode("latin-1")
    compressed = rest[0]
    _, _, rest = rest[2:].partition(b"\0")  # language tag
    _, _, rest = rest.partition(b"\0")  # translated key
    return key.decode("latin-1"), (zlib.decompress(rest) if compressed else rest).decode("utf-8")


def _unfilter(data: bytes, height: int, stride: int, bpp: int) -> np.ndarray:
    rows = np.frombuffer(data, dtype=np.uint8)
    if rows.size != height * (stride + 1):
        raise ValueError(f"image data holds {rows.size} bytes; expected {height * (stride + 1)}")
    rows = rows.reshape(height, stride + 1)
    out = np.zeros((height, stride), dtype=np.uint8)
    prev = np.zeros(stride, dtype=np.int16)
    for y in range(height):
        kind, line = int(rows[y, 0]), rows[y, 1:].astype(np.int16)
        if kind == 0:
            cur = line
        elif kind == 1:  # Sub: a running sum along each byte lane
            cur = (np.cumsum(line.reshape(-1, bpp), axis=0).ravel() % 256).astype(np.int16)
        elif kind == 2:
            cur = (line + prev) % 256
        elif kind in (3, 4):  # Average, Paeth: pixel by pixel (they read the decoded left)
            cur = np.zeros(stride, dtype=np.int16)
            zero = np.zeros(bpp, dtype=np.int16)
            for i in range(0, stride, bpp):
                left = cur[i - bpp : i] if i else zero
                up = prev[i : i + bpp]
                if kind == 3:
                    predicted = (left + up) >> 1
                else:
                    upleft = prev[i - bpp : i] if i else zero
                    predicted = _paeth(left, up, upleft)
                cur[i : i + bpp] = (line[i : i + bpp] + predicted) % 256
        else:
            raise ValueError(f"row {y}: unknown filter type {kind}")
        out[y] = cur
        prev = out[y].astype(np.int16)
    return out


def decode(data: bytes) -> tuple[np.ndarray, dict[str, str]]:
    """Pixels (uint8 or uint16, shape ``(height, width, channels)``) and text chunks of
    a PNG file's bytes. Raises ``ValueError`` for anything else or a damaged file."""
    if not data.startswith(SIGNATURE):
        raise ValueError("not a PNG file (no PNG signature)")
    pos = len(SIGNATURE)
    header: tuple[int, ...] | None = None
    idat: list[bytes] = []
    text: dict[str, str] = {}
    while True:
        if pos + 8 > len(data):
            raise ValueError("truncated PNG file (no IEND chunk)")
        (length,), kind = struct.unpack(">I", data[pos : pos + 4]), data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        crc = data[pos + 8 + length : pos + 12 + length]
        if len(body) != length or len(crc) != 4:
            raise ValueError(f"truncated PNG file (in a {kind!r} chunk)")
        if struct.unpack(">I", crc)[0] != zlib.crc32(kind + body) & 0xFFFFFFFF:
            raise ValueError(f"damaged PNG file: bad CRC in a {kind!r} chunk")
        pos += 12 + length
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind in (b"tEXt", b"zTXt", b"iTXt"):
            key, value = _text(kind, body)
            text[key] = value
        elif kind == b"IEND":
            break
    if header is None:
        raise ValueError("not a PNG file (no IHDR chunk)")
    width, height, depth, colour, _, _, interlace = header
    if depth not in (8, 16) or colour not in _CHANNELS or interlace:
        raise ValueError(
            f"unsupported PNG: bit depth {depth}, colour type {colour}, interlace {interlace}"
            " (read: 8 or 16 bits, grey, grey + alpha, RGB or RGBA, not interlaced)"
        )
    channels, size = _CHANNELS[colour], depth // 8
    raw = _unfilter(
        zlib.decompress(b"".join(idat)), height, width * channels * size, channels * size
    )
    dtype = np.dtype(np.uint8) if size == 1 else np.dtype(">u2")
    pixels = raw.view(dtype).reshape(height, width, channels)
    return pixels.astype(dtype.newbyteorder("=")), text


def read(path: str | os.PathLike[str]) -> tuple[np.ndarray, dict[str, str]]:
    """:func:`decode` of the file at ``path``; a ``ValueError`` names ``path``."""
    data = Path(path).read_bytes()
    try:
        return decode(data)
    except (ValueError, zlib.error, struct.error) as exc:
        raise ValueError(f"{path}: {exc}") from None
