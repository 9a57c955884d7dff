"""The ``brdf-rs`` command line, run as a user runs it (a subprocess), outputs checked.

Each command's ``--json`` is parsed and compared with the library computing the same
thing (same seed: same bits), files it writes are read back, and bad input must give one
line on stderr (no traceback) and exit code 2; failures (a file that cannot be written,
matplotlib missing) exit 1.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import brdf_rs
import brdf_rs.plot
import numpy as np
import pytest
from brdf_rs.cli import build_parser
from brdf_rs.cli import main as cli_main
from conftest import run_cli as run
from conftest import tiny_scene

PIL = pytest.importorskip("PIL.Image")


def run_json(*args: str, cwd: Path | None = None) -> dict:
    return json.loads(run(*args, "--json", cwd=cwd).stdout)


def png_size(path: Path) -> tuple[int, int]:
    with PIL.open(path) as image:
        assert image.format == "PNG"
        image.load()  # decodes every pixel: a truncated file fails here
        return image.size


# ------------------------------------------------------------------------ models, eval


def test_models_json_is_the_spec_table():
    specs = run_json("models")
    assert specs == json.loads(json.dumps(brdf_rs.models(), default=str))
    assert specs["ggx"]["family"] == "A"
    assert [p["name"] for p in specs["ggx"]["params"]] == ["kd", "ks", "alpha"]


def test_models_table_for_people_lists_every_model():
    out = run("models").stdout
    for name in brdf_rs.models():
        assert f"\n{name}  (family" in f"\n{out}"


def test_eval_json_and_text_give_the_library_value():
    args = ["eval", "torrance_sparrow", "--wi", "0,0.3,1", "--wo", "0.2,-0.3,1"]
    params = ["-p", "p=50", "-p", "kd=0.1,0.2,0.3"]
    want = brdf_rs.eval("torrance_sparrow", [0, 0.3, 1], [0.2, -0.3, 1], p=50.0, kd=[0.1, 0.2, 0.3])
    got = run_json(*args, *params)
    assert got["value"] == want.tolist()  # JSON floats round-trip exactly
    text = run(*args, *params).stdout.split()
    assert [float(x) for x in text] == want.tolist()  # %.17g round-trips too


# ----------------------------------------------------------------------------- table


def test_table_json_summary_matches_the_file_and_the_library(tmp_path):
    out = tmp_path / "t.npz"
    summary = run_json(
        "table",
        "normalized_phong",
        "--axis",
        "mu=mid:0:1:4",
        "--axis",
        "p=log:1:100:3",
        "-p",
        "kd=0",
        "-p",
        "ks=1",
        "--samples",
        "1024",
        "--seed",
        "7",
        "-o",
        str(out),
        "-q",
    )
    table = brdf_rs.Table.load(out)
    assert summary["output"] == str(out.resolve())
    assert summary["shape"] == [4, 3, 3] == list(table.value.shape)
    assert summary["seconds"] > 0
    assert summary["samples"] == int(table.samples.sum()) > 0
    assert summary["max_stderr"] == float(table.stderr[..., :2].max())
    want = brdf_rs.albedo_table(
        "normalized_phong",
        {"mu": (np.arange(4) + 0.5) / 4, "p": np.geomspace(1, 100, 3)},
        kd=0,
        ks=1,
        samples=1024,
        seed=7,
    )
    np.testing.assert_array_equal(table.value, want.value)


def test_table_with_no_arguments_builds_the_default_and_says_where(tmp_path):
    # The README's first command: a 32x32 torrance_sparrow table to tol 1e-4.
    result = run("table", "-q", cwd=tmp_path)
    path = tmp_path / "albedo_torrance_sparrow.npz"
    assert f"wrote {path.resolve()}" in result.stdout
    table = brdf_rs.Table.load(path)
    assert table.value.shape == (32, 32, 3)
    assert table.stderr.max() <= 1e-4


def test_table_plot_is_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    summary = run_json(
        "table",
        "ggx",
        "--axis",
        "mu=mid:0:1:6",
        "--axis",
        "alpha=0.1,0.4,0.8",
        "--samples",
        "256",
        "-o",
        str(tmp_path / "t.npz"),
        "--plot",
        str(tmp_path / "t.png"),
        "-q",
    )
    assert summary["plot"] == str((tmp_path / "t.png").resolve())
    width, height = png_size(tmp_path / "t.png")
    assert width > 100 and height > 100


# ------------------------------------------------------------------------ dfg, energy


def test_dfg_table_is_the_split_sum_of_the_albedo(tmp_path):
    out = tmp_path / "dfg.npz"
    summary = run_json(
        "dfg",
        "ggx",
        "--mu",
        "0.2,0.9",
        "--roughness",
        "0.1,0.6",
        "--samples",
        "4096",
        "-o",
        str(out),
    )
    table = brdf_rs.Table.load(out)
    assert summary["shape"] == [2, 2] and table.value.shape == (2, 2, 3)
    assert list(table.axes) == ["mu", "alpha"]
    a, b = table.value[..., 0], table.value[..., 1]
    assert np.all((a > 0) & (a <= 1)) and np.all((b >= 0) & (b < a))
    assert summary["max_stderr"] == float(table.stderr[..., :2].max())
    # F0·A + B is the specular albedo at that F0: check against a direct estimate at
    # F0 = 0.5 (independent points, so both errors count).
    direct = brdf_rs.albedo(
        "ggx", [[0.2], [0.9]], alpha=[[0.1, 0.6]], kd=0, ks=0.5, samples=1 << 15, seed=3
    )
    split = 0.5 * a + b
    se = np.hypot(direct.stderr[..., 0], np.hypot(0.5 * table.stderr[..., 0], table.stderr[..., 1]))
    assert np.all(np.abs(split - direct.value[..., 0]) <= 5 * se + 1e-12)


def test_dfg_defaults_cover_blinn_phong_fresnel_roughness_p(tmp_path):
    summary = run_json(
        "dfg", "blinn_phong_fresnel", "--mu", "0.5,1", "--samples", "256", "-q", cwd=tmp_path
    )
    assert summary["axes"]["p"] == [1.0, 10000.0, 32]
    assert Path(summary["output"]) == tmp_path / "dfg_blinn_phong_fresnel.npz"


def test_energy_table_file_json_and_library_agree(tmp_path):
    out = tmp_path / "e.npz"
    summary = run_json(
        "energy",
        "beckmann",
        "--mu",
        "mid:0:1:4",
        "--alpha",
        "0.05,0.5,1",
        "--tol",
        "1e-3",
        "-o",
        str(out),
    )
    want = brdf_rs.energy_compensation_table(
        "beckmann", (np.arange(4) + 0.5) / 4, [0.05, 0.5, 1.0], tol=1e-3
    )
    with np.load(out) as data:
        np.testing.assert_array_equal(data["e"], want.e)
        np.testing.assert_array_equal(data["e_avg"], want.e_avg)
        assert data["e"].shape == (4, 3) and json.loads(str(data["meta"]))["model"] == "beckmann"
    assert summary["e_avg"] == want.e_avg.tolist()
    assert summary["max_stderr"] <= 1e-3
    # Single scattering loses energy, more for rougher surfaces; none is created.
    e_avg = np.array(summary["e_avg"])
    assert np.all(e_avg <= 1 + 4 * np.array(summary["e_avg_stderr"]))
    assert e_avg[0] > e_avg[1] > e_avg[2] > 0.3


def test_table_and_dfg_take_a_relative_tolerance(tmp_path):
    """``--rtol`` reaches the library: the command's table is the library's with the same
    ``rtol``, bit for bit, and records it."""
    out = tmp_path / "t.npz"
    run(
        "table",
        "torrance_sparrow",
        "--axis",
        "mu=0.05,0.5",
        "--param",
        "p=10",
        "--param",
        "eta=1.05",
        "--param",
        "kd=0",
        "--samples",
        "256",
        "--rtol",
        "0.02",
        "-q",
        "-o",
        str(out),
    )
    want = brdf_rs.albedo_table(
        "torrance_sparrow", {"mu": [0.05, 0.5]}, p=10.0, eta=1.05, kd=0.0, samples=256, rtol=0.02
    )
    back = brdf_rs.Table.load(out)
    np.testing.assert_array_equal(back.value, want.value)
    assert back.meta["rtol"] == 0.02
    summary = run_json(
        "dfg",
        "ggx",
        "--mu",
        "0.1,0.9",
        "--roughness",
        "0.5",
        "--rtol",
        "0.01",
        "-o",
        str(tmp_path / "d.npz"),
    )
    table = brdf_rs.dfg_table("ggx", [0.1, 0.9], [0.5], rtol=0.01)
    assert summary["max_stderr"] == float(table.stderr[..., :2].max())


def test_energy_table_of_a_closed_form_says_so(tmp_path):
    """A model whose albedo seen from the view is in closed form: nothing is sampled, the
    file holds the library's table and says how it was made."""
    out = tmp_path / "e.npz"
    summary = run_json(
        "energy", "zeltner_sheen", "--mu", "0,0.1,1", "--alpha", "0.05,1", "-o", str(out)
    )
    want = brdf_rs.energy_compensation_table("zeltner_sheen", [0.0, 0.1, 1.0], [0.05, 1.0])
    with np.load(out) as data:
        np.testing.assert_array_equal(data["e"], want.e)
        np.testing.assert_array_equal(data["e_avg_stderr"], want.e_avg_stderr)
        meta = json.loads(str(data["meta"]))
    assert meta["estimator"] == want.estimator and "closed form" in meta["estimator"]
    assert summary["max_stderr"] == 0.0 and summary["e_avg"] == want.e_avg.tolist()
    assert 0 < max(summary["e_avg_stderr"]) < 1e-12


