#!/usr/bin/env python3
"""Renders the references of `crates/gonio-render/tests/corpus_scenes.rs` with Mitsuba 3.9.1.

Each scene of this folder (copies of Mitsuba's documentation scenes, `docs/scenes/bsdf_*.xml`,
with the film of `include/matpreview.xml` reduced to 120 x 90) is rendered with the
`scalar_spectral` variant at SPP samples per pixel, seed 0, into `reference/<scene>.exr`.

The principled scenes (`docs/scenes/principled_blend_creation/scene*.xml`) are Mitsuba's with
its `type="Sphere"`/`"Rectangle"` (which Mitsuba itself rejects) lower-cased, the film reduced to
96 x 96 and `envmap.hdr` reduced from 1024 x 512 to 256 x 128 (Mitsuba's `Bitmap.resample`).

The sensor and `direct` scenes (`sensor_thinlens`, `sensor_orthographic`,
`integrator_direct_both`, `_lum`), the cylinder scenes (`shape_cylinder_onesided`,
`_twosided`), the sdfgrid scenes (`shape_sdfgrid`, `_analytic`) and the curve scenes
(`shape_linearcurve_basic`, `_parameterization`, `shape_bsplinecurve_basic`, `_parameterization`) and the
`mesh_attribute` scenes (`texture_mesh_attribute_face`, `_vertex`, over `include/shape_scene.xml`)
and `shape_sphere_light_analytic` have their films reduced to 120 x 90 (the direct ones 120 x 80), as has
`medium_homogeneous_sss` (over `include/shape_scene.xml`; its bunny is `common/meshes/bunny.ply`); they
are rendered when named on the command line. Scenes that use `$spp` get SPP as that parameter.

`bsdf_measured_synthetic` and `bsdf_measured_synthetic_aniso` are ours: the material preview
(`include/matpreview.xml`, 120 x 90) with a `measured` object reading the synthetic RGL tables of
`testdata/measured` (`iso.bsdf`, `aniso.bsdf`, by the relative path `../../../measured/`), since
Mitsuba's `bsdf_measured_*` documentation scenes read real RGL files the corpus does not ship;
they are rendered with the other `bsdf_*.xml` (SPP as they, the default 256).

Usage (from this folder; takes minutes per scene):
    nice python3 make_references.py [SCENE ...]      # default: every bsdf_*.xml here
"""
import glob
import os
import sys
import time

import mitsuba as mi

# SPP=N in the environment overrides it (shape_sphere_light_analytic: 4096, its rough floor
# reflects the small bright sphere in fireflies that 256 spp leave in the reference;
# integrator_direct_both and integrator_direct_lum: 8192, one light sample on Veach's sharper
# plates leaves fireflies too).
SPP = int(os.environ.get("SPP", 256))

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
names = sys.argv[1:] or sorted(
    os.path.basename(p)[:-4] for p in glob.glob(os.path.join(here, "docs", "scenes", "bsdf_*.xml"))
)
for name in names:
    t = time.time()
    # A `_delta_pdf_mitsuba`, `_whitepoint_mitsuba` or `_lookup_mitsuba` copy (a gonio parameter
    # Mitsuba rejects) is compared with the original's render, `reference/<original>.exr`.
    if name.endswith(("_delta_pdf_mitsuba", "_whitepoint_mitsuba", "_lookup_mitsuba")):
        continue
    # A `_cells_swapped` copy is compared with Mitsuba's render of the original file.
    source = name.removesuffix("_cells_swapped")
    path = os.path.join(here, "docs", "scenes", source + ".xml")
    # The material-preview scenes take $spp; the principled ones fix their sampler's count.
    params = {"spp": str(SPP)} if "$spp" in open(path).read() else {}
    scene = mi.load_file(path, **params)
    img = mi.render(scene, spp=SPP, seed=0)
    mi.Bitmap(img).write(os.path.join(here, "reference", name + ".exr"))
    print(f"{name}: {SPP} spp, {time.time() - t:.0f} s", flush=True)
