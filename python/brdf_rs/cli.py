"""The ``brdf-rs`` command line.

argparse (the standard library) on purpose: the commands are plain subcommands with
typed options, and the core package then needs nothing beyond NumPy. Every command
prints a table for people or ``--json`` for machines; errors are one line on stderr
naming what was wrong, with exit code 2 for bad arguments and 1 for failures.
"""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _api

EXIT_USAGE = 2
EXIT_FAILURE = 1


class UsageError(Exception):
    """A bad command-line argument (exit code 2)."""


def _vector(text: str) -> list[float]:
    try:
        values = [float(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected x,y,z numbers, got {text!r}") from None
    if len(values) != 3:
        raise argparse.ArgumentTypeError(f"expected three comma-separated numbers, got {text!r}")
    return values


def _param(text: str) -> tuple[str, Any]:
    """Parses ``name=value``: a number, or comma-separated numbers (a colour or a list)."""
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected name=value, got {text!r}")
    name, _, value = text.partition("=")
    try:
        numbers = [float(x) for x in value.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name}: expected numbers, got {value!r}") from None
    return name.strip(), numbers[0] if len(numbers) == 1 else numbers


def _print_json(data: Any) -> None:
    json.dump(data, sys.stdout, indent=1, default=lambda x: np.asarray(x).tolist())
    sys.stdout.write("\n")


def cmd_models(args: argparse.Namespace) -> int:
    specs = _api.models()
    if args.json:
        _print_json(specs)
        return 0
    for name, spec in specs.items():
        print(f"{name}  (family {spec['family']}: {spec['summary']})")
        print(f"    {spec['formula']}")
        print(f"    source: {spec['source']}")
        if spec["tangent"]:
            print("    needs tangent=")
        for p in spec["params"]:
            default = "required" if p["default"] is None else f"default {p['default']:g}"
            print(f"    {p['name']:11s} {p['kind']:12s} {default:14s} {p['range']:22s} {p['doc']}")
    return 0


def cmd_eval(args: argparse.Namespace) -> int:
    params = dict(args.param)
    value = _api.eval(args.model, args.wi, args.wo, args.n, tangent=args.tangent, **params)
    if args.json:
        _print_json({"model": args.model, "wi": args.wi, "wo": args.wo, "value": value})
    else:
        print(" ".join(f"{v:.17g}" for v in value))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="brdf-rs",
        description="Evaluate, integrate and tabulate reflectance models (BRDFs).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    p = sub.add_parser("models", help="list every model: family, parameters, source")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(run=cmd_models)

    p = sub.add_parser("eval", help="evaluate one model for one pair of directions")
    p.add_argument("model")
    p.add_argument("--wi", type=_vector, required=True, help="toward the light: x,y,z")
    p.add_argument("--wo", type=_vector, required=True, help="toward the viewer: x,y,z")
    p.add_argument("--n", type=_vector, default=None, help="surface normal (default 0,0,1)")
    p.add_argument("--tangent", type=_vector, default=None, help="tangent x,y,z")
    p.add_argument(
        "--param", "-p", type=_param, action="append", default=[], help="name=value (repeat)"
    )
    p.add_argument("--json", action="store_true", help="machine-readable output")
    p.set_defaults(run=cmd_eval)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.run(args))
    except UsageError as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (TypeError, ValueError) as exc:
        print(f"brdf-rs {args.command}: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except KeyboardInterrupt:
        print(f"brdf-rs {args.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
