#!/usr/bin/env python3
"""Renders the reference of the `aov` row of `crates/gonio-render/tests/layers.rs` with Mitsuba
3.9.1 `scalar_spectral`: Mitsuba's `integrator_aov.xml` (over `include/integrator_scene.xml`,
whose film is reduced to 120 x 90) at SPP samples per pixel, seed 0, into
`reference/integrator_aov.exr` with all its channels (R, G, B, image.R ... image.A, nn.X ...,
position.X ..., depth.y.T). With `--noise`, renders it twice at NOISE_SPP (seeds 1 and 2) and
prints Mitsuba's own level per layer: the 8x8-block relMSE of the image layer, and for the
deterministic layers the largest per-pixel difference over pixels away from silhouettes.

Usage (from this folder):
    nice python3 make_layer_references.py [--noise]
"""
import os
import sys
import time

import mitsuba as mi
import numpy as np

SPP = 256
NOISE_SPP = 32
mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))


def render(spp, seed):
    path = os.path.join(here, "docs", "scenes", "integrator_aov.xml")
    scene = mi.load_file(path, spp=str(spp))
    mi.render(scene, spp=spp, seed=seed)
    return scene.sensors()[0].film().bitmap(raw=False)


def block_relmse(a, b, k=8):
    h, w = (a.shape[0] // k) * k, (a.shape[1] // k) * k
    ba = a[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))
    bb = b[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))
    return float(np.mean((ba - bb) ** 2 / (bb ** 2 + 1e-2)))


t = time.time()
if "--noise" in sys.argv:
    a, b = render(NOISE_SPP, 1), render(NOISE_SPP, 2)
    names = [f.name for f in a.struct_()]
    x, y = np.array(a), np.array(b)
    idx = lambda n: names.index(n)
    print("image: Mitsuba-vs-Mitsuba", block_relmse(x[..., idx("image.R"):idx("image.B") + 1],
                                                    y[..., idx("image.R"):idx("image.B") + 1]))
    for n in names[7:]:
        d = np.abs(x[..., idx(n)] - y[..., idx(n)])
        print(f"{n}: median |diff| {np.median(d):.3e}, 99th percentile {np.percentile(d, 99):.3e}")
else:
    render(SPP, 0).write(os.path.join(here, "reference", "integrator_aov.exr"))
print(f"{time.time() - t:.0f} s")
