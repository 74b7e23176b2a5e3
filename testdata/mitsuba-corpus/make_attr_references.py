#!/usr/bin/env python3
"""Mitsuba 3.9.1 references and noise levels for the mesh-attribute rows of
`crates/gonio-render/tests/corpus_scenes.rs` (issue #10).

* `emitter_area_mesh_attribute` (`docs/scenes/`, 96 x 72): a mesh emitter whose `radiance` is a
  `mesh_attribute` (`vertex_color` of `meshes/emitter_grid.ply`, made by
  `meshes/make_emitter_grid.py`) over a diffuse floor. Mitsuba 3.9.1 `scalar_spectral` crashes
  (segmentation fault) when its `path` or `direct` integrator samples such an emitter (next-event
  estimation), and its `ptracer` refuses it ("Texture::sample_spectrum(): not implemented!"). The
  reference is therefore rendered with `direct` and BSDF samples only (`emitter_samples` 0,
  `bsdf_samples` 1): with a black emitter BSDF and a single floor, that is the same image as the
  path tracer's (every path is camera -> floor -> emitter, or the emitter seen directly). SPP
  samples per pixel, seed 0, into `reference/emitter_area_mesh_attribute.exr`.
* `texture_mesh_attribute_instance`: Mitsuba's `texture_mesh_attribute_vertex.xml` with the bunny
  placed by a `shapegroup` + `instance` (same placement). Mitsuba 3.9.1 renders it wrong (it
  recomputes barycentrics from the world-space hit point against the group-space vertices: the
  mean pixel is printed, ~1e20); gonio's render is compared with Mitsuba's render of the directly
  placed mesh, `reference/texture_mesh_attribute_vertex.exr` (made by `make_references.py`).

With `--noise`, also prints Mitsuba's own seed-to-seed level of the emitter scene (two renders
at 32 spp, seeds 1 and 2, BSDF samples only), as `corpus_scenes.rs` measures it.

Usage (from this folder): nice -n 10 python3 make_attr_references.py [--noise]
"""
import os
import sys
import time

import mitsuba as mi
import numpy as np

SPP = 4096

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
scenes = os.path.join(here, "docs", "scenes")


def load_bsdf_only(spp):
    text = open(os.path.join(scenes, "emitter_area_mesh_attribute.xml")).read()
    direct = ('<integrator type="direct"><integer name="emitter_samples" value="0"/>'
              '<integer name="bsdf_samples" value="1"/></integrator>')
    text = text.replace('<integrator type="$integrator"/>', direct)
    assert direct in text
    tmp = os.path.join(scenes, "_emitter_area_mesh_attribute_bsdf_only.xml")
    open(tmp, "w").write(text)
    try:
        return mi.load_file(tmp, spp=str(spp))
    finally:
        os.remove(tmp)


def block_relmse(a, b, k=8):
    h, w = (a.shape[0] // k) * k, (a.shape[1] // k) * k
    ba = a[:h, :w, :3].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
    bb = b[:h, :w, :3].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3))
    return float(np.mean((ba - bb) ** 2 / (bb ** 2 + 1e-2)))


t = time.time()
img = mi.render(load_bsdf_only(SPP), spp=SPP, seed=0)
mi.Bitmap(img).write(os.path.join(here, "reference", "emitter_area_mesh_attribute.exr"))
print(f"emitter_area_mesh_attribute: {SPP} spp, {time.time() - t:.0f} s", flush=True)

inst = mi.load_file(os.path.join(scenes, "texture_mesh_attribute_instance.xml"), spp="4")
print("texture_mesh_attribute_instance in Mitsuba 3.9.1, mean pixel:",
      np.array(mi.render(inst, spp=4, seed=0)).mean(axis=(0, 1)))

if "--noise" in sys.argv:
    a = np.array(mi.render(load_bsdf_only(32), spp=32, seed=1))
    b = np.array(mi.render(load_bsdf_only(32), spp=32, seed=2))
    print(f"emitter_area_mesh_attribute: Mitsuba-vs-Mitsuba (32 spp, seeds 1, 2) {block_relmse(a, b):.3e}")
