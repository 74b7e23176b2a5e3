#!/usr/bin/env python3
"""Renders the `ptracer` references of `crates/gonio-render/tests/ptracer.rs` with Mitsuba 3.9.1.

`docs/scenes/integrator_ptracer_cbox.xml` (a 32 x 32 Cornell box of diffuse walls, light tracing,
max_depth 6) rendered with the `scalar_spectral` variant:

* `reference/integrator_ptracer_cbox.exr`: REF_SPP light paths per pixel, seed 0 (the reference);
* and printed, not stored: the 8 x 8-block relMSE (the measure of `gonio compare`) between two
  renders at CI_SPP with seeds 1 and 2, Mitsuba's own noise level at the size the test renders,
  which is the test's threshold.

Usage (from this folder): nice python3 make_ptracer_references.py
"""
import os
import time

import mitsuba as mi
import numpy as np

REF_SPP = 4096
CI_SPP = 64

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
path = os.path.join(here, "docs", "scenes", "integrator_ptracer_cbox.xml")
scene = mi.load_file(path)


def block_relmse(a, b, block=8):
    h, w = a.shape[0] // block, a.shape[1] // block
    am = a[: h * block, : w * block, :3].reshape(h, block, w, block, 3).mean(axis=(1, 3))
    bm = b[: h * block, : w * block, :3].reshape(h, block, w, block, 3).mean(axis=(1, 3))
    return float(np.mean((am - bm) ** 2 / (bm**2 + 1e-2)))


t = time.time()
a = np.array(mi.render(scene, spp=CI_SPP, seed=1))
b = np.array(mi.render(scene, spp=CI_SPP, seed=2))
print(f"Mitsuba seed 1 vs seed 2 at {CI_SPP} spp: block relMSE {block_relmse(a, b):.3e}", flush=True)
img = mi.render(scene, spp=REF_SPP, seed=0)
mi.Bitmap(img).write(os.path.join(here, "reference", "integrator_ptracer_cbox.exr"))
ref = np.array(img)
print(f"seed 1 vs reference: {block_relmse(a, ref):.3e}; {REF_SPP} spp in {time.time() - t:.0f} s", flush=True)
