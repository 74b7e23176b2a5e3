#!/usr/bin/env python3
"""Mitsuba 3.9.1's cost of one BSDF sample + eval, for comparison with gonio's kernel benchmark
(`cargo bench -p gonio-core --bench bsdf`).

Each model is the Mitsuba plugin gonio implements, with the parameters of gonio's benchmark. The
query directions and random numbers are 2^20 lanes; in `llvm_ad_spectral` one call processes all
lanes in a JIT-compiled vectorized kernel, so ns/call = wall time / 2^20. The first run of each
kernel includes JIT compilation and is discarded; the figure is the median of the next runs.

Set-up (once per machine; see tools/mitsuba-render.py in the shared folder):
    python3 -m venv venv-mitsuba && venv-mitsuba/bin/pip install mitsuba==3.9.1 numpy
    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1

Usage:
    venv-mitsuba/bin/python bench/bsdf/mitsuba_bsdf.py [--variant llvm_ad_spectral] [--lanes 20] [--runs 7]
"""
import argparse
import statistics
import time

import drjit as dr
import mitsuba as mi

MODELS = {
    "diffuse": '<bsdf version="3.0.0" type="diffuse"><float name="reflectance" value="0.5"/></bsdf>',
    "conductor_au": '<bsdf version="3.0.0" type="conductor"><string name="material" value="Au"/></bsdf>',
    "dielectric": '<bsdf version="3.0.0" type="dielectric"><float name="int_ior" value="1.5"/></bsdf>',
    "thindielectric": '<bsdf version="3.0.0" type="thindielectric"><float name="int_ior" value="1.5"/></bsdf>',
    "plastic": '<bsdf version="3.0.0" type="plastic"><float name="diffuse_reflectance" value="0.5"/></bsdf>',
}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--variant", default="llvm_ad_spectral")
    p.add_argument("--lanes", type=int, default=20, help="log2 of the number of lanes")
    p.add_argument("--runs", type=int, default=7)
    a = p.parse_args()
    mi.set_variant(a.variant)
    n = 1 << a.lanes
    rng = mi.PCG32(size=n)
    # Query directions: cosine-weighted upper hemisphere (as gonio's benchmark).
    wi = mi.warp.square_to_cosine_hemisphere(mi.Point2f(rng.next_float32(), rng.next_float32()))
    u1 = rng.next_float32()
    u2 = mi.Point2f(rng.next_float32(), rng.next_float32())
    wl_u = rng.next_float32()
    dr.eval(wi, u1, u2, wl_u)
    ctx = mi.BSDFContext()
    print(f"{'model':16} {'ns/(sample+eval)':>18}  ({a.variant}, {n} lanes, median of {a.runs - 1})")
    for name, xml in MODELS.items():
        bsdf = mi.load_string(xml)
        times = []
        for _ in range(a.runs):
            si = dr.zeros(mi.SurfaceInteraction3f, n)
            si.wi = wi
            si.wavelengths, _ = mi.sample_rgb_spectrum(wl_u)
            t0 = time.perf_counter()
            bs, weight = bsdf.sample(ctx, si, u1, u2)
            value = bsdf.eval(ctx, si, bs.wo)
            dr.eval(bs, weight, value)
            dr.sync_thread()
            times.append(time.perf_counter() - t0)
        ns = statistics.median(times[1:]) / n * 1e9
        print(f"{name:16} {ns:18.2f}")


if __name__ == "__main__":
    main()