def test_energy_table_of_a_dielectric_over_eta(tmp_path):
    """A transmitting model's table has an eta axis: the file holds the library's 3-D
    table and its axis; --eta is required for it and refused for the others."""
    out = tmp_path / "e.npz"
    args = ("--mu", "0.2,0.9", "--alpha", "0.1,0.6", "--tol", "1e-3", "-o", str(out))
    summary = run_json("energy", "ggx_dielectric", "--eta", "0.75,1.5", *args)
    want = brdf_rs.energy_compensation_table(
        "ggx_dielectric", [0.2, 0.9], [0.1, 0.6], eta=[0.75, 1.5], tol=1e-3
    )
    with np.load(out) as data:
        np.testing.assert_array_equal(data["e"], want.e)
        np.testing.assert_array_equal(data["e_avg"], want.e_avg)
        np.testing.assert_array_equal(data["eta"], [0.75, 1.5])
        assert "total albedo" in json.loads(str(data["meta"]))["quantity"]
    assert summary["shape"] == [2, 2, 2] and summary["e_avg"] == want.e_avg.tolist()
    assert "--eta" in run("energy", "ggx_dielectric", *args, code=2).stderr
    assert "--eta: only" in run("energy", "ggx", "--eta", "1.5", *args, code=2).stderr


