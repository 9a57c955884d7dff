"""Files the package writes and reads: atomic writes, failures, damaged files.

Every writer (``Table.save`` as .npz, .exr and .png, ``save_image``, the plots, the
command line's outputs and the scene table cache) replaces its file in one step: the
target holds its old content or the whole new one, whatever fails, whoever else writes
the same path at the same time, and nothing else is left in the folder. ``Table.load``
trusts nothing in a file: every kind of bad file gives one error naming the file.
"""

from __future__ import annotations

import errno
import json
import logging
import os
import subprocess
import sys
import time
from pathlib import Path

import brdf_rs
import numpy as np
import pytest
from brdf_rs import TableFileError, plot
from brdf_rs.cli import main as cli_main
from brdf_rs.cli import save_energy
from conftest import run_cli, tiny_scene


def small_table(seed: int = 0, n: int = 6, m: int = 5) -> brdf_rs.Table:
    """A consistent 2-D table with distinct values per seed (no integration needed)."""
    rng = np.random.default_rng(seed)
    return brdf_rs.Table(
        rng.random((n, m, 3)),
        rng.random((n, m, 3)) * 1e-3,
        rng.integers(1, 1000, size=(n, m)).astype(np.uint64),
        {"mu": np.linspace(0.1, 1, n), "p": np.geomspace(1, 100, m)},
        {"model": "normalized_phong", "axis_names": ["mu", "p"], "seed": seed},
    )


def assert_same_table(a: brdf_rs.Table, b: brdf_rs.Table) -> None:
    for key in ("value", "stderr", "samples"):
        np.testing.assert_array_equal(getattr(a, key), getattr(b, key))
    assert list(a.axes) == list(b.axes)
    for name in a.axes:
        np.testing.assert_array_equal(a.axes[name], b.axes[name])
    assert a.meta == b.meta


def listing(folder: Path) -> list[str]:
    """Every name in ``folder``, hidden ones too."""
    return sorted(p.name for p in folder.iterdir())


# ------------------------------------------------------------------- concurrent writers

#: Waits for the start signal (a file) after saying it is ready (another file).
START = """
import sys, time
from pathlib import Path
import numpy as np
import brdf_rs

folder, name, rounds, seed = Path(sys.argv[1]), sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
(folder.parent / f"ready-{seed}").touch()
deadline = time.monotonic() + 20
while not (folder.parent / "go").exists() and time.monotonic() < deadline:
    time.sleep(0.001)
paths = [folder / f"{r}-{name}" for r in range(rounds)]
"""

#: Saves its own table (every sample count equal to its seed) to every path in turn.
WRITER = (
    START
    + """
rng = np.random.default_rng(seed)
n = 48  # a write takes a few milliseconds: the writers overlap
table = brdf_rs.Table(
    rng.random((n, n, 3)), rng.random((n, n, 3)), np.full((n, n), seed, dtype=np.uint64),
    {"mu": np.linspace(0, 1, n), "p": np.linspace(1, 2, n)},
    {"model": "normalized_phong", "axis_names": ["mu", "p"], "seed": seed},
)
for path in paths:
    table.save(path)
"""
)

#: Loads whatever stands under the paths until told to stop: always a whole table.
READER = (
    START
    + """
reads = 0
while not (folder.parent / "stop").exists() and time.monotonic() < deadline:
    for path in paths:
        if path.exists():
            assert int(brdf_rs.Table.load(path).samples[0, 0]) in (1, 2, 3), path
            reads += 1
print(reads)
"""
)


def test_processes_saving_one_path_at_once_leave_one_whole_table(tmp_path):
    folder = tmp_path / "out"
    folder.mkdir()
    rounds = 8
    env = {**os.environ, "BRDF_RS_NUM_THREADS": "1"}

    def start(script: str, seed: int) -> subprocess.Popen:
        return subprocess.Popen(
            [sys.executable, "-c", script, str(folder), "t.npz", str(rounds), str(seed)],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            env=env,
        )

    writers = [start(WRITER, seed) for seed in (1, 2, 3)]
    reader = start(READER, 0)
    deadline = time.monotonic() + 20
    while len(list(tmp_path.glob("ready-*"))) < 4 and time.monotonic() < deadline:
        time.sleep(0.005)
    (tmp_path / "go").touch()
    for p in writers:
        _, err = p.communicate(timeout=30)
        assert p.returncode == 0, err
    (tmp_path / "stop").touch()
    out, err = reader.communicate(timeout=30)
    assert reader.returncode == 0, err
    assert int(out) > 0
    names = [f"{r}-t.npz" for r in range(rounds)]
    assert listing(folder) == sorted(names)  # no temporary file left behind
    for name in names:
        table = brdf_rs.Table.load(folder / name)
        seed = int(table.samples[0, 0])
        assert seed in (1, 2, 3) and table.meta["seed"] == seed
        assert np.all(table.samples == seed)  # one writer's table, whole


