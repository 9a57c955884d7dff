"""Runs the README's commands and examples as written, against an installed brdf-rs.

    python scripts/readme_check.py README.md            # with the environment's python
    python scripts/readme_check.py README.md --full     # also the full stress run (minutes)

.ci/run runs it in a fresh virtual environment holding only the wheel and the extras the
README names (png, plot, exr, stress), from an empty folder, so the repository is not on the
path. Every fenced ``sh`` and ``python`` block runs in README order, in one folder:

- ``sh``: each line (``&&`` chains split), through bash, with the environment's scripts
  first on PATH and ``.venv`` in the folder pointing at the environment (so
  ``.venv/bin/brdf-rs`` works as written). Each must exit 0, and every file it names
  with ``-o``, ``--exr`` or ``--plot`` must exist afterwards and not be empty. The install
  steps (making the venv, ``pip install -v .``, ``./scripts/test.sh``) are what the wheel
  stands in for: they are listed, not run. A line naming ``my_scene.toml`` (the user's
  own scene file) gets a copy of an example scene under that name first.
- ``python``: the blocks run one after another in one namespace (a reader's session).
  An expression statement whose line ends in a comment starting with a Python literal,
  as in ``f.shape   # (1000000, 3): RGB``, must evaluate to that literal.

The full stress run (``stress --cases all``) takes minutes: without ``--full`` it runs
with ``--cases quick`` instead, and says so. Exits non-zero on the first failure.
"""

from __future__ import annotations

import argparse
import ast
import io
import os
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig
import tempfile
import time
import tokenize
from pathlib import Path
from typing import Any

# Commands a from-source install runs; an installed wheel stands in for them.
INSTALL_STEPS = ("python3 -m venv .venv", ".venv/bin/pip install -v .", "./scripts/test.sh")
OUTPUT_FLAGS = ("-o", "--exr", "--plot")


def blocks(readme: str) -> list[tuple[str, str, int]]:
    """The fenced blocks of ``readme``: (language, text, line number of the fence)."""
    found = []
    for match in re.finditer(r"^```(\w*)\n(.*?)^```", readme, re.M | re.S):
        line = readme.count("\n", 0, match.start()) + 1
        found.append((match.group(1), match.group(2), line))
    return found


def strip_comment(line: str) -> str:
    """``line`` without a trailing shell comment (the README's never quote a ``#``)."""
    return re.sub(r"(^|\s)#.*$", "", line).strip()


def run_sh(text: str, first_line: int, env: dict[str, str], full: bool) -> None:
    for offset, raw in enumerate(text.splitlines(), start=1):
        where = f"README line {first_line + offset}"
        for command in filter(None, (c.strip() for c in strip_comment(raw).split("&&"))):
            if command in INSTALL_STEPS:
                print(f"{where}: {command!r}: the installed wheel stands in for it")
                continue
            words = shlex.split(command)
            if "stress" in words and not full and "all" in words:
                words[words.index("all")] = "quick"
                print(f"{where}: {command!r}: run with --cases quick (--full runs it as written)")
            if "my_scene.toml" in words:
                import brdf_rs

                shutil.copy(brdf_rs.example_scenes()["gallery"], "my_scene.toml")
            outputs = [words[i + 1] for i, w in enumerate(words[:-1]) if w in OUTPUT_FLAGS]
            for path in outputs:
                Path(path).unlink(missing_ok=True)
            start = time.perf_counter()
            result = subprocess.run(words, env=env, capture_output=True, text=True)
            seconds = time.perf_counter() - start
            if result.returncode != 0:
                sys.exit(
                    f"{where}: {shlex.join(words)!r} exited {result.returncode}\n"
                    f"{result.stdout}{result.stderr}"
                )
            if "Traceback" in result.stderr or "Warning" in result.stderr:
                sys.exit(f"{where}: {shlex.join(words)!r} wrote to stderr:\n{result.stderr}")
            for path in outputs:
                if not Path(path).is_file() or Path(path).stat().st_size == 0:
                    sys.exit(f"{where}: {shlex.join(words)!r} did not write {path}")
            print(f"{where}: {shlex.join(words)!r} ok ({seconds:.1f} s)")


def expected_values(source: str) -> dict[int, tuple[str, Any]]:
    """Line number → (comment, value) for comments that start with a Python literal."""
    found = {}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type != tokenize.COMMENT:
            continue
        text = token.string.lstrip("#").strip()
        # The literal is the whole comment or the part before a ": explanation".
        for candidate in (text, text.split(": ", 1)[0]):
            try:
                found[token.start[0]] = (text, ast.literal_eval(candidate))
                break
            except (ValueError, SyntaxError):
                continue
    return found


def run_python(text: str, first_line: int, namespace: dict[str, Any]) -> None:
    tree = ast.parse(text)
    expected = expected_values(text)
    for statement in tree.body:
        where = f"README line {first_line + statement.lineno}"
        if isinstance(statement, ast.Expr):
            code = compile(ast.Expression(statement.value), where, "eval")
            value = eval(code, namespace)  # the README's own example
            if statement.end_lineno in expected:
                comment, want = expected[statement.end_lineno]
                if value != want:
                    sys.exit(f"{where}: got {value!r}, the README says {comment!r}")
                print(f"{where}: {ast.unparse(statement.value)} == {want!r} ok")
        else:
            exec(compile(ast.Module([statement], []), where, "exec"), namespace)
    print(f"README line {first_line}: python block ok")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("readme", type=Path)
    parser.add_argument("--full", action="store_true", help="run the full stress suite too")
    parser.add_argument(
        "--editable", action="store_true", help="accept an editable install (while developing)"
    )
    args = parser.parse_args()
    readme = args.readme.resolve().read_text(encoding="utf-8")

    import brdf_rs

    package = Path(brdf_rs.__file__).resolve().parent
    site = Path(sysconfig.get_paths()["purelib"]).resolve()
    if package.parent != site and not args.editable:
        sys.exit(f"imported {package}, not the installed package in {site}")

    scripts = Path(sysconfig.get_paths()["scripts"])
    env = dict(os.environ, PATH=f"{scripts}{os.pathsep}{os.environ.get('PATH', '')}")
    env["MPLBACKEND"] = "Agg"
    namespace: dict[str, Any] = {"__name__": "__readme__"}
    with tempfile.TemporaryDirectory() as folder:
        os.chdir(folder)
        os.symlink(sys.prefix, ".venv")
        for language, text, line in blocks(readme):
            if language == "sh":
                run_sh(text, line, env, args.full)
            elif language == "python":
                run_python(text, line, namespace)
        os.chdir("/")
    print("README commands and examples passed")


if __name__ == "__main__":
    main()