# ----------------------------------------------------------------------------- bench


def test_bench_json_reports_real_timings_and_a_checked_table():
    models = ["lambert", "ggx", "kajiya_kay"]  # kajiya_kay needs a tangent
    result = run_json(
        "bench", "--models", *models, "--n", "2000", "--repeat", "1", "--table-size", "4",
        "--tol", "1e-3", "--threads", "1",
    )  # fmt: skip
    assert result["machine"]["threads"] == 1
    assert result["machine"]["isa"] in ("avx512", "avx2", "baseline")
    rows = {(r["model"], r["dtype"]): r for r in result["eval"]}
    assert set(rows) == {(m, d) for m in models for d in ("float64", "float32")}
    for r in rows.values():
        assert r["n"] == 2000 and r["seconds"] > 0
        assert math.isclose(r["mevals_per_s"], 2000 / r["seconds"] / 1e6)
    table = result["albedo_table"]
    assert table["shape"] == [4, 4] and table["samples"] > 0
    assert table["max_stderr"] <= 1e-3
    # normalized_phong's albedo is exactly 1 at mu = 1: the table must agree.
    assert table["max_error_in_stderr_at_mu_1"] < 6
    assert table["max_error_at_mu_1"] < 6e-3


def test_bench_text_is_a_table():
    out = run("bench", "--models", "lambert", "--n", "1000", "--repeat", "1", "--table-size", "2")
    lines = out.stdout.splitlines()
    assert any(line.split()[:1] == ["lambert"] and line.count("M/s") == 2 for line in lines)
    assert "albedo table: normalized_phong 2x2" in out.stdout