def test_threads_saving_one_path_at_once(tmp_path):
    from concurrent.futures import ThreadPoolExecutor

    tables = [small_table(seed, n=40, m=40) for seed in range(4)]
    target = tmp_path / "t.npz"
    with ThreadPoolExecutor(4) as pool:
        list(pool.map(lambda t: [t.save(target) for _ in range(10)], tables))
    back = brdf_rs.Table.load(target)
    assert any(np.array_equal(back.value, t.value) for t in tables)
    assert listing(tmp_path) == ["t.npz"]


# ------------------------------------------------------------ failed and interrupted


def _fail_after_half(exc: BaseException):
    """A stand-in for a writer: writes some bytes where it was told to, then raises."""

    def write(*args, **kwargs):
        for dest in (*args, *kwargs.values()):
            if isinstance(dest, (str, os.PathLike)):
                Path(dest).write_bytes(b"half a file")
                break
            if hasattr(dest, "write") and hasattr(dest, "name"):
                dest.write(b"half a file")
                break
        raise exc

    return write


def _disk_full(*args, **kwargs):
    """Writes some bytes and fails as a full disk does, naming the file it wrote."""
    for dest in (*args, *kwargs.values()):
        name = (
            os.fspath(dest) if isinstance(dest, (str, os.PathLike)) else getattr(dest, "name", None)
        )
        if isinstance(name, str):
            Path(name).write_bytes(b"half a file")
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), name)
    raise AssertionError("no file to write")


class _FakeExr:
    """Stands in for ``OpenEXR.File``: its ``write`` is the failing writer."""

    writer = None

    def __init__(self, *args, **kwargs):
        pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False

    def write(self, name):
        type(self).writer(name)


def _patch_writer(monkeypatch, kind: str, writer) -> None:
    """Makes the library's underlying writer for ``kind`` fail with ``writer``."""
    if kind in ("table.npz", "energy.npz"):
        monkeypatch.setattr(np, "savez_compressed", writer)
    elif kind in ("table.exr", "image.exr"):
        openexr = pytest.importorskip("OpenEXR")
        monkeypatch.setattr(_FakeExr, "writer", staticmethod(writer))
        monkeypatch.setattr(openexr, "File", _FakeExr)
    elif kind in ("table.png", "image.png"):
        png = pytest.importorskip("png")
        monkeypatch.setattr(png, "write_chunks", lambda out, chunks: writer(out))
    elif kind == "image.npy":
        monkeypatch.setattr(np, "save", writer)
    elif kind == "plot.png":
        pytest.importorskip("matplotlib")
        from matplotlib.figure import Figure

        monkeypatch.setattr(Figure, "savefig", lambda self, fname, **k: writer(fname))
    else:  # pragma: no cover
        raise AssertionError(kind)


def _save(kind: str, path: Path) -> None:
    """Writes ``path`` the way ``kind`` says, through the public functions."""
    if kind.startswith("table."):
        if kind == "table.exr":
            pytest.importorskip("OpenEXR")
        small_table(7).save(path)
    elif kind.startswith("image."):
        brdf_rs.save_image(path, np.full((4, 5, 3), 0.25, dtype=np.float32))
    elif kind == "energy.npz":
        result = brdf_rs.EnergyCompensation(
            "ggx", np.ones(2), np.ones(3), np.ones((2, 3)), np.ones(3), np.ones((2, 3)), np.ones(3)
        )
        save_energy(result, path)
    elif kind == "plot.png":
        plot.table_heatmap(small_table(7), path=path)
    else:  # pragma: no cover
        raise AssertionError(kind)


