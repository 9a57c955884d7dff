"""Renders the example scenes (python/brdf_rs/example_scenes/*.toml) into docs/ as PNG.

    python scripts/render_examples.py

docs/rtr_fig_7_38.png   RTR Figure 7.38: original vs normalized Phong at p = 25..100
docs/gallery.png        the shading assignment's terms on spheres
docs/gallery_diffuse.png, docs/gallery_specular.png   the same, --only diffuse / specular
docs/hdr_clamp.png, docs/hdr_reinhard.png, docs/hdr_aces.png   one over-bright scene,
                        three output transforms
docs/sheen.png          sheen layers: velvet and cloth spheres without and with their layer
"""

from __future__ import annotations

import time
from pathlib import Path

import brdf_rs

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"

JOBS = [
    ("rtr_fig_7_38.png", "rtr_fig_7_38", {}),
    ("gallery.png", "gallery", {}),
    ("gallery_diffuse.png", "gallery", {"only": "diffuse"}),
    ("gallery_specular.png", "gallery", {"only": "specular"}),
    ("hdr_clamp.png", "hdr", {"tonemap": "clamp"}),
    ("hdr_reinhard.png", "hdr", {"tonemap": "reinhard"}),
    ("hdr_aces.png", "hdr", {"tonemap": "aces"}),
    ("sheen.png", "sheen", {}),
]


def main() -> None:
    DOCS.mkdir(exist_ok=True)
    for out, name, options in JOBS:
        scene = brdf_rs.load_scene(brdf_rs.example_scenes()[name])
        start = time.perf_counter()
        image = brdf_rs.render(scene, **options)
        seconds = time.perf_counter() - start
        brdf_rs.save_image(DOCS / out, image)
        width, height = scene.resolution
        print(f"docs/{out}: {name} {options or ''} {width}x{height} in {seconds * 1e3:.0f} ms")


if __name__ == "__main__":
    main()
