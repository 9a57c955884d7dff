"""How long a from-source install takes: `pip install .` into a fresh virtual environment,
with nothing of this tree's Rust build reused, under each Cargo profile.

    python benches/install_time.py                       # release (pip's default) and dist
    python benches/install_time.py --profiles release

`release` is what `pip install .` builds (thin LTO, 16 codegen units); `dist` is the
profile of published wheels (fat LTO, one codegen unit), chosen here through maturin's
MATURIN_PEP517_ARGS. Each install gets its own empty CARGO_TARGET_DIR, so every crate
compiles; pip's download cache is left as it is (the time is the compilation's). Prints
a table of wall-clock seconds and writes benches/results/install_time.md.
"""

from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
RESULTS = ROOT / "benches" / "results"


def install_seconds(profile: str) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        venv = Path(tmp) / "venv"
        subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
        env = dict(os.environ, CARGO_TARGET_DIR=str(Path(tmp) / "target"))
        if profile != "release":
            env["MATURIN_PEP517_ARGS"] = f"--profile {profile}"
        start = time.perf_counter()
        subprocess.run(
            [str(venv / "bin" / "pip"), "install", "--quiet", str(ROOT)], env=env, check=True
        )
        seconds = time.perf_counter() - start
        # The install works: the compiled core evaluates.
        check = "import brdf_rs; assert brdf_rs.eval('lambert', [0, 0, 1], [0, 0, 1]).shape == (3,)"
        subprocess.run([str(venv / "bin" / "python"), "-c", check], check=True, cwd=tmp)
        return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--profiles", nargs="+", default=["release", "dist"])
    parser.add_argument("--out", type=Path, default=RESULTS / "install_time.md")
    args = parser.parse_args()
    rows = []
    for profile in args.profiles:
        seconds = install_seconds(profile)
        rows.append((profile, seconds))
        print(f"{profile:8s} {seconds:7.1f} s", flush=True)
    lines = [
        "`pip install .` from source into a fresh virtual environment, every crate compiled "
        f"(`python benches/install_time.py`), {time.strftime('%Y-%m-%d')}, "
        f"{os.cpu_count()} cores, {platform.machine()}; one run each, in turn.",
        "",
        "| Cargo profile | seconds |",
        "|---|---:|",
        *(f"| {profile} | {seconds:.0f} |" for profile, seconds in rows),
    ]
    args.out.write_text("\n".join(lines) + "\n")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
