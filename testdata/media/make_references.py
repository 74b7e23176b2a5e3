#!/usr/bin/env python3
"""Renders the references of `crates/gonio-render/tests/media.rs` with Mitsuba 3.9.1.

Each scene of this folder (ours: `medium_cube_null.xml`, a cube of chromatic, forward-scattering
medium behind `null` faces; `medium_sphere_glass.xml`, a glass sphere of isotropic medium) is
rendered with the `scalar_spectral` variant at 4096 samples per pixel, seed 0, into `<scene>.exr`.
The radiance-meter values in `media.rs` were made the same way (`mi.render` of the meter scenes
written out in that file, 65 536 samples per render, seeds 0, 1, ..., averaged).

Usage (from this folder; about 20 s per scene on two cores):
    python3 make_references.py
"""
import os

import mitsuba as mi

mi.set_variant("scalar_spectral")
here = os.path.dirname(os.path.abspath(__file__))
for name in ["medium_cube_null", "medium_sphere_glass"]:
    scene = mi.load_file(os.path.join(here, name + ".xml"))
    mi.Bitmap(mi.render(scene, spp=4096, seed=0)).write(os.path.join(here, name + ".exr"))
    print(name, flush=True)
