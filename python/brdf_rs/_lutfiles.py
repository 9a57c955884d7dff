"""The files of :mod:`brdf_rs.lut`: EXR, KTX2, DDS, 16-bit PNG and source code, each
written atomically and carrying the LUT's metadata (recipe, hash, command, axes, error
budget) as JSON, and read back by :func:`read` (for ``brdf-rs lut --verify``).

KTX2 and DDS are written by hand from their specifications (Khronos KTX 2.0 with a Khronos
Data Format basic descriptor block; Microsoft's DDS_HEADER and DDS_HEADER_DXT10):

- KTX2: key/value data holds ``KTXorientation`` = ``rd``, ``KTXwriter`` and
  ``brdf-rs:lut`` (the JSON);
- DDS has no metadata field: the JSON follows the pixel data, after the bytes
  ``brdf-rs:lut`` and a NUL (readers take the pixels by the header and ignore what
  follows).

A 3-D table (a dielectric's, layers over eta) is a 3-D texture in KTX2 (``pixelDepth``)
and DDS (a volume texture, ``TEXTURE3D``); EXR and PNG, which hold images, stack its
slices top to bottom (slice 0 on top; the metadata's ``depth`` says how many); a C/C++
header and the shader sources hold it with a trilinear lookup.
"""

from __future__ import annotations

import json
import re
import struct
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _atomic, _png
from ._brdf_rs import __version__

if TYPE_CHECKING:  # pragma: no cover
    from .lut import Lut

META_KEY = "brdf-rs:lut"
KTX2_IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
DDS_MAGIC = b"DDS "


#: The most values a GLSL or WGSL table array may hold: shader compilers and drivers
#: handle constant arrays far smaller than a texture (64K floats is already 256 KiB).
SHADER_ARRAY_MAX = 65536


def check(fmt_name: str, path: Path, values: int | None = None) -> str:
    """The container of ``path`` (its suffix), checked against the pixel format and, for
    GLSL and WGSL, against the array's number of ``values``, before any work: raises
    ``ValueError`` naming the argument."""
    from .lut import CONTAINERS, FORMATS

    suffix = path.suffix.lower()
    if suffix not in CONTAINERS:
        raise ValueError(f"path: unknown LUT file type {suffix!r}; use {', '.join(CONTAINERS)}")
    if suffix in (".glsl", ".wgsl") and values is not None and values > SHADER_ARRAY_MAX:
        raise ValueError(
            f"path: a {suffix} table is a constant array, and {values} values is more than"
            f" {SHADER_ARRAY_MAX} (shader compilers cannot be relied on to take it); write a"
            " texture (.ktx2, .dds, .exr, .png) or use smaller axes"
        )
    if suffix == ".dds" and FORMATS[fmt_name].dxgi == 0:
        raise ValueError(
            f"format: DXGI has no {fmt_name} format, so .dds cannot hold it (use .ktx2 or"
            " .exr, or a 32-bit float format)"
        )
    if suffix == ".exr" and FORMATS[fmt_name].encoding != "sfloat":
        raise ValueError(
            f"format: .exr holds half or float channels; {fmt_name} is not one (use"
            " R16G16_SFLOAT, R32G32_SFLOAT, R16_SFLOAT or R32_SFLOAT)"
        )
    return suffix


def save(lut: Lut, path: Path) -> Path:
    from . import _lutcode

    suffix = check(lut.spec.format, path, lut.decoded.size)
    meta = lut.meta(path.name)
    if suffix == ".exr":
        _save_exr(lut, path, meta)
    elif suffix == ".ktx2":
        _write(path, ktx2_bytes(lut, meta))
    elif suffix == ".dds":
        _write(path, dds_bytes(lut, meta))
    elif suffix == ".png":
        _save_png(lut, path, meta)
    else:
        _write(path, _lutcode.source(lut, meta, suffix).encode())
    return path


def _write(path: Path, data: bytes) -> None:
    with _atomic.atomic_write(path) as tmp, open(tmp, "wb") as f:
        f.write(data)


def _meta_text(meta: dict[str, Any]) -> str:
    return json.dumps(meta, sort_keys=True)


# -------------------------------------------------------------------------------- EXR

#: The EXR channel of each table channel, in order: R, G, B (readers take A as alpha and
#: B as blue, so the table's own names, e.g. ``A`` and ``B``, would be misread). What
#: each holds is in the ``brdf-rs:channels`` attribute and the metadata's ``channels``.
EXR_CHANNELS = ("R", "G", "B")
EXR_CHANNELS_KEY = "brdf-rs:channels"


