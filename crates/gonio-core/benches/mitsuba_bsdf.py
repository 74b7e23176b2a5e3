"""Mitsuba 3 reference for `benches/bsdf.rs` (issue 2 §8): ns per lane of BSDF sample + eval,
sample alone and eval alone, in a vectorized variant (default `llvm_ad_spectral`), 2^20 lanes.

Same setup as the divan bench: wi = (0.48, 0.36, 0.8)/1.06 (opaque, so Dr.Jit cannot fold it),
independent uniforms, 4 wavelengths per lane drawn as Mitsuba's spectral sensors do. Inputs are
evaluated before the clock starts; each figure is the median of 7 timed launches after a
warm-up launch (JIT compilation excluded), divided by the lane count. Delta BSDFs' `eval` is a
constant 0 that Dr.Jit does not compute per lane.

    pip install mitsuba==3.9.1
    python3 crates/gonio-core/benches/mitsuba_bsdf.py [variant]
"""
import statistics
import sys
import time

import drjit as dr
import mitsuba as mi

mi.set_variant(sys.argv[1] if len(sys.argv) > 1 else "llvm_ad_spectral")

N = 1 << 20
MODELS = {
    "diffuse": {"type": "diffuse"},
    "conductor_mirror": {"type": "conductor"},
    "conductor_au_spectral": {"type": "conductor", "material": "Au"},
    "dielectric": {"type": "dielectric"},
    "thindielectric": {"type": "thindielectric"},
    "plastic": {"type": "plastic"},
    "twosided_diffuse": {"type": "twosided", "b": {"type": "diffuse"}},
    "blend_mirror_diffuse": {
        "type": "blendbsdf",
        "weight": 0.5,
        "a": {"type": "conductor"},
        "b": {"type": "diffuse"},
    },
}


def launch(bsdf, what):
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(1, N)
    si = dr.zeros(mi.SurfaceInteraction3f, N)
    w = [0.48 / 1.06, 0.36 / 1.06, 0.8 / 1.06]
    si.wi = mi.Vector3f(*[dr.opaque(mi.Float, c, N) for c in w])
    si.n = mi.Normal3f(*[dr.opaque(mi.Float, c, N) for c in (0.0, 0.0, 1.0)])
    si.sh_frame = mi.Frame3f(si.n)
    # As Sensor::sample_wavelengths in spectral variants: 4 shifted samples of the visible pdf.
    si.wavelengths, _ = mi.sample_rgb_spectrum(mi.sample_shifted(sampler.next_1d()))
    ctx = mi.BSDFContext()
    u1, u2 = sampler.next_1d(), sampler.next_2d()
    dr.eval(si, u1, u2)
    dr.sync_thread()
    t0 = time.perf_counter()
    if what == "sample_eval":
        bs, weight = bsdf.sample(ctx, si, u1, u2)
        dr.eval(bs, weight, bsdf.eval(ctx, si, bs.wo))
    elif what == "sample":
        dr.eval(*bsdf.sample(ctx, si, u1, u2))
    else:
        dr.eval(bsdf.eval(ctx, si, mi.warp.square_to_cosine_hemisphere(u2)))
    dr.sync_thread()  # the LLVM backend launches kernels asynchronously
    return time.perf_counter() - t0


print("model\tsample_eval_ns\tsample_ns\teval_ns")
for name, desc in MODELS.items():
    bsdf = mi.load_dict(desc)
    row = [name]
    for what in ("sample_eval", "sample", "eval"):
        launch(bsdf, what)
        times = [launch(bsdf, what) for _ in range(7)]
        row.append(f"{statistics.median(times) / N * 1e9:.1f}")
    print("\t".join(row), flush=True)