# ------------------------------------------------------------------------- plot-lobe


def test_plot_lobe_writes_a_png(tmp_path):
    pytest.importorskip("matplotlib")
    out = tmp_path / "lobe.png"
    summary = run_json(
        "plot-lobe", "ward", "-p", "alpha_x=0.1", "-p", "alpha_y=0.3", "--theta-i", "30",
        "--theta-i", "60", "-o", str(out),
    )  # fmt: skip
    assert summary == {"model": "ward", "theta_i": [30.0, 60.0], "plot": str(out.resolve())}
    size = brdf_rs.plot.LOBE_SIZE  # inches, at 100 dpi
    assert png_size(out) == (round(size[0] * 100), round(size[1] * 100))


# ------------------------------------------------------------------ errors, exit codes


BAD = [
    (["eval", "foo", "--wi", "0,0,1", "--wo", "0,0,1"], 'unknown model "foo"'),
    (["eval", "ggx", "--wi", "0,0,1", "--wo", "0,0,1", "-p", "alpha=-1"], "alpha = -1.0 is out"),
    (["eval", "ggx", "--wi", "0,0,1", "--wo", "0,0,1", "-p", "beta=1"], 'parameter "beta"'),
    (["eval", "ggx", "--wi", "0,0,0", "--wo", "0,0,1"], "wi is a zero-length vector"),
    (["eval", "ggx", "--wi", "0,0", "--wo", "0,0,1"], "expected three comma-separated"),
    (["table", "lambert_shading", "-q"], "family-B shading term"),
    (["table", "ggx", "--axis", "q=1,2", "-q"], "axes['q']: unknown axis"),
    (["table", "ggx", "--axis", "alpha=0.1,0.2", "-q"], "needs a 'mu' axis"),
    (["table", "ggx", "-o", "x.jpg"], "-o x.jpg: unknown format; use .npz, .exr, .png"),
    (["table", "ggx", "-o", "no/such/dir/t.npz"], "directory no/such/dir does not exist"),
    (["table", "ggx", "--plot", "t.gif"], "--plot t.gif: unknown format"),
    (["table", "ggx", "--tol", "-1", "-q"], "tol: must be a positive number"),
    (["table", "ggx", "--rtol", "0", "-q"], "rtol: must be a positive number"),
    (["energy", "ggx", "--rtol", "-1", "-q"], "rtol: must be a positive number"),
    (["dfg", "lambert"], "a split-sum table takes blinn_phong_fresnel, ggx, beckmann"),
    (["dfg", "--mu", "0:1"], "argument --mu: need start:stop:count"),
    (["energy", "phong"], "energy compensation takes ggx, beckmann"),
    (["energy", "ggx", "-o", "e.exr"], "-o e.exr: unknown format; use .npz"),
    (["bench", "--models", "nope"], "unknown model 'nope'"),
    (["bench", "--n", "0"], "must be at least 1"),
    (["plot-lobe", "ggx", "--theta-i", "100", "-o", "l.png"], "theta_i: expected angles"),
    (["plot-lobe", "ggx", "-o", "l.txt"], "unknown format; use .png, .svg, .pdf"),
    (["nonsense"], "invalid choice: 'nonsense'"),
    (["models", "ggxx"], "unknown model 'ggxx'; did you mean 'ggx'?"),
    (["table", "ggx", "--samples", "many"], "argument --samples: invalid int value: 'many'"),
    (["eval", "ggx", "--wi", "0,0,1"], "the following arguments are required: --wo"),
    ([], "the following arguments are required: COMMAND"),
]


