#!/usr/bin/env python3
"""Render a Mitsuba 3 XML scene with Mitsuba itself, for side-by-side comparison with gonio.

A copy of the project's shared comparison tool (`shared/tools/mitsuba-render.py`), kept here so that
`bench/bench.py` needs nothing outside the repository.

Set-up (once per machine):
    python3 -m venv .venv-mitsuba && .venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
    # for the vectorized LLVM variants (llvm_ad_*), Mitsuba needs a recent libLLVM:
    apt-get update && apt-get install -y libllvm19
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1

Usage:
    .venv-mitsuba/bin/python bench/mitsuba_render.py SCENE.xml OUT.exr [--variant scalar_spectral]
        [--spp N] [-D name=value ...] [--repeat K] [--seed S]

Prints one line per run: variant, scene, spp, load seconds, render seconds (wall clock, the image
fully computed). With --repeat K the render is run K times and every time is printed.
"""
import argparse
import os
import time

import mitsuba as mi

p = argparse.ArgumentParser()
p.add_argument("scene")
p.add_argument("out")
p.add_argument("--variant", default="scalar_spectral")
p.add_argument("--spp", type=int, default=None)
p.add_argument("-D", action="append", default=[], help="scene parameter, name=value")
p.add_argument("--repeat", type=int, default=1)
p.add_argument("--seed", type=int, default=0, help="seed of the first run; run i uses seed + i")
a = p.parse_args()

mi.set_variant(a.variant)
params = dict(kv.split("=", 1) for kv in a.D)
if a.spp is not None:
    params["spp"] = str(a.spp)
t0 = time.perf_counter()
scene = mi.load_file(a.scene, **params)
t1 = time.perf_counter()
for i in range(a.repeat):
    t2 = time.perf_counter()
    img = mi.render(scene, spp=a.spp, seed=a.seed + i)
    pixels = mi.TensorXf(img).numpy()  # forces the computation to finish
    t3 = time.perf_counter()
    print(f"{a.variant} {os.path.basename(a.scene)} spp={a.spp} load={t1 - t0:.3f}s render={t3 - t2:.3f}s")
mi.Bitmap(img).write(a.out)
