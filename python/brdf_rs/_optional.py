"""Optional dependencies, imported when first needed (``import brdf_rs`` never pays for
them), with an error that says how to install each."""

from __future__ import annotations

from typing import Any

__all__ = ["matplotlib"]


def matplotlib() -> Any:
    """Imports matplotlib, or raises ``ImportError`` naming the ``plot`` extra."""
    try:
        import matplotlib
    except ImportError:
        raise ImportError(
            "brdf_rs.plot needs matplotlib: pip install 'brdf-rs[plot]' (or matplotlib>=3.7)"
        ) from None
    return matplotlib