@pytest.mark.parametrize(("args", "message"), BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input_is_one_line_and_exit_code_2(tmp_path, args, message):
    result = run(*args, cwd=tmp_path, code=2)
    assert "Traceback" not in result.stderr and "usage:" not in result.stderr
    # One line, ours or argparse's (no usage block before it).
    (line,) = result.stderr.strip().splitlines()
    assert message in line
    assert list(tmp_path.iterdir()) == []  # nothing written, no work done


@pytest.mark.parametrize(
    ("args", "prog"),
    [(["nonsense"], "brdf-rs"), (["dfg", "--mu", "0:1"], "brdf-rs dfg"), ([], "brdf-rs")],
)
def test_argparse_errors_point_to_help(tmp_path, args, prog):
    line = run(*args, cwd=tmp_path, code=2).stderr.strip()
    assert line.startswith(f"{prog}: ") and line.endswith(f"(see {prog} --help)")


def test_a_file_that_cannot_be_written_is_a_failure_exit_1(tmp_path):
    (tmp_path / "t.npz").mkdir()  # a directory where the table should go
    result = run(
        "table", "lambert", "--axis", "mu=0.5", "-o", str(tmp_path / "t.npz"), "-q", code=1
    )
    assert "Traceback" not in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_missing_matplotlib_is_a_clear_failure_before_any_work(tmp_path):
    code = (
        "import sys; sys.modules['matplotlib'] = None\n"
        "from brdf_rs.cli import main\n"
        "sys.exit(main(sys.argv[1:]))\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code, "table", "-q", "--plot", "t.png"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        check=False,
    )
    assert result.returncode == 1
    assert result.stderr.strip() == (
        "brdf-rs table: brdf_rs.plot needs matplotlib: pip install 'brdf-rs[plot]'"
        " (or matplotlib>=3.7)"
    )
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------- help, version, habits


def test_version_is_the_library_version():
    assert run("--version").stdout.strip() == f"brdf-rs {brdf_rs.__version__}"


def test_models_name_lists_only_that_model():
    out = run("models", "ggx").stdout
    assert out.startswith("ggx  (family A")
    assert "\nlambert  (family" not in out and "alpha" in out
    assert list(run_json("models", "ggx", "lambert")) == ["ggx", "lambert"]


def _subparsers(parser):
    (action,) = [a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction"]
    return action


def test_every_command_and_positional_is_described_and_options_show_defaults():
    subparsers = _subparsers(build_parser())
    commands = subparsers.choices
    assert set(commands) >= {"models", "eval", "table", "render", "tables", "dfg", "energy"}
    # `brdf-rs --help` lists each command with a line of help; `brdf-rs NAME --help`
    # starts with a description.
    listed = {a.dest: a.help for a in subparsers._choices_actions}
    for name, sub in commands.items():
        assert listed.get(name) and sub.description, name
        text = " ".join(sub.format_help().split())  # one line: wrapped help joined
        for action in sub._actions:
            if not action.option_strings:
                assert action.help, f"{name} {action.dest}: positional without a description"
                continue
            if action.dest == "help":
                continue
            assert action.help, f"{name} {action.option_strings[0]}: no help"
            default = action.default
            if default is None or default is False or default == []:
                continue
            spelled = {str(default), f"{default:g}" if isinstance(default, float) else ""}
            shown = any(f"default: {x}" in text or f"default {x}" in text for x in spelled if x)
            assert shown, f"{name} {action.option_strings[0]}: default {default!r} not shown"


def test_tables_says_where_its_cache_is(tmp_path):
    scene = tmp_path / "s.toml"
    scene.write_text(tiny_scene('model = "ggx"\nalpha = 0.5', lights=""), encoding="utf-8")
    cache = tmp_path / "cache"
    args = ["tables", str(scene), "--cache-dir", str(cache), "--samples", "256", "--mu-count", "4"]
    out = run(*args, "-q").stdout
    assert f"cache: {cache.resolve()}" in out
    assert run_json(*args)["cache_dir"] == str(cache)
    # By default: $BRDF_RS_CACHE, and the line names it.
    env = {**os.environ, "BRDF_RS_CACHE": str(tmp_path / "env-cache"), "BRDF_RS_NUM_THREADS": "1"}
    result = subprocess.run(
        [sys.executable, "-m", "brdf_rs", *args[:2], *args[4:], "-q"],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    assert f"cache: {(tmp_path / 'env-cache').resolve()}" in result.stdout
    assert (tmp_path / "env-cache").is_dir()


@pytest.mark.parametrize("command", ["energy", "dfg", "table"])
def test_plot_alone_writes_only_the_plot(tmp_path, command):
    pytest.importorskip("matplotlib")
    axes = {
        "energy": ["ggx", "--mu", "0.5,1", "--alpha", "0.3,0.6", "--tol", "1e-2"],
        "dfg": ["ggx", "--mu", "0.5,1", "--roughness", "0.3,0.6", "--samples", "256"],
        "table": ["ggx", "--axis", "mu=0.5,1", "--axis", "alpha=0.3,0.6", "--samples", "256"],
    }[command]
    result = run(command, *axes, "--plot", "x.png", "-q", cwd=tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.png"]
    assert "not saved (no -o)" in result.stdout
    # Without --plot, the table goes to its default name, as before.
    run(command, *axes, "-q", cwd=tmp_path)
    assert len(list(tmp_path.glob("*.npz"))) == 1


def test_table_says_when_it_replaces_a_file(tmp_path):
    args = ["table", "lambert", "--axis", "mu=0.5,1", "--samples", "64", "-o", "t.npz", "-q"]
    first = run(*args, cwd=tmp_path).stdout
    assert f"wrote {(tmp_path / 't.npz').resolve()}\n" in first and "replaced" not in first
    second = run(*args, cwd=tmp_path).stdout
    assert f"wrote {(tmp_path / 't.npz').resolve()} (replaced the existing file)" in second
    assert run_json(*args, cwd=tmp_path)["replaced"] is True


def test_bench_check_line_says_whether_it_passed(monkeypatch, capsys):
    from brdf_rs import _bench

    args = ["bench", "--models", "lambert", "--n", "1000", "--repeat", "1", "--table-size", "2"]
    assert cli_main(args) == 0
    (check,) = [line for line in capsys.readouterr().out.splitlines() if "check:" in line]
    assert check.endswith(": passed (limit 5 standard errors)")
    # A table that misses its exact value fails the check, and the command with it.
    real = _bench.albedo_table_benchmark

    def wrong(size, tol, seed=0):
        result = real(size, tol, seed)
        return {**result, "max_error_in_stderr_at_mu_1": 9.0, "check_passed": False}

    monkeypatch.setattr(_bench, "albedo_table_benchmark", wrong)
    assert cli_main(args) == 1
    (check,) = [line for line in capsys.readouterr().out.splitlines() if "check:" in line]
    assert "9.0 standard errors): FAILED (limit 5 standard errors)" in check


def test_the_console_script_is_installed():
    script = Path(sys.executable).parent / ("brdf-rs.exe" if os.name == "nt" else "brdf-rs")
    if not script.exists():
        pytest.skip("brdf-rs is not installed next to this interpreter")
    result = subprocess.run([script, "models", "--json"], capture_output=True, text=True)
    assert result.returncode == 0 and "torrance_sparrow" in json.loads(result.stdout)


# ----------------------------------------------------------- the library never prints


def test_the_library_never_prints_only_the_cli_does():
    """Library modules report through logging.getLogger("brdf_rs"); only cli.py (and
    __main__) write to stdout/stderr. Checked on the source (every call of print, and
    every use of sys.stdout / sys.stderr), and on a run that exercises the main paths."""
    import ast

    package = Path(brdf_rs.__file__).parent
    offenders = []
    for path in sorted(package.glob("*.py")):
        if path.name in ("cli.py", "__main__.py"):
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) == "print":
                offenders.append(f"{path.name}:{node.lineno} print()")
            if (
                isinstance(node, ast.Attribute)
                and node.attr in ("stdout", "stderr")
                and getattr(node.value, "id", None) == "sys"
            ):
                offenders.append(f"{path.name}:{node.lineno} sys.{node.attr}")
    assert offenders == []
    code = """
import brdf_rs, numpy as np
brdf_rs.eval("ggx", [0, 0, 1], [0.1, 0, 1])
brdf_rs.albedo_table("ggx", {"mu": [0.5, 1]}, tol=1e-3)
brdf_rs.dfg_table("ggx", [0.5], [0.3], samples=256)
brdf_rs.energy_compensation_table("ggx", [0.5], [0.3], tol=1e-3)
brdf_rs.render({"camera": {"position": [0, 0, 5], "resolution": [8, 8]}})
"""
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert (result.stdout, result.stderr) == ("", "")