def exr_channel_text(names: tuple[str, ...]) -> str:
    """``R = B, G = A+B``: which table channel each EXR channel holds."""
    return ", ".join(f"{EXR_CHANNELS[k]} = {n}" for k, n in enumerate(names))


def _save_exr(lut: Lut, path: Path, meta: dict[str, Any]) -> None:
    from . import _exr

    attributes = {
        META_KEY: _meta_text(meta),
        EXR_CHANNELS_KEY: exr_channel_text(lut.spec.channel_names),
    }
    stored = _stacked(lut.stored)
    channels = {EXR_CHANNELS[k]: stored[..., k] for k in range(len(lut.spec.channel_names))}
    _exr.write(path, channels, attributes)


def _stacked(values: np.ndarray) -> np.ndarray:
    """A 3-D table's slices stacked top to bottom into one image (2-D: as it is)."""
    if values.ndim == 4:
        return values.reshape(-1, *values.shape[2:])
    return values


def _unstacked(values: np.ndarray, meta: dict[str, Any]) -> np.ndarray:
    """An image of stacked slices back to (layers, rows, columns, channels) when the
    metadata has a ``depth``."""
    depth = meta.get("depth")
    if depth:
        return values.reshape(int(depth), -1, *values.shape[1:])
    return values


def _read_exr(path: Path) -> tuple[np.ndarray, dict[str, Any]]:
    import OpenEXR

    with OpenEXR.File(str(path)) as f:
        header = f.header()
        meta = json.loads(header[META_KEY])
        chans = f.channels()
        names = EXR_CHANNELS[: len(meta["recipe"]["channels"])]
        values = np.stack([np.asarray(chans[n].pixels, dtype=np.float64) for n in names], -1)
    return _unstacked(values, meta), meta


# ------------------------------------------------------------------------------- KTX2


def _dfd(fmt: Any) -> bytes:
    """A Khronos Data Format descriptor: the total size, then one basic descriptor block
    (RGBSDA colour model, BT.709 primaries, linear transfer) with a sample per channel."""
    nbytes = fmt.bits // 8
    samples = b""
    for ch in range(fmt.channels):
        if fmt.encoding == "sfloat":
            channel_type = ch | 0x80 | 0x40  # KHR_DF_SAMPLE_DATATYPE_FLOAT | SIGNED
            lower, upper = 0xBF800000, 0x3F800000  # -1.0f, 1.0f
        else:
            channel_type = ch
            lower, upper = 0, 65535
        samples += struct.pack(
            "<HBB4BII", ch * fmt.bits, fmt.bits - 1, channel_type, 0, 0, 0, 0, lower, upper
        )
    block_size = 24 + len(samples)
    block = struct.pack(
        "<IHH4B4B8B",
        0,  # vendorId 0 (Khronos), descriptorType 0 (basic)
        2,  # versionNumber: KDF 1.3
        block_size,
        1,  # colorModel KHR_DF_MODEL_RGBSDA
        1,  # colorPrimaries KHR_DF_PRIMARIES_BT709
        1,  # transferFunction KHR_DF_TRANSFER_LINEAR
        0,  # flags: straight alpha
        0,
        0,
        0,
        0,  # texelBlockDimension 1x1x1x1 (each minus one)
        nbytes * fmt.channels,  # bytesPlane0
        0,
        0,
        0,
        0,
        0,
        0,
        0,
    )
    body = block + samples
    return struct.pack("<I", 4 + len(body)) + body


def _kv(key: str, value: bytes) -> bytes:
    entry = key.encode() + b"\0" + value
    pad = (-len(entry)) % 4
    return struct.pack("<I", len(entry)) + entry + b"\0" * pad


