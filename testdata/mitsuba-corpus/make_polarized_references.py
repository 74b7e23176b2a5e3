#!/usr/bin/env python3
"""Renders the references of the polarized rows of `crates/gonio-render/tests/corpus_scenes.rs`
with Mitsuba 3.9.1 `scalar_spectral_polarized`.

Scenes (copies of Mitsuba's documentation scenes in `docs/scenes/`): `bsdf_polarizer_aligned`,
`_middle`, `_absorbing` (over `include/shape_scene.xml`, whose film is reduced to 120 x 90) and
`integrator_stokes_cbox` (its `res` default reduced to 48, the `spp` default to 32; the other
defaults are Mitsuba's), `bsdf_pplastic_diffuse_stokes` and `bsdf_pplastic_specular_stokes`
(`include/matpreview_stokes.xml`, film reduced to 120 x 90), and
`bsdf_measured_polarized_synthetic_stokes` (Mitsuba's `bsdf_measured_polarized_gold_stokes` with
its filename changed to our synthetic table `../../../measured_polarized/synthetic.pbsdf`, over
the same include; the KAIST gold table is not in the corpus). Each is rendered at SPP samples
per pixel with seed 0 into `reference/<scene>.exr` (all film channels: R, G, B and, for
`stokes`, S0.R ... S3.B), and, with `--noise`, twice at NOISE_SPP with seeds 1 and 2 into `/tmp`
to print the block relMSE of Mitsuba against itself per channel group (the level quoted in the
test).

Usage (from this folder):
    nice python3 make_polarized_references.py [--noise] [SCENE ...]
"""
import os
import sys
import time

import mitsuba as mi
import numpy as np

SPP = 256
NOISE_SPP = 32
SCENES = ["bsdf_polarizer_aligned", "bsdf_polarizer_middle", "bsdf_polarizer_absorbing",
          "integrator_stokes_cbox",
          # pplastic under `stokes` (include/matpreview_stokes.xml, film reduced to 120 x 90).
          "bsdf_pplastic_diffuse_stokes", "bsdf_pplastic_specular_stokes",
          # measured_polarized on the synthetic table of testdata/measured_polarized (same include).
          "bsdf_measured_polarized_synthetic_stokes"]

mi.set_variant("scalar_spectral_polarized")
here = os.path.dirname(os.path.abspath(__file__))
args = [a for a in sys.argv[1:] if not a.startswith("--")]
noise = "--noise" in sys.argv


def render(name, spp, seed):
    path = os.path.join(here, "docs", "scenes", name + ".xml")
    scene = mi.load_file(path, spp=str(spp))
    mi.render(scene, spp=spp, seed=seed)
    return scene.sensors()[0].film().bitmap(raw=False)


def block_relmse(a, b, k=8):
    h, w = (a.shape[0] // k) * k, (a.shape[1] // k) * k
    ba = a[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))
    bb = b[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))
    return float(np.mean((ba - bb) ** 2 / (bb ** 2 + 1e-2)))


for name in args or SCENES:
    t = time.time()
    if noise:
        a = render(name, NOISE_SPP, 1)
        b = render(name, NOISE_SPP, 2)
        names = a.channel_names() if hasattr(a, "channel_names") else None
        x, y = np.array(a), np.array(b)
        for g in range(x.shape[2] // 3):
            print(f"{name} channels {3*g}..{3*g+2}: Mitsuba-vs-Mitsuba {block_relmse(x[..., 3*g:3*g+3], y[..., 3*g:3*g+3]):.3e}", flush=True)
    else:
        bmp = render(name, SPP, 0)
        bmp.write(os.path.join(here, "reference", name + ".exr"))
    print(f"{name}: {time.time() - t:.0f} s", flush=True)
