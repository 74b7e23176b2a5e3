#!/usr/bin/env python3
"""Renders the references of the bench scenes of `bench/scenes/` with Mitsuba 3.9.1.

`bench/bench.py` measures each renderer's error (relMSE) against a converged image of the same
scene. The shared scenes have theirs in `testdata/mitsuba/reference/` (4096 spp,
`scalar_spectral`); the bench-only scenes (the corpus's material previews at 240 x 180 and the
1M-triangle terrain) get theirs from this script: Mitsuba 3.9.1 at SPP samples per pixel, seed 0,
written as half-float EXR to `bench/reference/<scene>.exr`. The default variant is
`llvm_ad_spectral` (the same estimator as `scalar_spectral`, several times faster); a reference's
own error adds about relMSE(64 spp) * 64 / SPP to every relMSE the bench reports.

Usage (from the repository root; minutes per scene on two cores):
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
        nice python3 bench/make_references.py [--spp 4096] [--variant llvm_ad_spectral] [SCENE ...]
"""
import argparse
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = ["bsdf_roughplastic_ggx", "bsdf_roughconductor_copper", "bsdf_roughdielectric_glass", "terrain-1m"]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scenes", nargs="*", default=SCENES)
    p.add_argument("--spp", type=int, default=4096)
    p.add_argument("--variant", default="llvm_ad_spectral")
    a = p.parse_args()

    import mitsuba as mi

    mi.set_variant(a.variant)
    os.makedirs(os.path.join(HERE, "reference"), exist_ok=True)
    for name in a.scenes:
        path = os.path.join(HERE, "scenes", name + ".xml")
        if name == "terrain-1m" and not os.path.exists(os.path.join(HERE, "scenes", "generated", "terrain-1m.ply")):
            subprocess.run([sys.executable, os.path.join(HERE, "make_terrain.py")], check=True)
        t = time.time()
        scene = mi.load_file(path, spp=str(a.spp))
        # Several passes at distinct seeds (one would exceed the LLVM variant's wavefront size).
        passes = max(1, a.spp // 256)
        acc = None
        for i in range(passes):
            img = mi.TensorXf(mi.render(scene, spp=a.spp // passes, seed=i)).numpy()
            acc = img if acc is None else acc + img
        bmp = mi.Bitmap(acc / passes, pixel_format=mi.Bitmap.PixelFormat.RGB)
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float16)
        bmp.write(os.path.join(HERE, "reference", name + ".exr"))
        print(f"{name}: {a.spp} spp ({a.variant}), {time.time() - t:.0f} s", flush=True)


if __name__ == "__main__":
    main()