KINDS = ["table.npz", "table.exr", "table.png", "image.png", "image.exr", "image.npy"]
KINDS += ["energy.npz", "plot.png"]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("exists", [False, True], ids=["new", "replacing"])
def test_an_interrupted_write_leaves_the_old_file_and_nothing_else(
    tmp_path, monkeypatch, kind, exists
):
    path = tmp_path / f"out.{kind.split('.')[1]}"
    if exists:
        path.write_bytes(b"the old content")
    _patch_writer(monkeypatch, kind, _fail_after_half(KeyboardInterrupt()))
    with pytest.raises(KeyboardInterrupt):
        _save(kind, path)
    assert listing(tmp_path) == (["out." + kind.split(".")[1]] if exists else [])
    if exists:
        assert path.read_bytes() == b"the old content"


@pytest.mark.parametrize("kind", KINDS)
def test_a_failed_write_names_the_users_path_and_leaves_nothing(tmp_path, monkeypatch, kind):
    folder = tmp_path / "here"
    folder.mkdir()
    path = folder / f"out.{kind.split('.')[1]}"
    path.write_bytes(b"the old content")
    _patch_writer(monkeypatch, kind, _disk_full)
    with pytest.raises(OSError) as info:
        _save(kind, path)
    assert info.value.errno == errno.ENOSPC
    assert info.value.filename == str(path), info.value
    assert str(info.value) == f"[Errno {errno.ENOSPC}] {os.strerror(errno.ENOSPC)}: '{path}'"
    assert listing(folder) == [path.name]
    assert path.read_bytes() == b"the old content"


@pytest.mark.parametrize("kind", KINDS)
def test_a_directory_in_the_way(tmp_path, kind):
    if kind.endswith(".exr"):
        pytest.importorskip("OpenEXR")
    path = tmp_path / f"adir.{kind.split('.')[1]}"
    path.mkdir()
    (path / "inside").write_text("kept")
    with pytest.raises(IsADirectoryError) as info:
        _save(kind, path)
    assert str(info.value) == f"[Errno {errno.EISDIR}] Is a directory: '{path}'"
    assert listing(tmp_path) == [path.name]
    assert listing(path) == ["inside"]


@pytest.mark.parametrize("kind", ["table.npz", "image.npy"])
def test_a_missing_folder_is_named_as_the_user_gave_it(tmp_path, kind):
    path = tmp_path / "no" / "such" / f"out.{kind.split('.')[1]}"
    with pytest.raises(FileNotFoundError) as info:
        _save(kind, path)
    assert str(info.value) == f"[Errno {errno.ENOENT}] {os.strerror(errno.ENOENT)}: '{path}'"


def test_a_write_keeps_permissions(tmp_path):
    old = os.umask(0o022)
    try:
        new = tmp_path / "new.npz"
        small_table().save(new)
        assert new.stat().st_mode & 0o777 == 0o644  # 0o666 less the umask, as open() gives
        kept = tmp_path / "kept.npz"
        kept.write_bytes(b"old")
        kept.chmod(0o640)
        small_table().save(kept)
        assert kept.stat().st_mode & 0o777 == 0o640
    finally:
        os.umask(old)


def test_cli_outputs_in_the_way(tmp_path):
    (tmp_path / "adir.npz").mkdir()
    (tmp_path / "adir.npy").mkdir()
    scene = Path(__file__).resolve().parents[1] / "examples" / "scenes" / "gallery.toml"
    for args, name in (
        (["table", "normalized_phong", "--axis", "mu=0.5,1", "-o", "adir.npz"], "adir.npz"),
        (["render", str(scene), "--resolution", "8x4", "--npy", "adir.npy"], "adir.npy"),
    ):
        # Refused before the work, with the error writing would give (exit 1: a file that
        # cannot be written).
        result = run_cli(*args, cwd=tmp_path, code=1)
        assert result.stderr.strip() == f"brdf-rs {args[0]}: [Errno 21] Is a directory: '{name}'"
        assert listing(tmp_path) == ["adir.npy", "adir.npz"]


