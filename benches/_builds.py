"""What the A/B benchmarks share: the builds they compare, each a Python that imports
one build of brdf_rs (``--build LABEL=PYTHON``, repeated; the first is the baseline),
and running the script's own worker mode under one of them."""

from __future__ import annotations

import argparse
import json
import subprocess
from typing import Any


def add_build_option(parser: argparse.ArgumentParser) -> None:
    """Adds the repeated ``--build LABEL=PYTHON``."""
    parser.add_argument(
        "--build",
        action="append",
        default=[],
        metavar="LABEL=PYTHON",
        help="LABEL=PYTHON: a Python that imports the build (split at the last =; first: baseline)",
    )


def parse_builds(parser: argparse.ArgumentParser, given: list[str], least: int) -> dict[str, str]:
    """The ``--build`` values as ``{label: python}`` in the order given; a parser error
    with fewer than ``least`` (1 or 2) or one without ``=``."""
    if len(given) < least or not all("=" in b for b in given):
        parser.error(f"give at least {('one', 'two')[least - 1]} --build LABEL=PYTHON")
    return dict(b.rsplit("=", 1) for b in given)


def run_worker(python: str, script: str, args: list[str]) -> Any:
    """Runs ``script --worker *args`` under ``python``; returns the JSON it prints."""
    cmd = [python, script, "--worker", *args]
    return json.loads(subprocess.run(cmd, capture_output=True, text=True, check=True).stdout)