def ktx2_bytes(lut: Lut, meta: dict[str, Any]) -> bytes:
    from .lut import FORMATS

    fmt = FORMATS[lut.spec.format]
    height, width = lut.stored.shape[-3:-1]
    depth = lut.stored.shape[0] if lut.stored.ndim == 4 else 0
    data = np.ascontiguousarray(lut.stored, dtype=fmt.dtype).tobytes()
    dfd = _dfd(fmt)
    # Keys sorted by their bytes: "KTXorientation" < "KTXwriter" < "brdf-rs:lut".
    kvd = (
        _kv("KTXorientation", b"rdi\0" if depth else b"rd\0")
        + _kv("KTXwriter", f"brdf-rs {__version__}\0".encode())
        + _kv(META_KEY, _meta_text(meta).encode() + b"\0")
    )
    header_size = 12 + 9 * 4 + 4 * 4 + 2 * 8
    level_index = 3 * 8
    dfd_offset = header_size + level_index
    kvd_offset = dfd_offset + len(dfd)
    end = kvd_offset + len(kvd)
    block = (fmt.bits // 8) * fmt.channels
    align = block * 4 // np.gcd(block, 4)  # lcm(texel block size, 4)
    data_offset = end + (-end) % align
    out = bytearray(KTX2_IDENTIFIER)
    out += struct.pack(
        "<9I",
        fmt.vk,
        fmt.bits // 8,  # typeSize
        width,
        height,
        depth,  # pixelDepth: 0 for a 2-D texture
        0,  # layerCount: not an array
        1,  # faceCount
        1,  # levelCount
        0,  # supercompressionScheme: none
    )
    out += struct.pack("<4I2Q", dfd_offset, len(dfd), kvd_offset, len(kvd), 0, 0)
    out += struct.pack("<3Q", data_offset, len(data), len(data))
    out += dfd + kvd
    out += b"\0" * (data_offset - len(out))
    out += data
    return bytes(out)


def _read_ktx2(raw: bytes) -> tuple[np.ndarray, dict[str, Any]]:
    from .lut import FORMATS

    vk, _, width, height, depth = struct.unpack_from("<5I", raw, 12)
    kvd_offset, kvd_length = struct.unpack_from("<2I", raw, 12 + 36 + 8)
    data_offset, _, _ = struct.unpack_from("<3Q", raw, 80)
    fmt = next(f for f in FORMATS.values() if f.vk == vk)
    meta: dict[str, Any] = {}
    pos, end = kvd_offset, kvd_offset + kvd_length
    while pos < end:
        (n,) = struct.unpack_from("<I", raw, pos)
        key, _, value = raw[pos + 4 : pos + 4 + n].partition(b"\0")
        if key.decode() == META_KEY:
            meta = json.loads(value.rstrip(b"\0"))
        pos += 4 + n + (-n) % 4
    shape = (height, width, fmt.channels) if depth == 0 else (depth, height, width, fmt.channels)
    stored = np.frombuffer(raw, fmt.dtype, int(np.prod(shape)), data_offset)
    return _decode(stored.reshape(shape), fmt), meta


def _decode(stored: np.ndarray, fmt: Any) -> np.ndarray:
    if fmt.encoding == "unorm":
        return stored.astype(np.float64) / 65535.0
    return stored.astype(np.float64)


# -------------------------------------------------------------------------------- DDS


def dds_bytes(lut: Lut, meta: dict[str, Any]) -> bytes:
    from .lut import FORMATS

    fmt = FORMATS[lut.spec.format]
    height, width = lut.stored.shape[-3:-1]
    depth = lut.stored.shape[0] if lut.stored.ndim == 4 else 0
    pitch = width * (fmt.bits // 8) * fmt.channels
    flags = 0x1 | 0x2 | 0x4 | 0x8 | 0x1000  # CAPS | HEIGHT | WIDTH | PITCH | PIXELFORMAT
    if depth:
        flags |= 0x800000  # DDSD_DEPTH
    header = struct.pack("<7I11I", 124, flags, height, width, pitch, depth, 1, *([0] * 11))
    pixel_format = struct.pack("<2I4s5I", 32, 0x4, b"DX10", 0, 0, 0, 0, 0)  # DDPF_FOURCC
    if depth:
        # DDSCAPS_COMPLEX | DDSCAPS_TEXTURE, DDSCAPS2_VOLUME; TEXTURE3D, arraySize 1
        caps = struct.pack("<5I", 0x8 | 0x1000, 0x200000, 0, 0, 0)
        dx10 = struct.pack("<5I", fmt.dxgi, 4, 0, 1, 0)
    else:
        caps = struct.pack("<5I", 0x1000, 0, 0, 0, 0)  # DDSCAPS_TEXTURE
        dx10 = struct.pack("<5I", fmt.dxgi, 3, 0, 1, 0)  # TEXTURE2D, arraySize 1
    data = np.ascontiguousarray(lut.stored, dtype=fmt.dtype).tobytes()
    trailer = META_KEY.encode() + b"\0" + _meta_text(meta).encode()
    return DDS_MAGIC + header + pixel_format + caps + dx10 + data + trailer


def _read_dds(raw: bytes) -> tuple[np.ndarray, dict[str, Any]]:
    from .lut import FORMATS

    (flags,) = struct.unpack_from("<I", raw, 8)
    height, width = struct.unpack_from("<2I", raw, 12)
    (depth,) = struct.unpack_from("<I", raw, 24)
    depth = depth if flags & 0x800000 else 0
    (dxgi,) = struct.unpack_from("<I", raw, 128)
    fmt = next(f for f in FORMATS.values() if f.dxgi == dxgi)
    shape = (height, width, fmt.channels) if depth == 0 else (depth, height, width, fmt.channels)
    stored = np.frombuffer(raw, fmt.dtype, int(np.prod(shape)), 148)
    rest = raw[148 + stored.nbytes :]
    key, _, text = rest.partition(b"\0")
    meta = json.loads(text) if key == META_KEY.encode() else {}
    return _decode(stored.reshape(shape), fmt), meta


# -------------------------------------------------------------------------------- PNG


def _save_png(lut: Lut, path: Path, meta: dict[str, Any]) -> None:
    """16-bit grey (one channel) or RGB (two: blue 0); per channel ``value = offset +
    scale * pixel / 65535`` with offset and scale recorded. The texels encoded are the
    format's decoded ones, so the budget's quantization holds plus the PNG's own step."""
    values = _stacked(lut.decoded)
    lo = values.reshape(-1, values.shape[-1]).min(axis=0)
    hi = values.reshape(-1, values.shape[-1]).max(axis=0)
    scale = np.where(hi > lo, hi - lo, 1.0)
    pixels = np.round((values - lo) / scale * 65535).astype(np.uint16)
    if pixels.shape[-1] == 2:
        pixels = np.concatenate([pixels, np.zeros_like(pixels[..., :1])], axis=-1)
    step = (scale / 65535).tolist()
    decoded = lo + scale * pixels[..., : values.shape[-1]] / 65535
    png_worst = np.abs(decoded - _stacked(lut.image)).reshape(-1, values.shape[-1]).max(axis=0)
    meta = dict(meta)
    meta["png"] = {
        "offset": lo.tolist(),
        "scale": scale.tolist(),
        "pixel_max": 65535,
        "channels": list(lut.spec.channel_names),
        "formula": "value = offset[c] + scale[c] * pixel / 65535",
        "step": step,
        "quant_worst_with_png": png_worst.tolist(),
    }
    text = {
        "Software": f"brdf-rs {__version__}",
        "Description": f"{lut.spec.kind} LUT; value = offset + scale * pixel / 65535 per"
        f" channel, offset and scale in the {META_KEY!r} text chunk",
        META_KEY: _meta_text(meta),
    }
    _png.write(path, pixels, text)


def _read_png(path: Path) -> tuple[np.ndarray, dict[str, Any]]:
    pixels, text = _png.read(path)
    meta = json.loads(text[META_KEY])
    p = meta["png"]
    n = len(p["channels"])
    lo, scale = np.asarray(p["offset"]), np.asarray(p["scale"])
    return _unstacked(lo + scale * pixels[..., :n].astype(np.float64) / 65535, meta), meta


# ------------------------------------------------------------------------------- read


def read(path: Path) -> tuple[np.ndarray, dict[str, Any]]:
    raw = path.read_bytes()
    suffix = path.suffix.lower()
    try:
        if raw.startswith(KTX2_IDENTIFIER):
            return _read_ktx2(raw)
        if raw.startswith(DDS_MAGIC):
            return _read_dds(raw)
        if raw.startswith(_png.SIGNATURE):
            return _read_png(path)
        if raw.startswith(b"\x76\x2f\x31\x01"):
            return _read_exr(path)
        if suffix in (".h", ".glsl", ".hlsl", ".wgsl"):
            return _read_source(raw.decode())
    # OpenEXR raises RuntimeError for a file it cannot read (a truncated one).
    except (KeyError, ValueError, RuntimeError, struct.error, StopIteration) as exc:
        raise ValueError(f"{path}: not a LUT file brdf-rs wrote ({exc})") from None
    raise ValueError(f"{path}: not a LUT file brdf-rs wrote (unknown content)")


_META_RE = re.compile(r"brdf-rs:lut (\{.*\})\s*$", re.MULTILINE)
_DATA_RE = re.compile(r"BEGIN DATA(.*?)END DATA", re.DOTALL)


def _read_source(text: str) -> tuple[np.ndarray, dict[str, Any]]:
    m = _META_RE.search(text)
    d = _DATA_RE.search(text)
    if m is None and "brdf-rs:lut-fit" in text:
        raise ValueError(
            "a polynomial fit, not a table: its header records the command that rebuilds it"
        )
    if m is None or d is None:
        raise ValueError("no brdf-rs:lut metadata or data block")
    meta = json.loads(m.group(1))
    body = re.sub(r"//.*|/\*.*?\*/", "", d.group(1), flags=re.DOTALL)
    numbers = re.findall(r"[-+]?\d+\.\d*(?:[eE][-+]?\d+)?", body)
    values = np.array([float(x) for x in numbers], dtype=np.float64)
    h, w = meta["height"], meta["width"]
    if meta.get("depth"):
        return values.reshape(int(meta["depth"]), h, w, -1), meta
    return values.reshape(h, w, -1), meta
