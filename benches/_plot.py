"""What the benchmarks' plots share."""

from __future__ import annotations

from typing import Any


def pyplot() -> Any:
    """matplotlib's ``pyplot`` on the file-only Agg backend, or None when matplotlib is
    not installed (said on stdout): the benchmark then writes its tables without a plot."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib not installed: no plot")
        return None
    return plt
