#!/usr/bin/env python3
"""Renders the references of the bench scenes with Mitsuba 3.9.1.

`bench/bench.py` measures each renderer's error (relMSE) against a converged image of the same
scene, made by this script: Mitsuba 3.9.1 at SPP samples per pixel (default 16384), in passes of
256 at seeds SEED_BASE, SEED_BASE + 1, ... (default 1000: no bench run uses them), written as
half-float EXR to `bench/reference/<scene>.exr`, for the shared scenes (from
`testdata/mitsuba/scenes/`; bench.py falls back to their 4096-spp references in
`testdata/mitsuba/reference/`) and the bench-only ones (the corpus's material previews at
240 x 180 and the 1M-triangle terrain, `bench/scenes/`). The default variant is
`llvm_ad_spectral` (the same estimator as `scalar_spectral`, several times faster); a
reference's own error adds about relMSE(64 spp) * 64 / SPP to every relMSE the bench reports
(0.4 % of it at 16384 spp, against 1.6 % at 4096: 12 % of gonio's error on materials and
thin-vs-thick).

Usage (from the repository root; 1.5 hours for all eight on an idle 2-core machine, the glass
preview the longest at about 15 minutes):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
        nice python3 bench/make_references.py [--spp 16384] [--seed-base 1000] [--variant llvm_ad_spectral] [SCENE ...]
"""
import argparse
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
# The shared scenes have 4096-spp references in testdata/mitsuba/reference/ (the tests' own);
# they are rendered from testdata/mitsuba/scenes/ into bench/reference/, which bench.py prefers.
SHARED = ["materials", "cornell-spheres", "thin-vs-thick", "furnace"]
SCENES = SHARED + ["bsdf_roughplastic_ggx", "bsdf_roughconductor_copper", "bsdf_roughdielectric_glass", "terrain-1m"]
ROOT = os.path.dirname(HERE)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scenes", nargs="*", default=SCENES)
    p.add_argument("--spp", type=int, default=16384)
    p.add_argument("--variant", default="llvm_ad_spectral")
    p.add_argument("--seed-base", type=int, default=1000,
                   help="seed of the first pass (the others follow); pick one no bench run uses")
    a = p.parse_args()

    import mitsuba as mi

    mi.set_variant(a.variant)
    os.makedirs(os.path.join(HERE, "reference"), exist_ok=True)
    for name in a.scenes:
        if name in SHARED:
            path = os.path.join(ROOT, "testdata", "mitsuba", "scenes", name + ".xml")
        else:
            path = os.path.join(HERE, "scenes", name + ".xml")
        if name == "terrain-1m" and not os.path.exists(os.path.join(HERE, "scenes", "generated", "terrain-1m.ply")):
            subprocess.run([sys.executable, os.path.join(HERE, "make_terrain.py")], check=True)
        t = time.time()
        scene = mi.load_file(path, spp=str(a.spp))
        # Several passes at distinct seeds (one would exceed the LLVM variant's wavefront size).
        passes = max(1, a.spp // 256)
        acc = None
        for i in range(passes):
            img = mi.TensorXf(mi.render(scene, spp=a.spp // passes, seed=a.seed_base + i)).numpy()
            acc = img if acc is None else acc + img
        bmp = mi.Bitmap(acc / passes, pixel_format=mi.Bitmap.PixelFormat.RGB)
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16)
        bmp.write(os.path.join(HERE, "reference", name + ".exr"))
        print(f"{name}: {a.spp} spp ({a.variant}), {time.time() - t:.0f} s", flush=True)


if __name__ == "__main__":
    main()