def test_cli_write_failure_is_one_line_naming_the_path(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(np, "savez_compressed", _disk_full)
    code = cli_main(
        ["table", "normalized_phong", "--axis", "mu=0.5,1", "--samples", "64", "-q", "-o", "t.npz"]
    )
    assert code == 1
    err = capsys.readouterr().err.strip()
    assert err == f"brdf-rs table: [Errno {errno.ENOSPC}] {os.strerror(errno.ENOSPC)}: 't.npz'"
    assert listing(tmp_path) == []


# ------------------------------------------------------------------ damaged table cache

SCENE = tiny_scene(
    'model = "normalized_phong"\nkd = 0\nks = 1\np = 4',
    lights='[[lights]]\ntype = "directional"\ndirection = [1, -1, -1]\n',
)


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _empty(path: Path) -> None:
    path.write_bytes(b"")


def _noise(path: Path) -> None:
    path.write_bytes(np.random.default_rng(0).bytes(path.stat().st_size))


def _corrupt_byte(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF  # inside the compressed data: a bad CRC
    path.write_bytes(bytes(data))


def _another_table(path: Path) -> None:
    small_table(3).save(path.with_name("other.npz"))
    path.with_name("other.npz").replace(path)


def _wrong_shapes(path: Path) -> None:
    with np.load(path) as data:
        arrays = {k: data[k] for k in data.files}
    arrays["value"] = arrays["value"][:2]
    np.savez(path.with_name("x.npz"), **arrays)
    path.with_name("x.npz").replace(path)


def _other_key(path: Path) -> None:
    table = brdf_rs.Table.load(path)
    table.meta["cache_key"]["samples"] += 1
    table.save(path)


DAMAGE = [_truncate, _empty, _noise, _corrupt_byte, _another_table, _wrong_shapes, _other_key]


@pytest.fixture(scope="module")
def built_cache(tmp_path_factory):
    cache = tmp_path_factory.mktemp("cache")
    (first,) = brdf_rs.scene_tables(scene_obj(), cache_dir=cache, mu_count=4, samples=64)
    assert not first.cached
    return cache, first.path, first.path.read_bytes()


def scene_obj():
    return brdf_rs.parse_scene(SCENE, "s.toml")


@pytest.mark.parametrize("damage", DAMAGE, ids=lambda f: f.__name__.strip("_"))
def test_a_damaged_cache_entry_is_rebuilt_with_a_warning(tmp_path, built_cache, damage, caplog):
    _, built, good = built_cache
    cache = tmp_path / "cache"
    cache.mkdir()
    path = cache / built.name
    path.write_bytes(good)
    damage(path)
    with caplog.at_level(logging.WARNING, logger="brdf_rs"):
        (result,) = brdf_rs.scene_tables(scene_obj(), cache_dir=cache, mu_count=4, samples=64)
    assert not result.cached and result.path == path
    warnings = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
    assert len(warnings) == 1 and str(path) in warnings[0] and "building it again" in warnings[0]
    # Rebuilt, the same bits as the first build; and now trusted.
    assert_same_table(brdf_rs.Table.load(path), brdf_rs.Table.load(built))
    assert listing(cache) == [path.name]
    caplog.clear()
    (again,) = brdf_rs.scene_tables(scene_obj(), cache_dir=cache, mu_count=4, samples=64)
    assert again.cached and not caplog.records


def test_cli_tables_rebuilds_a_damaged_cache(tmp_path, built_cache):
    _, built, good = built_cache
    cache = tmp_path / "cache"
    cache.mkdir()
    (cache / built.name).write_bytes(good[:100])
    scene = tmp_path / "s.toml"
    scene.write_text(SCENE)
    result = subprocess.run(
        [
            *(sys.executable, "-m", "brdf_rs", "tables", str(scene)),
            *("--cache-dir", str(cache), "--mu-count", "4", "--samples", "64", "--json"),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert "building it again" in result.stderr and built.name in result.stderr
    (row,) = json.loads(result.stdout)["tables"]
    assert row["cached"] is False
    assert_same_table(brdf_rs.Table.load(cache / built.name), brdf_rs.Table.load(built))


# ------------------------------------------------------------------------ Table.load


def _members(table: brdf_rs.Table) -> dict[str, np.ndarray]:
    return {
        "value": table.value,
        "stderr": table.stderr,
        "samples": table.samples,
        "meta": np.array(json.dumps(table.meta)),
        **{f"axis_{k}": v for k, v in table.axes.items()},
    }


def _write_npz(path: Path, **arrays) -> Path:
    np.savez(path, **arrays)
    return path


def test_a_saved_table_loads_back(tmp_path):
    table = small_table(5)
    assert_same_table(brdf_rs.Table.load(table.save(tmp_path / "t.npz")), table)
    computed = brdf_rs.albedo_table("normalized_phong", {"mu": [0.3, 1.0]}, samples=64)
    assert_same_table(brdf_rs.Table.load(computed.save(tmp_path / "c.npz")), computed)
    dfg = brdf_rs.dfg_table("ggx", [0.5, 1.0], [0.2, 0.5, 0.9], samples=64)
    assert_same_table(brdf_rs.Table.load(dfg.save(tmp_path / "d.npz")), dfg)


def _bad_files(tmp_path: Path) -> list[tuple[str, Path, str]]:
    """(what, file, the message's tail) for every kind of bad file."""
    good = small_table(1).save(tmp_path / "good.npz")
    raw = good.read_bytes()
    members = _members(small_table(1))
    out: list[tuple[str, Path, str]] = []

    def add(what: str, name: str, content: bytes | dict, match: str) -> None:
        path = tmp_path / name
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            _write_npz(path, **content)
        out.append((what, path, match))

    add("truncated", "truncated.npz", raw[: len(raw) // 2], "damaged or truncated")
    add("cut in the header", "head.npz", raw[:10], "damaged or truncated")
    add("empty", "empty.npz", b"", "empty file")
    add("random bytes", "noise.npz", np.random.default_rng(1).bytes(500), "not an .npz archive")
    add("pickle", "pickle.npz", b"\x80\x04\x95" + bytes(40), "not an .npz archive")
    add("npy", "array.npz", b"\x93NUMPY" + bytes(40), "not an .npz archive")
    corrupt = bytearray(raw)
    corrupt[len(raw) // 3] ^= 0xFF
    add("corrupt byte", "crc.npz", bytes(corrupt), "damaged or truncated")
    add("empty archive", "nothing.npz", {}, "no 'meta' array")
    add("no meta", "nometa.npz", {k: v for k, v in members.items() if k != "meta"}, "no 'meta'")
    add("meta not JSON", "badjson.npz", {**members, "meta": np.array("{")}, "not valid JSON")
    add(
        "meta not a string",
        "metabytes.npz",
        {**members, "meta": np.arange(3)},
        "'meta' must be a JSON string; got a int64 array of shape (3,)",
    )
    add(
        "meta a list",
        "metalist.npz",
        {**members, "meta": np.array("[1, 2]")},
        "'meta' must be a JSON object; got list",
    )
    meta = json.loads(str(members["meta"]))
    for key, value, match in (
        ("axis_names", None, "meta has no 'axis_names'"),
        ("model", None, "meta has no 'model'"),
        ("axis_names", "mu", "meta['axis_names'] must be a list of strings; got 'mu'"),
        ("axis_names", [], "must be a non-empty list of distinct strings; got []"),
        ("axis_names", ["mu", "mu"], "distinct strings; got ['mu', 'mu']"),
        ("axis_names", ["mu", 3], "distinct strings; got ['mu', 3]"),
        ("axis_names", ["mu"], "value: shape (6, 5, 3) does not match the axes mu[6]"),
        ("axis_names", ["mu", "p", "alpha"], "no 'axis_alpha' array"),
        ("model", 3, "meta['model'] must be a string; got 3"),
        ("seed", "zero", "meta['seed'] must be a number; got 'zero'"),
        ("samples", True, "meta['samples'] must be a number; got True"),
        ("fixed", [1], "meta['fixed'] must be an object; got [1]"),
    ):
        bad = {k: v for k, v in meta.items() if k != key}
        if value is not None:
            bad[key] = value
        name = f"meta_{key}_{len(out)}.npz"
        add(f"meta {key}={value!r}", name, {**members, "meta": np.array(json.dumps(bad))}, match)
    n, m = members["value"].shape[:2]
    for key, value, match in (
        ("value", None, "no 'value' array"),
        ("samples", None, "no 'samples' array"),
        ("axis_p", None, "no 'axis_p' array"),
        ("value", np.zeros((n, m)), f"value: shape ({n}, {m}) does not match the axes"),
        ("value", np.zeros((m, n, 3)), f"expected ({n}, {m}, 3)"),
        ("stderr", np.zeros((n, m, 1)), f"stderr: shape ({n}, {m}, 1) does not match"),
        ("samples", np.zeros((n, m, 3), np.int64), f"samples: shape ({n}, {m}, 3) does not"),
        ("axis_mu", np.linspace(0, 1, n + 1), f"expected ({n + 1}, {m}, 3)"),
        ("axis_mu", np.zeros((n, 1)), "axis_mu: expected a non-empty 1-D array"),
        ("axis_mu", np.zeros(0), "axis_mu: expected a non-empty 1-D array"),
        ("axis_p", np.array(["a"] * m), "axis_p: expected a non-empty 1-D array of real"),
        ("axis_p", np.array([1, 2, np.nan, 4, 5.0]), "axis_p[2] is nan: coordinates must be"),
        ("value", np.zeros((n, m, 3), np.int64), "value: expected floats; got dtype int64"),
        ("value", np.zeros((n, m, 3), complex), "value: expected floats; got dtype complex128"),
        ("samples", np.zeros((n, m)), "samples: expected integers; got dtype float64"),
        ("samples", np.full((n, m), -1), "samples[0, 0] is -1: must be non-negative"),
        ("stderr", np.full((n, m, 3), -1.0), "stderr[0, 0, 0] is -1.0: must be non-negative"),
    ):
        bad = {k: v for k, v in members.items() if k != key}
        if value is not None:
            bad[key] = value
        add(f"{key} {value!r}", f"array_{key}_{len(out)}.npz", bad, match)
    inf = members["value"].copy()
    inf[2, 3, 1] = np.inf
    add("value inf", "inf.npz", {**members, "value": inf}, "value[2, 3, 1] is inf: must be finite")
    # The tester's example: a consistent-looking file with shapes that do not fit.
    add(
        "mismatched shapes",
        "mismatch.npz",
        {
            "value": np.zeros((2, 2, 3)),
            "stderr": np.zeros((2, 2, 3)),
            "samples": np.zeros((2, 2), np.uint64),
            "axis_mu": np.linspace(0, 1, 7),
            "meta": np.array(json.dumps({"model": "ggx", "axis_names": ["mu"]})),
        },
        "value: shape (2, 2, 3) does not match the axes mu[7] (expected (7, 3))",
    )
    return out


def test_every_kind_of_bad_file_gives_one_error_naming_it(tmp_path):
    cases = _bad_files(tmp_path)
    assert len(cases) > 40
    for what, path, match in cases:
        with pytest.raises(TableFileError) as info:
            brdf_rs.Table.load(path)
        message = str(info.value)
        assert message.startswith(f"{path}: "), (what, message)
        assert match in message, (what, message)
        assert isinstance(info.value, ValueError)


def test_previews_are_not_tables(tmp_path):
    table = small_table(2)
    targets = [table.save(tmp_path / "t.png")]
    try:
        import OpenEXR  # noqa: F401
    except ImportError:
        pass
    else:
        targets.append(table.save(tmp_path / "t.exr"))
    for path in targets:
        with pytest.raises(TableFileError, match=rf"^{path}: .*\.exr and \.png are not read back"):
            brdf_rs.Table.load(path)


def test_load_never_reads_pickles(tmp_path):
    # An object array inside a well-formed archive is refused, not unpickled.
    members = _members(small_table(1))
    path = _write_npz(tmp_path / "obj.npz", **{**members, "value": np.array([None, 1], object)})
    with pytest.raises(TableFileError, match=r"damaged or truncated .*pickle"):
        brdf_rs.Table.load(path)


def test_load_errors_about_the_file_itself_stay_oserrors(tmp_path):
    with pytest.raises(FileNotFoundError) as info:
        brdf_rs.Table.load(tmp_path / "missing.npz")
    assert info.value.filename == str(tmp_path / "missing.npz")
    with pytest.raises(IsADirectoryError):
        brdf_rs.Table.load(tmp_path)


def test_save_refuses_a_table_load_would_refuse(tmp_path):
    table = small_table(1)
    table.axes["mu"] = table.axes["mu"][:3]
    with pytest.raises(ValueError, match=r"^table: value: shape \(6, 5, 3\) does not match"):
        table.save(tmp_path / "t.npz")
    table = small_table(1)
    table.meta["axis_names"] = ["p", "mu"]
    with pytest.raises(ValueError, match=r"axis_names'\] is \['p', 'mu'\] but the axes are"):
        table.save(tmp_path / "t.npz")
    assert listing(tmp_path) == []


def test_numpy_scalars_in_meta_are_written_as_numbers(tmp_path):
    # Options given as NumPy scalars (samples=np.int64(64)) end up in meta.
    table = brdf_rs.albedo_table(
        "normalized_phong", {"mu": [0.5, 1.0]}, samples=np.int64(64), seed=np.uint8(1)
    )
    back = brdf_rs.Table.load(table.save(tmp_path / "t.npz"))
    assert back.meta["samples"] == 64 and back.meta["seed"] == 1
    np.testing.assert_array_equal(back.value, table.value)
    table.meta["note"] = object()
    with pytest.raises(ValueError, match=r"^table: meta cannot be written as JSON: object"):
        table.save(tmp_path / "u.npz")
